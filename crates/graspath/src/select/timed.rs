//! The selected grasps' motions as timed joint trajectories: the best candidate of a one-arm
//! task, or the best pair's two candidates on one shared timeline; or the motions of any
//! candidates a caller names (one per arm), for a simulator that executes them.

use super::run::{scoring_setup, Selection};
use super::scalars::Scored;
use super::score::{score_candidates, timed_together, Failure};
use crate::grasp::Candidate;
use crate::task::Task;
use crate::timing::TimedTrajectory;
use std::sync::Arc;

/// One arm's motion, timed.
#[derive(Debug, Clone, PartialEq)]
pub struct SelectedMotion {
    /// The arm's name.
    pub arm: String,
    /// The candidate it grasps with.
    pub candidate: Arc<Candidate>,
    /// Its whole motion (approach, carry, retreat), timed.
    pub trajectory: TimedTrajectory,
    /// When the tool reaches the grasp (s from the start): where the gripper closes.
    pub grasp_time: f64,
    /// When the object reaches the place (s from the start): where the gripper opens.
    pub place_time: f64,
    /// When the motion reaches each IK sample of the approach, the path and the retreat
    /// (s from the start; see [`super::TimedMotion::sample_times`]).
    pub sample_times: Vec<f64>,
}

/// The selected motions of `selection` (a selection of `task`), timed as the task times
/// motions and sampled every `period` seconds (at the timing grid's points with `None`): the
/// best-ranked candidate's motion with one arm, the best pair's two motions on one timeline
/// with two ([`candidate_motions`]). `None` when the task does not time motions or nothing is
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
    candidate_motions(task, &chosen, period)
}

/// The motions of `chosen` — one candidate per arm of `task`, in the task's arm order —
/// scored, timed as the task times motions on one shared timeline (arms that carry the object
/// together wait for each other) and sampled every `period` seconds (at the timing grid's
/// points with `None`). `None` when the task does not time motions, `chosen` does not name one
/// candidate per arm, or a candidate is not feasible for its arm.
pub fn candidate_motions(
    task: &Task,
    chosen: &[Arc<Candidate>],
    period: Option<f64>,
) -> Option<Result<Vec<SelectedMotion>, Failure>> {
    task.timing?;
    if chosen.len() != task.arms.len() {
        return None;
    }
    let setups: Vec<_> = task
        .arms
        .iter()
        .map(|arm| scoring_setup(task, arm))
        .collect();
    let scores: Vec<_> = setups
        .iter()
        .zip(chosen)
        .map(|(setup, candidate)| {
            score_candidates(setup, std::slice::from_ref(candidate), &|| {})
                .pop()
                .expect("one score per candidate")
        })
        .collect();
    let members: Vec<_> = setups.iter().copied().zip(&scores).collect();
    let timed = timed_together(&members, period)?;
    Some(timed.map(|motions| {
        task.arms
            .iter()
            .zip(chosen)
            .zip(motions)
            .map(|((arm, candidate), motion)| SelectedMotion {
                arm: arm.name.clone(),
                candidate: Arc::clone(candidate),
                trajectory: motion.trajectory,
                grasp_time: motion.grasp_time,
                place_time: motion.place_time,
                sample_times: motion.sample_times,
            })
            .collect()
    }))
}
