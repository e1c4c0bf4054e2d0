//! `trajectory.json` and `trajectory-<arm>.csv`: the selected grasps' motions as timed joint
//! trajectories, in the layout of ROS 2 `trajectory_msgs/JointTrajectory` (JSON) and as one
//! CSV table per arm.

use graspath::select::{selected_motions, Failure, Scored, SelectedMotion, Selection};
use graspath::task::Task;
use serde_json::{json, Value};

/// `trajectory.json` and the `trajectory-<arm>.csv` files of `selection`'s selected motions,
/// sampled every `period` seconds (at the timing grid's points with `None`), as `(file name,
/// bytes)`: none when the task does not time motions or nothing is selected.
pub fn trajectory_files<S: Scored>(
    task: &Task,
    selection: &Selection<S>,
    period: Option<f64>,
) -> Result<Vec<(String, Vec<u8>)>, Failure> {
    let Some(motions) = selected_motions(task, selection, period) else {
        return Ok(Vec::new());
    };
    let motions = motions?;
    let mut json = serde_json::to_vec_pretty(&trajectory_json(&motions, period))
        .expect("a JSON value serialises");
    json.push(b'\n');
    let mut files = vec![("trajectory.json".to_string(), json)];
    files.extend(
        trajectory_csvs(&motions)
            .into_iter()
            .map(|(name, csv)| (name, csv.into_bytes())),
    );
    Ok(files)
}

/// `trajectory.json`: `duration` (s, the longest arm's), `period` (s, `null` at the timing
/// grid's points) and per arm its name, candidate id and label, its duration, when the tool
/// reaches the grasp and the place (`grasp_time`, `place_time`, s: where a gripper closes and
/// opens) and the `trajectory` as a `JointTrajectory` (`joint_names`, `points` with `positions`,
/// `velocities`, `accelerations`, `effort` and `time_from_start {sec, nanosec}`).
pub fn trajectory_json(motions: &[SelectedMotion], period: Option<f64>) -> Value {
    let arms: Vec<Value> = motions
        .iter()
        .map(|m| {
            json!({
                "arm": m.arm,
                "candidate": m.candidate.id,
                "label": m.candidate.label,
                "duration": m.trajectory.duration(),
                "grasp_time": m.grasp_time,
                "place_time": m.place_time,
                "trajectory": m.trajectory.to_joint_trajectory(),
            })
        })
        .collect();
    let duration = motions
        .iter()
        .map(|m| m.trajectory.duration())
        .fold(0.0, f64::max);
    json!({"duration": duration, "period": period, "arms": arms})
}

/// The CSV files of `motions`: `(file name, contents)`, one `trajectory-<arm>.csv` per arm
/// (the arm's position in the task when its name is not a plain file name).
pub fn trajectory_csvs(motions: &[SelectedMotion]) -> Vec<(String, String)> {
    motions
        .iter()
        .enumerate()
        .map(|(i, m)| {
            let plain = !m.arm.is_empty()
                && m.arm.len() <= 64
                && m.arm
                    .chars()
                    .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-');
            let name = if plain {
                m.arm.clone()
            } else {
                format!("arm{i}")
            };
            (format!("trajectory-{name}.csv"), m.trajectory.to_csv())
        })
        .collect()
}
