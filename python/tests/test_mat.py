"""``linkdyn run --format mat`` (and ``Result.save(format="mat")``) is read by an independent
MAT-file reader, SciPy's ``scipy.io.loadmat``, with every column's float64 bits equal to the
CSV's under the documented MATLAB name (``coupler.phi`` -> ``coupler_phi``). Skipped where SciPy
is not installed (CI installs only what the package and its examples need; tests/cli_mat.rs
parses the same file without SciPy).
"""

import json

import numpy as np
import pytest

import linkdyn

scipy_io = pytest.importorskip("scipy.io")

MODEL = "models/farahan2016.toml"


def read_csv(path):
    return np.genfromtxt(path, delimiter=",", names=True, deletechars="")


def rows(chars) -> list:
    """The rows of a char matrix as loadmat returns it (an array of padded strings)."""
    return [str(r).rstrip() for r in chars]


def test_loadmat_reads_the_csv_columns_and_the_names_back(cli, tmp_path):
    csv, mat = tmp_path / "r.csv", tmp_path / "r.mat"
    code, _, err = cli("run", MODEL, "--revs", "0.25", "--out", str(csv))
    assert code == 0, err
    code, _, err = cli("run", MODEL, "--revs", "0.25", "--out", str(mat), "--format", "mat")
    assert code == 0, err
    c = read_csv(csv)
    d = scipy_io.loadmat(mat)
    assert d["__version__"] == "1.0"
    names = [n.replace(".", "_") for n in c.dtype.names]
    assert [v[0] for v in scipy_io.whosmat(mat)] == names + ["provenance", "columns", "names"]
    for column, name in zip(c.dtype.names, names):
        assert d[name].dtype == np.float64 and d[name].shape == (len(c), 1), name
        column_bits = np.ascontiguousarray(d[name][:, 0]).view(np.uint64)
        assert np.array_equal(column_bits, c[column].view(np.uint64)), name
    assert rows(d["columns"]) == list(c.dtype.names)
    assert rows(d["names"]) == names
    provenance = json.loads(str(d["provenance"][0]))
    assert provenance == json.loads(mat.with_suffix(".json").read_text())["provenance"]
    # The same file from Python, byte for byte (same model, settings and provenance).
    result = linkdyn.load(MODEL).run(revs=0.25)
    mine = tmp_path / "py.mat"
    result.save(mine, format="mat")
    e = scipy_io.loadmat(mine)
    for name in names:
        assert np.array_equal(e[name].view(np.uint64), d[name].view(np.uint64)), name
