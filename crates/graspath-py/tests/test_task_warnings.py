"""``Task.warnings``: values that are probably mistakes, named by their task-file field, the
same as the command line prints and ``summary.json`` holds."""

from pathlib import Path

import graspath

REPO = Path(__file__).resolve().parents[3]
LEFT = REPO / "examples" / "pick_and_place_left.yaml"


def test_a_radians_field_holding_degrees_is_a_warning_and_the_task_still_loads(tmp_path):
    text = LEFT.read_text()
    pose = "pose: { xyz: [0.75, 0.0, -0.10] }"
    assert pose in text
    path = tmp_path / "task.yaml"
    path.write_text(text.replace(pose, "pose: { xyz: [0.75, 0.0, -0.10], rpy: [0, 0, 90] }"))
    task = graspath.Task.load(path)
    assert [field for field, _ in task.warnings] == ["object.pose.rpy"]
    assert "looks like degrees" in task.warnings[0][1]
    selection = graspath.select(task)
    assert selection.summary["warnings"] == [
        {"field": field, "message": message} for field, message in task.warnings
    ]


def test_the_shipped_example_has_no_warning():
    task = graspath.Task.load(LEFT)
    assert task.warnings == []
    assert "warnings" not in graspath.select(task).summary
