//! Bad robot input: each case gives one clear error naming the file and the element.

mod common;

use graspath::robot::{load_urdf_chain, parse_urdf_chain, RobotError, UrdfRobot};
use std::io::Write;

fn two_links(joint: &str) -> String {
    format!(r#"<robot name="r"><link name="base"/><link name="tip"/>{joint}</robot>"#)
}

#[test]
fn malformed_xml_names_the_file() {
    let err = parse_urdf_chain(
        "<robot name=\"r\"><link name=\"a\">",
        "broken.urdf",
        "a",
        "a",
    )
    .unwrap_err();
    assert!(matches!(err, RobotError::Parse { .. }), "{err:?}");
    assert!(
        err.to_string().starts_with("broken.urdf: not a valid URDF"),
        "{err}"
    );
}

#[test]
fn unknown_link_lists_close_names() {
    let Some(path) = common::shared_file("robots/baxter.urdf") else {
        return;
    };
    let err = load_urdf_chain(&path, "base", "left_griper", None).unwrap_err();
    let text = err.to_string();
    assert!(text.contains("no link named 'left_griper'"), "{text}");
    assert!(text.contains("left_gripper"), "suggestion missing: {text}");
    assert!(text.contains("baxter.urdf"), "{text}");
}

#[test]
fn tip_not_below_base() {
    let urdf = two_links(
        r#"<joint name="j" type="fixed"><parent link="base"/><child link="tip"/></joint>"#,
    );
    let err = parse_urdf_chain(&urdf, "r.urdf", "tip", "base").unwrap_err();
    assert!(matches!(err, RobotError::TipNotBelowBase { .. }), "{err:?}");
    assert!(
        err.to_string().contains("is not below base link 'tip'"),
        "{err}"
    );
}

#[test]
fn zero_axis_is_refused() {
    let urdf = two_links(
        r#"<joint name="j" type="revolute"><parent link="base"/><child link="tip"/>
           <axis xyz="0 0 0"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>"#,
    );
    let err = parse_urdf_chain(&urdf, "r.urdf", "base", "tip").unwrap_err();
    let text = err.to_string();
    assert!(
        text.contains("joint 'j'") && text.contains("axis/@xyz"),
        "{text}"
    );
}

#[test]
fn nan_origin_is_refused() {
    let urdf = two_links(
        r#"<joint name="j" type="revolute"><parent link="base"/><child link="tip"/>
           <origin xyz="0 NaN 0"/><axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>"#,
    );
    let err = parse_urdf_chain(&urdf, "r.urdf", "base", "tip").unwrap_err();
    let text = err.to_string();
    assert!(text.contains("origin/@xyz"), "{text}");
}

#[test]
fn inverted_limits_are_refused() {
    let urdf = two_links(
        r#"<joint name="j" type="revolute"><parent link="base"/><child link="tip"/>
           <axis xyz="0 0 1"/><limit lower="1" upper="-1" effort="1" velocity="1"/></joint>"#,
    );
    let err = parse_urdf_chain(&urdf, "r.urdf", "base", "tip").unwrap_err();
    assert!(err.to_string().contains("field 'limit'"), "{err}");
}

#[test]
fn wrong_configuration_length_and_nan() {
    let chain = graspath::robot::builtin::baxter(graspath::robot::builtin::Arm::Left);
    let err = chain.pose(&[0.0; 6]).unwrap_err();
    assert!(err
        .to_string()
        .contains("q has 6 values but the chain 'base->left_gripper' has 7 joints"));
    let mut q = [0.0; 7];
    q[3] = f64::NAN;
    assert!(matches!(
        chain.pose(&q),
        Err(RobotError::NonFiniteJoint { index: 3 })
    ));
}

#[test]
fn xacro_gets_an_instruction() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("arm.urdf.xacro");
    std::fs::File::create(&path)
        .unwrap()
        .write_all(b"<robot/>")
        .unwrap();
    let err = UrdfRobot::from_file(&path).unwrap_err();
    assert!(err.to_string().contains("expand it first"), "{err}");
    let err = UrdfRobot::from_xml(
        r#"<robot xmlns:xacro="http://www.ros.org/wiki/xacro"><xacro:macro name="m"/></robot>"#,
        "inline.urdf",
    )
    .unwrap_err();
    assert!(matches!(err, RobotError::Xacro { .. }));
}

#[test]
fn missing_file_names_it() {
    let err = UrdfRobot::from_file(std::path::Path::new("/nonexistent/robot.urdf")).unwrap_err();
    assert!(
        err.to_string()
            .starts_with("/nonexistent/robot.urdf: cannot read"),
        "{err}"
    );
}

#[test]
fn package_mesh_paths_do_not_stop_kinematics() {
    let urdf = r#"<robot name="m">
      <link name="base"><visual><geometry><mesh filename="package://nowhere/meshes/base.dae"/></geometry></visual></link>
      <link name="tip"><collision><geometry><mesh filename="package://nowhere/meshes/tip.stl" scale="1 1 1"/></geometry></collision></link>
      <joint name="j" type="revolute"><parent link="base"/><child link="tip"/>
        <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
    </robot>"#;
    let chain = parse_urdf_chain(urdf, "m.urdf", "base", "tip").unwrap();
    assert_eq!(chain.dof(), 1);
}
