"""Reference values for tests/dynamics.rs: Pinocchio's gravity torques, RNEA and CRBA on the
arm chains of example-robot-data's Panda, UR5 and Baxter, without and with a payload.

Each chain is Pinocchio's model of the whole URDF reduced to the joints between the chain's
base and tip (every other joint locked at zero, so that the bodies hanging from the chain off
its path, such as the Panda's fingers, stay attached as rigid bodies). The payload is appended
as a body at the tool frame (the tip link frame times `tip_from_tool`). Gravity is Pinocchio's
default, 9.81 m/s² along the root link's -z; the file records it in the chain's base frame.

Run (writes pinocchio_dynamics.json beside this file):
    target/pyenv/bin/pip install pin example-robot-data
    target/pyenv/bin/python crates/graspath/tests/data/dynamics/pinocchio_reference.py
"""

import json
import os
import sysconfig
from importlib.metadata import version

import numpy as np
import pinocchio as pin

ROBOTS = os.path.join(
    sysconfig.get_paths()["purelib"], "cmeel.prefix", "share", "example-robot-data", "robots"
)

CHAINS = [
    ("panda", "panda_description/urdf/panda.urdf", "panda_link0", "panda_hand_tcp"),
    ("ur5", "ur_description/urdf/ur5_robot.urdf", "base_link", "tool0"),
    ("baxter", "baxter_description/urdf/baxter.urdf", "base", "left_gripper"),
]

TIP_FROM_TOOL = {"xyz": [0.01, -0.02, 0.05], "rpy": [0.1, -0.2, 0.3]}
PAYLOAD_MASS = 1.7
PAYLOAD_COM = [0.02, -0.03, 0.11]
PAYLOAD_INERTIA = [[0.012, 0.001, -0.002], [0.001, 0.009, 0.0005], [-0.002, 0.0005, 0.006]]
SAMPLES = 20


def chain_model(full, base, tip):
    """The full model reduced to the joints between `base` and `tip`, and the ids of the
    base and tip frames in it."""
    tip_joint = full.frames[full.getFrameId(tip)].parentJoint
    base_joint = full.frames[full.getFrameId(base)].parentJoint
    keep = set(full.supports[tip_joint]) - set(full.supports[base_joint])
    locked = [j for j in range(1, full.njoints) if j not in keep]
    model = pin.buildReducedModel(full, locked, pin.neutral(full))
    return model, model.getFrameId(base), model.getFrameId(tip)


def main():
    rng = np.random.default_rng(31)
    tool = pin.SE3(pin.rpy.rpyToMatrix(np.array(TIP_FROM_TOOL["rpy"])), np.array(TIP_FROM_TOOL["xyz"]))
    payload = pin.Inertia(PAYLOAD_MASS, np.array(PAYLOAD_COM), np.array(PAYLOAD_INERTIA))
    out = {
        "generator": "pinocchio_reference.py",
        "pinocchio": pin.__version__,
        "example_robot_data": version("example-robot-data"),
        "tip_from_tool": TIP_FROM_TOOL,
        "payload": {"mass": PAYLOAD_MASS, "com": PAYLOAD_COM, "inertia": PAYLOAD_INERTIA},
        "robots": [],
    }
    for name, urdf, base, tip in CHAINS:
        full = pin.buildModelFromUrdf(os.path.join(ROBOTS, urdf))
        model, base_frame, tip_frame = chain_model(full, base, tip)
        data = model.createData()
        loaded = model.copy()
        tip_placement = model.frames[tip_frame]
        loaded.appendBodyToJoint(tip_placement.parentJoint, payload, tip_placement.placement * tool)
        loaded_data = loaded.createData()
        pin.framesForwardKinematics(model, data, pin.neutral(model))
        world_from_base = data.oMf[base_frame].rotation
        gravity_base = world_from_base.T @ model.gravity.linear
        names = [model.names[j] for j in range(1, model.njoints)]
        assert model.nq == model.nv == len(names), name
        lower = np.where(np.isfinite(model.lowerPositionLimit), model.lowerPositionLimit, -np.pi)
        upper = np.where(np.isfinite(model.upperPositionLimit), model.upperPositionLimit, np.pi)
        samples = []
        for _ in range(SAMPLES):
            q = rng.uniform(lower, upper)
            qd = rng.uniform(-2.0, 2.0, model.nv)
            qdd = rng.uniform(-5.0, 5.0, model.nv)
            row = {"q": q.tolist(), "qd": qd.tolist(), "qdd": qdd.tolist()}
            for key, (m, d) in {"": (model, data), "_payload": (loaded, loaded_data)}.items():
                g = pin.computeGeneralizedGravity(m, d, q).copy()
                tau = pin.rnea(m, d, q, qd, qdd).copy()
                upper_m = pin.crba(m, d, q).copy()
                mass = np.triu(upper_m) + np.triu(upper_m, 1).T
                row["g" + key] = g.tolist()
                row["tau" + key] = tau.tolist()
                row["mass_matrix" + key] = mass.reshape(-1).tolist()
            samples.append(row)
        out["robots"].append(
            {
                "name": name,
                "urdf": urdf,
                "base": base,
                "tip": tip,
                "joint_names": names,
                "gravity_base": gravity_base.tolist(),
                "moving_mass": float(sum(model.inertias[j].mass for j in range(1, model.njoints))),
                "samples": samples,
            }
        )
    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "pinocchio_dynamics.json")
    with open(path, "w") as f:
        json.dump(out, f, indent=1)
        f.write("\n")
    print(path)


if __name__ == "__main__":
    main()
