//! [`Error`]: any error of the library in one type, each variant one module's error with its
//! sources kept, so an application can handle them once (`?` converts every module error), and
//! [`fault_of`]: the classification ([`Fault`]) of any error chain that holds one.

use crate::cloud::CloudError;
use crate::collision::CollisionError;
use crate::fault::{Classify, ErrorKind, Fault};
use crate::geometry::shape::ShapeError;
use crate::geometry::{PoseError, PoseSpecError, QuaternionError};
use crate::grasp::hand::HandError;
use crate::grasp::model::ModelError;
use crate::grasp::{CandidateError, FamilyError, FramePlacementError};
use crate::output_files::OutputError;
use crate::physics::PhysicsError;
use crate::placement::{AxisError, PlacementError};
use crate::robot::RobotError;
use crate::select::PairInputError;
use crate::task::{PathError, TaskError};
use crate::timing::TimingError;
use std::error::Error as StdError;

/// Any error of the graspath library. The message is the module error's own; its
/// [`source`](std::error::Error::source) chain is kept. [`Error::fault`] says what kind of
/// failure it is and which file and field are at fault.
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
    /// A scene, a body or an arm's collision model.
    #[error(transparent)]
    Collision(#[from] CollisionError),
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
    /// A grasp file's frame that cannot be placed in the object frame.
    #[error(transparent)]
    FramePlacement(#[from] FramePlacementError),
    /// A candidate family on a shape.
    #[error(transparent)]
    Family(#[from] FamilyError),
    /// An object path.
    #[error(transparent)]
    Path(#[from] PathError),
    /// A task (file, builder or limits).
    #[error(transparent)]
    Task(#[from] TaskError),
    /// A path that cannot be timed.
    #[error(transparent)]
    Timing(#[from] TimingError),
    /// A world that cannot be written for a physics engine.
    #[error(transparent)]
    Physics(#[from] PhysicsError),
    /// Candidates that cannot be paired for two arms.
    #[error(transparent)]
    Pairs(#[from] PairInputError),
    /// An axis of a placement grid.
    #[error(transparent)]
    Axis(#[from] AxisError),
    /// A placement map.
    #[error(transparent)]
    Placement(#[from] PlacementError),
    /// Writing output files.
    #[error(transparent)]
    Output(#[from] OutputError),
}

/// `Result` with the library's [`Error`].
pub type Result<T> = std::result::Result<T, Error>;

impl Error {
    /// The module error inside.
    fn inner(&self) -> &dyn Classify {
        match self {
            Self::Pose(e) => e,
            Self::PoseSpec(e) => e,
            Self::Quaternion(e) => e,
            Self::Shape(e) => e,
            Self::Robot(e) => e,
            Self::Collision(e) => e,
            Self::Cloud(e) => e,
            Self::Hand(e) => e,
            Self::Model(e) => e,
            Self::Candidates(e) => e,
            Self::FramePlacement(e) => e,
            Self::Family(e) => e,
            Self::Path(e) => e,
            Self::Task(e) => e,
            Self::Timing(e) => e,
            Self::Physics(e) => e,
            Self::Pairs(e) => e,
            Self::Axis(e) => e,
            Self::Placement(e) => e,
            Self::Output(e) => e,
        }
    }

    /// What is at fault: the kind of failure, the file and field, the operating system's error
    /// kind. An error whose chain holds no kind (none does today) is [`ErrorKind::Internal`].
    pub fn fault(&self) -> Fault<'_> {
        fault_of(self).unwrap_or(Fault {
            kind: ErrorKind::Internal,
            file: None,
            field: None,
            io: None,
        })
    }

    /// The kind of failure ([`Error::fault`]'s).
    pub fn kind(&self) -> ErrorKind {
        self.fault().kind
    }
}

impl Classify for Error {
    fn kind(&self) -> Option<ErrorKind> {
        self.inner().kind()
    }

    fn file(&self) -> Option<&str> {
        self.inner().file()
    }

    fn field(&self) -> Option<&str> {
        self.inner().field()
    }
}

/// `error` as a graspath error when it is one: [`Error`] or one of the module errors it holds.
fn classified<'a>(error: &'a (dyn StdError + 'static)) -> Option<&'a dyn Classify> {
    macro_rules! first_of {
        ($($t:ty),* $(,)?) => {
            $(if let Some(e) = error.downcast_ref::<$t>() {
                return Some(e);
            })*
        };
    }
    first_of!(
        Error,
        PoseError,
        PoseSpecError,
        QuaternionError,
        ShapeError,
        RobotError,
        CollisionError,
        CloudError,
        HandError,
        ModelError,
        CandidateError,
        FramePlacementError,
        FamilyError,
        PathError,
        TaskError,
        TimingError,
        PhysicsError,
        PairInputError,
        AxisError,
        PlacementError,
        OutputError,
    );
    None
}

/// What is at fault in an error chain that holds a graspath error (or an I/O error) anywhere,
/// e.g. one an application wrapped in context: the kind of the outermost error that has one,
/// the innermost file and field named. `None` when no error of the chain is classified.
pub fn fault_of<'a>(error: &'a (dyn StdError + 'static)) -> Option<Fault<'a>> {
    Fault::walk(error, classified)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::output_files::{write_file, Existing};
    use std::path::Path;

    /// One error of each module, with the kind it has.
    fn one_of_each() -> Vec<(Error, ErrorKind)> {
        let missing = Path::new("/nonexistent/graspath/missing");
        let pose = crate::geometry::pose_from_rows(&[[f64::NAN; 4]; 4]).unwrap_err();
        let spec = crate::geometry::PoseSpec {
            xyz: Some([f64::NAN, 0.0, 0.0]),
            ..Default::default()
        }
        .to_isometry()
        .unwrap_err();
        let quaternion = crate::geometry::unit_quaternion_xyzw([0.0; 4]).unwrap_err();
        let shape = crate::geometry::shape::Shape::cuboid([0.0, 1.0, 1.0]).unwrap_err();
        let robot = crate::robot::UrdfRobot::from_file(missing).unwrap_err();
        let collision = CollisionError::BadBody {
            what: "table.height".into(),
            message: "must be finite".into(),
        };
        let cloud = crate::cloud::read_cloud(&missing.with_extension("ply")).unwrap_err();
        let hand = HandError::UnknownRoot {
            source_name: "hand.urdf".into(),
            link: "palm".into(),
            links: "base".into(),
        };
        let model = crate::grasp::model::GraspModel::read(missing).unwrap_err();
        let candidates = CandidateError::new("c.json", "line 7", "not a number");
        let frame = FramePlacementError {
            field: "frame",
            message: "no camera pose",
        };
        let family = FamilyError::ZeroCount;
        let path = PathError::TooManySamples {
            count: 1e12,
            limit: 100_000,
        };
        let task = crate::task::TaskFile::load(missing).unwrap_err();
        let timing = TimingError::BadPath("no sample".into());
        let physics = PhysicsError::Mimic {
            chain: "a->b".into(),
        };
        let pairs = PairInputError::NotTwoArms {
            task: "t".into(),
            arms: 1,
        };
        let axis = crate::placement::GridAxis::new(0.0, 1.0, 0, "x").unwrap_err();
        let placement = PlacementError::Axis(axis.clone());
        let output = write_file(Path::new("/dev/null"), b"", Existing::Replace).unwrap_err();
        vec![
            (pose.into(), ErrorKind::Content),
            (spec.into(), ErrorKind::Content),
            (quaternion.into(), ErrorKind::Content),
            (shape.into(), ErrorKind::Content),
            (robot.into(), ErrorKind::File),
            (collision.into(), ErrorKind::Content),
            (cloud.into(), ErrorKind::File),
            (hand.into(), ErrorKind::Content),
            (model.into(), ErrorKind::File),
            (candidates.into(), ErrorKind::Content),
            (frame.into(), ErrorKind::Content),
            (family.into(), ErrorKind::Content),
            (path.into(), ErrorKind::Limit),
            (task.into(), ErrorKind::File),
            (timing.into(), ErrorKind::Content),
            (physics.into(), ErrorKind::Content),
            (pairs.into(), ErrorKind::Content),
            (axis.into(), ErrorKind::Content),
            (placement.into(), ErrorKind::Content),
            (output.into(), ErrorKind::File),
        ]
    }

    #[test]
    fn every_module_error_converts_and_is_classified() {
        let errors = one_of_each();
        // One of each variant: adding a module error means adding it here.
        let variants: std::collections::HashSet<_> = errors
            .iter()
            .map(|(e, _)| std::mem::discriminant(e))
            .collect();
        assert_eq!(variants.len(), errors.len());
        for (error, kind) in &errors {
            assert_eq!(error.kind(), *kind, "{error}");
            // The module error alone, inside an application's own error, is found too.
            let inner: &(dyn StdError + 'static) = match error {
                Error::Robot(e) => e,
                Error::Task(e) => e,
                Error::Output(e) => e,
                other => other,
            };
            assert_eq!(fault_of(inner).map(|f| f.kind), Some(*kind), "{error}");
        }
    }

    #[test]
    fn a_missing_file_is_named_with_its_io_kind() {
        let missing = Path::new("/nonexistent/graspath/t.yaml");
        let error = Error::from(crate::task::TaskFile::load(missing).unwrap_err());
        let fault = error.fault();
        assert_eq!(fault.kind, ErrorKind::File);
        assert_eq!(fault.file, Some("/nonexistent/graspath/t.yaml"));
        assert_eq!(fault.io, Some(std::io::ErrorKind::NotFound));
        assert!(crate::Chain(&error)
            .to_string()
            .starts_with("/nonexistent/graspath/t.yaml: cannot read: "));
    }

    /// The names of the public error types declared in the library's sources under `dir`
    /// (`pub enum NameError` / `pub struct NameError`).
    fn declared_errors(dir: &Path, names: &mut Vec<String>) {
        for entry in std::fs::read_dir(dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                declared_errors(&path, names);
            } else if path.extension().is_some_and(|e| e == "rs") {
                let text = std::fs::read_to_string(&path).unwrap();
                for line in text.lines() {
                    let declared = line
                        .trim_start()
                        .strip_prefix("pub enum ")
                        .or_else(|| line.trim_start().strip_prefix("pub struct "));
                    let Some(rest) = declared else { continue };
                    let name: String = rest
                        .chars()
                        .take_while(|c| c.is_alphanumeric() || *c == '_')
                        .collect();
                    if name.ends_with("Error") {
                        names.push(name);
                    }
                }
            }
        }
    }

    #[test]
    fn every_public_error_type_converts_into_the_error_and_is_classified() {
        // Oracle: the library's sources, not a list kept by hand. Every public error type but
        // `Error` itself has a `#[from]` variant and is found in error chains.
        let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
        let mut names = Vec::new();
        declared_errors(&src, &mut names);
        names.retain(|n| n != "Error");
        assert!(names.len() >= 20, "{names:?}");
        let this = std::fs::read_to_string(src.join("error.rs")).unwrap();
        let classified_list = this
            .split("first_of!(")
            .nth(1)
            .and_then(|rest| rest.split(");").next())
            .unwrap();
        let listed: Vec<&str> = classified_list
            .split(',')
            .map(str::trim)
            .filter(|n| !n.is_empty())
            .collect();
        for name in &names {
            assert!(
                this.contains(&format!("(#[from] {name})")),
                "{name} has no From into graspath::Error"
            );
            assert!(
                listed.contains(&name.as_str()),
                "{name} is not found in error chains"
            );
        }
    }

    #[test]
    fn an_unclassified_chain_has_no_fault() {
        let other = std::fmt::Error;
        assert!(fault_of(&other).is_none());
    }
}
