//! Errors of robot loading and kinematics. Each names the file (or built-in model) and the
//! element at fault.

use crate::fault::ErrorKind;

/// An error from loading a robot or evaluating its kinematics.
#[derive(Debug, thiserror::Error)]
pub enum RobotError {
    /// The file could not be read; the operating system's error is the source.
    #[error("{source_name}: cannot read")]
    Io {
        /// The file.
        source_name: String,
        /// The operating system's error (or the size cap's, [`crate::input::read`]).
        #[source]
        source: std::io::Error,
    },
    /// A `.xacro` file was given and no `xacro` program is installed to expand it.
    #[error("{source_name}: this is a xacro file; {}", xacro_hint(.reason))]
    Xacro {
        /// The file.
        source_name: String,
        /// Why it was not expanded.
        reason: String,
    },
    /// A file not named `*.xacro` uses xacro markup. xacro runs code, so graspath expands only
    /// files the user names as xacro files.
    #[error("{source_name}:{line}: uses xacro markup ({markup}) but is not named *.xacro; xacro runs code, so only files named *.xacro are expanded: if you trust this file, name it (or a copy) *.xacro, or expand it yourself (`xacro FILE > robot.urdf`) and load the .urdf")]
    XacroMarkup {
        /// The file.
        source_name: String,
        /// 1-based line of the first xacro element or substitution.
        line: usize,
        /// What was found, e.g. `<xacro:macro>` or `${...} in an attribute of <origin>`.
        markup: String,
    },
    /// A xacro argument cannot be passed to `xacro`.
    #[error("{source_name}: xacro argument '{name}': {message}")]
    XacroArgument {
        /// The file.
        source_name: String,
        /// The argument's name (empty when the argument list as a whole is at fault).
        name: String,
        /// What is wrong.
        message: String,
    },
    /// The `xacro` program ran but failed (its exit code and standard error are included).
    #[error("{source_name}: `{command}` failed: {message}")]
    XacroFailed {
        /// The file.
        source_name: String,
        /// The command line that was run.
        command: String,
        /// Exit code (or time limit) and the end of the program's standard error.
        message: String,
    },
    /// The operating system refused a step of running `xacro` (locating the file, making its
    /// working folder, starting the program, waiting for it, reading its output); the
    /// operating system's error is the source.
    #[error("{source_name}: `{command}`: {action}")]
    XacroIo {
        /// The file.
        source_name: String,
        /// The command line that was (to be) run.
        command: String,
        /// The step that failed, e.g. `cannot start it`.
        action: &'static str,
        /// The operating system's error.
        #[source]
        source: std::io::Error,
    },
    /// An MJCF (MuJoCo XML) element or attribute cannot be used: a missing or malformed
    /// value, an unknown default class, an unsupported element.
    #[error("{source_name}:{line}: {element}, attribute '{attribute}': {message}")]
    Mjcf {
        /// The file.
        source_name: String,
        /// 1-based line of the element's start tag.
        line: usize,
        /// The element, e.g. `<joint name="j1"> in body 'link1'`.
        element: String,
        /// The attribute at fault (`pos`, `range`, ...; `-` for the element itself).
        attribute: String,
        /// What is wrong.
        message: String,
    },
    /// An MJCF joint that a serial chain cannot hold (a `ball` or `free` joint, an unlimited
    /// `slide` joint) lies between the chain's base and tip bodies.
    #[error("{source_name}: body '{body}', joint '{joint}': {message}")]
    MjcfJointInChain {
        /// The file.
        source_name: String,
        /// The body that carries the joint.
        body: String,
        /// The joint's name (or `#k`, its index in the body, when unnamed).
        joint: String,
        /// What is wrong and what to do.
        message: String,
    },
    /// A robot file whose format neither its name nor its root element tells
    /// ([`crate::robot::RobotSource::from_path`]).
    #[error("{source_name}: not a robot description graspath reads: {reason}; give a URDF (root <robot>, named *.urdf), a xacro file (named *.xacro) or a MuJoCo MJCF file (root <mujoco>, named *.xml or *.mjcf)")]
    UnknownFormat {
        /// The file.
        source_name: String,
        /// What was found instead (`its root element is <sdf>`, `the file is empty`).
        reason: String,
    },
    /// URDF options (search paths, xacro arguments) given for a robot that is not a URDF file.
    #[error("{source_name}: {option} are for a URDF or xacro file, and this is {format}")]
    UrdfOption {
        /// The file, or `built-in NAME`.
        source_name: String,
        /// `search paths` or `xacro arguments`.
        option: &'static str,
        /// What the robot is: `an MJCF file`, `a built-in robot`.
        format: &'static str,
    },
    /// A MuJoCo MJCF file was given where a URDF is read.
    #[error("{source_name}: not a valid URDF: this is a MuJoCo MJCF file (root <mujoco>): load it as MJCF (`robot: {{mjcf: FILE}}` in a task file)")]
    MjcfNotUrdf {
        /// The file.
        source_name: String,
    },
    /// The XML is malformed or is not a URDF robot.
    #[error("{source_name}: not a valid URDF: {message}")]
    Parse {
        /// The file.
        source_name: String,
        /// The parser's message.
        message: String,
    },
    /// The XML itself is malformed (an unclosed or mismatched tag, a broken attribute, ...).
    #[error("{source_name}:{line}:{column}: malformed XML: {message}")]
    Xml {
        /// The file.
        source_name: String,
        /// 1-based line.
        line: usize,
        /// 1-based column (characters).
        column: usize,
        /// The parser's message.
        message: String,
    },
    /// A link is the child of more than one joint (a URDF must be a tree).
    #[error("{source_name}: link '{link}' is the child of two joints, '{first}' and '{second}' (a URDF robot is a tree)")]
    TwoParents {
        /// The file.
        source_name: String,
        /// The link.
        link: String,
        /// The first joint naming it as child.
        first: String,
        /// The second joint naming it as child.
        second: String,
    },
    /// A collision element cannot be used (a non-positive size, a non-finite origin, ...).
    #[error("{source_name}: link '{link}', collision {index}: {message}")]
    BadCollision {
        /// The file.
        source_name: String,
        /// The link.
        link: String,
        /// Index of the `<collision>` element within the link (0-based).
        index: usize,
        /// What is wrong.
        message: String,
    },
    /// A collision mesh was not found at any of the places its URI may point to.
    #[error("{source_name}: link '{link}', collision mesh '{uri}': not found; tried {}{}", display_paths(.tried), mesh_hint(.uri))]
    MeshNotFound {
        /// The URDF file.
        source_name: String,
        /// The link.
        link: String,
        /// The mesh URI as written (`package://...`, `model://...`, a path).
        uri: String,
        /// Every path tried, in order.
        tried: Vec<std::path::PathBuf>,
    },
    /// A collision mesh URI of a scheme that cannot be resolved to a file.
    #[error("{source_name}: link '{link}', collision mesh '{uri}': unsupported URI scheme (use package://, model://, file:// or a path)")]
    MeshScheme {
        /// The URDF file.
        source_name: String,
        /// The link.
        link: String,
        /// The URI.
        uri: String,
    },
    /// A `package://` or `model://` mesh URI whose path climbs out of its package (a `..`).
    #[error("{source_name}: link '{link}', mesh '{uri}': a package path may not leave its package ('..' is refused)")]
    MeshOutsidePackage {
        /// The URDF file.
        source_name: String,
        /// The link.
        link: String,
        /// The URI.
        uri: String,
    },
    /// A collision mesh file was found but could not be read or used; the reader's error (a
    /// [`crate::cloud::CloudError`] or a [`crate::geometry::shape::ShapeError`]) is the source.
    #[error("{source_name}: link '{link}', collision mesh {}", .path.display())]
    MeshLoad {
        /// The URDF file.
        source_name: String,
        /// The link.
        link: String,
        /// The mesh file.
        path: std::path::PathBuf,
        /// The reader's error.
        #[source]
        source: Box<dyn std::error::Error + Send + Sync>,
    },
    /// A built-in robot name that does not exist.
    #[error("unknown built-in robot '{name}' (built in: {}){}", .known.join(", "), suggestion_text(.suggestions))]
    UnknownRobot {
        /// The name given.
        name: String,
        /// The built-in robots.
        known: Vec<String>,
        /// Close names.
        suggestions: Vec<String>,
    },
    /// A named chain (arm) the robot does not have.
    #[error("{source_name}: no chain named '{chain}' (chains: {}){}", if .known.is_empty() { "none; give base and tip links".to_string() } else { .known.join(", ") }, suggestion_text(.suggestions))]
    UnknownChain {
        /// The robot.
        source_name: String,
        /// The name given.
        chain: String,
        /// The named chains.
        known: Vec<String>,
        /// Close names.
        suggestions: Vec<String>,
    },
    /// A link name (an MJCF file's body name) that the robot does not have.
    #[error("{source_name}: no {element} named '{link}' (given as the {role} {element}){}", suggestion_text(.suggestions))]
    UnknownLink {
        /// The file.
        source_name: String,
        /// What the file calls its frames: `link` (URDF, built-in robots) or `body` (MJCF).
        element: &'static str,
        /// The requested name.
        link: String,
        /// `base`, `tip` or another role.
        role: &'static str,
        /// Link names that are close to the requested one.
        suggestions: Vec<String>,
    },
    /// The tip link (an MJCF file's body) is not a descendant of the base link.
    #[error("{source_name}: tip {element} '{tip}' is not below base {element} '{base}' (the root of '{tip}' is '{root}')")]
    TipNotBelowBase {
        /// The file.
        source_name: String,
        /// What the file calls its frames: `link` (URDF, built-in robots) or `body` (MJCF).
        element: &'static str,
        /// Base link.
        base: String,
        /// Tip link.
        tip: String,
        /// The root reached when walking up from the tip.
        root: String,
    },
    /// A joint field is invalid (zero axis, NaN origin, inverted limits, ...).
    #[error("{source_name}: joint '{joint}', field '{field}': {message}")]
    BadJoint {
        /// The file.
        source_name: String,
        /// The joint.
        joint: String,
        /// The URDF field, e.g. `origin/@xyz`, `axis/@xyz`, `limit`.
        field: &'static str,
        /// What is wrong.
        message: String,
    },
    /// A joint configuration of the wrong length.
    #[error("q has {got} values but the chain '{chain}' has {expected} joints")]
    WrongDof {
        /// Chain name (`base->tip`).
        chain: String,
        /// Joint count of the chain.
        expected: usize,
        /// Length given.
        got: usize,
    },
    /// A link-frame buffer of the wrong length.
    #[error("the frame buffer has {got} entries but the chain '{chain}' has {expected} links")]
    WrongLinkCount {
        /// Chain name (`base->tip`).
        chain: String,
        /// Link count of the chain.
        expected: usize,
        /// Length given.
        got: usize,
    },
    /// An output buffer of a batch call whose length does not fit the configurations given.
    #[error("the {what} buffer has {got} values but {expected} are needed")]
    WrongBufferLength {
        /// Which buffer (`pose`, `Jacobian`).
        what: &'static str,
        /// Values needed.
        expected: usize,
        /// Values given.
        got: usize,
    },
    /// A joint value is NaN or infinite.
    #[error("q[{index}] is not a finite number")]
    NonFiniteJoint {
        /// Index into q.
        index: usize,
    },
    /// A target pose has a NaN or infinite entry, or a rotation that is not unit.
    #[error("{what}: not a valid pose ({message})")]
    BadPose {
        /// Which pose, e.g. `target` or `targets[3]`.
        what: String,
        /// What is wrong.
        message: String,
    },
    /// A solver option is out of range.
    #[error("option '{name}': {message}")]
    BadOption {
        /// The option's field name.
        name: &'static str,
        /// What is wrong.
        message: String,
    },
    /// A fixed-size view was requested with the wrong joint count or a chain with mimic joints.
    #[error(
        "chain '{chain}' cannot be used as a fixed-size chain of {requested} joints: {reason}"
    )]
    NotFixedSize {
        /// Chain name.
        chain: String,
        /// The requested size.
        requested: usize,
        /// Why not.
        reason: String,
    },
    /// Dynamics was asked of a chain whose moving segment carries no inertial data: none of
    /// the links it moves has a mass, centre of mass and inertia in the source.
    #[error(
        "{source_name}: chain '{chain}' has no inertial data for the links moved by joint '{joint}' ({links}): dynamics needs each moving link's mass, centre of mass and inertia (a URDF or MJCF <inertial>; inertia from MJCF geoms is not computed)"
    )]
    NoInertia {
        /// The file or built-in model.
        source_name: String,
        /// Chain name (`base->tip`).
        chain: String,
        /// The moving joint whose segment has no data.
        joint: String,
        /// The links that segment moves, comma-separated.
        links: String,
    },
    /// Inertial data that cannot describe a body: a negative or non-finite mass, a
    /// non-finite centre of mass, an asymmetric inertia or one with a negative diagonal.
    #[error("{what}: not a valid rigid body ({message})")]
    BadInertia {
        /// Which body, e.g. `chain 'a->b', segment of joint 'j2'` or `payload`.
        what: String,
        /// What is wrong.
        message: String,
    },
    /// A joint-velocity, joint-acceleration or output buffer of the wrong length, or a
    /// non-finite joint velocity or acceleration.
    #[error("{what}: {message}")]
    BadDynamicsInput {
        /// `qd`, `qdd`, `tau` or `mass matrix`.
        what: &'static str,
        /// What is wrong.
        message: String,
    },
}

impl crate::fault::Classify for RobotError {
    /// A file that cannot be read, or a mesh that cannot be loaded, has its source's kind; a
    /// mesh found nowhere is [`ErrorKind::File`]; everything else is [`ErrorKind::Content`]
    /// (running `xacro` too, whatever its source: the file asked for the expansion).
    fn kind(&self) -> Option<ErrorKind> {
        match self {
            Self::Io { .. } | Self::MeshLoad { .. } => None,
            Self::MeshNotFound { .. } => Some(ErrorKind::File),
            _ => Some(ErrorKind::Content),
        }
    }

    fn file(&self) -> Option<&str> {
        match self {
            Self::Io { source_name, .. }
            | Self::Xacro { source_name, .. }
            | Self::XacroMarkup { source_name, .. }
            | Self::XacroArgument { source_name, .. }
            | Self::XacroFailed { source_name, .. }
            | Self::XacroIo { source_name, .. }
            | Self::Mjcf { source_name, .. }
            | Self::MjcfJointInChain { source_name, .. }
            | Self::MjcfNotUrdf { source_name }
            | Self::UnknownFormat { source_name, .. }
            | Self::UrdfOption { source_name, .. }
            | Self::Parse { source_name, .. }
            | Self::Xml { source_name, .. }
            | Self::TwoParents { source_name, .. }
            | Self::BadCollision { source_name, .. }
            | Self::MeshNotFound { source_name, .. }
            | Self::MeshScheme { source_name, .. }
            | Self::MeshOutsidePackage { source_name, .. }
            | Self::MeshLoad { source_name, .. }
            | Self::UnknownChain { source_name, .. }
            | Self::UnknownLink { source_name, .. }
            | Self::TipNotBelowBase { source_name, .. }
            | Self::BadJoint { source_name, .. }
            | Self::NoInertia { source_name, .. } => Some(source_name),
            Self::UnknownRobot { .. }
            | Self::WrongDof { .. }
            | Self::WrongLinkCount { .. }
            | Self::WrongBufferLength { .. }
            | Self::NonFiniteJoint { .. }
            | Self::BadPose { .. }
            | Self::BadOption { .. }
            | Self::NotFixedSize { .. }
            | Self::BadInertia { .. }
            | Self::BadDynamicsInput { .. } => None,
        }
    }

    fn field(&self) -> Option<&str> {
        match self {
            Self::Mjcf { attribute, .. } => Some(attribute),
            Self::BadJoint { field, .. } => Some(field),
            Self::BadOption { name, .. } => Some(name),
            Self::BadDynamicsInput { what, .. } => Some(what),
            _ => None,
        }
    }
}

fn suggestion_text(suggestions: &[String]) -> String {
    if suggestions.is_empty() {
        String::new()
    } else {
        format!("; did you mean: {}?", suggestions.join(", "))
    }
}

fn xacro_hint(reason: &str) -> String {
    format!("expand it first ({reason}): install xacro (`pip install xacro`, or ROS's xacro package) so it is expanded on load, or set GRASPATH_XACRO to the program, or expand it yourself (`xacro FILE > robot.urdf`) and load the .urdf")
}

fn display_paths(paths: &[std::path::PathBuf]) -> String {
    if paths.is_empty() {
        return "no place (no search path applies)".into();
    }
    paths
        .iter()
        .map(|p| p.display().to_string())
        .collect::<Vec<_>>()
        .join(", ")
}

fn mesh_hint(uri: &str) -> &'static str {
    if uri.starts_with("package://") || uri.starts_with("model://") {
        " (set ROS_PACKAGE_PATH or AMENT_PREFIX_PATH, or give a search path)"
    } else {
        ""
    }
}

/// Up to five names closest to `name` (by edit distance, or sharing a substring).
pub(crate) fn closest_names(name: &str, candidates: Vec<&str>) -> Vec<String> {
    let mut scored: Vec<(usize, &str)> = candidates
        .into_iter()
        .map(|c| {
            let mut d = strsim::levenshtein(name, c);
            if c.contains(name) || name.contains(c) {
                d = d.min(1);
            }
            (d, c)
        })
        .filter(|(d, c)| *d <= (name.len().max(c.len()) / 2).max(2))
        .collect();
    scored.sort();
    scored
        .into_iter()
        .take(5)
        .map(|(_, c)| c.to_string())
        .collect()
}
