//! What a task asks of the scoring and the ranking — which rows of `J` and of the tangent enter
//! `M_T`, which norm is maximised, how the likelihood combines with it — every default in
//! [`defaults`], and the [`Limits`] that bound the work a task may ask for.

/// Which rows of the Jacobian `J` (and of the path tangent `u`) enter the task-relevant index
/// `M_T = ‖J'ᵀ u‖²`. In a task file: `index: { mode: twist | translation | rotation,
/// length_scale }`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum JacobianRows {
    /// All six rows: the linear velocity of the wrist origin and the angular velocity, the
    /// angular rows of `J` and of the tangent scaled by a characteristic length (m). A length of
    /// 1 m reproduces the paper's raw `J`.
    Twist {
        /// Characteristic length L (m), > 0.
        length_scale: f64,
    },
    /// The three linear rows `Jv` and the linear part of the tangent.
    Translation,
    /// The three angular rows `Jω` and the angular part of the tangent.
    Rotation,
}

impl Default for JacobianRows {
    /// The paper's choice: the full twist with L = [`defaults::LENGTH_SCALE`].
    fn default() -> Self {
        JacobianRows::Twist {
            length_scale: defaults::LENGTH_SCALE,
        }
    }
}

impl JacobianRows {
    /// The task-file spelling: `twist`, `translation` or `rotation`.
    pub fn name(&self) -> &'static str {
        match self {
            JacobianRows::Twist { .. } => "twist",
            JacobianRows::Translation => "translation",
            JacobianRows::Rotation => "rotation",
        }
    }
}

/// What is measured at each sample and ranked by its norms over the path (`index.measure`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum IndexMeasure {
    /// The paper's task-relevant manipulability `M_T = uᵀ J' J'ᵀ u` (eq. 13).
    #[default]
    TaskRelevant,
    /// The velocity transmission ratio along the tangent, `1 / √(uᵀ (J' J'ᵀ)⁻¹ u)`: the speed
    /// along `u` a unit joint velocity reaches (0 where `u` is a singular direction). Not the
    /// paper's index: it weighs the directions the arm is slow in, not the fast ones.
    VelocityRatio,
    /// The time the whole motion takes, fastest within the joints' limits (smaller is better:
    /// candidates are ranked by its inverse, the task's rate); needs timing. The per-sample
    /// series is `M_T`, as with [`IndexMeasure::TaskRelevant`].
    Duration,
    /// The dynamic task-relevant manipulability `M_D = ‖H M⁻¹ J'ᵀ u‖²`: the square of the
    /// largest acceleration along `u` the joints' torques can still produce, each within its
    /// effort limit less what gravity takes (the arm and, while held, the object; see
    /// [`crate::manipulability::DynamicManipulability`]). Needs the arm's inertial data and
    /// every joint's effort limit. Not the paper's index.
    Dynamic,
}

impl IndexMeasure {
    /// The task-file spelling: `task_relevant`, `velocity_ratio`, `duration`, `dynamic`.
    pub fn as_str(self) -> &'static str {
        match self {
            IndexMeasure::TaskRelevant => "task_relevant",
            IndexMeasure::VelocityRatio => "velocity_ratio",
            IndexMeasure::Duration => "duration",
            IndexMeasure::Dynamic => "dynamic",
        }
    }

    /// Every measure, in the order the docs list them.
    pub const ALL: [Self; 4] = [
        Self::TaskRelevant,
        Self::VelocityRatio,
        Self::Duration,
        Self::Dynamic,
    ];

    /// The variant spelled `name`, if any.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|m| m.as_str() == name)
    }

    /// Every spelling, comma-separated, for messages.
    pub fn spellings() -> String {
        Self::ALL.map(Self::as_str).join(", ")
    }
}

/// Which path samples the norms are taken over (`index.over`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum NormSamples {
    /// Every sample of the path.
    #[default]
    All,
    /// The paper's reading of a task (eq. 15 over its waypoints): the initial pose and the
    /// last sample of each step (initial / pick / move / place for a three-step task). The path
    /// is still sampled densely for the IK, the continuity and the collision checks; `M_T` at a
    /// waypoint is measured along the motion leaving it (the last one: arriving at it).
    Waypoints,
}

impl NormSamples {
    /// The task-file spelling: `samples`, `waypoints`.
    pub fn as_str(self) -> &'static str {
        match self {
            NormSamples::All => "samples",
            NormSamples::Waypoints => "waypoints",
        }
    }

    /// The variant spelled `name`, if any.
    pub fn from_name(name: &str) -> Option<Self> {
        [Self::All, Self::Waypoints]
            .into_iter()
            .find(|m| m.as_str() == name)
    }
}

/// The per-sample index that is ranked: the measure, optionally multiplied by a joint-limit
/// penalty, and the samples its norms are taken over (`index: { measure,
/// joint_limit_penalty, over }`).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct RankedIndex {
    /// What is measured at each sample.
    pub measure: IndexMeasure,
    /// With `Some(k)`, each sample's value is multiplied by Tsai's joint-limit penalty
    /// `P(q) = 1 − exp(−k Π_i (q_i − l_i)(u_i − q_i) / (u_i − l_i)²)` (the product over the
    /// joints with limits; see [`crate::manipulability::joint_limit_penalty`]); `k > 0`.
    pub joint_limit_penalty: Option<f64>,
    /// Which samples the norms are taken over.
    pub over: NormSamples,
}

impl RankedIndex {
    /// Whether the ranked value is the paper's `M_T` itself.
    pub fn is_task_relevant(&self) -> bool {
        self.measure == IndexMeasure::TaskRelevant && self.joint_limit_penalty.is_none()
    }

    /// Whether the per-sample series is `M_T` itself (the paper's index, or the duration,
    /// which is ranked on the whole motion and keeps `M_T` per sample).
    pub fn series_is_m_t(&self) -> bool {
        matches!(
            self.measure,
            IndexMeasure::TaskRelevant | IndexMeasure::Duration
        ) && self.joint_limit_penalty.is_none()
    }
}

/// How a redundant arm's self-motion is chosen along the path (`ik.redundancy`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Redundancy {
    /// One IK branch, tracked from the start configuration (the paper's practice); more
    /// branches are searched only when it fails or collides.
    First,
    /// Every branch tracked; the one with the best norm is kept.
    BestBranch,
    /// Every branch tracked, then the arm's place in the self-motion around the best one
    /// chosen as a smooth function of the path's time for the largest ranked norm
    /// ([`crate::robot::optimize_smooth_self_motion`]); kept when it ranks higher than the
    /// branch. On an arm without redundancy it compares the IK branches. The default: a
    /// grasp is scored by what the arm can do from it, not by the solver's first branch.
    #[default]
    Optimize,
}

impl Redundancy {
    /// The task-file spelling: `first`, `best_branch`, `optimize`.
    pub fn as_str(self) -> &'static str {
        match self {
            Redundancy::First => "first",
            Redundancy::BestBranch => "best_branch",
            Redundancy::Optimize => "optimize",
        }
    }

    /// The variant spelled `name`, if any.
    pub fn from_name(name: &str) -> Option<Self> {
        [Self::First, Self::BestBranch, Self::Optimize]
            .into_iter()
            .find(|r| r.as_str() == name)
    }
}

/// The norm of the ranked index along the path that is maximised (each path's value:
/// [`PathNorms::value`](crate::manipulability::PathNorms::value)).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Norm {
    /// `μ_rms`, the root mean square over the path's time (the default): the continuous
    /// counterpart of the paper's `μ_l2`, independent of how densely the path is sampled, so
    /// scores compare across tasks and rankings hold when the sampling is refined.
    #[default]
    Rms,
    /// `μ_l2 = ‖M‖₂` over the samples (the paper's choice, eq. 15): it grows with the square
    /// root of the sample count.
    L2,
    /// `μ_l1`, the time integral of `M_T`.
    L1,
}

impl Norm {
    /// The task-file spelling: `rms`, `l2`, `l1`.
    pub fn as_str(self) -> &'static str {
        match self {
            Norm::Rms => "rms",
            Norm::L2 => "l2",
            Norm::L1 => "l1",
        }
    }

    /// The variant spelled `name`, if any.
    pub fn from_name(name: &str) -> Option<Self> {
        [Self::Rms, Self::L2, Self::L1]
            .into_iter()
            .find(|n| n.as_str() == name)
    }

    /// The name of its column in the candidate records: `mu_rms`, `mu_l2`, `mu_l1`.
    pub fn field(self) -> &'static str {
        match self {
            Norm::Rms => "mu_rms",
            Norm::L2 => "mu_l2",
            Norm::L1 => "mu_l1",
        }
    }
}

/// How the grasp likelihood combines with the norm into a score.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum LikelihoodRule {
    /// `norm × ℓ/ℓ_max` — the default. With equal likelihoods it is the paper's rule.
    #[default]
    Product,
    /// The norm alone.
    Ignore,
    /// `ln(norm) + weight · ln(ℓ/ℓ_max)`: a weight above 1 favours likely grasps more than the
    /// product does, below 1 less.
    Weighted {
        /// The likelihood's weight (≥ 0).
        weight: f64,
    },
}

/// How candidates are ranked and paired.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SelectionOptions {
    /// The norm to maximise.
    pub norm: Norm,
    /// Reject candidates with `μ_l∞ > μ0` (`None`: only singular paths, `μ_l∞ = ∞`, are rejected).
    pub mu0: Option<f64>,
    /// How the likelihood enters the score.
    pub likelihood: LikelihoodRule,
    /// How many best arm pairs to keep.
    pub pairs: usize,
    /// Two grasps closer than this (m, object frame) overlap.
    pub min_separation: f64,
    /// Reject candidates whose clearance from the scene along the motion is below this (m;
    /// `None`: only collisions reject).
    pub min_clearance: Option<f64>,
    /// Reject candidates whose torque margin along the motion (with a payload) is below this
    /// (`None`: only the effort limits reject).
    pub min_torque_margin: Option<f64>,
    /// Reject candidates whose timed motion takes longer than this (s; `None`: no bound).
    pub max_duration: Option<f64>,
    /// Rank by the inverse of the motion's duration instead of the norm (`index.measure:
    /// duration`).
    pub by_duration: bool,
    /// Two eligible candidates whose scores differ by at most this, relative to the larger
    /// (absolute for [`LikelihoodRule::Weighted`], whose score is a logarithm), are reported as
    /// tied (see [`crate::select::scores_tied`]); ranks are not changed by it.
    pub tie_tolerance: f64,
}

impl Default for SelectionOptions {
    fn default() -> Self {
        Self {
            norm: Norm::Rms,
            mu0: None,
            likelihood: LikelihoodRule::Product,
            pairs: defaults::PAIRS,
            min_separation: defaults::MIN_SEPARATION,
            min_clearance: None,
            min_torque_margin: None,
            max_duration: None,
            by_duration: false,
            tie_tolerance: defaults::TIE_TOLERANCE,
        }
    }
}

/// Every default of a task, in one place: the task-file loader, the builder, the Python
/// bindings and the docs (`docs/task-file.md`) all take them from here.
pub mod defaults {
    /// Characteristic length L of the `twist` index (m): the paper's raw `J`.
    pub const LENGTH_SCALE: f64 = 1.0;
    /// How many best arm pairs are kept.
    pub const PAIRS: usize = 10;
    /// Two grasps closer than this overlap (m; Baxter's gripper width).
    pub const MIN_SEPARATION: f64 = 0.08;
    /// Tsai's penalty gain `k` when `index.joint_limit_penalty: true` (Simox's default).
    pub const JOINT_LIMIT_PENALTY_GAIN: f64 = 50.0;
    /// A joint closer than this to a limit (rad or m) counts as at the limit.
    pub const LIMIT_HUG_DISTANCE: f64 = 0.02;
    /// A candidate whose path has at least this share of samples with a joint at a limit
    /// ([`LIMIT_HUG_DISTANCE`]) hugs the limit (flagged in its results).
    pub const LIMIT_HUG_SHARE: f64 = 0.5;
    /// Relative score difference under which two candidates are reported as tied (1 = 100 %).
    ///
    /// The IK stops within [`IK_TOLERANCE`] (m and rad) of each wrist pose, so the Jacobians
    /// are those of a configuration off by that much: `J` changes by about `ε / ℓ` relative,
    /// with `ℓ` the lever arm between the joints and the wrist (≥ 0.2 m on Baxter), and
    /// `M_T = ‖Jᵀ u‖²` by twice that, `2 · 1e-5 / 0.2 = 1e-4`. Score differences below it are
    /// within what the solver's tolerance alone can produce.
    pub const TIE_TOLERANCE: f64 = 1e-4;
    /// Samples per step of the object path when no sampling is given.
    pub const SAMPLES_PER_STEP: usize = 10;
    /// Duration of a step (s).
    pub const STEP_DURATION: f64 = 1.0;
    /// Largest joint motion between consecutive samples (rad or m); also the separation that
    /// makes two IK branches distinct.
    pub const MAX_JOINT_STEP: f64 = 0.5;
    /// How far inside its limits the IK keeps every revolute joint (rad): MoveIt Servo's
    /// default `joint_limit_margins` (5.7°). A motion planned up to a limit leaves the next
    /// perception or tracking error no room, and a controller faults on it; with this margin
    /// the chosen grasps do not ride the limits (`ik.limit_margin: 0` plans up to them, as the
    /// paper does).
    pub const IK_LIMIT_MARGIN: f64 = 0.1;
    /// Distinct IK branches searched from the grasp pose.
    pub const IK_BRANCHES: usize = 4;
    /// Random seed of the IK's restarts (task file `ik.random_seed`).
    pub const IK_RANDOM_SEED: u64 = 0;
    /// Position (m) and rotation (rad) tolerance of IK.
    pub const IK_TOLERANCE: f64 = 1e-5;
    /// The IK iteration budget of a candidate's grasp sample over all restarts: what an
    /// unreachable candidate costs before it is given up.
    pub const GRASP_IK_ITERATIONS: usize = 200;
    /// Iteration budget of the warm-started solve of one path sample.
    pub const PER_SAMPLE_IK_ITERATIONS: usize = 30;
    /// How far below the top face (or inside a face) a family's tool point sits (m).
    pub const FAMILY_DEPTH: f64 = 0.02;
    /// Distance an edge family keeps from each end of the edge (m).
    pub const FAMILY_MARGIN: f64 = 0.02;
}

/// Upper bounds on what one task may ask for, checked before anything is allocated or run, so
/// that a typo (`samples: 1000000000`) is a clear error instead of an exhausted machine. Each
/// can be raised in the task file (`limits: {...}`) or from the command line.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Limits {
    /// Largest number of grasp candidates (families, files and generated).
    pub max_candidates: usize,
    /// Largest number of samples of the object path (initial pose included).
    pub max_samples: usize,
    /// Largest IK iteration budget (`ik.iterations`).
    pub max_ik_iterations: usize,
    /// Largest number of IK branches (`ik.branches`).
    pub max_ik_branches: usize,
    /// Largest work estimate, in kinematics evaluations: arms × candidates × branches ×
    /// (grasp iterations + samples × per-sample iterations). About 10¹⁰ evaluations are
    /// 30 minutes on two cores.
    pub max_work: u64,
    /// Largest estimated memory (MiB) of a selection held whole in memory: `select
    /// --format json` and Python's `select` keep every candidate's joint trajectories
    /// ([`Task::selection_memory`](super::Task::selection_memory)). Streamed selections
    /// (`--format jsonl` / `parquet`) are not bounded by it.
    pub max_memory_mib: u64,
}

impl Default for Limits {
    fn default() -> Self {
        Self {
            max_candidates: 10_000_000,
            max_samples: 100_000,
            max_ik_iterations: 1_000_000,
            max_ik_branches: 64,
            max_work: 10_000_000_000,
            max_memory_mib: 3072,
        }
    }
}

impl Limits {
    /// The work estimate of scoring `candidates` candidates on `arms` arms along `samples`
    /// samples, in kinematics evaluations (saturating, never overflowing).
    pub fn work(
        arms: usize,
        candidates: usize,
        samples: usize,
        branches: usize,
        grasp_iterations: usize,
        per_sample_iterations: usize,
    ) -> u64 {
        let per_branch = (grasp_iterations as u64)
            .saturating_add((samples as u64).saturating_mul(per_sample_iterations as u64));
        (arms as u64)
            .saturating_mul(candidates as u64)
            .saturating_mul(branches as u64)
            .saturating_mul(per_branch)
    }
}

/// `Ok` when `count ≤ limit`; else a message naming the limit that can be raised.
pub(crate) fn check_count(
    what: &str,
    count: usize,
    limit: usize,
    limit_name: &str,
) -> Result<(), String> {
    if count > limit {
        Err(format!(
            "{what}: {count} is more than the limit {limit}; raise limits.{limit_name} if this is intended"
        ))
    } else {
        Ok(())
    }
}
