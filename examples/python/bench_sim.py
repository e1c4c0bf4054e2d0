"""How fast graspath.sim executes a candidate and runs an experiment, on one core.

For a task: the real-time factor (simulated seconds per wall-clock second) of its best
candidate's whole task, the median of ``--repeat`` runs per mode (the timed motion's scoring
included), and the wall time of the experiment `python -m graspath.sim` runs (``k`` = 5,
``n`` = 10, both modes, two speeds). Run: ``python examples/python/bench_sim.py TASK
[--arm-gravity-compensation]`` after ``pip install './crates/graspath-py[sim]'``.
"""

import argparse
import statistics
import time

import graspath
from graspath import sim


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("task")
    parser.add_argument("--repeat", type=int, default=10)
    parser.add_argument("--arm-gravity-compensation", action="store_true")
    args = parser.parse_args()
    task = graspath.Task.load(args.task)
    options = sim.SimOptions(arm_gravity_compensation=args.arm_gravity_compensation)
    world = sim.World(task, options)
    selection = graspath.select(task)
    if len(selection.arms) == 1:
        chosen = [selection.best(selection.arms[0])]
    else:
        # Positions of the best pair's candidates (ids equal positions in the shipped tasks).
        chosen = [int(selection.pairs[0][arm]) for arm in selection.arms]
    for mode in ("friction", "weld"):
        factors = []
        for _ in range(args.repeat):
            run = world.run(chosen, mode=mode)
            factors.append(run["duration"] / world.last_wall_time)
        print(
            f"{mode}: {run['duration']:.2f} s simulated, real-time factor median "
            f"{statistics.median(factors):.1f} (min {min(factors):.1f}, max {max(factors):.1f})"
        )
    started = time.perf_counter()
    document = sim.experiment(task, k=5, n_random=10, options=options)
    wall = time.perf_counter() - started
    print(f"experiment (k=5, n=10, 2 modes, 2 speeds): {len(document['runs'])} runs in {wall:.1f} s")


if __name__ == "__main__":
    main()
