//! Scoring candidates along a task (paper eq. 8–17): each candidate's wrist trajectory, its
//! trajectory IK, `M_T` at every sample, the norms over the path, and the classical indices at
//! the grasp for comparison.

mod branch_checks;
mod candidate_score;
mod dynamic_index;
mod grasp_checks;
mod path;
mod pipeline;
mod self_motion;
mod timing_check;
mod torque_check;

pub use candidate_score::{CandidateScore, SelfMotionScores};
pub use path::wrist_trajectory;
pub use pipeline::{CandidateChunks, IN_FLIGHT};
pub use timing_check::{MotionDurations, TimedMotion};

use crate::collision::{ArmInScene, Body, ObjectAlong};
pub use crate::failure::Failure;
use crate::failure::{FailureReason, Phase};
use crate::grasp::Candidate;
use crate::manipulability::{
    classical_indices, joint_limit_penalty, limit_distance, JacobianPart, PathNorms,
};
use crate::manipulability::{IndexMeasure, JacobianRows, Norm, RankedIndex};
use crate::robot::{
    solve_trajectories, solve_trajectory, RigidBody, TrajectoryIkOptions, TrajectoryIkResult,
};
use crate::task::{
    ArmSetup, Collisions, Gripper, ObjectPath, Redundancy, Stroke, TimingSettings, WholeMotionPlan,
};
use branch_checks::{check_branch, BranchCheck, BranchFindings, SceneCheck};
use dynamic_index::{dynamic_norm, dynamic_workspace};
use grasp_checks::{grasp_checks, FingerCheck, GraspCheck};
use nalgebra::{Isometry3, Matrix6xX};
use path::{counted_samples, index_along, IndexSeries, ObjectMotion};
use pipeline::score_in_order;
use self_motion::SelfMotionSearch;
use std::convert::Infallible;
use std::sync::Arc;
use timing_check::TimingCheck;
use torque_check::TorqueCheck;

/// How many candidates are produced (computed or read) at a time, and scored in parallel before
/// their results are handed on when scoring runs chunk by chunk (inside a rayon worker).
pub const STREAM_CHUNK: usize = 256;

/// How many candidates share one batch of first IK solves (their branches tracked four at a
/// time in vector lanes, see [`solve_trajectories`]).
const SOLVE_GROUP: usize = 16;

/// What scoring needs besides the candidate: the arm, the object path, which rows of `J` enter
/// `M_T`, the IK settings, and what the task knows of its world.
#[derive(Debug, Clone, Copy)]
pub struct ScoringSetup<'a> {
    /// The arm that grasps.
    pub arm: &'a ArmSetup,
    /// The object's path (world frame).
    pub path: &'a ObjectPath,
    /// Which rows of `J` and of the tangent enter `M_T`.
    pub rows: JacobianRows,
    /// The per-sample index that is ranked.
    pub ranked: RankedIndex,
    /// Trajectory IK settings.
    pub ik: &'a TrajectoryIkOptions,
    /// How far inside its limits the IK keeps every revolute joint (rad): the arm's
    /// [`ArmSetup::ik_chain`] is narrowed by it; named in `joint_limit` failures.
    pub ik_limit_margin: f64,
    /// How the arm's self-motion is chosen (first branch, best branch, or optimised).
    pub redundancy: Redundancy,
    /// The norm candidates are ranked by: of two branches (or a branch and the optimised
    /// self-motion) of one candidate, the larger is kept.
    pub norm: Norm,
    /// The tool's approach to the grasp and retreat after the place, the gripper, and the
    /// collision checks (all `None`: the motion is the object's path in empty space).
    pub world: WorldSetup<'a>,
    /// How the chosen motion is timed (`None`: not timed).
    pub timing: Option<&'a TimingSettings>,
}

/// What a task knows of its world ([`Task`](crate::task::Task)'s `approach`, `retreat`,
/// `gripper`, `collisions` and object body).
#[derive(Debug, Clone, Copy, Default)]
pub struct WorldSetup<'a> {
    /// The approach before the grasp.
    pub approach: Option<&'a Stroke>,
    /// The retreat after the place.
    pub retreat: Option<&'a Stroke>,
    /// The gripper (width check).
    pub gripper: Option<&'a Gripper>,
    /// Collision checks.
    pub collisions: Option<&'a Collisions>,
    /// The object's body, object frame.
    pub object: Option<&'a Body>,
    /// The object's mass properties, object frame, when the arm carries its weight.
    pub payload: Option<&'a RigidBody>,
}

impl WorldSetup<'_> {
    fn plan<'p>(&self, path: &'p ObjectPath) -> WholeMotionPlan<'p>
    where
        Self: 'p,
    {
        WholeMotionPlan {
            approach: self.approach,
            retreat: self.retreat,
            path,
        }
    }
}

/// Scores every candidate for one arm, makes each score into what `prepare` returns on the
/// worker that scored it (in parallel), and hands each result to `consume` in candidate order,
/// as soon as it and every candidate before it are scored, so a consumer can write results out
/// without holding them all; stops at the first error of the candidates (a file that can no
/// longer be read) or of `consume`. The candidates are produced, scored and consumed at the
/// same time: scored in parallel (rayon), in groups whose first IK solves are batched (at most
/// `SOLVE_GROUP` candidates, fewer when there are many threads), produced on a thread of their
/// own, and consumed by one worker at a time (so `consume` is `Send`); at most [`IN_FLIGHT`]
/// are scored and not yet consumed. The results depend neither on the thread count nor on the
/// grouping. `progress` is called once per candidate, as its group finishes.
///
/// In a scene, the hand and what rides rigidly with it (the links after the last moving
/// joint, the carried object) are first checked at the commanded tool poses: a grasp whose
/// hand collides is refused without solving the arm (`ArmInScene::check_tool_poses`).
/// IK tracks one branch from the first pose of the motion; only when it fails (or collides)
/// are up to `ik.branches` distinct initial solutions searched and tracked. With
/// [`Redundancy::BestBranch`], every branch is tracked and the one with the best norm is kept
/// (slower, and the ranking then reflects the best redundancy resolution rather than the first
/// one found); with [`Redundancy::Optimize`], the arm's place in the self-motion around the
/// best branch is then chosen as a smooth function of the path's time for the largest ranked
/// norm ([`crate::robot::optimize_smooth_self_motion`]), kept when it ranks higher and passes
/// the branch checks (else the best branch).
pub fn for_each_score<C, E, T: Send>(
    setup: &ScoringSetup<'_>,
    candidates: &C,
    progress: &(dyn Fn() + Sync),
    prepare: impl Fn(CandidateScore) -> T + Sync,
    consume: impl FnMut(T) -> Result<(), E> + Send,
) -> Result<(), E>
where
    C: CandidateChunks + ?Sized,
    E: From<C::Error> + Send,
{
    let base_from_world = setup.arm.world_from_base.inverse();
    let motion = ObjectMotion::new(setup.path, &base_from_world);
    let times = setup.path.times();
    let fingers = FingerCheck::new(&setup.world);
    let checks = grasp_checks(fingers.as_ref());
    // Groups small enough to give every thread several.
    let group = (STREAM_CHUNK / (4 * rayon::current_num_threads())).clamp(1, SOLVE_GROUP);
    let score = |members: &[Arc<Candidate>]| {
        let scores = score_group(setup, members, &motion, &times, &checks);
        scores.iter().for_each(|_| progress());
        scores.into_iter().map(&prepare).collect()
    };
    score_in_order(candidates, group, &score, consume)
}

/// The chosen motions of feasible candidates — one per arm, each scored with its arm's setup
/// — timed as the task times motions on one shared timeline, and sampled every `period`
/// seconds (at the timing grid's points with `None`): positions, velocities, accelerations
/// and, with the arm's dynamics, torques. Arms that carry the object together are timed as
/// one path of all their joints (the carry, or the whole motion without stops): every arm
/// passes its IK sample of each object pose at the same instant, under every arm's limits. An
/// approach or a retreat takes the slowest arm's time, the faster arms' timings slowed
/// uniformly to it. `None` when the task does not time motions or a candidate is not feasible.
pub fn timed_together(
    members: &[(ScoringSetup<'_>, &CandidateScore)],
    period: Option<f64>,
) -> Option<Result<Vec<TimedMotion>, Failure>> {
    if members.iter().any(|(_, score)| !score.feasible()) {
        return None;
    }
    let scorings: Vec<Scoring<'_>> = members
        .iter()
        .map(|(setup, score)| Scoring::new(setup, &score.candidate))
        .collect();
    let checks: Vec<TimingCheck<'_>> = scorings
        .iter()
        .map(TimingCheck::of)
        .collect::<Option<_>>()?;
    let timed = || -> Result<Vec<TimedMotion>, Failure> {
        let motions: Vec<Vec<Vec<f64>>> = members
            .iter()
            .map(|(_, score)| {
                score
                    .approach
                    .iter()
                    .chain(&score.joint_trajectory)
                    .chain(&score.retreat)
                    .cloned()
                    .collect()
            })
            .collect();
        timing_check::timed_jointly(&checks, &motions)?
            .into_iter()
            .zip(&checks)
            .map(|(segments, check)| check.sample(segments, period))
            .collect()
    };
    Some(timed())
}

/// Scores every candidate for one arm (see [`for_each_score`]), in candidate order.
pub fn score_candidates(
    setup: &ScoringSetup<'_>,
    candidates: &[Arc<Candidate>],
    progress: &(dyn Fn() + Sync),
) -> Vec<CandidateScore> {
    let mut scores = Vec::with_capacity(candidates.len());
    let Ok(()) = for_each_score::<_, Infallible, _>(
        setup,
        candidates,
        progress,
        |s| s,
        |s| {
            scores.push(s);
            Ok(())
        },
    );
    scores
}

/// A candidate on its way through scoring: its motion's tool poses and what checks them.
struct Scoring<'s> {
    setup: &'s ScoringSetup<'s>,
    candidate: &'s Arc<Candidate>,
    plan: WholeMotionPlan<'s>,
    /// The tool poses of the whole motion (approach, path, retreat), chain base frame.
    targets: Vec<Isometry3<f64>>,
    /// The arm in the scene, with a scene and the arm's bodies.
    checker: Option<ArmInScene<'s>>,
    /// The object's first and last poses on the path, world frame.
    first_pose: Isometry3<f64>,
    last_pose: Isometry3<f64>,
}

impl<'s> Scoring<'s> {
    fn new(setup: &'s ScoringSetup<'s>, candidate: &'s Arc<Candidate>) -> Self {
        let ScoringSetup {
            arm, path, world, ..
        } = setup;
        let plan = world.plan(path);
        let base_from_world = arm.world_from_base.inverse();
        let targets = plan
            .tool_poses(&candidate.object_from_wrist)
            .iter()
            .map(|p| base_from_world * p)
            .collect();
        let checker = match (world.collisions, &arm.bodies) {
            (Some(c), Some(bodies)) => Some(ArmInScene {
                arm: bodies,
                world_from_base: &arm.world_from_base,
                scene: &c.scene,
                object: world.object,
                options: &c.options,
            }),
            _ => None,
        };
        let first_pose = path
            .poses()
            .next()
            .copied()
            .unwrap_or_else(Isometry3::identity);
        let last_pose = path.poses().last().copied().unwrap_or(first_pose);
        Self {
            setup,
            candidate,
            plan,
            targets,
            checker,
            first_pose,
            last_pose,
        }
    }

    /// The IK options of the first solve: one branch tracked, unless every branch is to be
    /// compared.
    fn first_try(setup: &ScoringSetup<'_>) -> TrajectoryIkOptions {
        let ik = setup.ik;
        TrajectoryIkOptions {
            branches: if setup.redundancy == Redundancy::First {
                1
            } else {
                ik.branches
            },
            ..ik.clone()
        }
    }

    /// A failure whose sample counts the whole motion's samples, located in its phase.
    fn located(&self, mut failure: Failure) -> Failure {
        let (phase, sample) = self.plan.phase_of(failure.sample);
        failure.phase = phase;
        failure.sample = sample;
        let margin = self.setup.ik_limit_margin;
        if failure.reason == FailureReason::JointLimit && margin > 0.0 {
            failure.detail.push_str(&format!(
                " (the IK keeps every revolute joint ik.limit_margin = {margin} rad inside its limits)"
            ));
        }
        failure
    }

    /// The object carried along the path, for the collision checks.
    fn object_along(&self) -> ObjectAlong<'_> {
        let before = self.plan.approach_samples();
        ObjectAlong {
            path: before..before + self.setup.path.samples.len(),
            world_from_object_start: &self.first_pose,
            world_from_object_end: &self.last_pose,
            object_from_wrist: &self.candidate.object_from_wrist,
        }
    }
}

/// Scores the candidates of `group` (see [`for_each_score`]), in order. The first IK solve of
/// every candidate that gets that far is done in one batch ([`solve_trajectories`]).
fn score_group(
    setup: &ScoringSetup<'_>,
    group: &[Arc<Candidate>],
    motion: &ObjectMotion,
    times: &[f64],
    checks: &[&dyn GraspCheck],
) -> Vec<CandidateScore> {
    // The IK plans in the ranges narrowed by the task's limit margin.
    let chain = &setup.arm.ik_chain;
    let scorings: Vec<Scoring<'_>> = group.iter().map(|c| Scoring::new(setup, c)).collect();
    let early: Vec<Option<Failure>> = scorings
        .iter()
        .map(|s| checks.iter().find_map(|check| check.failure(s)))
        .collect();
    let trajectories: Vec<&[Isometry3<f64>]> = scorings
        .iter()
        .zip(&early)
        .filter(|(_, failure)| failure.is_none())
        .map(|(scoring, _)| scoring.targets.as_slice())
        .collect();
    let q_start = chain.mid_configuration();
    let firsts: Vec<Result<TrajectoryIkResult, String>> =
        match solve_trajectories(chain, &trajectories, &q_start, &Scoring::first_try(setup)) {
            Ok(results) => results
                .into_iter()
                .map(|r| r.map_err(|e| e.to_string()))
                .collect(),
            Err(e) => trajectories.iter().map(|_| Err(e.to_string())).collect(),
        };
    let mut firsts = firsts.into_iter();
    scorings
        .into_iter()
        .zip(early)
        .map(|(scoring, early)| match early {
            Some(failure) => {
                let mut score = CandidateScore::unscored(Arc::clone(scoring.candidate));
                score.failure = Some(failure);
                score
            }
            None => {
                let first = firsts.next().expect("one first solve per candidate solved");
                score_solved(scoring, first, motion, times)
            }
        })
        .collect()
}

/// The branch checks of one candidate, in the order they run: the arm in the scene (with a
/// scene and the arm's bodies), then the joint torques (with a payload), then the timing (when
/// the task times motions).
fn branch_checks<'a>(scoring: &'a Scoring<'a>) -> Vec<Box<dyn BranchCheck + 'a>> {
    let mut checks: Vec<Box<dyn BranchCheck + 'a>> = Vec::new();
    if let Some(scene) = SceneCheck::of(scoring) {
        checks.push(Box::new(scene));
    }
    if let Some(torques) = TorqueCheck::of(scoring) {
        checks.push(Box::new(torques));
    }
    if let Some(timing) = TimingCheck::of(scoring) {
        checks.push(Box::new(timing));
    }
    checks
}

/// The branch kept so far: the index along its path, its norms, the whole motion's joints and
/// what the branch checks measured on it.
struct ChosenBranch {
    series: IndexSeries,
    norms: PathNorms,
    /// Joint configurations of the whole motion (approach, path, retreat), rad or m.
    q: Vec<Vec<f64>>,
    findings: BranchFindings,
}

impl ChosenBranch {
    /// Whether `norms` rank above this branch's: a finite `μ_l∞` first, then a larger value
    /// of the task's ranked `norm`.
    fn norms_better(&self, norms: &PathNorms, norm: Norm) -> bool {
        (norms.linf.is_finite(), norms.value(norm))
            > (self.norms.linf.is_finite(), self.norms.value(norm))
    }

    /// Whether this branch, checked, ranks above `other` by `order`.
    fn better_than(&self, other: &ChosenBranch, order: BranchOrder) -> bool {
        if order.by_duration {
            let duration = |b: &ChosenBranch| b.findings.durations.map(|d| d.total());
            match (duration(self), duration(other)) {
                (Some(mine), Some(theirs)) if mine != theirs => return mine < theirs,
                (Some(_), None) => return true,
                (None, Some(_)) => return false,
                _ => {}
            }
        }
        other.norms_better(&self.norms, order.norm)
    }
}

/// How the branches of one candidate are compared: the task's ranked norm, or with
/// `index.measure: duration` the whole motion's duration first (shorter ranks above; equal
/// durations by the norm). Only the norm is known before a branch's checks, which time it.
#[derive(Debug, Clone, Copy)]
struct BranchOrder {
    norm: Norm,
    by_duration: bool,
}

impl BranchOrder {
    fn of(setup: &ScoringSetup<'_>) -> Self {
        Self {
            norm: setup.norm,
            by_duration: setup.ranked.measure == IndexMeasure::Duration,
        }
    }
}

/// The rest of a candidate's scoring, from its first IK solve (`first`, with
/// [`Scoring::first_try`]'s options; `Err` when its input was refused).
fn score_solved(
    scoring: Scoring<'_>,
    first: Result<TrajectoryIkResult, String>,
    motion: &ObjectMotion,
    times: &[f64],
) -> CandidateScore {
    let ScoringSetup {
        arm,
        path,
        rows: mode,
        ranked,
        ik,
        redundancy,
        ..
    } = *scoring.setup;
    let candidate = scoring.candidate;
    let compare_branches = redundancy != Redundancy::First;
    let chain = &arm.chain;
    // The IK plans in the ranges narrowed by the task's limit margin; the distances to the
    // limits and their penalty are measured against the limits themselves.
    let ik_chain = &arm.ik_chain;
    let n = path.samples.len();
    let before = scoring.plan.approach_samples();
    let targets = &scoring.targets;
    let q_start = chain.mid_configuration();
    let mut jacobian = Matrix6xX::zeros(chain.dof());
    let mut score = CandidateScore::unscored(Arc::clone(candidate));
    let located = |failure: Failure| scoring.located(failure);
    let checks = branch_checks(&scoring);
    let mut dynamic = dynamic_workspace(&scoring);
    let ranks_dynamic = ranked.measure == IndexMeasure::Dynamic;
    let order = BranchOrder::of(scoring.setup);
    // One branch tracked first; more are searched only when it fails or collides, or when
    // every branch is to be compared.
    let mut tries = vec![Scoring::first_try(scoring.setup)];
    if !compare_branches && ik.branches > 1 {
        tries.push(ik.clone());
    }
    let mut first = Some(first);
    // The first failure of a branch check (e.g. a collision) in this attempt.
    let mut refusal: Option<Failure> = None;
    // Branches the checks refused, with their failure: the search with more branches finds the
    // first one again, and it need not be checked twice.
    let mut refused: Vec<(Vec<Vec<f64>>, Failure)> = Vec::new();
    let mut best: Option<ChosenBranch> = None;
    let mut last_failure: Option<Failure> = None;
    // The first branch's whole motion and `μ_l2`, for the self-motion search.
    let mut first_branch: Option<(Vec<Vec<f64>>, f64)> = None;
    let counted = counted_samples(path, ranked.over);
    // The grasp's own configuration (see `CandidateScore::yoshikawa_at_grasp`), when the
    // motion starts at the grasp.
    let mut grasp_configuration: Option<Vec<f64>> = None;
    for (attempt, options) in tries.iter().enumerate() {
        let solved = first.take().unwrap_or_else(|| {
            solve_trajectory(ik_chain, targets, &q_start, options).map_err(|e| e.to_string())
        });
        let result = match solved {
            Ok(r) => r,
            Err(message) => {
                score.failure = Some(Failure::new(FailureReason::Unreachable, 0, message));
                return score;
            }
        };
        if attempt == 0 && before == 0 {
            grasp_configuration = result.first_pose.first().cloned();
        }
        score.feasible_branches = result.branches.len();
        for branch in &result.branches {
            let path_q = &branch.q[before..before + n];
            let series = index_along(
                chain,
                motion,
                &candidate.object_from_wrist,
                path_q,
                (mode, ranked),
                &mut jacobian,
                dynamic.as_mut().filter(|_| ranks_dynamic),
            );
            let norms = series.norms(times, &counted);
            if redundancy == Redundancy::Optimize && first_branch.is_none() && attempt == 0 {
                first_branch = Some((branch.q.clone(), norms.l2));
            }
            // By the norm a branch that cannot rank above the kept one is not checked; by
            // duration every branch is, since the checks time it.
            if !order.by_duration
                && best
                    .as_ref()
                    .is_some_and(|b| !b.norms_better(&norms, order.norm))
            {
                continue;
            }
            if let Some((_, failure)) = refused.iter().find(|(q, _)| *q == branch.q) {
                refusal.get_or_insert_with(|| failure.clone());
                continue;
            }
            match check_branch(&checks, &branch.q) {
                Ok(findings) => {
                    let checked = ChosenBranch {
                        series,
                        norms,
                        q: branch.q.clone(),
                        findings,
                    };
                    if best.as_ref().is_none_or(|b| checked.better_than(b, order)) {
                        best = Some(checked);
                    }
                }
                Err(failure) => {
                    refusal.get_or_insert_with(|| failure.clone());
                    refused.push((branch.q.clone(), failure));
                }
            }
        }
        last_failure = result.failure;
        // Another attempt with more branches only helps when the first pose was solved.
        let first_pose_solved = best.is_some()
            || refusal.is_some()
            || last_failure.as_ref().is_some_and(|f| f.sample > 0);
        if best.is_some() || !first_pose_solved || attempt + 1 == tries.len() {
            break;
        }
        refusal = None;
    }
    if let (Redundancy::Optimize, Some(chosen)) = (redundancy, best.as_mut()) {
        let search = SelfMotionSearch {
            setup: scoring.setup,
            candidate,
            motion,
            times,
            counted: &counted,
            targets,
            path: before..before + n,
            checks: &checks,
        };
        score.self_motion = search.improve(
            chosen,
            first_branch.as_ref(),
            dynamic.as_mut().filter(|_| ranks_dynamic),
        );
    }
    let grasp_reached = match best {
        Some(ChosenBranch {
            series,
            norms,
            q,
            findings,
        }) => {
            score.m_t = series.m_t;
            score.ranked_values = series.ranked;
            score.norms = Some(norms);
            score.clearance = findings.clearance;
            score.torque_margin = findings.torque_margin;
            score.payload_capacity = findings.payload_capacity;
            score.dynamic_manipulability = dynamic.as_mut().and_then(|workspace| {
                dynamic_norm(
                    &scoring,
                    workspace,
                    motion,
                    &q[before..before + n],
                    (times, &counted),
                )
            });
            score.durations = findings.durations;
            score.approach = q[..before].to_vec();
            score.retreat = q[before + n..].to_vec();
            score.joint_trajectory = q[before..before + n].to_vec();
            score.limit_distance = score
                .joint_trajectory
                .iter()
                .map(|q| limit_distance(q, chain.lower(), chain.upper()))
                .collect();
            true
        }
        None => {
            // A branch the checks refused was solved along the whole motion.
            let solved_whole = refusal.is_some();
            let failure = refusal.or(last_failure.map(located)).unwrap_or_else(|| {
                Failure::new(FailureReason::Unreachable, 0, "no IK branch was found")
            });
            // The classical indices at the grasp need the grasp pose to have been reached: a
            // failure after it on the path, in the retreat, or a branch refused by a check. An
            // approach that fails is not followed by a separate solve at the grasp (the
            // candidate cannot be executed, and an unreachable pre-grasp usually means an
            // unreachable grasp).
            let grasp_reached = (failure.phase == Phase::Path && failure.sample > 0)
                || failure.phase == Phase::Retreat
                || solved_whole;
            score.failure = Some(failure);
            grasp_reached
        }
    };
    if !grasp_reached {
        return score;
    }
    // With an approach, the motion starts at the pre-grasp: the grasp pose is solved alone,
    // by the same search from the same start.
    let grasp_q = grasp_configuration.or_else(|| {
        let alone = TrajectoryIkOptions {
            branches: 1,
            ..ik.clone()
        };
        solve_trajectory(ik_chain, &targets[before..=before], &q_start, &alone)
            .ok()
            .and_then(|r| r.first_pose.into_iter().next())
    });
    if let Some(q) = grasp_q {
        if chain.pose_and_jacobian_into(&q, &mut jacobian).is_ok() {
            let indices = classical_indices(&jacobian, JacobianPart::Full);
            let w = indices.yoshikawa;
            score.yoshikawa_at_grasp = Some(w);
            score.yoshikawa_penalized_at_grasp = ranked
                .joint_limit_penalty
                .map(|k| w * joint_limit_penalty(&q, chain.lower(), chain.upper(), k));
            score.inverse_condition_at_grasp = Some(indices.inverse_condition);
            score.inverse_condition_squared_at_grasp = Some(indices.inverse_condition_squared);
        }
    }
    score
}
