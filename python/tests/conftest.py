"""Shared fixtures: the repository root, the ``linkdyn`` command, and running it."""

import os
import pathlib
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]


def _binary() -> pathlib.Path:
    """The ``linkdyn`` command to compare against: ``$LINKDYN_BIN``, else the release build of
    this checkout (built here if it is missing)."""
    given = os.environ.get("LINKDYN_BIN")
    if given:
        return pathlib.Path(given)
    path = ROOT / "target" / "release" / "linkdyn"
    if not path.exists():
        subprocess.run(
            ["cargo", "build", "--release", "--bin", "linkdyn"], cwd=ROOT, check=True
        )
    return path


@pytest.fixture(scope="session")
def root() -> pathlib.Path:
    """The repository root (models/ lives there)."""
    return ROOT


@pytest.fixture(autouse=True)
def _in_root(monkeypatch):
    # Model paths are given relative to the root, as on the command line, so that the
    # provenance (which records the path as given) is the same for both.
    monkeypatch.chdir(ROOT)


@pytest.fixture(scope="session")
def cli():
    """Runs ``linkdyn ARGS...`` in the root; returns (exit code, stdout, stderr)."""
    binary = _binary()

    def run(*args: str):
        p = subprocess.run(
            [str(binary), *args], cwd=ROOT, capture_output=True, text=True, timeout=600
        )
        return p.returncode, p.stdout, p.stderr

    return run
