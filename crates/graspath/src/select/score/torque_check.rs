//! The joint torques that hold the arm and the carried object still at every sample of the
//! motion (gravity torques `g(q)` with the object as a payload at the tool from the grasp to
//! the place; the arm alone during the approach and the retreat), against the arm's effort
//! limits: a branch that needs more is refused (`torque_limit`); one that passes records its
//! torque margin and the payload capacity of the grasp for this task.

use super::branch_checks::{BranchCheck, BranchFindings};
use super::Scoring;
use crate::failure::{Failure, FailureReason, Phase};
use crate::robot::Dynamics;
use nalgebra::{Point3, Vector3};
use std::ops::Range;

/// The torque check of one candidate.
pub(super) struct TorqueCheck<'a> {
    scoring: &'a Scoring<'a>,
    dynamics: &'a Dynamics,
    /// The object's centre of mass in the tool frame (m): holding it needs its mass times the
    /// torques that hold one kilogram there (gravity torques are linear in the mass at a fixed
    /// centre of mass).
    object_com: Vector3<f64>,
    /// The object's mass (kg).
    mass: f64,
    /// The samples of the whole motion where the object is held (the path).
    held: Range<usize>,
    /// Each joint's effort limit (N·m or N), `None` where the robot gives none.
    limits: Vec<Option<f64>>,
}

impl<'a> TorqueCheck<'a> {
    /// The check of `scoring`'s candidate, when its task carries a payload.
    pub(super) fn of(scoring: &'a Scoring<'a>) -> Option<Self> {
        let payload = scoring.setup.world.payload?;
        let dynamics = scoring.setup.arm.dynamics.as_deref()?;
        let wrist_from_object = scoring.candidate.object_from_wrist.inverse();
        let object_com = wrist_from_object * Point3::from(payload.com);
        let before = scoring.plan.approach_samples();
        Some(Self {
            scoring,
            dynamics,
            object_com: object_com.coords,
            mass: payload.mass,
            held: before..before + scoring.setup.path.samples.len(),
            limits: dynamics.motion_limits().iter().map(|l| l.effort).collect(),
        })
    }
}

impl BranchCheck for TorqueCheck<'_> {
    fn check(&self, q: &[Vec<f64>], findings: &mut BranchFindings) -> Result<(), Failure> {
        let dof = self.dynamics.dof();
        let mut data = self.dynamics.data();
        let (mut arm, mut per_kg) = (vec![0.0; dof], vec![0.0; dof]);
        let mut margin = f64::INFINITY;
        let mut capacity = f64::INFINITY;
        for (sample, q) in q.iter().enumerate() {
            let held = self.held.contains(&sample);
            let evaluated = if held {
                self.dynamics.gravity_torques_and_point_load_into(
                    &mut data,
                    q,
                    &self.object_com,
                    &mut arm,
                    &mut per_kg,
                )
            } else {
                self.dynamics.gravity_torques_into(&mut data, q, &mut arm)
            };
            if let Err(e) = evaluated {
                return Err(self.failure(
                    sample,
                    None,
                    format!("the joint torques cannot be computed: {e}"),
                ));
            }
            for (j, limit) in self.limits.iter().enumerate() {
                let Some(limit) = *limit else { continue };
                // τ(m) = τ_arm + m · τ_per_kg: affine in the object's mass.
                let slope = if held { per_kg[j] } else { 0.0 };
                let tau = arm[j] + self.mass * slope;
                if tau.abs() > limit {
                    let joint = &self.scoring.setup.arm.chain.joint_names()[j];
                    return Err(self.failure(
                        sample,
                        Some(joint.clone()),
                        format!(
                            "joint '{joint}' needs {tau:.2} N·m to hold the arm{} still at \
                             sample {}, beyond its {limit:.2} N·m limit",
                            if held { " and the object" } else { "" },
                            self.scoring.plan.phase_of(sample).1
                        ),
                    ));
                }
                margin = margin.min(1.0 - tau.abs() / limit);
                // The largest mass within the limit here: |τ_arm + m · slope| ≤ limit.
                if slope > 0.0 {
                    capacity = capacity.min((limit - arm[j]) / slope);
                } else if slope < 0.0 {
                    capacity = capacity.min((-limit - arm[j]) / slope);
                }
            }
        }
        findings.torque_margin = margin.is_finite().then_some(margin);
        findings.payload_capacity = capacity.is_finite().then_some(capacity);
        Ok(())
    }
}

impl TorqueCheck<'_> {
    /// A `torque_limit` failure at whole-motion sample `sample` (at `joint`), located in its
    /// phase.
    fn failure(&self, sample: usize, joint: Option<String>, detail: String) -> Failure {
        self.scoring.located(Failure {
            reason: FailureReason::TorqueLimit,
            phase: Phase::Path,
            sample,
            detail,
            bodies: None,
            joint,
        })
    }
}
