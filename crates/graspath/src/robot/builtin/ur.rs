//! **Universal Robots** UR5 and UR10 (CB3) and UR5e and UR10e (e-Series): one 6-DOF arm from
//! `base` to `tool0`.
//!
//! Kinematics: Universal Robots' published standard DH parameters ("DH parameters for
//! calculations of kinematics and dynamics"), `α = (π/2, 0, 0, π/2, −π/2, 0)`, `a₁ = a₄ = a₅
//! = a₆ = 0`, `d₂ = d₃ = 0`, and per model the `d₁ a₂ a₃ d₄ d₅ d₆` of [`UR_DH`]; joint
//! limits ±2π (±360° on every joint, the datasheets' working range). Turned into joint
//! origins by [`super::dh_rows`]: link `i`'s frame is DH frame `i − 1` turned by `qᵢ`.
//!
//! **The elbow's range.** ROS-Industrial's `ur_description` and MuJoCo Menagerie limit the
//! elbow to ±π instead: the forearm meets the upper arm before a full turn, and no elbow
//! configuration beyond ±π reaches a pose that one within ±π does not. The built-in keeps
//! the datasheet's ±2π (the controller accepts it); a task that wants ROS's range narrows it:
//! `robot: {builtin: ur5e, joint_limits: {elbow_joint: [-3.141592653589793,
//! 3.141592653589793]}}`.
//!
//! **Base and tool frames**: `base` is the controller's base frame (the DH frame 0; ROS's
//! `ur_description` calls it `base` too, and its `base_link` is `base` turned by π about
//! `z`). `tool0` is the DH frame 6, the centre of the tool flange with `z` out of the flange
//! (ROS's `tool0`, the controller's TCP with a zero TCP offset). A tool offset follows
//! `tool0`.
//!
//! Collision primitives (approximations): a cylinder for the fixed base, and capsules along
//! the physical shoulder, upper-arm tube, elbow, forearm tube and wrists. The tubes lie off
//! the DH lines along the joint axes: the upper arm by the shoulder offset `s` and the
//! forearm by `s − e` (the elbow offset), the values of ROS-Industrial's `ur_description` /
//! `ur_e_description` (UR5 0.13585/0.1197, UR10 0.220941/0.1719, UR5e 0.138/0.131, UR10e
//! 0.176/0.137 m). Radii are the datasheets' housing sizes, rounded up. The fixed base is a
//! cylinder up to the top of `ur_description`'s base mesh (UR5 24 mm, UR10 38 mm, UR5e and
//! UR10e 99 mm above the mounting plane), and the shoulder housing starts there — as in those
//! meshes, whose shoulder reaches exactly down to the base's top — so an arm standing on a
//! table at its mounting plane keeps the base's height from it at any `q1`.

use super::{capsule_between, dh_rows, limits, spec_from_rows, DhRow, LinkInertia};
use crate::geometry::shape::Shape;
use crate::robot::collision::{CollisionGeometry, CollisionShape, LinkCollisions};
use crate::robot::spec::{ChainSpec, JointKind, MotionLimits};
use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use std::f64::consts::{FRAC_PI_2, PI, TAU};

/// A Universal Robots arm.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum UrModel {
    /// UR5 (CB3).
    Ur5,
    /// UR10 (CB3).
    Ur10,
    /// UR5e.
    Ur5e,
    /// UR10e.
    Ur10e,
}

/// Published DH lengths `[d1, a2, a3, d4, d5, d6]` (m) of UR5, UR10, UR5e, UR10e.
pub const UR_DH: [(UrModel, [f64; 6]); 4] = [
    (
        UrModel::Ur5,
        [0.089159, -0.425, -0.39225, 0.10915, 0.09465, 0.0823],
    ),
    (
        UrModel::Ur10,
        [0.1273, -0.612, -0.5723, 0.163941, 0.1157, 0.0922],
    ),
    (
        UrModel::Ur5e,
        [0.1625, -0.425, -0.3922, 0.1333, 0.0997, 0.0996],
    ),
    (
        UrModel::Ur10e,
        [0.1807, -0.6127, -0.57155, 0.17415, 0.11985, 0.11655],
    ),
];

/// DH twists `α₁ … α₆` (rad), the same for every model.
const ALPHA: [f64; 6] = [FRAC_PI_2, 0.0, 0.0, FRAC_PI_2, -FRAC_PI_2, 0.0];

const NAMES: [(&str, &str); 6] = [
    ("shoulder_pan_joint", "shoulder_link"),
    ("shoulder_lift_joint", "upper_arm_link"),
    ("elbow_joint", "forearm_link"),
    ("wrist_1_joint", "wrist_1_link"),
    ("wrist_2_joint", "wrist_2_link"),
    ("wrist_3_joint", "wrist_3_link"),
];

impl UrModel {
    /// `ur5`, `ur10`, `ur5e` or `ur10e`.
    pub fn name(self) -> &'static str {
        match self {
            UrModel::Ur5 => "ur5",
            UrModel::Ur10 => "ur10",
            UrModel::Ur5e => "ur5e",
            UrModel::Ur10e => "ur10e",
        }
    }

    /// `[d1, a2, a3, d4, d5, d6]` (m), from [`UR_DH`].
    pub fn dh(self) -> [f64; 6] {
        UR_DH
            .iter()
            .find(|(m, _)| *m == self)
            .map(|(_, p)| *p)
            .expect("every model has a row")
    }

    /// Shoulder and elbow offsets `(s, e)` (m) of the arm tubes off the DH lines.
    fn offsets(self) -> (f64, f64) {
        match self {
            UrModel::Ur5 => (0.13585, 0.1197),
            UrModel::Ur10 => (0.220941, 0.1719),
            UrModel::Ur5e => (0.138, 0.131),
            UrModel::Ur10e => (0.176, 0.137),
        }
    }

    /// The fixed base's height above the mounting plane (m): the top of the base housing
    /// in `ur_description`'s collision meshes (`base.stl`), where the rotating shoulder
    /// housing starts.
    fn base_height(self) -> f64 {
        match self {
            UrModel::Ur5 => 0.024,
            UrModel::Ur10 => 0.038,
            UrModel::Ur5e | UrModel::Ur10e => 0.099,
        }
    }

    /// Radii (m): base, shoulder and upper arm, forearm, wrists.
    fn radii(self) -> [f64; 4] {
        match self {
            UrModel::Ur5 | UrModel::Ur5e => [0.076, 0.062, 0.047, 0.046],
            UrModel::Ur10 | UrModel::Ur10e => [0.095, 0.078, 0.06, 0.048],
        }
    }
}

/// Link masses, centres of mass and inertias in the **DH frames** `1…6` (the frame at the far
/// end of each link), per model; see the module documentation for the sources.
pub const UR_INERTIA: [(UrModel, [LinkInertia; 6]); 4] = [
    (
        UrModel::Ur5,
        [
            LinkInertia::new(
                3.7,
                [0.0, -0.02561, 0.00193],
                [0.01497235833, 0.01040625, 0.01497235833, 0.0, 0.0, 0.0],
            ),
            LinkInertia::new(
                8.393,
                [0.2125, 0.0, 0.11336],
                [0.0151074, 0.1338858354, 0.1338858354, 0.0, 0.0, 0.0],
            ),
            LinkInertia::new(
                2.33,
                [0.15, 0.0, 0.0265],
                [0.004095, 0.03121680352, 0.03121680352, 0.0, 0.0, 0.0],
            ),
            LinkInertia::new(
                1.219,
                [0.0, -0.0018, 0.01634],
                [0.002013889583, 0.0021942, 0.002013889583, 0.0, 0.0, 0.0],
            ),
            LinkInertia::new(
                1.219,
                [0.0, 0.0018, 0.01634],
                [0.001831039583, 0.0021942, 0.001831039583, 0.0, 0.0, 0.0],
            ),
            LinkInertia::new(
                0.1879,
                [0.0, 0.0, -0.001159],
                [
                    8.062475833e-05,
                    8.062475833e-05,
                    0.0001321171875,
                    0.0,
                    0.0,
                    0.0,
                ],
            ),
        ],
    ),
    (
        UrModel::Ur10,
        [
            LinkInertia::new(
                7.1,
                [0.021, 0.0, 0.027],
                [0.03408, 0.03529, 0.02156, 2e-05, -0.00425, 8e-05],
            ),
            LinkInertia::new(
                12.7,
                [0.38, 0.0, 0.158],
                [0.02814, 0.77068, 0.76943, 5e-05, -0.01561, 2e-05],
            ),
            LinkInertia::new(
                4.27,
                [0.24, 0.0, 0.068],
                [0.01014, 0.30928, 0.30646, 8e-05, 0.00916, 0.0],
            ),
            LinkInertia::new(
                2.0,
                [0.0, 0.007, 0.018],
                [0.00296, 0.00222, 0.00258, -1e-05, 0.0, -0.00024],
            ),
            LinkInertia::new(
                2.0,
                [0.0, 0.007, 0.018],
                [0.00296, 0.00222, 0.00258, -1e-05, 0.0, -0.00024],
            ),
            LinkInertia::new(
                0.365,
                [0.0, 0.0, -0.026],
                [0.0004, 0.00041, 0.00034, 0.0, 0.0, 0.0],
            ),
        ],
    ),
    (
        UrModel::Ur5e,
        [
            LinkInertia::new(
                3.761,
                [0.0, -0.02561, 0.00193],
                [0.0102675, 0.00666, 0.0102675, 0.0, 0.0, 0.0],
            ),
            LinkInertia::new(
                8.058,
                [0.2125, 0.0, 0.11336],
                [0.0151074, 0.1338858354, 0.1338858354, 0.0, 0.0, 0.0],
            ),
            LinkInertia::new(
                2.846,
                [0.15, 0.0, 0.0265],
                [0.004095, 0.03120936758, 0.03120936758, 0.0, 0.0, 0.0],
            ),
            LinkInertia::new(
                1.37,
                [0.0, -0.0018, 0.01634],
                [0.0025599, 0.0021942, 0.0025599, 0.0, 0.0, 0.0],
            ),
            LinkInertia::new(
                1.3,
                [0.0, 0.0018, 0.01634],
                [0.0025599, 0.0021942, 0.0025599, 0.0, 0.0, 0.0],
            ),
            LinkInertia::new(
                0.365,
                [0.0, 0.0, -0.001159],
                [
                    9.890414008e-05,
                    9.890414008e-05,
                    0.0001321171875,
                    0.0,
                    0.0,
                    0.0,
                ],
            ),
        ],
    ),
    (
        UrModel::Ur10e,
        [
            LinkInertia::new(
                7.369,
                [0.021, 0.0, 0.027],
                [0.03408, 0.03529, 0.02156, 2e-05, -0.00425, 8e-05],
            ),
            LinkInertia::new(
                13.051,
                [0.38, 0.0, 0.158],
                [0.02814, 0.77068, 0.76943, 5e-05, -0.01561, 2e-05],
            ),
            LinkInertia::new(
                3.989,
                [0.24, 0.0, 0.068],
                [0.01014, 0.30928, 0.30646, 8e-05, 0.00916, 0.0],
            ),
            LinkInertia::new(
                2.1,
                [0.0, 0.007, 0.018],
                [0.00296, 0.00222, 0.00258, -1e-05, 0.0, -0.00024],
            ),
            LinkInertia::new(
                1.98,
                [0.0, 0.007, 0.018],
                [0.00296, 0.00222, 0.00258, -1e-05, 0.0, -0.00024],
            ),
            LinkInertia::new(
                0.615,
                [0.0, 0.0, -0.026],
                [0.0004, 0.00041, 0.00034, 0.0, 0.0, 0.0],
            ),
        ],
    ),
];

/// Velocity (rad/s) and effort (N·m) limits per model, joints 1–6 (Universal Robots' user
/// manuals and "max. joint torques" article, as in `Universal_Robots_ROS2_Description`);
/// UR publishes no acceleration limits.
fn ur_motion_limits(model: UrModel) -> [MotionLimits; 6] {
    let (big, small, wrist) = match model {
        UrModel::Ur5 | UrModel::Ur5e => ((PI, 150.0), (PI, 150.0), (PI, 28.0)),
        UrModel::Ur10 => ((2.0 * PI / 3.0, 330.0), (PI, 150.0), (PI, 56.0)),
        UrModel::Ur10e => ((2.0 * PI / 3.0, 330.0), (PI, 150.0), (PI, 54.0)),
    };
    let l = |(v, e): (f64, f64)| limits(v, e, None);
    [l(big), l(big), l(small), l(wrist), l(wrist), l(wrist)]
}

/// The full DH table of a model: `(d, a, α)` per joint.
pub fn ur_dh_table(model: UrModel) -> [(f64, f64, f64); 6] {
    let [d1, a2, a3, d4, d5, d6] = model.dh();
    let d = [d1, 0.0, 0.0, d4, d5, d6];
    let a = [0.0, a2, a3, 0.0, 0.0, 0.0];
    std::array::from_fn(|i| (d[i], a[i], ALPHA[i]))
}

/// The arm's chain description, `base → tool0`.
pub fn ur_spec(model: UrModel) -> ChainSpec {
    let table: Vec<DhRow> = ur_dh_table(model)
        .iter()
        .zip(NAMES)
        .map(|((d, a, alpha), (joint, child))| DhRow {
            joint,
            child,
            d: *d,
            a: *a,
            alpha: *alpha,
            limits: (-TAU, TAU),
        })
        .collect();
    let source = format!("built-in {}", model.name());
    let mut spec = spec_from_rows(&source, "base", &dh_rows(&table, "tool0_joint", "tool0"));
    let bodies = UR_INERTIA
        .iter()
        .find(|(m, _)| *m == model)
        .map(|(_, b)| b)
        .expect("every model has a row");
    let moving = spec
        .joints
        .iter_mut()
        .filter(|j| j.kind != JointKind::Fixed);
    for (((joint, body), (d, a, alpha)), limit) in moving
        .zip(bodies)
        .zip(ur_dh_table(model))
        .zip(ur_motion_limits(model))
    {
        // Link i's frame is DH frame i − 1 turned by qᵢ; DH frame i follows it by the row's
        // constant part Tz(d)·Tx(a)·Rx(α).
        let link_from_dh = Isometry3::from_parts(
            Translation3::new(a, 0.0, d),
            UnitQuaternion::from_axis_angle(&Vector3::x_axis(), alpha),
        );
        joint.child_inertial = Some(body.body().transformed(&link_from_dh));
        joint.limits = limit;
    }
    spec
}

/// Collision primitives, link by link (see the module documentation).
pub fn ur_collisions(model: UrModel) -> Vec<LinkCollisions> {
    let [d1, a2, a3, d4, d5, d6] = model.dh();
    let (s, e) = model.offsets();
    let [r_base, r_joint, r_fore, r_wrist] = model.radii();
    let base_height = model.base_height();
    let link = |name: &str, shapes: Vec<CollisionShape>| LinkCollisions {
        link: name.to_string(),
        shapes,
    };
    vec![
        link(
            "base",
            vec![CollisionShape {
                name: Some("base".into()),
                link_from_collision: Isometry3::from_parts(
                    Translation3::new(0.0, 0.0, base_height / 2.0),
                    Default::default(),
                ),
                geometry: CollisionGeometry::Shape(
                    Shape::cylinder(r_base, base_height).expect("positive sizes"),
                ),
            }],
        ),
        // Link 1's frame is the base frame turned by q1; joint 2's axis is its −y. The
        // shoulder housing stands on the fixed base: the column starts at the base's top.
        link(
            "shoulder_link",
            vec![
                capsule_between(
                    "shoulder column",
                    [0.0, 0.0, base_height + r_joint],
                    [0.0, 0.0, d1],
                    r_joint,
                ),
                capsule_between("shoulder", [0.0, 0.0, d1], [0.0, -s, d1], r_joint),
            ],
        ),
        // Links 2–4: DH frames 1–3 turned; joint axes along z, tubes along x.
        link(
            "upper_arm_link",
            vec![capsule_between(
                "upper arm",
                [0.0, 0.0, s],
                [a2, 0.0, s],
                r_joint,
            )],
        ),
        link(
            "forearm_link",
            vec![
                capsule_between("elbow", [0.0, 0.0, s], [0.0, 0.0, s - e], r_joint),
                capsule_between("forearm", [0.0, 0.0, s - e], [a3, 0.0, s - e], r_fore),
            ],
        ),
        link(
            "wrist_1_link",
            vec![capsule_between(
                "wrist 1",
                [0.0, 0.0, s - e],
                [0.0, 0.0, d4],
                r_wrist,
            )],
        ),
        link(
            "wrist_2_link",
            vec![capsule_between(
                "wrist 2",
                [0.0; 3],
                [0.0, 0.0, d5],
                r_wrist,
            )],
        ),
        link(
            "wrist_3_link",
            // Stops one radius short of the flange (tool0).
            vec![capsule_between(
                "wrist 3",
                [0.0; 3],
                [0.0, 0.0, (d6 - r_wrist).max(0.0)],
                r_wrist,
            )],
        ),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The shoulder's vertical extent over the mounting plane in `ur_description`'s collision
    /// meshes (`shoulder.stl`'s z range plus `d1`; the shoulder turns about z, so it is the
    /// same at every `q1`), and the base mesh's height: per model, (bottom, top, base).
    const MESH_SHOULDER: [(UrModel, f64, f64, f64); 4] = [
        (UrModel::Ur5, 0.024, 0.158, 0.024),
        (UrModel::Ur10, 0.038, 0.215, 0.038),
        (UrModel::Ur5e, 0.099, 0.234, 0.099),
        (UrModel::Ur10e, 0.099, 0.275, 0.099),
    ];

    /// The lowest and highest z (link frame) of a link's shapes, by their support points.
    fn z_range(link: &LinkCollisions) -> (f64, f64) {
        let (mut low, mut high) = (f64::INFINITY, f64::NEG_INFINITY);
        for s in &link.shapes {
            let CollisionGeometry::Shape(shape) = &s.geometry else {
                panic!("built-in shapes are primitives")
            };
            for dir in [Vector3::z(), -Vector3::z()] {
                let local = s.link_from_collision.inverse_transform_vector(&dir);
                let p = s.link_from_collision * shape.support(&local);
                low = low.min(p.z);
                high = high.max(p.z);
            }
        }
        (low, high)
    }

    #[test]
    fn the_shoulder_stands_on_the_base_as_in_the_link_meshes() {
        for (model, bottom, top, base) in MESH_SHOULDER {
            let links = ur_collisions(model);
            let (base_low, base_high) = z_range(&links[0]);
            assert!(
                base_low.abs() < 1e-12,
                "{model:?}: the base starts at its plane"
            );
            assert!(
                (base_high - base).abs() < 1e-3,
                "{model:?}: base top {base_high}"
            );
            // Link 1's frame is the base frame turned about z: its z range is the world's.
            let (low, high) = z_range(&links[1]);
            assert!(
                (low - bottom).abs() < 1e-3,
                "{model:?}: shoulder bottom {low}"
            );
            assert!(
                low >= base_high - 1e-12,
                "{model:?}: the shoulder enters the base"
            );
            assert!(
                (high - top).abs() < 0.02,
                "{model:?}: shoulder top {high} vs {top}"
            );
        }
    }
}
