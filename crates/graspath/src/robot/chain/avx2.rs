//! The forward pass with 256-bit vectors (AVX2), chosen at run time when the processor has it.
//!
//! A 3-vector lives in lanes 0–2 of one register (lane 3 is zero). Every lane does exactly the
//! IEEE operations of the scalar pass, in the same order and without fused multiply–add, so the
//! two passes give bit-identical poses and Jacobians; the sines and cosines of four joints are
//! computed at once.

use super::{pose_from_columns, MotionKind, Segment};
use crate::robot::trig::sin_cos4;
use nalgebra::{IsometryMatrix3, Matrix3, Vector3};
use std::arch::x86_64::*;

/// Whether this processor can run [`forward`] (checked once, then cached by the standard library).
#[inline(always)]
pub(super) fn available() -> bool {
    is_x86_feature_detected!("avx2")
}

/// `a·x + b·y + c·z`, evaluated as `((a·x + b·y) + c·z)` like the scalar `combine`.
#[inline(always)]
unsafe fn combine(x: __m256d, a: f64, y: __m256d, b: f64, z: __m256d, c: f64) -> __m256d {
    _mm256_add_pd(
        _mm256_add_pd(
            _mm256_mul_pd(x, _mm256_set1_pd(a)),
            _mm256_mul_pd(y, _mm256_set1_pd(b)),
        ),
        _mm256_mul_pd(z, _mm256_set1_pd(c)),
    )
}

/// `a × b` on lanes 0–2, as `a₁b₂ − a₂b₁, a₂b₀ − a₀b₂, a₀b₁ − a₁b₀`.
#[inline(always)]
unsafe fn cross(a: __m256d, b: __m256d) -> __m256d {
    // Lane orders (1, 2, 0, 3) and (2, 0, 1, 3).
    const YZX: i32 = 0b11_00_10_01;
    const ZXY: i32 = 0b11_01_00_10;
    _mm256_sub_pd(
        _mm256_mul_pd(
            _mm256_permute4x64_pd::<YZX>(a),
            _mm256_permute4x64_pd::<ZXY>(b),
        ),
        _mm256_mul_pd(
            _mm256_permute4x64_pd::<ZXY>(a),
            _mm256_permute4x64_pd::<YZX>(b),
        ),
    )
}

#[inline(always)]
unsafe fn lanes(v: __m256d) -> [f64; 3] {
    let mut out = [0.0; 4];
    _mm256_storeu_pd(out.as_mut_ptr(), v);
    [out[0], out[1], out[2]]
}

/// Writes Jacobian column `i` of `n` (`[linear; angular]`) at `column`. The 4-lane stores
/// spill one value into the next column, which that column's own store overwrites; the last
/// column stores its angular part without spilling.
#[inline(always)]
unsafe fn store_column(column: *mut f64, last: bool, linear: __m256d, angular: __m256d) {
    _mm256_storeu_pd(column, linear);
    if last {
        _mm_storeu_pd(column.add(3), _mm256_castpd256_pd128(angular));
        _mm_store_sd(column.add(5), _mm256_extractf128_pd::<1>(angular));
    } else {
        _mm256_storeu_pd(column.add(3), angular);
    }
}

/// The forward pass of `chain::forward_scalar`, four lanes at a time.
///
/// # Safety
/// The processor must support AVX2, and `jacobian`, when given, must hold `6 · segments.len()`
/// values.
#[target_feature(enable = "avx2")]
pub(super) unsafe fn forward(
    segments: &[Segment],
    joint_value: impl Fn(usize) -> f64,
    jacobian: Option<&mut [f64]>,
    tail: (&Matrix3<f64>, &Vector3<f64>),
) -> IsometryMatrix3<f64> {
    let n = segments.len();
    let jacobian = jacobian.map(|j| {
        debug_assert_eq!(j.len(), 6 * n);
        j.as_mut_ptr()
    });
    // Columns of the current frame's rotation and its origin, base frame.
    let mut c0 = _mm256_setr_pd(1.0, 0.0, 0.0, 0.0);
    let mut c1 = _mm256_setr_pd(0.0, 1.0, 0.0, 0.0);
    let mut c2 = _mm256_setr_pd(0.0, 0.0, 1.0, 0.0);
    let mut p = _mm256_setzero_pd();
    let (mut values, mut sines, mut cosines) = ([0.0; 4], [0.0; 4], [0.0; 4]);
    for (i, segment) in segments.iter().enumerate() {
        if i % 4 == 0 {
            values = std::array::from_fn(|k| if i + k < n { joint_value(i + k) } else { 0.0 });
            let (sin, cos) = sin_cos4(_mm256_loadu_pd(values.as_ptr()));
            _mm256_storeu_pd(sines.as_mut_ptr(), sin);
            _mm256_storeu_pd(cosines.as_mut_ptr(), cos);
        }
        let s = &segment.rotation;
        let t = &segment.translation;
        let (x, y, z) = if i == 0 {
            // The base frame: the placement is the segment's own transform.
            p = _mm256_setr_pd(t[0], t[1], t[2], 0.0);
            let column = |k: usize| _mm256_setr_pd(s[(0, k)], s[(1, k)], s[(2, k)], 0.0);
            (column(0), column(1), column(2))
        } else {
            p = _mm256_add_pd(p, combine(c0, t[0], c1, t[1], c2, t[2]));
            (
                combine(c0, s[(0, 0)], c1, s[(1, 0)], c2, s[(2, 0)]),
                combine(c0, s[(0, 1)], c1, s[(1, 1)], c2, s[(2, 1)]),
                combine(c0, s[(0, 2)], c1, s[(1, 2)], c2, s[(2, 2)]),
            )
        };
        let column = jacobian.map(|j| j.add(6 * i));
        match segment.kind {
            MotionKind::Revolute => {
                let sin = _mm256_set1_pd(sines[i % 4]);
                let cos = _mm256_set1_pd(cosines[i % 4]);
                c0 = _mm256_add_pd(_mm256_mul_pd(x, cos), _mm256_mul_pd(y, sin));
                c1 = _mm256_sub_pd(_mm256_mul_pd(y, cos), _mm256_mul_pd(x, sin));
                c2 = z;
                if let Some(column) = column {
                    // v = z × (p_tip − p): keep p for now, finish once the tip is known.
                    store_column(column, i + 1 == n, p, z);
                }
            }
            MotionKind::Prismatic => {
                (c0, c1, c2) = (x, y, z);
                p = _mm256_add_pd(p, _mm256_mul_pd(z, _mm256_set1_pd(values[i % 4])));
                if let Some(column) = column {
                    store_column(column, i + 1 == n, z, _mm256_setzero_pd());
                }
            }
        }
    }
    let (tail_rotation, tail_translation) = tail;
    let tt = tail_translation;
    let tip = _mm256_add_pd(p, combine(c0, tt[0], c1, tt[1], c2, tt[2]));
    let r = tail_rotation;
    let rotation = [0, 1, 2].map(|k| lanes(combine(c0, r[(0, k)], c1, r[(1, k)], c2, r[(2, k)])));
    if let Some(j) = jacobian {
        for (i, segment) in segments.iter().enumerate() {
            if segment.kind != MotionKind::Revolute {
                continue;
            }
            let column = j.add(6 * i);
            let origin = _mm256_loadu_pd(column);
            let axis = _mm256_setr_pd(*column.add(3), *column.add(4), *column.add(5), 0.0);
            let linear = cross(axis, _mm256_sub_pd(tip, origin));
            // Lane 3 of `origin` is the first angular value: keep it as it is.
            _mm256_storeu_pd(column, _mm256_blend_pd::<0b1000>(linear, origin));
        }
    }
    pose_from_columns(&rotation, &lanes(tip))
}

#[cfg(test)]
mod tests {
    use super::super::{forward_scalar, Chain};
    use crate::robot::spec::{ChainSpec, JointKind, JointSpec};
    use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
    use rand::rngs::Xoshiro256PlusPlus;
    use rand::{RngExt, SeedableRng};

    /// A random chain: random joint placements, axes and kinds, some mimic-free prismatic.
    fn random_chain(rng: &mut Xoshiro256PlusPlus, joints: usize) -> Chain {
        let mut specs = Vec::new();
        for i in 0..joints {
            let kind = match rng.random_range(0..6) {
                0 => JointKind::Prismatic,
                1 => JointKind::Fixed,
                2 => JointKind::Continuous,
                _ => JointKind::Revolute,
            };
            let axis = Vector3::new(
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
            );
            specs.push(JointSpec {
                name: format!("j{i}"),
                kind,
                parent_from_joint: Isometry3::from_parts(
                    Translation3::new(
                        rng.random_range(-0.4..0.4),
                        rng.random_range(-0.4..0.4),
                        rng.random_range(-0.4..0.4),
                    ),
                    UnitQuaternion::from_euler_angles(
                        rng.random_range(-3.0..3.0),
                        rng.random_range(-1.5..1.5),
                        rng.random_range(-3.0..3.0),
                    ),
                ),
                axis: axis.normalize(),
                lower: -3.0,
                upper: 3.0,
                mimic: None,
            });
        }
        Chain::from_spec(&ChainSpec {
            source_name: "random".into(),
            base_link: "base".into(),
            tip_link: "tip".into(),
            joints: specs,
            tip_from_tool: None,
        })
        .expect("valid random chain")
    }

    #[test]
    fn bit_identical_to_the_scalar_pass() {
        if !super::available() {
            eprintln!("no AVX2 on this processor: nothing to compare");
            return;
        }
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(7);
        for joints in 0..=14 {
            for _ in 0..50 {
                let chain = random_chain(&mut rng, joints);
                let n = chain.segments.len();
                let q: Vec<f64> = (0..n)
                    .map(|_| match rng.random_range(0..10) {
                        0 => rng.random_range(-2e5..2e5),
                        1 => 0.0,
                        2 => -0.0,
                        _ => rng.random_range(-7.0..7.0),
                    })
                    .collect();
                let tail = (&chain.tail_rotation, &chain.tail_translation);
                let (mut scalar, mut vector) = (vec![0.0; 6 * n], vec![1.0; 6 * n]);
                let a = forward_scalar(&chain.segments, |i| q[i], Some(&mut scalar), tail);
                // SAFETY: AVX2 is present (checked above); the storage has 6·n values.
                let b =
                    unsafe { super::forward(&chain.segments, |i| q[i], Some(&mut vector), tail) };
                let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                assert_eq!(
                    bits(scalar.as_slice()),
                    bits(vector.as_slice()),
                    "q = {q:?}"
                );
                assert_eq!(
                    bits(a.to_homogeneous().as_slice()),
                    bits(b.to_homogeneous().as_slice())
                );
                let c = unsafe { super::forward(&chain.segments, |i| q[i], None, tail) };
                assert_eq!(
                    bits(a.to_homogeneous().as_slice()),
                    bits(c.to_homogeneous().as_slice())
                );
            }
        }
    }
}
