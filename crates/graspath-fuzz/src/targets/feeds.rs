//! The feed functions: each gives one input to the code under test (a parser, a loader, a
//! CLI command's reader) and accepts `Ok` or a typed error; a few check invariants of what
//! they read.

use super::*;

/// Loads a task file. The one place that names the task loader, so that a move of `Task`
/// (e.g. to `graspath::task`) changes one line.
pub(super) fn load_task(path: &Path) {
    let _ = graspath::task::Task::load(path);
}

/// Successful cloud reads must hold only finite points, and unit normals when present.
pub(super) fn check_cloud<E>(result: Result<PointCloud, E>) {
    let Ok(cloud) = result else { return };
    assert!(
        !cloud.points.is_empty(),
        "invariant: a cloud read without error has points"
    );
    assert!(
        cloud.points.iter().all(|p| p.iter().all(|c| c.is_finite())),
        "invariant: a cloud read without error has only finite points"
    );
    if let Some(normals) = &cloud.normals {
        assert_eq!(
            normals.len(),
            cloud.points.len(),
            "invariant: one normal per point"
        );
        assert!(
            normals.iter().all(|n| (n.norm() - 1.0).abs() < 1e-6),
            "invariant: normals are unit vectors"
        );
    }
}

pub(super) fn sample_mesh(mesh: &graspath::cloud::TriangleMesh) {
    let options = SampleOptions {
        points: 64,
        ..SampleOptions::default()
    };
    check_cloud(mesh.sample(&options, "fuzz mesh"));
}

pub(super) fn run_urdf(ctx: &Ctx, bytes: &[u8]) {
    let text = String::from_utf8_lossy(bytes);
    let Ok(robot) = UrdfRobot::from_xml(&text, "fuzz.urdf") else {
        return;
    };
    let doc = robot.document();
    let children: std::collections::HashSet<&str> =
        doc.joints.iter().map(|j| j.child.link.as_str()).collect();
    let roots: Vec<&str> = doc
        .links
        .iter()
        .map(|l| l.name.as_str())
        .filter(|l| !children.contains(l))
        .take(2)
        .collect();
    let links: Vec<&str> = doc.links.iter().map(|l| l.name.as_str()).take(12).collect();
    let meshes = graspath::robot::MeshResolver::from_env(&ctx.dir, Vec::new());
    for base in &roots {
        let _ = graspath::grasp::hand::hand_from_urdf(&robot, base, &meshes);
        for tip in &links {
            let Ok(chain) = robot.chain(base, tip, None) else {
                continue;
            };
            let q = chain.mid_configuration();
            let _ = chain.within_limits(&q);
            let mut jacobian = nalgebra::Matrix6xX::zeros(chain.dof());
            if let Ok(pose) = chain.pose_and_jacobian_into(&q, &mut jacobian) {
                let _ = yoshikawa(&jacobian, JacobianPart::Full);
                let _ = inverse_condition(&jacobian, JacobianPart::Full);
                let target = nalgebra::convert(pose);
                let options = IkOptions {
                    max_time: None,
                    max_iterations: 50,
                    ..IkOptions::default()
                };
                let _ = solve_ik(&chain, &target, &q, &options);
            }
        }
    }
}

pub(super) fn tiny_generate_options() -> GenerateOptions {
    GenerateOptions {
        initial_grasps: 8,
        steps: 4,
        first_stage_steps: 2,
        query_kernels: 64,
        tries: 1,
        keep_fraction: 0.5,
        seed: 0,
    }
}

pub(super) fn run_model(_: &Ctx, bytes: &[u8]) {
    let text = String::from_utf8_lossy(bytes);
    let Ok(model) = GraspModel::from_json(&text, "fuzz_model.json") else {
        return;
    };
    let cloud = small_cloud(true);
    if let Ok(candidates) = generate(&model, &cloud, &tiny_generate_options(), "fuzz", &|_| {}) {
        let _ = candidates_json(&candidates, "fuzz");
    }
}

pub(super) fn run_generate(ctx: &Ctx, bytes: &[u8]) {
    let cloud = if bytes.starts_with(b"ply") {
        read_ply_bytes(bytes, "fuzz.ply")
    } else {
        read_pcd_bytes(bytes, "fuzz.pcd")
    };
    let (Ok(cloud), Some(model)) = (cloud, ctx.model()) else {
        return;
    };
    let _ = generate(model, &cloud, &tiny_generate_options(), "fuzz", &|_| {});
}

pub(super) fn run_demo(ctx: &Ctx, bytes: &[u8]) {
    let _ = graspath::grasp::model::train_file(&ctx.file("demo.json", bytes));
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct KinematicsLine {
    q: Vec<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct PoseLine {
    pose: [[f64; 4]; 4],
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct TrajectoryInput {
    poses: Vec<[[f64; 4]; 4]>,
}

/// The non-blank lines of a JSON Lines input, as the CLI reads them (`BufRead::lines`: a line
/// that is not UTF-8 ends the input with an error).
pub(super) fn json_lines(bytes: &[u8]) -> impl Iterator<Item = &str> {
    bytes
        .split(|b| *b == b'\n')
        .map_while(|line| std::str::from_utf8(line).ok())
        .map(|line| line.strip_suffix('\r').unwrap_or(line))
        .filter(|line| !line.trim().is_empty())
}

/// Mirrors `graspath kinematics` (crates/graspath-cli/src/commands/kinematics.rs), whose input
/// types are private to the binary.
pub(super) fn run_kinematics(ctx: &Ctx, bytes: &[u8]) {
    let chain = ctx.baxter();
    let mut jacobian = nalgebra::Matrix6xX::zeros(chain.dof());
    for line in json_lines(bytes) {
        let Ok(input) = serde_json::from_str::<KinematicsLine>(line) else {
            return;
        };
        let Ok(_pose) = chain.pose_and_jacobian_into(&input.q, &mut jacobian) else {
            return;
        };
        let _ = yoshikawa(&jacobian, JacobianPart::Full);
        let _ = yoshikawa(&jacobian, JacobianPart::Translation);
        let _ = inverse_condition(&jacobian, JacobianPart::Full);
        let _ = chain.within_limits(&input.q);
    }
}

/// Mirrors `graspath ik` on JSON Lines with the CLI's defaults (start `mid`, 5 ms per pose).
pub(super) fn run_ik(ctx: &Ctx, bytes: &[u8]) {
    let chain = ctx.baxter();
    let q_start = chain.mid_configuration();
    let options = IkOptions::default();
    for line in json_lines(bytes) {
        let Ok(input) = serde_json::from_str::<PoseLine>(line) else {
            return;
        };
        let Ok(target) = pose_from_rows(&input.pose) else {
            return;
        };
        if let Ok(solution) = solve_ik(chain, &target, &q_start, &options) {
            let _ = serde_json::to_string(&(
                solution.q,
                solution.position_error,
                solution.rotation_error,
            ));
        }
    }
}

/// Mirrors `graspath ik --trajectory` with the CLI's defaults (step 0.5, 4 branches).
pub(super) fn run_ik_trajectory(ctx: &Ctx, bytes: &[u8]) {
    let chain = ctx.baxter();
    let Ok(text) = std::str::from_utf8(bytes) else {
        return;
    };
    let Ok(input) = serde_json::from_str::<TrajectoryInput>(text) else {
        return;
    };
    let Ok(poses) = input
        .poses
        .iter()
        .map(pose_from_rows)
        .collect::<Result<Vec<_>, _>>()
    else {
        return;
    };
    if poses.is_empty() {
        return;
    }
    let defaults = TrajectoryIkOptions::default();
    let options = TrajectoryIkOptions {
        ik: IkOptions {
            max_time: None,
            ..IkOptions::default()
        },
        max_joint_step: 0.5,
        branches: 4,
        ..defaults
    };
    if let Ok(result) = solve_trajectory(chain, &poses, &chain.mid_configuration(), &options) {
        let _ = serde_json::to_string(&result);
    }
}

// ---------------------------------------------------------------------------------------------
// Seeds
