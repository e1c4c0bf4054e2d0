//! Ties in the summary and the report's sentences: a candidate listed twice (same grasp, two
//! ids) scores exactly the same both times, so the two must be reported as tied with each
//! other and with nothing else far away.

use graspath::geometry::shape::Shape;
use graspath::grasp::{edge_family, Candidate};
use graspath::robot::builtin::{baxter, Arm};
use graspath::select::select;
use graspath::task::{Sampling, Step, Task, TimedStep};
use graspath_report::{findings_sentences, summary_json};
use nalgebra::{Isometry3, Vector3};

#[test]
fn a_duplicated_candidate_is_tied_with_its_copy() {
    let shape = Shape::cuboid([0.06, 0.40, 0.10]).unwrap();
    let family = edge_family(&shape, 5, 0.02, 0.02).unwrap();
    // Every candidate twice: ids k and k + 5 are the same grasp.
    let candidates: Vec<Candidate> = family
        .iter()
        .cloned()
        .chain(family.iter().map(|c| Candidate {
            id: c.id + family.len(),
            label: format!("{} (copy)", c.label),
            ..c.clone()
        }))
        .collect();
    let steps = vec![
        TimedStep::new("lift", Step::translation(Vector3::new(0.0, 0.0, 0.2))),
        TimedStep::new("move", Step::translation(Vector3::new(0.0, 0.3, 0.0))),
    ];
    let task = Task::builder("dup")
        .arm("left", baxter(Arm::Left), Isometry3::identity())
        .shape(shape)
        .candidates(candidates)
        .object_motion(
            Isometry3::translation(0.75, 0.0, -0.1),
            steps,
            Sampling::PerStep(3),
        )
        .build()
        .unwrap();
    let selection = select(&task, &|| {}).unwrap();
    let arm = &selection.arms[0];
    let best = arm.best().expect("a feasible grasp");
    let best_id = arm.scores[best].candidate.id;
    let copy = (best_id + 5) % 10;
    let summary = summary_json(&task, &selection);
    let tied = summary["arms"][0]["selected"]["tied_with"]
        .as_array()
        .unwrap();
    // The copy is tied; any other tie must be within the tolerance by the definition.
    assert!(tied.contains(&serde_json::json!(copy)), "{tied:?}");
    let own = arm.rankings[best].score.unwrap();
    for (s, r) in arm.scores.iter().zip(&arm.rankings) {
        let id = s.candidate.id;
        if id == best_id {
            continue;
        }
        let within = r
            .score
            .is_some_and(|v| (v - own).abs() <= 1e-4 * v.abs().max(own.abs()));
        assert_eq!(
            tied.contains(&serde_json::json!(id)),
            within,
            "candidate {id}"
        );
    }
    assert_eq!(summary["tie_tolerance"], 1e-4);
    let sentence = &findings_sentences(&task, &selection)[0];
    assert!(
        sentence.contains(&format!(
            "left arm best: {}",
            arm.scores[best].candidate.label
        )),
        "{sentence}"
    );
    let n = tied.len();
    let others = if n == 1 {
        "1 other".to_string()
    } else {
        format!("{n} others")
    };
    assert!(
        sentence.contains(&format!("tied with {others} within 0.01 %")),
        "{sentence}"
    );
}
