//! Trajectory IK: every branch is continuous (bounded joint steps), in the limits and on
//! target at every sample; failures name the first failing sample and the reason.

mod common;

use common::{fk, pose_distance, shared_file, ur5_like};
use graspath::failure::FailureReason;
use graspath::robot::builtin::{baxter, Arm};
use graspath::robot::{
    load_urdf_chain, solve_ik, solve_trajectories, solve_trajectory, Chain, IkOptions, RobotError,
    TrajectoryIkOptions, TrajectoryIkResult,
};
use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};

/// Checks every branch against the independent oracle (forward kinematics) and the bounds.
fn check_branches(chain: &Chain, poses: &[Isometry3<f64>], result: &TrajectoryIkResult, step: f64) {
    for branch in &result.branches {
        assert_eq!(branch.q.len(), poses.len());
        for (i, q) in branch.q.iter().enumerate() {
            assert!(chain.within_limits(q), "sample {i} leaves the limits");
            let (dp, dr) = pose_distance(&fk(chain, q), &poses[i]);
            assert!(dp <= 1e-5 && dr <= 1e-5, "sample {i}: {dp} m, {dr} rad");
            if i > 0 {
                let jump = q
                    .iter()
                    .zip(&branch.q[i - 1])
                    .map(|(a, b)| (a - b).abs())
                    .fold(0.0, f64::max);
                assert!(jump <= step, "sample {i}: a joint moves {jump}");
            }
        }
    }
}

/// Poses along a smooth joint-space path inside Baxter's limits.
fn baxter_poses(chain: &Chain, samples: usize) -> Vec<Isometry3<f64>> {
    (0..samples)
        .map(|i| {
            let t = i as f64 / (samples - 1) as f64;
            let q = [
                0.2 + 0.4 * t,
                -0.5 + 0.3 * t,
                0.1 - 0.6 * t,
                1.2 - 0.4 * t,
                0.3 * (3.0 * t).sin(),
                0.8 - 0.5 * t,
                -0.4 + 1.2 * t,
            ];
            fk(chain, &q)
        })
        .collect()
}

#[test]
fn baxter_follows_a_reachable_trajectory_on_several_branches() {
    let chain = baxter(Arm::Left);
    let poses = baxter_poses(&chain, 50);
    let options = TrajectoryIkOptions::default();
    let result =
        solve_trajectory(&chain, &poses, &chain.mid_configuration(), &options).expect("ok");
    assert!(result.failure.is_none(), "{:?}", result.failure);
    assert!(
        result.branches.len() >= 2,
        "{} branches",
        result.branches.len()
    );
    check_branches(&chain, &poses, &result, options.max_joint_step);
    // Two branches are different joint paths for the same tip trajectory: distinct at the
    // start by more than a joint step, and different along the whole path.
    let (a, b) = (&result.branches[0], &result.branches[1]);
    for (qa, qb) in a.q.iter().zip(&b.q) {
        let difference = qa
            .iter()
            .zip(qb)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max);
        assert!(difference > 1e-3);
    }
    let start_difference = a.q[0]
        .iter()
        .zip(&b.q[0])
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max);
    assert!(start_difference > options.max_joint_step);
    // Deterministic.
    let again = solve_trajectory(&chain, &poses, &chain.mid_configuration(), &options).expect("ok");
    assert_eq!(result, again);
}

#[test]
fn urdf_robots_follow_reachable_trajectories() {
    for (file, base, tip) in [
        ("robots/panda.urdf", "panda_link0", "panda_hand_tcp"),
        ("robots/ur5_robot.urdf", "base_link", "tool0"),
    ] {
        let Some(path) = shared_file(file) else {
            return;
        };
        let chain = load_urdf_chain(&path, base, tip, None).expect("loads");
        let mid = chain.mid_configuration();
        let poses: Vec<_> = (0..40)
            .map(|i| {
                let t = i as f64 / 39.0;
                let q: Vec<f64> = mid
                    .iter()
                    .enumerate()
                    .map(|(j, m)| m + 0.4 * (t * (1.0 + j as f64 * 0.3)).sin() - 0.1)
                    .collect();
                fk(&chain, &q)
            })
            .collect();
        let options = TrajectoryIkOptions::default();
        let result = solve_trajectory(&chain, &poses, &mid, &options).expect("ok");
        assert!(result.feasible(), "{}: {:?}", chain.name(), result.failure);
        check_branches(&chain, &poses, &result, options.max_joint_step);
    }
}

#[test]
fn leaving_the_workspace_is_unreachable_at_the_first_sample_out() {
    let chain = baxter(Arm::Left);
    let start = fk(&chain, &[0.3, -0.3, 0.0, 1.0, 0.0, 0.5, 0.0]);
    // Move 0.15 m per sample straight away from the base: soon out of reach.
    let poses: Vec<_> = (0..30)
        .map(|i| {
            let direction = start.translation.vector.normalize();
            Isometry3::from_parts(
                Translation3::from(start.translation.vector + direction * (0.15 * i as f64)),
                start.rotation,
            )
        })
        .collect();
    let options = TrajectoryIkOptions {
        branches: 2,
        ..TrajectoryIkOptions::default()
    };
    let result =
        solve_trajectory(&chain, &poses, &chain.mid_configuration(), &options).expect("ok");
    assert!(result.branches.is_empty());
    let failure = result.failure.expect("explained");
    assert_eq!(failure.reason, FailureReason::Unreachable, "{failure}");
    assert!(failure.sample > 0 && failure.sample < 15, "{failure}");
    // Oracle: the single-pose solver cannot reach the failing sample either.
    let options = IkOptions {
        max_time: None,
        max_iterations: 20_000,
        ..IkOptions::default()
    };
    let single = solve_ik(
        &chain,
        &poses[failure.sample],
        &chain.mid_configuration(),
        &options,
    )
    .expect("ok");
    assert!(single.q.is_none());
    // And the sample before it was reachable.
    let before = solve_ik(
        &chain,
        &poses[failure.sample - 1],
        &chain.mid_configuration(),
        &options,
    )
    .expect("ok");
    assert!(before.q.is_some());
}

#[test]
fn a_first_sample_out_of_reach_is_reported_at_sample_zero() {
    let chain = baxter(Arm::Left);
    let poses = vec![Isometry3::translation(3.0, 3.0, 0.0); 5];
    let result = solve_trajectory(
        &chain,
        &poses,
        &chain.mid_configuration(),
        &TrajectoryIkOptions::default(),
    )
    .expect("ok");
    let failure = result.failure.expect("explained");
    assert_eq!(failure.sample, 0);
    assert_eq!(failure.reason, FailureReason::Unreachable);
    assert!(failure.detail.starts_with("out of reach: "), "{failure}");
    assert!(
        failure.detail.contains("the links between them span"),
        "{failure}"
    );
}

#[test]
fn pushing_a_joint_past_its_limit_is_a_joint_limit_failure() {
    // A 6-joint arm has no self-motion: once the shoulder pan passes its limit (here ±π), the
    // continuous solution leaves the limits.
    let chain = ur5_like(std::f64::consts::PI);
    let poses: Vec<_> = (0..31)
        .map(|i| {
            let pan = 2.6 + 0.03 * i as f64; // crosses π at i ≈ 18
            fk(&chain, &[pan, -1.2, 1.4, -0.6, 1.1, 0.3])
        })
        .collect();
    let options = TrajectoryIkOptions {
        branches: 1,
        ..TrajectoryIkOptions::default()
    };
    let q_start = [2.6, -1.2, 1.4, -0.6, 1.1, 0.3];
    let result = solve_trajectory(&chain, &poses, &q_start, &options).expect("ok");
    assert!(result.branches.is_empty());
    let failure = result.failure.expect("explained");
    assert_eq!(failure.reason, FailureReason::JointLimit, "{failure}");
    let first_out = (0..31)
        .find(|&i| 2.6 + 0.03 * i as f64 > std::f64::consts::PI)
        .expect("crosses");
    assert_eq!(failure.sample, first_out, "{failure}");
    assert!(failure.detail.contains("shoulder_pan_joint"), "{failure}");
}

#[test]
fn a_path_through_an_unreachable_pose_names_it_not_the_limit_met_on_the_way() {
    // The joint-limit path above, then a pose 3 m away: the path fails because of that pose,
    // and the failure says so, at its sample, with the distance.
    let chain = ur5_like(std::f64::consts::PI);
    let mut poses: Vec<_> = (0..31)
        .map(|i| fk(&chain, &[2.6 + 0.03 * i as f64, -1.2, 1.4, -0.6, 1.1, 0.3]))
        .collect();
    let options = TrajectoryIkOptions {
        branches: 1,
        ..TrajectoryIkOptions::default()
    };
    let q_start = [2.6, -1.2, 1.4, -0.6, 1.1, 0.3];
    let limited = solve_trajectory(&chain, &poses, &q_start, &options).expect("ok");
    assert_eq!(
        limited.failure.expect("explained").reason,
        FailureReason::JointLimit
    );
    poses.push(Isometry3::translation(3.0, 0.0, 0.0) * poses[30]);
    let result = solve_trajectory(&chain, &poses, &q_start, &options).expect("ok");
    assert!(result.branches.is_empty());
    let failure = result.failure.expect("explained");
    assert_eq!(failure.reason, FailureReason::Unreachable, "{failure}");
    assert_eq!(failure.sample, 31, "{failure}");
    assert!(failure.detail.starts_with("out of reach: "), "{failure}");
    // Oracle: the last pose is beyond the arm's reach sphere about its first joint.
    let origins = chain.joint_origins(&q_start).unwrap();
    let span: f64 = origins.windows(2).map(|w| (w[1] - w[0]).norm()).sum();
    let first_joint = origins[1];
    let target = poses[31].translation.vector;
    assert!((target - first_joint.coords).norm() > span);
}

/// Poses passing close to UR5's wrist singularity (wrist 2 near 0), where the wrist must turn
/// by about π between two samples.
fn near_wrist_singularity(chain: &Chain) -> Vec<Isometry3<f64>> {
    let q_singular = [0.4, -1.3, 1.5, -1.0, 0.0, 0.5];
    let singular = fk(chain, &q_singular);
    // Axes of joints 4 and 5 at the singular configuration (base frame).
    let (_, jacobian) = chain.pose_and_jacobian(&q_singular).expect("fk");
    let z4 = Vector3::new(jacobian[(3, 3)], jacobian[(4, 3)], jacobian[(5, 3)]);
    let z5 = Vector3::new(jacobian[(3, 4)], jacobian[(4, 4)], jacobian[(5, 4)]);
    let across = z5.cross(&z4).normalize();
    (0..41)
        .map(|i| {
            let s = -0.2 + 0.01 * i as f64;
            let turn = UnitQuaternion::from_scaled_axis(z5 * s + across * 0.002);
            Isometry3::from_parts(singular.translation, turn * singular.rotation)
        })
        .collect()
}

#[test]
fn a_wrist_flip_near_a_singularity_is_a_discontinuity() {
    let chain = ur5_like(2.0 * std::f64::consts::PI);
    let poses = near_wrist_singularity(&chain);
    let max_step = 0.5;
    // The naive approach: solve each sample from the previous solution, no step bound.
    let options = IkOptions {
        max_time: None,
        ..IkOptions::default()
    };
    let mut q = solve_ik(
        &chain,
        &poses[0],
        &[0.4, -1.3, 1.5, -1.0, 0.1, 0.5],
        &options,
    )
    .expect("ok")
    .q
    .expect("reachable");
    let mut naive_jump = 0.0f64;
    for pose in &poses[1..] {
        let next = solve_ik(&chain, pose, &q, &options)
            .expect("ok")
            .q
            .expect("reachable");
        let jump = next
            .iter()
            .zip(&q)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        naive_jump = naive_jump.max(jump);
        q = next;
    }
    assert!(
        naive_jump > max_step,
        "the naive path flips: largest jump {naive_jump}"
    );
    // Ours: either a continuous branch, or a discontinuity reported.
    let trajectory_options = TrajectoryIkOptions {
        max_joint_step: max_step,
        ..TrajectoryIkOptions::default()
    };
    let result = solve_trajectory(
        &chain,
        &poses,
        &[0.4, -1.3, 1.5, -1.0, 0.1, 0.5],
        &trajectory_options,
    )
    .expect("ok");
    check_branches(&chain, &poses, &result, max_step);
    if result.branches.is_empty() {
        // The swing happens where the path passes the singularity (s = 0, sample 20).
        let failure = result.failure.as_ref().expect("explained");
        assert_eq!(failure.reason, FailureReason::Discontinuity, "{failure}");
        assert!((19..=21).contains(&failure.sample), "{failure}");
        assert!(failure.detail.contains("wrist"), "{failure}");
    }
}

#[test]
fn bad_input_is_an_error() {
    let chain = baxter(Arm::Left);
    let poses = baxter_poses(&chain, 5);
    let options = TrajectoryIkOptions::default();
    let mid = chain.mid_configuration();
    assert!(matches!(
        solve_trajectory(&chain, &poses, &[0.0; 3], &options),
        Err(RobotError::WrongDof { .. })
    ));
    assert!(matches!(
        solve_trajectory(&chain, &[], &mid, &options),
        Err(RobotError::BadPose { .. })
    ));
    let mut bad = poses.clone();
    bad[3].translation.vector.x = f64::INFINITY;
    let err = solve_trajectory(&chain, &bad, &mid, &options).unwrap_err();
    assert!(err.to_string().contains("pose 3"), "{err}");
    let zero_step = TrajectoryIkOptions {
        max_joint_step: 0.0,
        ..TrajectoryIkOptions::default()
    };
    assert!(matches!(
        solve_trajectory(&chain, &poses, &mid, &zero_step),
        Err(RobotError::BadOption {
            name: "max_joint_step",
            ..
        })
    ));
}

/// A batch solves each trajectory as it would be solved alone, bit for bit, and in order:
/// feasible ones, ones that leave the workspace or the limits or flip the wrist, one out of
/// reach from the start, and, for one branch or several, each trajectory's own bad input
/// (empty, not finite) refused on its own. Input common to all is refused once. With one
/// branch a trajectory alone is tracked by the one-at-a-time loop, so the batch's lanes are
/// checked against it; with several both go through the lanes (the unit test in
/// `robot/ik/trajectory/tracking.rs` checks the lanes against the loop for every branch).
#[test]
fn a_batch_solves_each_trajectory_as_alone() {
    let chain = ur5_like(std::f64::consts::PI);
    let mut trajectories: Vec<Vec<Isometry3<f64>>> = vec![
        (0..31)
            .map(|i| fk(&chain, &[2.6 + 0.03 * i as f64, -1.2, 1.4, -0.6, 1.1, 0.3]))
            .collect(),
        near_wrist_singularity(&chain),
        vec![Isometry3::translation(3.0, 3.0, 0.0); 5],
        Vec::new(),
        (0..20)
            .map(|i| fk(&chain, &[0.3 - 0.02 * i as f64, -1.0, 1.2, -0.4, 0.9, 0.1]))
            .collect(),
    ];
    let mut bad = trajectories[4].clone();
    bad[7].translation.vector.y = f64::NAN;
    trajectories.push(bad);
    let start = fk(&chain, &[0.3, -1.0, 1.2, -0.4, 0.9, 0.1]);
    trajectories.push(
        (0..25)
            .map(|i| {
                let away = start.translation.vector.normalize() * (0.06 * i as f64);
                Isometry3::from_parts(
                    Translation3::from(start.translation.vector + away),
                    start.rotation,
                )
            })
            .collect(),
    );
    let q_start = [0.4, -1.3, 1.5, -1.0, 0.1, 0.5];
    let batch: Vec<&[Isometry3<f64>]> = trajectories.iter().map(Vec::as_slice).collect();
    for branches in [1, 3] {
        let options = TrajectoryIkOptions {
            branches,
            ..TrajectoryIkOptions::default()
        };
        let together =
            solve_trajectories(&chain, &batch, &q_start, &options).expect("valid options");
        assert_eq!(together.len(), batch.len());
        let mut feasible = 0;
        for (k, (poses, got)) in batch.iter().zip(&together).enumerate() {
            let alone = solve_trajectory(&chain, poses, &q_start, &options);
            // Debug prints every number to its last bit.
            assert_eq!(
                format!("{got:?}"),
                format!("{alone:?}"),
                "trajectory {k}, {branches} branches"
            );
            if let Ok(result) = got {
                check_branches(&chain, poses, result, options.max_joint_step);
                feasible += usize::from(result.feasible());
            }
        }
        assert!(feasible >= 1, "the batch has feasible trajectories");
        assert!(together[3].is_err() && together[5].is_err());
    }
    let zero_step = TrajectoryIkOptions {
        max_joint_step: 0.0,
        ..TrajectoryIkOptions::default()
    };
    assert!(matches!(
        solve_trajectories(&chain, &batch, &q_start, &zero_step),
        Err(RobotError::BadOption {
            name: "max_joint_step",
            ..
        })
    ));
    assert!(solve_trajectories(&chain, &[], &q_start, &zero_step).is_err());
    assert!(
        solve_trajectories(&chain, &[], &q_start, &TrajectoryIkOptions::default())
            .expect("valid")
            .is_empty()
    );
}

#[test]
fn a_first_pose_outside_the_limits_is_a_joint_limit_failure_at_sample_zero() {
    // Every joint limited to ±0.5 rad; the first pose needs the shoulder pan at 1.0 rad (every
    // other inverse-kinematics branch of this 6-joint arm needs larger angles still).
    let chain = ur5_like(0.5);
    let q = [1.0, -0.2, 0.3, -0.2, 0.3, 0.1];
    let poses = vec![fk(&chain, &q); 3];
    let result =
        solve_trajectory(&chain, &poses, &[0.0; 6], &TrajectoryIkOptions::default()).expect("ok");
    assert!(result.branches.is_empty());
    let failure = result.failure.expect("explained");
    assert_eq!(failure.sample, 0, "{failure}");
    assert_eq!(failure.reason, FailureReason::JointLimit, "{failure}");
    assert!(failure.detail.contains("shoulder_pan_joint"), "{failure}");
}

#[test]
fn results_do_not_depend_on_threads() {
    use rayon::prelude::*;
    fn send_sync<T: Send + Sync>() {}
    send_sync::<Chain>();
    send_sync::<TrajectoryIkOptions>();
    send_sync::<TrajectoryIkResult>();
    send_sync::<IkOptions>();
    send_sync::<graspath::robot::IkSolution>();

    let chain = baxter(Arm::Left);
    let base = baxter_poses(&chain, 20);
    // Twelve trajectories: the same path shifted by a few centimetres each.
    let trajectories: Vec<Vec<Isometry3<f64>>> = (0..12)
        .map(|k| {
            let shift = Translation3::new(0.01 * k as f64, -0.005 * k as f64, 0.0);
            base.iter().map(|pose| shift * pose).collect()
        })
        .collect();
    let options = TrajectoryIkOptions {
        branches: 2,
        ..TrajectoryIkOptions::default()
    };
    let mid = chain.mid_configuration();
    let sequential: Vec<_> = trajectories
        .iter()
        .map(|poses| solve_trajectory(&chain, poses, &mid, &options).expect("ok"))
        .collect();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(4)
        .build()
        .expect("a thread pool");
    let parallel: Vec<_> = pool.install(|| {
        trajectories
            .par_iter()
            .map(|poses| solve_trajectory(&chain, poses, &mid, &options).expect("ok"))
            .collect()
    });
    assert_eq!(sequential, parallel);
}

#[test]
fn random_joint_sweeps_give_valid_branches_or_a_located_failure() {
    use rand::rngs::Xoshiro256PlusPlus;
    use rand::{RngExt, SeedableRng};
    let chain = baxter(Arm::Left);
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(21);
    let options = TrajectoryIkOptions {
        branches: 2,
        ..TrajectoryIkOptions::default()
    };
    let mut feasible = 0;
    for _ in 0..40 {
        // A straight joint-space sweep from a random in-limit configuration; some sweeps leave
        // the limits, so their poses may need other branches or be infeasible.
        let q0: Vec<f64> = chain
            .lower()
            .iter()
            .zip(chain.upper())
            .map(|(&lo, &hi)| rng.random_range(lo..=hi))
            .collect();
        let direction: Vec<f64> = (0..7).map(|_| rng.random_range(-0.02..=0.02)).collect();
        let poses: Vec<_> = (0..30)
            .map(|i| {
                let q: Vec<f64> = q0
                    .iter()
                    .zip(&direction)
                    .map(|(a, d)| a + d * i as f64)
                    .collect();
                fk(&chain, &q)
            })
            .collect();
        let result =
            solve_trajectory(&chain, &poses, &chain.mid_configuration(), &options).expect("ok");
        check_branches(&chain, &poses, &result, options.max_joint_step);
        match &result.failure {
            None => {
                assert!(result.feasible());
                feasible += 1;
            }
            Some(failure) => {
                assert!(result.branches.is_empty());
                assert!(failure.sample < poses.len());
                assert!(!failure.detail.is_empty());
            }
        }
    }
    assert!(feasible >= 20, "{feasible} of 40 sweeps feasible");
}
