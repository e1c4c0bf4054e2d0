//! An object that starts or ends its path inside an obstacle is a task error naming the
//! obstacle, the depth and the pose — not a collision of every candidate; an object resting
//! on an obstacle, or near one, is not.

use graspath::task::Task;

/// The paper's cuboid (0.06 × 0.40 × 0.10 m at (0.75, 0, −0.10)), lifted, moved +0.3 m in y and
/// placed, among `obstacles` (YAML list).
fn task(dir: &tempfile::TempDir, obstacles: &str) -> Result<Task, String> {
    let text = format!(
        "robot: {{ builtin: baxter }}\n\
         arms: left\n\
         object:\n  pose: {{ xyz: [0.75, 0.0, -0.10] }}\n  shape: {{ box: {{ size: [0.06, 0.40, 0.10] }} }}\n\
         candidates:\n  family: {{ edge: {{ count: 5 }} }}\n\
         trajectory:\n  samples_per_step: 3\n  steps:\n    - {{ lift: 0.2 }}\n    - {{ move: [0.0, 0.3, 0.0] }}\n    - {{ place: 0.2 }}\n\
         scene: {{ obstacles: {obstacles} }}\n"
    );
    let path = dir.path().join("task.yaml");
    std::fs::write(&path, text).unwrap();
    Task::load(&path).map_err(|e| e.to_string())
}

#[test]
fn an_object_inside_an_obstacle_at_the_start_or_the_end_is_a_task_error() {
    let dir = tempfile::tempdir().unwrap();
    // A ball of radius 0.05 m centred 0.02 m off the box's side face (x = 0.78): it reaches
    // 0.03 m into the box (oracle: the sphere–box distance in closed form).
    let start = task(
        &dir,
        "[ { name: ball, sphere: { radius: 0.05 }, pose: { xyz: [0.80, 0.0, -0.10] } } ]",
    )
    .expect_err("refused");
    assert!(start.contains("object.pose"), "{start}");
    assert!(
        start.contains("start") && start.contains("obstacle ball") && start.contains("by 30.0 mm"),
        "{start}"
    );
    assert!(start.contains("(0.750, 0.000, -0.100)"), "{start}");
    // The same ball where the object is placed, at y = 0.3.
    let end = task(
        &dir,
        "[ { name: ball, sphere: { radius: 0.05 }, pose: { xyz: [0.80, 0.3, -0.10] } } ]",
    )
    .expect_err("refused");
    assert!(end.contains("trajectory"), "{end}");
    assert!(
        end.contains("end") && end.contains("obstacle ball") && end.contains("by 30.0 mm"),
        "{end}"
    );
    assert!(end.contains("(0.750, 0.300, -0.100)"), "{end}");
}

#[test]
fn an_object_resting_on_or_near_an_obstacle_is_accepted() {
    let dir = tempfile::tempdir().unwrap();
    // A board whose top is the box's bottom (z = −0.15): resting, depth 0.
    task(
        &dir,
        "[ { name: board, box: { size: [3.0, 3.0, 0.2] }, pose: { xyz: [0.75, 0.0, -0.25] } } ]",
    )
    .expect("resting is allowed");
    // A ball 1 cm clear of the box's side face.
    task(
        &dir,
        "[ { name: ball, sphere: { radius: 0.05 }, pose: { xyz: [0.84, 0.0, -0.10] } } ]",
    )
    .expect("clear");
    // 0.5 mm into the side face: within the default touch tolerance of 1 mm.
    task(
        &dir,
        "[ { name: ball, sphere: { radius: 0.05 }, pose: { xyz: [0.8295, 0.0, -0.10] } } ]",
    )
    .expect("a touch");
}
