"""`graspath.ray`: a dataset sharded over a local Ray instance writes the same Parquet bytes as the
single-process run, each object's top-k equals a brute-force sort of `graspath.select`'s
scores for that object's task file (run one file at a time, without shards), two-arm tasks'
pairs equal `graspath.select`'s, and a manifest's pose columns give what a task file with that
pose written in it gives."""

import logging
import os
import shutil
import subprocess
import sys

import numpy as np
import pytest

import graspath
from conftest import EXAMPLES

try:
    import pyarrow.parquet as pq
    import ray
except ImportError as e:  # pragma: no cover - depends on the environment
    if os.environ.get("CI") == "true":
        pytest.fail(f"CI=true but the Ray extra is missing ({e}): pip install ray pyarrow", pytrace=False)
    pytest.skip(f"the Ray extra is not installed ({e}): pip install graspath[ray]", allow_module_level=True)

import graspath.ray as gray

TOP_K = 4
FACES = (EXAMPLES / "workload_1000_faces.yaml").read_text()


@pytest.fixture(scope="module")
def dataset(tmp_path_factory):
    """Six objects: the faces workload with 40 candidates at four placements (one the left arm
    cannot reach at all), the cluttered scene (a mesh beside it) and the two-arm Pick-and-Place."""
    root = tmp_path_factory.mktemp("dataset")
    placements = ["0.70, 0.25, -0.05", "0.65, 0.35, 0.00", "0.75, 0.10, -0.10", "2.50, 0.25, -0.05"]
    for i, xyz in enumerate(placements):
        text = FACES.replace("count: 1000", "count: 40").replace("0.70, 0.25, -0.05", xyz)
        assert text != FACES
        (root / f"faces_{i}.yaml").write_text(text)
    shutil.copy(EXAMPLES / "scene" / "pick_and_place_left_cluttered.yaml", root / "cluttered.yaml")
    shutil.copy(EXAMPLES / "scene" / "bin.stl", root / "bin.stl")
    shutil.copy(EXAMPLES / "pick_and_place_both.yaml", root / "both.yaml")
    (root / "notes.txt").write_text("not a task file\n")
    return root


@pytest.fixture(scope="module")
def ray_instance():
    ray.init(num_cpus=2, include_dashboard=False)
    yield ray.get_runtime_context().gcs_address
    ray.shutdown()


@pytest.fixture(scope="module")
def local_file(dataset, tmp_path_factory):
    out = tmp_path_factory.mktemp("local") / "top.parquet"
    summary = gray.select_dataset(dataset, out, top_k=TOP_K, shard_size=37, local=True)
    assert summary["objects"] == 6 and summary["candidates"] == 4 * 40 + 21 + 21
    assert summary["shards"] == -(-summary["candidates"] // 37)
    return out


def test_ray_writes_the_bytes_of_the_single_process_run(dataset, ray_instance, local_file, tmp_path, caplog):
    caplog.set_level(logging.INFO, logger="graspath.ray")
    for shard_size in (37, 100):
        out = tmp_path / f"ray_{shard_size}.parquet"
        gray.select_dataset(dataset, out, top_k=TOP_K, shard_size=shard_size)
        assert out.read_bytes() == local_file.read_bytes(), f"shard_size={shard_size}"
        assert gray.pairs_path(out).read_bytes() == gray.pairs_path(local_file).read_bytes(), f"shard_size={shard_size}"
    progress = [r.getMessage() for r in caplog.records if r.getMessage().startswith("shard ")]
    assert len(progress) == 6 + 3  # one line per finished shard
    assert all("candidates/s" in line and "ETA" in line for line in progress)
    assert ray.is_initialized(), "a Ray instance it did not start is left running"


def test_top_k_equals_brute_force_over_the_full_scores(dataset, local_file):
    table = pq.read_table(local_file).to_pydict()
    rows = list(zip(*(table[c] for c in ("object", "arm", "rank", "candidate", "id", "score", "mu_l2", "mu_linf", "label"))))
    expected = []
    for path in sorted(dataset.glob("*.yaml")):
        task = graspath.Task.load(path)
        selection = graspath.select(task)
        for arm in task.arms:
            a = selection.arrays(arm)
            labels = [c["label"] for c in task.candidates]
            # Brute force: every ranked candidate, best score first, ties by candidate position.
            ranked = sorted((i for i in range(len(task)) if not np.isnan(a["score"][i])), key=lambda i: (-a["score"][i], i))
            for r, i in enumerate(ranked[:TOP_K]):
                assert a["rank"][i] == r + 1  # the library's own ranking agrees
                expected.append((path.name, arm, r + 1, i, int(a["id"][i]), a["score"][i], a["mu_l2"][i], a["mu_linf"][i], labels[i]))
    assert rows == expected
    objects = {r[0] for r in rows}
    assert "faces_3.yaml" not in objects, "the unreachable placement has no ranked candidate"
    assert {"both.yaml", "cluttered.yaml", "faces_0.yaml"} <= objects
    assert {(r[0], r[1]) for r in rows if r[0] == "both.yaml"} == {("both.yaml", "left"), ("both.yaml", "right")}


def test_the_files_have_the_fixed_schemas(local_file):
    f = pq.ParquetFile(local_file)
    schema = f.schema_arrow
    assert [(x.name, str(x.type), x.nullable) for x in schema] == [(n, t.replace("float64", "double"), nullable) for n, t, nullable, _ in gray.COLUMNS]
    assert schema.metadata[b"graspath.top_k"] == str(TOP_K).encode()
    assert f.metadata.num_row_groups == 1
    table = f.read()
    clearance = table.column("clearance").to_pylist()
    objects = table.column("object").to_pylist()
    assert all((c is None) == (o != "cluttered.yaml") for c, o in zip(clearance, objects))
    pairs = pq.ParquetFile(gray.pairs_path(local_file))
    assert gray.pairs_path(local_file).name == "top.pairs.parquet"
    assert [(x.name, str(x.type), x.nullable) for x in pairs.schema_arrow] == [(n, t.replace("float64", "double"), nullable) for n, t, nullable, _ in gray.PAIR_COLUMNS]
    assert pairs.schema_arrow.metadata[b"graspath.top_k"] == str(TOP_K).encode()
    assert set(pairs.read().column("object").to_pylist()) == {"both.yaml"}


def test_the_command_line_local_and_on_a_running_cluster(dataset, ray_instance, local_file, tmp_path):
    for name, mode in (("cli_local", ["--local"]), ("cli_ray", ["--address", ray_instance])):
        out = tmp_path / f"{name}.parquet"
        done = subprocess.run(
            [sys.executable, "-m", "graspath.ray", str(dataset), "--out", str(out), "-k", str(TOP_K), "--shard-size", "37", *mode],
            capture_output=True,
            text=True,
            timeout=600,
        )
        assert done.returncode == 0, done.stderr
        assert "candidates/s" in done.stderr and "ETA" in done.stderr
        assert out.read_bytes() == local_file.read_bytes(), name
        assert gray.pairs_path(out).read_bytes() == gray.pairs_path(local_file).read_bytes(), name
        assert f"pairs to {gray.pairs_path(out)}" in done.stdout


def test_a_manifest_names_objects_and_task_files(dataset, local_file, tmp_path):
    manifest = tmp_path / "objects.csv"
    files = sorted(p.name for p in dataset.glob("*.yaml"))
    manifest.write_text("object,task\n" + "".join(f"{f},{dataset / f}\n" for f in files))
    out = tmp_path / "manifest.parquet"
    gray.select_dataset(manifest, out, top_k=TOP_K, shard_size=37, local=True)
    assert out.read_bytes() == local_file.read_bytes()
    assert gray.pairs_path(out).read_bytes() == gray.pairs_path(local_file).read_bytes()


def test_bad_input_is_one_clear_error(dataset, local_file, tmp_path):
    out = tmp_path / "x.parquet"
    with pytest.raises(graspath.GraspathError, match="top_k must be a positive integer"):
        gray.select_dataset(dataset, out, top_k=0, local=True)
    with pytest.raises(graspath.GraspathError, match="shard_size must be a positive integer"):
        gray.select_dataset(dataset, out, shard_size=-3, local=True)
    with pytest.raises(graspath.GraspathError, match="the output exists"):
        gray.select_dataset(dataset, local_file, local=True)
    empty = tmp_path / "empty"
    empty.mkdir()
    with pytest.raises(graspath.GraspathError, match=r"empty: no task files"):
        gray.select_dataset(empty, out, local=True)
    with pytest.raises(graspath.GraspathError, match=r"nowhere: no such dataset"):
        gray.select_dataset(tmp_path / "nowhere", out, local=True)
    manifest = tmp_path / "m.csv"
    manifest.write_text("object,task\nbox,missing.yaml\n")
    with pytest.raises(graspath.GraspathError, match=r"missing.yaml: task file of object 'box' not found"):
        gray.select_dataset(manifest, out, local=True)
    manifest.write_text("object,file\nbox,missing.yaml\n")
    with pytest.raises(graspath.GraspathError, match=r"m.csv: the manifest needs a 'task' column"):
        gray.select_dataset(manifest, out, local=True)
    broken = tmp_path / "broken"
    broken.mkdir()
    (broken / "a.yaml").write_text(FACES.replace("count: 1000", "cuont: 10"))
    with pytest.raises(graspath.GraspathError, match=r"a.yaml.*cuont"):
        gray.select_dataset(broken, out, local=True)
    assert not out.exists() and not list(tmp_path.glob(".x.parquet*"))
    done = subprocess.run(
        [sys.executable, "-m", "graspath.ray", str(dataset), "--out", str(out), "--top-k", "0", "--local"],
        capture_output=True,
        text=True,
    )
    assert done.returncode == 2
    assert done.stderr.strip().splitlines() == ["graspath.ray: error: top_k must be a positive integer (got 0)"]


def test_a_manifest_of_objects_and_candidate_files(tmp_path):
    """One task file, several candidate files (the manifest's ``candidates`` column): each
    object's top k equals that of a task file written to name its candidate file itself."""
    template = EXAMPLES / "grasp_files" / "pick_and_place_graspgen.yaml"
    grasps = (EXAMPLES / "grasp_files" / "graspgen_box.yaml").read_text()
    (tmp_path / "grasps").mkdir()
    variants = {
        "as_given": grasps,
        "first_favoured": grasps.replace("confidence: 0.5\n", "confidence: 0.999\n", 1),
    }
    assert variants["first_favoured"] != grasps
    rows = ["object,task,candidates"]
    for name, text in variants.items():
        (tmp_path / "grasps" / f"{name}.yaml").write_text(text)
        rows.append(f"{name},{template},grasps/{name}.yaml")
    manifest = tmp_path / "objects.csv"
    manifest.write_text("\n".join(rows) + "\n")
    out = tmp_path / "top.parquet"
    gray.select_dataset(manifest, out, top_k=3, shard_size=5, local=True)
    table = pq.read_table(out).to_pydict()
    got = list(zip(table["object"], table["rank"], table["candidate"], table["score"]))
    expected = []
    for name in variants:
        # The oracle: a task file of its own whose candidates.file names the variant.
        own = tmp_path / f"{name}_task.yaml"
        own.write_text(template.read_text().replace("file: graspgen_box.yaml", f"file: grasps/{name}.yaml"))
        selection = graspath.select(graspath.Task.load(own))
        a = selection.arrays("left")
        ranked = sorted((i for i in range(len(a["score"])) if not np.isnan(a["score"][i])), key=lambda i: (-a["score"][i], i))
        expected += [(name, r + 1, i, a["score"][i]) for r, i in enumerate(ranked[:3])]
    assert got == expected
    # The variant's larger largest likelihood lowers every other candidate's relative one.
    assert got[3][3] < got[0][3], "the two candidate files give different scores"
    manifest.write_text(f"object,task,candidates\nbox,{template},grasps/missing.yaml\n")
    with pytest.raises(graspath.GraspathError, match=r"missing.yaml: candidate file of object 'box' not found"):
        gray.select_dataset(manifest, tmp_path / "x.parquet", local=True)


def select_pairs_of(path, count):
    """The oracle: ``graspath.select``'s first ``count`` pairs of one task file, run whole."""
    task = graspath.Task.load(path)
    selection = graspath.select(task)
    first, second = task.arms
    pairs = [(first, p[first], p[f"{first}_label"], second, p[second], p[f"{second}_label"], p["score"], p["rank"]) for p in selection.pairs[:count]]
    return pairs, selection.summary.get("colliding_pairs", 0)


def pairs_by_object(path):
    table = pq.read_table(path).to_pydict()
    columns = ("first_arm", "first_id", "first_label", "second_arm", "second_id", "second_label", "score", "rank")
    out = {}
    for row in zip(table["object"], *(table[c] for c in columns)):
        out.setdefault(row[0], []).append(tuple(row[1:]))
    return out


@pytest.fixture(scope="module")
def two_arm_dataset(tmp_path_factory):
    """The repository's two-arm examples: Pick-and-Place, Pick-Rotate-Place and Pick-and-Place on
    a table (where the check between the arms refuses pairs), beside a one-arm task."""
    root = tmp_path_factory.mktemp("two_arms")
    shutil.copy(EXAMPLES / "pick_and_place_both.yaml", root / "both.yaml")
    shutil.copy(EXAMPLES / "pick_rotate_place_both.yaml", root / "rotate.yaml")
    shutil.copy(EXAMPLES / "scene" / "pick_and_place_both_on_table.yaml", root / "table.yaml")
    shutil.copy(EXAMPLES / "pick_and_place_left.yaml", root / "left.yaml")
    return root


@pytest.mark.parametrize("top_k", [4, 12])
def test_pairs_equal_select_at_any_shard_size(two_arm_dataset, ray_instance, tmp_path, top_k):
    """Each two-arm object's pairs are ``select``'s first ``min(top_k, pairs)`` (``pairs`` is 10
    in the examples): the same pairs, order and scores, whatever the shards; Ray and local
    write the same bytes."""
    expected, colliding = {}, {}
    for name in ("both.yaml", "rotate.yaml", "table.yaml"):
        expected[name], colliding[name] = select_pairs_of(two_arm_dataset / name, top_k)
        assert len(expected[name]) == min(top_k, 10), name
    assert colliding["table.yaml"] > 0, "the table example no longer exercises the check between the arms"
    files = []
    for shard_size in (3, 10, 64):
        out = tmp_path / f"local_{shard_size}.parquet"
        summary = gray.select_dataset(two_arm_dataset, out, top_k=top_k, shard_size=shard_size, local=True)
        assert summary["pairs_out"] == gray.pairs_path(out) and summary["pairs"] == 3 * min(top_k, 10)
        assert pairs_by_object(gray.pairs_path(out)) == expected, f"shard_size={shard_size}"
        files.append(out)
    out = tmp_path / "ray_7.parquet"
    gray.select_dataset(two_arm_dataset, out, top_k=top_k, shard_size=7)
    files.append(out)
    for f in files[1:]:
        assert f.read_bytes() == files[0].read_bytes(), f.name
        assert gray.pairs_path(f).read_bytes() == gray.pairs_path(files[0]).read_bytes(), f.name


def test_one_arm_datasets_write_no_pairs_file(tmp_path):
    root = tmp_path / "one_arm"
    root.mkdir()
    shutil.copy(EXAMPLES / "pick_and_place_left.yaml", root / "left.yaml")
    out = tmp_path / "top.parquet"
    summary = gray.select_dataset(root, out, top_k=2, local=True)
    assert summary["pairs_out"] is None and summary["pairs"] == 0
    assert sorted(p.name for p in tmp_path.iterdir()) == ["one_arm", "top.parquet"]


def test_an_existing_pairs_file_is_not_replaced_without_overwrite(two_arm_dataset, tmp_path):
    out = tmp_path / "top.parquet"
    gray.pairs_path(out).write_text("keep me")
    with pytest.raises(graspath.GraspathError, match=r"top.pairs.parquet: the pairs output exists"):
        gray.select_dataset(two_arm_dataset, out, local=True)
    assert not out.exists() and gray.pairs_path(out).read_text() == "keep me"


# (object, task, xyz, rpy_deg / quaternion / rpy cell, the pose as the task file writes it)
POSED = [
    ("a", "faces.yaml", "0.65 0.30 -0.02", ("rpy_deg", "0 0 25"), "{ xyz: [0.65, 0.30, -0.02], rpy_deg: [0, 0, 25] }"),
    ("b", "faces.yaml", "0.70 0.20 0.00", ("quaternion", "0 0 0.2588190 0.9659258"), "{ xyz: [0.70, 0.20, 0.00], quaternion: [0, 0, 0.2588190, 0.9659258] }"),
    ("c", "faces.yaml", "0.72 0.22 -0.04", ("rpy", "0.1 0 -0.2"), "{ xyz: [0.72, 0.22, -0.04], rpy: [0.1, 0, -0.2] }"),
    ("d", "faces.yaml", "0.60 0.25 0.00", None, "{ xyz: [0.60, 0.25, 0.00] }"),
    ("e", "faces.yaml", "", None, None),
    ("pair", "both.yaml", "0.75 0.05 -0.10", ("rpy_deg", "0 0 -8"), "{ xyz: [0.75, 0.05, -0.10], rpy_deg: [0, 0, -8] }"),
]


def test_manifest_pose_columns_equal_task_files_with_that_pose(dataset, ray_instance, tmp_path):
    """One task file placed at several poses by the manifest's ``xyz`` / ``rpy_deg`` /
    ``quaternion`` / ``rpy`` columns: each object's top k (and, for the two-arm task, its
    pairs) equal ``select`` on a task file with that ``object.pose`` written in it."""
    (tmp_path / "faces.yaml").write_text((dataset / "faces_0.yaml").read_text())
    shutil.copy(EXAMPLES / "pick_and_place_both.yaml", tmp_path / "both.yaml")
    lines = ["object,task,xyz,rpy_deg,quaternion,rpy"]
    oracles = {}
    for name, task, xyz, rotation, written in POSED:
        cells = {"rpy_deg": "", "quaternion": "", "rpy": ""}
        if rotation:
            cells[rotation[0]] = rotation[1]
        lines.append(",".join([name, task, xyz, cells["rpy_deg"], cells["quaternion"], cells["rpy"]]))
        text = (tmp_path / task).read_text()
        if written is not None:
            old = next(line for line in text.splitlines() if line.strip().startswith("pose: { xyz:"))
            text = text.replace(old, f"  pose: {written}")
            assert text != (tmp_path / task).read_text()
        oracles[name] = tmp_path / f"oracle_{name}.yaml"
        oracles[name].write_text(text)
    manifest = tmp_path / "placed.csv"
    manifest.write_text("\n".join(lines) + "\n")
    out = tmp_path / "placed.parquet"
    gray.select_dataset(manifest, out, top_k=TOP_K, shard_size=11, local=True)
    table = pq.read_table(out).to_pydict()
    got = list(zip(*(table[c] for c in ("object", "arm", "rank", "candidate", "score", "mu_l2"))))
    expected = []
    for name, *_ in POSED:
        task = graspath.Task.load(oracles[name])
        selection = graspath.select(task)
        for arm in task.arms:
            a = selection.arrays(arm)
            ranked = sorted((i for i in range(len(task)) if not np.isnan(a["score"][i])), key=lambda i: (-a["score"][i], i))
            expected += [(name, arm, r + 1, i, a["score"][i], a["mu_l2"][i]) for r, i in enumerate(ranked[:TOP_K])]
    assert got == expected
    by_object = {}
    for row in got:
        by_object.setdefault(row[0], []).append(row[1:])
    assert len({tuple(v) for k, v in by_object.items() if k != "pair"}) == 5, "the poses give different results"
    assert pairs_by_object(gray.pairs_path(out)) == {"pair": select_pairs_of(oracles["pair"], TOP_K)[0]}
    # On Ray, the same bytes.
    on_ray = tmp_path / "placed_ray.parquet"
    gray.select_dataset(manifest, on_ray, top_k=TOP_K, shard_size=23)
    assert on_ray.read_bytes() == out.read_bytes()
    assert gray.pairs_path(on_ray).read_bytes() == gray.pairs_path(out).read_bytes()


@pytest.mark.parametrize(
    "header, row, message",
    [
        ("xyz", "0.7 nan 0", r"field 'xyz': not finite"),
        ("xyz", "0.7 0.2", r"field 'xyz': 2 numbers \('0.7 0.2'\), expected 3"),
        ("xyz", "0.7 0.2 0 1", r"field 'xyz': 4 numbers \('0.7 0.2 0 1'\), expected 3"),
        ("xyz", "0.7 abc 0", r"field 'xyz': '0.7 abc 0' is not 3 numbers separated by spaces"),
        ("xyz,quaternion", "0.7 0.2 0,0 0 0 2", r"field 'quaternion': must be a unit quaternion \[x, y, z, w\] \(its norm is 2.000000"),
        ("xyz,quaternion", "0.7 0.2 0,0 0 1", r"field 'quaternion': 3 numbers \('0 0 1'\), expected 4"),
        ("xyz,rpy_deg", "0.7 0.2 0,0 inf 0", r"field 'rpy_deg': not finite"),
        ("xyz,rpy", "0.7 0.2 0,0 0 nan", r"field 'rpy': not finite"),
        ("xyz,rpy_deg,quaternion", "0.7 0.2 0,0 0 10,0 0 0 1", r"fields 'rpy_deg', 'quaternion': give at most one of rpy, rpy_deg, quaternion"),
        ("xyz,rpy_deg", ",0 0 10", r"field 'xyz' is empty: a row that gives the object's orientation \('rpy_deg'\) gives its position too"),
    ],
)
def test_bad_manifest_poses_name_the_file_line_and_column(dataset, tmp_path, header, row, message):
    manifest = tmp_path / "objects.csv"
    task = dataset / "faces_0.yaml"
    # The bad row is the second object, on line 3.
    manifest.write_text(f"object,task,{header}\nfine,{task},{','.join(['0.7 0.25 -0.05'] + [''] * header.count(','))}\nbad,{task},{row}\n")
    out = tmp_path / "x.parquet"
    with pytest.raises(gray.DatasetError, match=r"objects.csv: line 3: " + message):
        gray.select_dataset(manifest, out, local=True)
    assert not out.exists() and not gray.pairs_path(out).exists()
    done = subprocess.run(
        [sys.executable, "-m", "graspath.ray", str(manifest), "--out", str(out), "--local"], capture_output=True, text=True
    )
    assert done.returncode == 2
    lines = done.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"graspath.ray: error: {manifest}: line 3: "), done.stderr
