//! Single-pose IK: every returned configuration is inside the limits and reaches the target
//! according to forward kinematics (which is checked against Pinocchio elsewhere); failures
//! and bad input are reported, never hidden.

mod common;

use common::{fk, pose_distance, shared_file, ur5_like};
use graspath::failure::FailureReason;
use graspath::robot::builtin::{baxter, Arm};
use graspath::robot::{
    load_urdf_chain, solve_ik, Chain, ChainSpec, IkOptions, JointKind, JointSpec, RobotError,
};
use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use proptest::prelude::*;
use rand::rngs::Xoshiro256PlusPlus;
use rand::{RngExt, SeedableRng};

fn no_time_limit() -> IkOptions {
    IkOptions {
        max_time: None,
        max_iterations: 20_000,
        ..IkOptions::default()
    }
}

fn random_q(chain: &Chain, rng: &mut Xoshiro256PlusPlus) -> Vec<f64> {
    chain
        .lower()
        .iter()
        .zip(chain.upper())
        .map(|(&lo, &hi)| {
            let (lo, hi) = (lo.max(-3.0), hi.min(3.0));
            rng.random_range(lo..=hi)
        })
        .collect()
}

/// Solves targets made by FK of random in-limit configurations from random in-limit start
/// configurations; every answer must be in the limits and within tolerance, and almost all must succeed.
fn check_reachable_targets(chain: &Chain, samples: usize, seed: u64) {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
    let options = no_time_limit();
    let mut solved = 0;
    for _ in 0..samples {
        let target = fk(chain, &random_q(chain, &mut rng));
        let start = random_q(chain, &mut rng);
        let solution = solve_ik(chain, &target, &start, &options).expect("valid input");
        match &solution.q {
            Some(q) => {
                solved += 1;
                assert!(chain.within_limits(q), "{q:?} leaves the limits");
                let (dp, dr) = pose_distance(&fk(chain, q), &target);
                assert!(dp <= options.position_tolerance, "position error {dp}");
                assert!(dr <= options.rotation_tolerance, "rotation error {dr}");
                assert!((dp - solution.position_error).abs() < 1e-9);
                assert!(solution.failure.is_none());
            }
            None => {
                let failure = solution.failure.as_ref().expect("a failure is explained");
                assert!(chain.within_limits(&failure.best_q));
            }
        }
    }
    assert!(
        solved * 1000 >= samples * 995,
        "{} solved {solved} of {samples}",
        chain.name()
    );
}

#[test]
fn baxter_solutions_are_in_limits_and_reach_the_target() {
    check_reachable_targets(&baxter(Arm::Left), 400, 1);
    check_reachable_targets(&baxter(Arm::Right), 200, 2);
}

#[test]
fn ur5_solutions_are_in_limits_and_reach_the_target() {
    check_reachable_targets(&ur5_like(std::f64::consts::PI), 300, 3);
}

#[test]
fn urdf_robots_solutions_are_in_limits_and_reach_the_target() {
    for (file, base, tip) in [
        ("robots/panda.urdf", "panda_link0", "panda_hand_tcp"),
        ("robots/ur5_robot.urdf", "base_link", "tool0"),
        ("robots/baxter.urdf", "base", "left_gripper"),
    ] {
        let Some(path) = shared_file(file) else {
            return;
        };
        let chain = load_urdf_chain(&path, base, tip, None).expect("loads");
        check_reachable_targets(&chain, 200, 4);
    }
}

#[test]
fn test_ur5_model_matches_the_urdf() {
    let Some(path) = shared_file("robots/ur5_robot.urdf") else {
        return;
    };
    let urdf = load_urdf_chain(&path, "base_link", "tool0", None).expect("loads");
    let ours = ur5_like(2.0 * std::f64::consts::PI);
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(5);
    for _ in 0..50 {
        let q = random_q(&ours, &mut rng);
        let (dp, dr) = pose_distance(&fk(&urdf, &q), &fk(&ours, &q));
        assert!(dp < 1e-9 && dr < 1e-9);
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// Arbitrary poses in a box around Baxter, many of them unreachable: whatever comes back
    /// is in the limits, and a configuration is only returned when it reaches the target.
    #[test]
    fn any_target_gives_an_in_limit_answer(
        xyz in prop::array::uniform3(-1.5..1.5f64),
        rotation in prop::array::uniform3(-3.0..3.0f64),
        seed in 0u64..1000,
    ) {
        let chain = baxter(Arm::Left);
        let target = Isometry3::from_parts(
            Translation3::new(xyz[0], xyz[1], xyz[2]),
            UnitQuaternion::from_scaled_axis(Vector3::new(rotation[0], rotation[1], rotation[2])),
        );
        let options = IkOptions { max_time: None, max_iterations: 800, random_seed: seed, ..IkOptions::default() };
        let solution = solve_ik(&chain, &target, &chain.mid_configuration(), &options).expect("valid input");
        match solution.q {
            Some(q) => {
                prop_assert!(chain.within_limits(&q));
                let (dp, dr) = pose_distance(&fk(&chain, &q), &target);
                prop_assert!(dp <= 1e-5 && dr <= 1e-5);
            }
            None => {
                let failure = solution.failure.expect("explained");
                prop_assert!(chain.within_limits(&failure.best_q));
                let (dp, dr) = pose_distance(&fk(&chain, &failure.best_q), &target);
                prop_assert!((dp - solution.position_error).abs() < 1e-9);
                prop_assert!((dr - solution.rotation_error).abs() < 1e-9);
                prop_assert!(dp > 1e-5 || dr > 1e-5);
            }
        }
    }
}

#[test]
fn a_target_out_of_reach_fails_with_its_reason() {
    let chain = baxter(Arm::Left);
    let target = Isometry3::translation(4.0, 0.0, 0.5);
    let solution = solve_ik(
        &chain,
        &target,
        &chain.mid_configuration(),
        &IkOptions::default(),
    )
    .expect("ok");
    assert!(solution.q.is_none());
    let failure = solution.failure.expect("explained");
    assert_eq!(failure.reason, FailureReason::Unreachable);
    assert!(solution.position_error > 2.0);
    assert!(chain.within_limits(&failure.best_q));
    assert!(failure.to_string().contains("out of the chain's reach"));
}

#[test]
fn a_reachable_position_with_an_impossible_orientation_spends_the_budget() {
    // Inside the reach sphere but pointing the gripper back into the shoulder: no solution.
    let chain = baxter(Arm::Left);
    let base = fk(&chain, &chain.mid_configuration());
    let target = Isometry3::from_parts(
        Translation3::new(0.1, 0.3, 0.3),
        base.rotation * UnitQuaternion::from_euler_angles(0.0, std::f64::consts::PI, 0.0),
    );
    let options = IkOptions {
        max_time: None,
        max_iterations: 3000,
        ..IkOptions::default()
    };
    let solution = solve_ik(&chain, &target, &chain.mid_configuration(), &options).expect("ok");
    if let Some(q) = &solution.q {
        // Should the pose be reachable after all, the answer must still be right.
        let (dp, dr) = pose_distance(&fk(&chain, q), &target);
        assert!(dp <= 1e-5 && dr <= 1e-5 && chain.within_limits(q));
        return;
    }
    let failure = solution.failure.expect("explained");
    assert_eq!(failure.reason, FailureReason::IterationLimit);
    assert_eq!(solution.iterations, 3000);
    assert!(failure.attempts > 2, "restarts were tried");
}

#[test]
fn results_are_deterministic_for_a_seed() {
    let chain = baxter(Arm::Left);
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(9);
    let options = IkOptions {
        max_time: None,
        random_seed: 77,
        ..IkOptions::default()
    };
    for _ in 0..30 {
        let target = fk(&chain, &random_q(&chain, &mut rng));
        let start = random_q(&chain, &mut rng);
        let a = solve_ik(&chain, &target, &start, &options).expect("ok");
        let b = solve_ik(&chain, &target, &start, &options).expect("ok");
        assert_eq!(a, b);
    }
}

#[test]
fn a_start_at_the_target_returns_at_once() {
    let chain = baxter(Arm::Left);
    let q = vec![0.2, -0.3, 0.1, 0.9, 0.4, 0.6, -0.2];
    let solution = solve_ik(&chain, &fk(&chain, &q), &q, &IkOptions::default()).expect("ok");
    assert_eq!(solution.q.as_deref(), Some(&q[..]));
    assert_eq!(solution.iterations, 1);
}

#[test]
fn a_start_outside_the_limits_is_clamped_first() {
    let chain = baxter(Arm::Left);
    let q = [0.2, -0.3, 0.1, 0.9, 0.4, 0.6, -0.2];
    let q_start = vec![10.0; 7];
    let solution = solve_ik(&chain, &fk(&chain, &q), &q_start, &no_time_limit()).expect("ok");
    assert!(chain.within_limits(&solution.q.expect("solved")));
}

/// A planar-ish chain with a continuous base joint, a prismatic joint and a wrist.
fn mixed_chain() -> Chain {
    let joint = |name: &str, kind, xyz: [f64; 3], axis: Vector3<f64>, lo: f64, hi: f64| JointSpec {
        name: name.into(),
        child_link: String::new(),
        kind,
        parent_from_joint: Isometry3::translation(xyz[0], xyz[1], xyz[2]),
        axis,
        lower: lo,
        upper: hi,
        mimic: None,
        limits: Default::default(),
        child_inertial: None,
    };
    let inf = f64::INFINITY;
    Chain::from_spec(&ChainSpec {
        source_name: "test mixed".into(),
        base_link: "base".into(),
        tip_link: "tip".into(),
        joints: vec![
            joint(
                "turn",
                JointKind::Continuous,
                [0.0, 0.0, 0.1],
                Vector3::z(),
                -inf,
                inf,
            ),
            joint(
                "lift",
                JointKind::Prismatic,
                [0.0, 0.0, 0.1],
                Vector3::z(),
                0.0,
                0.5,
            ),
            joint(
                "reach",
                JointKind::Prismatic,
                [0.1, 0.0, 0.0],
                Vector3::x(),
                0.1,
                0.6,
            ),
            joint(
                "roll",
                JointKind::Revolute,
                [0.05, 0.0, 0.0],
                Vector3::x(),
                -2.0,
                2.0,
            ),
            joint(
                "pitch",
                JointKind::Revolute,
                [0.05, 0.0, 0.0],
                Vector3::y(),
                -1.5,
                1.5,
            ),
            joint(
                "yaw",
                JointKind::Revolute,
                [0.05, 0.0, 0.0],
                Vector3::z(),
                -2.0,
                2.0,
            ),
        ],
        tip_from_tool: Some(Isometry3::translation(0.0, 0.0, 0.08)),
    })
    .expect("valid chain")
}

#[test]
fn prismatic_and_continuous_joints_are_solved() {
    let chain = mixed_chain();
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(11);
    for _ in 0..100 {
        let q_true = random_q(&chain, &mut rng);
        let target = fk(&chain, &q_true);
        let q_start = vec![0.0, 0.25, 0.35, 0.0, 0.0, 0.0];
        let solution = solve_ik(&chain, &target, &q_start, &no_time_limit()).expect("ok");
        let q = solution.q.expect("reachable by construction");
        assert!(chain.within_limits(&q));
        assert!(
            (q[0] - q_start[0]).abs() <= std::f64::consts::PI + 1e-12,
            "continuous joint wrapped near the start configuration"
        );
        let (dp, dr) = pose_distance(&fk(&chain, &q), &target);
        assert!(dp <= 1e-5 && dr <= 1e-5);
    }
}

#[test]
fn bad_input_is_an_error() {
    let chain = baxter(Arm::Left);
    let target = fk(&chain, &chain.mid_configuration());
    let options = IkOptions::default();
    let wrong = solve_ik(&chain, &target, &[0.0; 6], &options).unwrap_err();
    assert!(matches!(
        wrong,
        RobotError::WrongDof {
            expected: 7,
            got: 6,
            ..
        }
    ));
    let mut q_start = chain.mid_configuration();
    q_start[3] = f64::NAN;
    let nan = solve_ik(&chain, &target, &q_start, &options).unwrap_err();
    assert!(matches!(nan, RobotError::NonFiniteJoint { index: 3 }));
    let mut bad_target = target;
    bad_target.translation.vector.y = f64::NAN;
    let err = solve_ik(&chain, &bad_target, &chain.mid_configuration(), &options).unwrap_err();
    assert!(err.to_string().contains("target"), "{err}");
    for (position_tolerance, rotation_tolerance) in
        [(0.0, 1e-5), (1e-5, f64::NAN), (1e308, 1e-5), (1e-5, 4.0)]
    {
        let options = IkOptions {
            position_tolerance,
            rotation_tolerance,
            ..IkOptions::default()
        };
        let err = solve_ik(&chain, &target, &chain.mid_configuration(), &options).unwrap_err();
        assert!(matches!(err, RobotError::BadOption { .. }), "{err}");
    }
}
