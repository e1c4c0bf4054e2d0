//! The ranked index beside the paper's `M_T` (`index.measure`, `index.joint_limit_penalty`),
//! the distance to the joint limits, and the classical indices at the grasp, on the paper's
//! Pick-and-Place (left arm, the cuboid's top edge). Oracles: the velocity transmission ratio
//! from an explicit inverse of `J' J'ᵀ` and a tangent by finite differences of the wrist poses,
//! Tsai's penalty written out, limit distances by brute force, and invariance of the classical
//! indices under the redundancy setting.

use graspath::defaults;
use graspath::manipulability::JacobianRows;
use graspath::manipulability::{wrist_tangent, Direction, PathNorms, SampleIndex};
use graspath::select::{select, wrist_trajectory, CandidateScore};
use graspath::task::Task;
use nalgebra::{Matrix6, Matrix6xX, Vector6};
use std::path::PathBuf;

fn task(redundancy: &str, index: &str) -> Task {
    let example =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../examples/pick_and_place_left.yaml");
    let text = std::fs::read_to_string(&example).unwrap();
    let body: String = text
        .lines()
        .filter(|l| !l.starts_with("ik:") && !l.starts_with("index:"))
        .map(|l| format!("{l}\n"))
        .collect();
    let file = graspath::task::TaskFile::parse(
        &format!(
            "{body}ik: {{ redundancy: {redundancy}, branches: 8, iterations: 2000 }}\nindex: {index}\n"
        ),
        "pick_and_place_left.yaml",
        "yaml",
    )
    .unwrap();
    Task::from_file(&file, "pick_and_place_left.yaml", example.parent().unwrap()).unwrap()
}

/// The unit tangent of the wrist path at sample `i`, from the wrist poses themselves (forward
/// difference, the last sample backward), in twist mode with L = 1 m.
fn tangent(task: &Task, score: &CandidateScore, i: usize) -> Option<Vector6<f64>> {
    let wrists = wrist_trajectory(
        task.path(),
        &task.arms()[0].world_from_base,
        &score.candidate.object_from_wrist,
    );
    let (a, b) = if i + 1 < wrists.len() {
        (i, i + 1)
    } else {
        (i - 1, i)
    };
    match wrist_tangent(
        &wrists[a],
        &wrists[b],
        JacobianRows::Twist { length_scale: 1.0 },
    )? {
        Direction::Full(u) => Some(u),
        _ => unreachable!("twist mode gives 6-D directions"),
    }
}

fn jacobian(task: &Task, q: &[f64]) -> Matrix6xX<f64> {
    let chain = &task.arms()[0].chain;
    let mut j = Matrix6xX::zeros(chain.dof());
    chain.pose_and_jacobian_into(q, &mut j).unwrap();
    j
}

/// `μ_l2` of a series, as the library defines it, from the samples' times.
fn l2_of(task: &Task, values: &[Option<f64>]) -> f64 {
    let samples: Vec<SampleIndex> = values
        .iter()
        .zip(&task.path().samples)
        .map(|(&value, s)| SampleIndex {
            time: s.time,
            value,
        })
        .collect();
    PathNorms::of(&samples).l2
}

#[test]
fn the_velocity_ratio_is_ranked_and_m_t_is_still_reported() {
    let task = task("first", "{ measure: velocity_ratio }");
    let plain = self::task("first", "{}");
    let (ranked, reference) = (
        select(&task, &|| {}).unwrap(),
        select(&plain, &|| {}).unwrap(),
    );
    let mut checked = 0;
    for (score, paper) in ranked.arms[0].scores.iter().zip(&reference.arms[0].scores) {
        assert_eq!(score.feasible(), paper.feasible());
        let Some(norms) = score.norms else { continue };
        // The paper's M_T along the same motion is unchanged.
        assert_eq!(score.joint_trajectory, paper.joint_trajectory);
        assert_eq!(score.m_t, paper.m_t);
        let values = score.ranked_values.as_ref().expect("velocity ratios");
        for (i, (value, q)) in values.iter().zip(&score.joint_trajectory).enumerate() {
            let Some(u) = tangent(&task, score, i) else {
                assert!(value.is_none());
                continue;
            };
            let j = jacobian(&task, q);
            let inverse: Matrix6<f64> = (&j * j.transpose()).try_inverse().expect("regular");
            let expected = 1.0 / (u.transpose() * inverse * u)[(0, 0)].sqrt();
            let got = value.expect("a moving sample has a value");
            assert!(
                (got - expected).abs() <= 1e-6 * expected,
                "{got} vs {expected}"
            );
            checked += 1;
        }
        assert!((norms.l2 - l2_of(&task, values)).abs() <= 1e-12 * norms.l2);
    }
    assert!(checked > 100, "only {checked} samples checked");
}

#[test]
fn the_penalised_index_is_m_t_times_tsai_penalty_and_limits_are_measured() {
    let task = task("best_branch", "{ joint_limit_penalty: 20 }");
    let plain = self::task("best_branch", "{}");
    let chain = &task.arms()[0].chain;
    let (lower, upper) = (chain.lower(), chain.upper());
    // Tsai's penalty, written out.
    let penalty = |q: &[f64]| {
        let product: f64 = (0..q.len())
            .map(|j| (q[j] - lower[j]) * (upper[j] - q[j]) / (upper[j] - lower[j]).powi(2))
            .product();
        1.0 - (-20.0 * product).exp()
    };
    let selection = select(&task, &|| {}).unwrap();
    let reference = select(&plain, &|| {}).unwrap();
    let mut checked = 0;
    for (score, paper) in selection.arms[0]
        .scores
        .iter()
        .zip(&reference.arms[0].scores)
    {
        assert_eq!(score.yoshikawa_at_grasp, paper.yoshikawa_at_grasp);
        let Some(norms) = score.norms else {
            assert!(score.limit_distance.is_empty());
            continue;
        };
        let values = score.ranked_values.as_ref().expect("penalised values");
        for ((value, m_t), q) in values.iter().zip(&score.m_t).zip(&score.joint_trajectory) {
            match (value, m_t) {
                (Some(v), Some(m)) => {
                    let expected = m * penalty(q);
                    assert!((v - expected).abs() <= 1e-12 * expected.max(1e-300));
                    checked += 1;
                }
                (None, None) => {}
                _ => panic!("the ranked index and M_T disagree on which samples count"),
            }
        }
        assert!((norms.l2 - l2_of(&task, values)).abs() <= 1e-12 * norms.l2);
        // The distance to the nearest limit, by brute force over the joints.
        for (d, q) in score.limit_distance.iter().zip(&score.joint_trajectory) {
            let nearest = (0..q.len())
                .flat_map(|j| [q[j] - lower[j], upper[j] - q[j]])
                .fold(f64::INFINITY, f64::min);
            assert_eq!(*d, nearest);
        }
        let near = score
            .limit_distance
            .iter()
            .filter(|d| **d <= defaults::LIMIT_HUG_DISTANCE)
            .count();
        assert_eq!(
            score.hugs_limit(),
            2 * near >= score.limit_distance.len(),
            "half the samples or more at a limit is hugging it"
        );
        // The penalised Yoshikawa at the grasp.
        let w = paper.yoshikawa_at_grasp.unwrap();
        let grasp_w = score.yoshikawa_penalized_at_grasp.unwrap();
        assert!(grasp_w <= w && grasp_w > 0.0);
    }
    assert!(checked > 100, "only {checked} samples checked");
}

#[test]
fn the_classical_indices_at_the_grasp_do_not_depend_on_the_redundancy_setting() {
    let runs: Vec<_> = ["first", "best_branch", "optimize"]
        .iter()
        .map(|r| select(&task(r, "{}"), &|| {}).unwrap())
        .collect();
    let mut differing_branches = 0;
    for i in 0..runs[0].arms[0].scores.len() {
        let [a, b, c] = [0, 1, 2].map(|r| &runs[r].arms[0].scores[i]);
        for other in [b, c] {
            assert_eq!(
                a.yoshikawa_at_grasp, other.yoshikawa_at_grasp,
                "candidate {i}"
            );
            assert_eq!(
                a.inverse_condition_at_grasp,
                other.inverse_condition_at_grasp
            );
            assert_eq!(
                a.inverse_condition_squared_at_grasp,
                other.inverse_condition_squared_at_grasp
            );
        }
        if a.joint_trajectory.first() != b.joint_trajectory.first() {
            differing_branches += 1;
        }
    }
    // The test means something only where the tasks chose different configurations.
    assert!(
        differing_branches > 0,
        "every setting chose the same grasp configuration"
    );
}

#[test]
fn a_bad_measure_or_penalty_is_named() {
    let example =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../examples/pick_and_place_left.yaml");
    let text = std::fs::read_to_string(example).unwrap();
    let dir = tempfile::tempdir().unwrap();
    for (index, field) in [
        ("{ measure: yoshikawa }", "index.measure"),
        ("{ joint_limit_penalty: -3 }", "index.joint_limit_penalty"),
        ("{ joint_limit_penalty: 0 }", "index.joint_limit_penalty"),
        ("{ joint_limit_penalty: strong }", "index"),
    ] {
        let body: String = text
            .lines()
            .filter(|l| !l.starts_with("index:"))
            .map(|l| format!("{l}\n"))
            .collect();
        let path = dir.path().join("task.yaml");
        std::fs::write(&path, format!("{body}index: {index}\n")).unwrap();
        let error = match Task::load(&path) {
            Ok(_) => panic!("{index} was accepted"),
            Err(e) => e.to_string(),
        };
        assert!(error.contains(field), "{index}: {error}");
    }
}

#[test]
fn norms_over_the_waypoints_count_the_initial_pose_and_each_steps_end() {
    let dense = task("first", "{}");
    let waypoints = task("first", "{ over: waypoints }");
    let (a, b) = (
        select(&dense, &|| {}).unwrap(),
        select(&waypoints, &|| {}).unwrap(),
    );
    // The waypoints, from the path's own step indices: the first sample and the last of
    // each step.
    let steps: Vec<usize> = dense.path().samples.iter().map(|s| s.step).collect();
    let marked: Vec<usize> = (0..steps.len())
        .filter(|&i| i == 0 || steps.get(i + 1).is_none_or(|next| *next != steps[i]))
        .collect();
    assert_eq!(marked.len(), dense.path().step_labels.len() + 1);
    let mut checked = 0;
    for (x, y) in a.arms[0].scores.iter().zip(&b.arms[0].scores) {
        // The same motion and feasibility: only the norms change.
        assert_eq!(x.feasible(), y.feasible());
        assert_eq!(x.joint_trajectory, y.joint_trajectory);
        assert_eq!(x.m_t, y.m_t);
        let Some(norms) = y.norms else { continue };
        let values: Vec<f64> = marked.iter().filter_map(|&i| y.m_t[i]).collect();
        let l2 = values.iter().map(|v| v * v).sum::<f64>().sqrt();
        assert!((norms.l2 - l2).abs() <= 1e-12 * l2, "{} vs {l2}", norms.l2);
        assert_eq!(norms.evaluated, values.len());
        checked += 1;
    }
    assert!(checked > 10);
    // The ranking differs from the dense one somewhere (otherwise the option means nothing
    // on the paper's task).
    let best = |s: &graspath::select::Selection| s.arms[0].best();
    assert_ne!(best(&a), best(&b));
}
