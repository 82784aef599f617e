//! The plane parameter domain: the loop's best-fit (PCA) plane as an orthonormal frame.

use flatcut_mesh::vec3::{add, cross, dist, dot, norm, scale, sub};

use super::join::LoopSeg;

/// An orthonormal frame: origin, two in-plane axes and the normal.
#[derive(Clone, Copy, Debug)]
pub(super) struct Frame {
    pub(super) c: [f64; 3],
    pub(super) e1: [f64; 3],
    pub(super) e2: [f64; 3],
    pub(super) n: [f64; 3],
}

impl Frame {
    /// The best-fit plane of the loop: principal axes of the segment-length-weighted
    /// covariance of the loop (so the result does not depend on how densely a side is sampled).
    pub(super) fn pca(segs: &[LoopSeg]) -> Frame {
        let mut w_sum = 0.0;
        let mut c = [0.0; 3];
        for s in segs {
            let w = dist(s.p0, s.p1);
            c = add(c, scale(add(s.p0, s.p1), 0.5 * w));
            w_sum += w;
        }
        let c = scale(c, 1.0 / w_sum);
        let mut m = [[0.0; 3]; 3];
        for s in segs {
            // Exact second moment of a uniform segment: (a a' + b b' + (a b' + b a')/2)/3 · len.
            let w = dist(s.p0, s.p1);
            let a = sub(s.p0, c);
            let b = sub(s.p1, c);
            for i in 0..3 {
                for j in 0..3 {
                    m[i][j] +=
                        w * (a[i] * a[j] + b[i] * b[j] + 0.5 * (a[i] * b[j] + b[i] * a[j])) / 3.0;
                }
            }
        }
        let (vals, vecs) = jacobi_eigen(m);
        let mut order = [0usize, 1, 2];
        order.sort_by(|&i, &j| vals[j].total_cmp(&vals[i]));
        let col = |k: usize| [vecs[0][k], vecs[1][k], vecs[2][k]];
        let e1 = col(order[0]);
        let n = normalize(cross(e1, col(order[1])));
        let e2 = cross(n, e1);
        Frame { c, e1, e2, n }
    }

    pub(super) fn flipped(self) -> Frame {
        Frame {
            c: self.c,
            e1: self.e2,
            e2: self.e1,
            n: scale(self.n, -1.0),
        }
    }

    pub(super) fn project(&self, p: [f64; 3]) -> [f64; 2] {
        let d = sub(p, self.c);
        [dot(d, self.e1), dot(d, self.e2)]
    }

    pub(super) fn height(&self, p: [f64; 3]) -> f64 {
        dot(sub(p, self.c), self.n)
    }

    pub(super) fn point(&self, q: [f64; 2], h: f64) -> [f64; 3] {
        add(
            self.c,
            add(
                add(scale(self.e1, q[0]), scale(self.e2, q[1])),
                scale(self.n, h),
            ),
        )
    }
}

fn normalize(a: [f64; 3]) -> [f64; 3] {
    let l = norm(a);
    if l > 0.0 { scale(a, 1.0 / l) } else { a }
}

/// Eigen-decomposition of a symmetric 3×3 matrix by cyclic Jacobi rotations: eigenvalues and
/// the eigenvectors as columns.
#[allow(clippy::needless_range_loop)] // index arithmetic mirrors the textbook rotation
fn jacobi_eigen(mut a: [[f64; 3]; 3]) -> ([f64; 3], [[f64; 3]; 3]) {
    let mut v = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    for _ in 0..50 {
        let off = a[0][1].abs() + a[0][2].abs() + a[1][2].abs();
        let scale_ = a[0][0].abs() + a[1][1].abs() + a[2][2].abs();
        if off <= 1e-15 * scale_ || off == 0.0 {
            break;
        }
        for (p, q) in [(0, 1), (0, 2), (1, 2)] {
            if a[p][q] == 0.0 {
                continue;
            }
            let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
            let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
            let t = if theta == 0.0 { 1.0 } else { t };
            let c = 1.0 / (t * t + 1.0).sqrt();
            let s = t * c;
            // A ← Jᵀ A J with J the rotation in the (p, q) plane.
            for k in 0..3 {
                let akp = a[k][p];
                let akq = a[k][q];
                a[k][p] = c * akp - s * akq;
                a[k][q] = s * akp + c * akq;
            }
            for k in 0..3 {
                let apk = a[p][k];
                let aqk = a[q][k];
                a[p][k] = c * apk - s * aqk;
                a[q][k] = s * apk + c * aqk;
            }
            for row in v.iter_mut() {
                let vp = row[p];
                let vq = row[q];
                row[p] = c * vp - s * vq;
                row[q] = s * vp + c * vq;
            }
        }
    }
    ([a[0][0], a[1][1], a[2][2]], v)
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    /// Jacobi: A v = λ v for each eigenpair and orthonormal vectors, on a full symmetric matrix.
    #[test]
    fn jacobi_eigenpairs() {
        let a = [[4.0, 1.0, -2.0], [1.0, 3.0, 0.5], [-2.0, 0.5, 1.0]];
        let (vals, vecs) = jacobi_eigen(a);
        for k in 0..3 {
            let v = [vecs[0][k], vecs[1][k], vecs[2][k]];
            let av = [0, 1, 2].map(|i| (0..3).map(|j| a[i][j] * v[j]).sum::<f64>());
            for i in 0..3 {
                assert!((av[i] - vals[k] * v[i]).abs() < 1e-12);
            }
            assert!((norm(v) - 1.0).abs() < 1e-12);
        }
        // Trace and determinant.
        assert!((vals.iter().sum::<f64>() - 8.0).abs() < 1e-12);
    }
}
