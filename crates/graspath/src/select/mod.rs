//! Task-relevant grasp selection: score every candidate along the task for each arm, rank them
//! (single arm) and pair them (two arms); the selected motions timed as trajectories.

mod rank;
pub mod record;
mod run;
mod scalars;
mod score;
mod stream;
mod timed;

pub use rank::{
    assign_ranks, best_pairs, best_pairs_of, rank_against, rank_candidates, rank_pairs,
    ranking_alone, scores_tied, tied_with, values_tied, ArmPair, PairArm, PairScore, PositionPair,
    Ranking,
};
pub use run::{pairs_of_eligible, scoring_setup, select, ArmResult, PairInputError, Selection};
pub use scalars::{CandidateScalars, FailurePoint, Scored};
pub use score::{
    for_each_score, score_candidates, timed_together, wrist_trajectory, CandidateChunks,
    CandidateScore, Failure, MotionDurations, ScoringSetup, SelfMotionScores, TimedMotion,
    IN_FLIGHT, STREAM_CHUNK,
};
pub use stream::{select_streaming, select_streaming_prepared, Streamed, NAMED_BEST};
pub use timed::{candidate_motions, selected_motions, SelectedMotion};
