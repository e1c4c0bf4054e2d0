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
