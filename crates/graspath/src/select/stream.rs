//! Streaming selection: every candidate's full scores are handed on as soon as its chunk of
//! [`STREAM_CHUNK`](super::STREAM_CHUNK) candidates is scored, and only the per-candidate
//! scalars the ranking needs are kept, so the memory held does not grow with the per-sample
//! series (`M_T`, the ranked index, limit distances) or the joint trajectories.

use super::rank::{rank_candidates, rank_pairs, ranking_alone, Ranking};
use super::run::{arms_apart, pairs_need_motions, scoring_setup, ArmResult, Selection};
use super::score::{score_candidates, CandidateScore, STREAM_CHUNK};
use crate::task::Task;

/// One candidate's result as it is streamed: the arm, the full scores and the part of the
/// ranking that needs no other candidate (see [`ranking_alone`](super::ranking_alone):
/// `rank` is `None` and `pareto` is `false` until every candidate is scored).
#[derive(Debug, Clone, Copy)]
pub struct Streamed<'a> {
    /// The arm's name.
    pub arm: &'a str,
    /// The candidate's full scores (series and motions included).
    pub score: &'a CandidateScore,
    /// Its combined score and rejection; `rank: None`, `pareto: false`.
    pub ranking: &'a Ranking,
}

/// What a streamed selection keeps of a candidate's scores: every scalar (norms, classical
/// indices at the grasp, clearance, branch count, self-motion scores) and the failure's reason,
/// phase and sample, but no per-sample series (`m_t`, `ranked_values`, `limit_distance` are
/// empty) and no failure detail or bodies. The motions (`approach`, `joint_trajectory`,
/// `retreat`) are kept only when `keep_motion` is set.
pub fn scalars_of(score: &CandidateScore, keep_motion: bool) -> CandidateScore {
    let mut kept = CandidateScore::unscored(score.candidate.clone());
    kept.failure = score.failure.as_ref().map(|f| crate::failure::Failure {
        reason: f.reason,
        phase: f.phase,
        sample: f.sample,
        detail: String::new(),
        bodies: None,
    });
    kept.norms = score.norms;
    kept.yoshikawa_at_grasp = score.yoshikawa_at_grasp;
    kept.yoshikawa_penalized_at_grasp = score.yoshikawa_penalized_at_grasp;
    kept.inverse_condition_at_grasp = score.inverse_condition_at_grasp;
    kept.inverse_condition_squared_at_grasp = score.inverse_condition_squared_at_grasp;
    kept.clearance = score.clearance;
    kept.feasible_branches = score.feasible_branches;
    kept.self_motion = score.self_motion;
    if keep_motion {
        kept.approach = score.approach.clone();
        kept.joint_trajectory = score.joint_trajectory.clone();
        kept.retreat = score.retreat.clone();
    }
    kept
}

/// [`select`](super::select) with the results streamed: scores every arm's candidates chunk by
/// chunk (in parallel within a chunk) and calls `consume` for each candidate in candidate
/// order, arm by arm, as soon as its chunk is done; stops at the first error `consume`
/// returns. Returns the selection with each candidate reduced to [`scalars_of`] (rankings and
/// pairs equal to [`select`](super::select)'s). The memory held grows with the number of
/// candidates only by their scalars, except with two arms whose pairs are checked for
/// collisions between the arms (`collision.between_arms`): the eligible candidates then keep
/// their motions for that check. `progress` is called once per scored candidate and arm.
pub fn select_streaming<E>(
    task: &Task,
    progress: &(dyn Fn() + Sync),
    mut consume: impl FnMut(Streamed<'_>) -> Result<(), E>,
) -> Result<Selection, E> {
    let max_log = task
        .candidates
        .iter()
        .map(|c| c.log_likelihood)
        .fold(f64::NEG_INFINITY, f64::max);
    let keep_motions = task.arms.len() == 2 && pairs_need_motions(task);
    let mut arms = Vec::with_capacity(task.arms.len());
    for arm in &task.arms {
        let setup = scoring_setup(task, arm);
        let mut kept = Vec::with_capacity(task.candidates.len());
        for chunk in task.candidates.chunks(STREAM_CHUNK) {
            for score in score_candidates(&setup, chunk, progress) {
                let ranking = ranking_alone(&score, &task.selection, max_log);
                consume(Streamed {
                    arm: &arm.name,
                    score: &score,
                    ranking: &ranking,
                })?;
                kept.push(scalars_of(&score, keep_motions && ranking.score.is_some()));
            }
        }
        let rankings = rank_candidates(&kept, &task.selection);
        arms.push(ArmResult {
            arm: arm.name.clone(),
            scores: kept,
            rankings,
        });
    }
    let (pairs, colliding_pairs) = if arms.len() == 2 {
        let apart = |a: &CandidateScore, b: &CandidateScore| arms_apart(task, a, b);
        rank_pairs(
            (&arms[0].scores, &arms[0].rankings),
            (&arms[1].scores, &arms[1].rankings),
            &task.selection,
            &apart,
        )
    } else {
        (Vec::new(), 0)
    };
    Ok(Selection {
        arms,
        pairs,
        colliding_pairs,
    })
}
