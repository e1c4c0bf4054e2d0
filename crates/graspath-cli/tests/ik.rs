//! `graspath ik` run as a process: output format, unreachable targets, trajectories, and clear
//! errors (non-zero exit, the line or field named, no panic, no partial output).

mod common;

use common::graspath_with_input;

/// Runs and expects failure: returns stderr after checking the exit code, the absence of a
/// panic and of any output.
fn fails(args: &[&str], stdin: &str) -> String {
    let out = graspath_with_input(args, stdin);
    let stderr = String::from_utf8_lossy(&out.stderr).to_string();
    assert!(!out.status.success(), "expected failure: {stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(out.stdout.is_empty(), "no partial output");
    assert!(stderr.starts_with("graspath: error:"), "{stderr}");
    stderr
}

/// The tip pose of Baxter's left arm at `q`, via `graspath kinematics` (our FK, which the
/// library checks against Pinocchio).
fn pose_at(q: &[f64]) -> serde_json::Value {
    let line = serde_json::json!({ "q": q }).to_string();
    let out = graspath_with_input(&["kinematics", "--robot", "baxter", "--arm", "left"], &line);
    assert!(out.status.success());
    let value: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
    value["pose"].clone()
}

fn distance(a: &serde_json::Value, b: &serde_json::Value) -> f64 {
    let mut d = 0.0f64;
    for r in 0..4 {
        for c in 0..4 {
            let x = a[r][c].as_f64().expect("number");
            let y = b[r][c].as_f64().expect("number");
            d = d.max((x - y).abs());
        }
    }
    d
}

const BAXTER: [&str; 5] = ["ik", "--robot", "baxter", "--arm", "left"];

#[test]
fn solves_poses_and_reports_unreachable_ones_as_null() {
    let pose = pose_at(&[0.3, -0.4, 0.2, 1.1, -0.5, 0.8, 0.1]);
    let input = format!(
        "{}\n\n{}\n",
        serde_json::json!({ "pose": pose }),
        r#"{"pose":[[1,0,0,3],[0,1,0,0],[0,0,1,0],[0,0,0,1]]}"#
    );
    let out = graspath_with_input(&BAXTER, &input);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8(out.stdout).expect("utf-8");
    let lines: Vec<serde_json::Value> = text
        .lines()
        .map(|l| serde_json::from_str(l).expect("json line"))
        .collect();
    assert_eq!(lines.len(), 2);
    let q: Vec<f64> = serde_json::from_value(lines[0]["q"].clone()).expect("q");
    assert_eq!(q.len(), 7);
    assert!(
        distance(&pose_at(&q), &pose) < 2e-5,
        "FK of the answer reaches the target"
    );
    assert!(lines[0]["position_error"].as_f64().expect("number") <= 1e-5);
    assert!(lines[0]["iterations"].as_u64().expect("number") >= 1);
    assert!(lines[0]["time_us"].as_f64().expect("number") > 0.0);
    assert!(lines[1]["q"].is_null());
    assert!(lines[1]["position_error"].as_f64().expect("number") > 1.0);
}

#[test]
fn start_configurations_and_tolerance_are_accepted() {
    let pose = pose_at(&[0.1, -0.2, 0.3, 0.9, 0.2, 0.5, -0.1]);
    let input = serde_json::json!({ "pose": pose }).to_string();
    for start in [
        "mid",
        "zero",
        "0.1,-0.2,0.3,0.9,0.2,0.5,-0.1",
        "-0.5,0,0,1,0,0,0",
    ] {
        let mut args = BAXTER.to_vec();
        args.extend([
            "--start",
            start,
            "--tolerance",
            "1e-6",
            "--timeout-ms",
            "20",
        ]);
        let out = graspath_with_input(&args, &input);
        assert!(
            out.status.success(),
            "{start}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        let value: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
        assert!(value["q"].is_array(), "{start}");
        assert!(value["position_error"].as_f64().expect("number") <= 1e-6);
    }
}

#[test]
fn solves_a_trajectory_with_branches() {
    let poses: Vec<serde_json::Value> = (0..10)
        .map(|i| {
            let t = i as f64 / 9.0;
            pose_at(&[0.2 + 0.3 * t, -0.4, 0.1, 1.0 - 0.3 * t, 0.2, 0.6, 0.4 * t])
        })
        .collect();
    let document = serde_json::json!({ "poses": poses }).to_string();
    let mut args = BAXTER.to_vec();
    args.extend(["--trajectory", "--branches", "3"]);
    let out = graspath_with_input(&args, &document);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let value: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
    assert!(value["failure"].is_null());
    let branches = value["branches"].as_array().expect("branches");
    assert!(!branches.is_empty() && branches.len() <= 3);
    for branch in branches {
        let path: Vec<Vec<f64>> = serde_json::from_value(branch["q"].clone()).expect("q");
        assert_eq!(path.len(), 10);
        for (q, pose) in path.iter().zip(&poses) {
            assert!(distance(&pose_at(q), pose) < 2e-5);
        }
    }
}

/// `--start` sets the start configuration: the same start gives the same
/// bytes on every run (trajectories use iteration budgets only), the path starts at the first
/// pose, and the earlier spelling `--seed` is refused.
#[test]
fn the_start_flag_is_the_start_configuration() {
    let poses: Vec<serde_json::Value> = (0..6)
        .map(|i| {
            let t = i as f64 / 5.0;
            pose_at(&[0.2 + 0.3 * t, -0.4, 0.1, 1.0 - 0.3 * t, 0.2, 0.6, 0.4 * t])
        })
        .collect();
    let document = serde_json::json!({ "poses": poses }).to_string();
    let start = |flag: &str, start: &str| {
        let mut args = BAXTER.to_vec();
        args.extend(["--trajectory", "--branches", "1", flag, start]);
        graspath_with_input(&args, &document)
    };
    let run = |flag: &str, q: &str| {
        let out = start(flag, q);
        assert!(
            out.status.success(),
            "{flag} {q}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        out.stdout
    };
    let near = "0.2,-0.4,0.1,1.0,0.2,0.6,0.0";
    let new = run("--start", near);
    assert_eq!(new, run("--start", near));
    let refused = start("--seed", near);
    assert_eq!(refused.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&refused.stderr).contains("--seed"));
    let value: serde_json::Value = serde_json::from_slice(&new).expect("json");
    let first: Vec<f64> = serde_json::from_value(value["branches"][0]["q"][0].clone()).expect("q");
    assert!(distance(&pose_at(&first), &poses[0]) < 2e-5);
}

#[test]
fn an_unreachable_trajectory_reports_the_failure() {
    let document = r#"{"poses":[[[1,0,0,3],[0,1,0,0],[0,0,1,0],[0,0,0,1]],[[1,0,0,3.1],[0,1,0,0],[0,0,1,0],[0,0,0,1]]]}"#;
    let mut args = BAXTER.to_vec();
    args.push("--trajectory");
    let out = graspath_with_input(&args, document);
    assert!(out.status.success());
    let value: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
    assert_eq!(value["branches"].as_array().expect("array").len(), 0);
    assert_eq!(value["failure"]["reason"], "unreachable");
    assert_eq!(value["failure"]["sample"], 0);
    assert!(value["failure"]["detail"]
        .as_str()
        .expect("text")
        .contains("reach"));
}

#[test]
fn bad_input_gives_a_clear_error() {
    let good = r#"{"pose":[[1,0,0,0.5],[0,1,0,0.5],[0,0,1,0.2],[0,0,0,1]]}"#;
    let skewed = r#"{"pose":[[1,0.2,0,0.5],[0,1,0,0.5],[0,0,1,0.2],[0,0,0,1]]}"#;
    let stderr = fails(&BAXTER, &format!("{good}\n{skewed}\n"));
    assert!(
        stderr.contains("line 2") && stderr.contains("orthonormal"),
        "{stderr}"
    );
    let stderr = fails(
        &BAXTER,
        "{\"pose\": [[1,0,0,0],[0,1,0,0],[0,0,1,NaN],[0,0,0,1]]}\n",
    );
    assert!(stderr.contains("line 1"), "{stderr}");
    let stderr = fails(&BAXTER, "{\"pose\": [[1,0,0,0],[0,1,0,0],[0,0,1,0]]}\n");
    assert!(
        stderr.contains("line 1") && stderr.contains("length 4"),
        "{stderr}"
    );
    let stderr = fails(&BAXTER, "not json\n");
    assert!(stderr.contains("line 1"), "{stderr}");
    let stderr = fails(
        &BAXTER,
        "{\"pose\": [[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]], \"q\": 1}\n",
    );
    assert!(stderr.contains("unknown field"), "{stderr}");
    let stderr = fails(
        &BAXTER,
        "{\"pose\": [[1,0,0,0],[0,1,0,0],[0,0,1,0],[1,0,0,1]]}\n",
    );
    assert!(stderr.contains("last row"), "{stderr}");

    let mut args = BAXTER.to_vec();
    args.extend(["--start", "1,2,3"]);
    let stderr = fails(&args, good);
    assert!(
        stderr.contains("--start") && stderr.contains("7"),
        "{stderr}"
    );
    let mut args = BAXTER.to_vec();
    args.extend(["--start", "1,2,3,nan,5,6,7"]);
    assert!(fails(&args, good).contains("--start"));
    let mut args = BAXTER.to_vec();
    args.extend(["--start", "1,2,x,4,5,6,7"]);
    assert!(fails(&args, good).contains("'x' is not a number"));
    let mut args = BAXTER.to_vec();
    args.extend(["--tolerance", "0"]);
    assert!(fails(&args, good).contains("--tolerance"));
    let mut args = BAXTER.to_vec();
    args.extend(["--timeout-ms", "1e300"]);
    assert!(fails(&args, good).contains("--timeout-ms"));

    let mut args = BAXTER.to_vec();
    args.push("--trajectory");
    let stderr = fails(
        &args,
        r#"{"poses":[[[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]],[[2,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]]}"#,
    );
    assert!(
        stderr.contains("poses[1]") && stderr.contains("orthonormal"),
        "{stderr}"
    );
    assert!(fails(&args, r#"{"poses":[]}"#).contains("no poses"));
    assert!(fails(&args, r#"{"pose":[]}"#).contains("unknown field"));
    assert!(fails(&args, "").contains("not a valid trajectory document"));
}

/// The README's example runs on the file the repository ships: the first pose is reached (its
/// solution checked by forward kinematics), the second, 3 m further, is a result with no `q`.
#[test]
fn the_readme_example_runs_on_the_shipped_poses() {
    let file = concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/poses.jsonl");
    let text = std::fs::read_to_string(file).expect("examples/poses.jsonl is shipped");
    let readme =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../README.md")).unwrap();
    assert!(
        readme.contains("--input examples/poses.jsonl"),
        "the README names the file"
    );
    let out = graspath_with_input(
        &["ik", "--robot", "baxter", "--arm", "left", "--input", file],
        "",
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let lines: Vec<serde_json::Value> = String::from_utf8(out.stdout)
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(lines.len(), text.lines().count());
    let q: Vec<f64> = serde_json::from_value(lines[0]["q"].clone()).expect("reached");
    let reached = pose_at(&q);
    let wanted: serde_json::Value = serde_json::from_str(text.lines().next().unwrap()).unwrap();
    for r in 0..3 {
        let (a, b) = (
            reached[r][3].as_f64().unwrap(),
            wanted["pose"][r][3].as_f64().unwrap(),
        );
        assert!((a - b).abs() < 1e-5, "row {r}: {a} vs {b}");
    }
    assert!(lines[1]["q"].is_null());
}
