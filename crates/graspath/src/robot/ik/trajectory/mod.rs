//! Inverse kinematics along a whole trajectory of tip poses: continuous joint paths inside the
//! joint limits, one per distinct initial solution (redundancy branch, elbow or wrist flip).
//!
//! Sample 0 is solved from the start configuration `q_start` and from seeded random restarts;
//! every solution that differs from the ones already kept by more than
//! [`TrajectoryIkOptions::max_joint_step`] in some joint starts a branch (up to
//! [`TrajectoryIkOptions::branches`]). Each branch is then tracked sample by sample, each
//! solve warm-started from the previous sample's solution and
//! its Jacobian. A sample is accepted only when its solution is within tolerance, inside the
//! limits and no joint moves more than `max_joint_step` from the previous sample, so a branch
//! flip hidden inside a "continuous" path is a failure, never a silent jump.
//!
//! When the warm-started solve gives no acceptable solution, wider searches follow, cheapest
//! first: the other limit strategy from the previous solution; the pose step split into four
//! intermediate poses; a solve without limits from the previous solution; two seeded restarts
//! near the previous solution; three seeded restarts anywhere in the limits. The first acceptable
//! solution is taken; otherwise the sample fails with the reason:
//!
//! * `joint_limit`: the solve without limits converges within `max_joint_step` of the previous
//!   solution but outside the limits (the path would have to leave them), or it converges
//!   farther away and no solution inside the limits was found;
//! * `discontinuity`: solutions inside the limits exist, but only farther than
//!   `max_joint_step` from the previous sample (the detail names the joint and the jump);
//! * `unreachable`: the chain's geometry proves the target out of reach (the detail names the
//!   two points the target puts farther apart than the links between them span, see
//!   `Chain::out_of_reach`), or no solution near it was found (the
//!   detail gives the best residual). Every pose is checked for such a proof before the
//!   search, and the first proven out of reach fails the trajectory at once: the cause is
//!   named, not the discontinuity met while the arm stretches towards it.
//!
//! Only iteration budgets are used (the time budget
//! [`IkOptions::max_time`](super::IkOptions::max_time) is ignored here), so results are
//! identical from run to run and at any thread count.
//!
//! [`solve_trajectories`] solves a batch of trajectories with the same results, bit for bit,
//! as [`solve_trajectory`] one by one: the branches of the whole batch are tracked four at a
//! time, one per vector lane ([`super::lanes`]), which is where a selection spends most of its
//! time.
//!
//! The files of this folder, each importing only those before it:
//! * [`options`]: [`TrajectoryIkOptions`] and its defaults; [`result`]: [`JointPath`] and
//!   [`TrajectoryIkResult`].
//! * [`tracker`]: one trajectory's solve ([`tracker::Tracker`]) and what its steps share.
//! * [`first_pose`]: the search for the branches' initial solutions at the first pose.
//! * [`recovery`]: the ladder of wider searches of a sample the warm-started solve misses.
//! * [`tracking`]: branches tracked one by one or four at a time in vector lanes.
//! * [`solve`]: the entry points, [`solve_trajectory`] and [`solve_trajectories`].

mod first_pose;
mod options;
mod recovery;
mod result;
mod solve;
mod tracker;
mod tracking;

pub use options::TrajectoryIkOptions;
pub use result::{JointPath, TrajectoryIkResult};
pub use solve::{solve_trajectories, solve_trajectory};
