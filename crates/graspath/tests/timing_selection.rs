//! The timed motions of a selection, checked independently of the timing code: every written
//! velocity, acceleration and torque within its limit, at rest at both ends, through the IK
//! samples, velocities the finite differences of the positions; the same trajectories at any
//! thread count; `selection.max_duration` and `index.measure: duration`.

use graspath::select::{select, selected_motions, CandidateScore, Selection};
use graspath::task::{Task, TaskFile};
use std::path::Path;

/// The Panda picking a 1.5 kg box from above, lifting, carrying and placing it, with an
/// approach and a retreat; `extra` adds task-file lines.
fn task(extra: &str) -> Task {
    let text = format!(
        r#"
robot: {{ builtin: panda }}
object:
  pose: {{ xyz: [0.55, 0.0, 0.10] }}
  shape: {{ box: {{ size: [0.05, 0.05, 0.20] }} }}
  mass: 1.5
candidates:
  family: {{ faces: {{ count: 24, exclude: [bottom], depth: 0.02 }} }}
trajectory:
  samples_per_step: 6
  steps:
    - {{ lift: 0.15, label: lift }}
    - {{ move: [0.0, 0.25, 0.0], label: carry }}
    - {{ place: 0.15, label: place }}
approach: {{ distance: 0.08, samples: 4 }}
retreat: {{ distance: 0.08, samples: 4 }}
{extra}
"#
    );
    let file = TaskFile::parse(&text, "timed.yaml", "yaml").unwrap();
    Task::from_file(&file, "timed.yaml", Path::new(".")).unwrap()
}

/// Relative slack on a torque limit for points sampled between the timing's check points.
const SLACK: f64 = 5e-3;

fn best(selection: &Selection) -> &CandidateScore {
    let arm = &selection.arms[0];
    &arm.scores[arm.best().expect("a feasible grasp")]
}

#[test]
fn the_selected_motion_stays_within_every_limit_and_passes_through_the_ik_samples() {
    // A tracked branch, and the self-motion search's rougher joint paths.
    for redundancy in ["first", "optimize"] {
        selected_motion_within_limits(&format!("ik: {{ redundancy: {redundancy} }}"));
    }
}

fn selected_motion_within_limits(extra: &str) {
    let task = task(extra);
    let selection = select(&task, &|| {}).unwrap();
    let chosen = best(&selection);
    let durations = chosen.durations.expect("the task times motions");
    assert!(durations.approach > 0.0 && durations.carry > 0.0 && durations.retreat > 0.0);
    let period = 0.002;
    let motions = selected_motions(&task, &selection, Some(period))
        .expect("timed")
        .expect("feasible");
    assert_eq!(motions.len(), 1);
    let trajectory = &motions[0].trajectory;
    assert_eq!(motions[0].candidate.id, chosen.candidate.id);
    assert!((trajectory.duration() - durations.total()).abs() < 1e-9);
    let limits = task.arms()[0].chain.motion_limits().to_vec();
    let (mut worst, mut worst_torque): (f64, f64) = (0.0, 0.0);
    for point in &trajectory.points {
        for (j, l) in limits.iter().enumerate() {
            let v = point.velocities[j].abs() / l.velocity.unwrap();
            let a = point.accelerations[j].abs() / l.acceleration.unwrap();
            let tau = point.efforts.as_ref().expect("torques")[j].abs() / l.effort.unwrap();
            worst = worst.max(v).max(a);
            worst_torque = worst_torque.max(tau);
        }
    }
    // Velocities and accelerations are bounded exactly between the grid points, torques
    // checked at each interval's middle.
    assert!(
        worst <= 1.0 + 1e-9,
        "a velocity or acceleration limit exceeded by {worst}"
    );
    assert!(
        worst_torque <= 1.0 + SLACK,
        "a torque limit exceeded by {worst_torque}"
    );
    let worst = worst.max(worst_torque);
    // Some limit binds: the motion is time-optimal, not merely slow.
    assert!(worst > 0.9, "no limit is reached ({worst})");
    // At rest at both ends and at the stops (the grasp and the place).
    let first = &trajectory.points[0];
    let last = trajectory.points.last().unwrap();
    for p in [first, last] {
        assert!(p.velocities.iter().all(|v| v.abs() < 1e-9), "{p:?}");
    }
    for stop in [durations.approach, durations.approach + durations.carry] {
        let at = trajectory
            .points
            .iter()
            .min_by(|a, b| (a.time - stop).abs().total_cmp(&(b.time - stop).abs()))
            .unwrap();
        assert!(at.velocities.iter().all(|v| v.abs() < 0.05), "{at:?}");
    }
    // Velocities are the derivatives of the positions (central differences).
    let points = &trajectory.points;
    for k in 1..points.len() - 1 {
        let dt = points[k + 1].time - points[k - 1].time;
        for j in 0..7 {
            let fd = (points[k + 1].positions[j] - points[k - 1].positions[j]) / dt;
            // The acceleration jumps at grid points: the difference is off by at most
            // 2·period times the largest acceleration (Panda: 20 rad/s²).
            let tolerance = 2.0 * period * 20.0;
            assert!(
                (fd - points[k].velocities[j]).abs() <= tolerance,
                "t = {}: joint {j}: {fd} vs {}",
                points[k].time,
                points[k].velocities[j]
            );
        }
    }
    // At the timing grid's points the motion passes through every IK sample, in order.
    let on_grid = selected_motions(&task, &selection, None).unwrap().unwrap();
    let samples: Vec<&Vec<f64>> = chosen
        .approach
        .iter()
        .chain(&chosen.joint_trajectory)
        .chain(&chosen.retreat)
        .collect();
    let mut next = 0;
    for p in &on_grid[0].trajectory.points {
        if next < samples.len()
            && p.positions
                .iter()
                .zip(samples[next])
                .all(|(a, b)| (a - b).abs() < 1e-9)
        {
            next += 1;
            // A repeated sample (the motion's stops) is passed at the same point.
            while next < samples.len() && samples[next] == samples[next - 1] {
                next += 1;
            }
        }
    }
    assert_eq!(next, samples.len(), "the motion misses IK sample {next}");
}

#[test]
fn timed_motions_do_not_depend_on_the_thread_count() {
    let task = task("");
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let selection = select(&task, &|| {}).unwrap();
            let durations: Vec<_> = selection.arms[0]
                .scores
                .iter()
                .map(|s| s.durations)
                .collect();
            let motions = selected_motions(&task, &selection, Some(0.01))
                .unwrap()
                .unwrap();
            (durations, motions[0].trajectory.to_csv())
        })
    };
    assert_eq!(run(1), run(3));
}

#[test]
fn max_duration_rejects_and_duration_ranks_the_fastest_first() {
    let plain = select(&task(""), &|| {}).unwrap();
    let mut durations: Vec<f64> = plain.arms[0]
        .scores
        .iter()
        .filter_map(|s| s.durations.map(|d| d.total()))
        .collect();
    durations.sort_by(f64::total_cmp);
    assert!(durations.len() >= 3, "{durations:?}");
    let cut = 0.5 * (durations[0] + durations[durations.len() - 1]);
    let bounded = select(
        &task(&format!("selection: {{ max_duration: {cut} }}")),
        &|| {},
    )
    .unwrap();
    for (score, ranking) in bounded.arms[0].scores.iter().zip(&bounded.arms[0].rankings) {
        if let Some(d) = score.durations.map(|d| d.total()) {
            assert_eq!(ranking.rank.is_none(), d > cut, "{d} s vs {cut} s");
        }
    }
    let fastest = select(
        &task("index: { measure: duration }\nselection: { likelihood: ignore }"),
        &|| {},
    )
    .unwrap();
    let arm = &fastest.arms[0];
    let mut ranked: Vec<(usize, f64)> = arm
        .scores
        .iter()
        .zip(&arm.rankings)
        .filter_map(|(s, r)| Some((r.rank?, s.durations?.total())))
        .collect();
    ranked.sort_by_key(|(rank, _)| *rank);
    assert!(ranked.windows(2).all(|w| w[0].1 <= w[1].1), "{ranked:?}");
    let fastest_motion = arm
        .scores
        .iter()
        .filter_map(|s| s.durations.map(|d| d.total()))
        .fold(f64::INFINITY, f64::min);
    assert_eq!(ranked[0].1, fastest_motion);
    // Each candidate's branch is its fastest, so the fastest motion is no longer than the
    // fastest among the branches the index picks.
    assert!(
        fastest_motion <= durations[0],
        "{fastest_motion} s vs {} s",
        durations[0]
    );
}

/// With `index.measure: duration` each candidate's IK branch is its fastest: over the same
/// branches (`ik.redundancy: best_branch` compares every branch the IK finds), no candidate's
/// motion is longer than the one the index picks, the same candidates are feasible, and some
/// get a shorter motion (the branch with the largest index is not always the fastest).
#[test]
fn duration_chooses_each_candidates_fastest_branch() {
    let branches = "ik: { redundancy: best_branch, branches: 8 }";
    let by_index = select(&task(branches), &|| {}).unwrap();
    let by_duration = select(
        &task(&format!("{branches}\nindex: {{ measure: duration }}")),
        &|| {},
    )
    .unwrap();
    let mut shorter = 0;
    for (index, duration) in by_index.arms[0]
        .scores
        .iter()
        .zip(&by_duration.arms[0].scores)
    {
        assert_eq!(
            index.feasible(),
            duration.feasible(),
            "candidate {}",
            index.candidate.id
        );
        let (Some(a), Some(b)) = (index.durations, duration.durations) else {
            continue;
        };
        let (a, b) = (a.total(), b.total());
        assert!(
            b <= a,
            "candidate {}: {b} s by duration, {a} s by the index",
            index.candidate.id
        );
        if b < a * (1.0 - 1e-9) {
            shorter += 1;
        }
    }
    assert!(
        shorter > 0,
        "no candidate has a faster branch than its best by the index"
    );
}

#[test]
fn timing_can_be_turned_off_and_then_nothing_is_timed() {
    let selection = select(&task("timing: false"), &|| {}).unwrap();
    assert!(selection.arms[0]
        .scores
        .iter()
        .all(|s| s.durations.is_none()));
    let file = TaskFile::parse(
        "robot: { builtin: panda }\nobject: { pose: { xyz: [0.5, 0, 0.1] }, shape: { box: { size: [0.05, 0.05, 0.2] } } }\ncandidates: { family: { faces: { count: 4 } } }\ntrajectory: { steps: [ { lift: 0.1 } ] }\ntiming: false\nselection: { max_duration: 2 }\n",
        "off.yaml",
        "yaml",
    )
    .unwrap();
    let err = Task::from_file(&file, "off.yaml", Path::new(".")).unwrap_err();
    assert!(err.to_string().contains("selection.max_duration"), "{err}");
}

#[test]
fn an_object_speed_limit_holds_along_the_carry_and_slows_it() {
    let limit = 0.15; // m/s
    let plain = task("");
    let slow = task(&format!(
        "timing: {{ object_speed: {limit}, object_turn_rate: 1.0 }}"
    ));
    let (fast_selection, slow_selection) = (
        select(&plain, &|| {}).unwrap(),
        select(&slow, &|| {}).unwrap(),
    );
    let (fast, chosen) = (best(&fast_selection), best(&slow_selection));
    assert_eq!(
        fast.candidate.id, chosen.candidate.id,
        "the limit changes no feasibility"
    );
    let durations = chosen.durations.unwrap();
    assert!(durations.carry > fast.durations.unwrap().carry * 1.2);
    // Oracle: the object's origin by forward kinematics at every point of the written
    // trajectory, its speed by finite differences.
    let period = 0.002;
    let motion = &selected_motions(&slow, &slow_selection, Some(period))
        .unwrap()
        .unwrap()[0];
    let chain = &slow.arms()[0].chain;
    let origin = chosen
        .candidate
        .object_from_wrist
        .inverse()
        .translation
        .vector;
    let position = |q: &[f64]| chain.pose(q).unwrap() * nalgebra::Point3::from(origin);
    let (start, end) = (durations.approach, durations.approach + durations.carry);
    let mut fastest: f64 = 0.0;
    for pair in motion.trajectory.points.windows(2) {
        if pair[0].time < start || pair[1].time > end {
            continue;
        }
        let travelled = (position(&pair[1].positions) - position(&pair[0].positions)).norm();
        fastest = fastest.max(travelled / (pair[1].time - pair[0].time));
    }
    assert!(fastest <= limit * 1.01, "the object moves at {fastest} m/s");
    assert!(
        fastest >= limit * 0.9,
        "the limit does not bind ({fastest} m/s)"
    );
}

/// Limits on the carried object's acceleration (linear and angular) hold along the written
/// carry, checked by finite differences of the object's pose by forward kinematics, and bind:
/// the carry is slower than without them, and the largest acceleration comes near the limit
/// (the rows keep it within `cos 27.57° ≈ 0.886` of it in the worst direction).
#[test]
fn object_acceleration_limits_hold_along_the_carry_and_slow_it() {
    let (linear_limit, angular_limit) = (0.5, 2.0); // m/s², rad/s²
    let plain = task("");
    let gentle = task(&format!(
        "timing: {{ object_acceleration: {linear_limit}, object_angular_acceleration: {angular_limit} }}"
    ));
    let (plain_selection, gentle_selection) = (
        select(&plain, &|| {}).unwrap(),
        select(&gentle, &|| {}).unwrap(),
    );
    let (fast, chosen) = (best(&plain_selection), best(&gentle_selection));
    assert_eq!(
        fast.candidate.id, chosen.candidate.id,
        "the limits change no feasibility"
    );
    let durations = chosen.durations.unwrap();
    assert!(
        durations.carry > fast.durations.unwrap().carry * 1.1,
        "{} s against {} s",
        durations.carry,
        fast.durations.unwrap().carry
    );
    // Oracle: the object's pose by forward kinematics at every point of the written
    // trajectory, its accelerations by second differences.
    let period = 0.002;
    let motion = &selected_motions(&gentle, &gentle_selection, Some(period))
        .unwrap()
        .unwrap()[0];
    let chain = &gentle.arms()[0].chain;
    let tool_from_object = chosen.candidate.object_from_wrist.inverse();
    let origin = nalgebra::Point3::from(tool_from_object.translation.vector);
    let turn = tool_from_object.rotation.to_rotation_matrix();
    // The object's origin and orientation in the base frame.
    let pose = |q: &[f64]| {
        let base_from_tool = chain.pose(q).unwrap();
        (base_from_tool * origin, base_from_tool.rotation * turn)
    };
    let (start, end) = (durations.approach, durations.approach + durations.carry);
    let (mut linear, mut angular): (f64, f64) = (0.0, 0.0);
    for triple in motion.trajectory.points.windows(3) {
        if triple[0].time < start || triple[2].time > end {
            continue;
        }
        let h = triple[1].time - triple[0].time;
        if (triple[2].time - triple[1].time - h).abs() > 1e-9 {
            continue; // a phase's last, shorter step
        }
        let [a, b, c] = [0, 1, 2].map(|k| pose(&triple[k].positions));
        let second = (a.0.coords - 2.0 * b.0.coords + c.0.coords) / (h * h);
        linear = linear.max(second.norm());
        // Angular velocity over each step from the relative rotation, then its change.
        type Pose = (nalgebra::Point3<f64>, nalgebra::Rotation3<f64>);
        let rate = |from: &Pose, to: &Pose| (to.1 * from.1.inverse()).scaled_axis() / h;
        angular = angular.max((rate(&b, &c) - rate(&a, &b)).norm() / h);
    }
    assert!(linear <= linear_limit * 1.02, "{linear} m/s²");
    assert!(angular <= angular_limit * 1.02, "{angular} rad/s²");
    assert!(
        linear >= linear_limit * 0.8 || angular >= angular_limit * 0.8,
        "neither limit binds ({linear} m/s², {angular} rad/s²)"
    );
}

#[test]
fn the_motion_passes_each_ik_sample_at_its_sample_time() {
    for extra in ["", "timing: { stops: false }"] {
        let task = task(extra);
        let selection = select(&task, &|| {}).unwrap();
        let chosen = best(&selection);
        let duration = chosen.durations.expect("the task times motions").total();
        let motion = &selected_motions(&task, &selection, None)
            .expect("timed")
            .expect("feasible")[0];
        let samples: Vec<&Vec<f64>> = chosen
            .approach
            .iter()
            .chain(&chosen.joint_trajectory)
            .chain(&chosen.retreat)
            .collect();
        let times = &motion.sample_times;
        assert_eq!(times.len(), samples.len(), "{extra}");
        assert_eq!(times[0], 0.0, "{extra}");
        assert!((times[times.len() - 1] - duration).abs() < 1e-9, "{extra}");
        for (k, (q, t)) in samples.iter().zip(times).enumerate() {
            // Oracle: the motion sampled at the timing grid's points (through the forward
            // map from time to path parameter) is at sample k's configuration at time t.
            let point = motion
                .trajectory
                .points
                .iter()
                .find(|p| (p.time - t).abs() < 1e-9)
                .unwrap_or_else(|| panic!("{extra}: no grid point at {t} s (sample {k})"));
            assert!(
                point
                    .positions
                    .iter()
                    .zip(q.iter())
                    .all(|(a, b)| (a - b).abs() < 1e-9),
                "{extra}: sample {k} at {t} s: {:?} vs {q:?}",
                point.positions
            );
            if k > 0 {
                // Later samples later; samples that coincide at once.
                let previous = times[k - 1];
                if samples[k] == samples[k - 1] {
                    assert_eq!(*t, previous, "{extra}: sample {k}");
                } else {
                    assert!(
                        *t > previous,
                        "{extra}: sample {k} at {t} s after {previous} s"
                    );
                }
            }
        }
    }
}

#[test]
fn the_grasp_and_place_times_are_where_the_tool_holds_the_object_at_its_first_and_last_pose() {
    let task = task("");
    let selection = select(&task, &|| {}).unwrap();
    let chosen = best(&selection);
    let durations = chosen.durations.expect("the task times motions");
    let motion = &selected_motions(&task, &selection, None)
        .expect("timed")
        .expect("feasible")[0];
    // With stops, the grasp ends the approach and the place ends the carry.
    assert!((motion.grasp_time - durations.approach).abs() < 1e-9);
    assert!((motion.place_time - durations.approach - durations.carry).abs() < 1e-9);
    let chain = &task.arms()[0].chain;
    let base_from_world = task.arms()[0].world_from_base.inverse();
    let object_from_wrist = motion.candidate.object_from_wrist;
    for (time, sample) in [
        (motion.grasp_time, task.path().samples.first().unwrap()),
        (motion.place_time, task.path().samples.last().unwrap()),
    ] {
        // At the grid's points the motion passes through the IK samples: the point at that
        // time puts the tool at the object's pose times the grasp.
        let point = motion
            .trajectory
            .points
            .iter()
            .find(|p| (p.time - time).abs() < 1e-9)
            .expect("a grid point at the grasp and at the place");
        let tool: nalgebra::Isometry3<f64> =
            nalgebra::convert(chain.pose(&point.positions).unwrap());
        let planned = base_from_world * sample.world_from_object * object_from_wrist;
        let position = (tool.translation.vector - planned.translation.vector).norm();
        let angle = tool.rotation.angle_to(&planned.rotation);
        assert!(
            position < 1e-4 && angle < 1e-3,
            "{position} m, {angle} rad at {time} s"
        );
        assert!(
            point.velocities.iter().all(|v| v.abs() < 1e-6),
            "at rest at {time} s"
        );
    }
}
