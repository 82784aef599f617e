//! `atan2_upper_half` against the platform's `f64::atan2` (glibc's is correctly rounded) and
//! closed forms.

use flatcut_mesh::atan2::atan2_upper_half;
use proptest::prelude::*;
use std::f64::consts::{FRAC_PI_2, FRAC_PI_4, PI};

/// Distance in units in the last place between two finite non-negative doubles.
fn ulps(a: f64, b: f64) -> u64 {
    assert!(a >= 0.0 && b >= 0.0, "{a} {b}");
    a.to_bits().abs_diff(b.to_bits())
}

#[test]
fn within_two_ulp_of_atan2_over_the_half_plane() {
    // Every angle of the half-plane at 200 001 steps, at radii from 1e-150 to 1e150, plus the
    // octant and reduction boundaries approached from both sides.
    let mut worst = 0;
    let mut differ = 0usize;
    let mut total = 0usize;
    for radius in [1e-150, 1e-3, 0.7, 1.0, 3.0, 1e4, 1e150] {
        for i in 0..=200_000 {
            let a = PI * i as f64 / 200_000.0;
            let (y, x) = (radius * a.sin(), radius * a.cos());
            let got = atan2_upper_half(y, x);
            let want = y.atan2(x);
            worst = worst.max(ulps(got, want));
            differ += usize::from(got != want);
            total += 1;
        }
    }
    for t in [0.414_213_562_373_095_03f64, 1.0] {
        let mut v = t;
        for _ in 0..100 {
            for (y, x) in [(v, 1.0), (1.0, v), (v, -1.0), (1.0, -v)] {
                worst = worst.max(ulps(atan2_upper_half(y, x), y.atan2(x)));
            }
            v = f64::from_bits(v.to_bits() + 1);
        }
    }
    assert!(worst <= 2, "worst {worst} ulp");
    // Not a copy of atan2 by another name: most results agree, but not all.
    assert!(
        differ > 0 && differ < total / 4,
        "{differ} of {total} differ"
    );
}

#[test]
fn closed_forms_and_special_values() {
    assert_eq!(atan2_upper_half(1.0, 0.0), FRAC_PI_2);
    assert_eq!(atan2_upper_half(0.0, 1.0), 0.0);
    assert_eq!(atan2_upper_half(0.0, -1.0), PI);
    assert_eq!(atan2_upper_half(0.0, 0.0), 0.0);
    assert!(ulps(atan2_upper_half(1.0, 1.0), FRAC_PI_4) <= 1);
    assert!(ulps(atan2_upper_half(1.0, -1.0), 3.0 * FRAC_PI_4) <= 1);
    // The equilateral corner.
    assert!(ulps(atan2_upper_half(3f64.sqrt(), 1.0), PI / 3.0) <= 2);
    // Tiny angles are the ratio itself (atan u = u − u³/3 …).
    assert_eq!(atan2_upper_half(1e-200, 1.0), 1e-200);
    assert_eq!(atan2_upper_half(1e-20, 2.0), 5e-21);
    // The lower half-plane is reflected: the angle of (x, |y|).
    assert_eq!(atan2_upper_half(-0.3, -0.8), atan2_upper_half(0.3, -0.8));
    assert!(atan2_upper_half(f64::NAN, 1.0).is_nan());
    assert!(atan2_upper_half(1.0, f64::NAN).is_nan());
    assert!(atan2_upper_half(f64::NAN, f64::NAN).is_nan());
}

proptest! {
    #[test]
    fn any_finite_pair_is_within_two_ulp(
        y in 0.0f64..1e6,
        x in -1e6f64..1e6,
        exponent in -100i32..100,
    ) {
        let s = 10f64.powi(exponent);
        let (y, x) = (y * s, x * s);
        prop_assume!(y > 0.0 || x != 0.0);
        let got = atan2_upper_half(y, x);
        prop_assert!(ulps(got, y.atan2(x)) <= 2, "{y} {x}: {got} vs {}", y.atan2(x));
    }
}
