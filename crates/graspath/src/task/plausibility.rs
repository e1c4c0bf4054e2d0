//! Plausibility warnings: well-formed values that are probably a unit or convention mistake —
//! degrees in a radians field, radians in a degrees field, millimetres for metres, a
//! quaternion written `[w, x, y, z]`, a joint step over a quarter turn — and an object that
//! starts upside down or inside the table. Warnings, not errors: a deliberate value goes
//! through, and the task is scored as written.
//!
//! The rules (`docs/task-file.md`, "Plausibility warnings"):
//! * a radians field (`rpy`) with a value beyond a full turn (2π);
//! * a degrees field (`rpy_deg`, `angle_deg`, `step_deg`, `start_deg`, `rotation_deg`) whose
//!   non-zero values are all within a full turn in radians and one of them is a multiple of
//!   π/12 (15°) as radians to 1e-3 (`1.5708`, `0.7854`, `3.1416`);
//! * a position (`xyz`, `lift`, `place`, `move`) beyond [`MAX_PLAUSIBLE_POSITION`] m, or an
//!   object dimension beyond [`MAX_PLAUSIBLE_SIZE`] m: millimetres;
//! * a quaternion `[±1, 0, 0, 0]`: a half turn about `x` as written (`[x, y, z, w]`), the
//!   identity if it was meant as `[w, x, y, z]`;
//! * `ik.max_joint_step` over a quarter turn (π/2);
//! * the object's `z` axis pointing more than 45° below the horizontal at the start (upside
//!   down), or its lowest point more than [`TABLE_PENETRATION`] below the table's top.

use super::file::{FamilyFile, TaskFile};
use crate::collision::Table;
use crate::geometry::shape::Shape;
use crate::geometry::PoseSpec;
use nalgebra::{Isometry3, Vector3};
use std::f64::consts::{FRAC_PI_2, PI, TAU};

/// A value that is probably a mistake: the task-file field and what it looks like.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TaskWarning {
    /// The field, in task-file spelling (`object.pose.rpy`, `trajectory.steps[1].lift`).
    pub field: String,
    /// What the value looks like, and what was probably meant.
    pub message: String,
}

impl std::fmt::Display for TaskWarning {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}: {}", self.field, self.message)
    }
}

/// A position farther than this from the origin (m) is probably in millimetres.
pub const MAX_PLAUSIBLE_POSITION: f64 = 10.0;
/// An object dimension larger than this (m) is probably in millimetres.
pub const MAX_PLAUSIBLE_SIZE: f64 = 5.0;
/// How far (m) the object may reach below the table's top at the start before it is said to
/// start inside the table (resting on it is contact).
pub const TABLE_PENETRATION: f64 = 1e-3;

/// The warnings about the values written in `file` (units and conventions).
pub fn file_warnings(file: &TaskFile) -> Vec<TaskWarning> {
    let mut out = Vec::new();
    let mut poses: Vec<(String, &PoseSpec)> = vec![("object.pose".into(), &file.object.pose)];
    if let Some(tool) = &file.robot.tool {
        poses.push(("robot.tool".into(), tool));
    }
    for (name, arm) in &file.robot.chains {
        if let Some(tool) = &arm.tool {
            poses.push((format!("robot.chains.{name}.tool"), tool));
        }
        if let Some(base) = &arm.base_pose {
            poses.push((format!("robot.chains.{name}.base_pose"), base));
        }
    }
    let candidates = &file.candidates;
    for (field, pose) in [
        (
            "candidates.world_from_camera",
            &candidates.world_from_camera,
        ),
        (
            "candidates.camera_from_object",
            &candidates.camera_from_object,
        ),
        (
            "candidates.gripper_from_tool",
            &candidates.gripper_from_tool,
        ),
    ] {
        if let Some(pose) = pose {
            poses.push((field.into(), pose));
        }
    }
    for (i, step) in file.trajectory.steps.iter().enumerate() {
        if let Some(pose) = &step.pose {
            poses.push((format!("trajectory.steps[{i}].pose"), pose));
        }
    }
    if let Some(scene) = &file.scene {
        for (i, obstacle) in scene.obstacles.iter().enumerate() {
            if let Some(pose) = &obstacle.pose {
                poses.push((format!("scene.obstacles[{i}].pose"), pose));
            }
        }
    }
    if let Some(pose) = file
        .gripper
        .as_ref()
        .and_then(|g| g.tool_from_root.as_ref())
    {
        poses.push(("gripper.tool_from_root".into(), pose));
    }
    for (field, pose) in &poses {
        pose_warnings(field, pose, &mut out);
    }
    for (i, step) in file.trajectory.steps.iter().enumerate() {
        let field = |name: &str| format!("trajectory.steps[{i}].{name}");
        for (name, value) in [("lift", step.lift), ("place", step.place)] {
            if let Some(v) = value {
                millimetres(&field(name), &[v], &mut out);
            }
        }
        if let Some(v) = step.translate {
            millimetres(&field("move"), &v, &mut out);
        }
        if let Some(rotate) = &step.rotate {
            radians_in_degrees(&field("rotate.angle_deg"), &[rotate.angle_deg], &mut out);
        }
    }
    if let Some(spacing) = &file.trajectory.spacing {
        radians_in_degrees(
            "trajectory.spacing.rotation_deg",
            &[spacing.rotation_deg],
            &mut out,
        );
    }
    if let Some(FamilyFile::Yaw {
        step_deg,
        start_deg,
        ..
    }) = &candidates.family
    {
        radians_in_degrees("candidates.family.yaw.step_deg", &[*step_deg], &mut out);
        if let Some(start) = start_deg {
            radians_in_degrees("candidates.family.yaw.start_deg", &[*start], &mut out);
        }
    }
    if let Some(shape) = &file.object.shape {
        let aabb = shape.aabb();
        let size = (aabb.max - aabb.min).amax();
        if size > MAX_PLAUSIBLE_SIZE {
            out.push(TaskWarning {
                field: "object.shape".into(),
                message: format!(
                    "{size} m across: it looks like millimetres (lengths are in metres)"
                ),
            });
        }
    }
    if let Some(step) = file.ik.max_joint_step {
        if step > FRAC_PI_2 {
            out.push(TaskWarning {
                field: "ik.max_joint_step".into(),
                message: format!(
                    "{step} rad is more than a quarter turn between samples: a branch may jump \
                     between IK solutions unnoticed (it is in radians, not degrees)"
                ),
            });
        }
    }
    out
}

fn pose_warnings(field: &str, pose: &PoseSpec, out: &mut Vec<TaskWarning>) {
    if let Some(xyz) = pose.xyz {
        millimetres(&format!("{field}.xyz"), &xyz, out);
    }
    if let Some(rpy) = pose.rpy {
        if let Some(v) = rpy.iter().find(|v| v.abs() > TAU + 1e-9) {
            out.push(TaskWarning {
                field: format!("{field}.rpy"),
                message: format!(
                    "{v} is more than a full turn in radians: it looks like degrees (write \
                     rpy_deg for degrees)"
                ),
            });
        }
    }
    if let Some(rpy_deg) = pose.rpy_deg {
        radians_in_degrees(&format!("{field}.rpy_deg"), &rpy_deg, out);
    }
    if let Some(q) = pose.quaternion {
        if (q[0].abs() - 1.0).abs() < 1e-6 && q[1..].iter().all(|v| v.abs() < 1e-6) {
            out.push(TaskWarning {
                field: format!("{field}.quaternion"),
                message: format!(
                    "{q:?} is a half turn about x: quaternions are written [x, y, z, w] (the \
                     identity is [0, 0, 0, 1])"
                ),
            });
        }
    }
}

/// Degrees fields whose values look like radians: every non-zero value within a full turn
/// and one of them a multiple of π/12 to 1e-3.
fn radians_in_degrees(field: &str, values: &[f64], out: &mut Vec<TaskWarning>) {
    let nonzero: Vec<f64> = values.iter().copied().filter(|v| *v != 0.0).collect();
    let radian_like = |v: f64| {
        let k = (v / (PI / 12.0)).round();
        k != 0.0 && (v - k * PI / 12.0).abs() < 1e-3
    };
    if !nonzero.is_empty()
        && nonzero.iter().all(|v| v.abs() <= TAU)
        && nonzero.iter().any(|v| radian_like(*v))
    {
        let v = nonzero
            .iter()
            .find(|v| radian_like(**v))
            .copied()
            .unwrap_or(0.0);
        out.push(TaskWarning {
            field: field.into(),
            message: format!(
                "{v} looks like radians ({:.1}°) in a degrees field",
                v.to_degrees()
            ),
        });
    }
}

fn millimetres(field: &str, values: &[f64], out: &mut Vec<TaskWarning>) {
    if let Some(v) = values.iter().find(|v| v.abs() > MAX_PLAUSIBLE_POSITION) {
        out.push(TaskWarning {
            field: field.into(),
            message: format!(
                "{v} m is more than {MAX_PLAUSIBLE_POSITION} m: it looks like millimetres \
                 (positions are in metres)"
            ),
        });
    }
}

/// The warnings about the task's world at the start: an object at `world_from_object`
/// upside down, or (of `shape`) inside `table`.
pub fn world_warnings(
    world_from_object: &Isometry3<f64>,
    shape: Option<&Shape>,
    table: Option<&Table>,
) -> Vec<TaskWarning> {
    let mut out = Vec::new();
    let up = world_from_object.rotation * Vector3::z();
    if up.z < -std::f64::consts::FRAC_1_SQRT_2 {
        out.push(TaskWarning {
            field: "object.pose".into(),
            message: format!(
                "the object starts upside down (its z axis points {:.0}° below the horizontal)",
                up.z.clamp(-1.0, 1.0).asin().to_degrees().abs()
            ),
        });
    }
    if let (Some(shape), Some(table)) = (shape, table) {
        let down = world_from_object.rotation.inverse() * -Vector3::z();
        let lowest = world_from_object * shape.support(&down);
        let depth = table.height - lowest.z;
        if depth > TABLE_PENETRATION {
            out.push(TaskWarning {
                field: "object.pose".into(),
                message: format!(
                    "the object starts {:.1} mm inside the table (its lowest point at z = {:.4} \
                     m, the table's top at {} m): every grasp will collide with it",
                    depth * 1000.0,
                    lowest.z,
                    table.height
                ),
            });
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn warnings_of(yaml: &str) -> Vec<TaskWarning> {
        let file = TaskFile::parse(yaml, "t.yaml", "yaml").unwrap();
        file_warnings(&file)
    }

    const BASE: &str = "robot: { builtin: baxter }\narms: left\n\
        candidates: { family: { edge: { count: 3 } } }\n";

    fn task_with(object_pose: &str, steps: &str) -> String {
        format!(
            "{BASE}object: {{ pose: {object_pose}, shape: {{ box: {{ size: [0.06, 0.4, 0.1] }} }} }}\n\
             trajectory: {{ samples_per_step: 2, steps: [{steps}] }}\n"
        )
    }

    #[test]
    fn each_mistake_is_named_by_its_field_and_deliberate_values_pass() {
        let cases = [
            (
                "{ xyz: [0.75, 0, -0.1], rpy: [0, 0, 45] }",
                "{ lift: 0.2 }",
                Some("object.pose.rpy"),
            ),
            (
                "{ xyz: [0.75, 0, -0.1], rpy_deg: [0, 0, 1.5708] }",
                "{ lift: 0.2 }",
                Some("object.pose.rpy_deg"),
            ),
            (
                "{ xyz: [750, 0, -100] }",
                "{ lift: 0.2 }",
                Some("object.pose.xyz"),
            ),
            (
                "{ xyz: [0.75, 0, -0.1], quaternion: [1, 0, 0, 0] }",
                "{ lift: 0.2 }",
                Some("object.pose.quaternion"),
            ),
            (
                "{ xyz: [0.75, 0, -0.1] }",
                "{ lift: 200 }",
                Some("trajectory.steps[0].lift"),
            ),
            (
                "{ xyz: [0.75, 0, -0.1] }",
                "{ rotate: { angle_deg: 3.14159 } }",
                Some("trajectory.steps[0].rotate.angle_deg"),
            ),
            // Deliberate values: a yaw of 45° in degrees, 0.785 rad, 90°, a quarter turn.
            (
                "{ xyz: [0.75, 0, -0.1], rpy_deg: [0, 0, 45] }",
                "{ lift: 0.2 }",
                None,
            ),
            (
                "{ xyz: [0.75, 0, -0.1], rpy: [0, 0, 0.785] }",
                "{ rotate: { angle_deg: 90 } }",
                None,
            ),
            (
                "{ xyz: [0.75, 0, -0.1], quaternion: [0, 0, 0.7071068, 0.7071068] }",
                "{ place: 0.2 }",
                None,
            ),
        ];
        for (pose, steps, expected) in cases {
            let found = warnings_of(&task_with(pose, steps));
            match expected {
                Some(field) => {
                    assert_eq!(found.len(), 1, "{pose} {steps}: {found:?}");
                    assert_eq!(found[0].field, field);
                }
                None => assert!(found.is_empty(), "{pose} {steps}: {found:?}"),
            }
        }
    }

    #[test]
    fn a_joint_step_over_a_quarter_turn_and_a_shape_in_millimetres_are_named() {
        let text = format!(
            "{BASE}object: {{ pose: {{ xyz: [0.75, 0, -0.1] }}, shape: {{ box: {{ size: [60, 400, 100] }} }} }}\n\
             trajectory: {{ samples_per_step: 2, steps: [{{ lift: 0.2 }}] }}\nik: {{ max_joint_step: 30 }}\n"
        );
        let fields: Vec<String> = warnings_of(&text).into_iter().map(|w| w.field).collect();
        assert_eq!(fields, ["object.shape", "ik.max_joint_step"]);
        let quarter = text.replace("max_joint_step: 30", "max_joint_step: 1.5");
        let fields: Vec<String> = warnings_of(&quarter).into_iter().map(|w| w.field).collect();
        assert_eq!(fields, ["object.shape"]);
    }
}
