"""Every URDF of example-robot-data that graspath loads, against Pinocchio: for each file, the
chain from the root link to the leaf reached through the most moving joints, forward
kinematics at seeded configurations in its limits. Third-party files nobody here wrote:
``GRASPATH_ROBOT_DATA`` (set by ``.ci/run``) or example-robot-data installed beside numpy; CI
requires them, elsewhere the test skips. Skipped without Pinocchio (``pip install pin``)."""

import math
import os
import sysconfig
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest

import graspath

MOVING = {"revolute", "continuous", "prismatic"}


def robots_folder():
    given = os.environ.get("GRASPATH_ROBOT_DATA")
    folder = Path(given) if given else (
        Path(sysconfig.get_paths()["purelib"]) / "cmeel.prefix" / "share" / "example-robot-data" / "robots"
    )
    if not (folder / "panda_description").is_dir():
        if os.environ.get("CI") == "true":
            raise AssertionError(f"example-robot-data is not at {folder}")
        pytest.skip("example-robot-data is not installed (pip install example-robot-data)")
    return folder


def longest_chain(path):
    """(root, leaf, joints) of the root-to-leaf chain with the most moving joints, or None
    when the file has mimic joints on it or no moving joint at all."""
    root = ET.parse(path).getroot()
    joints = {}
    for joint in root.iter("joint"):
        parent, child = joint.find("parent"), joint.find("child")
        if parent is None or child is None:
            continue
        joints[child.get("link")] = (parent.get("link"), joint)
    links = [link.get("name") for link in root.iter("link")]
    roots = [name for name in links if name not in joints]
    if len(roots) != 1:
        return None
    best = None
    for leaf in links:
        chain, link = [], leaf
        while link in joints:
            parent, joint = joints[link]
            chain.append(joint)
            link = parent
        moving = [j for j in chain if j.get("type") in MOVING]
        if any(j.find("mimic") is not None for j in moving):
            continue
        if moving and (best is None or len(moving) > len(best[2])):
            best = (roots[0], leaf, list(reversed(moving)))
    return best


def test_loaded_example_robot_data_chains_equal_pinocchio():
    pin = pytest.importorskip("pinocchio", reason="Pinocchio (pip install pin) is not installed")
    folder = robots_folder()
    files = sorted(folder.rglob("*.urdf"))
    assert len(files) >= 60, f"{len(files)} URDFs under {folder}"
    rng = np.random.default_rng(3)
    compared, worst = [], 0.0
    for path in files:
        chain = longest_chain(path)
        if chain is None:
            continue
        base, tip, moving = chain
        try:
            robot = graspath.Robot.from_urdf(str(path), base, tip)
        except graspath.GraspathError:
            continue  # refused with its reason: the corpus test in Rust counts those
        model = pin.buildModelFromUrdf(str(path))
        data = model.createData()
        names = [j.get("name") for j in moving]
        assert robot.joint_names == names, path
        pin_joints = [model.joints[model.getJointId(n)] for n in names]
        lower = np.where(np.isfinite(robot.lower), robot.lower, -math.pi)
        upper = np.where(np.isfinite(robot.upper), robot.upper, math.pi)
        for _ in range(4):
            q = lower + (upper - lower) * rng.random(robot.dof)
            full = pin.neutral(model)
            for joint, value in zip(pin_joints, q):
                if joint.nq == 2:  # a continuous joint: (cos, sin)
                    full[joint.idx_q : joint.idx_q + 2] = [math.cos(value), math.sin(value)]
                else:
                    full[joint.idx_q] = value
            pin.framesForwardKinematics(model, data, full)
            world_from_base = data.oMf[model.getFrameId(base)]
            world_from_tip = data.oMf[model.getFrameId(tip)]
            expected = (world_from_base.inverse() * world_from_tip).homogeneous
            error = np.abs(robot.fk(q) - expected).max()
            worst = max(worst, error)
            assert error < 1e-12, f"{path.relative_to(folder)} {base}->{tip}: {error}"
        compared.append(path)
    print(f"{len(compared)} chains of {len(files)} URDFs equal Pinocchio; largest difference {worst:.1e}")
    assert len(compared) >= 50
