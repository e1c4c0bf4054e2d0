"""`graspath.dataset`: a manifest that is not CSV text or is beyond the caps that bound what is
read before any task loads is one `DatasetError` naming the manifest and the line; at the caps
it reads. Needs neither Ray nor pyarrow."""

import pytest

import graspath.dataset as gd


def manifest_of(tmp_path, rows, body=None):
    """A manifest of `rows` objects on task files that exist (their content is not read)."""
    for i in range(rows):
        (tmp_path / f"t{i}.yaml").write_text("{}\n")
    path = tmp_path / "objects.csv"
    text = "object,task\n" + "".join(f"o{i},t{i}.yaml\n" for i in range(rows))
    path.write_bytes(body if body is not None else text.encode())
    return path


def test_a_manifest_at_the_caps_reads_and_one_beyond_is_refused(tmp_path, monkeypatch):
    path = manifest_of(tmp_path, 3)
    size = path.stat().st_size
    monkeypatch.setattr(gd, "MAX_MANIFEST_OBJECTS", 3)
    monkeypatch.setattr(gd, "MAX_MANIFEST_BYTES", size)
    assert [o.name for o in gd.dataset_tasks(path)] == ["o0", "o1", "o2"]
    monkeypatch.setattr(gd, "MAX_MANIFEST_BYTES", size - 1)
    with pytest.raises(gd.DatasetError, match=rf"objects.csv: the manifest is more than {size - 1} bytes \(MAX_MANIFEST_BYTES\)"):
        gd.dataset_tasks(path)
    monkeypatch.setattr(gd, "MAX_MANIFEST_BYTES", size)
    monkeypatch.setattr(gd, "MAX_MANIFEST_OBJECTS", 2)
    # The third object is on line 4 (the header is line 1).
    with pytest.raises(gd.DatasetError, match=r"objects.csv: line 4: the manifest lists more than 2 objects \(MAX_MANIFEST_OBJECTS\)"):
        gd.dataset_tasks(path)


def test_a_manifest_that_is_not_csv_text_names_the_line(tmp_path):
    path = manifest_of(tmp_path, 2, b"object,task\no0,t0.yaml\no1,t\xff1.yaml\n")
    with pytest.raises(gd.DatasetError, match=r"objects.csv: line 3: not UTF-8 text \(byte 27: invalid start byte\)"):
        gd.dataset_tasks(path)
    # Lines ended by \r alone, as csv reads them.
    path = manifest_of(tmp_path, 2, b"object,task\ro0,t0.yaml\ro1,t\xff1.yaml\r")
    with pytest.raises(gd.DatasetError, match=r"objects.csv: line 3: not UTF-8 text"):
        gd.dataset_tasks(path)
    huge = "x" * 200_000
    path = manifest_of(tmp_path, 2, f"object,task\no0,t0.yaml\no1,{huge}\n".encode())
    with pytest.raises(gd.DatasetError, match=r"objects.csv: line 3: not a CSV manifest: field larger than field limit"):
        gd.dataset_tasks(path)
    # Blank lines count.
    path = manifest_of(tmp_path, 2, f"object,task\n\n\no0,t0.yaml\no1,{huge}\n".encode())
    with pytest.raises(gd.DatasetError, match=r"objects.csv: line 5: not a CSV manifest"):
        gd.dataset_tasks(path)
    path = manifest_of(tmp_path, 2, b"object,task\no0,t0.yaml\no1,t\x001.yaml\n")
    with pytest.raises(gd.DatasetError, match=r"task file of object 'o1' not found"):
        gd.dataset_tasks(path)
