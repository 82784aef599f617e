//! The cut line: the sew line offset outward by the seam allowance, with per-edge widths and
//! per-corner rules (docs/algorithms/seam_allowance.md).
//!
//! The allowance region is built as a union of simple convex pieces, each counter-clockwise:
//! the sew polygon itself, one strip per edge (the edge swept outward by its own width), and at
//! every convex vertex a corner piece chosen by its rule. The union is taken by i_overlay
//! (non-zero fill, its default 32-bit integer grid: about 1e-6 mm on a 2 m piece) and its outer contour is the cut line. Reflex vertices
//! need no corner piece: the neighbouring strips overlap and the union's boundary turns exactly
//! where the two offset lines cross. Near-touching parts of the outline simply merge in the
//! union, as a true offset does.

use i_overlay::core::fill_rule::FillRule;
use i_overlay::float::simplify::SimplifyShape;
use serde::Deserialize;

use crate::geom::{
    add, cross, dist, dot, line_intersection, norm, reflect, right_normal, scale, signed_area, sub,
    unit,
};

/// Largest distance (mm) between a round join's arc and its chords: 1 µm, ten times below the
/// 0.01 mm the cut line is held to.
pub const ARC_SAGITTA_MM: f64 = 0.001;
/// Points of the sew line closer than this (mm) are one point: below any cutter's resolution.
pub const DUPLICATE_POINT_MM: f64 = 1e-7;
/// A mirrored corner whose construction reaches farther than this many allowances from the
/// vertex (the fold line nearly parallel to the seam) falls back to a mitre.
pub const MIRROR_REACH: f64 = 4.0;

/// How the allowance is closed at a corner of the sew line (a convex vertex turning by at
/// least `corner_angle_rad`; gentler vertices are always joined round, which is the exact
/// parallel curve).
#[derive(Clone, Copy, Debug, PartialEq, Deserialize, serde::Serialize)]
#[serde(rename_all = "kebab-case", deny_unknown_fields)]
pub enum CornerRule {
    /// The two offset lines are extended until they meet; when that point lies farther than
    /// `limit` × the larger width from the vertex, the point is cut off square to the corner's
    /// bisector at that distance (`limit` ≥ 1, no unit).
    Miter {
        /// Mitre limit, in allowance widths (default 2).
        limit: f64,
    },
    /// The corner is cut off square to its bisector at one allowance width from the vertex
    /// (a mitre with limit 1).
    Square,
    /// A circular arc of the allowance radius about the vertex (the exact offset).
    Round,
    /// For darts and hems: the allowance beyond the fold edge (the dart leg or hem line) ends
    /// on the mirror image, about that edge, of the other edge's cut line, so the allowance
    /// lies flat and matches when the dart is closed or the hem turned up.
    Mirrored,
}

impl Default for CornerRule {
    fn default() -> Self {
        CornerRule::Miter { limit: 2.0 }
    }
}

/// The rule at one vertex of the sew line, resolved by the caller.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CornerSpec {
    /// The rule.
    pub rule: CornerRule,
    /// For [`CornerRule::Mirrored`]: the fold edge is the outgoing edge (`true`) or the
    /// incoming one (`false`).
    pub fold_next: bool,
}

/// The cut line around a counter-clockwise sew loop.
///
/// `widths_mm[i]` is the allowance of edge `sew[i] → sew[i+1]` (the last edge closes the loop),
/// `corners[i]` the rule at vertex `i`, applied when the loop turns left there by at least
/// `corner_angle_rad`. Returns the cut line, counter-clockwise, or `None` when the union is
/// empty (which a valid outline never gives).
pub fn seam_allowance(
    sew: &[[f64; 2]],
    widths_mm: &[f64],
    corners: &[CornerSpec],
    corner_angle_rad: f64,
) -> Option<Vec<[f64; 2]>> {
    // Drop repeated points, keeping the width of the edge that leaves each kept point.
    let mut pts: Vec<([f64; 2], f64, CornerSpec)> = Vec::with_capacity(sew.len());
    for i in 0..sew.len() {
        let next = sew[(i + 1) % sew.len()];
        if dist(sew[i], next) > DUPLICATE_POINT_MM {
            pts.push((sew[i], widths_mm[i], corners[i]));
        }
    }
    let n = pts.len();
    if n < 3 {
        return None;
    }
    let mut pieces: Vec<Vec<[f64; 2]>> = Vec::with_capacity(2 * n + 1);
    pieces.push(ccw(pts.iter().map(|p| p.0).collect()));
    // Where each edge's offset line starts and ends; a mirrored corner moves the end of the
    // non-fold edge's allowance to the fold line.
    let mut starts: Vec<Option<[f64; 2]>> = vec![None; n];
    let mut ends: Vec<Option<[f64; 2]>> = vec![None; n];
    for i in 0..n {
        let (v, w2, spec) = pts[i];
        let (u, w1, _) = pts[(i + n - 1) % n];
        let x = pts[(i + 1) % n].0;
        let d1 = unit(sub(v, u));
        let d2 = unit(sub(x, v));
        let turn = cross(d1, d2).atan2(dot(d1, d2));
        if turn <= 0.0 || (w1 <= 0.0 && w2 <= 0.0) {
            continue; // straight or reflex: the strips already meet
        }
        let rule = if turn < corner_angle_rad {
            CornerRule::Round
        } else {
            spec.rule
        };
        let corner = corner_piece(v, d1, d2, w1, w2, turn, rule, spec.fold_next);
        if let Some(q) = corner.moved_end {
            ends[(i + n - 1) % n] = Some(q);
        }
        if let Some(q) = corner.moved_start {
            starts[i] = Some(q);
        }
        pieces.push(ccw(corner.polygon));
    }
    for i in 0..n {
        let (a, w, _) = pts[i];
        let b = pts[(i + 1) % n].0;
        let nrm = right_normal(unit(sub(b, a)));
        if w > 0.0 {
            let s0 = starts[i].unwrap_or(add(a, scale(nrm, w)));
            let s1 = ends[i].unwrap_or(add(b, scale(nrm, w)));
            pieces.push(ccw(vec![a, s0, s1, b]));
        }
    }
    let shapes = pieces.simplify_shape(FillRule::NonZero);
    shapes
        .into_iter()
        .filter_map(|s| s.into_iter().next())
        .max_by(|a, b| signed_area(a).total_cmp(&signed_area(b)))
        .map(ccw)
}

fn ccw(mut poly: Vec<[f64; 2]>) -> Vec<[f64; 2]> {
    if signed_area(&poly) < 0.0 {
        poly.reverse();
    }
    poly
}

/// A corner piece, and where it moves the ends of the neighbouring edges' allowance.
struct Corner {
    polygon: Vec<[f64; 2]>,
    /// New end of the incoming edge's offset line.
    moved_end: Option<[f64; 2]>,
    /// New start of the outgoing edge's offset line.
    moved_start: Option<[f64; 2]>,
}

/// The convex-corner piece at `v` between incoming direction `d1` (width `w1`) and outgoing
/// `d2` (width `w2`), turning left by `turn` radians.
#[allow(clippy::too_many_arguments)]
fn corner_piece(
    v: [f64; 2],
    d1: [f64; 2],
    d2: [f64; 2],
    w1: f64,
    w2: f64,
    turn: f64,
    rule: CornerRule,
    fold_next: bool,
) -> Corner {
    let n1 = right_normal(d1);
    let n2 = right_normal(d2);
    let p1 = add(v, scale(n1, w1));
    let p2 = add(v, scale(n2, w2));
    let wmax = w1.max(w2);
    let plain = |polygon| Corner {
        polygon,
        moved_end: None,
        moved_start: None,
    };
    match rule {
        CornerRule::Round => {
            let mut out = vec![v];
            let step_max = 2.0 * (1.0 - ARC_SAGITTA_MM / wmax).clamp(-1.0, 1.0).acos();
            let steps = ((turn / step_max.max(1e-6)).ceil() as usize).clamp(1, 10_000);
            let a0 = n1[1].atan2(n1[0]);
            // The ends are the strips' own corner points, bit for bit, so no sliver of
            // rounding error separates the pieces in the union.
            out.push(p1);
            for k in 1..steps {
                let t = k as f64 / steps as f64;
                let a = a0 + turn * t;
                let r = w1 + (w2 - w1) * t;
                out.push(add(v, [r * a.cos(), r * a.sin()]));
            }
            out.push(p2);
            plain(out)
        }
        CornerRule::Square => plain(mitre(v, p1, d1, p2, d2, wmax)),
        CornerRule::Miter { limit } => plain(mitre(v, p1, d1, p2, d2, limit.max(1.0) * wmax)),
        CornerRule::Mirrored => mirrored(v, p1, d1, p2, d2, fold_next, wmax)
            .unwrap_or_else(|| plain(mitre(v, p1, d1, p2, d2, 2.0 * wmax))),
    }
}

/// Mitre corner [v, p1, M, p2], cut square to the bisector at `reach` from `v`.
fn mitre(
    v: [f64; 2],
    p1: [f64; 2],
    d1: [f64; 2],
    p2: [f64; 2],
    d2: [f64; 2],
    reach: f64,
) -> Vec<[f64; 2]> {
    let Some(m) = line_intersection(p1, d1, p2, d2) else {
        return vec![v, p1, p2];
    };
    let poly = vec![v, p1, m, p2];
    if dist(m, v) <= reach {
        return poly;
    }
    clip_half_plane(&poly, v, unit(sub(m, v)), reach)
}

/// Mirrored corner: the allowance beyond the fold edge ends on the fold-mirror of the other
/// edge's offset line. `None` when the construction runs off (fold nearly parallel).
fn mirrored(
    v: [f64; 2],
    p1: [f64; 2],
    d1: [f64; 2],
    p2: [f64; 2],
    d2: [f64; 2],
    fold_next: bool,
    wmax: f64,
) -> Option<Corner> {
    let reach = MIRROR_REACH * wmax;
    // The other edge's allowance stops at the fold line (at q) instead of at v + w·n.
    let corner = if fold_next {
        // Other edge's cut line L1 meets the fold line (through v along d2) at q; mirrored
        // about the fold it runs on to meet the fold edge's own cut line L2 at r.
        let q = line_intersection(p1, d1, v, d2)?;
        let dr = sub(reflect(add(q, d1), v, d2), q);
        let r = line_intersection(q, dr, p2, d2)?;
        Corner {
            polygon: vec![v, q, r, p2],
            moved_end: Some(q),
            moved_start: None,
        }
    } else {
        let q = line_intersection(p2, d2, v, d1)?;
        let dr = sub(reflect(add(q, d2), v, d1), q);
        let r = line_intersection(q, dr, p1, d1)?;
        Corner {
            polygon: vec![v, p1, r, q],
            moved_end: None,
            moved_start: Some(q),
        }
    };
    corner
        .polygon
        .iter()
        .all(|p| dist(*p, v) <= reach)
        .then_some(corner)
}

/// The convex polygon cut to the half-plane (x − o)·dir ≤ reach.
fn clip_half_plane(poly: &[[f64; 2]], o: [f64; 2], dir: [f64; 2], reach: f64) -> Vec<[f64; 2]> {
    let f = |p: [f64; 2]| dot(sub(p, o), dir) - reach;
    let mut out = Vec::with_capacity(poly.len() + 1);
    for i in 0..poly.len() {
        let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
        let (fa, fb) = (f(a), f(b));
        if fa <= 0.0 {
            out.push(a);
        }
        if (fa < 0.0) != (fb < 0.0) && norm(sub(b, a)) > 0.0 {
            let t = fa / (fa - fb);
            out.push(add(a, scale(sub(b, a), t)));
        }
    }
    out
}
