"""Writes the untrusted-input fixtures of tests/grasp_files.rs (`bad_grasp_files_give_one_clear_error`)
that need only numpy: arrays NumPy really writes (complex, long double, pickled dictionaries of
them) and hand-made pickles and headers that ask for far more memory than they hold.

    python3 make_bad.py      # needs numpy
"""
import io
import os
import zipfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
poses = np.stack([np.eye(4)] * 3)


def write(name, data):
    with open(os.path.join(HERE, name), "wb") as f:
        f.write(data)


def npz(members):
    """A stored .npz (what np.savez writes) of raw .npy member images."""
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w", zipfile.ZIP_STORED) as z:
        for name, data in members.items():
            z.writestr(name + ".npy", data)
    return buf.getvalue()


def object_npy(pickle_bytes):
    """A 0-d object .npy whose data is `pickle_bytes` (as np.save writes a dictionary)."""
    header = "{'descr': '|O', 'fortran_order': False, 'shape': (), }"
    header += " " * ((64 - (10 + len(header) + 1) % 64) % 64) + "\n"
    return b"\x93NUMPY\x01\x00" + len(header).to_bytes(2, "little") + header.encode() + pickle_bytes


# Complex and long-double arrays, as np.savez / np.save write them.
np.savez(os.path.join(HERE, "complex.npz"), grasps=poses.astype(np.complex128))
np.save(os.path.join(HERE, "longdouble.npy"), poses.astype(np.longdouble))
np.savez(os.path.join(HERE, "complex_segments.npz"),
         pred_grasps_cam={0: poses.astype(np.complex64)}, allow_pickle=True)

# Pickled dtypes with no size ('f0') or no name (''): the bytes NumPy writes for float32, edited.
buf = io.BytesIO()
np.save(buf, np.array({0: poses.astype(np.float32)}, dtype=object), allow_pickle=True)
real = buf.getvalue()
F4 = b"\x8c\x02f4"  # SHORT_BINUNICODE 'f4' (protocol 4, NumPy 2)
assert real.count(F4) == 1, "numpy pickles the dtype as SHORT_BINUNICODE 'f4'"
write("pickled_f0.npz", npz({"pred_grasps_cam": real.replace(F4, b"\x8c\x02f0")}))
write("pickled_empty_dtype.npz", npz({"pred_grasps_cam": real.replace(F4, b"\x8c\x00")}))

# A memo bomb: a list put twice into the next one, 40 times (2^40 copies of the first).
bomb = b"\x80\x02]q\x00" + b"(h\x00h\x00lq\x00" * 40 + b"."
write("memo_bomb.npz", npz({"pred_grasps_cam": object_npy(bomb)}))

# Lists nested 1000 deep: MARK 1000 times, then LIST 1000 times.
write("deep_pickle.npz", npz({"pred_grasps_cam": object_npy(b"\x80\x02" + b"(" * 1000 + b"l" * 1000 + b".")}))

# A 13-byte .npy whose version-2 header claims 4 GiB.
write("header_4gib.npy", b"\x93NUMPY\x02\x00\xff\xff\xff\xff{")

# ACRONYM JSON whose transforms are not rectangular: a number, then a 4x4 matrix.
write("ragged.json", b'{"transforms": [0, [[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]], '
      b'"quality_flex_object_in_gripper": [1, 1]}')
