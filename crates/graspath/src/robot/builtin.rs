//! Built-in robot models written from published kinematic parameters.
//!
//! **Baxter** (Rethink Robotics): both 7-DOF arms from the `base` link to the electric
//! gripper's tool frame (`left_gripper` / `right_gripper`), with the joint origins, axes and
//! limits published in Rethink's `baxter_description` (torso mount, shoulder `s0 s1`, elbow
//! `e0 e1`, wrist `w0 w1 w2`, hand, gripper base and the 0.1327 m endpoint of the standard
//! electric gripper fingers).

// The published parameters round π/2 and π/4 to 1.57079632679 and 0.7854; they are kept
// verbatim so the model equals the published one to the last digit.
#![allow(clippy::approx_constant)]

use super::chain::Chain;
use super::error::RobotError;
use super::spec::{ChainSpec, JointKind, JointSpec};
use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use std::fmt;
use std::str::FromStr;

/// One of Baxter's two arms.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Arm {
    /// The left arm (positive y in the base frame).
    Left,
    /// The right arm (negative y in the base frame).
    Right,
}

impl Arm {
    /// `left` or `right`.
    pub fn as_str(self) -> &'static str {
        match self {
            Arm::Left => "left",
            Arm::Right => "right",
        }
    }
}

impl fmt::Display for Arm {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

impl FromStr for Arm {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "left" => Ok(Arm::Left),
            "right" => Ok(Arm::Right),
            other => Err(format!("unknown arm '{other}': expected 'left' or 'right'")),
        }
    }
}

/// The name used in messages for the built-in Baxter model.
pub const BAXTER_SOURCE: &str = "built-in baxter";

/// The right angle used in Baxter's published joint origins (rad).
const PUBLISHED_RIGHT_ANGLE: f64 = 1.57079632679;

/// Shoulder, elbow and wrist limits of a Baxter arm (rad), `s0 s1 e0 e1 w0 w1 w2`.
const BAXTER_LIMITS: [(f64, f64); 7] = [
    (-1.70167993878, 1.70167993878),
    (-2.147, 1.047),
    (-3.05417993878, 3.05417993878),
    (-0.05, 2.618),
    (-3.059, 3.059),
    (-1.57079632679, 2.094),
    (-3.059, 3.059),
];

fn origin(xyz: [f64; 3], rpy: [f64; 3]) -> Isometry3<f64> {
    Isometry3::from_parts(
        Translation3::new(xyz[0], xyz[1], xyz[2]),
        UnitQuaternion::from_euler_angles(rpy[0], rpy[1], rpy[2]),
    )
}

fn fixed(name: &str, child: &str, xyz: [f64; 3], rpy: [f64; 3]) -> JointSpec {
    JointSpec {
        name: name.to_string(),
        child_link: child.to_string(),
        kind: JointKind::Fixed,
        parent_from_joint: origin(xyz, rpy),
        axis: Vector3::x(),
        lower: 0.0,
        upper: 0.0,
        mimic: None,
    }
}

fn revolute(
    name: String,
    child: String,
    xyz: [f64; 3],
    rpy: [f64; 3],
    limits: (f64, f64),
) -> JointSpec {
    JointSpec {
        name,
        child_link: child,
        kind: JointKind::Revolute,
        parent_from_joint: origin(xyz, rpy),
        axis: Vector3::z(),
        lower: limits.0,
        upper: limits.1,
        mimic: None,
    }
}

/// The chain description of one Baxter arm, `base → {arm}_gripper`.
pub fn baxter_spec(arm: Arm) -> ChainSpec {
    let side = arm.as_str();
    // The arms mount mirrored about the base x–z plane.
    let mirror = match arm {
        Arm::Left => 1.0,
        Arm::Right => -1.0,
    };
    let a = PUBLISHED_RIGHT_ANGLE;
    let arm_joints: [(&str, &str, [f64; 3], [f64; 3]); 7] = [
        (
            "s0",
            "upper_shoulder",
            [0.055695, 0.0, 0.011038],
            [0.0, 0.0, 0.0],
        ),
        (
            "s1",
            "lower_shoulder",
            [0.069, 0.0, 0.27035],
            [-a, 0.0, 0.0],
        ),
        ("e0", "upper_elbow", [0.102, 0.0, 0.0], [a, 0.0, a]),
        ("e1", "lower_elbow", [0.069, 0.0, 0.26242], [-a, -a, 0.0]),
        ("w0", "upper_forearm", [0.10359, 0.0, 0.0], [a, 0.0, a]),
        ("w1", "lower_forearm", [0.01, 0.0, 0.2707], [-a, -a, 0.0]),
        ("w2", "wrist", [0.115975, 0.0, 0.0], [a, 0.0, a]),
    ];
    let mut joints = vec![
        fixed("torso_t0", "torso", [0.0; 3], [0.0; 3]),
        fixed(
            &format!("{side}_torso_arm_mount"),
            &format!("{side}_arm_mount"),
            [0.024645, mirror * 0.219645, 0.118588],
            [0.0, 0.0, mirror * 0.7854],
        ),
    ];
    for ((name, child, xyz, rpy), limits) in arm_joints.into_iter().zip(BAXTER_LIMITS) {
        joints.push(revolute(
            format!("{side}_{name}"),
            format!("{side}_{child}"),
            xyz,
            rpy,
            limits,
        ));
    }
    joints.push(fixed(
        &format!("{side}_hand_joint"),
        &format!("{side}_hand_link"),
        [0.0, 0.0, 0.11355],
        [0.0; 3],
    ));
    joints.push(fixed(
        &format!("{side}_gripper_base_joint"),
        &format!("{side}_gripper_base_link"),
        [0.0, 0.0, 0.025],
        [0.0; 3],
    ));
    joints.push(fixed(
        &format!("{side}_endpoint"),
        &format!("{side}_gripper"),
        [0.0, 0.0, 0.1327],
        [0.0; 3],
    ));
    ChainSpec {
        source_name: BAXTER_SOURCE.to_string(),
        base_link: "base".to_string(),
        tip_link: format!("{side}_gripper"),
        joints,
        tip_from_tool: None,
    }
}

/// One Baxter arm as a chain, `base → {arm}_gripper`.
pub fn baxter(arm: Arm) -> Chain {
    Chain::from_spec(&baxter_spec(arm)).expect("the built-in Baxter model is valid")
}

/// One Baxter arm with a tool offset `tip_from_tool` after the gripper frame.
pub fn baxter_with_tool(arm: Arm, tip_from_tool: Isometry3<f64>) -> Result<Chain, RobotError> {
    let mut spec = baxter_spec(arm);
    spec.tip_from_tool = Some(tip_from_tool);
    Chain::from_spec(&spec)
}
