"""Every shipped example in ``python/examples`` runs to the end and writes what it says.

They are what a new user copies first; each is run here as a user would, from the repository
root, with figures written through matplotlib's file backend into a temporary folder.
"""

import os
import pathlib
import subprocess
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
EXAMPLES = sorted((ROOT / "python" / "examples").glob("*.py"))


def run_example(script: pathlib.Path, *args: str) -> subprocess.CompletedProcess:
    env = dict(os.environ, MPLBACKEND="Agg")
    return subprocess.run(
        [sys.executable, str(script), *args],
        cwd=ROOT,
        env=env,
        capture_output=True,
        text=True,
        timeout=600,
    )


def test_every_example_is_covered():
    names = {p.name for p in EXAMPLES}
    assert names == {"dask_sweep.py", "journal_orbit.py", "parameter_sweep.py",
                     "poincare_figure.py"}, names


@pytest.mark.parametrize("name", ["journal_orbit.py", "poincare_figure.py"])
def test_figure_examples_write_their_figure(name, tmp_path):
    pytest.importorskip("matplotlib")
    out = tmp_path / "figure.png"
    args = [str(out)] + (["6"] if name == "poincare_figure.py" else [])
    p = run_example(ROOT / "python" / "examples" / name, *args)
    assert p.returncode == 0, p.stderr
    assert out.stat().st_size > 10_000, "a figure, not an empty file"
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_parameter_sweep_prints_a_row_per_speed():
    p = run_example(ROOT / "python" / "examples" / "parameter_sweep.py")
    assert p.returncode == 0, p.stderr
    # The table's rows: rpm, impacts, peak force (the header and the timing line are not).
    rows = [l.split() for l in p.stdout.splitlines()]
    rows = [r for r in rows if len(r) == 3 and all(f.replace(".", "").isdigit() for f in r)]
    assert len(rows) >= 3, p.stdout
    # 250 rpm, the reference case: 22 impacts, first peak 7418.6 N (docs/benchmarks.md).
    assert rows[0] == ["250", "22", "7418.6"], p.stdout
    for rpm, impacts, force in rows:
        assert int(impacts) > 0 and float(force) > 0.0, p.stdout


def test_dask_sweep_agrees_with_the_library_sweep():
    p = run_example(ROOT / "python" / "examples" / "dask_sweep.py")
    assert p.returncode == 0, p.stderr
    assert "every executor gives Model.bifurcation's numbers, bit for bit" in p.stdout, p.stdout
