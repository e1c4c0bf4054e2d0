"""Grasp selection over a dataset of objects, sharded over a Ray cluster.

Install with the ``ray`` extra (``ray>=2.9`` and ``pyarrow``): from a checkout, ``pip install
"./crates/graspath-py[ray]"``. A dataset is a set of
objects, each a task file (graspath's task format, ``docs/task-file.md``) with its own object
pose, path, candidates and scene: a directory of task files, a ``.csv`` manifest of task files
with optional candidate files, object names and object poses (columns ``xyz`` and ``rpy``,
``rpy_deg`` or ``quaternion``: one task file serves many placed objects), or a sequence of task
file paths — the format, and its errors, in :mod:`graspath.dataset`.

The candidates of every object are cut into shards of about ``shard_size`` candidates (a shard
may hold the end of one object and the start of the next); each shard is one ``ray.remote`` task
that loads its task files and calls the Rust core (:func:`graspath.select_batch`) on its
candidate slices, keeping each slice's ``top_k`` best. The driver merges them into each object's
and arm's ``top_k`` (best score first, ties by candidate position: the ranking of
:func:`graspath.select`) and writes one Parquet file with the fixed schema :data:`COLUMNS`, rows
ordered by (object, arm, rank). With ``local=True`` (``--local``) the same shards run one
after the other in this process, without Ray; the file is the same, byte for byte.

Arm pairs: for a task with two arms, each shard also returns, for every ranked candidate of its
slices and each arm, the candidate's position and norms (:data:`PAIR_INPUT`: about 50 bytes a
candidate and arm, held by the driver until the pairs are formed — a pair's score is the sum of
the arms' norms (the slower arm's rate for a task ranked by duration), so a pair may join
candidates that are in neither arm's top ``k``). Once every
shard is done, one more task per two-arm object (a Ray task, or in this process with
``local=True``) loads the object's task and forms its best pairs with
:func:`graspath.select_pairs`: the best-first search of :func:`graspath.select` over each arm's
whole sorted list, with the grasp separation and, when the task's scene checks the arms
against each other (``collision.between_arms``), that check, for which it scores again only
the candidates of the pairs the search looks at. The object's pairs are the first
``min(top_k, pairs)`` of :func:`graspath.select`'s on that task (``pairs``: the task's
``selection.pairs``) — the same pairs, in the same order, with the same scores — at any shard
size. They are written to a second Parquet file beside the output, ``NAME.pairs.parquet`` for
``NAME.parquet`` (:func:`pairs_path`), with the fixed schema :data:`PAIR_COLUMNS`, rows ordered
by (object, rank); it is written only when the dataset has a task with two arms.

Every shard loads the whole task file of each object it touches (the candidates of a task that
generates them with the learned model are generated again in each of its shards — seeded, so
identically; to spare the work, write them to a file once with ``graspath generate`` and name
that file in the task).

Progress: each finished shard is logged (logger ``graspath.ray``, level INFO) with the
candidates done, candidates per second and the estimated time left; each object's pair step
with its pairs and time.

Command line::

    python -m graspath.ray DATASET --out top.parquet [--top-k 10] [--local | --address auto]

On a cluster, start Ray on every node (``ray start --head`` on one, ``ray start
--address=HEAD:6379`` on the others), install graspath on each, put the dataset on a file
system every node sees at the same path, and run the command with ``--address auto``.
"""

from __future__ import annotations

import argparse
import logging
import math
import os
import sys
import time
from pathlib import Path
from typing import Any, Callable, Dict, List, Optional, Sequence, Tuple, Union

import numpy as np

from . import GraspathError, GraspathFileError, GraspathValueError, __version__, select_batch, select_pairs
# DatasetError and DatasetObject are part of this module's interface too.
from .dataset import DatasetError, DatasetObject, Source, dataset_tasks, load_task  # noqa: F401

log = logging.getLogger("graspath.ray")

#: Candidates per shard unless ``shard_size`` says otherwise.
DEFAULT_SHARD_SIZE = 500
#: Rows per Parquet row group (fixed, so that the file does not depend on the writer's defaults).
ROW_GROUP_SIZE = 65536
#: The Parquet columns, in order: ``(name, arrow type, nullable, meaning)``.
COLUMNS: Tuple[Tuple[str, str, bool, str], ...] = (
    ("object", "string", False, "the object's name (task file, or the manifest's object)"),
    ("arm", "string", False, "the arm"),
    ("rank", "int64", False, "1 for the object's and arm's best candidate"),
    ("candidate", "int64", False, "position in the task's candidates"),
    ("id", "int64", False, "the candidate's id"),
    ("label", "string", False, "the candidate's label"),
    ("score", "float64", False, "the ranking score (norm combined with the likelihood)"),
    ("mu_l2", "float64", False, "‖M‖₂ of the ranked per-sample index"),
    ("mu_linf", "float64", False, "max 1/M_T over the path"),
    ("mu_l1", "float64", False, "time integral of the ranked index (s·index)"),
    ("mu_rms", "float64", False, "root mean square of the ranked index over the path's time"),
    ("log_likelihood", "float64", False, "the candidate's log-likelihood"),
    ("yoshikawa_at_grasp", "float64", True, "Yoshikawa's index at the grasp"),
    ("clearance", "float64", True, "smallest distance to the scene along the motion (m)"),
)

#: The pairs file's columns (:func:`pairs_path`), in order: ``(name, arrow type, nullable,
#: meaning)``; rows ordered by (object, rank).
PAIR_COLUMNS: Tuple[Tuple[str, str, bool, str], ...] = (
    ("object", "string", False, "the object's name"),
    ("rank", "int64", False, "1 for the object's best pair"),
    ("first_arm", "string", False, "the task's first arm"),
    ("first_candidate", "int64", False, "the first arm's candidate: position in the task's candidates"),
    ("first_id", "int64", False, "the first arm's candidate's id"),
    ("first_label", "string", False, "the first arm's candidate's label"),
    ("second_arm", "string", False, "the task's second arm"),
    ("second_candidate", "int64", False, "the second arm's candidate: position in the task's candidates"),
    ("second_id", "int64", False, "the second arm's candidate's id"),
    ("second_label", "string", False, "the second arm's candidate's label"),
    ("score", "float64", False, "the sum of the two arms' ranked norms (mu_rms by default, mu_l2 or mu_l1 with the task's norm; the slower arm's rate, 1/s, when ranked by duration)"),
)

#: The columns of :func:`graspath.select_batch` a shard keeps, for every ranked candidate and
#: arm of a two-arm task, to form the object's pairs (:func:`graspath.select_pairs`).
PAIR_INPUT = ("object", "arm_index", "candidate", "score", "mu_l2", "mu_l1", "mu_rms", "duration")

Piece = Tuple[int, int, int]
"""``(object, start, stop)``: candidates ``start:stop`` of one object."""

def schema(columns: Sequence[Tuple[str, str, bool, str]] = COLUMNS):
    """The fixed pyarrow schema of the output (:data:`COLUMNS`) or of the pairs file
    (:data:`PAIR_COLUMNS`)."""
    import pyarrow as pa

    types = {"string": pa.string(), "int64": pa.int64(), "float64": pa.float64()}
    return pa.schema([pa.field(name, types[kind], nullable) for name, kind, nullable, _ in columns])


def pairs_path(out: Union[str, "os.PathLike[str]"]) -> Path:
    """The pairs file written beside the output ``out``: ``top.pairs.parquet`` for
    ``top.parquet``."""
    out = Path(out)
    return out.with_name(f"{out.stem}.pairs{out.suffix}")


def plan_shards(candidate_counts: Sequence[int], shard_size: int) -> List[List[Piece]]:
    """Cuts the objects' candidates, in order, into shards of ``shard_size`` candidates (the
    last may be smaller); each shard is a list of ``(object, start, stop)`` pieces."""
    shards: List[List[Piece]] = []
    current: List[Piece] = []
    room = shard_size
    for obj, count in enumerate(candidate_counts):
        start = 0
        while start < count:
            stop = min(count, start + room)
            current.append((obj, start, stop))
            room -= stop - start
            start = stop
            if room == 0:
                shards.append(current)
                current, room = [], shard_size
    if current:
        shards.append(current)
    return shards


def run_shard(sources: Sequence[Source], pieces: Sequence[Piece], top_k: int, threads: Optional[int]) -> Dict[str, Any]:
    """One shard: loads the tasks its pieces name (``sources[object]``, see :func:`load_task`)
    and scores the pieces' candidate slices with :func:`graspath.select_batch`. Returns
    ``columns`` (numpy, each slice's ``top_k`` per arm, ``object`` mapped back to the dataset's
    object index), ``pair_rows`` (the :data:`PAIR_INPUT` columns of every ranked candidate and
    arm of the slices of two-arm tasks), ``candidates`` (scored) and ``seconds`` (wall time).
    What a Ray task runs, and what ``local=True`` runs in-process."""
    started = time.perf_counter()
    tasks = [load_task(sources[obj]) for obj, _, _ in pieces]
    columns = select_batch(tasks, slices=[(start, stop) for _, start, stop in pieces], threads=threads)
    two_arms = np.array([len(task.arms) == 2 for task in tasks], dtype=bool)
    pair_rows = two_arms[columns["object"]] & ~np.isnan(columns["score"])
    objects = np.array([obj for obj, _, _ in pieces], dtype=np.int64)
    columns["object"] = objects[columns["object"]]
    top = columns["rank"] <= top_k  # NaN (not ranked) compares false
    return {
        "columns": {name: values[top] for name, values in columns.items()},
        "pair_rows": {name: columns[name][pair_rows] for name in PAIR_INPUT},
        "candidates": sum(stop - start for _, start, stop in pieces),
        "seconds": time.perf_counter() - started,
    }


def gather_pair_rows(shards: Sequence[Dict[str, np.ndarray]]) -> Dict[int, Dict[str, np.ndarray]]:
    """The shards' ``pair_rows`` (see :func:`run_shard`) by object: for each object with
    rows, its :data:`PAIR_INPUT` columns (in shard order; :func:`graspath.select_pairs` does
    not depend on the order)."""
    if not shards:
        return {}
    merged = {name: np.concatenate([s[name] for s in shards]) for name in PAIR_INPUT}
    order = np.argsort(merged["object"], kind="stable")
    merged = {name: values[order] for name, values in merged.items()}
    objects, starts = np.unique(merged["object"], return_index=True)
    bounds = np.append(starts, len(order))
    return {
        int(obj): {name: values[bounds[k] : bounds[k + 1]] for name, values in merged.items()}
        for k, obj in enumerate(objects)
    }


def run_pairs(source: Source, rows: Dict[str, np.ndarray], top_k: int) -> Dict[str, Any]:
    """The pair step of one two-arm object: loads its task and forms its best ``top_k`` pairs
    from the shards' rows with :func:`graspath.select_pairs`. Returns ``columns`` (its
    columns) and ``seconds`` (wall time). What a Ray task runs, and what ``local=True`` runs
    in-process."""
    started = time.perf_counter()
    columns = select_pairs(load_task(source), rows, top_k=top_k)
    return {"columns": columns, "seconds": time.perf_counter() - started}


def merge_top_k(shards: Sequence[Dict[str, np.ndarray]], top_k: int) -> Dict[str, np.ndarray]:
    """The ``top_k`` rows of every object and arm among the shards' rows (the columns of
    :func:`graspath.select_batch`, at least one shard): sorted by (object, arm position, score
    best first, candidate position), ranked 1, 2, … within each object and arm. Only ranked rows
    (a score) take part. Independent of how the candidates were cut into shards."""
    names = list(shards[0].keys())
    merged = {n: np.concatenate([s[n] for s in shards]) for n in names}
    keep = ~np.isnan(merged["score"])
    merged = {n: v[keep] for n, v in merged.items()}
    order = np.lexsort((merged["candidate"], -merged["score"], merged["arm_index"], merged["object"]))
    merged = {n: v[order] for n, v in merged.items()}
    count = len(order)
    group = np.ones(count, dtype=bool)
    if count:
        group[1:] = (np.diff(merged["object"]) != 0) | (np.diff(merged["arm_index"]) != 0)
    starts = np.flatnonzero(group)
    sizes = np.diff(np.append(starts, count))
    rank = np.arange(count) - np.repeat(starts, sizes) + 1
    keep = rank <= top_k
    merged = {n: v[keep] for n, v in merged.items()}
    merged["rank"] = rank[keep].astype(np.int64)
    return merged


def _table(
    columns: Sequence[Tuple[str, str, bool, str]], values: Dict[str, np.ndarray], object_names: Sequence[str], top_k: int
):
    """The pyarrow table of ``values`` (numpy columns named as ``columns``, ``object`` the
    dataset's object index) with the schema of ``columns``: ``object`` as the object's name,
    NaN as null in nullable columns."""
    import pyarrow as pa

    names = np.array(object_names, dtype=object)
    arrays = []
    for field in schema(columns):
        if field.name == "object":
            arrays.append(pa.array(names[values["object"]].tolist() if len(values["object"]) else [], pa.string()))
        elif field.type == pa.string():
            arrays.append(pa.array(values[field.name].tolist(), pa.string()))
        elif field.nullable:
            arrays.append(pa.array(values[field.name], field.type, mask=np.isnan(values[field.name])))
        else:
            arrays.append(pa.array(values[field.name], field.type))
    metadata = {b"graspath.version": __version__.encode(), b"graspath.top_k": str(top_k).encode()}
    return pa.Table.from_arrays(arrays, schema=schema(columns).with_metadata(metadata))


def _pair_values(pairs: Dict[int, Dict[str, Any]]) -> Dict[str, np.ndarray]:
    """The pair steps' columns (:func:`run_pairs` of each object), object by object in dataset
    order, with ``object`` the object's index."""
    objects = sorted(pairs)
    parts = [pairs[obj]["columns"] for obj in objects]
    values = {}
    for name, kind, _, _ in PAIR_COLUMNS:
        if name == "object":
            arrays = [np.full(len(part["rank"]), obj, dtype=np.int64) for obj, part in zip(objects, parts)]
            empty = np.int64
        else:
            arrays = [part[name] for part in parts]
            empty = {"int64": np.int64, "float64": np.float64, "string": str}[kind]
        values[name] = np.concatenate(arrays) if arrays else np.array([], dtype=empty)
    return values


def write_parquet(files: Sequence[Tuple[Any, Path]]) -> None:
    """Writes each ``(table, path)`` with fixed settings (zstd, ``ROW_GROUP_SIZE`` rows per
    group, no timestamps) to a temporary file beside its path; once all are written, renames
    them into place. The same table gives the same bytes, and a failed write leaves no partial
    file."""
    import pyarrow.parquet as pq

    temporary = [(table, out.with_name(f".{out.name}.{os.getpid()}.tmp"), out) for table, out in files]
    try:
        for table, tmp, _ in temporary:
            pq.write_table(
                table,
                tmp,
                row_group_size=ROW_GROUP_SIZE,
                compression="zstd",
                use_dictionary=False,
                write_statistics=True,
                store_schema=True,
            )
        for _, tmp, out in temporary:
            os.replace(tmp, out)
    except BaseException:
        for _, tmp, _ in temporary:
            tmp.unlink(missing_ok=True)
        raise


class _Progress:
    """Logs each finished shard (candidates done, candidates/s, ETA), the end of the scoring
    and each object's pair step."""

    def __init__(self, total: int, shards: int, object_names: Sequence[str]):
        self.total, self.shards, self.object_names = total, shards, object_names
        self.done = self.finished = 0
        self.started = time.perf_counter()

    def scoring_done(self) -> None:
        elapsed = time.perf_counter() - self.started
        log.info(
            "scored %d candidates in %d shards in %.2f s (%.0f candidates/s)",
            self.total,
            self.shards,
            elapsed,
            self.total / max(elapsed, 1e-9),
        )

    def pairs_done(self, obj: int, result: Dict[str, Any]) -> None:
        log.info("pairs of %s: %d in %.2f s", self.object_names[obj], len(result["columns"]["rank"]), result["seconds"])

    def shard_done(self, index: int, result: Dict[str, Any]) -> None:
        self.done += result["candidates"]
        self.finished += 1
        elapsed = time.perf_counter() - self.started
        rate = self.done / elapsed if elapsed > 0 else math.inf
        eta = (self.total - self.done) / rate if rate > 0 else math.inf
        log.info(
            "shard %d/%d done (#%d: %d candidates in %.2f s): %d/%d candidates, %.0f candidates/s, ETA %.1f s",
            self.finished,
            self.shards,
            index,
            result["candidates"],
            result["seconds"],
            self.done,
            self.total,
            rate,
            eta,
        )


def select_dataset(
    dataset: Union[str, "os.PathLike[str]", Sequence[Union[str, "os.PathLike[str]"]]],
    out: Union[str, "os.PathLike[str]"],
    *,
    top_k: int = 10,
    shard_size: int = DEFAULT_SHARD_SIZE,
    local: bool = False,
    address: Optional[str] = None,
    num_cpus: Optional[int] = None,
    cpus_per_shard: float = 1,
    threads: Optional[int] = None,
    overwrite: bool = False,
) -> Dict[str, Any]:
    """Scores every candidate of every object of ``dataset`` and writes each object's and arm's
    ``top_k`` best candidates to the Parquet file ``out`` (schema :data:`COLUMNS`, rows by
    object, arm, rank) and, when the dataset has a two-arm task, each such object's best
    ``min(top_k, pairs)`` arm pairs to :func:`pairs_path` of ``out`` (schema
    :data:`PAIR_COLUMNS`, rows by object, rank).

    * ``shard_size``: candidates per shard (one Ray task each).
    * ``local``: run the shards in this process, one after the other, without Ray (``threads``
      threads each, default every core); the file is the same.
    * Otherwise Ray: ``address`` (``"auto"`` for a running cluster; ``None`` starts a local
      instance with ``num_cpus`` CPUs, default all, unless Ray is already initialised); each
      shard reserves ``cpus_per_shard`` CPUs and runs ``threads`` threads (default
      ``max(1, int(cpus_per_shard))``).
    * ``overwrite``: replace an existing ``out`` (and pairs file; else refused).

    Returns ``objects``, ``candidates`` (scored), ``rows`` (written), ``shards``, ``pairs``
    (pair rows written), ``seconds`` (wall time), ``out`` and ``pairs_out`` (the pairs file, or
    ``None`` without a two-arm task). Raises :class:`graspath.GraspathError` on bad input (a
    missing task file, a bad manifest row, a task the library refuses, ``top_k`` or
    ``shard_size`` below 1, an existing output) before any work is started."""
    started = time.perf_counter()
    if isinstance(top_k, bool) or not isinstance(top_k, int) or top_k < 1:
        raise GraspathValueError(f"top_k must be a positive integer (got {top_k!r})")
    if isinstance(shard_size, bool) or not isinstance(shard_size, int) or shard_size < 1:
        raise GraspathValueError(f"shard_size must be a positive integer (got {shard_size!r})")
    if not cpus_per_shard > 0:
        raise GraspathValueError(f"cpus_per_shard must be positive (got {cpus_per_shard!r})")
    if threads is not None and (isinstance(threads, bool) or not isinstance(threads, int) or threads < 1):
        raise GraspathValueError(f"threads must be a positive integer (got {threads!r})")
    out = Path(out)
    if out.exists() and not overwrite:
        raise GraspathFileError(f"{out}: the output exists (pass overwrite=True / --force to replace it)")
    if not out.parent.is_dir():
        raise GraspathFileError(f"{out.parent}: the output's folder does not exist")
    try:
        import pyarrow  # noqa: F401
    except ImportError as e:
        raise GraspathValueError(
            'pyarrow is not installed: pip install pyarrow (or, from a checkout, pip install "./crates/graspath-py[ray]")'
        ) from e

    objects = dataset_tasks(dataset)
    sources: List[Source] = [
        (str(o.task.resolve()), None if o.candidates is None else str(o.candidates.resolve()), o.pose) for o in objects
    ]
    counts, two_arms = [], []
    for source in sources:
        task = load_task(source)
        counts.append(len(task))
        two_arms.append(len(task.arms) == 2)
    pairs_out = pairs_path(out) if any(two_arms) else None
    if pairs_out is not None and pairs_out.exists() and not overwrite:
        raise GraspathFileError(f"{pairs_out}: the pairs output exists (pass overwrite=True / --force to replace it)")
    shards = plan_shards(counts, shard_size)
    total = sum(counts)
    log.info("%d objects, %d candidates, %d shards of up to %d candidates", len(objects), total, len(shards), shard_size)

    names = [o.name for o in objects]
    progress = _Progress(total, len(shards), names)
    results: Dict[int, Dict[str, Any]] = {}
    pairs: Dict[int, Dict[str, Any]] = {}
    if local:
        for index, pieces in enumerate(shards):
            results[index] = run_shard(sources, pieces, top_k, threads)
            progress.shard_done(index, results[index])
        progress.scoring_done()
        for obj, rows in gather_pair_rows([results[i]["pair_rows"] for i in range(len(shards))]).items():
            pairs[obj] = run_pairs(sources[obj], rows, top_k)
            progress.pairs_done(obj, pairs[obj])
    else:
        results, pairs = _run_on_ray(sources, shards, top_k, threads, address, num_cpus, cpus_per_shard, progress)

    # No candidates at all: the columns of an empty batch give the (empty) table its types.
    columns = [results[i]["columns"] for i in range(len(shards))] or [select_batch([], top_k=top_k)]
    files = [(_table(COLUMNS, merge_top_k(columns, top_k), names, top_k), out)]
    if pairs_out is not None:
        files.append((_table(PAIR_COLUMNS, _pair_values(pairs), names, top_k), pairs_out))
    write_parquet(files)
    rows, pair_rows = files[0][0].num_rows, (files[1][0].num_rows if pairs_out is not None else 0)
    seconds = time.perf_counter() - started
    log.info("wrote %s: %d rows (%d objects, %d candidates) in %.2f s", out, rows, len(objects), total, seconds)
    if pairs_out is not None:
        log.info("wrote %s: %d pairs (%d two-arm objects)", pairs_out, pair_rows, sum(two_arms))
    return {
        "objects": len(objects),
        "candidates": total,
        "rows": rows,
        "shards": len(shards),
        "pairs": pair_rows,
        "seconds": seconds,
        "out": out,
        "pairs_out": pairs_out,
    }


def _run_on_ray(
    sources: List[Source],
    shards: List[List[Piece]],
    top_k: int,
    threads: Optional[int],
    address: Optional[str],
    num_cpus: Optional[int],
    cpus_per_shard: float,
    progress: _Progress,
) -> Tuple[Dict[int, Dict[str, Any]], Dict[int, Dict[str, Any]]]:
    """The shards, then the pair steps of the two-arm objects, as Ray tasks: the results of
    :func:`run_shard` by shard and of :func:`run_pairs` by object."""
    try:
        import ray
    except ImportError as e:
        raise GraspathValueError(
            'ray is not installed: pip install "ray>=2.9" (or, from a checkout, pip install "./crates/graspath-py[ray]"), '
            "or run with local=True / --local"
        ) from e
    started_here = False
    if not ray.is_initialized():
        kwargs: Dict[str, Any] = {"address": address}
        if address is None and num_cpus is not None:
            kwargs["num_cpus"] = num_cpus
        began = time.perf_counter()
        ray.init(**kwargs)
        started_here = True
        log.info("Ray started in %.2f s", time.perf_counter() - began)
    log.info("Ray cluster: %s CPUs", ray.cluster_resources().get("CPU", 0))
    progress.started = time.perf_counter()  # rates and ETA from here, without Ray's start-up

    def run_all(pending: Dict[Any, int], done: Callable[[int, Dict[str, Any]], None]) -> Dict[int, Dict[str, Any]]:
        results: Dict[int, Dict[str, Any]] = {}
        while pending:
            ready, _ = ray.wait(list(pending), num_returns=1)
            for ref in ready:
                key = pending.pop(ref)
                results[key] = ray.get(ref)
                done(key, results[key])
        return results

    try:
        shard_threads = threads if threads is not None else max(1, int(cpus_per_shard))
        remote: Callable[..., Any] = ray.remote(num_cpus=cpus_per_shard)(run_shard)
        files = ray.put(sources)
        results = run_all(
            {remote.remote(files, pieces, top_k, shard_threads): i for i, pieces in enumerate(shards)}, progress.shard_done
        )
        progress.scoring_done()
        pair_step: Callable[..., Any] = ray.remote(num_cpus=cpus_per_shard)(run_pairs)
        inputs = gather_pair_rows([results[i]["pair_rows"] for i in range(len(shards))])
        pairs = run_all({pair_step.remote(sources[obj], rows, top_k): obj for obj, rows in inputs.items()}, progress.pairs_done)
        return results, pairs
    finally:
        if started_here:
            ray.shutdown()


def main(argv: Optional[Sequence[str]] = None) -> int:
    """``python -m graspath.ray``: see the module's documentation and ``--help``."""
    parser = argparse.ArgumentParser(
        prog="python -m graspath.ray",
        description="Score every grasp candidate of every object of a dataset (a directory of "
        "task files or a .csv manifest) on a Ray cluster, and write each object's and arm's "
        "top-k to a Parquet file, and the top-k arm pairs of two-arm tasks to NAME.pairs.parquet "
        "beside it (the same bytes with --local, without Ray).",
    )
    parser.add_argument(
        "dataset",
        help="a directory of task files (*.yaml, *.yml) or a .csv manifest (columns task, and optionally candidates, "
        "object, and the object's pose: xyz with rpy, rpy_deg or quaternion)",
    )
    parser.add_argument("-o", "--out", required=True, help="the Parquet file to write")
    parser.add_argument("-k", "--top-k", type=int, default=10, help="best candidates kept per object and arm (default 10)")
    parser.add_argument("--shard-size", type=int, default=DEFAULT_SHARD_SIZE, help=f"candidates per Ray task (default {DEFAULT_SHARD_SIZE})")
    mode = parser.add_mutually_exclusive_group()
    mode.add_argument("--local", action="store_true", help="run in this process without Ray (same output)")
    mode.add_argument("--address", help="the Ray cluster ('auto' for the one started with `ray start`); default: a local Ray instance")
    parser.add_argument("--num-cpus", type=int, help="CPUs of the local Ray instance (default: all)")
    parser.add_argument("--cpus-per-shard", type=float, default=1, help="CPUs each Ray task reserves (default 1)")
    parser.add_argument("--threads", type=int, help="threads per shard (default: --cpus-per-shard; with --local every core)")
    parser.add_argument("--force", action="store_true", help="replace an existing output file")
    parser.add_argument("-q", "--quiet", action="store_true", help="no progress lines")
    args = parser.parse_args(argv)
    logging.basicConfig(level=logging.WARNING if args.quiet else logging.INFO, format="%(asctime)s %(name)s: %(message)s")
    try:
        summary = select_dataset(
            args.dataset,
            args.out,
            top_k=args.top_k,
            shard_size=args.shard_size,
            local=args.local,
            address=args.address,
            num_cpus=args.num_cpus,
            cpus_per_shard=args.cpus_per_shard,
            threads=args.threads,
            overwrite=args.force,
        )
    except GraspathError as e:
        print(f"graspath.ray: error: {e}", file=sys.stderr)
        return 2
    if not args.quiet:
        pairs = f" and {summary['pairs']} pairs to {summary['pairs_out']}" if summary["pairs_out"] is not None else ""
        print(
            f"{summary['objects']} objects, {summary['candidates']} candidates, "
            f"{summary['rows']} rows in {summary['seconds']:.2f} s; wrote {summary['out']}{pairs}"
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
