//! Training from one demonstration: the demonstration file, and the model it yields.
//!
//! A demonstration file (JSON):
//!
//! ```text
//! {
//!   "format": "graspath-demonstration", "version": 1,
//!   "label": "pinch",                                       optional
//!   "hand": "baxter_electric_gripper"
//!         | {"urdf": "hand.urdf", "root": "palm", "wrist": "tcp", "search_paths": ["ros"]},
//!   "cloud": {"file": "object.pcd"}
//!          | {"primitive": {"shape": {"box": {"size": [0.05, 0.08, 0.12]}}, "points": 5000, "seed": 1}}
//!          | {"mesh": {"path": "object.stl", "points": 5000}},
//!   "features": { ... },                                    optional FeatureParams
//!   "parameters": { ... },                                  optional ModelParams
//!   "waypoints": [                                          pre-grasp first, grasp last
//!     {"object_from_wrist": [[4×4 row-major]], "hand_joints": [0.07]},
//!     {"object_from_wrist": [[...]], "hand_joints": [0.05]}
//!   ]
//! }
//! ```
//! Paths are relative to the demonstration file; poses are in the cloud's object frame (m).
//! `docs/demonstrations.md` documents every field.

use super::configuration::ConfigurationSpec;
use super::contact::train_contacts;
use super::file::{
    ApproachWaypoint, DemonstratedGrasp, GraspModel, MODEL_FORMAT, MODEL_FORMAT_VERSION,
};
use super::{ModelError, ModelParams};
use crate::cloud::{compute_features, CloudSource, FeatureParams, PointCloud};
use crate::geometry::pose_to_rows;
use crate::grasp::hand::{
    baxter_electric_gripper, hand_from_robot, hand_from_robot_with_wrist, Hand, BAXTER_GRIPPER_NAME,
};
use crate::robot::RobotSource;
use nalgebra::Isometry3;
use std::path::{Path, PathBuf};

/// The `format` string of demonstration files.
pub const DEMONSTRATION_FORMAT: &str = "graspath-demonstration";

/// Which hand a demonstration uses.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(untagged)]
pub enum HandSource {
    /// A built-in hand by name (`baxter_electric_gripper`).
    Builtin(String),
    /// A URDF hand: the file, the link whose subtree is the hand and, optionally, the link
    /// whose frame is the wrist frame (default: the root's).
    Urdf {
        /// The URDF file (relative to the demonstration file).
        urdf: PathBuf,
        /// The root link: it and every link below it are the hand.
        root: String,
        /// The wrist frame: a link fixed below the root (the Panda's `panda_hand_tcp`); the
        /// demonstration's and the generated `object_from_wrist` are in its frame. Default:
        /// the root link's frame.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        wrist: Option<String>,
        /// Folders tried first for `package://` and `model://` mesh URIs (relative to the
        /// demonstration file), before `ROS_PACKAGE_PATH`, `AMENT_PREFIX_PATH` and the URDF's
        /// own ancestors.
        #[serde(default, skip_serializing_if = "Vec::is_empty")]
        search_paths: Vec<PathBuf>,
    },
}

impl HandSource {
    /// Loads the hand; relative paths from `base_dir`.
    pub fn load(&self, base_dir: &Path, source_name: &str) -> Result<Hand, ModelError> {
        match self {
            HandSource::Builtin(name) if name == BAXTER_GRIPPER_NAME => Ok(baxter_electric_gripper()),
            HandSource::Builtin(other) => Err(ModelError::field(
                source_name,
                "hand",
                format!("unknown built-in hand '{other}' (built in: {BAXTER_GRIPPER_NAME}; or give {{\"urdf\": FILE, \"root\": LINK}})"),
            )),
            HandSource::Urdf {
                urdf,
                root,
                wrist,
                search_paths,
            } => {
                let model = RobotSource::Urdf {
                    path: base_dir.join(urdf),
                    search_paths: search_paths.iter().map(|p| base_dir.join(p)).collect(),
                    xacro_args: Default::default(),
                }
                .load()
                .map_err(crate::grasp::hand::HandError::from)?;
                Ok(match wrist {
                    Some(wrist) => hand_from_robot_with_wrist(&model, root, wrist)?,
                    None => hand_from_robot(&model, root)?,
                })
            }
        }
    }
}

/// One demonstrated waypoint.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DemoWaypoint {
    /// The wrist pose in the object frame, 4×4 row-major (m).
    pub object_from_wrist: [[f64; 4]; 4],
    /// The hand joints (rad or m).
    pub hand_joints: Vec<f64>,
}

/// A demonstration file's content.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Demonstration {
    /// Always [`DEMONSTRATION_FORMAT`].
    pub format: String,
    /// Always 1.
    pub version: u32,
    /// The grasp type's name.
    #[serde(default = "default_label")]
    pub label: String,
    /// The hand.
    pub hand: HandSource,
    /// The object cloud.
    pub cloud: CloudSource,
    /// Feature options (defaults when absent).
    #[serde(default)]
    pub features: Option<FeatureParams>,
    /// Model constants (defaults for the hand when absent).
    #[serde(default)]
    pub parameters: Option<ModelParams>,
    /// Pre-grasp first, grasp last.
    pub waypoints: Vec<DemoWaypoint>,
}

fn default_label() -> String {
    "grasp".into()
}

impl Demonstration {
    /// Reads and checks a demonstration file.
    pub fn read(path: &Path) -> Result<Self, ModelError> {
        let name = path.display().to_string();
        let text = ModelError::read_text(path)?;
        let mut json = serde_json::Deserializer::from_str(&text);
        let demo: Demonstration = serde_path_to_error::deserialize(&mut json).map_err(|e| {
            let path = e.path().to_string();
            let inner = e.into_inner();
            let field = if path.is_empty() || path == "." {
                format!("line {}", inner.line())
            } else {
                path
            };
            ModelError::field(
                &name,
                field,
                crate::input::plain_serde_message(&inner.to_string()),
            )
        })?;
        if demo.format != DEMONSTRATION_FORMAT {
            return Err(ModelError::field(
                &name,
                "format",
                format!("expected \"{DEMONSTRATION_FORMAT}\""),
            ));
        }
        if demo.version != 1 {
            return Err(ModelError::Version {
                source_name: name,
                found: demo.version.to_string(),
                expected: 1,
            });
        }
        Ok(demo)
    }
}

/// Trains from a demonstration file: loads its hand and cloud, then [`train`].
pub fn train_file(path: &Path) -> Result<GraspModel, ModelError> {
    let name = path.display().to_string();
    let demo = Demonstration::read(path)?;
    let base = path.parent().unwrap_or(Path::new("."));
    let hand = demo.hand.load(base, &name)?;
    let cloud = demo
        .cloud
        .load(base)
        .map_err(|e| e.in_file(&name, "cloud."))?;
    train(&demo, hand, &cloud, &name)
}

/// Trains a model from a demonstration with its hand and cloud already loaded;
/// `source_name` names the demonstration in errors.
pub fn train(
    demo: &Demonstration,
    hand: Hand,
    cloud: &PointCloud,
    source_name: &str,
) -> Result<GraspModel, ModelError> {
    if demo.waypoints.is_empty() {
        return Err(ModelError::field(
            source_name,
            "waypoints",
            "needs at least the grasp waypoint",
        ));
    }
    let mut wrists = Vec::new();
    for (k, w) in demo.waypoints.iter().enumerate() {
        // The 4×4 form of the one pose syntax, read by the one pose parser.
        let spec = crate::geometry::PoseSpec {
            matrix: Some(w.object_from_wrist),
            ..Default::default()
        };
        let pose = spec.to_isometry().map_err(|e| {
            ModelError::field(
                source_name,
                format!("waypoints[{k}].object_from_wrist"),
                e.message,
            )
        })?;
        if w.hand_joints.len() != hand.dof() {
            return Err(ModelError::field(
                source_name,
                format!("waypoints[{k}].hand_joints"),
                format!(
                    "has {} values, the hand '{}' has {} joints ({})",
                    w.hand_joints.len(),
                    hand.name,
                    hand.dof(),
                    hand.joints
                        .iter()
                        .map(|j| j.name.as_str())
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            ));
        }
        for (j, (v, joint)) in w.hand_joints.iter().zip(&hand.joints).enumerate() {
            if !v.is_finite() || *v < joint.lower - 1e-9 || *v > joint.upper + 1e-9 {
                return Err(ModelError::field(
                    source_name,
                    format!("waypoints[{k}].hand_joints[{j}]"),
                    format!(
                        "{v} is outside the limits [{}, {}] of joint '{}'",
                        joint.lower, joint.upper, joint.name
                    ),
                ));
            }
        }
        wrists.push(pose);
    }
    let params = demo
        .parameters
        .clone()
        .unwrap_or_else(|| ModelParams::for_hand(&hand));
    params.check(source_name)?;
    let feature_params = demo.features.unwrap_or_default();
    let features = compute_features(cloud, &feature_params, source_name)
        .map_err(|e| e.in_file(source_name, "features."))?;
    let grasp_index = demo.waypoints.len() - 1;
    let grasp_wrist = wrists[grasp_index];
    let grasp_joints = &demo.waypoints[grasp_index].hand_joints;
    let (contacts, clearances) =
        train_contacts(&hand, &features, &grasp_wrist, grasp_joints, &params);
    if contacts.is_empty() {
        return Err(ModelError::NoContact {
            source_name: source_name.to_string(),
            links: clearances,
            threshold_mm: params.contact_distance * 1000.0,
            min_points: params.min_points,
        });
    }
    let configuration = ConfigurationSpec {
        path: demo
            .waypoints
            .iter()
            .rev()
            .map(|w| w.hand_joints.clone())
            .collect(),
        sigma: hand.joints.iter().map(|j| j.sigma).collect(),
        beta: params.configuration_beta,
        kernels: params.configuration_kernels,
        cutoff: params.configuration_cutoff,
    };
    let grasp_from_object: Isometry3<f64> = grasp_wrist.inverse();
    let approach = demo
        .waypoints
        .iter()
        .zip(&wrists)
        .map(|(w, pose)| ApproachWaypoint {
            grasp_from_wrist: grasp_from_object * pose,
            hand_joints: w.hand_joints.clone(),
        })
        .collect();
    Ok(GraspModel {
        format: MODEL_FORMAT.to_string(),
        format_version: MODEL_FORMAT_VERSION,
        label: demo.label.clone(),
        hand,
        features: feature_params,
        parameters: params,
        contacts,
        configuration,
        approach,
        demonstration: DemonstratedGrasp {
            object_from_wrist: pose_to_rows(&grasp_wrist),
            hand_joints: grasp_joints.clone(),
        },
    })
}
