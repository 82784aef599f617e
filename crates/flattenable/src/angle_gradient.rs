//! θ(v), the summed corner angle at a vertex, and its exact gradient with respect to the
//! vertex and every one-ring neighbour (the paper's Eq. 4–5, derived in its ref. [37]).
//!
//! For the corner at `p` of a triangle (p, a, b) with u = a − p, w = b − p, unit normal
//! n = u × w / |u × w| and angle α = atan2(|u × w|, u · w):
//!
//! ∂α/∂a = −(n × u) / |u|²,   ∂α/∂b = −(w × n) / |w|²,   ∂α/∂p = −(∂α/∂a + ∂α/∂b).
//!
//! (Moving `a` towards `w` inside the plane closes the angle at the rate 1/|u|; motion along
//! u or n does not change α to first order.) θ(v_p) = Σ α over the faces at p, so its
//! gradient is the sum of these terms over the fan.

use flatcut_mesh::vec3::{angle, cross, dot, norm2, scale, sub};
use flatcut_mesh::{Topology, VertexId};

/// The corner angle at `p` of the triangle (p, a, b) and its gradients with respect to
/// `p`, `a` and `b` (in that order). Degenerate corners (|u × w| = 0) get zero gradients:
/// the angle is not differentiable there and callers reject such geometry beforehand.
#[inline]
pub fn corner_angle_gradient(p: [f64; 3], a: [f64; 3], b: [f64; 3]) -> (f64, [[f64; 3]; 3]) {
    let u = sub(a, p);
    let w = sub(b, p);
    let c = cross(u, w);
    let cn2 = norm2(c);
    let alpha = angle(u, w);
    if cn2 <= 0.0 || !cn2.is_finite() {
        return (alpha, [[0.0; 3]; 3]);
    }
    let n = scale(c, 1.0 / cn2.sqrt());
    let ga = scale(cross(n, u), -1.0 / dot(u, u));
    let gb = scale(cross(w, n), -1.0 / dot(w, w));
    let gp = [-(ga[0] + gb[0]), -(ga[1] + gb[1]), -(ga[2] + gb[2])];
    (alpha, [gp, ga, gb])
}

/// θ(v) and its gradient: `(θ, [(vertex, ∂θ/∂vertex)])`, the first entry being `v` itself
/// followed by its one-ring in [`Topology::one_ring`] order. Works for boundary vertices
/// too (θ is then the sum over the open fan). `v` must be a manifold vertex with faces;
/// otherwise `(0, [])`.
pub fn angle_sum_gradient(
    positions: &[[f64; 3]],
    faces: &[[u32; 3]],
    topo: &Topology,
    v: VertexId,
) -> (f64, Vec<(VertexId, [f64; 3])>) {
    let Some(ring) = topo.one_ring(v) else {
        return (0.0, Vec::new());
    };
    let mut out: Vec<(VertexId, [f64; 3])> = Vec::with_capacity(ring.len() + 1);
    out.push((v, [0.0; 3]));
    out.extend(ring.iter().map(|&q| (VertexId(q), [0.0; 3])));
    let mut theta = 0.0;
    for &h in topo.outgoing(v) {
        let f = faces[Topology::face(h).idx()];
        let k = (h % 3) as usize;
        let (a, b) = (f[(k + 1) % 3], f[(k + 2) % 3]);
        let (alpha, g) = corner_angle_gradient(
            positions[v.idx()],
            positions[a as usize],
            positions[b as usize],
        );
        theta += alpha;
        for (vert, gk) in [(v.0, g[0]), (a, g[1]), (b, g[2])] {
            if let Some(slot) = out.iter_mut().find(|(q, _)| q.0 == vert) {
                for c in 0..3 {
                    slot.1[c] += gk[c];
                }
            }
        }
    }
    (theta, out)
}

/// Sum of the corner angles of a fan with one `atan2` per vertex instead of one per corner
/// (the `atan2` calls were a fifth of the robust mode's time on a 3.5k-face piece).
///
/// Each corner contributes the complex number c + i s with c = u · w and s = |u × w|
/// (argument α, modulus |u| |w|); their product has argument θ modulo 2π, to round-off of
/// the same order as summing `atan2`s. The multiple of 2π comes from a cheap estimate of
/// every α (error < 4e-3 rad per corner, so the estimate is within π of θ up to valence
/// 700): θ = arg z + 2π · round((θ_estimate − arg z) / 2π).
#[derive(Clone, Copy, Debug)]
pub struct AngleSum {
    re: f64,
    im: f64,
    estimate: f64,
}

impl Default for AngleSum {
    fn default() -> Self {
        Self {
            re: 1.0,
            im: 0.0,
            estimate: 0.0,
        }
    }
}

/// The product is rescaled when its modulus leaves [1/RESCALE, RESCALE], far inside the
/// f64 range (a fan of many tiny or huge edges would otherwise under- or overflow).
const RESCALE: f64 = 1e100;

impl AngleSum {
    /// Adds the corner with c = u · w and s = |u × w| (s ≥ 0).
    #[inline]
    pub fn add(&mut self, c: f64, s: f64) {
        self.estimate += approx_angle(c, s);
        let re = self.re * c - self.im * s;
        let im = self.re * s + self.im * c;
        let m = re.abs().max(im.abs());
        if !(1.0 / RESCALE..=RESCALE).contains(&m) {
            // m = 0 (a zero-length edge) stays 0 and is caught in `finish`.
            let k = if m > 0.0 { 1.0 / m } else { 1.0 };
            self.re = re * k;
            self.im = im * k;
        } else {
            self.re = re;
            self.im = im;
        }
    }

    /// θ, or `None` when a corner was degenerate (a zero-length edge: the product lost its
    /// argument; the caller then sums `atan2`s). NaN input gives NaN.
    #[inline]
    pub fn finish(self) -> Option<f64> {
        if self.re == 0.0 && self.im == 0.0 {
            return None;
        }
        let a = self.im.atan2(self.re);
        Some(a + std::f64::consts::TAU * ((self.estimate - a) / std::f64::consts::TAU).round())
    }
}

/// atan2(s, c) for s ≥ 0 to within 4e-3 rad (atan x ≈ π/4 x + 0.273 x (1 − x) on [0, 1]);
/// only used to count whole turns.
#[inline]
fn approx_angle(c: f64, s: f64) -> f64 {
    use std::f64::consts::{FRAC_PI_2, FRAC_PI_4, PI};
    let atan01 = |x: f64| x * (FRAC_PI_4 + 0.273 * (1.0 - x));
    let ac = c.abs();
    let first = if s <= ac {
        if ac > 0.0 { atan01(s / ac) } else { 0.0 }
    } else {
        FRAC_PI_2 - atan01(ac / s)
    };
    if c >= 0.0 { first } else { PI - first }
}

/// Corner terms at `p` of the triangle (p, a, b): c = u · w, s = |u × w| and the
/// gradients of the angle with respect to p, a and b (as [`corner_angle_gradient`], whose
/// angle is atan2(s, c)).
#[inline]
pub fn corner_terms(p: [f64; 3], a: [f64; 3], b: [f64; 3]) -> (f64, f64, [[f64; 3]; 3]) {
    let u = sub(a, p);
    let w = sub(b, p);
    let cr = cross(u, w);
    let cn2 = norm2(cr);
    let c = dot(u, w);
    if cn2 <= 0.0 || !cn2.is_finite() {
        return (c, cn2.sqrt(), [[0.0; 3]; 3]);
    }
    let s = cn2.sqrt();
    let n = scale(cr, 1.0 / s);
    let ga = scale(cross(n, u), -1.0 / dot(u, u));
    let gb = scale(cross(w, n), -1.0 / dot(w, w));
    let gp = [-(ga[0] + gb[0]), -(ga[1] + gb[1]), -(ga[2] + gb[2])];
    (c, s, [gp, ga, gb])
}
