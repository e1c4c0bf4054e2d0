"""Untrusted arrays and grasp files: complex values refused (never their real part kept),
broadcast views refused before a huge copy is made, refused grasp files raise GraspathError
(never PanicException or a crash)."""

import os

import numpy as np
import pytest

import graspath

BAD = os.path.join(
    os.path.dirname(__file__), "..", "..", "graspath", "tests", "data", "grasp_files", "bad"
)


@pytest.fixture(scope="module")
def panda():
    return graspath.Robot.builtin("panda")


def test_complex_configurations_are_refused(panda):
    q = np.zeros((3, panda.dof), dtype=np.complex128)
    with pytest.raises(graspath.GraspathError, match="complex values are refused"):
        panda.fk(q)
    with pytest.raises(graspath.GraspathError, match="complex values are refused"):
        panda.fk([0j] * panda.dof)


def test_a_broadcast_view_of_a_billion_rows_is_refused_before_it_is_copied(panda):
    q = np.broadcast_to(np.zeros(panda.dof), (10**9, panda.dof))
    assert q.strides[0] == 0
    with pytest.raises(graspath.GraspathError, match="row-major copy would take more than"):
        panda.fk(q)
    # A small broadcast view is read through its strides.
    small = np.broadcast_to(np.zeros(panda.dof), (5, panda.dof))
    np.testing.assert_array_equal(panda.fk(small), panda.fk(np.zeros((5, panda.dof))))


# Contact-GraspNet archives (the pickled ones) are in the camera frame: given a camera pose, the
# file itself is read and refused.
CAMERA = {"camera_from_object": np.eye(4)}


@pytest.mark.parametrize(
    "name, fragment, options",
    [
        ("memo_bomb.npz", "decodes to more than", CAMERA),
        ("deep_pickle.npz", "nests containers more than 64 deep", CAMERA),
        ("header_4gib.npy", "more than 65536 is refused", {}),
        ("complex.npz", "complex numbers", {}),
        ("pickled_f0.npz", "is not a number type", CAMERA),
        ("pickled_empty_dtype.npz", "is not a number type", CAMERA),
        ("ragged.json", "not rectangular", {}),
    ],
)
def test_refused_grasp_files_raise_graspath_errors(name, fragment, options):
    with pytest.raises(graspath.GraspathError, match=fragment) as info:
        graspath.read_grasps(os.path.join(BAD, name), **options)
    assert name in str(info.value)
