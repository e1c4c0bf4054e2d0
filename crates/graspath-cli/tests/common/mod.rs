//! Helpers shared by the CLI's integration tests: the example tasks, running the binary at a
//! given thread count or with a standard input, and reading its JSON and JSON Lines outputs.

#![allow(dead_code)] // Each test binary uses its own subset.

use serde_json::Value;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

/// A file of the repository's `examples/` folder.
pub fn example(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples")
        .join(name)
}

/// Runs the binary with `args` on `threads` worker threads (`RAYON_NUM_THREADS`).
pub fn graspath(args: &[&str], threads: &str) -> Output {
    Command::new(env!("CARGO_BIN_EXE_graspath"))
        .args(args)
        .env("RAYON_NUM_THREADS", threads)
        .output()
        .expect("graspath runs")
}

/// Runs the binary with `args`, `stdin` written to its standard input.
pub fn graspath_with_input(args: &[&str], stdin: &str) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_graspath"))
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the binary runs");
    // The process may exit (on a bad option) before reading its input: a broken pipe here
    // is not an error of the test.
    let _ = child
        .stdin
        .take()
        .expect("stdin")
        .write_all(stdin.as_bytes());
    child.wait_with_output().expect("finishes")
}

/// `graspath select --task TASK --out OUT EXTRA…` on `threads` threads, whatever its outcome.
pub fn select_output(task: &Path, out: &Path, extra: &[&str], threads: &str) -> Output {
    let mut args = vec![
        "select",
        "--task",
        task.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ];
    args.extend(extra);
    graspath(&args, threads)
}

/// `graspath select --task TASK --out OUT --quiet EXTRA…` on `threads` threads; fails the test
/// (with the binary's stderr) unless it succeeds.
pub fn select(task: &Path, out: &Path, extra: &[&str], threads: &str) {
    let mut quiet = vec!["--quiet"];
    quiet.extend(extra);
    let output = select_output(task, out, &quiet, threads);
    assert!(
        output.status.success(),
        "graspath select {} failed: {}",
        task.display(),
        String::from_utf8_lossy(&output.stderr)
    );
}

/// A JSON document.
pub fn read_json(path: &Path) -> Value {
    serde_json::from_slice(&std::fs::read(path).unwrap()).unwrap()
}

/// A JSON Lines file, one value per line.
pub fn read_lines(path: &Path) -> Vec<Value> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect()
}

/// The faces workload (`examples/workload_1000_faces.yaml`) with `count` candidates and
/// `samples` samples, written into `dir` as `faces.yaml`.
pub fn faces_task(dir: &Path, count: usize, samples: usize) -> PathBuf {
    let text = std::fs::read_to_string(example("workload_1000_faces.yaml"))
        .unwrap()
        .replace("count: 1000", &format!("count: {count}"))
        .replace("samples: 50", &format!("samples: {samples}"));
    assert!(
        text.contains(&format!("count: {count}")) && text.contains(&format!("samples: {samples}")),
        "the workload file changed"
    );
    let path = dir.join("faces.yaml");
    std::fs::write(&path, text).unwrap();
    path
}
