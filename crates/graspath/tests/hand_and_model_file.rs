//! URDF hands (mimic joints, shapes, errors) and the model file (round trip, version check).
//! The contact-sample invariants are a unit test of `grasp::model::contact` (model internals).

use graspath::geometry::shape::Shape;
use graspath::grasp::hand::{hand_from_urdf, HandError};
use graspath::grasp::model::{train_file, GraspModel, ModelError};
use graspath::robot::{MeshResolver, UrdfRobot};
use nalgebra::{Point3, Vector3};
use std::path::PathBuf;

fn data() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data")
}

#[test]
fn urdf_hand_has_its_joints_links_and_mimic_fingers() {
    let robot = UrdfRobot::from_file(&data().join("three_finger_hand.urdf")).expect("urdf");
    let meshes = MeshResolver::from_env(&data(), Vec::new());
    let hand = hand_from_urdf(&robot, "palm", &meshes).expect("hand");
    let names: Vec<&str> = hand.joints.iter().map(|j| j.name.as_str()).collect();
    assert_eq!(names, ["a_joint", "bc_joint"]);
    assert_eq!(hand.links.len(), 4);
    assert!(matches!(hand.links[0].shapes[0].shape, Shape::Box(_)));
    // Finger c mimics b: at q = (0, θ) fingers b and c tilt inwards by the same angle, a stays.
    let theta = 0.3;
    let poses = hand.link_poses(&[0.0, theta]);
    let tip = |link: usize| poses[link] * Point3::new(0.0, 0.0, 0.07);
    let radial = |p: Point3<f64>| Vector3::new(p.x, p.y, 0.0).norm();
    assert!((radial(tip(1)) - 0.045).abs() < 1e-12);
    let expected = 0.045 - 0.07 * theta.sin();
    let b = hand.link_index("finger_b").expect("b");
    let c = hand.link_index("finger_c").expect("c");
    // The URDF gives the finger bases to 1 µm.
    assert!(
        (radial(tip(b)) - expected).abs() < 1e-6,
        "{} vs {expected}",
        radial(tip(b))
    );
    assert!((radial(tip(c)) - expected).abs() < 1e-6);
    assert!((radial(tip(b)) - radial(tip(c))).abs() < 1e-6);
    let err = hand_from_urdf(&robot, "wrist", &meshes).unwrap_err();
    assert!(
        matches!(err, HandError::UnknownRoot { .. }) && err.to_string().contains("palm"),
        "{err}"
    );
    // The message starts with the hand's file, as every input error does.
    assert!(
        err.to_string().starts_with(robot.source_name()) && robot.source_name().ends_with(".urdf"),
        "{err}"
    );
}

#[test]
fn model_file_round_trips_and_refuses_other_versions() {
    let model = train_file(&data().join("three_finger_demo.json")).expect("train");
    let dir = tempfile::tempdir().expect("tempdir");
    let path = dir.path().join("m.json");
    model.write(&path).expect("write");
    let back = GraspModel::read(&path).expect("read");
    assert_eq!(back, model);
    let text = std::fs::read_to_string(&path).expect("text").replacen(
        "\"format_version\":2",
        "\"format_version\":7",
        1,
    );
    let err = GraspModel::from_json(&text, "m.json").unwrap_err();
    assert!(matches!(err, ModelError::Version { .. }), "{err}");
    assert!(
        err.to_string().contains("m.json") && err.to_string().contains("format_version"),
        "{err}"
    );
    let err = GraspModel::from_json("{\"format\": \"something\"}", "x.json").unwrap_err();
    assert!(
        err.to_string().contains("x.json") && err.to_string().contains("'format'"),
        "{err}"
    );
}
