//! Two arms carrying one object on one timeline, checked independently of the timing code:
//! at every instant of the carry the object the left arm holds (by its forward kinematics and
//! its grasp) is where the right arm holds it; both pass the IK samples of each object pose
//! at the same time; every velocity, acceleration and torque of both arms within its limit;
//! both at rest at the ends; with stops and as one motion.

use graspath::select::{select, selected_motions, SelectedMotion, Selection};
use graspath::task::{Task, TaskFile};
use nalgebra::Isometry3;
use std::path::Path;

/// Baxter's two arms lifting a 0.5 kg bar by its ends, carrying it 0.3 m to the side and
/// placing it (the paper's two-arm pick and place, nearer and higher so that Baxter's shoulders,
/// whose spring is not modelled, hold it), with an approach and a retreat and an
/// explicit acceleration limit; `extra` adds task-file lines.
fn task(extra: &str) -> Task {
    let text = format!(
        r#"
robot: {{ builtin: baxter }}
arms: both
object:
  pose: {{ xyz: [0.60, 0.0, 0.15] }}
  shape: {{ box: {{ size: [0.06, 0.40, 0.10] }} }}
  mass: 0.5
candidates:
  family: {{ edge: {{ count: 11, depth: 0.02, margin: 0.02 }} }}
trajectory:
  samples_per_step: 6
  steps:
    - {{ lift: 0.2, label: pick }}
    - {{ move: [0.0, 0.3, 0.0], label: move }}
    - {{ place: 0.2, label: place }}
approach: {{ distance: 0.06, samples: 4 }}
retreat: {{ distance: 0.06, samples: 4 }}
selection: {{ pairs: 3, min_separation: 0.2 }}
timing: {{ max_acceleration: 4.0{extra} }}
"#
    );
    let file = TaskFile::parse(&text, "two_arms.yaml", "yaml").unwrap();
    Task::from_file(&file, "two_arms.yaml", Path::new(".")).unwrap()
}

/// The acceleration limit the task sets (rad/s²).
const ACCELERATION: f64 = 4.0;

/// Relative slack on a torque limit for points sampled between the timing's check points.
const SLACK: f64 = 5e-3;

/// The selection and the best pair's two timed motions, sampled every `period` seconds (at
/// the grid points with `None`).
fn motions(task: &Task, period: Option<f64>) -> (Selection, Vec<SelectedMotion>) {
    let selection = select(task, &|| {}).unwrap();
    assert!(!selection.pairs.is_empty(), "a feasible pair");
    let motions = selected_motions(task, &selection, period)
        .expect("the task times motions")
        .expect("the best pair is feasible");
    assert_eq!(motions.len(), 2);
    (selection, motions)
}

/// The object's pose (world frame) that arm `a` of `task` holds at joint positions `q`: its
/// tool pose times the inverse of its grasp.
fn held_pose(task: &Task, a: usize, motion: &SelectedMotion, q: &[f64]) -> Isometry3<f64> {
    let arm = &task.arms()[a];
    let tool: Isometry3<f64> = nalgebra::convert(arm.chain.pose(q).unwrap());
    arm.world_from_base * tool * motion.candidate.object_from_wrist.inverse()
}

/// The largest distance (m) and angle (rad) between the object poses the two arms hold at the
/// points of their trajectories between the grasp and the place.
fn disagreement(task: &Task, motions: &[SelectedMotion]) -> (f64, f64) {
    let (left, right) = (&motions[0], &motions[1]);
    assert_eq!(left.trajectory.points.len(), right.trajectory.points.len());
    let (mut distance, mut angle): (f64, f64) = (0.0, 0.0);
    let mut carried = 0;
    for (l, r) in left.trajectory.points.iter().zip(&right.trajectory.points) {
        assert_eq!(l.time, r.time, "one timeline");
        if l.time < left.grasp_time || l.time > left.place_time {
            continue;
        }
        carried += 1;
        let (a, b) = (
            held_pose(task, 0, left, &l.positions),
            held_pose(task, 1, right, &r.positions),
        );
        distance = distance.max((a.translation.vector - b.translation.vector).norm());
        angle = angle.max(a.rotation.angle_to(&b.rotation));
    }
    assert!(carried > 100, "the carry is sampled ({carried} points)");
    (distance, angle)
}

#[test]
fn both_arms_hold_the_object_at_one_pose_throughout_the_carry() {
    for extra in ["", ", stops: false"] {
        let task = task(extra);
        let (_, motions) = motions(&task, Some(0.002));
        let (left, right) = (&motions[0], &motions[1]);
        assert_eq!(left.grasp_time, right.grasp_time, "{extra}");
        assert_eq!(left.place_time, right.place_time, "{extra}");
        assert_eq!(left.trajectory.duration(), right.trajectory.duration());
        // Between IK samples each arm follows its own spline, which departs from the exact
        // inverse kinematics of the object's pose by about a millimetre here (samples 3 to 5
        // cm apart); timed separately, each on its own path parameter, the arms held the
        // object 36 mm apart mid-carry.
        let (distance, angle) = disagreement(&task, &motions);
        assert!(
            distance < 2e-3 && angle < 5e-3,
            "{extra}: the arms hold the object {distance} m and {angle} rad apart"
        );
    }
}

#[test]
fn both_arms_pass_each_object_pose_at_one_time() {
    for extra in ["", ", stops: false"] {
        let task = task(extra);
        let (_, motions) = motions(&task, None);
        let (left, right) = (&motions[0], &motions[1]);
        let before = task.approach().map_or(0, |stroke| stroke.samples);
        let path = task.path().samples.len();
        for k in before..before + path {
            assert_eq!(
                left.sample_times[k],
                right.sample_times[k],
                "{extra}: path sample {}",
                k - before
            );
        }
        // And each arm is at that sample's inverse kinematics then: the object at its pose.
        for (a, motion) in motions.iter().enumerate() {
            for (k, sample) in task.path().samples.iter().enumerate() {
                let time = motion.sample_times[before + k];
                let point = motion
                    .trajectory
                    .points
                    .iter()
                    .find(|p| (p.time - time).abs() < 1e-9)
                    .unwrap_or_else(|| panic!("{extra}: no grid point at {time} s"));
                let held = held_pose(&task, a, motion, &point.positions);
                let planned = sample.world_from_object;
                let distance = (held.translation.vector - planned.translation.vector).norm();
                assert!(
                    distance < 1e-4,
                    "{extra}: arm {a}, sample {k}: {distance} m"
                );
            }
        }
    }
}

#[test]
fn both_arms_keep_their_limits_start_and_end_at_rest_and_wait_for_the_slower_one() {
    for extra in ["", ", stops: false"] {
        let task = task(extra);
        let (selection, motions) = motions(&task, Some(0.002));
        let mut binding: f64 = 0.0;
        for (a, motion) in motions.iter().enumerate() {
            let limits = task.arms()[a].chain.motion_limits().to_vec();
            for point in &motion.trajectory.points {
                let efforts = point
                    .efforts
                    .as_ref()
                    .expect("torques with the object's mass");
                for (j, l) in limits.iter().enumerate() {
                    let v = point.velocities[j].abs() / l.velocity.unwrap();
                    let acc = point.accelerations[j].abs() / ACCELERATION;
                    let tau = efforts[j].abs() / l.effort.unwrap();
                    assert!(v <= 1.0 + 1e-9, "{extra}: arm {a} joint {j}: velocity {v}");
                    assert!(
                        acc <= 1.0 + 1e-9,
                        "{extra}: arm {a} joint {j}: acceleration {acc}"
                    );
                    assert!(
                        tau <= 1.0 + SLACK,
                        "{extra}: arm {a} joint {j}: torque {tau}"
                    );
                    binding = binding.max(v).max(acc).max(tau);
                }
            }
            let points = &motion.trajectory.points;
            for p in [&points[0], points.last().unwrap()] {
                assert!(
                    p.velocities.iter().all(|v| v.abs() < 1e-9),
                    "{extra}: {p:?}"
                );
            }
        }
        assert!(binding > 0.9, "{extra}: no limit is reached ({binding})");
        if !extra.is_empty() {
            continue;
        }
        // With stops, the approach and the retreat (each arm on its own path) take the slower
        // arm's own time, as each arm timed alone in the selection. The carry, one path of
        // both arms' joints through other knots, has a timing of its own.
        let pair = &selection.pairs[0];
        let own = |a: usize, id: usize| {
            let arm = &selection.arms[a];
            let score = arm
                .scores
                .iter()
                .find(|s| s.candidate.id == id)
                .expect("the pair's candidate is scored");
            score.durations.expect("timed")
        };
        let (first, second) = (own(0, pair.first.id), own(1, pair.second.id));
        let motion = &motions[0];
        let approach = first.approach.max(second.approach);
        let retreat = first.retreat.max(second.retreat);
        assert!((motion.grasp_time - approach).abs() < 1e-9, "{approach} s");
        let last = motion.trajectory.duration() - motion.place_time;
        assert!(
            (last - retreat).abs() < 1e-9,
            "{last} s against {retreat} s"
        );
    }
}
