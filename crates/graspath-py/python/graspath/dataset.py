"""The datasets :mod:`graspath.ray` reads (reading one needs neither Ray nor pyarrow).

A dataset is a set of task files (graspath's task format, ``docs/task-file.md``), one per
object — each with its own object pose, path, candidates (a family, a grasp file, a learned
model) and scene:

* a directory: every ``*.yaml`` / ``*.yml`` file directly in it, in name order, each object
  named by its file name;
* a manifest (``*.csv``), one row per object, with a ``task`` column (paths relative to the
  manifest), an optional ``candidates`` column (a candidate file — graspath JSON/CSV or a grasp
  generator's file — read instead of the task file's candidates, with the task file's
  ``candidates`` options such as ``format`` and ``frame``: objects × candidate files on one
  task file), optional pose columns (below) and an optional ``object`` column (the object's
  name; default the candidate file, else the task file — name the objects when rows share
  both);
* from Python, a sequence of task file paths.

The manifest's pose columns place the object: ``xyz`` and at most one of ``rpy``, ``rpy_deg``
or ``quaternion`` — the keys of the task file's pose syntax (``docs/task-file.md``, "Poses"),
with the same meaning: ``world_from_object`` of the object's start, ``xyz`` in metres in the
world frame, ``rpy`` URDF fixed-axis roll-pitch-yaw in radians, ``rpy_deg`` the same in
degrees, ``quaternion`` ``x y z w`` (norm 1 within 0.001). A cell holds its numbers separated
by spaces (or commas, in a quoted cell). A row whose pose cells are all empty keeps the task
file's ``object.pose``; a row that fills any replaces it whole (``xyz`` is then required, and
no rotation given is the identity), as if the task file said ``object.pose: {xyz: …, rpy_deg:
…}``: the path's relative steps start from it, absolute steps, the robot and the scene stay
(:meth:`graspath.Task.load` with ``object_pose``, the way :func:`graspath.placement_map` moves
the object; candidates the learned model generates in a scene keep the filtering done at the
file's pose). One task file then serves many placed objects::

    object,task,xyz,rpy_deg
    box_a,pick.yaml,0.70 0.25 -0.05,0 0 0
    box_b,pick.yaml,0.65 0.35 0.00,0 0 30

A bad value — a cell that is not the right count of numbers, NaN or infinite, a quaternion that
is not unit, two rotations in one row — is one :class:`DatasetError` naming the manifest, the
line and the column (``objects.csv: line 3: field 'quaternion': must be a unit quaternion …``),
raised before any task is loaded. So is a manifest that is not CSV text (not UTF-8, a field
longer than Python's ``csv`` field limit), and one beyond the caps that bound what is
read into memory before the first task loads: :data:`MAX_MANIFEST_BYTES` bytes and
:data:`MAX_MANIFEST_OBJECTS` objects (split a larger dataset into several manifests).
"""

from __future__ import annotations

import csv
import io
import os
import re
from pathlib import Path
from typing import Dict, List, NamedTuple, Optional, Sequence, Tuple, Union

from . import GraspathError, GraspathValueError, Task, pose_matrix

#: Task file suffixes picked up from a dataset directory.
TASK_SUFFIXES = (".yaml", ".yml")

#: The manifest's pose columns (the task file's pose keys) and how many numbers each holds.
POSE_COLUMNS = {"xyz": 3, "rpy": 3, "rpy_deg": 3, "quaternion": 4}

Source = Tuple[str, Optional[str], Optional[Dict[str, List[float]]]]
"""How a task loads (:func:`load_task`): the task file, the candidate file or ``None``, and
the object's start pose (a dict in the task file's pose syntax) or ``None``."""


class DatasetError(GraspathValueError):
    """A dataset that cannot be read: names the directory, manifest, file or field at fault (a
    :class:`ValueError`, as it was before graspath's exceptions had kinds)."""


class DatasetObject(NamedTuple):
    """One object of a dataset: its name, its task file and, from a manifest, a candidate file
    read instead of the task file's candidates and the object's start pose (a dict in the task
    file's pose syntax, see :data:`POSE_COLUMNS`) replacing the task file's ``object.pose``
    (each ``None`` when not given)."""

    name: str
    task: Path
    candidates: Optional[Path] = None
    pose: Optional[Dict[str, List[float]]] = None


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
            raise DatasetError(f"object '{obj.name}' appears twice in the dataset (name the objects with a manifest's 'object' column)")
        seen.add(obj.name)
        if not obj.task.is_file():
            raise DatasetError(f"{obj.task}: task file of object '{obj.name}' not found")
        if obj.candidates is not None and not obj.candidates.is_file():
            raise DatasetError(f"{obj.candidates}: candidate file of object '{obj.name}' not found")
    return objects


MANIFEST_COLUMNS = ("object", "task", "candidates", *POSE_COLUMNS)

#: The largest manifest read (bytes); checked before reading.
MAX_MANIFEST_BYTES = 256 << 20

#: The most objects a manifest may list.
MAX_MANIFEST_OBJECTS = 1_000_000


def _manifest(path: Path) -> List[DatasetObject]:
    if not path.is_file():
        raise DatasetError(f"{path}: no such manifest")
    too_large = f"{path}: the manifest is more than {MAX_MANIFEST_BYTES} bytes (MAX_MANIFEST_BYTES); split the dataset into several manifests"
    if path.stat().st_size > MAX_MANIFEST_BYTES:
        raise DatasetError(too_large)
    with path.open("rb") as f:
        data = f.read(MAX_MANIFEST_BYTES + 1)  # bounded even if the file grows meanwhile
    if len(data) > MAX_MANIFEST_BYTES:
        raise DatasetError(too_large)
    try:
        data.decode("utf-8")
    except UnicodeDecodeError as e:
        # Lines end as csv ends them: \r\n, \n or \r.
        line = len(re.findall(rb"\r\n|\r|\n", data[: e.start])) + 1
        raise DatasetError(f"{path}: line {line}: not UTF-8 text (byte {e.start}: {e.reason})") from None
    reader = csv.DictReader(io.TextIOWrapper(io.BytesIO(data), encoding="utf-8", newline=""))
    try:
        return _manifest_objects(path, reader)
    except csv.Error as e:
        # The underlying reader has counted the line it failed on.
        raise DatasetError(f"{path}: line {reader.reader.line_num}: not a CSV manifest: {e}") from None


def _manifest_objects(path: Path, reader: "csv.DictReader[str]") -> List[DatasetObject]:
    fields = reader.fieldnames or []
    if "task" not in fields:
        raise DatasetError(f"{path}: the manifest needs a 'task' column (has {fields})")
    unknown = [c for c in fields if c not in MANIFEST_COLUMNS]
    if unknown:
        raise DatasetError(f"{path}: unknown column(s) {unknown} (columns: {', '.join(MANIFEST_COLUMNS)})")
    objects = []
    for row in reader:
        where = f"{path}: line {reader.line_num}"
        if len(objects) == MAX_MANIFEST_OBJECTS:
            raise DatasetError(f"{where}: the manifest lists more than {MAX_MANIFEST_OBJECTS} objects (MAX_MANIFEST_OBJECTS); split the dataset into several manifests")
        task = (row.get("task") or "").strip()
        if not task:
            raise DatasetError(f"{where}: field 'task' is empty")
        candidates = (row.get("candidates") or "").strip()
        name = (row.get("object") or "").strip() or candidates or task
        pose = _manifest_pose(where, row)
        objects.append(DatasetObject(name, path.parent / task, path.parent / candidates if candidates else None, pose))
    if not objects:
        raise DatasetError(f"{path}: the manifest lists no objects")
    return objects


def _manifest_pose(where: str, row: Dict[str, Optional[str]]) -> Optional[Dict[str, List[float]]]:
    """The object's start pose a manifest row gives in its pose columns (a dict in the task
    file's pose syntax, checked by :func:`graspath.pose_matrix`), or ``None`` when they are
    all empty; ``where`` (the manifest and line) starts every error."""
    spec: Dict[str, List[float]] = {}
    for column, count in POSE_COLUMNS.items():
        cell = (row.get(column) or "").strip()
        if not cell:
            continue
        words = cell.replace(",", " ").split()
        try:
            values = [float(w) for w in words]
        except ValueError:
            raise DatasetError(f"{where}: field '{column}': '{cell}' is not {count} numbers separated by spaces") from None
        if len(values) != count:
            raise DatasetError(f"{where}: field '{column}': {len(values)} numbers ('{cell}'), expected {count}")
        spec[column] = values
    if not spec:
        return None
    rotations = [c for c in spec if c != "xyz"]
    if len(rotations) > 1:
        raise DatasetError(f"{where}: fields {', '.join(repr(c) for c in rotations)}: give at most one of rpy, rpy_deg, quaternion")
    if "xyz" not in spec:
        raise DatasetError(f"{where}: field 'xyz' is empty: a row that gives the object's orientation ('{rotations[0]}') gives its position too")
    try:
        pose_matrix(spec)
    except GraspathError as e:
        raise DatasetError(f"{where}: {e}") from None
    return spec


def load_task(source: Source) -> Task:
    """The task of one object (see :data:`Source`)."""
    task, candidates, pose = source
    return Task.load(task, candidates=candidates, object_pose=pose)
