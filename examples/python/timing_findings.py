"""How the time a task takes from a grasp relates to the task-relevant index: on the paper's
experiments and the 1000-candidate faces workload, the rank correlation (Spearman) between
each feasible candidate's `duration` and its `mu_l2`, and whether the fastest grasp is the one
the index picks.

Run: `python examples/python/timing_findings.py [--out timing_findings.json]` after
`pip install ./crates/graspath-py`. Prints one line per task and arm and writes the numbers as
JSON. Deterministic (the tasks' seeds).
"""

import argparse
import json
from pathlib import Path

import numpy as np

import graspath

EXAMPLES = Path(__file__).resolve().parents[1]
TASKS = [
    "pick_and_place_left.yaml",
    "pick_and_place_both.yaml",
    "pick_rotate_place_both.yaml",
    "t_shape_rotate.yaml",
    "t_shape_move.yaml",
    "t_shape_move_rotate.yaml",
    "workload_1000_faces.yaml",
    "scene/panda_shelf_pick.yaml",
]


def ranks(values):
    """Average ranks (1-based), ties sharing their mean rank."""
    order = np.argsort(values, kind="stable")
    ranked = np.empty(len(values))
    ranked[order] = np.arange(1, len(values) + 1)
    for value in np.unique(values):
        tied = values == value
        ranked[tied] = ranked[tied].mean()
    return ranked


def spearman(a, b):
    """Spearman's rank correlation of two equally long arrays."""
    ra, rb = ranks(a), ranks(b)
    return float(np.corrcoef(ra, rb)[0, 1])


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path("timing_findings.json"))
    args = parser.parse_args()
    findings = []
    for name in TASKS:
        selection = graspath.select(graspath.Task.load(EXAMPLES / name))
        for arm in selection.arms:
            a = selection.arrays(arm)
            timed = np.isfinite(a["duration"]) & np.isfinite(a["mu_l2"])
            if timed.sum() < 3:
                continue
            duration, mu = a["duration"][timed], a["mu_l2"][timed]
            ids = a["id"][timed]
            fastest = int(ids[np.argmin(duration)])
            best = selection.best(arm)
            best_duration = float(a["duration"][a["id"] == best][0]) if best is not None else None
            row = {
                "task": name,
                "arm": arm,
                "timed": int(timed.sum()),
                "spearman_duration_mu_l2": round(spearman(duration, mu), 3),
                "duration_range_s": [round(float(duration.min()), 3), round(float(duration.max()), 3)],
                "best_by_index": best,
                "best_by_index_duration_s": None if best_duration is None else round(best_duration, 3),
                "fastest": fastest,
                "fastest_is_best_by_index": fastest == best,
            }
            findings.append(row)
            print(
                f"{name} [{arm}]: {row['timed']} timed, Spearman(duration, mu_l2) = "
                f"{row['spearman_duration_mu_l2']:+.3f}, durations {row['duration_range_s'][0]}–"
                f"{row['duration_range_s'][1]} s; index's best {best} takes "
                f"{row['best_by_index_duration_s']} s, fastest {fastest}"
                f"{' (the same)' if fastest == best else ''}"
            )
    args.out.write_text(json.dumps({"findings": findings}, indent=1) + "\n")
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
