//! The self-motion of `graspath.Robot` (`nullspace`, `optimize_self_motion`): the joint
//! velocities that leave the tip still, and a joint path moved along them to raise the
//! task-relevant index.
//!
//! Poses in the chain **base frame** (metres), configurations in radians. The
//! `#[pymethods]` wrappers are in `robot.rs` (PyO3 wants one block per class).

use super::PyRobot;
use crate::convert::{array, error, index_mode, lib_error, poses, FloatArray};
use graspath::manipulability::{wrist_tangent, Direction};
use graspath::robot::{null_space, optimize_self_motion, KeptRows, SelfMotionOptions};
use nalgebra::Matrix6xX;
use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::types::PyDict;

impl PyRobot {
    /// An orthonormal basis `(dof, k)` of the self-motion directions at one configuration
    /// `q`, of the rows `rows` (`pose` or `position`): what `Robot.nullspace` returns.
    pub(super) fn self_motion_basis<'py>(
        &self,
        py: Python<'py>,
        q: FloatArray<'py>,
        rows: &str,
        tolerance: f64,
    ) -> PyResult<Py<PyAny>> {
        let rows = kept_rows(rows)?;
        if !(tolerance.is_finite() && tolerance >= 0.0) {
            return Err(error(format!(
                "tolerance must be a non-negative number, got {tolerance}"
            )));
        }
        let (q, None) = self.configurations(&q)? else {
            return Err(error("q must have shape (dof,)"));
        };
        let mut jacobian = Matrix6xX::zeros(self.chain.dof());
        self.chain
            .pose_and_jacobian_into(&q, &mut jacobian)
            .map_err(lib_error)?;
        let basis = null_space(&jacobian, rows, tolerance);
        let (dof, k) = basis.shape();
        // nalgebra is column-major; numpy wants rows.
        let flat: Vec<f64> = (0..dof)
            .flat_map(|r| (0..k).map(move |c| (r, c)))
            .map(|(r, c)| basis[(r, c)])
            .collect();
        Ok(array(py, flat, &[dof, k])?.into_any().unbind())
    }

    /// The joint path `q` `(n, dof)` on the tip poses `targets` moved along the self-motion
    /// to maximise `Σ M_T²` (index rows from `mode` and `length_scale`), checked and searched
    /// with `options`: the dict `Robot.optimize_self_motion` returns.
    pub(super) fn optimized_self_motion<'py>(
        &self,
        py: Python<'py>,
        targets: FloatArray<'py>,
        q: FloatArray<'py>,
        mode: &str,
        length_scale: f64,
        options: SelfMotionOptions,
    ) -> PyResult<Bound<'py, PyDict>> {
        // The fields read in the checks below; `options` itself goes to the search.
        let SelfMotionOptions {
            spacing,
            reach,
            max_joint_step,
            position_tolerance,
            rotation_tolerance,
        } = options;
        let dof = self.chain.dof();
        let (targets, _) = poses(&targets, "targets")?;
        let n = targets.len();
        let (data, batch) = self.configurations(&q)?;
        if batch != Some(n) {
            return Err(error(format!(
                "q must have shape ({n}, {dof}): one configuration per target"
            )));
        }
        for (name, value) in [
            ("max_joint_step", max_joint_step),
            ("spacing", spacing),
            ("position_tolerance", position_tolerance),
            ("rotation_tolerance", rotation_tolerance),
        ] {
            if !(value.is_finite() && value > 0.0) {
                return Err(error(format!(
                    "{name} must be a positive number, got {value}"
                )));
            }
        }
        if reach == 0 || reach > 1000 {
            return Err(error(format!(
                "reach must be between 1 and 1000, got {reach}"
            )));
        }
        let rows = index_mode(mode, length_scale)?;
        let seed: Vec<Vec<f64>> = data.chunks(dof).map(<[f64]>::to_vec).collect();
        // The seed must be a feasible path: on its targets, inside the limits, small steps.
        let (lower, upper) = (self.chain.lower(), self.chain.upper());
        for (i, (q, target)) in seed.iter().zip(&targets).enumerate() {
            let pose = self.chain.pose(q).map_err(lib_error)?;
            let off = (pose.translation.vector - target.translation.vector).norm();
            let turn = pose
                .rotation
                .angle_to(&target.rotation.to_rotation_matrix());
            if off > position_tolerance * 10.0 || turn > rotation_tolerance * 10.0 {
                return Err(error(format!(
                    "q[{i}] puts the tip {off:.3e} m and {turn:.3e} rad from targets[{i}]: \
                     give a joint path on the targets (e.g. a branch of ik_trajectory)"
                )));
            }
            if let Some(j) = (0..dof).find(|&j| q[j] < lower[j] || q[j] > upper[j]) {
                return Err(error(format!("q[{i}, {j}] is outside the joint limits")));
            }
            if i > 0 {
                let step = q
                    .iter()
                    .zip(&seed[i - 1])
                    .map(|(a, b)| (a - b).abs())
                    .fold(0.0, f64::max);
                if step > max_joint_step {
                    return Err(error(format!(
                        "q moves a joint {step:.3} between samples {} and {i}, more than \
                         max_joint_step ({max_joint_step})",
                        i - 1
                    )));
                }
            }
        }
        let directions: Vec<Option<Direction>> = (0..n)
            .map(|i| {
                let (a, b) = if i + 1 < n {
                    (i, i + 1)
                } else {
                    (i.saturating_sub(1), i)
                };
                (a != b)
                    .then(|| wrist_tangent(&targets[a], &targets[b], rows))
                    .flatten()
            })
            .collect();
        let value = |i: usize, _: &[f64], jacobian: &Matrix6xX<f64>| -> f64 {
            directions[i].map_or(0.0, |d| rows.task_relevant(jacobian, &d).powi(2))
        };
        let chain = &self.chain;
        let found = py
            .detach(|| {
                optimize_self_motion(chain, &targets, &[&seed], KeptRows::Pose, &value, &options)
            })
            .ok_or_else(|| error("no joint path was found around q"))?;
        let seed_total: f64 = {
            let mut jacobian = Matrix6xX::zeros(dof);
            seed.iter()
                .enumerate()
                .map(|(i, q)| {
                    chain
                        .pose_and_jacobian_into(q, &mut jacobian)
                        .map_or(0.0, |_| value(i, q, &jacobian))
                })
                .sum()
        };
        let m_t: Vec<f64> = found
            .values
            .iter()
            .zip(&directions)
            .map(|(v, d)| if d.is_some() { v.sqrt() } else { f64::NAN })
            .collect();
        let dict = PyDict::new(py);
        let flat: Vec<f64> = found.q.iter().flatten().copied().collect();
        dict.set_item("q", array(py, flat, &[n, dof])?)?;
        dict.set_item("m_t", PyArray1::from_vec(py, m_t))?;
        dict.set_item("mu_l2", found.total.sqrt())?;
        dict.set_item("mu_l2_seed", seed_total.sqrt())?;
        dict.set_item("mu_l2_min", found.worst_total.sqrt())?;
        Ok(dict)
    }
}

/// The kept rows of the self-motion by name: `pose` or `position`.
fn kept_rows(rows: &str) -> PyResult<KeptRows> {
    match rows {
        "pose" => Ok(KeptRows::Pose),
        "position" => Ok(KeptRows::Position),
        other => Err(error(format!(
            "rows '{other}' is not one of 'pose', 'position'"
        ))),
    }
}
