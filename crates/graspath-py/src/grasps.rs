//! `graspath.read_grasps`: a grasp file of any supported layout (graspath JSON/CSV, GraspGen,
//! ACRONYM, Contact-GraspNet / M2T2, generic `N×4×4` poses, GraspNet-1Billion / AnyGrasp) read
//! by the same library code as a task file's `candidates: {file, format, frame, ...}`
//! (`docs/grasp-files.md`), returned as numpy arrays.
//!
//! Frames: every returned pose is `object_from_wrist`, the tool (wrist) frame in the object
//! frame (metres); the file's own frame is placed by `frame`, `world_from_camera` /
//! `camera_from_object` and `world_from_object`, the generator's gripper frame mapped to the
//! tool frame by `gripper_from_tool` (default: the format's documented convention).

use crate::convert::{array, lib_error, push_isometry, single_pose, spelled, FloatArray};
use graspath::grasp::{read_grasp_file, GraspFileOptions, GraspFormat, GraspFrame};
use graspath::spelling::Spelled;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::PathBuf;

/// An optional 4×4 pose argument.
fn optional_pose(
    pose: Option<FloatArray<'_>>,
    what: &str,
) -> PyResult<Option<nalgebra::Isometry3<f64>>> {
    pose.map(|p| single_pose(&p, what)).transpose()
}

/// Reads a grasp file as candidates in the object frame.
///
/// ``format``: ``graspath``, ``graspgen``, ``acronym``, ``contact_graspnet``, ``m2t2``,
/// ``poses``, ``graspnet`` (``anygrasp``); ``None`` guesses it from the content. ``frame``:
/// ``object``, ``world`` or ``camera`` (``None``: the format's, ``camera`` for
/// Contact-GraspNet and GraspNet, ``world`` for M2T2, else ``object``). ``world_from_camera`` or
/// ``camera_from_object`` (4×4, metres) place a camera frame; ``world_from_object`` (4×4,
/// default identity) places the object in the world for ``world`` frames and
/// ``world_from_camera``. ``gripper_from_tool`` (4×4) overrides the format's gripper
/// convention; ``segment`` keeps one Contact-GraspNet / M2T2 segment (an id, or an object's
/// position in a per-object list).
///
/// Returns a dict: ``object_from_wrist`` (k, 4, 4), ``likelihood`` (k,) (the file's score, 1
/// where the file has none), ``log_likelihood`` (k,), ``width`` (k,) (metres, NaN where
/// absent), ``contact`` (k, 3) (object frame, NaN where absent), ``id`` (k,) (the grasp's row in
/// the file), ``label`` (list of k str) and ``format`` (the layout read).
#[pyfunction]
#[pyo3(signature = (
    path,
    format = None,
    frame = None,
    world_from_camera = None,
    camera_from_object = None,
    gripper_from_tool = None,
    segment = None,
    world_from_object = None,
))]
#[allow(clippy::too_many_arguments)]
pub fn read_grasps<'py>(
    py: Python<'py>,
    path: PathBuf,
    format: Option<&str>,
    frame: Option<&str>,
    world_from_camera: Option<FloatArray<'py>>,
    camera_from_object: Option<FloatArray<'py>>,
    gripper_from_tool: Option<FloatArray<'py>>,
    segment: Option<i64>,
    world_from_object: Option<FloatArray<'py>>,
) -> PyResult<Bound<'py, PyDict>> {
    let format = format
        .map(|name| spelled::<GraspFormat>("format", name))
        .transpose()?;
    let frame = frame
        .map(|name| spelled::<GraspFrame>("frame", name))
        .transpose()?;
    let world_from_camera = optional_pose(world_from_camera, "world_from_camera")?;
    let camera_from_object = optional_pose(camera_from_object, "camera_from_object")?;
    let gripper_from_tool = optional_pose(gripper_from_tool, "gripper_from_tool")?;
    let world_from_object =
        optional_pose(world_from_object, "world_from_object")?.unwrap_or_default();
    let (format, candidates) = py
        .detach(|| {
            let format = match format {
                Some(f) => f,
                None => graspath::grasp::guess_format(&path)?,
            };
            let frame = frame.unwrap_or_else(|| format.default_frame());
            let object_from_frame = frame
                .object_from_frame(
                    &world_from_object,
                    world_from_camera.as_ref(),
                    camera_from_object.as_ref(),
                )
                .map_err(|e| {
                    graspath::grasp::CandidateError::new(
                        path.display().to_string(),
                        e.field,
                        e.message,
                    )
                })?;
            let options = GraspFileOptions {
                format: Some(format),
                object_from_frame,
                gripper_from_tool,
                segment,
                max_candidates: None,
            };
            read_grasp_file(&path, &options)
        })
        .map_err(lib_error)?;
    let k = candidates.len();
    let mut poses = Vec::with_capacity(16 * k);
    let mut contacts = Vec::with_capacity(3 * k);
    for c in &candidates {
        push_isometry(&mut poses, &c.object_from_wrist);
        match c.contact {
            Some(p) => contacts.extend_from_slice(p.coords.as_slice()),
            None => contacts.extend_from_slice(&[f64::NAN; 3]),
        }
    }
    let log: Vec<f64> = candidates.iter().map(|c| c.log_likelihood).collect();
    let out = PyDict::new(py);
    out.set_item("object_from_wrist", array(py, poses, &[k, 4, 4])?)?;
    out.set_item(
        "likelihood",
        array(py, log.iter().map(|l| l.exp()).collect(), &[k])?,
    )?;
    out.set_item("log_likelihood", array(py, log, &[k])?)?;
    out.set_item(
        "width",
        array(
            py,
            candidates
                .iter()
                .map(|c| c.width.unwrap_or(f64::NAN))
                .collect(),
            &[k],
        )?,
    )?;
    out.set_item("contact", array(py, contacts, &[k, 3])?)?;
    let ids: Vec<i64> = candidates.iter().map(|c| c.id as i64).collect();
    out.set_item("id", numpy::PyArray1::from_vec(py, ids))?;
    out.set_item(
        "label",
        candidates
            .iter()
            .map(|c| c.label.clone())
            .collect::<Vec<_>>(),
    )?;
    out.set_item("format", format.as_str())?;
    Ok(out)
}
