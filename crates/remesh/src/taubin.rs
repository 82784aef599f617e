//! Taubin λ|μ smoothing (G. Taubin, "A signal processing approach to fair surface design",
//! SIGGRAPH 1995): each step moves every free vertex by λ times its umbrella vector (the
//! mean of its neighbours minus itself), then by μ times the new one, with μ < −λ < 0. The
//! pair is a low-pass filter: f(k) = (1 − λk)(1 − μk) for an eigenvalue k ∈ [0, 2] of the
//! uniform Laplacian is ≈ 1 below the pass-band frequency k_PB = 1/λ + 1/μ and small above
//! it, so scan noise (high k) goes while the shape (low k) stays — plain Laplacian smoothing
//! (μ = 0) shrinks the shape too.

use flatcut_mesh::TriMesh;

/// λ of the shrinking half-step (Taubin's example value).
pub const TAUBIN_LAMBDA: f64 = 0.5;
/// μ of the inflating half-step: k_PB = 1/λ + 1/μ ≈ 0.113, a pass band of wavelengths longer
/// than about 2π/√0.113 ≈ 19 edges on a regular grid.
pub const TAUBIN_MU: f64 = -0.53;

/// Applies `steps` λ|μ steps to the vertices of `mesh` that are not `fixed` (fixed ones keep
/// their positions bit for bit; vertices without neighbours stay too). Jacobi updates (every
/// vertex from the previous positions), so the result does not depend on vertex order.
pub fn taubin_smooth(mesh: &mut TriMesh, fixed: &[bool], steps: usize) {
    let n = mesh.positions.len();
    // Unique neighbours per vertex (CSR), from the faces.
    let mut pairs: Vec<(u32, u32)> = Vec::with_capacity(mesh.faces.len() * 6);
    for f in &mesh.faces {
        for k in 0..3 {
            let (a, b) = (f[k], f[(k + 1) % 3]);
            pairs.push((a, b));
            pairs.push((b, a));
        }
    }
    pairs.sort_unstable();
    pairs.dedup();
    let mut offset = vec![0usize; n + 1];
    for &(a, _) in &pairs {
        offset[a as usize + 1] += 1;
    }
    for v in 0..n {
        offset[v + 1] += offset[v];
    }
    let adj: Vec<u32> = pairs.iter().map(|&(_, b)| b).collect();
    let movable = |v: usize| !fixed.get(v).copied().unwrap_or(false) && offset[v + 1] > offset[v];
    let mut next = mesh.positions.clone();
    for _ in 0..steps {
        for factor in [TAUBIN_LAMBDA, TAUBIN_MU] {
            let pos = &mesh.positions;
            for (v, out) in next.iter_mut().enumerate() {
                if !movable(v) {
                    continue;
                }
                let ring = &adj[offset[v]..offset[v + 1]];
                let inv = 1.0 / ring.len() as f64;
                let mut mean = [0.0; 3];
                for &u in ring {
                    for (m, c) in mean.iter_mut().zip(pos[u as usize]) {
                        *m += c * inv;
                    }
                }
                for k in 0..3 {
                    out[k] = pos[v][k] + factor * (mean[k] - pos[v][k]);
                }
            }
            std::mem::swap(&mut mesh.positions, &mut next);
            // `next` now holds the previous positions; fixed vertices are equal in both.
        }
    }
}
