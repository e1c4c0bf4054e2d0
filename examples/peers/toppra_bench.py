"""Times toppra (TOPP-RA, Python with Cython kernels) on a 50-waypoint Panda path: the peer of
graspath's time-optimal path parameterisation benchmark.

The problem is built as in crates/graspath/tests/data/timing/toppra_reference.py: the Panda
chain of example-robot-data (panda_link0 -> panda_hand_tcp, Pinocchio's model reduced to it),
a smooth random joint path of --waypoints waypoints inside the joint limits, knots by chord
length (s_{i+1} = s_i + |q_{i+1} - q_i|_2), toppra.SplineInterpolator(knots, waypoints,
bc_type="natural") (scipy's natural cubic spline), the grid = the knots and every interval's
midpoint, and these constraints, all with collocation:

* joint velocity: ± the URDF's velocity limits;
* joint acceleration: ± a per-joint limit drawn uniformly in [20, 60] rad/s²;
* joint torque: ± the URDF's effort limits, tau = pin.rnea(model, data, q, qd, qdd).
The draw (--seed) is repeated until the problem is feasible and the torque limits lengthen
the motion by at least 1 %, so that all three kinds of constraint bind somewhere.

Timed, over --repeat runs after --warmup untimed ones (wall clock, time.perf_counter), with
toppra's seidel solver wrapper and ParametrizeConstAccel:
    TOPPRA(constraints, path, gridpoints=grid, ...).compute_trajectory(0, 0)
i.e. the evaluation of the constraints on the grid (in TOPPRA's constructor; RNEA three times
per grid point for the torque constraint), the backward and forward passes and the output
trajectory; once with velocity + acceleration + torque, once with velocity + acceleration only.
The spline itself is built once, outside the timing. Printed: median and min per
configuration, and the median of the constructor alone.

The problem is written to the JSON file given as the argument, so that the Rust benchmark can
time exactly the same one: {"generator", "toppra", "pinocchio", "example_robot_data", "scipy",
"problem": {name, robot, urdf, base, tip, joint_names, gravity_base, waypoints, knots, grid,
velocity_limits, acceleration_limits, torque_limits, payload (null), duration, sd_squared}
(the keys of a case of tests/data/timing/toppra_timing.json; duration and sd_squared with
torque), "duration_vel_acc" (without torque), "timing": {"repeat", "warmup", "loadavg",
"vel_acc_torque": {"median_s", "min_s", "median_setup_s"}, "vel_acc": {...}}}.

    target/pyenv/bin/pip install pin example-robot-data toppra==0.6.10
    target/pyenv/bin/python examples/peers/toppra_bench.py target/tmp/toppra_bench.json \
        [--repeat 50] [--warmup 5] [--waypoints 50] [--seed 7]
"""

import argparse
import json
import os
import statistics
import sys
import sysconfig
import time
from importlib.metadata import version

import numpy as np
import pinocchio as pin
import scipy
import toppra
import toppra.algorithm
import toppra.constraint

# The problem is built by the reference script's own helpers (the reduced chain model, the
# random path inside the limits).
sys.path.insert(
    0,
    os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "crates", "graspath",
                 "tests", "data", "timing"),
)
from toppra_reference import chain_model, random_path  # noqa: E402

ROBOTS = os.path.join(
    sysconfig.get_paths()["purelib"], "cmeel.prefix", "share", "example-robot-data", "robots"
)
URDF = "panda_description/urdf/panda.urdf"
BASE, TIP = "panda_link0", "panda_hand_tcp"
ACCELERATION_RANGE = (20.0, 60.0)  # rad/s², per joint
MAX_DRAWS = 200


def run(constraints, path, grid):
    """One timed unit: TOPPRA's setup (constraint evaluation) and compute_trajectory(0, 0).
    Returns (trajectory or None, algorithm, setup seconds, total seconds)."""
    start = time.perf_counter()
    algorithm = toppra.algorithm.TOPPRA(
        constraints, path, gridpoints=grid, solver_wrapper="seidel",
        parametrizer="ParametrizeConstAccel",
    )
    setup = time.perf_counter()
    trajectory = algorithm.compute_trajectory(0, 0)
    end = time.perf_counter()
    return trajectory, algorithm, setup - start, end - start


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("out", help="where to write the problem and the timings (.json)")
    parser.add_argument("--repeat", type=int, default=50, help="timed runs per configuration")
    parser.add_argument("--warmup", type=int, default=5, help="untimed runs before them")
    parser.add_argument("--waypoints", type=int, default=50)
    parser.add_argument("--seed", type=int, default=7)
    args = parser.parse_args()

    full = pin.buildModelFromUrdf(os.path.join(ROBOTS, URDF))
    model, base_frame, _ = chain_model(full, BASE, TIP)
    data = model.createData()
    pin.framesForwardKinematics(model, data, pin.neutral(model))
    gravity_base = data.oMf[base_frame].rotation.T @ model.gravity.linear
    dof = model.nq
    velocity_limits = model.velocityLimit.copy()
    torque_limits = model.effortLimit.copy()
    collocation = toppra.constraint.DiscretizationType.Collocation

    def inv_dyn(q, qd, qdd):
        return pin.rnea(model, data, q, qd, qdd)

    rng = np.random.default_rng(args.seed)
    for _ in range(MAX_DRAWS):
        waypoints = random_path(rng, model.lowerPositionLimit, model.upperPositionLimit,
                                args.waypoints)
        acceleration_limits = rng.uniform(*ACCELERATION_RANGE, dof)
        knots = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(waypoints, axis=0),
                                                                axis=1))])
        grid = np.empty(2 * len(knots) - 1)
        grid[0::2] = knots
        grid[1::2] = 0.5 * (knots[:-1] + knots[1:])
        path = toppra.SplineInterpolator(knots, waypoints, bc_type="natural")
        kinematic = [
            toppra.constraint.JointVelocityConstraint(velocity_limits),
            toppra.constraint.JointAccelerationConstraint(
                acceleration_limits, discretization_scheme=collocation),
        ]
        torque = toppra.constraint.JointTorqueConstraint(
            inv_dyn, np.stack([-torque_limits, torque_limits], axis=1), np.zeros(dof),
            discretization_scheme=collocation)
        full_run = run(kinematic + [torque], path, grid)
        if full_run[0] is None:
            continue
        free_run = run(kinematic, path, grid)
        if full_run[0].duration > free_run[0].duration * 1.01:
            break
    else:
        raise RuntimeError("no feasible draw where the torque limits bind")
    trajectory, algorithm = full_run[:2]

    timing = {"repeat": args.repeat, "warmup": args.warmup, "loadavg": os.getloadavg()[0]}
    for label, constraints in (("vel_acc_torque", kinematic + [torque]), ("vel_acc", kinematic)):
        setups, totals = [], []
        for i in range(args.warmup + args.repeat):
            result, _, setup, total = run(constraints, path, grid)
            assert result is not None
            if i >= args.warmup:
                setups.append(setup)
                totals.append(total)
        timing[label] = {
            "median_s": statistics.median(totals),
            "min_s": min(totals),
            "median_setup_s": statistics.median(setups),
        }
        print(f"toppra {label:14s} ({len(grid)} grid points, {args.repeat} runs): median "
              f"{1e3 * timing[label]['median_s']:.3f} ms, min {1e3 * timing[label]['min_s']:.3f} "
              f"ms (setup, median {1e3 * timing[label]['median_setup_s']:.3f} ms)")
    print(f"duration {trajectory.duration:.6f} s with torque, {free_run[0].duration:.6f} s "
          f"without; load average {timing['loadavg']:.2f}")

    out = {
        "generator": "toppra_bench.py",
        "toppra": version("toppra"),
        "pinocchio": pin.__version__,
        "example_robot_data": version("example-robot-data"),
        "scipy": scipy.__version__,
        "problem": {
            "name": f"panda_bench_n{args.waypoints}_seed{args.seed}",
            "robot": "panda",
            "urdf": URDF,
            "base": BASE,
            "tip": TIP,
            "joint_names": [model.names[j] for j in range(1, model.njoints)],
            "gravity_base": gravity_base.tolist(),
            "waypoints": waypoints.tolist(),
            "knots": knots.tolist(),
            "grid": grid.tolist(),
            "velocity_limits": velocity_limits.tolist(),
            "acceleration_limits": acceleration_limits.tolist(),
            "torque_limits": torque_limits.tolist(),
            "payload": None,
            "duration": float(trajectory.duration),
            "sd_squared": (np.asarray(algorithm.problem_data.sd_vec) ** 2).tolist(),
        },
        "duration_vel_acc": float(free_run[0].duration),
        "timing": timing,
    }
    os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
    with open(args.out, "w") as f:
        json.dump(out, f, indent=1)
        f.write("\n")
    print(args.out)


if __name__ == "__main__":
    main()
