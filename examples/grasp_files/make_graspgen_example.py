"""Writes graspgen_box.yaml the way GraspGen's demo_object_mesh.py --output_file does
(grasp_gen/dataset/eval_utils.py save_to_isaac_grasp_format): eleven top grasps of the
Franka hand along the top edge of the 0.06 × 0.40 × 0.10 m box of pick_and_place_left.yaml,
in the object frame, the hand's fingers closing across the box's 6 cm (hand x = object x),
its approach (hand z) pointing down, and its TCP 2 cm below the top face.

    python3 make_graspgen_example.py   # needs numpy and pyyaml
"""
import os

import numpy as np
import yaml

TCP = 0.10527314  # GraspGen config/grippers/franka_panda.yaml depth: hand base -> TCP
top, depth = 0.05, 0.02
grasps, confidences = [], []
for i, y in enumerate(np.linspace(-0.18, 0.18, 11)):
    # Hand z = -object z (down), hand x = object x (across the 6 cm), hand y = -object y.
    r = np.array([[1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, -1.0]])
    g = np.eye(4)
    g[:3, :3] = r
    g[:3, 3] = [0.0, y, top - depth + TCP]
    grasps.append(g)
    confidences.append(round(0.5 + 0.4 * np.cos(y / 0.18 * np.pi / 2), 4))  # central grasps likelier

data = {"format": "isaac_grasp", "format_version": 1.0, "grasps": {}}
for i, (g, c) in enumerate(zip(grasps, confidences)):
    # trimesh.transformations.quaternion_from_matrix of a 180° turn about x: (w, x, y, z) = (0, 1, 0, 0).
    data["grasps"][f"grasp_{i}"] = {
        "confidence": float(c),
        "position": g[:3, 3].tolist(),
        "orientation": {"w": 0.0, "xyz": [1.0, 0.0, 0.0]},
    }
with open(os.path.join(os.path.dirname(os.path.abspath(__file__)), "graspgen_box.yaml"), "w") as f:
    yaml.dump(data, f, default_flow_style=False, sort_keys=False)
