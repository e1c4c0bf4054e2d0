"""graspath: task-relevant grasp selection (Ghalamzan et al., IROS 2016) from Python.

Choose where a robot should grasp an object so that the arm can then carry out a given
manipulation task well. Everything numeric is numpy ``float64``; frames and units follow the
library: metres and radians, a transform named ``a_from_b`` maps coordinates in frame ``b`` to
frame ``a``, poses are 4×4 homogeneous matrices, every robot pose and Jacobian is in the chain
base frame with Jacobian rows ``[v; ω]``.

* :class:`Robot` — a serial chain (URDF, MJCF, or a built-in arm): ``fk``, ``jacobian``,
  ``fk_jacobian``, ``indices``, ``task_relevant``, ``ik``, ``ik_trajectory``, for one
  configuration ``(dof,)`` or a batch ``(n, dof)``.
* :class:`Task` — a selection task from a task file (``Task.load``), text, a dict, or arrays
  (``Task.from_arrays``).
* :func:`select` — scores and ranks every candidate; the :class:`Selection` holds the same
  records the CLI writes (``candidates``, ``pairs``, ``summary``) and numpy views (``arrays``).
* :func:`select_batch` — many tasks (objects) scored in one call, without the GIL: numpy columns
  with one row per object, arm and candidate (or each object's and arm's top ``k``).
* :func:`select_pairs` — a two-arm task's best arm pairs from its candidates' scores found
  apart (``select_batch`` rows, for instance of candidate slices): :func:`select`'s pairs.
* :func:`record_columns` — the per-candidate columns (name, type, unit, meaning, which outputs
  carry them) that every output above is read off (``docs/candidate-record.md``).
* :func:`pose_matrix` — a pose in the task file's syntax (``xyz``, ``rpy_deg``, …) as a 4×4
  matrix; ``Task.load(path, object_pose=...)`` moves a task's object to such a pose.
* :mod:`graspath.ray` — a dataset of task files sharded over a Ray cluster, each object's top
  ``k`` (and two-arm tasks' top ``k`` pairs) written to Parquet (``pip install
  graspath[ray]``; ``python -m graspath.ray``); :mod:`graspath.dataset` reads the datasets
  (directories of task files, manifests with candidate files and object poses).
* :func:`read_grasps` — a grasp generator's file (GraspGen, ACRONYM, Contact-GraspNet / M2T2,
  ``N×4×4`` poses, GraspNet / AnyGrasp) as numpy candidates in the object frame.
* :func:`result_cache` — the cache of large result arrays' memory: batch calls (``Robot.fk``,
  ``fk_jacobian``, ...) write into memory that earlier results freed (at most 1 GiB is kept).
* :class:`GraspathError` — the base of every exception graspath raises:
  :class:`GraspathFileError` (an :class:`OSError`; :class:`GraspathFileNotFoundError`, a
  :class:`FileNotFoundError`, for a missing input) for a file that cannot be read or written,
  :class:`GraspathValueError` (a :class:`ValueError`) for bad content; each names the ``file``
  and ``field`` at fault when known.
* :mod:`graspath.results` — the typed dicts the calls return (``IkResult``, ``Summary``,
  ``CandidateRecord``, ``TimedMotion``, …): their keys, which are optional, the value types.
* :func:`train` and :func:`generate` — the one-shot learned grasp model: trained from one
  demonstrated grasp, it generates candidates with likelihoods on a new object's point cloud
  (``docs/demonstrations.md``).
"""

from ._errors import (
    GraspathError,
    GraspathFileError,
    GraspathFileNotFoundError,
    GraspathValueError,
)
from ._graspath import (
    DEFAULTS,
    SPELLINGS,
    Robot,
    Selection,
    Task,
    __version__,
    candidate_motions,
    generate,
    placement_map,
    pose_matrix,
    read_grasps,
    record_columns,
    result_cache,
    robot_mjcf,
    select,
    select_batch,
    select_pairs,
    time_path,
    train,
    world_mjcf,
)

__all__ = [
    "DEFAULTS",
    "SPELLINGS",
    "GraspathError",
    "GraspathFileError",
    "GraspathFileNotFoundError",
    "GraspathValueError",
    "Robot",
    "Selection",
    "Task",
    "candidate_motions",
    "generate",
    "placement_map",
    "pose_matrix",
    "read_grasps",
    "record_columns",
    "result_cache",
    "robot_mjcf",
    "select",
    "select_batch",
    "select_pairs",
    "time_path",
    "train",
    "world_mjcf",
    "__version__",
]
