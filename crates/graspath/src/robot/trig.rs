//! A fast `sin_cos` for joint angles: one range reduction shared by both results, then
//! polynomials on `[−π/4, π/4]`. Agrees with the standard library to about one unit in the
//! last place for `|x| ≤ 1e5`; larger or non-finite arguments fall back to the standard library.

/// π/2 split so that `k · PIO2_HI` is exact for `|k| < 2²⁰` (fdlibm's `pio2_1`, `pio2_1t`:
/// the leading 33 bits of π/2 and the next 53).
const PIO2_HI: f64 = f64::from_bits(0x3FF9_21FB_5440_0000);
const PIO2_LO: f64 = f64::from_bits(0x3DD0_B461_1A62_6331);
const TWO_OVER_PI: f64 = std::f64::consts::FRAC_2_PI;

/// Taylor coefficients `(−1)^k / (2k+1)!` and `(−1)^k / (2k)!`; on `|r| ≤ π/4` the first omitted
/// terms are below 1e-19.
const SIN_COEFFS: [f64; 8] = [
    -1.0 / 6.0,
    1.0 / 120.0,
    -1.0 / 5_040.0,
    1.0 / 362_880.0,
    -1.0 / 39_916_800.0,
    1.0 / 6_227_020_800.0,
    -1.0 / 1_307_674_368_000.0,
    1.0 / 355_687_428_096_000.0,
];
const COS_COEFFS: [f64; 8] = [
    1.0 / 24.0,
    -1.0 / 720.0,
    1.0 / 40_320.0,
    -1.0 / 3_628_800.0,
    1.0 / 479_001_600.0,
    -1.0 / 87_178_291_200.0,
    1.0 / 20_922_789_888_000.0,
    -1.0 / 6_402_373_705_728_000.0,
];

/// `(sin x, cos x)`.
#[inline(always)]
pub(crate) fn sin_cos(x: f64) -> (f64, f64) {
    if x.is_nan() || x.abs() > 1e5 {
        return x.sin_cos();
    }
    // Round to nearest by adding and subtracting 1.5·2⁵² (exact for |x·2/π| < 2⁵¹; no libm call).
    const SHIFTER: f64 = 6_755_399_441_055_744.0;
    let k = (x * TWO_OVER_PI + SHIFTER) - SHIFTER;
    let r = (x - k * PIO2_HI) - k * PIO2_LO;
    let r2 = r * r;
    let mut s = SIN_COEFFS[7];
    let mut c = COS_COEFFS[7];
    for i in (0..7).rev() {
        s = s * r2 + SIN_COEFFS[i];
        c = c * r2 + COS_COEFFS[i];
    }
    let sin_r = r + r * r2 * s;
    let cos_r = 1.0 - 0.5 * r2 + r2 * r2 * c;
    match (k as i64) & 3 {
        0 => (sin_r, cos_r),
        1 => (cos_r, -sin_r),
        2 => (-sin_r, -cos_r),
        _ => (-cos_r, sin_r),
    }
}

#[cfg(test)]
mod tests {
    use super::sin_cos;

    #[test]
    fn agrees_with_the_standard_library() {
        let mut worst: f64 = 0.0;
        let n = 200_000;
        for i in 0..=n {
            let x = -20.0 + 40.0 * i as f64 / n as f64;
            let (s, c) = sin_cos(x);
            worst = worst.max((s - x.sin()).abs()).max((c - x.cos()).abs());
        }
        assert!(
            worst <= 3.0 * f64::EPSILON,
            "worst absolute error {worst:e}"
        );
        for x in [
            0.0,
            -0.0,
            1e-300,
            std::f64::consts::FRAC_PI_2,
            std::f64::consts::PI,
            1e4 + 0.3,
        ] {
            let (s, c) = sin_cos(x);
            assert!((s - x.sin()).abs() <= 2.0 * f64::EPSILON, "{x}");
            assert!((c - x.cos()).abs() <= 2.0 * f64::EPSILON, "{x}");
        }
        let (s, c) = sin_cos(1e9);
        assert_eq!((s, c), 1e9f64.sin_cos());
        assert!(sin_cos(f64::NAN).0.is_nan());
    }
}
