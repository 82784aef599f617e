//! θ(v), the summed corner angle at a vertex, and its exact gradient with respect to the
//! vertex and every one-ring neighbour (the paper's Eq. 4–5, derived in its ref. 37).
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
    (angle(sub(a, p), sub(b, p)), corner_gradient(p, a, b))
}

/// The gradients of [`corner_angle_gradient`] alone, without the angle (whose atan2 is the
/// expensive part): for points where θ is already known.
#[inline]
pub fn corner_gradient(p: [f64; 3], a: [f64; 3], b: [f64; 3]) -> [[f64; 3]; 3] {
    let [ga, gb] = corner_gradient_next_previous(sub(a, p), sub(b, p));
    let gp = [-(ga[0] + gb[0]), -(ga[1] + gb[1]), -(ga[2] + gb[2])];
    [gp, ga, gb]
}

/// ∂α/∂a and ∂α/∂b of a corner from its edges u = a − p and w = b − p (∂α/∂p is minus
/// their sum). Without branches, so that a loop over many corners vectorises: a degenerate
/// corner's values are computed and then replaced by zeros.
#[inline(always)]
pub fn corner_gradient_next_previous(u: [f64; 3], w: [f64; 3]) -> [[f64; 3]; 2] {
    let c = cross(u, w);
    let cn2 = norm2(c);
    let n = scale(c, 1.0 / cn2.sqrt());
    let ga = scale(cross(n, u), -1.0 / dot(u, u));
    let gb = scale(cross(w, n), -1.0 / dot(w, w));
    let defined = cn2 > 0.0 && cn2.is_finite();
    let pick = |g: [f64; 3]| if defined { g } else { [0.0; 3] };
    [pick(ga), pick(gb)]
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
