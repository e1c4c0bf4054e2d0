#!/usr/bin/env python3
"""Sets `faces_tracik.py`'s results against graspath's on the same candidates.

    python examples/peers/compare_faces.py OUT/candidates.json peer.npz

graspath's `candidates.json` must carry the joint trajectories (`--trajectories all` or
`feasible`, the default with `--format json`). Prints the feasible counts of each side, the
candidates feasible on one side only, and for those feasible on both: whether both took the
same IK branch (every joint within --same-branch rad of the other side's at every sample),
and the relative difference of mu_l2 and mu_linf, over those on the same branch and over all.
With --wrists and --urdf (the peer's inputs), also the peer's M_T (Pinocchio + numpy, as in
`faces_tracik.py`) at graspath's own joint paths against graspath's M_T: the index itself
compared on identical configurations, whatever branch either IK took.
"""

import argparse
import json

import numpy as np

from faces_tracik import arm_model, unit_tangents


def summary(values):
    if not len(values):
        return "none"
    v = np.abs(values)
    return (f"median {np.median(v):.2e}, 95th percentile {np.percentile(v, 95):.2e}, "
            f"largest {v.max():.2e}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("candidates", help="graspath's candidates.json")
    parser.add_argument("peer", help="faces_tracik.py's .npz")
    parser.add_argument("--wrists", help="the peer's input (export_wrist_paths' .npy)")
    parser.add_argument("--urdf", help="the peer's URDF")
    parser.add_argument("--tip", default="left_gripper")
    parser.add_argument("--same-branch", type=float, default=1e-3,
                        help="largest joint difference (rad) of the same IK branch")
    args = parser.parse_args()

    with open(args.candidates) as f:
        records = sorted(json.load(f), key=lambda r: r["id"])
    peer = np.load(args.peer)
    ours = np.array([r["feasible"] for r in records])
    theirs = peer["feasible"]
    assert len(ours) == len(theirs), "not the same candidates"
    print(f"feasible: graspath {ours.sum()}, peer {theirs.sum()} of {len(ours)}")
    print(f"feasible for graspath only: {(ours & ~theirs).sum()}, "
          f"for the peer only: {(~ours & theirs).sum()} {np.flatnonzero(~ours & theirs)[:20]}")
    for reason, name in [(1, "no IK solution"), (2, "joint jump")]:
        stopped = ours & (peer["failure"] == reason)
        print(f"  graspath-feasible, peer stopped by {name}: {stopped.sum()}")

    both = np.flatnonzero(ours & theirs)
    same, l2, linf = [], [], []
    for c in both:
        q = np.array(records[c]["joint_trajectory"])
        same.append(np.abs(q - peer["q"][c]).max() <= args.same_branch)
        l2.append(peer["mu_l2"][c] / records[c]["mu_l2"] - 1.0)
        linf.append(peer["mu_linf"][c] / records[c]["mu_linf"] - 1.0)
    same, l2, linf = np.array(same, bool), np.array(l2), np.array(linf)
    print(f"feasible on both: {len(both)}; same IK branch (joints within "
          f"{args.same_branch:g} rad at every sample): {same.sum()}")
    print(f"mu_l2 relative difference, same branch: {summary(l2[same])}")
    print(f"mu_linf relative difference, same branch: {summary(linf[same])}")
    print(f"mu_l2 relative difference, all feasible on both: {summary(l2)}")
    if len(both):
        ranked = both[np.argsort([-records[c]["mu_l2"] for c in both])]
        peer_best = int(np.argmin(np.where(theirs, peer["rank"], len(theirs))))
        print(f"best by mu_l2: graspath {ranked[0]}, peer {peer_best}")
    if args.wrists and args.urdf:
        same_q_index(records, ours, args)


def same_q_index(records, ours, args):
    """The peer's M_T at graspath's joint paths against graspath's own M_T."""
    import pinocchio as pin

    model, tip = arm_model(args.urdf, args.tip)
    data = model.createData()
    tangents, moving = unit_tangents(np.load(args.wrists))
    diff = []
    for c in np.flatnonzero(ours):
        for i, q in enumerate(records[c]["joint_trajectory"]):
            expected = records[c]["m_t"][i]
            if not moving[c, i] or expected is None:
                continue
            jac = pin.computeFrameJacobian(model, data, np.array(q), tip,
                                           pin.LOCAL_WORLD_ALIGNED)
            diff.append(((jac.T @ tangents[c, i]) ** 2).sum() / expected - 1.0)
    print(f"M_T at graspath's joint paths, Pinocchio + numpy against graspath "
          f"({len(diff)} samples), relative difference: {summary(np.array(diff))}")


if __name__ == "__main__":
    main()
