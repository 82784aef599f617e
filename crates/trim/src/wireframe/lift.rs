//! The harmonic lift: boundary and guide vertices at their 3D points, the interior solving
//! the cotan Laplace equation of the domain triangulation (flatcut_sparse's Cholesky).

use flatcut_sparse::Triplets;

use super::WireframeError;
use super::domain::Frame;

/// Cotan weights of the domain triangulation: (i, j, w_ij) per face corner, w = cot/2.
fn cotan_entries(domain: &[[f64; 2]], faces: &[[u32; 3]]) -> Vec<(usize, usize, f64)> {
    let mut out = Vec::with_capacity(faces.len() * 3);
    for f in faces {
        for k in 0..3 {
            let o = domain[f[k] as usize];
            let a = domain[f[(k + 1) % 3] as usize];
            let b = domain[f[(k + 2) % 3] as usize];
            let u = [a[0] - o[0], a[1] - o[1]];
            let v = [b[0] - o[0], b[1] - o[1]];
            let cr = (u[0] * v[1] - u[1] * v[0]).abs();
            let dt = u[0] * v[0] + u[1] * v[1];
            let cot = if cr > 0.0 { dt / cr } else { 0.0 };
            out.push((f[(k + 1) % 3] as usize, f[(k + 2) % 3] as usize, 0.5 * cot));
        }
    }
    out
}

/// Harmonic lift: fixed vertices at their 3D points, the rest solves the cotan Laplace
/// equation of the domain. Plane domain: heights only (in-plane = the domain position).
pub(super) fn lift(
    domain: &[[f64; 2]],
    faces: &[[u32; 3]],
    fixed: &[Option<[f64; 3]>],
    mode: Lift,
) -> Result<Vec<[f64; 3]>, WireframeError> {
    let n = domain.len();
    let mut unknown = vec![usize::MAX; n];
    let mut m = 0;
    for i in 0..n {
        if fixed[i].is_none() {
            unknown[i] = m;
            m += 1;
        }
    }
    // Fixed values per channel.
    let channels = match mode {
        Lift::Height(_) => 1,
        Lift::Xyz => 3,
    };
    let value = |i: usize, c: usize| -> f64 {
        let p = fixed[i].unwrap_or([0.0; 3]);
        match mode {
            Lift::Height(frame) => frame.height(p),
            Lift::Xyz => p[c],
        }
    };
    let mut sol = vec![0.0; m * channels];
    if m > 0 {
        let mut laplacian = Triplets::with_capacity(m, 9 * faces.len());
        for (i, j, w) in cotan_entries(domain, faces) {
            let (ui, uj) = (unknown[i], unknown[j]);
            if ui != usize::MAX {
                laplacian.push(ui, ui, w);
            }
            if uj != usize::MAX {
                laplacian.push(uj, uj, w);
            }
            match (ui != usize::MAX, uj != usize::MAX) {
                (true, true) => laplacian.push(ui, uj, -w),
                (true, false) => {
                    for c in 0..channels {
                        sol[c * m + ui] += w * value(j, c);
                    }
                }
                (false, true) => {
                    for c in 0..channels {
                        sol[c * m + uj] += w * value(i, c);
                    }
                }
                (false, false) => {}
            }
        }
        let pattern = laplacian.pattern().map_err(WireframeError::LiftSolve)?;
        let factor = pattern
            .factor(laplacian.values())
            .map_err(WireframeError::LiftSolve)?;
        factor
            .solve_in_place(&mut sol, channels)
            .map_err(WireframeError::LiftSolve)?;
    }
    Ok((0..n)
        .map(|i| match fixed[i] {
            Some(p) => p,
            None => {
                let u = unknown[i];
                match mode {
                    Lift::Height(frame) => frame.point(domain[i], sol[u]),
                    Lift::Xyz => [sol[u], sol[m + u], sol[2 * m + u]],
                }
            }
        })
        .collect())
}

/// What the harmonic lift solves for.
#[derive(Clone, Copy, Debug)]
pub(super) enum Lift {
    /// The domain is the orthogonal projection to this frame's plane: in-plane coordinates
    /// are the domain position, only the height is solved.
    Height(Frame),
    /// All three coordinates are harmonic functions on the domain.
    Xyz,
}
