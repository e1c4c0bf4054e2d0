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
}

impl FailureReason {
    /// The one spelling: `unreachable`, `joint_limit`, `discontinuity`, `iteration_limit`,
    /// `time_limit`.
    pub fn as_str(self) -> &'static str {
        match self {
            Self::Unreachable => "unreachable",
            Self::JointLimit => "joint_limit",
            Self::Discontinuity => "discontinuity",
            Self::IterationLimit => "iteration_limit",
            Self::TimeLimit => "time_limit",
        }
    }
}

impl fmt::Display for FailureReason {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

/// The first sample along a path that could not be followed, and why.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Failure {
    /// Why it failed.
    pub reason: FailureReason,
    /// Index of the first failing sample (0 = the grasp pose).
    pub sample: usize,
    /// A sentence with the numbers: the joint and value at fault, the jump, or the residual.
    pub detail: String,
}

impl fmt::Display for Failure {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
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
