//! A task built in code and the same task read from its YAML file give byte-identical results
//! (the Python leg of this check is `test_array_task_equals_the_file` in the pytest suite).

use graspath::geometry::shape::Shape;
use graspath::grasp::edge_family;
use graspath::manipulability::{JacobianRows, Norm};
use graspath::robot::builtin::{baxter, Arm};
use graspath::select::select;
use graspath::task::{Redundancy, Sampling, Step, Task, TimedStep};
use graspath_report::{candidates_json, pairs_json, summary_json};
use nalgebra::{Isometry3, Vector3};
use std::path::PathBuf;

fn example(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples")
        .join(name)
}

/// `examples/pick_and_place_both.yaml`, written in code.
fn pick_and_place_in_code(name: &str) -> Task {
    let shape = Shape::cuboid([0.06, 0.40, 0.10]).unwrap();
    let step =
        |label: &str, v: [f64; 3]| TimedStep::new(label, Step::translation(Vector3::from(v)));
    Task::builder(name)
        .robot_name("baxter")
        .arm("left", baxter(Arm::Left), Isometry3::identity())
        .arm("right", baxter(Arm::Right), Isometry3::identity())
        .shape(shape.clone())
        .candidates(edge_family(&shape, 21, 0.02, 0.02).unwrap())
        .object_motion(
            Isometry3::translation(0.75, 0.0, -0.10),
            vec![
                step("pick", [0.0, 0.0, 0.2]),
                step("move", [0.0, 0.3, 0.0]),
                step("place", [0.0, 0.0, -0.2]),
            ],
            Sampling::PerStep(10),
        )
        .rows(JacobianRows::Twist { length_scale: 1.0 })
        .norm(Norm::L2)
        .redundancy(Redundancy::BestBranch)
        .ik_limit_margin(0.0)
        .ik_branches(8)
        .grasp_ik_iterations(2000)
        .build()
        .unwrap()
}

#[test]
fn a_task_built_in_code_equals_its_task_file_byte_for_byte() {
    let path = example("pick_and_place_both.yaml");
    let from_file = Task::load(&path).unwrap();
    let in_code = pick_and_place_in_code(&path.display().to_string());
    let (a, b) = (
        select(&from_file, &|| {}).unwrap(),
        select(&in_code, &|| {}).unwrap(),
    );
    let bytes = |v: serde_json::Value| serde_json::to_vec_pretty(&v).unwrap();
    assert_eq!(
        bytes(candidates_json(&a)),
        bytes(candidates_json(&b)),
        "candidates.json"
    );
    assert_eq!(bytes(pairs_json(&a)), bytes(pairs_json(&b)), "pairs.json");
    assert_eq!(
        bytes(summary_json(&from_file, &a)),
        bytes(summary_json(&in_code, &b)),
        "summary.json"
    );
    assert!(!a.pairs.is_empty(), "the task has pairs to compare");
}

#[test]
fn builder_defaults_are_the_task_file_defaults() {
    // A file that sets nothing optional and a builder that sets nothing optional agree on
    // every setting (the grasp IK budget used to differ: 200 from files, 1000 in code).
    let yaml = r#"
robot: { builtin: baxter }
object: { pose: { xyz: [0.75, 0.0, -0.10] }, shape: { box: { size: [0.06, 0.40, 0.10] } } }
candidates: { family: { edge: { count: 3 } } }
trajectory: { steps: [ { lift: 0.2 } ] }
"#;
    let file = graspath::task::TaskFile::parse(yaml, "t.yaml", "yaml").unwrap();
    let from_file = Task::from_file(&file, "t.yaml", std::path::Path::new(".")).unwrap();
    let shape = Shape::cuboid([0.06, 0.40, 0.10]).unwrap();
    let in_code = Task::builder("t.yaml")
        .arm("left", baxter(Arm::Left), Isometry3::identity())
        .shape(shape.clone())
        .candidates(edge_family(&shape, 3, 0.02, 0.02).unwrap())
        .object_motion(
            Isometry3::translation(0.75, 0.0, -0.10),
            vec![TimedStep::new(
                "lift",
                Step::translation(Vector3::new(0.0, 0.0, 0.2)),
            )],
            Sampling::PerStep(10),
        )
        .build()
        .unwrap();
    assert_eq!(from_file.ik(), in_code.ik());
    assert_eq!(from_file.selection(), in_code.selection());
    assert_eq!(from_file.rows(), in_code.rows());
    assert_eq!(from_file.limits(), in_code.limits());
    assert_eq!(from_file.redundancy(), in_code.redundancy());
    assert_eq!(from_file.path(), in_code.path());
}
