//! atan2 on the closed upper half-plane (y ≥ 0): the angle between two vectors from
//! |a × b| and a · b, by range reduction and a polynomial.
//!
//! Why not `f64::atan2`: θ(v), a sum of corner angles, is evaluated several times per
//! iteration of flattenable processing, and the system's atan2 (glibc's is correctly
//! rounded, ~20 ns a call) was a fifth of a 3.5k-face run's time. This one has no
//! branches on data, so a loop over corners vectorises; it is within 2 ulp of the correctly
//! rounded value (`tests/atan2.rs`). It also gives the same bits on every platform: it uses
//! only IEEE additions, multiplications and one division (no FMA, whose presence varies),
//! where system libraries differ in the last bit, and the paths of round-off-sensitive runs
//! (a saddle's, docs/algorithms/flattenable.md) with them.

use std::f64::consts::{FRAC_PI_2, FRAC_PI_4, PI};

/// tan(π/8): above it the reduced argument t is mapped to (t − 1)/(t + 1) and π/4 added, so
/// the polynomial only ever sees |u| ≤ tan(π/8).
const TAN_PI_8: f64 = 0.414_213_562_373_095_03;

/// (atan √s − √s)/(s √s) ≈ Σ c_k s^k on s ∈ [0, tan²(π/8)]: Chebyshev interpolation of
/// degree 10, error 3e-17 before the coefficients were rounded to f64 and 4.5e-17 after
/// (mpmath `chebyfit`, 50 digits). In atan u = u + u s P(s) that term is at most 0.06 u, so
/// its error is far below an ulp of the result.
const ATAN_POLY: [f64; 11] = [
    -0.333_333_333_333_333_3,
    0.199_999_999_999_955_2,
    -0.142_857_142_846_665_42,
    0.111_111_110_152_563_61,
    -0.090_909_045_781_239_03,
    0.076_921_831_908_260_87,
    -0.066_645_114_473_819_48,
    0.058_581_489_128_022_1,
    -0.050_854_497_379_402_6,
    0.039_231_658_295_587_19,
    -0.019_176_887_119_062_26,
];

/// atan2(|y|, x): the angle in [0, π] of the vector (x, |y|), within 2 ulp of the correctly
/// rounded value. (0, 0) gives 0, as `f64::atan2`; a NaN argument gives NaN. Always inlined,
/// so that it takes the vector width of the SIMD context its caller is compiled for.
#[inline(always)]
pub fn atan2_upper_half(y: f64, x: f64) -> f64 {
    let y = y.abs();
    let ax = x.abs();
    // Octant reduction: t = min/max ∈ [0, 1], the angle is π/2 − atan t when y > |x|.
    let swap = y > ax;
    let (num, den) = if swap { (ax, y) } else { (y, ax) };
    // Above tan(π/8): atan t = π/4 + atan((t − 1)/(t + 1)), formed from num and den so that
    // it costs one division, not two.
    let reduce = num > TAN_PI_8 * den;
    let (n, d) = if reduce {
        (num - den, num + den)
    } else {
        (num, den)
    };
    // (0, 0): n = 0, and 0/1 keeps it 0 where 0/0 would be NaN. A NaN stays NaN.
    let u = n / if d == 0.0 { 1.0 } else { d };
    let s = u * u;
    // Estrin's scheme: shorter dependency chains than Horner's.
    let c = &ATAN_POLY;
    let s2 = s * s;
    let s4 = s2 * s2;
    let s8 = s4 * s4;
    let p01 = c[0] + c[1] * s;
    let p23 = c[2] + c[3] * s;
    let p45 = c[4] + c[5] * s;
    let p67 = c[6] + c[7] * s;
    let p89 = c[8] + c[9] * s;
    let p03 = p01 + p23 * s2;
    let p47 = p45 + p67 * s2;
    let p8a = p89 + c[10] * s2;
    let p = (p03 + p47 * s4) + p8a * s8;
    let mut a = u + u * (s * p);
    if reduce {
        a += FRAC_PI_4;
    }
    if swap {
        a = FRAC_PI_2 - a;
    }
    if x < 0.0 {
        a = PI - a;
    }
    a
}
