//! Streaming selection ([`select_streaming`]) against the in-memory one ([`select`]): every
//! streamed candidate's full scores equal `select`'s, its streamed ranking equals `select`'s
//! without rank and Pareto flag, the final rankings and pairs are equal, and the kept scores are
//! `select`'s reduced to scalars. Candidates come out in candidate order, arm by arm. A task
//! whose family is laid out on demand (`Task::from_file_chunked`) streams the same results.

use graspath::select::{
    select, select_streaming, CandidateScalars, Ranking, Scored, Selection, NAMED_BEST,
};
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
    let streamed: Selection<CandidateScalars> =
        select_streaming(task, &|| {}, |s| -> Result<(), ()> {
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
    for (got, want) in streamed.arms.iter().zip(&reference.arms) {
        assert_eq!(got.arm, want.arm);
        assert_eq!(got.rankings, want.rankings, "arm {}", want.arm);
        for ((g, w), r) in got.scores.iter().zip(&want.scores).zip(&want.rankings) {
            // The best ranked and the pairs' members carry their candidate.
            let named = r.rank.is_some_and(|k| k <= NAMED_BEST)
                || streamed.pairs.iter().any(|p| {
                    let c = if got.arm == reference.arms[0].arm {
                        &p.first
                    } else {
                        &p.second
                    };
                    c.id == w.candidate.id
                });
            let expected = CandidateScalars {
                candidate: named.then(|| w.candidate.clone()),
                ..CandidateScalars::of(w)
            };
            assert_eq!(g, &expected);
            assert_eq!(g.candidate().is_some(), named);
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
fn a_family_laid_out_on_demand_streams_the_in_memory_results() {
    // Every family, with counts around the chunk size (one short, exact, one over, several).
    for (family, count) in [
        ("faces", 255),
        ("faces", 256),
        ("faces", 257),
        ("faces", 600),
        ("edge", 300),
        ("yaw", 260),
    ] {
        let text = std::fs::read_to_string(examples().join("workload_1000_faces.yaml"))
            .unwrap()
            .replace("samples: 50", "samples: 8")
            .replace(
                "family: { faces: { count: 1000, exclude: [bottom], depth: 0.02 } }",
                &match family {
                    "faces" => format!("family: {{ faces: {{ count: {count} }} }}"),
                    "edge" => format!("family: {{ edge: {{ count: {count} }} }}"),
                    _ => format!("family: {{ yaw: {{ count: {count}, step_deg: 1 }} }}"),
                },
            );
        let file = TaskFile::parse(&text, "t.yaml", "yaml").expect("task parses");
        let whole = Task::from_file(&file, "t.yaml", &examples()).expect("task builds");
        let chunked = Task::from_file_chunked(&file, "t.yaml", &examples()).expect("task builds");
        assert!(chunked.candidates.is_empty() && chunked.candidate_family.is_some());
        assert_eq!(chunked.candidate_count(), count, "{family}");
        // Oracle: the family generated whole, by the in-memory path.
        assert_eq!(chunked.all_candidates().as_ref(), &whole.candidates[..]);
        for size in [1, 7, 256, count + 3] {
            let mut read = Vec::new();
            chunked
                .for_each_candidate_chunk(size, |chunk| -> Result<(), ()> {
                    assert!(!chunk.is_empty() && chunk.len() <= size);
                    read.extend_from_slice(chunk);
                    Ok(())
                })
                .unwrap();
            assert_eq!(
                read, whole.candidates,
                "{family} {count} in chunks of {size}"
            );
        }
        assert_eq!(chunked.max_log_likelihood(), whole.max_log_likelihood());
        if count == 600 || family != "faces" {
            let reference = select(&whole, &|| {});
            let streamed =
                select_streaming(&chunked, &|| {}, |_| -> Result<(), ()> { Ok(()) }).unwrap();
            for (got, want) in streamed.arms.iter().zip(&reference.arms) {
                assert_eq!(got.rankings, want.rankings, "{family}");
                let ids: Vec<usize> = got.scores.iter().map(Scored::id).collect();
                let want_ids: Vec<usize> = want.scores.iter().map(|s| s.candidate.id).collect();
                assert_eq!(ids, want_ids);
            }
        }
    }
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
