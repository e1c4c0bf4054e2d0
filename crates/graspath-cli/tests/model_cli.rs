//! The `train` and `generate` subcommands end to end, and their handling of bad input: one
//! clear error naming the file and field, a non-zero exit, and no output file.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn graspath(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_graspath"))
        .args(args)
        .output()
        .expect("run graspath")
}

fn examples() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../examples/grasp")
}

fn s(p: &Path) -> &str {
    p.to_str().expect("utf-8 path")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

const SMALL: [&str; 8] = [
    "--initial-grasps",
    "2000",
    "--steps",
    "100",
    "--query-kernels",
    "1500",
    "--seed",
    "3",
];

fn trained(dir: &Path) -> PathBuf {
    let model = dir.join("model.json");
    let out = graspath(&[
        "train",
        s(&examples().join("demo_box.json")),
        "--out",
        s(&model),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    model
}

#[test]
fn train_then_generate_writes_the_candidate_file() {
    let dir = tempfile::tempdir().expect("tempdir");
    let model = trained(dir.path());
    let candidates = dir.path().join("candidates.json");
    let cylinder = examples().join("cylinder.json");
    let mut args = vec![
        "generate",
        "--model",
        s(&model),
        "--cloud",
        s(&cylinder),
        "--out",
        s(&candidates),
        "--max-candidates",
        "10",
    ];
    args.extend(SMALL);
    let out = graspath(&args);
    assert!(out.status.success(), "{}", stderr(&out));
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(&candidates).expect("read")).expect("json");
    assert_eq!(json["format"], "graspath-candidates");
    assert_eq!(json["version"], 1);
    assert_eq!(json["frame"], "object");
    let list = json["candidates"].as_array().expect("list");
    assert_eq!(list.len(), 10);
    assert_eq!(list[0]["id"], 0);
    assert_eq!(list[0]["label"], "pinch");
    assert_eq!(
        list[0]["object_from_wrist"].as_array().expect("rows").len(),
        4
    );
    assert!(
        list[0]["log_likelihood"].as_f64().expect("number")
            >= list[9]["log_likelihood"].as_f64().expect("number")
    );
    assert_eq!(list[0]["contact"].as_array().expect("point").len(), 3);
    assert_eq!(list[0]["hand_joints"].as_array().expect("joints").len(), 1);
}

#[test]
fn a_cloud_without_normals_gets_estimated_normals_and_a_note() {
    let dir = tempfile::tempdir().expect("tempdir");
    let model = trained(dir.path());
    let ply = dir.path().join("object.ply");
    let mut text = String::from("ply\nformat ascii 1.0\nelement vertex 1600\nproperty float x\nproperty float y\nproperty float z\nend_header\n");
    // A 40 × 40 × 100 mm box surface on a grid, without normals.
    for i in 0..20 {
        for j in 0..20 {
            let (u, v) = (
                -0.02 + 0.04 * i as f64 / 19.0,
                -0.05 + 0.1 * j as f64 / 19.0,
            );
            for (x, y, z) in [(0.02, u, v), (-0.02, u, v), (u, 0.02, v), (u, -0.02, v)] {
                text.push_str(&format!("{x} {y} {z}\n"));
            }
        }
    }
    std::fs::write(&ply, text).expect("write");
    let candidates = dir.path().join("c.json");
    let mut args = vec![
        "generate",
        "--model",
        s(&model),
        "--cloud",
        s(&ply),
        "--out",
        s(&candidates),
    ];
    args.extend(SMALL);
    let out = graspath(&args);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("has no normals; estimating them"),
        "{}",
        stderr(&out)
    );
    assert!(candidates.exists());
}

/// Runs a failing command and checks the message names `file` and `what`, and that `out` was
/// not created.
fn fails(args: &[&str], file: &str, what: &str, out: &Path) {
    let o = graspath(args);
    assert!(!o.status.success());
    let err = stderr(&o);
    assert_eq!(err.lines().count(), 1, "one line: {err}");
    assert!(err.contains(file) && err.contains(what), "{err}");
    assert!(!err.contains("panicked"), "{err}");
    assert!(!out.exists(), "no partial output");
    let dir = out.parent().expect("dir");
    let leftovers: Vec<_> = std::fs::read_dir(dir)
        .expect("list")
        .flatten()
        .filter(|e| e.file_name().to_string_lossy().ends_with(".tmp"))
        .collect();
    assert!(leftovers.is_empty());
}

#[test]
fn bad_inputs_give_one_clear_error_and_no_output() {
    let dir = tempfile::tempdir().expect("tempdir");
    let model = trained(dir.path());
    let out = dir.path().join("out.json");
    let generate = |cloud: &Path, model: &Path| {
        let mut v = vec![
            "generate".to_string(),
            "--model".into(),
            s(model).into(),
            "--cloud".into(),
            s(cloud).into(),
            "--out".into(),
            s(&out).into(),
        ];
        v.extend(SMALL.iter().map(ToString::to_string));
        v
    };
    let run_fail = |args: Vec<String>, file: &str, what: &str| {
        let refs: Vec<&str> = args.iter().map(String::as_str).collect();
        fails(&refs, file, what, &out);
    };

    let empty = dir.path().join("empty.ply");
    std::fs::write(&empty, "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\nproperty float z\nend_header\n").expect("write");
    run_fail(generate(&empty, &model), "empty.ply", "no points");

    let nan = dir.path().join("nan.pcd");
    std::fs::write(&nan, "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 2\nHEIGHT 1\nPOINTS 2\nDATA ascii\nnan nan nan\nnan nan nan\n").expect("write");
    run_fail(generate(&nan, &model), "nan.pcd", "NaN");

    let text = std::fs::read_to_string(&model).expect("model");
    let old = dir.path().join("old_model.json");
    std::fs::write(
        &old,
        text.replacen("\"format_version\":2", "\"format_version\":3", 1),
    )
    .expect("write");
    run_fail(
        generate(&examples().join("cylinder.json"), &old),
        "old_model.json",
        "format_version",
    );

    let demo = std::fs::read_to_string(examples().join("demo_box.json")).expect("demo");
    let far = dir.path().join("far_demo.json");
    std::fs::write(
        &far,
        demo.replace("0.03], [0, 0, 0, 1]]", "0.5], [0, 0, 0, 1]]")
            .replace("\"seed\": 1", "\"seed\": 1, \"points\": 3000")
            .replacen("\"points\": 5000,\n", "", 1),
    )
    .expect("write");
    let o = graspath(&["train", s(&far), "--out", s(&out)]);
    assert!(!o.status.success());
    let err = stderr(&o);
    assert!(
        err.contains("far_demo.json") && err.contains("no hand link is in contact"),
        "{err}"
    );
    assert!(
        err.contains("'l_finger'") && err.contains("'palm'") && err.contains("closest"),
        "{err}"
    );
    assert!(!out.exists());

    let missing = dir.path().join("missing.pcd");
    run_fail(generate(&missing, &model), "missing.pcd", "No such file");
}

/// The whole paper pipeline from one task file: a trained model generates candidates with
/// likelihoods on the object's cloud, and the selection ranks them along the task.
#[test]
fn a_task_can_generate_its_candidates_from_a_trained_model() {
    let dir = tempfile::tempdir().expect("tempdir");
    let model = trained(dir.path());
    let task = dir.path().join("task.yaml");
    std::fs::write(
        &task,
        format!(
            r#"
robot: {{ builtin: baxter }}
arms: left
object: {{ pose: {{ xyz: [0.70, 0.25, -0.10] }} }}
candidates:
  generate: {{ model: {}, cloud: {}, seed: 3, initial_grasps: 2000, steps: 100, query_kernels: 1500, max_candidates: 15 }}
ik: {{ random_seed: 1 }}
trajectory:
  samples_per_step: 5
  steps: [ {{ lift: 0.2 }}, {{ move: [0, 0.2, 0] }}, {{ place: 0.2 }} ]
"#,
            s(&model),
            s(&examples().join("cylinder.json"))
        ),
    )
    .expect("write task");
    let out = dir.path().join("out");
    let o = graspath(&["select", "--task", s(&task), "--out", s(&out), "--quiet"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = std::fs::read_to_string(out.join("candidates.json")).expect("candidates.json");
    let list: serde_json::Value = serde_json::from_str(&text).expect("json");
    let list = list.as_array().expect("a list");
    assert_eq!(list.len(), 15);
    let logs: Vec<f64> = list
        .iter()
        .map(|c| c["log_likelihood"].as_f64().expect("log"))
        .collect();
    assert!(
        logs.windows(2).all(|w| w[0] >= w[1]),
        "generated best first"
    );
    assert!(logs[0] > logs[14], "likelihoods differ");
    // The ranking combines the likelihood: every ranked candidate's score is its ranked norm
    // (the default μ_rms) times its likelihood relative to the most likely candidate.
    for c in list.iter().filter(|c| c["rank"].is_u64()) {
        let expected = c["mu_rms"].as_f64().expect("mu")
            * (c["log_likelihood"].as_f64().expect("log") - logs[0]).exp();
        assert!(
            (c["score"].as_f64().expect("score") - expected).abs() <= 1e-12 * expected.max(1e-300)
        );
    }
}

/// The outlier flags of `generate`: NaN points skipped and counted, background cropped, the
/// counts reported; a bad value is one clear error naming the option.
#[test]
fn generate_flags_remove_outliers_and_report_them() {
    let dir = tempfile::tempdir().expect("tempdir");
    let model = trained(dir.path());
    let mut rows = Vec::new();
    // A 40 × 40 × 100 mm box surface on a grid, with exact outward normals.
    for i in 0..20 {
        for j in 0..20 {
            let (u, v) = (
                -0.02 + 0.04 * i as f64 / 19.0,
                -0.05 + 0.1 * j as f64 / 19.0,
            );
            for (p, n) in [
                ((0.02, u, v), (1, 0, 0)),
                ((-0.02, u, v), (-1, 0, 0)),
                ((u, 0.02, v), (0, 1, 0)),
                ((u, -0.02, v), (0, -1, 0)),
            ] {
                rows.push(format!("{} {} {} {} {} {}", p.0, p.1, p.2, n.0, n.1, n.2));
            }
        }
    }
    for _ in 0..3 {
        rows.push("nan nan nan 0 0 1".into());
    }
    for k in 0..20 {
        let a = k as f64 * 0.3;
        rows.push(format!("{} {} 0 0 0 1", 10.0 * a.cos(), 10.0 * a.sin()));
    }
    let ply = dir.path().join("scan.pcd");
    std::fs::write(
        &ply,
        format!(
            "VERSION 0.7\nFIELDS x y z normal_x normal_y normal_z\nSIZE 4 4 4 4 4 4\nTYPE F F F F F F\nCOUNT 1 1 1 1 1 1\nWIDTH {n}\nHEIGHT 1\nPOINTS {n}\nDATA ascii\n{}\n",
            rows.join("\n"),
            n = rows.len(),
        ),
    )
    .expect("write");
    let out = dir.path().join("c.json");
    let mut args = vec![
        "generate",
        "--model",
        s(&model),
        "--cloud",
        s(&ply),
        "--out",
        s(&out),
        "--crop-box",
        "-1,-1,-1,1,1,1",
        "--max-range",
        "5",
        "--sensor-origin",
        "0,0,-0.5",
    ];
    args.extend(SMALL);
    let o = graspath(&args);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains(
            "1623 points read, 1600 kept; removed: 3 NaN/infinite, 20 outside the crop box, 0 beyond the maximum range, 0 statistical outliers"
        ),
        "{}",
        stderr(&o)
    );
    assert!(out.exists());

    let bad = dir.path().join("bad.json");
    let mut args = vec![
        "generate",
        "--model",
        s(&model),
        "--cloud",
        s(&ply),
        "--out",
        s(&bad),
        "--max-range",
        "-1",
    ];
    args.extend(SMALL);
    fails(&args, "outlier removal", "max_range", &bad);
    let mut args = vec![
        "generate",
        "--model",
        s(&model),
        "--cloud",
        s(&ply),
        "--out",
        s(&bad),
        "--outlier-neighbours",
        "0",
    ];
    args.extend(SMALL);
    fails(&args, "outlier removal", "statistical.neighbours", &bad);
}

/// The earlier spellings `--seeds`, `candidates.generate.seeds` and `ik.seed` are gone: each is
/// refused by name, before anything runs, and nothing is written.
#[test]
fn the_removed_seed_spellings_are_refused_by_name() {
    let dir = tempfile::tempdir().expect("tempdir");
    let cylinder = examples().join("cylinder.json");
    let out = dir.path().join("c.json");
    let o = graspath(&[
        "generate",
        "--model",
        "model.json",
        "--cloud",
        s(&cylinder),
        "--out",
        s(&out),
        "--seeds",
        "1200",
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("--seeds"), "{}", stderr(&o));
    assert!(!out.exists());
    for (field, yaml) in [
        (
            "candidates.generate.seeds",
            "candidates:\n  generate: { model: m.json, cloud: c.ply, seeds: 800 }\n",
        ),
        (
            "ik.seed",
            "candidates: { family: { edge: { count: 2 } } }\nik: { seed: 1 }\n",
        ),
    ] {
        let task = dir.path().join("task.yaml");
        std::fs::write(
            &task,
            format!(
                "robot: {{ builtin: baxter }}\narms: left\nobject: {{ pose: {{ xyz: [0.7, 0.25, -0.1] }} }}\n\
                 {yaml}trajectory: {{ steps: [ {{ lift: 0.2 }} ] }}\n"
            ),
        )
        .expect("write task");
        let out = dir.path().join("out");
        let o = graspath(&["select", "--task", s(&task), "--out", s(&out), "--quiet"]);
        assert!(!o.status.success());
        let message = stderr(&o);
        let unknown = field.rsplit('.').next().expect("a key");
        assert!(
            message.contains(&format!("unknown field `{unknown}`")),
            "{message}"
        );
        assert!(
            message.contains(field.rsplit_once('.').expect("a parent").0),
            "{message}"
        );
        assert!(!out.exists());
    }
}
