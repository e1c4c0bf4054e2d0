//! What a trajectory solve returns: the joint paths of the branches that follow the whole
//! trajectory, or the failure of the one that got furthest.

use crate::failure::Failure;
use serde::{Deserialize, Serialize};

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
