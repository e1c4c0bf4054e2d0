//! Checks of the grasp itself, before any IK: what fails whatever the arm does (the gripper's
//! width, the hand and what rides with it colliding at the commanded tool poses). Each is a
//! [`GraspCheck`]; [`grasp_checks`] lists them in the order they run.

use super::branch_checks::collision_failure;
use super::{Scoring, WorldSetup};
use crate::collision::{signed_distance, Body, CollisionOptions, ToolMotion};
use crate::failure::{Failure, FailureReason, Phase};
use nalgebra::Isometry3;

/// A check of a candidate's grasp before its arm is solved.
pub(super) trait GraspCheck: Sync {
    /// Why the candidate fails whatever the arm does, if it does.
    fn failure(&self, scoring: &Scoring<'_>) -> Option<Failure>;
}

/// The grasp checks of one arm, in the order they run: the gripper's width (with a gripper),
/// then the hand in the scene (with a scene).
pub(super) fn grasp_checks<'a>(fingers: Option<&'a FingerCheck<'a>>) -> Vec<&'a dyn GraspCheck> {
    let mut checks: Vec<&dyn GraspCheck> = Vec::new();
    if let Some(fingers) = fingers {
        checks.push(fingers);
    }
    checks.push(&HandInScene);
    checks
}

/// The hand and what rides rigidly with it (the links after the last moving joint, the carried
/// object) at the commanded tool poses, against the scene (`ArmInScene::check_tool_poses`):
/// a grasp whose hand collides is refused without solving the arm.
pub(super) struct HandInScene;

impl GraspCheck for HandInScene {
    fn failure(&self, scoring: &Scoring<'_>) -> Option<Failure> {
        let hit = scoring.checker.as_ref()?.check_tool_poses(&ToolMotion {
            base_from_tool: &scoring.targets,
            object: scoring.object_along(),
        })?;
        Some(collision_failure(&hit, scoring))
    }
}

/// The gripper-width check of a task: a width given by the candidate's file must fit the
/// opening, and the open fingers at the grasp must not press into the object (when its shape
/// is known). Built once per arm; the finger bodies are shared by every candidate.
pub(super) struct FingerCheck<'a> {
    /// `(name, wrist_from_finger, body)` of each finger, open at the gripper's opening.
    fingers: Vec<(String, Isometry3<f64>, Body)>,
    opening: f64,
    tolerance: f64,
    object: Option<&'a Body>,
}

impl<'a> FingerCheck<'a> {
    pub(super) fn new(world: &WorldSetup<'a>) -> Option<Self> {
        let (gripper, object) = (world.gripper?, world.object);
        Some(Self {
            fingers: gripper
                .finger_shapes()
                .into_iter()
                .map(|(name, wrist_from_finger, shape)| {
                    let body = Body::from_shape(format!("hand {name}"), &shape);
                    (name, wrist_from_finger, body)
                })
                .collect(),
            opening: gripper.opening,
            tolerance: world
                .collisions
                .map_or(CollisionOptions::default().touch_tolerance, |c| {
                    c.options.touch_tolerance
                }),
            object,
        })
    }
}

impl GraspCheck for FingerCheck<'_> {
    fn failure(&self, scoring: &Scoring<'_>) -> Option<Failure> {
        let candidate = scoring.candidate;
        if let Some(width) = candidate
            .width
            .filter(|w| *w > self.opening + self.tolerance)
        {
            return Some(Failure {
                reason: FailureReason::GripperWidth,
                phase: Phase::Path,
                sample: 0,
                detail: format!(
                    "the grasp's width from its file, {width:.4} m, is more than the {:.3} m \
                     opening",
                    self.opening
                ),
                bodies: None,
                joint: None,
            });
        }
        let object = self.object?;
        for (name, wrist_from_finger, finger) in &self.fingers {
            let object_from_finger = candidate.object_from_wrist * wrist_from_finger;
            let depth =
                signed_distance(finger, &object_from_finger, object, &Isometry3::identity());
            if depth < -self.tolerance {
                return Some(Failure {
                    reason: FailureReason::GripperWidth,
                    phase: Phase::Path,
                    sample: 0,
                    detail: format!(
                        "the object is wider across the fingers than the {:.3} m opening: the \
                         {name} would press {:.4} m into it",
                        self.opening, -depth
                    ),
                    bodies: Some([format!("hand {name}"), "object".into()]),
                    joint: None,
                });
            }
        }
        None
    }
}
