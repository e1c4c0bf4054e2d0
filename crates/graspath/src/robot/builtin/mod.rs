//! Built-in robot models written from their manufacturers' published kinematic parameters and
//! joint limits, each with rough collision primitives. One file per robot:
//!
//! | name | robot | chains | tool frame (chain tip) | parameters |
//! |---|---|---|---|---|
//! | `baxter` | Rethink Baxter | `left`, `right` | `{arm}_gripper` ([`baxter`]) | URDF-style |
//! | `panda` | Franka Emika Panda | `arm` | `panda_hand_tcp` ([`panda`]) | URDF-style (= Craig DH) |
//! | `fr3` | Franka Research 3 | `arm` | `fr3_hand_tcp` ([`panda`]) | as Panda, FR3 limits |
//! | `ur5`, `ur10` | Universal Robots CB3 | `arm` | `tool0` ([`ur`]) | standard DH |
//! | `ur5e`, `ur10e` | Universal Robots e-Series | `arm` | `tool0` ([`ur`]) | standard DH |
//! | `iiwa14` | KUKA LBR iiwa 14 R820 | `arm` | `iiwa_flange` ([`iiwa`]) | URDF-style |
//! | `xarm7` | UFACTORY xArm 7 | `arm` | `link_eef` ([`xarm`]) | URDF-style |
//! | `gen3` | Kinova Gen3 7-DOF | `arm` | `end_effector_link` ([`kinova`]) | URDF-style |
//!
//! "URDF-style" tables give each joint's origin in its parent link frame (`xyz` in metres,
//! `rpy` in radians, URDF's fixed-axis roll–pitch–yaw) and turn about the joint frame's `z`;
//! "standard DH" tables give `d, a, α` per joint (`Rz(θ) · Tz(d) · Tx(a) · Rx(α)`), turned
//! into the same joint form by [`dh_rows`]. Single-arm robots have one chain, named `arm`.
//!
//! Collision primitives are approximations: capsules along the segments that join
//! consecutive joint origins (the kinematic skeleton, [`skeleton_capsules`]) with a radius
//! per link taken from the arm's published outer dimensions, except where a robot's file says
//! otherwise (Baxter's are the published ones; UR's follow the offset tubes).

// Published parameters round π/2 and π/4 (Baxter, xArm); they are kept verbatim so each
// model equals the published one to the last digit.
#![allow(clippy::approx_constant)]

mod baxter;
pub mod iiwa;
pub mod kinova;
pub mod panda;
pub mod ur;
pub mod xarm;

pub use baxter::{baxter, baxter_collisions, baxter_spec, baxter_with_tool, Arm, BAXTER_SOURCE};

use super::collision::{CollisionGeometry, CollisionShape, LinkCollisions};
use super::spec::{ChainSpec, JointKind, JointSpec, MotionLimits, RigidBody};
use crate::geometry::shape::Shape;
use nalgebra::{Isometry3, Matrix3, Translation3, UnitQuaternion, Vector3};
use std::fmt;

/// The name of the one chain of a single-arm built-in robot.
pub const ARM_CHAIN: &str = "arm";

/// A built-in robot model.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum BuiltinRobot {
    /// Rethink Robotics Baxter, two arms ([`baxter`]).
    Baxter,
    /// Franka Emika Panda with the Franka Hand's TCP ([`panda`]).
    Panda,
    /// Franka Research 3: the Panda's kinematics with the FR3 joint limits ([`panda`]).
    Fr3,
    /// Universal Robots UR5 (CB3) ([`ur`]).
    Ur5,
    /// Universal Robots UR10 (CB3) ([`ur`]).
    Ur10,
    /// Universal Robots UR5e ([`ur`]).
    Ur5e,
    /// Universal Robots UR10e ([`ur`]).
    Ur10e,
    /// KUKA LBR iiwa 14 R820 ([`iiwa`]).
    Iiwa14,
    /// UFACTORY xArm 7 ([`xarm`]).
    Xarm7,
    /// Kinova Gen3, 7 degrees of freedom ([`kinova`]).
    Gen3,
}

impl BuiltinRobot {
    /// Every built-in robot, in the order of [`BUILTIN_NAMES`].
    pub const ALL: [BuiltinRobot; 10] = [
        BuiltinRobot::Baxter,
        BuiltinRobot::Panda,
        BuiltinRobot::Fr3,
        BuiltinRobot::Ur5,
        BuiltinRobot::Ur10,
        BuiltinRobot::Ur5e,
        BuiltinRobot::Ur10e,
        BuiltinRobot::Iiwa14,
        BuiltinRobot::Xarm7,
        BuiltinRobot::Gen3,
    ];

    /// The name used in task files, the CLI and Python (`panda`, `ur5e`, …).
    pub fn name(self) -> &'static str {
        match self {
            BuiltinRobot::Baxter => "baxter",
            BuiltinRobot::Panda => "panda",
            BuiltinRobot::Fr3 => "fr3",
            BuiltinRobot::Ur5 => "ur5",
            BuiltinRobot::Ur10 => "ur10",
            BuiltinRobot::Ur5e => "ur5e",
            BuiltinRobot::Ur10e => "ur10e",
            BuiltinRobot::Iiwa14 => "iiwa14",
            BuiltinRobot::Xarm7 => "xarm7",
            BuiltinRobot::Gen3 => "gen3",
        }
    }

    /// The robot of that name, if it is built in.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|r| r.name() == name)
    }

    /// `built-in NAME`, for messages.
    pub fn source_name(self) -> String {
        format!("built-in {}", self.name())
    }

    /// The chains known by name: `left` and `right` for Baxter, [`ARM_CHAIN`] for the others.
    pub fn chain_names(self) -> &'static [&'static str] {
        match self {
            BuiltinRobot::Baxter => &["left", "right"],
            _ => &[ARM_CHAIN],
        }
    }

    /// The description of the chain named `chain` (see [`BuiltinRobot::chain_names`]), from the
    /// base link to the tool frame, without a tool offset; `None` for an unknown name.
    pub fn chain_spec(self, chain: &str) -> Option<ChainSpec> {
        match (self, chain) {
            (BuiltinRobot::Baxter, "left") => Some(baxter_spec(Arm::Left)),
            (BuiltinRobot::Baxter, "right") => Some(baxter_spec(Arm::Right)),
            (BuiltinRobot::Baxter, _) => None,
            (_, ARM_CHAIN) => Some(self.arm_spec()),
            _ => None,
        }
    }

    fn arm_spec(self) -> ChainSpec {
        match self {
            BuiltinRobot::Baxter => baxter_spec(Arm::Left),
            BuiltinRobot::Panda => panda::panda_spec(panda::Variant::Panda),
            BuiltinRobot::Fr3 => panda::panda_spec(panda::Variant::Fr3),
            BuiltinRobot::Ur5 => ur::ur_spec(ur::UrModel::Ur5),
            BuiltinRobot::Ur10 => ur::ur_spec(ur::UrModel::Ur10),
            BuiltinRobot::Ur5e => ur::ur_spec(ur::UrModel::Ur5e),
            BuiltinRobot::Ur10e => ur::ur_spec(ur::UrModel::Ur10e),
            BuiltinRobot::Iiwa14 => iiwa::iiwa14_spec(),
            BuiltinRobot::Xarm7 => xarm::xarm7_spec(),
            BuiltinRobot::Gen3 => kinova::gen3_spec(),
        }
    }

    /// Every chain's description, in the order of [`BuiltinRobot::chain_names`].
    pub fn chain_specs(self) -> Vec<ChainSpec> {
        self.chain_names()
            .iter()
            .filter_map(|name| self.chain_spec(name))
            .collect()
    }

    /// The robot's collision primitives, link by link (see each robot's module for where
    /// they come from).
    pub fn collisions(self) -> Vec<LinkCollisions> {
        match self {
            BuiltinRobot::Baxter => baxter_collisions(),
            BuiltinRobot::Panda => panda::panda_collisions(panda::Variant::Panda),
            BuiltinRobot::Fr3 => panda::panda_collisions(panda::Variant::Fr3),
            BuiltinRobot::Ur5 => ur::ur_collisions(ur::UrModel::Ur5),
            BuiltinRobot::Ur10 => ur::ur_collisions(ur::UrModel::Ur10),
            BuiltinRobot::Ur5e => ur::ur_collisions(ur::UrModel::Ur5e),
            BuiltinRobot::Ur10e => ur::ur_collisions(ur::UrModel::Ur10e),
            BuiltinRobot::Iiwa14 => iiwa::iiwa14_collisions(),
            BuiltinRobot::Xarm7 => xarm::xarm7_collisions(),
            BuiltinRobot::Gen3 => kinova::gen3_collisions(),
        }
    }
}

impl fmt::Display for BuiltinRobot {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// The built-in robots' names, as written in task files (`robot: {builtin: NAME}`).
pub const BUILTIN_NAMES: [&str; 10] = [
    "baxter", "panda", "fr3", "ur5", "ur10", "ur5e", "ur10e", "iiwa14", "xarm7", "gen3",
];

/// How a joint of a parameter table moves.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Motion {
    /// Revolute about the joint frame's `z`, within `[lower, upper]` (rad).
    Revolute(f64, f64),
    /// Revolute about `z` without limits.
    Continuous,
    /// No motion (a fixed frame such as a flange or tool frame).
    Fixed,
}

/// One row of a URDF-style parameter table: the joint frame in the parent link frame
/// (`xyz` in m, `rpy` in rad), then the motion about its `z`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JointRow {
    /// Joint name.
    pub joint: &'static str,
    /// The link the joint moves (its frame is the joint frame after the motion).
    pub child: &'static str,
    /// Origin translation in the parent link frame (m).
    pub xyz: [f64; 3],
    /// Origin rotation, URDF roll–pitch–yaw (rad).
    pub rpy: [f64; 3],
    /// Motion and limits.
    pub motion: Motion,
}

impl JointRow {
    /// A row whose origin rotation is a roll alone (about the parent's `x`, rad): the
    /// modified-DH-like tables of xArm and Kinova.
    pub const fn rolled(
        joint: &'static str,
        child: &'static str,
        xyz: [f64; 3],
        roll: f64,
        motion: Motion,
    ) -> Self {
        Self {
            joint,
            child,
            xyz,
            rpy: [roll, 0.0, 0.0],
            motion,
        }
    }
}

/// One row of a standard (distal) Denavit–Hartenberg table: link `i` is placed by
/// `Rz(θᵢ) · Tz(dᵢ) · Tx(aᵢ) · Rx(αᵢ)` in frame `i − 1`, with `θᵢ = qᵢ`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DhRow {
    /// Joint name.
    pub joint: &'static str,
    /// The link the joint moves.
    pub child: &'static str,
    /// Offset along the previous `z` (m).
    pub d: f64,
    /// Length along the new `x` (m).
    pub a: f64,
    /// Twist about the new `x` (rad).
    pub alpha: f64,
    /// Joint limits (rad).
    pub limits: (f64, f64),
}

/// A standard DH table as URDF-style rows: joint `i` turns about the `z` of DH frame `i − 1`
/// (so its origin is the constant part `Tz(d) · Tx(a) · Rx(α)` of row `i − 1`, the identity
/// for the first joint), and a last fixed joint `tip_joint` carries the constant part of the
/// last row to `tip` (the DH frame `n`). Link `i`'s frame is DH frame `i − 1` turned by `qᵢ`.
pub fn dh_rows(table: &[DhRow], tip_joint: &'static str, tip: &'static str) -> Vec<JointRow> {
    let mut rows = Vec::with_capacity(table.len() + 1);
    let mut previous = ([0.0; 3], [0.0; 3]);
    for row in table {
        rows.push(JointRow {
            joint: row.joint,
            child: row.child,
            xyz: previous.0,
            rpy: previous.1,
            motion: Motion::Revolute(row.limits.0, row.limits.1),
        });
        previous = ([row.a, 0.0, row.d], [row.alpha, 0.0, 0.0]);
    }
    rows.push(JointRow {
        joint: tip_joint,
        child: tip,
        xyz: previous.0,
        rpy: previous.1,
        motion: Motion::Fixed,
    });
    rows
}

/// `parent_from_joint` of an origin given as URDF `xyz` (m) and `rpy` (rad).
pub(crate) fn origin(xyz: [f64; 3], rpy: [f64; 3]) -> Isometry3<f64> {
    Isometry3::from_parts(
        Translation3::new(xyz[0], xyz[1], xyz[2]),
        UnitQuaternion::from_euler_angles(rpy[0], rpy[1], rpy[2]),
    )
}

/// A chain description from a URDF-style table; the tip is the last row's child.
pub fn spec_from_rows(source_name: &str, base_link: &str, rows: &[JointRow]) -> ChainSpec {
    let joints = rows
        .iter()
        .map(|row| {
            let (kind, lower, upper) = match row.motion {
                Motion::Revolute(lower, upper) => (JointKind::Revolute, lower, upper),
                Motion::Continuous => (JointKind::Continuous, f64::NEG_INFINITY, f64::INFINITY),
                Motion::Fixed => (JointKind::Fixed, 0.0, 0.0),
            };
            JointSpec {
                name: row.joint.to_string(),
                child_link: row.child.to_string(),
                kind,
                parent_from_joint: origin(row.xyz, row.rpy),
                axis: if kind == JointKind::Fixed {
                    Vector3::x()
                } else {
                    Vector3::z()
                },
                lower,
                upper,
                mimic: None,
                limits: Default::default(),
                child_inertial: None,
            }
        })
        .collect();
    ChainSpec {
        source_name: source_name.to_string(),
        base_link: base_link.to_string(),
        tip_link: rows.last().map_or(base_link, |r| r.child).to_string(),
        joints,
        tip_from_tool: None,
    }
}

/// The mass properties of one moving link as published, in the link's frame (the frame of the
/// joint that moves it, after the motion), everything rigidly attached to it up to the next
/// moving joint included.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinkInertia {
    /// Mass (kg).
    pub mass: f64,
    /// Centre of mass in the link frame (m).
    pub com: [f64; 3],
    /// Inertia about the centre of mass along the link frame's axes, `[ixx, iyy, izz, ixy,
    /// ixz, iyz]` (kg·m²).
    pub inertia: [f64; 6],
}

impl LinkInertia {
    /// A row of a robot's table: mass (kg), centre of mass (m), `[ixx, iyy, izz, ixy, ixz,
    /// iyz]` (kg·m²).
    pub const fn new(mass: f64, com: [f64; 3], inertia: [f64; 6]) -> Self {
        Self { mass, com, inertia }
    }

    /// The body in the link frame.
    pub fn body(&self) -> RigidBody {
        let [xx, yy, zz, xy, xz, yz] = self.inertia;
        RigidBody::new(
            self.mass,
            Vector3::from(self.com),
            Matrix3::new(xx, xy, xz, xy, yy, yz, xz, yz, zz),
        )
    }
}

/// Velocity (rad/s) and effort (N·m) limits, and the acceleration limit (rad/s²) where the
/// maker publishes one.
pub const fn limits(velocity: f64, effort: f64, acceleration: Option<f64>) -> MotionLimits {
    MotionLimits {
        velocity: Some(velocity),
        effort: Some(effort),
        acceleration,
    }
}

/// Gives the moving joints of `spec`, in order, the bodies of their child links and their
/// limits (one entry each); fixed joints carry nothing (their links are included in the
/// moving link before them).
pub fn with_dynamics(
    mut spec: ChainSpec,
    bodies: &[LinkInertia],
    joint_limits: &[MotionLimits],
) -> ChainSpec {
    let moving = spec
        .joints
        .iter_mut()
        .filter(|j| j.kind != JointKind::Fixed);
    for ((joint, body), limit) in moving.zip(bodies).zip(joint_limits) {
        joint.child_inertial = Some(body.body());
        joint.limits = *limit;
    }
    spec
}

/// A capsule of `radius` (m) about the segment from `a` to `b` (link frame, m).
pub fn capsule_between(name: &str, a: [f64; 3], b: [f64; 3], radius: f64) -> CollisionShape {
    let (link_from_collision, length) = segment_frame(a, b);
    CollisionShape {
        name: Some(name.to_string()),
        link_from_collision,
        geometry: CollisionGeometry::Shape(
            Shape::capsule(radius, length).expect("built-in radii are positive"),
        ),
    }
}

/// A cylinder of `radius` (m) whose axis runs from `a` to `b` (link frame, m, distinct).
pub fn cylinder_between(name: &str, a: [f64; 3], b: [f64; 3], radius: f64) -> CollisionShape {
    let (link_from_collision, length) = segment_frame(a, b);
    CollisionShape {
        name: Some(name.to_string()),
        link_from_collision,
        geometry: CollisionGeometry::Shape(
            Shape::cylinder(radius, length).expect("built-in sizes are positive"),
        ),
    }
}

/// The frame centred on the segment `a → b` with `z` along it, and the segment's length.
fn segment_frame(a: [f64; 3], b: [f64; 3]) -> (Isometry3<f64>, f64) {
    let a = Vector3::from(a);
    let b = Vector3::from(b);
    let axis = b - a;
    let length = axis.norm();
    let rotation = if length < 1e-12 {
        UnitQuaternion::identity()
    } else {
        UnitQuaternion::rotation_between(&Vector3::z(), &axis).unwrap_or_else(|| {
            // Antiparallel to z: half a turn about x.
            UnitQuaternion::from_axis_angle(&Vector3::x_axis(), std::f64::consts::PI)
        })
    };
    let centre = (a + b) / 2.0;
    (Isometry3::from_parts(centre.into(), rotation), length)
}

/// Capsules along the kinematic skeleton of `spec`: the link named in each `(link, radius)`
/// pair gets a capsule of that radius from its own origin to the origin of the next joint
/// of the chain (a sphere when they coincide). The base link gets a cylinder instead, from
/// its origin to the first joint's origin, so that nothing reaches below the mounting plane.
/// The last pair's capsule stops one radius short, so that its cap ends at the end point (a
/// flange), not beyond it.
pub fn skeleton_capsules(spec: &ChainSpec, radii: &[(&str, f64)]) -> Vec<LinkCollisions> {
    let mut out = Vec::new();
    for (k, (link, radius)) in radii.iter().enumerate() {
        let position = if *link == spec.base_link {
            Some(0)
        } else {
            spec.joints
                .iter()
                .position(|j| j.child_link == *link)
                .map(|k| k + 1)
        };
        let Some(next) = position else { continue };
        let end = spec
            .joints
            .get(next)
            .map_or(Vector3::zeros(), |j| j.parent_from_joint.translation.vector);
        let shape = if next == 0 {
            cylinder_between(link, [0.0; 3], end.into(), *radius)
        } else if k + 1 == radii.len() {
            let shortened = end * (1.0 - radius / end.norm().max(*radius));
            capsule_between(link, [0.0; 3], shortened.into(), *radius)
        } else {
            capsule_between(link, [0.0; 3], end.into(), *radius)
        };
        out.push(LinkCollisions {
            link: link.to_string(),
            shapes: vec![shape],
        });
    }
    out
}
