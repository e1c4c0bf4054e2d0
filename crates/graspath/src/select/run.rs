//! Running a whole task: every arm scored and ranked, and the best pairs when there are two arms.

use super::rank::{rank_candidates, rank_pairs, ArmPair, Ranking};
use super::score::{score_candidates, CandidateScore, ScoringSetup, WorldSetup};
use crate::task::Task;

/// One arm's results.
#[derive(Debug, Clone)]
pub struct ArmResult {
    /// The arm's name.
    pub arm: String,
    /// One score per task candidate, in candidate order; each carries its candidate.
    pub scores: Vec<CandidateScore>,
    /// `rankings[i]` ranks `scores[i]`.
    pub rankings: Vec<Ranking>,
}

impl ArmResult {
    /// The index of the best-ranked candidate, if any is eligible.
    pub fn best(&self) -> Option<usize> {
        self.rankings.iter().position(|r| r.rank == Some(1))
    }

    /// The feasible candidate (index) a classical index at the grasp would pick: the largest
    /// `index(score)`, the earlier candidate on ties.
    pub fn best_by(&self, index: impl Fn(&CandidateScore) -> Option<f64>) -> Option<usize> {
        self.scores
            .iter()
            .enumerate()
            .filter(|(_, s)| s.feasible())
            .filter_map(|(i, s)| index(s).map(|v| (i, v)))
            .max_by(|a, b| a.1.total_cmp(&b.1).then(b.0.cmp(&a.0)))
            .map(|(i, _)| i)
    }

    /// How many candidates are feasible along the whole path.
    pub fn feasible_count(&self) -> usize {
        self.scores.iter().filter(|s| s.feasible()).count()
    }
}

/// The result of a task.
#[derive(Debug, Clone)]
pub struct Selection {
    /// Per arm, in the task's order.
    pub arms: Vec<ArmResult>,
    /// With two arms: the best pairs (first arm × second arm).
    pub pairs: Vec<ArmPair>,
}

/// Scores, ranks and pairs. `progress` is called once per scored candidate and arm.
pub fn select(task: &Task, progress: &(dyn Fn() + Sync)) -> Selection {
    let arms: Vec<ArmResult> = task
        .arms
        .iter()
        .map(|arm| {
            let setup = ScoringSetup {
                arm,
                path: &task.path,
                rows: task.rows,
                ik: &task.ik,
                compare_branches: task.compare_branches,
                world: WorldSetup {
                    approach: task.approach.as_ref(),
                    retreat: task.retreat.as_ref(),
                    gripper: task.gripper.as_ref(),
                    collisions: task.collisions.as_ref(),
                    object: task.object_body.as_deref(),
                },
            };
            let scores = score_candidates(&setup, &task.candidates, progress);
            let rankings = rank_candidates(&scores, &task.selection);
            ArmResult {
                arm: arm.name.clone(),
                scores,
                rankings,
            }
        })
        .collect();
    let pairs = if arms.len() == 2 {
        rank_pairs(
            (&arms[0].scores, &arms[0].rankings),
            (&arms[1].scores, &arms[1].rankings),
            &task.selection,
        )
    } else {
        Vec::new()
    };
    Selection { arms, pairs }
}
