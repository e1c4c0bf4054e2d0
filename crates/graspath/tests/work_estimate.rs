//! The work estimate covers what costs (scoring, the scene, the two-arm pair search) and the
//! memory of a selection held whole is bounded: each part grows as the quantity it counts, a
//! task over a limit is refused before any work with the part named, and the memory estimate
//! bounds what a selection really holds.

use graspath::select::select;
use graspath::task::{Task, WorkEstimate};
use std::path::PathBuf;

fn task(text: &str) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("task.yaml");
    std::fs::write(&path, text).unwrap();
    (dir, path)
}

fn two_arms(count: usize, extra: &str) -> String {
    format!(
        "robot: {{ builtin: baxter }}\narms: both\n\
         object: {{ pose: {{ xyz: [0.75, 0, -0.10] }}, shape: {{ box: {{ size: [0.06, 0.40, 0.10] }} }} }}\n\
         candidates: {{ family: {{ faces: {{ count: {count}, exclude: [bottom] }} }} }}\n\
         trajectory: {{ samples: 5, steps: [ {{ lift: 0.2 }} ] }}\ntiming: false\n{extra}"
    )
}

fn scene(obstacles: usize, extra: &str) -> String {
    let mut text = format!(
        "robot: {{ builtin: baxter }}\narms: left\n\
         object: {{ pose: {{ xyz: [0.70, 0.25, -0.05] }}, shape: {{ box: {{ size: [0.06, 0.06, 0.20] }} }} }}\n\
         candidates: {{ family: {{ faces: {{ count: 40, exclude: [bottom] }} }} }}\n\
         trajectory: {{ samples: 10, steps: [ {{ lift: 0.2 }} ] }}\ntiming: false\n{extra}\
         scene:\n  table: {{ height: -0.15 }}\n"
    );
    if obstacles > 0 {
        text.push_str("  obstacles:\n");
        for k in 0..obstacles {
            text.push_str(&format!(
                "    - {{ name: o{k}, box: {{ size: [0.005, 0.005, 0.005] }}, pose: {{ xyz: [{}, 0.5, -0.6] }} }}\n",
                0.1 + 0.01 * k as f64
            ));
        }
    }
    text
}

/// The error of loading the task at `path` (which must be refused).
fn refusal(path: &std::path::Path) -> String {
    match Task::load(path) {
        Ok(_) => panic!("{} was not refused", path.display()),
        Err(e) => e.to_string(),
    }
}

fn estimate(text: &str) -> WorkEstimate {
    let (_dir, path) = task(text);
    Task::load(&path).unwrap().work_estimate()
}

#[test]
fn the_pair_part_grows_with_the_square_of_the_candidates_and_one_arm_has_none() {
    let small = estimate(&two_arms(100, ""));
    let large = estimate(&two_arms(400, ""));
    assert!(small.pairs > 0);
    // The candidate count is what the family gives; the pair part is its square / 4.
    let count = |text: &str| {
        let (_dir, path) = task(text);
        Task::load(&path).unwrap().candidate_count() as u64
    };
    let (n_small, n_large) = (count(&two_arms(100, "")), count(&two_arms(400, "")));
    assert_eq!(
        small.pairs,
        n_small * n_small / WorkEstimate::PAIR_VISITS_PER_EVALUATION
    );
    assert_eq!(
        large.pairs,
        n_large * n_large / WorkEstimate::PAIR_VISITS_PER_EVALUATION
    );
    assert_eq!(small.collisions, 0);
    let one = estimate(&scene(0, "").replace("scene:\n  table: { height: -0.15 }\n", ""));
    assert_eq!((one.pairs, one.collisions), (0, 0));
}

#[test]
fn the_scene_part_grows_with_the_scene_bodies() {
    let table = estimate(&scene(0, ""));
    let many = estimate(&scene(99, ""));
    assert!(table.collisions > 0);
    // The table is one body; 99 obstacles make 100.
    assert_eq!(many.collisions, table.collisions * 100);
    assert_eq!(many.scoring, table.scoring);
}

#[test]
fn a_task_over_the_work_limit_is_refused_with_the_part_that_costs() {
    let pairs = two_arms(20000, "limits: { max_work: 100000000 }\n");
    let (_dir, path) = task(&pairs);
    let message = refusal(&path);
    assert!(
        message.contains("limits.max_work") && message.contains("pairs"),
        "{message}"
    );
    let obstacles = scene(500, "limits: { max_work: 1000000 }\n");
    let (_dir, path) = task(&obstacles);
    let message = refusal(&path);
    assert!(
        message.contains("limits.max_work") && message.contains("501 scene bodies"),
        "{message}"
    );
}

/// The estimate bounds the joint values a selection holds, and the check refuses a selection
/// over the limit with the way out.
#[test]
fn the_memory_estimate_bounds_the_selection_and_its_limit_is_checked() {
    let text = scene(0, "approach: { distance: 0.1, samples: 3 }\n");
    let (_dir, path) = task(&text);
    let loaded = Task::load(&path).unwrap();
    let selection = select(&loaded, &|| ()).unwrap();
    let held: usize = selection.arms[0]
        .scores
        .iter()
        .map(|s| {
            (s.approach.len() + s.joint_trajectory.len() + s.retreat.len())
                * (24 + 8 * loaded.arms()[0].chain.dof())
                + (s.m_t.len() * 16)
                + s.limit_distance.len() * 8
        })
        .sum();
    assert!(held > 0);
    assert!(loaded.selection_memory() >= held as u64);
    // Within a small factor: an estimate, not a guess.
    assert!(loaded.selection_memory() <= 4 * held as u64 + 1024 * 40);
    loaded.check_selection_memory().unwrap();
    let tight = task(&scene(0, "limits: { max_memory_mib: 0 }\n"));
    let message = Task::load(&tight.1)
        .unwrap()
        .check_selection_memory()
        .unwrap_err()
        .to_string();
    assert!(
        message.contains("limits.max_memory_mib") && message.contains("JSON Lines or Parquet"),
        "{message}"
    );
}

/// The self-motion search and the timing are parts of their own, counted per sample, and
/// nothing when a task turns them off.
#[test]
fn the_self_motion_search_and_the_timing_have_their_parts() {
    let base = scene(0, "").replace("timing: false\n", "");
    let optimised = estimate(&base);
    let first = estimate(&format!("{base}ik: {{ redundancy: first }}\n"));
    let untimed = estimate(&format!("{base}timing: false\n"));
    // One arm, 40-odd candidates, 11 samples (the initial pose and 10).
    let (_dir, path) = task(&base);
    let loaded = Task::load(&path).unwrap();
    let per_sample = loaded.candidate_count() as u64 * loaded.path().samples.len() as u64;
    assert_eq!(
        optimised.self_motion,
        per_sample * WorkEstimate::SELF_MOTION_EVALUATIONS_PER_SAMPLE
    );
    assert_eq!(first.self_motion, 0);
    let timing = loaded.timing().expect("timed by default");
    let per_point = if timing.torque_limits {
        WorkEstimate::TIMING_EVALUATIONS_PER_TORQUE_POINT
    } else {
        1
    };
    assert_eq!(
        optimised.timing,
        per_sample * timing.subdivisions as u64 * per_point
    );
    assert_eq!(untimed.timing, 0);
    assert_eq!(
        optimised.total(),
        optimised.scoring + optimised.self_motion + optimised.timing + optimised.collisions
    );
    let over = format!("{base}limits: {{ max_work: 100000 }}\n");
    let (_dir, path) = task(&over);
    let message = refusal(&path);
    assert!(message.contains("self-motion search"), "{message}");
}
