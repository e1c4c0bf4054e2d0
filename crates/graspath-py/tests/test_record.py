"""Every per-candidate numpy output carries exactly the record schema's columns
(``graspath.record_columns()``, the list the Rust outputs are read off too), the stub documents
each of them, and the Ray layer's Parquet columns are schema columns of ``select_batch``."""

import ast
import re
from pathlib import Path

import numpy as np

import graspath
from conftest import EXAMPLES

CLUTTERED = EXAMPLES / "scene" / "pick_and_place_left_cluttered.yaml"
STUB = Path(graspath.__file__).with_name("_graspath.pyi")
BATCH_OWN = {"object", "arm_index", "candidate"}


def columns(output):
    return [c for c in graspath.record_columns() if output in c["outputs"]]


def test_the_schema_is_well_formed():
    cols = graspath.record_columns()
    names = [c["name"] for c in cols]
    assert len(names) == len(set(names))
    for c in cols:
        assert set(c) == {"name", "type", "nullable", "unit", "doc", "outputs", "json_field"}
        assert c["doc"] and c["outputs"], c["name"]


def test_arrays_and_batch_carry_exactly_the_schema_columns():
    task = graspath.Task.load(CLUTTERED)
    selection = graspath.select(task)
    arrays = selection.arrays("left")
    assert set(arrays) == {c["name"] for c in columns("arrays")}
    k = len(task)
    for c in columns("arrays"):
        value = arrays[c["name"]]
        assert value.shape[0] == k, c["name"]
        if c["type"] == "float64" or (c["type"] == "uint64" and c["nullable"]):
            assert value.dtype == np.float64, c["name"]
        elif c["type"] == "uint64":
            assert value.dtype == np.int64, c["name"]
        elif c["type"] == "bool":
            assert value.dtype == np.bool_, c["name"]
    # The arrays agree with the JSON records they are read off.
    records = selection.candidates
    assert list(arrays["label"]) == [r["label"] for r in records]
    assert list(arrays["failure_reason"]) == [r["failure"]["reason"] if r["failure"] else None for r in records]
    batch = graspath.select_batch([task])
    assert set(batch) == BATCH_OWN | {c["name"] for c in columns("select_batch")}


def test_json_records_carry_only_schema_columns():
    selection = graspath.select(graspath.Task.load(CLUTTERED))
    json_columns = {c["name"] for c in columns("json")}
    groups = {"failure": "failure_", "self_motion": "self_motion_"}
    for record in selection.candidates:
        for key, value in record.items():
            if key in groups:
                for field in value or {}:
                    assert groups[key] + field in json_columns, f"{key}.{field}"
            else:
                assert key in json_columns, key


def docstring(name, cls=None):
    tree = ast.parse(STUB.read_text())
    body = tree.body
    if cls:
        body = next(n for n in body if isinstance(n, ast.ClassDef) and n.name == cls).body
    node = next(n for n in body if isinstance(n, ast.FunctionDef) and n.name == name)
    return ast.get_docstring(node)


def test_the_stub_documents_every_column():
    documented = set(re.findall(r"``([a-z_0-9]+)``", docstring("arrays", "Selection")))
    missing = {c["name"] for c in columns("arrays")} - documented
    assert not missing, f"Selection.arrays() stub lacks {missing}"
    documented = set(re.findall(r"``([a-z_0-9]+)``", docstring("select_batch")))
    missing = (BATCH_OWN | {c["name"] for c in columns("select_batch")}) - documented
    assert not missing, f"select_batch stub lacks {missing}"


def test_ray_columns_are_batch_columns():
    from graspath import ray

    batch = {c["name"]: c for c in columns("select_batch")}
    arrow = {"float64": "float64", "uint64": "int64", "string": "string"}
    for name, kind, _, _ in ray.COLUMNS:
        if name == "object":
            continue  # the object's name, the Ray layer's own
        assert name in batch or name in BATCH_OWN, name
        if name in batch:
            assert arrow[batch[name]["type"]] == kind, name
