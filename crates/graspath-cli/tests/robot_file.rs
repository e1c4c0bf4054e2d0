//! `--robot-file FILE`: a URDF or MJCF file, its format told by its name or its root element,
//! gives the same chain as `--urdf` / `--mjcf`; `--robot` takes only the built-in names.

mod common;

use common::graspath_with_input;

use graspath::robot::builtin::BUILTIN_NAMES;
use std::path::{Path, PathBuf};

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../graspath/tests/data")
        .join(name)
}

/// `kinematics` output for `robot` (the robot options) at a few configurations of `dof` joints.
fn kinematics(robot: &[&str], dof: usize) -> String {
    let lines: String = (0..4)
        .map(|k| {
            let q: Vec<String> = (0..dof)
                .map(|j| format!("{}", ((k * 5 + j * 3) % 7) as f64 * 0.3 - 0.9))
                .collect();
            format!("{{\"q\":[{}]}}\n", q.join(","))
        })
        .collect();
    let mut args = vec!["kinematics"];
    args.extend_from_slice(robot);
    let o = graspath_with_input(&args, &lines);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{args:?}: {stderr}");
    let out = String::from_utf8(o.stdout).unwrap();
    assert_eq!(out.lines().count(), 4, "{out}");
    out
}

#[test]
fn robot_file_gives_the_same_chain_as_urdf_and_mjcf() {
    let dir = tempfile::tempdir().unwrap();
    // MJCF: *.xml as given, and a copy without an extension (told by its root <mujoco>).
    let mjcf = data("mjcf/ur5.xml");
    let bare = dir.path().join("ur5_model");
    std::fs::copy(&mjcf, &bare).unwrap();
    let chain = ["--base", "base", "--tip", "tool0"];
    let by_flag = kinematics(
        &[&["--mjcf", mjcf.to_str().unwrap()][..], &chain].concat(),
        6,
    );
    for file in [&mjcf, &bare] {
        let by_file = kinematics(
            &[&["--robot-file", file.to_str().unwrap()][..], &chain].concat(),
            6,
        );
        assert_eq!(by_file, by_flag, "{}", file.display());
    }
    // URDF: *.urdf as given, and a copy named *.xml (told by its root <robot>).
    let urdf = data("three_finger_hand.urdf");
    let xml = dir.path().join("hand.xml");
    std::fs::copy(&urdf, &xml).unwrap();
    let chain = ["--base", "palm", "--tip", "finger_a"];
    let by_flag = kinematics(
        &[&["--urdf", urdf.to_str().unwrap()][..], &chain].concat(),
        1,
    );
    for file in [&urdf, &xml] {
        let by_file = kinematics(
            &[&["--robot-file", file.to_str().unwrap()][..], &chain].concat(),
            1,
        );
        assert_eq!(by_file, by_flag, "{}", file.display());
    }
}

#[test]
fn robot_file_refuses_a_file_of_neither_format_and_misplaced_options() {
    let dir = tempfile::tempdir().unwrap();
    let sdf = dir.path().join("world.model");
    std::fs::write(&sdf, "<sdf version=\"1.9\"/>").unwrap();
    let o = graspath_with_input(
        &[
            "kinematics",
            "--robot-file",
            sdf.to_str().unwrap(),
            "--base",
            "a",
            "--tip",
            "b",
        ],
        "",
    );
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("world.model: not a robot description"),
        "{stderr}"
    );
    assert!(stderr.contains("its root element is <sdf>"), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    let mjcf = data("mjcf/ur5.xml");
    let o = graspath_with_input(
        &[
            "kinematics",
            "--robot-file",
            mjcf.to_str().unwrap(),
            "--base",
            "base",
            "--tip",
            "tool0",
            "--search-path",
            "meshes",
        ],
        "",
    );
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("search paths are for a URDF or xacro file, and this is an MJCF file"),
        "{stderr}"
    );
    // --robot-file needs the chain's links, and excludes the other robot options.
    let o = graspath_with_input(&["kinematics", "--robot-file", mjcf.to_str().unwrap()], "");
    assert_eq!(o.status.code(), Some(2));
    let o = graspath_with_input(
        &[
            "kinematics",
            "--robot-file",
            mjcf.to_str().unwrap(),
            "--robot",
            "ur5",
            "--base",
            "base",
            "--tip",
            "tool0",
        ],
        "",
    );
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("cannot be used with"));
}

#[test]
fn robot_takes_the_built_in_names_and_help_lists_them() {
    let o = graspath_with_input(&["kinematics", "--help"], "");
    assert!(o.status.success());
    let help = String::from_utf8(o.stdout).unwrap();
    let listed = format!("[possible values: {}]", BUILTIN_NAMES.join(", "));
    assert!(help.contains(&listed), "{help}");
    assert!(help.contains("--robot-file <FILE>"), "{help}");
    let o = graspath_with_input(&["kinematics", "--robot", "baxtor"], "");
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("invalid value 'baxtor' for '--robot <NAME>'"),
        "{stderr}"
    );
    assert!(stderr.contains("baxter"), "{stderr}");
    for name in BUILTIN_NAMES {
        let o = graspath_with_input(&["kinematics", "--robot", name], "");
        assert!(
            o.status.success(),
            "{name}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
    }
}
