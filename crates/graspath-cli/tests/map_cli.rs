//! `graspath map` end to end: the files it writes, the same bytes at any thread count, and one
//! clear error (exit code 2, nothing written) for a bad grid.

use std::path::Path;
use std::process::{Command, Output};

fn graspath(args: &[&str], threads: Option<usize>) -> Output {
    let mut command = Command::new(env!("CARGO_BIN_EXE_graspath"));
    command.args(args);
    if let Some(n) = threads {
        command.env("RAYON_NUM_THREADS", n.to_string());
    }
    command.output().expect("the binary runs")
}

const TASK: &str = r#"
robot: { builtin: baxter }
arms: left
object: { pose: { xyz: [0.75, 0.0, -0.10] }, shape: { box: { size: [0.06, 0.40, 0.10] } } }
candidates: { family: { edge: { count: 5 } } }
trajectory:
  samples_per_step: 3
  steps: [ { lift: 0.2 }, { move: [0, 0.3, 0] }, { place: 0.2 } ]
"#;

fn run_map(dir: &Path, out: &str, threads: usize) -> Output {
    let task = dir.join("task.yaml");
    graspath(
        &[
            "map",
            "--task",
            task.to_str().unwrap(),
            "--x",
            "0.6:0.8:3",
            "--y",
            "-0.1:0.1:2",
            "--out",
            dir.join(out).to_str().unwrap(),
            "--quiet",
        ],
        Some(threads),
    )
}

#[test]
fn map_writes_json_and_heatmaps_identically_at_any_thread_count() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("task.yaml"), TASK).unwrap();
    let o = run_map(dir.path(), "one", 1);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(o.stdout.is_empty(), "--quiet prints nothing");
    let o = run_map(dir.path(), "two", 2);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let one = dir.path().join("one");
    let mut names: Vec<String> = std::fs::read_dir(&one)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().to_string())
        .collect();
    names.sort();
    // One arm with a family: five heatmaps, each as SVG and PNG, and map.json.
    for stem in [
        "feasible",
        "best-score",
        "spread",
        "best-parameter",
        "trend",
    ] {
        for ext in ["svg", "png"] {
            let name = format!("map-{stem}-left.{ext}");
            assert!(names.contains(&name), "{name} missing from {names:?}");
        }
    }
    assert_eq!(names.len(), 11, "{names:?}");
    for name in &names {
        let a = std::fs::read(one.join(name)).unwrap();
        let b = std::fs::read(dir.path().join("two").join(name)).unwrap();
        assert!(a == b, "{name} differs between 1 and 2 threads");
    }
    let map: serde_json::Value =
        serde_json::from_slice(&std::fs::read(one.join("map.json")).unwrap()).unwrap();
    let placements = map["placements"].as_array().unwrap();
    assert_eq!(placements.len(), 6);
    // Grid order: x fastest.
    let xy: Vec<(f64, f64)> = placements
        .iter()
        .map(|p| (p["x"].as_f64().unwrap(), p["y"].as_f64().unwrap()))
        .collect();
    let expected = [
        (0.6, -0.1),
        (0.7, -0.1),
        (0.8, -0.1),
        (0.6, 0.1),
        (0.7, 0.1),
        (0.8, 0.1),
    ];
    assert_eq!(xy.len(), expected.len());
    for (e, g) in expected.iter().zip(&xy) {
        assert!(
            (e.0 - g.0).abs() < 1e-12 && (e.1 - g.1).abs() < 1e-12,
            "{xy:?}"
        );
    }
    assert_eq!(map["parameter"], "contact y (m, object frame)");
    for p in placements {
        let arm = &p["arms"][0];
        let (lo, hi) = (arm["mu_l2_min"].as_f64(), arm["mu_l2_max"].as_f64());
        if let (Some(lo), Some(hi)) = (lo, hi) {
            let spread = arm["spread"].as_f64().unwrap();
            assert!((spread - (hi - lo) / hi).abs() < 1e-15);
        }
    }
}

#[test]
fn a_bad_grid_is_one_clear_error_and_nothing_is_written() {
    let dir = tempfile::tempdir().unwrap();
    let task = dir.path().join("task.yaml");
    std::fs::write(&task, TASK).unwrap();
    for (x, expected) in [
        ("0.5:0.9", "--x: "),
        ("0.5:0.9:0", "at least 1"),
        ("a:0.9:3", "'a' is not a number"),
    ] {
        let out = dir.path().join("out");
        let o = graspath(
            &[
                "map",
                "--task",
                task.to_str().unwrap(),
                "--x",
                x,
                "--y",
                "0",
                "--out",
                out.to_str().unwrap(),
            ],
            None,
        );
        let text = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{x}: {text}");
        assert!(text.contains(expected), "{x}: {text}");
        assert!(!text.contains("panicked"), "{text}");
        assert!(!out.exists(), "{x}: nothing written");
    }
}
