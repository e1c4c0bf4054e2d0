//! The one place that decides "built-in robot, URDF file or MJCF file": a [`RobotSource`] loads into a
//! [`RobotModel`], which gives chains (by name for built-in arms, by base and tip link for any
//! robot), its link names and its links' collision geometry.
//!
//! ```
//! use graspath::robot::RobotSource;
//! // A single-arm built-in robot has one chain, `arm`:
//! let panda = RobotSource::builtin("panda").load()?;
//! assert_eq!(panda.named_chain("arm", None)?.tip_link(), "panda_hand_tcp");
//! // From a task file's `robot: {builtin: baxter}` and `arms: left`:
//! let model = RobotSource::builtin("baxter").load()?;
//! let left = model.named_chain("left", None)?;
//! assert_eq!(left.dof(), 7);
//! // The same chain by its links.
//! assert_eq!(model.chain("base", "left_gripper", None)?.dof(), 7);
//! // A typo gets a suggestion.
//! let err = RobotSource::builtin("baxtor").load().unwrap_err();
//! assert!(err.to_string().contains("did you mean: baxter?"));
//! // A URDF file: `RobotSource::urdf("robot.urdf").load()?.chain("base_link", "tool0", None)?`;
//! // an MJCF file, by body names: `RobotSource::mjcf("ur5.xml").load()?.chain("base", "tool0", None)?`.
//! # Ok::<(), graspath::robot::RobotError>(())
//! ```

use super::builtin::{BuiltinRobot, BUILTIN_NAMES};
use super::chain::Chain;
use super::collision::{LinkCollisions, MeshResolver};
use super::error::closest_names;
use super::error::RobotError;
use super::mjcf::MjcfRobot;
use super::spec::ChainSpec;
use super::urdf::UrdfRobot;
use super::xacro::{is_xacro_path, XacroOptions};
use nalgebra::Isometry3;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// The built-in robots' names (see [`super::builtin`]).
pub const BUILTIN_ROBOTS: [&str; 10] = BUILTIN_NAMES;

/// Where a robot comes from.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum RobotSource {
    /// A built-in model by name (`baxter`, `panda`, `ur5e`, …: the robots of
    /// [`crate::robot::builtin`]).
    Builtin(String),
    /// A URDF file; `search_paths` are tried first when resolving `package://` and
    /// `model://` mesh URIs (then `ROS_PACKAGE_PATH`, `AMENT_PREFIX_PATH`, the file's folder).
    /// A file named `*.xacro` is expanded first (xacro runs code: only expand files you trust), with
    /// `xacro_args` and with `$(find PKG)` looked up in the same folders as `package://PKG`.
    Urdf {
        /// The URDF (or `*.xacro`) file.
        path: PathBuf,
        /// Extra folders for mesh and package lookup.
        search_paths: Vec<PathBuf>,
        /// xacro arguments (`NAME:=VALUE`); only for a `*.xacro` file.
        xacro_args: BTreeMap<String, String>,
    },
    /// A MuJoCo MJCF file (see [`MjcfRobot`]): links are its bodies; mesh files are relative
    /// to its `<compiler meshdir>`.
    Mjcf {
        /// The MJCF file.
        path: PathBuf,
    },
}

impl RobotSource {
    /// A built-in robot by name.
    pub fn builtin(name: impl Into<String>) -> Self {
        RobotSource::Builtin(name.into())
    }

    /// A URDF file without extra search paths.
    pub fn urdf(path: impl Into<PathBuf>) -> Self {
        RobotSource::Urdf {
            path: path.into(),
            search_paths: Vec::new(),
            xacro_args: BTreeMap::new(),
        }
    }

    /// An MJCF (MuJoCo XML) file.
    pub fn mjcf(path: impl Into<PathBuf>) -> Self {
        RobotSource::Mjcf { path: path.into() }
    }

    /// Loads the model: a built-in one is checked by name ("did you mean"), a URDF file is
    /// read and checked (see [`UrdfRobot`]; a `*.xacro` file is expanded first when the `xacro`
    /// program is installed), an MJCF file likewise (see [`MjcfRobot`]). Meshes are not read.
    pub fn load(&self) -> Result<RobotModel, RobotError> {
        match self {
            RobotSource::Builtin(name) => match BuiltinRobot::from_name(name) {
                Some(robot) => Ok(RobotModel {
                    source_name: robot.source_name(),
                    kind: Kind::Builtin(robot),
                }),
                None => Err(RobotError::UnknownRobot {
                    name: name.clone(),
                    known: BUILTIN_ROBOTS.iter().map(ToString::to_string).collect(),
                    suggestions: closest_names(name, BUILTIN_ROBOTS.to_vec()),
                }),
            },
            RobotSource::Urdf {
                path,
                search_paths,
                xacro_args,
            } => {
                let base_dir = path.parent().unwrap_or(Path::new(".")).to_path_buf();
                let meshes = MeshResolver::from_env(&base_dir, search_paths.clone());
                let robot = if is_xacro_path(path) {
                    let options = XacroOptions {
                        args: xacro_args.clone(),
                        packages: Some(meshes.clone()),
                        ..XacroOptions::default()
                    };
                    UrdfRobot::from_xacro(path, &options)?
                } else if let Some(name) = xacro_args.keys().next() {
                    return Err(RobotError::XacroArgument {
                        source_name: path.display().to_string(),
                        name: name.clone(),
                        message:
                            "xacro arguments are given, but only a file named *.xacro is expanded"
                                .into(),
                    });
                } else {
                    UrdfRobot::from_file(path)?
                };
                Ok(RobotModel {
                    source_name: robot.source_name().to_string(),
                    kind: Kind::Urdf {
                        meshes,
                        robot: Box::new(robot),
                    },
                })
            }
            RobotSource::Mjcf { path } => {
                let robot = MjcfRobot::from_file(path)?;
                Ok(RobotModel {
                    source_name: robot.source_name().to_string(),
                    kind: Kind::Mjcf {
                        meshes: robot.mesh_resolver(),
                        robot: Box::new(robot),
                    },
                })
            }
        }
    }
}

#[derive(Debug, Clone)]
enum Kind {
    Builtin(BuiltinRobot),
    Urdf {
        robot: Box<UrdfRobot>,
        meshes: MeshResolver,
    },
    Mjcf {
        robot: Box<MjcfRobot>,
        meshes: MeshResolver,
    },
}

/// A loaded robot: chains, link names and link collision geometry. Cheap to keep; chains are
/// built on request.
#[derive(Debug, Clone)]
pub struct RobotModel {
    source_name: String,
    kind: Kind,
}

impl RobotModel {
    /// The robot's name: the built-in name (`baxter`, `panda`, …), the URDF `<robot name>`
    /// or the MJCF `<mujoco model>`.
    pub fn name(&self) -> &str {
        match &self.kind {
            Kind::Builtin(robot) => robot.name(),
            Kind::Urdf { robot, .. } => robot.name(),
            Kind::Mjcf { robot, .. } => robot.name(),
        }
    }

    /// The file or built-in model, for messages (`built-in baxter`, a path).
    pub fn source_name(&self) -> &str {
        &self.source_name
    }

    /// Whether this is a built-in model.
    pub fn is_builtin(&self) -> bool {
        matches!(self.kind, Kind::Builtin(_))
    }

    /// The built-in robot, if this is one.
    pub fn builtin(&self) -> Option<BuiltinRobot> {
        match self.kind {
            Kind::Builtin(robot) => Some(robot),
            Kind::Urdf { .. } | Kind::Mjcf { .. } => None,
        }
    }

    /// The parsed MJCF model, for an MJCF robot.
    pub fn mjcf(&self) -> Option<&MjcfRobot> {
        match &self.kind {
            Kind::Mjcf { robot, .. } => Some(robot),
            _ => None,
        }
    }

    /// The parsed URDF, for a URDF robot.
    pub fn urdf(&self) -> Option<&UrdfRobot> {
        match &self.kind {
            Kind::Urdf { robot, .. } => Some(robot),
            Kind::Builtin(_) | Kind::Mjcf { .. } => None,
        }
    }

    /// Where the robot's mesh URIs are looked up (a URDF or MJCF robot's; `None` for a
    /// built-in one).
    pub fn mesh_resolver(&self) -> Option<&MeshResolver> {
        match &self.kind {
            Kind::Urdf { meshes, .. } | Kind::Mjcf { meshes, .. } => Some(meshes),
            Kind::Builtin(_) => None,
        }
    }

    /// The chains known by name: `left` and `right` for Baxter, `arm` for a single-arm
    /// built-in robot, none for a URDF or MJCF robot (give base and tip links to
    /// [`RobotModel::chain`]).
    pub fn chain_names(&self) -> Vec<String> {
        match &self.kind {
            Kind::Builtin(robot) => robot
                .chain_names()
                .iter()
                .map(ToString::to_string)
                .collect(),
            Kind::Urdf { .. } | Kind::Mjcf { .. } => Vec::new(),
        }
    }

    /// The chain named `name` (see [`RobotModel::chain_names`]), with an optional tool offset
    /// `tip_from_tool`.
    pub fn named_chain(
        &self,
        name: &str,
        tip_from_tool: Option<Isometry3<f64>>,
    ) -> Result<Chain, RobotError> {
        let known = self.chain_names();
        let spec = match &self.kind {
            Kind::Builtin(robot) => robot.chain_spec(name),
            Kind::Urdf { .. } | Kind::Mjcf { .. } => None,
        };
        let Some(mut spec) = spec else {
            return Err(RobotError::UnknownChain {
                source_name: self.source_name.clone(),
                chain: name.to_string(),
                suggestions: closest_names(name, known.iter().map(String::as_str).collect()),
                known,
            });
        };
        spec.tip_from_tool = tip_from_tool;
        Chain::from_spec(&spec)
    }

    /// The chain from `base_link` down to `tip_link`, with an optional tool offset. For a
    /// built-in robot, any stretch of one of its named chains (Baxter: `base` …
    /// `{arm}_gripper`; Panda: `panda_link0` … `panda_hand_tcp`).
    pub fn chain(
        &self,
        base_link: &str,
        tip_link: &str,
        tip_from_tool: Option<Isometry3<f64>>,
    ) -> Result<Chain, RobotError> {
        match &self.kind {
            Kind::Urdf { robot, .. } => robot.chain(base_link, tip_link, tip_from_tool),
            Kind::Mjcf { robot, .. } => robot.chain(base_link, tip_link, tip_from_tool),
            Kind::Builtin(robot) => {
                let mut spec = builtin_sub_chain(*robot, base_link, tip_link, &self.link_names())?;
                spec.tip_from_tool = tip_from_tool;
                Chain::from_spec(&spec)
            }
        }
    }

    /// Every link name (URDF: file order; MJCF: body names, `world` first, then file order;
    /// built-in: base, then each chain's links).
    pub fn link_names(&self) -> Vec<String> {
        match &self.kind {
            Kind::Urdf { robot, .. } => {
                robot.link_names().iter().map(ToString::to_string).collect()
            }
            Kind::Mjcf { robot, .. } => {
                robot.body_names().iter().map(ToString::to_string).collect()
            }
            Kind::Builtin(robot) => {
                let mut names = Vec::new();
                for spec in robot.chain_specs() {
                    for name in Chain::from_spec(&spec)
                        .expect("the built-in models are valid")
                        .link_names()
                    {
                        if !names.contains(name) {
                            names.push(name.clone());
                        }
                    }
                }
                names
            }
        }
    }

    /// The collision geometry of every link that has any: a URDF robot's `<collision>`
    /// elements (mesh URIs resolved, not read), an MJCF robot's colliding geoms
    /// ([`MjcfRobot::collisions`]), or a built-in model's primitives
    /// ([`BuiltinRobot::collisions`]).
    pub fn collisions(&self) -> Result<Vec<LinkCollisions>, RobotError> {
        match &self.kind {
            Kind::Urdf { robot, meshes } => robot.collisions(meshes),
            Kind::Mjcf { robot, meshes } => robot.collisions(meshes),
            Kind::Builtin(robot) => Ok(robot.collisions()),
        }
    }
}

/// The stretch `base_link → tip_link` of one of a built-in robot's chains.
fn builtin_sub_chain(
    robot: BuiltinRobot,
    base_link: &str,
    tip_link: &str,
    all_links: &[String],
) -> Result<ChainSpec, RobotError> {
    let unknown = |link: &str, role: &'static str| RobotError::UnknownLink {
        source_name: robot.source_name(),
        link: link.to_string(),
        role,
        suggestions: closest_names(link, all_links.iter().map(String::as_str).collect()),
    };
    if !all_links.iter().any(|l| l == base_link) {
        return Err(unknown(base_link, "base"));
    }
    if !all_links.iter().any(|l| l == tip_link) {
        return Err(unknown(tip_link, "tip"));
    }
    for mut spec in robot.chain_specs() {
        // Link k of the chain is the child of joint k − 1 (link 0 is the base).
        let position = |link: &str| {
            if link == spec.base_link {
                Some(0)
            } else {
                spec.joints
                    .iter()
                    .position(|j| j.child_link == link)
                    .map(|k| k + 1)
            }
        };
        if let (Some(b), Some(t)) = (position(base_link), position(tip_link)) {
            if b <= t {
                spec.joints = spec.joints[b..t].to_vec();
                spec.base_link = base_link.to_string();
                spec.tip_link = tip_link.to_string();
                return Ok(spec);
            }
        }
    }
    let root = robot
        .chain_specs()
        .first()
        .map_or_else(String::new, |s| s.base_link.clone());
    Err(RobotError::TipNotBelowBase {
        source_name: robot.source_name(),
        base: base_link.to_string(),
        tip: tip_link.to_string(),
        root,
    })
}
