"""Selection from Python against the CLI's output on the same task (an independent run of the
`graspath` binary), and the other ways of building a task (dict, text, arrays) against files."""

import json
import math
import subprocess

import numpy as np
import pytest

import graspath
from conftest import EXAMPLES

LEFT = EXAMPLES / "pick_and_place_left.yaml"
BOTH = EXAMPLES / "pick_and_place_both.yaml"


def run_cli(binary, task, out):
    subprocess.run(
        [str(binary), "select", "--task", str(task), "--out", str(out), "--quiet"],
        check=True,
        capture_output=True,
    )
    return {p.name: p.read_bytes() for p in sorted(out.iterdir())}


# The IK and norm settings of examples/pick_and_place_left.yaml (the paper's).
SAME_IK_AS_THE_FILE = {"branches": 8, "ik_iterations": 2000, "redundancy": "best_branch", "ik_limit_margin": 0.0, "norm": "l2"}


@pytest.fixture(scope="module")
def left_selection():
    task = graspath.Task.load(LEFT)
    return task, graspath.select(task)


@pytest.fixture(scope="module")
def both_selection():
    task = graspath.Task.load(str(BOTH))
    return task, graspath.select(task)


@pytest.mark.parametrize("which", ["left", "both"])
def test_results_equal_the_cli(graspath_bin, tmp_path, left_selection, both_selection, which):
    path, (task, selection) = (LEFT, left_selection) if which == "left" else (BOTH, both_selection)
    cli = run_cli(graspath_bin, path, tmp_path / "cli")
    assert json.loads(cli["candidates.json"]) == selection.candidates
    assert json.loads(cli["summary.json"]) == selection.summary
    if which == "both":
        assert json.loads(cli["pairs.json"]) == selection.pairs
        assert len(selection.pairs) == 10
    else:
        assert "pairs.json" not in cli and selection.pairs == []
    written = selection.write(tmp_path / "py")
    assert sorted(p.name for p in written) == sorted(cli)
    for p in written:
        assert p.read_bytes() == cli[p.name], p.name


def test_records_mirror_candidates_json(left_selection):
    task, selection = left_selection
    records = selection.candidates
    assert len(records) == len(task) == 21
    first = records[0]
    for key in ("id", "arm", "label", "object_from_wrist", "feasible", "failure", "rank", "score",
                "mu_l2", "mu_linf", "mu_linf_infinite", "mu_l1", "mu_rms", "m_t", "joint_trajectory",
                "yoshikawa_at_grasp", "inverse_condition_squared_at_grasp", "pareto"):
        assert key in first
    assert selection.summary["arms"][0]["selected"]["id"] == selection.best("left")
    ranked = sorted((r for r in records if r["rank"]), key=lambda r: r["rank"])
    assert ranked[0]["id"] == selection.best("left")
    assert all(a["score"] >= b["score"] for a, b in zip(ranked, ranked[1:]))


def test_arrays_agree_with_records(left_selection):
    task, selection = left_selection
    arrays = selection.arrays("left")
    records = selection.candidates
    n = len(task.times)
    assert arrays["m_t"].shape == (21, n) and arrays["contact"].shape == (21, 3)
    assert arrays["id"].dtype == np.int64 and arrays["feasible"].dtype == np.bool_
    for i, r in enumerate(records):
        assert arrays["id"][i] == r["id"] and arrays["feasible"][i] == r["feasible"]
        assert (math.isnan(arrays["rank"][i]) if r["rank"] is None else arrays["rank"][i] == r["rank"])
        failure = r["failure"]
        assert (math.isnan(arrays["failure_sample"][i]) if failure is None else arrays["failure_sample"][i] == failure["sample"])
        for key in ("mu_l2", "mu_l1", "score", "yoshikawa_at_grasp"):
            value = r[key]
            assert (math.isnan(arrays[key][i]) if value is None else arrays[key][i] == value)
        for k, v in enumerate(r["m_t"]):
            assert (math.isnan(arrays["m_t"][i, k]) if v is None else arrays["m_t"][i, k] == v)
        path = selection.joint_trajectory("left", i)
        if r["feasible"]:
            np.testing.assert_array_equal(path, np.array(r["joint_trajectory"]))
        else:
            assert path is None


def test_m_t_recomputed_from_the_joint_path(left_selection):
    """Oracle: M_T = ‖Jᵀu‖² from the Jacobian at the reported joints and the wrist path's
    tangent computed here in numpy (log of consecutive wrist poses, base frame)."""
    task, selection = left_selection
    robot = task.robot("left")
    arrays = selection.arrays("left")
    i = int(np.nanargmax(arrays["mu_l2"]))
    q = selection.joint_trajectory("left", i)
    wrists = task.wrist_trajectory(i, "left")
    np.testing.assert_allclose(robot.fk(q), wrists, atol=2e-5)
    jacs = robot.jacobian(q)
    for k in range(len(q)):
        a, b = (k, k + 1) if k + 1 < len(q) else (k - 1, k)
        delta = np.linalg.inv(wrists[a]) @ wrists[b]
        twist = se3_log(delta)
        r = wrists[a][:3, :3]
        u = np.concatenate([r @ twist[:3], r @ twist[3:]])
        if np.linalg.norm(u) < 1e-9:
            assert math.isnan(arrays["m_t"][i, k])
            continue
        u /= np.linalg.norm(u)
        assert arrays["m_t"][i, k] == pytest.approx(u @ jacs[k] @ jacs[k].T @ u, rel=1e-9)
    assert arrays["mu_l2"][i] == pytest.approx(np.linalg.norm(arrays["m_t"][i][~np.isnan(arrays["m_t"][i])]), rel=1e-12)


def se3_log(m):
    """The body twist [v; ω] of a rigid transform (closed form)."""
    r, p = m[:3, :3], m[:3, 3]
    angle = np.arccos(np.clip((np.trace(r) - 1) / 2, -1, 1))
    if angle < 1e-9:
        return np.concatenate([p, np.zeros(3)])
    w_hat = angle / (2 * np.sin(angle)) * (r - r.T)
    w = np.array([w_hat[2, 1], w_hat[0, 2], w_hat[1, 0]])
    k = w_hat / angle
    v_inv = np.eye(3) - 0.5 * w_hat + (1 - angle * np.sin(angle) / (2 * (1 - np.cos(angle)))) * (k @ k)
    return np.concatenate([v_inv @ p, w])


def test_dual_arm_pairs_do_not_overlap(both_selection):
    task, selection = both_selection
    assert selection.arms == ["left", "right"]
    contacts = {arm: selection.arrays(arm)["contact"] for arm in selection.arms}
    for pair in selection.pairs:
        a, b = contacts["left"][pair["left"]], contacts["right"][pair["right"]]
        assert np.linalg.norm(a - b) >= 0.08
    left_alone = graspath.select(task.with_arms(["left"]))
    records = [r for r in selection.candidates if r["arm"] == "left"]
    assert left_alone.candidates == records
    assert graspath.select(task.with_arms(["right", "left"])).arms == ["right", "left"]


def test_dict_and_text_tasks_equal_the_file(left_selection):
    task, selection = left_selection
    text = LEFT.read_text()
    from_text = graspath.select(graspath.Task.parse(text, "yaml", name=str(LEFT)))
    assert from_text.candidates == selection.candidates
    document = {
        "robot": {"builtin": "baxter"},
        "arms": "left",
        "object": {"pose": {"xyz": [0.75, 0.0, -0.10]}, "shape": {"box": {"size": [0.06, 0.40, 0.10]}}},
        "candidates": {"family": {"edge": {"count": 21, "depth": 0.02, "margin": 0.02}}},
        "trajectory": {
            "samples_per_step": 10,
            "steps": [
                {"lift": 0.2, "label": "pick"},
                {"move": [0.0, 0.3, 0.0], "label": "move"},
                {"place": 0.2, "label": "place"},
            ],
        },
        "index": {"mode": "twist", "length_scale": 1.0},
        "selection": {"norm": "l2"},
        "ik": {"redundancy": "best_branch", "branches": 8, "iterations": 2000, "limit_margin": 0},
    }
    from_dict = graspath.select(graspath.Task.from_dict(document))
    assert from_dict.candidates == selection.candidates


def array_task(task, **settings):
    """``task`` (the left-arm example) rebuilt from its arrays: poses, times, labels, contacts
    and likelihoods, with ``settings`` as keywords."""
    c = task.candidates
    return graspath.Task.from_arrays(
        {"left": task.robot("left")},
        task.object_poses,
        task.candidate_poses,
        times=task.times,
        labels=[x["label"] for x in c],
        contacts=np.array([x["contact"] for x in c]),
        likelihoods=np.array([x["likelihood"] for x in c]),
        **settings,
    )


def test_array_task_equals_the_file(left_selection):
    task, selection = left_selection
    from_arrays = array_task(task, **SAME_IK_AS_THE_FILE)
    assert len(from_arrays) == 21 and from_arrays.arms == ["left"]
    np.testing.assert_array_equal(from_arrays.object_poses, task.object_poses)
    result = graspath.select(from_arrays)
    ignore = {"object_from_wrist"}  # re-orthonormalised on the way in: equal to ~1e-16
    for a, b in zip(result.candidates, selection.candidates):
        np.testing.assert_allclose(a["object_from_wrist"], b["object_from_wrist"], atol=1e-15)
        assert {k: v for k, v in a.items() if k not in ignore} == {k: v for k, v in b.items() if k not in ignore}



def test_array_task_defaults_equal_the_file_defaults(left_selection, tmp_path):
    """Without ``ik.limit_margin`` and ``selection.norm``, a file and ``Task.from_arrays``
    take the same defaults (0.1 rad, ``rms``): the same records, every chosen motion inside
    the narrowed ranges."""
    task, _ = left_selection
    text = LEFT.read_text().replace(", limit_margin: 0", "").replace("selection: { norm: l2 }\n", "")
    assert "limit_margin" not in text and "norm" not in text
    path = tmp_path / "defaults.yaml"
    path.write_text(text)
    from_file = graspath.select(graspath.Task.load(str(path)))
    from_arrays = graspath.select(array_task(task, branches=8, ik_iterations=2000, redundancy="best_branch"))
    assert from_arrays.norm == from_file.norm == "rms"
    for a, b in zip(from_arrays.candidates, from_file.candidates):
        assert a["mu_rms"] == b["mu_rms"] and a["score"] == b["score"]
        if a["feasible"]:
            assert a["limit_distance_min"] >= graspath.DEFAULTS["ik_limit_margin"] - 1e-12


def test_array_task_with_a_moved_base(left_selection):
    """Moving the world frame (object path and arm base together) changes nothing."""
    task, selection = left_selection
    world = np.eye(4)
    angle = 0.4
    world[:3, :3] = [[np.cos(angle), -np.sin(angle), 0], [np.sin(angle), np.cos(angle), 0], [0, 0, 1]]
    world[:3, 3] = [0.3, -1.0, 0.2]
    moved = graspath.Task.from_arrays(
        {"left": (task.robot("left"), world)},
        world @ task.object_poses,
        task.candidate_poses,
        times=task.times,
        **SAME_IK_AS_THE_FILE,
    )
    a = graspath.select(moved).arrays("left")
    b = selection.arrays("left")
    np.testing.assert_array_equal(a["feasible"], b["feasible"])
    np.testing.assert_allclose(a["mu_l2"], b["mu_l2"], rtol=1e-6)


class TestErrors:
    def test_task_file_errors_name_the_field(self, tmp_path):
        bad = tmp_path / "bad.yaml"
        bad.write_text(LEFT.read_text().replace("{ lift: 0.2, label: pick }", "{ lfit: 0.2 }"))
        with pytest.raises(graspath.GraspathError, match=r"field 'trajectory.steps\[0\].lfit'"):
            graspath.Task.load(bad)
        with pytest.raises(graspath.GraspathError, match="cannot read"):
            graspath.Task.load(tmp_path / "missing.yaml")
        with pytest.raises(graspath.GraspathError, match="not valid JSON"):
            graspath.Task.parse("{", "json")

    def test_array_task_errors(self, left_selection):
        task, _ = left_selection
        robot = task.robot("left")
        poses, cands = task.object_poses, task.candidate_poses
        with pytest.raises(graspath.GraspathError, match=r"object_poses has shape \(4, 4\)"):
            graspath.Task.from_arrays({"left": robot}, poses[0], cands)
        with pytest.raises(graspath.GraspathError, match=r"times has shape"):
            graspath.Task.from_arrays({"left": robot}, poses, cands, times=[0.0, 1.0])
        with pytest.raises(graspath.GraspathError, match=r"likelihoods\[0\] must be a positive"):
            graspath.Task.from_arrays({"left": robot}, poses, cands, likelihoods=np.zeros(21))
        with pytest.raises(graspath.GraspathError, match="arm 'left': give a Robot"):
            graspath.Task.from_arrays({"left": "baxter"}, poses, cands)
        with pytest.raises(graspath.GraspathError, match="mode: 'yaw' is not one of twist, translation, rotation"):
            graspath.Task.from_arrays({"left": robot}, poses, cands, mode="yaw")
        with pytest.raises(graspath.GraspathError, match="at least one arm"):
            graspath.Task.from_arrays({}, poses, cands)
        with pytest.raises(graspath.GraspathError, match="unknown arm 'right'"):
            task.with_arms(["right"])
        bent = cands.copy()
        bent[3, :3, :3] *= 1.5
        with pytest.raises(graspath.GraspathError, match=r"candidates\[3\]: the 3×3 rotation block"):
            graspath.Task.from_arrays({"left": robot}, poses, bent)


def test_a_task_in_a_scene_reports_clearance_and_where_candidates_collide(tmp_path):
    # The paper's pick-and-place on a table (the box resting on it) with an approach; and the
    # same with the table top 35 cm above the box, where every candidate reachable in empty
    # space collides with it.
    base = LEFT.read_text()
    on_table = tmp_path / "on_table.yaml"
    on_table.write_text(
        base + "\nscene: { table: { height: -0.15 } }\napproach: { distance: 0.1, samples: 3 }\n"
    )
    selection = graspath.select(graspath.Task.load(on_table))
    arrays = selection.arrays("left")
    feasible = arrays["feasible"]
    assert feasible.any()
    assert np.all(arrays["clearance"][feasible] >= 0.01)
    assert np.all(np.isnan(arrays["clearance"][~feasible]))
    under = tmp_path / "under.yaml"
    under.write_text(base + "\nscene: { table: { height: 0.25 } }\n")
    records = graspath.select(graspath.Task.load(under)).candidates
    free = graspath.select(graspath.Task.load(LEFT)).arrays("left")["feasible"]
    for record, was_feasible in zip(records, free):
        assert not record["feasible"]
        if was_feasible:
            assert record["failure"]["reason"] == "collision"
            assert "table" in record["failure"]["bodies"]
            assert record["failure"]["phase"] in ("approach", "path", "retreat")


def test_array_task_redundancy_matches_the_file(left_selection, tmp_path):
    """``redundancy="optimize"`` from arrays scores as ``ik.redundancy: optimize`` in the
    task file; a name that does not exist, and the earlier keyword ``compare_branches``, are
    refused."""
    task, _ = left_selection
    settings = dict(branches=8, ik_iterations=2000, ik_limit_margin=0.0, norm="l2")
    from_arrays = array_task(task, redundancy="optimize", **settings)
    text = LEFT.read_text().replace(
        "ik: { redundancy: best_branch,", "ik: { redundancy: optimize,"
    )
    assert "redundancy: optimize" in text
    path = tmp_path / "optimize.yaml"
    path.write_text(text)
    from_file = graspath.select(graspath.Task.load(str(path)))
    result = graspath.select(from_arrays)
    for a, b in zip(result.candidates, from_file.candidates):
        assert a["mu_l2"] == b["mu_l2"]
        assert a.get("self_motion") == b.get("self_motion")
    assert any(a.get("self_motion") for a in result.candidates)
    with pytest.raises(ValueError, match="redundancy: 'elbow_up' is not one of first, best_branch, optimize"):
        array_task(task, **settings, redundancy="elbow_up")
    with pytest.raises(TypeError, match="compare_branches"):
        array_task(task, **settings, compare_branches=True)
