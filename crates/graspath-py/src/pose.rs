//! Poses given from Python in the task file's pose syntax (`docs/task-file.md`, "Poses"):
//! `graspath.pose_matrix`, and `Task.load`'s `object_pose`.

use crate::convert::{array, error, lib_error, push_isometry, shape_text, single_pose, FloatArray};
use graspath::geometry::PoseSpec;
use graspath::task::TaskError;
use nalgebra::Isometry3;
use numpy::{PyArrayDyn, PyUntypedArrayMethods};
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
    // Numbers as any array-like of them (read by strides; complex, date and string values
    // refused, never cast), of the given shape.
    let numbers = |key: &str, item: &Bound<'_, PyAny>, shape: &[usize], what: &str| {
        let array: FloatArray<'_> = item.extract().map_err(|e: PyErr| {
            let reason = e.value(item.py()).to_string();
            fault(key, format!("give {what}: {reason}"))
        })?;
        if array.shape() != shape {
            return Err(fault(
                key,
                format!(
                    "give {what}, not an array of shape {}",
                    shape_text(array.shape())
                ),
            ));
        }
        Ok(array.as_array().iter().copied().collect::<Vec<f64>>())
    };
    let three = |v: Vec<f64>| [v[0], v[1], v[2]];
    let mut spec = PoseSpec::default();
    for (key, item) in dict.iter() {
        let key: String = key
            .extract()
            .map_err(|_| fault("", "the pose's keys must be strings".into()))?;
        match key.as_str() {
            "xyz" | "rpy" | "rpy_deg" => {
                let value = Some(three(numbers(&key, &item, &[3], "3 numbers")?));
                match key.as_str() {
                    "xyz" => spec.xyz = value,
                    "rpy" => spec.rpy = value,
                    _ => spec.rpy_deg = value,
                }
            }
            "quaternion" => {
                let q = numbers(&key, &item, &[4], "4 numbers")?;
                spec.quaternion = Some([q[0], q[1], q[2], q[3]]);
            }
            "matrix" => {
                let m = numbers(&key, &item, &[4, 4], "4 rows of 4 numbers")?;
                let row = |r: usize| [m[4 * r], m[4 * r + 1], m[4 * r + 2], m[4 * r + 3]];
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
