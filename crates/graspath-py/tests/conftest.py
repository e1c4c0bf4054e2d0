"""Shared fixtures: the repository, the shared folder (skipped when absent), the CLI binary."""

import os
import shutil
import subprocess
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[3]
EXAMPLES = REPO / "examples"


def shared_dir():
    """``$GRASPATH_SHARED`` or ``../shared`` beside the repository, if it holds the robots."""
    for candidate in (os.environ.get("GRASPATH_SHARED"), REPO.parent / "shared"):
        if candidate and (Path(candidate) / "robots" / "baxter.urdf").is_file():
            return Path(candidate)
    return None


def require(module: str, install: str):
    """Imports ``module`` (an oracle the suite compares with): when it is missing, the test
    skips, except under CI (``CI=true``), which installs it and must not skip silently."""
    import importlib

    try:
        return importlib.import_module(module)
    except ImportError:
        if os.environ.get("CI") == "true":
            raise
        pytest.skip(f"{module} is not installed ({install})")


@pytest.fixture(scope="session")
def shared():
    path = shared_dir()
    if path is None:
        pytest.skip("../shared is not present (set GRASPATH_SHARED to point at it)")
    return path


@pytest.fixture(scope="session")
def graspath_bin():
    """The `graspath` CLI: ``$GRASPATH_BIN``, else a binary in target/, else built with cargo."""
    env = os.environ.get("GRASPATH_BIN")
    if env:
        return Path(env)
    for profile in ("release", "debug"):
        candidate = REPO / "target" / profile / "graspath"
        if candidate.is_file():
            return candidate
    if shutil.which("cargo") is None:
        pytest.skip("no graspath binary in target/ and no cargo to build one")
    subprocess.run(
        ["cargo", "build", "-q", "--profile", "test", "-p", "graspath-cli"], cwd=REPO, check=True
    )
    return REPO / "target" / "debug" / "graspath"
