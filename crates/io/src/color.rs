//! Colour conversions: sRGB ↔ linear and the viridis ramp for scalar fields.
//!
//! flatcut keeps vertex colours linear (`TriMesh::attributes.colors`, as glTF's `COLOR_0`).
//! PLY `uchar` colours and OBJ `v x y z r g b` colours are display (sRGB) values and are
//! converted on read and write; 8-bit values round-trip exactly through linear f32.

/// sRGB-encoded component in [0, 1] → linear (IEC 61966-2-1).
pub fn srgb_to_linear(c: f32) -> f32 {
    let c = f64::from(c);
    (if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }) as f32
}

/// Linear component in [0, 1] → sRGB-encoded (IEC 61966-2-1); input clamped to [0, 1].
pub fn linear_to_srgb(c: f32) -> f32 {
    let c = f64::from(c.clamp(0.0, 1.0));
    (if c <= 0.003_130_8 {
        c * 12.92
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    }) as f32
}

/// 8-bit sRGB → linear.
pub fn u8_to_linear(c: u8) -> f32 {
    srgb_to_linear(f32::from(c) / 255.0)
}

/// Linear → 8-bit sRGB (rounded to nearest; NaN becomes 0).
pub fn linear_to_u8(c: f32) -> u8 {
    let c = if c.is_nan() { 0.0 } else { c };
    (linear_to_srgb(c) * 255.0).round().clamp(0.0, 255.0) as u8
}

/// matplotlib's viridis (perceptually uniform, colour-blind safe) sampled at t = 0, 0.1, …, 1,
/// sRGB; interpolated linearly between samples.
const VIRIDIS: [[f32; 3]; 11] = [
    [0.267_004, 0.004_874, 0.329_415],
    [0.282_623, 0.140_926, 0.457_517],
    [0.253_935, 0.265_254, 0.529_983],
    [0.206_756, 0.371_758, 0.553_117],
    [0.163_625, 0.471_133, 0.558_148],
    [0.127_568, 0.566_949, 0.550_556],
    [0.134_692, 0.658_636, 0.517_649],
    [0.266_941, 0.748_751, 0.440_573],
    [0.477_504, 0.821_444, 0.318_195],
    [0.741_388, 0.873_449, 0.149_561],
    [0.993_248, 0.906_157, 0.143_936],
];

/// The viridis colour of `t` in [0, 1] (clamped; NaN maps to 0) as **sRGB** components.
pub fn viridis_srgb(t: f64) -> [f32; 3] {
    let t = if t.is_nan() { 0.0 } else { t.clamp(0.0, 1.0) };
    let s = t * 10.0;
    let i = (s.floor() as usize).min(9);
    let f = (s - i as f64) as f32;
    let (a, b) = (VIRIDIS[i], VIRIDIS[i + 1]);
    [
        a[0] + (b[0] - a[0]) * f,
        a[1] + (b[1] - a[1]) * f,
        a[2] + (b[2] - a[2]) * f,
    ]
}

/// The viridis colour of `value` on the range `lo..hi` as a **linear** RGBA colour (alpha 1),
/// ready for glTF `COLOR_0`. A degenerate range (lo ≥ hi) maps everything to the middle.
pub fn viridis(value: f64, lo: f64, hi: f64) -> [f32; 4] {
    let t = if hi > lo {
        (value - lo) / (hi - lo)
    } else {
        0.5
    };
    let c = viridis_srgb(t);
    [
        srgb_to_linear(c[0]),
        srgb_to_linear(c[1]),
        srgb_to_linear(c[2]),
        1.0,
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn u8_round_trip_is_exact() {
        for c in 0..=255u8 {
            assert_eq!(linear_to_u8(u8_to_linear(c)), c, "value {c}");
        }
    }

    #[test]
    fn srgb_known_values() {
        // 50% sRGB grey is 21.4% linear (closed form ((0.5+0.055)/1.055)^2.4).
        assert!((srgb_to_linear(0.5) - 0.214_041_14).abs() < 1e-6);
        assert_eq!(srgb_to_linear(0.0), 0.0);
        assert_eq!(srgb_to_linear(1.0), 1.0);
    }

    #[test]
    fn viridis_ends_and_monotone_lightness() {
        assert_eq!(viridis_srgb(0.0), VIRIDIS[0]);
        assert_eq!(viridis_srgb(1.0), VIRIDIS[10]);
        assert_eq!(viridis_srgb(0.5), VIRIDIS[5]);
        // viridis is designed with monotonically increasing lightness: check relative
        // luminance (Rec. 709 weights on linear values) increases along the ramp.
        let lum = |t: f64| {
            let c = viridis(t, 0.0, 1.0);
            0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]
        };
        for i in 0..100 {
            assert!(lum(f64::from(i + 1) / 100.0) > lum(f64::from(i) / 100.0));
        }
        assert_eq!(viridis(5.0, 1.0, 1.0), viridis(0.5, 0.0, 1.0));
    }
}
