//! The recovery ladder of a sample whose warm-started solve gives no acceptable solution:
//! wider searches, cheapest first, and when none succeeds the reason the sample fails
//! (`joint_limit`, `discontinuity` or `unreachable`) with a detail.

use super::tracker::{max_difference, Tracker, CLASSIFY_RESTARTS};
use crate::failure::{Failure, FailureReason};
use crate::geometry::interpolate_decoupled;
use crate::robot::ik::attempt::{out_of_reach, run_attempt, RESTART_ATTEMPT_CAP};
use crate::robot::ik::kernel::{Budget, Patience, RunEnd, Strategy, Target, Workspace};
use rand::RngExt;

/// Restarts near the previous solution tried before a sample is declared failed.
const LOCAL_RESTARTS: usize = 2;
/// Intermediate poses used when a warm-started solve fails.
const SUBSTEPS: usize = 4;

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

impl Tracker<'_> {
    /// Retries sample `i` from `previous` (the solution at sample `i − 1`) with wider searches,
    /// cheapest first; `Ok` leaves the accepted solution in `ws`, `Err` says why there is none.
    pub(super) fn resolve(
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
