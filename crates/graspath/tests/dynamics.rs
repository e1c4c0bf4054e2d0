//! Gravity torques, inverse dynamics and the mass matrix against Pinocchio 4.1
//! (`computeGeneralizedGravity`, `rnea`, `crba`) on the arm chains of example-robot-data's
//! Panda, UR5 and Baxter, without and with a payload at the tool.
//!
//! The reference values are in `tests/data/dynamics/pinocchio_dynamics.json`, written by the
//! script beside it (`pinocchio_reference.py`, which says how to run it): Pinocchio's model of
//! the whole URDF reduced to the chain's joints (the others locked at zero), and the payload
//! appended as a body at the tool frame. The URDFs themselves are read from
//! example-robot-data (`GRASPATH_ROBOT_DATA`, set by `.ci/run`): in CI (`CI=true`) a missing
//! package fails these tests, elsewhere they print why they skip.

mod common;

use graspath::robot::Chain;
use nalgebra::{DMatrix, Isometry3, Translation3, UnitQuaternion, Vector3};
use serde_json::Value;

/// The largest error allowed, relative to the largest entry of the reference vector or
/// matrix.
const TOL: f64 = 1e-9;

fn reference() -> Value {
    common::reference_json("dynamics/pinocchio_dynamics.json")
}

fn vector3(v: &Value) -> Vector3<f64> {
    Vector3::from_vec(common::json_numbers(v))
}

/// `‖ours − reference‖∞ / ‖reference‖∞`, asserted below [`TOL`].
fn relative_error(ours: &[f64], reference: &[f64], what: &str) -> f64 {
    common::max_relative_error(ours, reference, TOL, what)
}

fn chain(data: &std::path::Path, robot: &Value, tip_from_tool: Option<Isometry3<f64>>) -> Chain {
    let name = |key: &str| robot[key].as_str().unwrap();
    common::example_robot_chain(
        data,
        name("urdf"),
        (name("base"), name("tip")),
        tip_from_tool,
    )
}

#[test]
fn gravity_rnea_and_crba_equal_pinocchio_on_panda_ur5_and_baxter() {
    let Some(data) = common::robot_data() else {
        return;
    };
    let reference = reference();
    let tool = &reference["tip_from_tool"];
    let (xyz, rpy) = (
        common::json_numbers(&tool["xyz"]),
        common::json_numbers(&tool["rpy"]),
    );
    let tip_from_tool = Isometry3::from_parts(
        Translation3::new(xyz[0], xyz[1], xyz[2]),
        UnitQuaternion::from_euler_angles(rpy[0], rpy[1], rpy[2]),
    );
    let payload = common::json_body(&reference["payload"]);
    let robots = reference["robots"].as_array().unwrap();
    assert_eq!(robots.len(), 3);
    for robot in robots {
        let name = robot["name"].as_str().unwrap();
        let gravity = vector3(&robot["gravity_base"]);
        let bare = chain(&data, robot, None).dynamics().unwrap();
        let tooled = chain(&data, robot, Some(tip_from_tool));
        let names = common::json_names(&robot["joint_names"]);
        assert_eq!(tooled.joint_names(), names.as_slice(), "{name}");
        let loaded = tooled.dynamics().unwrap().with_gravity(gravity).unwrap();
        let bare = bare.with_gravity(gravity).unwrap();
        let moving = robot["moving_mass"].as_f64().unwrap();
        assert!(
            (bare.moving_mass() - moving).abs() <= 1e-12 * moving,
            "{name}: moving mass {} vs {moving}",
            bare.moving_mass()
        );
        let mut bare_data = bare.data();
        let mut loaded_data = loaded.data();
        loaded_data.set_payload(Some(payload)).unwrap();
        let n = bare.dof();
        let mut tau = vec![0.0; n];
        let mut mass = DMatrix::zeros(n, n);
        let mut worst = [0.0f64; 6];
        let samples = robot["samples"].as_array().unwrap();
        assert!(samples.len() >= 20);
        for sample in samples {
            let (q, qd, qdd) = (
                common::json_numbers(&sample["q"]),
                common::json_numbers(&sample["qd"]),
                common::json_numbers(&sample["qdd"]),
            );
            for (k, (dynamics, workspace, key)) in [
                (&bare, &mut bare_data, ""),
                (&loaded, &mut loaded_data, "_payload"),
            ]
            .into_iter()
            .enumerate()
            {
                let what = |f: &str| format!("{name}: {f}{key} at q = {q:?}");
                dynamics
                    .gravity_torques_into(workspace, &q, &mut tau)
                    .unwrap();
                let e = relative_error(
                    &tau,
                    &common::json_numbers(&sample[format!("g{key}")]),
                    &what("g"),
                );
                worst[3 * k] = worst[3 * k].max(e);
                dynamics
                    .inverse_dynamics_into(workspace, &q, &qd, &qdd, &mut tau)
                    .unwrap();
                let e = relative_error(
                    &tau,
                    &common::json_numbers(&sample[format!("tau{key}")]),
                    &what("rnea"),
                );
                worst[3 * k + 1] = worst[3 * k + 1].max(e);
                dynamics.mass_matrix_into(workspace, &q, &mut mass).unwrap();
                // Row-major reference; M is symmetric, so compare its transpose's storage.
                let e = relative_error(
                    mass.transpose().as_slice(),
                    &common::json_numbers(&sample[format!("mass_matrix{key}")]),
                    &what("crba"),
                );
                worst[3 * k + 2] = worst[3 * k + 2].max(e);
            }
        }
        eprintln!(
            "{name}: largest relative errors: g {:.1e}, rnea {:.1e}, crba {:.1e}; with payload: g {:.1e}, rnea {:.1e}, crba {:.1e}",
            worst[0], worst[1], worst[2], worst[3], worst[4], worst[5]
        );
    }
}
