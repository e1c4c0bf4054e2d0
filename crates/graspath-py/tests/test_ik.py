"""Inverse kinematics: solutions reach their targets (checked with FK), stay in the limits,
batch = one at a time, trajectories are continuous, failures and bad input are reported."""

import numpy as np
import pytest

import graspath

EXACT = dict(max_time=None)  # iteration budgets only: reproducible


@pytest.fixture(scope="module")
def left():
    return graspath.Robot.baxter("left")


def targets(robot, n, seed=5):
    rng = np.random.default_rng(seed)
    q = robot.lower + (robot.upper - robot.lower) * (0.15 + 0.7 * rng.random((n, robot.dof)))
    return robot.fk(q)


def rotation_angle(a, b):
    r = a[:3, :3].T @ b[:3, :3]
    return np.arccos(np.clip((np.trace(r) - 1) / 2, -1, 1))


def test_single_pose_reaches_the_target(left):
    target = targets(left, 1)[0]
    result = left.ik(target, **EXACT)
    assert result["converged"] and result["failure"] is None
    q = result["q"]
    assert q.shape == (7,) and q.dtype == np.float64
    assert left.within_limits(q)
    reached = left.fk(q)
    assert np.linalg.norm(reached[:3, 3] - target[:3, 3]) <= 1e-5
    assert rotation_angle(reached, target) <= 1e-5
    assert result["position_error"] <= 1e-5 and result["iterations"] >= 1


def test_batch_equals_one_at_a_time(left):
    goals = targets(left, 24)
    batch = left.ik(goals, random_seed=3, **EXACT)
    assert batch["q"].shape == (24, 7) and batch["converged"].dtype == np.bool_
    assert batch["iterations"].dtype == np.int64
    assert batch["converged"].all()
    for i in range(24):
        one = left.ik(goals[i], random_seed=3, **EXACT)
        np.testing.assert_array_equal(one["q"], batch["q"][i])
        assert one["iterations"] == batch["iterations"][i]
        assert one["position_error"] == batch["position_error"][i]
    # Per-pose start configurations equal to the shared one give the same answers.
    starts = np.tile(left.mid_configuration(), (24, 1))
    again = left.ik(goals, starts, random_seed=3, **EXACT)
    np.testing.assert_array_equal(again["q"], batch["q"])


def test_unreachable_target_is_a_result_not_an_error(left):
    far = np.eye(4)
    far[:3, 3] = [5.0, 0.0, 0.0]
    result = left.ik(far, **EXACT)
    assert not result["converged"] and result["q"] is None
    assert result["failure"]["reason"] == "unreachable"
    assert left.within_limits(result["failure"]["best_q"])
    batch = left.ik(np.stack([far, targets(left, 1)[0]]), **EXACT)
    assert batch["converged"].tolist() == [False, True]
    assert np.isnan(batch["q"][0]).all() and not np.isnan(batch["best_q"][0]).any()
    assert batch["failure_reason"] == ["unreachable", None]


def test_trajectory_is_continuous_and_on_target(left):
    start = targets(left, 1, seed=9)[0]
    path = np.repeat(start[None], 20, axis=0)
    path[:, 2, 3] += np.linspace(0.0, 0.1, 20)  # a 10 cm lift
    result = left.ik_trajectory(path)
    assert result["feasible"] and result["failure"] is None
    for branch in result["branches"]:
        assert branch.shape == (20, 7)
        assert np.abs(np.diff(branch, axis=0)).max() <= 0.5
        reached = left.fk(branch)
        np.testing.assert_allclose(reached[:, :3, 3], path[:, :3, 3], atol=1e-5)
    assert result == result  # plain Python objects
    again = left.ik_trajectory(path)
    for a, b in zip(result["branches"], again["branches"]):
        np.testing.assert_array_equal(a, b)


def test_infeasible_trajectory_names_the_sample(left):
    start = targets(left, 1, seed=9)[0]
    path = np.repeat(start[None], 10, axis=0)
    path[:, 0, 3] += np.linspace(0.0, 3.0, 10)  # leaves the workspace
    result = left.ik_trajectory(path)
    assert not result["feasible"] and result["branches"] == []
    failure = result["failure"]
    assert failure["sample"] > 0 and failure["reason"] in ("unreachable", "joint_limit", "discontinuity")
    assert isinstance(failure["detail"], str) and failure["detail"]



def test_a_batch_of_trajectories_gives_each_what_it_gives_alone(left):
    """``(b, n, 4, 4)`` targets: a list of dicts, each equal (to the last bit) to the call with
    that trajectory alone; feasible and infeasible ones mixed, one and several branches."""
    paths = []
    for k, seed in enumerate((9, 3, 14, 5)):
        start = targets(left, 1, seed=seed)[0]
        path = np.repeat(start[None], 15, axis=0)
        path[:, 2, 3] += np.linspace(0.0, 0.08, 15)
        if k == 2:
            path[:, 0, 3] += np.linspace(0.0, 3.0, 15)  # leaves the workspace
        paths.append(path)
    batch = np.stack(paths)
    for branches in (1, 3):
        together = left.ik_trajectory(batch, branches=branches)
        assert isinstance(together, list) and len(together) == len(paths)
        assert [r["feasible"] for r in together].count(False) >= 1
        assert [r["feasible"] for r in together].count(True) >= 2
        for path, got in zip(paths, together):
            alone = left.ik_trajectory(path, branches=branches)
            assert got["feasible"] == alone["feasible"] and got["failure"] == alone["failure"]
            assert len(got["branches"]) == len(alone["branches"])
            for a, b in zip(got["branches"], alone["branches"]):
                assert a.tobytes() == b.tobytes()
    assert left.ik_trajectory(np.zeros((0, 5, 4, 4))) == []
    bad = batch.copy()
    bad[1, 3, 3] = [0, 0, 1, 1]
    with pytest.raises(graspath.GraspathError, match=r"targets\[1, 3\]: the last row must be \[0, 0, 0, 1\]"):
        left.ik_trajectory(bad)
    with pytest.raises(graspath.GraspathError, match=r"targets\[0\]: trajectory: not a valid pose"):
        left.ik_trajectory(np.zeros((2, 0, 4, 4)))
    with pytest.raises(graspath.GraspathError, match=r"\(n, 4, 4\), \(4, 4\) or \(b, n, 4, 4\)"):
        left.ik_trajectory(np.zeros((2, 3, 3)))


class TestErrors:
    def test_bad_pose(self, left):
        bad = np.eye(4)
        bad[:3, :3] *= 2
        with pytest.raises(graspath.GraspathError, match="target: the 3×3 rotation block is not orthonormal"):
            left.ik(bad)
        many = np.stack([np.eye(4), np.eye(4)])
        many[1, 3] = [0, 0, 1, 1]
        with pytest.raises(graspath.GraspathError, match=r"target\[1\]: the last row must be \[0, 0, 0, 1\]"):
            left.ik(many)
        with pytest.raises(graspath.GraspathError, match=r"\(4, 4\) or \(n, 4, 4\)"):
            left.ik(np.eye(3))

    def test_bad_start_and_options(self, left):
        with pytest.raises(graspath.GraspathError, match=r"q_start has shape \(3,\)"):
            left.ik(np.eye(4), np.zeros(3))
        with pytest.raises(graspath.GraspathError, match="q_start has 2 rows but there are 3"):
            left.ik(np.stack([np.eye(4)] * 3), np.zeros((2, 7)))
        with pytest.raises(graspath.GraspathError, match="option 'position_tolerance'"):
            left.ik(np.eye(4), position_tolerance=0.0)
        with pytest.raises(graspath.GraspathError, match="accepts almost any pose"):
            left.ik(np.eye(4), position_tolerance=1e308)
        for bad in (-1.0, 0.0, float("nan"), float("inf"), 1e300):
            with pytest.raises(graspath.GraspathError, match="max_time"):
                left.ik(np.eye(4), max_time=bad)
        with pytest.raises(graspath.GraspathError, match="option 'max_joint_step'"):
            left.ik_trajectory(np.stack([np.eye(4)] * 2), max_joint_step=0.0)
        with pytest.raises(graspath.GraspathError, match="trajectory: not a valid pose"):
            left.ik_trajectory(np.zeros((0, 4, 4)))


def test_narrowed_joint_limits_hold_for_ik(left):
    """A narrowed range (``Robot.with_joint_limits``) is the range IK keeps to; a range
    outside the joint's own is refused with the joint's name."""
    name = left.joint_names[3]
    lower, upper = left.lower[3], left.upper[3]
    narrow = left.with_joint_limits({name: (lower + 0.25 * (upper - lower), upper)})
    assert narrow.lower[3] == lower + 0.25 * (upper - lower) and narrow.upper[3] == upper
    assert np.array_equal(np.delete(narrow.lower, 3), np.delete(left.lower, 3))
    for target in targets(narrow, 6, seed=11):
        result = narrow.ik(target, **EXACT)
        if result["converged"]:
            assert narrow.within_limits(result["q"])
    with pytest.raises(graspath.GraspathError, match=name):
        left.with_joint_limits({name: (lower - 0.1, upper)})
    with pytest.raises(graspath.GraspathError, match="not a range"):
        left.with_joint_limits({name: (0.5, 0.5)})
