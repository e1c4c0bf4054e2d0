//! **Franka Emika Panda** and **Franka Research 3** (FR3): one 7-DOF arm from `panda_link0`
//! (`fr3_link0`) to the Franka Hand's tool centre point `panda_hand_tcp` (`fr3_hand_tcp`).
//!
//! Kinematics: Franka's published modified (Craig) DH parameters, written as the URDF-style
//! joint origins of `franka_description` — joint `i`'s origin is `Rx(αᵢ₋₁) · Tx(aᵢ₋₁) ·
//! Tz(dᵢ)`, which is exactly the table below (`d1 = 0.333`, `d3 = 0.316`, `a3 = 0.0825`,
//! `a4 = −0.0825`, `d5 = 0.384`, `a6 = 0.088`, flange `d = 0.107`). The FR3 has the same
//! kinematics and differs in its joint limits (Franka's FR3 datasheet).
//!
//! **Tool frame**: the flange (`panda_link8`, 0.107 m beyond joint 7 along its axis) is turned
//! by −π/4 about `z` to the hand frame `panda_hand` (fingers opening along its `y`), and the
//! tool centre point `panda_hand_tcp` lies 0.1034 m further along `z`, between the fingertips
//! — as in `franka_description`. A tool offset given by the user follows `panda_hand_tcp`;
//! the flange is reached with the sub-chain `panda_link0 → panda_link8`.
//!
//! Collision primitives (approximations): capsules along the skeleton with the radii below
//! (the arm's housings are about 0.12–0.15 m across in Franka's dimension drawing), and one
//! capsule across the hand's body (about 0.2 m wide, 0.08 m deep); the fingers belong to the
//! hand model.

use super::{capsule_between, skeleton_capsules, spec_from_rows, JointRow, Motion};
use crate::robot::collision::LinkCollisions;
use crate::robot::spec::ChainSpec;
use std::f64::consts::{FRAC_PI_2, FRAC_PI_4};

/// Which Franka arm.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Variant {
    /// Franka Emika Panda (link names `panda_*`).
    Panda,
    /// Franka Research 3 (link names `fr3_*`).
    Fr3,
}

/// Panda joint limits (rad), joints 1–7, from Franka's datasheet.
pub const PANDA_LIMITS: [(f64, f64); 7] = [
    (-2.8973, 2.8973),
    (-1.7628, 1.7628),
    (-2.8973, 2.8973),
    (-3.0718, -0.0698),
    (-2.8973, 2.8973),
    (-0.0175, 3.7525),
    (-2.8973, 2.8973),
];

/// FR3 joint limits (rad), joints 1–7, from Franka's FR3 datasheet.
pub const FR3_LIMITS: [(f64, f64); 7] = [
    (-2.7437, 2.7437),
    (-1.7837, 1.7837),
    (-2.9007, 2.9007),
    (-3.0421, -0.1518),
    (-2.8065, 2.8065),
    (0.5445, 4.5169),
    (-3.0159, 3.0159),
];

/// Joint origins in the parent link (xyz m, rpy rad), joints 1–7, flange, hand, TCP.
const ORIGINS: [([f64; 3], [f64; 3]); 10] = [
    ([0.0, 0.0, 0.333], [0.0, 0.0, 0.0]),
    ([0.0, 0.0, 0.0], [-FRAC_PI_2, 0.0, 0.0]),
    ([0.0, -0.316, 0.0], [FRAC_PI_2, 0.0, 0.0]),
    ([0.0825, 0.0, 0.0], [FRAC_PI_2, 0.0, 0.0]),
    ([-0.0825, 0.384, 0.0], [-FRAC_PI_2, 0.0, 0.0]),
    ([0.0, 0.0, 0.0], [FRAC_PI_2, 0.0, 0.0]),
    ([0.088, 0.0, 0.0], [FRAC_PI_2, 0.0, 0.0]),
    ([0.0, 0.0, 0.107], [0.0, 0.0, 0.0]),
    ([0.0, 0.0, 0.0], [0.0, 0.0, -FRAC_PI_4]),
    ([0.0, 0.0, 0.1034], [0.0, 0.0, 0.0]),
];

const PANDA_NAMES: [(&str, &str); 10] = [
    ("panda_joint1", "panda_link1"),
    ("panda_joint2", "panda_link2"),
    ("panda_joint3", "panda_link3"),
    ("panda_joint4", "panda_link4"),
    ("panda_joint5", "panda_link5"),
    ("panda_joint6", "panda_link6"),
    ("panda_joint7", "panda_link7"),
    ("panda_joint8", "panda_link8"),
    ("panda_hand_joint", "panda_hand"),
    ("panda_hand_tcp_joint", "panda_hand_tcp"),
];

const FR3_NAMES: [(&str, &str); 10] = [
    ("fr3_joint1", "fr3_link1"),
    ("fr3_joint2", "fr3_link2"),
    ("fr3_joint3", "fr3_link3"),
    ("fr3_joint4", "fr3_link4"),
    ("fr3_joint5", "fr3_link5"),
    ("fr3_joint6", "fr3_link6"),
    ("fr3_joint7", "fr3_link7"),
    ("fr3_joint8", "fr3_link8"),
    ("fr3_hand_joint", "fr3_hand"),
    ("fr3_hand_tcp_joint", "fr3_hand_tcp"),
];

fn names(variant: Variant) -> (&'static str, &'static [(&'static str, &'static str); 10]) {
    match variant {
        Variant::Panda => ("panda_link0", &PANDA_NAMES),
        Variant::Fr3 => ("fr3_link0", &FR3_NAMES),
    }
}

/// The arm's chain description, `*_link0 → *_hand_tcp`.
pub fn panda_spec(variant: Variant) -> ChainSpec {
    let (base, names) = names(variant);
    let limits = match variant {
        Variant::Panda => PANDA_LIMITS,
        Variant::Fr3 => FR3_LIMITS,
    };
    let rows: Vec<JointRow> = ORIGINS
        .iter()
        .zip(names)
        .enumerate()
        .map(|(k, ((xyz, rpy), (joint, child)))| JointRow {
            joint,
            child,
            xyz: *xyz,
            rpy: *rpy,
            motion: limits
                .get(k)
                .map_or(Motion::Fixed, |(lo, hi)| Motion::Revolute(*lo, *hi)),
        })
        .collect();
    let source = match variant {
        Variant::Panda => "built-in panda",
        Variant::Fr3 => "built-in fr3",
    };
    spec_from_rows(source, base, &rows)
}

/// Collision capsules, link by link (see the module documentation).
pub fn panda_collisions(variant: Variant) -> Vec<LinkCollisions> {
    let spec = panda_spec(variant);
    let (base, names) = names(variant);
    // Base, then links 1–7 (link 7 reaches the flange).
    let radii = [0.075, 0.075, 0.07, 0.07, 0.065, 0.06, 0.05];
    let mut links: Vec<(&str, f64)> = vec![(base, 0.09)];
    links.extend(names.iter().map(|(_, link)| *link).zip(radii));
    let mut out = skeleton_capsules(&spec, &links);
    let hand = names[8].1;
    out.push(LinkCollisions {
        link: hand.to_string(),
        shapes: vec![capsule_between(
            hand,
            [0.0, -0.07, 0.03],
            [0.0, 0.07, 0.03],
            0.04,
        )],
    });
    out
}
