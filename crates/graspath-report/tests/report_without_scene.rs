//! A task without a scene gives the same report as before the scene was drawn: the JSON
//! documents and the 3D view's data are byte-identical to fixtures written by the report code
//! of `main` before the scene work (commit c8efb49), for a small two-arm task in empty space.
//!
//! The oracle is that earlier code's output, kept in `tests/fixtures/no_scene/`. When the core's
//! numbers change on purpose (a different IK, new candidate families), regenerate the fixtures
//! with `GRASPATH_WRITE_FIXTURES=1 cargo test -p graspath-report --test report_without_scene`
//! from a checkout of the report code known to be right, and say so in the commit.

use graspath::select::record::Trajectories;
use graspath::select::{select, CandidateScore};
use graspath::task::{Task, TaskFile};
use graspath_report::{
    candidates_json, candidates_json_bytes, candidates_json_with, pairs_json, scene_json,
    summary_json,
};
use std::path::{Path, PathBuf};

/// The paper's two-arm pick-and-place, small: 5 candidates, 3 samples per step, not timed.
const TASK: &str = r#"
robot: { builtin: baxter }
arms: [left, right]
object:
  pose: { xyz: [0.75, 0.0, -0.10] }
  shape: { box: { size: [0.06, 0.40, 0.10] } }
candidates:
  family: { edge: { count: 5, depth: 0.02, margin: 0.02 } }
trajectory:
  samples_per_step: 3
  steps:
    - { lift: 0.2, label: pick }
    - { move: [0.0, 0.3, 0.0], label: move }
    - { place: 0.2, label: place }
# The fixtures predate timing, which adds the duration fields, the IK's limit margin, the
# default norm mu_rms (whose values the files now carry beside mu_l2) and the self-motion
# search by default.
ik: { branches: 4, limit_margin: 0, redundancy: first }
selection: { norm: l2 }
timing: false
"#;

fn fixtures() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/no_scene")
}

fn pretty(value: &serde_json::Value) -> String {
    serde_json::to_string_pretty(value).unwrap() + "\n"
}

fn compare_or_write(name: &str, text: &str) {
    let path = fixtures().join(name);
    if std::env::var_os("GRASPATH_WRITE_FIXTURES").is_some() {
        std::fs::write(&path, text).unwrap();
        return;
    }
    let expected =
        std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    assert!(
        expected == text,
        "{name} differs from the report of a task without a scene before the scene work \
         (first difference at byte {})",
        expected
            .bytes()
            .zip(text.bytes())
            .position(|(a, b)| a != b)
            .unwrap_or(expected.len().min(text.len()))
    );
}

#[test]
fn a_task_without_a_scene_reports_the_same_bytes_as_before() {
    let file = TaskFile::parse(TASK, "small.yaml", "yaml").unwrap();
    let task = Task::from_file(&file, "small.yaml", Path::new(".")).unwrap();
    assert!(task.collisions().is_none() && task.approach().is_none());
    let selection = select(&task, &|| {}).unwrap();
    assert!(!selection.pairs.is_empty(), "the task has pairs to compare");
    compare_or_write("candidates.json", &pretty(&candidates_json(&selection)));
    compare_or_write("pairs.json", &pretty(&pairs_json(&selection)));
    compare_or_write("summary.json", &pretty(&summary_json(&task, &selection)));
    compare_or_write("view.json", &pretty(&scene_json(&task, &selection)));
}

/// The CLI's `candidates.json` (records rendered in parallel) is the whole document in
/// serde_json's pretty form, for every choice of trajectories and for no candidates at all.
#[test]
fn candidates_json_bytes_are_the_pretty_document() {
    let file = TaskFile::parse(TASK, "small.yaml", "yaml").unwrap();
    let task = Task::from_file(&file, "small.yaml", Path::new(".")).unwrap();
    let mut selection = select(&task, &|| {}).unwrap();
    assert!(selection
        .arms
        .iter()
        .any(|a| a.scores.iter().any(|s| !s.feasible())));
    assert!(selection
        .arms
        .iter()
        .any(|a| a.scores.iter().any(CandidateScore::feasible)));
    for trajectories in [
        Trajectories::All,
        Trajectories::Feasible,
        Trajectories::None,
    ] {
        let bytes = candidates_json_bytes(&selection, trajectories);
        let expected = pretty(&candidates_json_with(&selection, trajectories));
        assert!(bytes == expected.as_bytes(), "{trajectories:?}");
    }
    selection.arms.clear();
    assert_eq!(
        candidates_json_bytes(&selection, Trajectories::All),
        pretty(&candidates_json(&selection)).as_bytes()
    );
}
