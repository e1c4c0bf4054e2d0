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
//! // an MJCF file, by body names: `RobotSource::mjcf("ur5.xml").load()?.chain("base", "tool0", None)?`;
//! // either, its format told by its name or content: `RobotSource::from_path("arm.xml")?.load()?`.
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
use std::io::Read;
use std::path::{Path, PathBuf};

/// The built-in robots' names (see [`super::builtin`]).
pub(super) const BUILTIN_ROBOTS: [&str; 10] = BUILTIN_NAMES;

/// The most bytes [`RobotSource::from_path`] reads from a file to find its root element:
/// 64 KiB, room for an XML declaration and a long licence comment.
pub(super) const FORMAT_PREFIX_BYTES: u64 = 64 << 10;

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

    /// The robot file at `path`, its format told by its extension (any letter case): `.urdf` is
    /// a URDF, `.xacro` (`.urdf.xacro`) a xacro file, expanded on load (see
    /// [`RobotSource::Urdf`]), `.mjcf` an MJCF file. A file named otherwise — `.xml`, which both
    /// formats use, or any other name — is told by its root element, read from at most its
    /// first 64 KiB: `<robot>` is a URDF, `<mujoco>` an MJCF file. A URDF told
    /// by its root is never expanded as xacro: xacro markup in it is refused on load, as in any
    /// file not named `*.xacro`.
    ///
    /// Errors: [`RobotError::Io`] when a file named otherwise cannot be read (missing, not a
    /// regular file), [`RobotError::UnknownFormat`] when its root is neither. A file named by
    /// its extension is read only by [`RobotSource::load`].
    pub fn from_path(path: impl Into<PathBuf>) -> Result<Self, RobotError> {
        let path = path.into();
        let extension = path
            .extension()
            .map(|e| e.to_string_lossy().to_ascii_lowercase());
        match extension.as_deref() {
            Some("urdf" | "xacro") => return Ok(Self::urdf(path)),
            Some("mjcf") => return Ok(Self::mjcf(path)),
            _ => {}
        }
        let source_name = path.display().to_string();
        let mut prefix = Vec::new();
        crate::input::open(&path)
            .and_then(|file| file.take(FORMAT_PREFIX_BYTES).read_to_end(&mut prefix))
            .map_err(|source| RobotError::Io {
                source_name: source_name.clone(),
                source,
            })?;
        let unknown = |reason: String| RobotError::UnknownFormat {
            source_name: source_name.clone(),
            reason,
        };
        match root_element(&prefix) {
            Some(b"robot") => Ok(Self::urdf(path)),
            Some(b"mujoco") => Ok(Self::mjcf(path)),
            Some(name) => Err(unknown(format!(
                "its root element is <{}>",
                String::from_utf8_lossy(name)
            ))),
            None if prefix.iter().all(u8::is_ascii_whitespace) => {
                Err(unknown("the file is empty".into()))
            }
            None if prefix.len() as u64 == FORMAT_PREFIX_BYTES => Err(unknown(format!(
                "no root element in its first {} KiB",
                FORMAT_PREFIX_BYTES >> 10
            ))),
            None => Err(unknown("it is not XML (no root element)".into())),
        }
    }

    /// This source with a URDF's options: `search_paths` (where `package://PKG` mesh URIs and
    /// xacro's `$(find PKG)` look first) and `xacro_args` (for a `*.xacro` file). Empty options
    /// leave any source as it is; options for a source that is not a URDF file are
    /// [`RobotError::UrdfOption`].
    pub fn with_urdf_options(
        self,
        search_paths: Vec<PathBuf>,
        xacro_args: BTreeMap<String, String>,
    ) -> Result<Self, RobotError> {
        let (source_name, format) = match self {
            RobotSource::Urdf { path, .. } => {
                return Ok(RobotSource::Urdf {
                    path,
                    search_paths,
                    xacro_args,
                })
            }
            _ if search_paths.is_empty() && xacro_args.is_empty() => return Ok(self),
            RobotSource::Mjcf { path } => (path.display().to_string(), "an MJCF file"),
            RobotSource::Builtin(name) => (format!("built-in {name}"), "a built-in robot"),
        };
        Err(RobotError::UrdfOption {
            source_name,
            option: if search_paths.is_empty() {
                "xacro arguments"
            } else {
                "search paths"
            },
            format,
        })
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

/// The name of the root element of the XML document that `prefix` begins (after a byte-order
/// mark, white space, the XML declaration, comments, processing instructions and a document
/// type declaration), or `None` when `prefix` ends first or is not XML.
fn root_element(prefix: &[u8]) -> Option<&[u8]> {
    let mut rest = prefix.strip_prefix(b"\xef\xbb\xbf").unwrap_or(prefix);
    loop {
        rest = rest.trim_ascii_start();
        let skip_past = |text: &[u8], end: &[u8]| {
            text.windows(end.len())
                .position(|w| w == end)
                .map(|k| k + end.len())
        };
        let after = if rest.starts_with(b"<?") {
            skip_past(rest, b"?>")?
        } else if rest.starts_with(b"<!--") {
            skip_past(&rest[4..], b"-->")? + 4
        } else if rest.starts_with(b"<!") {
            // `<!DOCTYPE name [internal subset]>`: the subset may hold `>`.
            let open = rest.iter().position(|&b| b == b'[' || b == b'>')?;
            if rest[open] == b'[' {
                let close = open + skip_past(&rest[open..], b"]")?;
                close + skip_past(&rest[close..], b">")?
            } else {
                open + 1
            }
        } else {
            break;
        };
        rest = &rest[after..];
    }
    let name = rest.strip_prefix(b"<")?;
    let end = name
        .iter()
        .position(|&b| b.is_ascii_whitespace() || b == b'>' || b == b'/')?;
    (end > 0).then_some(&name[..end])
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
        element: "link",
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
        element: "link",
        base: base_link.to_string(),
        tip: tip_link.to_string(),
        root,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fault::{Classify, ErrorKind, Fault};

    /// What the error says is at fault (the walk `graspath::fault_of` does, over robot errors).
    fn fault_of(err: &RobotError) -> Option<Fault<'_>> {
        Fault::walk(err, |e| {
            e.downcast_ref::<RobotError>().map(|r| r as &dyn Classify)
        })
    }

    const URDF: &str = r#"<robot name="r"><link name="base"/><joint name="j" type="revolute"><parent link="base"/><child link="tip"/><axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint><link name="tip"/></robot>"#;
    const MJCF: &str = r#"<mujoco model="m"><worldbody><body name="base"><body name="tip"><joint name="j" type="hinge" range="-1 1"/></body></body></worldbody></mujoco>"#;

    fn write(dir: &Path, name: &str, text: &[u8]) -> PathBuf {
        let path = dir.join(name);
        std::fs::write(&path, text).unwrap();
        path
    }

    #[test]
    fn the_extension_tells_the_format_without_reading_the_file() {
        // The files do not exist: only the name is looked at.
        for name in ["a.urdf", "a.URDF", "a.xacro", "a.urdf.xacro", "a.Xacro"] {
            assert_eq!(
                RobotSource::from_path(name).unwrap(),
                RobotSource::urdf(name),
                "{name}"
            );
        }
        for name in ["a.mjcf", "a.MJCF"] {
            assert_eq!(
                RobotSource::from_path(name).unwrap(),
                RobotSource::mjcf(name),
                "{name}"
            );
        }
    }

    #[test]
    fn xml_and_other_names_are_told_by_their_root_element() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        type Expected = fn(PathBuf) -> RobotSource;
        let cases: [(&str, &[u8], Expected); 6] = [
            ("urdf.xml", URDF.as_bytes(), |p| RobotSource::urdf(p)),
            ("mjcf.xml", MJCF.as_bytes(), |p| RobotSource::mjcf(p)),
            ("robot", URDF.as_bytes(), |p| RobotSource::urdf(p)),
            ("scene.model", MJCF.as_bytes(), |p| RobotSource::mjcf(p)),
            (
                "prolog.xml",
                b"\xef\xbb\xbf<?xml version=\"1.0\"?>\n<!-- <mujoco> in a comment -->\n<!DOCTYPE robot [<!ENTITY x \"<mujoco>\">]>\n<?pi x?>\n<robot name=\"r\"/>",
                |p| RobotSource::urdf(p),
            ),
            ("tab.txt", b"<mujoco\tmodel=\"m\"/>", |p| RobotSource::mjcf(p)),
        ];
        for (name, text, expected) in cases {
            let path = write(d, name, text);
            assert_eq!(
                RobotSource::from_path(&path).unwrap(),
                expected(path.clone()),
                "{name}"
            );
        }
        // Told apart, each loads with its own reader.
        let urdf = RobotSource::from_path(d.join("urdf.xml"))
            .unwrap()
            .load()
            .unwrap();
        let mjcf = RobotSource::from_path(d.join("mjcf.xml"))
            .unwrap()
            .load()
            .unwrap();
        assert_eq!(urdf.chain("base", "tip", None).unwrap().dof(), 1);
        assert_eq!(mjcf.chain("base", "tip", None).unwrap().dof(), 1);
    }

    #[test]
    fn a_file_of_neither_format_is_one_content_error_naming_it() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        let long_comment = format!("<!--{}-->\n<robot/>", " ".repeat(70_000));
        let cases: [(&str, &[u8], &str); 6] = [
            (
                "world.sdf",
                b"<?xml version=\"1.0\"?><sdf version=\"1.9\"/>",
                "its root element is <sdf>",
            ),
            (
                "robotic.xml",
                b"<robotics/>",
                "its root element is <robotics>",
            ),
            ("empty.xml", b"", "the file is empty"),
            ("blank.dat", b" \n\t", "the file is empty"),
            ("data.bin", b"\x00\x01binary", "it is not XML"),
            (
                "long.xml",
                long_comment.as_bytes(),
                "no root element in its first 64 KiB",
            ),
        ];
        for (name, text, reason) in cases {
            let path = write(d, name, text);
            let err = RobotSource::from_path(&path).unwrap_err();
            let message = err.to_string();
            assert!(
                message.starts_with(&format!("{}: not a robot description", path.display())),
                "{message}"
            );
            assert!(message.contains(reason), "{name}: {message}");
            assert!(
                message.contains("*.urdf") && message.contains("<mujoco>"),
                "{message}"
            );
            let fault = fault_of(&err).unwrap();
            assert_eq!(fault.kind, ErrorKind::Content, "{name}");
            assert_eq!(fault.file, Some(path.display().to_string().as_str()));
        }
    }

    #[test]
    fn a_missing_or_special_file_is_a_file_error() {
        let dir = tempfile::tempdir().unwrap();
        let missing = dir.path().join("missing.xml");
        let err = RobotSource::from_path(&missing).unwrap_err();
        let fault = fault_of(&err).unwrap();
        assert_eq!(fault.kind, ErrorKind::File);
        assert_eq!(fault.io, Some(std::io::ErrorKind::NotFound));
        assert!(err.to_string().contains("missing.xml"), "{err}");
        // A folder is refused before anything is read.
        let err = RobotSource::from_path(dir.path()).unwrap_err();
        assert_eq!(fault_of(&err).unwrap().kind, ErrorKind::File);
    }

    #[test]
    fn a_urdf_told_by_its_root_is_not_expanded_as_xacro() {
        let dir = tempfile::tempdir().unwrap();
        let text = r#"<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro"><xacro:macro name="m"/><link name="base"/></robot>"#;
        let path = write(dir.path(), "arm.xml", text.as_bytes());
        let source = RobotSource::from_path(&path).unwrap();
        assert_eq!(source, RobotSource::urdf(&path));
        let err = source.load().unwrap_err();
        assert!(matches!(err, RobotError::XacroMarkup { .. }), "{err}");
    }

    #[test]
    fn urdf_options_go_to_a_urdf_only() {
        let paths = vec![PathBuf::from("pkgs")];
        let args = BTreeMap::from([("dof".to_string(), "7".to_string())]);
        let urdf = RobotSource::urdf("a.urdf.xacro")
            .with_urdf_options(paths.clone(), args.clone())
            .unwrap();
        assert_eq!(
            urdf,
            RobotSource::Urdf {
                path: "a.urdf.xacro".into(),
                search_paths: paths.clone(),
                xacro_args: args.clone(),
            }
        );
        let mjcf = RobotSource::mjcf("a.xml");
        assert_eq!(
            mjcf.clone()
                .with_urdf_options(Vec::new(), BTreeMap::new())
                .unwrap(),
            mjcf
        );
        let err = mjcf
            .clone()
            .with_urdf_options(paths, BTreeMap::new())
            .unwrap_err();
        assert_eq!(
            err.to_string(),
            "a.xml: search paths are for a URDF or xacro file, and this is an MJCF file"
        );
        let err = RobotSource::builtin("panda")
            .with_urdf_options(Vec::new(), args)
            .unwrap_err();
        assert!(err.to_string().contains("xacro arguments"), "{err}");
        assert_eq!(fault_of(&err).unwrap().kind, ErrorKind::Content);
    }
}
