"""Reference time-optimal path parameterisations for the timing tests: toppra's TOPP-RA on
smooth random joint paths of example-robot-data's Panda, UR5 and Baxter arm chains, under joint
velocity, joint acceleration and (in half of the cases) joint torque limits.

Each chain is Pinocchio's model of the whole URDF reduced to the joints between the chain's
base and tip, as in ../dynamics/pinocchio_reference.py (every other joint locked at zero;
gravity 9.81 m/s² along the root link's -z, recorded in the chain's base frame). One Panda case
carries a payload, appended as a body at the tip frame (tip_from_tool = identity, so its com
and its inertia about the com are in the tip frame).

The problem of each case:
* waypoints q_0 .. q_{n-1} (n x dof, rad); knots by chord length, s_0 = 0,
  s_{i+1} = s_i + |q_{i+1} - q_i|_2; the path q(s) is the natural cubic spline through them
  (toppra.SplineInterpolator(knots, waypoints, bc_type="natural") is scipy's
  CubicSpline(knots, waypoints, bc_type="natural"), its derivatives taken with .derivative();
  spline_check records its values, checked against scipy's own to 1e-12);
* the grid: the knots and the midpoint of every knot interval (2n - 1 points);
* |qd_j| <= velocity_limits[j] (the URDF's), |qdd_j| <= acceleration_limits[j] and, when
  torque_limits is not null, |tau_j| <= torque_limits[j] with tau = rnea(q, qd, qdd) of the
  reduced model (with the payload when there is one; no friction);
* rest to rest: sd = 0 at both ends.
It is solved by toppra.algorithm.TOPPRA (seidel solver wrapper, every constraint with
collocation, ParametrizeConstAccel). Recorded: the squared path velocity x_i = sd_i² at every
grid point (sd_squared), the controllable sets K_i = [lower, upper] of the backward pass
(controllable_sets) and the trajectory's duration. Every torque case is drawn so that the torque
limits lengthen the motion (toppra without them is faster); infeasible draws are redrawn.

What toppra 0.6.10 does (from its source; the script replays it, see `replay`), which a
reimplementation has to match to agree with it to 1e-6 relative:
* Discretisation: collocation at the grid points only, for every constraint. Stage i
  (0 <= i < N, N = 2n - 2) constrains (u_i, x_i), u_i the constant path acceleration on
  [s_i, s_{i+1}] (x_{i+1} = x_i + 2 Δ_i u_i, Δ_i = s_{i+1} - s_i), with
    velocity:      0 <= x_i <= (min_j v_j / |q'_j(s_i)|)²  (joints with q'_j(s_i) = 0 skipped,
                   min capped at 1e8). toppra computes this in single precision: the bound is
                   float32(float32(min_j v_j / |q'_j|)²) (C floats in
                   _CythonUtils._create_velocity_constraint), up to ~1.5e-7 relative below or
                   above the double value;
    acceleration:  |q'(s_i) u_i + q''(s_i) x_i| <= a;
    torque:        |a(s_i) u_i + b(s_i) x_i + c(s_i)| <= tau_lim with c = rnea(q, 0, 0),
                   a = rnea(q, 0, q') - c and b = rnea(q, q', q'') - c at q = q(s_i).
  The constraints at the last grid point s_N are never used: the backward pass starts from
  K_N = [sd_end², sd_end²] = [0, 0] and the forward pass solves stages 0 .. N-1 only. Those at
  s_0 apply (to u_0, with x_0 = 0).
* Backward pass: for i = N-1 .. 0, K_i = [min x, max x] over the (u, x) feasible at stage i
  with K_{i+1,0} <= x + 2 Δ_i u <= K_{i+1,1} and |u| <= 1e8 (a 2-D LP, Seidel's algorithm; its
  objective carries a 1e-9 u tie-break that does not change the optimal x; it accepts a
  constraint violated by less than 1e-10, absolute). A negative lower end is set to 0; where the
  exact lower end is 0 toppra can return a rounding residue (~1e-15) instead. An infeasible LP
  (NaN) fails the whole problem.
* Forward pass: x_0 = sd_start² = 0 (it must lie in K_0 to 1e-5). For i = 0 .. N-1, u_i is
  the largest u with stage i's constraints at x = x_i and x_i + 2 Δ_i u in K_{i+1} (a 1-D LP;
  rows whose u coefficient has magnitude <= 1e-10 are left out), then
      y = x_i + 2 Δ_i u_i,  x_{i+1} = clamp(max(y - 1e-8, 0.9999 y), K_{i+1,0}, K_{i+1,1}),
  i.e. toppra lowers every step by 1e-8 (by 0.01 % below y = 1e-4) to stay inside the next
  controllable set despite rounding. Left out, x differs by ~1e-8 absolute per step, so most in
  relative terms where x is small (near the ends: up to 7e-6 relative in the draws tried), the
  duration by 1e-9 to 3e-8. When the 1-D LP is infeasible toppra lowers x_i by the same rule
  (0.999 instead of 0.9999) and retries, at most 10 times; no case here does. x_N = 0 as
  K_N = [0, 0]; sd_i = sqrt(x_i).
* Duration: ParametrizeConstAccel holds the path acceleration constant on each grid interval,
  so the duration is Σ_{i<N} 2 Δ_i / (sd_i + sd_{i+1}) (asserted below from sd_squared to 1e-9).
With these rules (and exact 2-D LPs) the replay reproduces toppra's K and x to ~1e-14 relative;
with a double-precision velocity bound instead, K and x differ by up to ~1.6e-7 relative and the
duration by up to ~1e-8.

Run (writes toppra_timing.json beside this file):
    target/pyenv/bin/pip install pin example-robot-data toppra==0.6.10
    target/pyenv/bin/python crates/graspath/tests/data/timing/toppra_reference.py
"""

import json
import os
import sys
from importlib.metadata import version

import numpy as np
import pinocchio as pin
import scipy
import toppra
import toppra.algorithm
import toppra.constraint
from scipy.interpolate import CubicSpline

# The robots, their chains, the payload and the chain models are the dynamics reference's.
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "dynamics"))
from pinocchio_reference import (  # noqa: E402
    CHAINS,
    PAYLOAD_COM,
    PAYLOAD_INERTIA,
    PAYLOAD_MASS,
    ROBOTS,
    chain_model,
)

# The cases of each robot: (name, waypoint count (None: random in [8, 50)), factor on the URDF
# effort limits (None: no torque constraint), payload). Each robot has a 50-waypoint case with
# and one without torque; the Panda's full-effort torque case carries the payload.
CASES = {
    "panda": [("n50_vel_acc", 50, None, False), ("vel_acc", None, None, False),
              ("torque_payload", None, 1.0, True), ("torque_half_effort", 50, 0.5, False)],
    "ur5": [("n50_vel_acc", 50, None, False), ("vel_acc", None, None, False),
            ("torque", None, 1.0, False), ("torque_half_effort", 50, 0.5, False)],
    "baxter": [("n50_vel_acc", 50, None, False), ("vel_acc", None, None, False),
               ("torque", None, 1.0, False), ("torque_half_effort", 50, 0.5, False)],
}
# Acceleration limits (rad/s², uniform per joint): higher with torque, so that torque binds.
ACCELERATION_RANGE = (2.0, 15.0)
ACCELERATION_RANGE_TORQUE = (20.0, 60.0)

SPLINE_CHECKS = 5  # parameter values per case where the spline is recorded
MAX_DRAWS = 200  # draws of a case before giving up
SEED = 2024


def random_path(rng, lower, upper, n):
    """n waypoints of a smooth random path: the segment between a random start and end inside
    the middle 80 % of the joint ranges, plus three sine harmonics (zero at both ends) whose
    amplitudes add up to at most 10 % of each range, so that every waypoint is within the
    limits; sampled at increasing, unevenly spaced path fractions."""
    span = upper - lower
    start = rng.uniform(lower + 0.1 * span, upper - 0.1 * span)
    end = rng.uniform(lower + 0.1 * span, upper - 0.1 * span)
    steps = rng.uniform(0.5, 1.5, n - 1)
    t = np.concatenate([[0.0], np.cumsum(steps) / steps.sum()])
    weights = rng.uniform(-1.0, 1.0, (3, len(lower)))
    weights *= 0.1 / np.maximum(np.abs(weights).sum(axis=0), 1.0)
    q = start + t[:, None] * (end - start)
    for k in range(3):
        q += np.sin((k + 1) * np.pi * t)[:, None] * weights[k] * span
    return q


def chord_knots(waypoints):
    """s_0 = 0, s_{i+1} = s_i + |q_{i+1} - q_i|_2."""
    steps = np.linalg.norm(np.diff(waypoints, axis=0), axis=1)
    return np.concatenate([[0.0], np.cumsum(steps)])


def midpoint_grid(knots):
    """The knots and the midpoint of every knot interval, ascending."""
    grid = np.empty(2 * len(knots) - 1)
    grid[0::2] = knots
    grid[1::2] = 0.5 * (knots[:-1] + knots[1:])
    return grid


def solve(path, grid, constraints):
    """toppra's rest-to-rest parameterisation: (trajectory, sd at the grid points, controllable
    sets), or None when it is infeasible."""
    algorithm = toppra.algorithm.TOPPRA(
        constraints, path, gridpoints=grid, solver_wrapper="seidel",
        parametrizer="ParametrizeConstAccel",
    )
    trajectory = algorithm.compute_trajectory(0, 0)
    if trajectory is None:
        return None
    data = algorithm.problem_data
    return trajectory, np.asarray(data.sd_vec), np.asarray(data.K)


def lp_x_range(rows, bound, u_max=1e8):
    """[min x, max x] over {(u, x): rows [u x 1]^T <= 0, |u| <= u_max, 0 <= x <= bound}, by
    enumerating the vertices (every pair of constraint lines), or None when it is empty."""
    lines = np.vstack([rows, [[1.0, 0.0, -u_max], [-1.0, 0.0, -u_max],
                              [0.0, 1.0, -bound], [0.0, -1.0, 0.0]]])
    i, j = np.triu_indices(len(lines), 1)
    det = lines[i, 0] * lines[j, 1] - lines[i, 1] * lines[j, 0]
    keep = np.abs(det) > 1e-300
    i, j, det = i[keep], j[keep], det[keep]
    u = (lines[i, 1] * lines[j, 2] - lines[i, 2] * lines[j, 1]) / det
    x = (lines[i, 2] * lines[j, 0] - lines[i, 0] * lines[j, 2]) / det
    points = np.stack([u, x, np.ones_like(u)])
    slack = np.abs(lines) @ np.abs(points)
    feasible = np.all(lines @ points <= 1e-12 * slack, axis=0)
    if not feasible.any():
        return None
    return x[feasible].min(), x[feasible].max()


def replay(path, grid, model, data, velocity_limits, acceleration_limits, torque_limits):
    """x_i and K_i by the rules in the module docstring, from the constraint rows evaluated
    here (the spline, Pinocchio's RNEA) and exact LPs."""
    q, dq, ddq = path(grid), path(grid, 1), path(grid, 2)
    count = len(grid) - 1
    delta = np.diff(grid)
    stage = []  # per grid point: rows (a, b, c) of a u + b x + c <= 0
    bound = np.empty(count + 1)
    for i in range(count + 1):
        a, b, c = [dq[i], -dq[i]], [ddq[i], -ddq[i]], [-acceleration_limits] * 2
        if torque_limits is not None:
            zero = np.zeros(len(q[i]))
            gravity = pin.rnea(model, data, q[i], zero, zero).copy()
            inertial = pin.rnea(model, data, q[i], zero, dq[i]) - gravity
            path_term = pin.rnea(model, data, q[i], dq[i], ddq[i]) - gravity
            a += [inertial, -inertial]
            b += [path_term, -path_term]
            c += [gravity - torque_limits, -gravity - torque_limits]
        stage.append(np.stack([np.concatenate(a), np.concatenate(b), np.concatenate(c)], axis=1))
        moving = dq[i] != 0.0
        sd_max = np.float32(min(np.min(velocity_limits[moving] / np.abs(dq[i][moving])), 1e8))
        bound[i] = float(sd_max * sd_max)  # squared in single precision, as toppra
    controllable = np.zeros((count + 1, 2))
    for i in range(count - 1, -1, -1):
        reach = [[2.0 * delta[i], 1.0, -controllable[i + 1, 1]],
                 [-2.0 * delta[i], -1.0, controllable[i + 1, 0]]]
        low, high = lp_x_range(np.vstack([stage[i], reach]), bound[i])
        controllable[i] = [max(low, 0.0), high]
    x = np.zeros(count + 1)
    for i in range(count):
        a, b, c = stage[i].T
        up = a > 1e-10
        u = min(np.min((-(b * x[i] + c) / a)[up], initial=np.inf),
                (controllable[i + 1, 1] - x[i]) / (2.0 * delta[i]))
        y = x[i] + 2.0 * delta[i] * u
        y = max(y - 1e-8, 0.9999 * y)
        x[i + 1] = min(controllable[i + 1, 1], max(controllable[i + 1, 0], y))
    return x, controllable


def main():
    rng = np.random.default_rng(SEED)
    collocation = toppra.constraint.DiscretizationType.Collocation
    payload = pin.Inertia(PAYLOAD_MASS, np.array(PAYLOAD_COM), np.array(PAYLOAD_INERTIA))
    out = {
        "generator": "toppra_reference.py",
        "toppra": version("toppra"),
        "pinocchio": pin.__version__,
        "example_robot_data": version("example-robot-data"),
        "scipy": scipy.__version__,
        "cases": [],
    }
    for robot, urdf, base, tip in CHAINS:
        full = pin.buildModelFromUrdf(os.path.join(ROBOTS, urdf))
        model, base_frame, tip_frame = chain_model(full, base, tip)
        data = model.createData()
        pin.framesForwardKinematics(model, data, pin.neutral(model))
        gravity_base = data.oMf[base_frame].rotation.T @ model.gravity.linear
        names = [model.names[j] for j in range(1, model.njoints)]
        dof = model.nq
        assert model.nv == dof == len(names), robot
        lower = np.where(np.isfinite(model.lowerPositionLimit), model.lowerPositionLimit, -np.pi)
        upper = np.where(np.isfinite(model.upperPositionLimit), model.upperPositionLimit, np.pi)
        velocity_limits = model.velocityLimit.copy()
        loaded = model.copy()
        tip_placement = model.frames[tip_frame]
        loaded.appendBodyToJoint(tip_placement.parentJoint, payload, tip_placement.placement)

        for name, count, effort_factor, with_payload in CASES[robot]:
            dynamics = loaded if with_payload else model
            dynamics_data = dynamics.createData()

            def inv_dyn(q, qd, qdd, m=dynamics, d=dynamics_data):
                return pin.rnea(m, d, q, qd, qdd).copy()

            torque = effort_factor is not None
            for draw in range(MAX_DRAWS):
                n = count if count is not None else int(rng.integers(8, 50))
                waypoints = random_path(rng, lower, upper, n)
                assert np.all((waypoints >= lower) & (waypoints <= upper)), "outside the limits"
                acceleration_limits = rng.uniform(
                    *(ACCELERATION_RANGE_TORQUE if torque else ACCELERATION_RANGE), dof)
                knots = chord_knots(waypoints)
                assert np.diff(knots).min() > 1e-3, "consecutive waypoints too close"
                grid = midpoint_grid(knots)
                path = toppra.SplineInterpolator(knots, waypoints, bc_type="natural")
                constraints = [
                    toppra.constraint.JointVelocityConstraint(velocity_limits),
                    toppra.constraint.JointAccelerationConstraint(
                        acceleration_limits, discretization_scheme=collocation),
                ]
                torque_limits = None
                if torque:
                    torque_limits = effort_factor * model.effortLimit
                    constraints.append(toppra.constraint.JointTorqueConstraint(
                        inv_dyn, np.stack([-torque_limits, torque_limits], axis=1),
                        np.zeros(dof), discretization_scheme=collocation))
                solved = solve(path, grid, constraints)
                if solved is None:
                    continue  # infeasible: draw again
                if torque:
                    # Keep only draws whose motion the torque limits make longer.
                    without = solve(path, grid, constraints[:2])[0].duration
                    if solved[0].duration <= without * (1.0 + 1e-6):
                        continue
                break
            else:
                raise RuntimeError(f"no suitable draw for {robot}_{name}")
            trajectory, sd, controllable = solved
            sd_squared = sd**2

            # The duration is Σ 2 Δs_i / (sd_i + sd_{i+1}) of the recorded squared velocities.
            root = np.sqrt(sd_squared)
            duration = float(trajectory.duration)
            expected = float(np.sum(2.0 * np.diff(grid) / (root[:-1] + root[1:])))
            assert abs(duration - expected) <= 1e-9 * duration, (duration, expected)

            # The rules of the docstring reproduce toppra.
            x, sets = replay(path, grid, dynamics, dynamics_data, velocity_limits,
                             acceleration_limits, torque_limits)
            assert np.allclose(x, sd_squared, rtol=1e-10, atol=1e-12), np.abs(x - sd_squared).max()
            assert np.allclose(sets, controllable, rtol=1e-10, atol=1e-12), name

            # The same problem with the constraints imposed at both ends of every stage
            # (toppra's Interpolation scheme; graspath's default for selection).
            interpolation = toppra.constraint.DiscretizationType.Interpolation
            interpolated = [
                toppra.constraint.JointVelocityConstraint(velocity_limits),
                toppra.constraint.JointAccelerationConstraint(
                    acceleration_limits, discretization_scheme=interpolation),
            ]
            if torque:
                interpolated.append(toppra.constraint.JointTorqueConstraint(
                    inv_dyn, np.stack([-torque_limits, torque_limits], axis=1),
                    np.zeros(dof), discretization_scheme=interpolation))
            interpolated_trajectory, interpolated_sd, _ = solve(path, grid, interpolated)

            # toppra's path is scipy's natural cubic spline through the knots.
            spline = CubicSpline(knots, waypoints, bc_type="natural")
            intervals = rng.choice(n - 1, SPLINE_CHECKS, replace=False)
            s = np.sort(knots[intervals] + rng.uniform(0.05, 0.95, SPLINE_CHECKS)
                        * np.diff(knots)[intervals])
            for order in range(3):
                assert np.allclose(path(s, order), spline(s, order), rtol=1e-12, atol=1e-12)

            out["cases"].append(
                {
                    "name": f"{robot}_{name}",
                    "robot": robot,
                    "urdf": urdf,
                    "base": base,
                    "tip": tip,
                    "joint_names": names,
                    "gravity_base": gravity_base.tolist(),
                    "waypoints": waypoints.tolist(),
                    "knots": knots.tolist(),
                    "grid": grid.tolist(),
                    "velocity_limits": velocity_limits.tolist(),
                    "acceleration_limits": acceleration_limits.tolist(),
                    "torque_limits": None if torque_limits is None else torque_limits.tolist(),
                    "payload": {"mass": PAYLOAD_MASS, "com": PAYLOAD_COM,
                                "inertia": PAYLOAD_INERTIA} if with_payload else None,
                    "duration": duration,
                    "sd_squared": sd_squared.tolist(),
                    "duration_interpolation": float(interpolated_trajectory.duration),
                    "sd_squared_interpolation": (interpolated_sd**2).tolist(),
                    "controllable_sets": controllable.tolist(),
                    "spline_check": {
                        "s": s.tolist(),
                        "q": path(s).tolist(),
                        "dq": path(s, 1).tolist(),
                        "ddq": path(s, 2).tolist(),
                    },
                }
            )
            note = f", {without:.6f} s without torque" if torque else ""
            print(f"{robot}_{name}: n = {n}, draw {draw + 1}, duration {duration:.6f} s{note}")
    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "toppra_timing.json")
    with open(path, "w") as f:
        json.dump(out, f, indent=1)
        f.write("\n")
    print(path)


if __name__ == "__main__":
    main()
