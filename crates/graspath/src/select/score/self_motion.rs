//! The self-motion search of one candidate ([`Redundancy::Optimize`](crate::task::Redundancy)):
//! the whole motion whose ranked index is largest over the arm's self-motion around its best
//! branch, the arm's place in the self-motion a smooth function of the path's time
//! ([`optimize_smooth_self_motion`]).

use super::branch_checks::{check_branch, BranchCheck, BranchFindings};
use super::path::{index_along, ObjectMotion};
use super::{BranchOrder, ChosenBranch, ScoringSetup, SelfMotionScores};
use crate::grasp::Candidate;
use crate::manipulability::DynamicManipulability;
use crate::manipulability::Norm;
use crate::robot::{optimize_smooth_self_motion, KeptRows, SelfMotionOptions, SmoothSelfMotion};
use nalgebra::{Isometry3, Matrix6xX};
use std::sync::{Mutex, PoisonError};

/// The self-motion search of one candidate ([`Redundancy::Optimize`]).
pub(super) struct SelfMotionSearch<'a> {
    pub(super) setup: &'a ScoringSetup<'a>,
    pub(super) candidate: &'a Candidate,
    pub(super) motion: &'a ObjectMotion,
    pub(super) times: &'a [f64],
    /// Which path samples the norms count.
    pub(super) counted: &'a [bool],
    /// The whole motion's tool poses, chain base frame.
    pub(super) targets: &'a [Isometry3<f64>],
    /// The object's path within the whole motion.
    pub(super) path: std::ops::Range<usize>,
    /// The checks a whole motion must pass.
    pub(super) checks: &'a [Box<dyn BranchCheck + 'a>],
}

impl SelfMotionSearch<'_> {
    /// Searches the self-motion around the chosen branch for the smooth whole motion with the
    /// largest `Σ wᵢ vᵢ²` of the ranked index `v` on the path (`wᵢ` the samples' shares of the
    /// path's time for `μ_rms` and `μ_l1`, 1 for `μ_l2`); replaces `chosen` when that motion
    /// ranks higher by the task's norm and passes the branch checks. Returns the range of
    /// `μ_l2` over the self-motion.
    /// `dynamic` evaluates the dynamic measure when the task ranks by it.
    pub(super) fn improve(
        &self,
        chosen: &mut ChosenBranch,
        first_branch: Option<&(Vec<Vec<f64>>, f64)>,
        dynamic: Option<&mut DynamicManipulability<'_>>,
    ) -> Option<SelfMotionScores> {
        let ScoringSetup {
            arm,
            rows: mode,
            ranked,
            ik,
            ..
        } = *self.setup;
        let chain = &arm.chain;
        let path = self.path.clone();
        // The search evaluates through a shared reference; the dynamic workspace is its
        // one piece of mutable state (never contended: one candidate, one thread).
        let dynamic = Mutex::new(dynamic);
        let value = |i: usize, q: &[f64], jacobian: &Matrix6xX<f64>| -> f64 {
            if !path.contains(&i) {
                return 0.0;
            }
            self.motion
                .tangent(i - path.start, &self.candidate.object_from_wrist, mode)
                .map_or(0.0, |d| {
                    ranked
                        .value(
                            mode,
                            jacobian,
                            &d,
                            [q, chain.lower(), chain.upper()],
                            dynamic
                                .lock()
                                .unwrap_or_else(PoisonError::into_inner)
                                .as_deref_mut(),
                        )
                        .powi(2)
                })
        };
        let options = SelfMotionOptions {
            max_joint_step: ik.max_joint_step,
            position_tolerance: ik.ik.position_tolerance,
            rotation_tolerance: ik.ik.rotation_tolerance,
            ..SelfMotionOptions::default()
        };
        let (times, weights) = self.times_and_weights();
        // The self-motion keeps the task's limit margin, as the branches do.
        let found = optimize_smooth_self_motion(
            &arm.ik_chain,
            self.targets,
            &chosen.q,
            KeptRows::Pose,
            &value,
            &options,
            &SmoothSelfMotion::new(&times, &weights),
        )?;
        let mut jacobian = Matrix6xX::zeros(chain.dof());
        let series = index_along(
            chain,
            self.motion,
            &self.candidate.object_from_wrist,
            &found.q[self.path.clone()],
            (mode, ranked),
            &mut jacobian,
            dynamic.into_inner().unwrap_or_else(PoisonError::into_inner),
        );
        let norms = series.norms(self.times, self.counted);
        let first_branch_l2 = first_branch.map_or(chosen.norms.l2, |(_, l2)| *l2);
        let optimised = ChosenBranch {
            series,
            norms,
            q: found.q,
            findings: BranchFindings::default(),
        };
        // By the norm only a better path is checked; by duration the checks time it first.
        let order = BranchOrder::of(self.setup);
        if order.by_duration || chosen.norms_better(&optimised.norms, order.norm) {
            if let Ok(findings) = check_branch(self.checks, &optimised.q) {
                let checked = ChosenBranch {
                    findings,
                    ..optimised
                };
                if checked.better_than(chosen, order) {
                    *chosen = checked;
                }
            }
        }
        // The range over every motion seen: the traced states' chains, the first branch and
        // the one kept.
        let (low, high) = (found.worst_total.sqrt(), found.best_total.sqrt());
        Some(SelfMotionScores {
            first_branch_l2,
            l2_range: (
                low.min(first_branch_l2).min(chosen.norms.l2),
                high.max(chosen.norms.l2),
            ),
        })
    }

    /// Each whole-motion sample's time (the approach at the path's start, the retreat at its
    /// end) and weight in the search: its share of the path's time (trapezoidal) when the
    /// task's norm integrates over time, 1 on the path for `μ_l2`; 0 off the path.
    fn times_and_weights(&self) -> (Vec<f64>, Vec<f64>) {
        let total = self.targets.len();
        let (start, end) = (self.path.start, self.path.end);
        let first = self.times.first().copied().unwrap_or(0.0);
        let last = self.times.last().copied().unwrap_or(0.0);
        let times = (0..total)
            .map(|i| {
                if i < start {
                    first
                } else if i >= end {
                    last
                } else {
                    self.times[i - start]
                }
            })
            .collect();
        let by_time = self.setup.norm != Norm::L2;
        let weights = (0..total)
            .map(|i| {
                if i < start || i >= end {
                    return 0.0;
                }
                let k = i - start;
                if !by_time {
                    return 1.0;
                }
                let before = if k > 0 {
                    self.times[k] - self.times[k - 1]
                } else {
                    0.0
                };
                let after = self.times.get(k + 1).map_or(0.0, |t| t - self.times[k]);
                0.5 * (before + after)
            })
            .collect();
        (times, weights)
    }
}
