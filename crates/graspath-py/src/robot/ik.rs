//! The inverse kinematics of `graspath.Robot` (`ik`, `ik_trajectory`): one pose or many
//! solved in parallel without the GIL, each result written once into new numpy arrays, and
//! the dicts the calls return.
//!
//! Poses are tip poses in the chain **base frame** (metres); configurations in radians (or
//! metres for a prismatic joint). The `#[pymethods]` wrappers are in `robot.rs` (PyO3 wants
//! one block per class).

use super::PyRobot;
use crate::convert::{array, error, lib_error, poses, rows, trajectories, FloatArray};
use crate::memory::new_float_array;
use graspath::robot::{
    solve_ik, solve_trajectories, IkOptions, IkSolution, TrajectoryIkOptions, TrajectoryIkResult,
};
use nalgebra::Isometry3;
use numpy::{PyArray1, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use rayon::prelude::*;
use std::time::Duration;

impl PyRobot {
    /// Solves one target pose `(4, 4)` or many `(n, 4, 4)` from `q_start` (`(dof,)` shared,
    /// `(n, dof)` one per pose, default the middle of the limits): the dict `Robot.ik`
    /// returns.
    pub(super) fn solve_poses<'py>(
        &self,
        py: Python<'py>,
        target: FloatArray<'py>,
        q_start: Option<FloatArray<'py>>,
        options: IkOptions,
    ) -> PyResult<Bound<'py, PyDict>> {
        let dof = self.chain.dof();
        if dof == 0 {
            return Err(error(format!(
                "the chain '{}' has no joints: there is nothing to solve for",
                self.chain.name()
            )));
        }
        let (targets, batch) = poses(&target, "target")?;
        let n = targets.len();
        let starts: Vec<f64> = match &q_start {
            None => self.chain.mid_configuration().repeat(n),
            Some(s) => {
                let (data, start_batch) = rows(s, dof, "q_start")?;
                match (start_batch, batch) {
                    (None, _) => data.repeat(n),
                    (Some(m), Some(n)) if m == n => data,
                    (Some(m), _) => {
                        return Err(error(format!(
                            "q_start has {m} rows but there are {n} target pose(s); give one \
                             start configuration (dof,) or one per pose (n, dof)"
                        )))
                    }
                }
            }
        };
        let chain = &self.chain;
        let dict = PyDict::new(py);
        let Some(n) = batch else {
            let s = py
                .detach(|| solve_ik(chain, &targets[0], &starts, &options))
                .map_err(lib_error)?;
            dict.set_item("q", s.q.clone().map(|q| PyArray1::from_vec(py, q)))?;
            dict.set_item("converged", s.converged())?;
            dict.set_item("position_error", s.position_error)?;
            dict.set_item("rotation_error", s.rotation_error)?;
            dict.set_item("iterations", s.iterations)?;
            match &s.failure {
                None => dict.set_item("failure", py.None())?,
                Some(f) => {
                    let failure = PyDict::new(py);
                    failure.set_item("reason", failure_reason(&s))?;
                    failure.set_item("best_q", PyArray1::from_vec(py, f.best_q.clone()))?;
                    failure.set_item("attempts", f.attempts)?;
                    failure.set_item("message", f.to_string())?;
                    dict.set_item("failure", failure)?;
                }
            }
            return Ok(dict);
        };
        // Every result is written once, in place, by the task that solves its pose.
        let q_out = new_float_array(py, &[n, dof])?;
        let best_out = new_float_array(py, &[n, dof])?;
        let converged_out = PyArray1::<bool>::zeros(py, n, false);
        let errors_out = [new_float_array(py, &[n])?, new_float_array(py, &[n])?];
        let iterations_out = PyArray1::<i64>::zeros(py, n, false);
        let mut reasons: Vec<Option<&'static str>> = vec![None; n];
        {
            let mut q_guard = q_out.try_readwrite().map_err(|e| error(e.to_string()))?;
            let mut best_guard = best_out.try_readwrite().map_err(|e| error(e.to_string()))?;
            let mut converged_guard = converged_out
                .try_readwrite()
                .map_err(|e| error(e.to_string()))?;
            let mut position_guard = errors_out[0]
                .try_readwrite()
                .map_err(|e| error(e.to_string()))?;
            let mut rotation_guard = errors_out[1]
                .try_readwrite()
                .map_err(|e| error(e.to_string()))?;
            let mut iterations_guard = iterations_out
                .try_readwrite()
                .map_err(|e| error(e.to_string()))?;
            let q_rows = q_guard.as_slice_mut().map_err(|e| error(e.to_string()))?;
            let best_rows = best_guard
                .as_slice_mut()
                .map_err(|e| error(e.to_string()))?;
            let converged = converged_guard
                .as_slice_mut()
                .map_err(|e| error(e.to_string()))?;
            let position = position_guard
                .as_slice_mut()
                .map_err(|e| error(e.to_string()))?;
            let rotation = rotation_guard
                .as_slice_mut()
                .map_err(|e| error(e.to_string()))?;
            let iterations = iterations_guard
                .as_slice_mut()
                .map_err(|e| error(e.to_string()))?;
            let failed = py.detach(|| {
                q_rows
                    .par_chunks_mut(dof.max(1))
                    .zip(best_rows.par_chunks_mut(dof.max(1)))
                    .zip(converged.par_iter_mut())
                    .zip(position.par_iter_mut())
                    .zip(rotation.par_iter_mut())
                    .zip(iterations.par_iter_mut())
                    .zip(reasons.par_iter_mut())
                    .zip(targets.par_iter())
                    .zip(starts.par_chunks(dof.max(1)))
                    .enumerate()
                    .map(|(k, item)| {
                        let (
                            (
                                (
                                    (((((q, best), converged), position), rotation), iterations),
                                    reason,
                                ),
                                target,
                            ),
                            start,
                        ) = item;
                        let s = solve_ik(chain, target, start, &options).map_err(|e| (k, e))?;
                        match (&s.q, &s.failure) {
                            (Some(v), _) => {
                                copy_into(q, v);
                                copy_into(best, v);
                            }
                            (None, failure) => {
                                q.fill(f64::NAN);
                                match failure {
                                    Some(f) => copy_into(best, &f.best_q),
                                    None => best.fill(f64::NAN),
                                }
                            }
                        }
                        *converged = s.converged();
                        *position = s.position_error;
                        *rotation = s.rotation_error;
                        *iterations = s.iterations as i64;
                        *reason = failure_reason(&s);
                        Ok(())
                    })
                    .filter_map(Result::err)
                    .min_by_key(|(k, _)| *k)
            });
            if let Some((_, e)) = failed {
                return Err(lib_error(e));
            }
        }
        dict.set_item("q", q_out)?;
        dict.set_item("best_q", best_out)?;
        dict.set_item("converged", converged_out)?;
        let [position_error, rotation_error] = errors_out;
        dict.set_item("position_error", position_error)?;
        dict.set_item("rotation_error", rotation_error)?;
        dict.set_item("iterations", iterations_out)?;
        dict.set_item("failure_reason", PyList::new(py, reasons)?)?;
        Ok(dict)
    }

    /// Solves one trajectory of tip poses `(n, 4, 4)` or a batch `(b, n, 4, 4)` from
    /// `q_start` (`(dof,)`, default the middle of the limits): the dict (or the list of dicts)
    /// `Robot.ik_trajectory` returns.
    pub(super) fn solve_pose_trajectories<'py>(
        &self,
        py: Python<'py>,
        targets: FloatArray<'py>,
        q_start: Option<FloatArray<'py>>,
        options: TrajectoryIkOptions,
    ) -> PyResult<Bound<'py, PyAny>> {
        let dof = self.chain.dof();
        let (trajectories, batch) = trajectories(&targets, "targets")?;
        let q_start = match &q_start {
            None => self.chain.mid_configuration(),
            Some(s) => match rows(s, dof, "q_start")? {
                (data, None) => data,
                (_, Some(_)) => return Err(error("q_start must have shape (dof,)")),
            },
        };
        let chain = &self.chain;
        let batch_of: Vec<&[Isometry3<f64>]> = trajectories.iter().map(Vec::as_slice).collect();
        let results = py
            .detach(|| solve_trajectories(chain, &batch_of, &q_start, &options))
            .map_err(lib_error)?;
        let mut dicts = Vec::with_capacity(results.len());
        for (k, result) in results.into_iter().enumerate() {
            let result = match (result, batch) {
                (Ok(result), _) => result,
                (Err(e), None) => return Err(lib_error(e)),
                (Err(e), Some(_)) => return Err(error(format!("targets[{k}]: {e}"))),
            };
            dicts.push(trajectory_dict(py, &result, dof)?);
        }
        match batch {
            None => Ok(dicts.remove(0).into_any()),
            Some(_) => Ok(PyList::new(py, dicts)?.into_any()),
        }
    }
}

/// The IK settings shared by `ik` and `ik_trajectory`.
pub(super) fn ik_options(
    position_tolerance: f64,
    rotation_tolerance: f64,
    max_iterations: usize,
    max_time: Option<f64>,
    random_seed: u64,
) -> PyResult<IkOptions> {
    let max_time = match max_time {
        None => None,
        Some(t) => match Duration::try_from_secs_f64(t) {
            Ok(budget) if t > 0.0 => Some(budget),
            _ => {
                return Err(error(format!(
                    "option 'max_time': must be a positive number of seconds (at most about 1.8e19) or None, got {t}"
                )))
            }
        },
    };
    Ok(IkOptions {
        position_tolerance,
        rotation_tolerance,
        max_time,
        max_iterations,
        random_seed,
    })
}

/// Copies `values` into `out` (as many as both hold).
fn copy_into(out: &mut [f64], values: &[f64]) {
    for (o, v) in out.iter_mut().zip(values) {
        *o = *v;
    }
}

fn failure_reason(solution: &IkSolution) -> Option<&'static str> {
    solution.failure.as_ref().map(|f| f.reason.as_str())
}

/// The dict `Robot.ik_trajectory` returns for one trajectory's result (`dof` joints).
fn trajectory_dict<'py>(
    py: Python<'py>,
    result: &TrajectoryIkResult,
    dof: usize,
) -> PyResult<Bound<'py, PyDict>> {
    let dict = PyDict::new(py);
    dict.set_item("feasible", result.feasible())?;
    let list = PyList::empty(py);
    for branch in &result.branches {
        let flat: Vec<f64> = branch.q.iter().flatten().copied().collect();
        list.append(array(py, flat, &[branch.q.len(), dof])?)?;
    }
    dict.set_item("branches", list)?;
    match &result.failure {
        None => dict.set_item("failure", py.None())?,
        Some(f) => {
            let failure = PyDict::new(py);
            failure.set_item("sample", f.sample)?;
            failure.set_item("reason", f.reason.as_str())?;
            failure.set_item("detail", &f.detail)?;
            dict.set_item("failure", failure)?;
        }
    }
    Ok(dict)
}
