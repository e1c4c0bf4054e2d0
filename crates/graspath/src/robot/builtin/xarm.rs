//! **UFACTORY xArm 7**: one 7-DOF arm from `link_base` to the flange `link_eef`.
//!
//! Kinematics: UFACTORY's published parameters as the URDF-style joint origins of its own
//! `xarm_description` (`xarm7.urdf.xacro`), verbatim — including its right angles written
//! as 1.5708 — so the model equals the published one to the last digit. They are UFACTORY's
//! modified DH table (`d1 = 0.267`, `d3 = 0.293`, `a3 = 0.0525`, `a4 = 0.0775`,
//! `d5 = 0.3425`, `a6 = 0.076`, `d7 = 0.097`). Limits as published: joints 1, 3, 5, 7 ±2π;
//! joint 2 −118°…120°, joint 4 −11°…225°, joint 6 −97°…180°.
//!
//! **Tool frame**: `link_eef`, the flange (the frame of link 7, `z` out of the flange). With
//! the xArm Gripper, UFACTORY's TCP offset is 0.172 m along `z`: give it as the tool offset.
//!
//! **Dynamics**: the link masses, centres of mass and inertias of UFACTORY's
//! `xarm_description` as shipped in example-robot-data 6.0.0 (`xarm7.urdf`), link frames;
//! velocity 3.14 rad/s on every joint and effort 50, 50, 30, 30, 30, 20, 20 N·m from the same
//! file. No acceleration limits are set (unknown).
//!
//! Collision primitives (approximations): a cylinder for the base and capsules along the
//! skeleton; radii from UFACTORY's dimension drawing (joint housings about 0.1–0.12 m
//! across).

// UFACTORY writes π/2 as 1.5708; kept verbatim.
#![allow(clippy::approx_constant)]

use super::{
    limits, skeleton_capsules, spec_from_rows, with_dynamics, JointRow, LinkInertia, Motion,
};
use crate::robot::collision::LinkCollisions;
use crate::robot::spec::{ChainSpec, MotionLimits};
use std::f64::consts::{PI, TAU};

/// The parameter table: joint, child link, origin xyz (m), origin roll (rad), limits (rad).
/// Links 1–7, link frames (see the module documentation).
pub const XARM7_INERTIA: [LinkInertia; 7] = [
    LinkInertia::new(
        2.382,
        [-0.0002, 0.02905, -0.01233],
        [
            0.0056905,
            0.0049566,
            0.003316654,
            -1.579e-05,
            5.125e-06,
            -0.000873378,
        ],
    ),
    LinkInertia::new(
        1.869,
        [0.00022, -0.12856, 0.01735],
        [
            0.0095989,
            0.00382472,
            0.007565669,
            1.541e-06,
            5.56e-06,
            -0.00317156,
        ],
    ),
    LinkInertia::new(
        1.6383,
        [0.0466, -0.02463, -0.00768],
        [
            0.00310955,
            0.00264483,
            0.0026624,
            0.00030837,
            -0.00058453,
            0.000338893,
        ],
    ),
    LinkInertia::new(
        1.7269,
        [0.07047, -0.11575, 0.012],
        [
            0.005889,
            0.00359703,
            0.00543244,
            0.00137112,
            0.00088143,
            -0.001762155,
        ],
    ),
    LinkInertia::new(
        1.3203,
        [-0.00032, 0.01604, -0.026],
        [
            0.00534665,
            0.0049779,
            0.0013624,
            1.5117e-05,
            -3.69e-07,
            -0.00022132,
        ],
    ),
    LinkInertia::new(
        1.325,
        [0.06469, 0.03278, 0.02141],
        [
            0.0014745, 0.0019037, 0.0023652, -0.000488, 0.0002953, 0.00014749,
        ],
    ),
    LinkInertia::new(
        0.17,
        [0.0, -0.00677, -0.01098],
        [9.3e-05, 5.87e-05, 0.000132, 0.0, 0.0, -3.6e-06],
    ),
];

/// Velocity (rad/s) and effort (N·m) limits, joints 1–7.
pub const XARM7_MOTION_LIMITS: [MotionLimits; 7] = [
    limits(3.14, 50.0, None),
    limits(3.14, 50.0, None),
    limits(3.14, 30.0, None),
    limits(3.14, 30.0, None),
    limits(3.14, 30.0, None),
    limits(3.14, 20.0, None),
    limits(3.14, 20.0, None),
];

const ROWS: [JointRow; 8] = [
    JointRow::rolled(
        "joint1",
        "link1",
        [0.0, 0.0, 0.267],
        0.0,
        Motion::Revolute(-TAU, TAU),
    ),
    JointRow::rolled(
        "joint2",
        "link2",
        [0.0, 0.0, 0.0],
        -1.5708,
        Motion::Revolute(-2.059, 2.0944),
    ),
    JointRow::rolled(
        "joint3",
        "link3",
        [0.0, -0.293, 0.0],
        1.5708,
        Motion::Revolute(-TAU, TAU),
    ),
    JointRow::rolled(
        "joint4",
        "link4",
        [0.0525, 0.0, 0.0],
        1.5708,
        Motion::Revolute(-0.19198, 3.927),
    ),
    JointRow::rolled(
        "joint5",
        "link5",
        [0.0775, -0.3425, 0.0],
        1.5708,
        Motion::Revolute(-TAU, TAU),
    ),
    JointRow::rolled(
        "joint6",
        "link6",
        [0.0, 0.0, 0.0],
        1.5708,
        Motion::Revolute(-1.69297, PI),
    ),
    JointRow::rolled(
        "joint7",
        "link7",
        [0.076, 0.097, 0.0],
        -1.5708,
        Motion::Revolute(-TAU, TAU),
    ),
    JointRow::rolled("joint_eef", "link_eef", [0.0, 0.0, 0.0], 0.0, Motion::Fixed),
];

/// The arm's chain description, `link_base → link_eef`.
pub fn xarm7_spec() -> ChainSpec {
    with_dynamics(
        spec_from_rows("built-in xarm7", "link_base", &ROWS),
        &XARM7_INERTIA,
        &XARM7_MOTION_LIMITS,
    )
}

/// Collision primitives, link by link (see the module documentation).
pub fn xarm7_collisions() -> Vec<LinkCollisions> {
    skeleton_capsules(
        &xarm7_spec(),
        &[
            ("link_base", 0.063),
            ("link1", 0.06),
            ("link2", 0.055),
            ("link3", 0.055),
            ("link4", 0.05),
            ("link5", 0.05),
            ("link6", 0.045),
            ("link7", 0.04),
        ],
    )
}
