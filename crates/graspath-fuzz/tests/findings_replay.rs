//! Every reproducer the long fuzz runs found (`findings/<target>/*.min.*`, described in
//! `TESTING.md`) replays without a finding: no panic, no hang, no allocation beyond the bounds.
//! Each runs in its own process, as the fuzzer replays it.

use std::path::PathBuf;
use std::process::Command;

#[test]
fn every_recorded_finding_is_fixed() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("findings");
    let mut replayed = 0;
    let mut failures = Vec::new();
    let death = tempfile::tempdir().unwrap();
    for target in std::fs::read_dir(&root).unwrap() {
        let target = target.unwrap().path();
        let name = target.file_name().unwrap().to_string_lossy().into_owned();
        for file in std::fs::read_dir(&target).unwrap() {
            let file = file.unwrap().path();
            let path = file.to_string_lossy();
            if !path.contains(".min.") || path.ends_with(".current") {
                continue;
            }
            let out = death.path().join(format!("death-{replayed}"));
            let status = Command::new(env!("CARGO_BIN_EXE_graspath-fuzz"))
                .args(["--target", &name, "--replay"])
                .arg(&file)
                .arg("--death")
                .arg(&out)
                .status()
                .unwrap();
            replayed += 1;
            if !status.success() {
                let what = std::fs::read_to_string(&out).unwrap_or_default();
                failures.push(format!("{}: {status}: {what}", file.display()));
            }
        }
    }
    assert!(replayed >= 40, "the reproducers are there ({replayed})");
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
