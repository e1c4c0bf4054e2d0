"""graspath.placement_map: the same document as `graspath map`, and at one placement the
same best candidate as a plain selection of the task."""

import json
import subprocess

import pytest

import graspath
from conftest import EXAMPLES

TASK = EXAMPLES / "pick_and_place_left.yaml"


def test_the_map_equals_the_cli(graspath_bin, tmp_path):
    ours = graspath.placement_map(TASK, x=(0.65, 0.75, 2), y=(-0.1, 0.1, 2))
    out = tmp_path / "map"
    subprocess.run(
        [str(graspath_bin), "map", "--task", str(TASK), "--x", "0.65:0.75:2", "--y", "-0.1:0.1:2",
         "--out", str(out), "--quiet"],
        check=True,
    )
    cli = json.loads((out / "map.json").read_text())
    # The task's name is the path as given; everything else is the same document.
    ours.pop("task", None), cli.pop("task", None)
    assert ours == cli


def test_one_placement_is_a_plain_selection():
    task = graspath.Task.load(TASK)
    selection = graspath.select(task)
    start = task.object_poses[0][:3, 3]
    ours = graspath.placement_map(TASK, x=(start[0], start[0], 1), y=(start[1], start[1], 1))
    records = ours["placements"]
    assert len(records) == 1
    arm = records[0]["arms"][0]
    assert arm["best"]["id"] == selection.best("left")
    assert arm["feasible"] == int(selection.arrays("left")["feasible"].sum())


def test_bad_axes_are_named():
    with pytest.raises(graspath.GraspathError, match="x"):
        graspath.placement_map(TASK, x=(0.7, 0.6, 0), y=(0.0, 0.0, 1))
    with pytest.raises(graspath.GraspathError, match="cannot read|No such"):
        graspath.placement_map(EXAMPLES / "missing.yaml", x=(0.7, 0.7, 1), y=(0.0, 0.0, 1))
