# %% [markdown]
# # Paper §IV-A, Fig. 5: which edge grasp lets Baxter's left arm pick, move and place the box?
#
# Ghalamzan et al., "Task-relevant grasp selection", IROS 2016. The cuboid stands in front of
# the robot; 21 top grasps lie along its top edge, from the left-most (+y) to the right-most
# (−y) contact. The task lifts the box 0.2 m, moves it 0.3 m to the left and places it 0.2 m
# lower (`examples/pick_and_place_left.yaml`). For each grasp we follow the wrist path with
# trajectory IK, evaluate the task-relevant manipulability M_T along it, and plot the paper's
# two norms, normalised: μ_l2 = ‖M‖₂ (maximise) and μ_l∞ = max 1/M_T (a constraint).
#
# Run: `python examples/python/fig5_pick_and_place.py [--task FILE] [--out PNG]`
# (after `pip install ./crates/graspath-py matplotlib`).

# %%
import argparse
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import graspath

here = Path(__file__).resolve().parent
parser = argparse.ArgumentParser(description=__doc__)
parser.add_argument("--task", type=Path, default=here.parent / "pick_and_place_left.yaml")
parser.add_argument("--arm", default="left")
parser.add_argument("--out", type=Path, default=Path("fig5_pick_and_place_left.png"))
args = parser.parse_args()

# %% Load the task and look at it.
task = graspath.Task.load(args.task)
print(task)
print("steps:", task.step_labels, "| samples:", len(task.times), "| duration:", task.times[-1], "s")
print("object path z (m):", np.round(task.object_poses[:, 2, 3], 3))

# %% Score and rank every candidate (trajectory IK, M_T, norms), as `graspath select` does.
selection = graspath.select(task)
a = selection.arrays(args.arm)
contact_y = a["contact"][:, 1]
feasible = a["feasible"]
print(f"{feasible.sum()} of {len(feasible)} grasps are feasible along the whole path")

# %% The table the paper's figure summarises.
order = np.argsort(-contact_y)  # left-most (+y) first, as in the paper
print(f"{'id':>3} {'contact y':>9} {'feasible':>8} {'mu_l2':>8} {'mu_linf':>9} {'rank':>4}")
for i in order:
    print(f"{a['id'][i]:>3} {contact_y[i]:>9.3f} {str(feasible[i]):>8} {a['mu_l2'][i]:>8.4f} "
          f"{a['mu_linf'][i]:>9.3f} {'-' if np.isnan(a['rank'][i]) else int(a['rank'][i]):>4}")
best = selection.best(args.arm)
record = next(r for r in selection.candidates if r["id"] == best and r["arm"] == args.arm)
print(f"selected: candidate {best} ({record['label']}), mu_l2 = {record['mu_l2']:.4f}, "
      f"mu_linf = {record['mu_linf']:.3f}")

# %% Fig. 5: normalised μ_l2 and μ_l∞ against the contact point along the edge.
l2 = a["mu_l2"] / np.nanmax(a["mu_l2"])
finite_linf = np.where(np.isfinite(a["mu_linf"]), a["mu_linf"], np.nan)
linf = finite_linf / np.nanmax(finite_linf)
fig, ax = plt.subplots(figsize=(6.4, 3.8), dpi=120)
ax.plot(contact_y[order], l2[order], "o-", label=r"$\mu_{l_2}$ (normalised)")
ax.plot(contact_y[order], linf[order], "s--", label=r"$\mu_{l_\infty}$ (normalised)")
if (~feasible).any():
    ax.plot(contact_y[~feasible], np.zeros((~feasible).sum()), "x", color="red",
            label="infeasible along the path")
ax.axvline(contact_y[list(a["id"]).index(best)], color="gray", lw=0.8, ls=":",
           label=f"selected (id {best})")
ax.invert_xaxis()  # left-most contact (+y) on the left, as seen by the robot
ax.set_xlabel("contact point along the top edge, y in the object frame (m)")
ax.set_ylabel("normalised value")
ax.set_title("Pick-and-place with Baxter's left arm (paper Fig. 5)")
ax.legend(fontsize=8, loc="best")
fig.tight_layout()
fig.savefig(args.out)
print("wrote", args.out)
