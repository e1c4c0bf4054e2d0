//! The options of a trajectory solve and their defaults.

use crate::robot::ik::single_pose::IkOptions;

/// Options of a trajectory solve.
#[derive(Debug, Clone, PartialEq)]
pub struct TrajectoryIkOptions {
    /// Tolerances, the iteration budget of the first sample (the search for initial
    /// solutions, over all restarts) and the random seed. `max_time` is ignored: only
    /// iteration budgets are used so that results are reproducible.
    pub ik: IkOptions,
    /// Largest change of any joint between consecutive samples (rad for revolute, m for
    /// prismatic joints). Also the separation that makes two initial solutions distinct.
    pub max_joint_step: f64,
    /// How many distinct initial solutions (branches) to look for and track.
    pub branches: usize,
    /// Iteration budget of the warm-started solve of one sample (recoveries and failure
    /// classification use a small multiple of it).
    pub per_sample_iterations: usize,
}

impl Default for TrajectoryIkOptions {
    /// 1e-5 m / 1e-5 rad, 1000 iterations for the first sample, 0.5 rad steps, 4 branches,
    /// 30 iterations per sample, random seed 0.
    fn default() -> Self {
        Self {
            ik: IkOptions {
                max_time: None,
                max_iterations: 1000,
                ..IkOptions::default()
            },
            max_joint_step: 0.5,
            branches: 4,
            per_sample_iterations: 30,
        }
    }
}
