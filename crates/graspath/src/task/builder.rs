//! [`Task`] and its one checked constructor, [`TaskBuilder`]: the task-file loader, the Python
//! bindings and library users all build tasks through it, so every default and every check is
//! applied in one place and the same task gives the same results however it was written.

use super::error::TaskError;
use super::path::{ObjectPath, Sampling, TimedStep};
use super::plausibility::TaskWarning;
use super::scene::{Collisions, Gripper, SceneSettings, Stroke, WorldInput};
pub(crate) use super::settings::check_count;
use super::settings::{LikelihoodRule, Limits, Redundancy, SelectionOptions};
use super::timing::{TimingRequest, TimingSettings};
use crate::collision::{ArmBodies, Body};
use crate::defaults;
use crate::geometry::shape::Shape;
use crate::grasp::{Candidate, CandidateError, CandidateSource};
use crate::manipulability::{IndexMeasure, JacobianRows, Norm, RankedIndex};
use crate::robot::{Chain, Dynamics, IkOptions, RigidBody, TrajectoryIkOptions};
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
/// [`TaskBuilder`] (or [`Task::load`] from a task file), so every value has been checked.
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
    /// default [`defaults::IK_LIMIT_MARGIN`]; 0 plans up to the limits, as the paper does):
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
    /// A builder for a task named `name` (the name appears in errors and reports).
    pub fn builder(name: impl Into<String>) -> TaskBuilder {
        TaskBuilder::new(name)
    }

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

    /// The work estimate of this task in kinematics evaluations (see [`Limits::max_work`]):
    /// the total of [`Task::work_estimate`].
    pub fn work(&self) -> u64 {
        self.work_estimate().total()
    }

    /// An upper bound on the memory (bytes) of this task's selection held whole
    /// ([`select`](crate::select::select)): per arm and candidate, its record and every
    /// sample's joint values (approach, path, retreat), `M_T` and limit distance.
    pub fn selection_memory(&self) -> u64 {
        const RECORD_BYTES: u64 = 1024;
        const VEC_BYTES: u64 = 24;
        let samples = (self.path.samples.len()
            + self.approach.map_or(0, |s| s.samples)
            + self.retreat.map_or(0, |s| s.samples)) as u64;
        let candidates = self.candidate_count() as u64;
        self.arms
            .iter()
            .map(|arm| {
                let per_sample = VEC_BYTES + 8 * arm.chain.dof() as u64 + 16 + 8;
                candidates
                    .saturating_mul(RECORD_BYTES.saturating_add(samples.saturating_mul(per_sample)))
            })
            .fold(0u64, u64::saturating_add)
    }

    /// `Ok` when [`Task::selection_memory`] is within `limits.max_memory_mib`; else an error
    /// that names the limit and the streamed formats that need no such memory. Called before
    /// a selection is held whole (`select --format json`, Python's `select`).
    pub fn check_selection_memory(&self) -> Result<(), TaskError> {
        let bytes = self.selection_memory();
        let limit = self.limits.max_memory_mib.saturating_mul(1 << 20);
        if bytes <= limit {
            return Ok(());
        }
        Err(TaskError::new(
            &self.source_name,
            "limits.max_memory_mib",
            format!(
                "holding the whole selection ({} arm(s) × {} candidates with their joint \
                 trajectories) takes about {} MiB, more than the limit {} MiB: stream it \
                 (JSON Lines or Parquet records, Python `select_batch`) or raise \
                 limits.max_memory_mib",
                self.arms.len(),
                self.candidate_count(),
                bytes >> 20,
                self.limits.max_memory_mib,
            ),
        ))
    }

    /// Whether the two arms' motions are checked against each other (a scene with
    /// `collision.between_arms`, two arms, and bodies for both).
    pub fn checks_arms_against_each_other(&self) -> bool {
        self.collisions
            .as_ref()
            .is_some_and(|c| c.options.between_arms)
            && self.arms.len() >= 2
            && self.arms[0].bodies.is_some()
            && self.arms[1].bodies.is_some()
    }

    /// The work estimate of this task by part, in kinematics evaluations: an upper bound on
    /// scoring (IK along every branch), on the collision checks against the scene, and on
    /// the two-arm pair search when no pair is valid (every pair visited).
    pub fn work_estimate(&self) -> WorkEstimate {
        let samples = self.path.samples.len()
            + self.approach.map_or(0, |s| s.samples)
            + self.retreat.map_or(0, |s| s.samples);
        let candidates = self.candidate_count() as u64;
        let scoring = Limits::work(
            self.arms.len(),
            self.candidate_count(),
            samples,
            self.ik.branches,
            self.ik.ik.max_iterations,
            self.ik.per_sample_iterations,
        );
        let bodies = |arm: &ArmSetup| arm.bodies.as_ref().map_or(0, |b| b.bodies.len()) as u64;
        let scene_bodies = self
            .collisions
            .as_ref()
            .map_or(0, |c| c.scene.bodies().len() as u64);
        // Every moving body and the object against every scene body, at every sample of
        // every branch.
        let collisions = self
            .arms
            .iter()
            .map(|arm| {
                candidates
                    .saturating_mul(self.ik.branches as u64)
                    .saturating_mul(samples as u64)
                    .saturating_mul(bodies(arm).saturating_add(1))
                    .saturating_mul(scene_bodies)
                    / WorkEstimate::COLLISION_PAIRS_PER_EVALUATION
            })
            .fold(0u64, u64::saturating_add);
        let pairs = if self.arms.len() == 2 {
            let visited = candidates.saturating_mul(candidates);
            let between = if self.checks_arms_against_each_other() {
                visited
                    .saturating_mul(samples as u64)
                    .saturating_mul(bodies(&self.arms[0]).saturating_mul(bodies(&self.arms[1])))
                    / WorkEstimate::COLLISION_PAIRS_PER_EVALUATION
            } else {
                0
            };
            (visited / WorkEstimate::PAIR_VISITS_PER_EVALUATION).saturating_add(between)
        } else {
            0
        };
        let per_candidate = |evaluations_per_sample: u64| -> u64 {
            (self.arms.len() as u64)
                .saturating_mul(candidates)
                .saturating_mul(samples as u64)
                .saturating_mul(evaluations_per_sample)
        };
        let self_motion = if self.redundancy == Redundancy::Optimize {
            per_candidate(WorkEstimate::SELF_MOTION_EVALUATIONS_PER_SAMPLE)
        } else {
            0
        };
        let timing = self.timing.as_ref().map_or(0, |t| {
            let per_grid_point = if t.torque_limits {
                WorkEstimate::TIMING_EVALUATIONS_PER_TORQUE_POINT
            } else {
                1
            };
            per_candidate((t.subdivisions as u64).saturating_mul(per_grid_point))
        });
        WorkEstimate {
            scoring,
            self_motion,
            timing,
            collisions,
            pairs,
        }
    }
}

/// The object path, given sampled or as steps to sample.
#[derive(Debug, Clone)]
enum PathInput {
    Sampled(ObjectPath),
    Steps {
        world_from_object: Isometry3<f64>,
        steps: Vec<TimedStep>,
        sampling: Sampling,
    },
}

/// Builds a checked [`Task`]. Settings left unset take the values in
/// [`defaults`](crate::defaults); [`TaskBuilder::build`] checks every value and names the
/// offending setting by its task-file field (`ik.iterations`, `selection.mu0`, …).
#[derive(Debug, Clone)]
pub struct TaskBuilder {
    name: String,
    robot_name: Option<String>,
    arms: Vec<ArmSetup>,
    shape: Option<Shape>,
    candidates: CandidateSource,
    path: Option<PathInput>,
    rows: JacobianRows,
    ranked: RankedIndex,
    norm: Norm,
    mu0: Option<f64>,
    likelihood: LikelihoodRule,
    pairs: usize,
    min_separation: f64,
    min_clearance: Option<f64>,
    min_torque_margin: Option<f64>,
    tie_tolerance: f64,
    max_joint_step: f64,
    ik_limit_margin: f64,
    ik_branches: usize,
    ik_random_seed: u64,
    ik_tolerance: f64,
    grasp_ik_iterations: usize,
    redundancy: Redundancy,
    limits: Limits,
    approach: Option<Stroke>,
    retreat: Option<Stroke>,
    gripper: Option<Gripper>,
    scene: Option<SceneSettings>,
    payload: Option<RigidBody>,
    timing: TimingRequest,
    max_duration: Option<f64>,
    warnings: Vec<TaskWarning>,
}

impl TaskBuilder {
    /// A builder with every setting at its default.
    pub fn new(name: impl Into<String>) -> Self {
        Self {
            name: name.into(),
            robot_name: None,
            arms: Vec::new(),
            shape: None,
            candidates: CandidateSource::Held(Vec::new()),
            path: None,
            rows: JacobianRows::default(),
            ranked: RankedIndex::default(),
            norm: Norm::default(),
            mu0: None,
            likelihood: LikelihoodRule::default(),
            pairs: defaults::PAIRS,
            min_separation: defaults::MIN_SEPARATION,
            min_clearance: None,
            min_torque_margin: None,
            tie_tolerance: defaults::TIE_TOLERANCE,
            max_joint_step: defaults::MAX_JOINT_STEP,
            ik_limit_margin: defaults::IK_LIMIT_MARGIN,
            ik_branches: defaults::IK_BRANCHES,
            ik_random_seed: defaults::IK_RANDOM_SEED,
            ik_tolerance: defaults::IK_TOLERANCE,
            grasp_ik_iterations: defaults::GRASP_IK_ITERATIONS,
            redundancy: Redundancy::default(),
            limits: Limits::default(),
            approach: None,
            retreat: None,
            gripper: None,
            scene: None,
            payload: None,
            timing: TimingRequest::Auto,
            max_duration: None,
            warnings: Vec::new(),
        }
    }

    /// The robot's name for reports (default: `robot`).
    pub fn robot_name(mut self, name: impl Into<String>) -> Self {
        self.robot_name = Some(name.into());
        self
    }

    /// Adds an arm: its chain and where its base is in the world frame (`world_from_base`).
    /// Arms are scored in the order added; the first two form the pairs.
    pub fn arm(
        mut self,
        name: impl Into<String>,
        chain: Chain,
        world_from_base: Isometry3<f64>,
    ) -> Self {
        self.arms.push(ArmSetup {
            name: name.into(),
            ik_chain: chain.clone(),
            chain,
            world_from_base,
            bodies: None,
            dynamics: None,
        });
        self
    }

    /// The object's mass properties (object frame: kg, m, kg·m² about the centre of mass): the
    /// arm carries it from the grasp to the place, and the joint torques along the motion are
    /// checked against each arm's effort limits (every arm then needs inertial data).
    pub fn payload(mut self, body: RigidBody) -> Self {
        self.payload = Some(body);
        self
    }

    /// Whether and how each feasible candidate's motion is timed (default:
    /// [`TimingRequest::Auto`]).
    pub fn timing(mut self, timing: TimingRequest) -> Self {
        self.timing = timing;
        self
    }

    /// Reject candidates whose timed motion takes longer than `seconds` (default: none; needs
    /// timing).
    pub fn max_duration(mut self, seconds: Option<f64>) -> Self {
        self.max_duration = seconds;
        self
    }

    /// Warnings about how the task was written (the loader's: units and conventions, see
    /// `task::plausibility`); [`TaskBuilder::build`] adds those about the world at the
    /// start.
    pub fn warnings(mut self, warnings: Vec<TaskWarning>) -> Self {
        self.warnings = warnings;
        self
    }

    /// The object's shape (object frame, m).
    pub fn shape(mut self, shape: Shape) -> Self {
        self.shape = Some(shape);
        self
    }

    /// The grasp candidates, `object_from_wrist` with log-likelihoods.
    pub fn candidates(mut self, candidates: Vec<Candidate>) -> Self {
        self.candidates = CandidateSource::Held(candidates.into_iter().map(Arc::new).collect());
        self
    }

    /// The grasp candidates held or produced on demand (see [`Task::candidates`]); replaces
    /// [`candidates`](Self::candidates).
    pub fn candidate_source(mut self, source: CandidateSource) -> Self {
        self.candidates = source;
        self
    }

    /// The object trajectory as an already sampled path (world frame).
    pub fn object_path(mut self, path: ObjectPath) -> Self {
        self.path = Some(PathInput::Sampled(path));
        self
    }

    /// The object trajectory as steps from `world_from_object`, sampled by `build` (after the
    /// sample count has been checked against the limits).
    pub fn object_motion(
        mut self,
        world_from_object: Isometry3<f64>,
        steps: Vec<TimedStep>,
        sampling: Sampling,
    ) -> Self {
        self.path = Some(PathInput::Steps {
            world_from_object,
            steps,
            sampling,
        });
        self
    }

    /// The object's start pose `world_from_object` when its trajectory is given as steps
    /// ([`object_motion`](Self::object_motion)); `None` for an already sampled path or none.
    pub fn object_start(&self) -> Option<Isometry3<f64>> {
        match &self.path {
            Some(PathInput::Steps {
                world_from_object, ..
            }) => Some(*world_from_object),
            _ => None,
        }
    }

    /// Moves the object's start pose to `world_from_object`, keeping its steps and sampling:
    /// relative steps (`lift`, `move`, `rotate`, `place`) start from the new pose, absolute
    /// `pose` steps stay where they are. The task is the one a task file with this
    /// `object.pose` describes. Errors (naming `trajectory`) when the path is not given as
    /// steps.
    pub fn with_object_start(
        mut self,
        world_from_object: Isometry3<f64>,
    ) -> Result<Self, TaskError> {
        match &mut self.path {
            Some(PathInput::Steps {
                world_from_object: start,
                ..
            }) => {
                *start = world_from_object;
                Ok(self)
            }
            _ => Err(TaskError::new(
                &self.name,
                "trajectory",
                "the object's start pose can be moved only for a trajectory given as steps \
                 from object.pose"
                    .to_string(),
            )),
        }
    }

    /// Which rows of `J` and of the tangent enter `M_T` (default: the full twist, L = 1 m).
    pub fn rows(mut self, rows: JacobianRows) -> Self {
        self.rows = rows;
        self
    }

    /// The norm to maximise (default `μ_l2`).
    pub fn norm(mut self, norm: Norm) -> Self {
        self.norm = norm;
        self
    }

    /// Reject candidates whose `μ_l∞` exceeds `mu0` (default: no bound).
    pub fn mu0(mut self, mu0: Option<f64>) -> Self {
        self.mu0 = mu0;
        self
    }

    /// How the likelihood combines with the norm (default: the product).
    pub fn likelihood(mut self, rule: LikelihoodRule) -> Self {
        self.likelihood = rule;
        self
    }

    /// How many best arm pairs to keep.
    pub fn pairs(mut self, pairs: usize) -> Self {
        self.pairs = pairs;
        self
    }

    /// Two grasps closer than this overlap (m, object frame).
    pub fn min_separation(mut self, metres: f64) -> Self {
        self.min_separation = metres;
        self
    }

    /// With a payload: reject candidates whose torque margin along the motion is below
    /// `margin` (in [0, 1]; default: none).
    pub fn min_torque_margin(mut self, margin: Option<f64>) -> Self {
        self.min_torque_margin = margin;
        self
    }

    /// Reject candidates whose clearance from the scene is below `metres` (default: none).
    pub fn min_clearance(mut self, metres: Option<f64>) -> Self {
        self.min_clearance = metres;
        self
    }

    /// Scores within this relative difference are reported as tied (default
    /// [`defaults::TIE_TOLERANCE`]; absolute for the weighted likelihood rule's log score).
    pub fn tie_tolerance(mut self, tolerance: f64) -> Self {
        self.tie_tolerance = tolerance;
        self
    }

    /// Largest joint motion between consecutive samples (rad or m).
    pub fn max_joint_step(mut self, step: f64) -> Self {
        self.max_joint_step = step;
        self
    }

    /// How far inside its limits the IK keeps every revolute joint (rad; 0: up to the
    /// limits). See [`Task::ik_limit_margin`].
    pub fn ik_limit_margin(mut self, margin: f64) -> Self {
        self.ik_limit_margin = margin;
        self
    }

    /// Distinct IK branches searched from the grasp pose.
    pub fn ik_branches(mut self, branches: usize) -> Self {
        self.ik_branches = branches;
        self
    }

    /// Random seed of the IK's restarts (task file `ik.random_seed`; not a start configuration).
    pub fn ik_random_seed(mut self, seed: u64) -> Self {
        self.ik_random_seed = seed;
        self
    }

    /// Position (m) and rotation (rad) tolerance of IK.
    pub fn ik_tolerance(mut self, tolerance: f64) -> Self {
        self.ik_tolerance = tolerance;
        self
    }

    /// The IK iteration budget of the grasp sample, over all restarts.
    pub fn grasp_ik_iterations(mut self, iterations: usize) -> Self {
        self.grasp_ik_iterations = iterations;
        self
    }

    /// The per-sample index that is ranked (default: the paper's `M_T`, no penalty).
    pub fn ranked(mut self, ranked: RankedIndex) -> Self {
        self.ranked = ranked;
        self
    }

    /// How the arm's self-motion is chosen along the path.
    pub fn redundancy(mut self, redundancy: Redundancy) -> Self {
        self.redundancy = redundancy;
        self
    }

    /// The bounds the task is checked against (default [`Limits::default`]).
    pub fn limits(mut self, limits: Limits) -> Self {
        self.limits = limits;
        self
    }

    /// The tool's straight approach to the grasp (default: none; the motion starts at the
    /// grasp).
    pub fn approach(mut self, stroke: Stroke) -> Self {
        self.approach = Some(stroke);
        self
    }

    /// The tool's straight retreat after the place (default: none).
    pub fn retreat(mut self, stroke: Stroke) -> Self {
        self.retreat = Some(stroke);
        self
    }

    /// The gripper (default: none; no width check, no hand bodies).
    pub fn gripper(mut self, gripper: Gripper) -> Self {
        self.gripper = Some(gripper);
        self
    }

    /// The scene and collision settings (default: none; nothing is checked for collisions).
    pub fn scene(mut self, settings: SceneSettings) -> Self {
        self.scene = Some(settings);
        self
    }

    /// Checks every setting and builds the task.
    pub fn build(self) -> Result<Task, TaskError> {
        let err = |field: &str, message: String| TaskError::new(&self.name, field, message);
        let limits = self.limits;
        if self.arms.is_empty() {
            return Err(err("arms", "name at least one arm".into()));
        }
        for (k, arm) in self.arms.iter().enumerate() {
            if self.arms[..k].iter().any(|a| a.name == arm.name) {
                return Err(err(
                    &format!("arms[{k}]"),
                    format!("arm '{}' is listed twice", arm.name),
                ));
            }
        }
        let count = self.candidates.len();
        check_count("candidates", count, limits.max_candidates, "max_candidates")
            .map_err(|m| err("candidates", m))?;
        if count == 0 {
            return Err(err("candidates", "give at least one candidate".into()));
        }
        if let JacobianRows::Twist { length_scale } = self.rows {
            if !(length_scale.is_finite() && length_scale > 0.0) {
                return Err(err(
                    "index.length_scale",
                    "must be a positive length in metres".into(),
                ));
            }
        }
        if let Some(k) = self.ranked.joint_limit_penalty {
            if !(k.is_finite() && k > 0.0) {
                return Err(err(
                    "index.joint_limit_penalty",
                    format!("the penalty's gain k must be a positive number, got {k}"),
                ));
            }
        }
        if let Some(mu0) = self.mu0 {
            if mu0.is_nan() || mu0 <= 0.0 {
                return Err(err("selection.mu0", "must be a positive number".into()));
            }
        }
        if let LikelihoodRule::Weighted { weight } = self.likelihood {
            if !(weight.is_finite() && weight >= 0.0) {
                return Err(err(
                    "selection.likelihood.weighted.weight",
                    "must be a number ≥ 0".into(),
                ));
            }
        }
        if !(self.min_separation.is_finite() && self.min_separation >= 0.0) {
            return Err(err(
                "selection.min_separation",
                "must be a distance ≥ 0 in metres".into(),
            ));
        }
        if let Some(min) = self.min_clearance {
            if !(min.is_finite() && min >= 0.0) {
                return Err(err(
                    "selection.min_clearance",
                    format!("must be a distance ≥ 0 in metres, got {min}"),
                ));
            }
        }
        if let Some(min) = self.min_torque_margin {
            if !(0.0..=1.0).contains(&min) {
                return Err(err(
                    "selection.min_torque_margin",
                    format!("must be a fraction of the effort limits in [0, 1], got {min}"),
                ));
            }
            if self.payload.is_none() {
                return Err(err(
                    "selection.min_torque_margin",
                    "needs the object's mass (object.mass or object.density): without it no \
                     torque is computed"
                        .into(),
                ));
            }
        }
        let timing = resolve_timing(self.timing, &self.arms).map_err(|(f, m)| err(f, m))?;
        if let Some(max) = self.max_duration {
            if !(max > 0.0 && max.is_finite()) {
                return Err(err(
                    "selection.max_duration",
                    format!("must be a positive duration in seconds, got {max}"),
                ));
            }
            if timing.is_none() {
                return Err(err(
                    "selection.max_duration",
                    "needs the motions timed (timing), which is off for this task".into(),
                ));
            }
        }
        let by_duration = self.ranked.measure == IndexMeasure::Duration;
        if by_duration {
            if timing.is_none() {
                return Err(err(
                    "index.measure",
                    "duration needs the motions timed (timing), which is off for this task".into(),
                ));
            }
            if self.ranked.joint_limit_penalty.is_some() {
                return Err(err(
                    "index.joint_limit_penalty",
                    "multiplies a per-sample index; it does not apply to measure duration".into(),
                ));
            }
        }
        if !(self.tie_tolerance.is_finite() && (0.0..1.0).contains(&self.tie_tolerance)) {
            return Err(err(
                "selection.tie_tolerance",
                format!(
                    "must be a relative difference in [0, 1), got {}",
                    self.tie_tolerance
                ),
            ));
        }
        if !(self.max_joint_step.is_finite() && self.max_joint_step > 0.0) {
            return Err(err(
                "ik.max_joint_step",
                "must be a positive angle in radians".into(),
            ));
        }
        if !(self.ik_limit_margin.is_finite() && (0.0..=0.5).contains(&self.ik_limit_margin)) {
            return Err(err(
                "ik.limit_margin",
                format!(
                    "must be an angle in radians from 0 to 0.5, got {}",
                    self.ik_limit_margin
                ),
            ));
        }
        if self.ik_branches == 0 {
            return Err(err("ik.branches", "must be at least 1".into()));
        }
        check_count(
            "ik.branches",
            self.ik_branches,
            limits.max_ik_branches,
            "max_ik_branches",
        )
        .map_err(|m| err("ik.branches", m))?;
        if self.grasp_ik_iterations == 0 {
            return Err(err("ik.iterations", "must be at least 1".into()));
        }
        check_count(
            "ik.iterations",
            self.grasp_ik_iterations,
            limits.max_ik_iterations,
            "max_ik_iterations",
        )
        .map_err(|m| err("ik.iterations", m))?;
        if !(self.ik_tolerance.is_finite() && self.ik_tolerance > 0.0) {
            return Err(err("ik.tolerance", "must be positive".into()));
        }
        // It bounds both the position (m) and the rotation (rad) error: beyond a metre any
        // pose would count as reached.
        if self.ik_tolerance > 1.0 {
            return Err(err(
                "ik.tolerance",
                format!(
                    "{:e} accepts almost any pose (it bounds the position error in m and the rotation error in rad); at most 1",
                    self.ik_tolerance
                ),
            ));
        }
        let path = match self.path {
            None => return Err(err("trajectory", "give the object's trajectory".into())),
            Some(PathInput::Sampled(path)) => path,
            Some(PathInput::Steps {
                world_from_object,
                steps,
                sampling,
            }) => ObjectPath::sample(world_from_object, &steps, sampling, limits.max_samples)
                .map_err(|e| err(&e.field(), e.to_string()))?,
        };
        check_count(
            "samples",
            path.samples.len(),
            limits.max_samples,
            "max_samples",
        )
        .map_err(|m| err("trajectory", m))?;
        if path.samples.is_empty() {
            return Err(err("trajectory", "give at least one object pose".into()));
        }
        if path.samples.iter().any(|s| !s.time.is_finite())
            || path.samples.windows(2).any(|w| w[1].time < w[0].time)
        {
            return Err(err(
                "trajectory",
                "sample times must be finite and non-decreasing (s)".into(),
            ));
        }
        let ik = TrajectoryIkOptions {
            ik: IkOptions {
                position_tolerance: self.ik_tolerance,
                rotation_tolerance: self.ik_tolerance,
                max_time: None,
                max_iterations: self.grasp_ik_iterations,
                random_seed: self.ik_random_seed,
            },
            max_joint_step: self.max_joint_step,
            branches: self.ik_branches,
            per_sample_iterations: defaults::PER_SAMPLE_IK_ITERATIONS,
        };
        let mut arms = self.arms;
        for arm in &mut arms {
            arm.ik_chain = arm.chain.with_limit_margin(self.ik_limit_margin);
        }
        let (collisions, bodies) = super::scene::check_world(
            WorldInput {
                approach: self.approach.as_ref(),
                retreat: self.retreat.as_ref(),
                gripper: self.gripper.as_ref(),
                scene: self.scene,
            },
            arms.iter().map(|a| &a.chain),
            &limits,
        )
        .map_err(|(field, m)| err(&field, m))?;
        for (arm, bodies) in arms.iter_mut().zip(bodies) {
            arm.bodies = bodies;
        }
        if let Some(payload) = &self.payload {
            super::payload::check_payload(payload).map_err(|m| err("object.mass", m))?;
            for arm in &mut arms {
                let model = super::payload::arm_dynamics(
                    &arm.name,
                    &arm.chain,
                    &arm.world_from_base,
                    "the object's mass asks for the joint torques along the task",
                )
                .map_err(|m| err("object.mass", m))?;
                arm.dynamics = Some(Arc::new(model));
            }
        }
        if self.ranked.measure == IndexMeasure::Dynamic {
            for arm in &mut arms {
                let why = "index.measure dynamic weighs the joints by their torques";
                if arm.dynamics.is_none() {
                    let model = super::payload::arm_dynamics(
                        &arm.name,
                        &arm.chain,
                        &arm.world_from_base,
                        why,
                    )
                    .map_err(|m| err("index.measure", m))?;
                    arm.dynamics = Some(Arc::new(model));
                }
                let unlimited = arm
                    .chain
                    .motion_limits()
                    .iter()
                    .zip(arm.chain.joint_names())
                    .find(|(l, _)| !l.effort.is_some_and(|e| e.is_finite() && e > 0.0));
                if let Some((_, joint)) = unlimited {
                    return Err(err(
                        "index.measure",
                        format!(
                            "arm '{}': joint '{joint}' has no effort limit; {why}",
                            arm.name
                        ),
                    ));
                }
            }
        }
        let object_body = (collisions.is_some() || self.gripper.is_some())
            .then_some(self.shape.as_ref())
            .flatten()
            .map(|shape| Arc::new(Body::from_shape("object", shape)));
        if let (Some(collisions), Some(object)) = (&collisions, &object_body) {
            super::scene::check_object_clear(collisions, object, &path)
                .map_err(|(field, m)| err(&field, m))?;
        }
        let mut task = Task {
            source_name: self.name.clone(),
            robot_name: self.robot_name.unwrap_or_else(|| "robot".into()),
            arms,
            shape: self.shape,
            max_log_likelihood: self.candidates.max_log_likelihood(),
            candidates: self.candidates,
            path,
            rows: self.rows,
            ranked: self.ranked,
            selection: SelectionOptions {
                norm: self.norm,
                mu0: self.mu0,
                likelihood: self.likelihood,
                pairs: self.pairs,
                min_separation: self.min_separation,
                min_clearance: self.min_clearance,
                min_torque_margin: self.min_torque_margin,
                max_duration: self.max_duration,
                by_duration,
                tie_tolerance: self.tie_tolerance,
            },
            ik,
            ik_limit_margin: self.ik_limit_margin,
            redundancy: self.redundancy,
            limits,
            approach: self.approach,
            retreat: self.retreat,
            gripper: self.gripper,
            collisions,
            object_body,
            payload: self.payload,
            timing,
            warnings: self.warnings,
        };
        if let Some(start) = task.path.samples.first() {
            let table = task.collisions.as_ref().and_then(|c| c.scene.table());
            let world = super::plausibility::world_warnings(
                &start.world_from_object,
                task.shape.as_ref(),
                table,
            );
            task.warnings.extend(world);
        }
        let estimate = task.work_estimate();
        let work = estimate.total();
        if work > limits.max_work {
            return Err(TaskError::new(
                &self.name,
                "limits.max_work",
                format!(
                    "the task asks for about {:.3e} kinematics evaluations, more than the limit \
                     {:.3e}: {}; reduce the task or raise limits.max_work",
                    work as f64,
                    limits.max_work as f64,
                    estimate.explain(&task),
                ),
            ));
        }
        Ok(task)
    }
}

/// A task's work estimate by part, in kinematics evaluations (one forward kinematics and
/// Jacobian of one arm; [`Limits::max_work`]). Each part is an upper bound measured against
/// release builds (BENCHMARKS.md, "Work estimate"): scoring assumes every IK branch runs its
/// whole budget, the self-motion search and the timing every sample at their largest costs,
/// the collision part every body checked against every scene body at every
/// sample, the pair part a search that finds no valid pair and so visits every pair.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct WorkEstimate {
    /// IK and indices: arms × candidates × branches × (grasp iterations + samples × per
    /// sample iterations).
    pub scoring: u64,
    /// With `ik.redundancy: optimize`, the self-motion search: arms × candidates × samples ×
    /// [`WorkEstimate::SELF_MOTION_EVALUATIONS_PER_SAMPLE`].
    pub self_motion: u64,
    /// When motions are timed: arms × candidates × samples × the timing's grid points per
    /// sample, each one evaluation (with torque limits,
    /// [`WorkEstimate::TIMING_EVALUATIONS_PER_TORQUE_POINT`]).
    pub timing: u64,
    /// The scene: arms × candidates × branches × samples × (arm bodies + object) × scene
    /// bodies, at [`WorkEstimate::COLLISION_PAIRS_PER_EVALUATION`] body pairs an evaluation.
    pub collisions: u64,
    /// Two arms: candidates² pairs visited, at [`WorkEstimate::PAIR_VISITS_PER_EVALUATION`]
    /// an evaluation, and with `collision.between_arms` the two motions' bodies checked
    /// against each other at every sample of every pair.
    pub pairs: u64,
}

impl WorkEstimate {
    /// Body pairs whose distance costs about one kinematics evaluation.
    pub const COLLISION_PAIRS_PER_EVALUATION: u64 = 8;
    /// Pairs of the two-arm search visited in about one kinematics evaluation.
    pub const PAIR_VISITS_PER_EVALUATION: u64 = 1;
    /// Kinematics evaluations of the self-motion search per sample: the curve traced both
    /// ways in 4 steps of about 4 corrections each, and the chosen place traced to (and
    /// checked against the previous sample's) in up to 8 corrections each. Like the other
    /// parts, an upper bound on the measured time (BENCHMARKS.md, "Smooth self-motion": the
    /// search takes about 35 evaluations' time per sample on two cores), not on every
    /// iteration budget.
    pub const SELF_MOTION_EVALUATIONS_PER_SAMPLE: u64 = 2 * 4 * 4 + 2 * 8;
    /// Evaluations per timing grid point with torque limits: the inverse dynamics of the arm
    /// three times (gravity, `M q'`, `M q'' + C q'`) and the path's derivatives.
    pub const TIMING_EVALUATIONS_PER_TORQUE_POINT: u64 = 4;

    /// The whole estimate (saturating).
    pub fn total(&self) -> u64 {
        self.scoring
            .saturating_add(self.self_motion)
            .saturating_add(self.timing)
            .saturating_add(self.collisions)
            .saturating_add(self.pairs)
    }

    /// The parts, with what each counts, for a message.
    fn explain(&self, task: &Task) -> String {
        let mut parts = vec![format!(
            "scoring {:.3e} ({} arm(s) × {} candidates × {} branches × ({} grasp iterations + {} \
             samples × {} per sample))",
            self.scoring as f64,
            task.arms.len(),
            task.candidate_count(),
            task.ik.branches,
            task.ik.ik.max_iterations,
            task.path.samples.len(),
            task.ik.per_sample_iterations,
        )];
        if self.self_motion > 0 {
            parts.push(format!(
                "self-motion search {:.3e} (ik.redundancy: optimize; first costs none)",
                self.self_motion as f64,
            ));
        }
        if self.timing > 0 {
            parts.push(format!(
                "timing {:.3e} (timing: false costs none)",
                self.timing as f64,
            ));
        }
        if self.collisions > 0 {
            parts.push(format!(
                "scene {:.3e} ({} scene bodies against the arm's bodies at every sample)",
                self.collisions as f64,
                task.collisions
                    .as_ref()
                    .map_or(0, |c| c.scene.bodies().len()),
            ));
        }
        if self.pairs > 0 {
            parts.push(format!(
                "pairs {:.3e} (up to {}² pairs of the two arms' candidates)",
                self.pairs as f64,
                task.candidate_count(),
            ));
        }
        parts.join(", ")
    }
}

/// The timing settings a request resolves to for `arms`: `Auto` is on with the defaults when
/// every joint has a velocity limit; `On` requires one; the settings are checked.
fn resolve_timing(
    request: TimingRequest,
    arms: &[ArmSetup],
) -> Result<Option<TimingSettings>, (&'static str, String)> {
    let unlimited = arms.iter().find_map(|arm| {
        let chain = &arm.chain;
        chain
            .motion_limits()
            .iter()
            .zip(chain.joint_names())
            .find(|(l, _)| l.velocity.is_none())
            .map(|(_, joint)| format!("arm '{}' joint '{joint}'", arm.name))
    });
    match request {
        TimingRequest::Off => Ok(None),
        TimingRequest::Auto => Ok(unlimited.is_none().then(TimingSettings::default)),
        TimingRequest::On(settings) => {
            settings.check()?;
            match unlimited {
                Some(joint) => Err((
                    "timing",
                    format!(
                        "{joint} has no velocity limit (the robot file gives none): a motion \
                         cannot be timed without one"
                    ),
                )),
                None => Ok(Some(settings)),
            }
        }
    }
}
