//! Time-optimal timing against toppra 0.6 (`toppra.algorithm.TOPPRA`, seidel solver; both
//! the collocation and the interpolation discretisation) on random paths of example-robot-data's Panda, UR5 and Baxter arm chains with
//! velocity, acceleration and torque limits (torques by Pinocchio's `rnea` on the reduced
//! model, one case with a payload at the tool).
//!
//! The reference values are in `tests/data/timing/toppra_timing.json`, written by the script
//! beside it (`toppra_reference.py`, which says how to run it and what toppra does that a
//! reimplementation must know). The URDFs are read from example-robot-data
//! (`GRASPATH_ROBOT_DATA`, set by `.ci/run`): in CI (`CI=true`) a missing package fails this
//! test, elsewhere it prints why it skips.
//!
//! Known differences, all far below the tolerances: toppra computes the velocity bound in
//! single precision (≈ 1e-7 relative), and its forward pass lowers each `ṡ²` by
//! `max(1e-8, 1e-4 · ṡ²)` as a safety margin (≈ 1e-8 of the duration).

mod common;

use graspath::robot::Chain;
use graspath::timing::{Discretization, JointSpline, PathLimits, PathPoint, TorqueLimits};
use nalgebra::Vector3;
use serde_json::Value;

/// Durations agree to this, relative (the issue asks for 1 %).
const DURATION_TOLERANCE: f64 = 1e-6;
/// `ṡ²` at the grid points agree to this, relative to the largest.
const SD_TOLERANCE: f64 = 1e-4;

fn reference() -> Value {
    common::reference_json("timing/toppra_timing.json")
}

fn chain(data: &std::path::Path, case: &Value) -> Chain {
    let name = |key: &str| case[key].as_str().unwrap();
    common::example_robot_chain(data, name("urdf"), (name("base"), name("tip")), None)
}

fn limits(v: &Value) -> Vec<Option<f64>> {
    common::json_numbers(v).into_iter().map(Some).collect()
}

#[test]
fn durations_equal_toppra_on_panda_ur5_and_baxter() {
    let Some(data) = common::robot_data() else {
        return;
    };
    let reference = reference();
    let cases = reference["cases"].as_array().unwrap();
    assert!(cases.len() >= 12);
    let mut with_torque = 0;
    for case in cases {
        let name = case["name"].as_str().unwrap();
        let waypoints: Vec<Vec<f64>> = case["waypoints"]
            .as_array()
            .unwrap()
            .iter()
            .map(common::json_numbers)
            .collect();
        // Our chord-length knots equal the script's, and our natural spline equals SciPy's.
        let spline = JointSpline::through(&waypoints).unwrap();
        let knots = common::json_numbers(&case["knots"]);
        common::max_relative_error(spline.knots(), &knots, 1e-12, &format!("{name}: knots"));
        let check = &case["spline_check"];
        let dof = waypoints[0].len();
        let [mut q, mut dq, mut ddq] = std::array::from_fn(|_| vec![0.0; dof]);
        for (k, s) in common::json_numbers(&check["s"]).into_iter().enumerate() {
            spline.evaluate_into(
                s,
                PathPoint {
                    q: &mut q,
                    dq: &mut dq,
                    ddq: &mut ddq,
                },
            );
            for (ours, key) in [(&q, "q"), (&dq, "dq"), (&ddq, "ddq")] {
                let scipy = common::json_numbers(&check[key][k]);
                common::max_relative_error(ours, &scipy, 1e-9, &format!("{name}: {key}({s})"));
            }
        }
        let chain = chain(&data, case);
        let names = common::json_names(&case["joint_names"]);
        assert_eq!(chain.joint_names(), names.as_slice(), "{name}");
        let gravity = Vector3::from_vec(common::json_numbers(&case["gravity_base"]));
        let dynamics = chain.dynamics().unwrap().with_gravity(gravity).unwrap();
        let payload = (!case["payload"].is_null()).then(|| common::json_body(&case["payload"]));
        let (velocity, acceleration) = (
            limits(&case["velocity_limits"]),
            limits(&case["acceleration_limits"]),
        );
        let effort = (!case["torque_limits"].is_null()).then(|| limits(&case["torque_limits"]));
        with_torque += usize::from(effort.is_some());
        for (discretization, duration_key, sd_key) in [
            (Discretization::Collocation, "duration", "sd_squared"),
            (
                Discretization::Interpolation,
                "duration_interpolation",
                "sd_squared_interpolation",
            ),
        ] {
            let path_limits = PathLimits {
                velocity: &velocity,
                acceleration: &acceleration,
                torque: effort.as_deref().map(|effort| TorqueLimits {
                    dynamics: &dynamics,
                    effort,
                    payload,
                }),
                object: None,
                subdivisions: 2,
                discretization,
            };
            let constraints = path_limits.constraints(&spline).unwrap();
            common::max_relative_error(
                &constraints.grid,
                &common::json_numbers(&case["grid"]),
                1e-12,
                &format!("{name}: grid"),
            );
            let timed = graspath::timing::time_optimal(&constraints).unwrap();
            let toppra = case[duration_key].as_f64().unwrap();
            let error = (timed.duration() - toppra).abs() / toppra;
            assert!(
                error <= DURATION_TOLERANCE,
                "{name} ({discretization:?}): {} s vs toppra's {toppra} s (relative {error:.2e})",
                timed.duration()
            );
            let sd = common::json_numbers(&case[sd_key]);
            common::max_relative_error(
                &timed.sd_squared,
                &sd,
                SD_TOLERANCE,
                &format!("{name} ({discretization:?}): sd²"),
            );
        }
    }
    assert!(with_torque >= 6, "the torque limits are exercised");
}
