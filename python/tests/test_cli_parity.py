"""The Python package gives the command line's numbers, bit for bit, and reads its files.

For the reference four-bar with a clearance joint (models/farahan2016.toml), the same
settings through ``linkdyn run --out`` and ``linkdyn.load(...).run(...)`` must give the same
columns in the same order with identical float64 bits: both call the same library, and the
CSV holds every number in its shortest round-trip form, so any difference is a bug (a
different default, a lost override, a lossy conversion), never rounding.
"""

import json

import numpy as np
import pytest

import linkdyn

MODEL = "models/farahan2016.toml"


def same_bits(a: np.ndarray, b: np.ndarray) -> bool:
    """Equal as float64 bit patterns (tells 0.0 from -0.0; NaN equals itself)."""
    a = np.ascontiguousarray(a, dtype=np.float64)
    b = np.ascontiguousarray(b, dtype=np.float64)
    return a.shape == b.shape and np.array_equal(a.view(np.uint64), b.view(np.uint64))


def read_csv(path):
    """The one-liner of docs/usage.md ("Output files")."""
    return np.genfromtxt(path, delimiter=",", names=True, deletechars="")


def assert_columns_identical(csv, result, case):
    names = list(csv.dtype.names)
    assert names == ["t"] + result.names, f"{case}: columns differ"
    for name in names:
        py = result[name]
        assert same_bits(csv[name], py), (
            f"{case}: column {name} differs; first mismatch at sample "
            f"{int(np.argmax(csv[name] != py))}: CLI {csv[name][np.argmax(csv[name] != py)]!r} "
            f"vs Python {py[np.argmax(csv[name] != py)]!r}"
        )


def summaries_match(cli_json, py_summary, case):
    """Everything but the wall times and the version string (the binary and the extension
    may be built at different commits of a working tree)."""
    for s in (cli_json, py_summary):
        s.pop("wall_time_s")
        s.pop("sink_time_s")
        s["provenance"].pop("linkdyn_version")
    assert cli_json == py_summary, f"{case}: summaries differ"


@pytest.mark.parametrize(
    "args, kwargs, overrides",
    [
        (["--revs", "1"], dict(revs=1), None),
        (
            ["--t-end", "0.01", "--dt", "1e-5", "--method", "dopri5", "--rtol", "1e-7",
             "--set", "drivers.motor.speed_rpm=3500"],
            dict(t_end=0.01, dt=1e-5, method="dopri5", rtol=1e-7),
            {"drivers.motor.speed_rpm": 3500},
        ),
        (["--revs", "0.5", "--formulation", "reduced"], dict(revs=0.5, formulation="reduced"), None),
        (["--revs", "0.25", "--energy"], dict(revs=0.25, energy=True), None),
    ],
    ids=["250rpm-2turns", "3500rpm-dopri5-set", "reduced", "energy"],
)
def test_columns_and_summary_are_the_cli_s_bit_for_bit(cli, tmp_path, args, kwargs, overrides):
    out = tmp_path / "r.csv"
    code, _, err = cli("run", MODEL, *args, "--out", str(out))
    assert code == 0, err
    result = linkdyn.load(MODEL, set=overrides).run(**kwargs)
    case = " ".join(args)
    assert_columns_identical(read_csv(out), result, case)
    summaries_match(json.loads(out.with_suffix(".json").read_text()), result.summary, case)


@pytest.mark.parametrize(
    "model",
    ["models/slider_crank_lubricated.toml", "models/slider_crank_prismatic_clearance.toml"],
    ids=["lubricated-pin", "slider-in-guide-with-clearance"],
)
def test_the_newer_joint_models_run_from_python_as_from_the_cli(cli, tmp_path, model):
    """A lubricated revolute joint (film columns, film dissipation in --energy) and a
    prismatic-clearance joint (corner contact columns, impact log): the same columns, bits
    and summary from Python as from the command line."""
    out = tmp_path / "r.csv"
    code, _, err = cli("run", model, "--revs", "0.25", "--energy", "--out", str(out))
    assert code == 0, err
    result = linkdyn.load(model).run(revs=0.25, energy=True)
    assert_columns_identical(read_csv(out), result, model)
    summaries_match(json.loads(out.with_suffix(".json").read_text()), result.summary, model)


def test_saved_csv_is_the_cli_s_byte_for_byte(cli, tmp_path):
    out = tmp_path / "cli.csv"
    code, _, err = cli("run", MODEL, "--revs", "0.5", "--out", str(out))
    assert code == 0, err
    result = linkdyn.load(MODEL).run(revs=0.5)
    mine = tmp_path / "py.csv"
    result.save(mine)
    # The version line may differ (see summaries_match); every other byte may not.
    strip = lambda p: [l for l in p.read_text().splitlines() if not l.startswith("# linkdyn ")]
    assert strip(mine) == strip(out)
    assert sorted(p.name for p in tmp_path.iterdir()) == [
        "cli.csv", "cli.impacts.csv", "cli.json", "py.csv", "py.impacts.csv", "py.json"]
    # The impact logs agree too, apart from the version line.
    assert strip(tmp_path / "py.impacts.csv") == strip(tmp_path / "cli.impacts.csv")


def test_set_overrides_reach_the_model_and_the_provenance():
    model = linkdyn.load(MODEL, set={"drivers.motor.speed_rpm": 3500, "bodies.crank.mass": 0.5})
    assert model.overrides == ["drivers.motor.speed_rpm=3500", "bodies.crank.mass=0.5"]
    # 3500 rpm = 3500·2π/60 rad/s, converted once in the library: equal to the last bit.
    assert model.drivers[0]["speed"] == 3500 * 2 * np.pi / 60, model.drivers[0]
    assert model.bodies[0]["mass"] == 0.5
    result = model.run(t_end=1e-3, dt=1e-4)
    assert result.summary["provenance"]["model"]["overrides"] == model.overrides
    # A list of "KEY=VALUE" strings is the same thing.
    same = linkdyn.load(MODEL, set=["drivers.motor.speed_rpm=3500", "bodies.crank.mass=0.5"])
    assert same.overrides == model.overrides
    # The crank turns at the new speed: φ(t) = ω t for a constant-speed driver from 0.
    phi = result["crank.phi"]
    omega = 3500 * 2 * np.pi / 60
    # Driver constraint held to the Baumgarte-stabilised accuracy (max |Φ| ~ 1e-10 rad).
    assert np.max(np.abs(phi - omega * result.t)) < 1e-8, np.max(np.abs(phi - omega * result.t))


def test_npz_reads_in_one_line_and_matches_the_csv(cli, tmp_path):
    csv, npz = tmp_path / "r.csv", tmp_path / "r.npz"
    code, _, err = cli("run", MODEL, "--revs", "0.5", "--out", str(csv))
    assert code == 0, err
    code, _, err = cli("run", MODEL, "--revs", "0.5", "--out", str(npz), "--format", "npz")
    assert code == 0, err
    d = np.load(npz)
    c = read_csv(csv)
    assert d.files == list(c.dtype.names) + ["provenance"]
    for name in c.dtype.names:
        assert d[name].dtype == np.float64 and d[name].shape == c[name].shape, name
        assert same_bits(d[name], c[name]), name
    provenance = json.loads(str(d["provenance"]))
    assert provenance == json.loads(npz.with_suffix(".json").read_text())["provenance"]
    # The same archive from Python.
    result = linkdyn.load(MODEL).run(revs=0.5)
    mine = tmp_path / "py.npz"
    result.save(mine, format="npz")
    e = np.load(mine)
    assert e.files == d.files
    for name in c.dtype.names:
        assert same_bits(e[name], d[name]), name


def test_csv_one_liners_of_the_readme(cli, tmp_path):
    out = tmp_path / "r.csv"
    code, _, err = cli("run", MODEL, "--revs", "0.25", "--out", str(out))
    assert code == 0, err
    s = np.genfromtxt(out, delimiter=",", names=True, deletechars="")
    a = np.loadtxt(out, delimiter=",", skiprows=1)
    assert a.shape == (len(s), len(s.dtype.names))
    for k, name in enumerate(s.dtype.names):
        assert same_bits(a[:, k], s[name]), name
    assert a[0, 0] == 0.0 and s["t"][-1] == pytest.approx(0.25 * 60 / 250, abs=1e-4)
    pd = pytest.importorskip("pandas")
    df = pd.read_csv(out, comment="#")
    assert list(df.columns) == list(s.dtype.names)
    assert same_bits(df["coupler.phi"].to_numpy(), s["coupler.phi"])
