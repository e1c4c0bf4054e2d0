//! The task file's world: `scene` (table and obstacles), `collision`, the tool's `approach`
//! and `retreat` strokes and the `gripper` (world frame; m, rad).

use crate::geometry::PoseSpec;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::PathBuf;

/// The scene: `table` and `obstacles`, world frame.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneFile {
    /// The table: its top at `height`; infinite unless `size` is given.
    #[serde(default)]
    pub table: Option<TableFile>,
    /// Obstacles, each one of `box`, `cylinder`, `sphere`, `capsule`, `mesh` or `cloud`.
    #[serde(default)]
    pub obstacles: Vec<ObstacleFile>,
}

/// The table.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TableFile {
    /// World `z` of the top surface (m).
    pub height: f64,
    /// Footprint `[x, y]` (m); default: infinite.
    #[serde(default)]
    pub size: Option<[f64; 2]>,
    /// Footprint centre `[x, y]` (m; default `[0, 0]`).
    #[serde(default)]
    pub centre: Option<[f64; 2]>,
    /// Slab thickness below the top (m; default 0.05), with a footprint.
    #[serde(default)]
    pub thickness: Option<f64>,
}

/// One obstacle: a name, exactly one geometry, and a pose (default identity).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ObstacleFile {
    /// A name for messages (default `obstacles[i]`).
    #[serde(default)]
    pub name: Option<String>,
    /// A box.
    #[serde(default, rename = "box")]
    pub cuboid: Option<crate::geometry::shape::Cuboid>,
    /// A cylinder along its `z`.
    #[serde(default)]
    pub cylinder: Option<crate::geometry::shape::Cylinder>,
    /// A sphere.
    #[serde(default)]
    pub sphere: Option<crate::geometry::shape::Sphere>,
    /// A capsule along its `z`.
    #[serde(default)]
    pub capsule: Option<crate::geometry::shape::Capsule>,
    /// A mesh file (STL or OBJ, metres), relative to the task file: a surface.
    #[serde(default)]
    pub mesh: Option<PathBuf>,
    /// A point cloud file (PLY, PCD or JSON), relative to the task file: each point a sphere
    /// of `radius`.
    #[serde(default)]
    pub cloud: Option<PathBuf>,
    /// The spheres' radius for a `cloud` (m).
    #[serde(default)]
    pub radius: Option<f64>,
    /// `world_from_obstacle`.
    #[serde(default)]
    pub pose: Option<PoseSpec>,
}

/// Collision settings.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CollisionFile {
    /// Clearance kept from the scene (m; default 0.01).
    #[serde(default)]
    pub margin: Option<f64>,
    /// Self-collision checks (default true).
    #[serde(default, rename = "self")]
    pub self_collision: Option<bool>,
    /// Arm-against-arm checks (default true).
    #[serde(default)]
    pub between_arms: Option<bool>,
    /// How deep an allowed contact may press (m; default 0.001).
    #[serde(default)]
    pub touch_tolerance: Option<f64>,
    /// The continuous check's resolution (m; default 0.0001).
    #[serde(default)]
    pub resolution: Option<f64>,
    /// Self-collision pairs: `sampled` (default) or `all`.
    #[serde(default)]
    pub self_pairs: Option<String>,
    /// Link pairs never checked against each other (as SRDF `disable_collisions`).
    #[serde(default)]
    pub disable: Vec<[String; 2]>,
    /// An SRDF file (relative to the task file) whose `disable_collisions` pairs are added.
    #[serde(default)]
    pub srdf: Option<PathBuf>,
}

/// An approach or retreat.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StrokeFile {
    /// Length of the stroke (m).
    pub distance: f64,
    /// Samples besides the grasp or place pose (default 5).
    #[serde(default)]
    pub samples: Option<usize>,
    /// The approach axis in the tool frame (default `[0, 0, 1]`).
    #[serde(default)]
    pub axis: Option<[f64; 3]>,
}

/// The gripper: `builtin: baxter`, an `opening` with optional finger and palm sizes, or a URDF
/// hand (`urdf`, `root`, `tool_from_root`, `fingers`, `open`).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GripperFile {
    /// A built-in gripper (`baxter`).
    #[serde(default)]
    pub builtin: Option<String>,
    /// Largest gap between the fingers (m).
    #[serde(default)]
    pub opening: Option<f64>,
    /// Finger `[length, width, thickness]` (m; default `[0.05, 0.02, 0.01]`).
    #[serde(default)]
    pub finger: Option<[f64; 3]>,
    /// Palm box `[x, y, z]` behind the finger roots (m).
    #[serde(default)]
    pub palm: Option<[f64; 3]>,
    /// A hand described in a URDF (relative to the task file); with `root` alone, the robot's
    /// own URDF.
    #[serde(default)]
    pub urdf: Option<PathBuf>,
    /// The hand's root link (its frame is the hand's frame).
    #[serde(default)]
    pub root: Option<String>,
    /// Where the hand's root link sits in the tool frame (default: identity).
    #[serde(default)]
    pub tool_from_root: Option<PoseSpec>,
    /// The finger links (default: every link moved by a hand joint).
    #[serde(default)]
    pub fingers: Option<Vec<String>>,
    /// The open hand's joint values by joint name (rad / m; default: each at its upper limit).
    #[serde(default)]
    pub open: Option<BTreeMap<String, f64>>,
}
