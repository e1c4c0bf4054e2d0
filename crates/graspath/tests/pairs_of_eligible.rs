//! Pairs formed from each arm's eligible candidates found apart ([`pairs_of_eligible`], what
//! `graspath.ray`'s per-object pair step runs) against [`select`]'s pairs on the repository's
//! two-arm examples: the same pairs, order, scores and refused count, whatever the order of
//! the lists given; and the errors on input that cannot be paired.

use graspath::select::{pairs_of_eligible, select, PairInputError, Selection};
use graspath::task::Task;
use std::path::PathBuf;

fn example_task(name: &str) -> Task {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples")
        .join(name);
    Task::load(&path).expect("the example loads")
}

/// Each arm's ranked candidates as `(position, μ_l2)`, in reverse candidate order.
fn eligible(selection: &Selection, arm: usize) -> Vec<(usize, f64)> {
    let result = &selection.arms[arm];
    let mut list: Vec<(usize, f64)> = result
        .scores
        .iter()
        .zip(&result.rankings)
        .enumerate()
        .filter(|(_, (_, r))| r.score.is_some())
        .map(|(i, (s, _))| (i, s.norms.expect("a ranked candidate has norms").l2))
        .collect();
    list.reverse();
    list
}

fn check_pairs_equal_select(task: &Task) -> usize {
    let reference = select(task, &|| {}).unwrap();
    let (first, second) = (eligible(&reference, 0), eligible(&reference, 1));
    assert!(!first.is_empty() && !second.is_empty());
    let candidates = task
        .all_candidates()
        .expect("the example task's candidates");
    let as_ids = |pairs: &[(usize, usize, f64)]| -> Vec<(usize, usize, f64)> {
        pairs
            .iter()
            .map(|&(i, j, score)| (candidates[i].id, candidates[j].id, score))
            .collect()
    };
    let expected: Vec<(usize, usize, f64)> = reference
        .pairs
        .iter()
        .map(|p| (p.first.id, p.second.id, p.score))
        .collect();
    assert_eq!(expected.len(), task.selection().pairs);
    let (pairs, refused) =
        pairs_of_eligible(task, &first, &second, task.selection().pairs).expect("pairs");
    assert_eq!(as_ids(&pairs), expected);
    assert_eq!(refused, reference.colliding_pairs);
    for count in [1, 3] {
        let (pairs, _) = pairs_of_eligible(task, &first, &second, count).expect("pairs");
        assert_eq!(as_ids(&pairs), expected[..count]);
    }
    reference.colliding_pairs
}

#[test]
fn pairs_from_eligible_lists_equal_select() {
    check_pairs_equal_select(&example_task("pick_and_place_both.yaml"));
    check_pairs_equal_select(&example_task("pick_rotate_place_both.yaml"));
}

#[test]
fn the_check_between_the_arms_scores_the_visited_candidates_again() {
    let task = example_task("scene/pick_and_place_both_on_table.yaml");
    let refused = check_pairs_equal_select(&task);
    assert!(refused > 0, "the example no longer refuses colliding pairs");
}

#[test]
fn input_that_cannot_be_paired_is_an_error() {
    let one_arm = example_task("pick_and_place_left.yaml");
    assert_eq!(
        pairs_of_eligible(&one_arm, &[], &[], 3),
        Err(PairInputError::NotTwoArms {
            task: one_arm.source_name().to_string(),
            arms: 1
        })
    );
    let both = example_task("pick_and_place_both.yaml");
    let err = pairs_of_eligible(&both, &[(0, 1.0)], &[(21, 1.0)], 3).unwrap_err();
    assert_eq!(
        err.to_string(),
        format!(
            "{}: arm 'right': candidate 21 is not one of the task's 21 candidates",
            both.source_name()
        )
    );
    let err = pairs_of_eligible(&both, &[(4, 1.0), (4, 2.0)], &[], 3).unwrap_err();
    assert!(matches!(err, PairInputError::Repeated { position: 4, .. }));
    assert!(err
        .to_string()
        .ends_with("arm 'left': candidate 4 is given twice"));
}
