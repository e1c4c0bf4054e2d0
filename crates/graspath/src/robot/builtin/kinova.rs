//! **Kinova Gen3** (7 degrees of freedom): one arm from `base_link` to `end_effector_link`.
//!
//! Kinematics: the URDF-style joint origins Kinova publishes in `ros_kortex`
//! (`kortex_description/arms/gen3/7dof`), lengths verbatim; its angles, written there to
//! four digits (3.1416, 1.5708) with round-off residues of 1e−16, are taken as π and π/2.
//! They match the classical DH table of Kinova's Gen3 user guide (`d₁ = −(0.1564 +
//! 0.1284)`, `d₃ = −(0.2104 + 0.2104)`, `d₅ = −(0.2084 + 0.1059)`, `d₇ = −(0.1059 + 0.0615)`
//! m, rounded there to 0.1 mm). Joints 1, 3, 5, 7 turn without limits; joints 2, 4, 6 are
//! limited to ±2.24, ±2.57 and ±2.09 rad: Kinova's Gen3 user guide gives ±128.9°, ±147.8° and
//! ±120.3°, and `ros2_kortex` (commit 7e0ac34, October 2024, "as per the values in the User
//! Guides"; `ros_kortex` and MuJoCo Menagerie's `kinova_gen3` agree) writes them rounded
//! down to two decimals, which is kept here. Before that commit the descriptions gave ±2.41,
//! ±2.66 and ±2.23 rad. A task narrows them further with `robot.joint_limits`.
//!
//! **Tool frame**: `end_effector_link`, the centre of the tool interface on the bracelet
//! (0.061525 m beyond the bracelet frame, turned by π about `x` so that `z` points out of the
//! interface), as in `ros_kortex`. A tool offset (for example a Robotiq 2F-85's TCP) follows
//! it.
//!
//! **Dynamics**: the link masses, centres of mass and inertias of Kinova's `ros_kortex`
//! (`kortex_description/arms/gen3/7dof/urdf/GEN3-7DOF-NOVISION_FOR_URDF_ARM_V12.urdf`,
//! commit 6cd75d4: the arm without the vision module), link frames; the same file's
//! velocity limits, 1.3963 rad/s (joints 1–4) and 1.2218 rad/s (5–7), and efforts, 39 N·m
//! (1–4) and 9 N·m (5–7). No acceleration limits are set (unknown).
//!
//! Collision primitives (approximations): a cylinder for the base and capsules along the
//! skeleton; radii from Kinova's dimension drawing (actuators about 0.1 m across, the wrist
//! 0.08 m).

use super::{
    limits, skeleton_capsules, spec_from_rows, with_dynamics, JointRow, LinkInertia, Motion,
};
use crate::robot::collision::LinkCollisions;
use crate::robot::spec::{ChainSpec, MotionLimits};
use std::f64::consts::{FRAC_PI_2, PI};

/// The parameter table: joint, child link, origin xyz (m), origin roll (rad), limits (rad).
/// Links 1–7 (shoulder to bracelet), link frames (see the module documentation).
pub const GEN3_INERTIA: [LinkInertia; 7] = [
    LinkInertia::new(
        1.377,
        [-2.3e-05, -0.010364, -0.07336],
        [0.00457, 0.004831, 0.001409, 1e-06, 2e-06, 0.000448],
    ),
    LinkInertia::new(
        1.163,
        [-4.4e-05, -0.09958, -0.013278],
        [0.011088, 0.001072, 0.011255, 5e-06, 0.0, -0.000691],
    ),
    LinkInertia::new(
        1.163,
        [-4.4e-05, -0.006641, -0.117892],
        [0.010932, 0.011127, 0.001043, 0.0, -7e-06, 0.000606],
    ),
    LinkInertia::new(
        0.93,
        [-1.8e-05, -0.075478, -0.015006],
        [0.008147, 0.000631, 0.008316, -1e-06, 0.0, -0.0005],
    ),
    LinkInertia::new(
        0.678,
        [1e-06, -0.009432, -0.063883],
        [0.001596, 0.001607, 0.000399, 0.0, 0.0, 0.000256],
    ),
    LinkInertia::new(
        0.678,
        [1e-06, -0.045483, -0.00965],
        [0.001641, 0.00041, 0.001641, 0.0, 0.0, -0.000278],
    ),
    LinkInertia::new(
        0.364,
        [-9.3e-05, 0.000132, -0.022905],
        [0.000214, 0.000223, 0.00024, 0.0, 1e-06, -2e-06],
    ),
];

/// Velocity (rad/s) and effort (N·m) limits, joints 1–7.
pub const GEN3_MOTION_LIMITS: [MotionLimits; 7] = [
    limits(1.3963, 39.0, None),
    limits(1.3963, 39.0, None),
    limits(1.3963, 39.0, None),
    limits(1.3963, 39.0, None),
    limits(1.2218, 9.0, None),
    limits(1.2218, 9.0, None),
    limits(1.2218, 9.0, None),
];

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
        Motion::Revolute(-2.24, 2.24),
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
        Motion::Revolute(-2.57, 2.57),
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
        Motion::Revolute(-2.09, 2.09),
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
    with_dynamics(
        spec_from_rows("built-in gen3", "base_link", &ROWS),
        &GEN3_INERTIA,
        &GEN3_MOTION_LIMITS,
    )
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
