//! `graspath select --report`: the figures and `report.html` are written beside the JSON, the
//! same input gives the same bytes, `--quiet` prints nothing and `--json` prints the summary.

use serde_json::Value;
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
    let summary: Value = serde_json::from_slice(&output.stdout).expect("--json prints JSON");
    assert_eq!(summary["arms"][0]["arm"], "left");
    assert!(dir.path().join("summary.json").is_file());
    assert!(!dir.path().join("report.html").exists());
}

/// The 3D view's data embedded in `report.html` (`<script type="application/json" id="data">`).
fn embedded_data(html: &str) -> Value {
    let open = "<script type=\"application/json\" id=\"data\">";
    let start = html.find(open).expect("the view's data") + open.len();
    let end = start + html[start..].find("</script>").expect("a closed script");
    serde_json::from_str(&html[start..end]).expect("the view's data is JSON")
}

/// The points of a written `JointTrajectory`: time from the start (s) and positions.
fn written_points(trajectory: &Value) -> Vec<(f64, Vec<f64>)> {
    let number = |v: &Value| v.as_f64().unwrap();
    trajectory["points"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| {
            let t = &p["time_from_start"];
            let time = number(&t["sec"]) + 1e-9 * number(&t["nanosec"]);
            let q = p["positions"].as_array().unwrap().iter().map(number);
            (time, q.collect())
        })
        .collect()
}

/// When the written trajectory `points` passes through configuration `q`, from point `from`
/// on: along the straight segments between consecutive points (the positions interpolated
/// linearly), the first local closest approach within `tolerance` (rad) of `q`; its time (s)
/// and the segment's first point.
fn passing_time(
    points: &[(f64, Vec<f64>)],
    q: &[f64],
    from: usize,
    tolerance: f64,
) -> Option<(f64, usize)> {
    let closest = |k: usize| {
        let ((t0, a), (t1, b)) = (&points[k], &points[k + 1]);
        let d: Vec<f64> = b.iter().zip(a).map(|(b, a)| b - a).collect();
        let length2: f64 = d.iter().map(|x| x * x).sum();
        let along: f64 = q.iter().zip(a).zip(&d).map(|((q, a), d)| (q - a) * d).sum();
        let lambda = if length2 > 0.0 {
            (along / length2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let distance = q
            .iter()
            .zip(a)
            .zip(&d)
            .map(|((q, a), d)| (a + lambda * d - q).powi(2))
            .sum::<f64>()
            .sqrt();
        (distance, t0 + lambda * (t1 - t0))
    };
    let mut k = (from..points.len() - 1).find(|&k| closest(k).0 <= tolerance)?;
    while k + 2 < points.len() && closest(k + 1).0 < closest(k).0 {
        k += 1;
    }
    Some((closest(k).1, k))
}

/// A record's joint configurations along its whole motion: approach, path, retreat.
fn whole_motion(record: &Value) -> Vec<Vec<f64>> {
    [
        "approach_trajectory",
        "joint_trajectory",
        "retreat_trajectory",
    ]
    .iter()
    .filter_map(|key| record[key].as_array())
    .flatten()
    .map(|q| {
        q.as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_f64().unwrap())
            .collect()
    })
    .collect()
}

/// The largest difference (s) between the times `times` at which the view has a motion reach
/// its samples `samples` and the times at which the written trajectory passes through them
/// (within `tolerance` rad), and the sample where it is largest.
fn worst_passing(
    times: &[f64],
    samples: &[Vec<f64>],
    points: &[(f64, Vec<f64>)],
    tolerance: f64,
) -> (f64, usize) {
    let mut from = 0;
    let mut worst = (0.0, 0);
    for (k, (t, q)) in times.iter().zip(samples).enumerate() {
        let (written, at) = passing_time(points, q, from, tolerance)
            .unwrap_or_else(|| panic!("the written trajectory misses sample {k}"));
        from = at;
        if (written - t).abs() > worst.0 {
            worst = ((written - t).abs(), k);
        }
    }
    worst
}

/// A stand-in for the cuboid's pick-and-place with the object held still before the place.
const STILL: &str = "pick_and_place_left.yaml, held still";

/// The view's motions are timed as `graspath select` times them: for every candidate with a
/// motion, its times start at 0, grow from each IK sample to the next (equal only where two
/// samples coincide) and end at the candidate's `duration` in `candidates.json`; the selected
/// motions (the best pair's on their shared timeline) pass through each IK sample at that
/// sample's time in the written `trajectory.json` (an independent check: the written
/// positions interpolated between its points).
#[test]
fn the_report_plays_the_motions_that_the_trajectory_files_hold() {
    for (task, period, near, tolerance) in [
        ("pick_and_place_left.yaml", "0", 1e-9, 2e-9),
        ("pick_and_place_both.yaml", "0", 1e-9, 2e-9),
        ("scene/pick_and_place_left_on_table.yaml", "0", 1e-9, 2e-9),
        ("pick_and_place_left.yaml", "0.01", 1e-3, 1e-3),
        (
            "scene/pick_and_place_left_on_table.yaml",
            "0.01",
            1e-3,
            1e-3,
        ),
        (STILL, "0", 1e-9, 2e-9),
        (STILL, "0.01", 1e-3, 1e-3),
    ] {
        let dir = tempfile::tempdir().unwrap();
        let out = &dir.path().join("out");
        let path = if task == STILL {
            // The cuboid's pick-and-place held still for 0.5 s before the place: its IK
            // samples there coincide, each pair merged into one knot of the timed path.
            let text = std::fs::read_to_string(example("pick_and_place_left.yaml"))
                .unwrap()
                .replace(
                    "    - { place: 0.2, label: place }",
                    "    - { move: [0, 0, 0], duration: 0.5, label: hold }\n    - { place: 0.2, label: place }",
                );
            let path = dir.path().join("still.yaml");
            std::fs::write(&path, text).unwrap();
            path
        } else {
            example(task)
        };
        graspath(&[
            "select",
            "--task",
            path.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--report",
            "--quiet",
            "--trajectory-period",
            period,
        ]);
        let data = embedded_data(&std::fs::read_to_string(out.join("report.html")).unwrap());
        let records = common::read_json(&out.join("candidates.json"));
        let written = common::read_json(&out.join("trajectory.json"));
        let n = data["times"].as_array().unwrap().len();
        let world = |key: &str| data["world"][key].as_u64().unwrap_or(0) as usize;
        let total = world("approach_samples") + n + world("retreat_samples");
        let (mut motions, mut repeated) = (0, 0);
        for arm in data["arms"].as_array().unwrap() {
            let name = arm["name"].as_str().unwrap();
            for result in arm["results"].as_array().unwrap() {
                let id = &data["candidates"][result["candidate"].as_u64().unwrap() as usize]["id"];
                let record = records
                    .as_array()
                    .unwrap()
                    .iter()
                    .find(|r| r["arm"] == name && r["id"] == *id)
                    .expect("a record of every result");
                assert_eq!(
                    result["duration"], record["duration"],
                    "{task}: {name} {id}"
                );
                if result["motion"].is_null() {
                    continue;
                }
                motions += 1;
                let times: Vec<f64> = result["motion"]["sample_times"]
                    .as_array()
                    .unwrap_or_else(|| panic!("{task}: {name} {id} has no sample times"))
                    .iter()
                    .map(|t| t.as_f64().unwrap())
                    .collect();
                let samples = whole_motion(record);
                assert_eq!((times.len(), samples.len()), (total, total), "{task}");
                repeated += (1..total).filter(|&k| samples[k] == samples[k - 1]).count();
                assert_eq!(times[0], 0.0, "{task}: {name} {id}");
                for k in 1..total {
                    if samples[k] == samples[k - 1] {
                        assert_eq!(times[k], times[k - 1], "{task}: {name} {id} sample {k}");
                    } else {
                        assert!(times[k] > times[k - 1], "{task}: {name} {id} sample {k}");
                    }
                }
                let duration = record["duration"].as_f64().unwrap();
                assert!(
                    (times[total - 1] - duration).abs() <= 1e-9,
                    "{task}: {name} {id}: ends at {} s, takes {duration} s",
                    times[total - 1]
                );
            }
        }
        assert!(motions > 0, "{task}: no motion in the view");
        assert_eq!(
            repeated > 0,
            task == STILL,
            "{task}: {repeated} repeated samples"
        );
        if let Some(pair) = data["pair_sample_times"].as_array() {
            // Each part of the motion takes the slower arm's time: the two end together.
            let end = |k: usize| {
                pair[k]
                    .as_array()
                    .unwrap()
                    .last()
                    .unwrap()
                    .as_f64()
                    .unwrap()
            };
            assert_eq!(end(0), end(1), "{task}");
        }
        // The selected motions: the best pair's shared timeline with two arms.
        for (k, arm) in written["arms"].as_array().unwrap().iter().enumerate() {
            let view = &data["arms"][k];
            let selected = match &data["pair"] {
                Value::Null => view["selected"].as_u64().unwrap(),
                pair => pair[k].as_u64().unwrap(),
            } as usize;
            let result = &view["results"][selected];
            let id = &data["candidates"][result["candidate"].as_u64().unwrap() as usize]["id"];
            assert_eq!(arm["candidate"], *id, "{task}");
            let times: Vec<f64> = match &data["pair_sample_times"] {
                Value::Null => &result["motion"]["sample_times"],
                pair => &pair[k],
            }
            .as_array()
            .unwrap()
            .iter()
            .map(|t| t.as_f64().unwrap())
            .collect();
            let record = records
                .as_array()
                .unwrap()
                .iter()
                .find(|r| r["arm"] == view["name"] && r["id"] == *id)
                .unwrap();
            let points = written_points(&arm["trajectory"]);
            let (worst, at) = worst_passing(&times, &whole_motion(record), &points, near);
            println!(
                "{task} at {period} s: {} off by {worst:.3e} s at sample {at}",
                view["name"]
            );
            assert!(
                worst <= tolerance,
                "{task}: {}'s sample {at} at {} s in the view, {worst} s off the written trajectory",
                view["name"],
                times[at]
            );
        }
    }
}

/// Every object key in `value`, recursively.
fn keys(value: &Value, into: &mut std::collections::BTreeSet<String>) {
    match value {
        Value::Object(map) => {
            for (key, v) in map {
                into.insert(key.clone());
                keys(v, into);
            }
        }
        Value::Array(items) => items.iter().for_each(|v| keys(v, into)),
        _ => {}
    }
}

/// `value` without the keys `names`, recursively.
fn without(value: &Value, names: &[&str]) -> Value {
    match value {
        Value::Object(map) => Value::Object(
            map.iter()
                .filter(|(key, _)| !names.contains(&key.as_str()))
                .map(|(key, v)| (key.clone(), without(v, names)))
                .collect(),
        ),
        Value::Array(items) => Value::Array(items.iter().map(|v| without(v, names)).collect()),
        other => other.clone(),
    }
}

/// With `timing: false` the view's data has no times of the motions and no durations, and is
/// otherwise the data of the same task timed (but for the task file's name): timing only adds `sample_times`, `duration` and
/// `pair_sample_times` (timing changes no candidate's feasibility or rank here).
#[test]
fn an_untimed_task_s_report_has_the_data_without_the_timing() {
    for name in ["pick_and_place_left.yaml", "pick_and_place_both.yaml"] {
        let dir = tempfile::tempdir().unwrap();
        let task = example(name);
        let untimed_task = dir.path().join(name);
        let text = std::fs::read_to_string(&task).unwrap() + "timing: false\n";
        std::fs::write(&untimed_task, text).unwrap();
        let data = |task: &Path, out: &str| {
            let out = dir.path().join(out);
            let (task, out) = (task.to_str().unwrap(), out.to_str().unwrap());
            graspath(&[
                "select", "--task", task, "--out", out, "--report", "--quiet",
            ]);
            let html = std::fs::read_to_string(Path::new(out).join("report.html")).unwrap();
            embedded_data(&html)
        };
        let (timed, untimed) = (data(&task, "timed"), data(&untimed_task, "untimed"));
        let timing = ["sample_times", "duration", "pair_sample_times"];
        let (mut with, mut plain) = Default::default();
        keys(&timed, &mut with);
        keys(&untimed, &mut plain);
        for key in timing {
            assert!(!plain.contains(key), "{name}: untimed data with '{key}'");
        }
        let added: Vec<&String> = with.difference(&plain).collect();
        let expected = if name.contains("both") {
            vec!["duration", "pair_sample_times", "sample_times"]
        } else {
            vec!["duration", "sample_times"]
        };
        assert_eq!(added, expected, "{name}");
        // The task's file name differs.
        let mut differing = timing.to_vec();
        differing.push("task");
        assert!(
            without(&timed, &differing) == without(&untimed, &["task"]),
            "{name}: the timed data differs from the untimed beyond the timing"
        );
    }
}
