//! Tasks: what the object must do after it is grasped.
//!
//! * [`ObjectPath`]: the desired object trajectory as waypoints (absolute poses or relative steps
//!   `lift`, `move`, `rotate`, `place`), sampled in SE(3) with times.
//! * [`ObjectShape`]: the object's primitive shape, for candidate families, clouds and views.
//! * [`TaskFile`]: the documented task-file schema (YAML or JSON), parsed with every unknown field
//!   rejected by its path.

mod file;
mod path;
mod shape;

pub use file::{
    ArmFile, ArmsFile, CandidatesFile, FamilyFile, GenerateFile, IkFile, IndexFile, LikelihoodFile,
    NormFile, ObjectFile, PoseFile, RobotFile, RotateFile, SelectionFile, SpacingFile, StepFile,
    TaskError, TaskFile, TrajectoryFile,
};
pub use path::{ObjectPath, PathSample, Sampling, Step, TimedStep};
pub use shape::ObjectShape;
