//! How long a motion takes: a branch's joint samples as a smooth path, its time-optimal
//! parameterisation under joint velocity, acceleration and torque limits (TOPP-RA), and the
//! timed trajectory a controller can execute.
//!
//! * [`JointSpline`]: the natural cubic spline `q(s)` through the IK samples, in a chord-length
//!   parameter `s`.
//! * [`Constraints`] and [`time_optimal`]: the reachability analysis on a grid of `s`.
//! * [`PathLimits`]: the constraints of a robot's path (its velocity and
//!   acceleration limits, and its torque limits through the inverse dynamics, with a carried
//!   payload) and the fastest motion from rest to rest.
//! * [`TimedTrajectory`]: the timed motion sampled in time (positions, velocities,
//!   accelerations, torques).
//!
//! Units: `s` in rad (the joint-space distance along the path), times in s, joint velocities
//! in rad/s (m/s), accelerations in rad/s² (m/s²), torques in N·m (N).

mod motion;
mod spline;
mod topp;
mod trajectory;

#[cfg(test)]
mod tests;

pub use motion::{ObjectLimits, PathLimits, TorqueLimits};
pub use spline::{JointSpline, PathPoint, REPEATED_SAMPLE};
pub use topp::{time_optimal, Constraints, Discretization, Limit, Row, TimedPath};
pub use trajectory::{TimedTrajectory, Torques, TrajectoryPoint, MAX_POINTS};

use crate::robot::RobotError;

/// Why a path cannot be timed.
#[derive(Debug, thiserror::Error)]
pub enum TimingError {
    /// The samples or knots do not make a path (none, unequal lengths, not finite, knots not
    /// increasing).
    #[error("the path cannot be timed: {0}")]
    BadPath(String),
    /// A limit is not a positive number.
    #[error("joint {joint}: the {what} limit {value} is not a positive number")]
    BadLimit {
        /// The joint's index in the chain.
        joint: usize,
        /// `velocity`, `acceleration` or `torque`.
        what: &'static str,
        /// The value given.
        value: f64,
    },
    /// No motion along the path satisfies the limits: at grid point `grid_point` (path
    /// parameter `s`) not even the slowest admissible motion stays within them.
    #[error("no timing satisfies the limits at path parameter {s:.4} (grid point {grid_point}){}", binding(.limit))]
    Infeasible {
        /// The grid point's index.
        grid_point: usize,
        /// The path parameter there.
        s: f64,
        /// The constraint most violated there, when one is.
        limit: Option<Limit>,
    },
    /// The inverse dynamics failed; the robot's error is the source.
    #[error("the joint torques cannot be computed")]
    Dynamics(#[from] RobotError),
}

impl crate::fault::Classify for TimingError {
    /// The inverse dynamics' failure has the robot error's kind; everything else is
    /// [`ErrorKind`](crate::fault::ErrorKind)`::Content`.
    fn kind(&self) -> Option<crate::fault::ErrorKind> {
        match self {
            Self::Dynamics(_) => None,
            _ => Some(crate::fault::ErrorKind::Content),
        }
    }
}

/// `: joint 3's torque`, for [`TimingError::Infeasible`].
fn binding(limit: &Option<Limit>) -> String {
    match limit {
        None => String::new(),
        Some(Limit::Velocity(j)) => format!(": joint {j}'s velocity limit binds"),
        Some(Limit::Acceleration(j)) => format!(": joint {j}'s acceleration limit binds"),
        Some(Limit::Torque(j)) => format!(": joint {j}'s torque limit binds"),
        Some(Limit::ObjectSpeed) => ": the object's speed limit binds".into(),
        Some(Limit::ObjectTurnRate) => ": the object's turn-rate limit binds".into(),
        Some(Limit::ObjectAcceleration) => ": the object's acceleration limit binds".into(),
        Some(Limit::ObjectAngularAcceleration) => {
            ": the object's angular acceleration limit binds".into()
        }
    }
}
