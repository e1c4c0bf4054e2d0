//! [`Task`]: a checked task, sealed. Its fields are the crate's; users read them through the
//! accessors here and change a task only through [`TaskBuilder`](super::TaskBuilder), [`Task::with_arms`],
//! [`Task::slice`] and [`Task::in_world_frame`], which keep its invariants.

use super::error::TaskError;
use super::path::ObjectPath;
use super::plausibility::TaskWarning;
use super::scene::{Collisions, Gripper, Stroke};
use super::settings::{Limits, Redundancy, SelectionOptions};
use super::timing::TimingSettings;
use crate::collision::{ArmBodies, Body};
use crate::geometry::shape::Shape;
use crate::grasp::{Candidate, CandidateError, CandidateSource};
use crate::manipulability::{JacobianRows, RankedIndex};
use crate::robot::{Chain, Dynamics, RigidBody, TrajectoryIkOptions};
use nalgebra::Isometry3;
use std::borrow::Cow;
use std::ops::Range;
use std::sync::Arc;

/// One arm taking part in the task.
#[derive(Debug, Clone)]
pub struct ArmSetup {
    /// The arm's name (`left`, `right`, or the key in `robot.chains`).
    pub name: String,
    /// Its kinematic chain (poses and Jacobians in the chain's base frame), with the joint
    /// limits as the robot gives them (or as the task narrowed them, `robot.joint_limits`).
    pub chain: Chain,
    /// The chain the IK plans in: `chain` with each revolute joint's range narrowed by the
    /// task's [`Task::ik_limit_margin`] at both ends ([`Chain::with_limit_margin`]), so the
    /// chosen motions keep that margin from the limits. Distances to the limits, the limits'
    /// penalty, timing and the exported robot use `chain`.
    pub ik_chain: Chain,
    /// Where the chain's base is in the task's world frame, `world_from_base`.
    pub world_from_base: Isometry3<f64>,
    /// The arm's bodies (links and hand) when the task checks collisions.
    pub bodies: Option<Arc<ArmBodies>>,
    /// The arm's dynamics model, gravity in its base frame, when the task carries a payload or
    /// ranks by the dynamic manipulability.
    pub dynamics: Option<Arc<Dynamics>>,
}

/// A task ready to score: who, what, where to grasp, and how the object must move. Built by
/// [`TaskBuilder`](super::TaskBuilder) (or [`Task::load`] from a task file), so every value
/// has been checked.
///
/// ```
/// use graspath::grasp::edge_family;
/// use graspath::robot::builtin::{baxter, Arm};
/// use graspath::geometry::shape::Shape;
/// use graspath::task::{Sampling, Step, Task, TimedStep};
/// use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
///
/// let shape = Shape::cuboid([0.06, 0.40, 0.10]).unwrap();
/// let lift = TimedStep::new("lift", Step::translation(Vector3::new(0.0, 0.0, 0.2)));
/// let task = Task::builder("pick")
///     .arm("left", baxter(Arm::Left), Isometry3::identity())
///     .shape(shape.clone())
///     .candidates(edge_family(&shape, 5, 0.02, 0.02).unwrap())
///     .object_motion(
///         Isometry3::from_parts(Translation3::new(0.75, 0.0, -0.1), UnitQuaternion::identity()),
///         vec![lift],
///         Sampling::PerStep(10),
///     )
///     .build()
///     .unwrap();
/// assert_eq!(task.path().samples.len(), 11);
/// assert_eq!(task.ik().ik.max_iterations, 200); // the task default, from `graspath::defaults`
/// ```
#[derive(Debug, Clone)]
pub struct Task {
    /// The task's name (its file, or the name given to the builder), for messages and reports.
    pub(crate) source_name: String,
    /// The robot's name (`baxter` or the URDF robot's name).
    pub(crate) robot_name: String,
    /// The arms used, in the order given.
    pub(crate) arms: Vec<ArmSetup>,
    /// The object's shape (object frame, m), when given: for candidate families and views.
    pub(crate) shape: Option<Shape>,
    /// The grasp candidates (wrist poses in the object frame): held, shared with the results
    /// that refer to them, or produced on demand (a task loaded by
    /// [`Task::from_file_chunked`]) so that a streamed selection never holds them all.
    pub(crate) candidates: CandidateSource,
    /// The largest natural log-likelihood the candidates' scores are relative to: the task's
    /// own candidates', or, for a [`Task::slice`], the whole task's.
    pub(crate) max_log_likelihood: f64,
    /// The sampled object trajectory in the world frame; its first pose is the grasp pose.
    pub(crate) path: ObjectPath,
    /// Which rows of `J` and of the tangent enter `M_T`.
    pub(crate) rows: JacobianRows,
    /// The per-sample index that is ranked (default: `M_T`).
    pub(crate) ranked: RankedIndex,
    /// How candidates are ranked.
    pub(crate) selection: SelectionOptions,
    /// Trajectory IK settings.
    pub(crate) ik: TrajectoryIkOptions,
    /// How far inside its limits the IK keeps every revolute joint (rad; `ik.limit_margin`,
    /// default [`crate::defaults::IK_LIMIT_MARGIN`]; 0 plans up to the limits, as the paper does):
    /// each arm's [`ArmSetup::ik_chain`].
    pub(crate) ik_limit_margin: f64,
    /// How the arm's self-motion is chosen (`ik.redundancy`).
    pub(crate) redundancy: Redundancy,
    /// The bounds the task was checked against.
    pub(crate) limits: Limits,
    /// The tool's straight approach to the grasp, if any.
    pub(crate) approach: Option<Stroke>,
    /// The tool's straight retreat after the place, if any.
    pub(crate) retreat: Option<Stroke>,
    /// The gripper: grasps wider than its opening are infeasible (`gripper_width`).
    pub(crate) gripper: Option<Gripper>,
    /// Collision checks against the scene, the arm itself and the other arm (`None`: the
    /// task says nothing about its world and nothing is checked).
    pub(crate) collisions: Option<Collisions>,
    /// The object's body (object frame) for the gripper and collision checks, when its shape
    /// is known and either is asked for.
    pub(crate) object_body: Option<Arc<Body>>,
    /// The object's mass properties (object frame: kg, m, kg·m² about its centre of mass),
    /// when the task gives its mass: the arm carries it from the grasp to the place, and the
    /// joint torques along the motion are checked against the arm's effort limits.
    pub(crate) payload: Option<RigidBody>,
    /// How each feasible candidate's motion is timed (`None`: not timed).
    pub(crate) timing: Option<TimingSettings>,
    /// Values that are probably mistakes (degrees in a radians field, millimetres, an object
    /// starting inside the table, ...): warnings, not errors — the task is scored as written.
    pub(crate) warnings: Vec<TaskWarning>,
}

impl Task {
    /// The same task seen from another world frame: the object path and every arm base moved by
    /// `new_world_from_world`. Scores and rankings must not change.
    pub fn in_world_frame(&self, new_world_from_world: &Isometry3<f64>) -> Self {
        let mut moved = self.clone();
        moved.path = self.path.transformed(new_world_from_world);
        for arm in &mut moved.arms {
            arm.world_from_base = new_world_from_world * arm.world_from_base;
        }
        moved
    }

    /// How many candidates the task has (held or produced on demand).
    pub fn candidate_count(&self) -> usize {
        self.candidates.len()
    }

    /// The largest natural log-likelihood the candidates' ranking scores are relative to
    /// (`−∞` without any; 0 for a family, whose candidates are equally likely): the task's own
    /// candidates', or, for a [`Task::slice`], the whole task's.
    pub fn max_log_likelihood(&self) -> f64 {
        self.max_log_likelihood
    }

    /// Calls `consume` with the candidates in order, at most `size` (≥ 1) at a time; stops at
    /// the first error. Candidates produced on demand are computed or read chunk by chunk and
    /// dropped after their call; a candidate file that can no longer be read is an error.
    pub fn for_each_candidate_chunk<E: From<CandidateError>>(
        &self,
        size: usize,
        consume: impl FnMut(&[Arc<Candidate>]) -> Result<(), E>,
    ) -> Result<(), E> {
        self.candidates.for_each_chunk(size, consume)
    }

    /// The candidate at position `index` in candidate order (`None` past the end); read from
    /// the candidate file when the task reads its candidates in chunks.
    pub fn candidate_at(&self, index: usize) -> Result<Option<Arc<Candidate>>, CandidateError> {
        self.candidates.candidate(index)
    }

    /// Every candidate, in order: borrowed when held, else produced all at once.
    pub fn all_candidates(&self) -> Result<Cow<'_, [Arc<Candidate>]>, CandidateError> {
        self.candidates.all()
    }

    /// The same task with only the arms named `names`, in that order (one arm of a two-arm
    /// task, or its arms swapped). Errors name an arm the task does not have or one named
    /// twice (field `arms`).
    pub fn with_arms<S: AsRef<str>>(&self, names: &[S]) -> Result<Task, TaskError> {
        let err = |message: String| TaskError::new(&self.source_name, "arms", message);
        if names.is_empty() {
            return Err(err("name at least one arm".into()));
        }
        let mut arms = Vec::with_capacity(names.len());
        for (k, name) in names.iter().map(AsRef::as_ref).enumerate() {
            if names[..k].iter().any(|n| n.as_ref() == name) {
                return Err(err(format!("arm '{name}' is listed twice")));
            }
            let arm = self.arms.iter().find(|a| a.name == name).ok_or_else(|| {
                let known: Vec<&str> = self.arms.iter().map(|a| a.name.as_str()).collect();
                err(format!("unknown arm '{name}' (arms: {})", known.join(", ")))
            })?;
            arms.push(arm.clone());
        }
        Ok(Task {
            arms,
            ..self.clone()
        })
    }

    /// The same task with only the candidates at the positions `range`, held; their ranking
    /// scores stay relative to the whole task's largest likelihood, so a candidate scores the
    /// same in a slice as in the whole task (ranks are within the slice). Errors: a range
    /// outside `0..candidate_count()` (field `candidates`), a candidate file that can no
    /// longer be read.
    pub fn slice(&self, range: Range<usize>) -> Result<Task, TaskError> {
        let count = self.candidate_count();
        if range.start > range.end || range.end > count {
            return Err(TaskError::new(
                &self.source_name,
                "candidates",
                format!(
                    "({}, {}) is not a candidate range: give 0 <= start <= stop <= {count}",
                    range.start, range.end
                ),
            ));
        }
        let held = self
            .candidates
            .held_range(range)
            .map_err(|e| TaskError::caused_by(&self.source_name, "candidates", e))?;
        Ok(Task {
            candidates: CandidateSource::Held(held),
            ..self.clone()
        })
    }

    /// The task's name (its file, or the name given to the builder), for messages and reports.
    pub fn source_name(&self) -> &str {
        &self.source_name
    }

    /// The robot's name (`baxter` or the URDF robot's name).
    pub fn robot_name(&self) -> &str {
        &self.robot_name
    }

    /// The arms used, in the order given.
    pub fn arms(&self) -> &[ArmSetup] {
        &self.arms
    }

    /// The object's shape (object frame, m), when given.
    pub fn shape(&self) -> Option<&Shape> {
        self.shape.as_ref()
    }

    /// The grasp candidates (wrist poses in the object frame): held or produced on demand.
    pub fn candidates(&self) -> &CandidateSource {
        &self.candidates
    }

    /// The sampled object trajectory in the world frame; its first pose is the grasp pose.
    pub fn path(&self) -> &ObjectPath {
        &self.path
    }

    /// Which rows of `J` and of the tangent enter `M_T`.
    pub fn rows(&self) -> JacobianRows {
        self.rows
    }

    /// The per-sample index that is ranked.
    pub fn ranked(&self) -> RankedIndex {
        self.ranked
    }

    /// How candidates are ranked and paired.
    pub fn selection(&self) -> &SelectionOptions {
        &self.selection
    }

    /// The trajectory IK's settings.
    pub fn ik(&self) -> &TrajectoryIkOptions {
        &self.ik
    }

    /// How far inside its limits the IK keeps every revolute joint (rad; `ik.limit_margin`).
    pub fn ik_limit_margin(&self) -> f64 {
        self.ik_limit_margin
    }

    /// How the arm's self-motion is chosen (`ik.redundancy`).
    pub fn redundancy(&self) -> Redundancy {
        self.redundancy
    }

    /// The bounds the task was checked against.
    pub fn limits(&self) -> &Limits {
        &self.limits
    }

    /// The tool's straight approach to the grasp, if any.
    pub fn approach(&self) -> Option<Stroke> {
        self.approach
    }

    /// The tool's straight retreat after the place, if any.
    pub fn retreat(&self) -> Option<Stroke> {
        self.retreat
    }

    /// The gripper, if given: grasps wider than its opening are infeasible.
    pub fn gripper(&self) -> Option<&Gripper> {
        self.gripper.as_ref()
    }

    /// The collision checks against the scene, the arm itself and the other arm (`None`:
    /// nothing is checked).
    pub fn collisions(&self) -> Option<&Collisions> {
        self.collisions.as_ref()
    }

    /// The object's body (object frame) for the gripper and collision checks.
    pub fn object_body(&self) -> Option<&Arc<Body>> {
        self.object_body.as_ref()
    }

    /// The object's mass properties (object frame: kg, m, kg·m² about its centre of mass),
    /// when the task gives its mass.
    pub fn payload(&self) -> Option<&RigidBody> {
        self.payload.as_ref()
    }

    /// How each feasible candidate's motion is timed (`None`: not timed).
    pub fn timing(&self) -> Option<&TimingSettings> {
        self.timing.as_ref()
    }

    /// Values that are probably mistakes: warnings, not errors.
    pub fn warnings(&self) -> &[TaskWarning] {
        &self.warnings
    }
}
