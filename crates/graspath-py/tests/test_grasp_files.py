"""``graspath.read_grasps`` on files written with numpy in the generators' published layouts,
and ``Robot.from_mjcf``, each against an oracle computed here with numpy (or the built-in arm).
"""

import json
import math

import numpy as np
import pytest

import graspath
from conftest import REPO


def rotation(axis, angle):
    """Rodrigues' formula: the rotation of ``angle`` about the unit ``axis``."""
    x, y, z = np.asarray(axis, float) / np.linalg.norm(axis)
    k = np.array([[0, -z, y], [z, 0, -x], [-y, x, 0]])
    return np.eye(3) + math.sin(angle) * k + (1 - math.cos(angle)) * k @ k


def rigid(rotation_matrix, translation):
    m = np.eye(4)
    m[:3, :3] = rotation_matrix
    m[:3, 3] = translation
    return m


def random_poses(count, seed):
    rng = np.random.default_rng(seed)
    return np.stack(
        [
            rigid(rotation(rng.normal(size=3), rng.uniform(-math.pi, math.pi)), rng.uniform(-0.2, 0.2, 3))
            for _ in range(count)
        ]
    )


def inverse(m):
    out = np.eye(4)
    out[:3, :3] = m[:3, :3].T
    out[:3, 3] = -m[:3, :3].T @ m[:3, 3]
    return out


def test_an_n_by_4_by_4_npy_gives_its_poses_as_tool_poses(tmp_path):
    poses = random_poses(7, 1)
    path = tmp_path / "grasps.npy"
    np.save(path, poses)
    g = graspath.read_grasps(path)
    assert g["format"] == "poses"
    np.testing.assert_allclose(g["object_from_wrist"], poses, rtol=0, atol=1e-12)
    np.testing.assert_array_equal(g["likelihood"], np.ones(7))
    np.testing.assert_array_equal(g["log_likelihood"], np.zeros(7))
    assert np.isnan(g["width"]).all() and g["width"].shape == (7,)
    assert np.isnan(g["contact"]).all() and g["contact"].shape == (7, 3)
    np.testing.assert_array_equal(g["id"], np.arange(7))
    assert len(g["label"]) == 7 and all(isinstance(s, str) for s in g["label"])


def test_an_npz_with_scores_and_widths_equals_the_same_grasps_as_graspath_json(tmp_path):
    poses = random_poses(5, 2)
    scores = np.array([0.9, 0.25, 0.5, 0.125, 0.75])
    widths = np.array([0.02, 0.03, 0.04, 0.05, 0.06])
    npz = tmp_path / "grasps.npz"
    np.savez(npz, grasps=poses, scores=scores, widths=widths)
    g = graspath.read_grasps(npz)
    assert g["format"] == "poses"
    np.testing.assert_allclose(g["object_from_wrist"], poses, rtol=0, atol=1e-12)
    np.testing.assert_allclose(g["likelihood"], scores, rtol=1e-14)
    np.testing.assert_allclose(g["log_likelihood"], np.log(scores), rtol=0, atol=1e-14)
    np.testing.assert_allclose(g["width"], widths, rtol=0, atol=0)
    # The same poses and likelihoods as graspath's own JSON.
    doc = {
        "format": "graspath-candidates",
        "version": 1,
        "frame": "object",
        "candidates": [
            {"id": i, "object_from_wrist": p.tolist(), "likelihood": float(s)}
            for i, (p, s) in enumerate(zip(poses, scores))
        ],
    }
    path = tmp_path / "grasps.json"
    path.write_text(json.dumps(doc))
    j = graspath.read_grasps(path)
    assert j["format"] == "graspath"
    np.testing.assert_allclose(j["object_from_wrist"], g["object_from_wrist"], rtol=0, atol=1e-12)
    np.testing.assert_allclose(j["likelihood"], g["likelihood"], rtol=1e-14)


def test_camera_and_world_frames_land_where_the_composed_transforms_put_them(tmp_path):
    camera_from_grasp = random_poses(4, 3)
    path = tmp_path / "camera.npy"
    np.save(path, camera_from_grasp)
    world_from_object = rigid(rotation([0, 0, 1], 0.7), [0.5, -0.1, 0.2])
    world_from_camera = rigid(rotation([1, 0.2, -0.3], 2.1), [0.9, 0.4, 1.3])
    expected = np.stack([inverse(world_from_object) @ world_from_camera @ p for p in camera_from_grasp])
    g = graspath.read_grasps(
        path, frame="camera", world_from_camera=world_from_camera, world_from_object=world_from_object
    )
    np.testing.assert_allclose(g["object_from_wrist"], expected, rtol=0, atol=1e-12)
    camera_from_object = inverse(world_from_camera) @ world_from_object
    g = graspath.read_grasps(path, frame="camera", camera_from_object=camera_from_object)
    np.testing.assert_allclose(g["object_from_wrist"], expected, rtol=0, atol=1e-12)
    # Poses given in the world frame.
    g = graspath.read_grasps(path, frame="world", world_from_object=world_from_object)
    expected = np.stack([inverse(world_from_object) @ p for p in camera_from_grasp])
    np.testing.assert_allclose(g["object_from_wrist"], expected, rtol=0, atol=1e-12)
    # A gripper frame mapped to the tool frame.
    gripper_from_tool = rigid(rotation([0, 1, 0], math.pi / 2), [0, 0, 0.1])
    g = graspath.read_grasps(path, gripper_from_tool=gripper_from_tool)
    np.testing.assert_allclose(
        g["object_from_wrist"], camera_from_grasp @ gripper_from_tool, rtol=0, atol=1e-12
    )


def test_graspnet_rows_are_camera_grasps_turned_into_the_tool_frame(tmp_path):
    # GraspGroup.save_npy's N×17 rows: score, width, height, depth, rotation (9), translation, object id.
    poses = random_poses(3, 4)
    rows = np.zeros((3, 17))
    rows[:, 0] = [0.8, 0.4, 0.2]
    rows[:, 1] = [0.03, 0.05, 0.07]
    rows[:, 2] = 0.02
    rows[:, 3] = 0.01
    rows[:, 4:13] = poses[:, :3, :3].reshape(3, 9)
    rows[:, 13:16] = poses[:, :3, 3]
    rows[:, 16] = -1
    path = tmp_path / "anygrasp.npy"
    np.save(path, rows)
    camera_from_object = rigid(rotation([0.3, 1, 0], 0.4), [0.0, 0.1, 0.6])
    g = graspath.read_grasps(path, camera_from_object=camera_from_object)
    assert g["format"] == "graspnet"
    # GraspNet's gripper approaches along its x and closes along y: the tool (z approach, y
    # closing) is the gripper turned 90° about y.
    gripper_from_tool = rigid(rotation([0, 1, 0], math.pi / 2), [0, 0, 0])
    expected = np.stack([inverse(camera_from_object) @ p @ gripper_from_tool for p in poses])
    np.testing.assert_allclose(g["object_from_wrist"], expected, rtol=0, atol=1e-12)
    np.testing.assert_allclose(g["likelihood"], rows[:, 0], rtol=1e-14)
    np.testing.assert_array_equal(g["width"], rows[:, 1])


def test_m2t2_objects_by_name_are_world_grasps_and_a_camera_pose_needs_frame_camera(tmp_path):
    # M2T2's demo.py keeps grasps, grasp_confidence, grasp_contacts as one array per object
    # (m2t2/action_decoder.py ActionDecoder.forward: (n, 4, 4), (n,), (n, 3), float32), in the
    # world frame (config.yaml eval.world_coord: True); saved here keyed by demo.py's object names.
    poses = [random_poses(2, 6).astype(np.float32), random_poses(1, 7).astype(np.float32)]
    confidence = [np.array([0.5, 0.25], np.float32), np.array([0.75], np.float32)]
    contacts = [np.full((2, 3), 0.01, np.float32), np.full((1, 3), -0.02, np.float32)]
    names = ["object_00", "object_01"]
    path = tmp_path / "m2t2.npz"
    np.savez(
        path,
        grasps=dict(zip(names, poses)),
        grasp_confidence=dict(zip(names, confidence)),
        grasp_contacts=dict(zip(names, contacts)),
    )
    world_from_object = rigid(rotation([0, 0, 1], 0.3), [0.5, -0.1, 0.02])
    g = graspath.read_grasps(path, world_from_object=world_from_object)
    assert g["format"] == "m2t2"
    # The Franka hand frame (fingers along x, approach z) to the tool frame, TCP 0.1034 m along z.
    hand_from_tool = rigid(rotation([0, 0, 1], -math.pi / 2), [0, 0, 0.1034])
    world = np.concatenate(poses).astype(float)
    expected = np.stack([inverse(world_from_object) @ p @ hand_from_tool for p in world])
    np.testing.assert_allclose(g["object_from_wrist"], expected, rtol=0, atol=1e-6)
    np.testing.assert_allclose(g["likelihood"], np.concatenate(confidence), rtol=1e-7)
    assert list(g["label"]) == ["object_00 grasp 0", "object_00 grasp 1", "object_01 grasp 0"]
    with pytest.raises(graspath.GraspathError, match="frame is world"):
        graspath.read_grasps(path, world_from_camera=np.eye(4))


@pytest.mark.parametrize(
    "make, kwargs, message",
    [
        (lambda p: np.save(p, np.zeros((3, 3, 3))), {}, "(3, 3, 3)"),
        (lambda p: np.save(p, np.zeros((3, 3, 3))), {"format": "poses"}, "(3, 3, 3)"),
        (lambda p: np.save(p, np.tile(np.diag([2.0, 1.0, 1.0, 1.0]), (2, 1, 1))), {}, "[0]"),
        (lambda p: np.save(p, random_poses(2, 5)), {"format": "yaml"}, "format: 'yaml' is not one of graspath"),
        (lambda p: np.save(p, random_poses(2, 5)), {"frame": "camera"}, "world_from_camera"),
        (lambda p: np.save(p, random_poses(2, 5)), {"frame": "tool"}, "frame: 'tool' is not one of object, world, camera"),
        (lambda p: np.save(p, random_poses(2, 5)), {"world_from_camera": np.eye(3)}, "world_from_camera"),
    ],
)
def test_bad_grasp_files_and_options_raise_one_clear_error(tmp_path, make, kwargs, message):
    path = tmp_path / "bad.npy"
    make(path)
    with pytest.raises(graspath.GraspathError) as info:
        graspath.read_grasps(path, **kwargs)
    assert message in str(info.value)


def test_a_missing_file_is_a_graspath_error_naming_it(tmp_path):
    with pytest.raises(graspath.GraspathError, match="nothing.npy"):
        graspath.read_grasps(tmp_path / "nothing.npy")


def test_mjcf_ur5_has_the_kinematics_of_the_builtin_ur5():
    mjcf = graspath.Robot.from_mjcf(REPO / "crates/graspath/tests/data/mjcf/ur5.xml", "base", "tool0")
    builtin = graspath.Robot.builtin("ur5")
    assert mjcf.dof == builtin.dof == 6
    rng = np.random.default_rng(7)
    q = rng.uniform(-math.pi, math.pi, size=(50, 6))
    np.testing.assert_allclose(mjcf.fk(q), builtin.fk(q), rtol=0, atol=1e-9)
    np.testing.assert_allclose(mjcf.jacobian(q), builtin.jacobian(q), rtol=0, atol=1e-9)
    np.testing.assert_allclose(mjcf.lower, builtin.lower, rtol=0, atol=1e-9)
    np.testing.assert_allclose(mjcf.upper, builtin.upper, rtol=0, atol=1e-9)
    # A tool offset follows the tip: fk(q) · tip_from_tool.
    tool = rigid(np.eye(3), [0, 0, 0.15])
    with_tool = graspath.Robot.from_mjcf(REPO / "crates/graspath/tests/data/mjcf/ur5.xml", "base", "tool0", tool=tool)
    np.testing.assert_allclose(with_tool.fk(q), builtin.fk(q) @ tool, rtol=0, atol=1e-9)


def test_mjcf_errors_name_the_body(tmp_path):
    with pytest.raises(graspath.GraspathError, match="no_such_body"):
        graspath.Robot.from_mjcf(REPO / "crates/graspath/tests/data/mjcf/ur5.xml", "base", "no_such_body")
    bad = tmp_path / "ball.xml"
    bad.write_text(
        '<mujoco><worldbody><body name="a"><body name="b"><joint name="j" type="ball"/>'
        '<geom type="sphere" size="0.1"/></body></body></worldbody></mujoco>'
    )
    with pytest.raises(graspath.GraspathError, match="ball"):
        graspath.Robot.from_mjcf(bad, "a", "b")
