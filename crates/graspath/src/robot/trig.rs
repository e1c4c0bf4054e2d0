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

/// Arguments above this magnitude (and NaN) go to the standard library.
const FAST_LIMIT: f64 = 1e5;
/// Adding and subtracting 1.5·2⁵² rounds to the nearest integer (exact for |y| < 2⁵¹).
const SHIFTER: f64 = 6_755_399_441_055_744.0;

/// `(sin x, cos x)`.
#[inline(always)]
pub(crate) fn sin_cos(x: f64) -> (f64, f64) {
    if x.is_nan() || x.abs() > FAST_LIMIT {
        return x.sin_cos();
    }
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

/// `(sin x, cos x)` of four arguments at once with AVX2: the same operations as [`sin_cos`]
/// in every lane, so the results are bit-identical to it.
///
/// # Safety
/// The processor must support AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[inline]
pub(crate) unsafe fn sin_cos4(
    x: std::arch::x86_64::__m256d,
) -> (std::arch::x86_64::__m256d, std::arch::x86_64::__m256d) {
    use std::arch::x86_64::*;
    let set = _mm256_set1_pd;
    let sign_bit = _mm256_set1_pd(-0.0);
    let shifted = _mm256_add_pd(_mm256_mul_pd(x, set(TWO_OVER_PI)), set(SHIFTER));
    let k = _mm256_sub_pd(shifted, set(SHIFTER));
    let r = _mm256_sub_pd(
        _mm256_sub_pd(x, _mm256_mul_pd(k, set(PIO2_HI))),
        _mm256_mul_pd(k, set(PIO2_LO)),
    );
    let r2 = _mm256_mul_pd(r, r);
    let mut s = set(SIN_COEFFS[7]);
    let mut c = set(COS_COEFFS[7]);
    for i in (0..7).rev() {
        s = _mm256_add_pd(_mm256_mul_pd(s, r2), set(SIN_COEFFS[i]));
        c = _mm256_add_pd(_mm256_mul_pd(c, r2), set(COS_COEFFS[i]));
    }
    let sin_r = _mm256_add_pd(r, _mm256_mul_pd(_mm256_mul_pd(r, r2), s));
    let cos_r = _mm256_add_pd(
        _mm256_sub_pd(set(1.0), _mm256_mul_pd(set(0.5), r2)),
        _mm256_mul_pd(_mm256_mul_pd(r2, r2), c),
    );
    // The quadrant k mod 4 sits in the low bits of `shifted` (its unit in the last place is 1).
    let quadrant = _mm256_castpd_si256(shifted);
    let odd = _mm256_castsi256_pd(_mm256_slli_epi64::<63>(quadrant));
    let sin_sign = _mm256_castsi256_pd(_mm256_slli_epi64::<63>(_mm256_srli_epi64::<1>(quadrant)));
    let cos_sign = _mm256_castsi256_pd(_mm256_slli_epi64::<63>(_mm256_srli_epi64::<1>(
        _mm256_add_epi64(quadrant, _mm256_set1_epi64x(1)),
    )));
    // Odd quadrants swap sine and cosine; bit 1 of k (of k + 1 for the cosine) flips the sign.
    let sin = _mm256_xor_pd(_mm256_blendv_pd(sin_r, cos_r, odd), sin_sign);
    let cos = _mm256_xor_pd(_mm256_blendv_pd(cos_r, sin_r, odd), cos_sign);
    let slow = _mm256_movemask_pd(_mm256_cmp_pd::<_CMP_NLE_UQ>(
        _mm256_andnot_pd(sign_bit, x),
        set(FAST_LIMIT),
    ));
    if slow == 0 {
        return (sin, cos);
    }
    let mut lanes = [0.0; 4];
    let (mut sines, mut cosines) = ([0.0; 4], [0.0; 4]);
    _mm256_storeu_pd(lanes.as_mut_ptr(), x);
    _mm256_storeu_pd(sines.as_mut_ptr(), sin);
    _mm256_storeu_pd(cosines.as_mut_ptr(), cos);
    for lane in 0..4 {
        if slow & (1 << lane) != 0 {
            (sines[lane], cosines[lane]) = lanes[lane].sin_cos();
        }
    }
    (
        _mm256_loadu_pd(sines.as_ptr()),
        _mm256_loadu_pd(cosines.as_ptr()),
    )
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

    #[cfg(target_arch = "x86_64")]
    #[test]
    fn four_lanes_match_one_lane_bit_for_bit() {
        use std::arch::x86_64::*;
        if !crate::cpu::has_avx2() {
            eprintln!("no AVX2 on this processor: nothing to compare");
            return;
        }
        let mut xs: Vec<f64> = (-40_000..40_000).map(|i| i as f64 * 7.853e-4).collect();
        for k in -8..8 {
            let edge = k as f64 * std::f64::consts::FRAC_PI_4;
            xs.extend([edge, edge.next_up(), edge.next_down()]);
        }
        xs.extend([
            0.0,
            -0.0,
            1e5,
            -1e5,
            1e5 + 1.0,
            -3e7,
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::MIN_POSITIVE,
        ]);
        for chunk in xs.chunks(4) {
            let mut lanes = [0.25; 4];
            lanes[..chunk.len()].copy_from_slice(chunk);
            let (mut sines, mut cosines) = ([0.0; 4], [0.0; 4]);
            // SAFETY: AVX2 is present (checked above).
            unsafe {
                let (s, c) = super::sin_cos4(_mm256_loadu_pd(lanes.as_ptr()));
                _mm256_storeu_pd(sines.as_mut_ptr(), s);
                _mm256_storeu_pd(cosines.as_mut_ptr(), c);
            }
            for lane in 0..4 {
                let (s, c) = sin_cos(lanes[lane]);
                assert_eq!(sines[lane].to_bits(), s.to_bits(), "sin {}", lanes[lane]);
                assert_eq!(cosines[lane].to_bits(), c.to_bits(), "cos {}", lanes[lane]);
            }
        }
    }
}
