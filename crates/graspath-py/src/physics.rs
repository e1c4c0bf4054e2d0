//! What `graspath.sim` drives MuJoCo with: the task's world as MJCF
//! (`graspath.world_mjcf`, `graspath.robot_mjcf`) and the timed motions of any candidates
//! (`graspath.candidate_motions`).

use crate::convert::{array, error, lib_error};
use crate::robot::PyRobot;
use crate::task::PyTask;
use graspath::physics::{chain_mjcf, world_mjcf as write_world, ArmNames, WorldOptions};
use graspath::select::{candidate_motions as motions_of, SelectedMotion};
use graspath::timing::TrajectoryPoint;
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// One timed motion as a dict: ``arm``, ``candidate`` (id), ``label``, ``duration`` (s),
/// ``grasp_time`` and ``place_time`` (s: where the gripper closes and opens),
/// ``joint_names``, ``time`` ``(n,)`` (s), ``positions``, ``velocities``, ``accelerations``
/// ``(n, dof)`` and ``efforts`` ``(n, dof)`` (N·m; ``None`` without the arm's dynamics).
pub fn motion_dict<'py>(py: Python<'py>, motion: &SelectedMotion) -> PyResult<Bound<'py, PyDict>> {
    let dict = PyDict::new(py);
    let trajectory = &motion.trajectory;
    let n = trajectory.points.len();
    let dof = trajectory.joint_names.len();
    let matrix = |f: &dyn Fn(&TrajectoryPoint) -> &[f64]| {
        let flat: Vec<f64> = trajectory
            .points
            .iter()
            .flat_map(|p| f(p).to_vec())
            .collect();
        array(py, flat, &[n, dof])
    };
    dict.set_item("arm", &motion.arm)?;
    dict.set_item("candidate", motion.candidate.id)?;
    dict.set_item("label", &motion.candidate.label)?;
    dict.set_item("duration", trajectory.duration())?;
    dict.set_item("grasp_time", motion.grasp_time)?;
    dict.set_item("place_time", motion.place_time)?;
    dict.set_item("joint_names", &trajectory.joint_names)?;
    let times: Vec<f64> = trajectory.points.iter().map(|p| p.time).collect();
    dict.set_item("time", array(py, times, &[n])?)?;
    dict.set_item("positions", matrix(&|p| &p.positions)?)?;
    dict.set_item("velocities", matrix(&|p| &p.velocities)?)?;
    dict.set_item("accelerations", matrix(&|p| &p.accelerations)?)?;
    let efforts = if trajectory.points.iter().all(|p| p.efforts.is_some()) {
        Some(matrix(&|p| p.efforts.as_deref().unwrap_or(&[]))?)
    } else {
        None
    };
    dict.set_item("efforts", efforts)?;
    Ok(dict)
}

/// Checks a sampling period (s), as `Selection.timed_motions` does.
pub fn check_period(period: Option<f64>) -> PyResult<()> {
    match period {
        Some(p) if !(1e-4..=10.0).contains(&p) => Err(error(format!(
            "period: {p} is not a sampling period from 0.0001 to 10 seconds (or None)"
        ))),
        _ => Ok(()),
    }
}

/// The timed motions of the candidates at positions ``candidates`` of ``task``'s candidate
/// order, one per arm in the task's arm order, timed as selection times motions (two arms on
/// one shared timeline) and sampled every ``period`` seconds (``None``: at the timing grid's
/// points): a list of dicts as :meth:`Selection.timed_motions` returns. ``None`` when a
/// candidate is not feasible for its arm; an error when the task does not time motions.
#[pyfunction]
#[pyo3(
    signature = (task, candidates, period = Some(0.01)),
    text_signature = "(task, candidates, period=0.01)"
)]
pub fn candidate_motions<'py>(
    py: Python<'py>,
    task: &Bound<'py, PyTask>,
    candidates: Vec<usize>,
    period: Option<f64>,
) -> PyResult<Option<Vec<Bound<'py, PyDict>>>> {
    check_period(period)?;
    let task = &task.get().task;
    if task.timing().is_none() {
        return Err(error(
            "the task does not time motions (timing: false, or a joint without a velocity limit)",
        ));
    }
    if candidates.len() != task.arms().len() {
        return Err(error(format!(
            "candidates: {} given, but the task has {} arm(s): give one candidate per arm",
            candidates.len(),
            task.arms().len()
        )));
    }
    let mut chosen = Vec::with_capacity(candidates.len());
    for index in candidates {
        let candidate = task
            .candidate_at(index)
            .map_err(lib_error)?
            .ok_or_else(|| {
                error(format!(
                    "candidates: {index} is past the task's {} candidates",
                    task.candidate_count()
                ))
            })?;
        chosen.push(candidate);
    }
    match py.detach(|| motions_of(task, &chosen, period)) {
        None => Ok(None),
        Some(Err(failure)) => Err(error(format!("cannot time the motion: {failure}"))),
        Some(Ok(motions)) => motions
            .iter()
            .map(|m| motion_dict(py, m))
            .collect::<PyResult<_>>()
            .map(Some),
    }
}

fn arm_dict<'py>(py: Python<'py>, arm: &ArmNames) -> PyResult<Bound<'py, PyDict>> {
    let dict = PyDict::new(py);
    dict.set_item("arm", &arm.arm)?;
    dict.set_item("joints", &arm.joints)?;
    dict.set_item("effort", &arm.effort)?;
    dict.set_item("tool", &arm.tool)?;
    dict.set_item("fingers", &arm.fingers)?;
    dict.set_item("finger_travel", arm.finger_travel)?;
    dict.set_item("grasp_weld", &arm.grasp_weld)?;
    dict.set_item("task_gripper", arm.task_gripper)?;
    Ok(dict)
}

/// ``task``'s world — its arms (bodies with their inertias, joints with limits, torque
/// motors), the gripper at each tool (force-limited sliding fingers), the object (a free body
/// at the path's start), the table and the obstacles — as one MJCF model for MuJoCo
/// (docs/simulation.md). Returns a dict: ``xml`` (the model), ``arms`` (per arm its
/// ``joints``, ``effort`` limits, ``tool`` body, ``fingers``, ``finger_travel`` (m),
/// ``grasp_weld``, ``task_gripper``), ``object``, ``object_mass`` (kg),
/// ``has_table`` and ``notes`` (what the model approximates). With
/// ``arm_gravity_compensation`` the arms' and hands' own weight is carried outside the motors
/// (MuJoCo ``gravcomp``: a gravity-assist spring or counterbalance).
#[pyfunction]
#[pyo3(signature = (task, *, timestep = 0.002, friction = 1.0, grip_force = 40.0, object_density = 500.0, arm_gravity_compensation = false))]
pub fn world_mjcf<'py>(
    py: Python<'py>,
    task: &Bound<'py, PyTask>,
    timestep: f64,
    friction: f64,
    grip_force: f64,
    object_density: f64,
    arm_gravity_compensation: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let options = WorldOptions {
        timestep,
        friction,
        grip_force,
        object_density,
        arm_gravity_compensation,
        ..WorldOptions::default()
    };
    let world = write_world(&task.get().task, &options).map_err(lib_error)?;
    let dict = PyDict::new(py);
    dict.set_item("xml", &world.xml)?;
    let arms = world
        .arms
        .iter()
        .map(|a| arm_dict(py, a))
        .collect::<PyResult<Vec<_>>>()?;
    dict.set_item("arms", arms)?;
    dict.set_item("object", &world.object)?;
    dict.set_item("object_mass", world.object_mass)?;
    dict.set_item("has_table", world.has_table)?;
    dict.set_item("notes", &world.notes)?;
    Ok(dict)
}

/// ``robot``'s chain alone as an MJCF model, its base at the world origin (no gripper, no
/// object): MuJoCo's kinematics and joint-space inertia of it equal graspath's. Returns
/// ``(xml, names)`` with ``names`` as one entry of :func:`world_mjcf`'s ``arms``.
#[pyfunction]
#[pyo3(signature = (robot, arm = "arm"))]
pub fn robot_mjcf<'py>(
    py: Python<'py>,
    robot: &Bound<'py, PyRobot>,
    arm: &str,
) -> PyResult<(String, Bound<'py, PyDict>)> {
    let (xml, names) = chain_mjcf(&robot.get().chain, arm).map_err(lib_error)?;
    Ok((xml, arm_dict(py, &names)?))
}
