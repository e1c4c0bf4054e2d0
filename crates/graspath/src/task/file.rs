//! The task-file schema (YAML or JSON; one schema, documented in `docs/task-file.md`).
//!
//! Every struct rejects unknown fields; errors name the file and the field's path
//! (`trajectory.steps[2].rotate.angle_deg`). Paths inside a task file are relative to it.

use super::error::TaskError;
pub(super) use super::file_scene::{CollisionFile, GripperFile, SceneFile, StrokeFile};
use super::settings::Limits;
use crate::cloud::OutlierOptions;
use crate::geometry::shape::Shape;
use crate::geometry::PoseSpec;
use nalgebra::Isometry3;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// A whole task file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TaskFile {
    /// The robot and its arm chains.
    pub robot: RobotFile,
    /// Which arms to use: one name, a list, or `both` (every arm the robot defines).
    #[serde(default)]
    pub arms: Option<ArmsFile>,
    /// The object's initial pose and shape.
    pub object: ObjectFile,
    /// Where the grasp candidates come from.
    pub candidates: CandidatesFile,
    /// The object trajectory after the grasp.
    pub trajectory: TrajectoryFile,
    /// How the task-relevant index is computed.
    #[serde(default)]
    pub index: IndexFile,
    /// How candidates are ranked.
    #[serde(default)]
    pub selection: SelectionFile,
    /// Trajectory IK settings.
    #[serde(default)]
    pub ik: IkFile,
    /// Bounds on the work the task may ask for (default: [`Limits::default`]).
    #[serde(default)]
    pub limits: Option<Limits>,
    /// The table and obstacles (world frame). Without it nothing is checked for collisions.
    #[serde(default)]
    pub scene: Option<SceneFile>,
    /// Collision settings (used with a scene).
    #[serde(default)]
    pub collision: Option<CollisionFile>,
    /// The tool's straight approach to the grasp.
    #[serde(default)]
    pub approach: Option<StrokeFile>,
    /// The tool's straight retreat after the place.
    #[serde(default)]
    pub retreat: Option<StrokeFile>,
    /// The gripper's opening and fingers.
    #[serde(default)]
    pub gripper: Option<GripperFile>,
    /// How each feasible candidate's motion is timed.
    #[serde(default)]
    pub timing: Option<TimingFile>,
}

/// One arm name, a list of names, or `both`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum ArmsFile {
    /// A single arm name, or `both`.
    One(String),
    /// Several arm names.
    Many(Vec<String>),
}

/// The robot: `builtin: baxter`, or `urdf:`, `mjcf:` or `file:` with one chain per arm.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RobotFile {
    /// A built-in robot (`baxter`, arms `left` and `right`).
    #[serde(default)]
    pub builtin: Option<String>,
    /// A URDF file (relative to the task file).
    #[serde(default)]
    pub urdf: Option<PathBuf>,
    /// A MuJoCo MJCF file (relative to the task file); chains name bodies as links.
    #[serde(default)]
    pub mjcf: Option<PathBuf>,
    /// A URDF, xacro or MJCF file (relative to the task file), its format told by its name or
    /// its root element ([`crate::robot::RobotSource::from_path`]).
    #[serde(default)]
    pub file: Option<PathBuf>,
    /// Folders (relative to the task file) where a URDF's `package://PKG` mesh URIs and a
    /// xacro file's `$(find PKG)` look first.
    #[serde(default)]
    pub search_paths: Vec<PathBuf>,
    /// xacro arguments for a `urdf: FILE.xacro` (`{dof: 7}`; numbers and booleans are passed
    /// as written).
    #[serde(default)]
    pub xacro_args: BTreeMap<String, XacroArgument>,
    /// Arm chains by name (required with `urdf`, `mjcf` or `file`; with `builtin` they may add a tool or base pose).
    #[serde(default)]
    pub chains: BTreeMap<String, ArmFile>,
    /// A tool offset `tip_from_tool` applied to every arm that does not set its own.
    #[serde(default)]
    pub tool: Option<PoseSpec>,
    /// Narrower joint ranges by joint name, `[lower, upper]` in rad (m for a prismatic
    /// joint), for every arm whose chain has the joint: `{elbow_joint: [-3.1416, 3.1416]}`.
    /// Each must lie inside the robot's own range (a task narrows, never widens); a continuous
    /// joint given a range becomes a revolute one.
    #[serde(default)]
    pub joint_limits: BTreeMap<String, [f64; 2]>,
}

/// A xacro argument's value as a task file writes it: text, a number or a boolean.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum XacroArgument {
    /// A boolean, passed as `true` / `false`.
    Bool(bool),
    /// An integer, passed in decimal.
    Integer(i64),
    /// A number, passed in Rust's shortest round-trip form.
    Number(f64),
    /// Text, passed as it is.
    Text(String),
}

impl XacroArgument {
    /// The text passed to `xacro` as `NAME:=TEXT`.
    pub fn text(&self) -> String {
        match self {
            XacroArgument::Bool(b) => b.to_string(),
            XacroArgument::Integer(i) => i.to_string(),
            XacroArgument::Number(x) => x.to_string(),
            XacroArgument::Text(t) => t.clone(),
        }
    }
}

/// One arm chain.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ArmFile {
    /// The chain's base link (required for URDF robots).
    #[serde(default)]
    pub base: Option<String>,
    /// The chain's tip link (required for URDF robots).
    #[serde(default)]
    pub tip: Option<String>,
    /// A tool offset `tip_from_tool`.
    #[serde(default)]
    pub tool: Option<PoseSpec>,
    /// Where the chain's base is in the task's world frame, `world_from_base` (default identity).
    #[serde(default)]
    pub base_pose: Option<PoseSpec>,
}

/// The object.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ObjectFile {
    /// The initial pose `world_from_object`.
    pub pose: PoseSpec,
    /// A primitive shape (for candidate families, views and demos).
    #[serde(default)]
    pub shape: Option<Shape>,
    /// The object's mass (kg): the arm then carries it, and the joint torques along the task
    /// are checked against the arm's effort limits (`docs/dynamics.md`). Not with `density`.
    #[serde(default)]
    pub mass: Option<f64>,
    /// The object's density (kg/m³): its mass is the density times the shape's volume.
    #[serde(default)]
    pub density: Option<f64>,
    /// The object's centre of mass, object frame (m); default: the shape's centroid. Needed
    /// with `mass` when the object has no shape.
    #[serde(default)]
    pub center_of_mass: Option<[f64; 3]>,
}

/// Where candidates come from: exactly one of `file`, `family` or `generate`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CandidatesFile {
    /// A candidate file, relative to the task file: graspath JSON or CSV, or a grasp
    /// generator's file (`docs/grasp-files.md`).
    #[serde(default)]
    pub file: Option<PathBuf>,
    /// The file's layout (`graspath`, `graspgen`, `acronym`, `contact_graspnet`, `m2t2`,
    /// `poses`, `graspnet`, `anygrasp`); default: guessed from the content.
    #[serde(default)]
    pub format: Option<String>,
    /// The frame of the file's poses: `object`, `world` or `camera` (default: the format's,
    /// `camera` for Contact-GraspNet and GraspNet / AnyGrasp, `world` for M2T2, else `object`).
    #[serde(default)]
    pub frame: Option<String>,
    /// With `frame: camera`: the camera in the world, `world_from_camera`.
    #[serde(default)]
    pub world_from_camera: Option<PoseSpec>,
    /// With `frame: camera`, instead of `world_from_camera`: `camera_from_object`.
    #[serde(default)]
    pub camera_from_object: Option<PoseSpec>,
    /// The tool frame in the generator's gripper frame, `gripper_from_tool` (default: the
    /// format's documented convention).
    #[serde(default)]
    pub gripper_from_tool: Option<PoseSpec>,
    /// Contact-GraspNet / M2T2: read only this segment, by id or by an object's position in a
    /// per-object list (default: all).
    #[serde(default)]
    pub segment: Option<i64>,
    /// A parametric family on the object's shape.
    #[serde(default)]
    pub family: Option<FamilyFile>,
    /// Candidates generated by a trained grasp model on the object's cloud.
    #[serde(default)]
    pub generate: Option<GenerateFile>,
}

/// Grasp generation from a trained model (`graspath train`) on a cloud in the object frame.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GenerateFile {
    /// The model file, relative to the task file.
    pub model: PathBuf,
    /// The object's cloud (`.ply`, `.pcd`, or a `.json` cloud source), object frame.
    pub cloud: PathBuf,
    /// Random seed of the generation (default 0).
    #[serde(default)]
    pub seed: Option<u64>,
    /// Number of initial grasps drawn before annealing (the model spec's "seeds"; default
    /// 50,000).
    #[serde(default)]
    pub initial_grasps: Option<usize>,
    /// Annealing steps (default 500).
    #[serde(default)]
    pub steps: Option<usize>,
    /// Query kernels per link (default 5,000).
    #[serde(default)]
    pub query_kernels: Option<usize>,
    /// Keep at most this many candidates, best first (default: all).
    #[serde(default)]
    pub max_candidates: Option<usize>,
    /// Outlier handling for clouds from real sensors (crop box, max range, statistical
    /// outlier removal; `docs/clouds.md`). Default: only non-finite points are skipped.
    #[serde(default)]
    pub outliers: Option<OutlierOptions>,
}

/// Parametric candidate families.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum FamilyFile {
    /// Top grasps along the box's top edge, from the left-most (+y) to the right-most (−y)
    /// contact, the gripper approaching from above (the paper's §IV-A).
    Edge {
        /// Number of candidates (≥ 1).
        count: usize,
        /// How far below the top face the tool point sits (m, default 0.02).
        #[serde(default)]
        depth: Option<f64>,
        /// Distance kept from each end of the edge (m, default 0.02).
        #[serde(default)]
        margin: Option<f64>,
    },
    /// One top grasp rotated about the object's z axis in fixed steps (the paper's §IV-B:
    /// 16 candidates 10° apart).
    Yaw {
        /// Number of candidates.
        count: usize,
        /// Step between candidates (degrees).
        step_deg: f64,
        /// Yaw of the first candidate (degrees, default 0).
        #[serde(default)]
        start_deg: Option<f64>,
        /// How far below the top the tool point sits (m, default 0.02).
        #[serde(default)]
        depth: Option<f64>,
    },
    /// Approaches over the box's faces: a grid on each face, approach along the inward normal,
    /// fingers closing across the narrower side.
    Faces {
        /// Total number of candidates (shared among the faces by area).
        count: usize,
        /// Faces to leave out: any of `top`, `bottom`, `left`, `right`, `front`, `back`.
        #[serde(default)]
        exclude: Vec<String>,
        /// How far inside the face the tool point sits (m, default 0.02).
        #[serde(default)]
        depth: Option<f64>,
    },
}

/// The object trajectory.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TrajectoryFile {
    /// The steps after the grasp, in order.
    pub steps: Vec<StepFile>,
    /// Samples per step (default 10 when no other sampling is given).
    #[serde(default)]
    pub samples_per_step: Option<usize>,
    /// Total samples over the path (initial pose included), shared by step length.
    #[serde(default)]
    pub samples: Option<usize>,
    /// Maximum spacing between samples.
    #[serde(default)]
    pub spacing: Option<SpacingFile>,
}

/// Sample spacing.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SpacingFile {
    /// Largest translation between samples (m).
    pub translation: f64,
    /// Largest rotation between samples (degrees).
    pub rotation_deg: f64,
}

/// One step: relative motions (`lift`, `place`, `move`, `rotate`, combinable) or an absolute
/// `pose`, with an optional duration (s, default 1) and label.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StepFile {
    /// Raise along world +z (m).
    #[serde(default)]
    pub lift: Option<f64>,
    /// Lower along world −z (m).
    #[serde(default)]
    pub place: Option<f64>,
    /// Translate by a world-frame vector (m).
    #[serde(default, rename = "move")]
    pub translate: Option<[f64; 3]>,
    /// Rotate about a world-frame axis through the object's origin.
    #[serde(default)]
    pub rotate: Option<RotateFile>,
    /// Go to an absolute object pose `world_from_object`.
    #[serde(default)]
    pub pose: Option<PoseSpec>,
    /// Duration (s).
    #[serde(default)]
    pub duration: Option<f64>,
    /// A name for reports.
    #[serde(default)]
    pub label: Option<String>,
}

/// A rotation about a world-frame axis.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RotateFile {
    /// The axis (normalised on reading; default `[0, 0, 1]`).
    #[serde(default)]
    pub axis: Option<[f64; 3]>,
    /// The angle (degrees, right-handed).
    pub angle_deg: f64,
}

/// How the task-relevant index is computed.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct IndexFile {
    /// `twist` (default), `translation` or `rotation`.
    #[serde(default)]
    pub mode: Option<String>,
    /// The characteristic length L (m) of `twist` mode (default 1, the paper's raw J).
    #[serde(default)]
    pub length_scale: Option<f64>,
    /// What is measured and ranked: `task_relevant` (default, the paper's `M_T`),
    /// `velocity_ratio`, `duration` or `dynamic` ([`IndexMeasure`](crate::manipulability::IndexMeasure)).
    #[serde(default)]
    pub measure: Option<String>,
    /// Multiply the ranked index by Tsai's joint-limit penalty: `true` (gain 50) or the gain.
    #[serde(default)]
    pub joint_limit_penalty: Option<PenaltyFile>,
    /// Which samples the norms are taken over: `samples` (default) or `waypoints` (the
    /// initial pose and each step's end, the paper's reading).
    #[serde(default)]
    pub over: Option<String>,
}

/// `index.joint_limit_penalty`: on with the default gain, off, or a gain.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum PenaltyFile {
    /// `true`: the default gain; `false`: no penalty.
    On(bool),
    /// The gain `k`.
    Gain(f64),
}

/// How the grasp likelihood enters the ranking.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum LikelihoodFile {
    /// Score = norm × likelihood (likelihoods scaled so the best is 1). With equal likelihoods
    /// this is the paper's rule.
    #[default]
    Product,
    /// Ignore the likelihood.
    Ignore,
    /// Score = ln(norm) + weight · ln(likelihood).
    Weighted {
        /// The likelihood's weight (≥ 0).
        weight: f64,
    },
}

/// How candidates are ranked.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SelectionFile {
    /// The norm to maximise: `rms` (default, the root mean square over the path's time),
    /// `l2` (the paper's choice) or `l1` (the time integral).
    #[serde(default)]
    pub norm: Option<String>,
    /// Reject candidates whose `μ_l∞` exceeds this (default: no limit).
    #[serde(default)]
    pub mu0: Option<f64>,
    /// How the likelihood combines with the norm.
    #[serde(default)]
    pub likelihood: Option<LikelihoodFile>,
    /// How many best arm pairs to keep (default 10).
    #[serde(default)]
    pub pairs: Option<usize>,
    /// Two grasps closer than this (m) overlap (default 0.08, Baxter's gripper width).
    #[serde(default)]
    pub min_separation: Option<f64>,
    /// Reject candidates whose clearance from the scene is below this (m; default none).
    #[serde(default)]
    pub min_clearance: Option<f64>,
    /// With the object's mass: reject candidates whose torque margin along the motion is below
    /// this (the worst `1 − |τ|/τ_max` over samples and joints; default none).
    #[serde(default)]
    pub min_torque_margin: Option<f64>,
    /// Reject candidates whose timed motion takes longer than this (s; default none).
    #[serde(default)]
    pub max_duration: Option<f64>,
    /// Scores within this relative difference are reported as tied (default 1e-4).
    #[serde(default)]
    pub tie_tolerance: Option<f64>,
}

/// How each feasible candidate's motion is timed (`timing:`); `timing: false` turns timing
/// off, `timing: true` or a map turns it on (an error for an arm without velocity limits).
/// Without the key, motions are timed when every joint has a velocity limit.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum TimingFile {
    /// `true` (on, defaults) or `false` (off).
    Switch(bool),
    /// On, with these settings.
    Settings(TimingSettingsFile),
}

/// The `timing:` settings; each absent one takes its default.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TimingSettingsFile {
    /// Stop at the grasp and the place (default true) or time one motion through.
    #[serde(default)]
    pub stops: Option<bool>,
    /// Grid intervals per interval between IK samples (default 2).
    #[serde(default)]
    pub subdivisions: Option<usize>,
    /// Fraction of the velocity limits used (default 1).
    #[serde(default)]
    pub velocity_scale: Option<f64>,
    /// Fraction of the acceleration limits used (default 1).
    #[serde(default)]
    pub acceleration_scale: Option<f64>,
    /// Acceleration limit of joints whose robot gives none (rad/s² or m/s²; default none).
    #[serde(default)]
    pub max_acceleration: Option<f64>,
    /// Otherwise their limit is the velocity limit over this time to full speed (s; default
    /// 0.5).
    #[serde(default)]
    pub acceleration_time: Option<f64>,
    /// Whether the torque limits bind with the object's mass (default true).
    #[serde(default)]
    pub torque_limits: Option<bool>,
    /// The largest linear speed of the carried object (m/s; default none).
    #[serde(default)]
    pub object_speed: Option<f64>,
    /// The largest angular speed of the carried object (rad/s; default none).
    #[serde(default)]
    pub object_turn_rate: Option<f64>,
    /// The largest linear acceleration of the carried object (m/s²; default none).
    #[serde(default)]
    pub object_acceleration: Option<f64>,
    /// The largest angular acceleration of the carried object (rad/s²; default none).
    #[serde(default)]
    pub object_angular_acceleration: Option<f64>,
}

/// Trajectory IK settings.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct IkFile {
    /// Largest joint motion between consecutive samples (rad or m; default 0.5).
    #[serde(default)]
    pub max_joint_step: Option<f64>,
    /// How far inside its limits the IK keeps every revolute joint (rad; default 0.1; 0 plans
    /// up to the limits, as the paper does).
    #[serde(default)]
    pub limit_margin: Option<f64>,
    /// Distinct IK branches tracked from the grasp pose (default 4).
    #[serde(default)]
    pub branches: Option<usize>,
    /// Random seed of the IK's random restarts (default 0).
    #[serde(default)]
    pub random_seed: Option<u64>,
    /// Position and rotation tolerance (m, rad; default 1e-5).
    #[serde(default)]
    pub tolerance: Option<f64>,
    /// Iteration budget for the grasp sample, over all restarts (default 200): what an
    /// unreachable candidate costs before it is given up.
    #[serde(default)]
    pub iterations: Option<usize>,
    /// `first`, `best_branch` or `optimize` (default `optimize`).
    #[serde(default)]
    pub redundancy: Option<String>,
}

/// A pose from its file form; `field` names it in errors.
pub fn pose(spec: &PoseSpec, file: &str, field: &str) -> Result<Isometry3<f64>, TaskError> {
    spec.to_isometry()
        .map_err(|e| TaskError::new(file, format!("{field}.{}", e.field), e.message))
}

impl TaskFile {
    /// Reads a task file: YAML for `.yaml`/`.yml`, JSON for `.json` (others: JSON, then YAML).
    pub fn load(path: &Path) -> Result<Self, TaskError> {
        let name = path.display().to_string();
        let text = crate::input::read_to_string(path, crate::input::MAX_TASK_FILE_BYTES)
            .map_err(|e| TaskError::with_source(&name, "", "cannot read", e))?;
        let extension = path.extension().and_then(|e| e.to_str()).unwrap_or("");
        Self::parse(&text, &name, extension)
    }

    /// Every file and folder the task reads, as written (relative to the task file's folder):
    /// the robot, its search paths, the candidate file or the model and cloud, the scene's
    /// meshes and clouds, the SRDF, the hand's URDF. Outputs must never replace them.
    pub fn input_paths(&self) -> Vec<&Path> {
        let robot = &self.robot;
        let candidates = &self.candidates;
        let mut out: Vec<&Path> = [&robot.urdf, &robot.mjcf, &candidates.file]
            .into_iter()
            .flatten()
            .map(PathBuf::as_path)
            .collect();
        out.extend(robot.search_paths.iter().map(PathBuf::as_path));
        if let Some(generate) = &candidates.generate {
            out.extend([generate.model.as_path(), generate.cloud.as_path()]);
        }
        if let Some(scene) = &self.scene {
            for obstacle in &scene.obstacles {
                out.extend(
                    obstacle
                        .mesh
                        .iter()
                        .chain(&obstacle.cloud)
                        .map(PathBuf::as_path),
                );
            }
        }
        if let Some(collision) = &self.collision {
            out.extend(collision.srdf.as_deref());
        }
        if let Some(gripper) = &self.gripper {
            out.extend(gripper.urdf.as_deref());
        }
        out
    }

    /// Parses task text; `format` is `yaml`, `yml` or `json` (anything else: JSON, then YAML).
    pub fn parse(text: &str, file: &str, format: &str) -> Result<Self, TaskError> {
        let value: serde_json::Value = match format {
            "yaml" | "yml" => yaml_value(text, file)?,
            "json" => serde_json::from_str(text)
                .map_err(|e| TaskError::new(file, "", format!("not valid JSON: {e}")))?,
            _ => match serde_json::from_str(text) {
                Ok(v) => v,
                Err(_) => yaml_value(text, file)?,
            },
        };
        serde_path_to_error::deserialize(value).map_err(|e| {
            let field = e.path().to_string();
            TaskError::new(
                file,
                field,
                crate::input::plain_serde_message(&e.into_inner().to_string()),
            )
        })
    }
}

fn yaml_value(text: &str, file: &str) -> Result<serde_json::Value, TaskError> {
    serde_saphyr::from_str(text)
        .map_err(|e| TaskError::new(file, "", format!("not valid YAML: {e}")))
}

#[cfg(test)]
mod tests {
    use super::*;

    const MINIMAL: &str = r#"
robot: { builtin: baxter }
object: { pose: { xyz: [0.7, 0.25, -0.05] }, shape: { box: { size: [0.06, 0.2, 0.06] } } }
candidates: { family: { edge: { count: 11 } } }
trajectory:
  samples: 20
  steps:
    - { lift: 0.2 }
    - { move: [0, 0.3, 0], rotate: { angle_deg: 90 } }
    - { place: 0.2, duration: 2 }
"#;

    #[test]
    fn minimal_yaml_parses() {
        let task = TaskFile::parse(MINIMAL, "t.yaml", "yaml").unwrap();
        assert_eq!(task.trajectory.steps.len(), 3);
        assert_eq!(
            task.trajectory.steps[1].rotate.as_ref().unwrap().angle_deg,
            90.0
        );
        assert_eq!(
            task.candidates.family,
            Some(FamilyFile::Edge {
                count: 11,
                depth: None,
                margin: None
            })
        );
    }

    #[test]
    fn unknown_field_is_named_with_its_path() {
        let text = MINIMAL.replace("{ lift: 0.2 }", "{ lift: 0.2, lfit: 1 }");
        let err = TaskFile::parse(&text, "t.yaml", "yaml").unwrap_err();
        assert_eq!(err.field, "trajectory.steps[0].lfit");
        assert!(err.message.contains("unknown field `lfit`"), "{err}");
        assert!(
            err.to_string()
                .starts_with("t.yaml: field 'trajectory.steps[0].lfit'"),
            "{err}"
        );
    }

    #[test]
    fn wrong_shape_of_a_value_is_named() {
        let text = MINIMAL.replace("xyz: [0.7, 0.25, -0.05]", "xyz: [0.7, 0.25]");
        let err = TaskFile::parse(&text, "t.yaml", "yaml").unwrap_err();
        assert_eq!(err.field, "object.pose.xyz");
    }

    #[test]
    fn json_and_yaml_agree() {
        let yaml = TaskFile::parse(MINIMAL, "t.yaml", "yaml").unwrap();
        let json = serde_json::to_string(&yaml).unwrap();
        let back = TaskFile::parse(&json, "t.json", "json").unwrap();
        assert_eq!(yaml, back);
    }
}
