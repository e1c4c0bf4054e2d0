//! A serial chain flattened for speed: the [`Chain`] type, its construction from a
//! [`ChainSpec`] with the checks the kinematics needs, and its accessors.
//!
//! Every joint frame is re-oriented once, at construction, so that its axis is the local `z`
//! axis; the constant re-orientations are folded into the neighbouring fixed transforms. One
//! forward pass then costs, per joint, one 3×3 product, one `sin_cos` and a column rotation,
//! and writes the Jacobian column at the same time. Nothing is allocated per call.
//!
//! The files of this module:
//! * `mod.rs` (this file): the flattened layout (segments, mimic drives, link slots), its
//!   construction and checks, the accessors and the joint-origin polyline.
//! * [`forward`]: the scalar passes (tip pose with the Jacobian, every link frame) and the
//!   single-configuration entry points, which choose the AVX2 kernel at run time.
//! * [`avx2`] (x86-64 only): the same passes on 256-bit vectors, chosen at run time when the
//!   processor has AVX2; they perform the scalar passes' IEEE operations in the same order, so
//!   results do not depend on the processor.
//! * [`batch`]: many configurations per call ([`Chain::for_each_pose_and_jacobian`]), four at
//!   a time on AVX2, one per vector lane.
//! * [`layout`]: the flattened layout as plain data ([`Chain::layout`]) for the dynamics and
//!   the physics writer, and the segment frames the dynamics kernels move.
//! * [`fixed`]: [`FixedChain`], a fixed-size copy with a stack-allocated Jacobian.
//! * [`sweep`]: bounds on how far link points move between two configurations.
//! * [`reach`]: proofs that a tip pose is out of reach, from the chain's geometry alone.
//! * `tests.rs`: the kernels against the scalar passes, bit for bit, on random chains.

use super::error::RobotError;
use super::spec::{ChainSpec, JointKind, MotionLimits, RigidBody};
use nalgebra::{Isometry3, Matrix3, Rotation3, Translation3, Unit, Vector3};

#[cfg(target_arch = "x86_64")]
mod avx2;
mod batch;
mod fixed;
mod forward;
mod layout;
mod reach;
mod sweep;
#[cfg(test)]
mod tests;

pub use fixed::FixedChain;
pub(in crate::robot) use layout::SegmentFrames;
pub use layout::{ChainLayout, LinkPlacement, SegmentLayout};
pub(crate) use reach::OutOfReach;
pub use sweep::{JointAxes, JointAxis, SweepBound};

/// Largest number of moving joints in one chain (mimic followers included).
pub(super) const MAX_JOINTS: usize = 64;

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
pub(super) const MAX_JOINT_OFFSET: f64 = 1000.0;

/// The largest joint limit magnitude (rad or m) of a revolute or prismatic joint. Gazebo's
/// SDF-to-URDF writer gives an unlimited joint ±1e16 (example-robot-data's `iris.urdf`), which
/// is kept; anything beyond is a corrupt file or a unit mistake, and would overflow the span
/// `upper − lower` that IK samples from.
pub(super) const MAX_JOINT_LIMIT: f64 = 1e16;

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
    if bounded && joint.lower.abs().max(joint.upper.abs()) > MAX_JOINT_LIMIT {
        let unit = if joint.kind == JointKind::Prismatic {
            "m (are the units metres?)"
        } else {
            "rad (a joint that turns without limit is `continuous`)"
        };
        return Err(bad(
            "limit",
            format!(
                "lower {} or upper {} is beyond ±{MAX_JOINT_LIMIT} {unit}",
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
    /// Velocity, effort and acceleration limits of the independent joints, in the order of `q`.
    motion_limits: Vec<MotionLimits>,
    /// The mass properties of everything moving segment `i` carries, in its aligned frame
    /// (after the joint motion); `None` when no link of the segment has inertial data.
    segment_bodies: Vec<Option<RigidBody>>,
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
        let mut motion_limits = Vec::new();
        let mut segment_bodies: Vec<Option<RigidBody>> = Vec::new();
        // Folds a link's body (in the link frame, `aligned_from_link = pending`) into the
        // current segment; links before the first moving joint sit on the base and carry
        // nothing the joints feel.
        let fold = |bodies: &mut Vec<Option<RigidBody>>,
                    body: &Option<RigidBody>,
                    pending: &Isometry3<f64>| {
            if let (Some(slot), Some(body)) = (bodies.last_mut(), body) {
                let body = body.transformed(pending);
                *slot = Some(match slot {
                    Some(held) => held.combined(&body),
                    None => body,
                });
            }
        };
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
                    fold(&mut segment_bodies, &joint.child_inertial, &pending);
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
                    motion_limits.push(joint.limits);
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
            segment_bodies.push(None);
            fold(&mut segment_bodies, &joint.child_inertial, &pending);
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
            motion_limits,
            segment_bodies,
        })
    }

    /// Velocity, effort and acceleration limits of the independent joints, in the order of
    /// `q` (rad/s, N·m, rad/s² for revolute joints; m/s, N, m/s² for prismatic ones).
    pub fn motion_limits(&self) -> &[MotionLimits] {
        &self.motion_limits
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

    /// This chain with the independent joint `joint` limited to `[lower, upper]` (rad, or m for
    /// a prismatic joint), inside its own range: a task narrows a joint's range (a cable, a
    /// fixture, a controller's software limits, ROS-Industrial's ±π UR elbow), never widens
    /// it. A continuous joint given a range becomes a revolute one. The error names the joint
    /// and the range it must lie in.
    pub fn with_joint_range(
        &self,
        joint: &str,
        lower: f64,
        upper: f64,
    ) -> Result<Chain, RobotError> {
        let bad = |message: String| RobotError::BadJoint {
            source_name: self.source_name.clone(),
            joint: joint.to_string(),
            field: "range",
            message,
        };
        let i = self
            .joint_names
            .iter()
            .position(|n| n == joint)
            .ok_or_else(|| {
                bad(format!(
                    "not an independent joint of the chain {} (joints: {})",
                    self.name(),
                    self.joint_names.join(", ")
                ))
            })?;
        if !(lower.is_finite() && upper.is_finite() && lower < upper) {
            return Err(bad(format!(
                "[{lower}, {upper}] is not a range: give finite [lower, upper] with lower < upper"
            )));
        }
        let (own_lower, own_upper) = (self.lower[i], self.upper[i]);
        if lower < own_lower || upper > own_upper {
            return Err(bad(format!(
                "[{lower}, {upper}] is not inside the joint's own range [{own_lower}, {own_upper}]: \
                 a task may narrow a joint's range, not widen it"
            )));
        }
        let mut chain = self.clone();
        chain.lower[i] = lower;
        chain.upper[i] = upper;
        if chain.joint_kinds[i] == JointKind::Continuous {
            chain.joint_kinds[i] = JointKind::Revolute;
        }
        Ok(chain)
    }

    /// This chain with every revolute joint's range narrowed by `margin` (rad) at both ends:
    /// `[l + m, u − m]` with `m = min(margin, (u − l) / 4)`, so that at least half of a short
    /// range remains. Continuous and prismatic joints keep their ranges, as does every joint
    /// when `margin` is not positive. A solver that plans in the narrowed ranges keeps each
    /// revolute joint `m` away from its limits (the task setting `ik.limit_margin`). The
    /// middle of every range ([`Chain::mid_configuration`]) is unchanged.
    pub fn with_limit_margin(&self, margin: f64) -> Chain {
        let mut chain = self.clone();
        if margin > 0.0 {
            for (j, kind) in self.joint_kinds.iter().enumerate() {
                let (lower, upper) = (self.lower[j], self.upper[j]);
                if *kind == JointKind::Revolute && lower.is_finite() && upper.is_finite() {
                    let m = margin.min(0.25 * (upper - lower));
                    chain.lower[j] = lower + m;
                    chain.upper[j] = upper - m;
                }
            }
        }
        chain
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

    /// Largest distance (m) segment `i` moves its child along its axis: 0 for a revolute
    /// joint, the larger limit for a prismatic one (through its mimic drive).
    fn travel(&self, i: usize) -> f64 {
        if self.segments[i].kind != MotionKind::Prismatic {
            return 0.0;
        }
        let (source, multiplier, offset) = match &self.drives {
            None => (i, 1.0, 0.0),
            Some(drives) => (drives[i].source, drives[i].multiplier, drives[i].offset),
        };
        let travel = self.lower[source].abs().max(self.upper[source].abs());
        multiplier.abs() * travel + offset.abs()
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
}

/// A unit vector from a possibly unnormalised axis, or `None` when it is (nearly) zero or
/// not finite.
pub(crate) fn unit_axis(axis: &Vector3<f64>) -> Option<Vector3<f64>> {
    if axis.iter().any(|c| !c.is_finite()) {
        return None;
    }
    // Entries so large that the norm overflows keep their direction: scale them down first.
    let axis = if axis.norm_squared().is_finite() {
        *axis
    } else {
        axis / axis.amax()
    };
    Unit::try_new(axis, 1e-9).map(Unit::into_inner)
}

/// The pose with rotation columns `rotation` and origin `origin` (base frame).
#[inline(always)]
pub(crate) fn pose_from_columns(
    rotation: &[[f64; 3]; 3],
    origin: &[f64; 3],
) -> nalgebra::IsometryMatrix3<f64> {
    let [x, y, z] = rotation;
    nalgebra::IsometryMatrix3::from_parts(
        Translation3::new(origin[0], origin[1], origin[2]),
        Rotation3::from_matrix_unchecked(Matrix3::new(
            x[0], y[0], z[0], x[1], y[1], z[1], x[2], y[2], z[2],
        )),
    )
}
