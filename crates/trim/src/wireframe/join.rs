//! Joining the boundary curves end to end into one closed loop, and checking that the loop
//! does not touch itself in 3D.

use flatcut_mesh::vec3::{add, dist, dot, scale, sub};

use super::{TOUCH_RELATIVE, VertexOrigin, WireCurve, WireframeError};

/// A segment of the joined loop, as a segment of an input curve.
#[derive(Clone, Copy, Debug)]
pub(super) struct LoopSeg {
    /// Start point (3D, mm).
    pub(super) p0: [f64; 3],
    /// End point.
    pub(super) p1: [f64; 3],
    /// The input curve.
    pub(super) curve: usize,
    /// The curve's point index at `p0` and at `p1`.
    pub(super) i0: usize,
    pub(super) i1: usize,
}

/// Joins the curves end to end into one closed loop of segments; returns the largest gap
/// closed. A curve is used forwards or reversed, whichever end is nearest the loop's end.
pub(super) fn join_loop(
    curves: &[WireCurve],
    tol: f64,
) -> Result<(Vec<LoopSeg>, f64), WireframeError> {
    let segs_of = |ci: usize, reversed: bool| -> Vec<LoopSeg> {
        let p = &curves[ci].points;
        let n = p.len();
        (0..n - 1)
            .map(|k| {
                let (i0, i1) = if reversed {
                    (n - 1 - k, n - 2 - k)
                } else {
                    (k, k + 1)
                };
                LoopSeg {
                    p0: p[i0],
                    p1: p[i1],
                    curve: ci,
                    i0,
                    i1,
                }
            })
            .collect()
    };
    let mut segs = segs_of(0, false);
    let mut used = vec![false; curves.len()];
    used[0] = true;
    let mut max_gap: f64 = 0.0;
    let first = curves[0].points[0];
    for _ in 1..curves.len() {
        let end = segs.last().map_or(first, |s| s.p1);
        let last_curve = segs.last().map_or(0, |s| s.curve);
        // Nearest free end.
        let mut best: Option<(f64, usize, bool)> = None;
        for (ci, c) in curves.iter().enumerate() {
            if used[ci] {
                continue;
            }
            for (rev, p) in [(false, c.points[0]), (true, c.points[c.points.len() - 1])] {
                let d = dist(end, p);
                if best.is_none_or(|b| d < b.0) {
                    best = Some((d, ci, rev));
                }
            }
        }
        let Some((gap, ci, rev)) = best else { break };
        if gap > tol {
            return Err(WireframeError::CurvesDoNotJoin {
                curve: curves[last_curve].name.clone(),
                end,
                nearest: curves[ci].name.clone(),
                gap_mm: gap,
                tolerance_mm: tol,
            });
        }
        max_gap = max_gap.max(gap);
        used[ci] = true;
        let mut more = segs_of(ci, rev);
        // The junction point is the earlier curve's end (the gap ≤ tol is closed here).
        more[0].p0 = end;
        segs.extend(more);
    }
    let (last, end) = segs.last().map(|s| (s.curve, s.p1)).unwrap_or((0, first));
    let gap = dist(end, first);
    if gap > tol {
        return Err(WireframeError::LoopNotClosed {
            first: curves[0].name.clone(),
            last: curves[last].name.clone(),
            gap_mm: gap,
            tolerance_mm: tol,
        });
    }
    max_gap = max_gap.max(gap);
    // The closing point is the start point: drop the duplicate by ending the last segment there.
    if let Some(s) = segs.last_mut() {
        s.p1 = first;
    }
    if segs.len() < 3 {
        return Err(WireframeError::TooFewPoints {
            what: "curve",
            name: curves[0].name.clone(),
            points: segs.len(),
            needed: 3,
        });
    }
    // A zero-length closing segment (a closed curve that repeats its first point within the
    // tolerance, but after the join the point is the same): drop it.
    if dist(segs[segs.len() - 1].p0, segs[segs.len() - 1].p1) == 0.0 {
        segs.pop();
    }
    Ok((segs, max_gap))
}

/// Errors if two non-adjacent loop segments come closer than the join tolerance in 3D.
pub(super) fn check_loop_in_3d(
    segs: &[LoopSeg],
    curves: &[WireCurve],
    diag: f64,
    tol: f64,
) -> Result<(), WireframeError> {
    let n = segs.len();
    let limit = tol.max(TOUCH_RELATIVE * diag);
    let boxes: Vec<([f64; 3], [f64; 3])> = segs
        .iter()
        .map(|s| {
            let lo = [0, 1, 2].map(|k| s.p0[k].min(s.p1[k]) - limit);
            let hi = [0, 1, 2].map(|k| s.p0[k].max(s.p1[k]) + limit);
            (lo, hi)
        })
        .collect();
    for a in 0..n {
        for b in a + 2..n {
            if a == 0 && b == n - 1 {
                continue;
            }
            let (la, ha) = boxes[a];
            let (lb, hb) = boxes[b];
            if (0..3).any(|k| la[k] > hb[k] || lb[k] > ha[k]) {
                continue;
            }
            let d = segment_distance(segs[a].p0, segs[a].p1, segs[b].p0, segs[b].p1);
            if d < limit {
                return Err(WireframeError::LoopTouchesItself {
                    curve_a: curves[segs[a].curve].name.clone(),
                    point_a: segs[a].i0,
                    curve_b: curves[segs[b].curve].name.clone(),
                    point_b: segs[b].i0,
                    gap_mm: d,
                });
            }
        }
    }
    Ok(())
}

/// Distance between two 3D segments (clamped closest points, Ericson §5.1.9).
pub(super) fn segment_distance(p1: [f64; 3], q1: [f64; 3], p2: [f64; 3], q2: [f64; 3]) -> f64 {
    let d1 = sub(q1, p1);
    let d2 = sub(q2, p2);
    let r = sub(p1, p2);
    let a = dot(d1, d1);
    let e = dot(d2, d2);
    let f = dot(d2, r);
    let c = dot(d1, r);
    let b = dot(d1, d2);
    let denom = a * e - b * b;
    let mut s = if denom > 0.0 {
        ((b * f - c * e) / denom).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let mut t = (b * s + f) / e;
    if t < 0.0 {
        t = 0.0;
        s = (-c / a).clamp(0.0, 1.0);
    } else if t > 1.0 {
        t = 1.0;
        s = ((b - c) / a).clamp(0.0, 1.0);
    }
    dist(add(p1, scale(d1, s)), add(p2, scale(d2, t)))
}

/// The loop segment nearest to `p` and the parameter of the closest point on it, if
/// within `tol`.
pub(super) fn nearest_on_loop(segs: &[LoopSeg], p: [f64; 3], tol: f64) -> Option<(usize, f64)> {
    let mut best: Option<(f64, usize, f64)> = None;
    for (i, s) in segs.iter().enumerate() {
        let ab = sub(s.p1, s.p0);
        let t = (dot(sub(p, s.p0), ab) / dot(ab, ab)).clamp(0.0, 1.0);
        let d = dist(p, add(s.p0, scale(ab, t)));
        if d <= tol && best.is_none_or(|b| d < b.0) {
            best = Some((d, i, t));
        }
    }
    best.map(|(_, i, t)| (i, t))
}

pub(super) fn on_curve(s: &LoopSeg, t: f64) -> VertexOrigin {
    // Report the parameter from the curve's own lower-numbered point.
    if s.i1 > s.i0 {
        VertexOrigin::OnCurve {
            curve: s.curve,
            segment: s.i0,
            t,
        }
    } else {
        VertexOrigin::OnCurve {
            curve: s.curve,
            segment: s.i1,
            t: 1.0 - t,
        }
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    #[test]
    fn segment_distances() {
        // Skew 3D segments: closest points at their interiors, distance 1.
        let d = segment_distance(
            [-1.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, -1.0, 1.0],
            [0.0, 1.0, 1.0],
        );
        assert!((d - 1.0).abs() < 1e-15);
        // Parallel, offset along the line: end to end.
        let d = segment_distance([0.0; 3], [1.0, 0.0, 0.0], [3.0, 4.0, 0.0], [5.0, 4.0, 0.0]);
        assert!((d - (4.0f64 + 16.0).sqrt()).abs() < 1e-15);
    }
}
