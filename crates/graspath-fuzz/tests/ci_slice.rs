//! The deterministic CI slice: every target, a fixed seed, each target's `ci_execs`
//! executions. Fails on any finding that `known::KNOWN_FINDINGS` does not list; prints the
//! known ones it tolerated, and the known entries it did not meet (candidates for removal once
//! their fixes are merged).

use graspath_fuzz::known::KNOWN_FINDINGS;
use graspath_fuzz::targets;
use std::process::Command;

#[test]
fn ci_slice_finds_nothing_unknown() {
    let findings = tempfile::tempdir().expect("temporary directory");
    let output = Command::new(env!("CARGO_BIN_EXE_graspath-fuzz"))
        .args([
            "--ci-slice",
            "--seed",
            "1",
            "--timeout-ms",
            "2000",
            "--minimise-seconds",
            "0",
        ])
        .arg("--findings")
        .arg(findings.path())
        .output()
        .expect("the fuzz binary runs");
    let stdout = String::from_utf8_lossy(&output.stdout);
    println!("{stdout}");
    // Exit code 1 means new findings; anything else but 0 is a harness failure.
    assert!(
        matches!(output.status.code(), Some(0) | Some(1)),
        "graspath-fuzz failed ({}): {}",
        output.status,
        String::from_utf8_lossy(&output.stderr)
    );
    let text = std::fs::read_to_string(findings.path().join("summary.json")).expect("summary.json");
    let summary: serde_json::Value = serde_json::from_str(&text).expect("summary is JSON");
    let reports = summary["targets"].as_array().expect("targets");
    // Nothing is skipped: every target ran its whole slice.
    assert_eq!(reports.len(), targets::all().len());
    for (report, target) in reports.iter().zip(targets::all()) {
        assert_eq!(report["target"], target.name);
        assert_eq!(
            report["execs"].as_u64(),
            Some(target.ci_execs),
            "{}",
            target.name
        );
    }
    let mut unknown = Vec::new();
    let mut met = Vec::new();
    for finding in reports
        .iter()
        .flat_map(|r| r["findings"].as_array().expect("findings"))
    {
        let line = format!(
            "{} {}: {} ({})",
            finding["target"].as_str().unwrap_or(""),
            finding["kind"].as_str().unwrap_or(""),
            finding["message"].as_str().unwrap_or(""),
            finding["reproducer"].as_str().unwrap_or("")
        );
        match finding["known"]["issue"].as_str() {
            Some(issue) => {
                println!("tolerated known finding [{issue}]: {line}");
                met.push((
                    finding["known"]["target"]
                        .as_str()
                        .unwrap_or("")
                        .to_string(),
                    finding["known"]["fragment"]
                        .as_str()
                        .unwrap_or("")
                        .to_string(),
                ));
            }
            None => unknown.push(line),
        }
    }
    for k in KNOWN_FINDINGS {
        if !met.iter().any(|(t, f)| t == k.target && f == k.fragment) {
            println!(
                "known finding not met by this slice: {} '{}' [{}]",
                k.target, k.fragment, k.issue
            );
        }
    }
    assert!(
        unknown.is_empty(),
        "new fuzz findings:\n{}",
        unknown.join("\n")
    );
}
