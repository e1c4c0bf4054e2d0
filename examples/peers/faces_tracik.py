#!/usr/bin/env python3
"""The 1000-candidate faces workload done the usual Python way: TRAC-IK, Pinocchio and numpy.

The peer of `graspath select --task examples/workload_1000_faces.yaml` in BENCHMARKS.md ("End to
end against a Python peer"). Its input is the wrist poses graspath's selection works from,
written once, before any timing, by

    cargo run --release -p graspath --example export_wrist_paths -- \
        examples/workload_1000_faces.yaml wrists.npy

(float64, shape (candidates, samples, 4, 4): base_from_wrist of each candidate at each path
sample, Baxter's `base` frame). For each candidate, in order, one sample at a time:

* TRAC-IK (`pytracik`, Speed mode, 5 ms, 1e-5) for the wrist pose, seeded by the previous
  sample's solution (the first sample from the middle of the joint limits);
* a candidate stops at its first failure: no IK solution, or (as graspath's feasibility
  requires) a joint moving more than --max-joint-step rad from the previous sample (0: no check);
* Pinocchio's geometric Jacobian of the tip in the base frame (`computeFrameJacobian`,
  LOCAL_WORLD_ALIGNED, rows [v; w]) at the solution.

Then numpy: the unit tangent of the wrist path at each sample (the SE(3) log of
wrist_i^-1 wrist_{i+1} in the base frame, the last sample's from the interval before it),
M_T = |J^T u|^2 (the paper's eq. 13, twist mode with L = 1), and over a feasible candidate's
samples mu_l2 = |M|_2 and mu_linf = max 1/M; candidates are ranked by mu_l2. Everything is
written to one .npz (--out): feasible, failure_sample (-1 if none), failure (0 none, 1 no IK
solution, 2 joint jump), q (candidates x samples x joints, NaN where not solved), m_t, mu_l2,
mu_linf (NaN when infeasible) and rank (0 = best, -1 infeasible).

Setup (a virtual environment; every package is a wheel from PyPI, nothing to build):

    python3 -m venv target/pyenv
    target/pyenv/bin/pip install numpy pin pytracik

    target/pyenv/bin/python examples/peers/faces_tracik.py --wrists wrists.npy \
        --urdf ../shared/robots/baxter.urdf --out peer.npz

`compare_faces.py` beside this file sets the results against graspath's `candidates.json`.
"""

import argparse
import sys
import time

import numpy as np
import pinocchio as pin
import pytracik

STILL_TWIST_TOLERANCE = 1e-9  # as graspath: a sample whose twist is smaller is skipped


def quaternions(rotations):
    """Unit quaternions (x, y, z, w) of rotation matrices (..., 3, 3) (Shepperd's method)."""
    r = rotations.reshape(-1, 3, 3)
    out = np.empty((len(r), 4))
    trace = np.trace(r, axis1=1, axis2=2)
    diag = np.stack([r[:, 0, 0], r[:, 1, 1], r[:, 2, 2]], axis=1)
    case = np.where(trace > diag.max(axis=1), 3, diag.argmax(axis=1))
    for k in range(4):
        m = r[case == k]
        if not len(m):
            continue
        if k == 3:
            s = 2.0 * np.sqrt(1.0 + np.trace(m, axis1=1, axis2=2))
            q = np.stack([m[:, 2, 1] - m[:, 1, 2], m[:, 0, 2] - m[:, 2, 0],
                          m[:, 1, 0] - m[:, 0, 1], 0.25 * s * s], axis=1)
        else:
            i, j, l = k, (k + 1) % 3, (k + 2) % 3
            s = 2.0 * np.sqrt(1.0 + m[:, i, i] - m[:, j, j] - m[:, l, l])
            q = np.empty((len(m), 4))
            q[:, i] = 0.25 * s * s
            q[:, j] = m[:, j, i] + m[:, i, j]
            q[:, l] = m[:, l, i] + m[:, i, l]
            q[:, 3] = m[:, l, j] - m[:, j, l]
        out[case == k] = q / s[:, None]
    return out.reshape(rotations.shape[:-2] + (4,))


def se3_log(t):
    """Twists (v, w) of homogeneous transforms (..., 4, 4): log of SE(3)."""
    r, p = t[..., :3, :3], t[..., :3, 3]
    cos = np.clip((np.trace(r, axis1=-2, axis2=-1) - 1.0) / 2.0, -1.0, 1.0)
    theta = np.arccos(cos)
    skew = np.stack([r[..., 2, 1] - r[..., 1, 2], r[..., 0, 2] - r[..., 2, 0],
                     r[..., 1, 0] - r[..., 0, 1]], axis=-1)
    small = theta < 1e-6
    sin = np.sin(theta)
    factor = np.where(small, 0.5 + theta**2 / 12.0, theta / (2.0 * np.where(small, 1.0, sin)))
    w = factor[..., None] * skew
    # V^-1 = I - W/2 + (1/theta^2)(1 - theta sin / (2 (1 - cos))) W^2
    half = np.where(small, 1.0, theta)
    coef = np.where(small, 1.0 / 12.0,
                    (1.0 - half * sin / (2.0 * np.where(small, 1.0, 1.0 - cos))) / half**2)
    wxp = np.cross(w, p)
    v = p - 0.5 * wxp + coef[..., None] * np.cross(w, wxp)
    return np.concatenate([v, w], axis=-1)


def unit_tangents(wrists):
    """Per candidate and sample: the unit direction of the wrist's motion in the base frame
    (6-D, [v; w]) and whether the wrist moves there at all."""
    inverse = np.linalg.inv(wrists[:, :-1])
    body = se3_log(inverse @ wrists[:, 1:])  # interval i -> i+1, wrist frame i
    body = np.concatenate([body, body[:, -1:]], axis=1)  # the last: backward difference
    rot = wrists[..., :3, :3]
    twist = np.concatenate([np.einsum("csij,csj->csi", rot, body[..., :3]),
                            np.einsum("csij,csj->csi", rot, body[..., 3:])], axis=-1)
    norm = np.linalg.norm(twist, axis=-1)
    moving = norm >= STILL_TWIST_TOLERANCE
    return twist / np.where(moving, norm, 1.0)[..., None], moving


def arm_model(urdf, tip):
    """Pinocchio's model of the chain from the URDF's root to `tip`, every other joint locked
    at zero, and the tip frame's id."""
    full = pin.buildModelFromUrdf(urdf)
    joint = full.frames[full.getFrameId(tip)].parentJoint
    chain = set()
    while joint > 0:
        chain.add(joint)
        joint = full.parents[joint]
    locked = [j for j in range(1, full.njoints) if j not in chain]
    model = pin.buildReducedModel(full, locked, pin.neutral(full))
    return model, model.getFrameId(tip)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--wrists", required=True, help="export_wrist_paths' .npy")
    parser.add_argument("--urdf", required=True, help="the robot's URDF (baxter.urdf)")
    parser.add_argument("--base", default="base")
    parser.add_argument("--tip", default="left_gripper")
    parser.add_argument("--out", required=True, help="results (.npz)")
    parser.add_argument("--timeout", type=float, default=0.005, help="TRAC-IK budget (s)")
    parser.add_argument("--epsilon", type=float, default=1e-5, help="TRAC-IK tolerance")
    parser.add_argument("--max-joint-step", type=float, default=0.5,
                        help="largest joint move between samples (rad); 0: not checked")
    parser.add_argument("--quiet", action="store_true")
    args = parser.parse_args()
    started = time.perf_counter()

    wrists = np.load(args.wrists)
    count, samples = wrists.shape[:2]
    with open(args.urdf) as f:
        solver = pytracik.TRAC_IK(args.base, args.tip, f.read(), args.timeout, args.epsilon,
                                  pytracik.SolveType.Speed)
    model, tip = arm_model(args.urdf, args.tip)
    data = model.createData()
    dof = pytracik.get_num_joints(solver)
    assert dof == model.nq, f"TRAC-IK has {dof} joints, Pinocchio {model.nq}"
    mid = 0.5 * (np.array(pytracik.get_joint_lower_bounds(solver))
                 + np.array(pytracik.get_joint_upper_bounds(solver)))

    # IK targets as plain floats: (x, y, z, qx, qy, qz, qw) per candidate and sample.
    targets = np.concatenate([wrists[..., :3, 3], quaternions(wrists[..., :3, :3])],
                             axis=-1).tolist()
    tangents, moving = unit_tangents(wrists)

    q_all = np.full((count, samples, dof), np.nan)
    jacobians = np.zeros((count, samples, 6, dof))
    failure = np.zeros(count, dtype=np.int8)
    failure_sample = np.full(count, -1)
    ik, jacobian, world = pytracik.ik, pin.computeFrameJacobian, pin.LOCAL_WORLD_ALIGNED
    for c in range(count):
        q = mid
        for i, (x, y, z, qx, qy, qz, qw) in enumerate(targets[c]):
            solution = ik(solver, q, x, y, z, qx, qy, qz, qw)
            if solution[0] < 0:
                failure[c], failure_sample[c] = 1, i
                break
            solution = solution[1:]
            if i > 0 and args.max_joint_step > 0 and \
                    np.abs(solution - q).max() > args.max_joint_step:
                failure[c], failure_sample[c] = 2, i
                break
            q = solution
            q_all[c, i] = q
            jacobians[c, i] = jacobian(model, data, q, tip, world)

    feasible = failure == 0
    # M_T = |J^T u|^2 at every solved sample; the norms over a feasible candidate's samples.
    m_t = np.einsum("csij,csi->csj", jacobians, tangents)
    m_t = np.where(moving & ~np.isnan(q_all[..., 0]), (m_t**2).sum(axis=-1), np.nan)
    counted = np.where(moving, m_t, 0.0)
    mu_l2 = np.where(feasible, np.sqrt((counted**2).sum(axis=1)), np.nan)
    with np.errstate(divide="ignore"):
        mu_linf = np.where(feasible, np.where(moving, 1.0 / np.where(moving, m_t, 1.0),
                                              -np.inf).max(axis=1), np.nan)
    order = np.argsort(-np.where(feasible, mu_l2, -np.inf), kind="stable")
    rank = np.full(count, -1)
    rank[order[: feasible.sum()]] = np.arange(feasible.sum())
    with open(args.out, "wb") as f:
        np.savez(f, feasible=feasible, failure=failure, failure_sample=failure_sample,
                 q=q_all, m_t=m_t, mu_l2=mu_l2, mu_linf=mu_linf, rank=rank)
    if not args.quiet:
        best = order[0] if feasible.any() else None
        print(f"{feasible.sum()} of {count} feasible ({(failure == 1).sum()} without an IK "
              f"solution, {(failure == 2).sum()} joint jumps); best {best} "
              f"mu_l2 {mu_l2[best] if best is not None else float('nan'):.6f}; "
              f"{time.perf_counter() - started:.2f} s after imports", file=sys.stderr)


if __name__ == "__main__":
    main()
