//! The configuration at which an infeasible candidate first collides, for the 3D view.
//!
//! Scores keep no joint configuration for an infeasible candidate, only the failure: phase,
//! sample within the phase and the two bodies. The report recomputes the motion the scorer
//! checked, with the core's public pieces: the whole motion's tool poses (approach strokes,
//! the object's path, retreat strokes), the trajectory IK with the task's settings from the
//! chain's mid configuration, and the collision check of its first branch — the branch whose
//! collision the scorer records when no branch is free (`select::for_each_score`). A collision
//! of the hand (or of what rides rigidly with it) is found, as the scorer finds it, at the
//! commanded tool poses before any IK, and shown with the arm at that pose's IK solution from
//! the mid configuration (no witness when that pose is out of reach). The witness
//! is kept **only when that check reproduces the recorded failure**: the same phase, the same
//! sample and the same two bodies; otherwise the view shows no witness for the candidate
//! (never a configuration that does not collide as stated).
//!
//! When the collision lies between two samples, the witness is the configuration on the
//! straight joint-space segment between them (64 equal steps) where the two bodies are
//! closest.

use graspath::collision::{
    signed_distance, ArmInScene, Body, ObjectAlong, ToolMotion, WholeMotion,
};
use graspath::failure::{FailureReason, Phase};
use graspath::robot::{solve_ik, solve_trajectory};
use graspath::select::CandidateScore;
use graspath::task::{ArmSetup, Task};
use nalgebra::{Isometry3, IsometryMatrix3};

/// Steps of the search for the closest configuration between two samples.
const BETWEEN_STEPS: usize = 64;

/// A reproduced first collision.
#[derive(Debug, Clone)]
pub(crate) struct Witness {
    /// The phase and the sample within it, as in the failure.
    pub phase: Phase,
    pub sample: usize,
    /// Whether the witness lies between `sample` and the next sample of the whole motion.
    pub between: bool,
    /// The two bodies, as in the failure.
    pub bodies: [String; 2],
    /// The joint configuration (rad / m).
    pub q: Vec<f64>,
    /// Where the object is at the witness, `world_from_object`.
    pub world_from_object: Isometry3<f64>,
    /// The signed distance of the two bodies at the witness (m; negative: penetration).
    pub distance: f64,
}

/// Where the object is at whole-motion sample `i` (or between `i` and `i + 1`) with the arm
/// at `q`: standing at its start before the grasp, carried by the tool from the grasp to the
/// place, left at its end after.
fn object_at(
    task: &Task,
    setup: &ArmSetup,
    object_from_wrist: &Isometry3<f64>,
    i: usize,
    between: bool,
    q: &[f64],
) -> Option<Isometry3<f64>> {
    let a = task.approach().map_or(0, |s| s.samples);
    let n = task.path().samples.len();
    let first = *task.path().poses().next()?;
    let last = *task.path().poses().last()?;
    if i < a {
        Some(first)
    } else if i + 1 < a + n || (i + 1 == a + n && !between) {
        let base_from_tool: Isometry3<f64> = nalgebra::convert(setup.chain.pose(q).ok()?);
        Some(setup.world_from_base * base_from_tool * object_from_wrist.inverse())
    } else {
        Some(last)
    }
}

/// Every body named `name` placed in the world with the arm at `q` and the object at
/// `world_from_object`.
fn placed<'a>(
    task: &'a Task,
    setup: &'a ArmSetup,
    name: &str,
    frames: &[IsometryMatrix3<f64>],
    world_from_object: &Isometry3<f64>,
) -> Vec<(&'a Body, Isometry3<f64>)> {
    let mut out = Vec::new();
    if let Some(bodies) = &setup.bodies {
        let world_from_base: IsometryMatrix3<f64> = nalgebra::convert(setup.world_from_base);
        for (link, link_from_body, body) in bodies.bodies() {
            if body.name() == name {
                out.push((
                    body,
                    nalgebra::convert(world_from_base * frames[link] * link_from_body),
                ));
            }
        }
    }
    if let Some(collisions) = task.collisions() {
        for (body, world_from_body) in collisions.scene.bodies() {
            if body.name() == name {
                out.push((body, *world_from_body));
            }
        }
    }
    if name == "object" {
        if let Some(body) = task.object_body().map(|b| &**b) {
            out.push((body, *world_from_object));
        }
    }
    out
}

/// The smallest signed distance (m) between the bodies named `names` with the arm at `q`, or
/// `None` when a name matches no body or the chain refuses `q`.
pub(crate) fn pair_distance(
    task: &Task,
    setup: &ArmSetup,
    names: &[String; 2],
    q: &[f64],
    world_from_object: &Isometry3<f64>,
) -> Option<f64> {
    let frames = setup.chain.link_frames(q).ok()?;
    let a = placed(task, setup, &names[0], &frames, world_from_object);
    let b = placed(task, setup, &names[1], &frames, world_from_object);
    let mut best: Option<f64> = None;
    for (x, pose_x) in &a {
        for (y, pose_y) in &b {
            let d = signed_distance(x, pose_x, y, pose_y);
            best = Some(best.map_or(d, |b: f64| b.min(d)));
        }
    }
    best
}

/// The first collision of an infeasible candidate, reproduced (see the module documentation),
/// or `None` when the candidate did not fail by a collision or the reproduction differs.
pub(crate) fn first_collision(
    task: &Task,
    setup: &ArmSetup,
    score: &CandidateScore,
) -> Option<Witness> {
    let failure = score.failure.as_ref()?;
    if failure.reason != FailureReason::Collision {
        return None;
    }
    let expected = failure.bodies.as_ref()?;
    let collisions = task.collisions()?;
    let bodies = setup.bodies.as_deref()?;
    let object_from_wrist = &score.candidate.object_from_wrist;
    let base_from_world = setup.world_from_base.inverse();
    let targets: Vec<Isometry3<f64>> = task
        .motion_plan()
        .tool_poses(object_from_wrist)
        .iter()
        .map(|p| base_from_world * p)
        .collect();
    let q_start = setup.chain.mid_configuration();
    let a = task.approach().map_or(0, |s| s.samples);
    let n = task.path().samples.len();
    let first = *task.path().poses().next()?;
    let last = *task.path().poses().last()?;
    let object = ObjectAlong {
        path: a..a + n,
        world_from_object_start: &first,
        world_from_object_end: &last,
        object_from_wrist,
    };
    let checker = ArmInScene {
        arm: bodies,
        world_from_base: &setup.world_from_base,
        scene: &collisions.scene,
        object: task.object_body().map(|b| &**b),
        options: &collisions.options,
    };
    // The hand and what rides with it are checked at the commanded tool poses first; a hit
    // there is shown with the arm at that pose's IK solution.
    let tool_hit = checker.check_tool_poses(&ToolMotion {
        base_from_tool: &targets,
        object: object.clone(),
    });
    // The configuration at the hit's sample and, for a hit between samples, at the next one.
    let (hit, at_hit, after_hit) = match tool_hit {
        Some(hit) => {
            let q = solve_ik(
                &setup.ik_chain,
                &targets[hit.sample],
                &q_start,
                &task.ik().ik,
            )
            .ok()?
            .q?;
            (hit, q, None)
        }
        None => {
            let result = solve_trajectory(&setup.ik_chain, &targets, &q_start, task.ik()).ok()?;
            let branch = result.branches.into_iter().next()?;
            let hit = checker
                .check(&WholeMotion {
                    q: &branch.q,
                    object,
                })
                .hit?;
            let at_hit = branch.q.get(hit.sample)?.clone();
            let after_hit = branch.q.get(hit.sample + 1).cloned();
            (hit, at_hit, after_hit)
        }
    };
    let (phase, sample) = task.motion_plan().phase_of(hit.sample);
    if (phase, sample) != (failure.phase, failure.sample) || hit.bodies != *expected {
        return None;
    }
    let at = |q: &[f64]| -> Option<(Isometry3<f64>, f64)> {
        let object = object_at(task, setup, object_from_wrist, hit.sample, hit.between, q)?;
        let d = pair_distance(task, setup, expected, q, &object)?;
        Some((object, d))
    };
    let (q, (world_from_object, distance)) = if hit.between {
        let (qa, qb) = (&at_hit, after_hit.as_ref()?);
        (1..BETWEEN_STEPS)
            .filter_map(|k| {
                let t = k as f64 / BETWEEN_STEPS as f64;
                let q: Vec<f64> = qa.iter().zip(qb).map(|(x, y)| x + t * (y - x)).collect();
                at(&q).map(|found| (q, found))
            })
            .min_by(|x, y| x.1 .1.total_cmp(&y.1 .1))?
    } else {
        let found = at(&at_hit)?;
        (at_hit, found)
    };
    Some(Witness {
        phase,
        sample,
        between: hit.between,
        bodies: expected.clone(),
        q,
        world_from_object,
        distance,
    })
}
