//! A serial chain flattened for speed, and its forward kinematics and geometric Jacobian.
//!
//! Every joint frame is re-oriented once, at construction, so that its axis is the local `z`
//! axis; the constant re-orientations are folded into the neighbouring fixed transforms. One
//! forward pass then costs, per joint, one 3×3 product, one `sin_cos` and a column rotation,
//! and writes the Jacobian column at the same time. Nothing is allocated per call.
//!
//! On x86-64 processors with AVX2 (detected at run time) the pass runs on 256-bit vectors
//! ([`avx2`]); it performs the same IEEE operations in the same order as the scalar pass, so
//! results do not depend on the processor. Batches of configurations
//! ([`Chain::for_each_pose_and_jacobian`]) run four at a time, one per vector lane.
//!
//! One file on purpose (about 900 lines): the chain's flattened layout, the scalar forward pass,
//! the link-frame pass and the batch entry points share private invariants (segment order,
//! aligned frames, mimic drives) that splitting would have to expose; the AVX2 pass is already
//! its own file.

use super::error::RobotError;
use super::spec::{ChainSpec, JointKind};
use nalgebra::{
    Isometry3, IsometryMatrix3, Matrix3, Matrix6xX, Rotation3, SMatrix, Translation3, Unit, Vector3,
};

#[cfg(target_arch = "x86_64")]
mod avx2;
mod sweep;

pub use sweep::SweepBound;

/// Largest number of moving joints in one chain (mimic followers included).
pub const MAX_JOINTS: usize = 64;

/// How an active joint moves its child.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MotionKind {
    /// Rotation about the joint axis (rad).
    Revolute,
    /// Translation along the joint axis (m).
    Prismatic,
}

/// One moving joint after flattening: the constant transform from the previous aligned joint
/// frame (or the base) to this joint's aligned frame at `q = 0`, whose `z` axis is the joint axis.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Segment {
    rotation: Matrix3<f64>,
    translation: Vector3<f64>,
    kind: MotionKind,
}

/// Which active joint drives a segment (mimic joints follow a leader).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Drive {
    source: usize,
    multiplier: f64,
    offset: f64,
}

/// Where a link's frame sits: on the aligned frame after moving segment `segment` (`None`: the
/// base frame), at the constant offset `aligned_from_link`.
#[derive(Debug, Clone, Copy, PartialEq)]
struct LinkSlot {
    segment: Option<usize>,
    rotation: Matrix3<f64>,
    translation: Vector3<f64>,
    /// The offset is exactly the identity (a joint axis already along `z`): copy the frame.
    identity: bool,
}

/// The largest distance (m) between consecutive joint frames: a larger offset is a unit
/// mistake (millimetres) or a corrupt file, and would overflow the kinematics.
pub const MAX_JOINT_OFFSET: f64 = 1000.0;

/// Checks what the kinematics needs of one joint: a finite origin within
/// [`MAX_JOINT_OFFSET`], and finite limits `lower ≤ upper` on a revolute or prismatic joint
/// (only a continuous joint is unbounded).
fn check_joint(spec: &ChainSpec, joint: &super::spec::JointSpec) -> Result<(), RobotError> {
    let bad = |field: &'static str, message: String| RobotError::BadJoint {
        source_name: spec.source_name.clone(),
        joint: joint.name.clone(),
        field,
        message,
    };
    let t = joint.parent_from_joint.translation.vector;
    let q = joint.parent_from_joint.rotation.coords;
    if t.iter().chain(q.iter()).any(|v| !v.is_finite()) {
        return Err(bad("origin", "must be finite".into()));
    }
    if t.amax() > MAX_JOINT_OFFSET {
        return Err(bad(
            "origin/@xyz",
            format!(
                "{:?} is more than {MAX_JOINT_OFFSET} m from the parent frame (are the units metres?)",
                t.as_slice()
            ),
        ));
    }
    let bounded = matches!(joint.kind, JointKind::Revolute | JointKind::Prismatic);
    if bounded
        && joint.mimic.is_none()
        && !(joint.lower.is_finite() && joint.upper.is_finite() && joint.lower <= joint.upper)
    {
        return Err(bad(
            "limit",
            format!(
                "lower {} and upper {} must be finite with lower <= upper",
                joint.lower, joint.upper
            ),
        ));
    }
    Ok(())
}

/// A serial kinematic chain from a base link to a tip link (plus an optional tool offset),
/// ready for fast forward kinematics. Cheap to share between threads (`Sync`, no interior state).
#[derive(Debug, Clone, PartialEq)]
pub struct Chain {
    source_name: String,
    base_link: String,
    tip_link: String,
    joint_names: Vec<String>,
    joint_kinds: Vec<JointKind>,
    lower: Vec<f64>,
    upper: Vec<f64>,
    segments: Vec<Segment>,
    /// `None` when segment `i` is driven by `q[i]` (no mimic joints).
    drives: Option<Vec<Drive>>,
    tail_rotation: Matrix3<f64>,
    tail_translation: Vector3<f64>,
    /// Every link from the base to the tip, in chain order.
    link_names: Vec<String>,
    link_slots: Vec<LinkSlot>,
}

/// A rotation taking the `z` axis onto the unit vector `axis`.
fn z_onto(axis: &Vector3<f64>) -> Rotation3<f64> {
    Rotation3::rotation_between(&Vector3::z(), axis).unwrap_or_else(|| {
        // `axis` is −z: turn half a revolution about x.
        Rotation3::from_axis_angle(&Vector3::x_axis(), std::f64::consts::PI)
    })
}

impl Chain {
    /// Flattens a chain description. Fixed joints become constant transforms; mimic joints
    /// follow their leader (which must be on the chain).
    pub fn from_spec(spec: &ChainSpec) -> Result<Self, RobotError> {
        let mut joint_names = Vec::new();
        let mut joint_kinds = Vec::new();
        let mut lower = Vec::new();
        let mut upper = Vec::new();
        let mut segments = Vec::new();
        let mut drives = Vec::new();
        let mut has_mimic = false;
        // The transform from the last aligned frame (or the base) to the current link frame.
        let mut pending = Isometry3::<f64>::identity();
        let slot = |segment: Option<usize>, pending: &Isometry3<f64>| {
            let rotation = pending.rotation.to_rotation_matrix().into_inner();
            let translation = pending.translation.vector;
            LinkSlot {
                segment,
                rotation,
                translation,
                identity: rotation == Matrix3::identity() && translation == Vector3::zeros(),
            }
        };
        let mut link_names = vec![spec.base_link.clone()];
        let mut link_slots = vec![slot(None, &pending)];
        let child_name = |joint: &super::spec::JointSpec| {
            if joint.child_link.is_empty() {
                format!("{}_child", joint.name)
            } else {
                joint.child_link.clone()
            }
        };
        for joint in &spec.joints {
            check_joint(spec, joint)?;
            let motion = match joint.kind {
                JointKind::Fixed => {
                    pending *= joint.parent_from_joint;
                    link_names.push(child_name(joint));
                    link_slots.push(slot(segments.len().checked_sub(1), &pending));
                    continue;
                }
                JointKind::Revolute | JointKind::Continuous => MotionKind::Revolute,
                JointKind::Prismatic => MotionKind::Prismatic,
            };
            let align = Isometry3::from_parts(Translation3::identity(), z_onto(&joint.axis).into());
            let placement = pending * joint.parent_from_joint * align;
            pending = align.inverse();
            let drive = match &joint.mimic {
                None => {
                    joint_names.push(joint.name.clone());
                    joint_kinds.push(joint.kind);
                    lower.push(joint.lower);
                    upper.push(joint.upper);
                    Drive {
                        source: joint_names.len() - 1,
                        multiplier: 1.0,
                        offset: 0.0,
                    }
                }
                Some(mimic) => {
                    has_mimic = true;
                    let source = joint_names
                        .iter()
                        .position(|n| *n == mimic.leader)
                        .ok_or_else(|| RobotError::BadJoint {
                            source_name: spec.source_name.clone(),
                            joint: joint.name.clone(),
                            field: "mimic/@joint",
                            message: format!(
                                "mimics '{}', which is not an earlier joint of the chain {} -> {}",
                                mimic.leader, spec.base_link, spec.tip_link
                            ),
                        })?;
                    Drive {
                        source,
                        multiplier: mimic.multiplier,
                        offset: mimic.offset,
                    }
                }
            };
            drives.push(drive);
            segments.push(Segment {
                rotation: placement.rotation.to_rotation_matrix().into_inner(),
                translation: placement.translation.vector,
                kind: motion,
            });
            link_names.push(child_name(joint));
            link_slots.push(slot(Some(segments.len() - 1), &pending));
        }
        if segments.len() > MAX_JOINTS {
            return Err(RobotError::BadJoint {
                source_name: spec.source_name.clone(),
                joint: spec.tip_link.clone(),
                field: "joint",
                message: format!("the chain has more than {MAX_JOINTS} moving joints"),
            });
        }
        let tail = pending * spec.tip_from_tool.unwrap_or_else(Isometry3::identity);
        Ok(Self {
            source_name: spec.source_name.clone(),
            base_link: spec.base_link.clone(),
            tip_link: spec.tip_link.clone(),
            joint_names,
            joint_kinds,
            lower,
            upper,
            segments,
            drives: has_mimic.then_some(drives),
            tail_rotation: tail.rotation.to_rotation_matrix().into_inner(),
            tail_translation: tail.translation.vector,
            link_names,
            link_slots,
        })
    }

    /// The links of the chain in order, base first, tip link last (the tool frame is not a
    /// link). [`Chain::link_frames_into`] writes one frame per entry.
    pub fn link_names(&self) -> &[String] {
        &self.link_names
    }

    /// The index of link `name` in [`Chain::link_names`].
    pub fn link_index(&self, name: &str) -> Option<usize> {
        self.link_names.iter().position(|n| n == name)
    }

    /// Every link frame at configuration `q` (rad / m), in one forward pass: `out[k]` receives
    /// `base_from_link` of link `k` of [`Chain::link_names`] (base frame, m). `out` must have
    /// exactly one entry per link. Nothing is allocated.
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
            None => self.link_frames_unchecked(|i| q[i], out),
            Some(d) => {
                self.link_frames_unchecked(|i| d[i].multiplier * q[d[i].source] + d[i].offset, out);
            }
        }
        Ok(())
    }

    /// Every link frame at `q`, newly allocated (see [`Chain::link_frames_into`]).
    pub fn link_frames(&self, q: &[f64]) -> Result<Vec<IsometryMatrix3<f64>>, RobotError> {
        let mut out = vec![IsometryMatrix3::identity(); self.link_slots.len()];
        self.link_frames_into(q, &mut out)?;
        Ok(out)
    }

    /// The forward pass of [`forward_scalar`] that also emits each link frame as soon as the
    /// aligned frame it hangs on is known.
    #[inline(always)]
    fn link_frames_unchecked(
        &self,
        joint_value: impl Fn(usize) -> f64,
        out: &mut [IsometryMatrix3<f64>],
    ) {
        let mut c = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        let mut p = [0.0; 3];
        let slots = &self.link_slots;
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
                let rotation = [0, 1, 2]
                    .map(|j| combine(&c[0], r[(0, j)], &c[1], r[(1, j)], &c[2], r[(2, j)]));
                out[*k] = pose_from_columns(&rotation, &origin);
                *k += 1;
            }
        };
        emit(&c, &p, &mut k, None);
        for (i, segment) in self.segments.iter().enumerate() {
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
                    let (sin, cos) = super::trig::sin_cos(value);
                    c = [
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
                    ];
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

    /// The number of independent joints (the length of `q`).
    pub fn dof(&self) -> usize {
        self.joint_names.len()
    }

    /// `base->tip`, for messages.
    pub fn name(&self) -> String {
        format!("{}->{}", self.base_link, self.tip_link)
    }

    /// The file or built-in model the chain came from.
    pub fn source_name(&self) -> &str {
        &self.source_name
    }

    /// The base link (the frame of every pose and Jacobian).
    pub fn base_link(&self) -> &str {
        &self.base_link
    }

    /// The tip link.
    pub fn tip_link(&self) -> &str {
        &self.tip_link
    }

    /// The names of the independent joints, in the order of `q`.
    pub fn joint_names(&self) -> &[String] {
        &self.joint_names
    }

    /// The kinds of the independent joints.
    pub fn joint_kinds(&self) -> &[JointKind] {
        &self.joint_kinds
    }

    /// Lower joint limits (rad or m; `-∞` for continuous joints).
    pub fn lower(&self) -> &[f64] {
        &self.lower
    }

    /// Upper joint limits (rad or m; `+∞` for continuous joints).
    pub fn upper(&self) -> &[f64] {
        &self.upper
    }

    /// The middle of the joint limits (0 for an unbounded joint).
    pub fn mid_configuration(&self) -> Vec<f64> {
        self.lower
            .iter()
            .zip(&self.upper)
            .map(|(&lo, &hi)| {
                if lo.is_finite() && hi.is_finite() {
                    0.5 * (lo + hi)
                } else {
                    0.0
                }
            })
            .collect()
    }

    /// Whether every joint value lies within its limits (bounds included).
    pub fn within_limits(&self, q: &[f64]) -> bool {
        q.len() == self.dof()
            && q.iter()
                .zip(self.lower.iter().zip(&self.upper))
                .all(|(&v, (&lo, &hi))| v >= lo && v <= hi)
    }

    /// Checks the length and finiteness of a configuration.
    pub fn check_configuration(&self, q: &[f64]) -> Result<(), RobotError> {
        if q.len() != self.dof() {
            return Err(RobotError::WrongDof {
                chain: self.name(),
                expected: self.dof(),
                got: q.len(),
            });
        }
        if let Some(index) = q.iter().position(|v| !v.is_finite()) {
            return Err(RobotError::NonFiniteJoint { index });
        }
        Ok(())
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

    /// Forward kinematics of many configurations: `q` holds them one after another (`dof`
    /// values each, rad / m). For configuration `k`, `emit(k, pose, jacobian)` receives the tip
    /// pose `base_from_tip` and the geometric Jacobian as a column-major 6 × dof slice (rows
    /// `[v; ω]`, base frame), exactly what [`Chain::pose_and_jacobian_into`] gives for it.
    ///
    /// On processors with AVX2, chains without mimic joints evaluate four configurations at
    /// once, one per vector lane, with the scalar pass's operations (bit-identical results);
    /// faster per configuration than one call each.
    ///
    /// Nothing is emitted when `q` is not a whole number of configurations
    /// ([`RobotError::WrongDof`]) or holds a value that is not finite
    /// ([`RobotError::NonFiniteJoint`], indexed into `q`).
    pub fn for_each_pose_and_jacobian(
        &self,
        q: &[f64],
        mut emit: impl FnMut(usize, &IsometryMatrix3<f64>, &[f64]),
    ) -> Result<(), RobotError> {
        self.check_batch(q)?;
        let dof = self.dof();
        #[cfg(target_arch = "x86_64")]
        if self.drives.is_none() && dof > 0 && avx2::available() {
            let n = self.segments.len();
            let mut values = vec![[0.0; 4]; n];
            let mut lanes = vec![[0.0; 4]; 6 * n];
            let mut column_major = vec![0.0; 6 * n];
            for (group, rows) in q.chunks(4 * dof).enumerate() {
                fill_lanes(&mut values, rows, dof);
                // SAFETY: AVX2 is present (checked above); the buffers have the sizes asked.
                let poses = unsafe {
                    avx2::forward4(&self.segments, &values, Some(&mut lanes), self.tail())
                };
                for (lane, pose) in lane_poses(&poses).iter().take(rows.len() / dof).enumerate() {
                    for (value, lanes) in column_major.iter_mut().zip(&lanes) {
                        *value = lanes[lane];
                    }
                    emit(4 * group + lane, pose, &column_major);
                }
            }
            return Ok(());
        }
        let mut jacobian = vec![0.0; 6 * dof];
        for (k, row) in q.chunks(dof.max(1)).enumerate() {
            let pose = self.pose_and_jacobian_unchecked(row, &mut jacobian);
            emit(k, &pose, &jacobian);
        }
        Ok(())
    }

    /// Like [`Chain::for_each_pose_and_jacobian`], for the tip poses alone.
    pub fn for_each_pose(
        &self,
        q: &[f64],
        mut emit: impl FnMut(usize, &IsometryMatrix3<f64>),
    ) -> Result<(), RobotError> {
        self.check_batch(q)?;
        let dof = self.dof();
        #[cfg(target_arch = "x86_64")]
        if self.drives.is_none() && dof > 0 && avx2::available() {
            let mut values = vec![[0.0; 4]; self.segments.len()];
            for (group, rows) in q.chunks(4 * dof).enumerate() {
                fill_lanes(&mut values, rows, dof);
                // SAFETY: AVX2 is present (checked above); `values` has one entry per segment.
                let poses = unsafe { avx2::forward4(&self.segments, &values, None, self.tail()) };
                for (lane, pose) in lane_poses(&poses).iter().take(rows.len() / dof).enumerate() {
                    emit(4 * group + lane, pose);
                }
            }
            return Ok(());
        }
        for (k, row) in q.chunks(dof.max(1)).enumerate() {
            emit(k, &self.pose_unchecked(row));
        }
        Ok(())
    }

    /// Checks a batch of configurations: whole rows, finite values.
    fn check_batch(&self, q: &[f64]) -> Result<(), RobotError> {
        let dof = self.dof();
        if !q.len().is_multiple_of(dof) {
            return Err(RobotError::WrongDof {
                chain: self.name(),
                expected: dof,
                got: q.len(),
            });
        }
        if let Some(index) = q.iter().position(|v| !v.is_finite()) {
            return Err(RobotError::NonFiniteJoint { index });
        }
        Ok(())
    }

    /// A sphere holding every reachable tip position, `(centre, radius)` in the base frame (m):
    /// the first joint's origin does not move, and every later offset, the tool offset and each
    /// prismatic travel add at most their length. The radius is `+∞` with an unbounded
    /// prismatic joint.
    pub(crate) fn reach_sphere(&self) -> (Vector3<f64>, f64) {
        let Some(first) = self.segments.first() else {
            return (self.tail_translation, 0.0);
        };
        let mut radius = self.tail_translation.norm();
        for (i, segment) in self.segments.iter().enumerate() {
            if i > 0 {
                radius += segment.translation.norm();
            }
            if segment.kind == MotionKind::Prismatic {
                let (source, multiplier, offset) = match &self.drives {
                    None => (i, 1.0, 0.0),
                    Some(drives) => (drives[i].source, drives[i].multiplier, drives[i].offset),
                };
                let travel = self.lower[source].abs().max(self.upper[source].abs());
                radius += multiplier.abs() * travel + offset.abs();
            }
        }
        (first.translation, radius)
    }

    /// The base origin, every moving joint's origin and the tip origin at `q`, in the base
    /// frame (m): the polyline a viewer draws as the arm's links.
    pub fn joint_origins(&self, q: &[f64]) -> Result<Vec<nalgebra::Point3<f64>>, RobotError> {
        self.check_configuration(q)?;
        let value = |i: usize| match &self.drives {
            None => q[i],
            Some(d) => d[i].multiplier * q[d[i].source] + d[i].offset,
        };
        let mut points = vec![nalgebra::Point3::origin()];
        let mut rotation = Matrix3::<f64>::identity();
        let mut position = Vector3::<f64>::zeros();
        for (i, segment) in self.segments.iter().enumerate() {
            position += rotation * segment.translation;
            points.push(nalgebra::Point3::from(position));
            let turned = rotation * segment.rotation;
            match segment.kind {
                MotionKind::Revolute => {
                    let (s, c) = value(i).sin_cos();
                    let (x, y) = (turned.column(0), turned.column(1));
                    rotation = Matrix3::from_columns(&[
                        x * c + y * s,
                        y * c - x * s,
                        turned.column(2).into_owned(),
                    ]);
                }
                MotionKind::Prismatic => {
                    rotation = turned;
                    position += turned.column(2) * value(i);
                }
            }
        }
        points.push(nalgebra::Point3::from(
            position + rotation * self.tail_translation,
        ));
        Ok(points)
    }

    fn tail(&self) -> (&Matrix3<f64>, &Vector3<f64>) {
        (&self.tail_rotation, &self.tail_translation)
    }

    /// A fixed-size copy for chains of exactly `N` joints without mimic joints: its forward
    /// kinematics returns a stack-allocated `6 × N` Jacobian.
    pub fn fixed<const N: usize>(&self) -> Result<FixedChain<N>, RobotError> {
        let refuse = |reason: String| RobotError::NotFixedSize {
            chain: self.name(),
            requested: N,
            reason,
        };
        if self.drives.is_some() {
            return Err(refuse("it has mimic joints".into()));
        }
        if self.segments.len() != N {
            return Err(refuse(format!("it has {} joints", self.segments.len())));
        }
        Ok(FixedChain {
            segments: std::array::from_fn(|i| self.segments[i]),
            tail_rotation: self.tail_rotation,
            tail_translation: self.tail_translation,
        })
    }
}

/// A chain of exactly `N` independent joints with its data in fixed-size arrays.
#[derive(Debug, Clone, PartialEq)]
pub struct FixedChain<const N: usize> {
    segments: [Segment; N],
    tail_rotation: Matrix3<f64>,
    tail_translation: Vector3<f64>,
}

impl<const N: usize> FixedChain<N> {
    /// The tip pose `base_from_tip` at `q`.
    pub fn pose(&self, q: &[f64; N]) -> IsometryMatrix3<f64> {
        forward(
            &self.segments,
            |i| q[i],
            None,
            (&self.tail_rotation, &self.tail_translation),
        )
    }

    /// The tip pose and the geometric Jacobian (rows `[v; ω]`, base frame) at `q`.
    pub fn pose_and_jacobian(&self, q: &[f64; N]) -> (IsometryMatrix3<f64>, SMatrix<f64, 6, N>) {
        let mut jacobian = SMatrix::<f64, 6, N>::zeros();
        let pose = forward(
            &self.segments,
            |i| q[i],
            Some(jacobian.as_mut_slice()),
            (&self.tail_rotation, &self.tail_translation),
        );
        (pose, jacobian)
    }
}

/// Fills `values[j]` with joint `j` of up to four configurations (`rows`, `dof` values each),
/// one per lane; missing lanes repeat the last configuration.
#[cfg(target_arch = "x86_64")]
fn fill_lanes(values: &mut [[f64; 4]], rows: &[f64], dof: usize) {
    let count = rows.len() / dof;
    for (j, lanes) in values.iter_mut().enumerate() {
        *lanes = std::array::from_fn(|lane| rows[lane.min(count - 1) * dof + j]);
    }
}

/// The four poses of a lane group.
#[cfg(target_arch = "x86_64")]
fn lane_poses(poses: &avx2::Poses4) -> [IsometryMatrix3<f64>; 4] {
    // SAFETY: `__m256d` and `[f64; 4]` have the same size and every bit pattern is valid.
    let lanes = |v: &std::arch::x86_64::__m256d| unsafe {
        std::mem::transmute::<std::arch::x86_64::__m256d, [f64; 4]>(*v)
    };
    let rotation = poses.rotation.each_ref().map(|c| c.each_ref().map(lanes));
    let origin = poses.origin.each_ref().map(lanes);
    std::array::from_fn(|lane| {
        pose_from_columns(
            &rotation.map(|c| c.map(|v| v[lane])),
            &origin.map(|v| v[lane]),
        )
    })
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
fn forward(
    segments: &[Segment],
    joint_value: impl Fn(usize) -> f64,
    jacobian: Option<&mut [f64]>,
    tail: (&Matrix3<f64>, &Vector3<f64>),
) -> IsometryMatrix3<f64> {
    if let Some(j) = jacobian.as_deref() {
        assert_eq!(j.len(), 6 * segments.len(), "Jacobian storage size");
    }
    #[cfg(target_arch = "x86_64")]
    if avx2::available() {
        // SAFETY: the processor supports AVX2 (checked just above).
        return unsafe { avx2::forward(segments, joint_value, jacobian, tail) };
    }
    forward_scalar(segments, joint_value, jacobian, tail)
}

/// The scalar forward pass. Writes the Jacobian (column-major, 6 per segment) when asked.
///
/// The rotation is kept as three column arrays so the compiler sees plain scalar arithmetic.
#[inline(always)]
fn forward_scalar(
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
                let (sin, cos) = super::trig::sin_cos(value);
                c = [
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
                ];
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

/// The pose with rotation columns `rotation` and origin `origin` (base frame).
#[inline(always)]
fn pose_from_columns(rotation: &[[f64; 3]; 3], origin: &[f64; 3]) -> IsometryMatrix3<f64> {
    let [x, y, z] = rotation;
    IsometryMatrix3::from_parts(
        Translation3::new(origin[0], origin[1], origin[2]),
        Rotation3::from_matrix_unchecked(Matrix3::new(
            x[0], y[0], z[0], x[1], y[1], z[1], x[2], y[2], z[2],
        )),
    )
}

/// A unit vector from a possibly unnormalised axis, or `None` when it is (nearly) zero or
/// not finite.
pub(crate) fn unit_axis(axis: &Vector3<f64>) -> Option<Vector3<f64>> {
    if axis.iter().any(|c| !c.is_finite()) {
        return None;
    }
    Unit::try_new(*axis, 1e-9).map(Unit::into_inner)
}
