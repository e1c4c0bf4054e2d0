//! The manipulability indices of `graspath.Robot` (`indices`, `task_relevant`,
//! `velocity_transmission_ratio`): one configuration, or a batch evaluated in parallel without
//! the GIL, each value written once into a new numpy array.
//!
//! The Jacobian is the chain's geometric Jacobian in the **base frame**, rows `[v; ω]`; the
//! `#[pymethods]` wrappers are in `robot.rs` (PyO3 wants one block per class).

use super::PyRobot;
use crate::convert::{error, lib_error, rows, spelled, FloatArray};
use crate::memory::{new_float_array, split_rows, split_rows_ref};
use graspath::manipulability::{singular_values, ClassicalIndices, Direction, JacobianPart};
use nalgebra::{Matrix6xX, Vector3, Vector6};
use numpy::{PyArray1, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rayon::prelude::*;

/// Configurations per rayon task of the index calls (an SVD or a projection each).
const INDEX_CHUNK: usize = 64;

impl PyRobot {
    /// The classical indices of the rows `part` of the Jacobian at `q` (`(dof,)` or
    /// `(n, dof)`): the dict `Robot.indices` returns.
    pub(super) fn classical_indices<'py>(
        &self,
        py: Python<'py>,
        q: FloatArray<'py>,
        part: &str,
    ) -> PyResult<Bound<'py, PyDict>> {
        let part = part_of(part)?;
        let dof = self.chain.dof();
        let (data, batch) = self.configurations(&q)?;
        let chain = &self.chain;
        let names = [
            "yoshikawa",
            "inverse_condition",
            "inverse_condition_squared",
        ];
        let dict = PyDict::new(py);
        let Some(n) = batch else {
            let mut jacobian = Matrix6xX::zeros(dof);
            chain
                .pose_and_jacobian_into(&data, &mut jacobian)
                .map_err(lib_error)?;
            let values = singular_values(&jacobian, part);
            let indices = ClassicalIndices::from_singular_values(&values);
            dict.set_item(names[0], indices.yoshikawa)?;
            dict.set_item(names[1], indices.inverse_condition)?;
            dict.set_item(names[2], indices.inverse_condition_squared)?;
            dict.set_item("singular_values", PyArray1::from_vec(py, values))?;
            return Ok(dict);
        };
        let rows = if part == JacobianPart::Full { 6 } else { 3 };
        let columns = [
            new_float_array(py, &[n])?,
            new_float_array(py, &[n])?,
            new_float_array(py, &[n])?,
        ];
        let singular = new_float_array(py, &[n, rows])?;
        let mut guards = columns
            .iter()
            .map(|c| c.try_readwrite().map_err(|e| error(e.to_string())))
            .collect::<PyResult<Vec<_>>>()?;
        let mut singular_guard = singular.try_readwrite().map_err(|e| error(e.to_string()))?;
        let [yoshikawa_out, condition_out, squared_out] = match guards.as_mut_slice() {
            [a, b, c] => [a, b, c].map(|g| g.as_slice_mut().map_err(|e| error(e.to_string()))),
            _ => return Err(error("three index columns")),
        };
        let (yoshikawa_out, condition_out, squared_out) =
            (yoshikawa_out?, condition_out?, squared_out?);
        let singular_out = singular_guard
            .as_slice_mut()
            .map_err(|e| error(e.to_string()))?;
        py.detach(|| {
            split_rows_ref(&data, dof, n, INDEX_CHUNK)
                .into_par_iter()
                .zip(split_rows(yoshikawa_out, 1, n, INDEX_CHUNK))
                .zip(split_rows(condition_out, 1, n, INDEX_CHUNK))
                .zip(split_rows(squared_out, 1, n, INDEX_CHUNK))
                .zip(split_rows(singular_out, rows, n, INDEX_CHUNK))
                .for_each_init(
                    || Matrix6xX::zeros(dof),
                    |jacobian, ((((q, yoshikawa), condition), squared), singular)| {
                        for (k, (y, (c, s))) in yoshikawa
                            .iter_mut()
                            .zip(condition.iter_mut().zip(squared.iter_mut()))
                            .enumerate()
                        {
                            let out = &mut singular[k * rows..(k + 1) * rows];
                            // The rows were checked (length, finite values): the call cannot
                            // fail, and NaN would mark it if it did.
                            let values = match chain
                                .pose_and_jacobian_into(&q[k * dof..(k + 1) * dof], jacobian)
                            {
                                Ok(_) => singular_values(jacobian, part),
                                Err(_) => vec![f64::NAN; rows],
                            };
                            let indices = ClassicalIndices::from_singular_values(&values);
                            (*y, *c, *s) = (
                                indices.yoshikawa,
                                indices.inverse_condition,
                                indices.inverse_condition_squared,
                            );
                            for (o, v) in out.iter_mut().zip(&values) {
                                *o = *v;
                            }
                        }
                    },
                );
        });
        drop(guards);
        drop(singular_guard);
        for (name, column) in names.iter().zip(columns) {
            dict.set_item(name, column)?;
        }
        dict.set_item("singular_values", singular)?;
        Ok(dict)
    }

    /// Evaluates a per-configuration directional index in parallel, each value written once
    /// into the result array.
    pub(super) fn directional<'py>(
        &self,
        py: Python<'py>,
        q: FloatArray<'py>,
        u: FloatArray<'py>,
        part: &str,
        index: fn(&Matrix6xX<f64>, &Direction) -> f64,
    ) -> PyResult<Py<PyAny>> {
        let part = part_of(part)?;
        let width = if part == JacobianPart::Full { 6 } else { 3 };
        let dof = self.chain.dof();
        let (data, batch) = self.configurations(&q)?;
        let n = batch.unwrap_or(1);
        let (directions, direction_batch) = rows(&u, width, "u")?;
        if let Some(m) = direction_batch {
            if m != n || batch.is_none() {
                return Err(error(format!(
                    "u has {m} rows but there are {n} configuration(s); give one direction \
                     ({width},) or one per configuration (n, {width})"
                )));
            }
        }
        let mut units = Vec::with_capacity(directions.len());
        for (k, d) in directions.chunks(width).enumerate() {
            let norm = d.iter().map(|v| v * v).sum::<f64>().sqrt();
            if !(norm.is_finite() && norm > 0.0) {
                return Err(error(format!("u[{k}] must be a finite non-zero direction")));
            }
            units.extend(d.iter().map(|v| v / norm));
        }
        let shared = direction_batch.is_none();
        let chain = &self.chain;
        let value = |jacobian: &mut Matrix6xX<f64>, i: usize, qi: &[f64]| -> f64 {
            let k = if shared { 0 } else { i };
            let direction = direction_of(part, &units[k * width..(k + 1) * width]);
            // The rows were checked (length, finite values): the call cannot fail, and NaN
            // would mark it if it did.
            match chain.pose_and_jacobian_into(qi, jacobian) {
                Ok(_) => index(jacobian, &direction),
                Err(_) => f64::NAN,
            }
        };
        let Some(n) = batch else {
            let result = value(&mut Matrix6xX::zeros(dof), 0, &data);
            return Ok(result.into_pyobject(py)?.into_any().unbind());
        };
        let values = new_float_array(py, &[n])?;
        let mut guard = values.try_readwrite().map_err(|e| error(e.to_string()))?;
        let out = guard.as_slice_mut().map_err(|e| error(e.to_string()))?;
        py.detach(|| {
            split_rows_ref(&data, dof, n, INDEX_CHUNK)
                .into_par_iter()
                .zip(split_rows(out, 1, n, INDEX_CHUNK))
                .enumerate()
                .for_each_init(
                    || Matrix6xX::zeros(dof),
                    |jacobian, (chunk, (q, out))| {
                        for (k, o) in out.iter_mut().enumerate() {
                            let i = chunk * INDEX_CHUNK + k;
                            *o = value(jacobian, i, &q[k * dof..(k + 1) * dof]);
                        }
                    },
                );
        });
        drop(guard);
        Ok(values.into_any().unbind())
    }
}

fn part_of(part: &str) -> PyResult<JacobianPart> {
    spelled("part", part)
}

fn direction_of(part: JacobianPart, u: &[f64]) -> Direction {
    match part {
        JacobianPart::Full => Direction::Full(Vector6::from_column_slice(u)),
        JacobianPart::Translation => Direction::Translation(Vector3::from_column_slice(u)),
        JacobianPart::Rotation => Direction::Rotation(Vector3::from_column_slice(u)),
    }
}
