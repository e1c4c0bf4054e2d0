//! Tasks: who grasps, what, and what the object must do after it is grasped.
//!
//! * [`Task`], built and checked by [`TaskBuilder`] (every default in [`crate::defaults`], every
//!   bound in [`Limits`]), or read from a task file by [`Task::load`];
//! * [`ObjectPath`]: the desired object trajectory as waypoints (absolute poses or relative steps
//!   `lift`, `move`, `rotate`, `place`), sampled in SE(3) with times;
//! * [`TaskFile`]: the documented task-file schema (YAML or JSON), parsed with every unknown field
//!   rejected by its path;
//! * the settings a task carries: [`Redundancy`], [`LikelihoodRule`], [`SelectionOptions`], and
//!   the index vocabulary of [`crate::manipulability`] (rows, measure, norm).

mod builder;
mod error;
mod file;
mod file_scene;
mod load;
mod load_candidates;
mod load_scene;
mod path;
mod payload;
mod plausibility;
mod scene;
mod sealed;
mod settings;
mod timing;
mod work;

pub use builder::TaskBuilder;
pub use error::TaskError;
pub use file::{
    pose, ArmFile, ArmsFile, CandidatesFile, FamilyFile, GenerateFile, IkFile, IndexFile,
    LikelihoodFile, ObjectFile, PenaltyFile, RobotFile, RotateFile, SelectionFile, SpacingFile,
    StepFile, TaskFile, TimingFile, TimingSettingsFile, TrajectoryFile, XacroArgument,
};
pub use load::builder_from_file;
pub use load_scene::{robot_link_shapes, STROKE_SAMPLES};
pub use path::{ObjectPath, PathError, PathSample, Sampling, Step, TimedStep};
pub use payload::{MAX_CENTER_OF_MASS_DISTANCE, MAX_PAYLOAD_MASS};
pub use plausibility::{
    file_warnings, world_warnings, TaskWarning, MAX_PLAUSIBLE_POSITION, MAX_PLAUSIBLE_SIZE,
    TABLE_PENETRATION,
};
pub use scene::{
    Collisions, Gripper, GripperBodies, GripperLink, SceneSettings, Stroke, WholeMotionPlan,
    DEFAULT_FINGER, MIN_RESOLUTION,
};
pub use sealed::{ArmSetup, Task};
pub use settings::{LikelihoodRule, Limits, Redundancy, SelectionOptions};
pub use timing::{TimingRequest, TimingSettings, DEFAULT_ACCELERATION_TIME};
pub use work::WorkEstimate;
