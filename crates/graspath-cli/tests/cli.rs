//! The `graspath` binary end to end: outputs, determinism, and one clear error (no panic, no
//! partial output) for each kind of bad input.

mod common;

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

fn graspath(args: &[&str], stdin: Option<&str>, threads: Option<usize>) -> Output {
    let mut command = Command::new(env!("CARGO_BIN_EXE_graspath"));
    command
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    if let Some(n) = threads {
        command.env("RAYON_NUM_THREADS", n.to_string());
    }
    let mut child = command.spawn().expect("the binary runs");
    if let Some(text) = stdin {
        child
            .stdin
            .take()
            .unwrap()
            .write_all(text.as_bytes())
            .unwrap();
    }
    drop(child.stdin.take());
    child.wait_with_output().unwrap()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).to_string()
}

fn assert_clean_failure(o: &Output, expected: &[&str]) {
    assert!(!o.status.success(), "should fail");
    let text = stderr(o);
    assert!(!text.contains("panicked"), "panic: {text}");
    for e in expected {
        assert!(text.contains(e), "missing '{e}' in: {text}");
    }
}

fn repo_root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

/// `graspath select --task TASK --out OUT EXTRA…` (its output, whatever it is).
fn select(task: &Path, out: &Path, extra: &[&str]) -> Output {
    common::select_output(task, out, extra, "2")
}

const SMALL_TASK: &str = r#"
robot: { builtin: baxter }
arms: left
object: { pose: { xyz: [0.75, 0.0, -0.10] }, shape: { box: { size: [0.06, 0.40, 0.10] } } }
candidates: { family: { edge: { count: 7 } } }
trajectory:
  samples_per_step: 4
  steps: [ { lift: 0.2 }, { move: [0, 0.3, 0] }, { place: 0.2 } ]
"#;

#[test]
fn kinematics_reports_the_line_at_fault() {
    let o = graspath(
        &["kinematics", "--robot", "baxter", "--arm", "right"],
        Some("{\"q\":[0,0,0,0,0,0,0]}\n{\"q\":[0,\"x\"]}\n"),
        None,
    );
    assert_clean_failure(&o, &["line 2", "not a valid input object"]);
    assert!(o.stdout.is_empty(), "no partial output");
    let o = graspath(
        &["kinematics", "--robot", "baxter", "--arm", "right"],
        Some("{\"q\":[0,0,0,0,0,0,0]}\n"),
        None,
    );
    let first: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(first["within_limits"], true);
    assert_eq!(first["jacobian"].as_array().unwrap().len(), 6);
    let o = graspath(
        &["kinematics", "--robot", "baxter"],
        Some("{\"q\":[0,0,0]}\n"),
        None,
    );
    assert_clean_failure(&o, &["line 1", "q has 3 values"]);
    let o = graspath(
        &["kinematics", "--robot", "baxter"],
        Some("{\"q\":[0,0,0,0,0,0,0],\"extra\":1}\n"),
        None,
    );
    assert_clean_failure(&o, &["line 1", "unknown field `extra`"]);
    let o = graspath(&["kinematics", "--robot", "kuka"], Some(""), None);
    assert_clean_failure(
        &o,
        &[
            "invalid value 'kuka' for '--robot <NAME>'",
            "possible values: baxter, panda",
        ],
    );
}

#[test]
fn kinematics_of_a_single_arm_builtin_robot() {
    // UR5e at q = 0: the published DH table in closed form puts tool0 at
    // (a2 + a3, -(d4 + d6), d1 - d5).
    let o = graspath(
        &["kinematics", "--robot", "ur5e"],
        Some("{\"q\":[0,0,0,0,0,0]}\n"),
        None,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let out: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let pose = &out["pose"];
    let expected = [-0.425 - 0.3922, -(0.1333 + 0.0996), 0.1625 - 0.0997];
    for (row, value) in expected.iter().enumerate() {
        let got = pose[row][3].as_f64().unwrap();
        assert!((got - value).abs() < 1e-12, "{row}: {got} vs {value}");
    }
    let o = graspath(
        &["kinematics", "--robot", "panda", "--arm", "left"],
        Some(""),
        None,
    );
    assert_clean_failure(&o, &["--arm", "no chain named 'left' (chains: arm)"]);
}

#[test]
fn select_is_byte_identical_at_any_thread_count() {
    let dir = tempfile::tempdir().unwrap();
    let task = write(dir.path(), "task.yaml", SMALL_TASK);
    let mut outputs = Vec::new();
    for threads in [1, 2] {
        let out = dir.path().join(format!("out{threads}"));
        let o = graspath(
            &[
                "select",
                "--task",
                task.to_str().unwrap(),
                "--out",
                out.to_str().unwrap(),
                "--quiet",
            ],
            None,
            Some(threads),
        );
        assert!(o.status.success(), "{}", stderr(&o));
        outputs.push((
            std::fs::read(out.join("candidates.json")).unwrap(),
            std::fs::read(out.join("summary.json")).unwrap(),
        ));
    }
    assert_eq!(outputs[0], outputs[1]);
    let candidates: serde_json::Value = serde_json::from_slice(&outputs[0].0).unwrap();
    let list = candidates.as_array().unwrap();
    assert_eq!(list.len(), 7);
    for c in list {
        for key in [
            "id",
            "label",
            "object_from_wrist",
            "contact",
            "likelihood",
            "feasible",
            "failure",
            "mu_l2",
            "mu_linf",
            "mu_l1",
            "mu_rms",
            "m_t",
            "yoshikawa_at_grasp",
            "inverse_condition_at_grasp",
            "joint_trajectory",
            "rank",
        ] {
            assert!(c.get(key).is_some(), "missing {key}");
        }
    }
}

#[test]
fn json_flag_prints_the_summary() {
    let dir = tempfile::tempdir().unwrap();
    let task = write(dir.path(), "task.yaml", SMALL_TASK);
    let out = dir.path().join("out");
    let o = graspath(
        &[
            "select",
            "--task",
            task.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--json",
        ],
        None,
        None,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let summary: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(summary["arms"][0]["arm"], "left");
    assert!(summary["arms"][0]["selected"]["id"].is_u64());
}

#[test]
fn bad_task_files_fail_cleanly_without_output() {
    let dir = tempfile::tempdir().unwrap();
    let cases: Vec<(&str, String, Vec<&str>)> = vec![
        (
            "unknown.yaml",
            SMALL_TASK.replace("arms: left", "arms: left\ncolour: red"),
            vec!["unknown.yaml", "colour"],
        ),
        (
            "units.yaml",
            SMALL_TASK.replace("xyz: [0.75, 0.0, -0.10]", "xyz: [0.75, 0.0]"),
            vec!["units.yaml", "object.pose.xyz"],
        ),
        (
            "nan.yaml",
            SMALL_TASK.replace("xyz: [0.75, 0.0, -0.10]", "xyz: [.nan, 0.0, -0.1]"),
            vec!["nan.yaml", "line 4", "non-finite"],
        ),
        (
            "empty.yaml",
            SMALL_TASK.replace("{ family: { edge: { count: 7 } } }", "{ file: empty.json }"),
            vec!["empty.yaml", "candidates.file", "contains no candidates"],
        ),
        (
            "step.yaml",
            SMALL_TASK.replace("{ lift: 0.2 }", "{ lift: 0.2, duration: -1 }"),
            vec!["step.yaml", "trajectory.steps[0].duration"],
        ),
    ];
    write(
        dir.path(),
        "empty.json",
        r#"{"format":"graspath-candidates","version":1,"candidates":[]}"#,
    );
    for (name, text, expected) in cases {
        let task = write(dir.path(), name, &text);
        let out = dir.path().join(format!("out-{name}"));
        let o = graspath(
            &[
                "select",
                "--task",
                task.to_str().unwrap(),
                "--out",
                out.to_str().unwrap(),
            ],
            None,
            None,
        );
        assert_clean_failure(&o, &expected);
        assert!(!out.exists(), "{name}: no output may be written");
    }
}

#[test]
fn a_chain_whose_tip_is_not_below_its_base_is_named() {
    let Some(urdf) = [
        std::env::var_os("GRASPATH_SHARED").map(PathBuf::from),
        Some(repo_root().join("../shared")),
    ]
    .into_iter()
    .flatten()
    .map(|d| d.join("robots/baxter.urdf"))
    .find(|p| p.is_file()) else {
        eprintln!("skipped: ../shared is not present");
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let text = SMALL_TASK.replace(
        "robot: { builtin: baxter }\narms: left",
        &format!("robot:\n  urdf: {}\n  chains: {{ left: {{ base: left_arm_mount, tip: right_gripper }} }}\narms: left", urdf.display()),
    );
    let task = write(dir.path(), "chain.yaml", &text);
    let o = graspath(
        &[
            "select",
            "--task",
            task.to_str().unwrap(),
            "--out",
            dir.path().join("o").to_str().unwrap(),
        ],
        None,
        None,
    );
    assert_clean_failure(
        &o,
        &[
            "chain.yaml",
            "robot.chains.left",
            "is not below base link 'left_arm_mount'",
        ],
    );
}

#[test]
fn an_unreachable_task_is_a_result_not_an_error() {
    let dir = tempfile::tempdir().unwrap();
    let task = write(
        dir.path(),
        "far.yaml",
        &SMALL_TASK.replace("xyz: [0.75, 0.0, -0.10]", "xyz: [3.0, 0.0, -0.10]"),
    );
    let out = dir.path().join("out");
    let o = graspath(
        &[
            "select",
            "--task",
            task.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--quiet",
        ],
        None,
        None,
    );
    // Nothing selected: exit code 3, the results written all the same.
    assert_eq!(o.status.code(), Some(3), "{}", stderr(&o));
    assert!(stderr(&o).contains("nothing selected"), "{}", stderr(&o));
    let candidates: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("candidates.json")).unwrap()).unwrap();
    for c in candidates.as_array().unwrap() {
        assert_eq!(c["feasible"], false);
        assert_eq!(c["failure"]["reason"], "unreachable");
        assert_eq!(c["failure"]["sample"], 0);
    }
    let summary: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("summary.json")).unwrap()).unwrap();
    assert!(summary["arms"][0]["selected"].is_null());
    assert_eq!(summary["nothing_selected"], true);
    // --allow-empty: exit 0 with the same files (--force replaces the first run's folder).
    let o = graspath(
        &[
            "select",
            "--task",
            task.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--quiet",
            "--force",
            "--allow-empty",
        ],
        None,
        None,
    );
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let again: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(again, summary);
}

#[test]
fn every_example_task_loads_and_the_demo_runs() {
    let examples = repo_root().join("examples");
    for entry in std::fs::read_dir(&examples).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "yaml") {
            graspath::task::Task::load(&path).unwrap_or_else(|e| panic!("{e}"));
        }
    }
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("demo");
    let o = graspath(&["demo", "--out", out.to_str().unwrap()], None, None);
    assert!(o.status.success(), "{}", stderr(&o));
    let findings: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("findings.json")).unwrap()).unwrap();
    assert_eq!(findings.as_array().unwrap().len(), 6);
    // Both readings of every task: norms over every sample as the file says, and over the
    // paper's waypoints (initial pose and each step's end: steps + 1 samples).
    for (finding, name) in findings.as_array().unwrap().iter().zip([
        "pick_and_place_left",
        "pick_and_place_both",
        "pick_rotate_place_both",
        "t_shape_rotate",
        "t_shape_move",
        "t_shape_move_rotate",
    ]) {
        let file = graspath::task::TaskFile::load(&examples.join(format!("{name}.yaml"))).unwrap();
        let steps = file.trajectory.steps.len();
        let waypoints = finding["ours_at_waypoints"]["sampling"].as_str().unwrap();
        assert!(
            waypoints.starts_with(&format!("waypoints: {} of ", steps + 1)),
            "{name}: {waypoints}"
        );
        assert!(finding["ours"]["sampling"]
            .as_str()
            .unwrap()
            .starts_with("dense"));
        assert!(finding["ours_at_waypoints"]["arms"].as_array().is_some());
    }
    assert!(out.join("pick_and_place_both/pairs.json").is_file());
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(stdout.contains("paper:") && stdout.contains("ours:"));
    readme_table_matches(&findings);
    readme_placements_match(&findings);
    readme_heavy_matches(&findings[0]["heavy"]);
    readme_figures_match(&out);
}

/// The README's "The same bar, heavier" table and statements against `findings.json`'s
/// `heavy` (the cuboid Pick-and-Place with the bar given a mass), and the finding's own
/// consistency: the failures per joint add up, the first mass with nothing feasible is named.
fn readme_heavy_matches(heavy: &serde_json::Value) {
    let readme = std::fs::read_to_string(repo_root().join("README.md")).unwrap();
    let section = &readme[readme.find("### The same bar, heavier").unwrap()..];
    let section = &section[..section.find("\n### ").unwrap()];
    let masses = heavy["masses"].as_array().unwrap();
    let mut first_empty = None;
    for m in masses {
        let joints = m["out_of_torque_at"].as_object().unwrap();
        let total: u64 = joints.values().map(|n| n.as_u64().unwrap()).sum();
        assert_eq!(total, m["torque_limit"].as_u64().unwrap());
        let feasible = m["feasible"].as_u64().unwrap();
        if feasible == 0 && first_empty.is_none() {
            first_empty = m["mass_kg"].as_f64();
        }
        let name = |key: &str| m[key].as_str().unwrap_or("none").to_string();
        let joint_text: Vec<String> = joints.iter().map(|(j, n)| format!("`{j}` ×{n}")).collect();
        let capacity = match m["largest_capacity"].as_object() {
            Some(c) => format!(
                "{:.2} (`{}`)",
                c["kg"].as_f64().unwrap(),
                c["label"].as_str().unwrap()
            ),
            None => "–".into(),
        };
        let row = format!(
            "| {} | {feasible} | {} ({}) | `{}` | `{}` | {capacity} |",
            m["mass_kg"].as_f64().unwrap(),
            m["torque_limit"],
            joint_text.join(", "),
            name("best"),
            name("best_by_dynamic_manipulability"),
        );
        assert!(section.contains(&row), "the README lacks the row {row}");
        if feasible > 0 {
            // "picks another contact than the kinematic index at every mass"
            assert_ne!(name("best"), name("best_by_dynamic_manipulability"));
            // "with any mass that grasp fails"
            assert_eq!(m["best_without_mass_feasible"], serde_json::json!(false));
        }
        // "every failure is the shoulder's"
        assert!(joints.keys().all(|j| j == "left_s1"), "{joints:?}");
    }
    assert_eq!(heavy["nothing_feasible_from_kg"].as_f64(), first_empty);
    let from = format!(
        "from {} kg no contact can do the task",
        first_empty.unwrap()
    );
    assert!(section.contains(&from), "the README lacks: {from}");
    let best = format!(
        "the index picks `{}`",
        heavy["best_without_mass"].as_str().unwrap()
    );
    assert!(section.contains(&best), "the README lacks: {best}");
    let moves = format!(
        "The best grasp moves from {} kg on",
        heavy["best_moves_at_kg"].as_f64().unwrap()
    );
    assert!(section.contains(&moves), "the README lacks: {moves}");
}

/// The figures the README and docs/report.md show (`docs/images/`) are the demo's, byte for
/// byte: a change that alters a figure must regenerate the shown copy.
fn readme_figures_match(demo: &Path) {
    let readme = std::fs::read_to_string(repo_root().join("README.md")).unwrap();
    let report_doc = std::fs::read_to_string(repo_root().join("docs/report.md")).unwrap();
    for (image, shown_in, from_demo) in [
        (
            "mt-heatmap-left.png",
            &readme,
            "pick_and_place_left/mt-heatmap-left.png",
        ),
        (
            "classical-indices-left.png",
            &report_doc,
            "pick_and_place_left/classical-indices-left.png",
        ),
        (
            "pairs-heatmap-rotate.png",
            &report_doc,
            "pick_rotate_place_both/pairs-heatmap.png",
        ),
    ] {
        let path = format!("docs/images/{image}");
        assert!(
            shown_in.contains(&format!("images/{image}")),
            "{path} is not shown"
        );
        let shown = std::fs::read(repo_root().join(&path)).unwrap();
        let made = std::fs::read(demo.join(from_demo)).unwrap();
        assert!(
            shown == made,
            "{path} differs from the demo's {from_demo}: copy it from `graspath demo`'s output"
        );
    }
}

/// The `code` spans of `line` after `marker`.
fn code_spans_after(line: &str, marker: &str) -> Vec<String> {
    line[line.find(marker).unwrap()..]
        .split('`')
        .skip(1)
        .step_by(2)
        .map(str::to_string)
        .collect()
}

/// A placement `[x, y]` of `findings.json` as the README prints it.
fn placement_text(p: &serde_json::Value) -> String {
    format!(
        "({:.2}, {:.2})",
        p[0].as_f64().unwrap(),
        p[1].as_f64().unwrap()
    )
}

/// The README's "where the findings hold" lists and the measured mechanism against
/// `findings.json`: per figure the placements where the finding holds and reverses, the verdict
/// at the task's own placement and the placement where it holds with the largest μ_l2 spread;
/// every cuboid arm's mechanism sentence quoted verbatim.
fn readme_placements_match(findings: &serde_json::Value) {
    let readme = std::fs::read_to_string(repo_root().join("README.md")).unwrap();
    let line_of = |figure: &str, marker: &str| {
        readme
            .lines()
            .find(|l| l.contains(&format!("{figure} ")) && l.contains(marker))
            .unwrap_or_else(|| panic!("no README line for {figure} {marker}"))
            .to_string()
    };
    for (figure, experiment) in [
        ("Fig. 5, 6", "pick_and_place_left"),
        ("Fig. 7", "pick_and_place_both"),
        ("Fig. 9", "pick_rotate_place_both"),
        ("Fig. 10 c, d", "t_shape_rotate"),
        ("Fig. 10 e, f", "t_shape_move"),
        ("Fig. 10 g, h", "t_shape_move_rotate"),
    ] {
        let map = &findings
            .as_array()
            .unwrap()
            .iter()
            .find(|f| f["experiment"] == experiment)
            .unwrap()["where_it_holds"];
        for (marker, key) in [("Holds at:", "holds_at"), ("reverses at:", "reverses_at")] {
            let quoted = code_spans_after(&line_of(figure, marker), marker);
            let expected: Vec<String> = map[key]
                .as_array()
                .unwrap()
                .iter()
                .map(placement_text)
                .collect();
            assert_eq!(quoted, expected, "README: {figure} {marker}");
        }
        let marker = "at the task's placement";
        let own = &map["at_the_task_placement"];
        let mut expected = vec![
            placement_text(&own["at"]),
            own["finding"].as_str().unwrap().to_string(),
        ];
        if let Some(strongest) = map["reproduced_at"].as_object() {
            expected.push(placement_text(&strongest["at"]));
            expected.extend(
                strongest["mu_l2_spread_percent"]
                    .as_array()
                    .unwrap()
                    .iter()
                    .map(|s| format!("{:.1} %", s.as_f64().unwrap())),
            );
        }
        let quoted = code_spans_after(&line_of(figure, marker), marker);
        assert_eq!(quoted, expected, "README: {figure} {marker}");
        for arm in map["mechanism"]["arms"].as_array().into_iter().flatten() {
            let words = arm["in_words"].as_str().unwrap();
            assert!(
                readme.contains(&format!("`{words}`")),
                "README does not quote the measured mechanism of {experiment}: {words}"
            );
        }
    }
}

/// What one row of the README's table of findings quotes, read from `findings.json`.
#[derive(Clone, Copy)]
enum Quote {
    /// The best candidate of the (first) arm and the candidates tied with it.
    Best,
    /// The candidates Yoshikawa's index and the inverse condition number pick at the grasp.
    Classical,
    /// Yoshikawa's pick alone.
    Yoshikawa,
    /// The best pair's two candidates.
    Pair,
    /// `F of C` feasible of the last arm.
    Feasible,
    /// The μ_l2 spread of the first arm.
    Spread,
}

/// The values (`code` spans) that a README cell must quote for `quotes` of one reading.
fn quoted(reading: &serde_json::Value, quotes: &[Quote]) -> std::collections::BTreeSet<String> {
    let arms = reading["arms"].as_array().unwrap();
    let text = |v: &serde_json::Value| v.as_str().unwrap().to_string();
    let mut out = std::collections::BTreeSet::new();
    for quote in quotes {
        match quote {
            Quote::Best => {
                // The best and every candidate tied with it.
                out.insert(text(&arms[0]["best_task_relevant"]));
                out.extend(
                    arms[0]["best_tied_with"]
                        .as_array()
                        .unwrap()
                        .iter()
                        .map(text),
                );
            }
            Quote::Classical => {
                out.insert(text(&arms[0]["best_yoshikawa_at_grasp"]));
                out.insert(text(&arms[0]["best_inverse_condition_at_grasp"]));
            }
            Quote::Yoshikawa => {
                out.insert(text(&arms[0]["best_yoshikawa_at_grasp"]));
            }
            Quote::Pair => {
                let pair = &reading["best_pair"];
                out.insert(text(&pair["left"]));
                out.insert(text(&pair["right"]));
            }
            Quote::Feasible => {
                for arm in arms.iter().skip(arms.len() - 1) {
                    out.insert(format!("{} of {}", arm["feasible"], arm["candidates"]));
                }
            }
            Quote::Spread => {
                out.insert(text(&arms[0]["mu_l2_spread"]));
            }
        }
    }
    out
}

/// The README's table of the paper's experiments quotes what the demo finds, cell by cell.
fn readme_table_matches(findings: &serde_json::Value) {
    use Quote::*;
    let readme = std::fs::read_to_string(repo_root().join("README.md")).unwrap();
    // (the row's figure, the experiment, what the dense column quotes, what the waypoint
    // column quotes)
    let rows: [(&str, &str, &[Quote], &[Quote]); 7] = [
        (
            "(Fig. 5, 6)",
            "pick_and_place_left",
            &[Best, Feasible, Spread],
            &[Best, Spread],
        ),
        ("(Fig. 8)", "pick_and_place_left", &[Classical], &[]),
        (
            "(Fig. 7)",
            "pick_and_place_both",
            &[Pair, Feasible],
            &[Pair],
        ),
        (
            "(Fig. 9)",
            "pick_rotate_place_both",
            &[Pair, Feasible],
            &[Pair],
        ),
        (
            "(Fig. 10 c, d)",
            "t_shape_rotate",
            &[Best, Yoshikawa, Spread],
            &[Best, Spread],
        ),
        (
            "(Fig. 10 e, f)",
            "t_shape_move",
            &[Best, Yoshikawa, Spread],
            &[Best, Spread],
        ),
        (
            "(Fig. 10 g, h)",
            "t_shape_move_rotate",
            &[Best, Yoshikawa, Spread],
            &[Best, Spread],
        ),
    ];
    let code_spans = |cell: &str| -> std::collections::BTreeSet<String> {
        cell.split('`')
            .skip(1)
            .step_by(2)
            .map(str::to_string)
            .collect()
    };
    for (figure, experiment, dense, waypoints) in rows {
        let line = readme
            .lines()
            .find(|l| l.starts_with("| ") && l.contains(figure))
            .unwrap_or_else(|| panic!("no README row for {figure}"));
        let cells: Vec<&str> = line.split('|').map(str::trim).collect();
        let finding = findings
            .as_array()
            .unwrap()
            .iter()
            .find(|f| f["experiment"] == experiment)
            .unwrap();
        assert_eq!(
            code_spans(cells[3]),
            quoted(&finding["ours"], dense),
            "README row {figure}, every sample"
        );
        assert_eq!(
            code_spans(cells[4]),
            quoted(&finding["ours_at_waypoints"], waypoints),
            "README row {figure}, waypoints"
        );
    }
}

/// `--xacro-arg` and `--search-path` reach the xacro program (a stand-in that records its
/// arguments and environment); a file not named *.xacro is never handed to it.
#[cfg(unix)]
#[test]
fn xacro_arguments_and_search_paths_reach_the_xacro_program() {
    use std::os::unix::fs::PermissionsExt;
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join("log");
    let urdf = r#"<robot name="r"><link name="base"/><joint name="j" type="revolute"><parent link="base"/><child link="tip"/><origin xyz="0.5 0 0"/><axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint><link name="tip"/></robot>"#;
    let stand_in = write(
        dir.path(),
        "xacro-stand-in",
        &format!(
            "#!/bin/sh\n{{ for a in \"$@\"; do echo \"arg=$a\"; done; export -p; }} > '{}'\necho '{urdf}'\n",
            log.display()
        ),
    );
    std::fs::set_permissions(&stand_in, std::fs::Permissions::from_mode(0o755)).unwrap();
    let xacro = write(dir.path(), "arm.urdf.xacro", "<robot/>");
    let share = dir.path().join("share");
    let run = |file: &Path, extra: &[&str]| {
        let mut command = Command::new(env!("CARGO_BIN_EXE_graspath"));
        command
            .args(["kinematics", "--urdf"])
            .arg(file)
            .args(["--base", "base", "--tip", "tip"])
            .args(extra)
            .env("GRASPATH_XACRO", &stand_in)
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped());
        command.output().unwrap()
    };
    let o = run(
        &xacro,
        &[
            "--xacro-arg",
            "reach:=0.65",
            "--xacro-arg",
            "side:=left",
            "--search-path",
            share.to_str().unwrap(),
        ],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let record = std::fs::read_to_string(&log).unwrap();
    assert!(
        record.contains("arg=reach:=0.65\narg=side:=left\n"),
        "{record}"
    );
    assert!(
        record.contains(&format!("search\t{}", share.display())),
        "{record}"
    );
    let o = run(&xacro, &["--xacro-arg", "reach=0.65"]);
    assert_eq!(o.status.code(), Some(2));
    assert_clean_failure(&o, &["--xacro-arg", "NAME:=VALUE"]);
    // A plain URDF with xacro markup is refused, and nothing runs.
    std::fs::remove_file(&log).unwrap();
    let markup = write(
        dir.path(),
        "arm.urdf",
        r#"<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro"><xacro:include filename="x.xacro"/></robot>"#,
    );
    let o = run(&markup, &[]);
    assert_eq!(o.status.code(), Some(2));
    assert_clean_failure(&o, &["arm.urdf:1: uses xacro markup", "*.xacro"]);
    assert!(!log.exists());
    let o = run(&markup, &["--xacro-arg", "a:=1"]);
    assert_clean_failure(&o, &["xacro argument 'a'", "only a file named *.xacro"]);
}

/// A run stopped by SIGTERM or SIGINT part-way through a streamed selection removes its
/// temporary folder, writes nothing, and exits with 128 + the signal's number; a folder being
/// replaced with `--force` is still there, unchanged.
#[cfg(unix)]
#[test]
fn a_signal_leaves_no_temporary_output_behind() {
    let dir = tempfile::tempdir().unwrap();
    let task = write(
        dir.path(),
        "faces.yaml",
        &std::fs::read_to_string(repo_root().join("examples/workload_1000_faces.yaml"))
            .unwrap()
            .replace("count: 1000", "count: 1000000"),
    );
    let previous = dir.path().join("out");
    std::fs::create_dir(&previous).unwrap();
    write(&previous, "summary.json", "{\"earlier\": true}");
    for (signal, code) in [("TERM", 143), ("INT", 130)] {
        let mut child = Command::new(env!("CARGO_BIN_EXE_graspath"))
            .args([
                "select",
                "--task",
                task.to_str().unwrap(),
                "--format",
                "jsonl",
            ])
            .args(["--out", previous.to_str().unwrap(), "--force", "--quiet"])
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let temporary = || {
            std::fs::read_dir(dir.path())
                .unwrap()
                .filter_map(Result::ok)
                .any(|e| e.file_name().to_string_lossy().contains(".graspath-"))
        };
        // Wait until the temporary folder exists (the selection has started writing).
        let started = std::time::Instant::now();
        while !temporary() {
            assert!(
                child.try_wait().unwrap().is_none(),
                "the run ended before it wrote anything"
            );
            assert!(
                started.elapsed().as_secs() < 120,
                "no temporary folder appeared"
            );
            std::thread::sleep(std::time::Duration::from_millis(5));
        }
        let killed = Command::new("kill")
            .args([format!("-{signal}"), child.id().to_string()])
            .status()
            .unwrap();
        assert!(killed.success());
        let output = child.wait_with_output().unwrap();
        assert_eq!(output.status.code(), Some(code), "{}", stderr(&output));
        assert!(
            stderr(&output).contains("stopped by a signal"),
            "{}",
            stderr(&output)
        );
        assert!(!temporary(), "a temporary entry is left after SIG{signal}");
        let names: Vec<String> = std::fs::read_dir(&previous)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        assert_eq!(names, ["summary.json"], "the earlier output was touched");
    }
}

/// The semantic mistakes a user makes in a well-formed task file: each is a warning on
/// stderr naming the file and the field, and in `summary.json`; the run goes on (a deliberate
/// value goes through) and exits as it would without the warning.
#[test]
fn well_formed_but_implausible_values_are_warned_about_by_field() {
    let dir = tempfile::tempdir().unwrap();
    let pose = "xyz: [0.75, 0.0, -0.10]";
    let table: [(&str, String, &str, &str); 6] = [
        (
            "degrees in a radians field",
            SMALL_TASK.replace(pose, &format!("{pose}, rpy: [0, 0, 45]")),
            "object.pose.rpy",
            "looks like degrees",
        ),
        (
            "radians in a degrees field",
            SMALL_TASK.replace("{ move: [0, 0.3, 0] }", "{ rotate: { angle_deg: 1.5708 } }"),
            "trajectory.steps[1].rotate.angle_deg",
            "looks like radians",
        ),
        (
            "millimetres",
            SMALL_TASK.replace("{ lift: 0.2 }", "{ lift: 200 }"),
            "trajectory.steps[0].lift",
            "looks like millimetres",
        ),
        (
            "a quaternion written w, x, y, z",
            SMALL_TASK.replace(pose, &format!("{pose}, quaternion: [1, 0, 0, 0]")),
            "object.pose.quaternion",
            "[x, y, z, w]",
        ),
        (
            "a joint step over a quarter turn",
            format!("{SMALL_TASK}ik: {{ max_joint_step: 30 }}\n"),
            "ik.max_joint_step",
            "more than a quarter turn",
        ),
        (
            "an object starting inside the table",
            format!("{SMALL_TASK}scene: {{ table: {{ height: -0.10 }} }}\n"),
            "object.pose",
            "50.0 mm inside the table",
        ),
    ];
    for (i, (what, text, field, message)) in table.iter().enumerate() {
        let task = write(dir.path(), &format!("task{i}.yaml"), text);
        let out = dir.path().join(format!("out{i}"));
        let o = select(&task, &out, &["--quiet", "--allow-empty"]);
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(0), "{what}: {err}");
        let line = format!("graspath: warning: {}: {field}: ", task.display());
        assert!(err.contains(&line), "{what}: no '{line}' in {err}");
        assert!(err.contains(message), "{what}: no '{message}' in {err}");
        let summary: serde_json::Value =
            serde_json::from_slice(&std::fs::read(out.join("summary.json")).unwrap()).unwrap();
        let warnings = summary["warnings"]
            .as_array()
            .expect("warnings in summary.json");
        assert!(
            warnings.iter().any(|w| w["field"] == *field),
            "{what}: {warnings:?}"
        );
    }
    // The plain task has none, and its summary no `warnings` key.
    let task = write(dir.path(), "plain.yaml", SMALL_TASK);
    let out = dir.path().join("plain");
    let o = select(&task, &out, &["--quiet"]);
    assert!(!stderr(&o).contains("warning"), "{}", stderr(&o));
    let summary: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("summary.json")).unwrap()).unwrap();
    assert!(summary.get("warnings").is_none());
}

/// The summary table's `limit` column is each listed grasp's `limit_distance_min` from
/// `candidates.json`, and the warning appears exactly when the selected grasp comes within
/// 0.02 rad of a joint limit (the faces workload's best rides one when planned up to the
/// limits, not with the default `ik.limit_margin`; the paper's cuboid task's does not).
#[test]
fn the_table_shows_how_close_each_grasp_comes_to_a_limit_and_warns_for_the_selected() {
    let dir = tempfile::tempdir().unwrap();
    let faces = std::fs::read_to_string(repo_root().join("examples/workload_1000_faces.yaml"))
        .unwrap()
        .replace("count: 1000", "count: 200");
    let at_limits = write(
        dir.path(),
        "faces_at_limits.yaml",
        &format!("{faces}ik: {{ limit_margin: 0 }}\n"),
    );
    let faces = write(dir.path(), "faces.yaml", &faces);
    let cuboid = repo_root().join("examples/pick_and_place_left.yaml");
    for (k, (task, warned)) in [(at_limits, true), (faces, false), (cuboid, false)]
        .into_iter()
        .enumerate()
    {
        let out = dir.path().join(format!("out{k}"));
        let o = select(&task, &out, &[]);
        assert!(o.status.success(), "{}", stderr(&o));
        let text = format!("{}{}", String::from_utf8_lossy(&o.stdout), stderr(&o));
        let records: serde_json::Value =
            serde_json::from_slice(&std::fs::read(out.join("candidates.json")).unwrap()).unwrap();
        let limit_of = |id: u64| {
            records
                .as_array()
                .unwrap()
                .iter()
                .find(|r| r["id"] == id)
                .unwrap()["limit_distance_min"]
                .as_f64()
                .unwrap()
        };
        let header = text
            .lines()
            .position(|l| l.trim_start().starts_with("rank"))
            .unwrap();
        assert!(text
            .lines()
            .nth(header)
            .unwrap()
            .trim_end()
            .ends_with("limit"));
        let rows: Vec<&str> = text
            .lines()
            .skip(header + 1)
            .take_while(|l| l.starts_with("      "))
            .collect();
        assert!(!rows.is_empty(), "{text}");
        for row in &rows {
            let fields: Vec<&str> = row.split_whitespace().collect();
            let id: u64 = fields[1].parse().unwrap();
            let shown = fields.last().unwrap();
            assert_eq!(*shown, format!("{:.4}", limit_of(id)), "{row}");
        }
        let best: u64 = rows[0].split_whitespace().nth(1).unwrap().parse().unwrap();
        assert_eq!(limit_of(best) <= 0.02, warned, "{text}");
        let warning = format!("warning: the selected grasp (id {best}) comes within");
        assert_eq!(text.contains(&warning), warned, "{text}");
    }
}

/// With `ik.redundancy: optimize` the terminal reports the selected grasp's `μ_l2` spread over
/// its self-motion: the numbers of its `self_motion` record in `candidates.json`.
#[test]
fn the_selected_grasps_self_motion_spread_is_reported() {
    let dir = tempfile::tempdir().unwrap();
    let faces = std::fs::read_to_string(repo_root().join("examples/workload_1000_faces.yaml"))
        .unwrap()
        .replace("count: 1000", "count: 100");
    let task = write(
        dir.path(),
        "faces.yaml",
        &format!("{faces}ik: {{ redundancy: optimize }}\n"),
    );
    let out = dir.path().join("out");
    let o = select(&task, &out, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = format!("{}{}", String::from_utf8_lossy(&o.stdout), stderr(&o));
    let summary: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("summary.json")).unwrap()).unwrap();
    let best = summary["arms"][0]["selected"]["id"].clone();
    let records: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("candidates.json")).unwrap()).unwrap();
    let record = records
        .as_array()
        .unwrap()
        .iter()
        .find(|r| r["id"] == best)
        .unwrap();
    let motion = &record["self_motion"];
    let (low, high, first) = (
        motion["mu_l2_min"].as_f64().unwrap(),
        motion["mu_l2_max"].as_f64().unwrap(),
        motion["mu_l2_first_branch"].as_f64().unwrap(),
    );
    assert!(low <= first + 1e-9 && first <= high + 1e-9, "{motion}");
    let expected = format!(
        "over its self-motion the selected grasp's mu_l2 spans {low:.4} to {high:.4} ({:.0} % of the largest; the first IK branch: {first:.4})",
        100.0 * (high - low) / high
    );
    assert!(text.contains(&expected), "{expected}\n{text}");
    // Without the self-motion search there is no such line.
    let plain = dir.path().join("plain");
    let o = select(
        &repo_root().join("examples/pick_and_place_left.yaml"),
        &plain,
        &[],
    );
    let text = format!("{}{}", String::from_utf8_lossy(&o.stdout), stderr(&o));
    assert!(!text.contains("over its self-motion"), "{text}");
}
