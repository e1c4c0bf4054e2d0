//! Forward kinematics, Jacobians and every index against Pinocchio 4.1 reference values
//! (`../shared/reference/baxter_left_pinocchio.json`), for both the URDF-loaded and the built-in
//! Baxter left arm.

mod common;

use graspath::manipulability::{
    inverse_condition, inverse_condition_squared, singular_values, task_relevant, yoshikawa,
    Direction, JacobianPart,
};
use graspath::robot::builtin::{baxter, Arm};
use graspath::robot::{load_urdf_chain, Chain};
use nalgebra::{Vector3, Vector6};
use serde_json::Value;

const TOL: f64 = 1e-9;

fn close(a: f64, b: f64, what: &str) {
    assert!(
        (a - b).abs() <= TOL * b.abs().max(1.0),
        "{what}: {a} vs reference {b}"
    );
}

fn check_chain(chain: &Chain, reference: &Value) {
    let names: Vec<String> = reference["joint_names"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_str().unwrap().to_string())
        .collect();
    assert_eq!(chain.joint_names(), names.as_slice());
    for (i, (lo, hi)) in chain.lower().iter().zip(chain.upper()).enumerate() {
        close(*lo, reference["lower"][i].as_f64().unwrap(), "lower limit");
        close(*hi, reference["upper"][i].as_f64().unwrap(), "upper limit");
    }
    let dirs_trans: Vec<Vector3<f64>> = reference["directions_trans"]
        .as_array()
        .unwrap()
        .iter()
        .map(|d| Vector3::from_iterator(d.as_array().unwrap().iter().map(|x| x.as_f64().unwrap())))
        .collect();
    let dirs_full: Vec<Vector6<f64>> = reference["directions_full"]
        .as_array()
        .unwrap()
        .iter()
        .map(|d| Vector6::from_iterator(d.as_array().unwrap().iter().map(|x| x.as_f64().unwrap())))
        .collect();
    let samples = reference["samples"].as_array().unwrap();
    assert!(samples.len() >= 20);
    for sample in samples {
        let q: Vec<f64> = sample["q"]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect();
        let (pose, jac) = chain.pose_and_jacobian(&q).unwrap();
        let m = pose.to_homogeneous();
        for r in 0..4 {
            for c in 0..4 {
                close(m[(r, c)], sample["T"][r][c].as_f64().unwrap(), "pose");
            }
        }
        for r in 0..6 {
            for c in 0..7 {
                close(jac[(r, c)], sample["J"][r][c].as_f64().unwrap(), "jacobian");
            }
        }
        let get = |k: &str| sample[k].as_f64().unwrap();
        close(
            yoshikawa(&jac, JacobianPart::Full),
            get("yoshikawa_full"),
            "yoshikawa_full",
        );
        close(
            yoshikawa(&jac, JacobianPart::Translation),
            get("yoshikawa_trans"),
            "yoshikawa_trans",
        );
        close(
            yoshikawa(&jac, JacobianPart::Rotation),
            get("yoshikawa_rot"),
            "yoshikawa_rot",
        );
        close(
            inverse_condition(&jac, JacobianPart::Full),
            get("inv_cond_J_full"),
            "inv_cond_J_full",
        );
        close(
            inverse_condition(&jac, JacobianPart::Translation),
            get("inv_cond_J_trans"),
            "inv_cond_J_trans",
        );
        close(
            inverse_condition_squared(&jac, JacobianPart::Full),
            get("inv_cond_JJt_full"),
            "inv_cond_JJt_full",
        );
        close(
            inverse_condition_squared(&jac, JacobianPart::Translation),
            get("inv_cond_JJt_trans"),
            "inv_cond_JJt_trans",
        );
        for (k, s) in singular_values(&jac, JacobianPart::Full).iter().enumerate() {
            close(*s, sample["sigma_full"][k].as_f64().unwrap(), "sigma_full");
        }
        for (k, s) in singular_values(&jac, JacobianPart::Translation)
            .iter()
            .enumerate()
        {
            close(
                *s,
                sample["sigma_trans"][k].as_f64().unwrap(),
                "sigma_trans",
            );
        }
        for (k, u) in dirs_trans.iter().enumerate() {
            let m_t = task_relevant(&jac, &Direction::Translation(*u));
            close(
                m_t,
                sample["task_manip_trans"][k].as_f64().unwrap(),
                "task_manip_trans",
            );
        }
        for (k, u) in dirs_full.iter().enumerate() {
            let m_t = task_relevant(&jac, &Direction::Full(*u));
            close(
                m_t,
                sample["task_manip_full"][k].as_f64().unwrap(),
                "task_manip_full",
            );
        }
    }
}

fn reference() -> Option<Value> {
    let path = common::shared_file("reference/baxter_left_pinocchio.json")?;
    Some(serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap())
}

#[test]
fn urdf_baxter_left_matches_pinocchio() {
    let Some(reference) = reference() else { return };
    let urdf = common::shared_file("robots/baxter.urdf").unwrap();
    let chain = load_urdf_chain(&urdf, "base", "left_gripper", None).unwrap();
    check_chain(&chain, &reference);
}

#[test]
fn builtin_baxter_left_matches_pinocchio() {
    let Some(reference) = reference() else { return };
    check_chain(&baxter(Arm::Left), &reference);
}

#[test]
fn special_configurations_match_pinocchio() {
    let Some(reference) = reference() else { return };
    let chain = baxter(Arm::Left);
    for (name, special) in reference["special"].as_object().unwrap() {
        let q: Vec<f64> = special["q"]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect();
        let pose = chain.pose(&q).unwrap().to_homogeneous();
        for r in 0..4 {
            for c in 0..4 {
                close(pose[(r, c)], special["T"][r][c].as_f64().unwrap(), name);
            }
        }
    }
}
