"""Every call the stub types with a :mod:`graspath.results` class returns exactly that shape: the
required keys, no key the class does not name, and values of the annotated types (numpy dtypes
included), checked recursively on real results."""

import typing
from typing import Any, List, Literal, Optional, Union, get_args, get_origin, get_type_hints

import numpy as np
import pytest

import graspath
from graspath import results
from conftest import EXAMPLES


def conforms(value, hint, where="result"):
    """Asserts that ``value`` has the type ``hint`` (TypedDicts, lists, unions, numpy arrays
    with their dtype, builtins)."""
    if hint is Any:
        return
    if typing.is_typeddict(hint):
        assert isinstance(value, dict), f"{where}: {type(value).__name__}, not a dict"
        keys = set(value)
        missing = hint.__required_keys__ - keys
        extra = keys - hint.__required_keys__ - hint.__optional_keys__
        assert not missing, f"{where}: {hint.__name__} lacks {sorted(missing)}"
        assert not extra, f"{where}: {hint.__name__} does not name {sorted(extra)}"
        hints = get_type_hints(hint)
        for key in keys:
            conforms(value[key], hints[key], f"{where}.{key}")
        return
    origin = get_origin(hint)
    if origin is Literal:
        assert value in get_args(hint), f"{where}: {value!r} not in {get_args(hint)}"
        return
    if origin is Union:
        errors = []
        for option in get_args(hint):
            try:
                conforms(value, option, where)
                return
            except AssertionError as e:
                errors.append(str(e))
        raise AssertionError(f"{where}: none of {hint} fits ({'; '.join(errors)})")
    if origin is list:
        assert isinstance(value, list), f"{where}: {type(value).__name__}, not a list"
        (item,) = get_args(hint)
        for k, v in enumerate(value):
            conforms(v, item, f"{where}[{k}]")
        return
    if origin is dict:
        assert isinstance(value, dict), f"{where}: {type(value).__name__}, not a dict"
        key_type, value_type = get_args(hint)
        for k, v in value.items():
            conforms(k, key_type, f"{where} key")
            conforms(v, value_type, f"{where}[{k!r}]")
        return
    if origin is np.ndarray:
        assert isinstance(value, np.ndarray), f"{where}: {type(value).__name__}, not an array"
        (dtype,) = get_args(get_args(hint)[1])
        assert value.dtype == dtype, f"{where}: dtype {value.dtype}, not {dtype}"
        return
    if hint is type(None):
        assert value is None, f"{where}: {value!r}, not None"
    elif hint is float:
        assert isinstance(value, (float, int)) and not isinstance(value, bool), f"{where}: {value!r}"
    elif hint is int:
        assert isinstance(value, int) and not isinstance(value, bool), f"{where}: {value!r}"
    else:
        assert isinstance(value, hint), f"{where}: {type(value).__name__}, not {hint.__name__}"


def test_the_checker_refuses_what_does_not_fit():
    """The checker itself fails on a missing key, an extra key, a wrong value type and a wrong
    dtype (it is not a test that cannot fail)."""
    good = {"sample": 3, "reason": "unreachable", "detail": "far"}
    conforms(good, results.TrajectoryFailure)
    for bad in (
        {"sample": 3, "reason": "unreachable"},
        {**good, "extra": 1},
        {**good, "sample": "3"},
    ):
        with pytest.raises(AssertionError):
            conforms(bad, results.TrajectoryFailure)
    with pytest.raises(AssertionError):
        conforms(np.zeros(3, dtype=np.int64), results.FloatArray)
    with pytest.raises(AssertionError):
        conforms([None], List[int])
    conforms([None, 1], List[Optional[int]])


@pytest.fixture(scope="module")
def panda():
    return graspath.Robot.builtin("panda")


def straight_path(robot, samples=5, length=0.05):
    start = robot.fk(robot.mid_configuration())
    path = np.repeat(start[None], samples, axis=0)
    path[:, 0, 3] += np.linspace(0.0, length, samples)
    return path


def test_robot_results(panda):
    q = panda.mid_configuration()
    conforms(panda.indices(q), results.Indices)
    conforms(panda.indices(np.tile(q, (3, 1)), part="translation"), results.Indices)
    target = panda.fk(q)
    conforms(panda.ik(target), results.IkResult)
    far = target.copy()
    far[0, 3] += 5.0
    failed = panda.ik(far, max_time=None, max_iterations=50)
    assert failed["failure"] is not None
    conforms(failed, results.IkResult)
    batch = panda.ik(np.stack([target, far]), max_time=None, max_iterations=50)
    assert batch["failure_reason"][1] is not None
    conforms(batch, results.IkBatchResult)
    path = straight_path(panda)
    found = panda.ik_trajectory(path)
    assert found["feasible"]
    conforms(found, results.TrajectoryIk)
    unreachable = path.copy()
    unreachable[:, 0, 3] += 5.0
    both = panda.ik_trajectory(np.stack([path, unreachable]))
    assert both[1]["failure"] is not None
    conforms(both, List[results.TrajectoryIk])
    conforms(panda.optimize_self_motion(path, found["branches"][0]), results.SelfMotion)


def test_selection_results():
    scene = graspath.Task.load(EXAMPLES / "scene" / "pick_and_place_left_cluttered.yaml")
    two_arms = graspath.Task.load(EXAMPLES / "pick_and_place_both.yaml")
    left = graspath.Robot.baxter("left")
    start = np.eye(4)
    start[:3, 3] = [0.75, 0.35, 0.0]
    poses = np.repeat(start[None], 11, axis=0)
    poses[:, 2, 3] += np.linspace(0.0, 0.2, 11)
    candidates = np.repeat(np.diag([1.0, -1.0, -1.0, 1.0])[None], 3, axis=0)
    candidates[:, 0, 3] = [-0.03, 0.0, 0.03]
    carried = graspath.Task.from_arrays(
        {"left": left}, poses, candidates, payload={"mass": 0.5}, redundancy="optimize"
    )
    seen = set()
    for task in (scene, two_arms, carried):
        conforms(task.candidates, List[results.TaskCandidate])
        selection = graspath.select(task)
        conforms(selection.candidates, List[results.CandidateRecord])
        conforms(selection.pairs, List[results.PairRecord])
        conforms(selection.summary, results.Summary)
        conforms(selection.timed_motions(), List[results.TimedMotion])
        for record in selection.candidates:
            groups = ("failure", "self_motion")
            seen |= set(record) - set(groups)
            for group in groups:
                if record.get(group):
                    seen |= {f"{group}.{k}" for k in record[group]}
    # The scene fails some candidates on a collision (the failure group's bodies), the
    # carried object fills the dynamics columns and the self-motion group.
    assert {"failure.bodies", "torque_margin", "self_motion.mu_l2_min", "clearance"} <= seen
    declared = record_type_fields()
    assert seen <= declared


def record_type_fields():
    """The JSON fields :class:`results.CandidateRecord` declares, group members as
    ``group.name``."""
    fields = set()
    for key, hint in get_type_hints(results.CandidateRecord).items():
        group = next((a for a in (hint, *get_args(hint)) if typing.is_typeddict(a)), None)
        if group is None:
            fields.add(key)
        else:
            fields |= {f"{key}.{member}" for member in get_type_hints(group)}
    return fields


def test_the_record_type_is_the_schema():
    """``CandidateRecord`` names exactly the columns ``record_columns()`` puts in a JSON record,
    in their places (``failure.reason``)."""
    schema = {c["json_field"] for c in graspath.record_columns() if c["json_field"] is not None}
    assert record_type_fields() == schema
    for column in graspath.record_columns():
        in_json = {"json", "jsonl"} & set(column["outputs"])
        assert (column["json_field"] is not None) == bool(in_json), column["name"]
    conforms(graspath.record_columns(), List[results.RecordColumn])


def test_module_function_results(panda, tmp_path):
    path = panda.ik_trajectory(straight_path(panda))["branches"][0]
    conforms(
        graspath.time_path(path, panda.velocity_limits, np.full(panda.dof, 5.0)), results.TimedPath
    )
    task = graspath.Task.load(EXAMPLES / "pick_and_place_left.yaml")
    best = graspath.select(task).best("left")
    position = [c["id"] for c in task.candidates].index(best)
    conforms(graspath.candidate_motions(task, [position]), List[results.TimedMotion])
    conforms(graspath.world_mjcf(task), results.MjcfWorld)
    xml, names = graspath.robot_mjcf(panda)
    assert isinstance(xml, str)
    conforms(names, results.MjcfArm)
    conforms(
        graspath.placement_map(
            EXAMPLES / "pick_and_place_left.yaml", (0.5, 0.6, 2), (0.0, 0.1, 2), yaw_deg=(0, 10, 2)
        ),
        results.PlacementMap,
    )
    conforms(graspath.result_cache(), results.ResultCache)
    model = tmp_path / "model.json"
    conforms(graspath.train(EXAMPLES / "grasp" / "demo_box.json", model), results.TrainedModel)
    conforms(
        graspath.generate(
            model,
            EXAMPLES / "grasp" / "cylinder.json",
            max_candidates=4,
            initial_grasps=400,
            steps=10,
            query_kernels=400,
        ),
        results.GeneratedGrasps,
    )
    grasps = tmp_path / "grasps.npy"
    np.save(grasps, np.repeat(np.eye(4)[None], 3, axis=0))
    conforms(graspath.read_grasps(grasps, format="poses"), results.GraspFile)
