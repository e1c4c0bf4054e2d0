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
//! Collision primitives (approximations): a cylinder for the base and capsules along the
//! skeleton; radii from UFACTORY's dimension drawing (joint housings about 0.1–0.12 m
//! across).

// UFACTORY writes π/2 as 1.5708; kept verbatim.
#![allow(clippy::approx_constant)]

use super::{skeleton_capsules, spec_from_rows, JointRow, Motion};
use crate::robot::collision::LinkCollisions;
use crate::robot::spec::ChainSpec;
use std::f64::consts::{PI, TAU};

/// The parameter table: joint, child link, origin xyz (m), origin roll (rad), limits (rad).
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
    spec_from_rows("built-in xarm7", "link_base", &ROWS)
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
