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


@pytest.mark.parametrize(
    "values, fragment",
    [
        (np.zeros(7, dtype="datetime64[s]"), "dates and durations are refused"),
        (np.zeros(7, dtype="timedelta64[ms]"), "dates and durations are refused"),
        (np.array(["0.1"] * 7), "strings are refused"),
        (["0.1"] * 7, "strings are refused"),
        (np.zeros(7, dtype="S3"), "strings are refused"),
        (np.zeros(7, dtype=[("a", "f8")]), "structured and raw records are refused"),
    ],
)
def test_values_numpy_would_cast_to_other_numbers_are_refused(panda, values, fragment):
    with pytest.raises(graspath.GraspathError, match=fragment):
        panda.fk(values)


def test_pose_fields_are_read_as_arrays_complex_refused_and_views_by_strides():
    with pytest.raises(graspath.GraspathError, match="field 'xyz'.*complex values are refused"):
        graspath.pose_matrix({"xyz": np.array([0.1, 0.2, 0.3 + 1j])})
    with pytest.raises(graspath.GraspathError, match=r"field 'matrix': give 4 rows of 4 numbers"):
        graspath.pose_matrix({"matrix": np.eye(3)})
    matrix = np.eye(4)
    matrix[:3, 3] = [0.1, 0.2, 0.3]
    # The transpose of a transposed copy: the same matrix, column-major in memory.
    fortran = np.asfortranarray(matrix)
    assert not fortran.flags.c_contiguous
    np.testing.assert_array_equal(graspath.pose_matrix({"matrix": fortran}), matrix)
    np.testing.assert_array_equal(
        graspath.pose_matrix({"xyz": np.array([0.3, 0.2, 0.1])[::-1]})[:3, 3], [0.1, 0.2, 0.3]
    )


def test_a_slice_of_the_entry_point_fuzz_campaign_finds_nothing():
    """The deterministic slice of `fuzz_entry_points.py` (its oracles: no exception other than
    GraspathError / TypeError, refused kinds never accepted, strided arrays read as their
    C-ordered copies)."""
    import fuzz_entry_points

    outcomes, findings = fuzz_entry_points.campaign(3000, seed=11)
    assert findings == [], findings[:3]
    # Both outcomes occur: the slice reaches the computations and the refusals.
    assert outcomes["accepted"] > 500 and outcomes["refused"] > 500, outcomes
