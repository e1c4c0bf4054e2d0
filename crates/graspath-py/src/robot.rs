//! `graspath.Robot`: one serial chain (a URDF or MJCF chain, or a built-in arm) with forward
//! kinematics, the geometric Jacobian, manipulability indices, inverse kinematics and
//! rigid-body dynamics, for one configuration or for many at once.
//!
//! Frames and units as in the library: every pose and Jacobian is in the chain **base frame**;
//! metres and radians; the Jacobian has rows `[v; ω]` (Pinocchio's `LOCAL_WORLD_ALIGNED`).
//!
//! The `#[pymethods]` block (PyO3 wants one per class) holds each method's signature and
//! documentation; the work is in the files beside it, one per concern: [`kinematics`] (poses,
//! Jacobians, limits), [`indices`] (manipulability), [`ik`], [`self_motion`] and
//! [`dynamics`].

use crate::convert::{array, error, lib_error, single_pose, FloatArray};
use graspath::manipulability::{task_relevant, velocity_transmission_ratio};
use graspath::robot::{
    Chain, Dynamics, RobotSource, SelfMotionOptions, TrajectoryIkOptions, UrdfRobot,
};
use nalgebra::Isometry3;
use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::collections::BTreeMap;
use std::path::PathBuf;
use std::sync::OnceLock;

mod dynamics;
mod ik;
mod indices;
mod kinematics;
mod self_motion;

pub(crate) use dynamics::payload_body;
use dynamics::Quantity;
use ik::ik_options;

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
}

/// A tool offset `tip_from_tool` from an optional `(4, 4)` array.
fn tool_pose(tool: Option<FloatArray<'_>>) -> PyResult<Option<Isometry3<f64>>> {
    tool.map(|t| single_pose(&t, "tool")).transpose()
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
        self.limit_flags(py, q)
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
        self.classical_indices(py, q, part)
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
        self.solve_poses(py, target, q_start, options)
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
        self.solve_pose_trajectories(py, targets, q_start, options)
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
        self.self_motion_basis(py, q, rows, tolerance)
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
        let options = SelfMotionOptions {
            spacing,
            reach,
            max_joint_step,
            position_tolerance,
            rotation_tolerance,
        };
        self.optimized_self_motion(py, targets, q, mode, length_scale, options)
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
