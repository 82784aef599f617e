//! Local–global as-rigid-as-possible parameterisation (Liu, Zhang, Xu, Gotsman, Gortler
//! 2008, "A local/global approach to mesh parameterization", the ARAP variant).
//!
//! E(u, R) = Σ_T Σ_{(i,j) ∈ T} w_ij^T ‖(u_i − u_j) − R_T (q_i^T − q_j^T)‖², with q^T the
//! triangle in its own frame and w_ij^T = ½ cot of the angle opposite (i, j) in T.
//! Local step: R_T = the rotation closest to S_T = Σ w (u_i − u_j)(q_i − q_j)ᵀ. Global step:
//! L u = b with L the cotangent Laplacian (one vertex fixed to remove translations) and
//! b_i = Σ_T Σ_j w_ij^T R_T (q_i − q_j). L depends only on the 3D shape, so its Cholesky
//! factorisation (symbolic and numeric) is computed once and every iteration is one
//! two-column solve.

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::LscmError;
use crate::lscm::PieceFlattening;
use crate::metrics::max_edge_strain;
use crate::triangle::{closest_rotation, local_frame, signed_area2};
use flatcut_sparse::SpdPattern;

/// Options of [`arap`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ArapOptions {
    /// Iteration limit. Default 100.
    pub max_iterations: usize,
    /// Stop when the ARAP energy decreases by less than this fraction of itself in one
    /// iteration (the edge-length error has then stopped improving in practice; ARAP
    /// converges linearly and slowly at the end, Gauss–Newton finishes). Default 1e-4.
    pub relative_tolerance: f64,
}

impl Default for ArapOptions {
    fn default() -> Self {
        Self {
            max_iterations: 100,
            relative_tolerance: 1e-4,
        }
    }
}

/// What [`arap`] did.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ArapReport {
    /// Iterations run.
    pub iterations: usize,
    /// ARAP energy (mm²) before and after.
    pub energy_before: f64,
    /// ARAP energy (mm²) after.
    pub energy_after: f64,
    /// Max |ℓ2D/ℓ3D − 1| after.
    pub max_edge_strain: f64,
    /// The last iteration had to shorten its step because the full step would have flipped
    /// more triangles than the start had (ARAP's energy does not prevent folds).
    pub stopped_by_fold: bool,
}

/// Step halvings tried before an iteration gives up (a step of 2⁻¹⁰ of the global step).
const MAX_HALVINGS: usize = 10;

/// Per-triangle data fixed by the 3D shape.
struct Tri {
    v: [u32; 3],
    q: [[f64; 2]; 3],
    /// w[k]: weight of the edge (v[k], v[k+1]) = ½ cot of the angle at v[k+2].
    w: [f64; 3],
}

/// Refines `p.uv` in place by local–global ARAP iterations, starting from the current
/// coordinates (normally LSCM). A step is kept only if it lowers the energy and flips no
/// more triangles than the start had, shortened by halving if needed (ARAP itself does not
/// prevent folds: on igl_camelhead, whose LSCM map shrinks the neck to a few percent of its
/// area, unguarded ARAP folded 748 faces).
pub fn arap(p: &mut PieceFlattening, opts: &ArapOptions) -> Result<ArapReport, LscmError> {
    let piece = &p.piece;
    let n = piece.positions.len();
    let tris: Vec<Tri> = piece
        .local_faces
        .iter()
        .map(|f| {
            let x = f.map(|v| piece.positions[v as usize]);
            let q = local_frame(x[0], x[1], x[2]);
            let mut w = [0.0; 3];
            for (k, wk) in w.iter_mut().enumerate() {
                let o = (k + 2) % 3;
                let a = [q[k][0] - q[o][0], q[k][1] - q[o][1]];
                let b = [q[(k + 1) % 3][0] - q[o][0], q[(k + 1) % 3][1] - q[o][1]];
                let cr = a[0] * b[1] - a[1] * b[0];
                *wk = 0.5 * (a[0] * b[0] + a[1] * b[1]) / cr;
            }
            Tri { v: *f, q, w }
        })
        .collect();
    let fixed = piece.vertices.binary_search(&p.pins[0]).unwrap_or(0);
    let mut index = vec![u32::MAX; n];
    let mut m = 0u32;
    for (v, slot) in index.iter_mut().enumerate() {
        if v != fixed {
            *slot = m;
            m += 1;
        }
    }
    let m = m as usize;
    let mut pairs = Vec::with_capacity(tris.len() * 6);
    let mut vals = Vec::with_capacity(tris.len() * 6);
    for t in &tris {
        for k in 0..3 {
            let (i, j) = (t.v[k] as usize, t.v[(k + 1) % 3] as usize);
            let w = t.w[k];
            for (a, b, s) in [(i, i, w), (j, j, w), (i, j, -w)] {
                let (ia, ib) = (index[a], index[b]);
                if ia != u32::MAX && ib != u32::MAX {
                    let (r, c) = (ia.max(ib) as usize, ia.min(ib) as usize);
                    pairs.push((r, c));
                    vals.push(s);
                }
            }
        }
    }
    let component = piece.component;
    let numerical = |cause| LscmError::Numerical {
        component,
        stage: "ARAP Laplacian",
        cause,
    };
    let pattern = SpdPattern::new(m, &pairs).map_err(numerical)?;
    let factor = pattern.factor(&vals).map_err(numerical)?;

    // The ARAP energy at u with its optimal rotations R(u): E(u, R(u)). Each iteration's
    // rotations serve both its energy and the next global step.
    let local = |uv: &[[f64; 2]]| -> (Vec<(f64, f64)>, f64) {
        let rots: Vec<(f64, f64)> = tris.par_iter().map(|t| rotation(t, uv)).collect();
        let e = tris
            .par_iter()
            .zip(&rots)
            .map(|(t, &r)| arap_triangle_energy(t, uv, r))
            .sum();
        (rots, e)
    };
    let flipped = |uv: &[[f64; 2]]| -> usize {
        tris.par_iter()
            .filter(|t| {
                let [a, b, c] = t.v.map(|v| uv[v as usize]);
                signed_area2(a, b, c) <= 0.0
            })
            .count()
    };
    let flipped_start = flipped(&p.uv);
    let mut stopped_by_fold = false;
    let (mut rots, energy_before) = local(&p.uv);
    let mut e_prev = energy_before;
    let mut iterations = 0;
    let mut rhs = vec![0.0; 2 * m];
    let mut uv = p.uv.clone();
    let u_fixed = p.uv[fixed];
    while iterations < opts.max_iterations {
        rhs.iter_mut().for_each(|x| *x = 0.0);
        for (t, &(c, s)) in tris.iter().zip(&rots) {
            for k in 0..3 {
                let (i, j) = (t.v[k] as usize, t.v[(k + 1) % 3] as usize);
                let w = t.w[k];
                let dq = [
                    t.q[k][0] - t.q[(k + 1) % 3][0],
                    t.q[k][1] - t.q[(k + 1) % 3][1],
                ];
                let rd = [c * dq[0] - s * dq[1], s * dq[0] + c * dq[1]];
                for (a, b, sign) in [(i, j, 1.0), (j, i, -1.0)] {
                    let ia = index[a];
                    if ia == u32::MAX {
                        continue;
                    }
                    rhs[ia as usize] += sign * w * rd[0];
                    rhs[m + ia as usize] += sign * w * rd[1];
                    if index[b] == u32::MAX {
                        rhs[ia as usize] += w * u_fixed[0];
                        rhs[m + ia as usize] += w * u_fixed[1];
                    }
                }
            }
        }
        factor.solve_in_place(&mut rhs, 2).map_err(numerical)?;
        let target: Vec<[f64; 2]> = (0..n)
            .map(|v| match index[v] {
                u32::MAX => uv[v],
                k => [rhs[k as usize], rhs[m + k as usize]],
            })
            .collect();
        iterations += 1;
        // The global step's direction is a descent direction of E(u, R(u)) (R is optimal at
        // the current u), so a step length t ≤ 1 that lowers the energy and adds no fold
        // exists unless the iteration has converged: halve t up to MAX_HALVINGS times.
        let mut accepted = None;
        let mut t = 1.0;
        for _ in 0..=MAX_HALVINGS {
            let trial: Vec<[f64; 2]> = uv
                .iter()
                .zip(&target)
                .map(|(a, b)| [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])])
                .collect();
            if flipped(&trial) <= flipped_start {
                let (trial_rots, e) = local(&trial);
                if e < e_prev {
                    accepted = Some((trial, trial_rots, e));
                    break;
                }
            } else {
                stopped_by_fold = true;
            }
            t *= 0.5;
        }
        let Some((next, next_rots, e)) = accepted else {
            break;
        };
        if t == 1.0 {
            stopped_by_fold = false;
        }
        uv = next;
        rots = next_rots;
        // A shortened step says nothing about convergence: only a full step may stop.
        let done = t == 1.0 && e_prev - e <= opts.relative_tolerance * e_prev;
        e_prev = e;
        if done {
            break;
        }
    }
    p.uv = uv;
    Ok(ArapReport {
        iterations,
        energy_before,
        energy_after: e_prev,
        max_edge_strain: max_edge_strain(&p.piece.positions, &p.piece.local_faces, &p.uv),
        stopped_by_fold,
    })
}

fn rotation(t: &Tri, uv: &[[f64; 2]]) -> (f64, f64) {
    let mut s = [[0.0; 2]; 2];
    for k in 0..3 {
        let (i, j) = (t.v[k] as usize, t.v[(k + 1) % 3] as usize);
        let du = [uv[i][0] - uv[j][0], uv[i][1] - uv[j][1]];
        let dq = [
            t.q[k][0] - t.q[(k + 1) % 3][0],
            t.q[k][1] - t.q[(k + 1) % 3][1],
        ];
        for a in 0..2 {
            for b in 0..2 {
                s[a][b] += t.w[k] * du[a] * dq[b];
            }
        }
    }
    closest_rotation(s)
}

fn arap_triangle_energy(t: &Tri, uv: &[[f64; 2]], (c, s): (f64, f64)) -> f64 {
    let mut e = 0.0;
    for k in 0..3 {
        let (i, j) = (t.v[k] as usize, t.v[(k + 1) % 3] as usize);
        let du = [uv[i][0] - uv[j][0], uv[i][1] - uv[j][1]];
        let dq = [
            t.q[k][0] - t.q[(k + 1) % 3][0],
            t.q[k][1] - t.q[(k + 1) % 3][1],
        ];
        let rd = [c * dq[0] - s * dq[1], s * dq[0] + c * dq[1]];
        e += t.w[k] * ((du[0] - rd[0]).powi(2) + (du[1] - rd[1]).powi(2));
    }
    e
}
