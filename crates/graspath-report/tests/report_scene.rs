//! The report of a task in a scene: the view carries the table and every obstacle as the task
//! file gives them, the arm's collision shapes on the link frames of the motion (approach →
//! path → retreat), a colliding candidate at a configuration where its two bodies really
//! collide, and `summary.json` counts the failures per reason. Output is deterministic.
//!
//! Oracles: the numbers written in the task file; link frames recomputed from the joint
//! trajectories of `candidates.json` with the chain's forward kinematics; the robot's collision
//! shapes read again from the robot source; exact distances of the two named bodies placed by
//! hand; failure counts from `candidates.json`.

use graspath::collision::{distance, Body};
use graspath::robot::RobotSource;
use graspath::select::record::Trajectories;
use graspath::select::select;
use graspath::task::{robot_link_shapes, Gripper, Task};
use graspath_report::{
    candidates_json, candidates_json_bytes, candidates_json_with, render_report, scene_json,
    summary_json,
};
use nalgebra::{Isometry3, Point3, Quaternion, Translation3, UnitQuaternion, Vector3};
use serde_json::Value;
use std::collections::BTreeMap;
use std::path::Path;

/// Baxter's left arm picks the paper's cuboid from a finite table, next to obstacles of every
/// kind; the arm runs into the `beam` for the grasps at the right-hand end (−y).
const SCENE_TASK: &str = r#"
robot: { builtin: baxter }
arms: left
object:
  pose: { xyz: [0.75, 0.0, -0.10] }
  shape: { box: { size: [0.06, 0.40, 0.10] } }
candidates:
  family: { edge: { count: 11 } }
trajectory:
  samples_per_step: 3
  steps:
    - { lift: 0.2, label: pick }
    - { move: [0.0, 0.3, 0.0], label: move }
    - { place: 0.2, label: place }
scene:
  table: { height: -0.15, size: [1.2, 1.6], centre: [0.8, 0.1] }
  obstacles:
    - { name: wall, box: { size: [0.05, 0.6, 0.5] }, pose: { xyz: [1.25, 0.0, 0.1] } }
    - { name: post, cylinder: { radius: 0.03, length: 0.15 }, pose: { xyz: [0.75, -0.26, -0.075] } }
    - { name: ball, sphere: { radius: 0.05 }, pose: { xyz: [0.6, -0.45, 0.0] } }
    - { name: beam, capsule: { radius: 0.02, length: 0.4 }, pose: { xyz: [0.6, -0.2, 0.3], rpy_deg: [90, 0, 0] } }
    - { name: bin, mesh: bin.obj, pose: { xyz: [0.5, -0.6, -0.15] } }
    - { name: scan, cloud: scan.ply, radius: 0.01 }
approach: { distance: 0.10, samples: 3 }
retreat: { distance: 0.10, samples: 3 }
gripper: { builtin: baxter }
"#;

/// A tetrahedron (OBJ, 1-based faces).
const BIN_OBJ: &str =
    "v 0 0 0\nv 0.2 0 0\nv 0 0.2 0\nv 0 0 0.2\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";

/// Three points (ASCII PLY).
const SCAN_PLY: &str = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nend_header\n1.3 0.5 0.2\n1.3 0.55 0.2\n1.3 0.6 0.25\n";

fn load(dir: &Path, yaml: &str) -> Task {
    std::fs::write(dir.join("bin.obj"), BIN_OBJ).unwrap();
    std::fs::write(dir.join("scan.ply"), SCAN_PLY).unwrap();
    let path = dir.join("scene.yaml");
    std::fs::write(&path, yaml).unwrap();
    Task::load(&path).unwrap()
}

fn f(v: &Value) -> f64 {
    v.as_f64().unwrap_or_else(|| panic!("not a number: {v}"))
}

fn vec3(v: &Value) -> Vector3<f64> {
    Vector3::new(f(&v[0]), f(&v[1]), f(&v[2]))
}

fn pose(v: &Value) -> Isometry3<f64> {
    Isometry3::from_parts(
        Translation3::new(f(&v[0]), f(&v[1]), f(&v[2])),
        UnitQuaternion::from_quaternion(Quaternion::new(f(&v[6]), f(&v[3]), f(&v[4]), f(&v[5]))),
    )
}

/// Poses agree to 0.2 mm and 1e-5 rad (the view rounds to 0.1 mm and 1e-6).
fn assert_close(a: &Isometry3<f64>, b: &Isometry3<f64>, what: &str) {
    let dt = (a.translation.vector - b.translation.vector).norm();
    let dr = a.rotation.angle_to(&b.rotation);
    assert!(dt < 2e-4 && dr < 1e-5, "{what}: {dt} m, {dr} rad apart");
}

fn body<'a>(view: &'a Value, name: &str) -> &'a Value {
    view["world"]["bodies"]
        .as_array()
        .unwrap()
        .iter()
        .find(|b| b["name"] == name)
        .unwrap_or_else(|| panic!("no body {name}"))
}

#[test]
fn the_view_carries_the_table_and_every_obstacle_as_the_task_file_gives_them() {
    let dir = tempfile::tempdir().unwrap();
    let task = load(dir.path(), SCENE_TASK);
    let selection = select(&task, &|| {}).unwrap();
    let view = scene_json(&task, &selection);
    let bodies = view["world"]["bodies"].as_array().unwrap();
    assert_eq!(bodies.len(), 7, "the table and six obstacles");
    assert_eq!(bodies[0]["name"], "table", "the table comes first");
    let at = |xyz: [f64; 3]| Isometry3::translation(xyz[0], xyz[1], xyz[2]);

    // The finite table: a slab 1.2 × 1.6 m, 5 cm thick (the default), its top at z = −0.15.
    let table = body(&view, "table");
    assert_eq!(table["geometry"]["type"], "box");
    assert_eq!(
        vec3(&table["geometry"]["size"]),
        Vector3::new(1.2, 1.6, 0.05)
    );
    assert_close(&pose(&table["pose"]), &at([0.8, 0.1, -0.175]), "table");

    let wall = body(&view, "obstacle wall");
    assert_eq!(wall["geometry"]["type"], "box");
    assert_eq!(
        vec3(&wall["geometry"]["size"]),
        Vector3::new(0.05, 0.6, 0.5)
    );
    assert_close(&pose(&wall["pose"]), &at([1.25, 0.0, 0.1]), "wall");

    let post = body(&view, "obstacle post");
    assert_eq!(post["geometry"]["type"], "cylinder");
    assert_eq!(
        (
            f(&post["geometry"]["radius"]),
            f(&post["geometry"]["length"])
        ),
        (0.03, 0.15)
    );
    assert_close(&pose(&post["pose"]), &at([0.75, -0.26, -0.075]), "post");

    let ball = body(&view, "obstacle ball");
    assert_eq!(ball["geometry"]["type"], "sphere");
    assert_eq!(f(&ball["geometry"]["radius"]), 0.05);
    assert_close(&pose(&ball["pose"]), &at([0.6, -0.45, 0.0]), "ball");

    // The beam lies along y: a quarter turn about x takes its z axis to −y.
    let beam = body(&view, "obstacle beam");
    assert_eq!(beam["geometry"]["type"], "capsule");
    assert_eq!(
        (
            f(&beam["geometry"]["radius"]),
            f(&beam["geometry"]["length"])
        ),
        (0.02, 0.4)
    );
    let world_from_beam = pose(&beam["pose"]);
    assert_close(
        &world_from_beam,
        &Isometry3::from_parts(
            Translation3::new(0.6, -0.2, 0.3),
            UnitQuaternion::from_axis_angle(&Vector3::x_axis(), std::f64::consts::FRAC_PI_2),
        ),
        "beam",
    );
    assert!((world_from_beam.rotation * Vector3::z() + Vector3::y()).norm() < 1e-6);

    // The mesh: the OBJ's vertices and faces (0-based), in the body frame.
    let bin = body(&view, "obstacle bin");
    assert_eq!(bin["geometry"]["type"], "mesh");
    let vertices: Vec<Vector3<f64>> = bin["geometry"]["vertices"]
        .as_array()
        .unwrap()
        .iter()
        .map(vec3)
        .collect();
    assert_eq!(
        vertices,
        vec![
            Vector3::zeros(),
            Vector3::new(0.2, 0.0, 0.0),
            Vector3::new(0.0, 0.2, 0.0),
            Vector3::new(0.0, 0.0, 0.2)
        ]
    );
    assert_eq!(
        bin["geometry"]["triangles"],
        serde_json::json!([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    );
    assert_close(&pose(&bin["pose"]), &at([0.5, -0.6, -0.15]), "bin");

    // The cloud: the PLY's points, each a sphere of the radius given.
    let scan = body(&view, "obstacle scan");
    assert_eq!(scan["geometry"]["type"], "points");
    assert_eq!(f(&scan["geometry"]["radius"]), 0.01);
    assert_eq!(scan["geometry"]["total"], 3);
    let points: Vec<Vector3<f64>> = scan["geometry"]["points"]
        .as_array()
        .unwrap()
        .iter()
        .map(vec3)
        .collect();
    let placed: Vec<Vector3<f64>> = points
        .iter()
        .map(|p| pose(&scan["pose"]) * Point3::from(*p))
        .map(|p| p.coords)
        .collect();
    for (got, want) in placed
        .iter()
        .zip([[1.3, 0.5, 0.2], [1.3, 0.55, 0.2], [1.3, 0.6, 0.25]])
    {
        assert!(
            (got - Vector3::from(want)).norm() < 1e-4,
            "{got} vs {want:?}"
        );
    }
    assert_eq!(view["world"]["approach_samples"], 3);
    assert_eq!(view["world"]["retreat_samples"], 3);
}

#[test]
fn an_infinite_table_is_a_half_space_at_its_height() {
    let dir = tempfile::tempdir().unwrap();
    let yaml = SCENE_TASK
        .replace(
            "table: { height: -0.15, size: [1.2, 1.6], centre: [0.8, 0.1] }",
            "table: { height: -0.15 }",
        )
        .replace("edge: { count: 11 }", "edge: { count: 2 }");
    let task = load(dir.path(), &yaml);
    let view = scene_json(&task, &select(&task, &|| {}).unwrap());
    let table = body(&view, "table");
    assert_eq!(table["geometry"]["type"], "half_space");
    assert_eq!(f(&table["geometry"]["height"]), -0.15);
    assert_close(&pose(&table["pose"]), &Isometry3::identity(), "table");
}

#[test]
fn the_arm_shapes_ride_on_the_link_frames_of_the_whole_motion() {
    let dir = tempfile::tempdir().unwrap();
    let task = load(dir.path(), SCENE_TASK);
    let selection = select(&task, &|| {}).unwrap();
    let view = scene_json(&task, &selection);
    let setup = &task.arms()[0];
    let chain = &setup.chain;
    let arm = &view["arms"][0];
    let names: Vec<String> = arm["bodies"]["links"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_str().unwrap().to_string())
        .collect();

    // Every link shape of the robot on this chain, at its pose on its link, as the robot
    // source describes it; then the gripper's shapes on the tip link, behind the tool.
    let model = RobotSource::builtin("baxter").load().unwrap();
    let shapes = robot_link_shapes(&model).unwrap();
    let mut expected: Vec<(String, String, Isometry3<f64>)> = shapes
        .iter()
        .filter(|s| chain.link_index(&s.link).is_some())
        .map(|s| {
            (
                format!("link {}", s.link),
                s.link.clone(),
                s.link_from_shape,
            )
        })
        .collect();
    let q0 = chain.mid_configuration();
    let tip = chain.link_names().len() - 1;
    let tip_from_tool: Isometry3<f64> = nalgebra::convert(
        chain.link_frames(&q0).unwrap()[tip].inverse() * chain.pose(&q0).unwrap(),
    );
    for (name, tool_from_shape, _) in Gripper::baxter().hand_shapes() {
        expected.push((
            format!("hand {name}"),
            chain.link_names()[tip].clone(),
            tip_from_tool * tool_from_shape,
        ));
    }
    let bodies = arm["bodies"]["bodies"].as_array().unwrap();
    assert_eq!(bodies.len(), expected.len());
    for (b, (name, link, link_from_body)) in bodies.iter().zip(&expected) {
        assert_eq!(b["name"], name.as_str());
        assert_eq!(&names[b["link"].as_u64().unwrap() as usize], link, "{name}");
        assert_close(&pose(&b["pose"]), link_from_body, name);
    }

    // The frames along approach, path and retreat are the chain's link frames at the joint
    // trajectories of candidates.json, placed by world_from_base.
    let records = candidates_json(&selection);
    let mut checked = 0;
    for (result, record) in arm["results"]
        .as_array()
        .unwrap()
        .iter()
        .zip(records.as_array().unwrap())
    {
        let Some(motion) = result["motion"].as_object() else {
            continue;
        };
        assert!(record["feasible"].as_bool().unwrap());
        for (frames, joints) in [
            (
                &motion["approach"]["frames"],
                &record["approach_trajectory"],
            ),
            (&motion["frames"], &record["joint_trajectory"]),
            (&motion["retreat"]["frames"], &record["retreat_trajectory"]),
        ] {
            let joints = joints.as_array().unwrap();
            assert_eq!(frames.as_array().unwrap().len(), joints.len());
            assert!(!joints.is_empty());
            for (at, q) in frames.as_array().unwrap().iter().zip(joints) {
                let q: Vec<f64> = q.as_array().unwrap().iter().map(f).collect();
                let link_frames = chain.link_frames(&q).unwrap();
                for (k, name) in names.iter().enumerate() {
                    let l = chain.link_index(name).unwrap();
                    let want = setup.world_from_base
                        * nalgebra::convert::<_, Isometry3<f64>>(link_frames[l]);
                    assert_close(&pose(&at[k]), &want, name);
                }
                checked += 1;
            }
        }
    }
    assert!(checked > 0, "a feasible candidate carries its frames");
}

/// The bodies named `name` placed in the world with the arm at `q`: the robot's shapes and the
/// gripper's from their sources, the scene's from the task, the object at `world_from_object`.
fn named_bodies(
    task: &Task,
    name: &str,
    q: &[f64],
    world_from_object: &Isometry3<f64>,
) -> Vec<(Body, Isometry3<f64>)> {
    let setup = &task.arms()[0];
    let chain = &setup.chain;
    let frames = chain.link_frames(q).unwrap();
    let placed =
        |link: usize| setup.world_from_base * nalgebra::convert::<_, Isometry3<f64>>(frames[link]);
    let mut out = Vec::new();
    let model = RobotSource::builtin("baxter").load().unwrap();
    for s in robot_link_shapes(&model).unwrap() {
        if let Some(l) = chain.link_index(&s.link) {
            if format!("link {}", s.link) == name {
                out.push((
                    Body::from_shape(name, &s.shape),
                    placed(l) * s.link_from_shape,
                ));
            }
        }
    }
    let world_from_tool =
        setup.world_from_base * nalgebra::convert::<_, Isometry3<f64>>(chain.pose(q).unwrap());
    for (finger, tool_from_shape, shape) in Gripper::baxter().hand_shapes() {
        if format!("hand {finger}") == name {
            out.push((
                Body::from_shape(name, &shape),
                world_from_tool * tool_from_shape,
            ));
        }
    }
    for (body, world_from_body) in task.collisions().unwrap().scene.bodies() {
        if body.name() == name {
            out.push((body.clone(), *world_from_body));
        }
    }
    if name == "object" {
        out.push((
            Body::from_shape("object", task.shape().unwrap()),
            *world_from_object,
        ));
    }
    out
}

#[test]
fn a_colliding_candidate_is_shown_where_its_two_bodies_collide() {
    let dir = tempfile::tempdir().unwrap();
    let task = load(dir.path(), SCENE_TASK);
    let selection = select(&task, &|| {}).unwrap();
    let view = scene_json(&task, &selection);
    let records = candidates_json(&selection);
    let margin = task.collisions().unwrap().options.margin;
    let mut shown = 0;
    for (result, record) in view["arms"][0]["results"]
        .as_array()
        .unwrap()
        .iter()
        .zip(records.as_array().unwrap())
    {
        let failure = &record["failure"];
        if failure["reason"] != "collision" {
            assert!(result["collision"].is_null());
            continue;
        }
        // Every collision of this small task is reproduced (fewer than the cap).
        let witness = &result["collision"];
        assert!(
            witness.is_object(),
            "candidate {}: no witness",
            record["id"]
        );
        assert_eq!(witness["phase"], failure["phase"]);
        assert_eq!(witness["sample"], failure["sample"]);
        assert_eq!(witness["bodies"], failure["bodies"]);
        let q: Vec<f64> = witness["q"].as_array().unwrap().iter().map(f).collect();
        let world_from_object = pose(&witness["object"]);
        let names = [
            witness["bodies"][0].as_str().unwrap(),
            witness["bodies"][1].as_str().unwrap(),
        ];
        let a = named_bodies(&task, names[0], &q, &world_from_object);
        let b = named_bodies(&task, names[1], &q, &world_from_object);
        assert!(!a.is_empty() && !b.is_empty(), "{names:?}");
        let closest = a
            .iter()
            .flat_map(|(x, px)| b.iter().map(move |(y, py)| distance(x, px, y, py)))
            .fold(f64::INFINITY, f64::min);
        // Closer than the margin they must keep (with 1e-5 m for the rounding of q and poses).
        assert!(
            closest < margin + 1e-5,
            "{names:?}: {closest} m apart at the witness"
        );
        // The arm drawn there is the chain at q.
        let origins = setup_origins(&task, &q);
        let drawn: Vec<Vector3<f64>> = witness["links"]
            .as_array()
            .unwrap()
            .iter()
            .map(vec3)
            .collect();
        for (o, d) in origins.iter().zip(&drawn) {
            assert!((o - d).norm() < 2e-4);
        }
        shown += 1;
    }
    assert!(shown > 0, "the task has colliding candidates");
}

fn setup_origins(task: &Task, q: &[f64]) -> Vec<Vector3<f64>> {
    let setup = &task.arms()[0];
    setup
        .chain
        .joint_origins(q)
        .unwrap()
        .iter()
        .map(|p| (setup.world_from_base * p).coords)
        .collect()
}

#[test]
fn the_summary_counts_failures_per_reason() {
    let dir = tempfile::tempdir().unwrap();
    let task = load(dir.path(), SCENE_TASK);
    let selection = select(&task, &|| {}).unwrap();
    let summary = summary_json(&task, &selection);
    let mut counted: BTreeMap<String, u64> = BTreeMap::new();
    let mut feasible = 0;
    for record in candidates_json(&selection).as_array().unwrap() {
        match record["failure"]["reason"].as_str() {
            Some(reason) => *counted.entry(reason.to_string()).or_default() += 1,
            None => feasible += 1,
        }
    }
    let failures: BTreeMap<String, u64> =
        serde_json::from_value(summary["arms"][0]["failures"].clone()).unwrap();
    assert_eq!(failures, counted);
    assert!(failures.contains_key("collision"), "{failures:?}");
    assert_eq!(summary["arms"][0]["feasible"], feasible);
    assert!(
        summary.get("colliding_pairs").is_none(),
        "one arm: no pairs"
    );
}

#[test]
fn two_arms_in_a_scene_report_the_refused_pairs() {
    let dir = tempfile::tempdir().unwrap();
    let yaml = SCENE_TASK
        .replace("arms: left", "arms: [left, right]")
        .replace("edge: { count: 11 }", "edge: { count: 5 }");
    let task = load(dir.path(), &yaml);
    let selection = select(&task, &|| {}).unwrap();
    let summary = summary_json(&task, &selection);
    assert_eq!(summary["colliding_pairs"], selection.colliding_pairs);
    for arm in summary["arms"].as_array().unwrap() {
        let failures: u64 = arm["failures"]
            .as_object()
            .unwrap()
            .values()
            .map(|v| v.as_u64().unwrap())
            .sum();
        assert_eq!(
            failures + arm["feasible"].as_u64().unwrap(),
            arm["candidates"].as_u64().unwrap()
        );
    }
}

#[test]
fn the_report_of_a_scene_is_deterministic() {
    let dir = tempfile::tempdir().unwrap();
    let task = load(dir.path(), SCENE_TASK);
    let a = render_report(&task, &select(&task, &|| {}).unwrap(), None).unwrap();
    let b = render_report(&task, &select(&task, &|| {}).unwrap(), None).unwrap();
    assert_eq!(a, b);
    let c = serde_json::to_vec(&scene_json(&task, &select(&task, &|| {}).unwrap())).unwrap();
    let d = serde_json::to_vec(&scene_json(&task, &select(&task, &|| {}).unwrap())).unwrap();
    assert_eq!(c, d);
}

/// `candidates.json` as the CLI renders it (each record straight from its fields, in parallel)
/// is the document built as a `serde_json::Value` (whose objects are sorted maps), in
/// serde_json's pretty form, with every optional field present somewhere: a collision's
/// bodies, clearances, approach and retreat motions, the penalised index and the self-motion
/// search.
#[test]
fn candidates_json_bytes_are_the_sorted_document_with_every_field() {
    let dir = tempfile::tempdir().unwrap();
    let yaml = format!(
        "{SCENE_TASK}index: {{ joint_limit_penalty: true }}\nik: {{ redundancy: optimize }}\n"
    );
    let task = load(dir.path(), &yaml);
    let selection = select(&task, &|| {}).unwrap();
    let document = candidates_json(&selection);
    let records = document.as_array().unwrap();
    for field in [
        "approach_trajectory",
        "retreat_trajectory",
        "clearance",
        "ranked_index",
        "yoshikawa_penalized_at_grasp",
        "self_motion",
    ] {
        assert!(
            records.iter().any(|r| r.get(field).is_some()),
            "no record has {field}"
        );
    }
    assert!(records.iter().any(|r| r["failure"]["bodies"].is_array()));
    for trajectories in [
        Trajectories::All,
        Trajectories::Feasible,
        Trajectories::None,
    ] {
        let mut expected =
            serde_json::to_vec_pretty(&candidates_json_with(&selection, trajectories)).unwrap();
        expected.push(b'\n');
        let bytes = candidates_json_bytes(&selection, trajectories);
        assert!(bytes == expected, "{trajectories:?}");
    }
}
