//! Least squares conformal maps with a free boundary (Lévy, Petitjean, Ray, Maillot 2002).
//!
//! For a triangle T with area A_T and the affine map J_T from its own 2D frame to the plane,
//! the conformal energy is
//!
//! E_C(u, v) = Σ_T ½ A_T ((u_x − v_y)² + (u_y + v_x)²) = Σ_T ½ A_T (‖J_T‖²_F − 2 det J_T),
//!
//! i.e. the Dirichlet energy minus the signed area (libigl's `lscm` minimises the same
//! quadratic form). It vanishes exactly for orientation-preserving similarities, so a
//! developable piece is recovered up to scale. Two pinned vertices remove the similarity
//! null space; the remaining free unknowns solve Q_ff x_f = −Q_fp x_p. Written with
//! z = u + iv, Q is a Hermitian n×n matrix with the cotangent Laplacian's pattern (see
//! [`lscm_piece`]), factorised with faer's sparse Cholesky (AMD order).
//!
//! Each connected component is a separate problem with its own pins.

use flatcut_mesh::geometry::corner_cot;
use flatcut_mesh::{Topology, TriMesh, VertexId, vec3};
use flatcut_sparse::c64;
use serde::{Deserialize, Serialize};

use crate::LscmError;
use crate::piece::{Piece, split_pieces};
use crate::triangle::local_frame;
use flatcut_sparse::SpdPattern;

/// How the two pinned vertices are chosen.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Pins {
    /// Per component, the two boundary vertices farthest apart in 3D (see [`auto_pins`]).
    #[default]
    Auto,
    /// These two vertices (one component; the other components use `Auto`).
    Given([VertexId; 2]),
}

/// Options of [`lscm`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct LscmOptions {
    /// Pin choice. Default: [`Pins::Auto`].
    pub pins: Pins,
    /// Up to this many boundary vertices the automatic pins are the exact diameter pair
    /// (O(b²) distance evaluations); above it the pair is the exact diameter of a candidate
    /// set (extreme points along 64 directions plus a double farthest-point sweep).
    /// Default 3000 (≈ 4.5M distances, a few ms).
    pub exact_pin_search_max_boundary: usize,
}

impl Default for LscmOptions {
    fn default() -> Self {
        Self {
            pins: Pins::Auto,
            exact_pin_search_max_boundary: 3000,
        }
    }
}

/// The flattening of one piece.
#[derive(Clone, Debug, PartialEq)]
pub struct PieceFlattening {
    /// The piece (component) and its maps back to the source mesh.
    pub piece: Piece,
    /// 2D position (mm) of each local vertex of the piece.
    pub uv: Vec<[f64; 2]>,
    /// The pinned vertices (source indices): pin 0 at (0, 0), pin 1 at (d, 0) with d their
    /// 3D distance, before any placement.
    pub pins: [VertexId; 2],
    /// The LSCM conformal energy E_C of `uv` as solved (mm²; 0 for a developable piece).
    pub conformal_energy: f64,
}

/// The flattening of a whole mesh: one [`PieceFlattening`] per connected component, and
/// the combined per-vertex coordinates.
#[derive(Clone, Debug, PartialEq)]
pub struct Flattening {
    /// One 2D position per source vertex (mm). Unreferenced vertices are at (0, 0). Straight
    /// out of [`lscm`] each piece is in its own pin frame (pieces may overlap); after
    /// [`crate::place`] the pieces lie side by side.
    pub uv: Vec<[f64; 2]>,
    /// The pieces, in component order.
    pub pieces: Vec<PieceFlattening>,
}

impl Flattening {
    /// Rewrites [`Flattening::uv`] from the pieces.
    pub fn gather(&mut self) {
        for p in &self.pieces {
            for (v, uv) in p.piece.vertices.iter().zip(&p.uv) {
                self.uv[v.idx()] = *uv;
            }
        }
    }
}

/// Flattens every connected component of `mesh` by free-boundary LSCM.
///
/// Preconditions checked (each refused with a named error, never a panic): faces present,
/// manifold, consistently oriented, no degenerate face, every component has a boundary,
/// distinct valid pins. Unreferenced vertices are ignored (uv (0, 0)).
pub fn lscm(mesh: &TriMesh, opts: &LscmOptions) -> Result<Flattening, LscmError> {
    let topo = Topology::build(mesh)?;
    lscm_with_topology(mesh, &topo, opts)
}

/// [`lscm`] with a topology already built for `mesh`.
pub fn lscm_with_topology(
    mesh: &TriMesh,
    topo: &Topology,
    opts: &LscmOptions,
) -> Result<Flattening, LscmError> {
    let pieces = split_pieces(mesh, topo)?;
    let given = match opts.pins {
        Pins::Auto => None,
        Pins::Given([a, b]) => {
            for v in [a, b] {
                if v.idx() >= mesh.vertex_count() || !topo.is_referenced(v) {
                    return Err(LscmError::InvalidPin { vertex: v });
                }
            }
            let vc = topo.vertex_components();
            if vc[a.idx()] != vc[b.idx()] {
                return Err(LscmError::PinsInDifferentComponents { a, b });
            }
            if a == b || mesh.positions[a.idx()] == mesh.positions[b.idx()] {
                return Err(LscmError::CoincidentPins { a, b });
            }
            Some((vc[a.idx()] as usize, [a, b]))
        }
    };
    let mut out = Vec::with_capacity(pieces.len());
    for piece in pieces {
        let pins = match given {
            Some((c, pins)) if c == piece.component => {
                let local = |v: VertexId| {
                    piece
                        .vertices
                        .binary_search(&v)
                        .map_err(|_| LscmError::InvalidPin { vertex: v })
                };
                [local(pins[0])? as u32, local(pins[1])? as u32]
            }
            _ => auto_pins(&piece, opts.exact_pin_search_max_boundary)?,
        };
        out.push(lscm_piece(piece, pins)?);
    }
    let mut flat = Flattening {
        uv: vec![[0.0; 2]; mesh.vertex_count()],
        pieces: out,
    };
    flat.gather();
    Ok(flat)
}

/// The two boundary vertices of `piece` (local indices) farthest apart in 3D.
///
/// Exact (all pairs) for up to `exact_max` boundary vertices. Above, the exact diameter of
/// a candidate set: the extreme boundary vertices along 64 fixed directions spread over
/// the sphere, plus the ends of a double farthest-point sweep. The true diameter pair is
/// extreme along its own direction, so the candidate diameter is within a factor
/// cos(δ/2) of the true one, δ the largest angle between a direction and its nearest
/// sampled one (≈ 0.3 rad for 64 directions: ≥ 98.9 % of the diameter, and usually exact).
pub fn auto_pins(piece: &Piece, exact_max: usize) -> Result<[u32; 2], LscmError> {
    let mut boundary: Vec<u32> = piece.boundary_loops.iter().flatten().copied().collect();
    boundary.sort_unstable();
    boundary.dedup();
    let pos = &piece.positions;
    let candidates: Vec<u32> = if boundary.len() <= exact_max {
        boundary.clone()
    } else {
        let mut c = Vec::with_capacity(160);
        // Fibonacci sphere directions: an even, deterministic spread.
        let k = 64;
        for i in 0..k {
            let z = 1.0 - (2.0 * i as f64 + 1.0) / k as f64;
            let r = (1.0 - z * z).sqrt();
            let phi = i as f64 * std::f64::consts::PI * (3.0 - 5f64.sqrt());
            let d = [r * phi.cos(), r * phi.sin(), z];
            let mut best = (f64::NEG_INFINITY, boundary[0]);
            for &v in &boundary {
                let s = vec3::dot(pos[v as usize], d);
                if s > best.0 {
                    best = (s, v);
                }
            }
            c.push(best.1);
        }
        let farthest = |from: u32| {
            let mut best = (-1.0, from);
            for &v in &boundary {
                let d = vec3::norm2(vec3::sub(pos[v as usize], pos[from as usize]));
                if d > best.0 {
                    best = (d, v);
                }
            }
            best.1
        };
        let a = farthest(boundary[0]);
        let b = farthest(a);
        c.push(a);
        c.push(b);
        c.sort_unstable();
        c.dedup();
        c
    };
    let mut best = (0.0, 0u32, 0u32);
    for (i, &a) in candidates.iter().enumerate() {
        let pa = pos[a as usize];
        for &b in &candidates[i + 1..] {
            let d = vec3::norm2(vec3::sub(pos[b as usize], pa));
            if d > best.0 {
                best = (d, a, b);
            }
        }
    }
    if best.0 <= 0.0 {
        let v = piece.vertices[boundary.first().copied().unwrap_or(0) as usize];
        return Err(LscmError::CoincidentPins { a: v, b: v });
    }
    Ok([best.1, best.2])
}

/// The two rows (coefficients of (u0, v0, u1, v1, u2, v2)) of the conformality residual of
/// a triangle given in its own frame `q`, and its area: E_T = ½ A (r₁² + r₂²) with
/// r₁ = u_x − v_y, r₂ = u_y + v_x and ∇φ_k = perp(q_{k+2} − q_{k+1}) / 2A.
#[inline]
pub(crate) fn conformal_rows(q: [[f64; 2]; 3]) -> (f64, [f64; 6], [f64; 6]) {
    let a2 = (q[1][0] - q[0][0]) * (q[2][1] - q[0][1]) - (q[1][1] - q[0][1]) * (q[2][0] - q[0][0]);
    let mut r1 = [0.0; 6];
    let mut r2 = [0.0; 6];
    for k in 0..3 {
        let (i, j) = ((k + 1) % 3, (k + 2) % 3);
        let gx = -(q[j][1] - q[i][1]) / a2;
        let gy = (q[j][0] - q[i][0]) / a2;
        r1[2 * k] = gx;
        r1[2 * k + 1] = -gy;
        r2[2 * k] = gy;
        r2[2 * k + 1] = gx;
    }
    (0.5 * a2, r1, r2)
}

/// The conformal energy E_C of `uv` on `piece`, Σ_T ½ A_T (r₁² + r₂²) with the residuals
/// r₁ = u_x − v_y, r₂ = u_y + v_x of each triangle in its own frame (a sum of squares,
/// which keeps its accuracy where the expanded form xᵀQx would cancel).
pub fn conformal_energy(piece: &Piece, uv: &[[f64; 2]]) -> f64 {
    let mut e = 0.0;
    for f in &piece.local_faces {
        let p = f.map(|v| piece.positions[v as usize]);
        let (area, r1, r2) = conformal_rows(local_frame(p[0], p[1], p[2]));
        let [a, b, c] = f.map(|v| uv[v as usize]);
        let x = [a[0], a[1], b[0], b[1], c[0], c[1]];
        let s1: f64 = r1.iter().zip(&x).map(|(r, x)| r * x).sum();
        let s2: f64 = r2.iter().zip(&x).map(|(r, x)| r * x).sum();
        e += 0.5 * area * (s1 * s1 + s2 * s2);
    }
    e
}

/// LSCM of one piece with pins given as local indices.
pub fn lscm_piece(piece: Piece, pins: [u32; 2]) -> Result<PieceFlattening, LscmError> {
    let n = piece.positions.len();
    let [pa, pb] = pins;
    let d = vec3::dist(piece.positions[pa as usize], piece.positions[pb as usize]);
    let pin_ids = [piece.vertices[pa as usize], piece.vertices[pb as usize]];
    if pa == pb || d <= 0.0 {
        return Err(LscmError::CoincidentPins {
            a: pin_ids[0],
            b: pin_ids[1],
        });
    }
    // Unknown index of each free vertex.
    let mut free = vec![u32::MAX; n];
    let mut nf = 0u32;
    for (v, slot) in free.iter_mut().enumerate() {
        if v as u32 != pa && v as u32 != pb {
            *slot = nf;
            nf += 1;
        }
    }
    let m = nf as usize;
    let mut pinned = vec![c64::new(0.0, 0.0); n];
    pinned[pb as usize] = c64::new(d, 0.0);

    // With z = u + iv per vertex, E_C = ½ zᴴ H z with the Hermitian H = L + iK: L the
    // cotangent Laplacian (the Dirichlet part ½ Σ_e w_e |z_i − z_j|², w_e = ½ (cot α + cot β))
    // and K the signed-area part, which by the shoelace formula lives on the boundary only:
    // Σ_T A_T det J_T = ½ Σ_{boundary halfedges i→j} Im(z̄_i z_j), giving K_ij = ½, K_ji = −½.
    // This is the quadratic form of the per-triangle blocks of [`conformal_energy`] (interior
    // u–v couplings cancel exactly), as an n×n complex system with the Laplacian's pattern
    // instead of a 2n×2n real one: a quarter of the symbolic work and less fill.
    let nt = piece.local_faces.len();
    let nb: usize = piece.boundary_loops.iter().map(Vec::len).sum();
    let mut pairs = Vec::with_capacity(nt * 6 + nb);
    let mut vals: Vec<c64> = Vec::with_capacity(nt * 6 + nb);
    let mut rhs = vec![c64::new(0.0, 0.0); m];
    // H[a, b] += val and H[b, a] += conj(val) (once for a = b, val real).
    let mut add = |a: usize, b: usize, val: c64| {
        let (fa, fb) = (free[a], free[b]);
        match (fa != u32::MAX, fb != u32::MAX) {
            (true, true) => {
                // Store the lower triangle: H[row, col] with row ≥ col.
                if fa >= fb {
                    pairs.push((fa as usize, fb as usize));
                    vals.push(val);
                } else {
                    pairs.push((fb as usize, fa as usize));
                    vals.push(val.conj());
                }
            }
            (true, false) => rhs[fa as usize] -= val * pinned[b],
            (false, true) => rhs[fb as usize] -= val.conj() * pinned[a],
            (false, false) => {}
        }
    };
    for f in &piece.local_faces {
        let p = f.map(|v| piece.positions[v as usize]);
        for o in 0..3 {
            // Corner o faces the edge (i, j).
            let (i, j) = (f[(o + 1) % 3] as usize, f[(o + 2) % 3] as usize);
            let w = 0.5 * corner_cot(p[o], p[(o + 1) % 3], p[(o + 2) % 3]);
            add(i, i, c64::new(w, 0.0));
            add(j, j, c64::new(w, 0.0));
            add(i, j, c64::new(-w, 0.0));
        }
    }
    for lp in &piece.boundary_loops {
        for k in 0..lp.len() {
            let (i, j) = (lp[k] as usize, lp[(k + 1) % lp.len()] as usize);
            add(i, j, c64::new(0.0, 0.5));
        }
    }
    let component = piece.component;
    let numerical = |cause| LscmError::Numerical {
        component,
        stage: "LSCM",
        cause,
    };
    if m > 0 {
        let pattern = SpdPattern::new(m, &pairs).map_err(numerical)?;
        let factor = pattern.factor(&vals).map_err(numerical)?;
        factor.solve_in_place(&mut rhs, 1).map_err(numerical)?;
    }
    let mut uv: Vec<[f64; 2]> = pinned.iter().map(|z| [z.re, z.im]).collect();
    for v in 0..n {
        let k = free[v];
        if k != u32::MAX {
            let z = rhs[k as usize];
            uv[v] = [z.re, z.im];
        }
    }
    let conformal_energy = conformal_energy(&piece, &uv);
    Ok(PieceFlattening {
        piece,
        uv,
        pins: pin_ids,
        conformal_energy,
    })
}
