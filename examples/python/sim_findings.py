"""The paper's experiments in physics: for each task, the top 5 grasps by the task-relevant
index, the classical index's choice (the largest Yoshikawa manipulability at the grasp), the
likelihood's choice and 10 random feasible grasps are executed in MuJoCo
(:mod:`graspath.sim`), each with a friction grip and welded, at the planned speed and at half
of it. Prints a Markdown table of success rates per task, group and mode, and writes every
experiment's ``sim.json`` document into one JSON file.

Run: ``python examples/python/sim_findings.py [--out sim_findings.json]
[--findings DEMO/findings.json]`` after ``pip install './crates/graspath-py[sim]'``. With
``--findings``, the summary is added to a ``graspath demo`` output's ``findings.json`` under
``physics``. Deterministic: the same inputs give the same bytes.

The world each task is simulated in (docs/simulation.md):

* Baxter's arms carry their own weight outside the motors (``arm_gravity_compensation``): the
  real arm's shoulder spring, which its published 50 N·m limit leaves out.
* Objects without a mass in the task weigh what a box of light wood (500 kg/m³) would: the
  cuboid 1.2 kg, the T-shape 0.36 kg. The heavy variant gives the Panda shelf box 2 kg, so
  that its motions are timed against the joint torque limits.
* Tasks without a table (the paper's own, without scene) hold the object where it starts until
  the gripper closes, and are judged where the object is when the gripper opens at the place.
"""

import argparse
import json
import os
import sys
import tempfile
from pathlib import Path

import graspath
from graspath import sim

EXAMPLES = Path(__file__).resolve().parents[1]

#: (name, task file, options, heavy-variant text substitution)
EXPERIMENTS = [
    ("Baxter Pick-and-Place, left arm, on the table", "scene/pick_and_place_left_on_table.yaml", True, None),
    ("Baxter Pick-and-Place, two arms, on the table", "scene/pick_and_place_both_on_table.yaml", True, None),
    ("Baxter Pick-and-Place, left arm (paper, no table)", "pick_and_place_left.yaml", True, None),
    ("Baxter Pick-Rotate-Place, two arms (paper)", "pick_rotate_place_both.yaml", True, None),
    ("Baxter T-shape move", "t_shape_move.yaml", True, None),
    ("Baxter T-shape rotate", "t_shape_rotate.yaml", True, None),
    ("Baxter T-shape move and rotate", "t_shape_move_rotate.yaml", True, None),
    ("Panda shelf pick", "scene/panda_shelf_pick.yaml", False, None),
    (
        "Panda shelf pick, 2 kg box (torque-limited timing)",
        "scene/panda_shelf_pick.yaml",
        False,
        ("shape: { box: { size: [0.05, 0.05, 0.20] } }", "shape: { box: { size: [0.05, 0.05, 0.20] } }\n  mass: 2.0"),
    ),
]


def load(relative: str, substitution, folder: Path) -> graspath.Task:
    path = EXAMPLES / relative
    if substitution is None:
        return graspath.Task.load(path)
    old, new = substitution
    text = path.read_text()
    assert old in text, f"{relative} no longer holds {old!r}"
    variant = folder / ("heavy_" + path.name)
    variant.write_text(text.replace(old, new))
    return graspath.Task.load(variant)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", default="sim_findings.json")
    parser.add_argument("--findings", help="a graspath demo findings.json to add the summary to")
    parser.add_argument("-k", type=int, default=5)
    parser.add_argument("-n", type=int, default=10)
    args = parser.parse_args()
    documents = []
    rows = []
    with tempfile.TemporaryDirectory() as folder:
        for name, relative, gravity_compensation, substitution in EXPERIMENTS:
            task = load(relative, substitution, Path(folder))
            options = sim.SimOptions(arm_gravity_compensation=gravity_compensation)
            document = sim.experiment(task, k=args.k, n_random=args.n, options=options)
            document["task"] = relative if substitution is None else f"{relative} (2 kg)"
            documents.append({"experiment": name, **document})
            for s in document["summary"]:
                rows.append((name, s))
            print(f"{name}: done", file=sys.stderr)
    print("| task | grasps | mode | planned speed | half speed |")
    print("|---|---|---|---|---|")
    for name, _, _, _ in EXPERIMENTS:
        for group in ("index", "classical", "likelihood", "random"):
            for mode in ("friction", "weld"):
                cells = {
                    s["slowdown"]: s
                    for n, s in rows
                    if n == name and s["group"] == group and s["mode"] == mode
                }
                if not cells:
                    continue
                text = [
                    f"{cells[k]['successes']}/{cells[k]['runs']}" if k in cells else "–"
                    for k in (1.0, 2.0)
                ]
                print(f"| {name} | {group} | {mode} | {text[0]} | {text[1]} |")
    out = {"experiments": documents}
    Path(args.out).write_text(json.dumps(out, indent=2, sort_keys=True) + "\n")
    if args.findings:
        findings = json.loads(Path(args.findings).read_text())
        findings["physics"] = [
            {"experiment": d["experiment"], "task": d["task"], "summary": d["summary"]}
            for d in documents
        ]
        tmp = args.findings + ".tmp"
        Path(tmp).write_text(json.dumps(findings, indent=2) + "\n")
        os.replace(tmp, args.findings)
    return 0


if __name__ == "__main__":
    sys.exit(main())
