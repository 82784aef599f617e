//! Small geometric helpers of the wire-frame surface: polygons in the domain, segment
//! distances, bounding boxes.

use flatcut_mesh::vec3::dist;

pub(super) fn signed_area(p: &[[f64; 2]]) -> f64 {
    let n = p.len();
    0.5 * (0..n)
        .map(|i| {
            let a = p[i];
            let b = p[(i + 1) % n];
            a[0] * b[1] - a[1] * b[0]
        })
        .sum::<f64>()
}

pub(super) fn bbox2(p: &[[f64; 2]]) -> ([f64; 2], [f64; 2]) {
    let mut lo = [f64::INFINITY; 2];
    let mut hi = [f64::NEG_INFINITY; 2];
    for q in p {
        for k in 0..2 {
            lo[k] = lo[k].min(q[k]);
            hi[k] = hi[k].max(q[k]);
        }
    }
    (lo, hi)
}

pub(super) fn diagonal(points: impl Iterator<Item = [f64; 3]>) -> f64 {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in points {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let d = dist(lo, hi);
    if d.is_finite() { d } else { 0.0 }
}

pub(super) fn lerp3(a: [f64; 3], b: [f64; 3], t: f64) -> [f64; 3] {
    [0, 1, 2].map(|k| a[k] + t * (b[k] - a[k]))
}

pub(super) fn dist2(a: [f64; 2], b: [f64; 2]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)).sqrt()
}

pub(super) fn cross2(o: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
}

/// Distance between two 2D segments (0 if they cross).
pub(super) fn segment_distance_2d(a: [f64; 2], b: [f64; 2], c: [f64; 2], d: [f64; 2]) -> f64 {
    let d1 = cross2(a, b, c);
    let d2 = cross2(a, b, d);
    let d3 = cross2(c, d, a);
    let d4 = cross2(c, d, b);
    if ((d1 > 0.0 && d2 < 0.0) || (d1 < 0.0 && d2 > 0.0))
        && ((d3 > 0.0 && d4 < 0.0) || (d3 < 0.0 && d4 > 0.0))
    {
        return 0.0;
    }
    let pt = |p: [f64; 2], s0: [f64; 2], s1: [f64; 2]| {
        let v = [s1[0] - s0[0], s1[1] - s0[1]];
        let l2 = v[0] * v[0] + v[1] * v[1];
        let t = if l2 > 0.0 {
            (((p[0] - s0[0]) * v[0] + (p[1] - s0[1]) * v[1]) / l2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        dist2(p, [s0[0] + t * v[0], s0[1] + t * v[1]])
    };
    pt(a, c, d)
        .min(pt(b, c, d))
        .min(pt(c, a, b))
        .min(pt(d, a, b))
}

/// The first pair of non-adjacent segments of the closed polygon closer than `tol`, if any
/// (also catches a projection that folds back onto an adjacent segment).
pub(super) fn first_crossing(p: &[[f64; 2]], tol: f64) -> Option<(usize, usize)> {
    let n = p.len();
    let seg = |i: usize| (p[i], p[(i + 1) % n]);
    // Adjacent segments folding back onto each other (an angle of ~0 between them).
    for i in 0..n {
        let (a, b) = seg(i);
        let c = p[(i + 2) % n];
        let u = [b[0] - a[0], b[1] - a[1]];
        let w = [c[0] - b[0], c[1] - b[1]];
        let lu = (u[0] * u[0] + u[1] * u[1]).sqrt();
        let lw = (w[0] * w[0] + w[1] * w[1]).sqrt();
        if lu <= tol || lw <= tol {
            return Some((i, (i + 1) % n));
        }
        let sin = (u[0] * w[1] - u[1] * w[0]) / (lu * lw);
        let cos = (u[0] * w[0] + u[1] * w[1]) / (lu * lw);
        if cos < 0.0 && sin.abs() < 1e-9 {
            return Some((i, (i + 1) % n));
        }
    }
    let boxes: Vec<([f64; 2], [f64; 2])> = (0..n)
        .map(|i| {
            let (a, b) = seg(i);
            (
                [a[0].min(b[0]) - tol, a[1].min(b[1]) - tol],
                [a[0].max(b[0]) + tol, a[1].max(b[1]) + tol],
            )
        })
        .collect();
    for i in 0..n {
        for j in i + 2..n {
            if i == 0 && j == n - 1 {
                continue;
            }
            let (la, ha) = boxes[i];
            let (lb, hb) = boxes[j];
            if la[0] > hb[0] || lb[0] > ha[0] || la[1] > hb[1] || lb[1] > ha[1] {
                continue;
            }
            let (a, b) = seg(i);
            let (c, d) = seg(j);
            if segment_distance_2d(a, b, c, d) <= tol {
                return Some((i, j));
            }
        }
    }
    None
}

pub(super) fn point_in_polygon(q: [f64; 2], poly: &[[f64; 2]]) -> bool {
    let n = poly.len();
    let mut inside = false;
    let mut j = n - 1;
    for i in 0..n {
        let (a, b) = (poly[i], poly[j]);
        if (a[1] > q[1]) != (b[1] > q[1]) {
            let x = a[0] + (q[1] - a[1]) / (b[1] - a[1]) * (b[0] - a[0]);
            if q[0] < x {
                inside = !inside;
            }
        }
        j = i;
    }
    inside
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    #[test]
    fn segment_distances_2d() {
        // Crossing and apart.
        assert_eq!(
            segment_distance_2d([0.0, 0.0], [2.0, 2.0], [0.0, 2.0], [2.0, 0.0]),
            0.0
        );
        assert!(
            (segment_distance_2d([0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]) - 1.0).abs()
                < 1e-15
        );
    }
}
