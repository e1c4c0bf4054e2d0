"""Fuzzing of the Python entry points with untrusted arrays: every dtype, order, stride and
shape numpy makes, and hostile values.

Each execution draws an entry point and an array (``draw_call``), calls it, and checks:

* **no panic, no crash**: the call returns or raises a :class:`graspath.GraspathError` or a
  ``TypeError`` (a Python object that is not an array at all); a ``PanicException`` or any
  other exception is a finding, and a crash (the process dying) leaves the input in the
  ``--current`` file;
* **read by strides**: when the call succeeds, it gives the same bytes as the same call on a
  C-ordered float64 copy of the array (a transposed, Fortran-ordered, negatively strided or
  broadcast view is read as the array it is, never in memory order);
* **refused, not cast**: a complex, string, date or duration array never succeeds (numpy's
  cast would drop an imaginary part, or pass parsed text or counts of time units as numbers).

Run a campaign (figures in TESTING.md)::

    python crates/graspath-py/tests/fuzz_entry_points.py --execs 10000000 --seed 1

``test_untrusted_arrays.py`` runs a deterministic slice of it in the test suite.
"""

from __future__ import annotations

import argparse
import math
import sys
import time
import traceback

import numpy as np

import graspath

#: dtypes an array may have; the last group is refused by every entry point.
NUMERIC = [
    np.float64, np.float32, np.float16, np.longdouble, np.int8, np.int16, np.int32, np.int64,
    np.uint8, np.uint16, np.uint32, np.uint64, np.bool_, object,
]
REFUSED = [np.complex64, np.complex128, "U3", "S3", "datetime64[s]", "timedelta64[s]"]
#: The dtype kinds of REFUSED: an array of one of them must never be accepted.
REFUSED_KINDS = "cUSMmV"

#: Values a configuration or direction may hold, beside ordinary ones.
HOSTILE = [0.0, -0.0, 1e-300, -1e-300, 1e300, -1e300, math.inf, -math.inf, math.nan, 3.0, -3.0]

ENTRY_POINTS = [
    "fk", "jacobian", "fk_jacobian", "indices", "task_relevant", "within_limits",
    "joint_origins", "gravity_torques", "inverse_dynamics", "mass_matrix", "ik", "pose_matrix",
]


class Finding(Exception):
    """An execution that broke an oracle."""


def draw_values(rng: np.random.Generator, shape) -> np.ndarray:
    values = rng.uniform(-3.0, 3.0, size=shape)
    if values.size and rng.random() < 0.3:
        flat = values.reshape(-1)
        for _ in range(int(rng.integers(1, 4))):
            flat[int(rng.integers(0, flat.size))] = HOSTILE[int(rng.integers(0, len(HOSTILE)))]
    return values


def draw_layout(rng: np.random.Generator, values: np.ndarray, dtype) -> np.ndarray:
    """``values`` as an array of ``dtype`` laid out in one of the ways numpy allows."""
    with np.errstate(all="ignore"):
        if dtype in ("U3", "S3"):
            array = values.astype(str).astype(dtype)
        elif dtype in ("datetime64[s]", "timedelta64[s]"):
            array = np.zeros(values.shape, dtype=dtype)
        elif dtype is object:
            array = values.astype(object)
        else:
            array = values.astype(dtype)
    layout = int(rng.integers(0, 6))
    if layout == 1 and array.ndim >= 1:
        array = np.asfortranarray(array)
    elif layout == 2 and array.ndim == 2:
        # A transposed copy, transposed back: the same values, column-major in memory.
        array = np.ascontiguousarray(array.T).T
    elif layout == 3 and array.ndim >= 1:
        # Every other row of a twice-as-long array: a strided view.
        bigger = np.repeat(array, 2, axis=0)
        array = bigger[::2]
    elif layout == 4 and array.ndim >= 1:
        array = array[::-1][::-1] if rng.random() < 0.5 else np.flip(np.flip(array, 0), 0)
    elif layout == 5 and array.ndim >= 1 and array.shape[0] > 0:
        array = np.broadcast_to(array[:1], array.shape)
    return array


def draw_call(rng: np.random.Generator, robot):
    """An entry point and its arguments: ``(name, function, args, kwargs, array)``."""
    name = ENTRY_POINTS[int(rng.integers(0, len(ENTRY_POINTS)))]
    dof = robot.dof
    refused = rng.random() < 0.1
    dtype = REFUSED[int(rng.integers(0, len(REFUSED)))] if refused else (
        np.float64 if rng.random() < 0.5 else NUMERIC[int(rng.integers(0, len(NUMERIC)))]
    )
    width = dof if rng.random() < 0.85 else int(rng.integers(0, dof + 3))
    rows = int(rng.integers(0, 6))
    shape = {0: (width,), 1: (rows, width), 2: (rows, width)}[int(rng.integers(0, 3))]
    if rng.random() < 0.05:
        shape = tuple(int(rng.integers(0, 4)) for _ in range(int(rng.integers(0, 4))))
    array = draw_layout(rng, draw_values(rng, shape), dtype)
    kwargs = {}
    if name == "task_relevant":
        u = draw_layout(rng, draw_values(rng, (6,) if rng.random() < 0.9 else (5,)), np.float64)
        args = (array, u)
    elif name == "inverse_dynamics":
        args = (array, draw_values(rng, array.shape[-1:] if array.ndim else ()), np.zeros(dof))
    elif name == "ik":
        target = np.eye(4)
        target[:3, 3] = [0.4, 0.0, 0.4]
        args = (target,)
        kwargs = {"seed": array, "max_time": float(rng.choice([0.001, 0.0, -1.0, 1e300, math.nan]))}
    elif name == "pose_matrix":
        args = ({"xyz": array.reshape(-1)[:3] if array.size >= 3 else array, "rpy": [0.0, 0.0, 0.0]},)
    else:
        args = (array,)
    function = graspath.pose_matrix if name == "pose_matrix" else getattr(robot, name)
    return name, function, args, kwargs, array


def as_plain(value):
    """A result as comparable bytes (arrays, floats, tuples, dicts and result objects)."""
    if isinstance(value, np.ndarray):
        return (value.dtype.str, value.shape, value.tobytes())
    if isinstance(value, (tuple, list)):
        return tuple(as_plain(v) for v in value)
    if isinstance(value, dict):
        return tuple((k, as_plain(v)) for k, v in sorted(value.items()))
    if isinstance(value, float):
        return np.float64(value).tobytes()
    if hasattr(value, "__dict__") or hasattr(value, "_asdict"):
        fields = value._asdict() if hasattr(value, "_asdict") else vars(value)
        return as_plain(dict(fields))
    return repr(value)


def plain_copy(array: np.ndarray):
    """The array as a C-ordered float64 copy, or ``None`` when it has no such meaning."""
    if array.dtype.kind not in "fiubO":
        return None
    with np.errstate(all="ignore"):
        return np.ascontiguousarray(array, dtype=np.float64)


def execute(robot, rng: np.random.Generator) -> str:
    """One execution; raises :class:`Finding` when an oracle breaks. Returns the outcome."""
    name, function, args, kwargs, array = draw_call(rng, robot)
    try:
        result = function(*args, **kwargs)
    except (graspath.GraspathError, TypeError):
        return "refused"
    except BaseException as error:  # noqa: BLE001 - every other exception is a finding
        raise Finding(
            f"{name}: {type(error).__module__}.{type(error).__name__}: {error} "
            f"(dtype {array.dtype}, shape {array.shape}, strides {array.strides})\n"
            + traceback.format_exc()
        ) from None
    if array.dtype.kind in REFUSED_KINDS:
        raise Finding(f"{name} accepted a {array.dtype} array of shape {array.shape}")
    copy = plain_copy(array)
    if name not in ("ik", "pose_matrix") and copy is not None:
        again = function(*(copy if a is array else a for a in args), **kwargs)
        if as_plain(again) != as_plain(result):
            raise Finding(
                f"{name}: a {array.dtype} array with strides {array.strides} "
                f"(shape {array.shape}) gives another result than its C-ordered copy"
            )
    return "accepted"


def campaign(execs: int, seed: int, current: str | None = None, report_every: int = 0):
    """Runs ``execs`` executions from ``seed``; returns ``(outcomes, findings)``."""
    robots = [graspath.Robot.builtin("panda"), graspath.Robot.baxter("left")]
    outcomes = {"accepted": 0, "refused": 0}
    findings = []
    start = time.perf_counter()
    for index in range(execs):
        rng = np.random.default_rng([seed, index])
        if current is not None and index % 1000 == 0:
            with open(current, "w") as f:
                f.write(f"{seed} {index}\n")
        robot = robots[index % len(robots)]
        try:
            outcomes[execute(robot, rng)] += 1
        except Finding as finding:
            findings.append((index, str(finding)))
        if report_every and (index + 1) % report_every == 0:
            elapsed = time.perf_counter() - start
            print(
                f"{index + 1} executions, {elapsed:.0f} s, {(index + 1) / elapsed:.0f}/s, "
                f"{outcomes}, {len(findings)} findings",
                flush=True,
            )
    return outcomes, findings


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--execs", type=int, default=100_000)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--current", default=None, help="file that names the running input")
    parser.add_argument("--report-every", type=int, default=100_000)
    options = parser.parse_args()
    start = time.perf_counter()
    outcomes, findings = campaign(options.execs, options.seed, options.current, options.report_every)
    elapsed = time.perf_counter() - start
    for index, text in findings[:20]:
        print(f"finding at input {index} (seed {options.seed}):\n{text}")
    print(
        f"{options.execs} executions in {elapsed:.0f} s ({options.execs / elapsed:.0f}/s): "
        f"{outcomes}, {len(findings)} findings"
    )
    return 1 if findings else 0


if __name__ == "__main__":
    sys.exit(main())
