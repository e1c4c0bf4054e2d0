//! Tasks in a scene, as a new user writes them: the object on a table, under it, too wide for
//! the gripper; and the errors a scene section can give.

use graspath::failure::{FailureReason, Phase};
use graspath::select::select;
use graspath::task::Task;
use std::path::PathBuf;

/// The paper's pick-and-place (Baxter's left arm, the cuboid's top edge) with `extra` YAML
/// appended and the object at height `z` (its centre, m).
fn task_file(dir: &tempfile::TempDir, z: f64, shape: &str, family: &str, extra: &str) -> PathBuf {
    let text = format!(
        "robot: {{ builtin: baxter }}\n\
         arms: left\n\
         object:\n  pose: {{ xyz: [0.75, 0.0, {z}] }}\n  shape: {shape}\n\
         candidates:\n  family: {family}\n\
         trajectory:\n  samples_per_step: 5\n  steps:\n    - {{ lift: 0.2 }}\n    - {{ move: [0.0, 0.3, 0.0] }}\n    - {{ place: 0.2 }}\n\
         {extra}"
    );
    let path = dir.path().join("task.yaml");
    std::fs::write(&path, text).unwrap();
    path
}

const CUBOID: &str = "{ box: { size: [0.06, 0.40, 0.10] } }";
const EDGE: &str = "{ edge: { count: 11 } }";

#[test]
fn an_object_standing_on_the_table_can_be_picked_and_the_table_is_kept_clear() {
    let dir = tempfile::tempdir().unwrap();
    // The box's bottom (z = −0.15) rests on the table top.
    let path = task_file(
        &dir,
        -0.10,
        CUBOID,
        EDGE,
        "scene: { table: { height: -0.15 } }\n\
         gripper: { builtin: baxter }\n\
         approach: { distance: 0.10, samples: 5 }\n\
         retreat: { distance: 0.10, samples: 5 }\n",
    );
    let task = Task::load(&path).unwrap();
    let selection = select(&task, &|| {});
    let arm = &selection.arms[0];
    assert!(
        arm.feasible_count() > 0,
        "{:?}",
        arm.scores.iter().map(|s| &s.failure).collect::<Vec<_>>()
    );
    for s in arm.scores.iter().filter(|s| s.feasible()) {
        // The approach and retreat were solved, and the robot keeps the margin.
        assert_eq!(s.approach.len(), 5);
        assert_eq!(s.retreat.len(), 5);
        let clearance = s.clearance.expect("a scene gives a clearance");
        assert!(clearance >= 0.01, "clearance {clearance}");
    }
    // The object resting on the table is not a collision at pick or place.
    for s in &arm.scores {
        if let Some(f) = &s.failure {
            if let Some(bodies) = &f.bodies {
                assert!(
                    !(bodies.contains(&"object".to_string())
                        && bodies.contains(&"table".to_string())),
                    "{f}"
                );
            }
        }
    }
}

#[test]
fn a_box_inside_the_table_collides_with_it_for_every_candidate() {
    let dir = tempfile::tempdir().unwrap();
    // The box where the arm reaches it in empty space, the table top 35 cm above its centre.
    let free = select(
        &Task::load(&task_file(&dir, -0.10, CUBOID, EDGE, "")).unwrap(),
        &|| {},
    );
    let reachable: Vec<usize> = (0..free.arms[0].scores.len())
        .filter(|&i| free.arms[0].scores[i].feasible())
        .collect();
    assert!(!reachable.is_empty());
    let path = task_file(
        &dir,
        -0.10,
        CUBOID,
        EDGE,
        "scene: { table: { height: 0.25 } }\n",
    );
    let selection = select(&Task::load(&path).unwrap(), &|| {});
    let arm = &selection.arms[0];
    assert_eq!(arm.feasible_count(), 0);
    for i in reachable {
        let f = arm.scores[i].failure.as_ref().unwrap();
        assert_eq!(f.reason, FailureReason::Collision, "{f}");
        let bodies = f.bodies.as_ref().unwrap();
        assert!(bodies.iter().any(|b| b == "table"), "{f}");
    }
}

#[test]
fn a_box_wider_than_the_opening_is_rejected_for_gripper_width() {
    let dir = tempfile::tempdir().unwrap();
    let path = task_file(
        &dir,
        -0.10,
        "{ box: { size: [0.5, 0.5, 0.1] } }",
        "{ faces: { count: 20 } }",
        "gripper: { opening: 0.08 }\n",
    );
    let task = Task::load(&path).unwrap();
    let selection = select(&task, &|| {});
    for s in &selection.arms[0].scores {
        let f = s.failure.as_ref().expect("no grasp fits");
        assert_eq!(f.reason, FailureReason::GripperWidth, "{f}");
        assert_eq!((f.phase, f.sample), (Phase::Path, 0));
    }
    // The same box 6 cm wide across the fingers fits.
    let path = task_file(&dir, -0.10, CUBOID, EDGE, "gripper: { opening: 0.08 }\n");
    let selection = select(&Task::load(&path).unwrap(), &|| {});
    assert!(selection.arms[0].scores.iter().all(|s| s
        .failure
        .as_ref()
        .is_none_or(|f| f.reason != FailureReason::GripperWidth)));
}

#[test]
fn scene_sections_that_cannot_be_used_name_their_field() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("broken.stl"), b"solid nothing\nendsolid\n").unwrap();
    let cases = [
        (
            "scene: { obstacles: [ { name: c, cone: { radius: 0.1 } } ] }\n",
            "cone",
        ),
        (
            "scene: { obstacles: [ { name: m, mesh: broken.stl } ] }\n",
            "scene.obstacles[0].mesh",
        ),
        (
            "scene: { obstacles: [ { name: m, mesh: missing.stl } ] }\n",
            "scene.obstacles[0].mesh",
        ),
        (
            "scene: { obstacles: [ { name: two, sphere: { radius: 0.1 }, capsule: { radius: 0.1, length: 0.2 } } ] }\n",
            "scene.obstacles[0]",
        ),
        (
            "scene: {}\ncollision: { disable: [[left_wrist, no_such_link]] }\n",
            "collision.disable[0]",
        ),
        (
            "scene: { table: { height: 0.0, size: [0.0, 1.0] } }\n",
            "table.size[0]",
        ),
        ("approach: { distance: -0.1 }\n", "approach.distance"),
        ("gripper: { opening: 0 }\n", "gripper.opening"),
        ("collision: { margin: 0.01 }\n", "collision"),
    ];
    for (extra, field) in cases {
        let path = task_file(&dir, -0.10, CUBOID, EDGE, extra);
        let error = Task::load(&path).expect_err(extra).to_string();
        assert!(error.contains(field), "{extra}: {error}");
        assert!(error.contains("task.yaml"), "{extra}: {error}");
    }
}
