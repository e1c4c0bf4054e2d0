//! The IK's joint-limit margin (`ik.limit_margin`): the narrowed ranges in closed form on every
//! built-in arm, and on the shipped 1000-candidate faces workload every chosen motion inside
//! them — so none of the top ten rides a limit by default — while planning up to the limits
//! (the paper's practice) puts the best grasps on one.

use graspath::defaults;
use graspath::robot::builtin::BuiltinRobot;
use graspath::robot::{Chain, JointKind};
use graspath::select::{select, Selection};
use graspath::task::{Task, TaskFile};
use std::path::PathBuf;

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The faces workload with `ik.limit_margin` set (`None`: the default).
fn faces_task(margin: Option<f64>) -> Task {
    let path = repo().join("examples/workload_1000_faces.yaml");
    let mut file = TaskFile::load(&path).expect("the workload loads");
    file.ik.limit_margin = margin;
    Task::from_file(&file, "workload_1000_faces.yaml", &repo().join("examples"))
        .expect("the workload builds")
}

/// `[l + m, u − m]`, `m = min(margin, (u − l) / 4)`, for revolute joints with finite limits.
fn narrowed(chain: &Chain, margin: f64) -> Vec<(f64, f64)> {
    chain
        .lower()
        .iter()
        .zip(chain.upper())
        .zip(chain.joint_kinds())
        .map(|((&l, &u), kind)| {
            if *kind == JointKind::Revolute && l.is_finite() && u.is_finite() {
                let m = margin.min((u - l) / 4.0);
                (l + m, u - m)
            } else {
                (l, u)
            }
        })
        .collect()
}

#[test]
fn every_built_in_arm_narrows_its_revolute_ranges_by_the_margin() {
    for robot in BuiltinRobot::ALL {
        let name = robot.name();
        for spec in robot.chain_specs() {
            let chain = Chain::from_spec(&spec).expect("a built-in chain");
            for margin in [0.0, 0.05, 0.1, 0.5] {
                let planned = chain.with_limit_margin(margin);
                let expected = narrowed(&chain, margin);
                for (j, (l, u)) in expected.iter().enumerate() {
                    assert_eq!(planned.lower()[j], *l, "{name} joint {j} margin {margin}");
                    assert_eq!(planned.upper()[j], *u, "{name} joint {j} margin {margin}");
                    assert!(planned.lower()[j] < planned.upper()[j]);
                }
                assert_eq!(planned.mid_configuration().len(), chain.dof());
                for (a, b) in planned
                    .mid_configuration()
                    .iter()
                    .zip(chain.mid_configuration())
                {
                    assert!((a - b).abs() < 1e-12, "{name}: the middle moved");
                }
                assert_eq!(planned.joint_kinds(), chain.joint_kinds());
            }
        }
    }
}

/// The ranked candidates of the single arm, best first: `(limit_distance_min, score)`.
fn ranked(selection: &Selection) -> Vec<(f64, f64)> {
    let arm = &selection.arms[0];
    let mut rows: Vec<(usize, f64, f64)> = arm
        .scores
        .iter()
        .zip(&arm.rankings)
        .filter_map(|(s, r)| {
            let distance = s
                .limit_distance
                .iter()
                .copied()
                .fold(f64::INFINITY, f64::min);
            Some((r.rank?, distance, r.score?))
        })
        .collect();
    rows.sort_by_key(|r| r.0);
    rows.into_iter().map(|(_, d, s)| (d, s)).collect()
}

#[test]
fn the_faces_workload_keeps_the_margin_by_default_and_rides_limits_without_it() {
    let task = faces_task(None);
    assert_eq!(task.ik_limit_margin(), defaults::IK_LIMIT_MARGIN);
    let margin = task.ik_limit_margin();
    let selection = select(&task, &|| {}).unwrap();
    let arm = &task.arms()[0];
    let bounds = narrowed(&arm.chain, margin);
    let result = &selection.arms[0];
    let mut feasible = 0;
    for score in result.scores.iter().filter(|s| s.feasible()) {
        feasible += 1;
        // Oracle: the narrowed ranges, computed here from the arm's own limits.
        for q in score
            .approach
            .iter()
            .chain(&score.joint_trajectory)
            .chain(&score.retreat)
        {
            for (j, (v, (l, u))) in q.iter().zip(&bounds).enumerate() {
                assert!(
                    *v >= l - 1e-12 && *v <= u + 1e-12,
                    "candidate {}: joint {j} at {v} outside [{l}, {u}]",
                    score.candidate.id
                );
            }
        }
    }
    assert!(feasible >= 10, "{feasible} feasible candidates");
    let with_margin = ranked(&selection);
    assert!(with_margin.len() >= 10);
    for (rank, (distance, _)) in with_margin.iter().take(10).enumerate() {
        assert!(
            *distance >= margin - 1e-12,
            "rank {}: {distance} rad from a limit",
            rank + 1
        );
    }

    // Planned up to the limits, the best grasps ride one (the reason for the default), and
    // score higher than any grasp that keeps the margin (what the margin costs).
    let paper = select(&faces_task(Some(0.0)), &|| {}).unwrap();
    let without = ranked(&paper);
    let on_a_limit = without
        .iter()
        .take(10)
        .filter(|(d, _)| *d < defaults::LIMIT_HUG_DISTANCE)
        .count();
    assert!(
        on_a_limit > 0,
        "no top-10 grasp on a limit without the margin"
    );
    assert!(without[0].1 >= with_margin[0].1);
    // No candidate is lost to the margin on this workload, and the margin never adds one.
    let feasible_without = paper.arms[0].scores.iter().filter(|s| s.feasible()).count();
    assert!(feasible <= feasible_without);
}

#[test]
fn a_margin_outside_its_range_names_the_field() {
    for bad in [-0.1, 0.6, f64::NAN] {
        let path = repo().join("examples/workload_1000_faces.yaml");
        let mut file = TaskFile::load(&path).expect("the workload loads");
        file.ik.limit_margin = Some(bad);
        let error =
            Task::from_file(&file, "faces.yaml", &repo().join("examples")).expect_err("refused");
        let text = error.to_string();
        assert!(
            text.contains("ik.limit_margin") && text.contains("faces.yaml"),
            "{text}"
        );
    }
}
