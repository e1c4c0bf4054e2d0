//! `graspath select --format jsonl`: the streamed records equal the in-memory `candidates.json`
//! field by field (with `rank` and `pareto` taken from `ranking.jsonl`), `summary.json` and
//! `pairs.json` are the same bytes, no output depends on the thread count (1, 2, 8), and
//! `--trajectories` keeps the motions it names. A task naming a candidate file (read in chunks
//! when streamed) gives the same records, and a bad record in it the same error and no output.

use serde_json::{json, Value};
use std::path::{Path, PathBuf};

mod common;

use common::{example, graspath, read_json, read_lines, select};

/// A faces workload of 300 candidates (two chunks) and 12 samples, written into `dir`.
fn faces_task(dir: &Path) -> PathBuf {
    common::faces_task(dir, 300, 12)
}

/// Streams and runs in memory, and checks every candidate's fields and ranks.
fn check_streamed_equals_in_memory(task: &Path, dir: &Path) {
    let (memory, streamed) = (dir.join("memory"), dir.join("streamed"));
    select(task, &memory, &[], "2");
    select(
        task,
        &streamed,
        &["--format", "jsonl", "--trajectories", "all"],
        "2",
    );
    let want = read_json(&memory.join("candidates.json"));
    let want = want.as_array().unwrap();
    let lines = read_lines(&streamed.join("candidates.jsonl"));
    let ranking = read_lines(&streamed.join("ranking.jsonl"));
    assert_eq!(lines.len(), want.len());
    assert!(!streamed.join("candidates.json").exists());
    // Ranks are 1.. within each arm, best first, and name eligible candidates only.
    let mut previous: Option<(String, u64)> = None;
    for r in &ranking {
        let (arm, rank) = (r["arm"].as_str().unwrap(), r["rank"].as_u64().unwrap());
        let expected = match &previous {
            Some((a, n)) if a == arm => n + 1,
            _ => 1,
        };
        assert_eq!(rank, expected, "{r}");
        previous = Some((arm.to_string(), rank));
    }
    let mut ranked = 0;
    for (line, record) in lines.iter().zip(want) {
        assert!(line.get("rank").is_none() && line.get("pareto").is_none());
        let key = (&line["arm"], &line["id"]);
        let entry = ranking
            .iter()
            .find(|r| (&r["arm"], &r["id"]) == key)
            .cloned();
        let mut merged = line.clone();
        match entry {
            Some(e) => {
                ranked += 1;
                assert_eq!(e["score"], line["score"], "{key:?}");
                merged["rank"] = e["rank"].clone();
                merged["pareto"] = e["pareto"].clone();
            }
            None => {
                merged["rank"] = Value::Null;
                merged["pareto"] = json!(false);
            }
        }
        assert_eq!(&merged, record, "candidate {key:?}");
    }
    assert_eq!(
        ranked,
        ranking.len(),
        "ranking.jsonl names unknown candidates"
    );
    assert!(ranked > 0, "the task should select something");
    for name in ["summary.json", "pairs.json"] {
        let a = std::fs::read(memory.join(name));
        let b = std::fs::read(streamed.join(name));
        match (a, b) {
            (Ok(a), Ok(b)) => assert!(a == b, "{name} differs"),
            (Err(_), Err(_)) => {}
            (a, b) => panic!(
                "{name}: written by one run only ({}, {})",
                a.is_ok(),
                b.is_ok()
            ),
        }
    }
}

#[test]
fn one_arm_streamed_records_equal_the_in_memory_records() {
    let dir = tempfile::tempdir().unwrap();
    let task = faces_task(dir.path());
    check_streamed_equals_in_memory(&task, dir.path());
}

#[test]
fn two_arms_streamed_records_and_pairs_equal_the_in_memory_ones() {
    let dir = tempfile::tempdir().unwrap();
    check_streamed_equals_in_memory(&example("pick_and_place_both.yaml"), dir.path());
}

/// The faces workload of 300 candidates with its family written out as a graspath candidate
/// file `name` (CSV or JSON by extension; likelihoods that differ) in a folder of `dir` of that
/// name; `bad`: the record of candidate 150 replaced by this CSV line.
fn candidate_file_task(dir: &Path, name: &str, bad: Option<&str>) -> PathBuf {
    let folder = dir.join(name.replace('.', "_"));
    std::fs::create_dir_all(&folder).unwrap();
    let faces = faces_task(&folder);
    let family = graspath::task::Task::load(&faces)
        .unwrap()
        .candidates()
        .held()
        .expect("held candidates")
        .to_vec();
    let likelihood = |k: usize| 0.3 + (k % 7) as f64 / 7.0;
    let mut text = String::new();
    if name.ends_with(".csv") {
        text.push_str("id,label,x,y,z,qx,qy,qz,qw,likelihood\n");
        for (k, c) in family.iter().enumerate() {
            let (t, q) = (
                c.object_from_wrist.translation,
                c.object_from_wrist.rotation,
            );
            match bad {
                Some(line) if k == 150 => text.push_str(line),
                _ => text.push_str(&format!(
                    "{k},{},{},{},{},{},{},{},{},{}",
                    c.label,
                    t.x,
                    t.y,
                    t.z,
                    q.i,
                    q.j,
                    q.k,
                    q.w,
                    likelihood(k)
                )),
            }
            text.push('\n');
        }
    } else {
        let entries: Vec<String> = family
            .iter()
            .enumerate()
            .map(|(k, c)| {
                let (t, q) = (
                    c.object_from_wrist.translation,
                    c.object_from_wrist.rotation,
                );
                json!({
                    "id": k,
                    "label": c.label,
                    "pose": {"xyz": [t.x, t.y, t.z], "quaternion": [q.i, q.j, q.k, q.w]},
                    "likelihood": likelihood(k),
                })
                .to_string()
            })
            .collect();
        text = format!("[\n{}\n]\n", entries.join(",\n"));
    }
    std::fs::write(folder.join(name), text).unwrap();
    let task = std::fs::read_to_string(&faces).unwrap().replace(
        "family: { faces: { count: 300, exclude: [bottom], depth: 0.02 } }",
        &format!("file: {name}"),
    );
    assert!(task.contains("file: "), "the workload file changed");
    std::fs::write(&faces, task).unwrap();
    faces
}

#[test]
fn a_candidate_file_streams_the_in_memory_records() {
    let dir = tempfile::tempdir().unwrap();
    for name in ["grasps.csv", "grasps.json"] {
        let task = candidate_file_task(dir.path(), name, None);
        check_streamed_equals_in_memory(&task, task.parent().unwrap());
    }
}

#[test]
fn a_bad_record_in_a_candidate_file_gives_the_in_memory_error_and_no_output() {
    let dir = tempfile::tempdir().unwrap();
    let task = candidate_file_task(dir.path(), "grasps.csv", Some("150,x,0,0,0,0,0,0,oops,1"));
    let mut errors = Vec::new();
    for format in ["json", "jsonl", "parquet"] {
        let out = dir.path().join(format!("out_{format}"));
        let output = graspath(
            &[
                "select",
                "--task",
                task.to_str().unwrap(),
                "--out",
                out.to_str().unwrap(),
                "--format",
                format,
            ],
            "2",
        );
        assert!(!output.status.success());
        assert!(!out.exists(), "{format}: output written");
        let stderr = String::from_utf8_lossy(&output.stderr).into_owned();
        // The header is line 1 and every label is on one line.
        assert!(
            stderr.contains("grasps.csv: line 152: column 'qw': 'oops' is not a number"),
            "{stderr}"
        );
        errors.push((output.status.code(), stderr));
    }
    assert_eq!(errors[0], errors[1]);
    assert_eq!(errors[0], errors[2]);
}

#[test]
fn every_output_is_the_same_bytes_at_one_two_and_eight_threads() {
    let dir = tempfile::tempdir().unwrap();
    let task = faces_task(dir.path());
    let formats: [(&str, &[&str]); 3] = [
        (
            "jsonl",
            &["candidates.jsonl", "ranking.jsonl", "summary.json"],
        ),
        (
            "parquet",
            &["candidates.parquet", "ranking.parquet", "summary.json"],
        ),
        ("json", &["candidates.json", "summary.json"]),
    ];
    for (format, files) in formats {
        let runs: Vec<PathBuf> = ["1", "2", "8"]
            .iter()
            .map(|threads| {
                let out = dir.path().join(format!("{format}-{threads}"));
                select(&task, &out, &["--format", format], threads);
                out
            })
            .collect();
        for name in files {
            let one = std::fs::read(runs[0].join(name)).unwrap();
            for other in &runs[1..] {
                let bytes = std::fs::read(other.join(name)).unwrap();
                assert!(
                    one == bytes,
                    "{format}: {name} differs in {}",
                    other.display()
                );
            }
        }
    }
    // Nothing but the output folders beside them (no temporary folder left behind).
    let names = std::fs::read_dir(dir.path()).unwrap().count();
    assert_eq!(names, 1 + 3 * formats.len());
}

#[test]
fn trajectories_option_keeps_the_motions_it_names() {
    let dir = tempfile::tempdir().unwrap();
    let task = faces_task(dir.path());
    let runs = [
        ("default", vec!["--format", "jsonl"]),
        ("none", vec!["--format", "jsonl", "--trajectories", "none"]),
        ("all", vec!["--format", "jsonl", "--trajectories", "all"]),
    ];
    for (name, extra) in &runs {
        select(&task, &dir.path().join(name), extra, "2");
    }
    let samples = 12;
    let (mut feasible, mut infeasible) = (0, 0);
    for line in read_lines(&dir.path().join("default/candidates.jsonl")) {
        let is_feasible = line["feasible"].as_bool().unwrap();
        let q = line.get("joint_trajectory");
        if is_feasible {
            feasible += 1;
            assert_eq!(q.unwrap().as_array().unwrap().len(), samples);
        } else {
            infeasible += 1;
            assert!(q.is_none(), "an infeasible candidate's trajectory: {line}");
        }
    }
    assert!(feasible > 0 && infeasible > 0, "{feasible} / {infeasible}");
    for line in read_lines(&dir.path().join("none/candidates.jsonl")) {
        assert!(line.get("joint_trajectory").is_none());
        if line["feasible"].as_bool().unwrap() {
            assert_eq!(line["m_t"].as_array().unwrap().len(), samples);
        }
    }
    for line in read_lines(&dir.path().join("all/candidates.jsonl")) {
        assert!(line.get("joint_trajectory").is_some());
    }
    // --format json --trajectories none drops them from candidates.json too.
    let json_none = dir.path().join("json-none");
    select(&task, &json_none, &["--trajectories", "none"], "2");
    for record in read_json(&json_none.join("candidates.json"))
        .as_array()
        .unwrap()
    {
        assert!(record.get("joint_trajectory").is_none());
    }
}

#[test]
fn report_with_jsonl_is_refused_as_bad_input() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let task = example("pick_and_place_left.yaml");
    let output = graspath(
        &[
            "select",
            "--task",
            task.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--format",
            "jsonl",
            "--report",
        ],
        "2",
    );
    assert_eq!(output.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&output.stderr).contains("--format json"));
    assert!(!out.exists());
}

/// Parses a progress line `TITLE: DONE/TOTAL candidates (P %), R candidates/s, elapsed T, ETA`
/// into (done, total).
fn progress_counts(line: &str) -> Option<(u64, u64)> {
    let (_, rest) = line.rsplit_once(": ")?;
    let (counts, rest) = rest.split_once(" candidates (")?;
    rest.contains(" candidates/s, elapsed ").then_some(())?;
    let (done, total) = counts.split_once('/')?;
    Some((done.parse().ok()?, total.parse().ok()?))
}

#[test]
fn progress_every_logs_rising_counts_and_a_final_line() {
    let dir = tempfile::tempdir().unwrap();
    let task = faces_task(dir.path());
    let out = dir.path().join("out");
    let output = graspath(
        &[
            "select",
            "--task",
            task.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--quiet",
            "--format",
            "jsonl",
            "--progress-every",
            "0.001",
        ],
        "2",
    );
    assert!(output.status.success());
    let stderr = String::from_utf8_lossy(&output.stderr);
    let counts: Vec<(u64, u64)> = stderr.lines().filter_map(progress_counts).collect();
    assert_eq!(
        counts.len(),
        stderr.lines().count(),
        "only progress lines: {stderr}"
    );
    // At least the final line; the counts never fall and end at every candidate, done.
    assert!(!counts.is_empty());
    assert!(counts.windows(2).all(|w| w[0].0 <= w[1].0));
    assert!(counts.iter().all(|&(_, total)| total == 300));
    assert_eq!(counts.last().unwrap().0, 300);
    assert!(stderr.lines().last().unwrap().ends_with(", done"));

    // Without the option, --quiet prints nothing; a zero or non-number interval is refused.
    let quiet = graspath(
        &[
            "select",
            "--task",
            task.to_str().unwrap(),
            "--out",
            dir.path().join("q").to_str().unwrap(),
            "--quiet",
        ],
        "2",
    );
    assert!(quiet.status.success() && quiet.stderr.is_empty());
    for bad in ["0", "-1", "nan", "soon", "1e20", "inf"] {
        let flag = format!("--progress-every={bad}");
        let refused = graspath(&["select", "--task", task.to_str().unwrap(), &flag], "2");
        assert_eq!(refused.status.code(), Some(2), "{flag}");
        assert!(String::from_utf8_lossy(&refused.stderr).contains("--progress-every"));
    }
}

/// One long candidate (50 000 path samples, a few hundred milliseconds): the timed lines keep coming while it is scored,
/// its count still 0, and the final line counts it.
#[test]
fn progress_every_ticks_inside_a_long_candidate() {
    let dir = tempfile::tempdir().unwrap();
    let task = dir.path().join("long.yaml");
    std::fs::write(
        &task,
        "robot: { builtin: baxter }\narms: left\n\
         object: { pose: { xyz: [0.70, 0.25, -0.05] }, shape: { box: { size: [0.06, 0.06, 0.20] } } }\n\
         candidates: { family: { faces: { count: 1, exclude: [bottom] } } }\n\
         trajectory: { samples: 50000, steps: [ { lift: 0.2 }, { move: [0.0, 0.3, 0.0] }, { place: 0.2 } ] }\n",
    )
    .unwrap();
    let out = dir.path().join("out");
    let output = graspath(
        &[
            "select",
            "--task",
            task.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--quiet",
            "--format",
            "jsonl",
            "--trajectories",
            "none",
            "--progress-every",
            "0.001",
        ],
        "1",
    );
    assert!(output.status.success());
    let stderr = String::from_utf8_lossy(&output.stderr);
    let counts: Vec<(u64, u64)> = stderr.lines().filter_map(progress_counts).collect();
    let during = counts.iter().filter(|&&(done, _)| done == 0).count();
    assert!(
        during >= 2,
        "no line while the candidate was scored: {stderr}"
    );
    assert_eq!(counts.last(), Some(&(1, 1)), "{stderr}");
    assert!(stderr.lines().last().unwrap().ends_with(", done"));
}

#[test]
fn timings_name_every_phase_on_stderr_and_change_no_output() {
    let dir = tempfile::tempdir().unwrap();
    let task = faces_task(dir.path());
    let (plain, timed) = (dir.path().join("plain"), dir.path().join("timed"));
    select(&task, &plain, &["--format", "parquet"], "2");
    let output = common::select_output(
        &task,
        &timed,
        &["--quiet", "--format", "parquet", "--timings"],
        "2",
    );
    assert!(output.status.success());
    assert!(output.stdout.is_empty(), "--quiet prints nothing on stdout");
    let stderr = String::from_utf8(output.stderr).unwrap();
    assert!(
        stderr.starts_with("graspath: timings (2 worker threads)"),
        "{stderr}"
    );
    let phase = |name: &str| -> Vec<f64> {
        let line = stderr
            .lines()
            .find(|l| l.trim_start().starts_with(name))
            .unwrap_or_else(|| panic!("no phase '{name}' in\n{stderr}"));
        line[line.find(name).unwrap() + name.len()..]
            .split_whitespace()
            .map(|v| v.parse().unwrap())
            .collect()
    };
    // entries, wall s, CPU s, busy threads, own CPU s
    let scoring = phase("score (arm 'left')");
    assert_eq!(scoring[0], 1.0);
    for name in [
        "read the task",
        "rank (arm 'left')",
        "write the ranking file",
    ] {
        assert_eq!(phase(name)[0], 1.0, "{name}");
    }
    assert_eq!(phase("produce candidates")[0], 1.0);
    assert!(phase("hand on results")[0] >= 1.0);
    let whole = phase("whole run");
    assert!(whole[0] >= scoring[1], "the run is longer than its scoring");
    assert!(
        stderr.contains("outside the parallel scoring: "),
        "{stderr}"
    );
    for name in ["candidates.parquet", "ranking.parquet", "summary.json"] {
        let a = std::fs::read(plain.join(name)).unwrap();
        let b = std::fs::read(timed.join(name)).unwrap();
        assert!(a == b, "{name} differs with --timings");
    }
}
