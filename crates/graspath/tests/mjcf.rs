//! MuJoCo MJCF files as a robot source.
//!
//! * `tests/data/mjcf/ur5.xml` and `panda.xml` are written from the published parameters of
//!   the built-in `ur5` and `panda` (and of ur_description / franka_description) with MJCF's
//!   own features — degrees, `euler`, `quat`, `axisangle`, `xyaxes`, `zaxis`, a joint `pos`
//!   off the body origin, a joint `ref`, default classes with `childclass` — and must give the
//!   same tip pose and Jacobian to 1e-9 at seeded random configurations. When
//!   `GRASPATH_ROBOT_DATA` points at example-robot-data (see tests/robot_data.rs) they are also
//!   checked against its URDFs.
//! * Small models check a body with several joints against MuJoCo's documented composition
//!   (`T(pos) R(axis, q − ref) T(−pos)` per joint, in order) with finite-difference Jacobians,
//!   and the geoms' sizes against MJCF's half-size conventions.
//! * Bad input gets one clear error naming the file and the attribute.

mod common;

use graspath::cloud::load_collision_mesh;
use graspath::geometry::shape::Shape;
use graspath::robot::{Chain, CollisionGeometry, MjcfRobot, RobotError, RobotSource, UrdfRobot};
use nalgebra::{Isometry3, IsometryMatrix3, Translation3, UnitQuaternion, Vector3, Vector6};
use std::f64::consts::PI;
use std::path::{Path, PathBuf};

const TOL: f64 = 1e-9;

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/mjcf")
        .join(name)
}

fn mjcf_chain(file: &str, base: &str, tip: &str) -> Chain {
    RobotSource::mjcf(data(file))
        .load()
        .unwrap_or_else(|e| panic!("{file}: {e}"))
        .chain(base, tip, None)
        .unwrap_or_else(|e| panic!("{file}: {e}"))
}

fn builtin(name: &str) -> Chain {
    RobotSource::builtin(name)
        .load()
        .unwrap()
        .named_chain("arm", None)
        .unwrap()
}

/// `reference_from_base · chain(q)` equals `reference(q)` at 200 seeded configurations inside
/// the reference's limits.
fn check_same_kinematics(
    what: &str,
    chain: &Chain,
    reference: &Chain,
    reference_from_base: IsometryMatrix3<f64>,
) {
    let configurations = common::configurations(reference, 200, 17);
    common::assert_same_kinematics(what, chain, reference, reference_from_base, &configurations);
}

fn assert_limits_close(what: &str, a: &Chain, b: &Chain) {
    for j in 0..a.dof() {
        assert!(
            (a.lower()[j] - b.lower()[j]).abs() < 1e-12
                && (a.upper()[j] - b.upper()[j]).abs() < 1e-12,
            "{what}: joint {j} limits [{}, {}] vs [{}, {}]",
            a.lower()[j],
            a.upper()[j],
            b.lower()[j],
            b.upper()[j]
        );
    }
}

#[test]
fn ur5_equals_the_builtin_ur5() {
    let mjcf = mjcf_chain("ur5.xml", "base", "tool0");
    let reference = builtin("ur5");
    check_same_kinematics("ur5", &mjcf, &reference, IsometryMatrix3::identity());
    assert_limits_close("ur5", &mjcf, &reference);
    // Degrees: ±360° is ±2π.
    assert!((mjcf.upper()[0] - 2.0 * PI).abs() < 1e-12);
    assert_eq!(mjcf.joint_names(), reference.joint_names());
    // The forearm's joint sits off its body origin: the chain has a link for the joint frame.
    assert!(mjcf
        .link_names()
        .iter()
        .any(|l| l == "forearm_link@elbow_joint"));
    assert!(mjcf.link_names().iter().any(|l| l == "forearm_link"));
}

#[test]
fn panda_equals_the_builtin_panda() {
    let mjcf = mjcf_chain("panda.xml", "panda_link0", "panda_hand_tcp");
    let reference = builtin("panda");
    check_same_kinematics("panda", &mjcf, &reference, IsometryMatrix3::identity());
    assert_limits_close("panda", &mjcf, &reference);
    assert_eq!(mjcf.joint_names(), reference.joint_names());
}

/// From the world body, the chain includes the base body's placement: `pos` and a
/// three-angle `euler`, which MJCF reads as x, then y, then z about the moving axes.
#[test]
fn panda_from_the_world_includes_the_euler_placement() {
    let mjcf = mjcf_chain("panda.xml", "world", "panda_hand_tcp");
    let world_from_link0 = Isometry3::from_parts(
        Translation3::new(0.1, 0.2, 0.3),
        UnitQuaternion::from_axis_angle(&Vector3::x_axis(), 0.1)
            * UnitQuaternion::from_axis_angle(&Vector3::y_axis(), 0.2)
            * UnitQuaternion::from_axis_angle(&Vector3::z_axis(), 0.3),
    );
    let world_from_link0: IsometryMatrix3<f64> = nalgebra::convert(world_from_link0);
    // The built-in chain, placed: world_from_link0 · panda(q) = mjcf(q) in the world frame.
    let reference = builtin("panda");
    for q in common::configurations(&reference, 50, 5) {
        let (expected, expected_j) = reference.pose_and_jacobian(&q).unwrap();
        let (pose, jacobian) = mjcf.pose_and_jacobian(&q).unwrap();
        let error = ((world_from_link0 * expected).to_homogeneous() - pose.to_homogeneous())
            .abs()
            .max();
        assert!(error <= TOL, "pose differs by {error:e}");
        let r = world_from_link0.rotation.matrix();
        for c in 0..q.len() {
            let v = r * expected_j.fixed_view::<3, 1>(0, c);
            let w = r * expected_j.fixed_view::<3, 1>(3, c);
            let got = jacobian.column(c);
            let error = (Vector6::new(v.x, v.y, v.z, w.x, w.y, w.z) - got)
                .abs()
                .max();
            assert!(error <= TOL, "Jacobian column {c} differs by {error:e}");
        }
    }
}

/// The fingers: `slide` joints from a nested default class (type, axis, range), closed form.
#[test]
fn panda_fingers_slide_along_their_axes() {
    for (tip, sign) in [("panda_leftfinger", 1.0), ("panda_rightfinger", -1.0)] {
        let finger = mjcf_chain("panda.xml", "panda_hand", tip);
        assert_eq!(finger.dof(), 1);
        assert_eq!((finger.lower()[0], finger.upper()[0]), (0.0, 0.04));
        for q in [0.0, 0.013, 0.04] {
            let (pose, jacobian) = finger.pose_and_jacobian(&[q]).unwrap();
            let expected = Vector3::new(0.0, sign * q, 0.0584);
            assert!((pose.translation.vector - expected).norm() < 1e-15);
            assert!(pose.rotation.matrix().relative_eq(
                &nalgebra::Matrix3::identity(),
                1e-15,
                1e-15
            ));
            let expected_j = Vector6::new(0.0, sign, 0.0, 0.0, 0.0, 0.0);
            assert!((jacobian.column(0) - expected_j).norm() < 1e-15);
        }
    }
}

fn urdf(data: &Path, relative: &str) -> graspath::robot::RobotModel {
    RobotSource::urdf(data.join(relative))
        .load()
        .unwrap_or_else(|e| panic!("{relative}: {e}"))
}

#[test]
fn ur5_and_panda_equal_the_example_robot_data_urdfs() {
    let Some(data) = common::robot_data() else {
        return;
    };
    let model = urdf(&data, "ur_description/urdf/ur5_robot.urdf");
    let reference = model.chain("base_link", "tool0", None).unwrap();
    let base_link_from_base = model
        .chain("base_link", "base", None)
        .unwrap()
        .pose(&[])
        .unwrap();
    let ur5 = mjcf_chain("ur5.xml", "base", "tool0");
    check_same_kinematics("ur5 vs URDF", &ur5, &reference, base_link_from_base);

    let model = urdf(&data, "panda_description/urdf/panda.urdf");
    let reference = model.chain("panda_link0", "panda_hand_tcp", None).unwrap();
    let panda = mjcf_chain("panda.xml", "panda_link0", "panda_hand_tcp");
    check_same_kinematics(
        "panda vs URDF",
        &panda,
        &reference,
        IsometryMatrix3::identity(),
    );
    assert_limits_close("panda vs URDF", &panda, &reference);
    let reference = model.chain("panda_hand", "panda_leftfinger", None).unwrap();
    let finger = mjcf_chain("panda.xml", "panda_hand", "panda_leftfinger");
    check_same_kinematics(
        "finger vs URDF",
        &finger,
        &reference,
        IsometryMatrix3::identity(),
    );
}

/// A free joint is left out when the chain starts at its body, and refused inside a chain.
#[test]
fn a_floating_base_is_left_out_or_refused() {
    let model = RobotSource::mjcf(data("ur5.xml")).load().unwrap();
    assert_eq!(model.chain("base", "tool0", None).unwrap().dof(), 6);
    let err = model.chain("world", "tool0", None).unwrap_err();
    assert!(matches!(err, RobotError::MjcfJointInChain { .. }), "{err}");
    let text = err.to_string();
    assert!(text.contains("ur5.xml"), "{text}");
    assert!(text.contains("body 'base', joint 'floating'"), "{text}");
    assert!(text.contains("free joint"), "{text}");
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

/// Two joints in one body, each with its own anchor and a `ref`, against MuJoCo's documented
/// composition: `body(q) = parent_from_body · Π_k T(pos_k) · R(axis_k, q_k − ref_k) · T(−pos_k)`
/// (a slide: `T(axis · (q − ref))`), and its Jacobian against central differences.
#[test]
fn several_joints_in_one_body_compose_in_order() {
    let dir = tempfile::tempdir().unwrap();
    let path = write(
        dir.path(),
        "two.xml",
        r#"<mujoco>
  <compiler angle="radian"/>
  <worldbody>
    <body name="a" pos="0.3 0 0.1" quat="0.8 0 0.6 0">
      <joint name="j1" axis="0 1 1" pos="0.1 -0.2 0.05" range="-2 2" ref="0.4"/>
      <joint name="j2" type="slide" axis="1 0 0.5" pos="0.2 0 0" range="-1 1" ref="-0.1"/>
      <joint name="j3" axis="1 0 0" pos="0 0.3 0" range="-2 2"/>
      <body name="b" pos="0.2 0.1 0" euler="0.3 -0.2 0.5"/>
    </body>
  </worldbody>
</mujoco>"#,
    );
    let chain = RobotSource::mjcf(&path)
        .load()
        .unwrap()
        .chain("world", "b", None)
        .unwrap();
    assert_eq!(chain.joint_names(), ["j1", "j2", "j3"]);
    let parent_from_a = Isometry3::from_parts(
        Translation3::new(0.3, 0.0, 0.1),
        UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(0.8, 0.0, 0.6, 0.0)),
    );
    let a_from_b = Isometry3::from_parts(
        Translation3::new(0.2, 0.1, 0.0),
        UnitQuaternion::from_axis_angle(&Vector3::x_axis(), 0.3)
            * UnitQuaternion::from_axis_angle(&Vector3::y_axis(), -0.2)
            * UnitQuaternion::from_axis_angle(&Vector3::z_axis(), 0.5),
    );
    let hinge = |axis: Vector3<f64>, pos: Vector3<f64>, angle: f64| {
        Translation3::from(pos)
            * UnitQuaternion::from_axis_angle(&nalgebra::Unit::new_normalize(axis), angle)
            * Translation3::from(-pos)
    };
    let oracle = |q: &[f64]| -> Isometry3<f64> {
        let slide_axis = Vector3::new(1.0, 0.0, 0.5).normalize();
        parent_from_a
            * hinge(
                Vector3::new(0.0, 1.0, 1.0),
                Vector3::new(0.1, -0.2, 0.05),
                q[0] - 0.4,
            )
            * Isometry3::from_parts(
                Translation3::from(slide_axis * (q[1] + 0.1)),
                UnitQuaternion::identity(),
            )
            * hinge(Vector3::x(), Vector3::new(0.0, 0.3, 0.0), q[2])
            * a_from_b
    };
    let h = 1e-6;
    for q in common::configurations(&chain, 30, 3) {
        let (pose, jacobian) = chain.pose_and_jacobian(&q).unwrap();
        let expected = oracle(&q);
        let error = (pose.to_homogeneous() - expected.to_homogeneous())
            .abs()
            .max();
        assert!(error < 1e-12, "pose differs by {error:e}");
        for j in 0..3 {
            let (mut plus, mut minus) = (q.clone(), q.clone());
            plus[j] += h;
            minus[j] -= h;
            let (p, m) = (oracle(&plus), oracle(&minus));
            let v = (p.translation.vector - m.translation.vector) / (2.0 * h);
            let w = (p.rotation * m.rotation.inverse()).scaled_axis() / (2.0 * h);
            let fd = Vector6::new(v.x, v.y, v.z, w.x, w.y, w.z);
            let error = (jacobian.column(j) - fd).abs().max();
            assert!(
                error < 1e-7,
                "column {j} differs from differences by {error:e}"
            );
        }
    }
}

/// Degrees are MuJoCo's default: the same model in degrees and in radians is the same chain;
/// an upper-case `eulerseq` turns about the fixed axes.
#[test]
fn angle_units_and_euler_sequences() {
    let dir = tempfile::tempdir().unwrap();
    let model = |compiler: &str, euler: &str, range: &str| {
        format!(
            r#"<mujoco>{compiler}<worldbody><body name="a" euler="{euler}">
                <joint name="j" axis="1 1 0" range="{range}"/><body name="b" pos="0.1 0.2 0.3"/>
            </body></worldbody></mujoco>"#
        )
    };
    let load = |name: &str, text: String| {
        let path = write(dir.path(), name, &text);
        MjcfRobot::from_file(&path)
            .unwrap()
            .chain("world", "b", None)
            .unwrap()
    };
    let degrees = load("deg.xml", model("", "30 -45 60", "-90 45"));
    let radians = load(
        "rad.xml",
        model(
            r#"<compiler angle="radian"/>"#,
            &format!("{} {} {}", PI / 6.0, -PI / 4.0, PI / 3.0),
            &format!("{} {}", -PI / 2.0, PI / 4.0),
        ),
    );
    assert!((degrees.lower()[0] + PI / 2.0).abs() < 1e-15);
    assert!((degrees.upper()[0] - PI / 4.0).abs() < 1e-15);
    for q in [-1.0, 0.0, 0.5] {
        let (a, b) = (degrees.pose(&[q]).unwrap(), radians.pose(&[q]).unwrap());
        assert!((a.to_homogeneous() - b.to_homogeneous()).abs().max() < 1e-14);
    }
    // Fixed axes: "XYZ" is Rz · Ry · Rx (x first, about the world axes).
    let fixed = load(
        "fixed.xml",
        model(
            r#"<compiler angle="radian" eulerseq="XYZ"/>"#,
            "0.1 0.2 0.3",
            "-1 1",
        ),
    );
    let at_zero = fixed.link_frames(&[0.0]).unwrap();
    let expected = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), 0.3)
        * UnitQuaternion::from_axis_angle(&Vector3::y_axis(), 0.2)
        * UnitQuaternion::from_axis_angle(&Vector3::x_axis(), 0.1);
    let a = fixed.link_names().iter().position(|l| l == "a").unwrap();
    let error = (at_zero[a].rotation.matrix() - expected.to_rotation_matrix().matrix())
        .abs()
        .max();
    assert!(error < 1e-15, "{error:e}");
}

fn shape_of(
    model: &graspath::robot::RobotModel,
    link: &str,
    name: &str,
) -> (Isometry3<f64>, Shape) {
    let collisions = model.collisions().unwrap();
    let link = collisions
        .iter()
        .find(|l| l.link == link)
        .unwrap_or_else(|| panic!("no collisions on {link}"));
    let shape = link
        .shapes
        .iter()
        .find(|s| s.name.as_deref() == Some(name))
        .unwrap_or_else(|| panic!("no shape {name}"));
    match &shape.geometry {
        CollisionGeometry::Shape(s) => (shape.link_from_collision, s.clone()),
        CollisionGeometry::Mesh(m) => panic!("{name} is a mesh: {m:?}"),
    }
}

/// Geom sizes follow MJCF: half-sizes for boxes, radius and half-length for capsules and
/// cylinders, `fromto` placing the geom's `z` between two points; defaults come from the
/// classes; visual geoms (contype = conaffinity = 0) are left out, planes are listed as skipped.
#[test]
fn geoms_become_collision_shapes() {
    let model = RobotSource::mjcf(data("ur5.xml")).load().unwrap();
    let close = |a: &Isometry3<f64>, b: &Isometry3<f64>| {
        (a.to_homogeneous() - b.to_homogeneous()).abs().max() < 1e-12
    };
    let (at, shape) = shape_of(&model, "base", "base_column");
    assert_eq!(shape, Shape::cylinder(0.076, 0.0535).unwrap());
    // fromto along +z: MuJoCo turns the geom half a turn about x (its z axis points from the
    // second point to the first).
    let flipped = Isometry3::from_parts(
        Translation3::new(0.0, 0.0, 0.0535 / 2.0),
        UnitQuaternion::from_axis_angle(&Vector3::x_axis(), PI),
    );
    assert!(close(&at, &flipped), "{at}");
    // fromto along −x of the upper-arm frame, radius from the class default; the geom's z
    // axis points from the second point to the first, as MuJoCo's compiler places it.
    let (at, shape) = shape_of(&model, "upper_arm_link", "upper_arm");
    assert_eq!(shape, Shape::capsule(0.062, 0.425).unwrap());
    let z = at.rotation * Vector3::z();
    assert!((z - Vector3::x()).norm() < 1e-12, "{z}");
    assert!((at.translation.vector - Vector3::new(-0.2125, 0.0, 0.13585)).norm() < 1e-12);
    let (_, shape) = shape_of(&model, "forearm_link", "forearm");
    assert_eq!(shape, Shape::cuboid([0.39225, 0.094, 0.094]).unwrap());
    // Nested class "wrist": its size overrides the parent class's.
    let (at, shape) = shape_of(&model, "wrist_1_link", "wrist_1");
    assert_eq!(shape, Shape::capsule(0.046, 0.08).unwrap());
    assert!(close(&at, &Isometry3::translation(0.0, 0.0, 0.05)));
    let (_, shape) = shape_of(&model, "wrist_2_link", "wrist_2");
    assert_eq!(shape, Shape::sphere(0.046).unwrap());
    let (_, shape) = shape_of(&model, "wrist_3_link", "flange");
    assert_eq!(shape, Shape::cylinder(0.046, 0.033).unwrap());
    let collisions = model.collisions().unwrap();
    assert!(collisions
        .iter()
        .flat_map(|l| &l.shapes)
        .all(|s| s.name.as_deref() != Some("shoulder_look")));
    let skipped = model.mjcf().unwrap().skipped_geoms();
    assert_eq!(skipped.len(), 1, "{skipped:?}");
    assert_eq!(skipped[0].body, "world");
    assert!(skipped[0].reason.contains("plane"), "{skipped:?}");
}

/// A mesh geom: its file is found under `<compiler meshdir>`, scaled by the asset's `scale`,
/// and reads as a triangle mesh; a missing file names every place tried.
#[test]
fn mesh_geoms_resolve_under_meshdir() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("assets")).unwrap();
    write(
        &dir.path().join("assets"),
        "tri.stl",
        "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid t\n",
    );
    // The mesh is named after its file's stem when it has no name.
    let text = |file: &str| {
        let stem = file.trim_end_matches(".stl");
        format!(
            r#"<mujoco><compiler meshdir="assets"/>
  <asset><mesh file="{file}" scale="2 2 2"/></asset>
  <worldbody><body name="a"><geom name="m" type="mesh" mesh="{stem}" pos="0 0 1"/></body></worldbody>
</mujoco>"#
        )
    };
    let path = write(dir.path(), "mesh.xml", &text("tri.stl"));
    let model = RobotSource::mjcf(&path).load().unwrap();
    let collisions = model.collisions().unwrap();
    let shape = &collisions[0].shapes[0];
    let CollisionGeometry::Mesh(mesh) = &shape.geometry else {
        panic!("not a mesh: {shape:?}")
    };
    assert_eq!(mesh.path, dir.path().join("assets/tri.stl"));
    assert_eq!(mesh.scale, [2.0; 3]);
    let read = load_collision_mesh(mesh).unwrap();
    assert_eq!(read.triangles().len(), 1);
    let path = write(dir.path(), "missing.xml", &text("gone.stl"));
    let err = RobotSource::mjcf(&path)
        .load()
        .unwrap()
        .collisions()
        .unwrap_err();
    assert!(matches!(err, RobotError::MeshNotFound { .. }), "{err}");
    assert!(err.to_string().contains("assets/gone.stl"), "{err}");
}

/// Loads `text` as `name` in a temporary folder and returns the error of loading it (or of
/// the chain `world → b`).
fn error_of(name: &str, text: &str) -> String {
    let dir = tempfile::tempdir().unwrap();
    let path = write(dir.path(), name, text);
    let err = match MjcfRobot::from_file(&path) {
        Err(e) => e,
        Ok(robot) => robot.chain("world", "b", None).unwrap_err(),
    };
    let message = err.to_string();
    assert!(
        message.contains(name),
        "the error names the file: {message}"
    );
    message
}

#[test]
fn bad_input_gets_clear_errors() {
    // A ball joint between base and tip.
    let m = error_of(
        "ball.xml",
        r#"<mujoco><worldbody><body name="a"><joint name="shoulder" type="ball"/>
           <body name="b" pos="0 0 1"/></body></worldbody></mujoco>"#,
    );
    assert!(m.contains("body 'a', joint 'shoulder'"), "{m}");
    assert!(m.contains("ball joint"), "{m}");
    // An unknown body as the tip, with a suggestion.
    let dir = tempfile::tempdir().unwrap();
    let path = write(
        dir.path(),
        "tip.xml",
        r#"<mujoco><worldbody><body name="forearm"><joint axis="1 0 0"/></body></worldbody></mujoco>"#,
    );
    let err = MjcfRobot::from_file(&path)
        .unwrap()
        .chain("world", "forarm", None)
        .unwrap_err();
    assert!(matches!(err, RobotError::UnknownLink { .. }), "{err}");
    let m = err.to_string();
    assert!(m.contains("tip.xml") && m.contains("'forarm'"), "{m}");
    assert!(m.contains("did you mean: forearm?"), "{m}");
    // In the file's own terms: bodies, not URDF links.
    assert!(
        m.contains("no body named 'forarm' (given as the tip body)"),
        "{m}"
    );
    let err = MjcfRobot::from_file(&path)
        .unwrap()
        .chain("forearm", "world", None)
        .unwrap_err();
    let m = err.to_string();
    assert!(
        m.contains("tip body 'world' is not below base body 'forearm'"),
        "{m}"
    );
    // Malformed XML: line and column.
    let m = error_of(
        "broken.xml",
        "<mujoco>\n<worldbody>\n<body name=\"a\">\n</worldbody>\n</mujoco>",
    );
    assert!(m.contains("broken.xml:4:"), "{m}");
    assert!(m.contains("malformed XML"), "{m}");
    // limited="true" without a range.
    let m = error_of(
        "limits.xml",
        r#"<mujoco><worldbody><body name="b">
<joint name="j" limited="true"/></body></worldbody></mujoco>"#,
    );
    assert!(m.contains("limits.xml:2:"), "{m}");
    assert!(m.contains("<joint name=\"j\">, attribute 'range'"), "{m}");
    // NaN in a body's pos.
    let m = error_of(
        "nan.xml",
        r#"<mujoco><worldbody><body name="b" pos="0 NaN 0"/></worldbody></mujoco>"#,
    );
    assert!(m.contains("<body name=\"b\">, attribute 'pos'"), "{m}");
    assert!(m.contains("finite"), "{m}");
    // The wrong root, an unknown class, two orientations, a bad number count.
    let m = error_of("robot.xml", "<robot name=\"r\"/>");
    assert!(m.contains("not <mujoco>"), "{m}");
    let m = error_of(
        "class.xml",
        r#"<mujoco><worldbody><body name="b" childclass="arm"/></worldbody></mujoco>"#,
    );
    assert!(
        m.contains("attribute 'childclass'") && m.contains("no default class 'arm'"),
        "{m}"
    );
    let m = error_of(
        "two.xml",
        r#"<mujoco><worldbody><body name="b" quat="1 0 0 0" euler="0 0 0"/></worldbody></mujoco>"#,
    );
    assert!(m.contains("give one orientation"), "{m}");
    let m = error_of(
        "count.xml",
        r#"<mujoco><worldbody><body name="b"><joint axis="0 1"/></body></worldbody></mujoco>"#,
    );
    assert!(
        m.contains("attribute 'axis'") && m.contains("expected 3 numbers"),
        "{m}"
    );
    // An unlimited slide joint in the chain.
    let m = error_of(
        "slide.xml",
        r#"<mujoco><worldbody><body name="b"><joint name="s" type="slide"/></body></worldbody></mujoco>"#,
    );
    assert!(m.contains("joint 's'") && m.contains("range"), "{m}");
    // A non-positive geom size.
    let m = error_of(
        "geom.xml",
        r#"<mujoco><worldbody><body name="b"><geom type="box" size="0.1 -0.1 0.1"/></body></worldbody></mujoco>"#,
    );
    assert!(m.contains("attribute 'size'"), "{m}");
}

/// An MJCF file handed to the URDF reader says where it belongs.
#[test]
fn the_urdf_reader_points_mjcf_files_to_the_mjcf_source() {
    let text = std::fs::read_to_string(data("ur5.xml")).unwrap();
    let err = UrdfRobot::from_xml(&text, "ur5.xml").unwrap_err();
    assert!(err.to_string().contains("mjcf: FILE"), "{err}");
}

/// `robot: {mjcf: FILE}` in a task file: chains name bodies, and a scene builds the arm's
/// collision bodies from the geoms; giving two robot sources is refused.
#[test]
fn task_files_take_mjcf_robots() {
    let dir = tempfile::tempdir().unwrap();
    let model = data("ur5.xml");
    let body = |robot: &str| {
        format!(
            "robot:\n  {robot}\n  chains: {{ arm: {{ base: base, tip: tool0 }} }}\n\
             object:\n  pose: {{ xyz: [0.45, 0.0, 0.2] }}\n  shape: {{ box: {{ size: [0.05, 0.05, 0.1] }} }}\n\
             candidates:\n  family: {{ edge: {{ count: 3 }} }}\n\
             trajectory:\n  samples_per_step: 3\n  steps:\n    - {{ lift: 0.1 }}\n\
             scene: {{ table: {{ height: 0.0 }} }}\n"
        )
    };
    let path = write(
        dir.path(),
        "task.yaml",
        &body(&format!("mjcf: {}", model.display())),
    );
    let task = graspath::task::Task::load(&path).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(task.robot_name(), "ur5");
    assert_eq!(task.arms().len(), 1);
    assert_eq!(task.arms()[0].chain.dof(), 6);
    assert!(task.arms()[0].bodies.is_some());
    let path = write(
        dir.path(),
        "both.yaml",
        &body(&format!("mjcf: {}\n  urdf: arm.urdf", model.display())),
    );
    let err = graspath::task::Task::load(&path).unwrap_err().to_string();
    assert!(
        err.contains("robot") && err.contains("not several"),
        "{err}"
    );
}

/// Names MuJoCo's compiler refuses to repeat (bodies, joints — `freejoint` included —, geoms,
/// meshes, default classes) are refused, naming the file, the line, the name and the first use.
#[test]
fn repeated_names_are_refused_as_mujoco_refuses_them() {
    for (file, text, fragments) in [
        (
            "joints.xml",
            "<mujoco><worldbody>\n<body name=\"a\"><joint name=\"j\"/><geom size=\"0.1\"/>\n<body name=\"b\"><joint name=\"j\"/><geom size=\"0.1\"/></body></body>\n</worldbody></mujoco>",
            &["joints.xml:3:", "<joint name=\"j\">", "a second joint named 'j' (first used on line 2)"][..],
        ),
        (
            "freejoint.xml",
            "<mujoco><worldbody>\n<body name=\"a\"><freejoint name=\"j\"/><geom size=\"0.1\"/>\n<body name=\"b\"><joint name=\"j\"/><geom size=\"0.1\"/></body></body>\n</worldbody></mujoco>",
            &["freejoint.xml:3:", "a second joint named 'j'"],
        ),
        (
            "bodies.xml",
            "<mujoco><worldbody>\n<body name=\"a\"/>\n<body name=\"a\"/>\n</worldbody></mujoco>",
            &["bodies.xml:3:", "a second body named 'a' (first used on line 2)"],
        ),
        (
            "world.xml",
            "<mujoco><worldbody>\n<body name=\"world\"/>\n</worldbody></mujoco>",
            &["world.xml:2:", "a second body named 'world' (the world body's name)"],
        ),
        (
            "geoms.xml",
            "<mujoco><worldbody>\n<geom name=\"g\" size=\"0.1\"/>\n<body name=\"a\"><geom name=\"g\" size=\"0.1\" contype=\"0\" conaffinity=\"0\"/></body>\n</worldbody></mujoco>",
            &["geoms.xml:3:", "a second geom named 'g'"],
        ),
        (
            "meshes.xml",
            "<mujoco><asset>\n<mesh file=\"a.stl\"/>\n<mesh file=\"parts/a.stl\"/>\n</asset><worldbody/></mujoco>",
            &["meshes.xml:3:", "a second mesh named 'a'"],
        ),
        (
            "classes.xml",
            "<mujoco><default>\n<default class=\"c\"/>\n<default class=\"c\"/>\n</default><worldbody/></mujoco>",
            &["classes.xml:3:", "default class 'c' is defined twice"],
        ),
    ] {
        let m = error_of(file, text);
        for fragment in fragments {
            assert!(m.contains(fragment), "{file}: {m}");
        }
    }
}

/// An element's own orientation replaces its class's whatever their kinds (MuJoCo's
/// compiler; Menagerie's ANYmal B): a geom's `quat` over its class's `euler`, a nested class's
/// `quat` over its parent's `euler`. Two on one element, or on one default, are refused.
#[test]
fn an_elements_orientation_replaces_its_class_orientation() {
    let dir = tempfile::tempdir().unwrap();
    let path = write(
        dir.path(),
        "precedence.xml",
        r#"<mujoco><default><geom type="sphere" size="0.1" euler="0 0 90"/>
<default class="inner"><geom quat="0 1 0 0"/></default></default>
<worldbody><body name="b">
<geom name="own" quat="0 0 1 0"/><geom name="class"/><geom name="inner" class="inner"/>
<geom name="inner_own" class="inner" axisangle="1 0 0 90"/>
</body></worldbody></mujoco>"#,
    );
    let robot = MjcfRobot::from_file(&path).unwrap();
    let shapes = &robot.collisions(&robot.mesh_resolver()).unwrap()[0].shapes;
    let rotation = |k: usize| UnitQuaternion::from(shapes[k].link_from_collision.rotation);
    let expected = [
        UnitQuaternion::from_axis_angle(&Vector3::y_axis(), PI),
        UnitQuaternion::from_axis_angle(&Vector3::z_axis(), PI / 2.0),
        UnitQuaternion::from_axis_angle(&Vector3::x_axis(), PI),
        UnitQuaternion::from_axis_angle(&Vector3::x_axis(), PI / 2.0),
    ];
    for (k, expected) in expected.iter().enumerate() {
        assert!(
            rotation(k).angle_to(expected) < 1e-12,
            "geom {:?}: {:?}",
            shapes[k].name,
            rotation(k)
        );
    }
    let m = error_of(
        "two_in_class.xml",
        "<mujoco><default>\n<geom quat=\"1 0 0 0\" euler=\"0 0 0\"/></default><worldbody/></mujoco>",
    );
    assert!(
        m.contains("two_in_class.xml:2:") && m.contains("give one orientation, not quat and euler"),
        "{m}"
    );
    let m = error_of(
        "two_on_geom.xml",
        "<mujoco><default><geom euler=\"0 0 1\"/></default><worldbody>\n<geom size=\"1\" zaxis=\"0 0 1\" xyaxes=\"1 0 0 0 1 0\"/></worldbody></mujoco>",
    );
    assert!(
        m.contains("two_on_geom.xml:2:") && m.contains("give one orientation"),
        "{m}"
    );
}

/// Chain checks on MJCF models speak MJCF: a body `pos` too far away or a joint `range` beyond
/// the largest limit name the element, its line and the attribute, not URDF fields.
#[test]
fn chain_errors_name_mjcf_elements_and_attributes() {
    let m = error_of(
        "far.xml",
        "<mujoco><worldbody>\n<body name=\"b\" pos=\"0 0 5000\"><joint name=\"j\" range=\"-1 1\"/><geom size=\"0.1\"/></body>\n</worldbody></mujoco>",
    );
    assert!(
        m.contains("far.xml:2:") && m.contains("<body name=\"b\">, attribute 'pos'"),
        "{m}"
    );
    assert!(!m.contains("origin") && !m.contains("URDF"), "{m}");
    let m = error_of(
        "range.xml",
        "<mujoco><compiler angle=\"radian\"/><worldbody>\n<body name=\"b\">\n<joint name=\"j\" range=\"-1e20 1\"/><geom size=\"0.1\"/></body>\n</worldbody></mujoco>",
    );
    assert!(
        m.contains("range.xml:3:") && m.contains("<joint name=\"j\">, attribute 'range'"),
        "{m}"
    );
    assert!(!m.contains("continuous") && !m.contains("limit'"), "{m}");
    // An unknown class among many: the message stays short and suggests the close ones.
    let mut text = String::from("<mujoco><default>");
    for k in 0..2000 {
        text.push_str(&format!("<default class=\"class{k}\"/>"));
    }
    text.push_str(
        "</default><worldbody><body name=\"b\" childclass=\"clas7\"/></worldbody></mujoco>",
    );
    let m = error_of("classes.xml", &text);
    assert!(
        m.contains("no default class 'clas7' (2001 classes defined; did you mean: class7"),
        "{m}"
    );
    assert!(m.len() < 400, "{m}");
}
