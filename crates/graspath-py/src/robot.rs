//! `graspath.Robot`: one serial chain (a URDF or MJCF chain, or a built-in arm) with forward
//! kinematics, the geometric Jacobian, manipulability indices, inverse kinematics and
//! rigid-body dynamics, for one configuration or for many at once.
//!
//! Frames and units as in the library: every pose and Jacobian is in the chain **base frame**;
//! metres and radians; the Jacobian has rows `[v; ω]` (Pinocchio's `LOCAL_WORLD_ALIGNED`).
//!
//! One file on purpose (over 1000 lines): it is the whole `Robot` class, whose methods PyO3
//! requires in one `#[pymethods]` block. The dynamics' argument parsing and batch evaluation
//! are in [`dynamics`].

use crate::convert::{
    array, check_finite, error, index_mode, lib_error, non_finite_error, poses, row_major, rows,
    shape_text, single_pose, spelled, trajectories, FloatArray,
};
use crate::memory::{kinematics_into, new_float_array, split_rows, split_rows_ref, ResultArray};
use graspath::manipulability::{
    singular_values, task_relevant, velocity_transmission_ratio, wrist_tangent, ClassicalIndices,
    Direction, JacobianPart,
};

use graspath::robot::{
    null_space, optimize_self_motion, solve_ik, solve_trajectories, Chain, Dynamics, IkOptions,
    IkSolution, KeptRows, MotionLimits, RobotError, RobotSource, SelfMotionOptions,
    TrajectoryIkOptions, TrajectoryIkResult, UrdfRobot,
};
use nalgebra::{Isometry3, Matrix6xX, Vector3, Vector6};
use numpy::{PyArray1, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyList};
use rayon::prelude::*;
use std::borrow::Cow;
use std::collections::BTreeMap;
use std::path::PathBuf;
use std::sync::OnceLock;
use std::time::Duration;

mod dynamics;

pub(crate) use dynamics::payload_body;
use dynamics::{Quantity, States};

/// A serial kinematic chain from a base link to a tip link.
#[pyclass(module = "graspath", name = "Robot", frozen)]
pub struct PyRobot {
    pub(crate) chain: Chain,
    /// The chain's dynamics model (or the message of why it has none), built on first use.
    dynamics: OnceLock<Result<Dynamics, String>>,
}

impl PyRobot {
    /// Wraps a chain.
    pub fn new(chain: Chain) -> Self {
        Self {
            chain,
            dynamics: OnceLock::new(),
        }
    }

    /// The chain's dynamics model with standard gravity; a `GraspathError` naming the robot
    /// and the links when a moving link has no inertial data.
    fn dynamics_model(&self) -> PyResult<&Dynamics> {
        self.dynamics
            .get_or_init(|| self.chain.dynamics().map_err(|e| e.to_string()))
            .as_ref()
            .map_err(|e| error(e.as_str()))
    }

    /// A dynamics call's model (with `gravity` when given), states and payload, checked, and
    /// its result.
    #[allow(clippy::too_many_arguments)]
    fn dynamics_call<'py>(
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
            qd: dynamics::like_q(qd, q.shape(), dof, "qd")?,
            qdd: dynamics::like_q(qdd, q.shape(), dof, "qdd")?,
            batch,
        };
        let gravity = dynamics::gravity_vector(gravity, model.gravity())?;
        let payload = payload_body(payload, "tool")?;
        let model = if gravity == model.gravity() {
            Cow::Borrowed(model)
        } else {
            Cow::Owned(model.clone().with_gravity(gravity).map_err(lib_error)?)
        };
        dynamics::evaluate(py, &model, payload, quantity, &states)
    }

    /// One of the joints' motion limits, `+inf` where unknown.
    fn limits<'py>(
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

    /// Configurations from `(dof,)` or `(n, dof)`, checked finite: row-major values (the
    /// array's own memory when it is C-contiguous float64) and `Some(n)` for the batch form.
    fn configurations<'a>(
        &self,
        q: &'a FloatArray<'_>,
    ) -> PyResult<(Cow<'a, [f64]>, Option<usize>)> {
        let (data, batch) = self.configurations_unchecked(q)?;
        check_finite(&data, self.chain.dof(), "q", batch.is_some())?;
        Ok((data, batch))
    }

    /// [`Self::configurations`] without the finiteness check (for calls whose kernel checks).
    fn configurations_unchecked<'a>(
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

/// Configurations per rayon task of the index calls (an SVD or a projection each).
const INDEX_CHUNK: usize = 64;

/// Configurations per rayon task of `within_limits` (a few comparisons each).
const SCALAR_CHUNK: usize = 4096;

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

/// The kept rows of the self-motion by name: `pose` or `position`.
fn kept_rows(rows: &str) -> PyResult<KeptRows> {
    match rows {
        "pose" => Ok(KeptRows::Pose),
        "position" => Ok(KeptRows::Position),
        other => Err(error(format!(
            "rows '{other}' is not one of 'pose', 'position'"
        ))),
    }
}

/// A tool offset `tip_from_tool` from an optional `(4, 4)` array.
fn tool_pose(tool: Option<FloatArray<'_>>) -> PyResult<Option<Isometry3<f64>>> {
    tool.map(|t| single_pose(&t, "tool")).transpose()
}

/// The IK settings shared by `ik` and `ik_trajectory`.
fn ik_options(
    position_tolerance: f64,
    rotation_tolerance: f64,
    max_iterations: usize,
    max_time: Option<f64>,
    random_seed: u64,
) -> PyResult<IkOptions> {
    let max_time = match max_time {
        None => None,
        Some(t) => match Duration::try_from_secs_f64(t) {
            Ok(budget) if t > 0.0 => Some(budget),
            _ => {
                return Err(error(format!(
                    "option 'max_time': must be a positive number of seconds (at most about 1.8e19) or None, got {t}"
                )))
            }
        },
    };
    Ok(IkOptions {
        position_tolerance,
        rotation_tolerance,
        max_time,
        max_iterations,
        random_seed,
    })
}

/// Copies `values` into `out` (as many as both hold).
fn copy_into(out: &mut [f64], values: &[f64]) {
    for (o, v) in out.iter_mut().zip(values) {
        *o = *v;
    }
}

fn failure_reason(solution: &IkSolution) -> Option<&'static str> {
    solution.failure.as_ref().map(|f| f.reason.as_str())
}

#[pymethods]
impl PyRobot {
    /// One arm of the built-in Baxter model (``base`` → ``{arm}_gripper``), optionally with a
    /// tool offset ``tool`` = ``tip_from_tool`` (4×4, metres).
    #[staticmethod]
    #[pyo3(signature = (arm = "left", tool = None))]
    fn baxter(arm: &str, tool: Option<FloatArray<'_>>) -> PyResult<Self> {
        let tool = tool_pose(tool)?;
        let model = RobotSource::builtin("baxter").load().map_err(lib_error)?;
        Ok(Self::new(model.named_chain(arm, tool).map_err(lib_error)?))
    }

    /// A built-in robot's chain: ``name`` is one of ``baxter``, ``panda``, ``fr3``, ``ur5``,
    /// ``ur10``, ``ur5e``, ``ur10e``, ``iiwa14``, ``xarm7``, ``gen3``; ``arm`` names the chain
    /// (``left``/``right`` for Baxter, ``arm`` for the others; default: the first). The chain
    /// runs from the robot's base to its documented tool frame (Panda: ``panda_hand_tcp``,
    /// UR: ``tool0``), optionally followed by ``tool`` = ``tip_from_tool`` (4×4, metres).
    #[staticmethod]
    #[pyo3(signature = (name, arm = None, tool = None))]
    fn builtin(name: &str, arm: Option<&str>, tool: Option<FloatArray<'_>>) -> PyResult<Self> {
        let tool = tool_pose(tool)?;
        let model = RobotSource::builtin(name).load().map_err(lib_error)?;
        let arm = match arm {
            Some(arm) => arm.to_string(),
            None => model.chain_names().first().cloned().unwrap_or_default(),
        };
        Ok(Self::new(model.named_chain(&arm, tool).map_err(lib_error)?))
    }

    /// The chain ``base_link`` → ``tip_link`` of a URDF file, optionally with a tool offset
    /// ``tool`` = ``tip_from_tool`` (4×4, metres). Link geometry is ignored. A file named
    /// ``*.xacro`` is expanded by the ``xacro`` program (it runs code: only for files you
    /// trust) with ``xacro_args`` (``{name: value}``); ``search_paths`` are where
    /// ``package://PKG`` and xacro's ``$(find PKG)`` look first.
    #[staticmethod]
    #[pyo3(signature = (path, base_link, tip_link, tool = None, *, search_paths = None, xacro_args = None))]
    fn from_urdf(
        path: PathBuf,
        base_link: &str,
        tip_link: &str,
        tool: Option<FloatArray<'_>>,
        search_paths: Option<Vec<PathBuf>>,
        xacro_args: Option<BTreeMap<String, String>>,
    ) -> PyResult<Self> {
        let tool = tool_pose(tool)?;
        let model = RobotSource::Urdf {
            path,
            search_paths: search_paths.unwrap_or_default(),
            xacro_args: xacro_args.unwrap_or_default(),
        }
        .load()
        .map_err(lib_error)?;
        Ok(Self::new(
            model.chain(base_link, tip_link, tool).map_err(lib_error)?,
        ))
    }

    /// The chain ``base_body`` → ``tip_body`` of an MJCF (MuJoCo XML) file: its bodies' hinge and
    /// slide joints with their ranges, optionally followed by a tool offset ``tool`` =
    /// ``tip_from_tool`` (4×4, metres). Poses and Jacobians are in ``base_body``'s frame.
    #[staticmethod]
    #[pyo3(signature = (path, base_body, tip_body, tool = None))]
    fn from_mjcf(
        path: PathBuf,
        base_body: &str,
        tip_body: &str,
        tool: Option<FloatArray<'_>>,
    ) -> PyResult<Self> {
        let tool = tool_pose(tool)?;
        let model = RobotSource::mjcf(path).load().map_err(lib_error)?;
        Ok(Self::new(
            model.chain(base_body, tip_body, tool).map_err(lib_error)?,
        ))
    }

    /// The chain ``base`` → ``tip`` (links; an MJCF file's bodies) of a URDF, xacro or MJCF
    /// file, its format told by its name (``.urdf``, ``.xacro``, ``.mjcf``) or, for ``.xml``
    /// and other names, by its root element (``<robot>`` or ``<mujoco>``), optionally followed
    /// by a tool offset ``tool`` = ``tip_from_tool`` (4×4, metres). ``search_paths`` and
    /// ``xacro_args`` are for a URDF as in :meth:`from_urdf` (a file told a URDF by its root is
    /// never expanded as xacro); for an MJCF file they are an error.
    #[classmethod]
    #[pyo3(signature = (path, base, tip, tool = None, *, search_paths = None, xacro_args = None))]
    fn load(
        _class: &Bound<'_, pyo3::types::PyType>,
        path: PathBuf,
        base: &str,
        tip: &str,
        tool: Option<FloatArray<'_>>,
        search_paths: Option<Vec<PathBuf>>,
        xacro_args: Option<BTreeMap<String, String>>,
    ) -> PyResult<Self> {
        let tool = tool_pose(tool)?;
        let model = RobotSource::from_path(path)
            .and_then(|source| {
                source.with_urdf_options(
                    search_paths.unwrap_or_default(),
                    xacro_args.unwrap_or_default(),
                )
            })
            .and_then(|source| source.load())
            .map_err(lib_error)?;
        Ok(Self::new(model.chain(base, tip, tool).map_err(lib_error)?))
    }

    /// The chain ``base_link`` → ``tip_link`` of URDF text; ``source_name`` names it in errors.
    #[staticmethod]
    #[pyo3(signature = (xml, base_link, tip_link, tool = None, source_name = "<urdf string>"))]
    fn from_urdf_string(
        xml: &str,
        base_link: &str,
        tip_link: &str,
        tool: Option<FloatArray<'_>>,
        source_name: &str,
    ) -> PyResult<Self> {
        let tool = tool_pose(tool)?;
        let robot = UrdfRobot::from_xml(xml, source_name).map_err(lib_error)?;
        Ok(Self::new(
            robot.chain(base_link, tip_link, tool).map_err(lib_error)?,
        ))
    }

    /// The number of independent joints (the length of a configuration).
    #[getter]
    fn dof(&self) -> usize {
        self.chain.dof()
    }

    /// ``base->tip``.
    #[getter]
    fn name(&self) -> String {
        self.chain.name()
    }

    /// The file or built-in model the chain came from.
    #[getter]
    fn source(&self) -> String {
        self.chain.source_name().to_string()
    }

    /// The base link: the frame of every pose and Jacobian.
    #[getter]
    fn base_link(&self) -> String {
        self.chain.base_link().to_string()
    }

    /// The tip link.
    #[getter]
    fn tip_link(&self) -> String {
        self.chain.tip_link().to_string()
    }

    /// The names of the independent joints, in the order of a configuration.
    #[getter]
    fn joint_names(&self) -> Vec<String> {
        self.chain.joint_names().to_vec()
    }

    /// Lower joint limits, shape ``(dof,)`` (rad or m; ``-inf`` for continuous joints).
    #[getter]
    fn lower<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, self.chain.lower())
    }

    /// Upper joint limits, shape ``(dof,)`` (rad or m; ``+inf`` for continuous joints).
    #[getter]
    fn upper<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, self.chain.upper())
    }

    /// This robot with narrower joint ranges, ``{joint: (lower, upper)}`` (rad, or m for a
    /// prismatic joint), each inside the joint's own range (the task file's
    /// ``robot.joint_limits``); a continuous joint given a range becomes a revolute one.
    fn with_joint_limits(&self, limits: BTreeMap<String, (f64, f64)>) -> PyResult<Self> {
        let mut chain = self.chain.clone();
        for (joint, (lower, upper)) in &limits {
            chain = chain
                .with_joint_range(joint, *lower, *upper)
                .map_err(lib_error)?;
        }
        Ok(Self::new(chain))
    }

    /// The middle of the joint limits, shape ``(dof,)`` (0 for an unbounded joint): the seed
    /// the selection uses.
    fn mid_configuration<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_vec(py, self.chain.mid_configuration())
    }

    /// Whether each configuration lies within the joint limits (bounds included): a ``bool``
    /// for ``(dof,)``, a ``bool`` array ``(n,)`` for ``(n, dof)``.
    fn within_limits<'py>(&self, py: Python<'py>, q: FloatArray<'py>) -> PyResult<Py<PyAny>> {
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

    /// The tip pose ``base_from_tip`` (metres): ``(4, 4)`` for ``q`` of shape ``(dof,)``,
    /// ``(n, 4, 4)`` for ``(n, dof)``. Batches are written in place in parallel without the
    /// GIL, each value bit-identical to the call on that configuration alone. ``q`` may have
    /// any layout (Fortran order and strided views are read through their strides). ``out``:
    /// an existing C-contiguous float64 array of that shape to write into (and return), so
    /// that repeated calls allocate nothing; on an error its contents are unspecified.
    #[pyo3(signature = (q, out = None))]
    fn fk<'py>(
        &self,
        py: Python<'py>,
        q: FloatArray<'py>,
        out: Option<Bound<'py, PyAny>>,
    ) -> PyResult<Py<PyAny>> {
        let (poses, _) = self.evaluate(py, q, Some(out), None)?;
        poses.ok_or_else(|| error("no pose was computed"))
    }

    /// The geometric Jacobian of the tip in the base frame, rows ``[v; ω]``: ``(6, dof)`` for
    /// ``q`` of shape ``(dof,)``, ``(n, 6, dof)`` for ``(n, dof)``; written as :meth:`fk`
    /// writes poses. ``out``: an existing C-contiguous float64 array of that shape to write
    /// into (and return).
    #[pyo3(signature = (q, out = None))]
    fn jacobian<'py>(
        &self,
        py: Python<'py>,
        q: FloatArray<'py>,
        out: Option<Bound<'py, PyAny>>,
    ) -> PyResult<Py<PyAny>> {
        let (_, jacobians) = self.evaluate(py, q, None, Some(out))?;
        jacobians.ok_or_else(|| error("no Jacobian was computed"))
    }

    /// Both the tip pose and the Jacobian, in one pass: ``(poses, jacobians)`` with shapes
    /// ``(4, 4)`` and ``(6, dof)``, or ``(n, 4, 4)`` and ``(n, 6, dof)``; written as :meth:`fk`
    /// writes poses. ``out``: a pair of existing C-contiguous float64 arrays of those shapes to
    /// write into (and return).
    #[pyo3(signature = (q, out = None))]
    fn fk_jacobian<'py>(
        &self,
        py: Python<'py>,
        q: FloatArray<'py>,
        out: Option<(Bound<'py, PyAny>, Bound<'py, PyAny>)>,
    ) -> PyResult<(Py<PyAny>, Py<PyAny>)> {
        let (pose_out, jacobian_out) = match out {
            Some((p, j)) => (Some(p), Some(j)),
            None => (None, None),
        };
        match self.evaluate(py, q, Some(pose_out), Some(jacobian_out))? {
            (Some(poses), Some(jacobians)) => Ok((poses, jacobians)),
            _ => Err(error("no Jacobian was computed")),
        }
    }

    /// The classical indices of the rows ``part`` (``"full"``, ``"translation"`` = ``Jv``,
    /// ``"rotation"`` = ``Jω``) of the Jacobian, as a dict of arrays (scalars for one
    /// configuration): ``yoshikawa`` = sqrt(det(J Jᵀ)), ``inverse_condition`` = σmin/σmax of J,
    /// ``inverse_condition_squared`` = λmin/λmax of J Jᵀ (the paper's eq. 12) and
    /// ``singular_values`` (descending, shape ``(rows,)`` or ``(n, rows)``).
    #[pyo3(signature = (q, part = "full"))]
    fn indices<'py>(
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

    /// The task-relevant manipulability ``M_T = uᵀ J Jᵀ u = ‖Jᵀ u‖²`` (paper eq. 13) of the rows
    /// ``part`` along the unit direction ``u``: 6-D ``[v; ω]`` for ``"full"`` (the paper's raw
    /// J), 3-D for ``"translation"`` and ``"rotation"``. ``u`` is normalised; it may be one
    /// direction for every configuration or one per configuration, shape ``(n, k)``.
    #[pyo3(signature = (q, u, part = "full"))]
    fn task_relevant<'py>(
        &self,
        py: Python<'py>,
        q: FloatArray<'py>,
        u: FloatArray<'py>,
        part: &str,
    ) -> PyResult<Py<PyAny>> {
        self.directional(py, q, u, part, task_relevant)
    }

    /// The velocity transmission ratio ``1 / sqrt(uᵀ (J Jᵀ)⁻¹ u)`` along the unit direction
    /// ``u`` (0 along a singular direction); arguments as for :meth:`task_relevant`.
    #[pyo3(signature = (q, u, part = "full"))]
    fn velocity_transmission_ratio<'py>(
        &self,
        py: Python<'py>,
        q: FloatArray<'py>,
        u: FloatArray<'py>,
        part: &str,
    ) -> PyResult<Py<PyAny>> {
        self.directional(py, q, u, part, velocity_transmission_ratio)
    }

    /// The positions of the base origin, every moving joint's origin and the tip, shape
    /// ``(dof + 2, 3)`` in the base frame (m): the polyline of the arm's links.
    fn joint_origins<'py>(&self, py: Python<'py>, q: FloatArray<'py>) -> PyResult<Py<PyAny>> {
        let (data, batch) = self.configurations(&q)?;
        if batch.is_some() {
            return Err(error("joint_origins takes one configuration, shape (dof,)"));
        }
        let points = self.chain.joint_origins(&data).map_err(lib_error)?;
        let count = points.len();
        let flat: Vec<f64> = points.iter().flat_map(|p| [p.x, p.y, p.z]).collect();
        Ok(array(py, flat, &[count, 3])?.into_any().unbind())
    }

    /// Inverse kinematics of one target pose ``(4, 4)`` or of many ``(n, 4, 4)`` (each solved
    /// independently, in parallel): the configuration, inside the limits, at which the tip
    /// reaches ``base_from_target``. ``q_start``, the start configuration, is ``(dof,)``
    /// (shared) or ``(n, dof)``; default the middle of the limits. ``random_seed`` seeds the
    /// random restarts.
    ///
    /// One pose gives a dict ``q`` (array, or ``None`` when not converged), ``converged``,
    /// ``position_error`` (m), ``rotation_error`` (rad), ``iterations``, ``failure`` (``None``
    /// or a dict ``reason`` in ``unreachable``/``time_limit``/``iteration_limit``,
    /// ``best_q``, ``attempts``). Many poses give a dict of arrays: ``q`` ``(n, dof)`` (NaN rows
    /// where not converged), ``best_q`` (the best configuration tried), ``converged``
    /// ``(n,)`` bool, ``position_error``, ``rotation_error``, ``iterations`` and
    /// ``failure_reason`` (a list of str or None).
    ///
    /// ``max_time`` is a wall-clock budget per pose (s); with it the result can depend on the
    /// machine's speed. Pass ``max_time=None`` for reproducible results (only ``max_iterations``
    /// stops the search).
    #[pyo3(signature = (
        target,
        q_start = None,
        *,
        position_tolerance = 1e-5,
        rotation_tolerance = 1e-5,
        max_iterations = 100_000,
        max_time = Some(0.005),
        random_seed = 0
    ),
    text_signature = "(self, target, q_start=None, *, position_tolerance=1e-05, \
                      rotation_tolerance=1e-05, max_iterations=100000, max_time=0.005, \
                      random_seed=0)")]
    #[allow(clippy::too_many_arguments)]
    fn ik<'py>(
        &self,
        py: Python<'py>,
        target: FloatArray<'py>,
        q_start: Option<FloatArray<'py>>,
        position_tolerance: f64,
        rotation_tolerance: f64,
        max_iterations: usize,
        max_time: Option<f64>,
        random_seed: u64,
    ) -> PyResult<Bound<'py, PyDict>> {
        let options = ik_options(
            position_tolerance,
            rotation_tolerance,
            max_iterations,
            max_time,
            random_seed,
        )?;
        let dof = self.chain.dof();
        if dof == 0 {
            return Err(error(format!(
                "the chain '{}' has no joints: there is nothing to solve for",
                self.chain.name()
            )));
        }
        let (targets, batch) = poses(&target, "target")?;
        let n = targets.len();
        let starts: Vec<f64> = match &q_start {
            None => self.chain.mid_configuration().repeat(n),
            Some(s) => {
                let (data, start_batch) = rows(s, dof, "q_start")?;
                match (start_batch, batch) {
                    (None, _) => data.repeat(n),
                    (Some(m), Some(n)) if m == n => data,
                    (Some(m), _) => {
                        return Err(error(format!(
                            "q_start has {m} rows but there are {n} target pose(s); give one \
                             start configuration (dof,) or one per pose (n, dof)"
                        )))
                    }
                }
            }
        };
        let chain = &self.chain;
        let dict = PyDict::new(py);
        let Some(n) = batch else {
            let s = py
                .detach(|| solve_ik(chain, &targets[0], &starts, &options))
                .map_err(lib_error)?;
            dict.set_item("q", s.q.clone().map(|q| PyArray1::from_vec(py, q)))?;
            dict.set_item("converged", s.converged())?;
            dict.set_item("position_error", s.position_error)?;
            dict.set_item("rotation_error", s.rotation_error)?;
            dict.set_item("iterations", s.iterations)?;
            match &s.failure {
                None => dict.set_item("failure", py.None())?,
                Some(f) => {
                    let failure = PyDict::new(py);
                    failure.set_item("reason", failure_reason(&s))?;
                    failure.set_item("best_q", PyArray1::from_vec(py, f.best_q.clone()))?;
                    failure.set_item("attempts", f.attempts)?;
                    failure.set_item("message", f.to_string())?;
                    dict.set_item("failure", failure)?;
                }
            }
            return Ok(dict);
        };
        // Every result is written once, in place, by the task that solves its pose.
        let q_out = new_float_array(py, &[n, dof])?;
        let best_out = new_float_array(py, &[n, dof])?;
        let converged_out = PyArray1::<bool>::zeros(py, n, false);
        let errors_out = [new_float_array(py, &[n])?, new_float_array(py, &[n])?];
        let iterations_out = PyArray1::<i64>::zeros(py, n, false);
        let mut reasons: Vec<Option<&'static str>> = vec![None; n];
        {
            let mut q_guard = q_out.try_readwrite().map_err(|e| error(e.to_string()))?;
            let mut best_guard = best_out.try_readwrite().map_err(|e| error(e.to_string()))?;
            let mut converged_guard = converged_out
                .try_readwrite()
                .map_err(|e| error(e.to_string()))?;
            let mut position_guard = errors_out[0]
                .try_readwrite()
                .map_err(|e| error(e.to_string()))?;
            let mut rotation_guard = errors_out[1]
                .try_readwrite()
                .map_err(|e| error(e.to_string()))?;
            let mut iterations_guard = iterations_out
                .try_readwrite()
                .map_err(|e| error(e.to_string()))?;
            let q_rows = q_guard.as_slice_mut().map_err(|e| error(e.to_string()))?;
            let best_rows = best_guard
                .as_slice_mut()
                .map_err(|e| error(e.to_string()))?;
            let converged = converged_guard
                .as_slice_mut()
                .map_err(|e| error(e.to_string()))?;
            let position = position_guard
                .as_slice_mut()
                .map_err(|e| error(e.to_string()))?;
            let rotation = rotation_guard
                .as_slice_mut()
                .map_err(|e| error(e.to_string()))?;
            let iterations = iterations_guard
                .as_slice_mut()
                .map_err(|e| error(e.to_string()))?;
            let failed = py.detach(|| {
                q_rows
                    .par_chunks_mut(dof.max(1))
                    .zip(best_rows.par_chunks_mut(dof.max(1)))
                    .zip(converged.par_iter_mut())
                    .zip(position.par_iter_mut())
                    .zip(rotation.par_iter_mut())
                    .zip(iterations.par_iter_mut())
                    .zip(reasons.par_iter_mut())
                    .zip(targets.par_iter())
                    .zip(starts.par_chunks(dof.max(1)))
                    .enumerate()
                    .map(|(k, item)| {
                        let (
                            (
                                (
                                    (((((q, best), converged), position), rotation), iterations),
                                    reason,
                                ),
                                target,
                            ),
                            start,
                        ) = item;
                        let s = solve_ik(chain, target, start, &options).map_err(|e| (k, e))?;
                        match (&s.q, &s.failure) {
                            (Some(v), _) => {
                                copy_into(q, v);
                                copy_into(best, v);
                            }
                            (None, failure) => {
                                q.fill(f64::NAN);
                                match failure {
                                    Some(f) => copy_into(best, &f.best_q),
                                    None => best.fill(f64::NAN),
                                }
                            }
                        }
                        *converged = s.converged();
                        *position = s.position_error;
                        *rotation = s.rotation_error;
                        *iterations = s.iterations as i64;
                        *reason = failure_reason(&s);
                        Ok(())
                    })
                    .filter_map(Result::err)
                    .min_by_key(|(k, _)| *k)
            });
            if let Some((_, e)) = failed {
                return Err(lib_error(e));
            }
        }
        dict.set_item("q", q_out)?;
        dict.set_item("best_q", best_out)?;
        dict.set_item("converged", converged_out)?;
        let [position_error, rotation_error] = errors_out;
        dict.set_item("position_error", position_error)?;
        dict.set_item("rotation_error", rotation_error)?;
        dict.set_item("iterations", iterations_out)?;
        dict.set_item("failure_reason", PyList::new(py, reasons)?)?;
        Ok(dict)
    }

    /// Inverse kinematics along a trajectory of tip poses ``(n, 4, 4)`` (base frame, in order):
    /// continuous joint paths inside the limits, one per distinct initial solution (branch),
    /// no joint moving more than ``max_joint_step`` between samples. Deterministic (iteration
    /// budgets only).
    ///
    /// Returns a dict: ``feasible`` (bool), ``branches`` (a list of ``(n, dof)`` arrays) and
    /// ``failure`` (``None``, or a dict ``sample``, ``reason`` in
    /// ``unreachable``/``joint_limit``/``discontinuity``, ``detail``).
    ///
    /// A batch of ``b`` trajectories ``(b, n, 4, 4)``, all from ``q_start`` with the same
    /// options, returns a list of ``b`` such dicts, each what the trajectory alone gives, bit
    /// for bit; they are solved together, their branches tracked four at a time in vector
    /// lanes (faster than one call per trajectory), with the GIL released.
    ///
    /// ``q_start`` is the start configuration ``(dof,)`` near which the first sample is solved
    /// (default the middle of the limits); ``random_seed`` seeds the restarts.
    #[pyo3(signature = (
        targets,
        q_start = None,
        *,
        max_joint_step = 0.5,
        branches = 4,
        per_sample_iterations = 30,
        max_iterations = 2000,
        position_tolerance = 1e-5,
        rotation_tolerance = 1e-5,
        random_seed = 0
    ))]
    #[allow(clippy::too_many_arguments)]
    fn ik_trajectory<'py>(
        &self,
        py: Python<'py>,
        targets: FloatArray<'py>,
        q_start: Option<FloatArray<'py>>,
        max_joint_step: f64,
        branches: usize,
        per_sample_iterations: usize,
        max_iterations: usize,
        position_tolerance: f64,
        rotation_tolerance: f64,
        random_seed: u64,
    ) -> PyResult<Bound<'py, PyAny>> {
        let dof = self.chain.dof();
        let (trajectories, batch) = trajectories(&targets, "targets")?;
        let q_start = match &q_start {
            None => self.chain.mid_configuration(),
            Some(s) => match rows(s, dof, "q_start")? {
                (data, None) => data,
                (_, Some(_)) => return Err(error("q_start must have shape (dof,)")),
            },
        };
        let options = TrajectoryIkOptions {
            ik: ik_options(
                position_tolerance,
                rotation_tolerance,
                max_iterations,
                None,
                random_seed,
            )?,
            max_joint_step,
            branches,
            per_sample_iterations,
        };
        let chain = &self.chain;
        let batch_of: Vec<&[Isometry3<f64>]> = trajectories.iter().map(Vec::as_slice).collect();
        let results = py
            .detach(|| solve_trajectories(chain, &batch_of, &q_start, &options))
            .map_err(lib_error)?;
        let mut dicts = Vec::with_capacity(results.len());
        for (k, result) in results.into_iter().enumerate() {
            let result = match (result, batch) {
                (Ok(result), _) => result,
                (Err(e), None) => return Err(lib_error(e)),
                (Err(e), Some(_)) => return Err(error(format!("targets[{k}]: {e}"))),
            };
            dicts.push(trajectory_dict(py, &result, dof)?);
        }
        match batch {
            None => Ok(dicts.remove(0).into_any()),
            Some(_) => Ok(PyList::new(py, dicts)?.into_any()),
        }
    }

    /// An orthonormal basis of the joint velocities that leave the tip's twist unchanged at
    /// ``q`` (its self-motion directions), shape ``(dof, k)``: ``k = dof − rank`` (1 for a
    /// 7-joint arm away from singularities). ``rows`` is ``"pose"`` (all six rows of J) or
    /// ``"position"`` (the linear rows only: the orientation is free). A direction counts
    /// when its singular value is at most ``tolerance`` times the largest.
    #[pyo3(signature = (q, rows = "pose", tolerance = 1e-9))]
    fn nullspace<'py>(
        &self,
        py: Python<'py>,
        q: FloatArray<'py>,
        rows: &str,
        tolerance: f64,
    ) -> PyResult<Py<PyAny>> {
        let rows = kept_rows(rows)?;
        if !(tolerance.is_finite() && tolerance >= 0.0) {
            return Err(error(format!(
                "tolerance must be a non-negative number, got {tolerance}"
            )));
        }
        let (q, None) = self.configurations(&q)? else {
            return Err(error("q must have shape (dof,)"));
        };
        let mut jacobian = Matrix6xX::zeros(self.chain.dof());
        self.chain
            .pose_and_jacobian_into(&q, &mut jacobian)
            .map_err(lib_error)?;
        let basis = null_space(&jacobian, rows, tolerance);
        let (dof, k) = basis.shape();
        // nalgebra is column-major; numpy wants rows.
        let flat: Vec<f64> = (0..dof)
            .flat_map(|r| (0..k).map(move |c| (r, c)))
            .map(|(r, c)| basis[(r, c)])
            .collect();
        Ok(array(py, flat, &[dof, k])?.into_any().unbind())
    }

    /// Moves a joint path along the arm's self-motion to maximise the task-relevant index
    /// along it: the path through the tip poses ``targets`` ``(n, 4, 4)`` (base frame) that
    /// maximises ``Σ M_T²`` (``μ_l2²``), where ``M_T`` at each sample is measured along the
    /// direction the tip moves to the next pose (the last sample: from the previous one),
    /// no joint moving more than ``max_joint_step`` between samples, inside the limits —
    /// what ``ik.redundancy: optimize`` does for a candidate. ``q`` ``(n, dof)`` is a joint
    /// path on the targets (e.g. a branch from :meth:`ik_trajectory`); the result is never
    /// worse than it. ``mode`` and ``length_scale`` as in a task file's ``index``;
    /// ``spacing`` (rad) and ``reach`` set how the self-motion is traced around ``q``.
    ///
    /// Returns a dict: ``q`` ``(n, dof)``, ``m_t`` ``(n,)`` (NaN where the tip is still),
    /// ``mu_l2`` (of the result, over samples, as ``sqrt(Σ M_T²)``), ``mu_l2_seed`` (of
    /// ``q``) and ``mu_l2_min`` (the smallest over the traced self-motion).
    #[pyo3(signature = (
        targets,
        q,
        *,
        mode = "twist",
        length_scale = 1.0,
        max_joint_step = 0.5,
        spacing = 0.2,
        reach = 4,
        position_tolerance = 1e-5,
        rotation_tolerance = 1e-5
    ))]
    #[allow(clippy::too_many_arguments)]
    fn optimize_self_motion<'py>(
        &self,
        py: Python<'py>,
        targets: FloatArray<'py>,
        q: FloatArray<'py>,
        mode: &str,
        length_scale: f64,
        max_joint_step: f64,
        spacing: f64,
        reach: usize,
        position_tolerance: f64,
        rotation_tolerance: f64,
    ) -> PyResult<Bound<'py, PyDict>> {
        let dof = self.chain.dof();
        let (targets, _) = poses(&targets, "targets")?;
        let n = targets.len();
        let (data, batch) = self.configurations(&q)?;
        if batch != Some(n) {
            return Err(error(format!(
                "q must have shape ({n}, {dof}): one configuration per target"
            )));
        }
        for (name, value) in [
            ("max_joint_step", max_joint_step),
            ("spacing", spacing),
            ("position_tolerance", position_tolerance),
            ("rotation_tolerance", rotation_tolerance),
        ] {
            if !(value.is_finite() && value > 0.0) {
                return Err(error(format!(
                    "{name} must be a positive number, got {value}"
                )));
            }
        }
        if reach == 0 || reach > 1000 {
            return Err(error(format!(
                "reach must be between 1 and 1000, got {reach}"
            )));
        }
        let rows = index_mode(mode, length_scale)?;
        let seed: Vec<Vec<f64>> = data.chunks(dof).map(<[f64]>::to_vec).collect();
        // The seed must be a feasible path: on its targets, inside the limits, small steps.
        let (lower, upper) = (self.chain.lower(), self.chain.upper());
        for (i, (q, target)) in seed.iter().zip(&targets).enumerate() {
            let pose = self.chain.pose(q).map_err(lib_error)?;
            let off = (pose.translation.vector - target.translation.vector).norm();
            let turn = pose
                .rotation
                .angle_to(&target.rotation.to_rotation_matrix());
            if off > position_tolerance * 10.0 || turn > rotation_tolerance * 10.0 {
                return Err(error(format!(
                    "q[{i}] puts the tip {off:.3e} m and {turn:.3e} rad from targets[{i}]: \
                     give a joint path on the targets (e.g. a branch of ik_trajectory)"
                )));
            }
            if let Some(j) = (0..dof).find(|&j| q[j] < lower[j] || q[j] > upper[j]) {
                return Err(error(format!("q[{i}, {j}] is outside the joint limits")));
            }
            if i > 0 {
                let step = q
                    .iter()
                    .zip(&seed[i - 1])
                    .map(|(a, b)| (a - b).abs())
                    .fold(0.0, f64::max);
                if step > max_joint_step {
                    return Err(error(format!(
                        "q moves a joint {step:.3} between samples {} and {i}, more than \
                         max_joint_step ({max_joint_step})",
                        i - 1
                    )));
                }
            }
        }
        let directions: Vec<Option<Direction>> = (0..n)
            .map(|i| {
                let (a, b) = if i + 1 < n {
                    (i, i + 1)
                } else {
                    (i.saturating_sub(1), i)
                };
                (a != b)
                    .then(|| wrist_tangent(&targets[a], &targets[b], rows))
                    .flatten()
            })
            .collect();
        let value = |i: usize, _: &[f64], jacobian: &Matrix6xX<f64>| -> f64 {
            directions[i].map_or(0.0, |d| rows.task_relevant(jacobian, &d).powi(2))
        };
        let options = SelfMotionOptions {
            spacing,
            reach,
            max_joint_step,
            position_tolerance,
            rotation_tolerance,
        };
        let chain = &self.chain;
        let found = py
            .detach(|| {
                optimize_self_motion(chain, &targets, &[&seed], KeptRows::Pose, &value, &options)
            })
            .ok_or_else(|| error("no joint path was found around q"))?;
        let seed_total: f64 = {
            let mut jacobian = Matrix6xX::zeros(dof);
            seed.iter()
                .enumerate()
                .map(|(i, q)| {
                    chain
                        .pose_and_jacobian_into(q, &mut jacobian)
                        .map_or(0.0, |_| value(i, q, &jacobian))
                })
                .sum()
        };
        let m_t: Vec<f64> = found
            .values
            .iter()
            .zip(&directions)
            .map(|(v, d)| if d.is_some() { v.sqrt() } else { f64::NAN })
            .collect();
        let dict = PyDict::new(py);
        let flat: Vec<f64> = found.q.iter().flatten().copied().collect();
        dict.set_item("q", array(py, flat, &[n, dof])?)?;
        dict.set_item("m_t", PyArray1::from_vec(py, m_t))?;
        dict.set_item("mu_l2", found.total.sqrt())?;
        dict.set_item("mu_l2_seed", seed_total.sqrt())?;
        dict.set_item("mu_l2_min", found.worst_total.sqrt())?;
        Ok(dict)
    }

    /// Joint effort limits, shape ``(dof,)`` (N·m, or N for a prismatic joint; ``inf`` where
    /// the source gives none), from the URDF ``<limit effort>``, the MJCF force ranges or the
    /// built-in arm's datasheet.
    #[getter]
    fn effort_limits<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.limits(py, |l| l.effort)
    }

    /// Joint velocity limits, shape ``(dof,)`` (rad/s or m/s; ``inf`` where the source gives
    /// none), as :func:`time_path` takes them.
    #[getter]
    fn velocity_limits<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.limits(py, |l| l.velocity)
    }

    /// Joint acceleration limits, shape ``(dof,)`` (rad/s² or m/s²; ``inf`` where the source
    /// gives none: most robots), as :func:`time_path` takes them.
    #[getter]
    fn acceleration_limits<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.limits(py, |l| l.acceleration)
    }

    /// The total mass of the links the joints move (kg; links before the first moving joint
    /// are not counted). A ``GraspathError`` when a moving link has no inertial data.
    #[getter]
    fn moving_mass(&self) -> PyResult<f64> {
        Ok(self.dynamics_model()?.moving_mass())
    }

    /// The gravity torques ``g(q)``: the joint torques (N·m, or N for a prismatic joint) that
    /// hold the arm, and the ``payload``, still at ``q`` against ``gravity`` (a vector in the
    /// chain's **base frame**, m/s²; default 9.81 m/s² along the base's −z). Shape ``(dof,)``
    /// for ``q`` of shape ``(dof,)``, ``(n, dof)`` for ``(n, dof)`` (in parallel, the GIL
    /// released; each row what the single call gives, bit for bit). Pinocchio's
    /// ``computeGeneralizedGravity``.
    ///
    /// ``payload``: ``None`` or a dict ``{"mass": kg, "com": [x, y, z], "inertia": I}`` carried
    /// rigidly at the tool frame (the frame of :meth:`fk`): ``com`` in the tool frame (m,
    /// default its origin), ``I`` about the centre of mass along the tool frame's axes
    /// (kg·m²), a ``(3, 3)`` symmetric matrix or the principal moments ``[ixx, iyy, izz]``
    /// (default 0: a point mass). The mass is at most 1000 kg, the centre of mass at most
    /// 10 m from the tool frame. Needs each moving link's inertial data (a ``GraspathError``
    /// names the links without).
    #[pyo3(
        signature = (q, *, gravity = None, payload = None),
        text_signature = "(self, q, *, gravity=(0.0, 0.0, -9.81), payload=None)"
    )]
    fn gravity_torques<'py>(
        &self,
        py: Python<'py>,
        q: FloatArray<'py>,
        gravity: Option<FloatArray<'py>>,
        payload: Option<Bound<'py, PyAny>>,
    ) -> PyResult<Py<PyAny>> {
        self.dynamics_call(
            py,
            Quantity::Gravity,
            &q,
            None,
            None,
            gravity.as_ref(),
            payload.as_ref(),
        )
    }

    /// Inverse dynamics by the recursive Newton–Euler algorithm: the joint torques
    /// ``τ = M(q) q̈ + C(q, q̇) q̇ + g(q)`` (N·m or N) for the joint velocities ``qd`` (rad/s)
    /// and accelerations ``qdd`` (rad/s²), each of ``q``'s shape: ``(dof,)`` gives ``(dof,)``,
    /// ``(n, dof)`` gives ``(n, dof)``. Pinocchio's ``rnea``. ``gravity`` and ``payload`` as
    /// for :meth:`gravity_torques`.
    #[pyo3(
        signature = (q, qd, qdd, *, gravity = None, payload = None),
        text_signature = "(self, q, qd, qdd, *, gravity=(0.0, 0.0, -9.81), payload=None)"
    )]
    fn inverse_dynamics<'py>(
        &self,
        py: Python<'py>,
        q: FloatArray<'py>,
        qd: FloatArray<'py>,
        qdd: FloatArray<'py>,
        gravity: Option<FloatArray<'py>>,
        payload: Option<Bound<'py, PyAny>>,
    ) -> PyResult<Py<PyAny>> {
        self.dynamics_call(
            py,
            Quantity::InverseDynamics,
            &q,
            Some(&qd),
            Some(&qdd),
            gravity.as_ref(),
            payload.as_ref(),
        )
    }

    /// The joint-space inertia matrix ``M(q)`` by the composite rigid body algorithm, both
    /// triangles written (symmetric; kg·m², kg on a prismatic joint's row and column):
    /// ``(dof, dof)`` for ``q`` of shape ``(dof,)``, ``(n, dof, dof)`` for ``(n, dof)``.
    /// Pinocchio's ``crba`` (which fills the upper triangle only). ``payload`` as for
    /// :meth:`gravity_torques`.
    #[pyo3(signature = (q, *, payload = None))]
    fn mass_matrix<'py>(
        &self,
        py: Python<'py>,
        q: FloatArray<'py>,
        payload: Option<Bound<'py, PyAny>>,
    ) -> PyResult<Py<PyAny>> {
        self.dynamics_call(
            py,
            Quantity::MassMatrix,
            &q,
            None,
            None,
            None,
            payload.as_ref(),
        )
    }

    fn __repr__(&self) -> String {
        format!(
            "Robot('{}', dof={}, source='{}')",
            self.chain.name(),
            self.chain.dof(),
            self.chain.source_name()
        )
    }
}

impl PyRobot {
    /// Poses and/or Jacobians of `q`: each wanted result (`Some`) goes into a new array
    /// (`Some(None)`) or into the caller's (`Some(Some(out))`), written in place in parallel
    /// without the GIL.
    #[allow(clippy::type_complexity)]
    fn evaluate<'py>(
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

    /// Evaluates a per-configuration directional index in parallel, each value written once
    /// into the result array.
    fn directional<'py>(
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

/// The dict `Robot.ik_trajectory` returns for one trajectory's result (`dof` joints).
fn trajectory_dict<'py>(
    py: Python<'py>,
    result: &TrajectoryIkResult,
    dof: usize,
) -> PyResult<Bound<'py, PyDict>> {
    let dict = PyDict::new(py);
    dict.set_item("feasible", result.feasible())?;
    let list = PyList::empty(py);
    for branch in &result.branches {
        let flat: Vec<f64> = branch.q.iter().flatten().copied().collect();
        list.append(array(py, flat, &[branch.q.len(), dof])?)?;
    }
    dict.set_item("branches", list)?;
    match &result.failure {
        None => dict.set_item("failure", py.None())?,
        Some(f) => {
            let failure = PyDict::new(py);
            failure.set_item("sample", f.sample)?;
            failure.set_item("reason", f.reason.as_str())?;
            failure.set_item("detail", &f.detail)?;
            dict.set_item("failure", failure)?;
        }
    }
    Ok(dict)
}
