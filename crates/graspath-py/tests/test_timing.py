"""Timing against toppra (PyPI), live: ``graspath.time_path`` on random joint paths with
velocity and acceleration limits equals ``toppra.algorithm.TOPPRA`` on the same natural cubic
spline, chord-length knots and grid, for both discretisations; and the selected motions of a
task (``Selection.timed_motions``) checked against their limits and the written files.

toppra is installed by CI (``.ci/run``); elsewhere the comparison skips when it is missing.
The torque limits are compared with toppra in the Rust tests (``tests/timing_toppra.rs``,
with Pinocchio's inverse dynamics)."""

import json
from pathlib import Path

import numpy as np
import pytest

import graspath
from conftest import require

REPO = Path(__file__).resolve().parents[3]
LEFT = REPO / "examples" / "pick_and_place_left.yaml"


def toppra_or_skip():
    return require("toppra", "pip install toppra")


def random_path(rng, n, dof):
    """A smooth random joint path: a line plus two sine harmonics."""
    t = np.linspace(0.0, 1.0, n)[:, None]
    start, end = rng.uniform(-1.5, 1.5, dof), rng.uniform(-1.5, 1.5, dof)
    wiggle = rng.uniform(-0.3, 0.3, (2, dof))
    return start + (end - start) * t + wiggle[0] * np.sin(np.pi * t) + wiggle[1] * np.sin(3 * np.pi * t)


@pytest.mark.parametrize("scheme", ["collocation", "interpolation"])
def test_durations_equal_toppra(scheme):
    toppra = toppra_or_skip()
    rng = np.random.default_rng(32)
    kind = {
        "collocation": toppra.constraint.DiscretizationType.Collocation,
        "interpolation": toppra.constraint.DiscretizationType.Interpolation,
    }[scheme]
    for case in range(8):
        dof = int(rng.integers(2, 8))
        n = int(rng.integers(5, 60))
        samples = random_path(rng, n, dof)
        velocity = rng.uniform(0.5, 3.0, dof)
        acceleration = rng.uniform(2.0, 20.0, dof)
        ours = graspath.time_path(
            samples, velocity, acceleration, subdivisions=2, discretization=scheme,
            check_between=False,
        )
        knots = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(samples, axis=0), axis=1))])
        np.testing.assert_allclose(ours["knots"], knots, rtol=1e-12, atol=1e-12)
        grid = np.sort(np.concatenate([knots, 0.5 * (knots[:-1] + knots[1:])]))
        np.testing.assert_allclose(ours["grid"], grid, rtol=1e-12, atol=1e-12)
        path = toppra.SplineInterpolator(knots, samples, bc_type="natural")
        constraints = [
            toppra.constraint.JointVelocityConstraint(velocity),
            toppra.constraint.JointAccelerationConstraint(acceleration, discretization_scheme=kind),
        ]
        algorithm = toppra.algorithm.TOPPRA(
            constraints, path, gridpoints=grid, parametrizer="ParametrizeConstAccel"
        )
        trajectory = algorithm.compute_trajectory(0, 0)
        assert trajectory is not None, case
        # Where a path must almost stop at a grid point, ṡ² is 0 in one solver and ~1e-8 in
        # the other (toppra lowers each step by a safety margin and rounds its velocity bound
        # to single precision), and the time 2Δ/(ṡ_i + ṡ_{i+1}) near there moves by up to
        # 5e-4 relative; elsewhere the two agree to 1e-8. The bound is 1 %.
        assert ours["duration"] == pytest.approx(trajectory.duration, rel=1e-3), case
        # The check between grid points only ever slows the motion down.
        checked = graspath.time_path(samples, velocity, acceleration, discretization=scheme)
        assert checked["slowdown"] >= 1.0
        assert checked["duration"] == pytest.approx(ours["duration"] * checked["slowdown"], rel=1e-12)


def test_one_joint_takes_the_trapezoids_time():
    # 2 rad at 1 rad/s and 2 rad/s²: 0.5 s up, 1.5 s cruise, 0.5 s down.
    samples = np.linspace(0.0, 2.0, 801)[:, None]
    timed = graspath.time_path(samples, [1.0], [2.0], check_between=False)
    assert timed["duration"] == pytest.approx(2.5, rel=2e-3)


def test_bad_inputs_are_refused():
    with pytest.raises(graspath.GraspathError, match="samples has shape"):
        graspath.time_path(np.zeros(3), [1.0], [1.0])
    with pytest.raises(graspath.GraspathError, match="velocity_limits has shape"):
        graspath.time_path(np.zeros((3, 2)), [1.0], [1.0, 1.0])
    with pytest.raises(graspath.GraspathError, match="not a positive number"):
        graspath.time_path(np.array([[0.0], [1.0]]), [-1.0], [1.0])
    with pytest.raises(graspath.GraspathError, match="discretization"):
        graspath.time_path(np.array([[0.0], [1.0]]), [1.0], [1.0], discretization="euler")
    with pytest.raises(graspath.GraspathError, match="not a finite number"):
        graspath.time_path(np.array([[0.0], [np.nan]]), [1.0], [1.0])


def test_the_selected_motion_is_timed_within_its_limits(tmp_path):
    task = graspath.Task.load(LEFT)
    selection = graspath.select(task)
    arrays = selection.arrays("left")
    best = selection.best("left")
    row = int(np.flatnonzero(arrays["id"] == best)[0])
    (motion,) = selection.timed_motions(period=0.005)
    assert motion["candidate"] == best
    assert motion["duration"] == pytest.approx(arrays["duration"][row], rel=1e-12)
    n = motion["time"].shape[0]
    assert motion["positions"].shape == motion["velocities"].shape == (n, 7)
    assert np.all(np.diff(motion["time"]) > 0)
    np.testing.assert_allclose(motion["velocities"][[0, -1]], 0.0, atol=1e-9)
    # Baxter: 1.5 rad/s (shoulder, elbow), 4 rad/s (wrist); accelerations over 0.5 s.
    velocity = np.array([1.5] * 4 + [4.0] * 3)
    assert np.all(np.abs(motion["velocities"]) <= velocity * 1.005)
    assert np.all(np.abs(motion["accelerations"]) <= velocity / 0.5 * 1.005)
    # The same motion written by Selection.write, at the same period.
    written = selection.write(tmp_path / "out", trajectory_period=0.005)
    assert {p.name for p in written} >= {"trajectory.json", "trajectory-left.csv"}
    document = json.loads((tmp_path / "out" / "trajectory.json").read_text())
    points = document["arms"][0]["trajectory"]["points"]
    assert len(points) == n
    np.testing.assert_array_equal(
        np.array([p["positions"] for p in points]), motion["positions"]
    )
    stamp = points[-1]["time_from_start"]
    assert stamp["sec"] + stamp["nanosec"] * 1e-9 == pytest.approx(motion["time"][-1], abs=1e-9)
