//! Quadric error decimation (Garland & Heckbert 1997, "Surface simplification using
//! quadric error metrics"): every vertex carries the sum of the squared-distance quadrics
//! of its faces' planes (area-weighted); an edge costs the quadric error at the position
//! minimising it; the cheapest edge is collapsed until the face budget is met. Boundary
//! edges add a heavily weighted plane through the edge, perpendicular to its face, so the
//! outline stays in place. The binary heap is updated lazily: a popped edge's cost is
//! recomputed and, if it rose since it was queued, the edge goes back in; nothing is pushed
//! when a collapse changes the neighbourhood (that would grow the heap tenfold, and its
//! cache misses dominated the run time).

use dary_heap::OctonaryHeap;

use flatcut_mesh::bvh::Bvh;
use flatcut_mesh::vec3::{add, cross, dist, dot, norm, normalize, scale, sub};
use flatcut_mesh::{INVALID, Topology, TriMesh};
use rayon::prelude::*;
use serde::Deserialize;

use crate::RemeshError;
use crate::halfedge::{HalfMesh, check_manifold, twin};
use crate::quality::{QualityReport, quality_with_bvh};
use crate::remesh::Provenance;

/// Weight of a boundary edge's perpendicular plane relative to the faces' planes: large
/// enough that collapses move boundary vertices only along the boundary (G&H §5 suggest a
/// large penalty), small enough to leave the system well conditioned.
const BOUNDARY_WEIGHT: f64 = 100.0;
/// A collapse may turn a surrounding face's normal by at most this much (cosine of ~78°):
/// beyond it the face is close to folding over.
const MIN_NORMAL_COS: f64 = 0.2;
/// Rounds of retrying the edges the checks refused once the queue has run dry.
const MAX_RETRY_ROUNDS: usize = 8;
/// A face shrinking below this fraction of its area counts as degenerate.
const DEGENERATE_REL: f64 = 1e-12;
/// The 3×3 quadric system counts as singular below this determinant relative to the cube of
/// its diagonal's size; the best of the endpoints and midpoint is taken then.
const SINGULAR_REL: f64 = 1e-10;
/// The optimal point is refused if it lies farther than this many edge lengths from the
/// edge's midpoint (an ill-conditioned solve), falling back as above.
const MAX_OPTIMUM_OFFSET: f64 = 2.0;

/// Options of [`decimate`]. Deserializes from the pipeline TOML (`[decimate]`).
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct DecimateOptions {
    /// Face budget: stop at or below this many faces (default 50 000; at least 4).
    pub target_faces: usize,
}

impl Default for DecimateOptions {
    fn default() -> Self {
        DecimateOptions {
            target_faces: 50_000,
        }
    }
}

/// Result of [`decimate`].
#[derive(Clone, Debug)]
pub struct Decimated {
    /// The decimated mesh (mm).
    pub mesh: TriMesh,
    /// Per output vertex, the closest point of the input surface.
    pub provenance: Vec<Provenance>,
    /// Quality of the result (edges measured against their mean).
    pub report: QualityReport,
}

/// Symmetric 4×4 quadric, upper triangle: a², ab, ac, ad, b², bc, bd, c², cd, d².
type Quadric = [f64; 10];

fn plane_quadric(n: [f64; 3], p: [f64; 3], w: f64) -> Quadric {
    let d = -dot(n, p);
    let [a, b, c] = n;
    [
        w * a * a,
        w * a * b,
        w * a * c,
        w * a * d,
        w * b * b,
        w * b * c,
        w * b * d,
        w * c * c,
        w * c * d,
        w * d * d,
    ]
}

fn qadd(a: &Quadric, b: &Quadric) -> Quadric {
    let mut r = *a;
    for i in 0..10 {
        r[i] += b[i];
    }
    r
}

fn qeval(q: &Quadric, p: [f64; 3]) -> f64 {
    let [x, y, z] = p;
    q[0] * x * x
        + 2.0 * q[1] * x * y
        + 2.0 * q[2] * x * z
        + 2.0 * q[3] * x
        + q[4] * y * y
        + 2.0 * q[5] * y * z
        + 2.0 * q[6] * y
        + q[7] * z * z
        + 2.0 * q[8] * z
        + q[9]
}

/// The point minimising `q` (Cramer's rule), or `None` when the system is singular.
fn qoptimum(q: &Quadric) -> Option<[f64; 3]> {
    let (a, b, c, d, e, f) = (q[0], q[1], q[2], q[4], q[5], q[7]);
    let rhs = [-q[3], -q[6], -q[8]];
    let det = a * (d * f - e * e) - b * (b * f - e * c) + c * (b * e - d * c);
    let size = a.abs() + d.abs() + f.abs();
    if det.is_nan() || det.abs() <= SINGULAR_REL * size * size * size {
        return None;
    }
    let x = (rhs[0] * (d * f - e * e) - b * (rhs[1] * f - e * rhs[2])
        + c * (rhs[1] * e - d * rhs[2]))
        / det;
    let y = (a * (rhs[1] * f - e * rhs[2]) - rhs[0] * (b * f - e * c)
        + c * (b * rhs[2] - rhs[1] * c))
        / det;
    let z = (a * (d * rhs[2] - rhs[1] * e) - b * (b * rhs[2] - rhs[1] * c)
        + rhs[0] * (b * e - d * c))
        / det;
    let p = [x, y, z];
    p.iter().all(|v| v.is_finite()).then_some(p)
}

/// A queue entry: the collapse cost rounded to f32 in the high half, the edge in the low
/// half, reversed so that `OctonaryHeap` pops the cheapest edge first (ties: the lowest edge).
/// Eight bytes compared as one integer instead of an (f64, u32) pair: the heap of every edge
/// of a 428k-face scan (640k entries) is most of the decimation loop's memory traffic, and
/// the order of costs that differ only beyond f32's 24 bits does not matter to the result.
/// Costs are ≥ 0 (clamped), so their f32 bit patterns order like the values.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
struct Entry(std::cmp::Reverse<u64>);

impl Entry {
    fn new(cost: f64, edge: u32) -> Self {
        let bits = (cost.max(0.0) as f32).to_bits();
        Self(std::cmp::Reverse((u64::from(bits) << 32) | u64::from(edge)))
    }
    fn edge(self) -> u32 {
        self.0.0 as u32
    }
}

/// Decimates `mesh` to at most `opts.target_faces` faces (fewer only if no further collapse
/// is allowed: the report's face count says where it stopped).
pub fn decimate(mesh: &TriMesh, opts: &DecimateOptions) -> Result<Decimated, RemeshError> {
    mesh.validate()?;
    if mesh.faces.is_empty() {
        return Err(RemeshError::EmptyMesh);
    }
    if opts.target_faces < 4 {
        return Err(RemeshError::InvalidOption {
            name: "target_faces",
            value: opts.target_faces as f64,
            reason: "must be at least 4",
        });
    }
    let topo = Topology::build(mesh)?;
    check_manifold(mesh, &topo)?;
    let mut m = HalfMesh::build(mesh, &topo);
    let nv = m.pos.len();
    let mut q: Vec<Quadric> = vec![[0.0; 10]; nv];
    for face in &mesh.faces {
        let [a, b, c] = face.map(|i| mesh.positions[i as usize]);
        let n = cross(sub(b, a), sub(c, a));
        let area2 = norm(n);
        if area2 == 0.0 {
            continue;
        }
        let pq = plane_quadric(scale(n, 1.0 / area2), a, 0.5 * area2);
        for &v in face {
            q[v as usize] = qadd(&q[v as usize], &pq);
        }
    }
    for h in 0..2 * m.edge_count() as u32 {
        if !m.is_boundary_h(h) {
            continue;
        }
        let t = twin(h);
        let (a, b) = (m.pos[m.from(t) as usize], m.pos[m.to(t) as usize]);
        let c = m.pos[m.to(m.next(t)) as usize];
        let fnorm = cross(sub(b, a), sub(c, a));
        let e = sub(b, a);
        let n = normalize(cross(e, fnorm));
        if !n.iter().all(|x| x.is_finite()) {
            continue;
        }
        let pq = plane_quadric(n, a, BOUNDARY_WEIGHT * dot(e, e));
        for v in [m.from(t), m.to(t)] {
            q[v as usize] = qadd(&q[v as usize], &pq);
        }
    }
    let ne = m.edge_count();
    let heap: OctonaryHeap<Entry> = (0..ne as u32)
        .into_par_iter()
        .map(|e| Entry::new(best_collapse(&m, &q, e).1, e))
        .collect::<Vec<_>>()
        .into();
    // The collapse loop is sequential: the input's BVH (for provenance and the quality
    // report, a quarter of the call on a 428k-face scan) is built on the other core meanwhile.
    let (bvh, ()) = rayon::join(
        || Bvh::build(mesh),
        || collapse_to_budget(&mut m, &mut q, heap, mesh.faces.len(), opts.target_faces),
    );
    let (out, _) = m.to_trimesh();
    let provenance: Vec<Provenance> = out
        .positions
        .par_iter()
        .map(|&p| match bvh.closest_point(p) {
            Some(cp) => Provenance {
                face: cp.face.0,
                barycentric: cp.barycentric,
                filled: false,
            },
            None => Provenance {
                face: 0,
                barycentric: [1.0, 0.0, 0.0],
                filled: false,
            },
        })
        .collect();
    let report = quality_with_bvh(&out, mesh, &bvh, None, None, &[]);
    Ok(Decimated {
        mesh: out,
        provenance,
        report,
    })
}

/// The cheapest position for collapsing edge `e` under the summed quadric of its ends, and
/// its cost (≥ 0): the quadric's minimiser when it lies within `MAX_OPTIMUM_OFFSET` edge
/// lengths of the midpoint, else the best of the ends and the midpoint.
fn best_collapse(m: &HalfMesh, q: &[Quadric], e: u32) -> ([f64; 3], f64) {
    let (a, b) = (m.to(2 * e + 1), m.to(2 * e));
    let qq = qadd(&q[a as usize], &q[b as usize]);
    let (pa, pb) = (m.pos[a as usize], m.pos[b as usize]);
    let mid = scale(add(pa, pb), 0.5);
    if let Some(p) = qoptimum(&qq) {
        if dist(p, mid) <= MAX_OPTIMUM_OFFSET * dist(pa, pb) {
            return (p, qeval(&qq, p).max(0.0));
        }
    }
    [pa, pb, mid]
        .into_iter()
        .map(|p| (p, qeval(&qq, p).max(0.0)))
        .min_by(|x, y| x.1.total_cmp(&y.1))
        .unwrap_or((mid, 0.0))
}

/// Collapses the cheapest allowed edges of `m` (queue `heap`) until at most `target_faces`
/// of its `faces` remain or no collapse is allowed.
fn collapse_to_budget(
    m: &mut HalfMesh,
    q: &mut [Quadric],
    mut heap: OctonaryHeap<Entry>,
    faces: usize,
    target_faces: usize,
) {
    let mut faces_left = faces;
    // Edges refused by the checks wait here; they may pass once their neighbourhood changed.
    let mut refused: Vec<u32> = Vec::new();
    let mut rounds = 0;
    while faces_left > target_faces {
        let Some(top) = heap.pop() else {
            // Give refused edges another chance while collapses keep happening.
            if refused.is_empty() || rounds >= MAX_RETRY_ROUNDS {
                break;
            }
            rounds += 1;
            heap.extend(
                refused
                    .drain(..)
                    .filter(|&e| !m.e_dead[e as usize])
                    .map(|e| Entry::new(best_collapse(m, q, e).1, e)),
            );
            continue;
        };
        let e = top.edge();
        if m.e_dead[e as usize] {
            continue;
        }
        // Lazy update: costs are only recomputed when popped; an edge whose current cost
        // is no longer the smallest in the queue goes back in at that cost.
        let (p, cost) = best_collapse(m, q, e);
        let now = Entry::new(cost, e);
        if now < top && heap.peek().is_some_and(|next| now < *next) {
            heap.push(now);
            continue;
        }
        let removed_faces = if m.is_boundary_e(e) { 1 } else { 2 };
        let h = [2 * e + 1, 2 * e]
            .into_iter()
            .find(|&h| m.collapse_ok(h) && collapse_keeps_normals(m, h, p));
        let Some(h) = h else {
            refused.push(e);
            continue;
        };
        let (v0, v1) = (m.from(h), m.to(h));
        m.collapse(h);
        m.pos[v1 as usize] = p;
        q[v1 as usize] = qadd(&q[v1 as usize], &q[v0 as usize]);
        faces_left -= removed_faces;
    }
}

/// Every face around either end of `h` that survives the collapse keeps its orientation
/// (normal turned by less than ~78°) and a non-zero area when the merged vertex sits at `p`.
fn collapse_keeps_normals(m: &HalfMesh, h: u32, p: [f64; 3]) -> bool {
    let (v0, v1) = (m.from(h), m.to(h));
    let mut ok = true;
    for v in [v0, v1] {
        m.for_out(v, |g| {
            if !ok || m.face(g) == INVALID {
                return;
            }
            let x = m.to(g);
            let y = m.to(m.next(g));
            if [x, y].iter().any(|&u| u == v0 || u == v1) {
                return;
            }
            let (pv, px, py) = (m.pos[v as usize], m.pos[x as usize], m.pos[y as usize]);
            let n_old = cross(sub(px, pv), sub(py, pv));
            let n_new = cross(sub(px, p), sub(py, p));
            let (lo, ln) = (norm(n_old), norm(n_new));
            if ln <= DEGENERATE_REL * lo || dot(n_old, n_new) < MIN_NORMAL_COS * lo * ln {
                ok = false;
            }
        });
    }
    ok
}
