//! **KUKA LBR iiwa 14 R820**: one 7-DOF arm from `iiwa_link_0` to the media flange
//! `iiwa_flange`.
//!
//! Kinematics: KUKA's published dimensions (base to shoulder 0.36 m = 0.1575 + 0.2025,
//! shoulder to elbow 0.42 m = 0.2045 + 0.2155, elbow to wrist 0.4 m = 0.1845 + 0.2155, wrist
//! to flange 0.126 m = 0.081 + 0.045), placed as URDF-style joint origins with the joint
//! frames and rotation senses of the widely used `iiwa_description` (IFL-CAMP `iiwa_stack`,
//! `robot_name = iiwa`), every joint turning about its frame's `z`. Limits: KUKA's ±170°,
//! ±120°, ±170°, ±120°, ±170°, ±120°, ±175°.
//!
//! **Tool frame**: `iiwa_flange`, the centre of the media flange, 0.045 m beyond link 7's
//! frame along joint 7's axis, with link 7's orientation (`iiwa_link_ee_kuka` in
//! `iiwa_description`, KUKA's flange coordinate system). A tool offset follows it.
//!
//! Collision primitives (approximations): a cylinder for link 0 and capsules along the
//! skeleton; radii from KUKA's dimension drawing (housings about 0.16–0.2 m across at the
//! shoulder and elbow, 0.13 m at the wrist).

use super::{skeleton_capsules, spec_from_rows, JointRow, Motion};
use crate::robot::collision::LinkCollisions;
use crate::robot::spec::ChainSpec;
use std::f64::consts::{FRAC_PI_2, PI};

const fn deg(d: f64) -> f64 {
    d * PI / 180.0
}

const fn rev(
    joint: &'static str,
    child: &'static str,
    xyz: [f64; 3],
    rpy: [f64; 3],
    limit_deg: f64,
) -> JointRow {
    JointRow {
        joint,
        child,
        xyz,
        rpy,
        motion: Motion::Revolute(-deg(limit_deg), deg(limit_deg)),
    }
}

/// The parameter table: joint, child link, origin xyz (m), origin rpy (rad), limit (±°).
const ROWS: [JointRow; 8] = [
    rev(
        "iiwa_joint_1",
        "iiwa_link_1",
        [0.0, 0.0, 0.1575],
        [0.0, 0.0, 0.0],
        170.0,
    ),
    rev(
        "iiwa_joint_2",
        "iiwa_link_2",
        [0.0, 0.0, 0.2025],
        [FRAC_PI_2, 0.0, PI],
        120.0,
    ),
    rev(
        "iiwa_joint_3",
        "iiwa_link_3",
        [0.0, 0.2045, 0.0],
        [FRAC_PI_2, 0.0, PI],
        170.0,
    ),
    rev(
        "iiwa_joint_4",
        "iiwa_link_4",
        [0.0, 0.0, 0.2155],
        [FRAC_PI_2, 0.0, 0.0],
        120.0,
    ),
    rev(
        "iiwa_joint_5",
        "iiwa_link_5",
        [0.0, 0.1845, 0.0],
        [-FRAC_PI_2, PI, 0.0],
        170.0,
    ),
    rev(
        "iiwa_joint_6",
        "iiwa_link_6",
        [0.0, 0.0, 0.2155],
        [FRAC_PI_2, 0.0, 0.0],
        120.0,
    ),
    rev(
        "iiwa_joint_7",
        "iiwa_link_7",
        [0.0, 0.081, 0.0],
        [-FRAC_PI_2, PI, 0.0],
        175.0,
    ),
    JointRow {
        joint: "iiwa_flange_joint",
        child: "iiwa_flange",
        xyz: [0.0, 0.0, 0.045],
        rpy: [0.0, 0.0, 0.0],
        motion: Motion::Fixed,
    },
];

/// The arm's chain description, `iiwa_link_0 → iiwa_flange`.
pub fn iiwa14_spec() -> ChainSpec {
    spec_from_rows("built-in iiwa14", "iiwa_link_0", &ROWS)
}

/// Collision primitives, link by link (see the module documentation).
pub fn iiwa14_collisions() -> Vec<LinkCollisions> {
    skeleton_capsules(
        &iiwa14_spec(),
        &[
            ("iiwa_link_0", 0.1),
            ("iiwa_link_1", 0.09),
            ("iiwa_link_2", 0.09),
            ("iiwa_link_3", 0.08),
            ("iiwa_link_4", 0.08),
            ("iiwa_link_5", 0.07),
            ("iiwa_link_6", 0.07),
            ("iiwa_link_7", 0.045),
        ],
    )
}
