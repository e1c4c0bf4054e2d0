//! Inverse kinematics of a single pose: the joint configuration, inside the joint limits, at
//! which the chain tip reaches a target pose given in the chain base frame.
//!
//! The solver combines what the best numerical solvers do:
//!
//! * **Levenberg–Marquardt with Sugihara's error-dependent damping** (λ = μ·(E + λ̄), E the
//!   weighted squared error; Sugihara, IEEE T-RO 2011), solved in the 6 × 6 task space so that
//!   any number of joints costs one 6 × 6 Cholesky factorisation per iteration; a step is
//!   accepted only if it lowers the error, otherwise μ grows.
//! * **Two limit strategies**, alternated over attempts: an active-set scheme (a joint resting
//!   on a limit and pushed outwards leaves the step, the step is clamped), and Chan & Dubey's
//!   weighted least norm (joints slow down smoothly as they approach a limit). The result of
//!   whichever converges first is kept; when none converges, the attempt with the lowest
//!   residual is reported.
//! * **Seeded random restarts** (uniform in the limits) when an attempt stalls, until the
//!   iteration or time budget is spent, as TRAC-IK does.
//!
//! Every returned configuration is inside the limits by construction: each iterate is
//! clamped. Continuous (unbounded) joints are returned within ±π of their value in the start
//! configuration `q_start`.
//! Results are deterministic for a given [`IkOptions::random_seed`] unless the time budget
//! is what stops the search.

use super::attempt::{out_of_reach, prepare_attempt, run_attempt, wrap_continuous};
use super::kernel::{Budget, Kernel, Patience, RunEnd, Target, Workspace};
use crate::failure::FailureReason;
use crate::robot::chain::{Chain, MAX_JOINTS};
use crate::robot::error::RobotError;
use nalgebra::Isometry3;
use rand::rngs::Xoshiro256PlusPlus;
use rand::SeedableRng;
use std::fmt;
use std::time::{Duration, Instant};

/// Options of a single-pose IK solve.
#[derive(Debug, Clone, PartialEq)]
pub struct IkOptions {
    /// Largest accepted distance between the tip position and the target position (m).
    pub position_tolerance: f64,
    /// Largest accepted rotation angle between the tip orientation and the target (rad).
    pub rotation_tolerance: f64,
    /// Wall-clock budget of one solve; `None` for no time limit (then only
    /// [`IkOptions::max_iterations`] stops the search). When the time budget is what ends a
    /// search, the result may depend on the machine's speed.
    pub max_time: Option<Duration>,
    /// Largest number of kinematics evaluations (≈ iterations), counted over all restarts.
    pub max_iterations: usize,
    /// Random seed of the restarts: the same random seed gives the same result. (Not the
    /// start configuration, which is the `q_start` argument of [`solve_ik`].)
    pub random_seed: u64,
}

impl Default for IkOptions {
    /// TRAC-IK's tolerances and time budget (1e-5 m, 1e-5 rad, 5 ms), a cap of 100,000
    /// iterations, random seed 0.
    fn default() -> Self {
        Self {
            position_tolerance: 1e-5,
            rotation_tolerance: 1e-5,
            max_time: Some(Duration::from_millis(5)),
            max_iterations: 100_000,
            random_seed: 0,
        }
    }
}

/// A failed solve: why it stopped and the best configuration it saw.
#[derive(Debug, Clone, PartialEq)]
pub struct IkFailure {
    /// Why the search stopped.
    /// `unreachable` (the chain's geometry proves the target out of reach: two of its points,
    /// one fixed by the base and one by the target, would be farther apart than the links
    /// between them span; the search stopped after one attempt), `time_limit` or `iteration_limit`.
    pub reason: FailureReason,
    /// The configuration (inside the limits, rad / m) with the lowest residual; its errors
    /// are [`IkSolution::position_error`] and [`IkSolution::rotation_error`].
    pub best_q: Vec<f64>,
    /// How many attempts were made (1 + random restarts).
    pub attempts: usize,
}

impl fmt::Display for IkFailure {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let why = match self.reason {
            FailureReason::Unreachable => "the target is out of the chain's reach",
            FailureReason::TimeLimit => "the time budget ran out",
            FailureReason::IterationLimit => "the iteration budget ran out",
            other => other.as_str(),
        };
        write!(
            f,
            "no solution within tolerance: {why} after {} attempt(s)",
            self.attempts
        )
    }
}

/// The result of a single-pose solve.
#[derive(Debug, Clone, PartialEq)]
pub struct IkSolution {
    /// The joint configuration (rad / m, inside the limits), or `None` when no configuration
    /// within tolerance was found.
    pub q: Option<Vec<f64>>,
    /// Distance between the tip position and the target (m): of `q` on success, of the best
    /// configuration tried on failure.
    pub position_error: f64,
    /// Rotation angle between the tip orientation and the target (rad), as above.
    pub rotation_error: f64,
    /// Kinematics evaluations spent (≈ iterations, over all restarts).
    pub iterations: usize,
    /// Set exactly when `q` is `None`.
    pub failure: Option<IkFailure>,
}

impl IkSolution {
    /// Whether a configuration within tolerance was found.
    pub fn converged(&self) -> bool {
        self.q.is_some()
    }
}

/// Finds a joint configuration at which the tip of `chain` reaches `base_from_target`
/// (the target tip pose in the chain base frame, m), starting from the joint configuration
/// `q_start` (rad / m, one value per joint; clamped into the limits first). Random restarts,
/// when needed, are drawn from [`IkOptions::random_seed`].
///
/// Returns `Err` only for bad input: a start configuration of the wrong length or with a non-finite value, a
/// non-finite target, or non-positive tolerances. An unreachable target is an `Ok` result
/// with `q: None` and a [`IkFailure`].
pub fn solve_ik(
    chain: &Chain,
    base_from_target: &Isometry3<f64>,
    q_start: &[f64],
    options: &IkOptions,
) -> Result<IkSolution, RobotError> {
    check_options(options)?;
    chain.check_configuration(q_start)?;
    check_pose(base_from_target, &"target")?;
    let deadline = options
        .max_time
        .and_then(|budget| Instant::now().checked_add(budget));
    let kernel = Kernel::new(
        chain,
        options.position_tolerance,
        options.rotation_tolerance,
    );
    let target = Target::new(base_from_target);
    let mut budget = Budget::new(options.max_iterations, deadline);
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(options.random_seed);
    let mut ws = Workspace::new();
    let search = search(&kernel, &target, q_start, &mut ws, &mut budget, &mut rng);
    let n = chain.dof();
    let mut best = search.best_q[..n].to_vec();
    wrap_continuous(chain, q_start, &mut best);
    let reason = if search.converged {
        None
    } else if search.out_of_reach {
        Some(FailureReason::Unreachable)
    } else if budget.timed_out {
        Some(FailureReason::TimeLimit)
    } else {
        Some(FailureReason::IterationLimit)
    };
    Ok(match reason {
        None => IkSolution {
            q: Some(best),
            position_error: search.position_error,
            rotation_error: search.rotation_error,
            iterations: budget.evaluations,
            failure: None,
        },
        Some(reason) => IkSolution {
            q: None,
            position_error: search.position_error,
            rotation_error: search.rotation_error,
            iterations: budget.evaluations,
            failure: Some(IkFailure {
                reason,
                best_q: best,
                attempts: search.attempts,
            }),
        },
    })
}

/// The outcome of [`search`].
struct SearchOutcome {
    /// Whether an attempt converged.
    converged: bool,
    /// Whether the chain's geometry proves the target out of reach.
    out_of_reach: bool,
    /// The converged configuration, or the one with the lowest cost (rad / m).
    best_q: [f64; MAX_JOINTS],
    /// Its distance to the target position (m) and rotation angle to the target (rad).
    position_error: f64,
    rotation_error: f64,
    /// How many attempts were made.
    attempts: usize,
}

/// Attempts from `q_start`, then random restarts, until one converges or the budget is spent.
fn search<R: rand::Rng>(
    kernel: &Kernel<'_>,
    target: &Target,
    q_start: &[f64],
    ws: &mut Workspace,
    budget: &mut Budget,
    rng: &mut R,
) -> SearchOutcome {
    let n = kernel.dof();
    let far = out_of_reach(kernel, target).is_some();
    let mut outcome = SearchOutcome {
        converged: false,
        out_of_reach: far,
        best_q: [0.0; MAX_JOINTS],
        position_error: f64::INFINITY,
        rotation_error: f64::INFINITY,
        attempts: 0,
    };
    outcome.best_q[..n].copy_from_slice(q_start);
    kernel.clamp(&mut outcome.best_q[..n]);
    let mut best_cost = f64::INFINITY;
    let mut k = 0;
    while !budget.exhausted() {
        let (strategy, cap) = prepare_attempt(kernel, k, q_start, rng, &mut ws.cur_mut().q);
        let end = run_attempt(kernel, target, ws, strategy, cap, Patience::SEARCH, budget);
        if end == RunEnd::OutOfBudget && ws.cur().cost.is_infinite() {
            break;
        }
        outcome.attempts += 1;
        let state = ws.cur();
        if end == RunEnd::Converged || state.cost < best_cost {
            best_cost = state.cost;
            outcome.best_q[..n].copy_from_slice(&state.q[..n]);
            outcome.position_error = state.position_error;
            outcome.rotation_error = state.rotation_error;
        }
        if end == RunEnd::Converged {
            outcome.converged = true;
            break;
        }
        k += 1;
        if far || n == 0 {
            // Out of reach, or nothing to move: more attempts cannot help.
            break;
        }
    }
    outcome
}

/// Checks tolerances and budgets.
pub(crate) fn check_options(options: &IkOptions) -> Result<(), RobotError> {
    let positive = |name: &'static str, value: f64| {
        if value.is_finite() && value > 0.0 {
            Ok(())
        } else {
            Err(RobotError::BadOption {
                name,
                message: format!("must be a positive finite number, got {value}"),
            })
        }
    };
    positive("position_tolerance", options.position_tolerance)?;
    positive("rotation_tolerance", options.rotation_tolerance)?;
    // A tolerance that accepts any pose "solves" everything: the largest that still asks
    // for something are a metre and a half turn.
    let at_most = |name: &'static str, value: f64, limit: f64, unit: &str| {
        if value <= limit {
            Ok(())
        } else {
            Err(RobotError::BadOption {
                name,
                message: format!(
                    "{value:e} {unit} accepts almost any pose; at most {limit} {unit}"
                ),
            })
        }
    };
    at_most("position_tolerance", options.position_tolerance, 1.0, "m")?;
    at_most(
        "rotation_tolerance",
        options.rotation_tolerance,
        std::f64::consts::PI,
        "rad",
    )?;
    if options.max_iterations == 0 {
        return Err(RobotError::BadOption {
            name: "max_iterations",
            message: "must be at least 1".into(),
        });
    }
    Ok(())
}

/// Checks that a pose is finite with a unit rotation quaternion; `what` names it in the error
/// (formatted only then).
pub(crate) fn check_pose(pose: &Isometry3<f64>, what: &dyn fmt::Display) -> Result<(), RobotError> {
    let t = pose.translation.vector;
    let q = pose.rotation.coords;
    if t.iter().chain(q.iter()).any(|v| !v.is_finite()) {
        return Err(RobotError::BadPose {
            what: what.to_string(),
            message: "an entry is NaN or infinite".into(),
        });
    }
    if (q.norm() - 1.0).abs() > 1e-6 {
        return Err(RobotError::BadPose {
            what: what.to_string(),
            message: format!("the rotation quaternion has norm {} instead of 1", q.norm()),
        });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::robot::builtin::{baxter, Arm};

    #[test]
    fn solves_a_reachable_baxter_pose_from_the_middle() {
        let chain = baxter(Arm::Left);
        let q_true = [0.3, -0.4, 0.2, 1.1, -0.5, 0.8, 0.1];
        let target: Isometry3<f64> = nalgebra::convert(chain.pose(&q_true).expect("fk"));
        let options = IkOptions {
            max_time: None,
            ..IkOptions::default()
        };
        let solution =
            solve_ik(&chain, &target, &chain.mid_configuration(), &options).expect("valid input");
        let q = solution.q.expect("converges");
        assert!(chain.within_limits(&q));
        let reached: Isometry3<f64> = nalgebra::convert(chain.pose(&q).expect("fk"));
        assert!((reached.translation.vector - target.translation.vector).norm() <= 1e-5);
        assert!(reached.rotation.angle_to(&target.rotation) <= 1e-5);
    }
}
