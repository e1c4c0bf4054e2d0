//! Inverse kinematics along a whole trajectory of tip poses: continuous joint paths inside the
//! joint limits, one per distinct initial solution (redundancy branch, elbow or wrist flip).
//!
//! Sample 0 is solved from the start configuration `q_start` and from seeded random restarts;
//! every solution that differs from the ones already kept by more than
//! [`TrajectoryIkOptions::max_joint_step`] in some joint starts a branch (up to
//! [`TrajectoryIkOptions::branches`]). Each branch is then tracked sample by sample, each
//! solve warm-started from the previous sample's solution and
//! its Jacobian. A sample is accepted only when its solution is within tolerance, inside the
//! limits and no joint moves more than `max_joint_step` from the previous sample, so a branch
//! flip hidden inside a "continuous" path is a failure, never a silent jump.
//!
//! When the warm-started solve gives no acceptable solution, wider searches follow, cheapest
//! first: the other limit strategy from the previous solution; the pose step split into four
//! intermediate poses; a solve without limits from the previous solution; two seeded restarts
//! near the previous solution; three seeded restarts anywhere in the limits. The first acceptable
//! solution is taken; otherwise the sample fails with the reason:
//!
//! * `joint_limit`: the solve without limits converges within `max_joint_step` of the previous
//!   solution but outside the limits (the path would have to leave them), or it converges
//!   farther away and no solution inside the limits was found;
//! * `discontinuity`: solutions inside the limits exist, but only farther than
//!   `max_joint_step` from the previous sample (the detail names the joint and the jump);
//! * `unreachable`: the chain's geometry proves the target out of reach (the detail names the
//!   two points the target puts farther apart than the links between them span, see
//!   `Chain::out_of_reach`), or no solution near it was found (the
//!   detail gives the best residual). Every pose is checked for such a proof before the
//!   search, and the first proven out of reach fails the trajectory at once: the cause is
//!   named, not the discontinuity met while the arm stretches towards it.
//!
//! Only iteration budgets are used (the time budget [`IkOptions::max_time`] is ignored here),
//! so results are identical from run to run and at any thread count.
//!
//! [`solve_trajectories`] solves a batch of trajectories with the same results, bit for bit,
//! as [`solve_trajectory`] one by one: the branches of the whole batch are tracked four at a
//! time, one per vector lane ([`super::lanes`]), which is where a selection spends most of its
//! time.
//!
//! One file on purpose (about 1000 lines, an eighth tests): the branch search, the tracking in
//! lanes and the per-sample recovery ladder share the tracker's state.

use super::attempt::{
    out_of_reach, prepare_attempt, run_attempt, wrap_continuous, RESTART_ATTEMPT_CAP,
};
use super::kernel::{Budget, Kernel, Patience, RunEnd, Strategy, Target, Workspace};
use super::lanes::{run_each, run_in_order, Attempt, Handed, Lanes};
use super::single_pose::{check_options, check_pose, IkOptions};
use crate::failure::{Failure, FailureReason};
use crate::geometry::interpolate_decoupled;
use crate::random::splitmix64;
use crate::robot::chain::{Chain, MAX_JOINTS};
use crate::robot::error::RobotError;
use nalgebra::Isometry3;
use rand::rngs::Xoshiro256PlusPlus;
use rand::{RngExt, SeedableRng};
use serde::{Deserialize, Serialize};
use std::ops::ControlFlow;

/// Options of a trajectory solve.
#[derive(Debug, Clone, PartialEq)]
pub struct TrajectoryIkOptions {
    /// Tolerances, the iteration budget of the first sample (the search for initial
    /// solutions, over all restarts) and the random seed. `max_time` is ignored: only
    /// iteration budgets are used so that results are reproducible.
    pub ik: IkOptions,
    /// Largest change of any joint between consecutive samples (rad for revolute, m for
    /// prismatic joints). Also the separation that makes two initial solutions distinct.
    pub max_joint_step: f64,
    /// How many distinct initial solutions (branches) to look for and track.
    pub branches: usize,
    /// Iteration budget of the warm-started solve of one sample (recoveries and failure
    /// classification use a small multiple of it).
    pub per_sample_iterations: usize,
}

impl Default for TrajectoryIkOptions {
    /// 1e-5 m / 1e-5 rad, 1000 iterations for the first sample, 0.5 rad steps, 4 branches,
    /// 30 iterations per sample, random seed 0.
    fn default() -> Self {
        Self {
            ik: IkOptions {
                max_time: None,
                max_iterations: 1000,
                ..IkOptions::default()
            },
            max_joint_step: 0.5,
            branches: 4,
            per_sample_iterations: 30,
        }
    }
}

/// A feasible joint path: one configuration per trajectory sample (rad / m), inside the
/// limits, each within tolerance of its target and within `max_joint_step` of the previous.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct JointPath {
    /// `q[i]` is the configuration at sample `i`.
    pub q: Vec<Vec<f64>>,
}

/// The result of a trajectory solve.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TrajectoryIkResult {
    /// Every feasible branch, sorted by the distance (largest joint difference) of its first
    /// configuration from `q_start` (clamped into the limits), then lexicographically.
    pub branches: Vec<JointPath>,
    /// Set when no branch follows the whole trajectory: the first failing sample of the branch
    /// that got furthest (the earliest branch among equals).
    pub failure: Option<Failure>,
    /// The configurations found at the first pose, in the order the search found them,
    /// whether or not their branch followed the trajectory. The first depends only on the
    /// first pose, `q_start` and the IK options (not on `branches`): the first pose's IK
    /// from `q_start`.
    #[serde(default)]
    pub first_pose: Vec<Vec<f64>>,
}

impl TrajectoryIkResult {
    /// Whether at least one branch follows the whole trajectory.
    pub fn feasible(&self) -> bool {
        !self.branches.is_empty()
    }
}

/// Joint paths that take the tip of `chain` through `base_from_targets` (tip poses in the
/// chain base frame, m, in order), starting near the joint configuration `q_start` (rad / m,
/// one value per joint). Random restarts are drawn from `options.ik.random_seed`.
///
/// Returns `Err` only for bad input: an empty trajectory, a non-finite pose, a start
/// configuration of the wrong length or non-finite, or out-of-range options.
pub fn solve_trajectory(
    chain: &Chain,
    base_from_targets: &[Isometry3<f64>],
    q_start: &[f64],
    options: &TrajectoryIkOptions,
) -> Result<TrajectoryIkResult, RobotError> {
    solve_trajectories(chain, &[base_from_targets], q_start, options)?
        .pop()
        .expect("one trajectory, one result")
}

/// [`solve_trajectory`] of each trajectory of `trajectories`, all from `q_start` with
/// `options`: the same results, bit for bit, in the same order. The branches of all the
/// trajectories are tracked four at a time, one per vector lane, so a batch takes less time
/// than its trajectories one by one.
///
/// The outer `Err` is for input common to all (the options, `q_start`); the inner one for a
/// trajectory's own poses (empty, or a non-finite pose).
pub fn solve_trajectories(
    chain: &Chain,
    trajectories: &[&[Isometry3<f64>]],
    q_start: &[f64],
    options: &TrajectoryIkOptions,
) -> Result<Vec<Result<TrajectoryIkResult, RobotError>>, RobotError> {
    check_options(&options.ik)?;
    if !(options.max_joint_step.is_finite() && options.max_joint_step > 0.0) {
        return Err(RobotError::BadOption {
            name: "max_joint_step",
            message: format!(
                "must be a positive finite number, got {}",
                options.max_joint_step
            ),
        });
    }
    for (name, value) in [
        ("branches", options.branches),
        ("per_sample_iterations", options.per_sample_iterations),
    ] {
        if value == 0 {
            return Err(RobotError::BadOption {
                name,
                message: "must be at least 1".into(),
            });
        }
    }
    chain.check_configuration(q_start)?;
    let kernel = Kernel::new(
        chain,
        options.ik.position_tolerance,
        options.ik.rotation_tolerance,
    );
    let searched: Vec<Result<Searched<'_>, RobotError>> = trajectories
        .iter()
        .map(|poses| {
            check_trajectory(poses)?;
            let tracker = Tracker {
                kernel,
                poses,
                options,
            };
            let starts = tracker.initial_solutions(q_start);
            Ok((tracker, starts))
        })
        .collect();
    let jobs: Vec<Job<'_>> = searched
        .iter()
        .filter_map(|searched| match searched {
            Ok((tracker, Ok(starts))) => Some((tracker, starts)),
            _ => None,
        })
        .flat_map(|(tracker, starts)| Job::branches(tracker, starts))
        .collect();
    let mut tracked = if let [job] = jobs.as_slice() {
        vec![job.tracker.track(job.branch, job.start)]
    } else {
        track_in_lanes(&jobs)
    }
    .into_iter();
    let mut start_clamped = q_start.to_vec();
    kernel.clamp(&mut start_clamped);
    Ok(searched
        .into_iter()
        .map(|searched| {
            let starts = match searched? {
                (_, Ok(starts)) => starts,
                (_, Err(failure)) => {
                    return Ok(TrajectoryIkResult {
                        branches: Vec::new(),
                        failure: Some(failure),
                        first_pose: Vec::new(),
                    })
                }
            };
            let outcomes = tracked.by_ref().take(starts.len());
            Ok(assemble(outcomes, starts, &start_clamped))
        })
        .collect())
}

/// A trajectory's tracker and its first pose's solutions (the branches' starts), or why there
/// are none.
type Searched<'a> = (Tracker<'a>, Result<Vec<Vec<f64>>, Failure>);

/// Why `poses` cannot be a trajectory: none, or one not finite.
fn check_trajectory(poses: &[Isometry3<f64>]) -> Result<(), RobotError> {
    if poses.is_empty() {
        return Err(RobotError::BadPose {
            what: "trajectory".into(),
            message: "it has no poses".into(),
        });
    }
    for (i, pose) in poses.iter().enumerate() {
        check_pose(pose, &format_args!("trajectory pose {i}"))?;
    }
    Ok(())
}

/// A trajectory's result from its branches' outcomes (branch by branch, in the order of
/// `starts`): the branches that follow it, nearest `start_clamped` (the clamped start
/// configuration) first, or else the failure of the branch that got furthest.
fn assemble(
    outcomes: impl Iterator<Item = Result<JointPath, Failure>>,
    starts: Vec<Vec<f64>>,
    start_clamped: &[f64],
) -> TrajectoryIkResult {
    let mut branches = Vec::new();
    let mut furthest: Option<Failure> = None;
    for outcome in outcomes {
        match outcome {
            Ok(path) => branches.push(path),
            Err(failure) => {
                if furthest.as_ref().is_none_or(|f| failure.sample > f.sample) {
                    furthest = Some(failure);
                }
            }
        }
    }
    branches.sort_by(|a: &JointPath, b: &JointPath| {
        max_difference(&a.q[0], start_clamped)
            .total_cmp(&max_difference(&b.q[0], start_clamped))
            .then_with(|| {
                a.q[0]
                    .iter()
                    .zip(&b.q[0])
                    .map(|(x, y)| x.total_cmp(y))
                    .find(|o| o.is_ne())
                    .unwrap_or(std::cmp::Ordering::Equal)
            })
    });
    let failure = if branches.is_empty() { furthest } else { None };
    TrajectoryIkResult {
        branches,
        failure,
        first_pose: starts,
    }
}

/// Largest absolute difference between two configurations (rad / m).
fn max_difference(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// The joint with the largest change, and that change.
fn largest_step(a: &[f64], b: &[f64]) -> (usize, f64) {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .enumerate()
        .fold(
            (0, 0.0),
            |best, (j, d)| if d > best.1 { (j, d) } else { best },
        )
}

/// Restarts near the previous solution tried before a sample is declared failed.
const LOCAL_RESTARTS: usize = 2;
/// Random restarts anywhere in the limits, to tell a discontinuity from unreachability.
const CLASSIFY_RESTARTS: usize = 3;
/// Intermediate poses used when a warm-started solve fails.
const SUBSTEPS: usize = 4;

/// The state of the search for initial solutions at sample 0.
struct FirstPoseSearch {
    /// Distinct solutions found (rad / m), in the order found.
    found: Vec<Vec<f64>>,
    budget: Budget,
    /// The lowest cost seen (m²) and its position and rotation errors (m, rad).
    best_cost: f64,
    best: (f64, f64),
    /// Largest joint difference under which two solutions are the same (rad / m).
    separation: f64,
}

impl FirstPoseSearch {
    /// Keeps a converged configuration unless one found already lies within the separation.
    fn keep_if_distinct(&mut self, q: Vec<f64>) {
        if self
            .found
            .iter()
            .all(|other| max_difference(other, &q) > self.separation)
        {
            self.found.push(q);
        }
    }
}

/// The best state an attempt ended in: configuration (rad / m), cost (m²), errors (m, rad).
#[derive(Clone, Copy)]
struct EndState<'a> {
    q: &'a [f64],
    cost: f64,
    position_error: f64,
    rotation_error: f64,
}

impl<'a> EndState<'a> {
    /// The current state of `ws`, for a chain of `n` joints.
    fn of(ws: &'a Workspace, n: usize) -> Self {
        let state = ws.cur();
        Self {
            q: &state.q[..n],
            cost: state.cost,
            position_error: state.position_error,
            rotation_error: state.rotation_error,
        }
    }
}

struct Tracker<'a> {
    kernel: Kernel<'a>,
    poses: &'a [Isometry3<f64>],
    options: &'a TrajectoryIkOptions,
}

impl Tracker<'_> {
    fn n(&self) -> usize {
        self.kernel.dof()
    }

    fn rng(&self, branch: usize, sample: usize) -> Xoshiro256PlusPlus {
        let seed = splitmix64(
            self.options.ik.random_seed ^ splitmix64((branch as u64) << 32 | sample as u64),
        );
        Xoshiro256PlusPlus::seed_from_u64(seed)
    }

    /// Distinct solutions at sample 0, the one from `q_start` first.
    ///
    /// Attempt 0 runs from `q_start` with the first limit strategy; attempt 1, from `q_start`
    /// with the other, only when attempt 0 fails; then random restarts. The attempts after the
    /// first run four at a time in vector lanes ([`run_in_order`]), with the results of running
    /// them one after the other.
    fn initial_solutions(&self, q_start: &[f64]) -> Result<Vec<Vec<f64>>, Failure> {
        let n = self.n();
        let kernel = &self.kernel;
        // A pose the chain's geometry proves out of reach fails the whole trajectory there,
        // before any search: its cause, rather than the discontinuity or joint limit that
        // tracking would meet first while the arm stretches towards it.
        for (i, pose) in self.poses.iter().enumerate() {
            if let Some(proof) = out_of_reach(kernel, &Target::new(pose)) {
                return Err(Failure::new(
                    FailureReason::Unreachable,
                    i,
                    proof.to_string(),
                ));
            }
        }
        let target = Target::new(&self.poses[0]);
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(self.options.ik.random_seed);
        let mut ws = Workspace::new();
        let wanted = self.options.branches;
        let max_attempts = wanted.saturating_mul(6).saturating_add(2);
        let mut search = FirstPoseSearch {
            found: Vec::with_capacity(wanted.min(16)),
            budget: Budget::new(self.options.ik.max_iterations, None),
            best_cost: f64::INFINITY,
            best: (f64::INFINITY, f64::INFINITY),
            separation: self.options.max_joint_step,
        };
        // Whether attempt `k` is made.
        let goes_on = |search: &FirstPoseSearch, k: usize| {
            !search.budget.exhausted()
                && search.found.len() < wanted
                && (search.found.is_empty() || k < max_attempts)
        };
        // Notes an attempt's end: its cost, and its configuration when it converged.
        let record = |search: &mut FirstPoseSearch, end: RunEnd, ended: EndState<'_>| {
            if ended.cost < search.best_cost {
                search.best_cost = ended.cost;
                search.best = (ended.position_error, ended.rotation_error);
            }
            if end == RunEnd::Converged {
                let mut q = ended.q.to_vec();
                wrap_continuous(kernel.chain, q_start, &mut q);
                search.keep_if_distinct(q);
            }
        };
        if goes_on(&search, 0) {
            let (strategy, cap) =
                prepare_attempt(kernel, 0, q_start, &mut rng, &mut ws.cur_mut().q);
            let end = run_attempt(
                kernel,
                &target,
                &mut ws,
                strategy,
                cap,
                Patience::SEARCH,
                &mut search.budget,
            );
            record(&mut search, end, EndState::of(&ws, n));
            // When the start converged with the first strategy, the second is not tried.
            let first = if search.found.is_empty() { 1 } else { 2 };
            if goes_on(&search, first) {
                let mut lanes = Lanes::new(*kernel, target, Patience::SEARCH);
                let left = search.budget.evaluations_left;
                run_in_order(
                    &mut lanes,
                    left,
                    |i| {
                        let mut q = [0.0; MAX_JOINTS];
                        let (strategy, cap) =
                            prepare_attempt(kernel, first + i, q_start, &mut rng, &mut q);
                        Some(Attempt { q, strategy, cap })
                    },
                    |i, attempt, handed| {
                        match handed {
                            Handed::Ended(end) => {
                                search.budget.charge(end.spent);
                                let ended = EndState {
                                    q: &end.q,
                                    cost: end.cost,
                                    position_error: end.position_error,
                                    rotation_error: end.rotation_error,
                                };
                                record(&mut search, end.end, ended);
                            }
                            Handed::Cut => {
                                ws.cur_mut().q = attempt.q;
                                let end = run_attempt(
                                    kernel,
                                    &target,
                                    &mut ws,
                                    attempt.strategy,
                                    attempt.cap,
                                    Patience::SEARCH,
                                    &mut search.budget,
                                );
                                record(&mut search, end, EndState::of(&ws, n));
                            }
                        }
                        if goes_on(&search, first + i + 1) {
                            ControlFlow::Continue(())
                        } else {
                            ControlFlow::Break(())
                        }
                    },
                );
            }
        }
        if !search.found.is_empty() {
            return Ok(search.found);
        }
        // No solution in the limits: classify from the start configuration.
        let mut start = [0.0; MAX_JOINTS];
        start[..n].copy_from_slice(q_start);
        kernel.clamp(&mut start[..n]);
        self.classify_first(&target, &start[..n], search.best)
            .map(|q| vec![q])
    }

    /// Why sample 0 has no solution in the limits; `Ok` with a solution should the search
    /// without limits find one inside them after all.
    fn classify_first(
        &self,
        target: &Target,
        start: &[f64],
        best: (f64, f64),
    ) -> Result<Vec<f64>, Failure> {
        let fail = |reason, detail| Err(Failure::new(reason, 0, detail));
        // The restarts, each with its own budget, run together in vector lanes; the first
        // (in restart order) that converges decides.
        let free = self.kernel.unconstrained();
        let mut rng = self.rng(usize::MAX, 0);
        let cap = self.options.per_sample_iterations.max(30).saturating_mul(2);
        let restarts: Vec<(Attempt, usize)> = (0..CLASSIFY_RESTARTS)
            .map(|k| {
                let mut q = [0.0; MAX_JOINTS];
                if k == 0 {
                    q[..start.len()].copy_from_slice(start);
                } else {
                    self.kernel
                        .random_configuration(&mut rng, &mut q[..start.len()]);
                }
                let attempt = Attempt {
                    q,
                    strategy: Strategy::Clamped,
                    cap,
                };
                (attempt, cap)
            })
            .collect();
        let mut lanes = Lanes::new(free, *target, Patience::SEARCH);
        if let Some(end) = run_each(&mut lanes, &restarts)
            .into_iter()
            .find(|end| end.end == RunEnd::Converged)
        {
            if self.kernel.chain.within_limits(&end.q) {
                return Ok(end.q);
            }
            return fail(FailureReason::JointLimit, self.limit_detail(&end.q));
        }
        fail(
            FailureReason::Unreachable,
            format!(
                "no solution found within the iteration budget; best residual {:.3e} m, {:.3e} rad",
                best.0, best.1
            ),
        )
    }

    /// Names the joint farthest outside its limits in `q`.
    fn limit_detail(&self, q: &[f64]) -> String {
        let chain = self.kernel.chain;
        let (mut worst, mut excess) = (0usize, 0.0f64);
        for (j, &v) in q.iter().enumerate() {
            let e = (chain.lower()[j] - v).max(v - chain.upper()[j]);
            if e > excess {
                worst = j;
                excess = e;
            }
        }
        format!(
            "the nearest solution needs joint '{}' at {:.4}, outside its limits [{:.4}, {:.4}]",
            chain.joint_names()[worst],
            q[worst],
            chain.lower()[worst],
            chain.upper()[worst]
        )
    }

    /// Follows the trajectory from `start` (a solution at sample 0).
    fn track(&self, branch: usize, start: &[f64]) -> Result<JointPath, Failure> {
        let n = self.n();
        let kernel = &self.kernel;
        let step = self.options.max_joint_step;
        let per_sample = self.options.per_sample_iterations;
        let mut path = Vec::with_capacity(self.poses.len());
        path.push(start.to_vec());
        let mut ws = Workspace::new();
        ws.cur_mut().q[..n].copy_from_slice(start);
        kernel.evaluate(&Target::new(&self.poses[0]), ws.cur_mut());
        let mut previous = [0.0f64; MAX_JOINTS];
        for i in 1..self.poses.len() {
            previous[..n].copy_from_slice(&ws.cur().q[..n]);
            let target = Target::new(&self.poses[i]);
            // The warm start: the previous solution's pose and Jacobian are already known.
            kernel.retarget(&target, ws.cur_mut());
            let mut budget = Budget::new(per_sample, None);
            let end = kernel.run(
                &target,
                &mut ws,
                Strategy::Clamped,
                per_sample,
                Patience::TRACKING,
                &mut budget,
            );
            let accepted = end == RunEnd::Converged
                && max_difference(&ws.cur().q[..n], &previous[..n]) <= step;
            if !accepted {
                self.resolve(branch, i, &previous[..n], &target, &mut ws)?;
            }
            path.push(ws.cur().q[..n].to_vec());
        }
        Ok(JointPath { q: path })
    }

    /// Retries sample `i` from `previous` (the solution at sample `i − 1`) with wider searches,
    /// cheapest first; `Ok` leaves the accepted solution in `ws`, `Err` says why there is none.
    fn resolve(
        &self,
        branch: usize,
        i: usize,
        previous: &[f64],
        target: &Target,
        ws: &mut Workspace,
    ) -> Result<(), Failure> {
        let n = previous.len();
        let kernel = &self.kernel;
        let chain = kernel.chain;
        let step = self.options.max_joint_step;
        let per_sample = self.options.per_sample_iterations;
        let fail = |reason, detail| Err(Failure::new(reason, i, detail));
        let acceptable = |ws: &Workspace, end: RunEnd| {
            end == RunEnd::Converged && max_difference(&ws.cur().q[..n], previous) <= step
        };
        if let Some(proof) = out_of_reach(kernel, target) {
            return fail(FailureReason::Unreachable, proof.to_string());
        }
        // 1. The other limit strategy from the previous solution.
        ws.cur_mut().q[..n].copy_from_slice(previous);
        let mut budget = Budget::new(per_sample.saturating_add(1), None);
        let end = run_attempt(
            kernel,
            target,
            ws,
            Strategy::LimitWeighted,
            per_sample,
            Patience::TRACKING,
            &mut budget,
        );
        if acceptable(ws, end) {
            return Ok(());
        }
        // 2. The pose step split into substeps (large motions between samples).
        ws.cur_mut().q[..n].copy_from_slice(previous);
        let mut budget = Budget::new(per_sample.saturating_add(1).saturating_mul(SUBSTEPS), None);
        let mut end = RunEnd::Stalled;
        for s in 1..=SUBSTEPS {
            // The last substep is the sample's own target, exactly.
            let sub = if s == SUBSTEPS {
                *target
            } else {
                let fraction = s as f64 / SUBSTEPS as f64;
                Target::new(&interpolate_decoupled(
                    &self.poses[i - 1],
                    &self.poses[i],
                    fraction,
                ))
            };
            end = run_attempt(
                kernel,
                &sub,
                ws,
                Strategy::Clamped,
                per_sample,
                Patience::TRACKING,
                &mut budget,
            );
            if end != RunEnd::Converged {
                break;
            }
        }
        if acceptable(ws, end) {
            return Ok(());
        }
        // 3. Without limits from the previous solution: a nearby solution outside the limits
        //    means the path has to leave them.
        let free = kernel.unconstrained();
        ws.cur_mut().q[..n].copy_from_slice(previous);
        let cap = per_sample.saturating_mul(2);
        let mut budget = Budget::new(cap.saturating_add(1), None);
        let free_end = run_attempt(
            &free,
            target,
            ws,
            Strategy::Clamped,
            cap,
            Patience::TRACKING,
            &mut budget,
        );
        let free_q: Option<Vec<f64>> =
            (free_end == RunEnd::Converged).then(|| ws.cur().q[..n].to_vec());
        if let Some(q) = &free_q {
            if max_difference(q, previous) <= step {
                if chain.within_limits(q) {
                    return Ok(());
                }
                return fail(FailureReason::JointLimit, self.limit_detail(q));
            }
        }
        // 4. Restarts near the previous solution, then anywhere in the limits.
        let mut rng = self.rng(branch, i);
        let radius = 0.5 * step;
        let mut nearest: Option<(usize, f64)> = None;
        let mut best = (f64::INFINITY, f64::INFINITY, f64::INFINITY);
        for k in 0..LOCAL_RESTARTS + CLASSIFY_RESTARTS {
            let strategy = if k.is_multiple_of(2) {
                Strategy::Clamped
            } else {
                Strategy::LimitWeighted
            };
            {
                let q = &mut ws.cur_mut().q[..n];
                if k < LOCAL_RESTARTS {
                    for (v, &p) in q.iter_mut().zip(previous) {
                        *v = p + rng.random_range(-radius..=radius);
                    }
                    kernel.clamp(q);
                } else {
                    kernel.random_configuration(&mut rng, q);
                }
            }
            let cap = if k < LOCAL_RESTARTS {
                per_sample
            } else {
                RESTART_ATTEMPT_CAP
            };
            let mut budget = Budget::new(cap.saturating_add(1), None);
            let end = run_attempt(
                kernel,
                target,
                ws,
                strategy,
                cap,
                Patience::SEARCH,
                &mut budget,
            );
            if acceptable(ws, end) {
                return Ok(());
            }
            let state = ws.cur();
            if state.cost < best.0 {
                best = (state.cost, state.position_error, state.rotation_error);
            }
            if end == RunEnd::Converged {
                let found = largest_step(&state.q[..n], previous);
                if nearest.is_none_or(|(_, d)| found.1 < d) {
                    nearest = Some(found);
                }
                if k >= LOCAL_RESTARTS {
                    break;
                }
            }
        }
        if let Some((joint, jump)) = nearest {
            return fail(
                FailureReason::Discontinuity,
                format!(
                    "the solutions found inside the limits move joint '{}' by {:.4} (more than max_joint_step {})",
                    chain.joint_names()[joint],
                    jump,
                    step
                ),
            );
        }
        if let Some(q) = &free_q {
            if !chain.within_limits(q) {
                return fail(FailureReason::JointLimit, self.limit_detail(q));
            }
        }
        fail(
            FailureReason::Unreachable,
            format!(
                "no solution found near the target; best residual {:.3e} m, {:.3e} rad",
                best.1, best.2
            ),
        )
    }
}

/// One branch to track: its trajectory's tracker, its number, its start (rad / m).
struct Job<'t> {
    tracker: &'t Tracker<'t>,
    branch: usize,
    start: &'t [f64],
}

impl<'t> Job<'t> {
    /// One job per branch of `tracker`'s trajectory, branch `b` from `starts[b]`.
    fn branches(
        tracker: &'t Tracker<'t>,
        starts: &'t [Vec<f64>],
    ) -> impl Iterator<Item = Job<'t>> + 't {
        starts.iter().enumerate().map(move |(branch, start)| Job {
            tracker,
            branch,
            start,
        })
    }
}

/// [`Tracker::track`] of every job, four at a time in vector lanes: each lane goes on from one
/// sample to the next as `track` does, and a sample its lane does not settle is resolved
/// alone ([`Tracker::resolve`]), the lane going on from the state found; a lane whose branch
/// ends takes the next job. Bit-identical to `track`, job by job. Every job's tracker has the
/// same kernel and options.
fn track_in_lanes(jobs: &[Job<'_>]) -> Vec<Result<JointPath, Failure>> {
    let Some(first_job) = jobs.first() else {
        return Vec::new();
    };
    let kernel = &first_job.tracker.kernel;
    let n = kernel.dof();
    let step = first_job.tracker.options.max_joint_step;
    let per_sample = first_job.tracker.options.per_sample_iterations;
    let mut outcomes: Vec<Option<Result<JointPath, Failure>>> = vec![None; jobs.len()];
    // Each started job's path so far; the sample its lane works on comes next.
    let mut paths: Vec<Vec<Vec<f64>>> = vec![Vec::new(); jobs.len()];
    // The lane each started job runs in, all along.
    let mut job_lane = vec![0; jobs.len()];
    let mut ws = Workspace::new();
    // Every run is resumed towards its own target; the lanes' shared one is never used.
    let mut lanes = Lanes::new(
        *kernel,
        Target::new(&first_job.tracker.poses[0]),
        Patience::TRACKING,
    );
    let mut ended = Vec::with_capacity(4);
    let mut started = 0;
    loop {
        while started < jobs.len() {
            let Some(lane) = lanes.free_lane() else { break };
            let k = started;
            started += 1;
            let job = &jobs[k];
            let poses = job.tracker.poses;
            ws.cur_mut().q[..n].copy_from_slice(job.start);
            kernel.evaluate(&Target::new(&poses[0]), ws.cur_mut());
            paths[k] = Vec::with_capacity(poses.len());
            paths[k].push(job.start.to_vec());
            if poses.len() == 1 {
                outcomes[k] = Some(Ok(JointPath {
                    q: std::mem::take(&mut paths[k]),
                }));
                continue;
            }
            job_lane[k] = lane;
            lanes.load(lane, ws.cur());
            lanes.resume(lane, k, Target::new(&poses[1]), per_sample);
        }
        if !lanes.busy() {
            break;
        }
        lanes.advance(&mut ended);
        for (k, end) in ended.drain(..) {
            let job = &jobs[k];
            let poses = job.tracker.poses;
            let lane = job_lane[k];
            let i = paths[k].len();
            let previous = paths[k].last().expect("a path starts with its start");
            let q = if end.end == RunEnd::Converged && max_difference(&end.q, previous) <= step {
                end.q
            } else {
                let target = Target::new(&poses[i]);
                if let Err(failure) = job
                    .tracker
                    .resolve(job.branch, i, previous, &target, &mut ws)
                {
                    outcomes[k] = Some(Err(failure));
                    continue;
                }
                lanes.load(lane, ws.cur());
                ws.cur().q[..n].to_vec()
            };
            paths[k].push(q);
            if i + 1 == poses.len() {
                outcomes[k] = Some(Ok(JointPath {
                    q: std::mem::take(&mut paths[k]),
                }));
            } else {
                lanes.resume(lane, k, Target::new(&poses[i + 1]), per_sample);
            }
        }
    }
    outcomes
        .into_iter()
        .map(|outcome| outcome.expect("every job is tracked to its end"))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::robot::builtin::{baxter, Arm, BuiltinRobot};

    /// Poses of a random joint-space path of `samples` samples from a random configuration,
    /// moving `speed` rad per sample in each joint at most; with `jump`, one sample in the
    /// middle jumps far (a resolve, a discontinuity or a limit), and with `away`, the last
    /// samples are pushed out of reach.
    fn random_path(
        chain: &Chain,
        rng: &mut Xoshiro256PlusPlus,
        samples: usize,
        speed: f64,
        jump: bool,
        away: bool,
    ) -> Vec<Isometry3<f64>> {
        let kernel = Kernel::new(chain, 1e-5, 1e-5);
        let n = chain.dof();
        let mut q = vec![0.0; n];
        kernel.random_configuration(rng, &mut q);
        let velocity: Vec<f64> = (0..n)
            .map(|_| speed * rng.random_range(-1.0..=1.0))
            .collect();
        (0..samples)
            .map(|i| {
                let mut at: Vec<f64> = q
                    .iter()
                    .zip(&velocity)
                    .map(|(q, v)| q + v * i as f64)
                    .collect();
                if jump && i >= samples / 2 {
                    at[n / 2] += 1.2;
                }
                let mut pose: Isometry3<f64> =
                    nalgebra::convert(chain.pose(&at).expect("finite configuration"));
                if away && i + 3 >= samples {
                    pose.translation.vector.z += 2.5;
                }
                pose
            })
            .collect()
    }

    /// The outcome of a branch as text: every number printed to its last bit.
    fn exact(outcome: &Result<JointPath, Failure>) -> String {
        format!("{outcome:?}")
    }

    /// Branches tracked four at a time in the lanes follow the same paths and fail at the same
    /// samples for the same reasons, bit for bit, as each tracked alone: several trajectories'
    /// branches mixed in one batch, lanes refilled as branches end, samples resolved alone
    /// (large jumps, samples out of reach), on an arm without and one with joint limits that
    /// bind often.
    #[test]
    fn branches_tracked_in_lanes_are_tracked_alone_bit_for_bit() {
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(21);
        let panda = BuiltinRobot::Panda.chain_specs().remove(0);
        let panda = Chain::from_spec(&panda).expect("the built-in Panda");
        for chain in [baxter(Arm::Left), panda] {
            let options = TrajectoryIkOptions {
                branches: 3,
                ..TrajectoryIkOptions::default()
            };
            let kernel = Kernel::new(&chain, 1e-5, 1e-5);
            let q_start = chain.mid_configuration();
            for case in 0..12 {
                let trajectories: Vec<Vec<Isometry3<f64>>> = (0..rng.random_range(1..6))
                    .map(|_| {
                        let samples = rng.random_range(1..25);
                        // Some held still: a lane resumed already within tolerance.
                        let speed = if rng.random_range(0..5) == 0 {
                            0.0
                        } else {
                            rng.random_range(0.005..0.12)
                        };
                        let jump = rng.random_range(0..3) == 0;
                        let away = rng.random_range(0..4) == 0;
                        random_path(&chain, &mut rng, samples, speed, jump, away)
                    })
                    .collect();
                let trackers: Vec<Tracker<'_>> = trajectories
                    .iter()
                    .map(|poses| Tracker {
                        kernel,
                        poses,
                        options: &options,
                    })
                    .collect();
                let starts: Vec<Vec<Vec<f64>>> = trackers
                    .iter()
                    .map(|t| t.initial_solutions(&q_start).unwrap_or_default())
                    .collect();
                let jobs: Vec<Job<'_>> = trackers
                    .iter()
                    .zip(&starts)
                    .flat_map(|(tracker, starts)| Job::branches(tracker, starts))
                    .collect();
                let in_lanes = track_in_lanes(&jobs);
                assert_eq!(in_lanes.len(), jobs.len());
                for (k, job) in jobs.iter().enumerate() {
                    let alone = job.tracker.track(job.branch, job.start);
                    assert_eq!(exact(&in_lanes[k]), exact(&alone), "case {case}, job {k}");
                }
            }
        }
    }
}
