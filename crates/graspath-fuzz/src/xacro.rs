//! The `xacro` target: the hand-off of robot files to the `xacro` program.
//!
//! An input is an optional first line `args: NAME=VALUE;NAME=VALUE...` (the xacro arguments)
//! and the robot file's text. Each input is loaded the way a task or the CLI loads a robot:
//!
//! * as `robot_under_test.urdf` through [`RobotSource::load`]: a file not named `*.xacro` is
//!   never expanded, whatever its text says; a load that fails with an error of the xacro
//!   *run* (the program missing, failing or unreadable) means it was handed to xacro, and is a
//!   finding;
//! * one input in [`EXPANDED_ONE_IN`] (chosen by a hash of its bytes, so a replay does the
//!   same) also as `robot_under_test.urdf.xacro`, expanded by a stand-in program
//!   ([`STAND_IN`]: it records its working folder and environment, then prints the file as its
//!   expansion) and parsed as URDF. The oracles: the program ran in a folder of its own, not
//!   the input's; its environment holds only the variables the hand-off passes; it did not
//!   run at all when the arguments were refused.

use crate::fixtures::{write_input as write, SMALL_ROBOT_URDF};
use graspath::robot::{
    expand_xacro_with, RobotError, RobotSource, UrdfRobot, XacroOptions, PASSED_ENVIRONMENT,
};
use std::collections::BTreeMap;
use std::path::Path;
use std::time::Duration;

/// One input in this many is also expanded by the stand-in program (a process start each).
const EXPANDED_ONE_IN: u64 = 64;

/// The most arguments taken from an input's first line (above the hand-off's own limit, so
/// that its check is reached).
const MAX_PARSED_ARGUMENTS: usize = 300;

/// The stand-in for `xacro`: writes its working folder and its environment (NUL-separated)
/// beside itself, then prints the file it was given as the expansion.
const STAND_IN: &str = "#!/bin/sh\n\
here=\"${0%/*}\"\n\
pwd > \"$here/xacro-ran-in\"\n\
env -0 > \"$here/xacro-ran-with\"\n\
exec cat \"$1\"\n";

/// Variables the shell itself sets in the stand-in's environment.
const SHELL_VARIABLES: [&str; 4] = ["PWD", "OLDPWD", "SHLVL", "_"];

/// Variables the hand-off adds to [`PASSED_ENVIRONMENT`].
const HAND_OFF_VARIABLES: [&str; 2] = ["PYTHONSAFEPATH", "GRASPATH_PACKAGE_ROOTS"];

/// Seeds: a URDF with xacro markup in an element, one with markup only in a comment, one
/// without markup, each with and without arguments, and arguments the hand-off refuses.
pub fn xacro_seeds() -> Vec<Vec<u8>> {
    let marked = SMALL_ROBOT_URDF.replace(
        "<link name=\"base\"/>",
        "<xacro:property name=\"reach\" value=\"0.4\"/>\n  <link name=\"base\"/>",
    );
    let commented = SMALL_ROBOT_URDF.replace(
        "<link name=\"base\"/>",
        "<!-- <xacro:include filename=\"/etc/passwd\"/> $(env HOME) -->\n  <link name=\"base\"/>",
    );
    let mut seeds = Vec::new();
    for body in [SMALL_ROBOT_URDF.to_string(), marked, commented] {
        for args in [
            "",
            "args: prefix=left_;reach=0.4\n",
            "args: 9bad=1;x=$(env HOME)\n",
        ] {
            seeds.push(format!("{args}{body}").into_bytes());
        }
    }
    seeds.push(format!("args: long={}\n{SMALL_ROBOT_URDF}", "v".repeat(5000)).into_bytes());
    seeds
}

/// The xacro arguments of an input's first line and the file's text.
fn split(bytes: &[u8]) -> (BTreeMap<String, String>, &[u8]) {
    let Some(rest) = bytes.strip_prefix(b"args: ") else {
        return (BTreeMap::new(), bytes);
    };
    let end = rest.iter().position(|&b| b == b'\n').unwrap_or(rest.len());
    let line = String::from_utf8_lossy(&rest[..end]);
    let args = line
        .split(';')
        .take(MAX_PARSED_ARGUMENTS)
        .map(|pair| match pair.split_once('=') {
            Some((name, value)) => (name.to_string(), value.to_string()),
            None => (pair.to_string(), String::new()),
        })
        .collect();
    (args, rest.get(end + 1..).unwrap_or_default())
}

/// FNV-1a of the input: which inputs are expanded.
fn fingerprint(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |hash, &b| {
        (hash ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// Whether `error` comes from running the xacro program (rather than from refusing to).
fn is_run_error(error: &RobotError) -> bool {
    matches!(
        error,
        RobotError::Xacro { .. } | RobotError::XacroFailed { .. } | RobotError::XacroIo { .. }
    )
}

/// Feeds one input (see the module documentation); `dir` is the worker's work directory.
pub fn run_xacro(dir: &Path, bytes: &[u8]) {
    let (args, body) = split(bytes);
    let urdf = write(dir, "robot_under_test.urdf", body);
    let loaded = RobotSource::urdf(&urdf)
        .with_urdf_options(Vec::new(), args.clone())
        .and_then(|source| source.load());
    if let Err(error) = &loaded {
        assert!(
            !is_run_error(error),
            "a file not named *.xacro was handed to xacro: {error}"
        );
    }
    if fingerprint(bytes).is_multiple_of(EXPANDED_ONE_IN) {
        expand_with_stand_in(dir, &args, body);
    }
}

/// Expands `body` as a `*.xacro` file with the stand-in program and checks where and how it
/// ran; returns whether it ran.
fn expand_with_stand_in(dir: &Path, args: &BTreeMap<String, String>, body: &[u8]) -> bool {
    let program = dir.join("xacro-stand-in");
    if !program.exists() {
        write_program(&program);
    }
    let (ran_in, ran_with) = (dir.join("xacro-ran-in"), dir.join("xacro-ran-with"));
    let _ = std::fs::remove_file(&ran_in);
    let _ = std::fs::remove_file(&ran_with);
    let file = write(dir, "robot_under_test.urdf.xacro", body);
    let options = XacroOptions {
        args: args.clone(),
        packages: None,
        timeout: Duration::from_secs(2),
    };
    let expanded = expand_xacro_with(&file, &program, &options);
    if let Ok(text) = &expanded {
        let _ = UrdfRobot::from_xml(text, "robot_under_test.urdf.xacro");
    }
    let Ok(folder) = std::fs::read_to_string(&ran_in) else {
        assert!(
            !matches!(expanded, Ok(_) | Err(RobotError::XacroFailed { .. })),
            "xacro's result came back but the stand-in did not record its run"
        );
        return false;
    };
    assert!(
        !matches!(expanded, Err(RobotError::XacroArgument { .. })),
        "xacro ran although its arguments were refused"
    );
    // The run's own folder is gone by now; the input's folder is not (compared by their
    // real paths, in case one is reached through a link).
    let folder = Path::new(folder.trim_end());
    let real = |path: &Path| path.canonicalize().unwrap_or_else(|_| path.to_path_buf());
    assert!(
        real(folder) != real(dir) && real(folder) != real(file.parent().unwrap_or(dir)),
        "xacro ran in the input's folder {}",
        folder.display()
    );
    let environment = std::fs::read(&ran_with).unwrap_or_default();
    for entry in environment.split(|&b| b == 0).filter(|e| !e.is_empty()) {
        let name = String::from_utf8_lossy(entry.split(|&b| b == b'=').next().unwrap_or(entry));
        let allowed = PASSED_ENVIRONMENT
            .iter()
            .chain(&HAND_OFF_VARIABLES)
            .chain(&SHELL_VARIABLES)
            .any(|passed| *passed == name);
        assert!(allowed, "xacro's environment holds the variable {name}");
    }
    true
}

/// Writes the stand-in program.
fn write_program(path: &Path) {
    use std::os::unix::fs::PermissionsExt;
    // A failed write shows up as an error of the run, which the oracles accept.
    let _ = std::fs::write(path, STAND_IN);
    let _ = std::fs::set_permissions(path, std::fs::Permissions::from_mode(0o755));
}

/// A generated input: arguments (well and badly named, long, with shell and xacro syntax) and a
/// URDF with xacro markup placed in an element, an attribute, a comment or CDATA.
pub fn xacro_document(rng: &mut crate::rng::Rng) -> Vec<u8> {
    const NAMES: [&str; 6] = ["prefix", "reach", "_x", "9bad", "a-b", ""];
    const VALUES: [&str; 6] = [
        "left_",
        "0.4",
        "$(env HOME)",
        "${__import__('os')}",
        "",
        "a;b",
    ];
    const MARKUP: [&str; 6] = [
        "<xacro:property name=\"p\" value=\"1\"/>",
        "<xacro:include filename=\"/etc/passwd\"/>",
        "<!-- <xacro:macro name=\"m\"/> -->",
        "<![CDATA[<xacro:arg name=\"a\"/>]]>",
        "<link name=\"${p}\"/>",
        "<xacro:if value=\"$(arg reach)\"><link name=\"extra\"/></xacro:if>",
    ];
    let mut text = String::new();
    if rng.chance(2, 3) {
        let pairs: Vec<String> = (0..1 + rng.below(4))
            .map(|_| format!("{}={}", rng.pick(&NAMES), rng.pick(&VALUES)))
            .collect();
        text.push_str(&format!("args: {}\n", pairs.join(";")));
    }
    let mut body = SMALL_ROBOT_URDF.to_string();
    for _ in 0..rng.below(3) {
        let markup = rng.pick(&MARKUP);
        body = body.replacen(
            "<link name=\"l1\"/>",
            &format!("{markup}\n  <link name=\"l1\"/>"),
            1,
        );
    }
    if rng.chance(1, 4) {
        body = body.replace("xmlns", "x").replace(
            "<robot ",
            "<robot xmlns:xacro=\"http://www.ros.org/wiki/xacro\" ",
        );
    }
    text.push_str(&body);
    text.into_bytes()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn arguments_come_from_the_first_line_only() {
        let (args, body) = split(b"args: a=1;b=x=y;c\n<robot/>");
        assert_eq!(args.get("a").map(String::as_str), Some("1"));
        assert_eq!(args.get("b").map(String::as_str), Some("x=y"));
        assert_eq!(args.get("c").map(String::as_str), Some(""));
        assert_eq!(body, b"<robot/>");
        let (args, body) = split(b"<robot/>\nargs: a=1");
        assert!(args.is_empty());
        assert_eq!(body, b"<robot/>\nargs: a=1");
    }

    /// The oracles can fail: a stand-in run in the input's folder, or with a secret in its
    /// environment, is reported.
    #[test]
    fn the_stand_in_records_its_folder_and_environment() {
        let temporary = tempfile::tempdir().unwrap();
        let dir = &temporary.path().canonicalize().unwrap();
        let program = dir.join("xacro-stand-in");
        write_program(&program);
        let file = write(dir, "r.urdf.xacro", SMALL_ROBOT_URDF.as_bytes());
        let out = std::process::Command::new(&program)
            .arg(&file)
            .current_dir(dir)
            .env("GRASPATH_FUZZ_SECRET", "s")
            .output()
            .unwrap();
        assert_eq!(out.stdout, SMALL_ROBOT_URDF.as_bytes());
        let folder = std::fs::read_to_string(dir.join("xacro-ran-in")).unwrap();
        assert_eq!(Path::new(folder.trim_end()), dir);
        let environment = std::fs::read(dir.join("xacro-ran-with")).unwrap();
        assert!(environment
            .split(|&b| b == 0)
            .any(|e| e == b"GRASPATH_FUZZ_SECRET=s"));
    }

    /// Through the hand-off the same stand-in runs elsewhere, with the passed variables only
    /// (this test process's own variables, `CARGO_*` and the rest, are not passed); refused
    /// arguments keep it from running.
    #[test]
    fn every_seed_passes_the_oracles() {
        let temporary = tempfile::tempdir().unwrap();
        let dir = temporary.path();
        let mut runs = [0, 0];
        let mut rng = crate::rng::Rng::new(3);
        let generated: Vec<Vec<u8>> = (0..20).map(|_| xacro_document(&mut rng)).collect();
        for input in xacro_seeds().iter().chain(&generated) {
            run_xacro(dir, input);
            let (args, body) = split(input);
            runs[usize::from(expand_with_stand_in(dir, &args, body))] += 1;
        }
        assert!(runs[0] > 0 && runs[1] > 0, "runs refused / ran: {runs:?}");
    }
}
