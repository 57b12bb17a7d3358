"""Shapes, dtypes and contents of Model and Result."""

import math
import subprocess
import sys

import numpy as np
import pytest

import linkdyn

MODEL = "models/farahan2016.toml"


@pytest.fixture(scope="module")
def run(root):
    # Half a crank turn at 250 rpm: 0.12 s, 1201 samples at dt = 1e-4 s.
    return linkdyn.load(root / MODEL).run(revs=0.5)


def test_arrays_are_float64_one_per_column_read_only(run):
    n = len(run)
    assert n == 1201 and run.t.shape == (n,) and run.t.dtype == np.float64
    assert run.t[0] == 0.0 and run.t[-1] == pytest.approx(0.12, abs=1e-12)
    for name in run.names:
        a = run[name]
        assert a.shape == (n,) and a.dtype == np.float64, name
        assert a is run.column(name) or np.shares_memory(a, run.column(name)), name
        assert not a.flags.writeable, name
    with pytest.raises(ValueError):
        run["B.ex"][0] = 1.0
    assert run.constraint_violation.shape == (n,)
    assert "coupler.phi" in run and "t" in run and "nope" not in run
    assert run["t"] is run.t or np.shares_memory(run["t"], run.t)


def test_columns_are_consistent_with_each_other(run):
    # Penetration δ = |e| − c with c = 0.5 mm (model file), from the same sample.
    e = np.hypot(run["B.ex"], run["B.ey"])
    assert np.max(np.abs(e - 5e-4 - run["B.delta"])) < 1e-15, "delta = |e| - c"
    # The journal stays in the bearing: a penetration is at most 0.1 R_J = 1 mm (the limit the
    # library enforces) and in this run much less (tens of µm).
    assert np.max(run["B.delta"]) < 1e-4, np.max(run["B.delta"])
    # Normal force only in contact, never pulling.
    assert np.all(run["B.fn"] >= 0.0)
    assert np.all(run["B.fn"][run["B.delta"] < 0] == 0.0)


def test_events_and_summary_agree(run):
    s = run.summary
    assert s["samples"] == len(run)
    (joint,) = s["clearance_joints"]
    impacts = [e for e in run.events if e["kind"] == "impact"]
    separations = [e for e in run.events if e["kind"] == "separation"]
    assert joint["joint"] == "B" and all(e["joint"] == "B" for e in run.events)
    assert (joint["impact_count"], joint["separations"]) == (len(impacts), len(separations))
    assert [i["t"] for i in joint["impacts"]] == [e["t"] for e in impacts], "the impact log"
    assert joint["first_impact_times"] == [e["t"] for e in impacts][:10]
    ts = [e["t"] for e in run.events]
    assert ts == sorted(ts), "events in time order"
    # True peaks, located on the dense output: never below the samples' maxima, and the
    # largest of the per-impact peaks of the log.
    assert joint["max_penetration"] >= float(np.max(run["B.delta"]))
    assert joint["peak_normal_force"] >= float(np.max(run["B.fn"]))
    assert joint["peak_normal_force"] == max(i["peak_normal_force"] for i in joint["impacts"])
    assert s["max_constraint_violation"] == float(np.max(run.constraint_violation))
    assert s["provenance"]["settings"]["method"] == "dop853"
    assert s["solver_stats"]["steps"] > 0
    assert run.summary is not s, "a new dict each time"


def test_model_description_and_check():
    m = linkdyn.load(MODEL)
    assert m.name == "farahan2016" and m.path == MODEL
    assert [b["name"] for b in m.bodies] == ["crank", "coupler", "rocker"]
    assert [j["name"] for j in m.joints] == ["O2", "A", "B", "O4"]
    assert m.joints[2]["type"] == "clearance" and m.joints[2]["clearance"] == 5e-4
    assert m.drivers[0]["speed_rpm"] == pytest.approx(250.0, rel=1e-15)
    assert m.clearance_joints == ["B"]
    c = m.check()
    # 3 bodies × 3 coordinates; rows: two revolute joints × 2, the rocker pivot × 2, the
    # driver 1 (the clearance joint is a force, not a constraint): 2 degrees of freedom,
    # the journal's two eccentricity components.
    assert (c["coordinates"], c["constraint_rows"], c["rank"]) == (9, 7, 7)
    assert c["degrees_of_freedom"] == m.degrees_of_freedom == 2
    assert c["redundant_constraints"] == []
    assert c["assembly_residual"] < 1e-10
    assert set(c["assembled"]) == {"crank", "coupler", "rocker"}


def test_check_matches_the_cli(cli):
    code, out, err = cli("check", "models/fourbar_ideal.toml")
    assert code == 0, err
    c = linkdyn.load("models/fourbar_ideal.toml").check()
    line = next(l for l in out.splitlines() if l.startswith("coordinates:"))
    assert line == (
        f"coordinates: {c['coordinates']}, constraint rows: {c['constraint_rows']}, "
        f"rank: {c['rank']}, degrees of freedom: {c['degrees_of_freedom']}"
    )


def test_to_pandas(run):
    pd = pytest.importorskip("pandas")
    df = run.to_pandas()
    assert list(df.columns) == ["t"] + run.names
    assert df.shape == (len(run), len(run.names) + 1)
    assert np.array_equal(df["B.fn"].to_numpy(), run["B.fn"])


def test_to_pandas_without_pandas_says_how_to_get_it():
    # A fresh interpreter in which `import pandas` fails.
    code = (
        "import sys; sys.modules['pandas'] = None\n"
        "import linkdyn\n"
        f"r = linkdyn.load({MODEL!r}).run(t_end=1e-3)\n"
        "try:\n    r.to_pandas()\nexcept ImportError as e:\n    print('ImportError:', e)\n"
    )
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    assert p.stdout.startswith("ImportError: Result.to_pandas() needs pandas"), p.stdout
    assert "pip install pandas" in p.stdout


def test_repr_and_version():
    m = linkdyn.load(MODEL)
    assert repr(m).startswith('<linkdyn.Model "farahan2016"')
    assert linkdyn.__version__ == linkdyn.version() and linkdyn.version().startswith("0.")
    r = m.run(t_end=1e-3)
    assert repr(r).startswith("<linkdyn.Result: 11 samples × 40 columns")
    assert math.isclose(r.t[-1], 1e-3, rel_tol=1e-12)
