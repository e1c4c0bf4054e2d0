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
//! **Dynamics.** Panda: the link masses, centres of mass and inertias of example-robot-data's
//! `panda_description/urdf/panda.urdf` (6.0.0; `franka_ros`'s description, whose arm links
//! carry the parameters identified by Gaz, Cognetti, Oliva, Robuffo Giordano and De Luca,
//! RA-L 2019), the Franka Hand (0.73 kg) and its two fingers (0.015 kg each, closed) folded
//! into link 7. FR3: Franka's `franka_description` (`robots/fr3/inertials.yaml` and
//! `end_effectors/franka_hand/inertials.yaml`, commit b299b39), the hand (0.6544 kg) and
//! fingers (0.0291 kg each) folded into link 7 the same way. Limits, from Franka's datasheets
//! (as in the two descriptions): effort 87 N·m (joints 1–4) and 12 N·m (5–7); velocity
//! Panda 2.175 / 2.61 rad/s, FR3 2.62 (1–4), 5.26, 4.18, 5.26 rad/s (`fr3/joint_limits.yaml`);
//! acceleration Panda 15, 7.5, 10, 12.5, 15, 20, 20 rad/s² (Franka's "robot and interface
//! specifications"); FR3 accelerations are not set (unknown). Inertias of the hands are
//! Franka's estimates, not identified values.
//!
//! Collision primitives (approximations): capsules along the skeleton with the radii below
//! (the arm's housings are about 0.12–0.15 m across in Franka's dimension drawing), and one
//! capsule across the hand's body (about 0.2 m wide, 0.08 m deep); the fingers belong to the
//! hand model.

use super::{
    capsule_between, limits, skeleton_capsules, spec_from_rows, with_dynamics, JointRow,
    LinkInertia, Motion,
};
use crate::robot::collision::LinkCollisions;
use crate::robot::spec::{ChainSpec, MotionLimits};
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

/// Panda links 1–7 (link 7 with the flange, hand and fingers), link frames; see the module
/// documentation for the source.
pub const PANDA_INERTIA: [LinkInertia; 7] = [
    LinkInertia::new(
        4.970684,
        [0.003875, 0.002081, -0.04762],
        [0.70337, 0.70661, 0.009117, -0.000139, 0.006772, 0.019169],
    ),
    LinkInertia::new(
        0.646926,
        [-0.003141, -0.02872, 0.003495],
        [0.007962, 0.02811, 0.025995, -0.003925, 0.010254, 0.000704],
    ),
    LinkInertia::new(
        3.228604,
        [0.027518, 0.039252, -0.066502],
        [0.037242, 0.036155, 0.01083, -0.004761, -0.011396, -0.012805],
    ),
    LinkInertia::new(
        3.587895,
        [-0.05317, 0.104419, 0.027454],
        [0.025853, 0.019552, 0.028323, 0.007796, -0.001332, 0.008641],
    ),
    LinkInertia::new(
        1.225946,
        [-0.011953, 0.041065, -0.038437],
        [0.035549, 0.029474, 0.008627, -0.002117, -0.004037, 0.000229],
    ),
    LinkInertia::new(
        1.666555,
        [0.060149, -0.014117, -0.010517],
        [0.001964, 0.004354, 0.005433, 0.000109, -0.001158, 0.000341],
    ),
    LinkInertia::new(
        1.495522,
        [0.001720874298, 0.001360354417, 0.1004852811],
        [
            0.01652985371,
            0.01410724864,
            0.006676955557,
            0.0003948922971,
            -0.0007066957106,
            -0.001051105327,
        ],
    ),
];

/// FR3 links 1–7 (link 7 with the flange, hand and fingers), link frames.
pub const FR3_INERTIA: [LinkInertia; 7] = [
    LinkInertia::new(
        2.927465345,
        [4.128e-07, -0.0181251324, -0.038603597],
        [
            0.02392731649,
            0.02248216133,
            0.006350098259,
            1.331790346e-05,
            -0.0001140477492,
            -0.001995032063,
        ],
    ),
    LinkInertia::new(
        2.935537034,
        [0.0031828864, -0.0743221644, 0.0088146084],
        [
            0.04193894626,
            0.02514514885,
            0.06170214473,
            0.0002025733152,
            0.004077784227,
            -0.004225215801,
        ],
    ),
    LinkInertia::new(
        2.24490137,
        [0.0407015686, -0.0048200565, -0.0289730823],
        [
            0.02410142547,
            0.01974053267,
            0.01904449448,
            0.002404694559,
            -0.00285626927,
            -0.002104212684,
        ],
    ),
    LinkInertia::new(
        2.615595579,
        [-0.0459100965, 0.063049296, -0.0085187868],
        [
            0.03452998322,
            0.02888162193,
            0.04125471171,
            0.01322552266,
            0.01015142998,
            -0.0009762833871,
        ],
    ),
    LinkInertia::new(
        2.327120759,
        [-0.0016039605, 0.0292536262, -0.097296599],
        [
            0.05161027846,
            0.04787729713,
            0.01642362558,
            -0.005715173388,
            -0.003567316763,
            0.01067398511,
        ],
    ),
    LinkInertia::new(
        1.817037652,
        [0.0597131221, -0.0410294666, -0.0101692726],
        [
            0.005412333594,
            0.01405832955,
            0.01608081792,
            0.00619345636,
            0.001421928931,
            -0.001314075374,
        ],
    ),
    LinkInertia::new(
        1.339743286,
        [0.006688116436, 0.008635018567, 0.0629612874],
        [
            0.008880215577,
            0.008852020162,
            0.001809609189,
            -0.0008046193808,
            -0.0001797136872,
            6.345985282e-05,
        ],
    ),
];

/// Panda velocity (rad/s), effort (N·m) and acceleration (rad/s²) limits, joints 1–7.
pub const PANDA_MOTION_LIMITS: [MotionLimits; 7] = [
    limits(2.175, 87.0, Some(15.0)),
    limits(2.175, 87.0, Some(7.5)),
    limits(2.175, 87.0, Some(10.0)),
    limits(2.175, 87.0, Some(12.5)),
    limits(2.61, 12.0, Some(15.0)),
    limits(2.61, 12.0, Some(20.0)),
    limits(2.61, 12.0, Some(20.0)),
];

/// FR3 velocity (rad/s) and effort (N·m) limits, joints 1–7.
pub const FR3_MOTION_LIMITS: [MotionLimits; 7] = [
    limits(2.62, 87.0, None),
    limits(2.62, 87.0, None),
    limits(2.62, 87.0, None),
    limits(2.62, 87.0, None),
    limits(5.26, 12.0, None),
    limits(4.18, 12.0, None),
    limits(5.26, 12.0, None),
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
    let (bodies, motion) = match variant {
        Variant::Panda => (&PANDA_INERTIA, &PANDA_MOTION_LIMITS),
        Variant::Fr3 => (&FR3_INERTIA, &FR3_MOTION_LIMITS),
    };
    with_dynamics(spec_from_rows(source, base, &rows), bodies, motion)
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
