"""Type stubs of the native module ``graspath._graspath`` (re-exported by ``graspath``).

Frames and units: metres and radians; poses are 4×4 homogeneous matrices named ``a_from_b``;
every robot pose and Jacobian is in the chain base frame, Jacobian rows ``[v; ω]``.
"""

from os import PathLike
from pathlib import Path
from typing import Any, Dict, List, Literal, Mapping, Optional, Sequence, Tuple, TypedDict, Union, overload

import numpy as np
import numpy.typing as npt

from .results import (
    CandidateRecord,
    GeneratedGrasps,
    GraspFile,
    IkBatchResult,
    IkResult,
    Indices,
    MjcfArm,
    MjcfWorld,
    PairRecord,
    PlacementMap,
    RecordColumn,
    ResultCache,
    SelfMotion,
    Summary,
    TaskCandidate,
    TimedMotion,
    TimedPath,
    TrainedModel,
    TrajectoryIk,
)

__version__: str
DEFAULTS: Dict[str, float]
"""The library's task defaults that ``Task.from_arrays`` spells out in its signature."""
SPELLINGS: Dict[str, List[str]]
"""Every spelling each named setting accepts (``norm``, ``measure``, ``mode``, ``redundancy``,
``part``, ``discretization``, ``format``, ``frame``), from the library's spelling tables: the
values of the ``Literal`` types below."""

ArrayLike = npt.ArrayLike
FloatArray = npt.NDArray[np.float64]
BoolArray = npt.NDArray[np.bool_]
IntArray = npt.NDArray[np.int64]
Part = Literal["full", "translation", "rotation"]
StrPath = Union[str, "PathLike[str]"]

class _PayloadMass(TypedDict):
    mass: float

class Payload(_PayloadMass, total=False):
    """A rigid payload carried at the tool frame: ``mass`` (kg, required), ``com`` (tool frame,
    m; default the origin), ``inertia`` about the centre of mass, tool frame axes (kg·m²; a
    3×3 symmetric matrix or the principal moments ``[ixx, iyy, izz]``; default 0)."""

    com: ArrayLike
    inertia: ArrayLike

class Robot:
    """A serial kinematic chain from a base link to a tip link (plus an optional tool)."""

    @staticmethod
    def baxter(arm: Literal["left", "right"] = "left", tool: Optional[ArrayLike] = None) -> Robot:
        """One arm of the built-in Baxter (``base`` → ``{arm}_gripper``); ``tool`` = ``tip_from_tool``."""
    @staticmethod
    def builtin(
        name: Literal[
            "baxter", "panda", "fr3", "ur5", "ur10", "ur5e", "ur10e", "iiwa14", "xarm7", "gen3"
        ],
        arm: Optional[str] = None,
        tool: Optional[ArrayLike] = None,
    ) -> Robot:
        """A built-in robot's chain (``arm``: ``left``/``right`` for Baxter, ``arm`` otherwise), base to tool frame."""
    @staticmethod
    def from_urdf(
        path: StrPath,
        base_link: str,
        tip_link: str,
        tool: Optional[ArrayLike] = None,
        *,
        search_paths: Optional[Sequence[StrPath]] = None,
        xacro_args: Optional[Mapping[str, str]] = None,
    ) -> Robot:
        """The chain ``base_link`` → ``tip_link`` of a URDF file; a ``*.xacro`` file is expanded
        by the ``xacro`` program with ``xacro_args`` (xacro runs code: only for files you
        trust); ``search_paths`` are where ``package://PKG`` and ``$(find PKG)`` look first."""
    @staticmethod
    def from_mjcf(
        path: StrPath, base_body: str, tip_body: str, tool: Optional[ArrayLike] = None
    ) -> Robot:
        """The chain ``base_body`` → ``tip_body`` of an MJCF (MuJoCo XML) file (hinge and slide joints)."""
    @classmethod
    def load(
        cls,
        path: StrPath,
        base: str,
        tip: str,
        tool: Optional[ArrayLike] = None,
        *,
        search_paths: Optional[Sequence[StrPath]] = None,
        xacro_args: Optional[Mapping[str, str]] = None,
    ) -> Robot:
        """The chain ``base`` → ``tip`` (links; an MJCF file's bodies) of a URDF, xacro or MJCF
        file, its format told by its name (``.urdf``, ``.xacro``, ``.mjcf``) or, for ``.xml`` and
        other names, by its root element (``<robot>`` or ``<mujoco>``); ``tool`` =
        ``tip_from_tool``. ``search_paths`` and ``xacro_args`` are for a URDF, as in
        :meth:`from_urdf` (only a file named ``*.xacro`` is expanded); for an MJCF file they
        raise :class:`GraspathValueError`. A file of neither format raises
        :class:`GraspathValueError` naming it; a missing one :class:`GraspathFileNotFoundError`."""
    @staticmethod
    def from_urdf_string(
        xml: str,
        base_link: str,
        tip_link: str,
        tool: Optional[ArrayLike] = None,
        source_name: str = "<urdf string>",
    ) -> Robot:
        """The chain ``base_link`` → ``tip_link`` of URDF text."""
    @property
    def dof(self) -> int:
        """The number of independent joints."""
    @property
    def name(self) -> str:
        """``base->tip``."""
    @property
    def source(self) -> str:
        """The file or built-in model the chain came from."""
    @property
    def base_link(self) -> str: ...
    @property
    def tip_link(self) -> str: ...
    @property
    def joint_names(self) -> List[str]: ...
    @property
    def lower(self) -> FloatArray:
        """Lower joint limits ``(dof,)`` (``-inf`` for continuous joints)."""
    @property
    def upper(self) -> FloatArray:
        """Upper joint limits ``(dof,)`` (``+inf`` for continuous joints)."""
    def with_joint_limits(self, limits: Mapping[str, Tuple[float, float]]) -> "Robot":
        """This robot with narrower joint ranges ``{joint: (lower, upper)}`` (rad, or m for a
        prismatic joint), each inside the joint's own range; a continuous joint given a range
        becomes a revolute one. Raises ``GraspathValueError`` otherwise."""
    def mid_configuration(self) -> FloatArray:
        """The middle of the joint limits ``(dof,)``."""
    @overload
    def within_limits(self, q: Sequence[float]) -> bool: ...
    @overload
    def within_limits(self, q: ArrayLike) -> Union[bool, BoolArray]: ...
    def fk(self, q: ArrayLike, out: Optional[FloatArray] = None) -> FloatArray:
        """``base_from_tip``: ``(4, 4)`` for ``(dof,)``, ``(n, 4, 4)`` for ``(n, dof)``; written
        in place in parallel without the GIL (``q`` in any layout; ``out``: C-contiguous
        float64 of that shape, written and returned)."""
    def jacobian(self, q: ArrayLike, out: Optional[FloatArray] = None) -> FloatArray:
        """Geometric Jacobian ``[v; ω]``: ``(6, dof)`` or ``(n, 6, dof)``; ``out`` as for ``fk``."""
    def fk_jacobian(
        self, q: ArrayLike, out: Optional[Tuple[FloatArray, FloatArray]] = None
    ) -> Tuple[FloatArray, FloatArray]:
        """``(poses, jacobians)`` in one pass; ``out`` a pair as for ``fk``."""
    def indices(self, q: ArrayLike, part: Part = "full") -> Indices:
        """``yoshikawa``, ``inverse_condition``, ``inverse_condition_squared`` (floats or
        ``(n,)`` arrays) and ``singular_values`` (``(rows,)`` or ``(n, rows)``).

        Returns
        -------
        Indices
            Float values for one configuration ``(dof,)``, ``(n,)`` arrays for ``(n, dof)``.
            See :mod:`graspath.results`.
        """
    def task_relevant(self, q: ArrayLike, u: ArrayLike, part: Part = "full") -> Union[float, FloatArray]:
        """``M_T = ‖Jᵀ u‖²`` along the (normalised) direction ``u`` (6-D for ``full``, else 3-D)."""
    def velocity_transmission_ratio(
        self, q: ArrayLike, u: ArrayLike, part: Part = "full"
    ) -> Union[float, FloatArray]:
        """``1 / sqrt(uᵀ (J Jᵀ)⁻¹ u)`` along ``u`` (0 along a singular direction)."""
    def joint_origins(self, q: ArrayLike) -> FloatArray:
        """Base origin, joint origins and tip, ``(dof + 2, 3)``."""
    def ik(
        self,
        target: ArrayLike,
        q_start: Optional[ArrayLike] = None,
        *,
        position_tolerance: float = 1e-5,
        rotation_tolerance: float = 1e-5,
        max_iterations: int = 100_000,
        max_time: Optional[float] = 0.005,
        random_seed: int = 0,
    ) -> Union[IkResult, IkBatchResult]:
        """IK of one pose ``(4, 4)`` (dict with ``q`` or ``None``, ``converged``, errors,
        ``iterations``, ``failure``) or many ``(n, 4, 4)`` (dict of arrays ``q`` with NaN rows,
        ``best_q``, ``converged``, ``position_error``, ``rotation_error``, ``iterations``,
        ``failure_reason``). ``q_start``: the start configuration ``(dof,)`` or ``(n, dof)``
        (default the middle of the limits); ``random_seed`` seeds the restarts.
        ``max_time=None`` for reproducible results.

        Returns
        -------
        IkResult or IkBatchResult
            :class:`~graspath.results.IkResult` for one pose, :class:`~graspath.results.IkBatchResult` for many.
            See :mod:`graspath.results`.
        """
    def ik_trajectory(
        self,
        targets: ArrayLike,
        q_start: Optional[ArrayLike] = None,
        *,
        max_joint_step: float = 0.5,
        branches: int = 4,
        per_sample_iterations: int = 30,
        max_iterations: int = 2000,
        position_tolerance: float = 1e-5,
        rotation_tolerance: float = 1e-5,
        random_seed: int = 0,
    ) -> Union[TrajectoryIk, List[TrajectoryIk]]:
        """Continuous joint paths through ``targets`` ``(n, 4, 4)`` from the start
        configuration ``q_start`` ``(dof,)`` (default the middle of the limits): ``feasible``,
        ``branches`` (list of ``(n, dof)``), ``failure`` (``None`` or ``sample``, ``reason``,
        ``detail``). A batch ``(b, n, 4, 4)`` gives a list of ``b`` such dicts, solved
        together (each what its trajectory alone gives).

        Returns
        -------
        TrajectoryIk or list of TrajectoryIk
            One per trajectory of a batch.
            See :mod:`graspath.results`.
        """
    def nullspace(
        self,
        q: ArrayLike,
        rows: Literal["pose", "position"] = "pose",
        tolerance: float = 1e-9,
    ) -> FloatArray:
        """An orthonormal basis ``(dof, k)`` of the joint velocities that leave the tip's
        twist (``"pose"``) or its linear velocity (``"position"``) unchanged at ``q``."""
    def optimize_self_motion(
        self,
        targets: ArrayLike,
        q: ArrayLike,
        *,
        mode: Literal["twist", "translation", "rotation"] = "twist",
        length_scale: float = 1.0,
        max_joint_step: float = 0.5,
        spacing: float = 0.2,
        reach: int = 4,
        position_tolerance: float = 1e-5,
        rotation_tolerance: float = 1e-5,
    ) -> SelfMotion:
        """The joint path through ``targets`` ``(n, 4, 4)`` in the self-motion around ``q``
        ``(n, dof)`` (a path on the targets) with the largest ``Σ M_T²``: ``q``, ``m_t``
        (NaN where the tip is still), ``mu_l2``, ``mu_l2_seed``, ``mu_l2_min``.

        Returns
        -------
        SelfMotion
            See :mod:`graspath.results`.
        """
    @property
    def effort_limits(self) -> FloatArray:
        """Joint effort limits ``(dof,)`` (N·m, N for prismatic joints; ``inf`` where unknown)."""
    @property
    def velocity_limits(self) -> FloatArray:
        """Joint velocity limits ``(dof,)`` (rad/s or m/s; ``inf`` where unknown)."""
    @property
    def acceleration_limits(self) -> FloatArray:
        """Joint acceleration limits ``(dof,)`` (rad/s² or m/s²; ``inf`` where unknown)."""
    @property
    def moving_mass(self) -> float:
        """The mass of the links the joints move (kg); an error without inertial data."""
    def gravity_torques(
        self,
        q: ArrayLike,
        *,
        gravity: ArrayLike = (0.0, 0.0, -9.81),
        payload: Optional[Payload] = None,
    ) -> FloatArray:
        """``g(q)`` (N·m): ``(dof,)`` for ``(dof,)``, ``(n, dof)`` for ``(n, dof)`` (in parallel
        without the GIL); ``gravity`` in the base frame (m/s²), ``payload`` at the tool frame."""
    def inverse_dynamics(
        self,
        q: ArrayLike,
        qd: ArrayLike,
        qdd: ArrayLike,
        *,
        gravity: ArrayLike = (0.0, 0.0, -9.81),
        payload: Optional[Payload] = None,
    ) -> FloatArray:
        """``τ = M(q) q̈ + C(q, q̇) q̇ + g(q)`` (RNEA, N·m); ``qd``, ``qdd`` of ``q``'s shape."""
    def mass_matrix(self, q: ArrayLike, *, payload: Optional[Payload] = None) -> FloatArray:
        """``M(q)`` (CRBA, kg·m², symmetric): ``(dof, dof)`` or ``(n, dof, dof)``."""

class Task:
    """A selection task: arms, object path, grasp candidates and settings."""

    @staticmethod
    def load(
        path: StrPath,
        *,
        candidates: Optional[StrPath] = None,
        object_pose: Union[Mapping[str, Sequence[Any]], ArrayLike, None] = None,
    ) -> Task:
        """Reads a task file (YAML or JSON); ``candidates`` reads that candidate file instead of
        the file's ``candidates`` source (keeping its ``format``, ``frame``, … options).

        ``object_pose`` replaces the file's ``object.pose`` (``world_from_object`` at the start,
        world frame, m): a dict in the task file's pose syntax (``{"xyz": [...], "rpy_deg":
        [...]}``, or ``rpy`` (rad), ``quaternion`` ``[x, y, z, w]``, ``matrix``; see
        :func:`pose_matrix`) or a 4×4 array. The path's relative steps start from it; absolute
        steps, the robot and the scene stay (as in :func:`placement_map`). The task equals the
        one a file with that ``object.pose`` describes (learned-model candidates in a scene keep
        the filtering done at the file's pose). Errors name the field
        (``object_pose.quaternion``, …)."""
    @staticmethod
    def parse(
        text: str,
        format: Literal["yaml", "yml", "json"] = "yaml",
        base_dir: Optional[StrPath] = None,
        name: str = "<task>",
    ) -> Task:
        """Parses task text; relative paths resolve against ``base_dir``."""
    @staticmethod
    def from_dict(
        data: Mapping[str, Any], base_dir: Optional[StrPath] = None, name: str = "<dict>"
    ) -> Task:
        """A task from a dict with the task file's schema."""
    @staticmethod
    def from_arrays(
        arms: Mapping[str, Union[Robot, Tuple[Robot, ArrayLike]]],
        object_poses: ArrayLike,
        candidates: ArrayLike,
        *,
        times: Optional[ArrayLike] = None,
        likelihoods: Optional[ArrayLike] = None,
        labels: Optional[Sequence[str]] = None,
        contacts: Optional[ArrayLike] = None,
        mode: Literal["twist", "translation", "rotation"] = "twist",
        length_scale: float = 1.0,
        norm: Literal["rms", "l2", "l1"] = "rms",
        mu0: Optional[float] = None,
        likelihood: Union[Literal["product", "ignore"], float, None] = None,
        pairs: int = 10,
        min_separation: float = 0.08,
        max_joint_step: float = 0.5,
        ik_limit_margin: float = 0.1,
        branches: int = 4,
        ik_random_seed: Optional[int] = None,
        ik_tolerance: float = 1e-5,
        ik_iterations: int = 200,
        redundancy: Optional[Literal["first", "best_branch", "optimize"]] = None,
        measure: Literal["task_relevant", "velocity_ratio", "duration", "dynamic"] = "task_relevant",
        joint_limit_penalty: Optional[float] = None,
        payload: Optional[Payload] = None,
        name: str = "<arrays>",
        robot_name: str = "robot",
    ) -> Task:
        """A task from ``object_poses`` ``(n, 4, 4)`` (world_from_object) and ``candidates``
        ``(k, 4, 4)`` (object_from_wrist). ``ik_random_seed`` (default 0) seeds the IK's
        restarts. ``redundancy`` is the task file's ``ik.redundancy`` (default
        ``"optimize"``). ``measure`` and
        ``joint_limit_penalty`` (a gain ``k``) are the task file's ``index.measure`` and
        ``index.joint_limit_penalty``; ``ik_limit_margin`` (rad) is ``ik.limit_margin``: how far
        inside its limits the IK keeps every revolute joint (0: up to the limits, as in the
        paper)."""
    def with_arms(self, arms: Sequence[str]) -> Task:
        """The same task with only the named arms, in that order."""
    @property
    def name(self) -> str: ...
    @property
    def robot_name(self) -> str: ...
    @property
    def warnings(self) -> List[Tuple[str, str]]:
        """``(field, message)`` of each value that is probably a mistake (degrees in a radians
        field, millimetres, an object inside the table, ...); the task is scored as written."""
    @property
    def arms(self) -> List[str]: ...
    @property
    def object_poses(self) -> FloatArray:
        """``world_from_object`` along the task, ``(n, 4, 4)``."""
    @property
    def times(self) -> FloatArray:
        """Sample times (s), ``(n,)``."""
    @property
    def sample_steps(self) -> List[int]: ...
    @property
    def step_labels(self) -> List[str]: ...
    @property
    def candidate_poses(self) -> FloatArray:
        """``object_from_wrist`` of every candidate, ``(k, 4, 4)``."""
    @property
    def candidates(self) -> List[TaskCandidate]:
        """``id``, ``label``, ``object_from_wrist``, ``likelihood``, ``log_likelihood``, ``contact``.

        Returns
        -------
        list of TaskCandidate
            See :mod:`graspath.results`.
        """
    def robot(self, arm: str) -> Robot: ...
    def world_from_base(self, arm: str) -> FloatArray: ...
    def wrist_trajectory(self, candidate: int, arm: str) -> FloatArray:
        """``base_from_wrist`` along the task for one candidate, ``(n, 4, 4)``."""
    def __len__(self) -> int: ...

class Selection:
    """The result of :func:`select`."""

    @property
    def candidates(self) -> List[CandidateRecord]:
        """The records of ``candidates.json``.

        Returns
        -------
        list of CandidateRecord
            See :mod:`graspath.results`.
        """
    @property
    def pairs(self) -> List[PairRecord]:
        """The records of ``pairs.json``.

        Returns
        -------
        list of PairRecord
            Best first.
            See :mod:`graspath.results`.
        """
    @property
    def summary(self) -> Summary:
        """The document ``summary.json``.

        Returns
        -------
        Summary
            See :mod:`graspath.results`.
        """
    @property
    def arms(self) -> List[str]: ...
    @property
    def norm(self) -> Literal["rms", "l2", "l1"]: ...
    def best(self, arm: str) -> Optional[int]:
        """The id of the best-ranked candidate of ``arm``."""
    def arrays(self, arm: str) -> Dict[str, npt.NDArray[Any]]:
        """Per-candidate numpy arrays, the record columns marked ``arrays`` in
        :func:`record_columns`: ``id``, ``label``, ``feasible``, ``failure_reason``,
        ``failure_sample``, ``failure_joint``, ``rejected``, ``rank``, ``score``, ``log_likelihood``, ``mu_l2``,
        ``mu_linf``, ``mu_l1``, ``mu_rms``, ``yoshikawa_at_grasp``, ``yoshikawa_penalized_at_grasp``,
        ``inverse_condition_at_grasp``, ``inverse_condition_squared_at_grasp``,
        ``limit_distance_min``, ``hugs_limit``, ``clearance``, ``torque_margin`` and
        ``payload_capacity`` (kg; with the object's mass), ``dynamic_manipulability`` ((m/s²)²; with the object's mass or ``measure="dynamic"``), ``duration``,
        ``approach_duration``, ``carry_duration``, ``retreat_duration`` (s),
        ``spline_deviation`` and ``limit_excursion`` (rad; when motions are timed),
        ``contact`` ``(k, 3)``, ``m_t``
        ``(k, n)``, ``ranked_index`` ``(k, n)``. Everything absent is NaN (``None`` for a
        text), never a sentinel: ``rank`` (float64, 1 for the best) is NaN when not ranked,
        ``failure_sample`` (float64) NaN when feasible."""
    def joint_trajectory(self, arm: str, candidate: int) -> Optional[FloatArray]:
        """The joint path ``(n, dof)`` of one candidate, or ``None`` when infeasible."""
    def timed_motions(self, period: Optional[float] = 0.01) -> List[TimedMotion]:
        """The selected motions, timed (empty when the task does not time motions or nothing
        is selected): per arm ``arm``, ``candidate``, ``label``, ``duration``, ``grasp_time``
        and ``place_time`` (s: where the gripper closes and opens), ``joint_names``, ``time`` ``(n,)``, ``positions``, ``velocities``,
        ``accelerations`` and ``efforts`` ``(n, dof)`` (``efforts`` ``None`` without
        dynamics), sampled every ``period`` s (``None``: at the timing grid's points).

        Returns
        -------
        list of TimedMotion
            One per arm.
            See :mod:`graspath.results`.
        """
    def write(self, out_dir: StrPath, trajectory_period: float = 0.01) -> List[Path]:
        """Writes the CLI's files into ``out_dir`` (with ``trajectory.json`` and
        ``trajectory-<arm>.csv`` when motions are timed)."""

def time_path(
    samples: npt.ArrayLike,
    velocity_limits: npt.ArrayLike,
    acceleration_limits: npt.ArrayLike,
    *,
    subdivisions: int = 2,
    discretization: Literal["interpolation", "collocation"] = "interpolation",
    check_between: bool = True,
) -> TimedPath:
    """The fastest rest-to-rest motion through the joint samples ``(n, dof)`` within the
    velocity and acceleration limits ``(dof,)`` (``inf``: none): TOPP-RA on the natural cubic
    spline through them (chord-length knots, each interval split into ``subdivisions``).
    Returns ``duration``, ``knots``, ``grid``, ``sd_squared``, ``times`` and ``slowdown``.

    Returns
    -------
    TimedPath
        See :mod:`graspath.results`.
    """

def candidate_motions(
    task: Task, candidates: Sequence[int], period: Optional[float] = 0.01
) -> Optional[List[TimedMotion]]:
    """The timed motions of the candidates at positions ``candidates`` (one per arm), as
    :meth:`Selection.timed_motions` gives them; ``None`` when one is not feasible.

    Returns
    -------
    list of TimedMotion or None
        One per arm.
        See :mod:`graspath.results`.
    """

def world_mjcf(
    task: Task,
    *,
    timestep: float = 0.002,
    friction: float = 1.0,
    grip_force: float = 40.0,
    object_density: float = 500.0,
    arm_gravity_compensation: bool = False,
) -> MjcfWorld:
    """The task's world (arms, gripper, object, table, obstacles) as MJCF for MuJoCo:
    ``xml``, ``arms`` (names per arm), ``object``, ``object_mass``,
    ``has_table``, ``notes``.

    Returns
    -------
    MjcfWorld
        See :mod:`graspath.results`.
    """

def robot_mjcf(robot: Robot, arm: str = "arm") -> Tuple[str, MjcfArm]:
    """The robot's chain alone as MJCF (base at the origin) and its names.

    Returns
    -------
    tuple of str and MjcfArm
        The mjcf text and the names in it.
        See :mod:`graspath.results`.
    """

def placement_map(
    task: StrPath,
    x: Tuple[float, float, int],
    y: Tuple[float, float, int],
    *,
    z: Optional[Tuple[float, float, int]] = None,
    yaw_deg: Optional[Tuple[float, float, int]] = None,
) -> PlacementMap:
    """The task file run with the object started at every placement of a grid (world x, y,
    optionally z in m and yaw in degrees, each ``(start, end, count)``): the document
    ``graspath map`` writes as ``map.json``.

    Returns
    -------
    PlacementMap
        See :mod:`graspath.results`.
    """

def train(demonstration: StrPath, out: StrPath, *, force: bool = False) -> TrainedModel:
    """Trains a grasp model from a demonstration file and writes it to ``out``: ``label``,
    ``hand``, ``contact_links`` (link -> contact points).

    Returns
    -------
    TrainedModel
        See :mod:`graspath.results`.
    """

def generate(
    model: StrPath,
    cloud: StrPath,
    *,
    initial_grasps: Optional[int] = None,
    steps: Optional[int] = None,
    query_kernels: Optional[int] = None,
    seed: int = 0,
    max_candidates: Optional[int] = None,
    out: Optional[StrPath] = None,
    force: bool = False,
) -> GeneratedGrasps:
    """Grasp candidates on a cloud from a trained model, best first: ``object_from_wrist``
    ``(k, 4, 4)``, ``log_likelihood`` ``(k,)``, ``label``; ``out`` also writes the candidates
    file ``graspath generate`` writes. ``None`` options take the model spec's defaults.

    Returns
    -------
    GeneratedGrasps
        See :mod:`graspath.results`.
    """

def select(task: Task) -> Selection:
    """Scores and ranks every candidate of ``task`` (single arm, or pairs with two arms)."""

def select_batch(
    tasks: Sequence[Task],
    *,
    slices: Optional[Sequence[Tuple[int, int]]] = None,
    top_k: Optional[int] = None,
    threads: Optional[int] = None,
) -> Dict[str, npt.NDArray[Any]]:
    """Scores the candidates of many tasks (objects, each with its own pose, path, candidates and
    scene) for each of their arms in one call, in parallel without the GIL; the values do not
    depend on ``threads`` (default: every core).

    Numpy columns, one row per object, arm and candidate in the order (object, arm, candidate),
    or with ``top_k`` (>= 1) only each object's and arm's ``top_k`` ranked rows in the order
    (object, arm, rank): ``object`` (int64, position in ``tasks``), ``arm`` (str), ``arm_index``
    (int64), ``candidate`` (int64, position in the task's candidates), ``id`` (int64), ``label``
    (str), ``feasible`` (bool), ``failure_reason`` (object: reason or ``None``), ``failure_sample``
    (float64, NaN when feasible), ``failure_joint`` (object: the joint at fault, or ``None``),
    ``rejected`` (object: why a feasible candidate is not ranked,
    or ``None``), ``log_likelihood``, ``mu_l2``, ``mu_linf`` (``inf`` on a singular path),
    ``mu_l1``, ``mu_rms``, ``yoshikawa_at_grasp``, ``clearance`` (m), ``torque_margin`` and
    ``payload_capacity`` (kg; with the object's mass), ``dynamic_manipulability`` ((m/s²)²; with the object's mass or ``measure="dynamic"``), ``duration`` (s; timed motions),
    ``score`` and ``rank`` (float64, 1 for
    the best; NaN wherever absent: infeasible, not ranked, no scene): besides ``object``,
    ``arm_index`` and ``candidate``, the record columns marked ``select_batch`` in
    :func:`record_columns`.

    ``slices`` (one ``(start, stop)`` per task) scores only those candidate positions: the
    scores are the whole task's (the likelihood is taken relative to the whole task's most
    likely candidate), the ranks are within the slice."""

def record_columns() -> List[RecordColumn]:
    """The candidate record's columns, in order: every per-candidate output (``candidates.json``,
    ``candidates.jsonl``, ``candidates.parquet``, :meth:`Selection.arrays`,
    :func:`select_batch`) is read off this list.

    Returns
    -------
    list of RecordColumn
        In the record's order.
        See :mod:`graspath.results`.
    """

def select_pairs(task: Task, rows: Mapping[str, ArrayLike], *, top_k: Optional[int] = None) -> Dict[str, npt.NDArray[Any]]:
    """The best arm pairs of a two-arm ``task`` from its candidates' scores found apart.

    ``rows``: the columns ``arm_index``, ``candidate``, ``score`` and the task's ranked norm
    (``mu_rms``, ``mu_l2`` or ``mu_l1``) of :func:`select_batch` for this task, holding every ranked row (``score`` not NaN) of both
    arms once — the whole task's rows or the union of its slices' rows (without ``top_k``);
    other columns and unranked rows are ignored.

    Numpy columns, one row per pair, best first: ``rank`` (int64), ``first_arm``,
    ``second_arm`` (str), ``first_candidate``, ``second_candidate`` (int64, positions in the
    task's candidates), ``first_id``, ``second_id`` (int64), ``first_label``, ``second_label``
    (str), ``score`` (float64, the sum of the arms' ranked norms: ``mu_rms`` by default,
    ``mu_l2`` or ``mu_l1`` with the task's ``norm``). They are the first ``top_k`` (default all) of :func:`select`'s pairs
    on the task, in the same order with the same scores; the check between the arms (a scene
    with ``collision.between_arms``) scores again only the candidates of the pairs it visits."""

def pose_matrix(spec: Mapping[str, Sequence[Any]]) -> FloatArray:
    """The 4×4 rigid transform (m) of a pose in the task file's syntax: ``xyz`` (m, default
    zero) with at most one of ``rpy`` (rad, URDF fixed-axis roll-pitch-yaw), ``rpy_deg`` or
    ``quaternion`` ``[x, y, z, w]`` (norm 1 within 0.001), or a ``matrix`` (4×4 rows) alone.
    Raises :class:`GraspathValueError` naming the sub-field at fault (``field 'quaternion': …``)."""

GraspFormatName = Literal[
    "graspath", "graspgen", "acronym", "contact_graspnet", "m2t2", "poses", "graspnet", "anygrasp"
]

def result_cache(max_bytes: Optional[int] = None) -> ResultCache:
    """The cache of large result arrays' memory: ``max_bytes`` (the limit, default 1 GiB),
    ``bytes`` (held now) and ``buffers``; ``max_bytes``, when given, sets the limit first (0
    frees every cached buffer and turns the cache off). Batch calls write their large results
    (1 MiB and more) into memory that earlier results freed instead of new memory.

    Returns
    -------
    ResultCache
        See :mod:`graspath.results`.
    """

def read_grasps(
    path: StrPath,
    format: Optional[GraspFormatName] = None,
    frame: Optional[Literal["object", "world", "camera"]] = None,
    world_from_camera: Optional[ArrayLike] = None,
    camera_from_object: Optional[ArrayLike] = None,
    gripper_from_tool: Optional[ArrayLike] = None,
    segment: Optional[int] = None,
    world_from_object: Optional[ArrayLike] = None,
) -> GraspFile:
    """A grasp file (graspath JSON/CSV, GraspGen, ACRONYM, Contact-GraspNet / M2T2, ``N×4×4``
    poses, GraspNet / AnyGrasp) read as a task file's ``candidates: {file, ...}`` reads it.

    ``frame`` defaults to the format's (``camera`` for Contact-GraspNet and GraspNet, ``world``
    for M2T2, else ``object``); ``world_from_object`` (default identity) places the object for ``world`` frames
    and ``world_from_camera``. Returns ``object_from_wrist`` ``(k, 4, 4)`` (tool frame in the object
    frame, m), ``likelihood`` ``(k,)`` (the file's score, 1 where absent), ``log_likelihood``
    ``(k,)``, ``width`` ``(k,)`` (m, NaN where absent), ``contact`` ``(k, 3)`` (NaN where
    absent), ``id`` ``(k,)`` (row in the file), ``label`` (list of str), ``format`` (str).

    Raises ``GraspathFileNotFoundError`` for a missing file, ``GraspathFileError`` for one that
    cannot be read (a folder), ``GraspathValueError`` for one over the 1 GiB cap or with bad
    content.

    Returns
    -------
    GraspFile
        See :mod:`graspath.results`.
    """
