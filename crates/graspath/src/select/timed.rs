//! The selected grasps' motions as timed joint trajectories: the best candidate of a one-arm
//! task, or the best pair's two candidates on one shared timeline.

use super::run::{scoring_setup, Selection};
use super::scalars::Scored;
use super::score::{score_candidates, timed_together, Failure};
use crate::grasp::Candidate;
use crate::task::Task;
use crate::timing::TimedTrajectory;
use std::sync::Arc;

/// One arm's selected motion, timed.
#[derive(Debug, Clone, PartialEq)]
pub struct SelectedMotion {
    /// The arm's name.
    pub arm: String,
    /// The candidate it grasps with.
    pub candidate: Arc<Candidate>,
    /// Its whole motion (approach, carry, retreat), timed.
    pub trajectory: TimedTrajectory,
}

/// The selected motions of `selection` (a selection of `task`), timed as the task times
/// motions and sampled every `period` seconds (at the timing grid's points with `None`): the
/// best-ranked candidate's motion with one arm, the best pair's two motions on one timeline
/// with two ([`timed_together`]). `None` when the task does not time motions or nothing is
/// selected. The chosen candidates are scored again (scoring is deterministic), so a streamed
/// selection, which keeps no motion, gives the same trajectories.
pub fn selected_motions<S: Scored>(
    task: &Task,
    selection: &Selection<S>,
    period: Option<f64>,
) -> Option<Result<Vec<SelectedMotion>, Failure>> {
    task.timing?;
    let chosen: Vec<Arc<Candidate>> = if task.arms.len() >= 2 {
        let pair = selection.pairs.first()?;
        vec![Arc::clone(&pair.first), Arc::clone(&pair.second)]
    } else {
        let arm = selection.arms.first()?;
        vec![Arc::clone(arm.scores[arm.best()?].candidate()?)]
    };
    let setups: Vec<_> = task
        .arms
        .iter()
        .map(|arm| scoring_setup(task, arm))
        .collect();
    let scores: Vec<_> = setups
        .iter()
        .zip(&chosen)
        .map(|(setup, candidate)| {
            score_candidates(setup, std::slice::from_ref(candidate), &|| {})
                .pop()
                .expect("one score per candidate")
        })
        .collect();
    let members: Vec<_> = setups.iter().copied().zip(&scores).collect();
    let timed = timed_together(&members, period)?;
    Some(timed.map(|trajectories| {
        task.arms
            .iter()
            .zip(chosen)
            .zip(trajectories)
            .map(|((arm, candidate), trajectory)| SelectedMotion {
                arm: arm.name.clone(),
                candidate,
                trajectory,
            })
            .collect()
    }))
}
