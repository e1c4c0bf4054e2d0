//! xacro runs code, so graspath runs it only for files named `*.xacro`, and then confined:
//! the program configured or found on an absolute `PATH` entry (never a module or program
//! from the working folder), in a fresh working folder, with a cleared environment, its
//! process group stopped as a whole. These checks use stand-in `xacro` programs (shell
//! scripts) that record what they were given; the real xacro is tested in `tests/xacro.rs`.
//!
//! One test function: it changes the process's environment and working folder, which the
//! other tests of a binary would share.
#![cfg(unix)]

use graspath::robot::{expand_xacro_with, RobotError, RobotSource, UrdfRobot, XacroOptions};
use std::collections::BTreeMap;
use std::os::unix::fs::PermissionsExt;
use std::path::{Path, PathBuf};
use std::time::Duration;

/// A one-joint robot, the output of every stand-in program.
const URDF: &str = r#"<robot name="r"><link name="base"/><joint name="j" type="revolute"><parent link="base"/><child link="tip"/><axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint><link name="tip"/></robot>"#;

fn write(path: &Path, text: &str) -> PathBuf {
    std::fs::write(path, text).unwrap();
    path.to_path_buf()
}

fn program(path: &Path, script: &str) -> PathBuf {
    write(path, &format!("#!/bin/sh\n{script}"));
    std::fs::set_permissions(path, std::fs::Permissions::from_mode(0o755)).unwrap();
    path.to_path_buf()
}

/// The first of the usual places that has `name` (the stand-ins call it by path: the `PATH`
/// they see is the test's).
fn system_program(name: &str) -> PathBuf {
    ["/bin", "/usr/bin"]
        .iter()
        .map(|d| Path::new(d).join(name))
        .find(|p| p.is_file())
        .unwrap_or_else(|| panic!("no {name} in /bin or /usr/bin"))
}

/// Whether process `pid` is gone (or a zombie: ended, not yet reaped by its new parent).
fn ended(pid: &str) -> bool {
    match std::fs::read_to_string(format!("/proc/{}/stat", pid.trim())) {
        Err(_) => true,
        Ok(stat) => stat
            .rsplit_once(')')
            .is_some_and(|(_, rest)| rest.trim_start().starts_with(['Z', 'X'])),
    }
}

#[test]
fn xacro_runs_only_when_named_and_then_confined() {
    let dir = tempfile::tempdir().unwrap();
    let root = dir.path().canonicalize().unwrap();
    // The user's working folder holds a `xacro.py` module and a `xacro` program: neither may
    // ever run.
    let work = root.join("work");
    std::fs::create_dir(&work).unwrap();
    let ran_module = root.join("ran-module");
    let ran_local = root.join("ran-local-program");
    write(
        &work.join("xacro.py"),
        &format!(
            "open({:?}, 'w').write('x')\n",
            ran_module.display().to_string()
        ),
    );
    program(
        &work.join("xacro"),
        &format!("echo x > '{}'\n", ran_local.display()),
    );
    let files = root.join("robot");
    std::fs::create_dir(&files).unwrap();
    let xacro_file = write(
        &files.join("arm.urdf.xacro"),
        r#"<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro"><xacro:property name="a" value="1"/></robot>"#,
    );
    // xacro markup in a file not named *.xacro, in an element or an attribute.
    let markup = write(
        &files.join("arm.urdf"),
        "<robot name=\"r\" xmlns:x=\"http://www.ros.org/wiki/xacro\">\n<link name=\"base\"/>\n<x:include filename=\"evil.xacro\"/>\n</robot>",
    );
    let substitution = write(
        &files.join("sub.urdf"),
        "<robot name=\"r\">\n<link name=\"base\"/>\n<link name=\"$(env HOME)\"/>\n</robot>",
    );
    // A URDF that xacro wrote: the namespace on the root and xacro text in comments only.
    let generated = write(
        &files.join("generated.urdf"),
        &URDF.replace(
            "<robot name=\"r\">",
            "<robot name=\"r\" xmlns:xacro=\"http://www.ros.org/wiki/xacro\">\n<!-- <xacro:macro name=\"m\"> ${pi} $(find p) -->",
        ),
    );

    std::env::set_current_dir(&work).unwrap();
    std::env::remove_var("GRASPATH_XACRO");
    let system_path = std::env::var_os("PATH").unwrap_or_default();
    let empty_bin = root.join("bin");
    std::fs::create_dir(&empty_bin).unwrap();
    // `.` and an empty entry name the working folder, which has a `xacro`.
    std::env::set_var("PATH", format!(".::{}", empty_bin.display()));
    std::env::set_var("GRASPATH_TEST_SECRET", "hunter2");

    // 1. Without a configured or installed xacro, nothing runs.
    let err = UrdfRobot::from_file(&markup).unwrap_err();
    assert!(
        matches!(err, RobotError::XacroMarkup { line: 3, .. }),
        "{err}"
    );
    let m = err.to_string();
    assert!(m.contains("<x:include>") && m.contains("*.xacro"), "{m}");
    let err = UrdfRobot::from_file(&substitution).unwrap_err();
    assert!(
        matches!(err, RobotError::XacroMarkup { line: 3, .. }),
        "{err}"
    );
    assert!(err.to_string().contains("<link>"), "{err}");
    let robot = UrdfRobot::from_file(&generated).unwrap();
    assert_eq!(robot.link_names(), ["base", "tip"]);
    let err = RobotSource::urdf(&xacro_file).load().unwrap_err();
    assert!(matches!(err, RobotError::Xacro { .. }), "{err}");
    assert!(
        err.to_string().contains("no `xacro` program on PATH"),
        "{err}"
    );
    assert!(!ran_module.exists() && !ran_local.exists());
    // Arguments for a file that is not expanded are refused, not dropped.
    let err = RobotSource::Urdf {
        path: generated.clone(),
        search_paths: Vec::new(),
        xacro_args: BTreeMap::from([("dof".into(), "7".into())]),
    }
    .load()
    .unwrap_err();
    assert!(matches!(err, RobotError::XacroArgument { .. }), "{err}");

    // 2. The configured program runs in a folder of its own, with a cleared environment and
    //    the file and arguments as a list.
    let log = root.join("log");
    let recorder = program(
        &root.join("recorder"),
        &format!(
            "{{ echo \"cwd=$(pwd)\"; for a in \"$@\"; do echo \"arg=$a\"; done; export -p; }} > '{}'\necho '{URDF}'\n",
            log.display()
        ),
    );
    std::env::set_var("GRASPATH_XACRO", &recorder);
    std::env::set_var("PATH", &system_path);
    let packages = root.join("packages");
    let source = RobotSource::Urdf {
        path: xacro_file.clone(),
        search_paths: vec![packages.clone()],
        xacro_args: BTreeMap::from([("reach".into(), "0.5 m; $(rm -rf /)".into())]),
    };
    let model = source.load().unwrap();
    assert_eq!(model.chain("base", "tip", None).unwrap().dof(), 1);
    let record = std::fs::read_to_string(&log).unwrap();
    let lines: Vec<&str> = record.lines().collect();
    let cwd = lines[0].strip_prefix("cwd=").unwrap();
    assert_ne!(Path::new(cwd), work);
    assert_ne!(Path::new(cwd), files);
    assert!(
        !Path::new(cwd).exists(),
        "its working folder is removed afterwards"
    );
    assert_eq!(lines[1], format!("arg={}", xacro_file.display()));
    assert_eq!(lines[2], "arg=reach:=0.5 m; $(rm -rf /)");
    assert!(!record.contains("GRASPATH_TEST_SECRET") && !record.contains("hunter2"));
    assert!(record.contains("PYTHONSAFEPATH"));
    let roots = record
        .lines()
        .find(|l| l.contains("GRASPATH_PACKAGE_ROOTS"))
        .unwrap();
    assert!(
        roots.contains(&format!("search\t{}", packages.display())),
        "{roots}"
    );
    assert!(!ran_module.exists() && !ran_local.exists());
    // A file not named *.xacro is never handed to it.
    std::fs::remove_file(&log).unwrap();
    assert!(UrdfRobot::from_file(&markup).is_err());
    assert!(RobotSource::urdf(&substitution).load().is_err());
    assert!(!log.exists());
    // A bad argument name is refused before anything runs.
    let err = RobotSource::Urdf {
        path: xacro_file.clone(),
        search_paths: Vec::new(),
        xacro_args: BTreeMap::from([("--inorder".into(), "1".into())]),
    }
    .load()
    .unwrap_err();
    assert!(matches!(err, RobotError::XacroArgument { .. }), "{err}");
    assert!(!log.exists());

    // 3. Processes it leaves behind are stopped with it; a failure gives its exit code.
    let sleep = system_program("sleep");
    let pid_file = root.join("pid");
    let leaves_child = program(
        &root.join("leaves-child"),
        &format!(
            "'{}' 600 &\necho $! > '{}'\necho '{URDF}'\n",
            sleep.display(),
            pid_file.display()
        ),
    );
    let text = expand_xacro_with(&xacro_file, &leaves_child, &XacroOptions::default()).unwrap();
    assert!(text.contains("<robot name=\"r\">"));
    let pid = std::fs::read_to_string(&pid_file).unwrap();
    assert!(ended(&pid), "the background process {pid} still runs");
    let fails = program(&root.join("fails"), "echo 'no such macro' >&2\nexit 3\n");
    let err = expand_xacro_with(&xacro_file, &fails, &XacroOptions::default()).unwrap_err();
    let m = err.to_string();
    assert!(
        m.contains("exit code 3") && m.contains("no such macro"),
        "{m}"
    );

    // 4. A run that does not end is stopped at its time limit, with its children.
    std::fs::remove_file(&pid_file).unwrap();
    let hangs = program(
        &root.join("hangs"),
        &format!(
            "'{}' 600 &\necho $! > '{}'\n'{}' 600\n",
            sleep.display(),
            pid_file.display(),
            sleep.display()
        ),
    );
    let options = XacroOptions {
        timeout: Duration::from_millis(500),
        ..XacroOptions::default()
    };
    let err = expand_xacro_with(&xacro_file, &hangs, &options).unwrap_err();
    assert!(err.to_string().contains("stopped after 0.5 s"), "{err}");
    let pid = std::fs::read_to_string(&pid_file).unwrap();
    assert!(ended(&pid), "the background process {pid} still runs");

    // 5. A program the operating system cannot start (executable, but neither a binary nor a
    //    script) fails with the operating system's error kept as the source, not flattened
    //    into the message.
    let not_a_program = root.join("not-a-program");
    std::fs::write(&not_a_program, [0u8, 1, 2, 3]).unwrap();
    std::fs::set_permissions(&not_a_program, std::fs::Permissions::from_mode(0o755)).unwrap();
    let err = expand_xacro_with(&xacro_file, &not_a_program, &XacroOptions::default()).unwrap_err();
    let RobotError::XacroIo { action, source, .. } = &err else {
        panic!("not an operating-system error: {err:?}");
    };
    assert_eq!(*action, "cannot start it");
    let cause = std::error::Error::source(&err).expect("a source");
    assert!(
        cause.downcast_ref::<std::io::Error>().is_some(),
        "{cause:?}"
    );
    assert_eq!(source.raw_os_error(), Some(8), "ENOEXEC: {source}");
    assert!(!err.to_string().contains(&source.to_string()), "{err}");
}
