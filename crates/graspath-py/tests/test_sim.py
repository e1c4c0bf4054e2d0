"""graspath's world in MuJoCo (``graspath.world_mjcf``, ``graspath.robot_mjcf``) and the
execution of grasps and their tasks (``graspath.sim``).

MuJoCo is the oracle of the exported models: its forward kinematics and joint-space inertia of
every built-in arm equal graspath's. Known outcomes check the simulation: a welded grasp
delivers the object, a light object held by friction at its middle stays in the hand, the same
grasp with the object made too heavy or too slippery slips and is reported as a drop, a motion
run twice as fast as its limits saturates the motors, and the same inputs give the same
``sim.json`` bytes. MuJoCo is installed by CI (``.ci/run``); elsewhere these tests skip when it
is missing.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import graspath
from conftest import require

REPO = Path(__file__).resolve().parents[3]
ON_TABLE = REPO / "examples" / "scene" / "pick_and_place_left_on_table.yaml"
BUILTINS = ["baxter", "panda", "fr3", "ur5", "ur10", "ur5e", "ur10e", "iiwa14", "xarm7", "gen3"]


def mujoco_or_skip():
    return require("mujoco", "pip install mujoco")


def robots():
    for name in BUILTINS:
        arms = ["left", "right"] if name == "baxter" else [None]
        for arm in arms:
            yield name, arm


@pytest.mark.parametrize("name,arm", list(robots()))
def test_mujocos_kinematics_and_inertia_of_every_builtin_arm_equal_graspaths(name, arm):
    mujoco = mujoco_or_skip()
    robot = graspath.Robot.builtin(name, arm) if arm else graspath.Robot.builtin(name)
    xml, names = graspath.robot_mjcf(robot)
    model = mujoco.MjModel.from_xml_string(xml)
    data = mujoco.MjData(model)
    assert model.nq == robot.dof == len(names["joints"])
    site = model.site(names["tool"]).id
    rng = np.random.default_rng(3)
    lower, upper = robot.lower, robot.upper
    for _ in range(20):
        q = rng.uniform(np.maximum(lower, -np.pi), np.minimum(upper, np.pi))
        data.qpos[:] = q
        mujoco.mj_forward(model, data)
        pose = robot.fk(q)
        np.testing.assert_allclose(data.site_xpos[site], pose[:3, 3], rtol=0, atol=1e-9)
        np.testing.assert_allclose(
            data.site_xmat[site].reshape(3, 3), pose[:3, :3], rtol=0, atol=1e-9
        )
        full = np.zeros((model.nv, model.nv))
        mujoco.mj_fullM(model, data, full)
        expected = robot.mass_matrix(q)
        scale = np.abs(expected).max()
        np.testing.assert_allclose(full, expected, rtol=0, atol=1e-9 * scale)
        # And the gravity torques (MuJoCo's bias at rest is gravity alone).
        np.testing.assert_allclose(
            data.qfrc_bias, robot.gravity_torques(q), rtol=0, atol=1e-9 * max(1.0, scale)
        )


def scene_tasks():
    return sorted((REPO / "examples" / "scene").glob("*.yaml")) + [
        REPO / "examples" / "t_shape_move.yaml",
        REPO / "examples" / "pick_and_place_both.yaml",
    ]


@pytest.mark.parametrize("path", scene_tasks(), ids=lambda p: p.name)
def test_every_example_world_loads_in_mujoco(path):
    mujoco = mujoco_or_skip()
    task = graspath.Task.load(path)
    world = graspath.world_mjcf(task)
    model = mujoco.MjModel.from_xml_string(world["xml"])
    arm_dofs = sum(len(a["joints"]) + len(a["fingers"]) for a in world["arms"])
    assert model.nv == arm_dofs + 6  # the object's free joint
    assert model.nu == arm_dofs
    obj = model.body(world["object"]).id
    np.testing.assert_allclose(model.body_mass[obj], world["object_mass"], rtol=1e-12)
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    # The object starts at the path's first pose.
    np.testing.assert_allclose(data.xpos[obj], task.object_poses[0][:3, 3], atol=1e-12)
    assert world["has_table"] == ("table:" in path.read_text())


@pytest.fixture(scope="module")
def table_world():
    mujoco_or_skip()
    from graspath import sim

    task = graspath.Task.load(ON_TABLE)
    selection = graspath.select(task)
    arrays = selection.arrays("left")
    middle = int(np.argmin(np.abs(np.array([float(l.split("=")[1]) for l in arrays["label"]]))))
    assert arrays["feasible"][middle]
    best = int(np.nanargmin(np.where(arrays["feasible"], arrays["rank"], np.nan)))
    return task, sim, middle, best


def test_a_welded_grasp_delivers_the_object_to_the_goal(table_world):
    task, sim, _, best = table_world
    world = sim.World(task, sim.SimOptions(arm_gravity_compensation=True))
    run = world.run([best], mode="weld")
    assert run["status"] == "simulated"
    assert run["success"], run
    assert run["final_position_error"] < 0.01
    assert run["slip_distance"] < 0.005
    assert run["saturated_fraction"] == 0.0
    assert run["unintended_contacts"] == {}
    # The motion took the planned time plus the stops and the settling.
    motion = graspath.candidate_motions(task, [best])[0]
    o = world.options
    planned = motion["duration"] + o.close_time + o.open_time + o.settle_time
    assert abs(run["duration"] - planned) < 0.02


def test_a_light_object_held_at_its_middle_stays_in_the_hand(table_world):
    task, sim, middle, _ = table_world
    world = sim.World(task, sim.SimOptions(arm_gravity_compensation=True, object_mass=0.3))
    run = world.run([middle], mode="friction")
    assert run["success"], run
    assert run["slip_distance"] < 0.005
    assert not run["dropped"]


@pytest.mark.parametrize(
    "change", [{"object_mass": 20.0}, {"friction": 0.02}], ids=["too heavy", "too slippery"]
)
def test_the_same_grasp_slips_when_the_object_is_too_heavy_or_too_slippery(table_world, change):
    task, sim, middle, _ = table_world
    options = {"arm_gravity_compensation": True, "object_mass": 0.3, **change}
    run = sim.World(task, sim.SimOptions(**options)).run([middle], mode="friction")
    assert run["dropped"], run
    assert run["slip_distance"] > sim.DROP_DISTANCE
    assert not run["success"]
    if "friction" in change:
        # A weld is never reported as a friction result: welded, the slippery object holds.
        welded = sim.World(task, sim.SimOptions(**options)).run([middle], mode="weld")
        assert welded["mode"] == "weld" and welded["success"] and not welded["dropped"]


def test_a_friction_grip_holds_exactly_when_its_friction_can_carry_the_weight(table_world):
    # Two fingers pressing with F each hold a weight m·g at most 2·μ·F: at μ = 0.06 the
    # 0.3 kg object (2.94 N) is held with 4.8 N, at μ = 0.03 (2.4 N) it slides out.
    task, sim, middle, _ = table_world
    runs = {}
    for friction in (0.03, 0.06):
        options = sim.SimOptions(
            arm_gravity_compensation=True, object_mass=0.3, friction=friction, grip_force=40.0
        )
        runs[friction] = sim.World(task, options).run([middle], mode="friction")
    assert 2 * 0.06 * 40.0 > 0.3 * 9.81 > 2 * 0.03 * 40.0
    assert runs[0.06]["success"] and runs[0.06]["slip_distance"] < 0.005
    assert runs[0.03]["dropped"] and not runs[0.03]["success"]


def test_a_motion_twice_as_fast_as_its_limits_saturates_and_is_reported(tmp_path):
    # The Panda shelf task with a 2 kg box: its motions are timed against the joint torque
    # limits (the task gives the mass), so at the planned speed the motors stay within them,
    # and at twice the speed they saturate and the arm falls behind.
    mujoco_or_skip()
    from graspath import sim

    text = (REPO / "examples" / "scene" / "panda_shelf_pick.yaml").read_text()
    shape = "shape: { box: { size: [0.05, 0.05, 0.20] } }"
    assert shape in text
    heavy = tmp_path / "panda_heavy.yaml"
    heavy.write_text(text.replace(shape, shape + "\n  mass: 2.0"))
    task = graspath.Task.load(heavy)
    best = graspath.select(task).best("arm")
    world = sim.World(task)
    planned = world.run([best], mode="weld", slowdown=1.0)
    fast = world.run([best], mode="weld", slowdown=0.5)
    assert planned["success"], planned
    assert planned["saturated_fraction"] == 0.0 and planned["peak_effort_ratio"] < 1.0
    assert fast["saturated_fraction"] > 0.0
    assert fast["peak_effort_ratio"] > 1.0
    assert fast["tracking_error_max"][0] > planned["tracking_error_max"][0]


def test_the_motors_carry_the_arm_unless_told_otherwise(table_world):
    # Baxter's 50 N·m shoulder cannot hold the arm without its spring: without gravity
    # compensation the run saturates from the start and fails.
    task, sim, _, best = table_world
    run = sim.World(task, sim.SimOptions()).run([best], mode="weld")
    assert run["saturated_fraction"] > 0.5
    assert not run["success"]


def test_the_same_inputs_give_the_same_sim_json_bytes(tmp_path, table_world):
    task, sim, _, _ = table_world
    outputs = []
    for name in ["a.json", "b.json"]:
        out = tmp_path / name
        result = subprocess.run(
            [
                sys.executable,
                "-m",
                "graspath.sim",
                str(ON_TABLE),
                "--out",
                str(out),
                "-k",
                "1",
                "-n",
                "1",
                "--modes",
                "weld",
                "--slowdowns",
                "1",
                "--arm-gravity-compensation",
            ],
            capture_output=True,
            text=True,
        )
        assert result.returncode == 0, result.stderr
        assert "success" in result.stdout
        outputs.append(out.read_bytes())
    assert outputs[0] == outputs[1]
    document = json.loads(outputs[0])
    groups = [c["group"] for c in document["choices"]]
    assert groups == ["index", "classical", "likelihood", "random"]
    assert len(document["runs"]) == 4
    assert {s["group"] for s in document["summary"]} == set(groups)


def hand_urdf(finger, palm, travel):
    """A parallel-jaw hand as a URDF: a palm box behind the finger roots on the root link
    ``hand`` and two box fingers on prismatic joints along ``±y`` (the fixture of
    ``tests/scene_tasks.rs``)."""
    length, width, thickness = finger

    def box(size):
        return f'<box size="{size[0]} {size[1]} {size[2]}"/>'

    def finger_link(name, side):
        return (
            f'<link name="{name}"><collision><origin xyz="0 {side * thickness / 2} {-length / 2}"/>'
            f"<geometry>{box([width, thickness, length])}</geometry></collision></link>"
        )

    def slide(name, child, side):
        return (
            f'<joint name="{name}" type="prismatic"><parent link="hand"/><child link="{child}"/>'
            f'<axis xyz="0 {side} 0"/><limit lower="0" upper="{travel}" effort="1" velocity="1"/></joint>'
        )

    return (
        f'<robot name="two_jaw"><link name="hand"><collision><origin xyz="0 0 {-length - palm[2] / 2}"/>'
        f"<geometry>{box(palm)}</geometry></collision></link>"
        + finger_link("left_finger", 1)
        + finger_link("right_finger", -1)
        + slide("left_slide", "left_finger", 1)
        + slide("right_slide", "right_finger", -1)
        + "</robot>"
    )


def test_a_urdf_hand_is_simulated_as_the_gripper_its_shapes_describe(tmp_path, table_world):
    # Oracle: the same fingers and palm given by their sizes. Both worlds slide the fingers
    # along the tool's ±y by half the opening, and the same grasp gives the same run.
    _, sim, middle, _ = table_world
    finger, palm = [0.09, 0.02, 0.01], [0.06, 0.11, 0.04]
    (tmp_path / "hand.urdf").write_text(hand_urdf(finger, palm, 0.035))
    text = ON_TABLE.read_text()
    assert "gripper: { builtin: baxter }" in text
    grippers = {
        "sized": f"gripper: {{ opening: 0.07, finger: {finger}, palm: {palm} }}",
        "urdf": "gripper: { urdf: hand.urdf, root: hand }",
    }
    runs = {}
    for name, gripper in grippers.items():
        path = tmp_path / f"{name}.yaml"
        path.write_text(text.replace("gripper: { builtin: baxter }", gripper))
        task = graspath.Task.load(path)
        world = sim.World(task, sim.SimOptions(arm_gravity_compensation=True, object_mass=0.3))
        names = world.world["arms"][0]
        axes = sorted(tuple(world.model.jnt_axis[world.model.joint(f).id]) for f in names["fingers"])
        np.testing.assert_allclose(axes, [(0, -1, 0), (0, 1, 0)], atol=1e-12)
        assert abs(names["finger_travel"] - 0.035) < 1e-12
        runs[name] = world.run([middle], mode="friction")
    assert runs["urdf"]["success"]
    for key in ("position_error", "slip_distance", "tracking_error_max"):
        np.testing.assert_allclose(runs["urdf"][key], runs["sized"][key], rtol=1e-6, atol=1e-9)


def test_bad_options_are_refused_with_their_name(table_world):
    task, sim, _, best = table_world
    with pytest.raises(ValueError, match="mode"):
        sim.SimOptions(mode="glue").check()
    with pytest.raises(ValueError, match="slowdown"):
        sim.World(task).run([best], slowdown=0.0)
    with pytest.raises(graspath.GraspathError, match="grip_force"):
        graspath.world_mjcf(task, grip_force=-1.0)
    with pytest.raises(graspath.GraspathError, match="one candidate per arm"):
        graspath.candidate_motions(task, [best, best])
    result = subprocess.run(
        [sys.executable, "-m", "graspath.sim", str(REPO / "no-such-task.yaml")],
        capture_output=True,
        text=True,
    )
    assert result.returncode == 2
    assert "no-such-task.yaml" in result.stderr
