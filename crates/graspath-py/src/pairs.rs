//! `graspath.select_pairs`: a two-arm task's best arm pairs from its candidates' scores found
//! apart (the rows of `graspath.select_batch`, for instance the union of its slices' rows, as
//! `graspath.ray` gathers them from its shards).

use crate::convert::{error, lib_error};
use crate::task::PyTask;
use graspath::select::pairs_of_eligible;
use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

/// One column of `rows`, named `name`, as a vector (errors name the column).
fn column<'py, T: FromPyObjectOwned<'py>>(
    rows: &Bound<'py, PyAny>,
    name: &str,
) -> PyResult<Vec<T>> {
    let value = rows
        .get_item(name)
        .map_err(|_| error(format!("rows: no '{name}' column")))?;
    let numpy = rows.py().import("numpy")?;
    numpy
        .call_method1("ravel", (value,))?
        .call_method0("tolist")?
        .extract()
        .map_err(|e| error(format!("rows['{name}']: {}", Into::<PyErr>::into(e))))
}

/// The best arm pairs of a two-arm ``task`` from its candidates' scores found apart:
/// ``rows`` holds the columns ``arm_index``, ``candidate``, ``score`` and the task's ranked
/// norm (``mu_rms``, ``mu_l2`` or ``mu_l1``; ``duration`` for a task ranked by it) of
/// :func:`select_batch` for this task (other columns are ignored), and every ranked row
/// (``score`` not NaN) of both arms must be among them, each once — the rows of the whole
/// task, or the union of its slices' rows (slices need no ``top_k``: pairs are formed from
/// each arm's whole list). Rows without a score are ignored.
///
/// Returns numpy columns with one row per pair, best first: ``rank`` (int64, 1 for the best),
/// ``first_arm``, ``second_arm`` (str, the task's two arms in order), ``first_candidate``,
/// ``second_candidate`` (int64, positions in the task's candidates), ``first_id``,
/// ``second_id`` (int64), ``first_label``, ``second_label`` (str) and ``score`` (float64, the
/// sum of the two arms' ranked norms: ``μ_rms`` by default, ``μ_l2`` or ``μ_l1`` with the
/// task's ``norm``; with ``measure: duration`` the slower arm's rate, 1/s). They are
/// the first ``top_k`` of :func:`select`'s pairs on the task (default: all of them, the task's
/// ``pairs``), in the same order with the same scores: the same best-first search, and the
/// check between the arms (a scene with ``collision.between_arms``) scores again only the
/// candidates of the pairs it looks at, each once. Runs without the GIL.
#[pyfunction]
#[pyo3(signature = (task, rows, *, top_k = None))]
pub fn select_pairs<'py>(
    py: Python<'py>,
    task: &Bound<'py, PyTask>,
    rows: &Bound<'py, PyAny>,
    top_k: Option<usize>,
) -> PyResult<Bound<'py, PyDict>> {
    if top_k == Some(0) {
        return Err(error(
            "top_k must be at least 1 (or None for the task's pairs)",
        ));
    }
    let task = &task.get().task;
    let arm_index: Vec<i64> = column(rows, "arm_index")?;
    let candidate: Vec<i64> = column(rows, "candidate")?;
    let score: Vec<f64> = column(rows, "score")?;
    // What each arm's candidates are paired by: the ranked norm, or with `measure: duration`
    // the rate 1 / duration (the pair then takes the slower arm's, as in `select`).
    let norm: Vec<f64> = if task.selection().by_duration {
        column::<f64>(rows, "duration")?
            .into_iter()
            .map(|d| 1.0 / d)
            .collect()
    } else {
        column(rows, task.selection().norm.field())?
    };
    let n = arm_index.len();
    if [candidate.len(), score.len(), norm.len()] != [n; 3] {
        return Err(error(format!(
            "rows: the columns have different lengths (arm_index {n}, candidate {}, score {}, \
             norm {})",
            candidate.len(),
            score.len(),
            norm.len()
        )));
    }
    let mut eligible: [Vec<(usize, f64)>; 2] = [Vec::new(), Vec::new()];
    for k in 0..n {
        if score[k].is_nan() {
            continue;
        }
        let arm = usize::try_from(arm_index[k])
            .ok()
            .filter(|&a| a < 2)
            .ok_or_else(|| {
                error(format!(
                    "rows: row {k}: arm_index {} is not 0 or 1 (a task with two arms)",
                    arm_index[k]
                ))
            })?;
        let position = usize::try_from(candidate[k]).map_err(|_| {
            error(format!(
                "rows: row {k}: candidate {} is negative",
                candidate[k]
            ))
        })?;
        if !norm[k].is_finite() {
            return Err(error(format!(
                "rows: row {k}: a ranked candidate's norm must be finite (got {})",
                norm[k]
            )));
        }
        eligible[arm].push((position, norm[k]));
    }
    let count = top_k.map_or(task.selection().pairs, |k| k.min(task.selection().pairs));
    let (pairs, _) = py
        .detach(|| pairs_of_eligible(task, &eligible[0], &eligible[1], count))
        .map_err(lib_error)?;
    let numpy = py.import("numpy")?;
    let str_type = py.import("builtins")?.getattr("str")?;
    let text = |values: Vec<String>| -> PyResult<Bound<'py, PyAny>> {
        let kwargs = PyDict::new(py);
        kwargs.set_item("dtype", &str_type)?;
        numpy.call_method("array", (PyList::new(py, values)?,), Some(&kwargs))
    };
    let int =
        |values: Vec<usize>| PyArray1::from_vec(py, values.into_iter().map(|v| v as i64).collect());
    let all = task.all_candidates().map_err(lib_error)?;
    let dict = PyDict::new(py);
    dict.set_item("rank", int((1..=pairs.len()).collect()))?;
    for (arm, side) in ["first", "second"].into_iter().enumerate() {
        let position = |&(i, j, _): &(usize, usize, f64)| if arm == 0 { i } else { j };
        let positions: Vec<usize> = pairs.iter().map(position).collect();
        dict.set_item(
            format!("{side}_arm"),
            text(vec![task.arms()[arm].name.clone(); pairs.len()])?,
        )?;
        dict.set_item(
            format!("{side}_id"),
            int(positions.iter().map(|&p| all[p].id).collect()),
        )?;
        dict.set_item(
            format!("{side}_label"),
            text(positions.iter().map(|&p| all[p].label.clone()).collect())?,
        )?;
        dict.set_item(format!("{side}_candidate"), int(positions))?;
    }
    dict.set_item(
        "score",
        PyArray1::from_vec(py, pairs.iter().map(|p| p.2).collect()),
    )?;
    Ok(dict)
}
