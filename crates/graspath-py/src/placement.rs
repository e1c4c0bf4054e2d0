//! `graspath.placement_map`: a task's selection with the object started at every placement of
//! a grid, as `graspath map` runs it, returned as the same document as its `map.json`.

use crate::convert::{json_to_py, lib_error};
use graspath::placement::{placement_map as run_map, FamilyParameter, GridAxis, PlacementGrid};
use graspath::task::{builder_from_file, TaskFile};
use graspath_report::placement_map_json;
use pyo3::prelude::*;
use std::path::{Path, PathBuf};

/// One axis from `(start, end, count)`; `what` names it in errors.
fn axis(values: (f64, f64, usize), what: &str) -> PyResult<GridAxis> {
    let (start, end, count) = values;
    GridAxis::new(start, end, count, what).map_err(lib_error)
}

/// The task file at ``task`` run with the object's start moved to every placement of a grid:
/// ``x`` and ``y`` (world frame, m) and optionally ``z`` (m) and ``yaw_deg`` (degrees about
/// world z, added to the task's orientation), each ``(start, end, count)``. Parallel and
/// deterministic; every placement's result equals a plain selection of the task moved there.
///
/// Returns the document ``graspath map`` writes as ``map.json`` (a dict: the grid, and per
/// placement the feasible count, the best candidate and score, the spread of ``μ_l2`` and its
/// trend along the candidates' family parameter, the best pair with two arms).
#[pyfunction]
#[pyo3(signature = (task, x, y, *, z = None, yaw_deg = None))]
pub fn placement_map<'py>(
    py: Python<'py>,
    task: PathBuf,
    x: (f64, f64, usize),
    y: (f64, f64, usize),
    z: Option<(f64, f64, usize)>,
    yaw_deg: Option<(f64, f64, usize)>,
) -> PyResult<Bound<'py, PyAny>> {
    let grid = PlacementGrid {
        x: axis(x, "x")?,
        y: axis(y, "y")?,
        z: z.map(|z| axis(z, "z")).transpose()?,
        yaw: yaw_deg
            .map(|a| axis(a, "yaw_deg").map(|a| a.scaled(1f64.to_radians())))
            .transpose()?,
    };
    let name = task.display().to_string();
    let file = TaskFile::load(&task).map_err(lib_error)?;
    let base_dir = task.parent().map(Path::to_path_buf).unwrap_or_default();
    let builder = builder_from_file(&file, &name, &base_dir).map_err(lib_error)?;
    let built = builder.clone().build().map_err(lib_error)?;
    let parameter =
        FamilyParameter::from_task_file(&file, &built.all_candidates().map_err(lib_error)?);
    drop(built);
    let map = py
        .detach(|| run_map(&builder, &grid, parameter, &|| {}))
        .map_err(lib_error)?;
    json_to_py(py, &placement_map_json(&name, &map))
}
