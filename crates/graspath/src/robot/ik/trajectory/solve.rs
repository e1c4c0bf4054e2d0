//! The entry points of trajectory IK: one trajectory ([`solve_trajectory`]) or a batch
//! ([`solve_trajectories`]): the inputs checked, each trajectory's branches searched at its first
//! pose, every branch of the batch tracked, and each trajectory's result assembled.

use super::options::TrajectoryIkOptions;
use super::result::{JointPath, TrajectoryIkResult};
use super::tracker::{max_difference, Tracker};
use super::tracking::{track_in_lanes, Job};
use crate::failure::Failure;
use crate::robot::chain::Chain;
use crate::robot::error::RobotError;
use crate::robot::ik::kernel::Kernel;
use crate::robot::ik::single_pose::{check_options, check_pose};
use nalgebra::Isometry3;

/// Joint paths that take the tip of `chain` through `base_from_targets` (tip poses in the
/// chain base frame, m, in order), starting near the joint configuration `q_start` (rad / m,
/// one value per joint). Random restarts are drawn from `options.ik.random_seed`.
///
/// Returns `Err` only for bad input: an empty trajectory, a non-finite pose, a start
/// configuration of the wrong length or non-finite, or out-of-range options.
pub fn solve_trajectory(
    chain: &Chain,
    base_from_targets: &[Isometry3<f64>],
    q_start: &[f64],
    options: &TrajectoryIkOptions,
) -> Result<TrajectoryIkResult, RobotError> {
    solve_trajectories(chain, &[base_from_targets], q_start, options)?
        .pop()
        .expect("one trajectory, one result")
}

/// [`solve_trajectory`] of each trajectory of `trajectories`, all from `q_start` with
/// `options`: the same results, bit for bit, in the same order. The branches of all the
/// trajectories are tracked four at a time, one per vector lane, so a batch takes less time
/// than its trajectories one by one.
///
/// The outer `Err` is for input common to all (the options, `q_start`); the inner one for a
/// trajectory's own poses (empty, or a non-finite pose).
pub fn solve_trajectories(
    chain: &Chain,
    trajectories: &[&[Isometry3<f64>]],
    q_start: &[f64],
    options: &TrajectoryIkOptions,
) -> Result<Vec<Result<TrajectoryIkResult, RobotError>>, RobotError> {
    check_options(&options.ik)?;
    if !(options.max_joint_step.is_finite() && options.max_joint_step > 0.0) {
        return Err(RobotError::BadOption {
            name: "max_joint_step",
            message: format!(
                "must be a positive finite number, got {}",
                options.max_joint_step
            ),
        });
    }
    for (name, value) in [
        ("branches", options.branches),
        ("per_sample_iterations", options.per_sample_iterations),
    ] {
        if value == 0 {
            return Err(RobotError::BadOption {
                name,
                message: "must be at least 1".into(),
            });
        }
    }
    chain.check_configuration(q_start)?;
    let kernel = Kernel::new(
        chain,
        options.ik.position_tolerance,
        options.ik.rotation_tolerance,
    );
    let searched: Vec<Result<Searched<'_>, RobotError>> = trajectories
        .iter()
        .map(|poses| {
            check_trajectory(poses)?;
            let tracker = Tracker {
                kernel,
                poses,
                options,
            };
            let starts = tracker.initial_solutions(q_start);
            Ok((tracker, starts))
        })
        .collect();
    let jobs: Vec<Job<'_>> = searched
        .iter()
        .filter_map(|searched| match searched {
            Ok((tracker, Ok(starts))) => Some((tracker, starts)),
            _ => None,
        })
        .flat_map(|(tracker, starts)| Job::branches(tracker, starts))
        .collect();
    let mut tracked = if let [job] = jobs.as_slice() {
        vec![job.tracker.track(job.branch, job.start)]
    } else {
        track_in_lanes(&jobs)
    }
    .into_iter();
    let mut start_clamped = q_start.to_vec();
    kernel.clamp(&mut start_clamped);
    Ok(searched
        .into_iter()
        .map(|searched| {
            let starts = match searched? {
                (_, Ok(starts)) => starts,
                (_, Err(failure)) => {
                    return Ok(TrajectoryIkResult {
                        branches: Vec::new(),
                        failure: Some(failure),
                        first_pose: Vec::new(),
                    })
                }
            };
            let outcomes = tracked.by_ref().take(starts.len());
            Ok(assemble(outcomes, starts, &start_clamped))
        })
        .collect())
}

/// A trajectory's tracker and its first pose's solutions (the branches' starts), or why there
/// are none.
type Searched<'a> = (Tracker<'a>, Result<Vec<Vec<f64>>, Failure>);

/// Why `poses` cannot be a trajectory: none, or one not finite.
fn check_trajectory(poses: &[Isometry3<f64>]) -> Result<(), RobotError> {
    if poses.is_empty() {
        return Err(RobotError::BadPose {
            what: "trajectory".into(),
            message: "it has no poses".into(),
        });
    }
    for (i, pose) in poses.iter().enumerate() {
        check_pose(pose, &format_args!("trajectory pose {i}"))?;
    }
    Ok(())
}

/// A trajectory's result from its branches' outcomes (branch by branch, in the order of
/// `starts`): the branches that follow it, nearest `start_clamped` (the clamped start
/// configuration) first, or else the failure of the branch that got furthest.
fn assemble(
    outcomes: impl Iterator<Item = Result<JointPath, Failure>>,
    starts: Vec<Vec<f64>>,
    start_clamped: &[f64],
) -> TrajectoryIkResult {
    let mut branches = Vec::new();
    let mut furthest: Option<Failure> = None;
    for outcome in outcomes {
        match outcome {
            Ok(path) => branches.push(path),
            Err(failure) => {
                if furthest.as_ref().is_none_or(|f| failure.sample > f.sample) {
                    furthest = Some(failure);
                }
            }
        }
    }
    branches.sort_by(|a: &JointPath, b: &JointPath| {
        max_difference(&a.q[0], start_clamped)
            .total_cmp(&max_difference(&b.q[0], start_clamped))
            .then_with(|| {
                a.q[0]
                    .iter()
                    .zip(&b.q[0])
                    .map(|(x, y)| x.total_cmp(y))
                    .find(|o| o.is_ne())
                    .unwrap_or(std::cmp::Ordering::Equal)
            })
    });
    let failure = if branches.is_empty() { furthest } else { None };
    TrajectoryIkResult {
        branches,
        failure,
        first_pose: starts,
    }
}
