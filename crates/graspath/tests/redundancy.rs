//! `ik.redundancy` on the paper's Pick-and-Place (left arm, the cuboid's top edge): the
//! optimised self-motion is never worse than the branches it starts from, and every joint
//! path it returns is re-checked by forward kinematics, the joint limits and the step bound.

use graspath::select::select;
use graspath::task::{Redundancy, Task};
use std::path::PathBuf;

fn task(redundancy: &str) -> Task {
    let example =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../examples/pick_and_place_left.yaml");
    let mut file = graspath::task::TaskFile::load(&example).unwrap();
    file.ik.redundancy = Some(redundancy.into());
    Task::from_file(&file, "pick_and_place_left.yaml", example.parent().unwrap()).unwrap()
}

#[test]
fn the_optimised_self_motion_beats_the_first_and_the_best_branch() {
    let (first, best, optimized) = (task("first"), task("best_branch"), task("optimize"));
    assert_eq!(optimized.redundancy(), Redundancy::Optimize);
    let (a, b, c) = (
        select(&first, &|| {}).unwrap(),
        select(&best, &|| {}).unwrap(),
        select(&optimized, &|| {}).unwrap(),
    );
    let chain = &optimized.arms()[0].chain;
    let mut gained = 0;
    for ((x, y), z) in a.arms[0]
        .scores
        .iter()
        .zip(&b.arms[0].scores)
        .zip(&c.arms[0].scores)
    {
        assert_eq!(x.feasible(), z.feasible());
        let Some(nz) = z.norms else { continue };
        let (nx, ny) = (x.norms.unwrap(), y.norms.unwrap());
        assert!(
            nz.l2 >= nx.l2 && nz.l2 >= ny.l2,
            "{} < {} or {}",
            nz.l2,
            nx.l2,
            ny.l2
        );
        let found = z
            .self_motion
            .expect("an optimised candidate reports its self-motion");
        assert_eq!(found.first_branch_l2, nx.l2);
        assert!(found.l2_range.0 <= nx.l2 && found.l2_range.1 >= nz.l2);
        if nz.l2 > ny.l2 * 1.001 {
            gained += 1;
        }
        // Re-checked: the wrist on its target at every sample, inside the limits, small steps.
        let wrists = graspath::select::wrist_trajectory(
            optimized.path(),
            &optimized.arms()[0].world_from_base,
            &z.candidate.object_from_wrist,
        );
        for (i, (q, target)) in z.joint_trajectory.iter().zip(&wrists).enumerate() {
            let pose = chain.pose(q).unwrap();
            let error = (pose.translation.vector - target.translation.vector).norm();
            assert!(error <= 1e-5, "sample {i}: {error} m off the path");
            assert!(q
                .iter()
                .enumerate()
                .all(|(j, v)| *v >= chain.lower()[j] && *v <= chain.upper()[j]));
            if i > 0 {
                let step = q
                    .iter()
                    .zip(&z.joint_trajectory[i - 1])
                    .map(|(p, r)| (p - r).abs())
                    .fold(0.0, f64::max);
                assert!(step <= optimized.ik().max_joint_step + 1e-12);
            }
        }
    }
    assert!(gained >= 5, "the search gains on only {gained} candidates");
}

#[test]
fn a_redundancy_that_does_not_exist_or_an_earlier_spelling_is_named() {
    let dir = tempfile::tempdir().unwrap();
    let example =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../examples/pick_and_place_left.yaml");
    let text = std::fs::read_to_string(example).unwrap();
    for (ik, field) in [
        ("ik: { redundancy: elbow_up }", "ik.redundancy"),
        // `compare_branches` was an earlier spelling of `redundancy`.
        ("ik: { compare_branches: true }", "compare_branches"),
    ] {
        let body: String = text
            .lines()
            .filter(|l| !l.starts_with("ik:"))
            .map(|l| format!("{l}\n"))
            .collect();
        let path = dir.path().join("task.yaml");
        std::fs::write(&path, format!("{body}{ik}\n")).unwrap();
        let error = match Task::load(&path) {
            Ok(_) => panic!("{ik} was accepted"),
            Err(e) => e.to_string(),
        };
        assert!(error.contains(field), "{error}");
    }
}
