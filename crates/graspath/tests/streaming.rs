//! Streaming selection ([`select_streaming`]) against the in-memory one ([`select`]): every
//! streamed candidate's full scores equal `select`'s, its streamed ranking equals `select`'s
//! without rank and Pareto flag, the final rankings and pairs are equal, and the kept scores are
//! `select`'s reduced to scalars. Candidates come out in candidate order, arm by arm. A task
//! whose family is laid out on demand, or whose candidate file is read in chunks
//! (`Task::from_file_chunked`), streams the same results as the task held whole.

use graspath::grasp::{CandidateError, CandidateSource};
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
    check_streamed_task_equals_in_memory(task, task);
}

/// `streamed_task` streamed against `task` selected in memory (the same task, or the same
/// task file loaded whole).
fn check_streamed_task_equals_in_memory(streamed_task: &Task, task: &Task) {
    let reference = select(task, &|| {}).unwrap();
    let mut seen: Vec<(String, usize)> = Vec::new();
    let streamed: Selection<CandidateScalars> =
        select_streaming(streamed_task, &|| {}, |s| -> Result<(), CandidateError> {
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
    assert!(task.candidate_count() > 2 * graspath::select::STREAM_CHUNK);
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
        assert!(chunked.candidates().held().is_none());
        assert!(matches!(chunked.candidates(), CandidateSource::Family(_)));
        assert_eq!(chunked.candidate_count(), count, "{family}");
        // Oracle: the family generated whole, by the in-memory path.
        assert_eq!(
            chunked.all_candidates().unwrap().as_ref(),
            whole.candidates().held().expect("held candidates")
        );
        for size in [1, 7, 256, count + 3] {
            let mut read = Vec::new();
            chunked
                .for_each_candidate_chunk(size, |chunk| -> Result<(), CandidateError> {
                    assert!(!chunk.is_empty() && chunk.len() <= size);
                    read.extend_from_slice(chunk);
                    Ok(())
                })
                .unwrap();
            assert_eq!(
                read,
                whole.candidates().held().expect("held candidates"),
                "{family} {count} in chunks of {size}"
            );
        }
        assert_eq!(chunked.max_log_likelihood(), whole.max_log_likelihood());
        if count == 600 || family != "faces" {
            let reference = select(&whole, &|| {}).unwrap();
            let streamed = select_streaming(&chunked, &|| {}, |_| -> Result<(), CandidateError> {
                Ok(())
            })
            .unwrap();
            for (got, want) in streamed.arms.iter().zip(&reference.arms) {
                assert_eq!(got.rankings, want.rankings, "{family}");
                let ids: Vec<usize> = got.scores.iter().map(Scored::id).collect();
                let want_ids: Vec<usize> = want.scores.iter().map(|s| s.candidate.id).collect();
                assert_eq!(ids, want_ids);
            }
        }
        if count == 255 {
            check_select_equals(&chunked, &whole);
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
    assert!(task.collisions().is_some());
    check_streaming_equals_in_memory(&task);
}

/// A task file's text with its candidate family (`family`, the text of its `family:` line)
/// replaced by a graspath candidate file `name` (CSV or JSON by its extension) written into
/// `dir`: the family's candidates with likelihoods that differ, so the ranking uses them.
fn with_candidate_file(text: &str, family: &str, dir: &Path, name: &str) -> String {
    assert!(text.contains(family), "the task file changed");
    let whole = task_from(text, &examples());
    let path = dir.join(name);
    let likelihood = |k: usize| 0.2 + (k % 5) as f64 / 5.0;
    let mut file = String::new();
    if name.ends_with(".csv") {
        file.push_str("id,label,x,y,z,qx,qy,qz,qw,likelihood\n");
        for (k, c) in whole
            .candidates()
            .held()
            .expect("held candidates")
            .iter()
            .enumerate()
        {
            let (t, q) = (
                c.object_from_wrist.translation,
                c.object_from_wrist.rotation,
            );
            file.push_str(&format!(
                "{},\"{}, from the family\",{},{},{},{},{},{},{},{}\n",
                c.id + 100,
                c.label,
                t.x,
                t.y,
                t.z,
                q.i,
                q.j,
                q.k,
                q.w,
                likelihood(k)
            ));
        }
    } else {
        let entries: Vec<String> = whole
            .candidates().held().expect("held candidates")
            .iter()
            .enumerate()
            .map(|(k, c)| {
                let (t, q) = (c.object_from_wrist.translation, c.object_from_wrist.rotation);
                format!(
                    "{{\"id\": {}, \"pose\": {{\"xyz\": [{}, {}, {}], \"quaternion\": [{}, {}, {}, {}]}}, \"log_likelihood\": {}}}",
                    c.id + 100,
                    t.x,
                    t.y,
                    t.z,
                    q.i,
                    q.j,
                    q.k,
                    q.w,
                    likelihood(k).ln()
                )
            })
            .collect();
        file.push_str(&format!(
            "{{\"format\": \"graspath-candidates\", \"candidates\": [\n{}\n]}}\n",
            entries.join(",\n")
        ));
    }
    std::fs::write(&path, file).unwrap();
    text.replace(family, &format!("file: {}", path.display()))
}

/// The task file loaded whole and with its candidate file read in chunks: the same
/// candidates at every chunk size and by position, and the same streamed results as the
/// in-memory selection of the task loaded whole.
fn check_candidate_file_task(text: &str) {
    let file = TaskFile::parse(text, "t.yaml", "yaml").expect("task parses");
    let whole = Task::from_file(&file, "t.yaml", &examples()).expect("task builds");
    let chunked = Task::from_file_chunked(&file, "t.yaml", &examples()).expect("task builds");
    assert!(chunked.candidates().held().is_none());
    assert!(matches!(chunked.candidates(), CandidateSource::File(_)));
    let n = whole.candidate_count();
    assert_eq!(chunked.candidate_count(), n);
    assert_eq!(chunked.max_log_likelihood(), whole.max_log_likelihood());
    for size in [1, 7, 256, n + 3] {
        let mut read = Vec::new();
        chunked
            .for_each_candidate_chunk(size, |chunk| -> Result<(), CandidateError> {
                assert!(!chunk.is_empty() && chunk.len() <= size);
                read.extend_from_slice(chunk);
                Ok(())
            })
            .unwrap();
        assert_eq!(
            read,
            whole.candidates().held().expect("held candidates"),
            "chunks of {size}"
        );
    }
    for (i, c) in whole
        .candidates()
        .held()
        .expect("held candidates")
        .iter()
        .enumerate()
    {
        assert_eq!(chunked.candidate_at(i).unwrap().as_ref(), Some(c));
    }
    assert_eq!(chunked.candidate_at(n).unwrap(), None);
    check_streamed_task_equals_in_memory(&chunked, &whole);
    check_select_equals(&chunked, &whole);
}

/// `select` itself — not only the streamed selection — on a task whose candidates are
/// produced on demand gives what it gives on the task held whole.
fn check_select_equals(on_demand: &Task, whole: &Task) {
    let got = select(on_demand, &|| {}).expect("the candidates are produced");
    let want = select(whole, &|| {}).unwrap();
    assert_eq!(got.arms.len(), want.arms.len());
    for (g, w) in got.arms.iter().zip(&want.arms) {
        assert_eq!(g.scores, w.scores);
        assert_eq!(g.rankings, w.rankings);
    }
    assert_eq!(got.pairs, want.pairs);
}

#[test]
fn select_on_a_candidate_file_that_is_gone_is_an_error_not_a_panic() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(examples().join("workload_1000_faces.yaml"))
        .unwrap()
        .replace("samples: 50", "samples: 4");
    let text = with_candidate_file(
        &text,
        "family: { faces: { count: 1000, exclude: [bottom], depth: 0.02 } }",
        dir.path(),
        "candidates.json",
    );
    let file = TaskFile::parse(&text, "t.yaml", "yaml").expect("task parses");
    let chunked = Task::from_file_chunked(&file, "t.yaml", &examples()).expect("task builds");
    std::fs::remove_file(dir.path().join("candidates.json")).unwrap();
    let error = select(&chunked, &|| {}).expect_err("the file is gone");
    assert!(error.to_string().contains("candidates.json"), "{error}");
}

/// A task cut into candidate slices: each candidate scores exactly as in the whole task (its
/// likelihood relative to the whole task's best), and ranks within a slice follow the whole
/// task's order.
#[test]
fn a_slice_scores_its_candidates_as_the_whole_task() {
    let whole = example_task("pick_and_place_left.yaml");
    let n = whole.candidate_count();
    let reference = select(&whole, &|| {}).unwrap();
    let cut = n / 3;
    for range in [0..cut, cut..n, 0..n, cut..cut] {
        let slice = whole.slice(range.clone()).unwrap();
        assert_eq!(slice.candidate_count(), range.len());
        assert_eq!(slice.max_log_likelihood(), whole.max_log_likelihood());
        let got = select(&slice, &|| {}).unwrap();
        let want = &reference.arms[0];
        for (i, (score, ranking)) in got.arms[0]
            .scores
            .iter()
            .zip(&got.arms[0].rankings)
            .enumerate()
        {
            let k = range.start + i;
            assert_eq!(score, &want.scores[k]);
            assert_eq!(ranking.score, want.rankings[k].score);
        }
        // Ranks within the slice: the whole task's ranks, renumbered (brute force).
        let mut by_whole: Vec<(usize, usize)> = (0..range.len())
            .filter_map(|i| want.rankings[range.start + i].rank.map(|r| (r, i)))
            .collect();
        by_whole.sort();
        for (r, &(_, i)) in by_whole.iter().enumerate() {
            assert_eq!(got.arms[0].rankings[i].rank, Some(r + 1));
        }
    }
    let error = whole.slice(2..n + 1).unwrap_err();
    assert_eq!(error.field, "candidates");
}

#[test]
fn with_arms_keeps_the_named_arms_in_order() {
    let both = example_task("pick_and_place_both.yaml");
    let swapped = both.with_arms(&["right", "left"]).unwrap();
    let names: Vec<&str> = swapped.arms().iter().map(|a| a.name.as_str()).collect();
    assert_eq!(names, ["right", "left"]);
    let left = both.with_arms(&["left"]).unwrap();
    let alone = select(&left, &|| {}).unwrap();
    let together = select(&both, &|| {}).unwrap();
    assert_eq!(alone.arms[0].scores, together.arms[0].scores);
    assert!(alone.pairs.is_empty());
    for (names, message) in [
        (&["left", "left"][..], "listed twice"),
        (&["middle"][..], "unknown arm 'middle' (arms: left, right)"),
        (&[][..], "at least one arm"),
    ] {
        let error = both.with_arms(names).unwrap_err();
        assert_eq!(error.field, "arms");
        assert!(error.to_string().contains(message), "{error}");
    }
}

#[test]
fn a_candidate_file_read_in_chunks_streams_the_in_memory_results() {
    let dir = tempfile::tempdir().unwrap();
    let faces = std::fs::read_to_string(examples().join("workload_1000_faces.yaml"))
        .unwrap()
        .replace("count: 1000", "count: 600")
        .replace("samples: 50", "samples: 8");
    let family = "family: { faces: { count: 600, exclude: [bottom], depth: 0.02 } }";
    check_candidate_file_task(&with_candidate_file(&faces, family, dir.path(), "f.csv"));
    check_candidate_file_task(&with_candidate_file(&faces, family, dir.path(), "f.json"));
}

#[test]
fn two_arms_with_a_candidate_file_read_in_chunks_stream_the_in_memory_pairs() {
    let dir = tempfile::tempdir().unwrap();
    let both = std::fs::read_to_string(examples().join("pick_and_place_both.yaml"))
        .unwrap()
        .replace("count: 21", "count: 150");
    let family = "family: { edge: { count: 150, depth: 0.02, margin: 0.02 } }";
    for name in ["e.csv", "e.json"] {
        let text = with_candidate_file(&both, family, dir.path(), name);
        check_candidate_file_task(&text);
        let whole = task_from(&text, &examples());
        assert!(
            !select(&whole, &|| {}).unwrap().pairs.is_empty(),
            "no pair to compare"
        );
    }
}

#[test]
fn a_candidate_file_cut_short_while_it_is_streamed_ends_the_selection_with_its_error() {
    let dir = tempfile::tempdir().unwrap();
    let faces = std::fs::read_to_string(examples().join("workload_1000_faces.yaml"))
        .unwrap()
        .replace("count: 1000", "count: 8000")
        .replace("samples: 50", "samples: 4");
    // Enough candidates that the file is cut well after what the selection reads ahead of
    // the results it hands on (at most `IN_FLIGHT` candidates and a few chunks).
    let family = "family: { faces: { count: 8000, exclude: [bottom], depth: 0.02 } }";
    let text = with_candidate_file(&faces, family, dir.path(), "cut.csv");
    let file = TaskFile::parse(&text, "t.yaml", "yaml").expect("task parses");
    let task = Task::from_file_chunked(&file, "t.yaml", &examples()).expect("task builds");
    let path = dir.path().join("cut.csv");
    let mut calls = 0;
    let result = select_streaming(&task, &|| {}, |_| -> Result<(), Stop> {
        calls += 1;
        if calls == 1 {
            let bytes = std::fs::read(&path).unwrap();
            std::fs::write(&path, &bytes[..bytes.len() / 2]).unwrap();
        }
        Ok(())
    });
    match result {
        Err(Stop::Candidates(e)) => assert!(e.file.ends_with("cut.csv"), "{e}"),
        other => panic!("expected the file's error, got {other:?}"),
    }
    assert!(calls < 8000, "the selection went on after the file was cut");
}

/// A consumer's own error, or a candidate file's.
#[derive(Debug, PartialEq)]
enum Stop {
    DiskFull,
    Candidates(CandidateError),
}

impl From<CandidateError> for Stop {
    fn from(e: CandidateError) -> Self {
        Self::Candidates(e)
    }
}

#[test]
fn a_consumer_error_stops_the_stream() {
    let task = example_task("pick_and_place_left.yaml");
    let mut calls = 0;
    let result = select_streaming(&task, &|| {}, |_| {
        calls += 1;
        if calls == 3 {
            Err(Stop::DiskFull)
        } else {
            Ok(())
        }
    });
    assert_eq!(result.unwrap_err(), Stop::DiskFull);
    assert_eq!(calls, 3);
}
