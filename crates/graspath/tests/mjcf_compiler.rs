//! MJCF files in the style of MuJoCo's compiler tests — orientations in every form given on
//! elements and by (nested) default classes, `<compiler angle>` in degrees and radians, Euler
//! sequences about moving and fixed axes, joint `ref` and `pos`, several joints in one body,
//! `<frame>` — equal MuJoCo's own compiler and forward kinematics to 1e-12: the world pose of
//! every body and every named geom at seeded joint values.
//!
//! The reference is `tests/data/mjcf/compiler/compiler_mujoco.json`, written by
//! `mujoco_poses.py` beside the files (MuJoCo from PyPI). When the Python named by
//! `GRASPATH_PYTHON` (else `python3`) can import `mujoco`, the script is also run afresh and
//! its output checked the same way; with `CI=true` a missing `mujoco` is a failure (`.ci/run`
//! installs it).

use graspath::robot::{MjcfRobot, RobotSource};
use nalgebra::{IsometryMatrix3, Matrix3, Quaternion, Rotation3, UnitQuaternion, Vector3};
use serde_json::Value;
use std::collections::HashMap;
use std::io::Write;
use std::path::{Path, PathBuf};

const TOL: f64 = 1e-12;

fn folder() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/mjcf/compiler")
}

fn numbers(value: &Value) -> Vec<f64> {
    value
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect()
}

/// Checks every case of a reference (the JSON the script prints) against graspath.
fn check_reference(reference: &Value, what: &str) {
    let cases = reference["cases"].as_object().unwrap();
    assert!(cases.len() >= 3, "{what}: {} cases", cases.len());
    let mut checked = (0, 0);
    for (file, configurations) in cases {
        let mut largest = 0.0f64;
        let path = folder().join(file);
        let model = RobotSource::mjcf(&path)
            .load()
            .unwrap_or_else(|e| panic!("{file}: {e}"));
        let robot: &MjcfRobot = model.mjcf().unwrap();
        let collisions = robot.collisions(&robot.mesh_resolver()).unwrap();
        // Each named geom: its body and its frame in the body.
        let mut geoms = HashMap::new();
        for link in &collisions {
            for shape in &link.shapes {
                if let Some(name) = &shape.name {
                    geoms.insert(name.clone(), (link.link.clone(), shape.link_from_collision));
                }
            }
        }
        for configuration in configurations.as_array().unwrap() {
            let qpos = configuration["qpos"].as_object().unwrap();
            let world_from = |body: &str| -> IsometryMatrix3<f64> {
                let chain = robot
                    .chain("world", body, None)
                    .unwrap_or_else(|e| panic!("{file}: {e}"));
                let q: Vec<f64> = chain
                    .joint_names()
                    .iter()
                    .map(|j| qpos[j].as_f64().unwrap())
                    .collect();
                chain.pose(&q).unwrap()
            };
            for (body, expected) in configuration["bodies"].as_object().unwrap() {
                let e = numbers(expected);
                let rotation =
                    UnitQuaternion::from_quaternion(Quaternion::new(e[3], e[4], e[5], e[6]));
                let expected = IsometryMatrix3::from_parts(
                    Vector3::new(e[0], e[1], e[2]).into(),
                    rotation.to_rotation_matrix(),
                );
                let error = (world_from(body).to_homogeneous() - expected.to_homogeneous())
                    .abs()
                    .max();
                assert!(
                    error <= TOL,
                    "{what}: {file}, body '{body}' at {qpos:?}: differs from MuJoCo by {error:e}"
                );
                largest = largest.max(error);
                checked.0 += 1;
            }
            for (geom, expected) in configuration["geoms"].as_object().unwrap() {
                let e = numbers(expected);
                let (body, body_from_geom) = geoms
                    .get(geom)
                    .unwrap_or_else(|| panic!("{file}: geom '{geom}' is not a collision shape"));
                let body_from_geom = IsometryMatrix3::from_parts(
                    body_from_geom.translation,
                    body_from_geom.rotation.to_rotation_matrix(),
                );
                let world_from_geom = world_from(body) * body_from_geom;
                // geom_xmat is row-major.
                let matrix = Matrix3::from_row_slice(&e[3..12]);
                let expected = IsometryMatrix3::from_parts(
                    Vector3::new(e[0], e[1], e[2]).into(),
                    Rotation3::from_matrix_unchecked(matrix),
                );
                let error = (world_from_geom.to_homogeneous() - expected.to_homogeneous())
                    .abs()
                    .max();
                assert!(
                    error <= TOL,
                    "{what}: {file}, geom '{geom}' at {qpos:?}: differs from MuJoCo by {error:e}"
                );
                largest = largest.max(error);
                checked.1 += 1;
            }
        }
        eprintln!("{what}: {file}: largest difference from MuJoCo {largest:e}");
    }
    assert!(
        checked.0 > 20 && checked.1 > 40,
        "{what}: checked {checked:?}"
    );
}

#[test]
fn compiler_cases_equal_the_recorded_mujoco_poses() {
    let text = std::fs::read_to_string(folder().join("compiler_mujoco.json")).unwrap();
    check_reference(&serde_json::from_str(&text).unwrap(), "recorded");
}

/// Runs `mujoco_poses.py` with a Python that has `mujoco`; `None` (after saying why) when there
/// is none, a failure in CI.
fn fresh_reference() -> Option<Value> {
    let python = std::env::var("GRASPATH_PYTHON").unwrap_or_else(|_| "python3".into());
    let output = std::process::Command::new(&python)
        .arg(folder().join("mujoco_poses.py"))
        .output();
    let why = match output {
        Err(e) => format!("cannot run {python}: {e}"),
        Ok(out) if out.status.success() => {
            return Some(serde_json::from_slice(&out.stdout).unwrap());
        }
        Ok(out) => format!(
            "{python} mujoco_poses.py failed: {}",
            String::from_utf8_lossy(&out.stderr)
                .lines()
                .last()
                .unwrap_or("")
        ),
    };
    if std::env::var("CI").is_ok_and(|v| v == "true") {
        panic!("MuJoCo is required in CI: {why} (.ci/run installs it and sets GRASPATH_PYTHON)");
    }
    let _ = writeln!(
        std::io::stderr(),
        "SKIPPED: MuJoCo not available ({why}); `pip install mujoco` and set GRASPATH_PYTHON"
    );
    None
}

#[test]
fn compiler_cases_equal_mujoco_run_now() {
    if let Some(reference) = fresh_reference() {
        check_reference(&reference, "fresh");
    }
}
