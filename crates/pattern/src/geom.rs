//! Small 2D helpers shared by the pattern algorithms (points are `[x, y]` in mm).

/// a − b.
pub fn sub(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    [a[0] - b[0], a[1] - b[1]]
}
/// a + b.
pub fn add(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    [a[0] + b[0], a[1] + b[1]]
}
/// s·a.
pub fn scale(a: [f64; 2], s: f64) -> [f64; 2] {
    [a[0] * s, a[1] * s]
}
/// a · b.
pub fn dot(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}
/// z of a × b.
pub fn cross(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}
/// |a|.
pub fn norm(a: [f64; 2]) -> f64 {
    a[0].hypot(a[1])
}
/// |a − b|.
pub fn dist(a: [f64; 2], b: [f64; 2]) -> f64 {
    norm(sub(a, b))
}
/// a / |a| (zero stays zero).
pub fn unit(a: [f64; 2]) -> [f64; 2] {
    let n = norm(a);
    if n > 0.0 {
        scale(a, 1.0 / n)
    } else {
        [0.0, 0.0]
    }
}
/// The right-hand normal of a direction: the outward side of an edge of a counter-clockwise loop.
pub fn right_normal(d: [f64; 2]) -> [f64; 2] {
    [d[1], -d[0]]
}

/// Signed area of a closed polygon (positive when counter-clockwise), mm².
pub fn signed_area(poly: &[[f64; 2]]) -> f64 {
    let n = poly.len();
    (0..n)
        .map(|i| cross(poly[i], poly[(i + 1) % n]))
        .sum::<f64>()
        * 0.5
}

/// Length of an open polyline.
pub fn polyline_length(pts: &[[f64; 2]]) -> f64 {
    pts.windows(2).map(|w| dist(w[0], w[1])).sum()
}

/// Distance from `p` to the segment `a`–`b`.
pub fn point_segment_distance(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let ab = sub(b, a);
    let l2 = dot(ab, ab);
    let t = if l2 > 0.0 {
        (dot(sub(p, a), ab) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    dist(p, add(a, scale(ab, t)))
}

/// Distance from `p` to the closed polygon's outline.
pub fn point_polygon_distance(p: [f64; 2], poly: &[[f64; 2]]) -> f64 {
    let n = poly.len();
    (0..n)
        .map(|i| point_segment_distance(p, poly[i], poly[(i + 1) % n]))
        .fold(f64::INFINITY, f64::min)
}

/// Even–odd point-in-polygon test.
pub fn point_in_polygon(p: [f64; 2], poly: &[[f64; 2]]) -> bool {
    let n = poly.len();
    let mut inside = false;
    for i in 0..n {
        let (a, b) = (poly[i], poly[(i + 1) % n]);
        if (a[1] > p[1]) != (b[1] > p[1]) {
            let x = a[0] + (p[1] - a[1]) / (b[1] - a[1]) * (b[0] - a[0]);
            if p[0] < x {
                inside = !inside;
            }
        }
    }
    inside
}

/// Intersection of the lines `p + t·d` and `q + s·e`; `None` when (nearly) parallel.
pub fn line_intersection(p: [f64; 2], d: [f64; 2], q: [f64; 2], e: [f64; 2]) -> Option<[f64; 2]> {
    let den = cross(d, e);
    if den.abs() < 1e-12 * norm(d) * norm(e) {
        return None;
    }
    let t = cross(sub(q, p), e) / den;
    Some(add(p, scale(d, t)))
}

/// Proper or touching intersection of segments `a`–`b` and `c`–`d`: the parameter along a–b.
pub fn segment_intersection(a: [f64; 2], b: [f64; 2], c: [f64; 2], d: [f64; 2]) -> Option<f64> {
    let r = sub(b, a);
    let s = sub(d, c);
    let den = cross(r, s);
    if den == 0.0 {
        return None;
    }
    let t = cross(sub(c, a), s) / den;
    let u = cross(sub(c, a), r) / den;
    ((0.0..=1.0).contains(&t) && (0.0..=1.0).contains(&u)).then_some(t)
}

/// Reflection of point `p` about the line through `o` with unit direction `d`.
pub fn reflect(p: [f64; 2], o: [f64; 2], d: [f64; 2]) -> [f64; 2] {
    let v = sub(p, o);
    let along = scale(d, dot(v, d));
    add(o, sub(scale(along, 2.0), v))
}

/// Bounding box `[min, max]` of points (zeros when empty).
pub fn bbox(pts: &[[f64; 2]]) -> [[f64; 2]; 2] {
    if pts.is_empty() {
        return [[0.0; 2]; 2];
    }
    let mut b = [[f64::INFINITY; 2], [f64::NEG_INFINITY; 2]];
    for p in pts {
        for k in 0..2 {
            b[0][k] = b[0][k].min(p[k]);
            b[1][k] = b[1][k].max(p[k]);
        }
    }
    b
}

/// The point at arc length `s` along a polyline (clamped to its ends), and the index of the
/// segment it lies on.
pub fn point_at_arc(pts: &[[f64; 2]], s: f64) -> ([f64; 2], usize) {
    let mut acc = 0.0;
    for i in 0..pts.len().saturating_sub(1) {
        let l = dist(pts[i], pts[i + 1]);
        if acc + l >= s && l > 0.0 {
            let t = ((s - acc) / l).clamp(0.0, 1.0);
            return (add(pts[i], scale(sub(pts[i + 1], pts[i]), t)), i);
        }
        acc += l;
    }
    let last = pts.len().saturating_sub(1);
    (
        pts.get(last).copied().unwrap_or([0.0; 2]),
        last.saturating_sub(1),
    )
}
