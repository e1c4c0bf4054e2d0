"""Batch forward kinematics + Jacobian of the built-in Panda from Python: graspath's batch calls
(new result arrays and `out=` arrays) against the plain batched PyTorch script
`examples/peers/torch_fk_jacobian.py`, at one and at two threads, in one run.

Run: `python examples/python/bench_batch.py [--n 1000000] [--repeat 9] [--threads 1 2]` after
`pip install ./crates/graspath-py torch`. Each thread count runs in its own process
(RAYON_NUM_THREADS for graspath, `torch.set_num_threads` for PyTorch, both set before the first
call); inside it the calls take turns, `--repeat` rounds, and the median of each is reported:
wall-clock time, and the CPU time of the process's threads (`getrusage`), which time spent
waiting for a core (on a busy machine) does not inflate.
The PyTorch script is first checked against graspath (float64, largest difference ≤ 1e-12).
"""

import argparse
import json
import os
import platform
import resource
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[2]


def worker(args):
    import graspath

    sys.path.insert(0, str(REPO / "examples" / "peers"))
    try:
        import torch
        from torch_fk_jacobian import PandaKinematics, check_against_graspath

        torch.set_num_threads(args.threads)
        error = check_against_graspath()
        kinematics = PandaKinematics()
    except ImportError:
        torch, error, kinematics = None, None, None

    robot = graspath.Robot.builtin("panda")
    rng = np.random.default_rng(0)
    q = robot.lower + (robot.upper - robot.lower) * rng.random((args.n, robot.dof))
    poses_out = np.empty((args.n, 4, 4))
    jacobians_out = np.empty((args.n, 6, robot.dof))
    calls = {
        "fk_jacobian(q)": lambda: robot.fk_jacobian(q),
        "fk_jacobian(q, out=)": lambda: robot.fk_jacobian(q, out=(poses_out, jacobians_out)),
        "fk(q)": lambda: robot.fk(q),
        "fk(q, out=)": lambda: robot.fk(q, out=poses_out),
        "jacobian(q)": lambda: robot.jacobian(q),
        "jacobian(q, out=)": lambda: robot.jacobian(q, out=jacobians_out),
    }
    if torch is not None:
        q_torch = torch.from_numpy(q)
        calls["torch fk_jacobian, float64"] = lambda: kinematics.fk_jacobian(q_torch)
    def cpu_seconds():
        usage = resource.getrusage(resource.RUSAGE_SELF)  # every thread of this process
        return usage.ru_utime + usage.ru_stime

    times = {name: [] for name in calls}
    cpu = {name: [] for name in calls}
    for name, call in calls.items():
        call()  # warm-up: first-call costs (thread pools, imports) are not measured
    for _ in range(args.repeat):
        for name, call in calls.items():
            start, start_cpu = time.perf_counter(), cpu_seconds()
            result = call()
            del result  # a new result is freed inside the timing, as in a loop of calls
            times[name].append(time.perf_counter() - start)
            cpu[name].append(cpu_seconds() - start_cpu)
    print(
        json.dumps(
            {
                "threads": args.threads,
                "torch": torch.__version__ if torch is not None else None,
                "torch_error": error,
                "median": {name: float(np.median(t)) for name, t in times.items()},
                "min": {name: float(np.min(t)) for name, t in times.items()},
                "max": {name: float(np.max(t)) for name, t in times.items()},
                "cpu": {name: float(np.median(t)) for name, t in cpu.items()},
            }
        )
    )


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--n", type=int, default=1_000_000)
    parser.add_argument("--repeat", type=int, default=9)
    parser.add_argument("--threads", type=int, nargs="+", default=[1, 2])
    parser.add_argument("--worker", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.worker:
        args.threads = args.threads[0]
        worker(args)
        return
    import graspath

    print(f"python {platform.python_version()}, numpy {np.__version__}, graspath {graspath.__version__}, "
          f"{os.cpu_count()} CPUs; {args.n} Panda configurations, median of {args.repeat}")
    results = []
    for threads in args.threads:
        env = dict(os.environ, RAYON_NUM_THREADS=str(threads), OMP_NUM_THREADS=str(threads))
        out = subprocess.run(
            [sys.executable, __file__, "--worker", "--n", str(args.n), "--repeat", str(args.repeat),
             "--threads", str(threads)],
            env=env, check=True, capture_output=True, text=True,
        ).stdout
        results.append(json.loads(out.strip().splitlines()[-1]))
    first = results[0]
    if first["torch"]:
        print(f"torch {first['torch']} (CPU), largest difference to graspath {first['torch_error']:.1e}")
    header = "| call | " + " | ".join(
        f"{r['threads']} thread(s): wall median (range), configs/s | CPU time" for r in results
    ) + " |"
    print(header)
    print("|---" * (2 * len(results) + 1) + "|")
    for name in first["median"]:
        cells = []
        for r in results:
            t = r["median"][name]
            cells.append(f"{t * 1e3:.1f} ms ({r['min'][name] * 1e3:.0f}–{r['max'][name] * 1e3:.0f}), {args.n / t / 1e6:.1f} M/s")
            cells.append(f"{r['cpu'][name] * 1e3:.1f} ms")
        print(f"| {name} | " + " | ".join(cells) + " |")
    for r in results:
        m = r["median"]
        line = (f"{r['threads']} thread(s): new/out= fk_jacobian {m['fk_jacobian(q)'] / m['fk_jacobian(q, out=)']:.2f}, "
                f"fk {m['fk(q)'] / m['fk(q, out=)']:.2f}, jacobian {m['jacobian(q)'] / m['jacobian(q, out=)']:.2f}; "
                f"fk_jacobian out= per core {args.n / m['fk_jacobian(q, out=)'] / r['threads'] / 1e6:.1f} M/s")
        if "torch fk_jacobian, float64" in m:
            line += (f"; graspath new arrays vs torch: "
                     f"{m['torch fk_jacobian, float64'] / m['fk_jacobian(q)']:.1f}x")
        print(line)
    if len(results) > 1:
        a, b = results[0]["median"], results[-1]["median"]
        print(f"{results[-1]['threads']} threads vs {results[0]['threads']}: "
              + ", ".join(f"{name} {a[name] / b[name]:.2f}x" for name in a))


if __name__ == "__main__":
    main()
