//! Scoring candidates along a task (paper eq. 8–17): each candidate's wrist trajectory, its
//! trajectory IK, `M_T` at every sample, the norms over the path, and the classical indices at
//! the grasp for comparison.

use crate::collision::{
    signed_distance, ArmInScene, Body, CollisionHit, CollisionOptions, ObjectAlong, ToolMotion,
    WholeMotion,
};
pub use crate::failure::Failure;
use crate::failure::{FailureReason, Phase};
use crate::geometry::se3_log;
use crate::grasp::Candidate;
use crate::manipulability::{
    classical_indices, joint_limit_penalty, limit_distance, Direction, JacobianPart, PathNorms,
    SampleIndex,
};
use crate::robot::{
    optimize_self_motion, solve_trajectories, solve_trajectory, Chain, KeptRows, SelfMotionOptions,
    TrajectoryIkOptions, TrajectoryIkResult,
};
use crate::task::{
    defaults, ArmSetup, Collisions, Gripper, JacobianRows, NormSamples, ObjectPath, RankedIndex,
    Redundancy, Stroke, WholeMotionPlan,
};
use nalgebra::{Isometry3, Matrix6xX, Rotation3, Vector3, Vector6};
use rayon::prelude::*;
use std::sync::Arc;

/// How many candidates are scored in parallel before their results are handed on in order.
pub const STREAM_CHUNK: usize = 256;

/// How many candidates share one batch of first IK solves (their branches tracked four at a
/// time in vector lanes, see [`solve_trajectories`]).
const SOLVE_GROUP: usize = 16;

/// A candidate's scores for one arm.
#[derive(Debug, Clone, PartialEq)]
pub struct CandidateScore {
    /// The candidate scored (shared with the task).
    pub candidate: Arc<Candidate>,
    /// Set when the arm cannot follow the whole path from this grasp.
    pub failure: Option<Failure>,
    /// `M_T` at each sample (`None` where the object is still), along the chosen IK branch.
    pub m_t: Vec<Option<f64>>,
    /// The ranked index at each sample when it is not `M_T` itself (`index.measure:
    /// velocity_ratio` or a joint-limit penalty; `None` otherwise).
    pub ranked_values: Option<Vec<Option<f64>>>,
    /// The norms of the ranked index, `ranked_values` or else `m_t` (when feasible).
    pub norms: Option<PathNorms>,
    /// Yoshikawa's index of the full `J` at the grasp (when the grasp is reachable), at the
    /// grasp's own configuration: the grasp pose's IK from the arm's mid configuration (the
    /// first solution of the trajectory solver's search there), whatever branch or
    /// self-motion the task then follows — so the classical indices depend on the grasp pose
    /// only, never on the task.
    pub yoshikawa_at_grasp: Option<f64>,
    /// Yoshikawa's index at the grasp times the joint-limit penalty there (with
    /// `index.joint_limit_penalty`).
    pub yoshikawa_penalized_at_grasp: Option<f64>,
    /// `σmin/σmax` of `J` at the grasp configuration.
    pub inverse_condition_at_grasp: Option<f64>,
    /// `λmin/λmax` of `J Jᵀ` at the grasp configuration (the paper's eq. 12).
    pub inverse_condition_squared_at_grasp: Option<f64>,
    /// Per path sample, how far the joint nearest to a limit is from it (rad or m; `+∞`
    /// without limited joints), along the chosen motion (when feasible).
    pub limit_distance: Vec<f64>,
    /// Joint configurations along the path (rad / m), one per sample, of the chosen branch.
    pub joint_trajectory: Vec<Vec<f64>>,
    /// Joint configurations of the approach, before the grasp (empty without an approach).
    pub approach: Vec<Vec<f64>>,
    /// Joint configurations of the retreat, after the place (empty without a retreat).
    pub retreat: Vec<Vec<f64>>,
    /// The smallest distance between the robot (hand and carried object included) and the
    /// scene at any sample of the motion (m), when the task has a scene.
    pub clearance: Option<f64>,
    /// How many distinct feasible IK branches were found.
    pub feasible_branches: usize,
    /// With `ik.redundancy: optimize`: what the self-motion search found (for a feasible
    /// candidate whose first branch is feasible).
    pub self_motion: Option<SelfMotionScores>,
}

/// How much of a candidate's `μ_l2` is the grasp and how much the arm's self-motion.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SelfMotionScores {
    /// `μ_l2` along the first IK branch (the paper's practice).
    pub first_branch_l2: f64,
    /// The smallest and the largest `μ_l2` of any joint path found in the self-motion
    /// (collision checks aside); the candidate's score uses the largest collision-free one.
    pub l2_range: (f64, f64),
}

impl CandidateScore {
    /// A candidate not scored yet: no failure, no values, no trajectory.
    pub fn unscored(candidate: Arc<Candidate>) -> Self {
        Self {
            candidate,
            failure: None,
            m_t: Vec::new(),
            ranked_values: None,
            norms: None,
            yoshikawa_at_grasp: None,
            yoshikawa_penalized_at_grasp: None,
            inverse_condition_at_grasp: None,
            inverse_condition_squared_at_grasp: None,
            limit_distance: Vec::new(),
            joint_trajectory: Vec::new(),
            approach: Vec::new(),
            retreat: Vec::new(),
            clearance: None,
            feasible_branches: 0,
            self_motion: None,
        }
    }

    /// Whether IK succeeded along the whole path.
    pub fn feasible(&self) -> bool {
        self.failure.is_none()
    }

    /// Whether the chosen motion hugs a joint limit: at least
    /// [`defaults::LIMIT_HUG_SHARE`] of the path samples have a joint within
    /// [`defaults::LIMIT_HUG_DISTANCE`] of a limit.
    pub fn hugs_limit(&self) -> bool {
        let near = self
            .limit_distance
            .iter()
            .filter(|d| **d <= defaults::LIMIT_HUG_DISTANCE)
            .count();
        !self.limit_distance.is_empty()
            && near as f64 >= defaults::LIMIT_HUG_SHARE * self.limit_distance.len() as f64
    }
}

/// The object's body twists between consecutive samples, `log(O_i⁻¹ O_{i+1})`, shared by every
/// candidate: a wrist rigidly attached at `object_from_wrist = (R, p)` moves with the twist
/// `Ad_{W⁻¹} ξ`, so its base-frame tangent is `R_base_object · (v + ω × p, ω)`.
struct ObjectMotion {
    /// Per sample: the object's body twist of the interval that defines its tangent.
    twists: Vec<Vector6<f64>>,
    /// Per sample: `base_from_object` rotation.
    rotations: Vec<Rotation3<f64>>,
}

impl ObjectMotion {
    fn new(path: &ObjectPath, base_from_world: &Isometry3<f64>) -> Self {
        let poses: Vec<Isometry3<f64>> = path.poses().copied().collect();
        let n = poses.len();
        let twists = (0..n)
            .map(|i| {
                // Forward difference; the last sample takes the backward difference.
                let (a, b) = if i + 1 < n {
                    (i, i + 1)
                } else {
                    (i.saturating_sub(1), i)
                };
                if a == b {
                    Vector6::zeros()
                } else {
                    se3_log(&(poses[a].inverse() * poses[b]))
                }
            })
            .collect();
        let rotations = poses
            .iter()
            .map(|p| (base_from_world * p).rotation.to_rotation_matrix())
            .collect();
        Self { twists, rotations }
    }

    /// The unit tangent direction at sample `i` for a wrist at `object_from_wrist`.
    fn tangent(
        &self,
        i: usize,
        object_from_wrist: &Isometry3<f64>,
        mode: JacobianRows,
    ) -> Option<Direction> {
        let xi = &self.twists[i];
        let v = Vector3::new(xi[0], xi[1], xi[2]);
        let w = Vector3::new(xi[3], xi[4], xi[5]);
        let p = object_from_wrist.translation.vector;
        let r = &self.rotations[i];
        let linear = r * (v + w.cross(&p));
        let angular = r * w;
        mode.direction(&linear, &angular)
    }
}

/// The wrist poses `base_from_wrist` along the path for one candidate and arm.
pub fn wrist_trajectory(
    path: &ObjectPath,
    world_from_base: &Isometry3<f64>,
    object_from_wrist: &Isometry3<f64>,
) -> Vec<Isometry3<f64>> {
    let base_from_world = world_from_base.inverse();
    path.poses()
        .map(|world_from_object| base_from_world * world_from_object * object_from_wrist)
        .collect()
}

/// The per-sample indices along one joint path (`None` where the object is still).
#[derive(Debug, Clone, PartialEq)]
struct IndexSeries {
    /// `M_T` (eq. 13).
    m_t: Vec<Option<f64>>,
    /// The ranked index, when it is not `M_T` itself.
    ranked: Option<Vec<Option<f64>>>,
}

impl IndexSeries {
    /// The values the norms are taken of.
    fn ranked(&self) -> &[Option<f64>] {
        self.ranked.as_deref().unwrap_or(&self.m_t)
    }

    /// The norms of the ranked values at the path samples marked in `counted` (`times`: the
    /// samples' times, s).
    fn norms(&self, times: &[f64], counted: &[bool]) -> PathNorms {
        let samples: Vec<SampleIndex> = self
            .ranked()
            .iter()
            .zip(times)
            .zip(counted)
            .filter(|(_, counted)| **counted)
            .map(|((&value, &time), _)| SampleIndex { time, value })
            .collect();
        PathNorms::of(&samples)
    }
}

/// Which path samples the norms are taken over ([`NormSamples`]): all of them, or the
/// initial pose and the last sample of each step.
fn counted_samples(path: &ObjectPath, over: NormSamples) -> Vec<bool> {
    let samples = &path.samples;
    (0..samples.len())
        .map(|i| match over {
            NormSamples::All => true,
            NormSamples::Waypoints => {
                i == 0 || i + 1 == samples.len() || samples[i + 1].step != samples[i].step
            }
        })
        .collect()
}

/// `M_T` and the ranked index at every sample along one joint path.
fn index_along(
    chain: &Chain,
    motion: &ObjectMotion,
    object_from_wrist: &Isometry3<f64>,
    joints: &[Vec<f64>],
    (mode, ranked): (JacobianRows, RankedIndex),
    jacobian: &mut Matrix6xX<f64>,
) -> IndexSeries {
    let mut m_t = Vec::with_capacity(joints.len());
    let mut values = Vec::with_capacity(joints.len());
    for (i, q) in joints.iter().enumerate() {
        let at = motion
            .tangent(i, object_from_wrist, mode)
            .filter(|_| chain.pose_and_jacobian_into(q, jacobian).is_ok());
        m_t.push(at.map(|d| mode.task_relevant(jacobian, &d)));
        if !ranked.is_task_relevant() {
            values.push(
                at.map(|d| ranked.value(mode, jacobian, &d, [q, chain.lower(), chain.upper()])),
            );
        }
    }
    IndexSeries {
        m_t,
        ranked: (!ranked.is_task_relevant()).then_some(values),
    }
}

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
    /// How the arm's self-motion is chosen (first branch, best branch, or optimised).
    pub redundancy: Redundancy,
    /// The tool's approach to the grasp and retreat after the place, the gripper, and the
    /// collision checks (all `None`: the motion is the object's path in empty space).
    pub world: WorldSetup<'a>,
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

/// Scores every candidate for one arm and hands each result to `consume` as soon as its chunk
/// of [`STREAM_CHUNK`] candidates is done, in candidate order, so a consumer can write results
/// out without holding them all. A chunk's candidates are scored in parallel (rayon), in
/// groups whose first IK solves are batched (at most [`SOLVE_GROUP`] candidates, fewer when
/// there are many threads); the results depend neither on the thread count nor on the
/// grouping. `progress` is called once per candidate, as its group finishes.
///
/// In a scene, the hand and what rides rigidly with it (the links after the last moving
/// joint, the carried object) are first checked at the commanded tool poses: a grasp whose
/// hand collides is refused without solving the arm (`ArmInScene::check_tool_poses`).
/// IK tracks one branch from the first pose of the motion; only when it fails (or collides)
/// are up to `ik.branches` distinct initial solutions searched and tracked. With
/// [`Redundancy::BestBranch`], every branch is tracked and the one with the best norm is kept
/// (slower, and the ranking then reflects the best redundancy resolution rather than the first
/// one found); with [`Redundancy::Optimize`], the self-motion around the branches is then
/// searched for the whole motion whose `μ_l2` is largest ([`optimize_self_motion`]), which is
/// kept when it is collision-free (else the best branch).
pub fn for_each_score(
    setup: &ScoringSetup<'_>,
    candidates: &[Arc<Candidate>],
    progress: &(dyn Fn() + Sync),
    mut consume: impl FnMut(CandidateScore),
) {
    let base_from_world = setup.arm.world_from_base.inverse();
    let motion = ObjectMotion::new(setup.path, &base_from_world);
    let times = setup.path.times();
    let fingers = FingerCheck::new(&setup.world);
    // Groups small enough to give every thread several.
    let group = (STREAM_CHUNK / (4 * rayon::current_num_threads())).clamp(1, SOLVE_GROUP);
    for chunk in candidates.chunks(STREAM_CHUNK) {
        let scores: Vec<Vec<CandidateScore>> = chunk
            .par_chunks(group)
            .map(|group| {
                let scores = score_group(setup, group, &motion, &times, fingers.as_ref());
                scores.iter().for_each(|_| progress());
                scores
            })
            .collect();
        scores.into_iter().flatten().for_each(&mut consume);
    }
}

/// Scores every candidate for one arm (see [`for_each_score`]), in candidate order.
pub fn score_candidates(
    setup: &ScoringSetup<'_>,
    candidates: &[Arc<Candidate>],
    progress: &(dyn Fn() + Sync),
) -> Vec<CandidateScore> {
    let mut scores = Vec::with_capacity(candidates.len());
    for_each_score(setup, candidates, progress, |s| scores.push(s));
    scores
}

/// The gripper-width check of a task: a width given by the candidate's file must fit the
/// opening, and the open fingers at the grasp must not press into the object (when its shape
/// is known). Built once per arm; the finger bodies are shared by every candidate.
struct FingerCheck<'a> {
    /// `(name, wrist_from_finger, body)` of each finger, open at the gripper's opening.
    fingers: Vec<(String, Isometry3<f64>, Body)>,
    opening: f64,
    tolerance: f64,
    object: Option<&'a Body>,
}

impl<'a> FingerCheck<'a> {
    fn new(world: &WorldSetup<'a>) -> Option<Self> {
        let (gripper, object) = (world.gripper?, world.object);
        Some(Self {
            fingers: gripper
                .finger_shapes()
                .into_iter()
                .map(|(name, wrist_from_finger, shape)| {
                    let body = Body::from_shape(format!("hand {name}"), &shape);
                    (name, wrist_from_finger, body)
                })
                .collect(),
            opening: gripper.opening,
            tolerance: world
                .collisions
                .map_or(CollisionOptions::default().touch_tolerance, |c| {
                    c.options.touch_tolerance
                }),
            object,
        })
    }

    fn failure(&self, candidate: &Candidate) -> Option<Failure> {
        if let Some(width) = candidate
            .width
            .filter(|w| *w > self.opening + self.tolerance)
        {
            return Some(Failure {
                reason: FailureReason::GripperWidth,
                phase: Phase::Path,
                sample: 0,
                detail: format!(
                    "the grasp's width from its file, {width:.4} m, is more than the {:.3} m \
                     opening",
                    self.opening
                ),
                bodies: None,
            });
        }
        let object = self.object?;
        for (name, wrist_from_finger, finger) in &self.fingers {
            let object_from_finger = candidate.object_from_wrist * wrist_from_finger;
            let depth =
                signed_distance(finger, &object_from_finger, object, &Isometry3::identity());
            if depth < -self.tolerance {
                return Some(Failure {
                    reason: FailureReason::GripperWidth,
                    phase: Phase::Path,
                    sample: 0,
                    detail: format!(
                        "the object is wider across the fingers than the {:.3} m opening: the \
                         {name} would press {:.4} m into it",
                        self.opening, -depth
                    ),
                    bodies: Some([format!("hand {name}"), "object".into()]),
                });
            }
        }
        None
    }
}

/// A candidate on its way through scoring: its motion's tool poses and what checks them.
struct Scoring<'s> {
    setup: &'s ScoringSetup<'s>,
    candidate: &'s Arc<Candidate>,
    plan: WholeMotionPlan<'s>,
    /// The tool poses of the whole motion (approach, path, retreat), chain base frame.
    targets: Vec<Isometry3<f64>>,
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

    /// What fails whatever the arm does, found before any IK: the gripper's width, and the
    /// hand and what rides with it colliding at the tool poses.
    fn fails_before_ik(&self, fingers: Option<&FingerCheck<'_>>) -> Option<Failure> {
        if let Some(failure) = fingers.and_then(|f| f.failure(self.candidate)) {
            return Some(failure);
        }
        let hit = self.checker.as_ref()?.check_tool_poses(&ToolMotion {
            base_from_tool: &self.targets,
            object: self.object_along(),
        })?;
        Some(self.located(collision_failure(&hit)))
    }
}

/// Scores the candidates of `group` (see [`for_each_score`]), in order. The first IK solve of
/// every candidate that gets that far is done in one batch ([`solve_trajectories`]).
fn score_group(
    setup: &ScoringSetup<'_>,
    group: &[Arc<Candidate>],
    motion: &ObjectMotion,
    times: &[f64],
    fingers: Option<&FingerCheck<'_>>,
) -> Vec<CandidateScore> {
    let chain = &setup.arm.chain;
    let scorings: Vec<Scoring<'_>> = group.iter().map(|c| Scoring::new(setup, c)).collect();
    let early: Vec<Option<Failure>> = scorings
        .iter()
        .map(|s| s.fails_before_ik(fingers))
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
    let n = path.samples.len();
    let before = scoring.plan.approach_samples();
    let targets = &scoring.targets;
    let q_start = chain.mid_configuration();
    let mut jacobian = Matrix6xX::zeros(chain.dof());
    let mut score = CandidateScore::unscored(Arc::clone(candidate));
    let located = |failure: Failure| scoring.located(failure);
    let checker = scoring.checker.as_ref();
    let object_along = scoring.object_along();
    // One branch tracked first; more are searched only when it fails or collides, or when
    // every branch is to be compared.
    let mut tries = vec![Scoring::first_try(scoring.setup)];
    if !compare_branches && ik.branches > 1 {
        tries.push(ik.clone());
    }
    let mut first = Some(first);
    let mut collision: Option<Failure> = None;
    // Branches found colliding, with their failure: the search with more branches finds the
    // first one again, and it need not be checked twice.
    let mut collided: Vec<(Vec<Vec<f64>>, Failure)> = Vec::new();
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
            solve_trajectory(chain, targets, &q_start, options).map_err(|e| e.to_string())
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
            );
            let norms = series.norms(times, &counted);
            if redundancy == Redundancy::Optimize && first_branch.is_none() && attempt == 0 {
                first_branch = Some((branch.q.clone(), norms.l2));
            }
            let better = match &best {
                None => true,
                Some((_, b, _, _)) => {
                    (norms.linf.is_finite(), norms.l2) > (b.linf.is_finite(), b.l2)
                }
            };
            if !better {
                continue;
            }
            if let Some((_, failure)) = collided.iter().find(|(q, _)| *q == branch.q) {
                if collision.is_none() {
                    collision = Some(failure.clone());
                }
                continue;
            }
            let clearance = match &checker {
                None => None,
                Some(checker) => {
                    let check = checker.check(&WholeMotion {
                        q: &branch.q,
                        object: object_along.clone(),
                    });
                    if let Some(hit) = check.hit {
                        let failure = located(collision_failure(&hit));
                        if collision.is_none() {
                            collision = Some(failure.clone());
                        }
                        collided.push((branch.q.clone(), failure));
                        continue;
                    }
                    check.clearance
                }
            };
            best = Some((series, norms, branch.q.clone(), clearance));
        }
        last_failure = result.failure;
        // Another attempt with more branches only helps when the first pose was solved.
        let first_pose_solved = best.is_some()
            || collision.is_some()
            || last_failure.as_ref().is_some_and(|f| f.sample > 0);
        if best.is_some() || !first_pose_solved || attempt + 1 == tries.len() {
            break;
        }
        collision = None;
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
            checker,
            object_along: &object_along,
        };
        score.self_motion = search.improve(chosen, first_branch.as_ref());
    }
    let grasp_reached = match best {
        Some((series, norms, q, clearance)) => {
            score.m_t = series.m_t;
            score.ranked_values = series.ranked;
            score.norms = Some(norms);
            score.clearance = clearance;
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
            let failure = collision.or(last_failure.map(located)).unwrap_or_else(|| {
                Failure::new(FailureReason::Unreachable, 0, "no IK branch was found")
            });
            // The classical indices at the grasp need the grasp pose to have been reached: a
            // failure after it on the path, in the retreat, or a collision. An approach that
            // fails is not followed by a separate solve at the grasp (the candidate cannot be
            // executed, and an unreachable pre-grasp usually means an unreachable grasp).
            let grasp_reached = (failure.phase == Phase::Path && failure.sample > 0)
                || failure.phase == Phase::Retreat
                || failure.reason == FailureReason::Collision;
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
        solve_trajectory(chain, &targets[before..=before], &q_start, &alone)
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

/// The branch kept so far: `M_T` per path sample, its norms, the whole motion's joints and
/// its clearance.
type ChosenBranch = (IndexSeries, PathNorms, Vec<Vec<f64>>, Option<f64>);

/// The self-motion search of one candidate ([`Redundancy::Optimize`]).
struct SelfMotionSearch<'a> {
    setup: &'a ScoringSetup<'a>,
    candidate: &'a Candidate,
    motion: &'a ObjectMotion,
    times: &'a [f64],
    /// Which path samples the norms count.
    counted: &'a [bool],
    /// The whole motion's tool poses, chain base frame.
    targets: &'a [Isometry3<f64>],
    /// The object's path within the whole motion.
    path: std::ops::Range<usize>,
    checker: Option<&'a ArmInScene<'a>>,
    object_along: &'a ObjectAlong<'a>,
}

impl SelfMotionSearch<'_> {
    /// Searches the self-motion around the chosen branch and the first branch for the whole
    /// motion with the largest `Σ v²` of the ranked index `v` on the path; replaces `chosen` when that motion is
    /// better and collision-free. Returns what was found.
    fn improve(
        &self,
        chosen: &mut ChosenBranch,
        first_branch: Option<&(Vec<Vec<f64>>, f64)>,
    ) -> Option<SelfMotionScores> {
        let ScoringSetup {
            arm,
            rows: mode,
            ranked,
            ik,
            ..
        } = *self.setup;
        let chain = &arm.chain;
        let mut seeds: Vec<&[Vec<f64>]> = vec![&chosen.2];
        if let Some((q, _)) = first_branch.filter(|(q, _)| *q != chosen.2) {
            seeds.push(q);
        }
        let path = self.path.clone();
        let value = |i: usize, q: &[f64], jacobian: &Matrix6xX<f64>| -> f64 {
            if !path.contains(&i) {
                return 0.0;
            }
            self.motion
                .tangent(i - path.start, &self.candidate.object_from_wrist, mode)
                .map_or(0.0, |d| {
                    ranked
                        .value(mode, jacobian, &d, [q, chain.lower(), chain.upper()])
                        .powi(2)
                })
        };
        let options = SelfMotionOptions {
            max_joint_step: ik.max_joint_step,
            position_tolerance: ik.ik.position_tolerance,
            rotation_tolerance: ik.ik.rotation_tolerance,
            ..SelfMotionOptions::default()
        };
        let found = optimize_self_motion(
            chain,
            self.targets,
            &seeds,
            KeptRows::Pose,
            &value,
            &options,
        )?;
        let mut jacobian = Matrix6xX::zeros(chain.dof());
        let series = index_along(
            chain,
            self.motion,
            &self.candidate.object_from_wrist,
            &found.q[self.path.clone()],
            (mode, ranked),
            &mut jacobian,
        );
        let norms = series.norms(self.times, self.counted);
        let scores = SelfMotionScores {
            first_branch_l2: first_branch.map_or(chosen.1.l2, |(_, l2)| *l2),
            l2_range: (found.worst_total.sqrt(), found.total.sqrt()),
        };
        if (norms.linf.is_finite(), norms.l2) <= (chosen.1.linf.is_finite(), chosen.1.l2) {
            return Some(scores);
        }
        let clearance = match self.checker {
            None => None,
            Some(checker) => {
                let check = checker.check(&WholeMotion {
                    q: &found.q,
                    object: self.object_along.clone(),
                });
                if check.hit.is_some() {
                    return Some(scores);
                }
                check.clearance
            }
        };
        *chosen = (series, norms, found.q, clearance);
        Some(scores)
    }
}

/// A collision hit as a failure (whole-motion sample; the caller locates its phase).
fn collision_failure(hit: &CollisionHit) -> Failure {
    let [a, b] = &hit.bodies;
    let at = if hit.between {
        format!("between samples {} and {}", hit.sample, hit.sample + 1)
    } else {
        format!("at sample {}", hit.sample)
    };
    Failure {
        reason: FailureReason::Collision,
        phase: Phase::Path,
        sample: hit.sample,
        detail: format!(
            "{a} and {b} are {:.4} m apart {at} of the motion; they must keep {:.4} m",
            hit.distance, hit.required
        ),
        bodies: Some(hit.bodies.clone()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::manipulability::wrist_tangent;
    use crate::task::{Sampling, Step, TimedStep};
    use nalgebra::{Translation3, UnitQuaternion};

    #[test]
    fn shared_object_twists_give_the_wrist_tangent_by_definition() {
        // Oracle: `wrist_tangent` on the explicit wrist poses (log of wrist_i⁻¹ wrist_{i+1}).
        let steps = vec![
            TimedStep {
                label: "lift+rotate".into(),
                step: Step::Relative {
                    translation: Vector3::new(0.0, 0.1, 0.2),
                    axis: nalgebra::Unit::new_normalize(Vector3::new(0.2, 0.3, 1.0)),
                    angle: 1.2,
                },
                duration: 1.0,
            },
            TimedStep {
                label: "move".into(),
                step: Step::Relative {
                    translation: Vector3::new(0.0, 0.3, 0.0),
                    axis: Vector3::z_axis(),
                    angle: 0.0,
                },
                duration: 1.0,
            },
        ];
        let start = Isometry3::from_parts(
            Translation3::new(0.7, 0.2, -0.05),
            UnitQuaternion::from_euler_angles(0.1, -0.2, 0.7),
        );
        let path = ObjectPath::sample(start, &steps, Sampling::PerStep(5), 1000).unwrap();
        let world_from_base = Isometry3::from_parts(
            Translation3::new(0.1, -0.3, 0.9),
            UnitQuaternion::from_euler_angles(0.0, 0.1, -0.4),
        );
        let object_from_wrist = Isometry3::from_parts(
            Translation3::new(0.03, -0.08, 0.05),
            UnitQuaternion::from_euler_angles(3.0, 0.2, 1.0),
        );
        let motion = ObjectMotion::new(&path, &world_from_base.inverse());
        let wrists = wrist_trajectory(&path, &world_from_base, &object_from_wrist);
        for mode in [
            JacobianRows::Twist { length_scale: 0.3 },
            JacobianRows::Translation,
            JacobianRows::Rotation,
        ] {
            for i in 0..wrists.len() {
                let (a, b) = if i + 1 < wrists.len() {
                    (i, i + 1)
                } else {
                    (i - 1, i)
                };
                let expected = wrist_tangent(&wrists[a], &wrists[b], mode).map(|d| d.as_full());
                let got = motion
                    .tangent(i, &object_from_wrist, mode)
                    .map(|d| d.as_full());
                match (expected, got) {
                    (Some(e), Some(g)) => {
                        assert!((e - g).norm() < 1e-9, "{mode:?} sample {i}: {e} vs {g}");
                    }
                    (None, None) => assert!(
                        matches!(mode, JacobianRows::Rotation),
                        "only a rotation-free interval is still"
                    ),
                    other => panic!("{mode:?} sample {i}: only one side is still: {other:?}"),
                }
            }
        }
    }
}
