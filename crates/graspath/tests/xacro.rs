//! `.xacro` robot files are expanded by the `xacro` command when it is installed (the program
//! in `GRASPATH_XACRO`, else `xacro` on `PATH`, else `python3 -m xacro`). `.ci/run` installs
//! xacro into its virtualenv and sets `GRASPATH_XACRO`; with `CI=true` a missing xacro fails
//! these tests, elsewhere they print why they skip.
//!
//! Run locally: `python3 -m venv target/pyenv && target/pyenv/bin/pip install xacro`, then
//! `GRASPATH_XACRO=target/pyenv/bin/xacro cargo test -p graspath --test xacro -- --nocapture`.

use graspath::robot::{expand_xacro, expand_xacro_with, RobotError, RobotSource, XacroCommand};
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
fn xacro_available(probe: &Path) -> bool {
    match expand_xacro(probe) {
        Err(RobotError::Xacro { reason, .. }) => {
            if std::env::var("CI").is_ok_and(|v| v == "true") {
                panic!("xacro is required in CI: {reason} (.ci/run installs it)");
            }
            let _ = writeln!(
                std::io::stderr(),
                "SKIPPED: xacro is not installed ({reason}); `pip install xacro` to run these checks"
            );
            false
        }
        Err(e) => panic!("xacro is installed but failed: {e}"),
        Ok(_) => true,
    }
}

#[test]
fn a_xacro_file_is_expanded_and_equals_its_urdf() {
    let dir = tempfile::tempdir().unwrap();
    let xacro = write(dir.path(), "arm.urdf.xacro", XACRO);
    let urdf = write(dir.path(), "arm.urdf", URDF);
    if !xacro_available(&xacro) {
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
    let good = write(dir.path(), "good.xacro", XACRO);
    if !xacro_available(&good) {
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
}

#[test]
fn without_xacro_the_error_says_how_to_install_it() {
    let dir = tempfile::tempdir().unwrap();
    let path = write(dir.path(), "arm.urdf.xacro", XACRO);
    let missing = [XacroCommand {
        program: dir.path().join("no-such-xacro"),
        args: Vec::new(),
    }];
    let err = expand_xacro_with(&path, &missing).unwrap_err();
    assert!(matches!(err, RobotError::Xacro { .. }), "{err}");
    let m = err.to_string();
    assert!(m.contains("arm.urdf.xacro"), "{m}");
    assert!(m.contains("pip install xacro"), "{m}");
    assert!(m.contains("no-such-xacro"), "{m}");
}
