//! What a task knows about the world beyond the arm and the object's path: the scene to
//! collide with, the approach before the grasp and the retreat after the place, and the
//! gripper's opening and fingers. Without a scene no collision is checked (the behaviour of a
//! task that says nothing about its world).

use super::path::ObjectPath;
use super::settings::{check_count, Limits};
use crate::collision::{
    distance, signed_distance, ArmBodies, Body, CollisionOptions, LinkShape, Scene, SelfPairs,
};
use crate::failure::Phase;
use crate::geometry::shape::Shape;
use crate::grasp::hand::{Hand, HandJointKind, StockGripper};
use crate::robot::Chain;
use nalgebra::{Isometry3, Translation3, Unit, Vector3};
use std::sync::Arc;

/// A straight stroke of the tool along its approach axis: before the grasp the tool comes in
/// from `distance` back along the axis; after the place it backs out by `distance`. In a task
/// file: `approach: { distance, samples, axis }` and `retreat: {...}`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Stroke {
    /// How far the pre-grasp (or post-place) pose is from the grasp (place) pose (m).
    pub distance: f64,
    /// Samples of the stroke besides the grasp (place) pose itself.
    pub samples: usize,
    /// The approach axis in the tool frame (unit; default `+z`, from the palm towards the
    /// object, the convention of the built-in Baxter tool and of most grippers' TCP frames).
    pub axis: Unit<Vector3<f64>>,
}

impl Stroke {
    /// A stroke of `distance` (m) in `samples` samples along the tool's `+z`.
    pub fn new(distance: f64, samples: usize) -> Self {
        Self {
            distance,
            samples,
            axis: Vector3::z_axis(),
        }
    }

    /// `wrist_from_stroke` of stroke sample `k` of `samples`, where `k = 0` is the farthest
    /// and `k = samples` the grasp itself: back along the axis by `distance · (1 − k/samples)`.
    pub fn offset(&self, k: usize) -> Isometry3<f64> {
        let back = self.distance * (1.0 - k as f64 / self.samples as f64);
        Translation3::from(-self.axis.into_inner() * back).into()
    }
}

/// A gripper: its opening and its bodies in the tool frame — a parallel gripper's box fingers
/// (they close along `y`, approach along `z`, and end at the tool origin) and palm, or the
/// links of a hand described in a URDF, opened. In a task file:
/// `gripper: { opening, finger: [length, width, thickness], palm: [x, y, z] }`,
/// `gripper: { builtin: baxter }` or `gripper: { urdf, root, tool_from_root, fingers, open }`.
#[derive(Debug, Clone, PartialEq)]
pub struct Gripper {
    /// The largest gap between the inner finger faces (m); for a URDF hand, the smallest
    /// distance between two of its finger links when open.
    pub opening: f64,
    /// The bodies.
    pub bodies: GripperBodies,
}

/// A gripper's bodies ([`Gripper`]).
#[derive(Debug, Clone, PartialEq)]
pub enum GripperBodies {
    /// Two box fingers and an optional palm box.
    Parallel {
        /// Finger length along the approach axis, width along `x`, thickness along `y` (m).
        finger: [f64; 3],
        /// A palm box behind the finger roots, size along `x, y, z` (m), if modelled.
        palm: Option<[f64; 3]>,
    },
    /// The collision shapes of a hand's links at its open configuration.
    Links(Vec<GripperLink>),
}

/// One collision shape of a URDF hand's link, open ([`Gripper::from_hand`]).
#[derive(Debug, Clone, PartialEq)]
pub struct GripperLink {
    /// The link's name.
    pub link: String,
    /// The shape's pose in the tool frame (m).
    pub tool_from_shape: Isometry3<f64>,
    /// The shape.
    pub shape: Shape,
    /// A finger: checked against the object's width, and allowed to touch it at the grasp.
    pub finger: bool,
}

/// The default finger size of a gripper given only by its opening (m): 5 cm long, 2 cm wide,
/// 1 cm thick.
pub const DEFAULT_FINGER: [f64; 3] = [0.05, 0.02, 0.01];

impl Gripper {
    /// A parallel gripper opening to `opening` (m) with [`DEFAULT_FINGER`] fingers and no palm.
    pub fn parallel(opening: f64) -> Self {
        Self {
            opening,
            bodies: GripperBodies::Parallel {
                finger: DEFAULT_FINGER,
                palm: None,
            },
        }
    }

    /// The built-in Baxter electric gripper (the dimensions of
    /// [`crate::grasp::hand::baxter_electric_gripper`] at its widest opening, 7 cm): 9 cm
    /// fingers, 2 cm wide and 1 cm thick, and its 6 × 11 cm palm from the gripper base to the
    /// finger roots.
    pub fn baxter() -> Self {
        Self {
            opening: 0.07,
            bodies: GripperBodies::Parallel {
                finger: [0.09, 0.02, 0.01],
                palm: Some([0.06, 0.11, 0.1327 - 0.09]),
            },
        }
    }

    /// A stock gripper ([`StockGripper`]) open to its full stroke: its hand's links in its TCP
    /// frame, the two finger links its fingers.
    pub fn stock(gripper: StockGripper) -> Self {
        Self::from_hand(
            &gripper.hand(),
            &Isometry3::identity(),
            &[gripper.opening()],
            &["l_finger".into(), "r_finger".into()],
        )
        .expect("a stock hand names its two fingers")
    }

    /// A hand's links at configuration `open` (its joints' values, rad / m; the hand's
    /// [`Hand::link_poses`]), placed by `tool_from_root` (where the hand's root link sits in
    /// the tool frame). The links named in `fingers` are the fingers (none named: every link
    /// moved by a hand joint). The opening is the smallest distance between shapes of two
    /// different finger links. Errors `(field, message)` in task-file spelling.
    pub fn from_hand(
        hand: &Hand,
        tool_from_root: &Isometry3<f64>,
        open: &[f64],
        fingers: &[String],
    ) -> Result<Self, (String, String)> {
        for name in fingers {
            if hand.link_index(name).is_none() {
                return Err((
                    "gripper.fingers".into(),
                    format!(
                        "'{name}' is not a link of the hand (links: {})",
                        hand.links
                            .iter()
                            .map(|l| l.name.as_str())
                            .collect::<Vec<_>>()
                            .join(", ")
                    ),
                ));
            }
        }
        // Links moved by a joint: a non-fixed joint on the way from the root.
        let mut moving = vec![false; hand.links.len()];
        for (i, link) in hand.links.iter().enumerate() {
            moving[i] =
                link.joint.kind != HandJointKind::Fixed || link.parent.is_some_and(|p| moving[p]);
        }
        let poses = hand.link_poses(open);
        let mut links = Vec::new();
        for (i, link) in hand.links.iter().enumerate() {
            let finger = if fingers.is_empty() {
                moving[i]
            } else {
                fingers.contains(&link.name)
            };
            for shape in &link.shapes {
                links.push(GripperLink {
                    link: link.name.clone(),
                    tool_from_shape: tool_from_root * poses[i] * shape.link_from_shape,
                    shape: shape.shape.clone(),
                    finger,
                });
            }
        }
        let finger_shapes: Vec<&GripperLink> = links.iter().filter(|l| l.finger).collect();
        let mut opening = f64::INFINITY;
        for (k, a) in finger_shapes.iter().enumerate() {
            for b in &finger_shapes[k + 1..] {
                if a.link != b.link {
                    let (x, y) = (
                        Body::from_shape("a", &a.shape),
                        Body::from_shape("b", &b.shape),
                    );
                    opening = opening.min(distance(&x, &a.tool_from_shape, &y, &b.tool_from_shape));
                }
            }
        }
        if !opening.is_finite() {
            return Err((
                "gripper.fingers".into(),
                "the hand needs collision shapes on at least two finger links".into(),
            ));
        }
        Ok(Self {
            opening,
            bodies: GripperBodies::Links(links),
        })
    }

    /// The fingers, open at `opening`, as `(name, tool_from_shape, shape)`.
    pub fn finger_shapes(&self) -> Vec<(String, Isometry3<f64>, Shape)> {
        match &self.bodies {
            GripperBodies::Parallel { finger, .. } => {
                let [length, width, thickness] = *finger;
                let shape =
                    Shape::cuboid([width, thickness, length]).expect("finger sizes are checked");
                let y = self.opening / 2.0 + thickness / 2.0;
                vec![
                    (
                        "left finger".into(),
                        Isometry3::translation(0.0, y, -length / 2.0),
                        shape.clone(),
                    ),
                    (
                        "right finger".into(),
                        Isometry3::translation(0.0, -y, -length / 2.0),
                        shape,
                    ),
                ]
            }
            GripperBodies::Links(links) => links
                .iter()
                .filter(|l| l.finger)
                .map(|l| (l.link.clone(), l.tool_from_shape, l.shape.clone()))
                .collect(),
        }
    }

    /// Every hand body (fingers, and the palm or the hand's other links), tool frame.
    pub fn hand_shapes(&self) -> Vec<(String, Isometry3<f64>, Shape)> {
        match &self.bodies {
            GripperBodies::Parallel { finger, palm } => {
                let mut shapes = self.finger_shapes();
                if let Some(palm) = palm {
                    shapes.push((
                        "palm".into(),
                        Isometry3::translation(0.0, 0.0, -finger[0] - palm[2] / 2.0),
                        Shape::cuboid(*palm).expect("palm sizes are checked"),
                    ));
                }
                shapes
            }
            GripperBodies::Links(links) => links
                .iter()
                .map(|l| (l.link.clone(), l.tool_from_shape, l.shape.clone()))
                .collect(),
        }
    }

    /// Checks every size; the error names the field.
    pub(crate) fn check(&self) -> Result<(), (String, String)> {
        let positive = |field: String, v: f64| {
            if v.is_finite() && v > 0.0 {
                Ok(())
            } else {
                Err((
                    field,
                    format!("must be a positive finite length in metres, got {v}"),
                ))
            }
        };
        positive("gripper.opening".into(), self.opening)?;
        if let GripperBodies::Parallel { finger, palm } = &self.bodies {
            for (k, v) in finger.iter().enumerate() {
                positive(format!("gripper.finger[{k}]"), *v)?;
            }
            if let Some(palm) = palm {
                for (k, v) in palm.iter().enumerate() {
                    positive(format!("gripper.palm[{k}]"), *v)?;
                }
            }
        }
        Ok(())
    }
}

/// The scene settings a task is built with ([`super::TaskBuilder::scene`]).
#[derive(Debug, Clone, Default)]
pub struct SceneSettings {
    /// The table and obstacles.
    pub scene: Scene,
    /// Margins and which checks run.
    pub options: CollisionOptions,
    /// The robot's link geometry (every link that has any; links not on an arm's chain are
    /// ignored).
    pub robot_shapes: Vec<LinkShape>,
    /// How self-collision pairs are chosen.
    pub self_pairs: SelfPairs,
    /// Link pairs never checked (SRDF `disable_collisions`).
    pub disabled: Vec<(String, String)>,
}

/// The collision checks of a built task.
#[derive(Debug, Clone)]
pub struct Collisions {
    /// The table and obstacles, world frame.
    pub scene: Arc<Scene>,
    /// Margins and which checks run.
    pub options: CollisionOptions,
}

/// `Err((field, message))` when the object, at the start or at the end of its path,
/// overlaps an obstacle by more than `collision.touch_tolerance`: every grasp would then
/// collide, and the cause is the task's placement, not the grasps. The field is
/// `object.pose` for the start and `trajectory` for the end; the message names the
/// obstacle, the depth and where the object is. (The table is a plausibility warning:
/// an object resting on it touches it.)
pub(crate) fn check_object_clear(
    collisions: &Collisions,
    object: &Body,
    path: &ObjectPath,
) -> Result<(), (String, String)> {
    let (Some(first), Some(last)) = (path.samples.first(), path.samples.last()) else {
        return Ok(());
    };
    let tolerance = collisions.options.touch_tolerance;
    for (field, moment, sample) in [("object.pose", "start", first), ("trajectory", "end", last)] {
        let pose = &sample.world_from_object;
        for obstacle in collisions.scene.obstacles() {
            let depth = -signed_distance(object, pose, &obstacle.body, &obstacle.world_from_body);
            if depth > tolerance {
                let at = pose.translation.vector;
                return Err((
                    field.to_string(),
                    format!(
                        "at the {moment} of its path the object, at ({:.3}, {:.3}, {:.3}) m, \
                         overlaps {} by {:.1} mm: every grasp would collide; move the object \
                         or the obstacle",
                        at.x,
                        at.y,
                        at.z,
                        obstacle.body.name(),
                        depth * 1000.0
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// The finest continuous-check resolution a task may ask for (m): below a nanometre the
/// bisection between samples would only spend time.
pub const MIN_RESOLUTION: f64 = 1e-9;

/// The world settings a builder holds, for [`check_world`].
pub(crate) struct WorldInput<'a> {
    pub approach: Option<&'a Stroke>,
    pub retreat: Option<&'a Stroke>,
    pub gripper: Option<&'a Gripper>,
    pub scene: Option<SceneSettings>,
}

/// The collision checks of a task and each arm's bodies (`None` without a scene).
type World = (Option<Collisions>, Vec<Option<Arc<ArmBodies>>>);

/// Checks the world settings and builds each arm's bodies (one per chain, in order) when there
/// is a scene; errors are `(field, message)` in task-file spelling.
pub(crate) fn check_world<'c>(
    input: WorldInput<'_>,
    chains: impl ExactSizeIterator<Item = &'c Chain>,
    limits: &Limits,
) -> Result<World, (String, String)> {
    for (field, stroke) in [("approach", input.approach), ("retreat", input.retreat)] {
        let Some(stroke) = stroke else { continue };
        if !(stroke.distance.is_finite() && stroke.distance > 0.0) {
            return Err((
                format!("{field}.distance"),
                format!(
                    "must be a positive finite length in metres, got {}",
                    stroke.distance
                ),
            ));
        }
        if stroke.samples == 0 {
            return Err((format!("{field}.samples"), "must be at least 1".into()));
        }
        check_count(
            &format!("{field}.samples"),
            stroke.samples,
            limits.max_samples,
            "max_samples",
        )
        .map_err(|m| (format!("{field}.samples"), m))?;
    }
    if let Some(gripper) = input.gripper {
        gripper.check()?;
    }
    let Some(settings) = input.scene else {
        return Ok((None, vec![None; chains.len()]));
    };
    let options = settings.options;
    for (field, value, lowest) in [
        ("collision.margin", options.margin, 0.0),
        ("collision.touch_tolerance", options.touch_tolerance, 0.0),
        ("collision.resolution", options.resolution, MIN_RESOLUTION),
    ] {
        if !(value.is_finite() && value >= lowest) {
            return Err((
                field.to_string(),
                format!("must be a finite length ≥ {lowest} in metres, got {value}"),
            ));
        }
    }
    let hand = input.gripper.map(Gripper::hand_shapes).unwrap_or_default();
    let self_pairs = if options.self_collision {
        settings.self_pairs
    } else {
        SelfPairs::None
    };
    let bodies = chains
        .map(|chain| {
            ArmBodies::new(
                chain,
                &settings.robot_shapes,
                &hand,
                &settings.disabled,
                self_pairs,
            )
            .map(|b| Some(Arc::new(b)))
            .map_err(|e| ("collision".to_string(), e.to_string()))
        })
        .collect::<Result<Vec<_>, _>>()?;
    Ok((
        Some(Collisions {
            scene: Arc::new(settings.scene),
            options,
        }),
        bodies,
    ))
}

/// The whole motion of a candidate — approach, the object's path, retreat — as tool poses and
/// phases.
#[derive(Debug, Clone, Copy)]
pub struct WholeMotionPlan<'a> {
    /// The approach before the grasp.
    pub approach: Option<&'a Stroke>,
    /// The retreat after the place.
    pub retreat: Option<&'a Stroke>,
    /// The object's path, world frame.
    pub path: &'a ObjectPath,
}

impl WholeMotionPlan<'_> {
    /// The tool poses `world_from_wrist` of the whole motion for the grasp
    /// `object_from_wrist`: the approach's samples (farthest first), the path's, then the
    /// retreat's.
    pub fn tool_poses(&self, object_from_wrist: &Isometry3<f64>) -> Vec<Isometry3<f64>> {
        let poses: Vec<&Isometry3<f64>> = self.path.poses().collect();
        let before = self.approach.map_or(0, |s| s.samples);
        let after = self.retreat.map_or(0, |s| s.samples);
        let mut out = Vec::with_capacity(poses.len() + before + after);
        if let (Some(stroke), Some(first)) = (self.approach, poses.first()) {
            let grasp = *first * object_from_wrist;
            out.extend((0..stroke.samples).map(|k| grasp * stroke.offset(k)));
        }
        out.extend(poses.iter().map(|p| *p * object_from_wrist));
        if let (Some(stroke), Some(last)) = (self.retreat, poses.last()) {
            let place = *last * object_from_wrist;
            out.extend((1..=stroke.samples).map(|k| place * stroke.offset(stroke.samples - k)));
        }
        out
    }

    /// How many approach samples come before the grasp.
    pub fn approach_samples(&self) -> usize {
        self.approach.map_or(0, |s| s.samples)
    }

    /// The phase and in-phase index of whole-motion sample `i`.
    pub fn phase_of(&self, i: usize) -> (Phase, usize) {
        let a = self.approach_samples();
        let n = self.path.samples.len();
        if i < a {
            (Phase::Approach, i)
        } else if i < a + n {
            (Phase::Path, i - a)
        } else {
            (Phase::Retreat, i - a - n)
        }
    }
}

impl super::Task {
    /// The task's whole-motion plan (approach, path, retreat).
    pub fn motion_plan(&self) -> WholeMotionPlan<'_> {
        WholeMotionPlan {
            approach: self.approach.as_ref(),
            retreat: self.retreat.as_ref(),
            path: &self.path,
        }
    }
}
