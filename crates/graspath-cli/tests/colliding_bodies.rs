//! The summary names what the collisions hit: `summary.json`'s `colliding_bodies` per arm
//! against a tally of the collision failures in `candidates.json`, the same when the selection
//! is streamed, and the terminal's "most frequent collisions" line.

mod common;

use common::{example, read_json, read_lines, select, select_output};
use serde_json::Value;
use std::collections::BTreeMap;

/// Oracle: `[bodies, count]` of the collision failures among `records`, the most frequent
/// first, then by the bodies' names.
fn tally(records: &[Value]) -> Vec<(Vec<String>, u64)> {
    let mut counts: BTreeMap<Vec<String>, u64> = BTreeMap::new();
    for failure in records.iter().map(|r| &r["failure"]) {
        if failure["reason"] == "collision" {
            let bodies: Vec<String> = failure["bodies"]
                .as_array()
                .expect("a collision names its bodies")
                .iter()
                .map(|b| b.as_str().unwrap().to_string())
                .collect();
            *counts.entry(bodies).or_default() += 1;
        }
    }
    let mut pairs: Vec<(Vec<String>, u64)> = counts.into_iter().collect();
    pairs.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(&b.0)));
    pairs
}

fn summary_pairs(summary: &Value) -> Vec<(Vec<String>, u64)> {
    summary["arms"][0]["colliding_bodies"]
        .as_array()
        .map(|list| {
            list.iter()
                .map(|p| {
                    let bodies = p["bodies"]
                        .as_array()
                        .unwrap()
                        .iter()
                        .map(|b| b.as_str().unwrap().to_string())
                        .collect();
                    (bodies, p["candidates"].as_u64().unwrap())
                })
                .collect()
        })
        .unwrap_or_default()
}

#[test]
fn the_summary_counts_the_colliding_body_pairs_held_or_streamed() {
    let dir = tempfile::tempdir().unwrap();
    for (k, name) in [
        "scene/panda_shelf_pick.yaml",
        "scene/pick_and_place_left_cluttered.yaml",
    ]
    .into_iter()
    .enumerate()
    {
        let task = example(name);
        let held = dir.path().join(format!("held{k}"));
        select(&task, &held, &[], "2");
        let records = read_json(&held.join("candidates.json"));
        let expected = tally(records.as_array().unwrap());
        assert!(!expected.is_empty(), "{name}: no collision to count");
        let summary = read_json(&held.join("summary.json"));
        assert_eq!(summary_pairs(&summary), expected, "{name}");
        let total: u64 = expected.iter().map(|p| p.1).sum();
        assert_eq!(summary["arms"][0]["failures"]["collision"], total, "{name}");

        let streamed = dir.path().join(format!("streamed{k}"));
        select(&task, &streamed, &["--format", "jsonl"], "1");
        assert_eq!(
            tally(&read_lines(&streamed.join("candidates.jsonl"))),
            expected,
            "{name}"
        );
        let summary = read_json(&streamed.join("summary.json"));
        assert_eq!(summary_pairs(&summary), expected, "{name} streamed");

        // The terminal names the three most frequent.
        let shown = dir.path().join(format!("shown{k}"));
        let output = select_output(&task, &shown, &[], "2");
        let text = String::from_utf8_lossy(&output.stdout).to_string()
            + &String::from_utf8_lossy(&output.stderr);
        let line = text
            .lines()
            .find(|l| l.trim_start().starts_with("most frequent collisions:"))
            .unwrap_or_else(|| panic!("{name}: no collision line in {text}"));
        let listed: Vec<String> = expected
            .iter()
            .take(3)
            .map(|(b, n)| format!("{} – {} ({n})", b[0], b[1]))
            .collect();
        assert!(line.ends_with(&listed.join(", ")), "{name}: {line}");
    }
    // A task without collisions has no such key or line.
    let plain = dir.path().join("plain");
    select(&example("pick_and_place_left.yaml"), &plain, &[], "2");
    let summary = read_json(&plain.join("summary.json"));
    assert!(summary["arms"][0].get("colliding_bodies").is_none());
}
