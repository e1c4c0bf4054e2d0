//! Plausibility warnings on whole task files: none on any shipped example (no false alarm on
//! the tasks users copy), and the world at the start — an object inside the table or upside
//! down — named with the field, the task still built and scored as written.

use graspath::task::{Task, TaskWarning};
use std::path::{Path, PathBuf};

fn examples() -> Vec<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples");
    let mut out = Vec::new();
    for folder in [root.clone(), root.join("scene")] {
        for entry in std::fs::read_dir(folder).unwrap() {
            let path = entry.unwrap().path();
            if path.extension().is_some_and(|e| e == "yaml") {
                out.push(path);
            }
        }
    }
    out.sort();
    out
}

#[test]
fn no_shipped_example_gets_a_warning() {
    let examples = examples();
    assert!(examples.len() >= 10);
    for path in examples {
        let task = Task::load(&path).unwrap();
        assert!(
            task.warnings().is_empty(),
            "{}: {:?}",
            path.display(),
            task.warnings()
        );
    }
}

fn on_table(pose: &str) -> Vec<TaskWarning> {
    let text = format!(
        "robot: {{ builtin: baxter }}\narms: left\n\
         object: {{ pose: {pose}, shape: {{ box: {{ size: [0.06, 0.40, 0.10] }} }} }}\n\
         candidates: {{ family: {{ edge: {{ count: 3 }} }} }}\n\
         trajectory: {{ samples_per_step: 2, steps: [ {{ lift: 0.2 }} ] }}\n\
         scene: {{ table: {{ height: -0.15 }} }}\n"
    );
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("task.yaml");
    std::fs::write(&path, text).unwrap();
    Task::load(&path).unwrap().warnings().to_vec()
}

#[test]
fn an_object_inside_the_table_or_upside_down_at_the_start_is_named() {
    // Resting on the top (its bottom at z = −0.15) and 0.5 mm into it: no warning.
    assert!(on_table("{ xyz: [0.75, 0, -0.10] }").is_empty());
    assert!(on_table("{ xyz: [0.75, 0, -0.1005] }").is_empty());
    // Its centre on the table's top: half of it (5 cm) inside.
    let inside = on_table("{ xyz: [0.75, 0, -0.15] }");
    assert_eq!(inside.len(), 1, "{inside:?}");
    assert_eq!(inside[0].field, "object.pose");
    assert!(
        inside[0].message.contains("50.0 mm inside the table"),
        "{}",
        inside[0].message
    );
    // Turned over about x: upside down, resting on its top face.
    let over = on_table("{ xyz: [0.75, 0, -0.10], rpy_deg: [180, 0, 0] }");
    assert_eq!(over.len(), 1, "{over:?}");
    assert!(
        over[0].message.contains("upside down"),
        "{}",
        over[0].message
    );
    // Lying on its side is deliberate enough: 90° is not upside down.
    assert!(on_table("{ xyz: [0.75, 0, 0.05], rpy_deg: [90, 0, 0] }").is_empty());
}
