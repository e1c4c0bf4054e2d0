//! The dynamics of an MJCF chain against MuJoCo 4.0 (`mj_inverse`, `mj_fullM`): the made-up
//! arm of `tests/data/mjcf/dynamics_arm.xml` (inertials in every form MJCF allows, a body
//! with two hinges, a hinge with `ref`, a slide joint, bodies off the chain) at 20 seeded
//! states from `dynamics_arm_mujoco.json`, written by `dynamics_arm_mujoco.py` beside it.
//! Also the effort limits read from `actuatorfrcrange` and the actuators, and the errors of
//! models without inertial data.

mod common;

use graspath::robot::{MjcfRobot, RobotError};
use nalgebra::Vector3;
use serde_json::Value;
use std::path::PathBuf;

fn data_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/mjcf")
}

/// `‖ours − reference‖∞ / ‖reference‖∞`, asserted below 1e-9.
fn relative_error(ours: &[f64], reference: &[f64], what: &str) -> f64 {
    common::max_relative_error(ours, reference, 1e-9, what)
}

#[test]
fn mjcf_dynamics_equal_mujoco() {
    let path = data_dir().join("dynamics_arm.xml");
    let robot = MjcfRobot::from_file(&path).unwrap();
    let chain = robot.chain("base", "tool", None).unwrap();
    let reference: Value = serde_json::from_str(
        &std::fs::read_to_string(data_dir().join("dynamics_arm_mujoco.json")).unwrap(),
    )
    .unwrap();
    let names: Vec<String> = reference["joint_names"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_str().unwrap().to_string())
        .collect();
    assert_eq!(chain.joint_names(), names.as_slice());
    let gravity = Vector3::from_vec(common::json_numbers(&reference["gravity_base"]));
    let dynamics = chain.dynamics().unwrap().with_gravity(gravity).unwrap();
    let mut data = dynamics.data();
    let n = dynamics.dof();
    let mut tau = vec![0.0; n];
    let mut mass = nalgebra::DMatrix::zeros(n, n);
    let mut worst = [0.0f64; 3];
    for sample in reference["samples"].as_array().unwrap() {
        let (q, qd, qdd) = (
            common::json_numbers(&sample["q"]),
            common::json_numbers(&sample["qd"]),
            common::json_numbers(&sample["qdd"]),
        );
        dynamics
            .gravity_torques_into(&mut data, &q, &mut tau)
            .unwrap();
        worst[0] = worst[0].max(relative_error(
            &tau,
            &common::json_numbers(&sample["g"]),
            "g",
        ));
        dynamics
            .inverse_dynamics_into(&mut data, &q, &qd, &qdd, &mut tau)
            .unwrap();
        worst[1] = worst[1].max(relative_error(
            &tau,
            &common::json_numbers(&sample["tau"]),
            "rnea",
        ));
        dynamics.mass_matrix_into(&mut data, &q, &mut mass).unwrap();
        worst[2] = worst[2].max(relative_error(
            mass.transpose().as_slice(),
            &common::json_numbers(&sample["mass_matrix"]),
            "mass matrix",
        ));
    }
    eprintln!(
        "dynamics_arm: largest relative errors against MuJoCo: g {:.1e}, inverse dynamics {:.1e}, mass matrix {:.1e}",
        worst[0], worst[1], worst[2]
    );
}

/// `actuatorfrcrange` and the actuators' `forcerange × gear` (the smallest wins; a class
/// default supplies them too); a joint without either has no effort limit, and MJCF gives no
/// velocity limits.
#[test]
fn mjcf_effort_limits_come_from_the_actuators() {
    let robot = MjcfRobot::from_file(&data_dir().join("dynamics_arm.xml")).unwrap();
    let chain = robot.chain("base", "tool", None).unwrap();
    let efforts: Vec<Option<f64>> = chain.motion_limits().iter().map(|l| l.effort).collect();
    assert_eq!(
        efforts,
        [
            Some(150.0),
            Some(120.0),
            Some(100.0),
            Some(40.0),
            None,
            None
        ]
    );
    assert!(chain.motion_limits().iter().all(|l| l.velocity.is_none()));
}

/// A moving body without `<inertial>` (MuJoCo would take its mass from its geoms) and a model
/// with `inertiafromgeom="true"` both refuse dynamics by name; neither is a zero mass.
#[test]
fn mjcf_without_inertial_data_is_an_error() {
    let text = std::fs::read_to_string(data_dir().join("dynamics_arm.xml")).unwrap();
    let without = text.replace(
        r#"<inertial pos="0.03 0 0" mass="1.1" diaginertia="0.002 0.002 0.001"/>"#,
        "",
    );
    assert_ne!(without, text);
    let robot = MjcfRobot::from_xml_in(&without, "no_inertial.xml", &data_dir()).unwrap();
    // The slide joint j5 moves the body `slider` alone, which now has no inertial.
    let chain = robot.chain("base", "tool", None).unwrap();
    let err = chain.dynamics().unwrap_err();
    assert!(
        matches!(&err, RobotError::NoInertia { joint, .. } if joint == "j5"),
        "{err}"
    );
    assert!(err.to_string().contains("geoms"), "{err}");

    let from_geoms = text.replace(
        r#"<compiler autolimits="true"/>"#,
        r#"<compiler autolimits="true" inertiafromgeom="true"/>"#,
    );
    let robot = MjcfRobot::from_xml_in(&from_geoms, "from_geoms.xml", &data_dir()).unwrap();
    let err = robot
        .chain("base", "tool", None)
        .unwrap()
        .dynamics()
        .unwrap_err();
    assert!(matches!(err, RobotError::NoInertia { .. }), "{err}");
}
