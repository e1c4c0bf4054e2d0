//! The carried object's weight in the selection: the torque check along the motion, the
//! payload capacity of a grasp (checked against a bisection on the mass that re-runs the whole
//! selection), `torque_limit` past it, `selection.min_torque_margin`, the task file's mass
//! fields, and the physics of a bar held at its end or at its centre.

use graspath::failure::FailureReason;
use graspath::robot::builtin::{baxter, Arm};
use graspath::robot::RigidBody;
use graspath::select::{select, CandidateScore};
use graspath::task::{Task, TaskFile};
use nalgebra::Vector3;
use std::path::Path;

/// Baxter's left arm lifting, carrying and placing a box; one IK branch (so the motion does
/// not depend on the mass), the object's mass or density given by `object_fields`.
fn task(object_fields: &str, selection: &str) -> Result<Task, graspath::task::TaskError> {
    let text = format!(
        r#"
robot: {{ builtin: baxter }}
arms: left
object:
  pose: {{ xyz: [0.75, 0.0, -0.10] }}
  shape: {{ box: {{ size: [0.06, 0.40, 0.10] }} }}
  {object_fields}
candidates:
  family: {{ edge: {{ count: 9, depth: 0.02, margin: 0.02 }} }}
trajectory:
  samples_per_step: 5
  steps:
    - {{ lift: 0.2, label: pick }}
    - {{ move: [0.0, 0.3, 0.0], label: move }}
    - {{ place: 0.2, label: place }}
ik: {{ branches: 1, iterations: 2000, redundancy: first }}
selection: {{ {selection} }}
"#
    );
    let file = TaskFile::parse(&text, "payload.yaml", "yaml")?;
    Task::from_file(&file, "payload.yaml", Path::new("."))
}

fn scores(mass: f64) -> Vec<CandidateScore> {
    let task = task(&format!("mass: {mass}"), "").expect("a valid task");
    select(&task, &|| {}).unwrap().arms.remove(0).scores
}

#[test]
fn payload_capacity_is_the_largest_mass_the_motion_carries() {
    let light = scores(0.05);
    let unloaded = task("", "").unwrap();
    let plain = select(&unloaded, &|| {}).unwrap().arms.remove(0).scores;
    let mut checked = 0;
    for (k, score) in light.iter().enumerate() {
        // The motion is the object's weight's, not the check's: the same joints as without it.
        if !score.feasible() {
            continue;
        }
        assert_eq!(score.joint_trajectory, plain[k].joint_trajectory);
        let capacity = score
            .payload_capacity
            .expect("a limited joint bears the object");
        let margin = score.torque_margin.expect("a margin with a payload");
        assert!((0.0..=1.0).contains(&margin), "{margin}");
        // Oracle: bisection on the mass, re-running the selection, for this candidate.
        let (mut lo, mut hi) = (0.05, capacity * 2.0 + 1.0);
        for _ in 0..20 {
            let mid = 0.5 * (lo + hi);
            if scores(mid)[k].feasible() {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        assert!(
            (lo - capacity).abs() <= 1e-4 * capacity.max(1.0),
            "candidate {k}: bisection {lo} vs capacity {capacity}"
        );
        // Past it, the candidate fails for its torques, and says which joint.
        let heavy = &scores(capacity * 1.01)[k];
        let failure = heavy.failure.as_ref().expect("too heavy");
        assert_eq!(failure.reason, FailureReason::TorqueLimit, "{failure}");
        assert!(failure.detail.contains("N·m"), "{failure}");
        // The joint is a field too, the one the sentence names.
        let joint = failure.joint.as_deref().expect("the joint at fault");
        assert!(
            unloaded.arms()[0]
                .chain
                .joint_names()
                .iter()
                .any(|j| j == joint),
            "{joint}"
        );
        assert!(
            failure
                .detail
                .starts_with(&format!("joint '{joint}' needs")),
            "{failure}"
        );
        checked += 1;
        if checked == 2 {
            break;
        }
    }
    assert_eq!(checked, 2, "the test task has feasible candidates");
}

#[test]
fn a_density_gives_the_mass_of_the_shape_and_the_margin_falls_with_it() {
    // 0.06 × 0.40 × 0.10 m = 2.4e-3 m³: 100 kg/m³ is 0.24 kg.
    let by_density = task("density: 100", "").unwrap();
    assert!((by_density.payload().unwrap().mass - 0.24).abs() < 1e-12);
    let by_mass = select(&task("mass: 0.24", "").unwrap(), &|| {}).unwrap();
    let by_density = select(&by_density, &|| {}).unwrap();
    for (a, b) in by_mass.arms[0]
        .scores
        .iter()
        .zip(&by_density.arms[0].scores)
    {
        assert_eq!(a.feasible(), b.feasible());
        assert_eq!(a.joint_trajectory, b.joint_trajectory);
        if let (Some(x), Some(y)) = (a.torque_margin, b.torque_margin) {
            assert!((x - y).abs() < 1e-12, "{x} vs {y}");
        }
    }
    let lighter = scores(0.1);
    for (light, heavy) in lighter.iter().zip(&by_mass.arms[0].scores) {
        if let (Some(a), Some(b)) = (light.torque_margin, heavy.torque_margin) {
            assert!(a > b, "a lighter object leaves more margin: {a} vs {b}");
        }
    }
}

#[test]
fn min_torque_margin_rejects_and_needs_a_mass() {
    let selection = select(
        &task("mass: 0.1", "min_torque_margin: 0.5").unwrap(),
        &|| {},
    )
    .unwrap();
    let arm = &selection.arms[0];
    for (score, ranking) in arm.scores.iter().zip(&arm.rankings) {
        if let Some(margin) = score.torque_margin {
            assert_eq!(ranking.rejected.is_some(), margin < 0.5, "{margin}");
        }
    }
    let err = task("", "min_torque_margin: 0.5").unwrap_err().to_string();
    assert!(err.contains("selection.min_torque_margin"), "{err}");
}

#[test]
fn bad_mass_fields_name_the_field() {
    for (fields, field, fragment) in [
        ("mass: 2000", "object.mass", "grams"),
        ("mass: -1", "object.mass", "positive"),
        ("mass: 1\n  density: 10", "object.density", "not both"),
        ("density: 0", "object.density", "positive"),
        (
            "center_of_mass: [0, 0, 0.1]",
            "object.center_of_mass",
            "mass",
        ),
        (
            "mass: 1\n  center_of_mass: [0, 0, 50]",
            "object.center_of_mass",
            "millimetres",
        ),
    ] {
        let err = task(fields, "").unwrap_err().to_string();
        assert!(
            err.contains(field) && err.contains(fragment),
            "{fields}: {err}"
        );
    }
}

#[test]
fn a_bar_held_at_its_end_needs_more_shoulder_and_wrist_torque_than_at_its_centre() {
    // A 2 kg, 40 cm horizontal bar pointing away from the shoulder, held at its centre (centre
    // of mass at the tool) or at its near end (centre of mass 20 cm farther out).
    let chain = baxter(Arm::Left);
    let dynamics = chain.dynamics().unwrap();
    let q = [0.3, -0.4, -0.2, 1.2, 0.1, 0.8, 0.0];
    let base_from_tool = chain.pose(&q).unwrap();
    let tool = base_from_tool.translation.vector;
    let outward = Vector3::new(tool.x, tool.y, 0.0).normalize();
    let offset_in_tool = base_from_tool.rotation.inverse() * (outward * 0.2);
    let torques = |com: Vector3<f64>| {
        let mut data = dynamics.data();
        data.set_payload(Some(RigidBody::point(2.0, com))).unwrap();
        let mut tau = vec![0.0; 7];
        dynamics
            .gravity_torques_into(&mut data, &q, &mut tau)
            .unwrap();
        tau
    };
    let centre = torques(Vector3::zeros());
    let end = torques(offset_in_tool);
    let names = chain.joint_names();
    for joint in ["left_s1", "left_w1"] {
        let j = names.iter().position(|n| n == joint).unwrap();
        assert!(
            end[j].abs() > centre[j].abs() + 0.5,
            "{joint}: {} at the end vs {} at the centre",
            end[j],
            centre[j]
        );
    }
    // The extra shoulder torque is the extra lever times the weight (horizontal offset
    // 0.2 m, 2 kg, 9.81 m/s²), up to the shoulder axis's tilt.
    let s1 = names.iter().position(|n| n == "left_s1").unwrap();
    let extra = (end[s1] - centre[s1]).abs();
    assert!(
        extra > 0.5 * 0.2 * 2.0 * 9.81 && extra <= 0.2 * 2.0 * 9.81 + 1e-9,
        "{extra}"
    );
}
