"""Rigid-body dynamics of ``graspath.Robot``: gravity torques, inverse dynamics (RNEA) and the
mass matrix (CRBA), with and without a payload at the tool frame.

* against Pinocchio (``pip install pin``) on example-robot-data's Panda and UR5, each
  Pinocchio's model of the whole URDF reduced to the chain's joints (as
  ``crates/graspath/tests/data/dynamics/pinocchio_reference.py`` builds it), the payload
  appended as a body at the tool frame; skipped when Pinocchio or example-robot-data is absent
  (example-robot-data: ``$GRASPATH_ROBOT_DATA``, else the ``cmeel.prefix`` of this Python);
* identities that need no oracle: ``τ(q, 0, e_i) − g(q)`` is column ``i`` of ``M(q)``, the
  payload's gravity torques are linear in its mass, a batch equals its rows called alone bit
  for bit, ``M`` of the built-in arms is symmetric positive definite;
* every bad input is a ``GraspathValueError`` (a ``ValueError``) naming the argument.
"""

import os
import sysconfig
from pathlib import Path

import numpy as np
import pytest

import graspath

# The largest error allowed, relative to the largest entry of Pinocchio's value.
TOL = 1e-9

# A tool offset tip_from_tool and a payload (tool frame), as in the Rust reference data.
TOOL_XYZ = np.array([0.01, -0.02, 0.05])
TOOL_RPY = np.array([0.1, -0.2, 0.3])
PAYLOAD = {
    "mass": 1.7,
    "com": [0.02, -0.03, 0.11],
    "inertia": [[0.012, 0.001, -0.002], [0.001, 0.009, 0.0005], [-0.002, 0.0005, 0.006]],
}

CHAINS = [
    ("panda", "panda_description/urdf/panda.urdf", "panda_link0", "panda_hand_tcp"),
    ("ur5", "ur_description/urdf/ur5_robot.urdf", "base_link", "tool0"),
]

SAMPLES = 20


def robot_data():
    """example-robot-data's ``robots`` folder, or ``None``."""
    candidates = [
        os.environ.get("GRASPATH_ROBOT_DATA"),
        Path(sysconfig.get_paths()["purelib"]) / "cmeel.prefix" / "share" / "example-robot-data" / "robots",
    ]
    for candidate in candidates:
        if candidate and (Path(candidate) / "panda_description").is_dir():
            return Path(candidate)
    return None


def rotation_rpy(rpy):
    """``Rz(yaw) Ry(pitch) Rx(roll)``, the URDF convention."""
    (cr, cp, cy), (sr, sp, sy) = np.cos(rpy), np.sin(rpy)
    rx = np.array([[1, 0, 0], [0, cr, -sr], [0, sr, cr]])
    ry = np.array([[cp, 0, sp], [0, 1, 0], [-sp, 0, cp]])
    rz = np.array([[cy, -sy, 0], [sy, cy, 0], [0, 0, 1]])
    return rz @ ry @ rx


def tool_matrix():
    tool = np.eye(4)
    tool[:3, :3] = rotation_rpy(TOOL_RPY)
    tool[:3, 3] = TOOL_XYZ
    return tool


def assert_relative(ours, reference, what):
    scale = max(np.max(np.abs(reference)), 1e-12)
    error = np.max(np.abs(np.asarray(ours) - reference)) / scale
    assert error <= TOL, f"{what}: relative error {error:.3e}"


def random_states(robot, count, seed):
    rng = np.random.default_rng(seed)
    lower = np.where(np.isfinite(robot.lower), robot.lower, -np.pi)
    upper = np.where(np.isfinite(robot.upper), robot.upper, np.pi)
    q = rng.uniform(lower, upper, (count, robot.dof))
    qd = rng.uniform(-2.0, 2.0, (count, robot.dof))
    qdd = rng.uniform(-5.0, 5.0, (count, robot.dof))
    return q, qd, qdd


@pytest.fixture(scope="module")
def pin():
    return pytest.importorskip("pinocchio", reason="Pinocchio (pip install pin) is not installed")


@pytest.fixture(scope="module")
def robots():
    path = robot_data()
    if path is None:
        pytest.skip("example-robot-data is not installed (pip install example-robot-data, or set GRASPATH_ROBOT_DATA)")
    return path


class PinocchioChain:
    """The chain in Pinocchio: the whole URDF reduced to the chain's joints (the others locked
    at zero), with and without the payload appended at the tool frame."""

    def __init__(self, pin, path, base, tip, joint_names, gravity_base):
        self.pin = pin
        full = pin.buildModelFromUrdf(str(path))
        tip_joint = full.frames[full.getFrameId(tip)].parentJoint
        base_joint = full.frames[full.getFrameId(base)].parentJoint
        keep = set(full.supports[tip_joint]) - set(full.supports[base_joint])
        locked = [j for j in range(1, full.njoints) if j not in keep]
        self.model = pin.buildReducedModel(full, locked, pin.neutral(full))
        names = [self.model.names[j] for j in range(1, self.model.njoints)]
        assert self.model.nq == self.model.nv == len(names)
        # graspath's joint order in Pinocchio's vectors.
        self.order = [names.index(n) for n in joint_names]
        data = self.model.createData()
        pin.framesForwardKinematics(self.model, data, pin.neutral(self.model))
        world_from_base = data.oMf[self.model.getFrameId(base)].rotation
        self.model.gravity.linear = world_from_base @ np.asarray(gravity_base, dtype=float)
        tip_frame = self.model.frames[self.model.getFrameId(tip)]
        tool = pin.SE3(rotation_rpy(TOOL_RPY), TOOL_XYZ)
        payload = pin.Inertia(PAYLOAD["mass"], np.array(PAYLOAD["com"]), np.array(PAYLOAD["inertia"]))
        self.loaded = self.model.copy()
        self.loaded.appendBodyToJoint(tip_frame.parentJoint, payload, tip_frame.placement * tool)
        self.data = {False: self.model.createData(), True: self.loaded.createData()}

    def _vector(self, values):
        out = np.zeros(self.model.nv)
        out[self.order] = values
        return out

    def evaluate(self, q, qd, qdd, loaded):
        pin = self.pin
        model = self.loaded if loaded else self.model
        data = self.data[loaded]
        q, qd, qdd = self._vector(q), self._vector(qd), self._vector(qdd)
        g = pin.computeGeneralizedGravity(model, data, q).copy()
        tau = pin.rnea(model, data, q, qd, qdd).copy()
        upper = pin.crba(model, data, q).copy()
        mass = np.triu(upper) + np.triu(upper, 1).T
        o = self.order
        return g[o], tau[o], mass[np.ix_(o, o)]


@pytest.mark.parametrize("name,urdf,base,tip", CHAINS)
@pytest.mark.parametrize("gravity", [None, (0.4, -2.0, -9.6)], ids=["standard", "tilted"])
def test_gravity_rnea_and_crba_equal_pinocchio(pin, robots, name, urdf, base, tip, gravity):
    robot = graspath.Robot.from_urdf(robots / urdf, base, tip, tool_matrix(), search_paths=[robots.parent.parent])
    gravity_base = (0.0, 0.0, -9.81) if gravity is None else gravity
    reference = PinocchioChain(pin, robots / urdf, base, tip, robot.joint_names, gravity_base)
    q, qd, qdd = random_states(robot, SAMPLES, seed=5)
    keywords = {} if gravity is None else {"gravity": gravity}
    for loaded in (False, True):
        payload = PAYLOAD if loaded else None
        g = robot.gravity_torques(q, payload=payload, **keywords)
        tau = robot.inverse_dynamics(q, qd, qdd, payload=payload, **keywords)
        mass = robot.mass_matrix(q, payload=payload)
        assert g.shape == tau.shape == (SAMPLES, robot.dof)
        assert mass.shape == (SAMPLES, robot.dof, robot.dof)
        for i in range(SAMPLES):
            g_ref, tau_ref, mass_ref = reference.evaluate(q[i], qd[i], qdd[i], loaded)
            what = f"{name} sample {i} payload={loaded}"
            assert_relative(g[i], g_ref, f"gravity, {what}")
            assert_relative(tau[i], tau_ref, f"rnea, {what}")
            assert_relative(mass[i], mass_ref, f"crba, {what}")


@pytest.mark.parametrize("name,urdf,base,tip", CHAINS)
def test_moving_mass_and_limits_equal_the_urdf(pin, robots, name, urdf, base, tip):
    robot = graspath.Robot.from_urdf(robots / urdf, base, tip, search_paths=[robots.parent.parent])
    reference = PinocchioChain(pin, robots / urdf, base, tip, robot.joint_names, (0.0, 0.0, -9.81))
    model = reference.model
    mass = sum(model.inertias[j].mass for j in range(1, model.njoints))
    assert robot.moving_mass == pytest.approx(mass, rel=1e-12)
    # Pinocchio reads <limit effort velocity>, in its own joint order.
    o = reference.order
    np.testing.assert_array_equal(robot.effort_limits, np.asarray(model.effortLimit)[o])
    np.testing.assert_array_equal(robot.velocity_limits, np.asarray(model.velocityLimit)[o])
    # URDF gives no acceleration limits: unknown is inf.
    assert np.all(robot.acceleration_limits == np.inf)


def builtin_arms():
    return [graspath.Robot.builtin(name) for name in ("panda", "ur5", "iiwa14")] + [graspath.Robot.baxter("left")]


@pytest.mark.parametrize("robot", builtin_arms(), ids=lambda r: r.source)
def test_inverse_dynamics_at_rest_minus_gravity_is_the_mass_matrix(robot):
    q, _, _ = random_states(robot, 5, seed=8)
    payload = {"mass": 0.8, "com": [0.0, 0.01, 0.06], "inertia": [0.002, 0.003, 0.001]}
    zero = np.zeros(robot.dof)
    for qi in q:
        g = robot.gravity_torques(qi, payload=payload)
        mass = robot.mass_matrix(qi, payload=payload)
        np.testing.assert_allclose(robot.inverse_dynamics(qi, zero, zero, payload=payload), g, rtol=0, atol=1e-12)
        for i, column in enumerate(np.eye(robot.dof)):
            tau = robot.inverse_dynamics(qi, zero, column, payload=payload)
            np.testing.assert_allclose(tau - g, mass[:, i], rtol=0, atol=1e-10 * np.abs(mass).max())


@pytest.mark.parametrize("robot", builtin_arms(), ids=lambda r: r.source)
def test_mass_matrix_of_built_in_arms_is_symmetric_positive_definite(robot):
    q, _, _ = random_states(robot, 50, seed=2)
    for loaded in (None, PAYLOAD):
        mass = robot.mass_matrix(q, payload=loaded)
        assert np.array_equal(mass, np.swapaxes(mass, 1, 2))
        assert np.all(np.linalg.eigvalsh(mass) > 0)


def test_payload_gravity_torques_are_linear_in_its_mass_and_rise_with_it():
    robot = graspath.Robot.builtin("panda")
    q = np.array([0.0, -0.3, 0.0, -2.2, 0.0, 2.0, 0.8])
    arm = robot.gravity_torques(q)
    one = robot.gravity_torques(q, payload={"mass": 1.0, "com": [0, 0, 0.05]}) - arm
    three = robot.gravity_torques(q, payload={"mass": 3.0, "com": [0, 0, 0.05]}) - arm
    np.testing.assert_allclose(three, 3.0 * one, rtol=0, atol=1e-12)
    # A massless payload is no payload; the inertia does not change g.
    np.testing.assert_array_equal(robot.gravity_torques(q, payload={"mass": 0.0}), arm)
    heavy = {"mass": 1.0, "com": [0, 0, 0.05], "inertia": np.diag([0.1, 0.2, 0.3])}
    np.testing.assert_allclose(robot.gravity_torques(q, payload=heavy) - arm, one, rtol=0, atol=1e-12)
    # The principal moments equal the diagonal matrix.
    np.testing.assert_array_equal(
        robot.mass_matrix(q, payload=heavy), robot.mass_matrix(q, payload={**heavy, "inertia": [0.1, 0.2, 0.3]})
    )
    # Without gravity nothing needs holding.
    assert np.all(robot.gravity_torques(q, gravity=[0, 0, 0], payload=heavy) == 0.0)


def test_batches_equal_their_rows_bit_for_bit():
    robot = graspath.Robot.builtin("panda")
    q, qd, qdd = random_states(robot, 300, seed=13)
    for payload in (None, PAYLOAD):
        g = robot.gravity_torques(q, payload=payload, gravity=(0.1, 0.2, -9.7))
        tau = robot.inverse_dynamics(q, qd, qdd, payload=payload)
        mass = robot.mass_matrix(q, payload=payload)
        for i in range(len(q)):
            assert np.array_equal(g[i], robot.gravity_torques(q[i], payload=payload, gravity=(0.1, 0.2, -9.7)))
            assert np.array_equal(tau[i], robot.inverse_dynamics(q[i], qd[i], qdd[i], payload=payload))
            assert np.array_equal(mass[i], robot.mass_matrix(q[i], payload=payload))
    # Any layout reads the same values.
    fortran = np.asfortranarray(q)
    assert np.array_equal(robot.gravity_torques(fortran), robot.gravity_torques(q))
    assert np.array_equal(robot.mass_matrix(q[::2]), robot.mass_matrix(np.ascontiguousarray(q[::2])))
    # Lists work, and empty batches give empty results.
    assert np.array_equal(robot.gravity_torques(q[0].tolist()), robot.gravity_torques(q[0]))
    assert robot.gravity_torques(np.zeros((0, 7))).shape == (0, 7)
    assert robot.mass_matrix(np.zeros((0, 7))).shape == (0, 7, 7)


def test_limits_of_a_built_in_arm():
    panda = graspath.Robot.builtin("panda")
    np.testing.assert_array_equal(panda.effort_limits, [87, 87, 87, 87, 12, 12, 12])
    np.testing.assert_array_equal(panda.acceleration_limits, [15, 7.5, 10, 12.5, 15, 20, 20])
    assert panda.velocity_limits.shape == (7,) and np.all(np.isfinite(panda.velocity_limits))
    assert 15.0 < panda.moving_mass < 20.0
    ur5 = graspath.Robot.builtin("ur5")
    assert np.all(ur5.acceleration_limits == np.inf)
    assert np.all(np.isfinite(ur5.effort_limits))


URDF_WITHOUT_INERTIA = """<robot name="bare">
  <link name="base"/>
  <link name="upper"><inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="forearm"/>
  <joint name="shoulder" type="revolute"><parent link="base"/><child link="upper"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="10" velocity="1"/></joint>
  <joint name="elbow" type="revolute"><parent link="upper"/><child link="forearm"/><origin xyz="0.3 0 0"/>
    <axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="5" velocity="2"/></joint>
</robot>"""


def test_a_robot_without_inertial_data_is_a_clear_error():
    robot = graspath.Robot.from_urdf_string(URDF_WITHOUT_INERTIA, "base", "forearm", source_name="bare.urdf")
    # Kinematics and limits still work.
    assert robot.fk([0.0, 0.0]).shape == (4, 4)
    np.testing.assert_array_equal(robot.effort_limits, [10, 5])
    np.testing.assert_array_equal(robot.acceleration_limits, [np.inf, np.inf])
    calls = [
        lambda: robot.gravity_torques([0.0, 0.0]),
        lambda: robot.inverse_dynamics([0.0, 0.0], [0.0, 0.0], [0.0, 0.0]),
        lambda: robot.mass_matrix(np.zeros((3, 2))),
        lambda: robot.moving_mass,
    ]
    for call in calls:
        with pytest.raises(graspath.GraspathError) as raised:
            call()
        message = str(raised.value)
        assert "bare.urdf" in message and "'elbow'" in message and "forearm" in message, message


def test_a_chain_without_joints_gives_empty_results():
    urdf = """<robot name="fixed"><link name="a"><inertial><mass value="1"/>
      <inertia ixx="1" iyy="1" izz="1" ixy="0" ixz="0" iyz="0"/></inertial></link><link name="b"/>
      <joint name="j" type="fixed"><parent link="a"/><child link="b"/></joint></robot>"""
    robot = graspath.Robot.from_urdf_string(urdf, "a", "b")
    assert robot.dof == 0
    assert robot.gravity_torques(np.zeros(0)).shape == (0,)
    assert robot.mass_matrix(np.zeros((4, 0))).shape == (4, 0, 0)
    assert robot.inverse_dynamics(np.zeros((2, 0)), np.zeros((2, 0)), np.zeros((2, 0)), payload=PAYLOAD).shape == (2, 0)
    assert robot.moving_mass == 0.0


@pytest.mark.parametrize(
    "call,pattern",
    [
        (lambda r: r.gravity_torques(np.zeros(6)), r"q has shape \(6,\) but the chain .* has 7 joints"),
        (lambda r: r.gravity_torques(np.zeros((2, 3, 7))), r"q has shape \(2, 3, 7\)"),
        (lambda r: r.mass_matrix([[0.0] * 7, [0.0] * 6 + [np.nan]]), r"q\[1, 6\] is not a finite number"),
        (lambda r: r.gravity_torques([0.0] * 6 + [np.inf]), r"q\[6\] is not a finite number"),
        (lambda r: r.inverse_dynamics(np.zeros(7), np.zeros(6), np.zeros(7)), r"qd has shape \(6,\) but q has shape \(7,\)"),
        (lambda r: r.inverse_dynamics(np.zeros((3, 7)), np.zeros((3, 7)), np.zeros(7)), r"qdd has shape \(7,\) but q has shape \(3, 7\)"),
        (lambda r: r.inverse_dynamics(np.zeros((3, 7)), np.full((3, 7), np.nan), np.zeros((3, 7))), r"qd\[0, 0\] is not a finite number"),
        (lambda r: r.inverse_dynamics(np.zeros(7), np.zeros(7), [0.0] * 3 + [np.inf] + [0.0] * 3), r"qdd\[3\] is not a finite number"),
        (lambda r: r.gravity_torques(np.zeros(7), gravity=[0.0, -9.81]), r"gravity has shape \(2,\) but \(3,\)"),
        (lambda r: r.gravity_torques(np.zeros(7), gravity=[0.0, np.nan, -9.81]), r"gravity\[1\] is not a finite number"),
        (lambda r: r.gravity_torques(np.zeros(7), gravity=[0j, 0j, -9.81 + 0j]), r"complex values are refused"),
        (lambda r: r.gravity_torques(np.zeros(7), payload=2.0), r"payload must be None or a dict"),
        (lambda r: r.gravity_torques(np.zeros(7), payload={"mass": 1.0, "center_of_mass": [0, 0, 0]}), r"payload has an unknown key 'center_of_mass'"),
        (lambda r: r.gravity_torques(np.zeros(7), payload={1: 2}), r"payload has an unknown key 1"),
        (lambda r: r.gravity_torques(np.zeros(7), payload={"com": [0, 0, 0]}), r"payload\['mass'\] is missing"),
        (lambda r: r.gravity_torques(np.zeros(7), payload={"mass": "heavy"}), r"payload\['mass'\] must be a number"),
        (lambda r: r.gravity_torques(np.zeros(7), payload={"mass": -1.0}), r"payload\['mass'\] must be a finite non-negative"),
        (lambda r: r.gravity_torques(np.zeros(7), payload={"mass": np.nan}), r"payload\['mass'\] must be a finite non-negative"),
        (lambda r: r.gravity_torques(np.zeros(7), payload={"mass": 1500.0}), r"payload\['mass'\] is 1500 kg, more than 1000 kg"),
        (lambda r: r.gravity_torques(np.zeros(7), payload={"mass": 1.0, "com": [0, 0]}), r"payload\['com'\] has shape \(2,\)"),
        (lambda r: r.gravity_torques(np.zeros(7), payload={"mass": 1.0, "com": [0, np.inf, 0]}), r"payload\['com'\]\[1\] is not a finite number"),
        (lambda r: r.gravity_torques(np.zeros(7), payload={"mass": 1.0, "com": [0, 0, 50.0]}), r"payload\['com'\] is 50.000 m from the tool frame"),
        (lambda r: r.gravity_torques(np.zeros(7), payload={"mass": 1.0, "com": "abc"}), r"payload\['com'\] must be an array of numbers"),
        (lambda r: r.mass_matrix(np.zeros(7), payload={"mass": 1.0, "inertia": np.zeros((2, 2))}), r"payload\['inertia'\] has shape \(2, 2\)"),
        (lambda r: r.mass_matrix(np.zeros(7), payload={"mass": 1.0, "inertia": [[1, 0.5, 0], [0, 1, 0], [0, 0, 1]]}), r"payload\['inertia'\] must be symmetric"),
        (lambda r: r.mass_matrix(np.zeros(7), payload={"mass": 1.0, "inertia": [0.1, -0.1, 0.1]}), r"non-negative diagonal"),
        (lambda r: r.mass_matrix(np.zeros(7), payload={"mass": 1.0, "inertia": np.diag([1.0, np.nan, 1.0])}), r"payload\['inertia'\]\[1, 1\] is not a finite number"),
    ],
)
def test_bad_inputs_are_errors_naming_the_argument(call, pattern):
    robot = graspath.Robot.builtin("panda")
    with pytest.raises(graspath.GraspathValueError, match=pattern):
        call(robot)
    assert issubclass(graspath.GraspathValueError, ValueError)


def test_signatures_show_the_defaults():
    import inspect

    parameters = inspect.signature(graspath.Robot.gravity_torques).parameters
    assert parameters["gravity"].default == (0.0, 0.0, -9.81)
    assert parameters["payload"].default is None
    assert parameters["gravity"].kind is inspect.Parameter.KEYWORD_ONLY
    parameters = inspect.signature(graspath.Robot.inverse_dynamics).parameters
    assert list(parameters)[:4] == ["self", "q", "qd", "qdd"]
    # The default shown is the default used.
    robot = graspath.Robot.builtin("ur5")
    q = np.full(6, 0.3)
    assert np.array_equal(robot.gravity_torques(q), robot.gravity_torques(q, gravity=(0.0, 0.0, -9.81)))


def test_a_task_with_a_payload_ranks_by_the_dynamic_manipulability():
    """Task.from_arrays(payload=..., measure="dynamic"): each sample's ranked value is
    ‖H M⁻¹ Jᵀ u‖² written out in numpy from the robot's own Jacobian, gravity torques, mass
    matrix (the object's mass moved to the tool by the grasp) and effort limits, with H the
    effort limits less the gravity torques; the task's torque columns come with it."""
    left = graspath.Robot.baxter("left")
    start = np.eye(4)
    start[:3, 3] = [0.75, 0.35, 0.0]
    poses = np.repeat(start[None], 11, axis=0)
    poses[:, 2, 3] += np.linspace(0.0, 0.2, 11)
    candidates = []
    for yaw in np.linspace(-0.6, 0.6, 5):
        c = np.eye(4)
        c[:3, :3] = np.array(
            [[np.cos(yaw), -np.sin(yaw), 0], [np.sin(yaw), np.cos(yaw), 0], [0, 0, 1]]
        ) @ np.diag([1.0, -1.0, -1.0])
        c[2, 3] = 0.05
        candidates.append(c)
    payload = {"mass": 0.5, "com": [0.0, 0.02, 0.0]}
    task = graspath.Task.from_arrays(
        {"left": left}, poses, np.array(candidates), payload=payload, measure="dynamic",
        redundancy="first",
    )
    selection = graspath.select(task)
    values = selection.arrays("left")
    assert values["feasible"].sum() >= 3
    effort = left.effort_limits
    # The object moves straight up in the world (= the base frame here): u = +z.
    u = np.array([0.0, 0.0, 1.0, 0.0, 0.0, 0.0])
    for row in np.flatnonzero(values["feasible"]):
        wrist_from_object = np.linalg.inv(candidates[row])
        com = (wrist_from_object @ np.array([*payload["com"], 1.0]))[:3]
        tool_payload = {"mass": payload["mass"], "com": com}
        q = selection.joint_trajectory("left", int(row))
        expected = []
        for qi in q:
            jac = left.jacobian(qi)
            g = left.gravity_torques(qi, payload=tool_payload)
            mass = left.mass_matrix(qi, payload=tool_payload)
            headroom = np.maximum(effort - np.abs(g), 0.0)
            expected.append(np.sum((headroom * np.linalg.solve(mass, jac.T @ u)) ** 2))
        np.testing.assert_allclose(values["ranked_index"][row], expected, rtol=1e-9)
        assert np.isfinite(values["torque_margin"][row])
        assert np.isfinite(values["dynamic_manipulability"][row])
    with pytest.raises(graspath.GraspathError, match=r"payload\['com'\].*object frame"):
        graspath.Task.from_arrays(
            {"left": left}, poses, np.array(candidates), payload={"mass": 1.0, "com": [0.0, 0.0]}
        )
