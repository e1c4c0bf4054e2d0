"""Grasp selection over a dataset of objects, sharded over a Ray cluster.

Install with ``pip install graspath[ray]`` (``ray>=2.9`` and ``pyarrow``). A dataset is a set of
task files (graspath's task format, ``docs/task-file.md``), one per object — each with its own
object pose, path, candidates (a family, a grasp file, a learned model) and scene:

* a directory: every ``*.yaml`` / ``*.yml`` file directly in it, in name order, each object
  named by its file name;
* a manifest (``*.csv``), one row per object, with a ``task`` column (paths relative to the
  manifest), an optional ``candidates`` column (a candidate file — graspath JSON/CSV or a grasp
  generator's file — read instead of the task file's candidates, with the task file's
  ``candidates`` options such as ``format`` and ``frame``: objects × candidate files on one
  task file) and an optional ``object`` column (the object's name; default the candidate file,
  else the task file);
* from Python, a sequence of task file paths.

The candidates of every object are cut into shards of about ``shard_size`` candidates (a shard
may hold the end of one object and the start of the next); each shard is one ``ray.remote`` task
that loads its task files and calls the Rust core (:func:`graspath.select_batch`) on its
candidate slices, keeping each slice's ``top_k`` best. The driver merges them into each object's
and arm's ``top_k`` (best score first, ties by candidate position: the ranking of
:func:`graspath.select`) and writes one Parquet file with the fixed schema :data:`COLUMNS`, rows
ordered by (object, arm, rank). With ``local=True`` (``--local``) the same shards run one
after the other in this process, without Ray; the file is the same, byte for byte.

Every shard loads the whole task file of each object it touches (the candidates of a task that
generates them with the learned model are generated again in each of its shards — seeded, so
identically; to spare the work, write them to a file once with ``graspath generate`` and name
that file in the task). A two-arm task gives each arm's top ``k``; its arm pairs are not
formed from shards (:func:`graspath.select` on that task gives them).

Progress: each finished shard is logged (logger ``graspath.ray``, level INFO) with the
candidates done, candidates per second and the estimated time left.

Command line::

    python -m graspath.ray DATASET --out top.parquet [--top-k 10] [--local | --address auto]

On a cluster, start Ray on every node (``ray start --head`` on one, ``ray start
--address=HEAD:6379`` on the others), install graspath on each, put the dataset on a file
system every node sees at the same path, and run the command with ``--address auto``.
"""

from __future__ import annotations

import argparse
import csv
import logging
import math
import os
import sys
import time
from pathlib import Path
from typing import Any, Callable, Dict, List, NamedTuple, Optional, Sequence, Tuple, Union

import numpy as np

from . import GraspathError, Task, __version__, select_batch

log = logging.getLogger("graspath.ray")

#: Candidates per shard unless ``shard_size`` says otherwise.
DEFAULT_SHARD_SIZE = 500
#: Rows per Parquet row group (fixed, so that the file does not depend on the writer's defaults).
ROW_GROUP_SIZE = 65536
#: Task file suffixes picked up from a dataset directory.
TASK_SUFFIXES = (".yaml", ".yml")

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
    ("log_likelihood", "float64", False, "the candidate's log-likelihood"),
    ("yoshikawa_at_grasp", "float64", True, "Yoshikawa's index at the grasp"),
    ("clearance", "float64", True, "smallest distance to the scene along the motion (m)"),
)

Piece = Tuple[int, int, int]
"""``(object, start, stop)``: candidates ``start:stop`` of one object."""


class DatasetError(GraspathError):
    """A dataset that cannot be read: names the directory, manifest, file or field at fault."""


def schema():
    """The fixed pyarrow schema of the output (see :data:`COLUMNS`)."""
    import pyarrow as pa

    types = {"string": pa.string(), "int64": pa.int64(), "float64": pa.float64()}
    return pa.schema([pa.field(name, types[kind], nullable) for name, kind, nullable, _ in COLUMNS])


class DatasetObject(NamedTuple):
    """One object of a dataset: its name, its task file and, from a manifest's ``candidates``
    column, a candidate file read instead of the task file's candidates (else ``None``)."""

    name: str
    task: Path
    candidates: Optional[Path] = None


def dataset_tasks(dataset: Union[str, "os.PathLike[str]", Sequence[Union[str, "os.PathLike[str]"]]]) -> List[DatasetObject]:
    """The objects of a dataset, in the dataset's order (see the module's documentation).
    Raises :class:`DatasetError` on a missing directory, manifest, task or candidate file, an
    empty dataset or a duplicated object name."""
    if isinstance(dataset, (str, os.PathLike)):
        root = Path(dataset)
        if root.is_dir():
            files = sorted(p for p in root.iterdir() if p.suffix in TASK_SUFFIXES and p.is_file())
            if not files:
                raise DatasetError(f"{root}: no task files (*.yaml, *.yml) in the directory")
            objects = [DatasetObject(p.name, p) for p in files]
        elif root.suffix == ".csv":
            objects = _manifest(root)
        elif root.exists():
            raise DatasetError(f"{root}: a dataset is a directory of task files or a .csv manifest")
        else:
            raise DatasetError(f"{root}: no such dataset directory or manifest")
    else:
        objects = [DatasetObject(str(p), Path(p)) for p in dataset]
        if not objects:
            raise DatasetError("the dataset is empty: give at least one task file")
    seen = set()
    for obj in objects:
        if obj.name in seen:
            raise DatasetError(f"object '{obj.name}' appears twice in the dataset")
        seen.add(obj.name)
        if not obj.task.is_file():
            raise DatasetError(f"{obj.task}: task file of object '{obj.name}' not found")
        if obj.candidates is not None and not obj.candidates.is_file():
            raise DatasetError(f"{obj.candidates}: candidate file of object '{obj.name}' not found")
    return objects


MANIFEST_COLUMNS = ("object", "task", "candidates")


def _manifest(path: Path) -> List[DatasetObject]:
    if not path.is_file():
        raise DatasetError(f"{path}: no such manifest")
    with path.open(newline="", encoding="utf-8") as f:
        reader = csv.DictReader(f)
        fields = reader.fieldnames or []
        if "task" not in fields:
            raise DatasetError(f"{path}: the manifest needs a 'task' column (has {fields})")
        unknown = [c for c in fields if c not in MANIFEST_COLUMNS]
        if unknown:
            raise DatasetError(f"{path}: unknown column(s) {unknown} (columns: {', '.join(MANIFEST_COLUMNS)})")
        objects = []
        for line, row in enumerate(reader, start=2):
            task = (row.get("task") or "").strip()
            if not task:
                raise DatasetError(f"{path}: line {line}: field 'task' is empty")
            candidates = (row.get("candidates") or "").strip()
            name = (row.get("object") or "").strip() or candidates or task
            objects.append(DatasetObject(name, path.parent / task, path.parent / candidates if candidates else None))
    if not objects:
        raise DatasetError(f"{path}: the manifest lists no objects")
    return objects


def load_task(source: Tuple[str, Optional[str]]) -> Task:
    """The task of one object, ``(task file, candidate file or None)``."""
    task, candidates = source
    return Task.load(task) if candidates is None else Task.load(task, candidates=candidates)


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


def run_shard(
    sources: Sequence[Tuple[str, Optional[str]]], pieces: Sequence[Piece], top_k: int, threads: Optional[int]
) -> Dict[str, Any]:
    """One shard: loads the tasks its pieces name (``sources[object]``: task file, candidate
    file or ``None``, see :func:`load_task`) and scores the
    pieces' candidate slices with :func:`graspath.select_batch`, keeping each slice's ``top_k``.
    Returns ``columns`` (numpy, ``object`` mapped back to the dataset's object index),
    ``candidates`` (scored) and ``seconds`` (wall time). What a Ray task runs, and what
    ``local=True`` runs in-process."""
    started = time.perf_counter()
    tasks = [load_task(sources[obj]) for obj, _, _ in pieces]
    columns = select_batch(
        tasks, slices=[(start, stop) for _, start, stop in pieces], top_k=top_k, threads=threads
    )
    objects = np.array([obj for obj, _, _ in pieces], dtype=np.int64)
    columns["object"] = objects[columns["object"]]
    return {
        "columns": columns,
        "candidates": sum(stop - start for _, start, stop in pieces),
        "seconds": time.perf_counter() - started,
    }


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


def _table(merged: Dict[str, np.ndarray], object_names: Sequence[str], top_k: int):
    import pyarrow as pa

    names = np.array(object_names, dtype=object)
    columns = {
        "object": pa.array(names[merged["object"]].tolist() if len(merged["object"]) else [], pa.string()),
        "arm": pa.array(merged["arm"].tolist(), pa.string()),
        "label": pa.array(merged["label"].tolist(), pa.string()),
    }
    arrays = []
    for field in schema():
        if field.name in columns:
            arrays.append(columns[field.name])
        elif field.nullable:
            values = merged[field.name]
            arrays.append(pa.array(values, field.type, mask=np.isnan(values)))
        else:
            arrays.append(pa.array(merged[field.name], field.type))
    metadata = {b"graspath.version": __version__.encode(), b"graspath.top_k": str(top_k).encode()}
    return pa.Table.from_arrays(arrays, schema=schema().with_metadata(metadata))


def write_parquet(table, out: Path) -> None:
    """Writes ``table`` with fixed settings (zstd, ``ROW_GROUP_SIZE`` rows per group, no
    timestamps), to a temporary file beside ``out`` that is then renamed: the same table gives
    the same bytes, and a failed write leaves no partial file."""
    import pyarrow.parquet as pq

    tmp = out.with_name(f".{out.name}.{os.getpid()}.tmp")
    try:
        pq.write_table(
            table,
            tmp,
            row_group_size=ROW_GROUP_SIZE,
            compression="zstd",
            use_dictionary=False,
            write_statistics=True,
            store_schema=True,
        )
        os.replace(tmp, out)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise


class _Progress:
    """Logs each finished shard: candidates done, candidates/s, ETA."""

    def __init__(self, total: int, shards: int):
        self.total, self.shards = total, shards
        self.done = self.finished = 0
        self.started = time.perf_counter()

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
    object, arm, rank).

    * ``shard_size``: candidates per shard (one Ray task each).
    * ``local``: run the shards in this process, one after the other, without Ray (``threads``
      threads each, default every core); the file is the same.
    * Otherwise Ray: ``address`` (``"auto"`` for a running cluster; ``None`` starts a local
      instance with ``num_cpus`` CPUs, default all, unless Ray is already initialised); each
      shard reserves ``cpus_per_shard`` CPUs and runs ``threads`` threads (default
      ``max(1, int(cpus_per_shard))``).
    * ``overwrite``: replace an existing ``out`` (else refused).

    Returns ``objects``, ``candidates`` (scored), ``rows`` (written), ``shards``, ``seconds``
    (wall time) and ``out``. Raises :class:`graspath.GraspathError` on bad input (a missing
    task file, a task the library refuses, ``top_k`` or ``shard_size`` below 1, an existing
    ``out``) before any work is started."""
    started = time.perf_counter()
    if isinstance(top_k, bool) or not isinstance(top_k, int) or top_k < 1:
        raise GraspathError(f"top_k must be a positive integer (got {top_k!r})")
    if isinstance(shard_size, bool) or not isinstance(shard_size, int) or shard_size < 1:
        raise GraspathError(f"shard_size must be a positive integer (got {shard_size!r})")
    if not cpus_per_shard > 0:
        raise GraspathError(f"cpus_per_shard must be positive (got {cpus_per_shard!r})")
    if threads is not None and (isinstance(threads, bool) or not isinstance(threads, int) or threads < 1):
        raise GraspathError(f"threads must be a positive integer (got {threads!r})")
    out = Path(out)
    if out.exists() and not overwrite:
        raise GraspathError(f"{out}: the output exists (pass overwrite=True / --force to replace it)")
    if not out.parent.is_dir():
        raise GraspathError(f"{out.parent}: the output's folder does not exist")
    try:
        import pyarrow  # noqa: F401
    except ImportError as e:
        raise GraspathError("pyarrow is not installed: pip install graspath[ray]") from e

    objects = dataset_tasks(dataset)
    sources = [(str(o.task.resolve()), None if o.candidates is None else str(o.candidates.resolve())) for o in objects]
    counts = [len(load_task(source)) for source in sources]
    shards = plan_shards(counts, shard_size)
    total = sum(counts)
    log.info("%d objects, %d candidates, %d shards of up to %d candidates", len(objects), total, len(shards), shard_size)

    progress = _Progress(total, len(shards))
    results: Dict[int, Dict[str, Any]] = {}
    if local:
        for index, pieces in enumerate(shards):
            results[index] = run_shard(sources, pieces, top_k, threads)
            progress.shard_done(index, results[index])
    else:
        results = _run_on_ray(sources, shards, top_k, threads, address, num_cpus, cpus_per_shard, progress)

    log.info(
        "scored %d candidates in %d shards in %.2f s (%.0f candidates/s)",
        total,
        len(shards),
        time.perf_counter() - progress.started,
        total / max(time.perf_counter() - progress.started, 1e-9),
    )
    # No candidates at all: the columns of an empty batch give the (empty) table its types.
    columns = [results[i]["columns"] for i in range(len(shards))] or [select_batch([], top_k=top_k)]
    merged = merge_top_k(columns, top_k)
    table = _table(merged, [o.name for o in objects], top_k)
    write_parquet(table, out)
    seconds = time.perf_counter() - started
    log.info("wrote %s: %d rows (%d objects, %d candidates) in %.2f s", out, table.num_rows, len(objects), total, seconds)
    return {
        "objects": len(objects),
        "candidates": total,
        "rows": table.num_rows,
        "shards": len(shards),
        "seconds": seconds,
        "out": out,
    }


def _run_on_ray(
    sources: List[Tuple[str, Optional[str]]],
    shards: List[List[Piece]],
    top_k: int,
    threads: Optional[int],
    address: Optional[str],
    num_cpus: Optional[int],
    cpus_per_shard: float,
    progress: _Progress,
) -> Dict[int, Dict[str, Any]]:
    try:
        import ray
    except ImportError as e:
        raise GraspathError("ray is not installed: pip install graspath[ray] (or run with local=True / --local)") from e
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
    try:
        shard_threads = threads if threads is not None else max(1, int(cpus_per_shard))
        remote: Callable[..., Any] = ray.remote(num_cpus=cpus_per_shard)(run_shard)
        files = ray.put(sources)
        pending = {remote.remote(files, pieces, top_k, shard_threads): i for i, pieces in enumerate(shards)}
        results: Dict[int, Dict[str, Any]] = {}
        while pending:
            ready, _ = ray.wait(list(pending), num_returns=1)
            for ref in ready:
                index = pending.pop(ref)
                results[index] = ray.get(ref)
                progress.shard_done(index, results[index])
        return results
    finally:
        if started_here:
            ray.shutdown()


def main(argv: Optional[Sequence[str]] = None) -> int:
    """``python -m graspath.ray``: see the module's documentation and ``--help``."""
    parser = argparse.ArgumentParser(
        prog="python -m graspath.ray",
        description="Score every grasp candidate of every object of a dataset (a directory of "
        "task files or a .csv manifest) on a Ray cluster, and write each object's and arm's "
        "top-k to a Parquet file (the same bytes with --local, without Ray).",
    )
    parser.add_argument("dataset", help="a directory of task files (*.yaml, *.yml) or a .csv manifest (columns task, and optionally candidates, object)")
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
        print(
            f"{summary['objects']} objects, {summary['candidates']} candidates, "
            f"{summary['rows']} rows in {summary['seconds']:.2f} s; wrote {summary['out']}"
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
