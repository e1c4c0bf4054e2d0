//! The stock Panda hand of example-robot-data's `panda.urdf` (links `panda_hand`,
//! `panda_leftfinger`, `panda_rightfinger`; collision meshes given as `package://` URIs) trains
//! from one demonstration and generates grasps; the model's wrist frame is `panda_hand_tcp`,
//! the frame the built-in Panda chain and a URDF chain to `panda_hand_tcp` end at.
//!
//! Needs example-robot-data (`GRASPATH_ROBOT_DATA`, see `tests/robot_data.rs`): skipped with a
//! message locally, a failure in CI.

mod common;

use graspath::cloud::PointCloud;
use graspath::grasp::hand::{hand_from_robot, hand_from_robot_with_wrist, Hand, HandError};
use graspath::grasp::model::{generate, train_file, Candidate, GenerateOptions};
use graspath::robot::{RobotModel, RobotSource};
use nalgebra::{Isometry3, Point3, Vector3};
use rand::rngs::StdRng;
use rand::{RngExt, SeedableRng};
use std::path::{Path, PathBuf};

/// `panda_hand_tcp_joint`'s origin in franka_description: the tool point 0.1034 m along the
/// hand's z.
const TCP_DEPTH: f64 = 0.1034;
/// `panda_finger_joint{1,2}`'s origin: the fingers' frames 0.0584 m along the hand's z.
const FINGER_DEPTH: f64 = 0.0584;
/// The box grasped (m): the fingers close along the object's y across its 0.04 m.
const BOX: [f64; 3] = [0.06, 0.04, 0.12];

fn panda_urdf(data: &Path) -> PathBuf {
    data.join("panda_description/urdf/panda.urdf")
}

fn panda_model(data: &Path) -> RobotModel {
    RobotSource::urdf(panda_urdf(data))
        .load()
        .expect("panda.urdf")
}

/// The demonstration: a top-down pinch across the box's y, the tool point 2 cm below the top
/// face; the tool frame (z approach, fingers closing along y) is turned half a turn about x
/// from the object frame.
fn write_demonstration(dir: &Path, urdf: &Path) -> PathBuf {
    let top = BOX[2] / 2.0;
    let waypoint = |z: f64, opening: f64| {
        serde_json::json!({
            "object_from_wrist": [[1, 0, 0, 0], [0, -1, 0, 0], [0, 0, -1, z], [0, 0, 0, 1]],
            "hand_joints": [opening],
        })
    };
    let demo = serde_json::json!({
        "format": "graspath-demonstration",
        "version": 1,
        "label": "panda pinch",
        "hand": { "urdf": urdf, "root": "panda_hand", "wrist": "panda_hand_tcp" },
        "cloud": { "primitive": { "shape": { "box": { "size": BOX } }, "points": 4000, "seed": 3 } },
        "waypoints": [waypoint(top + 0.08, 0.04), waypoint(top - 0.02, BOX[1] / 2.0 + 0.0005)],
    });
    let path = dir.join("panda_demo.json");
    std::fs::write(&path, serde_json::to_vec_pretty(&demo).unwrap()).unwrap();
    path
}

#[test]
fn the_stock_panda_hand_has_its_links_in_the_tool_frame() {
    let Some(data) = common::robot_data() else {
        return;
    };
    let model = panda_model(&data);
    let hand = hand_from_robot_with_wrist(&model, "panda_hand", "panda_hand_tcp").expect("hand");
    assert_eq!(hand.dof(), 1, "panda_finger_joint2 mimics joint1");
    let mut rng = StdRng::seed_from_u64(5);
    for _ in 0..20 {
        let q = rng.random_range(0.0..0.04);
        let poses = hand.link_poses(&[q]);
        let at = |name: &str| poses[hand.link_index(name).expect(name)];
        // Closed forms from the URDF's joint origins and axes (±y for the two fingers).
        let expect = [
            ("panda_hand", Vector3::new(0.0, 0.0, -TCP_DEPTH)),
            (
                "panda_leftfinger",
                Vector3::new(0.0, q, FINGER_DEPTH - TCP_DEPTH),
            ),
            (
                "panda_rightfinger",
                Vector3::new(0.0, -q, FINGER_DEPTH - TCP_DEPTH),
            ),
            ("panda_hand_tcp", Vector3::zeros()),
        ];
        for (name, t) in expect {
            let pose = at(name);
            assert!(
                (pose.translation.vector - t).norm() < 1e-12,
                "{name}: {pose}"
            );
            assert!(pose.rotation.angle() < 1e-12, "{name}: {pose}");
        }
    }
    // The mesh of `panda_hand` was found through its package:// URI.
    assert!(!hand.links[0].shapes.is_empty());
    // The same frame as a chain ending at panda_hand_tcp: hand_from_tcp of the URDF's chains.
    let to_hand = model.chain("panda_link0", "panda_hand", None).unwrap();
    let to_tcp = model.chain("panda_link0", "panda_hand_tcp", None).unwrap();
    let q: Vec<f64> = to_hand
        .lower()
        .iter()
        .zip(to_hand.upper())
        .map(|(l, u)| 0.3 * l + 0.7 * u)
        .collect();
    let hand_from_tcp = common::fk(&to_hand, &q).inverse() * common::fk(&to_tcp, &q);
    let tcp_from_hand = hand.link_poses(&[0.0])[0];
    let d = hand_from_tcp * tcp_from_hand;
    assert!(
        d.translation.vector.norm() < 1e-12 && d.rotation.angle() < 1e-12,
        "{d}"
    );
    // Without a wrist link the frame is the root's.
    let at_root = hand_from_robot(&model, "panda_hand").unwrap();
    assert_eq!(
        at_root.links[0].joint.parent_from_joint,
        Isometry3::identity()
    );
}

#[test]
fn a_wrist_that_moves_with_the_fingers_or_is_not_in_the_hand_is_refused() {
    let Some(data) = common::robot_data() else {
        return;
    };
    let model = panda_model(&data);
    for (wrist, says) in [
        ("panda_leftfinger", "moves with a hand joint"),
        ("panda_link3", "not a link below the root"),
    ] {
        let err = hand_from_robot_with_wrist(&model, "panda_hand", wrist).unwrap_err();
        assert!(matches!(err, HandError::BadWrist { .. }), "{err}");
        let text = err.to_string();
        assert!(text.contains(wrist) && text.contains(says), "{text}");
    }
}

/// Deepest penetration (m) of a cloud point into a hand link at the grasp.
fn deepest(hand: &Hand, c: &Candidate, cloud: &PointCloud) -> f64 {
    let poses = hand.link_poses(&c.hand_joints);
    let wrist_from_object = c.object_from_wrist.inverse();
    let mut worst: f64 = 0.0;
    for p in &cloud.points {
        let p = wrist_from_object * p;
        for (i, pose) in poses.iter().enumerate() {
            if let Some(prox) = hand.link_proximity(i, pose, &p) {
                worst = worst.max(-prox.signed_distance);
            }
        }
    }
    worst
}

#[test]
fn the_stock_panda_hand_trains_and_generates_pinches_of_the_box() {
    let Some(data) = common::robot_data() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let demo = write_demonstration(dir.path(), &panda_urdf(&data));
    let model = train_file(&demo).expect("train with the stock Panda hand");
    let links: Vec<&str> = model.contact_links().map(|(l, _)| l).collect();
    assert!(
        links.contains(&"panda_leftfinger") && links.contains(&"panda_rightfinger"),
        "{links:?}"
    );
    // The model file round-trips with the hand's wrist placement.
    let text = String::from_utf8(model.to_json().unwrap()).unwrap();
    let again = graspath::grasp::model::GraspModel::from_json(&text, "model").expect("read back");
    assert_eq!(again.hand, model.hand);

    let cloud = graspath::cloud::CloudSource::Primitive {
        shape: graspath::geometry::shape::Shape::cuboid(BOX)
            .unwrap()
            .into(),
        sampling: graspath::cloud::SampleOptions {
            points: 4000,
            seed: 11,
            ..Default::default()
        },
    }
    .load(dir.path())
    .unwrap();
    let options = GenerateOptions {
        initial_grasps: 4000,
        steps: 200,
        first_stage_steps: 30,
        query_kernels: 2000,
        seed: 2,
        ..GenerateOptions::default()
    };
    let candidates = generate(&model, &cloud, &options, "box cloud", &|_| {}).expect("generate");
    let best = candidates.first().expect("a candidate");
    // The tool point (between the pads) lies in the box, within 1 cm.
    let tcp = Point3::from(best.object_from_wrist.translation.vector);
    for k in 0..3 {
        assert!(tcp[k].abs() < BOX[k] / 2.0 + 0.01, "tool point {tcp}");
    }
    // Both pads touch the object, the opening is in the fingers' range, nothing goes in.
    let poses = model.hand.link_poses(&best.hand_joints);
    let wrist_from_object = best.object_from_wrist.inverse();
    for finger in ["panda_leftfinger", "panda_rightfinger"] {
        let i = model.hand.link_index(finger).unwrap();
        let closest = cloud
            .points
            .iter()
            .filter_map(|p| {
                model
                    .hand
                    .link_proximity(i, &poses[i], &(wrist_from_object * p))
            })
            .map(|prox| prox.signed_distance)
            .fold(f64::INFINITY, f64::min);
        assert!(closest < 0.01, "{finger} is {:.1} mm away", closest * 1e3);
    }
    assert!(
        (0.0..=0.04).contains(&best.hand_joints[0]),
        "{:?}",
        best.hand_joints
    );
    let depth = deepest(&model.hand, best, &cloud);
    assert!(depth < 0.004, "penetration {depth}");
}

/// A copy of `panda.urdf` outside example-robot-data's folders cannot find its `package://`
/// meshes by itself (the error lists where it looked); the demonstration's `search_paths`
/// (relative to the demonstration file) point it at the package's `share` folder.
#[test]
fn a_copied_panda_urdf_finds_its_meshes_through_the_demonstrations_search_paths() {
    let Some(data) = common::robot_data() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let copy = dir.path().join("panda.urdf");
    std::fs::copy(panda_urdf(&data), &copy).unwrap();
    let share = data.parent().and_then(Path::parent).unwrap().to_path_buf();
    let source = |search_paths: Vec<PathBuf>| graspath::grasp::model::HandSource::Urdf {
        urdf: "panda.urdf".into(),
        root: "panda_hand".into(),
        wrist: Some("panda_hand_tcp".into()),
        search_paths,
    };
    let ros_paths_set = ["ROS_PACKAGE_PATH", "AMENT_PREFIX_PATH"]
        .iter()
        .any(|v| std::env::var_os(v).is_some_and(|p| !p.is_empty()));
    if !ros_paths_set {
        let missing = source(Vec::new())
            .load(dir.path(), "demo.json")
            .unwrap_err()
            .to_string();
        assert!(
            missing.contains("package://example-robot-data") && missing.contains("hand.stl"),
            "{missing}"
        );
    }
    let hand = source(vec![share])
        .load(dir.path(), "demo.json")
        .expect("meshes found through search_paths");
    assert_eq!(hand.dof(), 1);
    assert!(!hand.links[0].shapes.is_empty());
}
