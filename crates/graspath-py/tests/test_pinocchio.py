"""FK and Jacobians against Pinocchio (``pip install pin``) on the shared URDFs, for random
configurations in batch. Skipped when Pinocchio or ../shared is absent."""

import numpy as np
import pytest

import graspath

pin = pytest.importorskip("pinocchio", reason="Pinocchio (pip install pin) is not installed")

CHAINS = [
    ("baxter.urdf", "base", "left_gripper"),
    ("baxter.urdf", "base", "right_gripper"),
    ("panda.urdf", "panda_link0", "panda_hand_tcp"),
    ("ur5_robot.urdf", "base_link", "tool0"),
    ("ur5_joint_limited_robot.urdf", "world", "ee_link"),
]


class PinocchioChain:
    """The same chain evaluated by Pinocchio on the whole URDF model, other joints at neutral,
    expressed in the base link's frame."""

    def __init__(self, path, base, tip, joint_names):
        self.model = pin.buildModelFromUrdf(str(path))
        self.data = self.model.createData()
        self.base = self.model.getFrameId(base)
        self.tip = self.model.getFrameId(tip)
        joints = [self.model.joints[self.model.getJointId(n)] for n in joint_names]
        assert all(j.nq == 1 for j in joints)
        self.idx_q = [j.idx_q for j in joints]
        self.idx_v = [j.idx_v for j in joints]

    def pose_and_jacobian(self, q):
        full = pin.neutral(self.model)
        full[self.idx_q] = q
        jac = pin.computeFrameJacobian(self.model, self.data, full, self.tip, pin.LOCAL_WORLD_ALIGNED)
        pin.updateFramePlacements(self.model, self.data)
        world_from_base = self.data.oMf[self.base]
        world_from_tip = self.data.oMf[self.tip]
        base_from_tip = (world_from_base.inverse() * world_from_tip).homogeneous
        r = world_from_base.rotation.T
        jac = jac[:, self.idx_v]
        return base_from_tip, np.vstack([r @ jac[:3], r @ jac[3:]])


@pytest.mark.parametrize("urdf,base,tip", CHAINS)
def test_fk_and_jacobian_match_pinocchio(shared, urdf, base, tip):
    path = shared / "robots" / urdf
    robot = graspath.Robot.from_urdf(path, base, tip)
    reference = PinocchioChain(path, base, tip, robot.joint_names)
    rng = np.random.default_rng(11)
    lower, upper = np.maximum(robot.lower, -np.pi), np.minimum(robot.upper, np.pi)
    q = lower + (upper - lower) * rng.random((200, robot.dof))
    poses, jacobians = robot.fk_jacobian(q)
    for i in range(len(q)):
        pose, jac = reference.pose_and_jacobian(q[i])
        np.testing.assert_allclose(poses[i], pose, atol=1e-10, err_msg=f"{urdf} pose {i}")
        np.testing.assert_allclose(jacobians[i], jac, atol=1e-10, err_msg=f"{urdf} jacobian {i}")


def test_built_in_baxter_matches_pinocchio(shared):
    path = shared / "robots" / "baxter.urdf"
    for arm in ("left", "right"):
        robot = graspath.Robot.baxter(arm)
        reference = PinocchioChain(path, "base", f"{arm}_gripper", robot.joint_names)
        q = robot.lower + (robot.upper - robot.lower) * np.random.default_rng(3).random((50, 7))
        poses, jacobians = robot.fk_jacobian(q)
        for i in range(len(q)):
            pose, jac = reference.pose_and_jacobian(q[i])
            np.testing.assert_allclose(poses[i], pose, atol=1e-9)
            np.testing.assert_allclose(jacobians[i], jac, atol=1e-9)
