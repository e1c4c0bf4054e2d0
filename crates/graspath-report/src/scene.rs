//! The data of the report's 3D view, as JSON: the object's shape and its poses along the path,
//! every candidate's wrist pose, and per arm and candidate the arm's links along its IK solution
//! with the manipulability ellipsoid and the path tangent at each sample.
//!
//! Frames: everything the viewer draws is in the task's **world frame** (m); arm chains are
//! computed in their base frames and mapped with `ArmSetup::world_from_base`. Candidate wrist
//! poses stay in the **object frame** (`object_from_wrist`), so the viewer attaches them to the
//! object. Poses are `[x, y, z, qx, qy, qz, qw]`. Coordinates are rounded to 0.1 mm.
//!
//! A task that describes its world (a scene, an approach or retreat, or a gripper) adds:
//! `world` (the scene's bodies in the world frame, the approach and retreat sample counts, the
//! margin); per arm `bodies` (its collision bodies on their links, see `world`) and
//! `rest_frames`; per motion `approach` and `retreat` (joint origins and, for the first
//! [`MAX_BODY_MOTIONS_PER_ARM`], link frames `world_from_link`) and the path's `frames`; per
//! result its `clearance` and `collision`, the reproduced first collision of an infeasible
//! candidate (see `witness`). A task that says nothing about its world gets exactly the data
//! it had before.
//!
//! A task that times motions (`timing`, on by default) adds per result its `duration` (s, the
//! records' `duration`; `null` when not timed), per motion `sample_times` (s from the start of
//! the approach: when the candidate's time-optimal motion reaches each whole-motion sample —
//! approach, path, retreat — so that the viewer plays it in real time) and
//! `pair_sample_times` (the best pair's two motions on their shared timeline). A task without
//! timing gets none of these keys.

use crate::witness::{first_collision, Witness};
use crate::world::{
    arm_bodies_json, body_links, has_world, joint_origins, link_frames, point, pose, round, round6,
    scene_bodies,
};
use graspath::failure::Phase;
use graspath::geometry::shape::{Shape, Stem};
use graspath::grasp::Candidate;
use graspath::robot::Chain;
use graspath::select::{scoring_setup, timed_together, ArmResult, CandidateScore, Selection};
use graspath::spelling::Spelled;
use graspath::task::{ArmSetup, Task};
use nalgebra::{Isometry3, Matrix3, Point3, SymmetricEigen, Vector3};
use serde_json::{json, Map, Value};
use std::sync::Arc;

/// At most this many candidates per arm carry their arm motion (best ranked first, then the
/// other feasible ones in candidate order), which bounds the report's size on large sets.
pub const MAX_MOTIONS_PER_ARM: usize = 400;

/// In a task with a world, at most this many of the candidates with a motion (in the same
/// order) also carry the link frames that move the arm's collision bodies.
pub const MAX_BODY_MOTIONS_PER_ARM: usize = 100;

/// At most this many infeasible candidates per arm (in candidate order) carry the witness of
/// their first collision (each is recomputed: see `witness`).
pub const MAX_WITNESSES_PER_ARM: usize = 100;

fn vector(v: &Vector3<f64>) -> Value {
    json!([round(v.x), round(v.y), round(v.z)])
}

/// The object for the 3D view: a box, a cylinder or a T-shape with a round stem as they are;
/// any other shape as its bounding box.
fn shape_json(shape: &Shape) -> Value {
    match shape {
        Shape::Box(b) => json!({"type": "box", "size": b.size()}),
        Shape::Cylinder(c) => {
            json!({"type": "cylinder", "radius": c.radius(), "length": c.length()})
        }
        Shape::TShape(t) => match t.stem() {
            Stem::Cylinder(stem) => json!({
                "type": "t_shape",
                "bar": t.bar().size(),
                "handle_radius": stem.radius(),
                "handle_length": stem.length(),
            }),
            Stem::Box(_) => bounding_box_json(shape),
        },
        other => bounding_box_json(other),
    }
}

fn bounding_box_json(shape: &Shape) -> Value {
    let aabb = shape.aabb();
    json!({"type": "box", "size": (aabb.max - aabb.min).as_slice()})
}

/// The principal axes of the translational manipulability ellipsoid `Jv Jvᵀ` (base frame),
/// longest first, each an eigenvector scaled by the square root of its eigenvalue (m/rad).
pub(crate) fn ellipsoid_axes(jv_jvt: &Matrix3<f64>) -> [Vector3<f64>; 3] {
    let eigen = SymmetricEigen::new(*jv_jvt);
    let mut order = [0usize, 1, 2];
    order.sort_by(|&a, &b| {
        eigen.eigenvalues[b]
            .total_cmp(&eigen.eigenvalues[a])
            .then(a.cmp(&b))
    });
    order.map(|k| eigen.eigenvectors.column(k) * eigen.eigenvalues[k].max(0.0).sqrt())
}

/// The arm along one joint trajectory: links (world), ellipsoid (world) and `None` where a
/// configuration is rejected by the chain.
fn motion(
    chain: &Chain,
    world_from_base: &Isometry3<f64>,
    joints: &[Vec<f64>],
) -> Option<(Vec<Value>, Vec<Value>)> {
    let mut links = Vec::with_capacity(joints.len());
    let mut ellipsoids = Vec::with_capacity(joints.len());
    for q in joints {
        let origins = chain.joint_origins(q).ok()?;
        links.push(Value::Array(
            origins
                .iter()
                .map(|p| point(&(world_from_base * p)))
                .collect(),
        ));
        let (base_from_tip, jacobian) = chain.pose_and_jacobian(q).ok()?;
        let jv = jacobian.fixed_rows::<3>(0);
        let axes = ellipsoid_axes(&(jv * jv.transpose()));
        let centre = world_from_base * Point3::from(base_from_tip.translation.vector);
        let mut e = vec![round(centre.x), round(centre.y), round(centre.z)];
        for a in axes {
            let w = world_from_base.rotation * a;
            e.extend([round(w.x), round(w.y), round(w.z)]);
        }
        ellipsoids.push(json!(e));
    }
    Some((links, ellipsoids))
}

/// The unit direction of the wrist origin's motion at each sample (world frame; forward
/// difference, backward at the last sample), `null` where the wrist origin does not move.
fn wrist_tangents(task: &Task, object_from_wrist: &Isometry3<f64>) -> Vec<Value> {
    let positions: Vec<Vector3<f64>> = task
        .path()
        .poses()
        .map(|world_from_object| (world_from_object * object_from_wrist).translation.vector)
        .collect();
    let n = positions.len();
    (0..n)
        .map(|i| {
            let (a, b) = if i + 1 < n {
                (i, i + 1)
            } else {
                (i.saturating_sub(1), i)
            };
            let d = positions[b] - positions[a];
            if d.norm() < 1e-9 {
                Value::Null
            } else {
                vector(&d.normalize())
            }
        })
        .collect()
}

/// When `task` times motions: per member (one candidate of each arm of the task, in order),
/// the time (s from the start of its approach, rounded to 1 ns) at which its timed motion
/// reaches each whole-motion sample (approach, path, retreat), the members on one timeline as
/// `graspath select` times them ([`timed_together`]). `None` without timing, for an
/// infeasible member, or where the timing fails (the view then plays per sample).
fn sample_times(task: &Task, members: &[(&ArmSetup, &CandidateScore)]) -> Option<Vec<Vec<f64>>> {
    let members: Vec<_> = members
        .iter()
        .map(|(arm, score)| (scoring_setup(task, arm), *score))
        .collect();
    let motions = timed_together(&members, None)?.ok()?;
    Some(
        motions
            .iter()
            .map(|m| {
                m.sample_times
                    .iter()
                    .map(|&t| (t * 1e9).round() / 1e9)
                    .collect()
            })
            .collect(),
    )
}

fn finite(v: Option<f64>) -> Option<f64> {
    v.filter(|v| v.is_finite())
}

/// The world part of one candidate's motion: the approach and retreat (joint origins, and the
/// body-carrying link frames when `links` is given) and the link frames along the path.
fn world_motion(
    setup: &ArmSetup,
    score: &CandidateScore,
    links: Option<&[usize]>,
    motion: &mut Map<String, Value>,
) {
    let stretch = |joints: &[Vec<f64>]| -> Value {
        let origins: Vec<Value> = joints
            .iter()
            .filter_map(|q| joint_origins(setup, q))
            .collect();
        let mut part = Map::new();
        part.insert("links".into(), Value::Array(origins));
        if let Some(links) = links {
            let frames: Vec<Value> = joints
                .iter()
                .filter_map(|q| link_frames(setup, links, q).map(Value::Array))
                .collect();
            part.insert("frames".into(), Value::Array(frames));
        }
        Value::Object(part)
    };
    motion.insert("approach".into(), stretch(&score.approach));
    motion.insert("retreat".into(), stretch(&score.retreat));
    if let Some(links) = links {
        let frames: Vec<Value> = score
            .joint_trajectory
            .iter()
            .filter_map(|q| link_frames(setup, links, q).map(Value::Array))
            .collect();
        motion.insert("frames".into(), Value::Array(frames));
    }
}

/// A reproduced first collision for the view: where (phase, sample), which bodies, and the
/// arm (joint origins, body link frames) and object there.
fn witness_json(setup: &ArmSetup, links: Option<&[usize]>, w: &Witness) -> Value {
    json!({
        "phase": w.phase.as_str(),
        "sample": w.sample,
        "between": w.between,
        "bodies": w.bodies,
        "distance": round6(w.distance),
        "q": w.q.iter().map(|&v| round6(v)).collect::<Vec<_>>(),
        "links": joint_origins(setup, &w.q),
        "frames": links.and_then(|l| link_frames(setup, l, &w.q)),
        "object": pose(&w.world_from_object),
    })
}

fn arm_json(task: &Task, setup: &ArmSetup, arm: &ArmResult) -> Value {
    let chain = &setup.chain;
    let world = has_world(task);
    let rest: Vec<Value> = chain
        .joint_origins(&chain.mid_configuration())
        .map(|o| {
            o.iter()
                .map(|p| point(&(setup.world_from_base * p)))
                .collect()
        })
        .unwrap_or_default();
    // Which candidates carry their motion: the ranked ones best first, then other feasible.
    let mut with_motion: Vec<usize> = (0..arm.scores.len())
        .filter(|&i| arm.rankings[i].rank.is_some())
        .collect();
    with_motion.sort_by_key(|&i| arm.rankings[i].rank);
    with_motion.extend(
        (0..arm.scores.len())
            .filter(|&i| arm.rankings[i].rank.is_none() && arm.scores[i].feasible()),
    );
    with_motion.truncate(MAX_MOTIONS_PER_ARM);
    let mut has_motion = vec![false; arm.scores.len()];
    let mut has_frames = vec![false; arm.scores.len()];
    for (k, &i) in with_motion.iter().enumerate() {
        has_motion[i] = true;
        has_frames[i] = k < MAX_BODY_MOTIONS_PER_ARM;
    }
    let links: Option<Vec<usize>> = setup.bodies.as_deref().map(body_links);
    let mut witnesses = 0;
    let results: Vec<Value> = arm
        .scores
        .iter()
        .zip(&arm.rankings)
        .enumerate()
        .map(|(i, (s, r))| {
            let c = &s.candidate;
            let moving = has_motion[i] && !s.joint_trajectory.is_empty();
            let motion = moving
                .then(|| motion(chain, &setup.world_from_base, &s.joint_trajectory))
                .flatten()
                .map(|(links_along, ellipsoid)| {
                    let mut m = Map::new();
                    m.insert("links".into(), Value::Array(links_along));
                    m.insert("ellipsoid".into(), Value::Array(ellipsoid));
                    m.insert(
                        "tangent".into(),
                        Value::Array(wrist_tangents(task, &c.object_from_wrist)),
                    );
                    m.insert(
                        "m_t".into(),
                        json!(s.m_t.iter().map(|v| finite(*v)).collect::<Vec<_>>()),
                    );
                    if world {
                        let frames = links.as_deref().filter(|_| has_frames[i]);
                        world_motion(setup, s, frames, &mut m);
                    }
                    if let Some(mut times) = sample_times(task, &[(setup, s)]) {
                        m.insert("sample_times".into(), json!(times.swap_remove(0)));
                    }
                    Value::Object(m)
                });
            let status = match (&s.failure, &r.rejected) {
                (Some(f), _) if f.phase != Phase::Path => format!(
                    "{} at {} sample {}: {}",
                    f.reason, f.phase, f.sample, f.detail
                ),
                (Some(f), _) => format!("{} at sample {}: {}", f.reason, f.sample, f.detail),
                (None, Some(why)) => format!("rejected: {why}"),
                (None, None) => "feasible".into(),
            };
            let mut result = json!({
                "candidate": i,
                "rank": r.rank,
                "score": finite(r.score),
                "mu_l2": s.norms.map(|n| n.l2),
                "mu_linf": s.norms.and_then(|n| finite(Some(n.linf))),
                "mu_l1": s.norms.map(|n| n.l1),
                "mu_rms": s.norms.map(|n| n.rms),
                "yoshikawa": finite(s.yoshikawa_at_grasp),
                "inverse_condition": finite(s.inverse_condition_squared_at_grasp),
                "feasible": s.feasible(),
                "status": status,
                "motion": motion,
            });
            if task.timing().is_some() {
                result["duration"] = json!(s.durations.map(|d| d.total()));
            }
            if world {
                let witness = (witnesses < MAX_WITNESSES_PER_ARM)
                    .then(|| first_collision(task, setup, s))
                    .flatten();
                if witness.is_some() {
                    witnesses += 1;
                }
                result["clearance"] = json!(s.clearance.map(round6));
                result["collision"] = witness
                    .map(|w| witness_json(setup, links.as_deref(), &w))
                    .unwrap_or(Value::Null);
            }
            result
        })
        .collect();
    let mut out = json!({
        "name": arm.arm,
        "world_from_base": pose(&setup.world_from_base),
        "rest": rest,
        "selected": arm.best(),
        "results": results,
    });
    if world {
        out["bodies"] = setup
            .bodies
            .as_deref()
            .map_or(Value::Null, |b| arm_bodies_json(chain, b));
        out["rest_frames"] =
            json!(links
                .as_deref()
                .and_then(|l| link_frames(setup, l, &chain.mid_configuration())));
    }
    out
}

/// The 3D view's data (see the module documentation for frames and units).
pub fn scene_json(task: &Task, selection: &Selection) -> Value {
    let arms: Vec<Value> = task
        .arms()
        .iter()
        .zip(&selection.arms)
        .map(|(setup, arm)| arm_json(task, setup, arm))
        .collect();
    // Every arm scores every candidate, in candidate order.
    let scored = &selection.arms[0].scores;
    let candidates: Vec<Value> = scored
        .iter()
        .map(|s| &s.candidate)
        .map(|c| json!({"id": c.id, "label": c.label, "wrist": pose(&c.object_from_wrist)}))
        .collect();
    let mut view = json!({
        "task": task.source_name(),
        "robot": task.robot_name(),
        "norm": task.selection().norm.as_str(),
        "times": task.path().samples.iter().map(|s| round6(s.time)).collect::<Vec<_>>(),
        "steps": task.path().step_labels,
        "sample_step": task.path().samples.iter().map(|s| s.step).collect::<Vec<_>>(),
        "object": {
            "shape": task.shape().map(shape_json),
            "poses": task.path().poses().map(pose).collect::<Vec<_>>(),
        },
        "candidates": candidates,
        "arms": arms,
        "pair": selection.pairs.first().map(|p| {
            let index = |c: &Arc<Candidate>| scored.iter().position(|s| Arc::ptr_eq(&s.candidate, c));
            json!([index(&p.first), index(&p.second)])
        }),
    });
    // The best pair's motions on their shared timeline (each part the slower arm's time).
    let pair_times = selection.pairs.first().and_then(|p| {
        let members: Option<Vec<_>> = [&p.first, &p.second]
            .into_iter()
            .zip(task.arms().iter().zip(&selection.arms))
            .map(|(c, (setup, arm))| {
                let score = arm.scores.iter().find(|s| Arc::ptr_eq(&s.candidate, c))?;
                Some((setup, score))
            })
            .collect();
        sample_times(task, &members?)
    });
    if let Some(times) = pair_times {
        view["pair_sample_times"] = json!(times);
    }
    if has_world(task) {
        view["world"] = json!({
            "bodies": scene_bodies(task),
            "approach_samples": task.approach().map_or(0, |s| s.samples),
            "retreat_samples": task.retreat().map_or(0, |s| s.samples),
            "margin": task.collisions().map(|c| c.options.margin),
        });
    }
    view
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ellipsoid_axes_rebuild_the_matrix() {
        // Oracle: Σ a_k a_kᵀ = V Λ Vᵀ = the matrix itself.
        let m = Matrix3::new(2.0, 0.3, -0.1, 0.3, 1.0, 0.2, -0.1, 0.2, 0.5);
        let axes = ellipsoid_axes(&m);
        let rebuilt: Matrix3<f64> = axes.iter().map(|a| a * a.transpose()).sum();
        assert!((rebuilt - m).norm() < 1e-12, "{rebuilt} vs {m}");
        assert!(axes[0].norm() >= axes[1].norm() && axes[1].norm() >= axes[2].norm());
    }
}
