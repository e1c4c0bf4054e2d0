//! `graspath.time_path`: the time-optimal timing of any joint path (TOPP-RA on the natural
//! cubic spline through its samples), the computation every feasible candidate's motion goes
//! through.

use crate::convert::{array, check_finite, error, lib_error, spelled, Buffer, FloatArray};
use graspath::timing::{Discretization, JointSpline, PathLimits};
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// The most samples a path may have.
const MAX_SAMPLES: usize = 1_000_000;

/// The fastest motion from rest to rest through the joint configurations ``samples``
/// ``(n, dof)`` (rad or m) within the joint ``velocity_limits`` and ``acceleration_limits``
/// ``(dof,)`` (rad/s, rad/s²; ``inf`` for none): the natural cubic spline through the samples
/// in the chord-length parameter ``s`` (rad), timed by TOPP-RA on the knots with every interval
/// split into ``subdivisions`` parts, the limits imposed at both ends of each grid interval
/// (``discretization="interpolation"``) or at its start (``"collocation"``, toppra's default
/// for these constraints). With ``check_between`` (default) the motion is then slowed
/// uniformly where the limits would be exceeded between grid points, as selection does.
///
/// Returns a dict: ``duration`` (s), ``knots`` ``(m,)`` (the parameter of each distinct
/// sample), ``grid`` ``(g,)``, ``sd_squared`` ``(g,)`` (``ṡ²`` at the grid points), ``times``
/// ``(g,)`` (s), ``slowdown`` (the factor applied, 1 when none). Torque limits need a robot:
/// they are applied in selection when the task gives the object's mass (docs/timing.md).
#[pyfunction]
#[pyo3(signature = (samples, velocity_limits, acceleration_limits, *, subdivisions = 2, discretization = "interpolation", check_between = true))]
pub fn time_path<'py>(
    py: Python<'py>,
    samples: FloatArray<'py>,
    velocity_limits: FloatArray<'py>,
    acceleration_limits: FloatArray<'py>,
    subdivisions: usize,
    discretization: &str,
    check_between: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let samples = Buffer::from_array(&samples, "samples")?;
    let [n, dof] = samples.shape[..] else {
        return Err(error(format!(
            "samples has shape {} but (n, dof) is expected",
            samples.shape_text()
        )));
    };
    if n == 0 || dof == 0 || n > MAX_SAMPLES {
        return Err(error(format!(
            "samples has shape {}: give 1 to {MAX_SAMPLES} samples of at least one joint",
            samples.shape_text()
        )));
    }
    check_finite(&samples.data, dof, "samples", true)?;
    let limits = |array: &FloatArray<'py>, what: &str| -> PyResult<Vec<Option<f64>>> {
        let buffer = Buffer::from_array(array, what)?;
        if buffer.shape != [dof] {
            return Err(error(format!(
                "{what} has shape {} but ({dof},) is expected",
                buffer.shape_text()
            )));
        }
        Ok(buffer
            .data
            .iter()
            .map(|&v| (v != f64::INFINITY).then_some(v))
            .collect())
    };
    let velocity = limits(&velocity_limits, "velocity_limits")?;
    let acceleration = limits(&acceleration_limits, "acceleration_limits")?;
    if !(1..=64).contains(&subdivisions) {
        return Err(error(format!(
            "subdivisions must be between 1 and 64, got {subdivisions}"
        )));
    }
    let discretization: Discretization = spelled("discretization", discretization)?;
    let rows: Vec<Vec<f64>> = samples.data.chunks(dof).map(<[f64]>::to_vec).collect();
    let path_limits = PathLimits {
        velocity: &velocity,
        acceleration: &acceleration,
        torque: None,
        object: None,
        subdivisions,
        discretization,
    };
    let (spline, timed, slowdown) = py
        .detach(|| -> Result<_, graspath::timing::TimingError> {
            let spline = JointSpline::through(&rows)?;
            let timed = graspath::timing::time_optimal(&path_limits.constraints(&spline)?)?;
            let factor = if check_between {
                path_limits.slowdown(&spline, &timed)?
            } else {
                1.0
            };
            let timed = if factor > 1.0 {
                timed.slowed(factor)
            } else {
                timed
            };
            Ok((spline, timed, factor))
        })
        .map_err(lib_error)?;
    let dict = PyDict::new(py);
    dict.set_item("duration", timed.duration())?;
    let knots = spline.knots().to_vec();
    let m = knots.len();
    dict.set_item("knots", array(py, knots, &[m])?)?;
    let g = timed.grid.len();
    dict.set_item("grid", array(py, timed.grid.clone(), &[g])?)?;
    dict.set_item("sd_squared", array(py, timed.sd_squared.clone(), &[g])?)?;
    dict.set_item("times", array(py, timed.times.clone(), &[g])?)?;
    dict.set_item("slowdown", slowdown)?;
    Ok(dict)
}
