//! The MJCF worlds graspath writes (`graspath::physics`): read back as plain XML, their bodies'
//! placements, composed along the nesting with the joints turned, give the chain's tool pose;
//! their joint ranges, masses and names are the task's. (MuJoCo's own reading of the same
//! files is compared with graspath in the Python tests, `test_sim.py`.)

mod common;

use graspath::physics::{chain_mjcf, world_mjcf, PhysicsError, WorldOptions};
use graspath::robot::builtin::BuiltinRobot;
use graspath::robot::Chain;
use graspath::task::Task;
use nalgebra::{Isometry3, Quaternion, Translation3, UnitQuaternion, Vector3};
use quick_xml::events::Event;
use quick_xml::Reader;
use std::collections::HashMap;
use std::path::Path;

/// One element as read: its tag, its attributes and its depth.
#[derive(Debug, Clone)]
struct Element {
    tag: String,
    attributes: HashMap<String, String>,
    depth: usize,
}

fn elements(xml: &str) -> Vec<Element> {
    let mut reader = Reader::from_str(xml);
    let mut out = Vec::new();
    let mut depth = 0;
    loop {
        let (e, opens) = match reader.read_event().expect("well-formed XML") {
            Event::Start(e) => (e, true),
            Event::Empty(e) => (e, false),
            Event::End(_) => {
                depth -= 1;
                continue;
            }
            Event::Eof => break,
            _ => continue,
        };
        let attributes = e
            .attributes()
            .map(|a| {
                let a = a.unwrap();
                (
                    String::from_utf8(a.key.as_ref().to_vec()).unwrap(),
                    a.unescape_value().unwrap().into_owned(),
                )
            })
            .collect();
        out.push(Element {
            tag: String::from_utf8(e.name().as_ref().to_vec()).unwrap(),
            attributes,
            depth,
        });
        depth += usize::from(opens);
    }
    out
}

fn numbers(text: &str) -> Vec<f64> {
    text.split_whitespace()
        .map(|v| v.parse().unwrap())
        .collect()
}

fn placement(e: &Element) -> Isometry3<f64> {
    let p = e.attributes.get("pos").map_or(vec![0.0; 3], |t| numbers(t));
    let q = e
        .attributes
        .get("quat")
        .map_or(vec![1.0, 0.0, 0.0, 0.0], |t| numbers(t));
    Isometry3::from_parts(
        Translation3::new(p[0], p[1], p[2]),
        UnitQuaternion::from_quaternion(Quaternion::new(q[0], q[1], q[2], q[3])),
    )
}

/// The world pose of the body named `target`, composing the placements of the bodies that
/// hold it, each hinge (about its body's `z`) turned by the next value of `q`.
fn body_pose(elements: &[Element], target: &str, q: &[f64]) -> Isometry3<f64> {
    let mut stack: Vec<(usize, Isometry3<f64>)> = Vec::new();
    let mut joint = 0;
    for e in elements {
        while stack.last().is_some_and(|(d, _)| *d >= e.depth) {
            stack.pop();
        }
        let parent = stack.last().map_or_else(Isometry3::identity, |(_, p)| *p);
        match e.tag.as_str() {
            "body" => {
                let pose = parent * placement(e);
                if e.attributes["name"] == target {
                    return pose;
                }
                stack.push((e.depth, pose));
            }
            "joint" => {
                assert_eq!(e.attributes["axis"], "0 0 1");
                let turn = match e.attributes["type"].as_str() {
                    "hinge" => Isometry3::rotation(Vector3::z() * q[joint]),
                    "slide" => Isometry3::translation(0.0, 0.0, q[joint]),
                    other => panic!("joint type {other}"),
                };
                joint += 1;
                let (depth, pose) = stack.pop().expect("a joint inside a body");
                stack.push((depth, pose * turn));
            }
            _ => {}
        }
    }
    panic!("no body {target}");
}

#[test]
fn every_builtin_arm_written_alone_has_graspaths_kinematics_limits_and_masses() {
    for robot in BuiltinRobot::ALL {
        for spec in robot.chain_specs() {
            let chain = Chain::from_spec(&spec).unwrap();
            let (xml, names) = chain_mjcf(&chain, "arm").unwrap();
            let read = elements(&xml);
            assert_eq!(names.joints.len(), chain.dof());
            let joints: Vec<&Element> = read.iter().filter(|e| e.tag == "joint").collect();
            for (i, joint) in joints.iter().enumerate() {
                assert_eq!(
                    joint.attributes["name"],
                    format!("arm/{}", chain.joint_names()[i])
                );
                if let Some(range) = joint.attributes.get("range") {
                    assert_eq!(numbers(range), vec![chain.lower()[i], chain.upper()[i]]);
                }
            }
            let dynamics = chain.dynamics().unwrap();
            let mass: f64 = read
                .iter()
                .filter(|e| e.tag == "inertial")
                .map(|e| numbers(&e.attributes["mass"])[0])
                .sum();
            assert!(
                (mass - dynamics.moving_mass()).abs() <= 1e-12 * mass,
                "{}: {mass} vs {}",
                robot.name(),
                dynamics.moving_mass()
            );
            for q in common::configurations(&chain, 20, 7) {
                let written = body_pose(&read, "arm/tool", &q);
                let pose: Isometry3<f64> = nalgebra::convert(chain.pose(&q).unwrap());
                let position = (written.translation.vector - pose.translation.vector).norm();
                let angle = written.rotation.angle_to(&pose.rotation);
                assert!(
                    position < 1e-12 && angle < 1e-12,
                    "{} {}: {position} m, {angle} rad",
                    robot.name(),
                    chain.name()
                );
            }
        }
    }
}

fn example_task(relative: &str) -> Task {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .join(relative);
    Task::load(&path).unwrap()
}

#[test]
fn a_scene_task_is_written_with_its_table_obstacles_gripper_and_object() {
    let task = example_task("examples/scene/pick_and_place_left_cluttered.yaml");
    let world = world_mjcf(&task, &WorldOptions::default()).unwrap();
    let read = elements(&world.xml);
    let names: Vec<&String> = read
        .iter()
        .filter_map(|e| e.attributes.get("name"))
        .collect();
    // Names are unique within each kind (MuJoCo's rule).
    for tag in [
        "body", "geom", "joint", "site", "mesh", "motor", "position", "weld",
    ] {
        let mut seen = std::collections::HashSet::new();
        for e in read.iter().filter(|e| e.tag == tag) {
            assert!(
                seen.insert(e.attributes["name"].clone()),
                "{tag} {:?}",
                e.attributes["name"]
            );
        }
    }
    assert!(names.iter().any(|n| *n == "table"));
    let scene = &task.collisions().unwrap().scene;
    for obstacle in scene.obstacles() {
        assert!(
            read.iter()
                .any(|e| e.tag == "body" && e.attributes["name"] == obstacle.body.name()),
            "{}",
            obstacle.body.name()
        );
    }
    // The bin mesh is said to collide as its hull.
    assert!(world.notes.iter().any(|n| n.contains("convex hull")));
    // The object: a 0.06 × 0.40 × 0.10 m box at 500 kg/m³, at the path's first pose.
    assert!((world.object_mass - 0.06 * 0.40 * 0.10 * 500.0).abs() < 1e-12);
    let start: Isometry3<f64> = task.path().samples[0].world_from_object;
    let object = placement(
        read.iter()
            .find(|e| e.tag == "body" && e.attributes["name"] == "object")
            .unwrap(),
    );
    assert!((object.translation.vector - start.translation.vector).norm() < 1e-15);
    // Baxter's gripper: two sliding fingers that close by half the 7 cm opening.
    let arm = &world.arms[0];
    assert_eq!(arm.fingers.len(), 2);
    assert!((arm.finger_travel - 0.035).abs() < 1e-15);
    assert!(arm.task_gripper);
    let motors = read.iter().filter(|e| e.tag == "motor").count();
    assert_eq!(motors, task.arms()[0].chain.dof());
    for (joint, effort) in arm.joints.iter().zip(&arm.effort) {
        let motor = read
            .iter()
            .find(|e| e.tag == "motor" && e.attributes["joint"] == *joint)
            .unwrap();
        assert_eq!(
            numbers(&motor.attributes["ctrlrange"]),
            vec![-effort, *effort]
        );
    }
}

#[test]
fn a_task_without_scene_or_gripper_says_what_the_model_assumes() {
    let task = example_task("examples/t_shape_move.yaml");
    let world = world_mjcf(&task, &WorldOptions::default()).unwrap();
    assert!(!world.has_table);
    assert!(world.notes.iter().any(|n| n.contains("no scene")));
    assert!(world.notes.iter().any(|n| n.contains("no gripper")));
    assert!(!world.arms[0].task_gripper);
    // The T is two geoms: the bar and the stem.
    let read = elements(&world.xml);
    let parts = read
        .iter()
        .filter(|e| e.tag == "geom" && e.attributes["name"].starts_with("object/"))
        .count();
    assert_eq!(parts, 2);
}

#[test]
fn gravity_compensation_marks_every_moving_arm_body() {
    let task = example_task("examples/scene/pick_and_place_left_on_table.yaml");
    let options = WorldOptions {
        arm_gravity_compensation: true,
        ..WorldOptions::default()
    };
    let read = elements(&world_mjcf(&task, &options).unwrap().xml);
    for e in read.iter().filter(|e| e.tag == "body") {
        let name = &e.attributes["name"];
        let moving_arm_body =
            name.starts_with("left/") && name != "left/base" && name != "left/tool";
        assert_eq!(
            e.attributes.get("gravcomp").map(String::as_str),
            moving_arm_body.then_some("1"),
            "{name}"
        );
    }
}

#[test]
fn bad_options_and_unwritable_robots_are_refused_with_their_cause() {
    let task = example_task("examples/scene/pick_and_place_left_on_table.yaml");
    for options in [
        WorldOptions {
            timestep: 0.0,
            ..WorldOptions::default()
        },
        WorldOptions {
            friction: f64::NAN,
            ..WorldOptions::default()
        },
        WorldOptions {
            grip_force: -1.0,
            ..WorldOptions::default()
        },
    ] {
        assert!(matches!(
            world_mjcf(&task, &options),
            Err(PhysicsError::BadOption { .. })
        ));
    }
    // A chain without inertial data cannot be simulated.
    let chain = common::ur5_like(3.0);
    assert!(
        chain.dynamics().is_err(),
        "the test chain has no inertial data"
    );
    assert!(matches!(
        chain_mjcf(&chain, "arm"),
        Err(PhysicsError::NoInertia { .. })
    ));
}
