//! The forward kinematics of `graspath.Robot` (`fk`, `jacobian`, `fk_jacobian`,
//! `within_limits`) over one configuration or a batch: written in place in parallel without
//! the GIL, into new numpy arrays or the caller's.
//!
//! Poses `base_from_tip` and Jacobians (rows `[v; ω]`) in the chain **base frame**, metres.
//! The `#[pymethods]` wrappers are in `robot.rs` (PyO3 wants one block per class).

use super::PyRobot;
use crate::convert::{
    check_finite, error, lib_error, non_finite_error, row_major, shape_text, FloatArray,
};
use crate::memory::{kinematics_into, split_rows, split_rows_ref, ResultArray};
use graspath::robot::RobotError;
use numpy::{PyArray1, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyBool;
use rayon::prelude::*;
use std::borrow::Cow;

/// Configurations per rayon task of `within_limits` (a few comparisons each).
const SCALAR_CHUNK: usize = 4096;

impl PyRobot {
    /// Whether each configuration of `q` (`(dof,)` or `(n, dof)`) is within the joint
    /// limits: what `Robot.within_limits` returns.
    pub(super) fn limit_flags<'py>(
        &self,
        py: Python<'py>,
        q: FloatArray<'py>,
    ) -> PyResult<Py<PyAny>> {
        let dof = self.chain.dof();
        let (data, batch) = self.configurations(&q)?;
        let Some(n) = batch else {
            return Ok(PyBool::new(py, self.chain.within_limits(&data))
                .to_owned()
                .into_any()
                .unbind());
        };
        let flags = PyArray1::<bool>::zeros(py, n, false);
        let mut guard = flags.try_readwrite().map_err(|e| error(e.to_string()))?;
        let out = guard.as_slice_mut().map_err(|e| error(e.to_string()))?;
        let chain = &self.chain;
        py.detach(|| {
            split_rows_ref(&data, dof, n, SCALAR_CHUNK)
                .into_par_iter()
                .zip(split_rows(out, 1, n, SCALAR_CHUNK))
                .for_each(|(q, out)| {
                    for (k, flag) in out.iter_mut().enumerate() {
                        *flag = chain.within_limits(&q[k * dof..(k + 1) * dof]);
                    }
                });
        });
        drop(guard);
        Ok(flags.into_any().unbind())
    }

    /// Poses and/or Jacobians of `q`: each wanted result (`Some`) goes into a new array
    /// (`Some(None)`) or into the caller's (`Some(Some(out))`), written in place in parallel
    /// without the GIL.
    #[allow(clippy::type_complexity)]
    pub(super) fn evaluate<'py>(
        &self,
        py: Python<'py>,
        q: FloatArray<'py>,
        poses: Option<Option<Bound<'py, PyAny>>>,
        jacobians: Option<Option<Bound<'py, PyAny>>>,
    ) -> PyResult<(Option<Py<PyAny>>, Option<Py<PyAny>>)> {
        let dof = self.chain.dof();
        let (data, batch) = self.configurations_unchecked(&q)?;
        let lead: Vec<usize> = batch.into_iter().collect();
        let shape = |tail: &[usize]| [lead.as_slice(), tail].concat();
        let poses = poses
            .map(|out| ResultArray::new(py, out, &shape(&[4, 4]), "out (poses)"))
            .transpose()?;
        let jacobians = jacobians
            .map(|out| ResultArray::new(py, out, &shape(&[6, dof]), "out (jacobians)"))
            .transpose()?;
        let mut pose_guard = poses.as_ref().map(ResultArray::writer).transpose()?;
        let mut jacobian_guard = jacobians.as_ref().map(ResultArray::writer).transpose()?;
        let fresh =
            poses.as_ref().is_some_and(|a| a.fresh) || jacobians.as_ref().is_some_and(|a| a.fresh);
        let pose_slice = pose_guard
            .as_mut()
            .map(|g| g.as_slice_mut())
            .transpose()
            .map_err(|e| error(e.to_string()))?;
        let jacobian_slice = jacobian_guard
            .as_mut()
            .map(|g| g.as_slice_mut())
            .transpose()
            .map_err(|e| error(e.to_string()))?;
        let chain = &self.chain;
        py.detach(|| kinematics_into(chain, &data, pose_slice, jacobian_slice, fresh))
            .map_err(|e| match e {
                RobotError::NonFiniteJoint { index } => {
                    non_finite_error(index, dof, "q", batch.is_some())
                }
                e => lib_error(e),
            })?;
        drop((pose_guard, jacobian_guard));
        Ok((
            poses.map(ResultArray::unbind),
            jacobians.map(ResultArray::unbind),
        ))
    }

    /// Configurations from `(dof,)` or `(n, dof)`, checked finite: row-major values (the
    /// array's own memory when it is C-contiguous float64) and `Some(n)` for the batch form.
    pub(super) fn configurations<'a>(
        &self,
        q: &'a FloatArray<'_>,
    ) -> PyResult<(Cow<'a, [f64]>, Option<usize>)> {
        let (data, batch) = self.configurations_unchecked(q)?;
        check_finite(&data, self.chain.dof(), "q", batch.is_some())?;
        Ok((data, batch))
    }

    /// [`Self::configurations`] without the finiteness check (for calls whose kernel checks).
    pub(super) fn configurations_unchecked<'a>(
        &self,
        q: &'a FloatArray<'_>,
    ) -> PyResult<(Cow<'a, [f64]>, Option<usize>)> {
        let dof = self.chain.dof();
        let batch = match q.shape() {
            [w] if *w == dof => None,
            [n, w] if *w == dof => Some(*n),
            shape => {
                return Err(error(format!(
                    "q has shape {} but the chain '{}' has {dof} joints: expected ({dof},) or \
                     (n, {dof})",
                    shape_text(shape),
                    self.chain.name()
                )))
            }
        };
        Ok((row_major(q, "q")?, batch))
    }
}
