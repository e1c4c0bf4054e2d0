//! `graspath select --report`: the figures and `report.html` are written beside the JSON, the
//! same input gives the same bytes, `--quiet` prints nothing and `--json` prints the summary.

use std::path::Path;

mod common;

use common::example;

fn graspath(args: &[&str]) -> std::process::Output {
    let output = common::graspath(args, "2");
    assert!(
        output.status.success(),
        "graspath {args:?} failed: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    output
}

fn run(out: &Path, extra: &[&str]) -> std::process::Output {
    let task = example("pick_and_place_left.yaml");
    let mut args = vec![
        "select",
        "--task",
        task.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ];
    args.extend(extra);
    graspath(&args)
}

#[test]
fn report_files_are_written_deterministically() {
    let dir = tempfile::tempdir().unwrap();
    let (a, b) = (dir.path().join("a"), dir.path().join("b"));
    let quiet = run(&a, &["--report", "--quiet"]);
    assert!(quiet.stdout.is_empty(), "--quiet printed to stdout");
    run(&b, &["--report", "--quiet"]);
    let expected = [
        "candidates.json",
        "summary.json",
        "report.html",
        "norms-left.svg",
        "norms-left.png",
        "mt-heatmap-left.svg",
        "mt-heatmap-left.png",
        "classical-indices-left.svg",
        "classical-indices-left.png",
    ];
    for name in expected {
        let x = std::fs::read(a.join(name)).unwrap_or_else(|e| panic!("{name}: {e}"));
        let y = std::fs::read(b.join(name)).unwrap();
        assert!(x == y, "{name} differs between two runs");
    }
    let html = std::fs::read_to_string(a.join("report.html")).unwrap();
    assert!(html.contains("<svg") && html.contains("three.js r170"));
    assert!(
        !html.contains("src=\"http"),
        "the report must not load from the network"
    );
    // No temporary files are left behind.
    let leftovers: Vec<_> = std::fs::read_dir(&a)
        .unwrap()
        .filter_map(Result::ok)
        .filter(|e| e.file_name().to_string_lossy().starts_with('.'))
        .collect();
    assert!(leftovers.is_empty(), "{leftovers:?}");
}

#[test]
fn without_report_only_json_is_written_and_json_mode_prints_the_summary() {
    let dir = tempfile::tempdir().unwrap();
    let output = run(dir.path(), &["--json"]);
    let summary: serde_json::Value =
        serde_json::from_slice(&output.stdout).expect("--json prints JSON");
    assert_eq!(summary["arms"][0]["arm"], "left");
    assert!(dir.path().join("summary.json").is_file());
    assert!(!dir.path().join("report.html").exists());
}
