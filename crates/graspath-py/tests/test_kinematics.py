"""Forward kinematics, Jacobians and indices: shapes and dtypes, batch = one at a time, and
independent oracles (finite differences of FK, numpy's SVD, the URDF Baxter vs the built-in)."""

import numpy as np
import pytest

import graspath

RNG = np.random.default_rng(7)


def random_configurations(robot, n):
    lower, upper = robot.lower, robot.upper
    return lower + (upper - lower) * RNG.random((n, robot.dof))


@pytest.fixture(scope="module")
def left():
    return graspath.Robot.baxter("left")


def test_robot_description(left):
    assert left.dof == 7
    assert left.name == "base->left_gripper"
    assert left.joint_names[0] == "left_s0" and left.joint_names[-1] == "left_w2"
    assert left.lower.dtype == np.float64 and left.lower.shape == (7,)
    assert np.all(left.lower < left.upper)
    mid = left.mid_configuration()
    np.testing.assert_allclose(mid, 0.5 * (left.lower + left.upper))
    assert left.within_limits(mid) is True
    flags = left.within_limits(np.stack([mid, left.upper + 0.1]))
    assert flags.dtype == np.bool_ and flags.tolist() == [True, False]
    assert "left_gripper" in repr(left)


def test_shapes_and_dtypes(left):
    q = random_configurations(left, 5)
    pose = left.fk(q[0])
    assert pose.shape == (4, 4) and pose.dtype == np.float64
    poses = left.fk(q)
    assert poses.shape == (5, 4, 4) and poses.dtype == np.float64
    jac = left.jacobian(q[0])
    assert jac.shape == (6, 7) and jac.dtype == np.float64
    jacs = left.jacobian(q)
    assert jacs.shape == (5, 6, 7)
    p2, j2 = left.fk_jacobian(q)
    assert p2.shape == (5, 4, 4) and j2.shape == (5, 6, 7)
    assert p2.flags["C_CONTIGUOUS"] and j2.flags["C_CONTIGUOUS"]
    # Lists, ints and non-contiguous views are accepted.
    np.testing.assert_array_equal(left.fk([0, 0, 0, 0, 0, 0, 0]), left.fk(np.zeros(7)))
    wide = np.asfortranarray(np.repeat(q, 2, axis=0))[::2]
    np.testing.assert_array_equal(left.fk(wide), poses)
    assert left.fk(np.zeros((0, 7))).shape == (0, 4, 4)


def test_batch_equals_one_at_a_time(left):
    q = random_configurations(left, 1000)  # several rayon chunks
    poses, jacs = left.fk_jacobian(q)
    for i in range(0, 1000, 37):
        pose, jac = left.fk_jacobian(q[i])
        np.testing.assert_array_equal(poses[i], pose)
        np.testing.assert_array_equal(jacs[i], jac)
        np.testing.assert_array_equal(left.fk(q[i]), pose)
    np.testing.assert_array_equal(left.fk(q), poses)
    np.testing.assert_array_equal(left.jacobian(q), jacs)
    idx = left.indices(q[:50], part="translation")
    for i in range(0, 50, 7):
        one = left.indices(q[i], part="translation")
        assert one["yoshikawa"] == idx["yoshikawa"][i]
        np.testing.assert_array_equal(one["singular_values"], idx["singular_values"][i])


def test_large_batch_new_arrays_equal_out_arrays(left):
    # Tens of megabytes: the new arrays get their pages mapped before they are written.
    q = random_configurations(left, 50_000)
    poses, jacs = left.fk_jacobian(q)
    p_out, j_out = np.full((50_000, 4, 4), np.nan), np.full((50_000, 6, 7), np.nan)
    left.fk_jacobian(q, out=(p_out, j_out))
    np.testing.assert_array_equal(poses, p_out)
    np.testing.assert_array_equal(jacs, j_out)
    for i in range(0, 50_000, 4999):
        pose, jac = left.fk_jacobian(q[i])
        np.testing.assert_array_equal(poses[i], pose)
        np.testing.assert_array_equal(jacs[i], jac)


def test_fk_is_a_rigid_transform(left):
    for pose in left.fk(random_configurations(left, 20)):
        rotation = pose[:3, :3]
        np.testing.assert_allclose(rotation.T @ rotation, np.eye(3), atol=1e-12)
        assert np.linalg.det(rotation) == pytest.approx(1.0)
        np.testing.assert_array_equal(pose[3], [0, 0, 0, 1])


def rotation_log(r):
    angle = np.arccos(np.clip((np.trace(r) - 1) / 2, -1, 1))
    if angle < 1e-12:
        return np.zeros(3)
    w = np.array([r[2, 1] - r[1, 2], r[0, 2] - r[2, 0], r[1, 0] - r[0, 1]])
    return angle / (2 * np.sin(angle)) * w


def test_jacobian_matches_finite_differences_of_fk(left):
    """Oracle: central differences of FK (linear rows) and of the rotation (angular rows)."""
    h = 1e-6
    for q in random_configurations(left, 10):
        jac = left.jacobian(q)
        for j in range(left.dof):
            dq = np.zeros(left.dof)
            dq[j] = h
            plus, minus = left.fk(q + dq), left.fk(q - dq)
            v = (plus[:3, 3] - minus[:3, 3]) / (2 * h)
            w = rotation_log(plus[:3, :3] @ minus[:3, :3].T) / (2 * h)
            np.testing.assert_allclose(jac[:3, j], v, atol=1e-7)
            np.testing.assert_allclose(jac[3:, j], w, atol=1e-7)


def test_indices_match_numpy(left):
    """Oracle: numpy's SVD of the Jacobian rows, and uᵀ J Jᵀ u computed in numpy."""
    q = random_configurations(left, 30)
    jacs = left.jacobian(q)
    for part, rows in (("full", slice(0, 6)), ("translation", slice(0, 3)), ("rotation", slice(3, 6))):
        idx = left.indices(q, part=part)
        for key in ("yoshikawa", "inverse_condition", "inverse_condition_squared"):
            assert idx[key].shape == (30,) and idx[key].dtype == np.float64
        for i, jac in enumerate(jacs):
            s = np.linalg.svd(jac[rows], compute_uv=False)
            np.testing.assert_allclose(idx["singular_values"][i], s, rtol=1e-9)
            assert idx["yoshikawa"][i] == pytest.approx(np.sqrt(np.linalg.det(jac[rows] @ jac[rows].T)), rel=1e-7)
            assert idx["inverse_condition"][i] == pytest.approx(s[-1] / s[0], rel=1e-9)
            assert idx["inverse_condition_squared"][i] == pytest.approx((s[-1] / s[0]) ** 2, rel=1e-9)
    u = RNG.normal(size=6)
    m_t = left.task_relevant(q, u)
    unit = u / np.linalg.norm(u)
    expected = np.array([unit @ jac @ jac.T @ unit for jac in jacs])
    np.testing.assert_allclose(m_t, expected, rtol=1e-12)
    # One direction per configuration.
    us = RNG.normal(size=(30, 3))
    m_v = left.task_relevant(q, us, part="translation")
    for i, jac in enumerate(jacs):
        ui = us[i] / np.linalg.norm(us[i])
        assert m_v[i] == pytest.approx(ui @ jac[:3] @ jac[:3].T @ ui, rel=1e-12)
        ratio = left.velocity_transmission_ratio(q[i], us[i], part="translation")
        assert ratio == pytest.approx(1 / np.sqrt(ui @ np.linalg.inv(jac[:3] @ jac[:3].T) @ ui), rel=1e-8)
    assert isinstance(left.task_relevant(q[0], u), float)


def test_joint_origins_end_at_the_tip(left):
    q = random_configurations(left, 1)[0]
    points = left.joint_origins(q)
    assert points.shape == (left.dof + 2, 3)
    np.testing.assert_allclose(points[-1], left.fk(q)[:3, 3], atol=1e-12)


def test_tool_offset_moves_the_tip(left):
    tool = np.eye(4)
    tool[2, 3] = 0.1
    with_tool = graspath.Robot.baxter("left", tool=tool)
    q = random_configurations(left, 4)
    np.testing.assert_allclose(with_tool.fk(q), left.fk(q) @ tool, atol=1e-12)


def test_urdf_baxter_equals_the_built_in(shared):
    urdf = graspath.Robot.from_urdf(shared / "robots" / "baxter.urdf", "base", "right_gripper")
    built_in = graspath.Robot.baxter("right")
    assert urdf.joint_names == built_in.joint_names
    q = random_configurations(built_in, 50)
    p1, j1 = urdf.fk_jacobian(q)
    p2, j2 = built_in.fk_jacobian(q)
    np.testing.assert_allclose(p1, p2, atol=1e-9)
    np.testing.assert_allclose(j1, j2, atol=1e-9)


def test_urdf_from_string_equals_from_file(shared):
    path = shared / "robots" / "panda.urdf"
    a = graspath.Robot.from_urdf(path, "panda_link0", "panda_hand_tcp")
    b = graspath.Robot.from_urdf_string(path.read_text(), "panda_link0", "panda_hand_tcp")
    q = random_configurations(a, 10)
    np.testing.assert_array_equal(a.fk(q), b.fk(q))


class TestErrors:
    def test_wrong_dof(self, left):
        with pytest.raises(graspath.GraspathError, match=r"q has shape \(6,\) but the chain 'base->left_gripper' has 7 joints"):
            left.fk(np.zeros(6))
        with pytest.raises(ValueError, match=r"\(3, 8\)"):
            left.jacobian(np.zeros((3, 8)))
        with pytest.raises(graspath.GraspathError):
            left.fk(np.zeros((2, 3, 7)))

    def test_non_finite(self, left):
        q = np.zeros((4, 7))
        q[2, 5] = np.nan
        with pytest.raises(graspath.GraspathError, match=r"q\[2, 5\] is not a finite number"):
            left.fk_jacobian(q)
        with pytest.raises(graspath.GraspathError, match=r"q\[1\] is not a finite number"):
            left.fk([0, np.inf, 0, 0, 0, 0, 0])

    def test_not_numbers(self, left):
        with pytest.raises((TypeError, ValueError)):
            left.fk(["a"] * 7)

    def test_bad_part_and_direction(self, left):
        with pytest.raises(graspath.GraspathError, match="part: 'twist' is not one of full, translation, rotation"):
            left.indices(np.zeros(7), part="twist")
        with pytest.raises(graspath.GraspathError, match="non-zero"):
            left.task_relevant(np.zeros(7), np.zeros(6))
        with pytest.raises(graspath.GraspathError, match=r"\(3,\)"):
            left.task_relevant(np.zeros(7), np.ones(6), part="translation")

    def test_unknown_arm_and_links(self, shared):
        with pytest.raises(graspath.GraspathError, match=r"no chain named 'middle' \(chains: left, right\)"):
            graspath.Robot.baxter("middle")
        with pytest.raises(graspath.GraspathError, match="no link named 'left_grippr'.*did you mean: left_gripper"):
            graspath.Robot.from_urdf(shared / "robots" / "baxter.urdf", "base", "left_grippr")
        with pytest.raises(graspath.GraspathError, match="cannot read"):
            graspath.Robot.from_urdf(shared / "robots" / "missing.urdf", "a", "b")

    def test_bad_tool(self):
        tool = np.eye(4)
        tool[0, 0] = 2.0
        with pytest.raises(graspath.GraspathError, match="tool: the 3×3 rotation block is not orthonormal"):
            graspath.Robot.baxter("left", tool=tool)

    def test_bad_input_is_a_value_error(self):
        tool = np.eye(4)
        tool[0, 0] = 2.0
        with pytest.raises(ValueError) as raised:
            graspath.Robot.baxter("left", tool=tool)
        assert isinstance(raised.value, graspath.GraspathValueError)
        assert isinstance(raised.value, graspath.GraspathError)


def test_out_arrays_are_filled_and_returned(left):
    q = random_configurations(left, 300)
    poses, jacs = left.fk_jacobian(q)
    p_out, j_out = np.full((300, 4, 4), np.nan), np.full((300, 6, 7), np.nan)
    p_ret, j_ret = left.fk_jacobian(q, out=(p_out, j_out))
    assert p_ret is p_out and j_ret is j_out
    np.testing.assert_array_equal(p_out, poses)
    np.testing.assert_array_equal(j_out, jacs)
    f_out = np.empty((300, 4, 4))
    assert left.fk(q, out=f_out) is f_out
    np.testing.assert_array_equal(f_out, poses)
    one = np.empty((6, 7))
    assert left.jacobian(q[0], out=one) is one
    np.testing.assert_array_equal(one, jacs[0])
    with pytest.raises(graspath.GraspathError, match=r"out \(poses\) has shape \(2, 4, 4\) but \(300, 4, 4\)"):
        left.fk(q, out=np.empty((2, 4, 4)))
    with pytest.raises(graspath.GraspathError, match="float64"):
        left.fk(q, out=np.empty((300, 4, 4), dtype=np.float32))
    with pytest.raises(graspath.GraspathError, match="C-contiguous"):
        left.fk(q, out=np.empty((300, 4, 8))[:, :, ::2])


def test_builtin_arms():
    # UR5e at q = 0: the DH table in closed form puts tool0 at (a2 + a3, -(d4 + d6), d1 - d5).
    ur5e = graspath.Robot.builtin("ur5e")
    assert ur5e.dof == 6 and ur5e.tip_link == "tool0"
    np.testing.assert_allclose(
        ur5e.fk(np.zeros(6))[:3, 3], [-0.425 - 0.3922, -(0.1333 + 0.0996), 0.1625 - 0.0997], atol=1e-12
    )
    assert graspath.Robot.builtin("panda").tip_link == "panda_hand_tcp"
    q = graspath.Robot.baxter("right").mid_configuration()
    np.testing.assert_array_equal(
        graspath.Robot.builtin("baxter", "right").fk(q), graspath.Robot.baxter("right").fk(q)
    )
    with pytest.raises(graspath.GraspathError, match="did you mean: panda"):
        graspath.Robot.builtin("pand")
    with pytest.raises(graspath.GraspathError, match="arm"):
        graspath.Robot.builtin("ur5e", "left")


XACRO_ARM = """<?xml version="1.0"?>
<robot name="arm" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:arg name="reach" default="0.4"/>
  <link name="base"/>
  <joint name="j1" type="revolute">
    <parent link="base"/><child link="tip"/><origin xyz="$(arg reach) 0 0"/>
    <axis xyz="0 0 1"/><limit lower="-2" upper="2" effort="1" velocity="1"/>
  </joint>
  <link name="tip"/>
</robot>
"""


class TestXacro:
    """Only files named *.xacro are expanded (xacro runs code), with their arguments."""

    def test_markup_outside_a_xacro_file_is_refused(self, tmp_path):
        path = tmp_path / "arm.urdf"
        path.write_text(XACRO_ARM)
        with pytest.raises(graspath.GraspathError, match=r"arm.urdf:3: uses xacro markup .*\*\.xacro"):
            graspath.Robot.from_urdf(path, "base", "tip")
        with pytest.raises(graspath.GraspathError, match="only a file named \\*.xacro is expanded"):
            graspath.Robot.from_urdf(path, "base", "tip", xacro_args={"reach": "1"})

    def test_arguments_reach_xacro(self, tmp_path):
        import os
        import shutil

        if not (os.environ.get("GRASPATH_XACRO") or shutil.which("xacro")):
            if os.environ.get("CI") == "true":
                pytest.fail("xacro is required in CI (.ci/run installs it and sets GRASPATH_XACRO)")
            pytest.skip("xacro is not installed")
        path = tmp_path / "arm.urdf.xacro"
        path.write_text(XACRO_ARM)
        for reach, args in [(0.4, None), (0.65, {"reach": "0.65"})]:
            robot = graspath.Robot.from_urdf(path, "base", "tip", xacro_args=args, search_paths=[tmp_path])
            pose = robot.fk(np.array([0.3]))
            np.testing.assert_allclose(pose[:3, 3], [reach, 0.0, 0.0], atol=1e-12)
