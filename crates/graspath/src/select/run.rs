//! Running a whole task: every arm scored and ranked, and the best pairs when there are two arms.

use super::rank::{
    best_pairs_of, rank_against, rank_pairs, ArmPair, PairArm, PairScore, PositionPair, Ranking,
};
use super::scalars::Scored;
use super::score::{score_candidates, CandidateScore, ScoringSetup, WorldSetup};
use crate::collision::{check_arms, ArmMotion};
use crate::grasp::CandidateError;
use crate::task::{ArmSetup, Task};
use std::collections::{HashMap, HashSet};
use std::sync::{Arc, Mutex, OnceLock, PoisonError};

/// One arm's results: the full scores ([`select`]) or their scalars
/// ([`CandidateScalars`](super::CandidateScalars), [`select_streaming`](super::select_streaming)).
#[derive(Debug, Clone)]
pub struct ArmResult<S = CandidateScore> {
    /// The arm's name.
    pub arm: String,
    /// One score per task candidate, in candidate order.
    pub scores: Vec<S>,
    /// `rankings[i]` ranks `scores[i]`.
    pub rankings: Vec<Ranking>,
}

impl<S: Scored> ArmResult<S> {
    /// The index of the best-ranked candidate, if any is eligible.
    pub fn best(&self) -> Option<usize> {
        self.rankings.iter().position(|r| r.rank == Some(1))
    }

    /// The feasible candidate (index) a classical index at the grasp would pick: the largest
    /// `index(score)`, the earlier candidate on ties.
    pub fn best_by(&self, index: impl Fn(&S) -> Option<f64>) -> Option<usize> {
        self.scores
            .iter()
            .enumerate()
            .filter(|(_, s)| s.feasible())
            .filter_map(|(i, s)| index(s).map(|v| (i, v)))
            .max_by(|a, b| a.1.total_cmp(&b.1).then(b.0.cmp(&a.0)))
            .map(|(i, _)| i)
    }

    /// The ids of the other eligible candidates tied with candidate `i` (see
    /// [`tied_with`](super::tied_with)), in increasing id order.
    pub fn tied_with(&self, i: usize, options: &crate::task::SelectionOptions) -> Vec<usize> {
        super::rank::tied_with(&self.scores, &self.rankings, i, options)
    }

    /// How many candidates are feasible along the whole path.
    pub fn feasible_count(&self) -> usize {
        self.scores.iter().filter(|s| s.feasible()).count()
    }

    /// The pairs of bodies the collision failures name, each with how many candidates failed
    /// on it: the most frequent first, then by the bodies' names. What to move (an obstacle,
    /// the object, the robot's base) to free the most candidates.
    pub fn colliding_body_pairs(&self) -> Vec<(&[String; 2], usize)> {
        let mut counts: std::collections::BTreeMap<&[String; 2], usize> = Default::default();
        for bodies in self.scores.iter().filter_map(Scored::colliding_bodies) {
            *counts.entry(bodies).or_default() += 1;
        }
        let mut pairs: Vec<(&[String; 2], usize)> = counts.into_iter().collect();
        // Stable: equal counts keep the bodies' order.
        pairs.sort_by_key(|p| std::cmp::Reverse(p.1));
        pairs
    }
}

/// The result of a task: every candidate's full scores ([`select`]) or their scalars
/// ([`select_streaming`](super::select_streaming)).
#[derive(Debug, Clone)]
pub struct Selection<S = CandidateScore> {
    /// Per arm, in the task's order.
    pub arms: Vec<ArmResult<S>>,
    /// With two arms: the best pairs (first arm × second arm).
    pub pairs: Vec<ArmPair>,
    /// With two arms in a scene: how many pairs better than the last kept were refused
    /// because the arms collide with each other along the motion.
    pub colliding_pairs: usize,
}

/// Scores, ranks and pairs every candidate, held in memory with its whole motion. `progress`
/// is called once per scored candidate and arm. Candidates produced on demand are produced all
/// at once (stream a large task with [`select_streaming`](super::select_streaming)); a
/// candidate file that can no longer be read (removed or changed since the task was loaded)
/// is the error.
pub fn select(task: &Task, progress: &(dyn Fn() + Sync)) -> Result<Selection, CandidateError> {
    let candidates =
        tracing::info_span!("load the candidates").in_scope(|| task.all_candidates())?;
    let arms: Vec<ArmResult> = task
        .arms
        .iter()
        .map(|arm| {
            let setup = scoring_setup(task, arm);
            let scores = tracing::info_span!("score", arm = arm.name.as_str())
                .in_scope(|| score_candidates(&setup, &candidates, progress));
            let rankings = tracing::info_span!("rank", arm = arm.name.as_str())
                .in_scope(|| rank_against(&scores, &task.selection, task.max_log_likelihood()));
            ArmResult {
                arm: arm.name.clone(),
                scores,
                rankings,
            }
        })
        .collect();
    let (pairs, colliding_pairs) = if arms.len() == 2 {
        let _pairing = tracing::info_span!("pair").entered();
        let apart = |a: &CandidateScore, b: &CandidateScore| {
            arms_apart(task, &whole_motion(a), &whole_motion(b))
        };
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

/// Why [`pairs_of_eligible`] cannot pair the candidates it is given.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PairInputError {
    /// The task does not have exactly two arms.
    #[error("{task}: arm pairs need a task with two arms (it has {arms})")]
    NotTwoArms {
        /// The task's name.
        task: String,
        /// Its number of arms.
        arms: usize,
    },
    /// A position is not one of the task's candidates.
    #[error(
        "{task}: arm '{arm}': candidate {position} is not one of the task's {count} candidates"
    )]
    OutOfRange {
        /// The task's name.
        task: String,
        /// The arm.
        arm: String,
        /// The position given.
        position: usize,
        /// The task's number of candidates.
        count: usize,
    },
    /// A position is given twice for one arm.
    #[error("{task}: arm '{arm}': candidate {position} is given twice")]
    Repeated {
        /// The task's name.
        task: String,
        /// The arm.
        arm: String,
        /// The position given twice.
        position: usize,
    },
    /// The task's candidate file cannot be read again (removed or changed since the task
    /// was loaded).
    #[error(transparent)]
    Candidates(#[from] CandidateError),
}

impl crate::fault::Classify for PairInputError {
    /// A candidate file's error has its own kind; everything else is
    /// [`ErrorKind`](crate::fault::ErrorKind)`::Content`.
    fn kind(&self) -> Option<crate::fault::ErrorKind> {
        match self {
            Self::Candidates(e) => e.kind(),
            _ => Some(crate::fault::ErrorKind::Content),
        }
    }

    fn file(&self) -> Option<&str> {
        match self {
            Self::NotTwoArms { task, .. }
            | Self::OutOfRange { task, .. }
            | Self::Repeated { task, .. } => Some(task),
            Self::Candidates(e) => e.file(),
        }
    }

    fn field(&self) -> Option<&str> {
        match self {
            Self::Candidates(e) => e.field(),
            _ => None,
        }
    }
}

/// The best `count` arm pairs of a two-arm `task`, from each arm's eligible candidates and
/// their norms found by an earlier scoring — candidate slices scored apart, as
/// `graspath.ray`'s shards do: `first` and `second` are `(position in the task's candidates,
/// norm)` of every ranked candidate of the first and second arm (the norm the task ranks by,
/// `μ_l2`, or `μ_l1` with `norm: l1`), in any order. With every ranked candidate given and
/// `count ≤ selection.pairs`, the pairs, as `(first-arm position, second-arm position,
/// score)` best first, are the first `count` of [`select`]'s, in the same order with the same
/// scores (the sum of the two norms); also returned: how many better pairs the check between
/// the arms refused.
///
/// The check between the arms (a scene with `collision.between_arms`) needs the two arms'
/// motions: the candidates of the pairs the search looks at are scored again, each once, and
/// only they (scoring is deterministic and per candidate, so their motions are those of the
/// earlier scoring).
///
/// Errors: the task does not have two arms, or a position is out of range or repeated.
pub fn pairs_of_eligible(
    task: &Task,
    first: &[(usize, f64)],
    second: &[(usize, f64)],
    count: usize,
) -> Result<(Vec<PositionPair>, usize), PairInputError> {
    if task.arms.len() != 2 {
        return Err(PairInputError::NotTwoArms {
            task: task.source_name.clone(),
            arms: task.arms.len(),
        });
    }
    let candidates = task.candidate_count();
    for (arm, eligible) in task.arms.iter().zip([first, second]) {
        let mut seen = HashSet::with_capacity(eligible.len());
        for &(position, _) in eligible {
            if position >= candidates {
                return Err(PairInputError::OutOfRange {
                    task: task.source_name.clone(),
                    arm: arm.name.clone(),
                    position,
                    count: candidates,
                });
            }
            if !seen.insert(position) {
                return Err(PairInputError::Repeated {
                    task: task.source_name.clone(),
                    arm: arm.name.clone(),
                    position,
                });
            }
        }
    }
    // Every position is in range (checked above).
    let all = task.all_candidates()?;
    // Whole motions scored on demand, once per arm and candidate (pairs are checked in
    // parallel: a motion another thread is scoring is waited for, not scored again).
    type Motion = Arc<Vec<Vec<f64>>>;
    type Slot = Arc<OnceLock<Motion>>;
    let motions: Mutex<HashMap<(usize, usize), Slot>> = Mutex::default();
    let motion = |arm: usize, position: usize| -> Motion {
        let slot = Arc::clone(
            motions
                .lock()
                .unwrap_or_else(PoisonError::into_inner)
                .entry((arm, position))
                .or_default(),
        );
        let motion = slot.get_or_init(|| {
            let setup = scoring_setup(task, &task.arms[arm]);
            let scores = score_candidates(&setup, std::slice::from_ref(&all[position]), &|| {});
            Arc::new(scores.first().map(whole_motion).unwrap_or_default())
        });
        Arc::clone(motion)
    };
    let need_motions = task.checks_arms_against_each_other();
    let apart =
        |i: usize, j: usize| !need_motions || arms_apart(task, &motion(0, i), &motion(1, j));
    Ok(best_pairs_of(
        PairArm {
            eligible: first.to_vec(),
            grasp_point: &|i| all[i].grasp_point(),
        },
        PairArm {
            eligible: second.to_vec(),
            grasp_point: &|j| all[j].grasp_point(),
        },
        (task.selection.min_separation, count),
        PairScore::of_options(&task.selection),
        &apart,
    ))
}

/// What scoring one of the task's arms needs.
pub fn scoring_setup<'a>(task: &'a Task, arm: &'a ArmSetup) -> ScoringSetup<'a> {
    ScoringSetup {
        arm,
        path: &task.path,
        rows: task.rows,
        ranked: task.ranked,
        ik: &task.ik,
        ik_limit_margin: task.ik_limit_margin,
        redundancy: task.redundancy,
        norm: task.selection.norm,
        world: WorldSetup {
            approach: task.approach.as_ref(),
            retreat: task.retreat.as_ref(),
            gripper: task.gripper.as_ref(),
            collisions: task.collisions.as_ref(),
            object: task.object_body.as_deref(),
            payload: task.payload.as_ref(),
        },
        timing: task.timing.as_ref(),
    }
}

/// A candidate's whole motion: approach, path and retreat (rad or m per joint and sample).
pub(super) fn whole_motion(s: &CandidateScore) -> Vec<Vec<f64>> {
    s.approach
        .iter()
        .chain(&s.joint_trajectory)
        .chain(&s.retreat)
        .cloned()
        .collect()
}

/// Whether the first two arms, following the whole motions `qa` and `qb` (see
/// [`whole_motion`]) at the same time, stay apart (always, without a scene or with
/// `collision.between_arms: false`).
pub(super) fn arms_apart(task: &Task, qa: &[Vec<f64>], qb: &[Vec<f64>]) -> bool {
    let Some(collisions) = &task.collisions else {
        return true;
    };
    let (first, second) = (&task.arms[0], &task.arms[1]);
    let (Some(bodies_a), Some(bodies_b)) = (&first.bodies, &second.bodies) else {
        return true;
    };
    if !collisions.options.between_arms {
        return true;
    }
    let label_a = format!("{} arm: ", first.name);
    let label_b = format!("{} arm: ", second.name);
    check_arms(
        &ArmMotion {
            arm: bodies_a,
            world_from_base: &first.world_from_base,
            q: qa,
            label: &label_a,
        },
        &ArmMotion {
            arm: bodies_b,
            world_from_base: &second.world_from_base,
            q: qb,
            label: &label_b,
        },
        collisions.options.resolution,
    )
    .is_none()
}
