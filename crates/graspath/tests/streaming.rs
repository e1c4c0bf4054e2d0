//! Streaming selection ([`select_streaming`]) against the in-memory one ([`select`]): every
//! streamed candidate's full scores equal `select`'s, its streamed ranking equals `select`'s
//! without rank and Pareto flag, the final rankings and pairs are equal, and the kept scores are
//! `select`'s reduced to scalars. Candidates come out in candidate order, arm by arm.

use graspath::select::{scalars_of, select, select_streaming, Ranking, Selection};
use graspath::task::{Task, TaskFile};
use std::path::{Path, PathBuf};

fn examples() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../examples")
}

fn task_from(text: &str, base: &Path) -> Task {
    let file = TaskFile::parse(text, "t.yaml", "yaml").expect("task parses");
    Task::from_file(&file, "t.yaml", base).expect("task builds")
}

fn example_task(name: &str) -> Task {
    let path = examples().join(name);
    let text = std::fs::read_to_string(&path).unwrap();
    task_from(&text, path.parent().unwrap())
}

fn check_streaming_equals_in_memory(task: &Task) {
    let reference = select(task, &|| {});
    let mut seen: Vec<(String, usize)> = Vec::new();
    let streamed: Selection = select_streaming(task, &|| {}, |s| -> Result<(), ()> {
        let arm = reference
            .arms
            .iter()
            .position(|a| a.arm == s.arm)
            .expect("a known arm");
        let i = seen.iter().filter(|(a, _)| a == s.arm).count();
        let want = &reference.arms[arm];
        assert_eq!(s.score, &want.scores[i], "arm {} candidate {i}", s.arm);
        let alone = Ranking {
            rank: None,
            pareto: false,
            ..want.rankings[i].clone()
        };
        assert_eq!(s.ranking, &alone, "arm {} candidate {i}", s.arm);
        seen.push((s.arm.to_string(), s.score.candidate.id));
        Ok(())
    })
    .unwrap();
    // Candidate order, arm by arm.
    let order: Vec<(String, usize)> = reference
        .arms
        .iter()
        .flat_map(|a| a.scores.iter().map(|s| (a.arm.clone(), s.candidate.id)))
        .collect();
    assert_eq!(seen, order);
    assert_eq!(streamed.arms.len(), reference.arms.len());
    let pairs_checked_between_arms = task.arms.len() == 2
        && task
            .collisions
            .as_ref()
            .is_some_and(|c| c.options.between_arms);
    for (got, want) in streamed.arms.iter().zip(&reference.arms) {
        assert_eq!(got.arm, want.arm);
        assert_eq!(got.rankings, want.rankings, "arm {}", want.arm);
        for ((g, w), r) in got.scores.iter().zip(&want.scores).zip(&want.rankings) {
            // The pair check between arms needs the eligible candidates' motions.
            let keep = pairs_checked_between_arms && r.score.is_some();
            assert_eq!(g, &scalars_of(w, keep));
            assert!(g.m_t.is_empty() && g.limit_distance.is_empty());
            assert_eq!(
                g.joint_trajectory.is_empty(),
                !keep || w.joint_trajectory.is_empty()
            );
        }
        assert_eq!(got.best(), want.best());
        assert_eq!(got.feasible_count(), want.feasible_count());
    }
    assert_eq!(streamed.pairs, reference.pairs);
    assert_eq!(streamed.colliding_pairs, reference.colliding_pairs);
}

#[test]
fn several_chunks_of_one_arm_stream_the_in_memory_results() {
    // 600 candidates: three chunks of `STREAM_CHUNK` = 256, the last one partial.
    let text = std::fs::read_to_string(examples().join("workload_1000_faces.yaml"))
        .unwrap()
        .replace("count: 1000", "count: 600")
        .replace("samples: 50", "samples: 12");
    assert!(text.contains("count: 600"), "the workload file changed");
    let task = task_from(&text, &examples());
    assert!(task.candidates.len() > 2 * graspath::select::STREAM_CHUNK);
    check_streaming_equals_in_memory(&task);
}

#[test]
fn two_arms_stream_the_in_memory_results_and_pairs() {
    check_streaming_equals_in_memory(&example_task("pick_and_place_both.yaml"));
}

#[test]
fn two_arms_in_a_scene_keep_the_motions_the_pair_check_needs() {
    let task = example_task("scene/pick_and_place_both_on_table.yaml");
    assert!(task.collisions.is_some());
    check_streaming_equals_in_memory(&task);
}

#[test]
fn a_consumer_error_stops_the_stream() {
    let task = example_task("pick_and_place_left.yaml");
    let mut calls = 0;
    let result = select_streaming(&task, &|| {}, |_| {
        calls += 1;
        if calls == 3 {
            Err("disk full")
        } else {
            Ok(())
        }
    });
    assert_eq!(result.unwrap_err(), "disk full");
    assert_eq!(calls, 3);
}
