//! [`Task`] and its one checked constructor, [`TaskBuilder`]: the task-file loader, the Python
//! bindings and library users all build tasks through it, so every default and every check is
//! applied in one place and the same task gives the same results however it was written.

use super::error::TaskError;
use super::path::{ObjectPath, Sampling, TimedStep};
use super::plausibility::TaskWarning;
use super::scene::{Gripper, SceneSettings, Stroke, WorldInput};
use super::sealed::{ArmSetup, Task};
use super::settings::{check_count, LikelihoodRule, Limits, Redundancy, SelectionOptions};
use super::timing::TimingRequest;
use crate::collision::Body;
use crate::defaults;
use crate::geometry::shape::Shape;
use crate::grasp::{Candidate, CandidateSource};
use crate::manipulability::{IndexMeasure, JacobianRows, Norm, RankedIndex};
use crate::robot::{Chain, IkOptions, RigidBody, TrajectoryIkOptions};
use nalgebra::Isometry3;
use std::sync::Arc;

impl Task {
    /// A builder for a task named `name` (the name appears in errors and reports).
    pub fn builder(name: impl Into<String>) -> TaskBuilder {
        TaskBuilder::new(name)
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
        let timing = super::timing::resolve_timing(
            self.timing,
            self.arms.iter().map(|a| (a.name.as_str(), &a.chain)),
        )
        .map_err(|(f, m)| err(f, m))?;
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
        super::payload::attach_dynamics(&mut arms, self.payload.as_ref(), self.ranked.measure)
            .map_err(|(field, m)| err(field, m))?;
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
