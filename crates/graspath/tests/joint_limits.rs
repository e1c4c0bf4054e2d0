//! Joint ranges as their makers publish them, and a task narrowing them
//! (`robot.joint_limits`): the Kinova Gen3 against MuJoCo Menagerie's `kinova_gen3` file, the
//! UR elbow at ROS-Industrial's ±π, and the errors of a range that cannot be applied.

use graspath::robot::{Chain, RobotSource};
use graspath::select::select;
use graspath::task::Task;
use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use rand::{RngExt, SeedableRng};
use std::f64::consts::PI;
use std::path::Path;

fn data(name: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/mjcf")
        .join(name)
}

/// Menagerie's `kinova_gen3` (its bodies, joints and ranges, written as Menagerie writes
/// them) and the built-in `gen3`: the same joint ranges and the same tool pose.
#[test]
fn gen3_has_the_ranges_and_kinematics_of_menagerie_s_gen3() {
    // Menagerie's `pinch_site` on the bracelet: 0.061525 m down its z, turned by π about x;
    // the built-in's `end_effector_link` is that frame.
    let tool = Isometry3::from_parts(
        Translation3::new(0.0, 0.0, -0.061525),
        UnitQuaternion::from_axis_angle(&Vector3::x_axis(), PI),
    );
    let menagerie = RobotSource::mjcf(data("kinova_gen3_menagerie.xml"))
        .load()
        .unwrap()
        .chain("base_link", "bracelet_link", Some(tool))
        .unwrap();
    let builtin = RobotSource::builtin("gen3")
        .load()
        .unwrap()
        .named_chain("arm", None)
        .unwrap();
    assert_eq!(menagerie.dof(), 7);
    assert_eq!(builtin.lower(), menagerie.lower());
    assert_eq!(builtin.upper(), menagerie.upper());
    // Kinova's user guide: ±128.9°, ±147.8°, ±120.3°, written rounded down to 0.01 rad.
    for (joint, degrees) in [(1, 128.9_f64), (3, 147.8), (5, 120.3)] {
        let published = degrees.to_radians();
        assert!(builtin.upper()[joint] <= published && published - builtin.upper()[joint] < 0.01);
        assert_eq!(builtin.lower()[joint], -builtin.upper()[joint]);
    }
    let mut rng = rand::rngs::StdRng::seed_from_u64(7);
    for _ in 0..200 {
        let q: Vec<f64> = (0..7).map(|_| rng.random_range(-2.0..2.0)).collect();
        let a = builtin.pose(&q).unwrap();
        let b = menagerie.pose(&q).unwrap();
        let dt = (a.translation.vector - b.translation.vector).norm();
        let dr = (a.rotation.matrix() - b.rotation.matrix()).amax();
        assert!(
            dt < 1e-12 && dr < 1e-12,
            "q = {q:?}: {dt} m, rotation matrices {dr} apart"
        );
    }
}

fn ur5e_task(joint_limits: &str) -> std::io::Result<(tempfile::TempDir, std::path::PathBuf)> {
    let text = format!(
        "robot: {{ builtin: ur5e{joint_limits} }}\n\
         object: {{ pose: {{ xyz: [0.45, 0.1, 0.05] }}, shape: {{ box: {{ size: [0.06, 0.06, 0.10] }} }} }}\n\
         candidates: {{ family: {{ faces: {{ count: 24, exclude: [bottom] }} }} }}\n\
         trajectory: {{ samples_per_step: 6, steps: [ {{ lift: 0.15 }}, {{ rotate: {{ axis: [0, 0, 1], angle_deg: 90 }} }} ] }}\n"
    );
    let dir = tempfile::tempdir()?;
    let path = dir.path().join("task.yaml");
    std::fs::write(&path, text)?;
    Ok((dir, path))
}

fn elbow(chain: &Chain) -> usize {
    chain
        .joint_names()
        .iter()
        .position(|n| n == "elbow_joint")
        .unwrap()
}

/// ROS-Industrial's ±π elbow on the built-in UR5e: the task's chain has it, and every
/// configuration of every feasible candidate (approach, carry, retreat) stays inside it.
#[test]
fn a_task_narrows_the_ur_elbow_to_ros_range_and_every_motion_keeps_it() {
    let (_dir, path) =
        ur5e_task(", joint_limits: { elbow_joint: [-3.141592653589793, 3.141592653589793] }")
            .unwrap();
    let task = Task::load(&path).unwrap();
    let chain = &task.arms()[0].chain;
    let e = elbow(chain);
    assert_eq!((chain.lower()[e], chain.upper()[e]), (-PI, PI));
    // The other joints keep the datasheet's ±2π.
    for j in (0..6).filter(|&j| j != e) {
        assert_eq!(chain.upper()[j], 2.0 * PI);
    }
    let selection = select(&task, &|| ()).unwrap();
    let arm = &selection.arms[0];
    assert!(
        arm.feasible_count() > 0,
        "the narrowed task still has feasible grasps"
    );
    for score in arm.scores.iter().filter(|s| s.failure.is_none()) {
        for q in score
            .approach
            .iter()
            .chain(&score.joint_trajectory)
            .chain(&score.retreat)
        {
            assert!(q[e].abs() <= PI, "elbow at {} rad", q[e]);
            assert!(chain.within_limits(q));
        }
    }
}

fn load_error(joint_limits: &str) -> String {
    let (_dir, path) = ur5e_task(joint_limits).unwrap();
    graspath::Chain(&Task::load(&path).unwrap_err()).to_string()
}

#[test]
fn a_range_that_cannot_be_applied_is_one_error_naming_the_joint() {
    let widen = load_error(", joint_limits: { elbow_joint: [-7, 7] }");
    assert!(
        widen.contains("robot.joint_limits.elbow_joint") && widen.contains("not widen"),
        "{widen}"
    );
    let unknown = load_error(", joint_limits: { elbow: [-1, 1] }");
    assert!(
        unknown.contains("robot.joint_limits.elbow") && unknown.contains("elbow_joint"),
        "{unknown}"
    );
    for empty in ["[1, 1]", "[1, -1]"] {
        let message = load_error(&format!(", joint_limits: {{ wrist_1_joint: {empty} }}"));
        assert!(
            message.contains("robot.joint_limits.wrist_1_joint") && message.contains("not a range"),
            "{empty}: {message}"
        );
    }
    // Non-finite numbers are refused by the task reader itself.
    for non_finite in ["[.nan, 1]", "[-.inf, 1]"] {
        let message = load_error(&format!(
            ", joint_limits: {{ wrist_1_joint: {non_finite} }}"
        ));
        assert!(message.contains("non-finite"), "{non_finite}: {message}");
    }
    let short = load_error(", joint_limits: { elbow_joint: [1] }");
    assert!(short.contains("joint_limits"), "{short}");
}

/// A continuous joint given a range is bounded: the built-in Gen3's joint 1.
#[test]
fn a_continuous_joint_given_a_range_becomes_revolute() {
    let chain = RobotSource::builtin("gen3")
        .load()
        .unwrap()
        .named_chain("arm", None)
        .unwrap();
    assert!(chain.upper()[0].is_infinite());
    let narrowed = chain.with_joint_range("joint_1", -1.0, 2.0).unwrap();
    assert_eq!((narrowed.lower()[0], narrowed.upper()[0]), (-1.0, 2.0));
    assert_eq!(
        narrowed.joint_kinds()[0],
        graspath::robot::JointKind::Revolute
    );
    assert!(!narrowed.within_limits(&[2.5, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]));
    assert!(chain.within_limits(&[2.5, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]));
    for (lower, upper) in [(f64::NAN, 1.0), (-1.0, f64::INFINITY), (1.0, 1.0)] {
        let message = chain
            .with_joint_range("joint_1", lower, upper)
            .unwrap_err()
            .to_string();
        assert!(
            message.contains("joint_1") && message.contains("not a range"),
            "{message}"
        );
    }
}
