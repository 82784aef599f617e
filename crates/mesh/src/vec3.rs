//! Small vector helpers on `[f64; 3]`, kept free so that the mesh stays plain arrays.

/// a − b
#[inline]
pub fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
/// a + b
#[inline]
pub fn add(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}
/// s · a
#[inline]
pub fn scale(a: [f64; 3], s: f64) -> [f64; 3] {
    [a[0] * s, a[1] * s, a[2] * s]
}
/// a · b
#[inline]
pub fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
/// a × b
#[inline]
pub fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
/// |a|
#[inline]
pub fn norm(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}
/// |a|²
#[inline]
pub fn norm2(a: [f64; 3]) -> f64 {
    dot(a, a)
}
/// a / |a|, or zero for the zero vector.
#[inline]
pub fn normalize(a: [f64; 3]) -> [f64; 3] {
    let n = norm(a);
    if n > 0.0 { scale(a, 1.0 / n) } else { [0.0; 3] }
}
/// |a − b|
#[inline]
pub fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    norm(sub(a, b))
}
/// Distance from `p` to the segment `a`–`b` (a degenerate segment is the point `a`).
#[inline]
pub fn point_segment_distance(p: [f64; 3], a: [f64; 3], b: [f64; 3]) -> f64 {
    let d = sub(b, a);
    let l2 = norm2(d);
    let t = if l2 > 0.0 {
        (dot(sub(p, a), d) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    dist(p, add(a, scale(d, t)))
}
/// The angle between a and b in radians, in the stable atan2 form
/// (|a × b|, a · b), exact near 0 and π where acos is not; the atan2 is
/// [`crate::atan2::atan2_upper_half`] (within 2 ulp, the same bits on every platform).
#[inline(always)]
pub fn angle(a: [f64; 3], b: [f64; 3]) -> f64 {
    crate::atan2::atan2_upper_half(norm(cross(a, b)), dot(a, b))
}
