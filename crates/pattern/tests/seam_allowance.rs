//! The cut line against the done-when: sampled every 1 mm it lies at the allowance from the
//! sew line (±0.01 mm) away from corners, and each corner rule holds at the corners.

#![allow(clippy::unwrap_used)]

use flatcut_pattern::geom::{
    cross, dist, dot, point_in_polygon, point_polygon_distance, signed_area, sub, unit,
};
use flatcut_pattern::{CornerRule, CornerSpec, seam_allowance};

const CORNER_ANGLE: f64 = 0.35;

fn spec(rule: CornerRule) -> CornerSpec {
    CornerSpec {
        rule,
        fold_next: true,
    }
}

/// Convex vertices turning by at least the corner angle (the only places the offset may
/// depart from the exact distance).
fn corners(poly: &[[f64; 2]]) -> Vec<[f64; 2]> {
    let n = poly.len();
    (0..n)
        .filter(|&i| {
            let d1 = unit(sub(poly[i], poly[(i + n - 1) % n]));
            let d2 = unit(sub(poly[(i + 1) % n], poly[i]));
            cross(d1, d2).atan2(dot(d1, d2)) >= CORNER_ANGLE
        })
        .map(|i| poly[i])
        .collect()
}

/// Samples the closed polyline every `step` mm.
fn samples(poly: &[[f64; 2]], step: f64) -> Vec<[f64; 2]> {
    let mut out = Vec::new();
    let mut carry = 0.0;
    for i in 0..poly.len() {
        let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
        let l = dist(a, b);
        let mut s = carry;
        while s < l {
            let t = s / l;
            out.push([a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])]);
            s += step;
        }
        carry = s - l;
    }
    out
}

/// Checks the distance property; returns how many samples were checked.
fn check_distance(sew: &[[f64; 2]], w: f64, rule: CornerRule) -> (Vec<[f64; 2]>, usize) {
    let n = sew.len();
    let cut = seam_allowance(sew, &vec![w; n], &vec![spec(rule); n], CORNER_ANGLE).unwrap();
    assert!(signed_area(&cut) > 0.0, "cut line is counter-clockwise");
    for p in sew {
        assert!(
            point_in_polygon(*p, &cut),
            "sew point {p:?} inside the cut line"
        );
    }
    let cs = corners(sew);
    let mut checked = 0;
    for p in samples(&cut, 1.0) {
        let d = point_polygon_distance(p, sew);
        if cs.iter().any(|c| dist(*c, p) < 2.0 * w) {
            assert!(
                d >= w - 0.01,
                "near a corner the cut line never comes closer: {d} at {p:?}"
            );
            continue;
        }
        assert!((d - w).abs() <= 0.01, "|{d} - {w}| > 0.01 mm at {p:?}");
        checked += 1;
    }
    (cut, checked)
}

#[test]
fn rectangle_mitre_has_exact_corners() {
    let sew = [[0.0, 0.0], [100.0, 0.0], [100.0, 60.0], [0.0, 60.0]];
    let (cut, checked) = check_distance(&sew, 10.0, CornerRule::Miter { limit: 2.0 });
    assert!(checked > 150, "{checked}");
    // A right-angle mitre is at (−w, −w) from each corner, within √2 w < 2 w.
    for c in [[-10.0, -10.0], [110.0, -10.0], [110.0, 70.0], [-10.0, 70.0]] {
        assert!(
            cut.iter().any(|p| dist(*p, c) < 1e-6),
            "corner {c:?} in {cut:?}"
        );
    }
    assert!((signed_area(&cut) - 120.0 * 80.0).abs() < 1e-3);
}

#[test]
fn concave_l_shape_and_circle() {
    let l = [
        [0.0, 0.0],
        [120.0, 0.0],
        [120.0, 40.0],
        [40.0, 40.0],
        [40.0, 100.0],
        [0.0, 100.0],
    ];
    let (cut, checked) = check_distance(&l, 8.0, CornerRule::Miter { limit: 2.0 });
    assert!(checked > 250, "{checked}");
    // The reflex corner (40, 40): offset lines cross at (48, 48).
    assert!(cut.iter().any(|p| dist(*p, [48.0, 48.0]) < 1e-6), "{cut:?}");
    // A polygonal circle: every vertex is gentle, so the whole cut line is the exact offset.
    let circle: Vec<[f64; 2]> = (0..180)
        .map(|k| {
            let a = std::f64::consts::TAU * k as f64 / 180.0;
            [50.0 * a.cos(), 50.0 * a.sin()]
        })
        .collect();
    let (_, checked) = check_distance(&circle, 12.0, CornerRule::Miter { limit: 2.0 });
    assert!(checked > 350, "{checked}");
}

#[test]
fn nearly_self_touching_comb() {
    // Two prongs 0.4 mm apart (a slit nearly closing the outline): the offsets merge across the
    // slit exactly as the true offset does, and the distance still holds everywhere else.
    let comb = [
        [0.0, 0.0],
        [100.0, 0.0],
        [100.0, 80.0],
        [50.2, 80.0],
        [50.2, 10.0],
        [49.8, 10.0],
        [49.8, 80.0],
        [0.0, 80.0],
    ];
    let (cut, checked) = check_distance(&comb, 10.0, CornerRule::Round);
    assert!(checked > 150, "{checked}");
    // Round joins: no point of the cut line comes inside the slit region.
    assert!(cut.iter().all(|p| point_polygon_distance(*p, &comb) > 9.99));
    let (_, checked) = check_distance(&comb, 10.0, CornerRule::Square);
    assert!(checked > 150, "{checked}");
}

#[test]
fn mitre_limit_and_square_cut_at_their_reach() {
    // A 30° spike at the origin pointing down -x: mitre reach w / sin(15°) = 3.86 w.
    let spike = [[0.0, 0.0], [100.0, -26.794919], [100.0, 26.794919]];
    let w = 5.0;
    let far = |rule| {
        let cut = seam_allowance(&spike, &[w; 3], &[spec(rule); 3], CORNER_ANGLE).unwrap();
        cut.iter().map(|p| -p[0]).fold(f64::MIN, f64::max)
    };
    assert!((far(CornerRule::Miter { limit: 2.0 }) - 2.0 * w).abs() < 1e-6);
    assert!((far(CornerRule::Square) - w).abs() < 1e-6);
    let unlimited = far(CornerRule::Miter { limit: 10.0 });
    let expected = w / (15f64).to_radians().sin();
    assert!(
        (unlimited - expected).abs() < 1e-4,
        "{unlimited} vs {expected}"
    );
    assert!((far(CornerRule::Round) - w).abs() < 1e-3);
}

#[test]
fn mirrored_corner_is_the_fold_mirror_of_the_other_cut_line() {
    // Hem (outgoing edge along +x... fold) meeting a side seam at 70°: the hem allowance's end
    // is the reflection about the hem line of the side seam's cut line.
    // Sew loop counter-clockwise: side seam comes down to v = (0, 0), hem runs to +x.
    let a = 70f64.to_radians();
    let top = [-100.0 * a.cos(), 100.0 * a.sin()];
    let sew = [top, [0.0, 0.0], [200.0, 0.0], [200.0, 100.0 * a.sin()]];
    let (w_side, w_hem) = (10.0, 30.0);
    let widths = [w_side, w_hem, 10.0, 10.0];
    let mut corners = [spec(CornerRule::Miter { limit: 4.0 }); 4];
    corners[1] = CornerSpec {
        rule: CornerRule::Mirrored,
        fold_next: true,
    };
    let cut = seam_allowance(&sew, &widths, &corners, CORNER_ANGLE).unwrap();
    // The side seam's cut line: the line parallel to top→v at w_side outside.
    let d = unit(sub([0.0, 0.0], top));
    let n = [d[1], -d[0]];
    let on_side_line = |p: [f64; 2]| (dot(p, n) - w_side).abs() < 1e-6;
    // Its mirror about the hem line (y = 0): reflect (x, y) → (x, −y).
    let on_mirror = |p: [f64; 2]| on_side_line([p[0], -p[1]]);
    let below: Vec<_> = cut.iter().filter(|p| p[1] < -1e-6 && p[0] < 20.0).collect();
    assert!(!below.is_empty(), "{cut:?}");
    // Every cut-line vertex below the hem line near v lies on the mirror line or on the hem's
    // own cut line y = −w_hem.
    for p in below {
        assert!(
            on_mirror(*p) || (p[1] + w_hem).abs() < 1e-6,
            "{p:?} is neither on the mirrored line nor the hem cut line"
        );
    }
    assert!(cut.iter().any(|p| p[1] < -1.0 && on_mirror(*p)));
}

#[test]
fn per_edge_widths() {
    let sew = [[0.0, 0.0], [100.0, 0.0], [100.0, 60.0], [0.0, 60.0]];
    let cut = seam_allowance(
        &sew,
        &[10.0, 20.0, 10.0, 0.0],
        &[spec(CornerRule::Miter { limit: 3.0 }); 4],
        CORNER_ANGLE,
    )
    .unwrap();
    let b = flatcut_pattern::geom::bbox(&cut);
    assert!(
        (b[0][0] - 0.0).abs() < 1e-6,
        "zero allowance on the left: {b:?}"
    );
    assert!((b[1][0] - 120.0).abs() < 1e-6);
    assert!((b[0][1] + 10.0).abs() < 1e-6);
    assert!((b[1][1] - 70.0).abs() < 1e-6);
}
