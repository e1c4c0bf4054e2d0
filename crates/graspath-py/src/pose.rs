//! Poses given from Python in the task file's pose syntax (`docs/task-file.md`, "Poses"):
//! `graspath.pose_matrix`, and `Task.load`'s `object_pose`.

use crate::convert::{array, error, lib_error, push_isometry, single_pose, FloatArray};
use graspath::geometry::PoseSpec;
use graspath::task::TaskError;
use nalgebra::Isometry3;
use numpy::PyArrayDyn;
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// A pose in the task file's syntax, from a Python mapping (see `docs/task-file.md`,
/// "Poses"): each key one of `xyz`, `rpy`, `rpy_deg`, `quaternion` (that many numbers) or
/// `matrix` (4 rows of 4), checked as a rigid transform by [`PoseSpec::to_isometry`]. An error
/// is the sub-field at fault (empty for the whole value) and what is wrong with it.
fn pose_from_mapping(value: &Bound<'_, PyAny>) -> Result<Isometry3<f64>, (String, String)> {
    let fault = |field: &str, message: String| (field.to_string(), message);
    let dict = value.cast::<PyDict>().map_err(|_| {
        fault(
            "",
            "give a dict in the task file's pose syntax (xyz, rpy, rpy_deg, quaternion, matrix)"
                .into(),
        )
    })?;
    let numbers = |key: &str, item: &Bound<'_, PyAny>, count: usize| {
        let values: Vec<f64> = item
            .extract()
            .map_err(|_| fault(key, format!("give {count} numbers")))?;
        if values.len() != count {
            return Err(fault(
                key,
                format!("{} numbers given, expected {count}", values.len()),
            ));
        }
        Ok(values)
    };
    let three = |v: Vec<f64>| [v[0], v[1], v[2]];
    let mut spec = PoseSpec::default();
    for (key, item) in dict.iter() {
        let key: String = key
            .extract()
            .map_err(|_| fault("", "the pose's keys must be strings".into()))?;
        match key.as_str() {
            "xyz" => spec.xyz = Some(three(numbers(&key, &item, 3)?)),
            "rpy" => spec.rpy = Some(three(numbers(&key, &item, 3)?)),
            "rpy_deg" => spec.rpy_deg = Some(three(numbers(&key, &item, 3)?)),
            "quaternion" => {
                let q = numbers(&key, &item, 4)?;
                spec.quaternion = Some([q[0], q[1], q[2], q[3]]);
            }
            "matrix" => {
                let shape = || fault("matrix", "give 4 rows of 4 numbers".into());
                let rows: Vec<Vec<f64>> = item.extract().map_err(|_| shape())?;
                if rows.len() != 4 || rows.iter().any(|r| r.len() != 4) {
                    return Err(shape());
                }
                let row = |r: usize| [rows[r][0], rows[r][1], rows[r][2], rows[r][3]];
                spec.matrix = Some([row(0), row(1), row(2), row(3)]);
            }
            other => {
                return Err(fault(
                    other,
                    "not a pose field (xyz, rpy, rpy_deg, quaternion, matrix)".into(),
                ))
            }
        }
    }
    spec.to_isometry().map_err(|e| fault(e.field, e.message))
}

/// `Task.load`'s `object_pose`: a mapping in the task file's pose syntax or a 4×4 array;
/// errors name the task `name` and the field (`object_pose.quaternion`, …).
pub fn world_from_object(value: &Bound<'_, PyAny>, name: &str) -> PyResult<Isometry3<f64>> {
    if value.cast::<PyDict>().is_ok() {
        return pose_from_mapping(value).map_err(|(field, message)| {
            let field = if field.is_empty() {
                "object_pose".to_string()
            } else {
                format!("object_pose.{field}")
            };
            lib_error(TaskError::new(name, field, message))
        });
    }
    let matrix: FloatArray<'_> = value.extract().map_err(|_| {
        lib_error(TaskError::new(
            name,
            "object_pose",
            "give a dict in the task file's pose syntax or a 4×4 array".to_string(),
        ))
    })?;
    single_pose(&matrix, "object_pose").map_err(|e| error(format!("{name}: {e}")))
}

/// The 4×4 rigid transform (row-major, m) a pose written in the task file's syntax describes:
/// a mapping with ``xyz`` (m, default zero) and at most one of ``rpy`` (rad, URDF fixed-axis
/// roll-pitch-yaw), ``rpy_deg`` (degrees) or ``quaternion`` (``[x, y, z, w]``, norm 1 within
/// 0.001, then normalised), or a ``matrix`` (4×4 rows) alone. Raises :class:`GraspathError`
/// naming the sub-field at fault (``field 'quaternion': must be a unit quaternion …``).
#[pyfunction]
pub fn pose_matrix<'py>(
    py: Python<'py>,
    spec: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    let world_from_object = pose_from_mapping(spec).map_err(|(field, message)| {
        error(if field.is_empty() {
            message
        } else {
            format!("field '{field}': {message}")
        })
    })?;
    let mut values = Vec::with_capacity(16);
    push_isometry(&mut values, &world_from_object);
    array(py, values, &[4, 4])
}
