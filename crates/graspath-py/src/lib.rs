//! Python bindings of graspath: the native module `graspath._graspath`, re-exported by the
//! Python package `graspath` (see `python/graspath/__init__.py` and the type stubs beside it).
//!
//! * `robot::PyRobot` (`graspath.Robot`): URDF and MJCF chains and the built-in arms; forward
//!   kinematics, Jacobians, indices and IK for one configuration or a batch (numpy in and out,
//!   batches in parallel with rayon, the GIL released).
//! * `task::PyTask` (`graspath.Task`): tasks from files (optionally with the object moved),
//!   text, dicts or arrays.
//! * `pose::pose_matrix` (`graspath.pose_matrix`): a pose in the task file's syntax as a 4×4
//!   matrix; the same syntax for `Task.load`'s `object_pose`.
//! * `grasps::read_grasps` (`graspath.read_grasps`): grasp-generator files (GraspGen, ACRONYM,
//!   Contact-GraspNet / M2T2, `N×4×4` poses, GraspNet / AnyGrasp) as numpy candidates.
//! * `selection::select` / `selection::PySelection` (`graspath.select`,
//!   `graspath.Selection`): scoring and ranking, with the records the CLI writes.
//! * `batch::select_batch` (`graspath.select_batch`): many tasks (objects) scored in one call,
//!   as numpy columns; candidate slices for sharding (`python/graspath/ray.py`).
//! * `pairs::select_pairs` (`graspath.select_pairs`): a two-arm task's best arm pairs from
//!   its candidates' scores found apart (`select_batch` rows, shards of `graspath.ray`).
//! * `model::train` / `model::generate` (`graspath.train`, `graspath.generate`): the learned
//!   grasp model, writing the files the CLI writes.
//! * `placement::placement_map` (`graspath.placement_map`): the selection over a grid of
//!   object placements, the document `graspath map` writes.
//!
//! * `memory::result_cache` (`graspath.result_cache`): the cache of large result arrays'
//!   memory, which batch calls write into instead of new memory.
//!
//! Every library error becomes the exception of its kind (`convert::lib_error`, classes in
//! `python/graspath/_errors.py`, all under `graspath.GraspathError`): a `GraspathFileError`
//! (`OSError`; `GraspathFileNotFoundError` for a missing input) for a file that cannot be read
//! or written, a `GraspathValueError` (`ValueError`) for bad content, with the library's whole
//! message and the `file` and `field` at fault.

mod batch;
mod convert;
mod grasps;
mod memory;
mod model;
mod pairs;
mod physics;
mod placement;
mod pose;
mod record;
mod robot;
mod selection;
mod task;
mod timing;

use pyo3::prelude::*;

/// The native module. Python code imports `graspath`, which re-exports everything here.
#[pymodule]
#[pyo3(name = "_graspath")]
fn graspath_native(module: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = module.py();
    module.add_class::<robot::PyRobot>()?;
    module.add_class::<task::PyTask>()?;
    module.add_class::<selection::PySelection>()?;
    module.add_function(wrap_pyfunction!(selection::select, module)?)?;
    module.add_function(wrap_pyfunction!(batch::select_batch, module)?)?;
    module.add_function(wrap_pyfunction!(record::record_columns, module)?)?;
    module.add_function(wrap_pyfunction!(pairs::select_pairs, module)?)?;
    module.add_function(wrap_pyfunction!(pose::pose_matrix, module)?)?;
    module.add_function(wrap_pyfunction!(placement::placement_map, module)?)?;
    module.add_function(wrap_pyfunction!(model::train, module)?)?;
    module.add_function(wrap_pyfunction!(model::generate, module)?)?;
    module.add("DEFAULTS", task::defaults_dict(py)?)?;
    module.add("SPELLINGS", task::spellings_dict(py)?)?;
    module.add_function(wrap_pyfunction!(grasps::read_grasps, module)?)?;
    module.add_function(wrap_pyfunction!(memory::result_cache, module)?)?;
    module.add_function(wrap_pyfunction!(timing::time_path, module)?)?;
    module.add_function(wrap_pyfunction!(physics::world_mjcf, module)?)?;
    module.add_function(wrap_pyfunction!(physics::robot_mjcf, module)?)?;
    module.add_function(wrap_pyfunction!(physics::candidate_motions, module)?)?;
    module.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
