"""The exceptions have the library's kinds: a missing file is a ``FileNotFoundError``, a file that
cannot be read or written an ``OSError``, bad content a ``ValueError`` naming the file and the
field; every one is a ``graspath.GraspathError``, its message the library's whole message."""

import errno

import pytest

import graspath

TASK = """
robot: {{ builtin: baxter }}
arms: left
object: {{ pose: {{ xyz: [0.75, 0.0, -0.10], quaternion: {quaternion} }}, shape: {{ box: {{ size: [0.06, 0.40, 0.10] }} }} }}
candidates: {{ family: {{ edge: {{ count: 3 }} }} }}
trajectory: {{ steps: [ {{ lift: 0.2 }} ] }}
"""


def test_a_missing_task_file_is_a_file_not_found_error(tmp_path):
    missing = tmp_path / "missing.yaml"
    with pytest.raises(FileNotFoundError) as raised:
        graspath.Task.load(missing)
    e = raised.value
    assert isinstance(e, graspath.GraspathFileNotFoundError)
    assert isinstance(e, graspath.GraspathFileError)
    assert isinstance(e, OSError)
    assert isinstance(e, graspath.GraspathError)
    assert not isinstance(e, ValueError)
    assert e.file == str(missing)
    assert e.field is None
    assert e.errno == errno.ENOENT
    # The message names the file and keeps the operating system's.
    assert str(e).startswith(f"{missing}: cannot read: ")
    assert "No such file" in str(e)


def test_a_missing_robot_file_is_a_file_not_found_error(tmp_path):
    missing = tmp_path / "arm.urdf"
    with pytest.raises(graspath.GraspathFileNotFoundError, match="arm.urdf: cannot read: ") as raised:
        graspath.Robot.from_urdf(missing, "base", "tip")
    assert raised.value.file == str(missing)


def test_a_missing_candidate_file_is_a_file_not_found_error(tmp_path):
    """A task's candidate file and a grasp file read alone: the operating system's error is
    kept, so a missing file is a FileNotFoundError naming the file, as a missing task is."""
    missing = tmp_path / "nowhere.json"
    with pytest.raises(graspath.GraspathFileNotFoundError) as raised:
        graspath.read_grasps(missing)
    e = raised.value
    assert isinstance(e, FileNotFoundError) and not isinstance(e, ValueError)
    assert e.file == str(missing)
    assert e.field == "file"
    assert e.errno == errno.ENOENT
    assert str(e).startswith(f"{missing}: file: cannot read: ")
    task = tmp_path / "t.yaml"
    task.write_text(
        TASK.format(quaternion="[0, 0, 0, 1]").replace("{ family: { edge: { count: 3 } } }", "{ file: nowhere.json }")
    )
    with pytest.raises(graspath.GraspathFileNotFoundError) as raised:
        graspath.Task.load(task)
    assert raised.value.file == str(missing)
    assert raised.value.errno == errno.ENOENT
    # A folder where the file should be is a file error too, not bad content.
    with pytest.raises(graspath.GraspathFileError) as raised:
        graspath.read_grasps(tmp_path)
    assert not isinstance(raised.value, (FileNotFoundError, ValueError))


def test_a_candidate_file_over_its_cap_is_a_value_error(tmp_path):
    """The documented cap of a candidate file is 1 GiB; a sparse file one byte larger takes no
    disk space and is refused before it is read."""
    huge = tmp_path / "huge.json"
    with open(huge, "wb") as f:
        f.truncate((1 << 30) + 1)
    with pytest.raises(graspath.GraspathValueError, match="is larger than 1073741824 bytes") as raised:
        graspath.read_grasps(huge)
    assert raised.value.file == str(huge)


def test_a_folder_read_as_a_file_is_an_os_error_not_a_missing_file(tmp_path):
    with pytest.raises(graspath.GraspathFileError) as raised:
        graspath.Task.load(tmp_path)
    assert not isinstance(raised.value, FileNotFoundError)
    assert raised.value.file == str(tmp_path)


def test_a_bad_field_is_a_value_error_naming_the_file_and_the_field(tmp_path):
    task = tmp_path / "t.yaml"
    task.write_text(TASK.format(quaternion="[0, 0, 0, 2]"))
    with pytest.raises(ValueError) as raised:
        graspath.Task.load(task)
    e = raised.value
    assert isinstance(e, graspath.GraspathValueError)
    assert isinstance(e, graspath.GraspathError)
    assert not isinstance(e, OSError)
    assert e.file == str(task)
    assert e.field == "object.pose.quaternion"
    assert "must be a unit quaternion" in str(e)


def test_a_file_a_task_names_is_named_with_its_own_field(tmp_path):
    """The most specific file at fault: the candidate file the task names, not the task."""
    task = tmp_path / "t.yaml"
    task.write_text(TASK.format(quaternion="[0, 0, 0, 1]").replace("{ family: { edge: { count: 3 } } }", "{ file: nowhere.json }"))
    with pytest.raises(graspath.GraspathError, match="nowhere.json") as raised:
        graspath.Task.load(task)
    assert raised.value.file is not None


def test_an_argument_is_a_value_error_without_a_file():
    task = graspath.Task.from_dict(
        {
            "robot": {"builtin": "baxter"},
            "arms": "left",
            "object": {"pose": {"xyz": [0.75, 0.0, -0.1]}, "shape": {"box": {"size": [0.06, 0.4, 0.1]}}},
            "candidates": {"family": {"edge": {"count": 3}}},
            "trajectory": {"steps": [{"lift": 0.2}]},
        }
    )
    with pytest.raises(graspath.GraspathValueError, match="top_k must be at least 1") as raised:
        graspath.select_batch([task], top_k=0)
    assert raised.value.file is None and raised.value.field is None


def test_an_existing_output_folder_is_refused_as_a_file_error(tmp_path):
    source = tmp_path / "t.yaml"
    source.write_text(TASK.format(quaternion="[0, 0, 0, 1]"))
    selection = graspath.select(graspath.Task.load(source))
    out = tmp_path / "out"
    out.mkdir()
    (out / "keep").write_text("mine")
    with pytest.raises(graspath.GraspathFileError, match="the folder exists and is not empty") as raised:
        selection.write(out)
    assert raised.value.file == str(out)
    assert (out / "keep").read_text() == "mine"
