//! Every link frame along a chain (`Chain::link_frames_into`) against three oracles: a naive
//! composition of the URDF joint transforms written here, the tip pose of sub-chains built to
//! each link as their tip, and Pinocchio's joint placements on Baxter's left arm.

mod common;

use graspath::robot::builtin::{baxter, baxter_spec, Arm};
use graspath::robot::{Chain, ChainSpec, JointKind, RobotError, UrdfRobot};
use nalgebra::{Isometry3, IsometryMatrix3, Matrix4, Translation3, UnitQuaternion};
use rand::{rngs::StdRng, RngExt, SeedableRng};
use serde_json::Value;

/// `base_from_link` of every link by composing `parent_from_joint · motion(q)` joint by joint.
fn naive_frames(spec: &ChainSpec, chain: &Chain, q: &[f64]) -> Vec<Isometry3<f64>> {
    let mut frames = vec![Isometry3::identity()];
    let mut pose = Isometry3::identity();
    for joint in &spec.joints {
        let value = |name: &str| q[chain.joint_names().iter().position(|n| n == name).unwrap()];
        let v = match (&joint.mimic, joint.kind) {
            (_, JointKind::Fixed) => 0.0,
            (Some(m), _) => m.multiplier * value(&m.leader) + m.offset,
            (None, _) => value(&joint.name),
        };
        let motion = match joint.kind {
            JointKind::Fixed => Isometry3::identity(),
            JointKind::Prismatic => Isometry3::from_parts(
                Translation3::from(joint.axis * v),
                UnitQuaternion::identity(),
            ),
            _ => Isometry3::from_parts(
                Translation3::identity(),
                UnitQuaternion::from_scaled_axis(joint.axis * v),
            ),
        };
        pose = pose * joint.parent_from_joint * motion;
        frames.push(pose);
    }
    frames
}

fn random_q(chain: &Chain, rng: &mut StdRng) -> Vec<f64> {
    chain
        .lower()
        .iter()
        .zip(chain.upper())
        .map(|(&lo, &hi)| {
            let (lo, hi) = (lo.max(-3.0), hi.min(3.0));
            lo + rng.random::<f64>() * (hi - lo)
        })
        .collect()
}

fn assert_close(a: &IsometryMatrix3<f64>, b: &Matrix4<f64>, tol: f64, what: &str) {
    let d = (a.to_homogeneous() - b).abs().max();
    assert!(d < tol, "{what}: differs by {d}");
}

fn check_against_naive(spec: &ChainSpec) {
    let chain = Chain::from_spec(spec).unwrap();
    assert_eq!(chain.link_names().len(), spec.joints.len() + 1);
    assert_eq!(chain.link_names()[0], spec.base_link);
    let mut rng = StdRng::seed_from_u64(5);
    let mut frames = vec![IsometryMatrix3::identity(); chain.link_names().len()];
    for _ in 0..50 {
        let q = random_q(&chain, &mut rng);
        chain.link_frames_into(&q, &mut frames).unwrap();
        for (k, naive) in naive_frames(spec, &chain, &q).iter().enumerate() {
            assert_close(
                &frames[k],
                &naive.to_homogeneous(),
                1e-12,
                &chain.link_names()[k],
            );
        }
        // The tip link's frame with the tool offset is the tip pose.
        let tip = frames.last().unwrap();
        let tool = spec.tip_from_tool.unwrap_or_else(Isometry3::identity);
        let expected: Isometry3<f64> = nalgebra::convert(chain.pose(&q).unwrap());
        let got = nalgebra::convert::<_, Isometry3<f64>>(*tip) * tool;
        assert!(
            (got.to_homogeneous() - expected.to_homogeneous())
                .abs()
                .max()
                < 1e-12
        );
    }
}

#[test]
fn builtin_baxter_links_match_a_naive_composition() {
    for arm in [Arm::Left, Arm::Right] {
        check_against_naive(&baxter_spec(arm));
    }
    let names = baxter(Arm::Left).link_names().to_vec();
    assert_eq!(names.first().map(String::as_str), Some("base"));
    assert!(names.iter().any(|n| n == "left_upper_elbow"));
    assert_eq!(names.last().map(String::as_str), Some("left_gripper"));
}

#[test]
fn prismatic_mimic_and_fixed_links_match_a_naive_composition() {
    let urdf = r#"<robot name="mix">
      <link name="a"/><link name="b"/><link name="c"/><link name="d"/><link name="e"/>
      <joint name="offset" type="fixed"><parent link="a"/><child link="b"/>
        <origin xyz="0.1 0.2 0.3" rpy="0.3 -0.2 0.1"/></joint>
      <joint name="slide" type="prismatic"><parent link="b"/><child link="c"/>
        <axis xyz="0 1 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
      <joint name="turn" type="continuous"><parent link="c"/><child link="d"/>
        <origin xyz="0.3 0 0" rpy="0.1 0.2 0.3"/><axis xyz="1 0 0"/></joint>
      <joint name="follow" type="revolute"><parent link="d"/><child link="e"/>
        <origin xyz="0.2 0.1 0"/><axis xyz="0 0 -1"/><limit lower="-3" upper="3" effort="1" velocity="1"/>
        <mimic joint="turn" multiplier="2" offset="0.1"/></joint>
    </robot>"#;
    let robot = UrdfRobot::from_xml(urdf, "mix.urdf").unwrap();
    check_against_naive(&robot.chain_spec("a", "e", None).unwrap());
    check_against_naive(
        &robot
            .chain_spec("b", "d", Some(Isometry3::translation(0.0, 0.0, 0.1)))
            .unwrap(),
    );
}

#[test]
fn link_frames_equal_sub_chain_tips() {
    let Some(path) = common::shared_file("robots/panda.urdf") else {
        return;
    };
    let robot = UrdfRobot::from_file(&path).unwrap();
    let chain = robot.chain("panda_link0", "panda_hand_tcp", None).unwrap();
    let mut rng = StdRng::seed_from_u64(8);
    for _ in 0..20 {
        let q = random_q(&chain, &mut rng);
        let frames = chain.link_frames(&q).unwrap();
        for (k, name) in chain.link_names().iter().enumerate().skip(1) {
            let sub = robot.chain("panda_link0", name, None).unwrap();
            let pose = sub.pose(&q[..sub.dof()]).unwrap();
            assert_close(&frames[k], &pose.to_homogeneous(), 1e-12, name);
        }
    }
}

#[test]
fn urdf_baxter_joint_frames_match_pinocchio() {
    let Some(reference) = common::shared_file("reference/baxter_left_pinocchio.json") else {
        return;
    };
    let reference: Value =
        serde_json::from_str(&std::fs::read_to_string(reference).unwrap()).unwrap();
    let urdf = common::shared_file("robots/baxter.urdf").unwrap();
    let robot = UrdfRobot::from_file(&urdf).unwrap();
    let spec = robot.chain_spec("base", "left_gripper", None).unwrap();
    let chain = Chain::from_spec(&spec).unwrap();
    let matrix = |v: &Value| Matrix4::from_fn(|r, c| v[r][c].as_f64().unwrap());
    let joints = reference["joints"].as_array().unwrap();
    // Pinocchio's joint i frame is the URDF frame of the joint's child link.
    let links: Vec<usize> = joints
        .iter()
        .map(|j| {
            let name = j["name"].as_str().unwrap();
            assert_eq!(j["pinocchio_type"], "JointModelRZ");
            let child = &spec
                .joints
                .iter()
                .find(|s| s.name == name)
                .unwrap()
                .child_link;
            chain.link_index(child).unwrap()
        })
        .collect();
    for sample in reference["samples"].as_array().unwrap() {
        let q: Vec<f64> = sample["q"]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect();
        let frames = chain.link_frames(&q).unwrap();
        let mut world_from_joint = Matrix4::identity();
        for (i, joint) in joints.iter().enumerate() {
            let (s, c) = q[i].sin_cos();
            let rz = Matrix4::new(
                c, -s, 0.0, 0.0, s, c, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0,
            );
            world_from_joint = world_from_joint * matrix(&joint["placement_in_parent"]) * rz;
            assert_close(
                &frames[links[i]],
                &world_from_joint,
                1e-9,
                joint["name"].as_str().unwrap(),
            );
        }
        let tip = world_from_joint * matrix(&reference["tip_placement_in_last_joint"]);
        assert_close(frames.last().unwrap(), &tip, 1e-9, "tip");
        assert_close(frames.last().unwrap(), &matrix(&sample["T"]), 1e-9, "T");
    }
}

#[test]
fn wrong_buffer_or_configuration_is_refused() {
    let chain = baxter(Arm::Left);
    let mut short = vec![IsometryMatrix3::identity(); 3];
    let err = chain.link_frames_into(&[0.0; 7], &mut short).unwrap_err();
    assert!(
        matches!(err, RobotError::WrongLinkCount { got: 3, .. }),
        "{err}"
    );
    assert!(err.to_string().contains("links"), "{err}");
    assert!(matches!(
        chain.link_frames(&[0.0; 6]),
        Err(RobotError::WrongDof { .. })
    ));
}
