//! Per-triangle linear algebra shared by every stage: the triangle's own 2D frame, the
//! Jacobian of the 3D→2D affine map and its singular values.

use flatcut_mesh::vec3::{cross, dot, norm, normalize, sub};

/// Corner coordinates of a 3D triangle in its own orthonormal 2D frame: corner 0 at the
/// origin, corner 1 on +x, corner 2 with y ≥ 0. A counter-clockwise face (seen from its
/// normal) stays counter-clockwise, so a map that keeps this frame's orientation shows the
/// outside of the surface to a viewer looking down −z at the plane.
#[inline]
pub fn local_frame(p0: [f64; 3], p1: [f64; 3], p2: [f64; 3]) -> [[f64; 2]; 3] {
    let e1 = sub(p1, p0);
    let e2 = sub(p2, p0);
    let l1 = norm(e1);
    let x = normalize(e1);
    let n = cross(e1, e2);
    let y = normalize(cross(n, e1));
    [[0.0, 0.0], [l1, 0.0], [dot(e2, x), dot(e2, y)]]
}

/// Twice the signed area of a 2D triangle (positive when counter-clockwise).
#[inline]
pub fn signed_area2(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> f64 {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

/// The 2×2 Jacobian `J` (row-major `[[a, b], [c, d]]`) of the affine map taking the
/// triangle `q` (its own 2D frame) to `uv`: `uv_k − uv_0 = J (q_k − q_0)`. `None` if `q`
/// has zero area.
#[inline]
pub fn jacobian(q: [[f64; 2]; 3], uv: [[f64; 2]; 3]) -> Option<[[f64; 2]; 2]> {
    let (qx1, qy1) = (q[1][0] - q[0][0], q[1][1] - q[0][1]);
    let (qx2, qy2) = (q[2][0] - q[0][0], q[2][1] - q[0][1]);
    let det = qx1 * qy2 - qx2 * qy1;
    if det == 0.0 || !det.is_finite() {
        return None;
    }
    let (ux1, uy1) = (uv[1][0] - uv[0][0], uv[1][1] - uv[0][1]);
    let (ux2, uy2) = (uv[2][0] - uv[0][0], uv[2][1] - uv[0][1]);
    // J = U Q⁻¹ with Q = [q1 q2] (columns), Q⁻¹ = [[qy2, −qx2], [−qy1, qx1]] / det.
    let inv = [[qy2 / det, -qx2 / det], [-qy1 / det, qx1 / det]];
    Some([
        [
            ux1 * inv[0][0] + ux2 * inv[1][0],
            ux1 * inv[0][1] + ux2 * inv[1][1],
        ],
        [
            uy1 * inv[0][0] + uy2 * inv[1][0],
            uy1 * inv[0][1] + uy2 * inv[1][1],
        ],
    ])
}

/// Singular values σ₁ ≥ σ₂ ≥ 0 of a 2×2 matrix, in closed form: with
/// E = (a+d)/2, F = (a−d)/2, G = (c+b)/2, H = (c−b)/2, σ = √(E²+H²) ± √(F²+G²).
#[inline]
pub fn singular_values(j: [[f64; 2]; 2]) -> (f64, f64) {
    let [[a, b], [c, d]] = j;
    let e = 0.5 * (a + d);
    let f = 0.5 * (a - d);
    let g = 0.5 * (c + b);
    let h = 0.5 * (c - b);
    let q = e.hypot(h);
    let r = f.hypot(g);
    (q + r, (q - r).abs())
}

/// The rotation closest to a 2×2 matrix `s` in the Frobenius norm (its polar factor
/// restricted to det = +1), as (cos, sin). Used by the ARAP local step.
#[inline]
pub fn closest_rotation(s: [[f64; 2]; 2]) -> (f64, f64) {
    let [[a, b], [c, d]] = s;
    // argmax_θ tr(R(θ)ᵀ S) = atan2(c − b, a + d).
    let theta = (c - b).atan2(a + d);
    (theta.cos(), theta.sin())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_preserves_lengths_and_orientation() {
        let p = [[1.0, 2.0, 3.0], [4.0, 2.5, 3.5], [2.0, 5.0, 1.0]];
        let q = local_frame(p[0], p[1], p[2]);
        for (i, j) in [(0, 1), (1, 2), (2, 0)] {
            let l3 = norm(sub(p[j], p[i]));
            let l2 = (q[j][0] - q[i][0]).hypot(q[j][1] - q[i][1]);
            assert!((l3 - l2).abs() < 1e-12 * l3);
        }
        assert!(q[2][1] > 0.0);
    }

    #[test]
    fn singular_values_match_eigenvalues_of_jtj() {
        let j = [[1.3, -0.4], [0.7, 2.1]];
        let (s1, s2) = singular_values(j);
        // Eigenvalues of JᵀJ from trace and determinant: a second, independent formula.
        let ata = [
            j[0][0] * j[0][0] + j[1][0] * j[1][0],
            j[0][0] * j[0][1] + j[1][0] * j[1][1],
            j[0][1] * j[0][1] + j[1][1] * j[1][1],
        ];
        let tr = ata[0] + ata[2];
        let det = ata[0] * ata[2] - ata[1] * ata[1];
        let disc = (tr * tr / 4.0 - det).sqrt();
        assert!((s1 * s1 - (tr / 2.0 + disc)).abs() < 1e-12);
        assert!((s2 * s2 - (tr / 2.0 - disc)).abs() < 1e-12);
    }

    #[test]
    fn closest_rotation_recovers_a_rotation() {
        let t: f64 = 0.83;
        let (c, s) = (t.cos(), t.sin());
        let (rc, rs) = closest_rotation([[2.0 * c, -2.0 * s], [2.0 * s, 2.0 * c]]);
        assert!((rc - c).abs() < 1e-14 && (rs - s).abs() < 1e-14);
    }
}
