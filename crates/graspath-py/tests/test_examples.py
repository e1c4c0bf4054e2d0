"""The Python examples run end to end (the Fig. 5 script writes its PNG)."""

import subprocess
import sys

import pytest

from conftest import REPO

pytest.importorskip("matplotlib", reason="matplotlib is not installed")


def test_fig5_script_writes_a_png(tmp_path):
    out = tmp_path / "fig5.png"
    result = subprocess.run(
        [sys.executable, str(REPO / "examples" / "python" / "fig5_pick_and_place.py"), "--out", str(out)],
        capture_output=True,
        text=True,
        check=True,
    )
    assert "selected: candidate" in result.stdout
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
