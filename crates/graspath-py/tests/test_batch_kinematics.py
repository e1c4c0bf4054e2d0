"""Batch kinematics calls written in place in parallel: bit-identical to one call per
configuration at 1 and several threads (RAYON_NUM_THREADS in subprocesses), new arrays equal to
`out=` arrays, any input layout (Fortran order, strided views) read by its strides, and the
Panda's poses and Jacobians against an independent numpy evaluation of its published joint
origins."""

import math
import os
import subprocess
import sys

import numpy as np
import pytest

import graspath

RNG = np.random.default_rng(37)

# The Panda's joint origins (xyz m, rpy rad) from franka_description: joints 1-7, flange,
# hand, TCP; every joint turns about its own z.
PANDA_ORIGINS = [
    ((0.0, 0.0, 0.333), (0.0, 0.0, 0.0)),
    ((0.0, 0.0, 0.0), (-math.pi / 2, 0.0, 0.0)),
    ((0.0, -0.316, 0.0), (math.pi / 2, 0.0, 0.0)),
    ((0.0825, 0.0, 0.0), (math.pi / 2, 0.0, 0.0)),
    ((-0.0825, 0.384, 0.0), (-math.pi / 2, 0.0, 0.0)),
    ((0.0, 0.0, 0.0), (math.pi / 2, 0.0, 0.0)),
    ((0.088, 0.0, 0.0), (math.pi / 2, 0.0, 0.0)),
    ((0.0, 0.0, 0.107), (0.0, 0.0, 0.0)),
    ((0.0, 0.0, 0.0), (0.0, 0.0, -math.pi / 4)),
    ((0.0, 0.0, 0.1034), (0.0, 0.0, 0.0)),
]


def transform(xyz, rpy, angle=0.0):
    """The homogeneous transform of a URDF origin followed by a turn `angle` about z."""
    (r, p, y), c = rpy, np.cos
    rx = np.array([[1, 0, 0], [0, c(r), -np.sin(r)], [0, np.sin(r), c(r)]])
    ry = np.array([[c(p), 0, np.sin(p)], [0, 1, 0], [-np.sin(p), 0, c(p)]])
    rz = np.array([[c(y), -np.sin(y), 0], [np.sin(y), c(y), 0], [0, 0, 1]])
    turn = np.array([[c(angle), -np.sin(angle), 0], [np.sin(angle), c(angle), 0], [0, 0, 1]])
    m = np.eye(4)
    m[:3, :3] = rz @ ry @ rx @ turn
    m[:3, 3] = xyz
    return m


def panda_oracle(q):
    """Pose and geometric Jacobian (base frame, rows [v; ω]) of one Panda configuration."""
    m = np.eye(4)
    axes, origins = [], []
    for i, (xyz, rpy) in enumerate(PANDA_ORIGINS):
        m = m @ transform(xyz, rpy, q[i] if i < 7 else 0.0)
        if i < 7:
            axes.append(m[:3, 2].copy())
            origins.append(m[:3, 3].copy())
    jacobian = np.zeros((6, 7))
    for i, (z, p) in enumerate(zip(axes, origins)):
        jacobian[:3, i] = np.cross(z, m[:3, 3] - p)
        jacobian[3:, i] = z
    return m, jacobian


@pytest.fixture(scope="module")
def panda():
    return graspath.Robot.builtin("panda")


def configurations(robot, n):
    return robot.lower + (robot.upper - robot.lower) * RNG.random((n, robot.dof))


def test_panda_batch_equals_an_independent_evaluation(panda):
    q = configurations(panda, 300)
    poses, jacobians = panda.fk_jacobian(q)
    for i in range(0, 300, 13):
        pose, jacobian = panda_oracle(q[i])
        np.testing.assert_allclose(poses[i], pose, rtol=0, atol=1e-12)
        np.testing.assert_allclose(jacobians[i], jacobian, rtol=0, atol=1e-12)


# Run in a subprocess with RAYON_NUM_THREADS set: writes every batch result of one input.
THREADED = """
import sys, numpy as np, graspath
robot = graspath.Robot.builtin(sys.argv[1])
q = np.load(sys.argv[2])
u = np.load(sys.argv[3])
poses, jacobians = robot.fk_jacobian(q)
p_out, j_out = np.full_like(poses, np.nan), np.full_like(jacobians, np.nan)
robot.fk_jacobian(q, out=(p_out, j_out))
indices = robot.indices(q, part="translation")
np.savez(
    sys.argv[4],
    poses=poses, jacobians=jacobians, p_out=p_out, j_out=j_out,
    fk=robot.fk(q), jacobian=robot.jacobian(q),
    fk_out=robot.fk(q, out=np.empty_like(poses)), jacobian_out=robot.jacobian(q, out=np.empty_like(jacobians)),
    yoshikawa=indices["yoshikawa"], singular_values=indices["singular_values"],
    inverse_condition=indices["inverse_condition"],
    task_relevant=robot.task_relevant(q, u), ratio=robot.velocity_transmission_ratio(q, u),
    within=robot.within_limits(q),
)
"""


def run_threaded(tmp_path, robot_name, q, u, threads):
    np.save(tmp_path / "q.npy", q)
    np.save(tmp_path / "u.npy", u)
    out = tmp_path / f"out{threads}.npz"
    env = dict(os.environ, RAYON_NUM_THREADS=str(threads))
    subprocess.run(
        [sys.executable, "-c", THREADED, robot_name, tmp_path / "q.npy", tmp_path / "u.npy", out],
        check=True,
        env=env,
    )
    return dict(np.load(out))


@pytest.mark.parametrize("robot_name", ["panda", "baxter"])
def test_bit_identical_to_single_calls_at_one_and_several_threads(tmp_path, robot_name):
    robot = graspath.Robot.builtin(robot_name)
    # Several parallel tasks (256 configurations each), the last not a whole lane group; a few
    # configurations outside the limits for within_limits.
    n = 5 * 256 + 3
    q = configurations(robot, n)
    q[::97] += 0.5
    u = RNG.normal(size=(n, 6))
    one, three = (run_threaded(tmp_path, robot_name, q, u, t) for t in (1, 3))
    for name in one:
        np.testing.assert_array_equal(one[name], three[name], err_msg=name)
    for name, out_name in [("poses", "p_out"), ("jacobians", "j_out"), ("poses", "fk"),
                           ("jacobians", "jacobian"), ("poses", "fk_out"), ("jacobians", "jacobian_out")]:
        np.testing.assert_array_equal(one[name], one[out_name], err_msg=out_name)
    for i in list(range(0, n, 61)) + [n - 1]:
        pose, jacobian = robot.fk_jacobian(q[i])
        np.testing.assert_array_equal(one["poses"][i], pose)
        np.testing.assert_array_equal(one["jacobians"][i], jacobian)
        indices = robot.indices(q[i], part="translation")
        assert one["yoshikawa"][i] == indices["yoshikawa"]
        assert one["inverse_condition"][i] == indices["inverse_condition"]
        np.testing.assert_array_equal(one["singular_values"][i], indices["singular_values"])
        assert one["task_relevant"][i] == robot.task_relevant(q[i], u[i])
        assert one["ratio"][i] == robot.velocity_transmission_ratio(q[i], u[i])
        assert one["within"][i] == robot.within_limits(q[i])
    inside = np.all((q >= robot.lower) & (q <= robot.upper), axis=1)
    np.testing.assert_array_equal(one["within"], inside)
    assert not inside.all() and inside.any()


def test_batch_ik_equals_single_calls(panda):
    q = configurations(panda, 24)
    targets = panda.fk(q)
    options = dict(max_time=None, max_iterations=3000)
    batch = panda.ik(targets, q_start=panda.mid_configuration(), **options)
    for i in range(0, 24, 5):
        one = panda.ik(targets[i], q_start=panda.mid_configuration(), **options)
        assert batch["converged"][i] == one["converged"]
        assert batch["iterations"][i] == one["iterations"]
        assert batch["position_error"][i] == one["position_error"]
        if one["converged"]:
            np.testing.assert_array_equal(batch["q"][i], one["q"])
            np.testing.assert_array_equal(batch["best_q"][i], one["q"])
            assert batch["failure_reason"][i] is None
        else:
            assert np.isnan(batch["q"][i]).all()
            np.testing.assert_array_equal(batch["best_q"][i], one["failure"]["best_q"])
            assert batch["failure_reason"][i] == one["failure"]["reason"]
    assert batch["converged"].any()
    # Fortran-ordered targets are the same poses.
    again = panda.ik(np.asfortranarray(targets), q_start=panda.mid_configuration(), **options)
    np.testing.assert_array_equal(again["q"], batch["q"])


def layouts(q):
    """The same configurations in other memory layouts."""
    wide = np.zeros((q.shape[0] * 2, q.shape[1] * 3))
    wide[::2, ::3] = q
    reversed_rows = np.ascontiguousarray(q[::-1])[::-1]
    return {
        "fortran": np.asfortranarray(q),
        "strided": wide[::2, ::3],
        "negative strides": reversed_rows,
        "transposed": np.ascontiguousarray(q.T).T,
    }


def test_any_input_layout_is_read_through_its_strides(panda):
    q = configurations(panda, 300)
    poses, jacobians = panda.fk_jacobian(q)
    u = RNG.normal(size=(300, 3))
    indices = panda.indices(q)
    relevant = panda.task_relevant(q, u, part="translation")
    for name, view in layouts(q).items():
        assert not view.flags["C_CONTIGUOUS"], name
        p, j = panda.fk_jacobian(view)
        np.testing.assert_array_equal(p, poses, err_msg=name)
        np.testing.assert_array_equal(j, jacobians, err_msg=name)
        np.testing.assert_array_equal(panda.fk(view), poses, err_msg=name)
        np.testing.assert_array_equal(panda.jacobian(view), jacobians, err_msg=name)
        np.testing.assert_array_equal(panda.indices(view)["singular_values"], indices["singular_values"])
        np.testing.assert_array_equal(panda.within_limits(view), panda.within_limits(q))
        np.testing.assert_array_equal(
            panda.task_relevant(view, np.asfortranarray(u), part="translation"), relevant, err_msg=name
        )


def test_out_arrays_of_other_layouts_are_refused_and_errors_name_the_value(panda):
    q = configurations(panda, 1000)
    with pytest.raises(graspath.GraspathError, match="C-contiguous"):
        panda.fk(q, out=np.asfortranarray(np.empty((1000, 4, 4))))
    with pytest.raises(graspath.GraspathError, match="C-contiguous"):
        panda.jacobian(q, out=np.empty((1000, 6, 14))[:, :, ::2])
    read_only = np.empty((1000, 4, 4))
    read_only.flags.writeable = False
    with pytest.raises(graspath.GraspathError, match="cannot be written"):
        panda.fk(q, out=read_only)
    # Non-finite values in different parallel tasks: the first is named, with new arrays and
    # with out= arrays, for every call.
    q[700, 2] = np.inf
    q[300, 5] = np.nan
    p, j = np.empty((1000, 4, 4)), np.empty((1000, 6, 7))
    for call in (
        lambda: panda.fk_jacobian(q),
        lambda: panda.fk_jacobian(q, out=(p, j)),
        lambda: panda.fk(q),
        lambda: panda.jacobian(q, out=j),
        lambda: panda.fk_jacobian(np.asfortranarray(q)),
        lambda: panda.indices(q),
        lambda: panda.within_limits(q),
    ):
        with pytest.raises(graspath.GraspathError, match=r"q\[300, 5\] is not a finite number"):
            call()
    with pytest.raises(graspath.GraspathError, match=r"q\[5\] is not a finite number"):
        panda.fk(q[300])


def test_jacobian_out_is_written_in_place_and_single_results_keep_their_types(panda):
    q = configurations(panda, 50)
    out = np.full((50, 6, 7), np.nan)
    assert panda.jacobian(q, out=out) is out
    np.testing.assert_array_equal(out, panda.fk_jacobian(q)[1])
    assert panda.within_limits(q[0]) is True
    assert isinstance(panda.task_relevant(q[0], [1.0, 0, 0, 0, 0, 0]), float)
    one = panda.indices(q[0])
    assert isinstance(one["yoshikawa"], float) and one["singular_values"].shape == (6,)
    empty = panda.indices(np.zeros((0, 7)))
    assert empty["yoshikawa"].shape == (0,) and empty["singular_values"].shape == (0, 6)
    assert panda.within_limits(np.zeros((0, 7))).shape == (0,)
    assert panda.fk_jacobian(np.zeros((0, 7)))[1].shape == (0, 6, 7)


def test_large_results_reuse_freed_memory_and_every_value_is_rewritten(panda):
    default = graspath.result_cache()["max_bytes"]
    assert default == 1 << 30
    n = 20_000  # 2.6 MB of poses, 6.7 MB of Jacobians: both from the cache
    q = configurations(panda, n)
    poses, jacobians = panda.fk_jacobian(q)
    del poses, jacobians
    held = graspath.result_cache()
    assert held["buffers"] >= 2 and held["bytes"] >= n * (16 + 42) * 8
    other = configurations(panda, n)
    poses, jacobians = panda.fk_jacobian(other)  # in the freed buffers
    assert graspath.result_cache()["bytes"] <= held["bytes"] - n * (16 + 42) * 8
    p_out, j_out = np.empty_like(poses), np.empty_like(jacobians)
    panda.fk_jacobian(other, out=(p_out, j_out))
    np.testing.assert_array_equal(poses, p_out)
    np.testing.assert_array_equal(jacobians, j_out)
    # A view keeps its buffer: nothing else is written into it while the view lives.
    view = poses[n - 3 :]
    del poses
    again = panda.fk(q)
    np.testing.assert_array_equal(view, p_out[n - 3 :])
    np.testing.assert_array_equal(again, panda.fk(q, out=np.empty((n, 4, 4))))
    indices = panda.indices(q[:5000])
    np.testing.assert_array_equal(indices["yoshikawa"], [panda.indices(qi)["yoshikawa"] for qi in q[:5000]])
    assert graspath.result_cache(max_bytes=0) == {"max_bytes": 0, "bytes": 0, "buffers": 0}
    del view, again
    assert graspath.result_cache()["bytes"] == 0
    np.testing.assert_array_equal(panda.fk_jacobian(other)[1], j_out)
    graspath.result_cache(max_bytes=default)
