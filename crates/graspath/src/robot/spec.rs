//! A chain described joint by joint, before flattening: what a URDF file or a built-in model
//! provides.

use nalgebra::{Isometry3, Vector3};

/// The motion a joint allows.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum JointKind {
    /// Rotation about the axis within `[lower, upper]` (rad).
    Revolute,
    /// Rotation about the axis without limits.
    Continuous,
    /// Translation along the axis within `[lower, upper]` (m).
    Prismatic,
    /// No motion: folded into a constant transform.
    Fixed,
}

/// A joint whose value follows another joint: `q = multiplier · q_leader + offset`.
#[derive(Debug, Clone, PartialEq)]
pub struct Mimic {
    /// The name of the joint that is followed.
    pub leader: String,
    /// Factor applied to the leader's value.
    pub multiplier: f64,
    /// Offset added (rad or m).
    pub offset: f64,
}

/// One joint of a chain, as in URDF: the child frame is
/// `parent_from_child = parent_from_joint · motion(axis, q)`.
#[derive(Debug, Clone, PartialEq)]
pub struct JointSpec {
    /// Joint name.
    pub name: String,
    /// The link the joint moves (URDF `<child>`): its frame is the joint frame after the
    /// motion. Empty when unknown; [`crate::robot::Chain::link_names`] then names it after the
    /// joint.
    pub child_link: String,
    /// The kind of motion.
    pub kind: JointKind,
    /// The joint frame in the parent link frame (URDF `<origin>`), metres.
    pub parent_from_joint: Isometry3<f64>,
    /// Unit axis in the joint frame (URDF `<axis>`; default `x`).
    pub axis: Vector3<f64>,
    /// Lower limit (rad or m); `-∞` for continuous joints.
    pub lower: f64,
    /// Upper limit (rad or m); `+∞` for continuous joints.
    pub upper: f64,
    /// Set when the joint mimics another joint.
    pub mimic: Option<Mimic>,
}

/// A serial chain from a base link to a tip link, every joint in order from the base.
#[derive(Debug, Clone, PartialEq)]
pub struct ChainSpec {
    /// Where it came from: a file path or `built-in <model>`; used in error messages.
    pub source_name: String,
    /// The base link: poses and Jacobians are expressed in its frame.
    pub base_link: String,
    /// The tip link.
    pub tip_link: String,
    /// The joints from base to tip, fixed ones included.
    pub joints: Vec<JointSpec>,
    /// An extra constant transform after the tip link (a tool centre point), `tip_from_tool`.
    pub tip_from_tool: Option<Isometry3<f64>>,
}
