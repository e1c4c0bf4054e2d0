//! The built-in arms against third-party robot descriptions: the URDFs (and meshes) of the
//! `example-robot-data` package (PyPI; Gepetto/LAAS). `.ci/run` installs it and sets
//! `GRASPATH_ROBOT_DATA` to its `robots` folder. In CI (`CI=true`) a missing package fails
//! these tests; elsewhere they print why they are skipped.
//!
//! Run locally: `python3 -m venv target/pyenv && target/pyenv/bin/pip install
//! example-robot-data`, then `GRASPATH_ROBOT_DATA=$(target/pyenv/bin/python -c 'import
//! sysconfig; print(sysconfig.get_paths()["purelib"])')/cmeel.prefix/share/example-robot-data/robots
//! cargo test -p graspath --test robot_data -- --nocapture`.

mod common;

use graspath::cloud::load_collision_mesh;
use graspath::robot::builtin::ARM_CHAIN;
use graspath::robot::{Chain, CollisionGeometry, RobotModel, RobotSource};
use nalgebra::IsometryMatrix3;

/// A URDF of example-robot-data, with mesh lookup rooted at its `share` folder (the
/// `package://example-robot-data/robots/...` URIs resolve there).
fn urdf(data: &std::path::Path, relative: &str) -> RobotModel {
    let share = data
        .parent()
        .and_then(|p| p.parent())
        .unwrap()
        .to_path_buf();
    RobotSource::Urdf {
        path: data.join(relative),
        search_paths: vec![share],
        xacro_args: Default::default(),
    }
    .load()
    .unwrap_or_else(|e| panic!("{relative}: {e}"))
}

fn builtin(name: &str, chain: &str) -> Chain {
    RobotSource::builtin(name)
        .load()
        .unwrap()
        .named_chain(chain, None)
        .unwrap()
}

/// `reference_from_base · built_in(q)` equals `reference(q)` at 200 seeded configurations
/// inside the built-in chain's limits.
fn check_same_kinematics(
    what: &str,
    built_in: &Chain,
    reference: &Chain,
    reference_from_base: IsometryMatrix3<f64>,
) {
    let configurations = common::configurations(built_in, 200, 23);
    common::assert_same_kinematics(
        what,
        built_in,
        reference,
        reference_from_base,
        &configurations,
    );
}

#[test]
fn panda_and_fr3_equal_the_panda_urdf() {
    let Some(data) = common::robot_data() else {
        return;
    };
    let model = urdf(&data, "panda_description/urdf/panda.urdf");
    let reference = model.chain("panda_link0", "panda_hand_tcp", None).unwrap();
    let panda = builtin("panda", ARM_CHAIN);
    check_same_kinematics("panda", &panda, &reference, IsometryMatrix3::identity());
    assert_eq!(panda.lower(), reference.lower());
    assert_eq!(panda.upper(), reference.upper());
    check_same_kinematics(
        "fr3",
        &builtin("fr3", ARM_CHAIN),
        &reference,
        IsometryMatrix3::identity(),
    );
}

#[test]
fn xarm7_equals_its_urdf() {
    let Some(data) = common::robot_data() else {
        return;
    };
    let model = urdf(&data, "xarm_description/urdf/xarm7.urdf");
    let reference = model.chain("link_base", "link_eef", None).unwrap();
    let xarm = builtin("xarm7", ARM_CHAIN);
    check_same_kinematics("xarm7", &xarm, &reference, IsometryMatrix3::identity());
    assert_eq!(xarm.lower(), reference.lower());
    assert_eq!(xarm.upper(), reference.upper());
}

#[test]
fn baxter_equals_its_urdf() {
    let Some(data) = common::robot_data() else {
        return;
    };
    let model = urdf(&data, "baxter_description/urdf/baxter.urdf");
    for side in ["left", "right"] {
        let reference = model
            .chain("base", &format!("{side}_gripper"), None)
            .unwrap();
        check_same_kinematics(
            side,
            &builtin("baxter", side),
            &reference,
            IsometryMatrix3::identity(),
        );
    }
}

/// ur_description's chains start at `base_link`; the built-in ones at `base`, which the URDF
/// places below `base_link` (the transform is read from the file, not typed here).
#[test]
fn ur5_and_ur10_equal_ur_description() {
    let Some(data) = common::robot_data() else {
        return;
    };
    for name in ["ur5", "ur10"] {
        let model = urdf(&data, &format!("ur_description/urdf/{name}_robot.urdf"));
        let reference = model.chain("base_link", "tool0", None).unwrap();
        let base_link_from_base = model
            .chain("base_link", "base", None)
            .unwrap()
            .pose(&[])
            .unwrap();
        let built_in = builtin(name, ARM_CHAIN);
        check_same_kinematics(name, &built_in, &reference, base_link_from_base);
    }
}

/// The full robots load with their collision meshes: every mesh URI resolves to a file, the
/// STL meshes read, and the arm chains build.
#[test]
fn full_robots_load_with_their_collision_meshes() {
    let Some(data) = common::robot_data() else {
        return;
    };
    let robots = [
        (
            "panda_description/urdf/panda.urdf",
            vec![("panda_link0", "panda_hand_tcp")],
        ),
        (
            "ur_description/urdf/ur5_robot.urdf",
            vec![("base_link", "tool0")],
        ),
        (
            "baxter_description/urdf/baxter.urdf",
            vec![("base", "left_gripper"), ("base", "right_gripper")],
        ),
    ];
    for (file, chains) in robots {
        let model = urdf(&data, file);
        for (base, tip) in chains {
            let chain = model.chain(base, tip, None).unwrap();
            assert!(chain.dof() >= 6, "{file}: {base} → {tip}");
        }
        let collisions = model.collisions().unwrap_or_else(|e| panic!("{file}: {e}"));
        let mut meshes = 0;
        let mut read = 0;
        for link in &collisions {
            for shape in &link.shapes {
                if let CollisionGeometry::Mesh(mesh) = &shape.geometry {
                    meshes += 1;
                    assert!(mesh.path.is_file(), "{file}: {}", mesh.uri);
                    let extension = mesh.path.extension().and_then(|e| e.to_str());
                    // Baxter's meshes are COLLADA, which the mesh reader does not take.
                    if extension.is_some_and(|e| e.eq_ignore_ascii_case("stl")) {
                        let trimesh = load_collision_mesh(mesh).unwrap();
                        assert!(!trimesh.triangles().is_empty(), "{}", mesh.uri);
                        read += 1;
                    }
                }
            }
        }
        assert!(meshes > 0, "{file}: no collision meshes");
        eprintln!("{file}: {meshes} collision meshes resolved, {read} read");
    }
}

/// Gravity torques, inverse dynamics and the mass matrix of `built_in` equal `reference`'s
/// (both with gravity along their own base's −z, which is the same direction when
/// `reference_from_base` is a turn about z) to `tolerance`, relative to the largest entry, at
/// 50 seeded states.
fn check_same_dynamics(what: &str, built_in: &Chain, reference: &Chain, tolerance: f64) {
    let ours = built_in.dynamics().unwrap();
    let theirs = reference.dynamics().unwrap();
    let mut worst = 0.0f64;
    let relative = |a: &[f64], b: &[f64]| {
        let scale = b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let error = a
            .iter()
            .zip(b)
            .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
        error / scale
    };
    for (k, q) in common::configurations(built_in, 50, 41).iter().enumerate() {
        let qd: Vec<f64> = (0..q.len())
            .map(|j| ((k + j) % 5) as f64 * 0.4 - 0.8)
            .collect();
        let qdd: Vec<f64> = (0..q.len())
            .map(|j| ((k * 3 + j) % 7) as f64 - 3.0)
            .collect();
        let pairs = [
            (
                ours.gravity_torques(q).unwrap(),
                theirs.gravity_torques(q).unwrap(),
            ),
            (
                ours.inverse_dynamics(q, &qd, &qdd).unwrap(),
                theirs.inverse_dynamics(q, &qd, &qdd).unwrap(),
            ),
            (
                ours.mass_matrix(q).unwrap().as_slice().to_vec(),
                theirs.mass_matrix(q).unwrap().as_slice().to_vec(),
            ),
        ];
        for (a, b) in &pairs {
            worst = worst.max(relative(a, b));
        }
    }
    assert!(
        worst <= tolerance,
        "{what}: built-in dynamics differ from the URDF's by {worst:e} (relative)"
    );
    eprintln!("{what}: built-in dynamics within {worst:.1e} of the URDF's");
}

/// The built-in Panda, Baxter and xArm 7 carry their URDFs' masses, centres of mass and
/// inertias (the off-chain links, such as fingers and cameras, folded in) and their velocity
/// and effort limits. The tables are written to 10 significant digits.
#[test]
fn built_in_dynamics_equal_the_urdfs() {
    let Some(data) = common::robot_data() else {
        return;
    };
    let cases = [
        (
            "panda",
            ARM_CHAIN,
            "panda_description/urdf/panda.urdf",
            "panda_link0",
            "panda_hand_tcp",
        ),
        (
            "baxter",
            "left",
            "baxter_description/urdf/baxter.urdf",
            "base",
            "left_gripper",
        ),
        (
            "baxter",
            "right",
            "baxter_description/urdf/baxter.urdf",
            "base",
            "right_gripper",
        ),
        (
            "xarm7",
            ARM_CHAIN,
            "xarm_description/urdf/xarm7.urdf",
            "link_base",
            "link_eef",
        ),
    ];
    for (name, chain, file, base, tip) in cases {
        let reference = urdf(&data, file).chain(base, tip, None).unwrap();
        let built_in = builtin(name, chain);
        let what = format!("{name} {chain}");
        check_same_dynamics(&what, &built_in, &reference, 1e-8);
        for (j, (ours, theirs)) in built_in
            .motion_limits()
            .iter()
            .zip(reference.motion_limits())
            .enumerate()
        {
            assert_eq!(ours.velocity, theirs.velocity, "{what}: joint {j} velocity");
            assert_eq!(ours.effort, theirs.effort, "{what}: joint {j} effort");
        }
    }
}

/// The built-in UR5 and UR10 take Universal Robots' published masses and centres of mass
/// (in the DH frames); ROS-Industrial's `ur_description` (example-robot-data) has nearly the
/// same masses with centres placed by hand at the links' middles. The two are different
/// models, so they agree only roughly: the total masses to 1 %, and the shoulder-lift and
/// elbow gravity torques, which the heavy links dominate, to 20 % of the largest such torque
/// over the configurations. A
/// centre of mass moved into a wrong frame (a sign, a swapped axis, a missing link length)
/// is off by far more.
#[test]
fn ur_gravity_is_close_to_ur_description() {
    let Some(data) = common::robot_data() else {
        return;
    };
    for name in ["ur5", "ur10"] {
        let model = urdf(&data, &format!("ur_description/urdf/{name}_robot.urdf"));
        // ur_description's chain starts at `base_link`, the built-in `base` turned about z:
        // the same gravity direction, and joint torques do not depend on the base frame.
        let reference = model.chain("base_link", "tool0", None).unwrap();
        let built_in = builtin(name, ARM_CHAIN);
        let ours = built_in.dynamics().unwrap();
        let theirs = reference.dynamics().unwrap();
        let (m_ours, m_theirs) = (ours.moving_mass(), theirs.moving_mass());
        assert!(
            (m_ours - m_theirs).abs() <= 0.01 * m_theirs,
            "{name}: moving mass {m_ours} kg vs {m_theirs} kg"
        );
        // The largest difference over the configurations, relative to the largest torque
        // (the shoulder lift's with the arm stretched out).
        let (mut difference, mut scale) = (0.0f64, 0.0f64);
        for q in common::configurations(&built_in, 50, 43) {
            let a = ours.gravity_torques(&q).unwrap();
            let b = theirs.gravity_torques(&q).unwrap();
            for j in [1, 2] {
                difference = difference.max((a[j] - b[j]).abs());
                scale = scale.max(b[j].abs());
            }
        }
        let worst = difference / scale;
        assert!(
            worst <= 0.2,
            "{name}: shoulder and elbow gravity torques differ by {worst:.3} of the largest"
        );
        eprintln!(
            "{name}: shoulder and elbow gravity torques within {worst:.3} of ur_description's"
        );
    }
}
