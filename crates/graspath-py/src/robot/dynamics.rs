//! The rigid-body dynamics of `graspath.Robot` (`gravity_torques`, `inverse_dynamics`,
//! `mass_matrix`): reading the gravity vector and the payload dict, and evaluating one
//! configuration or a batch (in parallel, without the GIL) into new numpy arrays.
//!
//! Frames and units as in `graspath::robot::Dynamics`: the gravity vector and every result
//! in the chain **base frame**; the payload in the **tool frame**; kg, m, kg·m², N·m.
//! The `#[pymethods]` wrappers are in `robot.rs` (PyO3 wants one block per class).

use super::PyRobot;
use crate::convert::{array, check_finite, error, lib_error, row_major, shape_text, FloatArray};
use crate::memory::{new_float_array, split_rows};
use graspath::robot::{Dynamics, DynamicsData, MotionLimits, RigidBody, RobotError};
use graspath::task::{MAX_CENTER_OF_MASS_DISTANCE, MAX_PAYLOAD_MASS};
use nalgebra::{DMatrix, Matrix3, Vector3};
use numpy::{PyArray1, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rayon::prelude::*;
use std::borrow::Cow;

/// Configurations per rayon task of the dynamics calls (under a microsecond each).
const DYNAMICS_CHUNK: usize = 64;

/// The keys of a payload dict.
const PAYLOAD_KEYS: [&str; 3] = ["mass", "com", "inertia"];

/// What a dynamics call computes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Quantity {
    /// `g(q)`, `(dof,)` per configuration.
    Gravity,
    /// `τ(q, q̇, q̈)` by RNEA, `(dof,)` per configuration.
    InverseDynamics,
    /// `M(q)` by CRBA, `(dof, dof)` per configuration.
    MassMatrix,
}

/// The joint states of one call: row-major `(dof,)` or `(n, dof)` values, checked.
pub(super) struct States<'a> {
    pub q: Cow<'a, [f64]>,
    pub qd: Option<Cow<'a, [f64]>>,
    pub qdd: Option<Cow<'a, [f64]>>,
    /// `Some(n)` for the batch form `(n, dof)`.
    pub batch: Option<usize>,
}

impl PyRobot {
    /// The chain's dynamics model with standard gravity; a `GraspathError` naming the robot
    /// and the links when a moving link has no inertial data.
    pub(super) fn dynamics_model(&self) -> PyResult<&Dynamics> {
        self.dynamics
            .get_or_init(|| self.chain.dynamics().map_err(|e| e.to_string()))
            .as_ref()
            .map_err(|e| error(e.as_str()))
    }

    /// A dynamics call's model (with `gravity` when given), states and payload, checked, and
    /// its result.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn dynamics_call<'py>(
        &self,
        py: Python<'py>,
        quantity: Quantity,
        q: &FloatArray<'py>,
        qd: Option<&FloatArray<'py>>,
        qdd: Option<&FloatArray<'py>>,
        gravity: Option<&FloatArray<'py>>,
        payload: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Py<PyAny>> {
        let model = self.dynamics_model()?;
        let (q_values, batch) = self.configurations(q)?;
        let dof = self.chain.dof();
        let states = States {
            q: q_values,
            qd: like_q(qd, q.shape(), dof, "qd")?,
            qdd: like_q(qdd, q.shape(), dof, "qdd")?,
            batch,
        };
        let gravity = gravity_vector(gravity, model.gravity())?;
        let payload = payload_body(payload, "tool")?;
        let model = if gravity == model.gravity() {
            Cow::Borrowed(model)
        } else {
            Cow::Owned(model.clone().with_gravity(gravity).map_err(lib_error)?)
        };
        evaluate(py, &model, payload, quantity, &states)
    }

    /// One of the joints' motion limits, `+inf` where unknown.
    pub(super) fn limits<'py>(
        &self,
        py: Python<'py>,
        limit: fn(&MotionLimits) -> Option<f64>,
    ) -> Bound<'py, PyArray1<f64>> {
        let values: Vec<f64> = self
            .chain
            .motion_limits()
            .iter()
            .map(|l| limit(l).unwrap_or(f64::INFINITY))
            .collect();
        PyArray1::from_vec(py, values)
    }
}

/// Joint velocities or accelerations `what` of `q`'s shape (`(dof,)` or `(n, dof)`),
/// row-major and checked finite.
pub(super) fn like_q<'a>(
    array: Option<&'a FloatArray<'_>>,
    q_shape: &[usize],
    dof: usize,
    what: &str,
) -> PyResult<Option<Cow<'a, [f64]>>> {
    let Some(array) = array else {
        return Ok(None);
    };
    if array.shape() != q_shape {
        return Err(error(format!(
            "{what} has shape {} but q has shape {}: give one value per joint of each \
             configuration",
            shape_text(array.shape()),
            shape_text(q_shape)
        )));
    }
    let values = row_major(array, what)?;
    check_finite(&values, dof, what, q_shape.len() == 2)?;
    Ok(Some(values))
}

/// The gravity vector (base frame, m/s²) from an optional `(3,)` array; `None` is the
/// model's default (9.81 m/s² along the base's −z).
pub(super) fn gravity_vector(
    gravity: Option<&FloatArray<'_>>,
    default: Vector3<f64>,
) -> PyResult<Vector3<f64>> {
    let Some(gravity) = gravity else {
        return Ok(default);
    };
    if gravity.shape() != [3] {
        return Err(error(format!(
            "gravity has shape {} but (3,) is expected (a vector in the chain's base frame, m/s²)",
            shape_text(gravity.shape())
        )));
    }
    let values = row_major(gravity, "gravity")?;
    check_finite(&values, 3, "gravity", false)?;
    Ok(Vector3::from_column_slice(&values))
}

/// A payload from `None` or a dict `{"mass": kg, "com": (3,) m, "inertia": (3, 3) or (3,)
/// kg·m²}` in the frame named `frame` (`tool` for a robot's dynamics calls, `object` for a
/// task's carried object; `com` defaults to its origin, `inertia` to zero: a point mass). Every
/// value is checked; errors name the key.
pub(crate) fn payload_body(
    payload: Option<&Bound<'_, PyAny>>,
    frame: &str,
) -> PyResult<Option<RigidBody>> {
    let Some(payload) = payload else {
        return Ok(None);
    };
    if payload.is_none() {
        return Ok(None);
    }
    let dict = payload.cast::<PyDict>().map_err(|_| {
        error(format!(
            "payload must be None or a dict {{'mass': kg, 'com': [x, y, z] ({frame} frame, m), \
             'inertia': 3x3 or [ixx, iyy, izz] (kg·m² about the centre of mass)}}"
        ))
    })?;
    for key in dict.keys() {
        let known = key
            .extract::<String>()
            .is_ok_and(|k| PAYLOAD_KEYS.contains(&k.as_str()));
        if !known {
            return Err(error(format!(
                "payload has an unknown key {}: the keys are 'mass', 'com' and 'inertia'",
                key.repr()
                    .map_or_else(|_| "?".to_string(), |r| r.to_string())
            )));
        }
    }
    let mass = match dict.get_item("mass")? {
        None => return Err(error("payload['mass'] is missing (kg)")),
        Some(value) => value
            .extract::<f64>()
            .map_err(|_| error("payload['mass'] must be a number (kg)"))?,
    };
    if !(mass.is_finite() && mass >= 0.0) {
        return Err(error(format!(
            "payload['mass'] must be a finite non-negative mass (kg), got {mass}"
        )));
    }
    if mass > MAX_PAYLOAD_MASS {
        return Err(error(format!(
            "payload['mass'] is {mass} kg, more than {MAX_PAYLOAD_MASS} kg: is it in grams? Give \
             kilograms"
        )));
    }
    let com = match dict.get_item("com")? {
        None => Vector3::zeros(),
        Some(value) => {
            let (values, _) = float_values(
                &value,
                "payload['com']",
                &[&[3]],
                &format!("(3,) ({frame} frame, m)"),
            )?;
            check_finite(&values, 3, "payload['com']", false)?;
            Vector3::from_column_slice(&values)
        }
    };
    if com.norm() > MAX_CENTER_OF_MASS_DISTANCE {
        return Err(error(format!(
            "payload['com'] is {:.3} m from the {frame} frame's origin, more than \
             {MAX_CENTER_OF_MASS_DISTANCE} m: is it in millimetres? Give metres",
            com.norm()
        )));
    }
    let inertia = match dict.get_item("inertia")? {
        None => Matrix3::zeros(),
        Some(value) => {
            let (values, shape) = float_values(
                &value,
                "payload['inertia']",
                &[&[3, 3], &[3]],
                "(3, 3) or (3,) (the principal moments ixx, iyy, izz; kg·m² about the centre \
                 of mass)",
            )?;
            let matrix = shape.len() == 2;
            check_finite(&values, 3, "payload['inertia']", matrix)?;
            if matrix {
                Matrix3::from_row_slice(&values)
            } else {
                Matrix3::from_diagonal(&Vector3::from_column_slice(&values))
            }
        }
    };
    let body = RigidBody::new(mass, com, inertia);
    if !body.is_valid() {
        return Err(error(format!(
            "payload['inertia'] must be symmetric with a non-negative diagonal (kg·m² about the \
             centre of mass), got {:?}",
            [inertia.row(0), inertia.row(1), inertia.row(2)].map(|r| [r[0], r[1], r[2]])
        )));
    }
    Ok(Some(body))
}

/// Row-major float64 values and the shape of a payload entry of one of the shapes `allowed`
/// (`expected` says which in the error); `what` names it.
fn float_values(
    value: &Bound<'_, PyAny>,
    what: &str,
    allowed: &[&[usize]],
    expected: &str,
) -> PyResult<(Vec<f64>, Vec<usize>)> {
    let array = value
        .extract::<FloatArray<'_>>()
        .map_err(|e| error(format!("{what} must be an array of numbers: {e}")))?;
    let shape = array.shape().to_vec();
    if !allowed.contains(&shape.as_slice()) {
        return Err(error(format!(
            "{what} has shape {} but {expected} is expected",
            shape_text(&shape)
        )));
    }
    Ok((row_major(&array, what)?.into_owned(), shape))
}

/// The shape of one configuration's result.
fn tail(quantity: Quantity, dof: usize) -> Vec<usize> {
    match quantity {
        Quantity::MassMatrix => vec![dof, dof],
        Quantity::Gravity | Quantity::InverseDynamics => vec![dof],
    }
}

/// One thread's workspace: the kernels' data (with the payload) and a mass matrix.
struct Workspace {
    data: DynamicsData,
    mass: DMatrix<f64>,
}

impl Workspace {
    fn new(model: &Dynamics, payload: Option<RigidBody>) -> Result<Self, RobotError> {
        let mut data = model.data();
        data.set_payload(payload)?;
        let dof = model.dof();
        Ok(Self {
            data,
            mass: DMatrix::zeros(dof, dof),
        })
    }

    /// Configuration `i` of `states` into `out` (`dof` or `dof²` values, row-major).
    fn evaluate(
        &mut self,
        model: &Dynamics,
        quantity: Quantity,
        states: &States<'_>,
        i: usize,
        out: &mut [f64],
    ) -> Result<(), RobotError> {
        let dof = model.dof();
        let row = i * dof..(i + 1) * dof;
        let q = &states.q[row.clone()];
        match quantity {
            Quantity::Gravity => model.gravity_torques_into(&mut self.data, q, out),
            Quantity::InverseDynamics => {
                let (Some(qd), Some(qdd)) = (&states.qd, &states.qdd) else {
                    return Err(RobotError::BadDynamicsInput {
                        what: "qd",
                        message: "is missing".to_string(),
                    });
                };
                model.inverse_dynamics_into(&mut self.data, q, &qd[row.clone()], &qdd[row], out)
            }
            Quantity::MassMatrix => {
                model.mass_matrix_into(&mut self.data, q, &mut self.mass)?;
                for (r, out_row) in out.chunks_mut(dof.max(1)).enumerate() {
                    for (c, o) in out_row.iter_mut().enumerate() {
                        *o = self.mass[(r, c)];
                    }
                }
                Ok(())
            }
        }
    }
}

/// Evaluates `quantity` at every configuration of `states` into a new array: `(dof,)` /
/// `(dof, dof)` for one, `(n, dof)` / `(n, dof, dof)` for a batch (in parallel, GIL released;
/// each row the value of the single call, bit for bit: the same kernel on the same values).
pub(super) fn evaluate(
    py: Python<'_>,
    model: &Dynamics,
    payload: Option<RigidBody>,
    quantity: Quantity,
    states: &States<'_>,
) -> PyResult<Py<PyAny>> {
    let dof = model.dof();
    let tail = tail(quantity, dof);
    let width: usize = tail.iter().product();
    // The payload is checked here, once: the workspaces of the parallel loop cannot fail.
    let mut workspace = Workspace::new(model, payload).map_err(lib_error)?;
    let Some(n) = states.batch else {
        let mut out = vec![0.0; width];
        workspace
            .evaluate(model, quantity, states, 0, &mut out)
            .map_err(lib_error)?;
        return Ok(array(py, out, &tail)?.into_any().unbind());
    };
    let shape: Vec<usize> = std::iter::once(n).chain(tail.iter().copied()).collect();
    let result = new_float_array(py, &shape)?;
    if width == 0 || n == 0 {
        return Ok(result.into_any().unbind());
    }
    let mut guard = result.try_readwrite().map_err(|e| error(e.to_string()))?;
    let out = guard.as_slice_mut().map_err(|e| error(e.to_string()))?;
    let failed = py.detach(|| {
        split_rows(out, width, n, DYNAMICS_CHUNK)
            .into_par_iter()
            .enumerate()
            .map_init(
                || Workspace::new(model, payload).map_err(|e| e.to_string()),
                |workspace, (chunk, out)| {
                    let first = chunk * DYNAMICS_CHUNK;
                    let rows = DYNAMICS_CHUNK.min(n - first);
                    let workspace = match workspace {
                        Ok(workspace) => workspace,
                        Err(e) => return Some((first, e.clone())),
                    };
                    (0..rows).find_map(|k| {
                        let out = &mut out[k * width..(k + 1) * width];
                        workspace
                            .evaluate(model, quantity, states, first + k, out)
                            .err()
                            .map(|e| (first + k, e.to_string()))
                    })
                },
            )
            .flatten()
            .min_by_key(|(i, _)| *i)
    });
    drop(guard);
    if let Some((i, e)) = failed {
        return Err(error(format!("configuration {i}: {e}")));
    }
    Ok(result.into_any().unbind())
}
