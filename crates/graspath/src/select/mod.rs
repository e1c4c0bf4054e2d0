//! Task-relevant grasp selection: score every candidate along the task for each arm, rank them
//! (single arm) and pair them (two arms).

mod rank;
mod run;
mod score;
mod setup;

pub use rank::{
    rank_candidates, rank_pairs, ArmPair, LikelihoodRule, Norm, Ranking, SelectionOptions,
};
pub use run::{select, ArmResult, Selection};
pub use score::{score_candidates, wrist_trajectory, CandidateScore, Failure};
pub use setup::{pose, ArmSetup, Task, DEFAULT_GRASP_ITERATIONS};
