"""graspath.train and graspath.generate write what `graspath train` / `graspath generate`
write, byte for byte, and return the candidates as arrays."""

import json
import subprocess

import numpy as np
import pytest

import graspath
from conftest import EXAMPLES

SMALL = dict(initial_grasps=800, steps=30, query_kernels=800, seed=3)
CLI_SMALL = ["--initial-grasps", "800", "--steps", "30", "--query-kernels", "800", "--seed", "3"]


def test_train_and_generate_equal_the_cli(graspath_bin, tmp_path):
    demo = EXAMPLES / "grasp" / "demo_box.json"
    cloud = EXAMPLES / "grasp" / "cylinder.json"
    ours_model = tmp_path / "ours_model.json"
    info = graspath.train(demo, ours_model)
    assert info["label"] == "pinch" and info["contact_links"]
    cli_model = tmp_path / "cli_model.json"
    subprocess.run([str(graspath_bin), "train", str(demo), "--out", str(cli_model), "--quiet"], check=True)
    assert ours_model.read_bytes() == cli_model.read_bytes()

    ours_out = tmp_path / "ours_candidates.json"
    result = graspath.generate(ours_model, cloud, max_candidates=8, out=ours_out, **SMALL)
    cli_out = tmp_path / "cli_candidates.json"
    subprocess.run(
        [str(graspath_bin), "generate", "--model", str(cli_model), "--cloud", str(cloud), "--out", str(cli_out),
         "--max-candidates", "8", "--quiet", *CLI_SMALL],
        check=True,
    )
    assert ours_out.read_bytes() == cli_out.read_bytes()
    # The arrays are the file's candidates.
    records = json.loads(cli_out.read_text())["candidates"]
    assert result["object_from_wrist"].shape == (8, 4, 4)
    np.testing.assert_array_equal(result["object_from_wrist"], np.array([r["object_from_wrist"] for r in records]))
    np.testing.assert_array_equal(result["log_likelihood"], [r["log_likelihood"] for r in records])
    assert (np.diff(result["log_likelihood"]) <= 0).all(), "best first"
    # Seeded: the same call, the same candidates.
    again = graspath.generate(ours_model, cloud, max_candidates=8, **SMALL)
    np.testing.assert_array_equal(again["object_from_wrist"], result["object_from_wrist"])


def test_bad_files_are_named(tmp_path):
    with pytest.raises(graspath.GraspathError, match="missing.json"):
        graspath.train(EXAMPLES / "grasp" / "missing.json", tmp_path / "m.json")
    model = tmp_path / "m.json"
    graspath.train(EXAMPLES / "grasp" / "demo_box.json", model)
    with pytest.raises(graspath.GraspathError):
        graspath.train(EXAMPLES / "grasp" / "demo_box.json", model)  # exists, no force
    with pytest.raises(graspath.GraspathError, match="nothing.ply"):
        graspath.generate(model, tmp_path / "nothing.ply", **SMALL)
