//! What a task asks of the self-motion search ([`Redundancy`]) and of the ranking — how the
//! likelihood combines with the norm, which candidates are kept and paired — and the
//! [`Limits`] that bound the work a task may ask for. The index vocabulary (rows, measure,
//! norm) is [`crate::manipulability`]'s; every default is in [`crate::defaults`].

use crate::defaults;
use crate::manipulability::Norm;
use crate::spelling::spelled;

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

spelled!(Redundancy {
    First => "first",
    BestBranch => "best_branch",
    Optimize => "optimize",
});

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
