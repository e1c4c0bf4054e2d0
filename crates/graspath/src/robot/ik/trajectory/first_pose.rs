//! The search for initial solutions at the first pose: every distinct solution starts a
//! branch ([`Tracker::initial_solutions`]); when there is none inside the limits, why
//! ([`Tracker::classify_first`]).

use super::tracker::{max_difference, Tracker, CLASSIFY_RESTARTS};
use crate::failure::{Failure, FailureReason};
use crate::robot::chain::MAX_JOINTS;
use crate::robot::ik::attempt::{out_of_reach, prepare_attempt, run_attempt, wrap_continuous};
use crate::robot::ik::kernel::{Budget, Patience, RunEnd, Strategy, Target, Workspace};
use crate::robot::ik::lanes::{run_each, run_in_order, Attempt, Handed, Lanes};
use rand::rngs::Xoshiro256PlusPlus;
use rand::SeedableRng;
use std::ops::ControlFlow;

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

impl Tracker<'_> {
    /// Distinct solutions at sample 0, the one from `q_start` first.
    ///
    /// Attempt 0 runs from `q_start` with the first limit strategy; attempt 1, from `q_start`
    /// with the other, only when attempt 0 fails; then random restarts. The attempts after the
    /// first run four at a time in vector lanes ([`run_in_order`]), with the results of running
    /// them one after the other.
    pub(super) fn initial_solutions(&self, q_start: &[f64]) -> Result<Vec<Vec<f64>>, Failure> {
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
}
