//! Collisions: the scene (a table and obstacles), the bodies of an arm and its hand, and the
//! checks of a whole motion — at every sample and, with a proven bound, between samples — with
//! its clearance.
//!
//! Frames: scene bodies are placed in the world frame; arm bodies ride on their link frames
//! (chain base frame, placed in the world by the arm's `world_from_base`); the hand rides on
//! the tool frame; the object is in the object frame, standing at its start pose before the
//! grasp, carried by the tool from the grasp to the place, and left at its final pose. All
//! lengths are metres.
//!
//! Exact distances come from parry3d-f64, behind one conversion boundary (`bridge`); the broad
//! phase (bounding spheres, then a few spheres covering each box, cylinder or capsule against
//! the other body's closed-form point distance), the half-space table and the continuous bound
//! are our own.

mod arm;
mod arms;
mod body;
mod bridge;
mod motion;
mod scene;

pub use arm::{ArmBodies, LinkShape, SelfPairs, ALWAYS_FRACTION, SELF_PAIR_SAMPLES};
pub use arms::{check_arms, ArmMotion};
pub use body::{Body, BodyKind, Table, MAX_OBSTACLE_POINTS};
pub use motion::{
    keeps_apart, ArmInScene, CollisionHit, CollisionOptions, MotionCheck, ObjectAlong, ToolMotion,
    WholeMotion,
};
pub use scene::{Obstacle, Scene, DEFAULT_TABLE_THICKNESS};

/// A scene, a body or an arm's collision model that cannot be built.
#[derive(Debug, thiserror::Error)]
pub enum CollisionError {
    /// A body's input is unusable.
    #[error("{what}: {message}")]
    BadBody {
        /// The input, e.g. `table.height` or `obstacles[2] (cloud scan.ply)`.
        what: String,
        /// What is wrong.
        message: String,
    },
    /// A link named in a collision setting is not a link of the robot.
    #[error("{context}: `{link}` is not a link of the robot")]
    UnknownLink {
        /// The link named.
        link: String,
        /// Where it was named.
        context: String,
    },
    /// The arm's chain refused a configuration while the collision model was built; the
    /// robot's error is the source.
    #[error("robot")]
    Robot(#[from] crate::robot::RobotError),
}

impl crate::fault::Classify for CollisionError {
    /// The robot's refusal has the robot error's kind; everything else is
    /// [`ErrorKind`](crate::fault::ErrorKind)`::Content`.
    fn kind(&self) -> Option<crate::fault::ErrorKind> {
        match self {
            Self::Robot(_) => None,
            _ => Some(crate::fault::ErrorKind::Content),
        }
    }

    fn field(&self) -> Option<&str> {
        match self {
            Self::BadBody { what, .. } => Some(what),
            _ => None,
        }
    }
}

/// The two bodies placed in one frame.
fn placed<'a>(
    a: &'a Body,
    frame_from_a: &nalgebra::Isometry3<f64>,
    b: &'a Body,
    frame_from_b: &nalgebra::Isometry3<f64>,
) -> (body::Placed<'a>, body::Placed<'a>) {
    (
        body::Placed::new(a, nalgebra::convert(*frame_from_a)),
        body::Placed::new(b, nalgebra::convert(*frame_from_b)),
    )
}

/// The signed distance (m) between two bodies at their poses (any common frame): positive
/// apart, negative by the penetration depth when they overlap (0 when the depth is unknown,
/// e.g. inside a mesh surface).
pub fn signed_distance(
    a: &Body,
    frame_from_a: &nalgebra::Isometry3<f64>,
    b: &Body,
    frame_from_b: &nalgebra::Isometry3<f64>,
) -> f64 {
    let (a, b) = placed(a, frame_from_a, b, frame_from_b);
    a.signed_distance(&b)
}

/// The distance (m) between two bodies at their poses; 0 when they touch or overlap.
pub fn distance(
    a: &Body,
    frame_from_a: &nalgebra::Isometry3<f64>,
    b: &Body,
    frame_from_b: &nalgebra::Isometry3<f64>,
) -> f64 {
    let (a, b) = placed(a, frame_from_a, b, frame_from_b);
    a.distance(&b)
}
