//! The demo's heavy-object finding: the paper's cuboid Pick-and-Place (Baxter's left arm, the
//! 40 cm bar along its top edge) with the bar given a mass, from light to 2 kg
//! (`docs/dynamics.md`). Does the best grasp move as the bar gets heavier, and where does the
//! arm run out of torque?

use anyhow::Result;
use graspath::failure::FailureReason;
use graspath::select::{select, ArmResult, CandidateScore};
use graspath::task::{Task, TaskFile};
use serde_json::{json, Map, Value};
use std::collections::BTreeMap;
use std::path::Path;

/// The bar's masses (kg), lightest first.
pub(super) const MASSES_KG: [f64; 6] = [0.1, 0.25, 0.5, 1.0, 1.5, 2.0];

/// The finding for one arm at one mass: how many candidates stay feasible, the best grasp by
/// the task's index and by the dynamic manipulability, whether the best grasp without a mass
/// (`light_best`) is still feasible, how many fail for their torques and at which joint, and
/// the grasp with the largest payload capacity along its chosen motion.
fn at_mass(mass: f64, arm: &ArmResult, light_best: Option<&str>) -> Value {
    let label = |i: usize| arm.scores[i].candidate.label.clone();
    let mut joints: BTreeMap<String, usize> = BTreeMap::new();
    let mut torque_failures = 0;
    for failure in arm.scores.iter().filter_map(|s| s.failure.as_ref()) {
        if failure.reason == FailureReason::TorqueLimit {
            torque_failures += 1;
            if let Some(joint) = &failure.joint {
                *joints.entry(joint.clone()).or_default() += 1;
            }
        }
    }
    let capacity = arm
        .best_by(|s| s.payload_capacity)
        .map(|i| json!({"label": label(i), "kg": arm.scores[i].payload_capacity}));
    json!({
        "mass_kg": mass,
        "feasible": arm.feasible_count(),
        "best": arm.best().map(label),
        "best_without_mass_feasible": arm
            .scores
            .iter()
            .find(|s| Some(s.candidate.label.as_str()) == light_best)
            .map(CandidateScore::feasible),
        "best_by_dynamic_manipulability": arm.best_by(|s| s.dynamic_manipulability).map(label),
        "torque_limit": torque_failures,
        "out_of_torque_at": Value::Object(joints.into_iter().map(|(j, n)| (j, json!(n))).collect::<Map<_, _>>()),
        "largest_capacity": capacity,
    })
}

/// `file` (the cuboid's task, read from `source`) at each of [`MASSES_KG`]: per mass the
/// finding of [`at_mass`]; `best_without_mass` (the light task's best, `light_best`),
/// `best_moves_at_kg` (the lightest mass whose best differs from it, `null` when none does) and
/// `nothing_feasible_from_kg` (the lightest mass at which no grasp can do the task).
pub(super) fn heavy_finding(
    file: &TaskFile,
    source: &str,
    light_best: Option<String>,
) -> Result<Value> {
    let mut masses = Vec::new();
    let mut arm_name = None;
    let mut best_moves_at = None;
    let mut nothing_from = None;
    for mass in MASSES_KG {
        let mut heavy = file.clone();
        heavy.object.mass = Some(mass);
        let task = Task::from_file(&heavy, source, Path::new("."))?;
        let selection = select(&task, &|| {})?;
        let arm = &selection.arms[0];
        arm_name.get_or_insert_with(|| arm.arm.clone());
        let finding = at_mass(mass, arm, light_best.as_deref());
        let best = finding["best"].as_str().map(str::to_string);
        if best_moves_at.is_none() && best.is_some() && best != light_best {
            best_moves_at = Some(mass);
        }
        if nothing_from.is_none() && arm.feasible_count() == 0 {
            nothing_from = Some(mass);
        }
        masses.push(finding);
    }
    Ok(json!({
        "arm": arm_name,
        "best_without_mass": light_best,
        "best_moves_at_kg": best_moves_at,
        "nothing_feasible_from_kg": nothing_from,
        "masses": masses,
        "note": "Baxter's shoulder spring is not modelled, so s1 carries the whole arm: the torque check is conservative at s1 (docs/dynamics.md)",
    }))
}

/// The finding in one line for the demo's printout.
pub(super) fn summarise(heavy: &Value) -> String {
    let masses = heavy["masses"].as_array().map(Vec::as_slice).unwrap_or(&[]);
    let parts: Vec<String> = masses
        .iter()
        .map(|m| {
            let joints: Vec<String> = m["out_of_torque_at"]
                .as_object()
                .into_iter()
                .flatten()
                .map(|(joint, n)| format!("{joint} ×{n}"))
                .collect();
            format!(
                "{} kg: {} feasible, best {}{}",
                m["mass_kg"],
                m["feasible"],
                m["best"].as_str().unwrap_or("none"),
                if joints.is_empty() {
                    String::new()
                } else {
                    format!(" (out of torque: {})", joints.join(", "))
                }
            )
        })
        .collect();
    parts.join("; ")
}
