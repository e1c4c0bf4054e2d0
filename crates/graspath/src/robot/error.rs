//! Errors of robot loading and kinematics. Each names the file (or built-in model) and the
//! element at fault.

/// An error from loading a robot or evaluating its kinematics.
#[derive(Debug, thiserror::Error)]
pub enum RobotError {
    /// The file could not be read.
    #[error("{source_name}: cannot read: {message}")]
    Io {
        /// The file.
        source_name: String,
        /// The operating system's message.
        message: String,
    },
    /// A `.xacro` file was given; it must be expanded first.
    #[error("{source_name}: this is a xacro file; expand it first, e.g. `xacro {source_name} > robot.urdf`, and load the .urdf")]
    Xacro {
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
    /// A link name that the robot does not have.
    #[error("{source_name}: no link named '{link}' (given as the {role} link){}", suggestion_text(.suggestions))]
    UnknownLink {
        /// The file.
        source_name: String,
        /// The requested name.
        link: String,
        /// `base`, `tip` or another role.
        role: &'static str,
        /// Link names that are close to the requested one.
        suggestions: Vec<String>,
    },
    /// The tip link is not a descendant of the base link.
    #[error("{source_name}: tip link '{tip}' is not below base link '{base}' (the root of '{tip}' is '{root}')")]
    TipNotBelowBase {
        /// The file.
        source_name: String,
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
}

fn suggestion_text(suggestions: &[String]) -> String {
    if suggestions.is_empty() {
        String::new()
    } else {
        format!("; did you mean: {}?", suggestions.join(", "))
    }
}
