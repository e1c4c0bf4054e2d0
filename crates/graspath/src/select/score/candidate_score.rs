//! [`CandidateScore`]: what scoring found for one candidate and arm — its failure or its
//! index series, norms, motion and clearances — the row every output is read from.

use super::*;
use crate::defaults::{LIMIT_HUG_DISTANCE, LIMIT_HUG_SHARE};

/// A candidate's scores for one arm.
#[derive(Debug, Clone, PartialEq)]
pub struct CandidateScore {
    /// The candidate scored (shared with the task).
    pub candidate: Arc<Candidate>,
    /// Set when the arm cannot follow the whole path from this grasp.
    pub failure: Option<Failure>,
    /// `M_T` at each sample (`None` where the object is still), along the chosen IK branch.
    pub m_t: Vec<Option<f64>>,
    /// The ranked index at each sample when it is not `M_T` itself (`index.measure:
    /// velocity_ratio` or a joint-limit penalty; `None` otherwise).
    pub ranked_values: Option<Vec<Option<f64>>>,
    /// The norms of the ranked index, `ranked_values` or else `m_t` (when feasible).
    pub norms: Option<PathNorms>,
    /// Yoshikawa's index of the full `J` at the grasp (when the grasp is reachable), at the
    /// grasp's own configuration: the grasp pose's IK from the arm's mid configuration (the
    /// first solution of the trajectory solver's search there), whatever branch or
    /// self-motion the task then follows — so the classical indices depend on the grasp pose
    /// only, never on the task.
    pub yoshikawa_at_grasp: Option<f64>,
    /// Yoshikawa's index at the grasp times the joint-limit penalty there (with
    /// `index.joint_limit_penalty`).
    pub yoshikawa_penalized_at_grasp: Option<f64>,
    /// `σmin/σmax` of `J` at the grasp configuration.
    pub inverse_condition_at_grasp: Option<f64>,
    /// `λmin/λmax` of `J Jᵀ` at the grasp configuration (the paper's eq. 12).
    pub inverse_condition_squared_at_grasp: Option<f64>,
    /// Per path sample, how far the joint nearest to a limit is from it (rad or m; `+∞`
    /// without limited joints), along the chosen motion (when feasible).
    pub limit_distance: Vec<f64>,
    /// Joint configurations along the path (rad / m), one per sample, of the chosen branch.
    pub joint_trajectory: Vec<Vec<f64>>,
    /// Joint configurations of the approach, before the grasp (empty without an approach).
    pub approach: Vec<Vec<f64>>,
    /// Joint configurations of the retreat, after the place (empty without a retreat).
    pub retreat: Vec<Vec<f64>>,
    /// The smallest distance between the robot (hand and carried object included) and the
    /// scene at any sample of the motion (m), when the task has a scene.
    pub clearance: Option<f64>,
    /// How many distinct feasible IK branches were found.
    pub feasible_branches: usize,
    /// With `ik.redundancy: optimize`: what the self-motion search found (for a feasible
    /// candidate whose first branch is feasible).
    pub self_motion: Option<SelfMotionScores>,
    /// With the object's mass: the worst `1 − |τ_j| / τ_max,j` along the chosen motion (joints
    /// with an effort limit; gravity torques of the arm and, from the grasp to the place, the
    /// object).
    pub torque_margin: Option<f64>,
    /// With the object's mass: the largest object mass (kg) the chosen motion can carry within
    /// the effort limits (`None` when no limited joint bears the object).
    pub payload_capacity: Option<f64>,
    /// With the object's mass or `index.measure: dynamic`: the task's norm of the dynamic
    /// task-relevant manipulability `M_D` along the chosen path
    /// ([`crate::manipulability::DynamicManipulability`]; `(m/s²)²` per sample).
    pub dynamic_manipulability: Option<f64>,
    /// When the task times motions: how long the chosen motion takes (its approach, carry and
    /// retreat), fastest within the joints' limits.
    pub durations: Option<MotionDurations>,
}

/// How much of a candidate's `μ_l2` is the grasp and how much the arm's self-motion.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SelfMotionScores {
    /// `μ_l2` along the first IK branch (the paper's practice).
    pub first_branch_l2: f64,
    /// The smallest and the largest `μ_l2` of the joint paths seen in the self-motion: every
    /// chain of traced configurations within the joint-step bound, the first branch and the
    /// motion kept (collision checks aside). The kept motion is smooth in time, so its own
    /// `μ_l2` may lie below the largest.
    pub l2_range: (f64, f64),
}

impl CandidateScore {
    /// A candidate not scored yet: no failure, no values, no trajectory.
    pub fn unscored(candidate: Arc<Candidate>) -> Self {
        Self {
            candidate,
            failure: None,
            m_t: Vec::new(),
            ranked_values: None,
            norms: None,
            yoshikawa_at_grasp: None,
            yoshikawa_penalized_at_grasp: None,
            inverse_condition_at_grasp: None,
            inverse_condition_squared_at_grasp: None,
            limit_distance: Vec::new(),
            joint_trajectory: Vec::new(),
            approach: Vec::new(),
            retreat: Vec::new(),
            clearance: None,
            feasible_branches: 0,
            self_motion: None,
            torque_margin: None,
            payload_capacity: None,
            dynamic_manipulability: None,
            durations: None,
        }
    }

    /// Whether IK succeeded along the whole path.
    pub fn feasible(&self) -> bool {
        self.failure.is_none()
    }

    /// The smallest distance (rad or m) of any joint to its limit along the chosen motion;
    /// `None` when infeasible.
    pub fn limit_distance_min(&self) -> Option<f64> {
        let min = self
            .limit_distance
            .iter()
            .copied()
            .fold(f64::INFINITY, f64::min);
        min.is_finite().then_some(min)
    }

    /// Whether the chosen motion hugs a joint limit: at least
    /// [`LIMIT_HUG_SHARE`] of the path samples have a joint within
    /// [`LIMIT_HUG_DISTANCE`] of a limit.
    pub fn hugs_limit(&self) -> bool {
        let near = self
            .limit_distance
            .iter()
            .filter(|d| **d <= LIMIT_HUG_DISTANCE)
            .count();
        !self.limit_distance.is_empty()
            && near as f64 >= LIMIT_HUG_SHARE * self.limit_distance.len() as f64
    }
}
