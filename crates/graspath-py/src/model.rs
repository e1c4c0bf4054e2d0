//! `graspath.train` and `graspath.generate`: the learned grasp model, as `graspath train` and
//! `graspath generate` run it.
//!
//! Frames and units as in the library: candidates are `object_from_wrist` poses (m) in the
//! cloud's (object) frame, likelihoods as natural logarithms.

use crate::convert::{array, lib_error};
use graspath::cloud::{load_cloud_filtered, OutlierOptions};
use graspath::geometry::pose_to_rows;
use graspath::grasp::model::train_file;
use graspath::grasp::model::{
    candidates_json, generate as run_generate, GenerateOptions, GraspModel,
};
use graspath::output_files::{write_file, Existing};
use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::PathBuf;

/// Trains a grasp model from the demonstration file ``demonstration`` (its hand, cloud and
/// grasp; see docs/demonstrations.md) and writes it to ``out`` (JSON; an existing file is
/// refused unless ``force``). Returns a dict: ``label``, ``hand`` and ``contact_links`` (link
/// name → contact points).
#[pyfunction]
#[pyo3(signature = (demonstration, out, *, force = false))]
pub fn train<'py>(
    py: Python<'py>,
    demonstration: PathBuf,
    out: PathBuf,
    force: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let model = py
        .detach(|| train_file(&demonstration))
        .map_err(lib_error)?;
    let bytes = model.to_json().map_err(lib_error)?;
    write_file(&out, &bytes, Existing::replace_if(force)).map_err(lib_error)?;
    let dict = PyDict::new(py);
    dict.set_item("label", &model.label)?;
    dict.set_item("hand", &model.hand.name)?;
    let links = PyDict::new(py);
    for (link, points) in model.contact_links() {
        links.set_item(link, points)?;
    }
    dict.set_item("contact_links", links)?;
    Ok(dict)
}

/// Grasp candidates on the point cloud ``cloud`` (PLY, PCD, ...) from the trained model
/// ``model``, best first, seeded (the same inputs and ``seed`` give the same candidates).
/// ``initial_grasps``, ``steps`` and ``query_kernels`` default (``None``) to the model
/// spec's values, as `graspath generate`'s; ``max_candidates`` keeps the best ones; ``out``
/// also writes the candidates file `graspath generate` writes (a task's `candidates: {file}`).
///
/// Returns a dict: ``object_from_wrist`` ``(k, 4, 4)``, ``log_likelihood`` ``(k,)`` and
/// ``label`` (the model's).
#[pyfunction]
#[pyo3(signature = (
    model,
    cloud,
    *,
    initial_grasps = None,
    steps = None,
    query_kernels = None,
    seed = 0,
    max_candidates = None,
    out = None,
    force = false
))]
#[allow(clippy::too_many_arguments)]
pub fn generate<'py>(
    py: Python<'py>,
    model: PathBuf,
    cloud: PathBuf,
    initial_grasps: Option<usize>,
    steps: Option<usize>,
    query_kernels: Option<usize>,
    seed: u64,
    max_candidates: Option<usize>,
    out: Option<PathBuf>,
    force: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let defaults = GenerateOptions::default();
    let options = GenerateOptions {
        initial_grasps: initial_grasps.unwrap_or(defaults.initial_grasps),
        steps: steps.unwrap_or(defaults.steps),
        query_kernels: query_kernels.unwrap_or(defaults.query_kernels),
        seed,
        ..defaults
    };
    let source = cloud.display().to_string();
    let (model, candidates) = py
        .detach(|| -> Result<_, graspath::Error> {
            let model = GraspModel::read(&model)?;
            let (points, _) = load_cloud_filtered(&cloud, &OutlierOptions::default())?;
            let mut candidates = run_generate(&model, &points, &options, &source, &|_| {})?;
            if let Some(n) = max_candidates {
                candidates.truncate(n);
            }
            Ok((model, candidates))
        })
        .map_err(lib_error)?;
    if let Some(out) = out {
        let bytes = candidates_json(&candidates, &model.label).map_err(lib_error)?;
        write_file(&out, &bytes, Existing::replace_if(force)).map_err(lib_error)?;
    }
    let k = candidates.len();
    let poses: Vec<f64> = candidates
        .iter()
        .flat_map(|c| pose_to_rows(&c.object_from_wrist).into_iter().flatten())
        .collect();
    let dict = PyDict::new(py);
    dict.set_item("object_from_wrist", array(py, poses, &[k, 4, 4])?)?;
    let likelihoods: Vec<f64> = candidates.iter().map(|c| c.log_likelihood).collect();
    dict.set_item("log_likelihood", PyArray1::from_vec(py, likelihoods))?;
    dict.set_item("label", &model.label)?;
    Ok(dict)
}
