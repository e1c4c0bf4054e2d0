//! Placement maps: a placement's record is what `select` gives on a task file whose
//! `object.pose` is that placement (byte for byte), the map is the same at any thread count,
//! and bad grids or tasks give one clear error.

use graspath::placement::{
    placement_map, placement_map_with, FamilyParameter, GridAxis, PlacementError, PlacementGrid,
    PlacementRecord,
};
use graspath::select::select;
use graspath::task::{builder_from_file, Task, TaskFile};
use std::path::Path;

/// The paper's two-arm Pick-and-Place, small: 5 edge candidates, 3 samples per step.
fn task_yaml(pose: &str) -> String {
    format!(
        r#"
robot: {{ builtin: baxter }}
arms: [left, right]
object:
  pose: {pose}
  shape: {{ box: {{ size: [0.06, 0.40, 0.10] }} }}
candidates:
  family: {{ edge: {{ count: 5, depth: 0.02, margin: 0.02 }} }}
trajectory:
  samples_per_step: 3
  steps:
    - {{ lift: 0.2, label: pick }}
    - {{ move: [0.0, 0.3, 0.0], label: move }}
    - {{ place: 0.2, label: place }}
ik: {{ branches: 2 }}
"#
    )
}

fn parse(yaml: &str) -> TaskFile {
    TaskFile::parse(yaml, "task.yaml", "yaml").unwrap()
}

fn grid() -> PlacementGrid {
    PlacementGrid {
        x: GridAxis::new(0.6, 0.85, 3, "--x").unwrap(),
        y: GridAxis::new(-0.15, 0.25, 2, "--y").unwrap(),
        z: Some(GridAxis::new(-0.1, 0.05, 2, "--z").unwrap()),
        yaw: None,
    }
}

fn bytes(record: &PlacementRecord) -> Vec<u8> {
    serde_json::to_vec(record).unwrap()
}

#[test]
fn each_placement_equals_select_on_the_task_file_with_that_pose() {
    let file = parse(&task_yaml("{ xyz: [0.75, 0.0, -0.10] }"));
    let builder = builder_from_file(&file, "task.yaml", Path::new(".")).unwrap();
    let candidates = builder
        .clone()
        .build()
        .unwrap()
        .candidates()
        .held()
        .expect("held candidates")
        .to_vec();
    let parameter = FamilyParameter::from_task_file(&file, &candidates);
    assert_eq!(parameter.as_ref().unwrap().values.len(), 5);
    let grid = grid();
    let map = placement_map(&builder, &grid, parameter.clone(), &|| {}).unwrap();
    assert_eq!(map.records.len(), 12);
    let start = builder.object_start().unwrap();
    let placements = grid.placements(&start).unwrap();
    let mut selected_somewhere = false;
    for (placement, record) in placements.iter().zip(&map.records) {
        // The oracle: the task file rewritten with this object pose, loaded and selected the
        // ordinary way. `{:?}` prints each coordinate so that it parses back to the same f64.
        let t = placement.world_from_object.translation.vector;
        let yaml = task_yaml(&format!("{{ xyz: [{:?}, {:?}, {:?}] }}", t.x, t.y, t.z));
        let task = Task::from_file(&parse(&yaml), "task.yaml", Path::new(".")).unwrap();
        assert_eq!(
            task.path().samples[0].world_from_object,
            placement.world_from_object
        );
        let selection = select(&task, &|| {}).unwrap();
        let expected =
            PlacementRecord::from_selection(&task, &selection, placement, parameter.as_ref());
        assert_eq!(
            bytes(record),
            bytes(&expected),
            "placement {:?}",
            placement.index
        );
        // And the record says what the selection says.
        for (arm, result) in record.arms.iter().zip(&selection.arms) {
            assert_eq!(arm.feasible, result.feasible_count());
            assert_eq!(
                arm.best.as_ref().map(|b| b.id),
                result.best().map(|i| result.scores[i].candidate.id)
            );
            let l2: Vec<f64> = result
                .scores
                .iter()
                .filter(|s| s.feasible())
                .map(|s| s.norms.unwrap().l2)
                .collect();
            assert_eq!(arm.mu_l2_max, l2.iter().copied().reduce(f64::max));
            assert_eq!(arm.mu_l2_min, l2.iter().copied().reduce(f64::min));
            selected_somewhere |= arm.best.is_some();
        }
    }
    assert!(
        selected_somewhere,
        "the grid should reach the object somewhere"
    );
}

#[test]
fn the_map_is_the_same_at_any_thread_count() {
    let file = parse(&task_yaml("{ xyz: [0.75, 0.0, -0.10] }"));
    let builder = builder_from_file(&file, "task.yaml", Path::new(".")).unwrap();
    let mut grid = grid();
    grid.yaw =
        Some(GridAxis::new(-30f64.to_radians(), 30f64.to_radians(), 2, "--yaw-deg").unwrap());
    let run = |threads: usize| -> Vec<u8> {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let map = pool.install(|| placement_map(&builder, &grid, None, &|| {}).unwrap());
        serde_json::to_vec(&map.records).unwrap()
    };
    let one = run(1);
    assert_eq!(one, run(2));
    assert_eq!(one, run(5));
}

#[test]
fn placement_map_with_hands_each_placement_in_grid_order() {
    let file = parse(&task_yaml("{ xyz: [0.75, 0.0, -0.10] }"));
    let builder = builder_from_file(&file, "task.yaml", Path::new(".")).unwrap();
    let grid = grid();
    let plain = placement_map(&builder, &grid, None, &|| {}).unwrap();
    let (map, seen) = placement_map_with(&builder, &grid, None, &|| {}, &|task, selection, at| {
        let feasible: Vec<usize> = selection
            .arms
            .iter()
            .map(graspath::select::ArmResult::feasible_count)
            .collect();
        (at.index, task.path().samples[0].world_from_object, feasible)
    })
    .unwrap();
    // The records are those of the plain map; the inspected values follow the grid's order and
    // see each placement's own task (its start pose) and selection (its feasible counts).
    assert_eq!(
        serde_json::to_vec(&map.records).unwrap(),
        serde_json::to_vec(&plain.records).unwrap()
    );
    let placements = grid.placements(&builder.object_start().unwrap()).unwrap();
    assert_eq!(seen.len(), placements.len());
    for ((index, start, feasible), (placement, record)) in
        seen.iter().zip(placements.iter().zip(&map.records))
    {
        assert_eq!(*index, placement.index);
        assert_eq!(*start, placement.world_from_object);
        let from_record: Vec<usize> = record.arms.iter().map(|a| a.feasible).collect();
        assert_eq!(*feasible, from_record);
    }
}

#[test]
fn a_yawed_placement_turns_the_start_pose_and_the_relative_steps_follow() {
    // Oracle: the sampled path of the yawed task equals the unyawed path's relative
    // translations (world-frame steps) from the turned start pose.
    let file = parse(&task_yaml("{ xyz: [0.75, 0.0, -0.10] }"));
    let builder = builder_from_file(&file, "task.yaml", Path::new(".")).unwrap();
    let yaw = 40f64.to_radians();
    let grid = PlacementGrid {
        x: GridAxis::single(0.7, "--x").unwrap(),
        y: GridAxis::single(0.1, "--y").unwrap(),
        z: None,
        yaw: Some(GridAxis::single(yaw, "--yaw-deg").unwrap()),
    };
    let p = grid.placements(&builder.object_start().unwrap()).unwrap()[0];
    let task = builder
        .with_object_start(p.world_from_object)
        .unwrap()
        .build()
        .unwrap();
    let first = task.path().samples[0].world_from_object;
    assert!((first.rotation.angle() - yaw).abs() < 1e-12);
    assert!((first.translation.vector - nalgebra::Vector3::new(0.7, 0.1, -0.1)).norm() < 1e-15);
    let last = task.path().samples.last().unwrap().world_from_object;
    // lift 0.2, move +0.3 y, place 0.2: a net move of 0.3 m along world y, no turn.
    let moved = last.translation.vector - first.translation.vector;
    assert!((moved - nalgebra::Vector3::new(0.0, 0.3, 0.0)).norm() < 1e-12);
    assert!(last.rotation.angle_to(&first.rotation) < 1e-12);
}

#[test]
fn bad_maps_are_one_clear_error() {
    let file = parse(&task_yaml("{ xyz: [0.75, 0.0, -0.10] }"));
    let builder = builder_from_file(&file, "task.yaml", Path::new(".")).unwrap();
    // A path given already sampled has no start pose to move.
    let sampled = builder.clone().build().unwrap().path().clone();
    let fixed = builder.clone().object_path(sampled);
    match placement_map(&fixed, &grid(), None, &|| {}) {
        Err(PlacementError::Task(e)) => assert_eq!(e.field, "trajectory"),
        other => panic!("expected a trajectory error, got {other:?}"),
    }
    // The whole map's work is bounded by the task's limit.
    let mut limits = graspath::task::Limits::default();
    let one = builder.clone().build().unwrap().work();
    limits.max_work = one * 5;
    let small = builder.clone().limits(limits);
    match placement_map(&small, &grid(), None, &|| {}) {
        Err(e @ PlacementError::TooMuchWork { .. }) => {
            assert!(e.to_string().contains("limits.max_work"), "{e}");
        }
        other => panic!("expected TooMuchWork, got {other:?}"),
    }
    // An axis: named by its flag.
    let e = GridAxis::parse("0.5:0.9", "--x").unwrap_err();
    assert!(e.to_string().starts_with("--x: "), "{e}");
}
