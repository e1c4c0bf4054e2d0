//! The forward pass with 256-bit vectors (AVX2), chosen at run time when the processor has it.
//!
//! A 3-vector lives in lanes 0–2 of one register (lane 3 is zero). Every lane does exactly the
//! IEEE operations of the scalar pass, in the same order and without fused multiply–add, so the
//! two passes give bit-identical poses and Jacobians; the sines and cosines of four joints are
//! computed at once.

use super::{pose_from_columns, LinkSlot, MotionKind, Segment};
use crate::robot::trig::sin_cos4;
use nalgebra::{IsometryMatrix3, Matrix3, Vector3};
use std::arch::x86_64::*;

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

/// Writes the low three lanes of `v` to `dst[0..3]`.
#[inline(always)]
unsafe fn store3(dst: *mut f64, v: __m256d) {
    _mm_storeu_pd(dst, _mm256_castpd256_pd128(v));
    _mm_store_sd(dst.add(2), _mm256_extractf128_pd::<1>(v));
}

/// Writes the pose with rotation columns `c` and origin `p` into `frame`. The first two
/// 4-lane stores spill one value into the next column, which that column's store overwrites.
#[inline(always)]
unsafe fn store_pose(frame: &mut IsometryMatrix3<f64>, c: [__m256d; 3], p: __m256d) {
    let rotation = frame.rotation.matrix_mut_unchecked().as_mut_ptr();
    _mm256_storeu_pd(rotation, c[0]);
    _mm256_storeu_pd(rotation.add(3), c[1]);
    store3(rotation.add(6), c[2]);
    store3(frame.translation.vector.as_mut_ptr(), p);
}

/// Writes every link frame that hangs on the aligned frame (`c`, `p`) of `segment`, starting
/// at link `*k`, like the scalar pass's `emit`.
#[inline(always)]
unsafe fn emit_links(
    slots: &[LinkSlot],
    out: &mut [IsometryMatrix3<f64>],
    k: &mut usize,
    segment: Option<usize>,
    c: [__m256d; 3],
    p: __m256d,
) {
    while let Some(slot) = slots.get(*k).filter(|slot| slot.segment == segment) {
        let frame = &mut out[*k];
        *k += 1;
        if slot.identity {
            store_pose(frame, c, p);
            continue;
        }
        let (r, t) = (&slot.rotation, &slot.translation);
        let origin = _mm256_add_pd(p, combine(c[0], t[0], c[1], t[1], c[2], t[2]));
        // Written out rather than with `array::map`: a closure would not inherit AVX2.
        let rotation = [
            combine(c[0], r[(0, 0)], c[1], r[(1, 0)], c[2], r[(2, 0)]),
            combine(c[0], r[(0, 1)], c[1], r[(1, 1)], c[2], r[(2, 1)]),
            combine(c[0], r[(0, 2)], c[1], r[(1, 2)], c[2], r[(2, 2)]),
        ];
        store_pose(frame, rotation, origin);
    }
}

/// The link-frame pass of `chain::forward::link_frames_scalar` on 256-bit vectors: every link
/// frame `out[k]` (`base_from_link`, base frame, m), bit-identical to the scalar pass. The
/// sines and cosines of four joints are computed at once.
///
/// # Safety
/// The processor must support AVX2. (`out` must hold one entry per slot; a shorter `out`
/// panics, it is never written out of bounds.)
#[target_feature(enable = "avx2")]
pub(super) unsafe fn link_frames(
    segments: &[Segment],
    slots: &[LinkSlot],
    joint_value: impl Fn(usize) -> f64,
    out: &mut [IsometryMatrix3<f64>],
) {
    let n = segments.len();
    // Columns of the current aligned frame's rotation and its origin, base frame.
    let mut c = [
        _mm256_setr_pd(1.0, 0.0, 0.0, 0.0),
        _mm256_setr_pd(0.0, 1.0, 0.0, 0.0),
        _mm256_setr_pd(0.0, 0.0, 1.0, 0.0),
    ];
    let mut p = _mm256_setzero_pd();
    let mut k = 0;
    emit_links(slots, out, &mut k, None, c, p);
    let (mut values, mut sines, mut cosines) = ([0.0; 4], [0.0; 4], [0.0; 4]);
    for (i, segment) in segments.iter().enumerate() {
        if i % 4 == 0 {
            for (j, value) in values.iter_mut().enumerate() {
                *value = if i + j < n { joint_value(i + j) } else { 0.0 };
            }
            let (sin, cos) = sin_cos4(_mm256_loadu_pd(values.as_ptr()));
            _mm256_storeu_pd(sines.as_mut_ptr(), sin);
            _mm256_storeu_pd(cosines.as_mut_ptr(), cos);
        }
        let s = &segment.rotation;
        let t = &segment.translation;
        p = _mm256_add_pd(p, combine(c[0], t[0], c[1], t[1], c[2], t[2]));
        let x = combine(c[0], s[(0, 0)], c[1], s[(1, 0)], c[2], s[(2, 0)]);
        let y = combine(c[0], s[(0, 1)], c[1], s[(1, 1)], c[2], s[(2, 1)]);
        let z = combine(c[0], s[(0, 2)], c[1], s[(1, 2)], c[2], s[(2, 2)]);
        match segment.kind {
            MotionKind::Revolute => {
                let sin = _mm256_set1_pd(sines[i % 4]);
                let cos = _mm256_set1_pd(cosines[i % 4]);
                c = [
                    _mm256_add_pd(_mm256_mul_pd(x, cos), _mm256_mul_pd(y, sin)),
                    _mm256_sub_pd(_mm256_mul_pd(y, cos), _mm256_mul_pd(x, sin)),
                    z,
                ];
            }
            MotionKind::Prismatic => {
                c = [x, y, z];
                p = _mm256_add_pd(p, _mm256_mul_pd(z, _mm256_set1_pd(values[i % 4])));
            }
        }
        emit_links(slots, out, &mut k, Some(i), c, p);
    }
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

/// The 4 × 4 transpose of rows `a, b, c, d`: element `k` of the result is
/// `[a[k], b[k], c[k], d[k]]`.
#[inline(always)]
unsafe fn transpose4(a: __m256d, b: __m256d, c: __m256d, d: __m256d) -> [__m256d; 4] {
    let ab_even = _mm256_unpacklo_pd(a, b); // a0 b0 a2 b2
    let ab_odd = _mm256_unpackhi_pd(a, b); // a1 b1 a3 b3
    let cd_even = _mm256_unpacklo_pd(c, d); // c0 d0 c2 d2
    let cd_odd = _mm256_unpackhi_pd(c, d); // c1 d1 c3 d3
    [
        _mm256_permute2f128_pd::<0x20>(ab_even, cd_even),
        _mm256_permute2f128_pd::<0x20>(ab_odd, cd_odd),
        _mm256_permute2f128_pd::<0x31>(ab_even, cd_even),
        _mm256_permute2f128_pd::<0x31>(ab_odd, cd_odd),
    ]
}

/// Writes the tip poses of the first `count` lanes of a group as row-major homogeneous 4 × 4
/// matrices, 16 values each, one after the other from `out[0]` (the values of the lanes,
/// moved, never recomputed). Nothing is written when `out` is shorter than `16 · count`.
///
/// # Safety
/// The processor must support AVX2.
#[target_feature(enable = "avx2")]
pub(super) unsafe fn store_pose_rows(poses: &Poses4, count: usize, out: &mut [f64]) {
    let count = count.min(4);
    if out.len() < 16 * count {
        return;
    }
    let out = out.as_mut_ptr();
    for r in 0..3 {
        let rows = transpose4(
            poses.rotation[0][r],
            poses.rotation[1][r],
            poses.rotation[2][r],
            poses.origin[r],
        );
        for (lane, row) in rows.iter().enumerate().take(count) {
            // SAFETY: `16 · lane + 4 · r + 4 ≤ 16 · count ≤ out.len()`.
            _mm256_storeu_pd(out.add(16 * lane + 4 * r), *row);
        }
    }
    let last = _mm256_setr_pd(0.0, 0.0, 0.0, 1.0);
    for lane in 0..count {
        // SAFETY: as above.
        _mm256_storeu_pd(out.add(16 * lane + 12), last);
    }
}

/// Writes the Jacobians of the first `count` lanes of a group, given in lane layout
/// (`lanes[6·i + r]` holds row `r` of column `i`, as [`forward4`] writes them), as row-major
/// 6 × dof matrices one after the other from `out[0]` (moved, never recomputed). Nothing is
/// written when `lanes` or `out` is too short.
///
/// # Safety
/// The processor must support AVX2.
#[target_feature(enable = "avx2")]
pub(super) unsafe fn store_jacobian_rows(
    lanes: &[[f64; 4]],
    dof: usize,
    count: usize,
    out: &mut [f64],
) {
    let count = count.min(4);
    if lanes.len() < 6 * dof || out.len() < 6 * dof * count {
        return;
    }
    let out = out.as_mut_ptr();
    for r in 0..6 {
        for i in (0..dof).step_by(4) {
            let width = (dof - i).min(4);
            // Written out rather than with closures: a closure would not inherit AVX2.
            let mut columns = [_mm256_setzero_pd(); 4];
            for (k, column) in columns.iter_mut().enumerate().take(width) {
                *column = _mm256_loadu_pd(lanes[6 * (i + k) + r].as_ptr());
            }
            let rows = transpose4(columns[0], columns[1], columns[2], columns[3]);
            for (lane, row) in rows.iter().enumerate().take(count) {
                // SAFETY: the `width` values written end at
                // `6·dof·lane + dof·r + i + width ≤ 6 · dof · count ≤ out.len()`.
                let at = out.add(6 * dof * lane + dof * r + i);
                // A short block is stored in halves and singles (masked stores are slow on
                // some processors).
                let (low, high) = (
                    _mm256_castpd256_pd128(*row),
                    _mm256_extractf128_pd::<1>(*row),
                );
                match width {
                    4 => _mm256_storeu_pd(at, *row),
                    3 => {
                        _mm_storeu_pd(at, low);
                        _mm_store_sd(at.add(2), high);
                    }
                    2 => _mm_storeu_pd(at, low),
                    _ => _mm_store_sd(at, low),
                }
            }
        }
    }
}
