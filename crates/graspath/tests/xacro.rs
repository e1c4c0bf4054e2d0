//! Files named `*.xacro` are expanded by the `xacro` program when it is installed (the program
//! in `GRASPATH_XACRO`, else `xacro` on `PATH`), with xacro arguments and `$(find PKG)` looked
//! up in the robot's package search paths. `.ci/run` installs xacro into its virtualenv and
//! sets `GRASPATH_XACRO`; with `CI=true` a missing xacro fails these tests, elsewhere they
//! print why they skip. How the run is confined is tested with stand-in programs in
//! `tests/xacro_confined.rs`.
//!
//! Run locally: `python3 -m venv target/pyenv && target/pyenv/bin/pip install xacro`, then
//! `GRASPATH_XACRO=target/pyenv/bin/xacro cargo test -p graspath --test xacro -- --nocapture`.

use graspath::robot::{
    expand_xacro_with, find_xacro_program, RobotError, RobotSource, XacroOptions,
};
use std::collections::BTreeMap;
use std::io::Write;
use std::path::Path;

/// A two-joint arm written with a `xacro:property` and a `xacro:macro`.
const XACRO: &str = r#"<?xml version="1.0"?>
<robot name="arm" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:property name="upper" value="0.4"/>
  <xacro:property name="half_pi" value="${pi/2}"/>
  <xacro:macro name="hinge" params="name parent child x rx">
    <joint name="${name}" type="revolute">
      <parent link="${parent}"/>
      <child link="${child}"/>
      <origin xyz="${x} 0 0.1" rpy="${rx} 0 0"/>
      <axis xyz="0 0 1"/>
      <limit lower="-2" upper="2" effort="1" velocity="1"/>
    </joint>
    <link name="${child}"/>
  </xacro:macro>
  <link name="base"/>
  <xacro:hinge name="j1" parent="base" child="l1" x="0" rx="0"/>
  <xacro:hinge name="j2" parent="l1" child="l2" x="${upper}" rx="${half_pi}"/>
  <joint name="tip_joint" type="fixed">
    <parent link="l2"/><child link="tip"/><origin xyz="${upper * 0.75} 0 0"/>
  </joint>
  <link name="tip"/>
</robot>
"#;

/// The same arm written out by hand.
const URDF: &str = r#"<?xml version="1.0"?>
<robot name="arm">
  <link name="base"/>
  <joint name="j1" type="revolute">
    <parent link="base"/><child link="l1"/><origin xyz="0 0 0.1" rpy="0 0 0"/>
    <axis xyz="0 0 1"/><limit lower="-2" upper="2" effort="1" velocity="1"/>
  </joint>
  <link name="l1"/>
  <joint name="j2" type="revolute">
    <parent link="l1"/><child link="l2"/><origin xyz="0.4 0 0.1" rpy="1.5707963267948966 0 0"/>
    <axis xyz="0 0 1"/><limit lower="-2" upper="2" effort="1" velocity="1"/>
  </joint>
  <link name="l2"/>
  <joint name="tip_joint" type="fixed">
    <parent link="l2"/><child link="tip"/><origin xyz="0.30000000000000004 0 0"/>
  </joint>
  <link name="tip"/>
</robot>
"#;

fn write(dir: &Path, name: &str, text: &str) -> std::path::PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

/// Whether xacro is installed; prints why not, and panics in CI where it must be.
fn xacro_available() -> bool {
    match find_xacro_program() {
        Err(reason) => {
            if std::env::var("CI").is_ok_and(|v| v == "true") {
                panic!("xacro is required in CI: {reason} (.ci/run installs it)");
            }
            let _ = writeln!(
                std::io::stderr(),
                "SKIPPED: xacro is not installed ({reason}); `pip install xacro` to run these checks"
            );
            false
        }
        Ok(_) => true,
    }
}

#[test]
fn a_xacro_file_is_expanded_and_equals_its_urdf() {
    let dir = tempfile::tempdir().unwrap();
    let xacro = write(dir.path(), "arm.urdf.xacro", XACRO);
    let urdf = write(dir.path(), "arm.urdf", URDF);
    if !xacro_available() {
        return;
    }
    let expanded = RobotSource::urdf(&xacro)
        .load()
        .unwrap()
        .chain("base", "tip", None)
        .unwrap();
    let written = RobotSource::urdf(&urdf)
        .load()
        .unwrap()
        .chain("base", "tip", None)
        .unwrap();
    assert_eq!(expanded.joint_names(), written.joint_names());
    assert_eq!(expanded.lower(), written.lower());
    for q in [[0.0, 0.0], [0.3, -1.2], [-1.9, 1.7], [1.0, 0.5]] {
        let (a, ja) = expanded.pose_and_jacobian(&q).unwrap();
        let (b, jb) = written.pose_and_jacobian(&q).unwrap();
        assert!((a.to_homogeneous() - b.to_homogeneous()).abs().max() < 1e-12);
        assert!((ja - jb).abs().max() < 1e-12);
    }
}

#[test]
fn a_failing_xacro_reports_its_standard_error() {
    let dir = tempfile::tempdir().unwrap();
    if !xacro_available() {
        return;
    }
    let bad = write(
        dir.path(),
        "bad.xacro",
        r#"<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro"><link name="${nowhere}"/></robot>"#,
    );
    let err = RobotSource::urdf(&bad).load().unwrap_err();
    assert!(matches!(err, RobotError::XacroFailed { .. }), "{err}");
    let m = err.to_string();
    assert!(m.contains("bad.xacro") && m.contains("nowhere"), "{m}");
    assert!(m.contains("exit code 2"), "{m}");
    assert!(!m.contains("exit status exit status"), "{m}");
}

#[test]
fn without_xacro_the_error_says_how_to_install_it() {
    let dir = tempfile::tempdir().unwrap();
    let path = write(dir.path(), "arm.urdf.xacro", XACRO);
    let missing = dir.path().join("no-such-xacro");
    let err = expand_xacro_with(&path, &missing, &XacroOptions::default()).unwrap_err();
    assert!(matches!(err, RobotError::Xacro { .. }), "{err}");
    let m = err.to_string();
    assert!(m.contains("arm.urdf.xacro"), "{m}");
    assert!(m.contains("pip install xacro"), "{m}");
    assert!(m.contains("no-such-xacro"), "{m}");
}

/// A two-joint arm whose second link length is a xacro argument and whose joints come from a
/// file of a package found with `$(find arm_parts)`, as ROS 2 descriptions are written.
const XACRO_WITH_PACKAGE: &str = r#"<?xml version="1.0"?>
<robot name="arm" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:arg name="reach" default="0.4"/>
  <xacro:include filename="$(find arm_parts)/urdf/hinge.xacro"/>
  <link name="base"/>
  <xacro:hinge name="j1" parent="base" child="l1" x="0" rx="0"/>
  <xacro:hinge name="j2" parent="l1" child="l2" x="$(arg reach)" rx="${pi/2}"/>
  <joint name="tip_joint" type="fixed">
    <parent link="l2"/><child link="tip"/><origin xyz="0.3 0 0"/>
  </joint>
  <link name="tip"/>
</robot>
"#;

const HINGE_MACRO: &str = r#"<?xml version="1.0"?>
<robot xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:macro name="hinge" params="name parent child x rx">
    <joint name="${name}" type="revolute">
      <parent link="${parent}"/>
      <child link="${child}"/>
      <origin xyz="${x} 0 0.1" rpy="${rx} 0 0"/>
      <axis xyz="0 0 1"/>
      <limit lower="-2" upper="2" effort="1" velocity="1"/>
    </joint>
    <link name="${child}"/>
  </xacro:macro>
</robot>
"#;

/// The tip of [`XACRO_WITH_PACKAGE`] at `q` with second link length `reach`, in closed form:
/// `Rz(q1)·T(0,0,0.1)·T(reach,0,0.1)·Rx(π/2)·Rz(q2)·T(0.3,0,0)`.
fn tip_position(reach: f64, q: [f64; 2]) -> [f64; 3] {
    // In l2's frame the tip is 0.3 along x; Rz(q2) turns it, Rx(π/2) sends y to z.
    let (x2, y2) = (0.3 * q[1].cos(), 0.3 * q[1].sin());
    let (lx, ly, lz) = (reach + x2, 0.0, 0.2 + y2);
    let (c, s) = (q[0].cos(), q[0].sin());
    [c * lx - s * ly, s * lx + c * ly, lz]
}

#[test]
fn find_uses_the_search_paths_and_arguments_reach_xacro() {
    if !xacro_available() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let share = dir.path().join("share");
    std::fs::create_dir_all(share.join("arm_parts/urdf")).unwrap();
    write(&share.join("arm_parts/urdf"), "hinge.xacro", HINGE_MACRO);
    let robot_dir = dir.path().join("robot");
    std::fs::create_dir_all(&robot_dir).unwrap();
    let path = write(&robot_dir, "arm.urdf.xacro", XACRO_WITH_PACKAGE);
    let load = |search_paths: Vec<std::path::PathBuf>, reach: Option<&str>| {
        RobotSource::Urdf {
            path: path.clone(),
            search_paths,
            xacro_args: reach
                .map(|r| BTreeMap::from([("reach".to_string(), r.to_string())]))
                .unwrap_or_default(),
        }
        .load()
    };
    for (reach, given) in [(0.4, None), (0.65, Some("0.65"))] {
        let chain = load(vec![share.clone()], given)
            .unwrap()
            .chain("base", "tip", None)
            .unwrap();
        for q in [[0.0, 0.0], [0.3, -1.2], [-1.9, 1.7]] {
            let tip = chain.pose(&q).unwrap().translation.vector;
            let expected = tip_position(reach, q);
            for k in 0..3 {
                assert!((tip[k] - expected[k]).abs() < 1e-12, "{tip:?} {expected:?}");
            }
        }
    }
    // Without the search path the package is not found, and xacro says which.
    let err = load(Vec::new(), None).unwrap_err();
    assert!(matches!(err, RobotError::XacroFailed { .. }), "{err}");
    assert!(err.to_string().contains("arm_parts"), "{err}");
}

#[test]
fn a_task_file_gives_xacro_arguments_and_search_paths() {
    if !xacro_available() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let share = dir.path().join("share");
    std::fs::create_dir_all(share.join("arm_parts/urdf")).unwrap();
    write(&share.join("arm_parts/urdf"), "hinge.xacro", HINGE_MACRO);
    write(dir.path(), "arm.urdf.xacro", XACRO_WITH_PACKAGE);
    let task = |robot: &str| {
        let path = write(
            dir.path(),
            "task.yaml",
            &format!(
                "robot: {robot}\narms: arm\nobject: {{ pose: {{ xyz: [0.5, 0, 0.2] }}, shape: {{ box: {{ size: [0.05, 0.05, 0.05] }} }} }}\ncandidates: {{ family: {{ edge: {{ count: 3 }} }} }}\ntrajectory: {{ steps: [ {{ lift: 0.05 }} ] }}\n"
            ),
        );
        graspath::task::Task::load(&path)
    };
    let loaded = task(
        "{ urdf: arm.urdf.xacro, search_paths: [share], xacro_args: { reach: 0.65 }, chains: { arm: { base: base, tip: tip } } }",
    )
    .unwrap();
    let chain = &loaded.arms()[0].chain;
    let tip = chain.pose(&[0.3, -1.2]).unwrap().translation.vector;
    let expected = tip_position(0.65, [0.3, -1.2]);
    for k in 0..3 {
        assert!((tip[k] - expected[k]).abs() < 1e-12, "{tip:?} {expected:?}");
    }
    // The settings belong to a URDF robot; an argument is a name xacro can take.
    let err = task("{ builtin: panda, xacro_args: { reach: 1 } }").unwrap_err();
    assert!(err.to_string().contains("robot.xacro_args"), "{err}");
    let err = task("{ builtin: panda, search_paths: [share] }").unwrap_err();
    assert!(err.to_string().contains("robot.search_paths"), "{err}");
    let err = task(
        "{ urdf: arm.urdf.xacro, search_paths: [share], xacro_args: { 'bad name': 1 }, chains: { arm: { base: base, tip: tip } } }",
    )
    .unwrap_err();
    let err = graspath::Chain(&err).to_string();
    assert!(err.contains("xacro argument 'bad name'"), "{err}");
}
