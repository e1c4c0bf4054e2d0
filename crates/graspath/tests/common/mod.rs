//! Helpers shared by the integration tests: locating `../shared` and example-robot-data
//! (skipped when absent, except example-robot-data in CI).

#![allow(dead_code)]

use std::path::PathBuf;

/// The shared folder beside the repository, if present.
pub fn shared_dir() -> Option<PathBuf> {
    let manifest = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let candidates = [
        std::env::var_os("GRASPATH_SHARED").map(PathBuf::from),
        Some(manifest.join("../../../shared")),
    ];
    candidates
        .into_iter()
        .flatten()
        .find(|p| p.join("robots/baxter.urdf").is_file())
}

/// A file under the shared folder, or `None` (with a message) when the folder is absent.
pub fn shared_file(relative: &str) -> Option<PathBuf> {
    match shared_dir() {
        Some(dir) => Some(dir.join(relative)),
        None => {
            eprintln!("skipped: ../shared is not present (set GRASPATH_SHARED to point at it)");
            None
        }
    }
}

/// The `robots` folder of example-robot-data (`GRASPATH_ROBOT_DATA`, set by `.ci/run`), or
/// `None` after printing why the test skips. Panics in CI (`CI=true`), where the package must
/// be installed.
pub fn robot_data() -> Option<PathBuf> {
    use std::io::Write;
    let dir = std::env::var_os("GRASPATH_ROBOT_DATA").map(PathBuf::from);
    let found = dir.clone().filter(|d| d.join("panda_description").is_dir());
    if found.is_none() {
        let why = match dir {
            None => "GRASPATH_ROBOT_DATA is not set".to_string(),
            Some(d) => format!("{} holds no panda_description", d.display()),
        };
        if std::env::var("CI").is_ok_and(|v| v == "true") {
            panic!("example-robot-data is required in CI: {why} (.ci/run installs it)");
        }
        // Straight to the process's stderr: the harness captures `eprintln!`, and a skip must
        // not hide behind `ok`.
        let _ = writeln!(
            std::io::stderr(),
            "SKIPPED: example-robot-data not found ({why}); see README, \"Tests on third-party robots\""
        );
    }
    found
}

use graspath::robot::{Chain, ChainSpec, JointKind, JointSpec, RobotSource};
use nalgebra::{Isometry3, IsometryMatrix3, Matrix6xX, Translation3, UnitQuaternion, Vector3};
use rand::rngs::StdRng;
use rand::{RngExt, SeedableRng};

/// The JSON document `tests/data/<relative>` (reference values written by the scripts beside
/// them).
pub fn reference_json(relative: &str) -> serde_json::Value {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(relative);
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// A reference file's body `{mass, com, inertia}` (kg, m, kg·m² as a 3 × 3 list).
pub fn json_body(v: &serde_json::Value) -> graspath::robot::RigidBody {
    let inertia: Vec<f64> = v["inertia"]
        .as_array()
        .expect("inertia rows")
        .iter()
        .flat_map(json_numbers)
        .collect();
    graspath::robot::RigidBody::new(
        v["mass"].as_f64().expect("mass"),
        Vector3::from_vec(json_numbers(&v["com"])),
        nalgebra::Matrix3::from_row_slice(&inertia),
    )
}

/// A reference file's list of joint names.
pub fn json_names(v: &serde_json::Value) -> Vec<String> {
    v.as_array()
        .expect("names")
        .iter()
        .map(|n| n.as_str().expect("a name").to_string())
        .collect()
}

/// The chain `base` → `tip` (with `tip_from_tool`) of the example-robot-data URDF `urdf`
/// (relative to `data`, the package's `robots` folder; its meshes' packages are found in the
/// `share` folder above it).
pub fn example_robot_chain(
    data: &std::path::Path,
    urdf: &str,
    (base, tip): (&str, &str),
    tip_from_tool: Option<Isometry3<f64>>,
) -> Chain {
    let share = data
        .parent()
        .and_then(|p| p.parent())
        .expect("robots lies in share/example-robot-data")
        .to_path_buf();
    RobotSource::Urdf {
        path: data.join(urdf),
        search_paths: vec![share],
        xacro_args: Default::default(),
    }
    .load()
    .unwrap_or_else(|e| panic!("{urdf}: {e}"))
    .chain(base, tip, tip_from_tool)
    .unwrap_or_else(|e| panic!("{urdf}: {e}"))
}

/// `count` seeded configurations of `chain`, uniform inside its limits (over one revolution for
/// a joint without limits).
pub fn configurations(chain: &Chain, count: usize, seed: u64) -> Vec<Vec<f64>> {
    let mut rng = StdRng::seed_from_u64(seed);
    (0..count)
        .map(|_| {
            (0..chain.dof())
                .map(|j| {
                    let (lo, hi) = (chain.lower()[j], chain.upper()[j]);
                    if lo.is_finite() && hi > lo {
                        rng.random_range(lo..hi)
                    } else {
                        rng.random_range(-std::f64::consts::PI..std::f64::consts::PI)
                    }
                })
                .collect()
        })
        .collect()
}

/// `reference_from_base · chain(q)` equals `reference(q)` at every `q` of `configurations`:
/// the pose and the Jacobian (rotated into the reference base frame) to 1e-9.
pub fn assert_same_kinematics(
    what: &str,
    chain: &Chain,
    reference: &Chain,
    reference_from_base: IsometryMatrix3<f64>,
    configurations: &[Vec<f64>],
) {
    const TOL: f64 = 1e-9;
    assert_eq!(chain.dof(), reference.dof(), "{what}: joints");
    let r = reference_from_base.rotation.matrix();
    for q in configurations {
        let (pose, jacobian) = chain.pose_and_jacobian(q).unwrap();
        let (expected, expected_j) = reference.pose_and_jacobian(q).unwrap();
        let error = ((reference_from_base * pose).to_homogeneous() - expected.to_homogeneous())
            .abs()
            .max();
        assert!(error <= TOL, "{what} at {q:?}: pose differs by {error:e}");
        let mut rotated = Matrix6xX::zeros(jacobian.ncols());
        rotated
            .fixed_rows_mut::<3>(0)
            .copy_from(&(r * jacobian.fixed_rows::<3>(0)));
        rotated
            .fixed_rows_mut::<3>(3)
            .copy_from(&(r * jacobian.fixed_rows::<3>(3)));
        let error = (rotated - expected_j).abs().max();
        assert!(
            error <= TOL,
            "{what} at {q:?}: Jacobian differs by {error:e}"
        );
    }
}

/// The UR5 arm (`base_link` → `tool0`) from Universal Robots' published joint origins (the
/// values of `ur_description`), with every joint limited to `±limit` (rad). Built in the test
/// so that the suite does not need `../shared`.
pub fn ur5_like(limit: f64) -> Chain {
    let half_pi = std::f64::consts::FRAC_PI_2;
    let joint = |name: &str, xyz: [f64; 3], rpy: [f64; 3], axis: Vector3<f64>| JointSpec {
        name: name.into(),
        child_link: format!("{name}_child"),
        kind: JointKind::Revolute,
        parent_from_joint: Isometry3::from_parts(
            Translation3::new(xyz[0], xyz[1], xyz[2]),
            UnitQuaternion::from_euler_angles(rpy[0], rpy[1], rpy[2]),
        ),
        axis,
        lower: -limit,
        upper: limit,
        mimic: None,
        limits: Default::default(),
        child_inertial: None,
    };
    let y = Vector3::y();
    let z = Vector3::z();
    let joints = vec![
        joint("shoulder_pan_joint", [0.0, 0.0, 0.089159], [0.0; 3], z),
        joint(
            "shoulder_lift_joint",
            [0.0, 0.13585, 0.0],
            [0.0, half_pi, 0.0],
            y,
        ),
        joint("elbow_joint", [0.0, -0.1197, 0.425], [0.0; 3], y),
        joint("wrist_1_joint", [0.0, 0.0, 0.39225], [0.0, half_pi, 0.0], y),
        joint("wrist_2_joint", [0.0, 0.093, 0.0], [0.0; 3], z),
        joint("wrist_3_joint", [0.0, 0.0, 0.09465], [0.0; 3], y),
    ];
    Chain::from_spec(&ChainSpec {
        source_name: "test ur5".into(),
        base_link: "base_link".into(),
        tip_link: "tool0".into(),
        joints,
        tip_from_tool: Some(Isometry3::from_parts(
            Translation3::new(0.0, 0.0823, 0.0),
            UnitQuaternion::from_euler_angles(-half_pi, 0.0, 0.0),
        )),
    })
    .expect("a valid chain")
}

/// The tip pose at `q` as an `Isometry3`.
pub fn fk(chain: &Chain, q: &[f64]) -> Isometry3<f64> {
    nalgebra::convert(chain.pose(q).expect("q has the chain's length"))
}

/// Position (m) and rotation (rad) distance between two poses.
pub fn pose_distance(a: &Isometry3<f64>, b: &Isometry3<f64>) -> (f64, f64) {
    (
        (a.translation.vector - b.translation.vector).norm(),
        a.rotation.angle_to(&b.rotation),
    )
}

/// The numbers of a JSON array (reference data written by the oracle scripts).
pub fn json_numbers(v: &serde_json::Value) -> Vec<f64> {
    v.as_array()
        .expect("an array")
        .iter()
        .map(|x| x.as_f64().expect("a number"))
        .collect()
}

/// `‖ours − reference‖∞ / ‖reference‖∞`, asserted at most `tolerance`; `what` names the
/// quantity in the failure.
pub fn max_relative_error(ours: &[f64], reference: &[f64], tolerance: f64, what: &str) -> f64 {
    assert_eq!(ours.len(), reference.len(), "{what}: length");
    let scale = reference.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let error = ours
        .iter()
        .zip(reference)
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    let relative = error / scale.max(f64::MIN_POSITIVE);
    assert!(
        relative <= tolerance,
        "{what}: relative error {relative:e}\n ours      {ours:?}\n reference {reference:?}"
    );
    relative
}
