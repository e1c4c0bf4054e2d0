"""Reference values for tests/mjcf_dynamics.rs: MuJoCo's inverse dynamics (`mj_inverse`) and
joint-space inertia (`mj_fullM`) of the chain `base -> tool` of dynamics_arm.xml, at seeded
states. The finger's slide joint, off the chain, is held at 0 with zero velocity and
acceleration, so the finger moves with the wrist as a rigid body. Gravity is MuJoCo's, 9.81
m/s² along the world's -z; the file records it in the frame of body `base`.

Run (writes dynamics_arm_mujoco.json beside this file):
    python3 -m venv /tmp/mj && /tmp/mj/bin/pip install mujoco==4.0.0 numpy
    /tmp/mj/bin/python crates/graspath/tests/data/mjcf/dynamics_arm_mujoco.py
"""

import json
import os

import mujoco
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
CHAIN = ["j1", "j2", "j3", "j4", "j5", "j6"]


def main():
    model = mujoco.MjModel.from_xml_path(os.path.join(HERE, "dynamics_arm.xml"))
    data = mujoco.MjData(model)
    dofs = [model.jnt_dofadr[model.joint(name).id] for name in CHAIN]
    qpos = [model.jnt_qposadr[model.joint(name).id] for name in CHAIN]
    ranges = [model.jnt_range[model.joint(name).id] for name in CHAIN]
    mujoco.mj_forward(model, data)
    world_from_base = data.xmat[model.body("base").id].reshape(3, 3)
    gravity_base = world_from_base.T @ model.opt.gravity
    rng = np.random.default_rng(7)
    samples = []
    for _ in range(20):
        data.qpos[:] = model.qpos0
        data.qvel[:] = 0.0
        data.qacc[:] = 0.0
        q = np.array([rng.uniform(lo, hi) for lo, hi in ranges])
        qd = rng.uniform(-2.0, 2.0, len(CHAIN))
        qdd = rng.uniform(-5.0, 5.0, len(CHAIN))
        data.qpos[qpos] = q
        row = {"q": q.tolist(), "qd": qd.tolist(), "qdd": qdd.tolist()}
        mujoco.mj_inverse(model, data)
        row["g"] = data.qfrc_inverse[dofs].tolist()
        data.qvel[dofs] = qd
        data.qacc[dofs] = qdd
        mujoco.mj_inverse(model, data)
        row["tau"] = data.qfrc_inverse[dofs].tolist()
        full = np.zeros((model.nv, model.nv))
        mujoco.mj_fullM(model, data, full)
        row["mass_matrix"] = full[np.ix_(dofs, dofs)].reshape(-1).tolist()
        samples.append(row)
    out = {
        "generator": "dynamics_arm_mujoco.py",
        "mujoco": mujoco.__version__,
        "joint_names": CHAIN,
        "gravity_base": gravity_base.tolist(),
        "samples": samples,
    }
    with open(os.path.join(HERE, "dynamics_arm_mujoco.json"), "w") as f:
        json.dump(out, f, indent=1)
        f.write("\n")


if __name__ == "__main__":
    main()
