//! Inverse kinematics: joint configurations, inside the joint limits, at which the chain tip
//! reaches target poses given in the chain base frame (m, rad): one pose ([`solve_ik`]), a
//! whole trajectory with its redundancy branches ([`solve_trajectory`], a batch with
//! [`solve_trajectories`]), and the self-motion of a redundant arm along a found path
//! ([`optimize_self_motion`]).
//!
//! The files of this folder, the numerical core first:
//! * `simd`: the arithmetic of one run and of four runs in vector lanes, as one trait.
//! * `kernel`: the pose error, one damped least-squares step with joint-limit handling, and
//!   a Levenberg–Marquardt run.
//! * `lanes`: four runs at once, one per vector lane, bit-identical to each run alone.
//! * `attempt`: one attempt of a run (its start, limit strategy and cap) and what every
//!   solver shares around it.
//! * `single_pose`: the single-pose solver, [`solve_ik`], with its options and results.
//! * `trajectory/`: trajectory IK, [`solve_trajectory`] and [`solve_trajectories`].
//! * `self_motion`: the null space of the Jacobian and the self-motion that improves a
//!   path's value.

mod attempt;
mod kernel;
mod lanes;
mod self_motion;
mod simd;
mod single_pose;
mod trajectory;

pub use self_motion::{
    null_space, optimize_self_motion, optimize_smooth_self_motion, KeptRows, SampleValue,
    SelfMotionOptions, SelfMotionPath, SmoothSelfMotion,
};
pub use single_pose::{solve_ik, IkFailure, IkOptions, IkSolution};
pub use trajectory::{
    solve_trajectories, solve_trajectory, JointPath, TrajectoryIkOptions, TrajectoryIkResult,
};
