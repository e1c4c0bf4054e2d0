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
//! **Dynamics**: the link masses, centres of mass and inertias of the `lbr_fri_ros2_stack`
//! description (`lbr_description/urdf/iiwa14/iiwa14_description.xacro`, commit 218d723,
//! from KUKA's CAD data), moved from its link frames into this model's (the two differ by a
//! constant transform per link, checked to 1e-15 over random configurations). Limits from
//! KUKA's LBR iiwa 14 R820 specification: maximum torques 320, 320, 176, 176, 110, 40, 40 N·m
//! and speeds 85, 85, 100, 75, 130, 135, 135 °/s. No acceleration limits are set (unknown).
//!
//! Collision primitives (approximations): a cylinder for link 0 and capsules along the
//! skeleton; radii from KUKA's dimension drawing (housings about 0.16–0.2 m across at the
//! shoulder and elbow, 0.13 m at the wrist).

use super::{
    limits, skeleton_capsules, spec_from_rows, with_dynamics, JointRow, LinkInertia, Motion,
};
use crate::robot::collision::LinkCollisions;
use crate::robot::spec::{ChainSpec, MotionLimits};
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
/// Links 1–7, link frames (see the module documentation).
pub const IIWA14_INERTIA: [LinkInertia; 7] = [
    LinkInertia::new(
        5.289529,
        [0.0, -0.033795, 0.122404],
        [0.042462, 0.042838, 0.01587, 0.0, 0.0, 0.006341],
    ),
    LinkInertia::new(
        5.688888,
        [-0.000136, 0.076322, 0.037548],
        [0.055182, 0.016523, 0.053983, -5.6e-05, 3.3e-05, 0.010034],
    ),
    LinkInertia::new(
        3.461245,
        [0.0, 0.034913, 0.146608],
        [0.02172, 0.02073, 0.007701, 0.0, 0.0, -0.003845],
    ),
    LinkInertia::new(
        4.122995,
        [0.0, 0.086944, 0.029293],
        [0.03241, 0.009883, 0.030758, 0.0, 0.0, 0.006022],
    ),
    LinkInertia::new(
        1.563756,
        [0.0, 0.029824, 0.099267],
        [0.008677, 0.007297, 0.003935, 0.0, 0.0, -0.002869],
    ),
    LinkInertia::new(
        2.457878,
        [0.0, 0.00495, 0.00032],
        [0.007227, 0.004734, 0.006958, 0.0, 0.0, 0.000318],
    ),
    LinkInertia::new(
        0.265331,
        [3e-06, -2e-06, 0.023782],
        [0.000175, 0.000175, 0.000306, 0.0, 0.0, 0.0],
    ),
];

/// Velocity (rad/s) and effort (N·m) limits, joints 1–7.
pub const IIWA14_MOTION_LIMITS: [MotionLimits; 7] = [
    limits(deg(85.0), 320.0, None),
    limits(deg(85.0), 320.0, None),
    limits(deg(100.0), 176.0, None),
    limits(deg(75.0), 176.0, None),
    limits(deg(130.0), 110.0, None),
    limits(deg(135.0), 40.0, None),
    limits(deg(135.0), 40.0, None),
];

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
    with_dynamics(
        spec_from_rows("built-in iiwa14", "iiwa_link_0", &ROWS),
        &IIWA14_INERTIA,
        &IIWA14_MOTION_LIMITS,
    )
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
