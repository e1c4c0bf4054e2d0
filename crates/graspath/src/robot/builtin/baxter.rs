//! **Baxter** (Rethink Robotics): both 7-DOF arms from the `base` link to the electric
//! gripper's tool frame (`left_gripper` / `right_gripper`), with the joint origins, axes and
//! limits published in Rethink's `baxter_description` (torso mount, shoulder `s0 s1`, elbow
//! `e0 e1`, wrist `w0 w1 w2`, hand, gripper base and the 0.1327 m endpoint of the standard
//! electric gripper fingers).
//!
//! **Dynamics**: the link masses, centres of mass and inertias of `baxter_description` as
//! shipped in example-robot-data 6.0.0 (`baxter.urdf`), link frames, with the hand, the
//! gripper base, the fixed sensor links and the gripper's two fingers (closed) folded into
//! the wrist link `w2` (the same numbers for both arms); velocity 1.5 rad/s and effort
//! 50 N·m on `s0 s1 e0 e1`, 4.0 rad/s and 15 N·m on `w0 w1 w2`, from the same file. No
//! acceleration limits are set (unknown).

// The published parameters round π/2 and π/4 to 1.57079632679 and 0.7854; they are kept
// verbatim so the model equals the published one to the last digit.
#![allow(clippy::approx_constant)]

use super::{limits, origin, with_dynamics, LinkInertia};
use crate::geometry::shape::Shape;
use crate::robot::chain::Chain;
use crate::robot::collision::{CollisionGeometry, CollisionShape, LinkCollisions};
use crate::robot::error::RobotError;
use crate::robot::spec::{ChainSpec, JointKind, JointSpec, MotionLimits};
use nalgebra::{Isometry3, Vector3};
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
        limits: Default::default(),
        child_inertial: None,
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
        limits: Default::default(),
        child_inertial: None,
    }
}

/// Shoulder to wrist links (`s0 … w2`), link frames, either arm (see the module documentation).
pub(super) const BAXTER_INERTIA: [LinkInertia; 7] = [
    LinkInertia::new(
        5.70044,
        [0.01783, 0.00086, 0.19127],
        [
            0.04709102262,
            0.03766976455,
            0.03595988478,
            0.00012787556,
            0.00614870039,
            0.00078086899,
        ],
    ),
    LinkInertia::new(
        3.22708,
        [0.06845119458, 0.002689916643, -0.005289836075],
        [
            0.01175210771,
            0.0278861366,
            0.02078765231,
            -0.0003009536104,
            0.002076737228,
            -0.000188218507,
        ],
    ),
    LinkInertia::new(
        4.31272,
        [-0.00276, 0.00132, 0.18086],
        [
            0.02661733557,
            0.02844355207,
            0.01248008322,
            0.00029270634,
            0.00392189887,
            0.0010838933,
        ],
    ),
    LinkInertia::new(
        2.07216,
        [0.02611298674, 0.001589923268, -0.01116946095],
        [
            0.007115849589,
            0.01318268426,
            0.009268913912,
            0.00036037157,
            0.0007458804722,
            -0.0001966324041,
        ],
    ),
    LinkInertia::new(
        2.24675,
        [-0.001682439969, 0.00459979526, 0.1395191312],
        [
            0.01667747847,
            0.01675492125,
            0.003746624126,
            0.0001840118339,
            0.0001864692861,
            -0.0006473324988,
        ],
    ),
    LinkInertia::new(
        1.60979,
        [0.06041, 0.00697, 0.006],
        [
            0.00387607152,
            0.00700537914,
            0.0055275524,
            -0.00044384784,
            -0.00021115038,
            0.00015348067,
        ],
    ),
    LinkInertia::new(
        0.90268,
        [0.003097722227, 0.0005753714495, 0.08719067111],
        [
            0.04378759515,
            0.04384990004,
            0.04056629688,
            7.059177175e-06,
            4.689007807e-05,
            2.576346357e-05,
        ],
    ),
];

/// Velocity (rad/s) and effort (N·m) limits, `s0 s1 e0 e1 w0 w1 w2`.
pub(super) const BAXTER_MOTION_LIMITS: [MotionLimits; 7] = [
    limits(1.5, 50.0, None),
    limits(1.5, 50.0, None),
    limits(1.5, 50.0, None),
    limits(1.5, 50.0, None),
    limits(4.0, 15.0, None),
    limits(4.0, 15.0, None),
    limits(4.0, 15.0, None),
];

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
    with_dynamics(
        ChainSpec {
            source_name: BAXTER_SOURCE.to_string(),
            base_link: "base".to_string(),
            tip_link: format!("{side}_gripper"),
            joints,
            tip_from_tool: None,
        },
        &BAXTER_INERTIA,
        &BAXTER_MOTION_LIMITS,
    )
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

/// `parent_from_collision` of a collision element published on a fixed sibling link, moved
/// onto the revolute link beside it: both joints leave the same parent, differ by a
/// translation along the revolute axis, and the element is a cylinder about that axis, so the
/// result does not depend on the joint angle.
fn onto_revolute_link(
    parent_from_revolute: &Isometry3<f64>,
    parent_from_fixed: &Isometry3<f64>,
    fixed_from_collision: &Isometry3<f64>,
) -> Isometry3<f64> {
    parent_from_revolute.inverse() * parent_from_fixed * fixed_from_collision
}

/// Baxter's collision geometry, link by link (both arms, torso, pedestal, head), from the
/// `<collision>` elements of the published description (`baxter_description`, as in
/// `../shared/robots/baxter.urdf`); link names are that file's.
///
/// * **Published primitives, as written**: the arm links' cylinders (radius 0.06 m; the hand
///   0.04 m; the gripper base 0.029 m) with their origins, and the two head spheres (radius
///   0.22 m) of `collision_head_link_1/2`, which hang on `base` at `(0.11, 0, 0.75)` and are
///   given here on `base` directly.
/// * **The upper-arm and forearm cylinders** that the description puts on the fixed links
///   `{arm}_upper_elbow_visual` and `{arm}_upper_forearm_visual` are given on
///   `{arm}_upper_elbow` and `{arm}_upper_forearm`: the fixed and revolute joints share their
///   parent and differ by a shift along the revolute axis, which is the cylinders' axis, so
///   the placement is the same at every joint angle.
/// * **Approximations** where the description has a mesh: the torso
///   (`base_link_collision.DAE`) is a 0.30 × 0.30 × 0.66 m box centred at `(−0.065, 0, 0.29)`
///   in the torso frame (from `z = −0.04` to the neck at 0.62, behind the arm mounts); the
///   pedestal (`pedestal_link_collision.DAE`) is a 0.30 × 0.30 × 0.88 m column below it
///   (`z` from −0.93 to −0.05) and a 0.75 × 0.75 × 0.08 m foot at the floor (`z` from −0.93
///   to −0.85), both on `torso` (the pedestal link is fixed to the torso at the identity).
/// * Left out: the 1 mm placeholder spheres of `head`, `screen` and `sonar_ring`, and the
///   gripper fingers, which belong to the hand model ([`crate::grasp::hand`]).
pub fn baxter_collisions() -> Vec<LinkCollisions> {
    let a = PUBLISHED_RIGHT_ANGLE;
    let cylinder =
        |name: &str, radius: f64, length: f64, xyz: [f64; 3], rpy: [f64; 3]| CollisionShape {
            name: Some(name.to_string()),
            link_from_collision: origin(xyz, rpy),
            geometry: CollisionGeometry::Shape(
                Shape::cylinder(radius, length).expect("published sizes are positive"),
            ),
        };
    let boxed = |name: &str, size: [f64; 3], xyz: [f64; 3]| CollisionShape {
        name: Some(name.to_string()),
        link_from_collision: origin(xyz, [0.0; 3]),
        geometry: CollisionGeometry::Shape(Shape::cuboid(size).expect("positive sizes")),
    };
    let sphere = |name: &str, xyz: [f64; 3]| CollisionShape {
        name: Some(name.to_string()),
        link_from_collision: origin(xyz, [0.0; 3]),
        geometry: CollisionGeometry::Shape(Shape::sphere(0.22).expect("positive radius")),
    };
    let mut out = vec![
        LinkCollisions {
            link: "base".into(),
            shapes: vec![
                sphere("collision_head_link_1", [0.11 - 0.07, -0.04, 0.75]),
                sphere("collision_head_link_2", [0.11 - 0.07, 0.04, 0.75]),
            ],
        },
        LinkCollisions {
            link: "torso".into(),
            shapes: vec![
                boxed(
                    "torso (approximation)",
                    [0.30, 0.30, 0.66],
                    [-0.065, 0.0, 0.29],
                ),
                boxed(
                    "pedestal column (approximation)",
                    [0.30, 0.30, 0.88],
                    [-0.065, 0.0, -0.49],
                ),
                boxed(
                    "pedestal foot (approximation)",
                    [0.75, 0.75, 0.08],
                    [-0.065, 0.0, -0.89],
                ),
            ],
        },
    ];
    let elbow_visual = onto_revolute_link(
        &origin([0.102, 0.0, 0.0], [a, 0.0, a]),
        &origin([0.107, 0.0, 0.0], [a, 0.0, a]),
        &origin([0.0, 0.0, 0.1365], [0.0; 3]),
    );
    let forearm_visual = onto_revolute_link(
        &origin([0.10359, 0.0, 0.0], [a, 0.0, a]),
        &origin([0.088, 0.0, 0.0], [a, 0.0, a]),
        &origin([0.0, 0.0, 0.136], [0.0; 3]),
    );
    let moved = |name: &str, length: f64, pose: &Isometry3<f64>| CollisionShape {
        name: Some(name.to_string()),
        link_from_collision: *pose,
        geometry: CollisionGeometry::Shape(
            Shape::cylinder(0.06, length).expect("published sizes are positive"),
        ),
    };
    for side in ["left", "right"] {
        let link = |name: &str, shapes: Vec<CollisionShape>| LinkCollisions {
            link: format!("{side}_{name}"),
            shapes,
        };
        out.extend([
            link(
                "upper_shoulder",
                vec![cylinder(
                    "upper_shoulder",
                    0.06,
                    0.2722,
                    [0.0, 0.0, 0.1361],
                    [0.0; 3],
                )],
            ),
            link(
                "lower_shoulder",
                vec![cylinder("lower_shoulder", 0.06, 0.12, [0.0; 3], [0.0; 3])],
            ),
            link(
                "upper_elbow",
                vec![
                    cylinder("upper_elbow", 0.06, 0.107, [0.0, 0.0, -0.0535], [0.0; 3]),
                    moved("upper_elbow_visual", 0.273, &elbow_visual),
                ],
            ),
            link(
                "lower_elbow",
                vec![cylinder("lower_elbow", 0.06, 0.10, [0.0; 3], [0.0; 3])],
            ),
            link(
                "upper_forearm",
                vec![
                    cylinder("upper_forearm", 0.06, 0.088, [0.0, 0.0, -0.044], [0.0; 3]),
                    moved("upper_forearm_visual", 0.272, &forearm_visual),
                ],
            ),
            link(
                "lower_forearm",
                vec![cylinder("lower_forearm", 0.06, 0.10, [0.0; 3], [0.0; 3])],
            ),
            link(
                "wrist",
                vec![cylinder("wrist", 0.06, 0.165, [0.0; 3], [0.0; 3])],
            ),
            link(
                "hand_link",
                vec![cylinder(
                    "hand",
                    0.04,
                    0.0464,
                    [0.0, 0.0, -0.0232],
                    [0.0; 3],
                )],
            ),
            link(
                "gripper_base_link",
                vec![cylinder(
                    "gripper_base",
                    0.029,
                    0.1,
                    [0.0; 3],
                    [-a, 3.14159265359, 0.0],
                )],
            ),
        ]);
    }
    out
}
