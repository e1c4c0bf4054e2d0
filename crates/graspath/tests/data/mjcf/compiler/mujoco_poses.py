"""Reference poses for tests/mjcf_compiler.rs: MuJoCo's own compiler and forward kinematics on
the MJCF files beside this script. For each file, at seeded joint values (the first set is
every joint at 0), the world pose of every body (`xpos`, `xquat`) and of every named geom
(`geom_xpos`, `geom_xmat`) after `mj_kinematics`.

Run (prints the JSON; the test compares it with compiler_mujoco.json, and with a fresh run
when `mujoco` can be imported by GRASPATH_PYTHON):
    python3 -m pip install mujoco numpy
    python3 crates/graspath/tests/data/mjcf/compiler/mujoco_poses.py > \
        crates/graspath/tests/data/mjcf/compiler/compiler_mujoco.json
"""

import json
import os
import sys

import mujoco
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))


def case(path, rng):
    model = mujoco.MjModel.from_xml_path(path)
    data = mujoco.MjData(model)
    joints = [model.joint(j) for j in range(model.njnt)]
    out = []
    for k in range(4):
        qpos = {}
        for joint in joints:
            lo, hi = model.jnt_range[joint.id]
            if k == 0:
                value = 0.0
            elif model.jnt_limited[joint.id]:
                value = rng.uniform(lo, hi)
            else:
                value = rng.uniform(-np.pi, np.pi)
            qpos[joint.name] = float(value)
            data.qpos[model.jnt_qposadr[joint.id]] = value
        mujoco.mj_kinematics(model, data)
        bodies = {
            model.body(b).name: list(data.xpos[b]) + list(data.xquat[b])
            for b in range(1, model.nbody)
        }
        geoms = {
            model.geom(g).name: list(data.geom_xpos[g]) + list(data.geom_xmat[g])
            for g in range(model.ngeom)
            if model.geom(g).name
        }
        out.append({"qpos": qpos, "bodies": bodies, "geoms": geoms})
    return out


def main():
    rng = np.random.default_rng(7)
    files = sorted(f for f in os.listdir(HERE) if f.endswith(".xml"))
    result = {
        "mujoco": mujoco.__version__,
        "cases": {f: case(os.path.join(HERE, f), rng) for f in files},
    }
    json.dump(result, sys.stdout, indent=1)
    sys.stdout.write("\n")


if __name__ == "__main__":
    main()
