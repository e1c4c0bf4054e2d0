//! Streaming selection: every candidate's full scores are handed on in candidate order as soon
//! as they and the scores before them are done ([`for_each_score`]: at most
//! [`IN_FLIGHT`](super::IN_FLIGHT) candidates scored and not yet consumed), and only a
//! compact record of scalars ([`CandidateScalars`], about 250 bytes) and its ranking are kept
//! per candidate and arm, so the memory held does not grow with the per-sample series (`M_T`,
//! the ranked index, limit distances), the joint trajectories or the candidates themselves (a
//! family's are computed and a candidate file's read chunk by chunk, see
//! [`Task::for_each_candidate_chunk`]).

use super::rank::{assign_ranks, best_pairs, ranking_alone, ArmPair, Ranking};
use super::run::{arms_apart, scoring_setup, whole_motion, ArmResult, Selection};
use super::scalars::CandidateScalars;
use super::score::{for_each_score, CandidateScore};
use crate::grasp::CandidateError;
use crate::task::Task;
use std::sync::Arc;

/// How many of each arm's best-ranked candidates a streamed selection holds the candidate of
/// ([`CandidateScalars::candidate`]), for the summaries that name them by label.
pub const NAMED_BEST: usize = 5;

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

/// [`select`](super::select) with the results streamed: scores every arm's candidates in
/// parallel and calls `consume` for each candidate in candidate order, arm by arm, as soon as
/// it and the candidates before it are scored (by one worker at a time while the others score
/// the next ones: [`for_each_score`]); stops at the first error `consume`
/// returns. Returns the selection with each candidate reduced to its [`CandidateScalars`]
/// (rankings and pairs equal to [`select`](super::select)'s); the candidates themselves are
/// held only for the [`NAMED_BEST`] best ranked of each arm and the kept pairs' members.
///
/// The memory held grows with the number of candidates only by the scalars and rankings,
/// except with two arms whose pairs are checked for collisions between the arms
/// (`collision.between_arms`): the eligible candidates then keep their whole motions for that
/// check. `progress` is called once per scored candidate and arm. A candidate file that can no
/// longer be read (changed since the task was loaded) ends the selection with its error.
///
/// `consume` runs one call at a time: work on each result that needs no other (rendering a
/// record) runs on every core when it is done in [`select_streaming_prepared`]'s `prepare`.
pub fn select_streaming<E: From<CandidateError> + Send>(
    task: &Task,
    progress: &(dyn Fn() + Sync),
    mut consume: impl FnMut(Streamed<'_>) -> Result<(), E> + Send,
) -> Result<Selection<CandidateScalars>, E> {
    select_streaming_prepared(task, progress, |_| (), |streamed, ()| consume(streamed))
}

/// [`select_streaming`] with each result first prepared where it was scored: `prepare` runs on
/// the worker that scored the candidate, in parallel with the others (render a record, encode
/// it), and `consume` gets the result again with what `prepare` made of it, in candidate order
/// and one call at a time (write it out). The ranking alone, the compact record and (for the
/// pair check) the whole motion are also taken on the scoring worker.
pub fn select_streaming_prepared<P: Send, E: From<CandidateError> + Send>(
    task: &Task,
    progress: &(dyn Fn() + Sync),
    prepare: impl Fn(Streamed<'_>) -> P + Sync,
    mut consume: impl FnMut(Streamed<'_>, P) -> Result<(), E> + Send,
) -> Result<Selection<CandidateScalars>, E> {
    let max_log = task.max_log_likelihood();
    let keep_motions = task.arms.len() == 2 && task.checks_arms_against_each_other();
    let count = task.candidate_count();
    let mut arms = Vec::with_capacity(task.arms.len());
    // Per arm, with `keep_motions`: each candidate's whole motion when it is eligible.
    let mut motions: Vec<Vec<Option<Vec<Vec<f64>>>>> = Vec::new();
    for arm in &task.arms {
        let setup = scoring_setup(task, arm);
        let mut scores = Vec::with_capacity(count);
        let mut rankings = Vec::with_capacity(count);
        let mut kept_motions = Vec::new();
        let scoring = tracing::info_span!("score", arm = arm.name.as_str()).entered();
        let ready = |score: CandidateScore| {
            let ranking = ranking_alone(&score, &task.selection, max_log);
            let prepared = prepare(Streamed {
                arm: &arm.name,
                score: &score,
                ranking: &ranking,
            });
            Ready {
                scalars: CandidateScalars::of(&score),
                motion: (keep_motions && ranking.score.is_some()).then(|| whole_motion(&score)),
                score,
                ranking,
                prepared,
            }
        };
        for_each_score(
            &setup,
            task.candidates(),
            progress,
            ready,
            |ready| -> Result<(), E> {
                let streamed = Streamed {
                    arm: &arm.name,
                    score: &ready.score,
                    ranking: &ready.ranking,
                };
                consume(streamed, ready.prepared)?;
                if keep_motions {
                    kept_motions.push(ready.motion);
                }
                scores.push(ready.scalars);
                rankings.push(ready.ranking);
                Ok(())
            },
        )?;
        drop(scoring);
        tracing::info_span!("rank", arm = arm.name.as_str())
            .in_scope(|| assign_ranks(&scores, &mut rankings, &task.selection));
        let _fetching = tracing::info_span!("fetch the best candidates").entered();
        for (i, (score, ranking)) in scores.iter_mut().zip(&rankings).enumerate() {
            if ranking.rank.is_some_and(|r| r <= NAMED_BEST) {
                score.candidate = task.candidate_at(i)?;
            }
        }
        motions.push(kept_motions);
        arms.push(ArmResult {
            arm: arm.name.clone(),
            scores,
            rankings,
        });
    }
    let (pairs, colliding_pairs) = if arms.len() == 2 {
        let _pairing = tracing::info_span!("pair").entered();
        let apart = |i: usize, j: usize| match (&motions[0][..], &motions[1][..]) {
            ([], _) | (_, []) => true,
            (a, b) => match (&a[i], &b[j]) {
                (Some(qa), Some(qb)) => arms_apart(task, qa, qb),
                _ => true,
            },
        };
        let (best, refused) = best_pairs(
            (&arms[0].scores, &arms[0].rankings),
            (&arms[1].scores, &arms[1].rankings),
            &task.selection,
            &apart,
        );
        let mut pairs = Vec::with_capacity(best.len());
        for (k, (i, j, score)) in best.into_iter().enumerate() {
            let (Some(first), Some(second)) = (task.candidate_at(i)?, task.candidate_at(j)?) else {
                continue;
            };
            arms[0].scores[i].candidate = Some(Arc::clone(&first));
            arms[1].scores[j].candidate = Some(Arc::clone(&second));
            pairs.push(ArmPair {
                first,
                second,
                score,
                rank: k + 1,
            });
        }
        (pairs, refused)
    } else {
        (Vec::new(), 0)
    };
    Ok(Selection {
        arms,
        pairs,
        colliding_pairs,
    })
}

/// A scored candidate with what its worker prepared for the consumer.
struct Ready<P> {
    score: CandidateScore,
    ranking: Ranking,
    scalars: CandidateScalars,
    /// The whole motion, kept for the check between the arms when the candidate is eligible.
    motion: Option<Vec<Vec<f64>>>,
    prepared: P,
}
