//! The self-motion search of one candidate ([`Redundancy::Optimize`](crate::task::Redundancy)):
//! the whole motion whose ranked index is largest over the arm's self-motion around its
//! branches.

use super::branch_checks::{check_branch, BranchCheck, BranchFindings};
use super::path::{index_along, ObjectMotion};
use super::{ChosenBranch, ScoringSetup, SelfMotionScores};
use crate::grasp::Candidate;
use crate::robot::{optimize_self_motion, KeptRows, SelfMotionOptions};
use nalgebra::{Isometry3, Matrix6xX};

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
    /// Searches the self-motion around the chosen branch and the first branch for the whole
    /// motion with the largest `Σ v²` of the ranked index `v` on the path (`μ_l2²`); replaces
    /// `chosen` when that motion ranks higher by the task's norm and is collision-free.
    /// Returns what was found.
    pub(super) fn improve(
        &self,
        chosen: &mut ChosenBranch,
        first_branch: Option<&(Vec<Vec<f64>>, f64)>,
    ) -> Option<SelfMotionScores> {
        let ScoringSetup {
            arm,
            rows: mode,
            ranked,
            ik,
            ..
        } = *self.setup;
        let chain = &arm.chain;
        let mut seeds: Vec<&[Vec<f64>]> = vec![&chosen.q];
        if let Some((q, _)) = first_branch.filter(|(q, _)| *q != chosen.q) {
            seeds.push(q);
        }
        let path = self.path.clone();
        let value = |i: usize, q: &[f64], jacobian: &Matrix6xX<f64>| -> f64 {
            if !path.contains(&i) {
                return 0.0;
            }
            self.motion
                .tangent(i - path.start, &self.candidate.object_from_wrist, mode)
                .map_or(0.0, |d| {
                    ranked
                        .value(mode, jacobian, &d, [q, chain.lower(), chain.upper()])
                        .powi(2)
                })
        };
        let options = SelfMotionOptions {
            max_joint_step: ik.max_joint_step,
            position_tolerance: ik.ik.position_tolerance,
            rotation_tolerance: ik.ik.rotation_tolerance,
            ..SelfMotionOptions::default()
        };
        // The self-motion keeps the task's limit margin, as the branches do.
        let found = optimize_self_motion(
            &arm.ik_chain,
            self.targets,
            &seeds,
            KeptRows::Pose,
            &value,
            &options,
        )?;
        let mut jacobian = Matrix6xX::zeros(chain.dof());
        let series = index_along(
            chain,
            self.motion,
            &self.candidate.object_from_wrist,
            &found.q[self.path.clone()],
            (mode, ranked),
            &mut jacobian,
        );
        let norms = series.norms(self.times, self.counted);
        let scores = SelfMotionScores {
            first_branch_l2: first_branch.map_or(chosen.norms.l2, |(_, l2)| *l2),
            l2_range: (found.worst_total.sqrt(), found.total.sqrt()),
        };
        let optimised = ChosenBranch {
            series,
            norms,
            q: found.q,
            findings: BranchFindings::default(),
        };
        if !optimised.better_than(chosen, self.setup.norm) {
            return Some(scores);
        }
        if let Ok(findings) = check_branch(self.checks, &optimised.q) {
            *chosen = ChosenBranch {
                findings,
                ..optimised
            };
        }
        Some(scores)
    }
}
