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

/// Three lanes-of-four values: component `r` of a 3-vector for four configurations.
type Lanes3 = [__m256d; 3];

/// `a·x + b·y + c·z` per component, evaluated like the scalar `combine`.
#[inline(always)]
unsafe fn combine4(x: &Lanes3, a: f64, y: &Lanes3, b: f64, z: &Lanes3, c: f64) -> Lanes3 {
    let (a, b, c) = (_mm256_set1_pd(a), _mm256_set1_pd(b), _mm256_set1_pd(c));
    let one = |r: usize| {
        _mm256_add_pd(
            _mm256_add_pd(_mm256_mul_pd(x[r], a), _mm256_mul_pd(y[r], b)),
            _mm256_mul_pd(z[r], c),
        )
    };
    [one(0), one(1), one(2)]
}

/// `a + b` per component.
#[inline(always)]
unsafe fn add3(a: &Lanes3, b: &Lanes3) -> Lanes3 {
    [
        _mm256_add_pd(a[0], b[0]),
        _mm256_add_pd(a[1], b[1]),
        _mm256_add_pd(a[2], b[2]),
    ]
}

/// `a − b` per component.
#[inline(always)]
unsafe fn sub3(a: &Lanes3, b: &Lanes3) -> Lanes3 {
    [
        _mm256_sub_pd(a[0], b[0]),
        _mm256_sub_pd(a[1], b[1]),
        _mm256_sub_pd(a[2], b[2]),
    ]
}

/// `a · s` per component.
#[inline(always)]
unsafe fn scale3(a: &Lanes3, s: __m256d) -> Lanes3 {
    [
        _mm256_mul_pd(a[0], s),
        _mm256_mul_pd(a[1], s),
        _mm256_mul_pd(a[2], s),
    ]
}

/// The same 3-vector in every lane.
#[inline(always)]
unsafe fn splat3(v: [f64; 3]) -> Lanes3 {
    [
        _mm256_set1_pd(v[0]),
        _mm256_set1_pd(v[1]),
        _mm256_set1_pd(v[2]),
    ]
}

/// `a × b` per lane, as `a₁b₂ − a₂b₁, a₂b₀ − a₀b₂, a₀b₁ − a₁b₀`.
#[inline(always)]
unsafe fn cross3(a: &Lanes3, b: &Lanes3) -> Lanes3 {
    [
        _mm256_sub_pd(_mm256_mul_pd(a[1], b[2]), _mm256_mul_pd(a[2], b[1])),
        _mm256_sub_pd(_mm256_mul_pd(a[2], b[0]), _mm256_mul_pd(a[0], b[2])),
        _mm256_sub_pd(_mm256_mul_pd(a[0], b[1]), _mm256_mul_pd(a[1], b[0])),
    ]
}

/// The tip pose of four configurations: rotation columns and origin, one lane per
/// configuration.
pub(super) struct Poses4 {
    pub rotation: [Lanes3; 3],
    pub origin: Lanes3,
}

/// The scalar forward pass (`chain::forward_scalar`) for four configurations at once, one per
/// lane: every lane performs exactly the scalar pass's operations, so each configuration gets
/// bit-identical results. `values[i]` holds segment `i`'s joint values of the four
/// configurations; the Jacobian, when asked, goes to `jacobian[6·i + row]` (rows `[v; ω]`).
///
/// # Safety
/// The processor must support AVX2; `values` and `jacobian` (when given) must hold
/// `segments.len()` and `6 · segments.len()` entries.
#[target_feature(enable = "avx2")]
pub(super) unsafe fn forward4(
    segments: &[Segment],
    values: &[[f64; 4]],
    mut jacobian: Option<&mut [[f64; 4]]>,
    (tail_rotation, tail_translation): (&Matrix3<f64>, &Vector3<f64>),
) -> Poses4 {
    let zero = _mm256_setzero_pd();
    let mut c: [Lanes3; 3] = [
        splat3([1.0, 0.0, 0.0]),
        splat3([0.0, 1.0, 0.0]),
        splat3([0.0, 0.0, 1.0]),
    ];
    let mut p: Lanes3 = [zero; 3];
    for (i, segment) in segments.iter().enumerate() {
        let s = &segment.rotation;
        let t = &segment.translation;
        let (x, y, z) = if i == 0 {
            p = splat3([t[0], t[1], t[2]]);
            (
                splat3([s[(0, 0)], s[(1, 0)], s[(2, 0)]]),
                splat3([s[(0, 1)], s[(1, 1)], s[(2, 1)]]),
                splat3([s[(0, 2)], s[(1, 2)], s[(2, 2)]]),
            )
        } else {
            p = add3(&p, &combine4(&c[0], t[0], &c[1], t[1], &c[2], t[2]));
            (
                combine4(&c[0], s[(0, 0)], &c[1], s[(1, 0)], &c[2], s[(2, 0)]),
                combine4(&c[0], s[(0, 1)], &c[1], s[(1, 1)], &c[2], s[(2, 1)]),
                combine4(&c[0], s[(0, 2)], &c[1], s[(1, 2)], &c[2], s[(2, 2)]),
            )
        };
        let value = _mm256_loadu_pd(values[i].as_ptr());
        let column: [__m256d; 6] = match segment.kind {
            MotionKind::Revolute => {
                let (sin, cos) = sin_cos4(value);
                c = [
                    add3(&scale3(&x, cos), &scale3(&y, sin)),
                    sub3(&scale3(&y, cos), &scale3(&x, sin)),
                    z,
                ];
                [p[0], p[1], p[2], z[0], z[1], z[2]]
            }
            MotionKind::Prismatic => {
                c = [x, y, z];
                p = add3(&p, &scale3(&z, value));
                [z[0], z[1], z[2], zero, zero, zero]
            }
        };
        if let Some(j) = jacobian.as_deref_mut() {
            for (row, v) in column.iter().enumerate() {
                _mm256_storeu_pd(j[6 * i + row].as_mut_ptr(), *v);
            }
        }
    }
    let tt = tail_translation;
    let tip = add3(&p, &combine4(&c[0], tt[0], &c[1], tt[1], &c[2], tt[2]));
    let r = tail_rotation;
    let rotation = [
        combine4(&c[0], r[(0, 0)], &c[1], r[(1, 0)], &c[2], r[(2, 0)]),
        combine4(&c[0], r[(0, 1)], &c[1], r[(1, 1)], &c[2], r[(2, 1)]),
        combine4(&c[0], r[(0, 2)], &c[1], r[(1, 2)], &c[2], r[(2, 2)]),
    ];
    if let Some(j) = jacobian {
        for (i, segment) in segments.iter().enumerate() {
            if segment.kind != MotionKind::Revolute {
                continue;
            }
            let column = &mut j[6 * i..6 * i + 6];
            let load = |row: &[f64; 4]| _mm256_loadu_pd(row.as_ptr());
            let origin = [load(&column[0]), load(&column[1]), load(&column[2])];
            let axis = [load(&column[3]), load(&column[4]), load(&column[5])];
            let linear = cross3(&axis, &sub3(&tip, &origin));
            for (row, v) in column.iter_mut().zip(linear) {
                _mm256_storeu_pd(row.as_mut_ptr(), v);
            }
        }
    }
    Poses4 {
        rotation,
        origin: tip,
    }
}

#[cfg(test)]
mod tests {
    use super::super::{forward_scalar, Chain};
    use crate::robot::spec::{ChainSpec, JointKind, JointSpec, Mimic};
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
                child_link: format!("l{i}"),
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

    #[test]
    fn batches_equal_one_call_per_configuration_bit_for_bit() {
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(11);
        for joints in [1, 3, 6, 7, 9] {
            for _ in 0..20 {
                let chain = random_chain(&mut rng, joints);
                let dof = chain.dof();
                if dof == 0 {
                    continue;
                }
                for count in 0..=9 {
                    let q: Vec<f64> = (0..count * dof)
                        .map(|_| rng.random_range(-7.0..7.0))
                        .collect();
                    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                    let mut seen = Vec::new();
                    chain
                        .for_each_pose_and_jacobian(&q, |k, pose, jacobian| {
                            let (one, expected) =
                                chain.pose_and_jacobian(&q[k * dof..(k + 1) * dof]).unwrap();
                            assert_eq!(
                                bits(pose.to_homogeneous().as_slice()),
                                bits(one.to_homogeneous().as_slice())
                            );
                            assert_eq!(bits(jacobian), bits(expected.as_slice()));
                            seen.push(k);
                        })
                        .unwrap();
                    assert_eq!(seen, (0..count).collect::<Vec<_>>());
                    let mut poses = 0;
                    chain
                        .for_each_pose(&q, |k, pose| {
                            let one = chain.pose(&q[k * dof..(k + 1) * dof]).unwrap();
                            assert_eq!(
                                bits(pose.to_homogeneous().as_slice()),
                                bits(one.to_homogeneous().as_slice())
                            );
                            poses += 1;
                        })
                        .unwrap();
                    assert_eq!(poses, count);
                }
            }
        }
    }

    #[test]
    fn batches_of_a_chain_with_a_mimic_joint_equal_single_calls() {
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(5);
        let joint = |name: &str, mimic: Option<Mimic>| JointSpec {
            name: name.into(),
            child_link: String::new(),
            kind: JointKind::Revolute,
            parent_from_joint: Isometry3::from_parts(
                Translation3::new(0.1, 0.02, 0.3),
                UnitQuaternion::from_euler_angles(0.3, -0.2, 0.1),
            ),
            axis: Vector3::new(0.0, 1.0, 0.0),
            lower: -3.0,
            upper: 3.0,
            mimic,
        };
        let chain = Chain::from_spec(&ChainSpec {
            source_name: "mimic".into(),
            base_link: "base".into(),
            tip_link: "tip".into(),
            joints: vec![
                joint("a", None),
                joint("b", None),
                joint(
                    "c",
                    Some(Mimic {
                        leader: "a".into(),
                        multiplier: 2.0,
                        offset: 0.1,
                    }),
                ),
            ],
            tip_from_tool: None,
        })
        .expect("valid chain");
        assert_eq!(chain.dof(), 2);
        let q: Vec<f64> = (0..14).map(|_| rng.random_range(-3.0..3.0)).collect();
        let mut count = 0;
        chain
            .for_each_pose_and_jacobian(&q, |k, pose, jacobian| {
                let (one, expected) = chain.pose_and_jacobian(&q[2 * k..2 * k + 2]).unwrap();
                assert_eq!(pose, &one);
                assert_eq!(jacobian, expected.as_slice());
                count += 1;
            })
            .unwrap();
        assert_eq!(count, 7);
    }

    #[test]
    fn batches_refuse_partial_rows_and_non_finite_values() {
        let chain = random_chain(&mut Xoshiro256PlusPlus::seed_from_u64(3), 7);
        let dof = chain.dof();
        assert!(dof > 1);
        let partial = vec![0.0; 2 * dof + 1];
        let err = chain.for_each_pose(&partial, |_, _| {}).unwrap_err();
        assert!(
            err.to_string().contains(&format!("{} values", 2 * dof + 1)),
            "{err}"
        );
        let mut nan = vec![0.0; 3 * dof];
        nan[dof + 1] = f64::NAN;
        let err = chain
            .for_each_pose_and_jacobian(&nan, |_, _, _| panic!("nothing may be emitted"))
            .unwrap_err();
        assert!(
            err.to_string().contains(&format!("q[{}]", dof + 1)),
            "{err}"
        );
    }
}
