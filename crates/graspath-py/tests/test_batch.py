"""`graspath.select_batch` against `graspath.select` run task by task (the library's own ranking,
`rank_candidates`, which the batch does not call), and its slices, top-k and thread counts
against the whole batch."""

import numpy as np
import pytest

import graspath
from conftest import EXAMPLES

LEFT = EXAMPLES / "pick_and_place_left.yaml"
BOTH = EXAMPLES / "pick_and_place_both.yaml"
CLUTTERED = EXAMPLES / "scene" / "pick_and_place_left_cluttered.yaml"

FLOAT_COLUMNS = ("mu_l2", "mu_linf", "mu_l1", "yoshikawa_at_grasp", "clearance", "score", "rank", "failure_sample")


def likely_task():
    """The left Pick-and-Place with unequal likelihoods (the score takes them relative to the
    most likely candidate, so a slice must see the whole task's largest)."""
    task = graspath.Task.load(LEFT)
    likelihoods = np.linspace(0.2, 1.0, len(task))[::-1].copy()
    likelihoods[7] = 3.0
    return graspath.Task.from_arrays(
        {"left": task.robot("left")},
        task.object_poses,
        task.candidate_poses,
        times=task.times,
        likelihoods=likelihoods,
        branches=8,
        ik_iterations=2000,
        redundancy="best_branch",
        name="likely",
    )


@pytest.fixture(scope="module")
def tasks():
    return [graspath.Task.load(LEFT), likely_task(), graspath.Task.load(BOTH), graspath.Task.load(CLUTTERED)]


@pytest.fixture(scope="module")
def batch(tasks):
    return graspath.select_batch(tasks)


@pytest.fixture(scope="module")
def one_by_one(tasks):
    return [graspath.select(t) for t in tasks]


def rows_of(columns, obj, arm):
    mask = (columns["object"] == obj) & (columns["arm"] == arm)
    return {k: v[mask] for k, v in columns.items()}


def test_every_row_equals_select_task_by_task(tasks, batch, one_by_one):
    expected_rows = sum(len(t) * len(t.arms) for t in tasks)
    assert all(len(v) == expected_rows for v in batch.values())
    assert batch["object"].dtype == np.int64 and batch["feasible"].dtype == np.bool_
    checked_clearance = False
    for obj, (task, selection) in enumerate(zip(tasks, one_by_one)):
        for arm_index, arm in enumerate(task.arms):
            rows = rows_of(batch, obj, arm)
            arrays = selection.arrays(arm)
            records = [r for r in selection.candidates if r["arm"] == arm]
            np.testing.assert_array_equal(rows["candidate"], np.arange(len(task)))
            np.testing.assert_array_equal(rows["arm_index"], arm_index)
            np.testing.assert_array_equal(rows["id"], arrays["id"])
            np.testing.assert_array_equal(rows["feasible"], arrays["feasible"])
            for name in FLOAT_COLUMNS:
                np.testing.assert_array_equal(rows[name], arrays[name], err_msg=f"{task.name} {arm} {name}")
            assert list(rows["label"]) == [r["label"] for r in records]
            assert list(rows["failure_reason"]) == [r["failure"]["reason"] if r["failure"] else None for r in records]
            assert list(rows["rejected"]) == [r.get("rejected") for r in records]
            np.testing.assert_allclose(
                rows["log_likelihood"], [c["log_likelihood"] for c in task.candidates], rtol=0, atol=0
            )
            checked_clearance |= bool(np.isfinite(rows["clearance"]).any())
    assert checked_clearance, "the scene task gives clearances"
    assert np.isnan(rows_of(batch, 0, "left")["clearance"]).all(), "no scene, no clearance"


def test_the_likelihood_enters_the_score(batch, one_by_one):
    """The likely task ranks differently from the same task without likelihoods (otherwise
    the slice test below would not test the relative likelihood)."""
    plain, likely = rows_of(batch, 0, "left"), rows_of(batch, 1, "left")
    assert not np.array_equal(plain["rank"], likely["rank"], equal_nan=True)


def test_any_thread_count_gives_the_same_columns(tasks, batch):
    for threads in (1, 2, 3):
        other = graspath.select_batch(tasks, threads=threads)
        for name, values in batch.items():
            np.testing.assert_array_equal(other[name], values, err_msg=name)


def test_slices_merge_to_the_whole_ranking(tasks, batch):
    """Cut every task into three slices: each slice's scores are the whole task's, and sorting
    their union by score (ties by candidate) gives the whole task's ranks."""
    cuts = [(0, 5), (5, 13), (13, None)]
    parts = []
    for start, stop in cuts:
        slices = [(start, len(t) if stop is None else stop) for t in tasks]
        parts.append(graspath.select_batch(tasks, slices=slices))
        for obj, t in enumerate(tasks):
            mask = parts[-1]["object"] == obj
            assert set(parts[-1]["candidate"][mask]) == set(range(*slices[obj]))
    for obj, task in enumerate(tasks):
        for arm in task.arms:
            whole = rows_of(batch, obj, arm)
            pieces = [rows_of(p, obj, arm) for p in parts]
            candidate = np.concatenate([p["candidate"] for p in pieces])
            score = np.concatenate([p["score"] for p in pieces])
            np.testing.assert_array_equal(candidate, whole["candidate"])
            np.testing.assert_array_equal(score, whole["score"])
            ranked = np.flatnonzero(~np.isnan(score))
            order = ranked[np.lexsort((candidate[ranked], -score[ranked]))]
            merged_rank = np.full(len(score), np.nan)
            merged_rank[order] = np.arange(1, len(order) + 1)
            np.testing.assert_array_equal(merged_rank, whole["rank"])
            for p in pieces:  # ranks within each slice: 1..m over its ranked rows
                ranks = p["rank"][~np.isnan(p["rank"])]
                assert sorted(ranks) == list(range(1, len(ranks) + 1))


def test_top_k_is_the_best_k_of_every_object_and_arm(tasks, batch):
    top = graspath.select_batch(tasks, top_k=3)
    expected = []
    for obj, task in enumerate(tasks):
        for arm in task.arms:
            rows = rows_of(batch, obj, arm)
            ranked = np.flatnonzero(~np.isnan(rows["score"]))
            best = ranked[np.lexsort((rows["candidate"][ranked], -rows["score"][ranked]))][:3]
            expected += [(obj, arm, int(rows["candidate"][c]), r + 1) for r, c in enumerate(best)]
    got = list(zip(top["object"].tolist(), top["arm"].tolist(), top["candidate"].tolist(), top["rank"].astype(int).tolist()))
    assert got == expected


def test_empty_batches_and_empty_slices(tasks):
    empty = graspath.select_batch([])
    assert set(empty) >= {"object", "arm", "candidate", "score", "rank"}
    assert all(len(v) == 0 for v in empty.values())
    nothing = graspath.select_batch(tasks[:1], slices=[(4, 4)], top_k=2)
    assert all(len(v) == 0 for v in nothing.values())


def test_bad_input_is_one_clear_error(tasks):
    with pytest.raises(graspath.GraspathError, match="top_k must be at least 1"):
        graspath.select_batch(tasks, top_k=0)
    with pytest.raises(graspath.GraspathError, match="threads must be at least 1"):
        graspath.select_batch(tasks, threads=0)
    with pytest.raises(graspath.GraspathError, match=r"slices: 1 given for 4 tasks"):
        graspath.select_batch(tasks, slices=[(0, 1)])
    with pytest.raises(graspath.GraspathError, match=r"slices\[1\] = \(3, 22\) is not a candidate range of task 1 \('likely', 21 candidates\)"):
        graspath.select_batch(tasks[:2], slices=[(0, 1), (3, 22)])
    with pytest.raises(graspath.GraspathError, match=r"slices\[0\] = \(5, 4\)"):
        graspath.select_batch(tasks[:1], slices=[(5, 4)])
    with pytest.raises(TypeError):
        graspath.select_batch([LEFT])


def test_load_with_another_candidate_file(tmp_path):
    """``Task.load(path, candidates=file)`` reads that file with the task file's candidate
    options: the task equals one whose ``candidates.file`` names it; a missing file is an error
    naming it."""
    template = EXAMPLES / "grasp_files" / "pick_and_place_graspgen.yaml"
    grasps = tmp_path / "other.yaml"
    grasps.write_text((EXAMPLES / "grasp_files" / "graspgen_box.yaml").read_text().replace("confidence: 0.5\n", "confidence: 0.9\n", 1))
    own = tmp_path / "task.yaml"
    own.write_text(template.read_text().replace("file: graspgen_box.yaml", "file: other.yaml"))
    a, b = graspath.Task.load(template, candidates=grasps), graspath.Task.load(own)
    assert len(a) == len(b) > 0
    np.testing.assert_array_equal(a.candidate_poses, b.candidate_poses)
    assert [c["likelihood"] for c in a.candidates] == [c["likelihood"] for c in b.candidates]
    assert a.candidates[0]["likelihood"] == 0.9
    with pytest.raises(graspath.GraspathError, match="nothere.yaml"):
        graspath.Task.load(template, candidates=tmp_path / "nothere.yaml")


def pairs_of(selection, task, count):
    """``select``'s first ``count`` pairs as ``(first id, second id, first label, second label,
    score, rank)``."""
    first, second = task.arms
    return [(p[first], p[second], p[f"{first}_label"], p[f"{second}_label"], p["score"], p["rank"]) for p in selection.pairs[:count]]


def pair_rows(columns):
    return list(zip(*(columns[c].tolist() for c in ("first_id", "second_id", "first_label", "second_label", "score", "rank"))))


def by_duration(tmp_path_factory):
    """``pick_and_place_both.yaml`` ranked by its motions' duration (pairs: the slower arm's)."""
    text = BOTH.read_text().replace("index: { mode: twist,", "index: { measure: duration, mode: twist,")
    assert "measure: duration" in text
    path = tmp_path_factory.mktemp("duration") / "pick_and_place_both_duration.yaml"
    path.write_text(text)
    return path


@pytest.mark.parametrize("path", [BOTH, EXAMPLES / "pick_rotate_place_both.yaml", EXAMPLES / "scene" / "pick_and_place_both_on_table.yaml", "by_duration"])
def test_pairs_from_slices_equal_select(path, tmp_path_factory):
    """``select_pairs`` on the union of slices' rows gives ``select``'s pairs (the same pairs,
    order and scores), for every cut of the candidates and any ``top_k``; on the table the check
    between the arms refuses pairs, so the candidates it re-scores decide the result."""
    if path == "by_duration":
        path = by_duration(tmp_path_factory)
    task = graspath.Task.load(path)
    selection = graspath.select(task)
    if "on_table" in path.name:
        assert selection.summary["colliding_pairs"] > 0, "the example no longer exercises the check between the arms"
    n = len(task)
    assert len(selection.pairs) == 10
    for cuts in ([0, n], [0, 7, n], [0, 1, 5, 13, 20, n]):
        parts = [graspath.select_batch([task], slices=[(a, b)]) for a, b in zip(cuts, cuts[1:])]
        # Reversed: the rows' order does not matter.
        rows = {c: np.concatenate([p[c] for p in parts][::-1]) for c in ("arm_index", "candidate", "score", "mu_l2", "mu_l1", "duration")}
        for top_k in (None, 1, 4, 25):
            got = graspath.select_pairs(task, rows, top_k=top_k)
            assert pair_rows(got) == pairs_of(selection, task, 10 if top_k is None else top_k), (cuts, top_k)
            assert got["first_arm"].tolist() == [task.arms[0]] * len(got["rank"])
            assert got["second_arm"].tolist() == [task.arms[1]] * len(got["rank"])
            ids = [c["id"] for c in task.candidates]
            assert [ids[i] for i in got["first_candidate"]] == got["first_id"].tolist()
            assert [ids[i] for i in got["second_candidate"]] == got["second_id"].tolist()


def test_pairs_bad_input_is_one_clear_error(tasks):
    both = tasks[2]
    rows = graspath.select_batch([both])
    ranked = ~np.isnan(rows["score"])
    assert ranked.sum() > 2
    with pytest.raises(graspath.GraspathError, match=r"pick_and_place_left.yaml: arm pairs need a task with two arms \(it has 1\)"):
        graspath.select_pairs(tasks[0], graspath.select_batch(tasks[:1]))
    twice = {c: np.concatenate([rows[c], rows[c][ranked][:1]]) for c in rows}
    with pytest.raises(graspath.GraspathError, match=r"pick_and_place_both.yaml: arm '(left|right)': candidate \d+ is given twice"):
        graspath.select_pairs(both, twice)
    far = {c: v.copy() for c, v in rows.items()}
    far["candidate"][np.flatnonzero(ranked)[0]] = 21
    with pytest.raises(graspath.GraspathError, match=r"candidate 21 is not one of the task's 21 candidates"):
        graspath.select_pairs(both, far)
    with pytest.raises(graspath.GraspathError, match=r"rows: no 'mu_l2' column"):
        graspath.select_pairs(both, {c: rows[c] for c in ("arm_index", "candidate", "score")})
    with pytest.raises(graspath.GraspathError, match="top_k must be at least 1"):
        graspath.select_pairs(both, rows, top_k=0)


FACES = (EXAMPLES / "workload_1000_faces.yaml").read_text().replace("count: 1000", "count: 30")
FACES_POSE = "pose: { xyz: [0.70, 0.25, -0.05] }"


@pytest.mark.parametrize(
    "pose, written",
    [
        ({"xyz": [0.65, 0.3, -0.02], "rpy_deg": [0, 0, 25]}, "{ xyz: [0.65, 0.3, -0.02], rpy_deg: [0, 0, 25] }"),
        ({"xyz": [0.7, 0.2, 0.0], "quaternion": [0, 0, 0.2588190, 0.9659258]}, "{ xyz: [0.7, 0.2, 0.0], quaternion: [0, 0, 0.2588190, 0.9659258] }"),
        ({"xyz": [0.72, 0.22, -0.04], "rpy": [0.1, 0, -0.2]}, "{ xyz: [0.72, 0.22, -0.04], rpy: [0.1, 0, -0.2] }"),
        ({"xyz": [0.6, 0.25, 0.0]}, "{ xyz: [0.6, 0.25, 0.0] }"),
    ],
)
def test_load_with_an_object_pose_equals_the_pose_written_in_the_file(tmp_path, pose, written):
    """``Task.load(path, object_pose=...)`` is the task of a file whose ``object.pose`` is that
    pose: the same path, candidates and selection, value for value."""
    assert FACES_POSE in FACES
    template = tmp_path / "faces.yaml"
    template.write_text(FACES)
    own = tmp_path / "own.yaml"
    own.write_text(FACES.replace(FACES_POSE, f"pose: {written}"))
    moved, oracle = graspath.Task.load(template, object_pose=pose), graspath.Task.load(own)
    np.testing.assert_array_equal(moved.object_poses, oracle.object_poses)
    np.testing.assert_array_equal(moved.object_poses[0], graspath.pose_matrix(pose))
    assert not np.array_equal(moved.object_poses, graspath.Task.load(template).object_poses)
    np.testing.assert_array_equal(moved.candidate_poses, oracle.candidate_poses)
    a, b = graspath.select(moved).arrays("left"), graspath.select(graspath.Task.load(own)).arrays("left")
    for column in ("score", "rank", "mu_l2", "mu_linf", "mu_l1"):
        np.testing.assert_array_equal(a[column], b[column], err_msg=column)
    # A 4×4 matrix places the object too.
    by_matrix = graspath.Task.load(template, object_pose=graspath.pose_matrix(pose))
    np.testing.assert_allclose(by_matrix.object_poses, oracle.object_poses, atol=1e-12)


def test_bad_object_poses_name_the_field(tmp_path):
    template = tmp_path / "faces.yaml"
    template.write_text(FACES)
    cases = [
        ({"xyz": [0.7, float("nan"), 0]}, r"faces.yaml: field 'object_pose.xyz': not finite"),
        ({"xyz": [0.7, 0.2]}, r"faces.yaml: field 'object_pose.xyz': give 3 numbers, not an array of shape \(2,\)"),
        ({"xyz": [0.7, 0.2, 0], "quaternion": [0, 0, 0, 2]}, r"field 'object_pose.quaternion': must be a unit quaternion \[x, y, z, w\] \(its norm is 2.000000"),
        ({"xyz": [0.7, 0.2, 0], "rpy_deg": [0, 0, 1], "quaternion": [0, 0, 0, 1]}, r"field 'object_pose.rpy': give at most one of rpy, rpy_deg, quaternion"),
        ({"xyz": [0.7, 0.2, 0], "yaw": [1, 2, 3]}, r"field 'object_pose.yaw': not a pose field"),
        ("0.7 0.2 0", r"field 'object_pose': give a dict in the task file's pose syntax or a 4×4 array"),
    ]
    for pose, message in cases:
        with pytest.raises(graspath.GraspathError, match=message):
            graspath.Task.load(template, object_pose=pose)
    with pytest.raises(graspath.GraspathError, match=r"^field 'quaternion': must be a unit quaternion"):
        graspath.pose_matrix({"quaternion": [1, 1, 0, 0]})
