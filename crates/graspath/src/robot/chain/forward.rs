//! The scalar forward passes and the single-configuration entry points: the tip pose (with
//! the geometric Jacobian when asked) and every link frame along the chain. Each entry point
//! runs the AVX2 kernel of [`super::avx2`] when the processor has it (checked at run time) and
//! the scalar pass otherwise; both give bit-identical results.

use super::{pose_from_columns, Chain, LinkSlot, MotionKind, Segment, MAX_JOINTS};
use crate::robot::error::RobotError;
use nalgebra::{IsometryMatrix3, Matrix3, Matrix6xX, Vector3};

impl Chain {
    /// Every link frame at configuration `q` (rad / m), in one forward pass: `out[k]` receives
    /// `base_from_link` of link `k` of [`Chain::link_names`] (base frame, m). `out` must have
    /// exactly one entry per link. Nothing is allocated.
    ///
    /// On x86-64 processors with AVX2 (detected at run time) the pass runs on 256-bit vectors;
    /// it performs the scalar pass's IEEE operations in the same order, so the frames are
    /// bit-identical on every processor. Link offsets that are exactly the identity (a joint
    /// axis already along `z`) are copied, not multiplied.
    ///
    /// ```
    /// use graspath::robot::builtin::{baxter, Arm};
    /// use nalgebra::IsometryMatrix3;
    /// let chain = baxter(Arm::Left);
    /// let mut frames = vec![IsometryMatrix3::identity(); chain.link_names().len()];
    /// chain.link_frames_into(&[0.0; 7], &mut frames)?;
    /// let wrist = chain.link_index("left_wrist").expect("a link of the chain");
    /// assert!(frames[wrist].translation.vector.norm() > 0.5);
    /// # Ok::<(), graspath::robot::RobotError>(())
    /// ```
    pub fn link_frames_into(
        &self,
        q: &[f64],
        out: &mut [IsometryMatrix3<f64>],
    ) -> Result<(), RobotError> {
        self.check_configuration(q)?;
        if out.len() != self.link_slots.len() {
            return Err(RobotError::WrongLinkCount {
                chain: self.name(),
                expected: self.link_slots.len(),
                got: out.len(),
            });
        }
        match &self.drives {
            None => link_frames(&self.segments, &self.link_slots, |i| q[i], out),
            Some(d) => link_frames(
                &self.segments,
                &self.link_slots,
                |i| d[i].multiplier * q[d[i].source] + d[i].offset,
                out,
            ),
        }
        Ok(())
    }

    /// Every link frame at `q`, newly allocated (see [`Chain::link_frames_into`]).
    pub fn link_frames(&self, q: &[f64]) -> Result<Vec<IsometryMatrix3<f64>>, RobotError> {
        let mut out = vec![IsometryMatrix3::identity(); self.link_slots.len()];
        self.link_frames_into(q, &mut out)?;
        Ok(out)
    }

    /// The tip pose `base_from_tip` at configuration `q` (rad / m).
    pub fn pose(&self, q: &[f64]) -> Result<IsometryMatrix3<f64>, RobotError> {
        self.check_configuration(q)?;
        Ok(self.pose_unchecked(q))
    }

    /// The tip pose and the geometric Jacobian (6 × dof, rows `[v; ω]`, base frame) at `q`.
    ///
    /// `jacobian` is resized once if it has the wrong number of columns; with the right size
    /// nothing is allocated.
    pub fn pose_and_jacobian_into(
        &self,
        q: &[f64],
        jacobian: &mut Matrix6xX<f64>,
    ) -> Result<IsometryMatrix3<f64>, RobotError> {
        self.check_configuration(q)?;
        if jacobian.ncols() != self.dof() {
            *jacobian = Matrix6xX::zeros(self.dof());
        }
        Ok(self.pose_and_jacobian_unchecked(q, jacobian.as_mut_slice()))
    }

    /// The tip pose and a newly allocated geometric Jacobian at `q`.
    pub fn pose_and_jacobian(
        &self,
        q: &[f64],
    ) -> Result<(IsometryMatrix3<f64>, Matrix6xX<f64>), RobotError> {
        let mut jacobian = Matrix6xX::zeros(self.dof());
        let pose = self.pose_and_jacobian_into(q, &mut jacobian)?;
        Ok((pose, jacobian))
    }

    /// Forward kinematics without checks; `q.len()` must equal [`Chain::dof`].
    pub(crate) fn pose_unchecked(&self, q: &[f64]) -> IsometryMatrix3<f64> {
        match &self.drives {
            None => forward(&self.segments, |i| q[i], None, self.tail()),
            Some(drives) => forward(
                &self.segments,
                |i| drives[i].multiplier * q[drives[i].source] + drives[i].offset,
                None,
                self.tail(),
            ),
        }
    }

    /// Pose and Jacobian without checks; `jacobian` is the column-major 6 × dof storage.
    pub(crate) fn pose_and_jacobian_unchecked(
        &self,
        q: &[f64],
        jacobian: &mut [f64],
    ) -> IsometryMatrix3<f64> {
        match &self.drives {
            None => forward(&self.segments, |i| q[i], Some(jacobian), self.tail()),
            Some(drives) => {
                let mut expanded = [0.0; 6 * MAX_JOINTS];
                let expanded = &mut expanded[..6 * self.segments.len()];
                let pose = forward(
                    &self.segments,
                    |i| drives[i].multiplier * q[drives[i].source] + drives[i].offset,
                    Some(expanded),
                    self.tail(),
                );
                jacobian.fill(0.0);
                for (i, drive) in drives.iter().enumerate() {
                    for r in 0..6 {
                        jacobian[6 * drive.source + r] += drive.multiplier * expanded[6 * i + r];
                    }
                }
                pose
            }
        }
    }
}

/// `a·x + b·y + c·z` for 3-vectors.
#[inline(always)]
fn combine(x: &[f64; 3], a: f64, y: &[f64; 3], b: f64, z: &[f64; 3], c: f64) -> [f64; 3] {
    [
        x[0] * a + y[0] * b + z[0] * c,
        x[1] * a + y[1] * b + z[1] * c,
        x[2] * a + y[2] * b + z[2] * c,
    ]
}

#[inline(always)]
fn cross(a: &[f64; 3], b: &[f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// The forward pass: the AVX2 kernel when the processor has it, the scalar one otherwise.
/// Both do the same IEEE operations in the same order and give bit-identical results.
#[inline(always)]
pub(super) fn forward(
    segments: &[Segment],
    joint_value: impl Fn(usize) -> f64,
    jacobian: Option<&mut [f64]>,
    tail: (&Matrix3<f64>, &Vector3<f64>),
) -> IsometryMatrix3<f64> {
    if let Some(j) = jacobian.as_deref() {
        assert_eq!(j.len(), 6 * segments.len(), "Jacobian storage size");
    }
    #[cfg(target_arch = "x86_64")]
    if crate::cpu::has_avx2() {
        // SAFETY: the processor supports AVX2 (checked just above).
        return unsafe { super::avx2::forward(segments, joint_value, jacobian, tail) };
    }
    forward_scalar(segments, joint_value, jacobian, tail)
}

/// The scalar forward pass. Writes the Jacobian (column-major, 6 per segment) when asked.
///
/// The rotation is kept as three column arrays so the compiler sees plain scalar arithmetic.
#[inline(always)]
pub(super) fn forward_scalar(
    segments: &[Segment],
    joint_value: impl Fn(usize) -> f64,
    jacobian: Option<&mut [f64]>,
    tail: (&Matrix3<f64>, &Vector3<f64>),
) -> IsometryMatrix3<f64> {
    // Columns of the current frame's rotation and its origin, base frame.
    let mut c = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let mut p = [0.0; 3];
    let mut jacobian = jacobian;
    for (i, segment) in segments.iter().enumerate() {
        let s = &segment.rotation;
        let t = &segment.translation;
        let column = |k: usize| [s[(0, k)], s[(1, k)], s[(2, k)]];
        let (x, y, z) = if i == 0 {
            // The base frame: the placement is the segment's own transform.
            p = [t[0], t[1], t[2]];
            (column(0), column(1), column(2))
        } else {
            let offset = combine(&c[0], t[0], &c[1], t[1], &c[2], t[2]);
            p = [p[0] + offset[0], p[1] + offset[1], p[2] + offset[2]];
            (
                combine(&c[0], s[(0, 0)], &c[1], s[(1, 0)], &c[2], s[(2, 0)]),
                combine(&c[0], s[(0, 1)], &c[1], s[(1, 1)], &c[2], s[(2, 1)]),
                combine(&c[0], s[(0, 2)], &c[1], s[(1, 2)], &c[2], s[(2, 2)]),
            )
        };
        let value = joint_value(i);
        match segment.kind {
            MotionKind::Revolute => {
                c = turned(&x, &y, z, value);
                if let Some(j) = jacobian.as_deref_mut() {
                    // v = z × (p_tip − p): keep p for now, finish once the tip is known.
                    if let Some(column) = j.get_mut(6 * i..6 * i + 6) {
                        column.copy_from_slice(&[p[0], p[1], p[2], z[0], z[1], z[2]]);
                    }
                }
            }
            MotionKind::Prismatic => {
                c = [x, y, z];
                p = [
                    p[0] + z[0] * value,
                    p[1] + z[1] * value,
                    p[2] + z[2] * value,
                ];
                if let Some(j) = jacobian.as_deref_mut() {
                    if let Some(column) = j.get_mut(6 * i..6 * i + 6) {
                        column.copy_from_slice(&[z[0], z[1], z[2], 0.0, 0.0, 0.0]);
                    }
                }
            }
        }
    }
    let (tail_rotation, tail_translation) = tail;
    let tt = tail_translation;
    let offset = combine(&c[0], tt[0], &c[1], tt[1], &c[2], tt[2]);
    let tip = [p[0] + offset[0], p[1] + offset[1], p[2] + offset[2]];
    let r = tail_rotation;
    let rotation = [0, 1, 2].map(|k| combine(&c[0], r[(0, k)], &c[1], r[(1, k)], &c[2], r[(2, k)]));
    if let Some(j) = jacobian {
        for (segment, column) in segments.iter().zip(j.chunks_exact_mut(6)) {
            if segment.kind == MotionKind::Revolute {
                let lever = [tip[0] - column[0], tip[1] - column[1], tip[2] - column[2]];
                let v = cross(&[column[3], column[4], column[5]], &lever);
                column[..3].copy_from_slice(&v);
            }
        }
    }
    pose_from_columns(&rotation, &tip)
}

/// The link-frame pass: the AVX2 kernel when the processor has it, the scalar one otherwise.
/// Both do the same IEEE operations in the same order and give bit-identical frames.
#[inline(always)]
pub(super) fn link_frames(
    segments: &[Segment],
    slots: &[LinkSlot],
    joint_value: impl Fn(usize) -> f64,
    out: &mut [IsometryMatrix3<f64>],
) {
    assert_eq!(out.len(), slots.len(), "link frame storage size");
    #[cfg(target_arch = "x86_64")]
    if crate::cpu::has_avx2() {
        // SAFETY: the processor supports AVX2 (checked just above); `out` has one entry per
        // slot (asserted above).
        unsafe { super::avx2::link_frames(segments, slots, joint_value, out) };
        return;
    }
    link_frames_scalar(segments, slots, joint_value, out);
}

/// The scalar link-frame pass: the forward pass of [`forward_scalar`] (without the
/// Jacobian) that writes each link frame `out[k]` (`base_from_link`, base frame, m) as soon
/// as the aligned frame it hangs on is known. `out` holds one entry per slot.
#[inline(always)]
pub(super) fn link_frames_scalar(
    segments: &[Segment],
    slots: &[LinkSlot],
    joint_value: impl Fn(usize) -> f64,
    out: &mut [IsometryMatrix3<f64>],
) {
    let mut c = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let mut p = [0.0; 3];
    let mut k = 0;
    let mut emit = |c: &[[f64; 3]; 3], p: &[f64; 3], k: &mut usize, segment: Option<usize>| {
        while *k < slots.len() && slots[*k].segment == segment {
            let slot = &slots[*k];
            if slot.identity {
                out[*k] = pose_from_columns(c, p);
                *k += 1;
                continue;
            }
            let (r, t) = (&slot.rotation, &slot.translation);
            let offset = combine(&c[0], t[0], &c[1], t[1], &c[2], t[2]);
            let origin = [p[0] + offset[0], p[1] + offset[1], p[2] + offset[2]];
            let rotation =
                [0, 1, 2].map(|j| combine(&c[0], r[(0, j)], &c[1], r[(1, j)], &c[2], r[(2, j)]));
            out[*k] = pose_from_columns(&rotation, &origin);
            *k += 1;
        }
    };
    emit(&c, &p, &mut k, None);
    for (i, segment) in segments.iter().enumerate() {
        let s = &segment.rotation;
        let t = &segment.translation;
        let offset = combine(&c[0], t[0], &c[1], t[1], &c[2], t[2]);
        p = [p[0] + offset[0], p[1] + offset[1], p[2] + offset[2]];
        let x = combine(&c[0], s[(0, 0)], &c[1], s[(1, 0)], &c[2], s[(2, 0)]);
        let y = combine(&c[0], s[(0, 1)], &c[1], s[(1, 1)], &c[2], s[(2, 1)]);
        let z = combine(&c[0], s[(0, 2)], &c[1], s[(1, 2)], &c[2], s[(2, 2)]);
        let value = joint_value(i);
        match segment.kind {
            MotionKind::Revolute => {
                c = turned(&x, &y, z, value);
            }
            MotionKind::Prismatic => {
                c = [x, y, z];
                p = [
                    p[0] + z[0] * value,
                    p[1] + z[1] * value,
                    p[2] + z[2] * value,
                ];
            }
        }
        emit(&c, &p, &mut k, Some(i));
    }
}

/// The columns `x, y, z` of a revolute joint's frame turned by `value` (rad) about `z`.
#[inline(always)]
fn turned(x: &[f64; 3], y: &[f64; 3], z: [f64; 3], value: f64) -> [[f64; 3]; 3] {
    let (sin, cos) = crate::robot::trig::sin_cos(value);
    [
        [
            x[0] * cos + y[0] * sin,
            x[1] * cos + y[1] * sin,
            x[2] * cos + y[2] * sin,
        ],
        [
            y[0] * cos - x[0] * sin,
            y[1] * cos - x[1] * sin,
            y[2] * cos - x[2] * sin,
        ],
        z,
    ]
}
