//! **Kinova Gen3** (7 degrees of freedom): one arm from `base_link` to `end_effector_link`.
//!
//! Kinematics: the URDF-style joint origins Kinova publishes in `ros_kortex`
//! (`kortex_description/arms/gen3/7dof`), lengths verbatim; its angles, written there to
//! four digits (3.1416, 1.5708) with round-off residues of 1e−16, are taken as π and π/2.
//! They match the classical DH table of Kinova's Gen3 user guide (`d₁ = −(0.1564 +
//! 0.1284)`, `d₃ = −(0.2104 + 0.2104)`, `d₅ = −(0.2084 + 0.1059)`, `d₇ = −(0.1059 + 0.0615)`
//! m, rounded there to 0.1 mm). Joints 1, 3, 5, 7 turn without limits; joints 2, 4, 6 are
//! limited to ±2.41, ±2.66 and ±2.23 rad as published (the controller's software limits
//! can be set tighter).
//!
//! **Tool frame**: `end_effector_link`, the centre of the tool interface on the bracelet
//! (0.061525 m beyond the bracelet frame, turned by π about `x` so that `z` points out of the
//! interface), as in `ros_kortex`. A tool offset (for example a Robotiq 2F-85's TCP) follows
//! it.
//!
//! Collision primitives (approximations): a cylinder for the base and capsules along the
//! skeleton; radii from Kinova's dimension drawing (actuators about 0.1 m across, the wrist
//! 0.08 m).

use super::{skeleton_capsules, spec_from_rows, JointRow, Motion};
use crate::robot::collision::LinkCollisions;
use crate::robot::spec::ChainSpec;
use std::f64::consts::{FRAC_PI_2, PI};

/// The parameter table: joint, child link, origin xyz (m), origin roll (rad), limits (rad).
const ROWS: [JointRow; 8] = [
    JointRow::rolled(
        "joint_1",
        "shoulder_link",
        [0.0, 0.0, 0.15643],
        PI,
        Motion::Continuous,
    ),
    JointRow::rolled(
        "joint_2",
        "half_arm_1_link",
        [0.0, 0.005375, -0.12838],
        FRAC_PI_2,
        Motion::Revolute(-2.41, 2.41),
    ),
    JointRow::rolled(
        "joint_3",
        "half_arm_2_link",
        [0.0, -0.21038, -0.006375],
        -FRAC_PI_2,
        Motion::Continuous,
    ),
    JointRow::rolled(
        "joint_4",
        "forearm_link",
        [0.0, 0.006375, -0.21038],
        FRAC_PI_2,
        Motion::Revolute(-2.66, 2.66),
    ),
    JointRow::rolled(
        "joint_5",
        "spherical_wrist_1_link",
        [0.0, -0.20843, -0.006375],
        -FRAC_PI_2,
        Motion::Continuous,
    ),
    JointRow::rolled(
        "joint_6",
        "spherical_wrist_2_link",
        [0.0, 0.00017505, -0.10593],
        FRAC_PI_2,
        Motion::Revolute(-2.23, 2.23),
    ),
    JointRow::rolled(
        "joint_7",
        "bracelet_link",
        [0.0, -0.10593, -0.00017505],
        -FRAC_PI_2,
        Motion::Continuous,
    ),
    JointRow::rolled(
        "end_effector",
        "end_effector_link",
        [0.0, 0.0, -0.061525],
        PI,
        Motion::Fixed,
    ),
];

/// The arm's chain description, `base_link → end_effector_link`.
pub fn gen3_spec() -> ChainSpec {
    spec_from_rows("built-in gen3", "base_link", &ROWS)
}

/// Collision primitives, link by link (see the module documentation).
pub fn gen3_collisions() -> Vec<LinkCollisions> {
    skeleton_capsules(
        &gen3_spec(),
        &[
            ("base_link", 0.06),
            ("shoulder_link", 0.055),
            ("half_arm_1_link", 0.055),
            ("half_arm_2_link", 0.055),
            ("forearm_link", 0.05),
            ("spherical_wrist_1_link", 0.045),
            ("spherical_wrist_2_link", 0.045),
            ("bracelet_link", 0.045),
        ],
    )
}
