//! Why a candidate, a trajectory or a single IK solve failed: one enum of reasons with one
//! spelling everywhere — the library, the CLI, the JSON files and Python.

use serde::{Deserialize, Serialize};
use std::fmt;

/// Why something could not be done. Serialised in `snake_case` (`unreachable`, `joint_limit`,
/// …); [`FailureReason::as_str`] gives the same spelling.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FailureReason {
    /// No configuration reaches the target pose: it is out of the chain's reach, or no solution
    /// near it was found.
    Unreachable,
    /// A solution exists only outside the joint limits.
    JointLimit,
    /// Solutions exist only farther than the joint-step bound from the previous sample.
    Discontinuity,
    /// A single IK solve ran out of its iteration budget.
    IterationLimit,
    /// A single IK solve ran out of its time budget.
    TimeLimit,
    /// Two bodies come closer than allowed: the arm, its hand or the carried object against
    /// the scene, itself, the object or the other arm.
    Collision,
    /// The object is wider across the fingers than the gripper opens.
    GripperWidth,
    /// Holding the arm and the carried object still needs more torque at a joint than its
    /// effort limit allows.
    TorqueLimit,
    /// No timing of the motion stays within the joints' velocity, acceleration and torque
    /// limits (e.g. a torque needed at rest beyond its limit, or a limit of zero).
    TimingInfeasible,
}

impl FailureReason {
    /// The one spelling: `unreachable`, `joint_limit`, `discontinuity`, `iteration_limit`,
    /// `time_limit`, `collision`, `gripper_width`, `torque_limit`, `timing_infeasible`.
    pub fn as_str(self) -> &'static str {
        match self {
            Self::Unreachable => "unreachable",
            Self::JointLimit => "joint_limit",
            Self::Discontinuity => "discontinuity",
            Self::IterationLimit => "iteration_limit",
            Self::TimeLimit => "time_limit",
            Self::Collision => "collision",
            Self::GripperWidth => "gripper_width",
            Self::TorqueLimit => "torque_limit",
            Self::TimingInfeasible => "timing_infeasible",
        }
    }
}

impl fmt::Display for FailureReason {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

/// The phases of a candidate's whole motion.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Phase {
    /// From the pre-grasp pose straight in to the grasp (the grasp itself is the path's
    /// sample 0).
    Approach,
    /// The object's path, from the grasp (sample 0) to the place.
    #[default]
    Path,
    /// After the place, the hand backing away from the object.
    Retreat,
}

impl Phase {
    /// The one spelling: `approach`, `path`, `retreat`.
    pub fn as_str(self) -> &'static str {
        match self {
            Self::Approach => "approach",
            Self::Path => "path",
            Self::Retreat => "retreat",
        }
    }
}

impl fmt::Display for Phase {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

/// The first sample along a motion that could not be followed, and why.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Failure {
    /// Why it failed.
    pub reason: FailureReason,
    /// The phase of the motion it failed in.
    #[serde(default)]
    pub phase: Phase,
    /// Index of the first failing sample within its phase (path: 0 = the grasp pose).
    pub sample: usize,
    /// A sentence with the numbers: the joint and value at fault, the jump, the residual, or
    /// the distance of the two bodies.
    pub detail: String,
    /// For collisions: the two bodies (`link left_wrist`, `obstacle wall`, `table`, `object`,
    /// `hand l_finger`, `right arm: link ...`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bodies: Option<[String; 2]>,
    /// The joint at fault, when one is: the joint whose torque limit is exceeded
    /// (`torque_limit`) or whose limit no timing satisfies (`timing_infeasible`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub joint: Option<String>,
}

impl Failure {
    /// A failure on the object's path at `sample`, without bodies.
    pub fn new(reason: FailureReason, sample: usize, detail: impl Into<String>) -> Self {
        Self {
            reason,
            phase: Phase::Path,
            sample,
            detail: detail.into(),
            bodies: None,
            joint: None,
        }
    }
}

impl fmt::Display for Failure {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.phase != Phase::Path {
            write!(f, "{} ", self.phase)?;
        }
        write!(
            f,
            "sample {}: {}: {}",
            self.sample, self.reason, self.detail
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_serialised_spelling_is_the_displayed_one() {
        for reason in [
            FailureReason::Unreachable,
            FailureReason::JointLimit,
            FailureReason::Discontinuity,
            FailureReason::IterationLimit,
            FailureReason::TimeLimit,
            FailureReason::Collision,
            FailureReason::GripperWidth,
            FailureReason::TorqueLimit,
            FailureReason::TimingInfeasible,
        ] {
            let json = serde_json::to_string(&reason).unwrap();
            assert_eq!(json, format!("\"{}\"", reason.as_str()));
            assert_eq!(
                serde_json::from_str::<FailureReason>(&json).unwrap(),
                reason
            );
        }
    }
}
