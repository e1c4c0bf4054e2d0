//! [`Error`]: any error of the library in one type, each variant the module's own error with its
//! sources kept, so an application can handle them once (`?` converts every module error).

use crate::cloud::CloudError;
use crate::fsutil::OutputError;
use crate::geometry::shape::ShapeError;
use crate::geometry::{PoseError, PoseSpecError, QuaternionError};
use crate::grasp::hand::HandError;
use crate::grasp::model::ModelError;
use crate::grasp::{CandidateError, FamilyError};
use crate::robot::RobotError;
use crate::task::{PathError, TaskError};

/// Any error of the graspath library. The message is the module error's own; its
/// [`source`](std::error::Error::source) chain is kept.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// A pose matrix that is not a rigid transform.
    #[error(transparent)]
    Pose(#[from] PoseError),
    /// A pose in a file that cannot be read.
    #[error(transparent)]
    PoseSpec(#[from] PoseSpecError),
    /// Four numbers that are not a unit quaternion.
    #[error(transparent)]
    Quaternion(#[from] QuaternionError),
    /// A shape with sizes or a mesh that cannot be used.
    #[error(transparent)]
    Shape(#[from] ShapeError),
    /// A robot model, chain or configuration.
    #[error(transparent)]
    Robot(#[from] RobotError),
    /// A point cloud or mesh.
    #[error(transparent)]
    Cloud(#[from] CloudError),
    /// A hand model.
    #[error(transparent)]
    Hand(#[from] HandError),
    /// The learned grasp model, its training or generation.
    #[error(transparent)]
    Model(#[from] ModelError),
    /// A candidate file.
    #[error(transparent)]
    Candidates(#[from] CandidateError),
    /// A candidate family on a shape.
    #[error(transparent)]
    Family(#[from] FamilyError),
    /// An object path.
    #[error(transparent)]
    Path(#[from] PathError),
    /// A task (file, builder or limits).
    #[error(transparent)]
    Task(#[from] TaskError),
    /// Writing output files.
    #[error(transparent)]
    Output(#[from] OutputError),
}

/// `Result` with the library's [`Error`].
pub type Result<T> = std::result::Result<T, Error>;
