//! Placement of flattened pieces: the right side up (never mirrored), the grain along +y,
//! the bounding box at the origin, and several pieces side by side.

use flatcut_mesh::vec3::{cross, dot, norm, scale, sub};
use serde::{Deserialize, Serialize};

use crate::LscmError;
use crate::lscm::{Flattening, PieceFlattening};
use crate::triangle::signed_area2;

/// Options of [`place`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct PlacementOptions {
    /// The 3D direction (any length, not zero) that must point along +y in the pattern.
    /// Default `None`: the piece's principal axis (largest-variance direction of its vertex
    /// positions, signed so that its largest coordinate is positive).
    pub grain: Option<[f64; 3]>,
    /// Gap between pieces laid side by side along +x, in mm. Default 10.
    pub component_gap_mm: f64,
}

impl Default for PlacementOptions {
    fn default() -> Self {
        Self {
            grain: None,
            component_gap_mm: 10.0,
        }
    }
}

/// Places every piece (see [`place_piece`]) and lays them side by side along +x in
/// component order, each bounding box starting at y = 0, then rewrites `flat.uv`.
pub fn place(flat: &mut Flattening, opts: &PlacementOptions) -> Result<(), LscmError> {
    if !(opts.component_gap_mm.is_finite() && opts.component_gap_mm >= 0.0) {
        return Err(LscmError::InvalidOption {
            name: "component_gap_mm",
            value: opts.component_gap_mm,
            reason: "must be finite and ≥ 0",
        });
    }
    let mut x = 0.0;
    for p in &mut flat.pieces {
        place_piece(p, opts.grain)?;
        let width = p.uv.iter().map(|q| q[0]).fold(0.0, f64::max);
        for q in &mut p.uv {
            q[0] += x;
        }
        x += width + opts.component_gap_mm;
    }
    flat.gather();
    Ok(())
}

/// Places one piece in place:
/// 1. if its total signed area is negative it is reflected (u → −u), so that counter-
///    clockwise faces stay counter-clockwise: the pattern shows the outside of the surface
///    to a viewer looking down −z (LSCM and ARAP never produce a reflected piece from a
///    consistently oriented mesh; the check makes the guarantee independent of the solver);
/// 2. it is rotated so that the image of `grain` (averaged over faces, area-weighted)
///    points along +y;
/// 3. it is translated so that its bounding box starts at (0, 0).
pub fn place_piece(p: &mut PieceFlattening, grain: Option<[f64; 3]>) -> Result<(), LscmError> {
    let faces = &p.piece.local_faces;
    let signed: f64 = faces
        .iter()
        .map(|f| {
            signed_area2(
                p.uv[f[0] as usize],
                p.uv[f[1] as usize],
                p.uv[f[2] as usize],
            )
        })
        .sum();
    if signed < 0.0 {
        for q in &mut p.uv {
            q[0] = -q[0];
        }
    }
    let g = match grain {
        Some(g) => {
            if !(g.iter().all(|c| c.is_finite()) && norm(g) > 0.0) {
                return Err(LscmError::InvalidOption {
                    name: "grain",
                    value: norm(g),
                    reason: "the grain direction must be a finite, non-zero 3D vector",
                });
            }
            scale(g, 1.0 / norm(g))
        }
        None => principal_axis(&p.piece.positions),
    };
    let mut d = grain_image(p, g);
    if d[0].hypot(d[1]).is_nan() || d[0].hypot(d[1]) <= 0.0 {
        // The grain is normal to the surface everywhere: fall back to the 2D principal axis.
        d = principal_axis_2d(&p.uv);
    }
    // Rotate by α so that d ↦ +y.
    let alpha = std::f64::consts::FRAC_PI_2 - d[1].atan2(d[0]);
    let (s, c) = alpha.sin_cos();
    for q in &mut p.uv {
        *q = [c * q[0] - s * q[1], s * q[0] + c * q[1]];
    }
    let (mut lo_x, mut lo_y) = (f64::INFINITY, f64::INFINITY);
    for q in &p.uv {
        lo_x = lo_x.min(q[0]);
        lo_y = lo_y.min(q[1]);
    }
    for q in &mut p.uv {
        q[0] -= lo_x;
        q[1] -= lo_y;
    }
    Ok(())
}

/// Σ_T A_T (∇u·g, ∇v·g): the area-weighted image of the 3D direction `g` in the plane, with
/// ∇u = Σ_k u_k ∇φ_k and ∇φ_k = n × (p_{k+2} − p_{k+1}) / 2A.
fn grain_image(p: &PieceFlattening, g: [f64; 3]) -> [f64; 2] {
    let mut d = [0.0; 2];
    for f in &p.piece.local_faces {
        let x = f.map(|v| p.piece.positions[v as usize]);
        let n2 = cross(sub(x[1], x[0]), sub(x[2], x[0])); // 2A · n
        let a2 = norm(n2);
        if a2 <= 0.0 {
            continue;
        }
        let mut gu = 0.0;
        let mut gv = 0.0;
        for k in 0..3 {
            // 2A ∇φ_k = n × e_k; (n × e)·g / 2A with n = n2 / 2A.
            let e = sub(x[(k + 2) % 3], x[(k + 1) % 3]);
            let dphi_g = dot(cross(n2, e), g) / (a2 * a2);
            gu += p.uv[f[k] as usize][0] * dphi_g;
            gv += p.uv[f[k] as usize][1] * dphi_g;
        }
        d[0] += 0.5 * a2 * gu;
        d[1] += 0.5 * a2 * gv;
    }
    d
}

/// The unit direction of largest variance of `points` (power iteration on the 3×3
/// covariance), signed so that its largest-magnitude coordinate is positive.
pub fn principal_axis(points: &[[f64; 3]]) -> [f64; 3] {
    let n = points.len().max(1) as f64;
    let mut c = [0.0; 3];
    for p in points {
        for k in 0..3 {
            c[k] += p[k] / n;
        }
    }
    let mut m = [[0.0; 3]; 3];
    for p in points {
        let d = sub(*p, c);
        for i in 0..3 {
            for j in 0..3 {
                m[i][j] += d[i] * d[j];
            }
        }
    }
    // Fixed, generic start vector and iteration count: deterministic; an exactly repeated
    // top eigenvalue (a round disk) has no preferred axis anyway.
    let mut v = [0.57, 0.69, 0.43];
    for _ in 0..200 {
        let w = [dot(m[0], v), dot(m[1], v), dot(m[2], v)];
        let l = norm(w);
        if l <= 0.0 {
            return [0.0, 1.0, 0.0];
        }
        v = scale(w, 1.0 / l);
    }
    let big = (0..3)
        .max_by(|&a, &b| v[a].abs().total_cmp(&v[b].abs()))
        .unwrap_or(0);
    if v[big] < 0.0 { scale(v, -1.0) } else { v }
}

fn principal_axis_2d(uv: &[[f64; 2]]) -> [f64; 2] {
    let pts: Vec<[f64; 3]> = uv.iter().map(|q| [q[0], q[1], 0.0]).collect();
    let a = principal_axis(&pts);
    [a[0], a[1]]
}
