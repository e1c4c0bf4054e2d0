"""Writes the grasp-file fixtures of tests/grasp_files.rs the way each generator saves them,
and `expected.json`: every candidate's object_from_tool computed here, independently of
graspath, from the conventions in docs/grasp-files.md.

    python3 make_fixtures.py      # needs numpy, h5py, pyyaml

Writers mirrored (file that defines each layout):
* ACRONYM    acronym_tools/acronym.py load_grasps: h5 grasps/transforms (N,4,4) f8,
             grasps/qualities/flex/object_in_gripper (N,) i8 (chunked, gzip as the dataset)
* GraspGen   grasp_gen/dataset/eval_utils.py save_to_isaac_grasp_format (YAML) and
             docs/GRASP_DATASET_FORMAT.md (JSON grasps.transforms / grasps.object_in_gripper)
* Contact-GraspNet contact_graspnet/inference.py: np.savez(pred_grasps_cam=dict, scores=dict,
             contact_pts=dict), float32 arrays per segment; contact_grasp_estimator.py
             GraspEstimator.predict_grasps returns pred_points[selection_idcs].squeeze(), so a
             segment with one grasp has contact_pts (3,), and predict_scene_grasps with
             filter_grasps leaves contact_pts (0,) where filter_segment keeps none
* M2T2     demo.py load_and_predict: outputs['grasps'], ['grasp_confidence'], ['grasp_contacts']
             are lists with one array per object (m2t2/action_decoder.py ActionDecoder.forward:
             (n, 4, 4), (n,), (n, 3), float32), in the world frame (config.yaml
             eval.world_coord: True); saved with np.savez as lists (an object array, or the
             (K, n, 4, 4) array numpy makes of equal-length lists) or as dictionaries keyed by
             demo.py's object names object_{i:02d}
* GraspNet   graspnetAPI/grasp.py GraspGroup.save_npy: np.save of the (N,17) array
"""
import json
import os

import h5py
import numpy as np
import yaml

HERE = os.path.dirname(os.path.abspath(__file__))
rng = np.random.default_rng(17)


def rotation(q):
    w, x, y, z = q / np.linalg.norm(q)
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ])


def pose(r, t):
    m = np.eye(4)
    m[:3, :3] = r
    m[:3, 3] = t
    return m


def random_poses(n, scale=0.1):
    return np.array([pose(rotation(rng.normal(size=4)), rng.uniform(-scale, scale, 3)) for _ in range(n)])


def permutation_poses(n, scale=0.1):
    """Rotations whose float32 entries are exact (signed permutations, det +1)."""
    out = []
    while len(out) < n:
        p = np.eye(3)[rng.permutation(3)] * rng.choice([-1.0, 1.0], 3)
        if np.linalg.det(p) > 0:
            t = np.round(rng.uniform(-scale, scale, 3) * 1024) / 1024  # exact in float32
            out.append(pose(p, t))
    return np.array(out)


def quaternion_wxyz(m):
    """trimesh.transformations.quaternion_from_matrix (w first), the non-symmetric branch."""
    r = m[:3, :3]
    t = np.trace(r)
    if t > 0:
        s = np.sqrt(t + 1.0) * 2
        return np.array([0.25 * s, (r[2, 1] - r[1, 2]) / s, (r[0, 2] - r[2, 0]) / s, (r[1, 0] - r[0, 1]) / s])
    i = int(np.argmax(np.diag(r)))
    j, k = (i + 1) % 3, (i + 2) % 3
    s = np.sqrt(1.0 + r[i, i] - r[j, j] - r[k, k]) * 2
    q = np.empty(4)
    q[0] = (r[k, j] - r[j, k]) / s
    q[1 + i] = 0.25 * s
    q[1 + j] = (r[j, i] + r[i, j]) / s
    q[1 + k] = (r[k, i] + r[i, k]) / s
    return q if q[0] >= 0 else -q


# Gripper conventions (docs/grasp-files.md): the tool frame in the generator's gripper frame.
FRANKA = pose(np.array([[0.0, 1.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]), [0.0, 0.0, 0.1034])
# GraspGen's Franka Panda: the same frame, TCP at config/grippers/franka_panda.yaml's depth.
GRASPGEN_FRANKA = pose(FRANKA[:3, :3], [0.0, 0.0, 0.10527314])
GRASPNET = pose(np.array([[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]]), [0.0, 0.0, 0.0])

# The task's frames for camera-frame files.
WORLD_FROM_OBJECT = pose(rotation(np.array([0.9, 0.1, -0.2, 0.3])), [0.6, -0.1, 0.05])
WORLD_FROM_CAMERA = pose(rotation(np.array([0.2, 0.9, 0.3, -0.1])), [0.4, 0.2, 0.5])
OBJECT_FROM_CAMERA = np.linalg.inv(WORLD_FROM_OBJECT) @ WORLD_FROM_CAMERA

expected = {
    "world_from_object": WORLD_FROM_OBJECT.tolist(),
    "world_from_camera": WORLD_FROM_CAMERA.tolist(),
    "files": {},
}


def record(name, object_from_frame, frame_from_gripper, gripper_from_tool, scores, widths=None, contacts=None, ids=None):
    keep = [i for i in range(len(frame_from_gripper)) if scores is None or scores[i] > 0]
    expected["files"][name] = [
        {
            "id": int(ids[i]) if ids is not None else i,
            "object_from_tool": (object_from_frame @ frame_from_gripper[i] @ gripper_from_tool).tolist(),
            "log_likelihood": float(np.log(scores[i])) if scores is not None else 0.0,
            "width": None if widths is None else float(widths[i]),
            "contact": None if contacts is None else (object_from_frame @ np.append(contacts[i], 1.0))[:3].tolist(),
        }
        for i in keep
    ]


# ACRONYM HDF5, object frame.
T = random_poses(12)
success = np.array([1, 0, 1, 1, 0, 1, 1, 1, 0, 1, 1, 1], dtype=np.int64)
with h5py.File(os.path.join(HERE, "acronym.h5"), "w") as f:
    f.create_dataset("grasps/transforms", data=T, chunks=(4, 2, 2), compression="gzip")
    f.create_dataset("grasps/qualities/flex/object_in_gripper", data=success, chunks=(6,), compression="gzip")
    f["object/file"] = "meshes/Mug/x.obj"
    f["object/scale"] = 0.01
record("acronym.h5", np.eye(4), T, FRANKA, success.astype(float))

# GraspGen Isaac grasp YAML, object frame.
G = random_poses(5)
conf = rng.uniform(0.2, 1.0, 5)
data = {"format": "isaac_grasp", "format_version": 1.0, "grasps": {}}
for i, (g, c) in enumerate(zip(G, conf.tolist())):
    q = quaternion_wxyz(g)
    data["grasps"][f"grasp_{i}"] = {
        "confidence": c,
        "position": g[:3, 3].tolist(),
        "orientation": {"w": float(q[0]), "xyz": q[1:].tolist()},
    }
with open(os.path.join(HERE, "graspgen.yaml"), "w") as f:
    yaml.dump(data, f, default_flow_style=False, sort_keys=False)
# The oracle is the pose the YAML describes (quaternion re-expanded, as GraspGen's loader does).
G_back = np.array([pose(rotation(quaternion_wxyz(g)), g[:3, 3]) for g in G])
record("graspgen.yaml", np.eye(4), G_back, GRASPGEN_FRANKA, conf)

# GraspGen dataset JSON.
J = random_poses(4)
mask = [True, False, True, True]
with open(os.path.join(HERE, "graspgen_dataset.json"), "w") as f:
    json.dump({"object": {"file": "x.obj", "scale": 1.0}, "grasps": {"transforms": J.tolist(), "object_in_gripper": mask}}, f)
record("graspgen_dataset.json", np.eye(4), J, GRASPGEN_FRANKA, np.array(mask, dtype=float))

# Contact-GraspNet: dictionaries per segment, float32, camera frame.
segs = {1: permutation_poses(3), 3: permutation_poses(2)}
seg_scores = {k: (np.round(rng.uniform(0.1, 1.0, len(v)) * 256) / 256).astype(np.float32) for k, v in segs.items()}
seg_contacts = {k: (np.round(rng.uniform(-0.1, 0.1, (len(v), 3)) * 1024) / 1024).astype(np.float32) for k, v in segs.items()}
np.savez(os.path.join(HERE, "contact_graspnet.npz"),
         pred_grasps_cam={k: v.astype(np.float32) for k, v in segs.items()},
         scores=seg_scores, contact_pts=seg_contacts)
allT = np.concatenate([segs[1], segs[3]])
record("contact_graspnet.npz", OBJECT_FROM_CAMERA, allT, FRANKA,
       np.concatenate([seg_scores[1], seg_scores[3]]).astype(float),
       contacts=np.concatenate([seg_contacts[1], seg_contacts[3]]).astype(float))

# Generic N×4×4 .npy (tool poses, object frame) and .npz with scores.
P = random_poses(6)
np.save(os.path.join(HERE, "poses.npy"), P)
record("poses.npy", np.eye(4), P, np.eye(4), None)
S = rng.uniform(0.1, 1.0, 6)
np.savez_compressed(os.path.join(HERE, "poses.npz"), grasps=P, scores=S)
record("poses.npz", np.eye(4), P, np.eye(4), S)

# GraspNet / AnyGrasp N×17 (GraspGroup.save_npy), camera frame.
Q = permutation_poses(5)
rows = []
for i, q in enumerate(Q):
    score, width, height, depth = [0.9, 0.5, 0.0, 0.25, 0.75][i], [0.04, 0.06, 0.02, 0.1, 0.08][i], 0.02, 0.02
    rows.append(np.concatenate([[score, width, height, depth], q[:3, :3].reshape(-1), q[:3, 3], [i % 2]]))
arr = np.array(rows, dtype=np.float32)
np.save(os.path.join(HERE, "graspnet.npy"), arr)
record("graspnet.npy", OBJECT_FROM_CAMERA, Q, GRASPNET, arr[:, 0].astype(float), widths=arr[:, 1].astype(float))

# Bad inputs (tests/grasp_files.rs and graspath-cli's bad-input table).
BAD = os.path.join(HERE, "bad")
os.makedirs(BAD, exist_ok=True)
with h5py.File(os.path.join(BAD, "no_transforms.h5"), "w") as f:  # ACRONYM without its grasps
    f["object/scale"] = 0.01
    f["grasps/qualities/flex/object_in_gripper"] = np.ones(3, dtype=np.int64)
with h5py.File(os.path.join(BAD, "transforms_3x3.h5"), "w") as f:  # wrong shape
    f["grasps/transforms"] = np.tile(np.eye(3), (2, 1, 1))
damaged = os.path.join(BAD, "damaged_transforms.h5")  # the grasps' object header overwritten
with h5py.File(damaged, "w") as f:
    f["object/scale"] = 0.01
    f["grasps/transforms"] = np.tile(np.eye(4), (2, 1, 1))
    header = h5py.h5o.get_info(f["grasps/transforms"].id).addr
with open(damaged, "r+b") as f:
    f.seek(header)
    f.write(b"\xff" * 8)
np.savez(os.path.join(BAD, "wrong_shape.npz"), pred_grasps_cam=np.zeros((3, 4)), scores=np.ones(3))
# Contact-GraspNet keys with the poses one array but the scores per segment.
np.savez(os.path.join(BAD, "mixed_segments.npz"), pred_grasps_cam=np.tile(np.eye(4), (2, 1, 1)),
         scores={1: np.ones(2)})
skew = random_poses(2)
skew[1, 0, 1] += 0.5  # not a rotation
np.save(os.path.join(BAD, "not_rigid.npy"), skew)
nan = random_poses(2)
nan[0, 2, 3] = np.nan
np.save(os.path.join(BAD, "nan.npy"), nan)
open(os.path.join(BAD, "empty.npy"), "wb").close()
scores_short = random_poses(3)
np.savez(os.path.join(BAD, "scores_mismatch.npz"), grasps=scores_short, scores=np.ones(2))
# A header declaring 10^12 poses followed by one pose's bytes.
header = "{'descr': '<f8', 'fortran_order': False, 'shape': (1000000000000, 4, 4), }"
header += " " * ((64 - (10 + len(header) + 1) % 64) % 64) + "\n"
with open(os.path.join(BAD, "huge_header.npy"), "wb") as f:
    f.write(b"\x93NUMPY\x01\x00" + len(header).to_bytes(2, "little") + header.encode() + np.eye(4).tobytes())
with open(os.path.join(BAD, "huge_header.h5"), "wb") as f:
    # The ACRONYM fixture with its transforms' dataspace claiming 2^40 grasps.
    data = bytearray(open(os.path.join(HERE, "acronym.h5"), "rb").read())
    dims = (12).to_bytes(8, "little") + (4).to_bytes(8, "little") + (4).to_bytes(8, "little")
    at = data.find(dims)
    assert at > 0, "dataspace of grasps/transforms not found"
    data[at:at + 8] = (1 << 40).to_bytes(8, "little")
    f.write(bytes(data))

# Contact-GraspNet with local_regions (one predict_grasps per segment): segment 2 has exactly
# one grasp, so its contact_pts is squeezed to (3,); segment 5 has three; segment 7 was emptied
# by filter_segment (pred_grasps_cam (0, 4, 4), scores (0,), contact_pts (0,)).
one = {2: permutation_poses(1), 5: permutation_poses(3)}
one_scores = {k: (np.round(rng.uniform(0.1, 1.0, len(v)) * 256) / 256).astype(np.float32) for k, v in one.items()}
one_contacts = {k: (np.round(rng.uniform(-0.1, 0.1, (len(v), 3)) * 1024) / 1024).astype(np.float32) for k, v in one.items()}
np.savez(os.path.join(HERE, "contact_graspnet_one_grasp.npz"),
         pred_grasps_cam={2: one[2].astype(np.float32), 5: one[5].astype(np.float32),
                          7: np.zeros((0, 4, 4), dtype=np.float32)},
         scores={2: one_scores[2], 5: one_scores[5], 7: np.zeros(0, dtype=np.float32)},
         contact_pts={2: one_contacts[2].squeeze(), 5: one_contacts[5].squeeze(),
                      7: np.zeros(0, dtype=np.float32)})
assert np.load(os.path.join(HERE, "contact_graspnet_one_grasp.npz"), allow_pickle=True)["contact_pts"].item()[2].shape == (3,)
record("contact_graspnet_one_grasp.npz", OBJECT_FROM_CAMERA, np.concatenate([one[2], one[5]]), FRANKA,
       np.concatenate([one_scores[2], one_scores[5]]).astype(float),
       contacts=np.concatenate([one_contacts[2], one_contacts[5]]).astype(float))

# M2T2, world frame: three objects with 2, 1 and 3 grasps.
WORLD_TO_OBJECT = np.linalg.inv(WORLD_FROM_OBJECT)
m_grasps = [permutation_poses(n).astype(np.float32) for n in (2, 1, 3)]
m_conf = [(np.round(rng.uniform(0.1, 1.0, len(g)) * 256) / 256).astype(np.float32) for g in m_grasps]
m_contacts = [(np.round(rng.uniform(-0.1, 0.1, (len(g), 3)) * 1024) / 1024).astype(np.float32) for g in m_grasps]


def object_list(arrays):
    # What np.array(list, dtype=object) makes of a list of arrays of different lengths.
    out = np.empty(len(arrays), dtype=object)
    for i, a in enumerate(arrays):
        out[i] = a
    return out


np.savez(os.path.join(HERE, "m2t2_objects.npz"), grasps=object_list(m_grasps),
         grasp_confidence=object_list(m_conf), grasp_contacts=object_list(m_contacts))
m_all = np.concatenate(m_grasps).astype(float)
m_all_conf = np.concatenate(m_conf).astype(float)
m_all_contacts = np.concatenate(m_contacts).astype(float)
record("m2t2_objects.npz", WORLD_TO_OBJECT, m_all, FRANKA, m_all_conf, contacts=m_all_contacts)
names = {f"object_{i:02d}": i for i in range(len(m_grasps))}
np.savez(os.path.join(HERE, "m2t2_named.npz"),
         grasps={n: m_grasps[i] for n, i in names.items()},
         grasp_confidence={n: m_conf[i] for n, i in names.items()},
         grasp_contacts={n: m_contacts[i] for n, i in names.items()})
record("m2t2_named.npz", WORLD_TO_OBJECT, m_all, FRANKA, m_all_conf, contacts=m_all_contacts)
# Two objects with two grasps each: np.savez turns the lists into (2, 2, 4, 4), (2, 2), (2, 2, 3).
np.savez(os.path.join(HERE, "m2t2_equal.npz"), grasps=[m_grasps[0], m_grasps[2][:2]],
         grasp_confidence=[m_conf[0], m_conf[2][:2]], grasp_contacts=[m_contacts[0], m_contacts[2][:2]])
assert np.load(os.path.join(HERE, "m2t2_equal.npz"))["grasps"].shape == (2, 2, 4, 4)
record("m2t2_equal.npz", WORLD_TO_OBJECT, np.concatenate([m_grasps[0], m_grasps[2][:2]]).astype(float), FRANKA,
       np.concatenate([m_conf[0], m_conf[2][:2]]).astype(float),
       contacts=np.concatenate([m_contacts[0], m_contacts[2][:2]]).astype(float))

with open(os.path.join(HERE, "expected.json"), "w") as f:
    json.dump(expected, f, indent=1)
print("wrote", ", ".join(sorted(expected["files"])))
