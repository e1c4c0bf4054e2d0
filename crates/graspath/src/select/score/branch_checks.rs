//! Checks of one IK branch's whole motion (approach, path, retreat), after IK: each refuses
//! the branch with a failure or records what it measured ([`BranchFindings`]), which the
//! candidate's score keeps for the branch chosen. `branch_checks` (in the parent module) lists
//! them in the order they run; a new check is a type in its own file and one line there.

use super::Scoring;
use crate::collision::{ArmInScene, CollisionHit, ObjectAlong, WholeMotion};
use crate::failure::{Failure, FailureReason, Phase};

/// What the branch checks measured on a branch that passed them all.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(super) struct BranchFindings {
    /// The smallest distance between the robot (hand and carried object included) and the
    /// scene at any sample of the motion (m), with a scene.
    pub(super) clearance: Option<f64>,
    /// With a payload: the worst `1 − |τ_j| / τ_max,j` over the samples and the joints with an
    /// effort limit.
    pub(super) torque_margin: Option<f64>,
    /// With a payload: the largest object mass (kg) this motion can carry within the effort
    /// limits (`None` when no limited joint bears the object).
    pub(super) payload_capacity: Option<f64>,
    /// When the task times motions: how long the motion takes.
    pub(super) durations: Option<super::MotionDurations>,
}

/// A check of one branch's whole motion.
pub(super) trait BranchCheck {
    /// Checks the joint configurations `q` of the whole motion (one per sample); `Err` with
    /// the failure (its sample in the whole motion's numbering, located in its phase) refuses
    /// the branch, otherwise what was measured goes into `findings`.
    fn check(&self, q: &[Vec<f64>], findings: &mut BranchFindings) -> Result<(), Failure>;
}

/// Runs `checks` on the whole motion `q`: what they measured, or the first failure.
pub(super) fn check_branch(
    checks: &[Box<dyn BranchCheck + '_>],
    q: &[Vec<f64>],
) -> Result<BranchFindings, Failure> {
    let mut findings = BranchFindings::default();
    for check in checks {
        check.check(q, &mut findings)?;
    }
    Ok(findings)
}

/// The arm, its hand and the carried object against the scene, the arm itself and the object,
/// at every sample of the motion and between samples; measures the clearance.
pub(super) struct SceneCheck<'a> {
    scoring: &'a Scoring<'a>,
    checker: &'a ArmInScene<'a>,
    object: ObjectAlong<'a>,
}

impl<'a> SceneCheck<'a> {
    pub(super) fn of(scoring: &'a Scoring<'a>) -> Option<Self> {
        Some(Self {
            scoring,
            checker: scoring.checker.as_ref()?,
            object: scoring.object_along(),
        })
    }
}

impl BranchCheck for SceneCheck<'_> {
    fn check(&self, q: &[Vec<f64>], findings: &mut BranchFindings) -> Result<(), Failure> {
        let check = self.checker.check(&WholeMotion {
            q,
            object: self.object.clone(),
        });
        if let Some(hit) = check.hit {
            return Err(collision_failure(&hit, self.scoring));
        }
        findings.clearance = check.clearance;
        Ok(())
    }
}

/// A collision hit as a failure, located in its phase: the detail numbers the samples as the
/// failure's `phase` and `sample` do (0 = the phase's first).
pub(super) fn collision_failure(hit: &CollisionHit, scoring: &Scoring<'_>) -> Failure {
    let [a, b] = &hit.bodies;
    let (phase, sample) = scoring.plan.phase_of(hit.sample);
    let at = if hit.between {
        let (next_phase, next) = scoring.plan.phase_of(hit.sample + 1);
        if next_phase == phase {
            format!("between {phase} samples {sample} and {next}")
        } else {
            format!("between {phase} sample {sample} and {next_phase} sample {next}")
        }
    } else {
        format!("at {phase} sample {sample}")
    };
    scoring.located(Failure {
        reason: FailureReason::Collision,
        phase: Phase::Path,
        sample: hit.sample,
        detail: format!(
            "{a} and {b} are {:.4} m apart {at}; they must keep {:.4} m",
            hit.distance, hit.required
        ),
        bodies: Some(hit.bodies.clone()),
        joint: None,
    })
}
