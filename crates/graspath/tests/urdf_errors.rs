//! Bad robot input: each case gives one clear error naming the file and the element.

mod common;

use graspath::robot::{
    load_urdf_chain, parse_urdf_chain, MeshResolver, RobotError, RobotSource, UrdfRobot,
};

fn two_links(joint: &str) -> String {
    format!(r#"<robot name="r"><link name="base"/><link name="tip"/>{joint}</robot>"#)
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

/// An axis whose norm overflows keeps its direction (it used to become a zero axis).
#[test]
fn a_huge_axis_keeps_its_direction() {
    let chain = |axis: &str| {
        let urdf = two_links(&format!(
            r#"<joint name="j" type="revolute"><parent link="base"/><child link="tip"/>
               <origin xyz="0.1 0.2 0.3"/><axis xyz="{axis}"/>
               <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>"#
        ));
        parse_urdf_chain(&urdf, "r.urdf", "base", "tip").unwrap()
    };
    let (huge, plain) = (chain("1e300 -1e300 0"), chain("1 -1 0"));
    for q in [-0.7, 0.2, 0.9] {
        let (a, b) = (huge.pose(&[q]).unwrap(), plain.pose(&[q]).unwrap());
        let gap = (a.to_homogeneous() - b.to_homogeneous()).abs().max();
        assert!(gap < 1e-15, "{gap}");
        // The rotation stays a rotation.
        let r = a.rotation.matrix();
        assert!(
            (r.transpose() * r - nalgebra::Matrix3::identity())
                .abs()
                .max()
                < 1e-12
        );
    }
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

/// Limits beyond ±1e16 are refused (their span would overflow what IK samples from);
/// Gazebo's ±1e16 for an unlimited joint is kept, and IK works on it.
#[test]
fn huge_limits_are_refused_and_gazebos_unlimited_is_kept() {
    let joint = |kind: &str, limit: &str| {
        two_links(&format!(
            r#"<joint name="j" type="{kind}"><parent link="base"/><child link="tip"/>
               <axis xyz="1 0 0"/><limit lower="-{limit}" upper="{limit}" effort="1" velocity="1"/></joint>"#
        ))
    };
    for kind in ["prismatic", "revolute"] {
        let err = parse_urdf_chain(&joint(kind, "1e308"), "r.urdf", "base", "tip").unwrap_err();
        let m = err.to_string();
        assert!(
            m.contains("field 'limit'") && m.contains("beyond ±10000000000000000"),
            "{m}"
        );
        let chain = parse_urdf_chain(&joint(kind, "1e16"), "r.urdf", "base", "tip").unwrap();
        let target = chain.pose(&[0.25]).unwrap();
        let solution = graspath::robot::solve_ik(
            &chain,
            &nalgebra::convert(target),
            &[0.0],
            &graspath::robot::IkOptions::default(),
        )
        .unwrap();
        let q = solution.q.expect("solved");
        let reached = chain.pose(&q).unwrap();
        let gap = (reached.to_homogeneous() - target.to_homogeneous())
            .abs()
            .max();
        assert!(gap < 1e-6, "{kind}: {gap}");
    }
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

/// Xacro markup outside a file named `*.xacro` is refused with its line (xacro runs code:
/// only files the user names as xacro files are expanded; files are: tests/xacro.rs); in a
/// comment it is no markup.
#[test]
fn xacro_markup_is_refused_but_not_in_comments() {
    let err = UrdfRobot::from_xml(
        "<robot xmlns:xacro=\"http://www.ros.org/wiki/xacro\">\n<xacro:macro name=\"m\"/></robot>",
        "inline.urdf",
    )
    .unwrap_err();
    assert!(
        matches!(err, RobotError::XacroMarkup { line: 2, .. }),
        "{err}"
    );
    let m = err.to_string();
    assert!(
        m.starts_with("inline.urdf:2: uses xacro markup (the element <xacro:macro>)"),
        "{m}"
    );
    assert!(m.contains("*.xacro") && m.contains("runs code"), "{m}");
    // Another prefix bound to the namespace, and a substitution in an attribute.
    for (text, markup) in [
        (
            r#"<robot xmlns:x="https://ros.org/wiki/xacro"><link name="a"/><x:if value="1"/></robot>"#,
            "<x:if>",
        ),
        (
            r#"<robot xmlns:xa="http://wiki.ros.org/xacro"><link name="a"/><xa:arg name="x"/></robot>"#,
            "<xa:arg>",
        ),
        (
            r#"<robot><link name="a"><visual><origin xyz="${l} 0 0"/></visual></link></robot>"#,
            "<origin>",
        ),
    ] {
        let err = UrdfRobot::from_xml(text, "inline.urdf").unwrap_err();
        assert!(matches!(err, RobotError::XacroMarkup { .. }), "{err}");
        assert!(err.to_string().contains(markup), "{err}");
    }
    // xacro's output keeps the namespace declaration and any comments: it is plain URDF.
    let robot = UrdfRobot::from_xml(
        r#"<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <!-- =================================================================================== -->
  <!-- <xacro:macro name="arm"> made with ${prefix} and $(find pkg) -->
  <link name="a"/>
</robot>"#,
        "generated.urdf",
    )
    .unwrap();
    assert_eq!(robot.link_names(), ["a"]);
}

/// A robot without links (example-robot-data ships such a `ur3.urdf`, comments only) is
/// refused as such, as urdfdom refuses it.
#[test]
fn a_robot_without_links_is_refused() {
    let err = UrdfRobot::from_xml(
        "<robot xmlns:xacro=\"http://wiki.ros.org/xacro\"><!-- Author --></robot>",
        "ur3.urdf",
    )
    .unwrap_err();
    assert!(
        err.to_string()
            .contains("ur3.urdf: not a valid URDF: the robot has no <link> element"),
        "{err}"
    );
}

/// `<texture/>` without a file (iCub, Romeo) is accepted, as urdfdom and Pinocchio accept
/// it; the rest of the material, and every line number after it, is unchanged.
#[test]
fn a_texture_without_a_file_is_accepted() {
    let robot = |texture: &str| {
        format!(
            "<robot name=\"r\">\n<material name=\"m\">\n  <color rgba=\"1 0 0 1\"/>\n  {texture}\n</material>\n<link name=\"a\"/>\n<link name=\"b\"/>\n<joint name=\"j\" type=\"revolute\"><parent link=\"a\"/><child link=\"b\"/></joint>\n</robot>"
        )
    };
    for texture in ["<texture/>", "<texture>\n</texture>", "<texture></texture>"] {
        // The joint lacks its <limit>: the error's line shows nothing moved.
        let err = UrdfRobot::from_xml(&robot(texture), "icub.urdf").unwrap_err();
        let m = err.to_string();
        let line = if texture.contains('\n') { 9 } else { 8 };
        assert!(m.contains(&format!("(line {line};")), "{texture}: {m}");
    }
    let fixed = robot("<texture/>").replace(
        "</joint>",
        "<limit lower=\"-1\" upper=\"1\" effort=\"1\" velocity=\"1\"/></joint>",
    );
    let model = UrdfRobot::from_xml(&fixed, "icub.urdf").unwrap();
    assert_eq!(model.link_names(), ["a", "b"]);
}

/// A `package://` mesh URI may not climb out of its package.
#[test]
fn package_paths_stay_inside_their_package() {
    let dir = tempfile::tempdir().unwrap();
    let package = dir.path().join("share/pkg");
    std::fs::create_dir_all(package.join("meshes")).unwrap();
    std::fs::write(dir.path().join("share/secret.stl"), "solid x\nendsolid x\n").unwrap();
    std::fs::write(package.join("meshes/part.stl"), "solid x\nendsolid x\n").unwrap();
    let resolver = MeshResolver {
        search_paths: vec![dir.path().join("share")],
        ..MeshResolver::default()
    };
    assert_eq!(
        resolver
            .resolve("package://pkg/meshes/part.stl", "r.urdf", "l")
            .unwrap(),
        package.join("meshes/part.stl")
    );
    for uri in [
        "package://pkg/../secret.stl",
        "package://pkg/meshes/../../secret.stl",
        "package://../share/secret.stl",
        "model://pkg/../secret.stl",
    ] {
        let err = resolver.resolve(uri, "r.urdf", "l").unwrap_err();
        assert!(
            matches!(err, RobotError::MeshOutsidePackage { .. }),
            "{uri}: {err}"
        );
        assert!(
            err.to_string().contains("may not leave its package"),
            "{err}"
        );
    }
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

const LIMIT: &str = r#"<limit lower="-1" upper="1" effort="1" velocity="1"/>"#;

/// Bad URDF text, and fragments the one error must contain (the file name always).
#[test]
fn bad_urdf_table() {
    let joint = |kind: &str, extra: &str| {
        two_links(&format!(
            r#"<joint name="j" type="{kind}"><parent link="base"/><child link="tip"/><axis xyz="0 0 1"/>{extra}</joint>"#
        ))
    };
    let cases: Vec<(&str, String, Vec<&str>)> = vec![
        (
            "unclosed root",
            "<robot name=\"r\">\n  <link name=\"a\">".into(),
            vec!["bad.urdf:2:3", "malformed XML", "<link> is never closed"],
        ),
        (
            "mismatched end tag",
            "<robot name=\"r\">\n<link name=\"a\"></joint>\n</robot>".into(),
            vec!["bad.urdf:2:", "malformed XML"],
        ),
        (
            "broken attribute",
            "<robot name=\"r\">\n\n   <link name=a/></robot>".into(),
            vec!["bad.urdf:3:4", "in <link>"],
        ),
        (
            "empty file",
            String::new(),
            vec!["bad.urdf:1:1", "no root element"],
        ),
        (
            "revolute without limit",
            joint("revolute", ""),
            vec![
                "joint 'j'",
                "field 'limit'",
                "revolute joint needs a <limit",
                "line 1",
            ],
        ),
        (
            "prismatic without limit",
            joint("prismatic", ""),
            vec!["joint 'j'", "prismatic joint needs a <limit"],
        ),
        (
            "child of two joints",
            format!(
                r#"<robot name="r"><link name="base"/><link name="mid"/><link name="tip"/>
                <joint name="a" type="fixed"><parent link="base"/><child link="tip"/></joint>
                <joint name="b" type="revolute"><parent link="mid"/><child link="tip"/>{LIMIT}</joint></robot>"#
            ),
            vec!["link 'tip' is the child of two joints, 'a' and 'b'"],
        ),
        (
            "inverted limits",
            joint(
                "revolute",
                r#"<limit lower="1" upper="-1" effort="1" velocity="1"/>"#,
            ),
            vec!["joint 'j'", "field 'limit'", "not an interval"],
        ),
        (
            "negative effort",
            joint(
                "revolute",
                r#"<limit lower="-1" upper="1" effort="-50" velocity="1"/>"#,
            ),
            vec!["joint 'j'", "field 'limit'", "<limit effort> is -50", "0 or more"],
        ),
        (
            "negative velocity",
            joint(
                "prismatic",
                r#"<limit lower="-1" upper="1" effort="5" velocity="-0.5"/>"#,
            ),
            vec!["joint 'j'", "<limit velocity> is -0.5"],
        ),
        (
            "NaN effort",
            joint(
                "revolute",
                r#"<limit lower="-1" upper="1" effort="NaN" velocity="1"/>"#,
            ),
            vec!["joint 'j'", "<limit effort> is NaN"],
        ),
        (
            "a link named twice",
            "<robot name=\"r\">\n<link name=\"base\"/>\n<link name=\"tip\"/>\n<link name=\"base\"><inertial><mass value=\"2\"/></inertial></link>\n</robot>".into(),
            vec!["line 4: a second link named \"base\" (the first is on line 2)"],
        ),
        (
            "a joint named twice",
            format!(
                "<robot name=\"r\"><link name=\"base\"/><link name=\"mid\"/><link name=\"tip\"/>\n<joint name=\"j\" type=\"fixed\"><parent link=\"base\"/><child link=\"mid\"/></joint>\n<joint name=\"j\" type=\"revolute\"><parent link=\"mid\"/><child link=\"tip\"/>{LIMIT}</joint></robot>"
            ),
            vec!["line 3: a second joint named \"j\" (the first is on line 2)"],
        ),
    ];
    for (what, text, fragments) in cases {
        let err = match UrdfRobot::from_xml(&text, "bad.urdf") {
            Ok(robot) => robot.chain("base", "tip", None).map(|_| ()).unwrap_err(),
            Err(e) => e,
        };
        let message = err.to_string();
        assert!(message.contains("bad.urdf"), "{what}: {message}");
        for fragment in fragments {
            assert!(
                message.contains(fragment),
                "{what}: '{fragment}' not in: {message}"
            );
        }
    }
    // A limit of 0 is none given (a common way of writing "unknown"): accepted, unlimited.
    let zero = joint(
        "revolute",
        r#"<limit lower="-1" upper="1" effort="0" velocity="0"/>"#,
    );
    let chain = parse_urdf_chain(&zero, "ok.urdf", "base", "tip").unwrap();
    assert_eq!(chain.motion_limits()[0].effort, None);
    assert_eq!(chain.motion_limits()[0].velocity, None);
    // A continuous joint needs no limit; a fixed one neither.
    assert!(parse_urdf_chain(&joint("continuous", ""), "ok.urdf", "base", "tip").is_ok());
    assert!(parse_urdf_chain(&joint("revolute", LIMIT), "ok.urdf", "base", "tip").is_ok());
}

fn mesh_robot(filename: &str) -> String {
    format!(
        r#"<robot name="m"><link name="base"/>
        <link name="arm"><collision><origin xyz="0 0 0.1"/><geometry><mesh filename="{filename}" scale="2 2 2"/></geometry></collision></link>
        <joint name="j" type="fixed"><parent link="base"/><child link="arm"/></joint></robot>"#
    )
}

/// Bad collision elements and meshes that cannot be found: the URDF, the link and the
/// paths tried are named.
#[test]
fn bad_collision_table() {
    let dir = tempfile::tempdir().unwrap();
    let resolver = MeshResolver {
        base_dir: dir.path().join("robot/urdf"),
        search_paths: vec![dir.path().join("extra")],
        ros_package_path: vec![dir.path().join("ros")],
        ament_prefix_path: vec![dir.path().join("ament")],
    };
    let collision = |geometry: &str| {
        format!(
            r#"<robot name="c"><link name="base"><collision><geometry>{geometry}</geometry></collision></link></robot>"#
        )
    };
    let extra = dir.path().join("extra").display().to_string();
    let ros = dir.path().join("ros").display().to_string();
    let ament = dir.path().join("ament").display().to_string();
    let cases: Vec<(&str, String, Vec<String>)> = vec![
        (
            "package mesh missing",
            mesh_robot("package://arm_pkg/meshes/arm.stl"),
            vec![
                "link 'arm'".into(),
                "collision mesh 'package://arm_pkg/meshes/arm.stl': not found".into(),
                format!("{extra}/arm_pkg/meshes/arm.stl"),
                format!("{extra}/share/arm_pkg/meshes/arm.stl"),
                format!("{ros}/arm_pkg/meshes/arm.stl"),
                format!("{ament}/share/arm_pkg/meshes/arm.stl"),
                "ROS_PACKAGE_PATH".into(),
            ],
        ),
        (
            "relative mesh missing",
            mesh_robot("meshes/arm.obj"),
            vec!["robot/urdf/meshes/arm.obj".into()],
        ),
        (
            "unsupported scheme",
            mesh_robot("http://example.invalid/arm.stl"),
            vec!["unsupported URI scheme".into()],
        ),
        (
            "negative box",
            collision(r#"<box size="0.1 -0.2 0.3"/>"#),
            vec!["link 'base', collision 0".into(), "box.size[1]".into()],
        ),
        (
            "zero sphere",
            collision(r#"<sphere radius="0"/>"#),
            vec!["sphere.radius".into()],
        ),
        (
            "zero cylinder length",
            collision(r#"<cylinder radius="0.1" length="0"/>"#),
            vec!["cylinder.length".into()],
        ),
    ];
    for (what, text, fragments) in cases {
        let robot = UrdfRobot::from_xml(&text, "c.urdf").unwrap();
        let message = robot.collisions(&resolver).unwrap_err().to_string();
        assert!(message.starts_with("c.urdf: "), "{what}: {message}");
        for fragment in fragments {
            assert!(
                message.contains(&fragment),
                "{what}: '{fragment}' not in: {message}"
            );
        }
    }
}

#[test]
fn unknown_robots_and_chains_get_suggestions() {
    let err = RobotSource::builtin("baxtr").load().unwrap_err();
    assert!(matches!(err, RobotError::UnknownRobot { .. }));
    assert!(err.to_string().contains("did you mean: baxter?"), "{err}");
    let model = RobotSource::builtin("baxter").load().unwrap();
    let err = model.named_chain("lef", None).unwrap_err();
    assert!(err.to_string().contains("did you mean: left?"), "{err}");
    let err = model.chain("base", "left_wrsit", None).unwrap_err();
    assert!(err.to_string().contains("left_wrist"), "{err}");
    let err = model.chain("left_wrist", "right_wrist", None).unwrap_err();
    assert!(matches!(err, RobotError::TipNotBelowBase { .. }), "{err}");
    let err = RobotSource::urdf("/nonexistent/r.urdf").load().unwrap_err();
    assert!(
        err.to_string()
            .starts_with("/nonexistent/r.urdf: cannot read"),
        "{err}"
    );
}
