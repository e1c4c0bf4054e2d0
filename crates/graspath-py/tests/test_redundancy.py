"""The arm's self-motion from Python: the null space of the Jacobian and the optimiser on a
user's own wrist path, checked against forward kinematics and the Jacobian (numpy)."""

import numpy as np
import pytest

import graspath


@pytest.fixture(scope="module")
def left():
    return graspath.Robot.baxter("left")


def mid_range(robot, n, seed):
    rng = np.random.default_rng(seed)
    return robot.lower + (robot.upper - robot.lower) * (0.25 + 0.5 * rng.random((n, robot.dof)))


def test_the_nullspace_is_orthonormal_and_moves_nothing(left):
    for q in mid_range(left, 5, seed=3):
        basis = left.nullspace(q)
        assert basis.shape == (7, 1)
        np.testing.assert_allclose(basis.T @ basis, np.eye(1), atol=1e-12)
        # J·N = 0 with the Jacobian of the library's other entry point.
        np.testing.assert_allclose(left.jacobian(q) @ basis, 0.0, atol=1e-9)
        # Keeping only the position frees three more directions.
        assert left.nullspace(q, rows="position").shape == (7, 4)
    with pytest.raises(graspath.GraspathError, match="rows"):
        left.nullspace(mid_range(left, 1, seed=1)[0], rows="elbow")
    with pytest.raises(graspath.GraspathError, match="q"):
        left.nullspace(np.full(7, np.nan))


def lift_path(robot):
    """Tip poses of a joint-space sweep between two mid-range configurations: reachable and
    continuous by construction."""
    q0, q1 = mid_range(robot, 2, seed=11)
    q1 = q0 + 0.3 * (q1 - q0)
    return robot.fk(np.linspace(q0, q1, 15))


def skew(w):
    return np.array([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]])


def m_t_along(robot, path, q):
    """M_T per sample from the Jacobian and the tip's motion to the next pose, the twist
    log(T_i⁻¹ T_{i+1}) in the base frame (SE(3) logarithm written out in numpy)."""
    values = []
    for i in range(len(path)):
        a, b = (i, i + 1) if i + 1 < len(path) else (i - 1, i)
        ra = path[a, :3, :3]
        relative = ra.T @ path[b, :3, :3]
        dp = ra.T @ (path[b, :3, 3] - path[a, :3, 3])
        angle = np.arccos(np.clip((np.trace(relative) - 1) / 2, -1, 1))
        if angle < 1e-9:
            w, v = np.zeros(3), dp
        else:
            axis = np.array([relative[2, 1] - relative[1, 2], relative[0, 2] - relative[2, 0], relative[1, 0] - relative[0, 1]])
            w = axis / (2 * np.sin(angle)) * angle
            wx = skew(w)
            v_inverse = np.eye(3) - 0.5 * wx + (1 - angle * np.sin(angle) / (2 * (1 - np.cos(angle)))) / angle**2 * wx @ wx
            v = v_inverse @ dp
        u = np.concatenate([ra @ v, ra @ w])
        u /= np.linalg.norm(u)
        values.append(np.sum((robot.jacobian(q[i]).T @ u) ** 2))
    return np.array(values)


def test_the_optimiser_improves_a_user_path_and_stays_on_it(left):
    path = lift_path(left)
    seed = left.ik_trajectory(path)["branches"][0]
    result = left.optimize_self_motion(path, seed)
    assert result["mu_l2"] > result["mu_l2_seed"]  # a real improvement on this path
    q = result["q"]
    assert q.shape == seed.shape
    # On the targets, inside the limits, within the step bound.
    np.testing.assert_allclose(left.fk(q)[:, :3, 3], path[:, :3, 3], atol=1e-5)
    assert left.within_limits(q).all()
    assert np.abs(np.diff(q, axis=0)).max() <= 0.5 + 1e-12
    # Its M_T is the one numpy computes along the path, and never worse than the seed's.
    np.testing.assert_allclose(result["m_t"], m_t_along(left, path, q), rtol=1e-9)
    seed_l2 = np.sqrt(np.sum(m_t_along(left, path, seed) ** 2))
    assert result["mu_l2_seed"] == pytest.approx(seed_l2, rel=1e-9)
    assert result["mu_l2"] >= seed_l2
    assert result["mu_l2_min"] <= seed_l2
    assert result["mu_l2"] == pytest.approx(np.sqrt(np.sum(result["m_t"] ** 2)), rel=1e-12)


def test_the_optimiser_refuses_a_path_off_its_targets(left):
    path = lift_path(left)
    seed = left.ik_trajectory(path)["branches"][0].copy()
    seed[3] += 0.05
    with pytest.raises(graspath.GraspathError, match=r"q\[3\]"):
        left.optimize_self_motion(path, seed)
    with pytest.raises(graspath.GraspathError, match="shape"):
        left.optimize_self_motion(path, seed[:5])
    with pytest.raises(graspath.GraspathError, match="spacing"):
        left.optimize_self_motion(path, left.ik_trajectory(path)["branches"][0], spacing=0.0)


def test_the_ranked_index_options_match_the_task_file(tmp_path):
    """Task.from_arrays(measure=..., joint_limit_penalty=...) ranks what the task file's
    index.measure / index.joint_limit_penalty rank; the penalised values are M_T times Tsai's
    penalty written out in numpy, and the limit distances are the joints' own."""
    left = graspath.Robot.baxter("left")
    start = np.eye(4)
    start[:3, 3] = [0.75, 0.35, 0.0]
    poses = np.repeat(start[None], 11, axis=0)
    poses[:, 2, 3] += np.linspace(0.0, 0.2, 11)
    candidates = []
    for yaw in np.linspace(-0.6, 0.6, 7):
        c = np.eye(4)
        c[:3, :3] = np.array([[np.cos(yaw), -np.sin(yaw), 0], [np.sin(yaw), np.cos(yaw), 0], [0, 0, 1]]) @ np.diag([1.0, -1.0, -1.0])
        c[2, 3] = 0.05
        candidates.append(c)
    arms = {"left": left}
    # One tracked branch, so that both tasks follow the same motion (the default self-motion
    # search would move the elbow towards what each index ranks).
    plain = graspath.select(
        graspath.Task.from_arrays(arms, poses, np.array(candidates), redundancy="first")
    ).arrays("left")
    k = 20.0
    penalised = graspath.select(
        graspath.Task.from_arrays(
            arms, poses, np.array(candidates), joint_limit_penalty=k, redundancy="first"
        )
    )
    values = penalised.arrays("left")
    assert values["feasible"].any()
    lower, upper = left.lower, left.upper
    for row in np.flatnonzero(values["feasible"]):
        q = penalised.joint_trajectory("left", int(row))
        product = np.prod((q - lower) * (upper - q) / (upper - lower) ** 2, axis=1)
        expected = plain["m_t"][row] * (1.0 - np.exp(-k * product))
        np.testing.assert_allclose(values["ranked_index"][row], expected, rtol=1e-9, equal_nan=True)
        nearest = np.min(np.minimum(q - lower, upper - q))
        assert values["limit_distance_min"][row] == pytest.approx(nearest, abs=0)
    np.testing.assert_array_equal(plain["ranked_index"], plain["m_t"])
    np.testing.assert_array_equal(values["yoshikawa_at_grasp"], plain["yoshikawa_at_grasp"])
    assert (values["yoshikawa_penalized_at_grasp"][values["feasible"]] < values["yoshikawa_at_grasp"][values["feasible"]]).all()
    with pytest.raises(graspath.GraspathError, match="measure"):
        graspath.Task.from_arrays(arms, poses, np.array(candidates), measure="yoshikawa")
    with pytest.raises(graspath.GraspathError, match="joint_limit_penalty"):
        graspath.Task.from_arrays(arms, poses, np.array(candidates), joint_limit_penalty=-1.0)
