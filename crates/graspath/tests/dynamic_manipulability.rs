//! The dynamic task-relevant manipulability in the selection: its per-sample values and its
//! column recomputed independently from the chosen motion (explicit `M⁻¹` by LU, `g(q)`, the
//! Jacobian, the wrist tangent from the wrist poses, the object's mass moved to the tool by the
//! grasp), ranking by it, and the task errors when the robot cannot give it.

use graspath::manipulability::{wrist_tangent, PathNorms, SampleIndex};
use graspath::manipulability::{IndexMeasure, JacobianRows};
use graspath::select::{select, wrist_trajectory, CandidateScore};
use graspath::task::{Task, TaskFile};
use nalgebra::{DMatrix, DVector, Matrix6xX, Vector3};
use std::path::Path;

/// Baxter's left arm lifting, carrying and placing a box; one IK branch.
fn task(index: &str, object_fields: &str) -> Task {
    let text = format!(
        r#"
robot: {{ builtin: baxter }}
arms: left
object:
  pose: {{ xyz: [0.75, 0.0, -0.10] }}
  shape: {{ box: {{ size: [0.06, 0.40, 0.10] }} }}
  {object_fields}
candidates:
  family: {{ edge: {{ count: 9, depth: 0.02, margin: 0.02 }} }}
trajectory:
  samples_per_step: 5
  steps:
    - {{ lift: 0.2, label: pick }}
    - {{ move: [0.0, 0.3, 0.0], label: move }}
    - {{ place: 0.2, rotate: {{ axis: [0, 0, 1], angle_deg: 20 }}, label: place }}
index: {{ {index} }}
ik: {{ branches: 1, iterations: 2000, redundancy: first }}
timing: false
"#
    );
    let file = TaskFile::parse(&text, "dynamic.yaml", "yaml").expect("a valid task file");
    Task::from_file(&file, "dynamic.yaml", Path::new(".")).expect("a valid task")
}

/// Oracle: `M_D` at each path sample of `score`'s chosen motion, from explicit matrices.
fn recomputed(task: &Task, score: &CandidateScore) -> Vec<Option<f64>> {
    let payload = task.payload();
    let arm = &task.arms()[0];
    let chain = &arm.chain;
    let gravity = arm.world_from_base.inverse().rotation * Vector3::new(0.0, 0.0, -9.81);
    let dynamics = chain.dynamics().unwrap().with_gravity(gravity).unwrap();
    let mut data = dynamics.data();
    let object_from_wrist = score.candidate.object_from_wrist;
    data.set_payload(payload.map(|p| p.transformed(&object_from_wrist.inverse())))
        .unwrap();
    let wrists = wrist_trajectory(task.path(), &arm.world_from_base, &object_from_wrist);
    let dof = chain.dof();
    let length_scale = match task.rows() {
        JacobianRows::Twist { length_scale } => length_scale,
        _ => 1.0,
    };
    (0..wrists.len())
        .map(|i| {
            // The motion leaving each sample; at the last one the last interval's screw
            // motion continued, so the twist is expressed at that sample.
            let (from, to) = if i + 1 < wrists.len() {
                (wrists[i], wrists[i + 1])
            } else {
                (wrists[i], wrists[i] * wrists[i - 1].inverse() * wrists[i])
            };
            let u = wrist_tangent(&from, &to, task.rows())?.as_full();
            let q = &score.joint_trajectory[i];
            let mut jacobian = Matrix6xX::zeros(dof);
            chain.pose_and_jacobian_into(q, &mut jacobian).unwrap();
            for r in 3..6 {
                for c in 0..dof {
                    jacobian[(r, c)] *= length_scale;
                }
            }
            let mut g = vec![0.0; dof];
            dynamics.gravity_torques_into(&mut data, q, &mut g).unwrap();
            let mut mass = DMatrix::zeros(dof, dof);
            dynamics.mass_matrix_into(&mut data, q, &mut mass).unwrap();
            let inverse = mass.lu().try_inverse().unwrap();
            let limits = dynamics.motion_limits();
            let headroom = DMatrix::from_diagonal(&DVector::from_iterator(
                dof,
                (0..dof).map(|j| (limits[j].effort.unwrap() - g[j].abs()).max(0.0)),
            ));
            let gain = u.transpose() * jacobian * inverse * headroom;
            Some(gain.norm_squared())
        })
        .collect()
}

fn norm_of(task: &Task, values: &[Option<f64>]) -> f64 {
    let samples: Vec<SampleIndex> = values
        .iter()
        .zip(&task.path().samples)
        .map(|(&value, s)| SampleIndex {
            time: s.time,
            value,
        })
        .collect();
    PathNorms::of(&samples).value(task.selection().norm)
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-9 * a.abs().max(b.abs()).max(1e-12)
}

#[test]
fn ranking_by_the_dynamic_measure_ranks_the_recomputed_values() {
    let object = "mass: 0.4\n  center_of_mass: [0.0, 0.05, 0.0]";
    let task = task("measure: dynamic", object);
    assert_eq!(task.ranked().measure, IndexMeasure::Dynamic);
    let arm = select(&task, &|| {}).unwrap().arms.remove(0);
    let mut checked = 0;
    for score in arm.scores.iter().filter(|s| s.feasible()) {
        let expected = recomputed(&task, score);
        let got = score.ranked_values.as_ref().expect("the ranked series");
        assert_eq!(got.len(), expected.len());
        for (i, (g, e)) in got.iter().zip(&expected).enumerate() {
            match (g, e) {
                (Some(g), Some(e)) => assert!(close(*g, *e), "sample {i}: {g} vs {e}"),
                (None, None) => {}
                other => panic!("sample {i}: {other:?}"),
            }
        }
        let norm = norm_of(&task, &expected);
        let ranked = score.norms.unwrap().value(task.selection().norm);
        assert!(close(ranked, norm), "{ranked} vs {norm}");
        assert!(close(score.dynamic_manipulability.unwrap(), norm));
        checked += 1;
    }
    assert!(
        checked >= 3,
        "only {checked} feasible candidates: {:?}",
        arm.scores.iter().map(|s| &s.failure).collect::<Vec<_>>()
    );
    // The ranking follows the dynamic norm (likelihoods are equal in a family).
    let mut by_rank: Vec<(usize, f64)> = arm
        .rankings
        .iter()
        .zip(&arm.scores)
        .filter_map(|(r, s)| Some((r.rank?, s.dynamic_manipulability?)))
        .collect();
    by_rank.sort_by_key(|&(rank, _)| rank);
    let ranked: Vec<f64> = by_rank.iter().map(|&(_, v)| v).collect();
    assert!(ranked.windows(2).all(|w| w[0] >= w[1]), "{ranked:?}");
}

#[test]
fn the_column_is_reported_with_the_object_s_mass_and_only_then() {
    let with_mass = task("", "mass: 0.4");
    let scores = select(&with_mass, &|| {}).unwrap().arms.remove(0).scores;
    let mut checked = 0;
    for score in scores.iter().filter(|s| s.feasible()) {
        let expected = norm_of(&with_mass, &recomputed(&with_mass, score));
        let got = score.dynamic_manipulability.expect("a column with a mass");
        assert!(close(got, expected), "{got} vs {expected}");
        checked += 1;
    }
    assert!(checked >= 3);
    let without = task("", "");
    let plain = select(&without, &|| {}).unwrap().arms.remove(0).scores;
    assert!(plain.iter().all(|s| s.dynamic_manipulability.is_none()));
    // The same motions without the object: the measure grows back (the object's weight takes
    // headroom and its inertia adds to M) at every sample here.
    let empty = task("measure: dynamic", "");
    let empty_scores = select(&empty, &|| {}).unwrap().arms.remove(0).scores;
    for (loaded, bare) in scores
        .iter()
        .zip(&empty_scores)
        .filter(|(s, _)| s.feasible())
    {
        assert_eq!(loaded.joint_trajectory, bare.joint_trajectory);
        assert!(bare.dynamic_manipulability.unwrap() > loaded.dynamic_manipulability.unwrap());
    }
}

#[test]
fn the_dynamic_measure_needs_inertial_data_and_effort_limits() {
    let dir = tempfile::tempdir().unwrap();
    for (name, inertial, limit) in [
        (
            "no_inertia",
            "",
            r#"<limit lower="-2" upper="2" effort="5" velocity="1"/>"#,
        ),
        (
            "no_effort",
            r#"<inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>"#,
            r#"<limit lower="-2" upper="2" effort="0" velocity="1"/>"#,
        ),
    ] {
        let urdf = format!(
            r#"<robot name="r"><link name="base"/><link name="a">{inertial}</link><link name="tip"/>
            <joint name="j1" type="revolute"><parent link="base"/><child link="a"/><axis xyz="0 0 1"/>{limit}</joint>
            <joint name="j2" type="fixed"><parent link="a"/><child link="tip"/><origin xyz="0.3 0 0"/></joint></robot>"#
        );
        let path = dir.path().join(format!("{name}.urdf"));
        std::fs::write(&path, urdf).unwrap();
        let text = format!(
            r#"
robot: {{ urdf: {}, chains: {{ arm: {{ base: base, tip: tip }} }} }}
object: {{ pose: {{ xyz: [0.3, 0.0, 0.0] }}, shape: {{ box: {{ size: [0.05, 0.05, 0.05] }} }} }}
candidates: {{ family: {{ yaw: {{ count: 1, step_deg: 10, start_deg: 0, depth: 0.0 }} }} }}
trajectory: {{ samples_per_step: 3, steps: [ {{ move: [0.0, 0.01, 0.0] }} ] }}
index: {{ measure: dynamic }}
"#,
            path.display()
        );
        let file = TaskFile::parse(&text, "t.yaml", "yaml").unwrap();
        let error = Task::from_file(&file, "t.yaml", dir.path()).unwrap_err();
        let message = format!("{}", graspath::Chain(&error));
        assert!(message.contains("index.measure"), "{name}: {message}");
        let expected = if name == "no_inertia" {
            "no inertial data"
        } else {
            "joint 'j1' has no effort limit"
        };
        assert!(message.contains(expected), "{name}: {message}");
    }
}
