"""Batch forward kinematics + Jacobian from Python: graspath's batch call against a Python
loop over Pinocchio's computeFrameJacobian, on Baxter's left arm (7 joints).

Run: `python examples/python/bench_fk.py [--n 100000] [--repeat 5]` after
`pip install ./crates/graspath-py pin`. Pinocchio evaluates the same chain as a reduced model
(every other joint of baxter.urdf locked at zero), so both compute one 7-joint chain; its
LOCAL_WORLD_ALIGNED Jacobian is the same quantity as graspath's (rows [v; ω], base axes).
"""

import argparse
import os
import platform
import time
from pathlib import Path

import numpy as np

import graspath


def best_of(repeat, fn):
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        fn()
        times.append(time.perf_counter() - start)
    return min(times)


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--n", type=int, default=100_000)
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--shared", type=Path, default=None, help="the shared folder (robots/)")
    args = parser.parse_args()
    repo = Path(__file__).resolve().parents[2]
    shared = args.shared or Path(os.environ.get("GRASPATH_SHARED", repo.parent / "shared"))

    robot = graspath.Robot.baxter("left")
    rng = np.random.default_rng(0)
    q = robot.lower + (robot.upper - robot.lower) * rng.random((args.n, robot.dof))
    print(f"python {platform.python_version()}, numpy {np.__version__}, graspath {graspath.__version__}")
    print(f"{args.n} configurations of {robot.name} ({robot.dof} joints), best of {args.repeat}")

    t_batch = best_of(args.repeat, lambda: robot.fk_jacobian(q))
    print(f"graspath fk_jacobian, batch    : {t_batch * 1e3:9.1f} ms  {t_batch / args.n * 1e6:7.3f} us/config")
    poses_out = np.empty((args.n, 4, 4))
    jacobians_out = np.empty((args.n, 6, robot.dof))
    t_out = best_of(args.repeat, lambda: robot.fk_jacobian(q, out=(poses_out, jacobians_out)))
    print(f"graspath fk_jacobian, batch, out=: {t_out * 1e3:7.1f} ms  {t_out / args.n * 1e6:7.3f} us/config")
    t_fk = best_of(args.repeat, lambda: robot.fk(q))
    print(f"graspath fk, batch             : {t_fk * 1e3:9.1f} ms  {t_fk / args.n * 1e6:7.3f} us/config")
    m = min(args.n, 20_000)
    t_single = best_of(max(1, args.repeat // 2), lambda: [robot.fk_jacobian(qi) for qi in q[:m]])
    print(f"graspath fk_jacobian, Python loop: {t_single / m * 1e6:7.3f} us/config (over {m})")

    try:
        import pinocchio as pin
    except ImportError:
        print("pinocchio is not installed (pip install pin): no comparison")
        return
    urdf = shared / "robots" / "baxter.urdf"
    if not urdf.is_file():
        print(f"{urdf} not found: no comparison")
        return
    full = pin.buildModelFromUrdf(str(urdf))
    keep = set(robot.joint_names)
    lock = [j for j in range(1, full.njoints) if full.names[j] not in keep]
    model = pin.buildReducedModel(full, lock, pin.neutral(full))
    data = model.createData()
    tip = model.getFrameId("left_gripper")
    order = [model.joints[model.getJointId(n)].idx_q for n in robot.joint_names]
    qp = np.zeros((args.n, model.nq))
    qp[:, order] = q

    # Same numbers first (base is the root of baxter.urdf).
    poses, jacs = robot.fk_jacobian(q[:100])
    for i in range(100):
        jac = pin.computeFrameJacobian(model, data, qp[i], tip, pin.LOCAL_WORLD_ALIGNED)
        np.testing.assert_allclose(jac[:, order], jacs[i], atol=1e-9)
        np.testing.assert_allclose(data.oMf[tip].homogeneous, poses[i], atol=1e-9)

    def pinocchio_loop():
        for qi in qp:
            pin.computeFrameJacobian(model, data, qi, tip, pin.LOCAL_WORLD_ALIGNED)

    t_pin = best_of(max(1, args.repeat // 2), pinocchio_loop)
    print(f"pinocchio computeFrameJacobian, Python loop: {t_pin * 1e3:9.1f} ms  {t_pin / args.n * 1e6:7.3f} us/config")
    print(f"speed-up of the batch call: {t_pin / t_batch:.1f}x (new arrays), {t_pin / t_out:.1f}x (out= arrays)")


if __name__ == "__main__":
    main()
