"""The typed dicts graspath's calls return, for type checkers and for reading.

Each class names the keys a result always has and, where a base class marks them optional
(``total=False``), the keys it has only in some cases; the docstring says when. Values are
plain Python (``int``, ``float``, ``str``, lists) or numpy arrays as annotated. Frames and units
as everywhere in graspath: metres, radians, seconds; poses are 4×4 matrices ``a_from_b``.

These are :class:`typing.TypedDict` classes: at run time a result is an ordinary ``dict``.
"""

from typing import Any, Dict, List, Literal, Optional, TypedDict, Union

import numpy as np
import numpy.typing as npt

FloatArray = npt.NDArray[np.float64]
BoolArray = npt.NDArray[np.bool_]
IntArray = npt.NDArray[np.int64]

__all__ = [
    "CandidateFailure",
    "CandidateRecord",
    "CandidateSelfMotion",
    "CollidingBodies",
    "GeneratedGrasps",
    "GraspFile",
    "GridAxis",
    "Indices",
    "IkBatchResult",
    "IkFailure",
    "IkResult",
    "MjcfArm",
    "MjcfWorld",
    "PairRecord",
    "Placement",
    "PlacementArm",
    "PlacementBest",
    "PlacementGrid",
    "PlacementMap",
    "PlacementPair",
    "PlacementTrend",
    "RecordColumn",
    "ResultCache",
    "SelectedGrasp",
    "SelfMotion",
    "Summary",
    "SummaryArm",
    "SummaryIndex",
    "SummaryWarning",
    "TaskCandidate",
    "TimedMotion",
    "TimedPath",
    "TrainedModel",
    "TrajectoryFailure",
    "TrajectoryIk",
]


# --- Robot ------------------------------------------------------------------------------------


class Indices(TypedDict):
    """:meth:`Robot.indices`: the classical indices of the chosen Jacobian rows.

    Attributes
    ----------
    yoshikawa, inverse_condition, inverse_condition_squared
        ``sqrt(det(J Jᵀ))``, ``σmin/σmax`` of J and ``λmin/λmax`` of J Jᵀ: a float for one
        configuration, ``(n,)`` for ``n``.
    singular_values
        Descending, ``(rows,)`` or ``(n, rows)``.
    """

    yoshikawa: Union[float, FloatArray]
    inverse_condition: Union[float, FloatArray]
    inverse_condition_squared: Union[float, FloatArray]
    singular_values: FloatArray


class IkFailure(TypedDict):
    """Why one pose's IK failed (:class:`IkResult` ``failure``).

    Attributes
    ----------
    reason
        ``unreachable``, ``time_limit`` or ``iteration_limit``.
    best_q
        The configuration closest to the target that was tried, ``(dof,)``.
    attempts
        Restarts tried.
    message
        The reason in words.
    """

    reason: str
    best_q: FloatArray
    attempts: int
    message: str


class IkResult(TypedDict):
    """:meth:`Robot.ik` on one pose.

    Attributes
    ----------
    q
        The solution ``(dof,)``, ``None`` when not converged.
    converged
        Whether ``q`` is within both tolerances.
    position_error, rotation_error
        Of the returned (or best) configuration, m and rad.
    iterations
        Solver iterations used.
    failure
        ``None`` when converged.
    """

    q: Optional[FloatArray]
    converged: bool
    position_error: float
    rotation_error: float
    iterations: int
    failure: Optional[IkFailure]


class IkBatchResult(TypedDict):
    """:meth:`Robot.ik` on ``n`` poses: one row per pose.

    Attributes
    ----------
    q
        ``(n, dof)``, NaN rows where not converged.
    best_q
        ``(n, dof)``, the best configuration tried (the solution where converged).
    converged
        ``(n,)`` bool.
    position_error, rotation_error
        ``(n,)``, m and rad.
    iterations
        ``(n,)`` int64.
    failure_reason
        ``None`` where converged, else as :class:`IkFailure` ``reason``.
    """

    q: FloatArray
    best_q: FloatArray
    converged: BoolArray
    position_error: FloatArray
    rotation_error: FloatArray
    iterations: IntArray
    failure_reason: List[Optional[str]]


class TrajectoryFailure(TypedDict):
    """Where and why trajectory IK failed (:class:`TrajectoryIk` ``failure``).

    Attributes
    ----------
    sample
        The first sample no branch passes.
    reason
        ``unreachable``, ``joint_limit`` or ``discontinuity``.
    detail
        The reason in words.
    """

    sample: int
    reason: str
    detail: str


class TrajectoryIk(TypedDict):
    """:meth:`Robot.ik_trajectory` on one trajectory.

    Attributes
    ----------
    feasible
        Whether at least one branch passes every sample.
    branches
        The continuous joint paths, each ``(n, dof)``.
    failure
        ``None`` when feasible.
    """

    feasible: bool
    branches: List[FloatArray]
    failure: Optional[TrajectoryFailure]


class SelfMotion(TypedDict):
    """:meth:`Robot.optimize_self_motion`.

    Attributes
    ----------
    q
        The optimised joint path ``(n, dof)``.
    m_t
        ``M_T`` per sample ``(n,)`` (NaN where the tip is still).
    mu_l2, mu_l2_seed, mu_l2_min
        ``sqrt(Σ M_T²)`` of the result, of the given path and the smallest over the traced
        self-motion.
    """

    q: FloatArray
    m_t: FloatArray
    mu_l2: float
    mu_l2_seed: float
    mu_l2_min: float


# --- Task -------------------------------------------------------------------------------------


class TaskCandidate(TypedDict):
    """One of :attr:`Task.candidates`.

    Attributes
    ----------
    id, label
        The candidate's id and label.
    object_from_wrist
        ``(4, 4)``, m.
    likelihood, log_likelihood
        The candidate's likelihood and its natural logarithm.
    contact
        The contact point ``(3,)`` in the object frame (m), ``None`` when not given.
    """

    id: int
    label: str
    object_from_wrist: FloatArray
    likelihood: float
    log_likelihood: float
    contact: Optional[FloatArray]


# --- Selection --------------------------------------------------------------------------------


class _CandidateFailureWhy(TypedDict):
    reason: str
    phase: Optional[str]
    sample: Optional[int]
    detail: Optional[str]


class CandidateFailure(_CandidateFailureWhy, total=False):
    """A record's ``failure`` group (``None`` when the candidate is feasible): ``reason``,
    ``phase``, ``sample`` and ``detail`` always, ``bodies`` (the colliding pair) for a
    collision, ``joint`` (the joint at fault) for ``torque_limit`` and for a
    ``timing_infeasible`` that a joint's limit causes. See ``docs/candidate-record.md``."""

    bodies: List[str]
    joint: str


class CandidateSelfMotion(TypedDict):
    """A record's ``self_motion`` group (with ``ik.redundancy: optimize``): ``μ_l2`` of the
    first branch, and the smallest and largest over the traced self-motion."""

    mu_l2_first_branch: Optional[float]
    mu_l2_min: Optional[float]
    mu_l2_max: Optional[float]


class CandidateRecord(TypedDict, total=False):
    """One of :attr:`Selection.candidates`: a record of ``candidates.json``.

    Its keys are the candidate record's columns that ``json`` carries
    (:func:`graspath.record_columns`, ``json_field``; ``docs/candidate-record.md`` has each
    column's type, unit and meaning); a column without a value for the candidate is ``None``
    or, for the columns of features the task does not use (a scene, timing, dynamics, the
    self-motion search), left out.
    """

    arm: str
    id: int
    label: str
    object_from_wrist: List[List[float]]
    contact: Optional[List[float]]
    likelihood: Optional[float]
    log_likelihood: Optional[float]
    feasible: bool
    failure: Optional[CandidateFailure]
    rejected: Optional[str]
    rank: Optional[int]
    score: Optional[float]
    pareto: Optional[bool]
    mu_l2: Optional[float]
    mu_linf: Optional[float]
    mu_linf_infinite: bool
    mu_l1: Optional[float]
    mu_rms: Optional[float]
    skipped_samples: Optional[int]
    m_t: List[Optional[float]]
    ranked_index: List[Optional[float]]
    yoshikawa_at_grasp: Optional[float]
    yoshikawa_penalized_at_grasp: Optional[float]
    inverse_condition_at_grasp: Optional[float]
    inverse_condition_squared_at_grasp: Optional[float]
    feasible_branches: int
    limit_distance: List[Optional[float]]
    limit_distance_min: Optional[float]
    hugs_limit: Optional[bool]
    clearance: Optional[float]
    torque_margin: Optional[float]
    payload_capacity: Optional[float]
    dynamic_manipulability: Optional[float]
    duration: Optional[float]
    approach_duration: Optional[float]
    carry_duration: Optional[float]
    retreat_duration: Optional[float]
    spline_deviation: Optional[float]
    limit_excursion: Optional[float]
    self_motion: CandidateSelfMotion
    joint_trajectory: Optional[List[List[float]]]
    approach_trajectory: Optional[List[List[float]]]
    retreat_trajectory: Optional[List[List[float]]]


PairRecord = Dict[str, Any]
"""One of :attr:`Selection.pairs` (a record of ``pairs.json``): ``rank`` (1 for the best),
``score`` (the summed ranked norms), and per arm, under the arm's own name, the candidate's
``id`` (``"left": 3``) and its label (``"left_label"``). Keyed by the task's arm names, so not a
fixed set of keys."""


class SelectedGrasp(TypedDict):
    """An arm's ``selected`` grasp in :class:`SummaryArm` (the norms ``None`` when absent, and
    ``mu_linf`` ``None`` on a singular path); ``tied_with``: the ids of candidates tied with
    it."""

    id: int
    label: Optional[str]
    score: Optional[float]
    mu_l2: Optional[float]
    mu_linf: Optional[float]
    mu_l1: Optional[float]
    mu_rms: Optional[float]
    yoshikawa_at_grasp: Optional[float]
    tied_with: List[int]


class CollidingBodies(TypedDict):
    """A pair of bodies collisions named and how many candidates failed on it."""

    bodies: List[str]
    candidates: int


class _SummaryArmCounts(TypedDict):
    arm: str
    candidates: int
    feasible: int
    eligible: int
    selected: Optional[SelectedGrasp]
    best_by_yoshikawa_at_grasp: Optional[int]


class SummaryArm(_SummaryArmCounts, total=False):
    """One arm in :class:`Summary`: the candidate counts, the selected grasp (``None`` when
    none is eligible) and the candidate the Yoshikawa index alone would pick; with a scene,
    ``failures`` (candidates per failure reason) and, when some collide,
    ``colliding_bodies``."""

    failures: Dict[str, int]
    colliding_bodies: List[CollidingBodies]


class _SummaryIndexMode(TypedDict):
    mode: str


class SummaryIndex(_SummaryIndexMode, total=False):
    """The index settings in :class:`Summary`: ``mode``; ``length_scale`` for ``twist``;
    ``measure`` and ``joint_limit_penalty`` for a measure other than ``task_relevant``;
    ``over`` when the norms are not over every sample."""

    length_scale: float
    measure: str
    joint_limit_penalty: Optional[float]
    over: str


class SummaryWarning(TypedDict):
    """A value of the task that is probably a mistake: the field and why."""

    field: str
    message: str


class _SummaryDocument(TypedDict):
    task: str
    robot: str
    samples: int
    steps: List[str]
    duration_s: Optional[float]
    index: SummaryIndex
    norm: str
    mu0: Optional[float]
    arms: List[SummaryArm]
    best_pair: Optional[PairRecord]
    tie_tolerance: float
    nothing_selected: bool


class Summary(_SummaryDocument, total=False):
    """:attr:`Selection.summary`: the document ``summary.json``. ``best_pair`` (two arms) is
    the first of :attr:`Selection.pairs` with ``tied_with``; ``colliding_pairs`` (two arms in a
    scene) counts the pairs refused because the arms collide; ``warnings`` is present when the
    task has some."""

    colliding_pairs: int
    warnings: List[SummaryWarning]


class TimedMotion(TypedDict):
    """One arm's timed motion (:meth:`Selection.timed_motions`, :func:`candidate_motions`).

    Attributes
    ----------
    arm, candidate, label
        The arm and the candidate's id and label.
    duration, grasp_time, place_time
        s: the whole motion, and when the gripper closes and opens.
    joint_names
        The columns' joints.
    time
        ``(n,)`` s.
    positions, velocities, accelerations
        ``(n, dof)``: rad, rad/s, rad/s².
    efforts
        ``(n, dof)`` N·m, ``None`` without the arm's dynamics.
    """

    arm: str
    candidate: int
    label: str
    duration: float
    grasp_time: float
    place_time: float
    joint_names: List[str]
    time: FloatArray
    positions: FloatArray
    velocities: FloatArray
    accelerations: FloatArray
    efforts: Optional[FloatArray]


# --- Module functions -------------------------------------------------------------------------


class TimedPath(TypedDict):
    """:func:`time_path`: the fastest rest-to-rest timing of a joint path.

    Attributes
    ----------
    duration
        s.
    knots
        The spline's knots in the path parameter ``s``, one per sample.
    grid
        The TOPP-RA grid in ``s``.
    sd_squared
        ``ṡ²`` at each grid point.
    times
        The time at each grid point, s.
    slowdown
        How far the check between grid points slowed the timing (1: not at all).
    """

    duration: float
    knots: FloatArray
    grid: FloatArray
    sd_squared: FloatArray
    times: FloatArray
    slowdown: float


class MjcfArm(TypedDict):
    """The names of one arm in an MJCF model (:func:`world_mjcf`, :func:`robot_mjcf`): its
    ``joints`` and their ``effort`` limits (N·m), the ``tool`` site, the gripper's
    ``fingers`` and their ``finger_travel`` (m), the ``grasp_weld`` constraint, and whether
    the task's gripper was built (``task_gripper``)."""

    arm: str
    joints: List[str]
    effort: List[float]
    tool: str
    fingers: List[str]
    finger_travel: float
    grasp_weld: str
    task_gripper: bool


class MjcfWorld(TypedDict):
    """:func:`world_mjcf`: the model's ``xml``, its ``arms``, the ``object`` body and its mass
    (kg), whether it has a table and ``notes`` on what was approximated."""

    xml: str
    arms: List[MjcfArm]
    object: str
    object_mass: float
    has_table: bool
    notes: List[str]


class GridAxis(TypedDict):
    """One axis of a placement grid: ``count`` values from ``start`` to ``end`` (m, or
    degrees for yaw)."""

    start: float
    end: float
    count: int
    values: List[float]


class PlacementGrid(TypedDict):
    """The placement grid's axes (``z`` and ``yaw_deg`` ``None`` when not varied)."""

    x: GridAxis
    y: GridAxis
    z: Optional[GridAxis]
    yaw_deg: Optional[GridAxis]


class PlacementBest(TypedDict):
    """An arm's best candidate at a placement; ``parameter`` its family parameter (``None``
    without a family)."""

    id: int
    label: str
    score: float
    mu_l2: float
    tied_with: List[int]
    parameter: Optional[float]


class PlacementTrend(TypedDict):
    """How ``μ_l2`` follows the family parameter at a placement: their correlation and the
    parameter of the largest ``μ_l2``."""

    correlation: Optional[float]
    argmax_parameter: Optional[float]


class _PlacementArmCounts(TypedDict):
    arm: str
    feasible: int
    eligible: int
    best: Optional[PlacementBest]
    mu_l2_min: Optional[float]
    mu_l2_max: Optional[float]
    spread: Optional[float]


class PlacementArm(_PlacementArmCounts, total=False):
    """One arm at a placement; ``trend`` only for candidates of a parametric family."""

    trend: PlacementTrend


class PlacementPair(TypedDict):
    """The best pair at a placement (two arms): the candidates' ids, the pair's score and how
    many pairs tie with it."""

    first: int
    second: int
    score: float
    tied_with: int


class Placement(TypedDict):
    """One placement of :class:`PlacementMap`: its grid ``index`` (x, y, z, yaw), the object's
    position (m) and yaw (degrees), and what the selection found there."""

    index: List[int]
    x: float
    y: float
    z: float
    yaw_deg: float
    arms: List[PlacementArm]
    best_pair: Optional[PlacementPair]
    nothing_selected: bool


class PlacementMap(TypedDict):
    """:func:`placement_map`: the document ``map.json`` (``docs/placement-maps.md``)."""

    task: str
    arms: List[str]
    grid: PlacementGrid
    parameter: Optional[str]
    tie_tolerance: float
    placements: List[Placement]


class TrainedModel(TypedDict):
    """:func:`train`: the trained model's ``label``, ``hand`` and how many contact points it
    keeps per hand link (``contact_links``)."""

    label: str
    hand: str
    contact_links: Dict[str, int]


class GeneratedGrasps(TypedDict):
    """:func:`generate`: ``object_from_wrist`` ``(k, 4, 4)`` and ``log_likelihood`` ``(k,)``,
    best first, and the model's ``label``."""

    object_from_wrist: FloatArray
    log_likelihood: FloatArray
    label: str


class GraspFile(TypedDict):
    """:func:`read_grasps`: the file's candidates.

    Attributes
    ----------
    object_from_wrist
        ``(k, 4, 4)``, the tool frame in the object frame, m.
    likelihood, log_likelihood
        ``(k,)``: the file's score (1 where absent) and its logarithm.
    width
        ``(k,)`` gripper opening, m (NaN where absent).
    contact
        ``(k, 3)`` contact point in the object frame, m (NaN where absent).
    id
        ``(k,)`` row in the file.
    label
        One per candidate.
    format
        The format the file was read as.
    """

    object_from_wrist: FloatArray
    likelihood: FloatArray
    log_likelihood: FloatArray
    width: FloatArray
    contact: FloatArray
    id: IntArray
    label: List[str]
    format: str


class RecordColumn(TypedDict):
    """One of :func:`record_columns`: a per-candidate output column (``docs/candidate-record.md``).

    Attributes
    ----------
    name
        The column's name (in Parquet, numpy and Ray).
    type
        ``float64``, ``uint64``, ``bool``, ``string``, ``float64 × 3``, …
    nullable
        Whether a candidate may have no value.
    unit
        The unit, or ``""``.
    doc
        The column's meaning in one line.
    outputs
        The outputs that carry it.
    json_field
        Its place in a JSON record (``failure.reason`` inside a group), ``None`` when no JSON
        output carries it.
    """

    name: str
    type: str
    nullable: bool
    unit: str
    doc: str
    outputs: List[Literal["json", "jsonl", "parquet", "arrays", "select_batch"]]
    json_field: Optional[str]


class ResultCache(TypedDict):
    """:func:`result_cache`: the limit (bytes), the bytes held now and the buffers held."""

    max_bytes: int
    bytes: int
    buffers: int
