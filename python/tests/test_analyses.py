"""The analyses from Python give the command line's numbers, bit for bit, as NumPy arrays.

Each case runs a ``linkdyn`` analysis command with ``--out`` and the same analysis through
``Model``, then compares every CSV column with the Python array as float64 bit patterns: both
call the same library function on the same model and settings, and the CSV holds shortest
round-trip digits, so any difference is a bug (a default, a lost option, a conversion), never
rounding. The printed verdict, peaks and exponent, and the ``#`` provenance lines, must match
too. Then shapes, dtypes and units are checked against what each result claims.
"""

import math
import re

import numpy as np
import pytest

import linkdyn
from cli_files import first_difference, provenance_lines, read, same_bits, without_version

MODEL = "models/farahan2016.toml"
FAST = {"drivers.motor.speed_rpm": 3500}
FAST_SET = ["--set", "drivers.motor.speed_rpm=3500"]


def run_cli(cli, tmp_path, command, *args):
    out = tmp_path / f"{command}.csv"
    code, stdout, err = cli(command, MODEL, *args, "--out", str(out))
    assert code == 0, err
    return out, stdout


def assert_same(csv_column, array, case):
    assert same_bits(csv_column, array), f"{case}: {first_difference(csv_column, array)}"


def assert_same_provenance(csv_lines, result, case):
    assert without_version(csv_lines) == provenance_lines(result.provenance), case


@pytest.mark.parametrize(
    "args, kwargs, overrides",
    [
        (["--revs", "12", "--transient", "4", "--observe", "B.ex,B.ey", "--formulation",
          "reduced", *FAST_SET],
         dict(revs=12, transient=4, observe=["B.ex", "B.ey"], formulation="reduced"), FAST),
        # No --observe: every state, y[i]; a section phase; a looser tolerance.
        (["--revs", "3", "--phase", "1.5", "--rtol", "1e-7"],
         dict(revs=3, phase=1.5, rtol=1e-7), None),
    ],
    ids=["reduced-3500rpm-B.ex,B.ey", "dae-states-phase"],
)
def test_poincare_is_the_cli_s(cli, tmp_path, args, kwargs, overrides):
    out, stdout = run_cli(cli, tmp_path, "poincare", *args)
    s = linkdyn.load(MODEL, set=overrides).poincare(**kwargs)
    lines, names, csv = read(out)
    case = " ".join(args)
    assert names == ["turn", "t"] + s.names, case
    assert_same(csv["turn"], s.turn, case + " turn")
    assert_same(csv["t"], s.t, case + " t")
    for n in s.names:
        assert_same(csv[n], s[n], f"{case} {n}")
    assert_same_provenance(lines, s, case)
    printed = dict(l.split(": ", 1) for l in stdout.splitlines())
    assert printed["verdict"] == s.verdict, case
    tolerance = ", ".join(f"{n} {_rust_e(t, 2)}" for n, t in zip(s.names, s.tolerance))
    assert printed[
        "period tolerance (1000 x the integration tolerance carried to each column)"
    ] == tolerance, case
    if s.settled_at_turn is not None:
        assert printed["settled"].startswith(f"every point from turn {s.settled_at_turn} on"), case
    else:
        assert "settled" not in printed, case


def test_poincare_shapes_units_and_verdict():
    model = linkdyn.load(MODEL, set=FAST)
    s = model.poincare(revs=12, transient=4, observe="B.ex, B.ey", formulation="reduced")
    # One point per turn from the transient on, at t_k = k·T (T = 60/3500 s): the section
    # instants are computed, not sampled, so they agree to rounding (1e-12 s ≪ dt).
    T = 60 / 3500
    assert s.names == ["B.ex", "B.ey"]
    assert s.turn.dtype == np.int64 and list(s.turn) == list(range(4, 12))
    assert s.points.shape == (8, 2) and s.points.dtype == np.float64
    assert s.driver_period == pytest.approx(T, rel=1e-15)
    assert np.max(np.abs(s.t - s.turn * T)) < 1e-12, s.t - s.turn * T
    # At 3500 rpm the journal tracks the bearing wall (Farahan et al. 2016, Sec. 4): at every
    # section it is in contact, |e| > c = 0.5 mm, and the penetration |e| − c (tens of µm
    # under kN loads) stays below a tenth of the clearance.
    e = np.hypot(s["B.ex"], s["B.ey"])
    assert np.all((e > 0.5e-3) & (e < 0.55e-3)), e
    # Period one: the verdict, its details, the settled turn and the points themselves.
    assert s.verdict == "period-1" and s.period == 1
    assert s.verdict_details["verdict"] == "period" and s.verdict_details["mismatch"] <= 1
    assert s.settled_at_turn is not None and 4 <= s.settled_at_turn <= 11
    settled = s.points[s.turn >= s.settled_at_turn]
    spread = settled.max(axis=0) - settled.min(axis=0)
    assert np.all(spread <= s.tolerance), (spread, s.tolerance)
    assert s.stats["steps"] > 0 and len(s) == 8
    if _pandas():
        assert list(s.to_pandas().columns) == ["turn", "t", "B.ex", "B.ey"]
    with pytest.raises(KeyError, match='no column "B.fn"'):
        s["B.fn"]


def _pandas() -> bool:
    try:
        import pandas  # noqa: F401
    except ImportError:
        return False
    return True


def test_spectrum_is_the_cli_s(cli, tmp_path):
    out, stdout = run_cli(
        cli, tmp_path, "spectrum", "--observe", "B.fn", "--revs", "4", "--transient", "1")
    sp = linkdyn.load(MODEL).spectrum("B.fn", revs=4, transient=1)
    lines, names, csv = read(out)
    assert names == ["frequency_hz", "amplitude"]
    assert_same(csv["frequency_hz"], sp.frequency, "frequency")
    assert_same(csv["amplitude"], sp.amplitude, "amplitude")
    assert_same_provenance(lines, sp, "spectrum")
    printed = stdout.splitlines()
    assert printed[0] == f"driving frequency: {sp.driving_frequency:.6f} Hz"
    expected = [
        f"peak: {p['frequency']:.6f} Hz, amplitude {_rust_e(p['amplitude'], 6)} = "
        f"{p['multiple']:.3f} x driving"
        for p in sp.peaks
    ]
    assert printed[1:] == expected


def _rust_e(x: float, digits: int) -> str:
    """Rust's `{:.6e}`: no '+' and no leading zeros in the exponent (3.916913e1)."""
    m, e = f"{x:.{digits}e}".split("e")
    return f"{m}e{int(e)}"


def test_spectrum_shapes_units_and_peaks():
    sp = linkdyn.load(MODEL).spectrum("B.fn", revs=4, transient=1)
    # 250 rpm: f_d = 250/60 Hz, exactly |ω|/2π of the driver.
    assert sp.driving_frequency == pytest.approx(250 / 60, rel=1e-15)
    # 3 turns at dt = 1e-4 s: N = 7201 samples (both ends), N//2 + 1 bins from 0 to 1/(2 dt).
    assert sp.n_samples == 7201 and sp.dt == pytest.approx(1e-4, rel=1e-9)
    assert sp.frequency.shape == sp.amplitude.shape == (7201 // 2 + 1,)
    assert sp.frequency[0] == 0.0
    assert sp.frequency[1] == pytest.approx(1 / (7201 * 1e-4), rel=1e-9)
    assert sp.window == "hann" and not sp.resampled
    # The normal force repeats every turn: its strongest peaks sit on whole multiples of f_d
    # (to 1e-3: the refined peak of 3 turns' window, Δf = f_d/3, interpolated).
    assert len(sp.peaks) >= 3
    for p in sp.peaks[:4]:
        assert abs(p["multiple"] - round(p["multiple"])) < 1e-3, p
        assert p["frequency"] == pytest.approx(p["multiple"] * sp.driving_frequency, rel=1e-12)
        assert sp.frequency[p["bin"]] == pytest.approx(p["frequency"], abs=sp.frequency[1])
    assert np.array_equal(sp.peak_multiples, [p["multiple"] for p in sp.peaks])
    amplitudes = [p["amplitude"] for p in sp.peaks]
    assert amplitudes == sorted(amplitudes, reverse=True)


@pytest.mark.parametrize(
    "observe, source", [("coupler.phi", "coupler.omega"), ("B.fn", "central differences")]
)
def test_phase_is_the_cli_s(cli, tmp_path, observe, source):
    out, _ = run_cli(
        cli, tmp_path, "phase", "--observe", observe, "--revs", "1.5", "--transient", "0.5")
    ph = linkdyn.load(MODEL).phase(observe, revs=1.5, transient=0.5)
    lines, names, csv = read(out)
    assert names == ["t", "value", "rate"]
    for n in names:
        assert_same(csv[n], getattr(ph, n), f"{observe} {n}")
    assert_same_provenance(lines, ph, observe)
    assert ph.rate_source == source


def test_phase_rate_is_the_rate_column():
    model = linkdyn.load(MODEL)
    ph = model.phase("coupler.phi", revs=1.5, transient=0.5)
    r = model.run(revs=1.5)
    # The window starts at the first sample at or after 0.5 turns (T = 0.24 s).
    first = int(np.argmax(r.t >= 0.5 * 0.24 - 1e-12))
    assert same_bits(ph.t, r.t[first:])
    assert same_bits(ph.value, r["coupler.phi"][first:])
    assert same_bits(ph.rate, r["coupler.omega"][first:])
    assert len(ph) == len(r) - first


def test_lyapunov_is_the_cli_s(cli, tmp_path):
    args = ["--revs", "6", "--transient", "2", "--formulation", "reduced"]
    out, stdout = run_cli(cli, tmp_path, "lyapunov", *args)
    e = linkdyn.load(MODEL).lyapunov(revs=6, transient=2, formulation="reduced")
    lines, names, csv = read(out)
    assert names == ["t", "lambda"]
    assert_same(csv["t"], e.t, "t")
    assert_same(csv["lambda"], e.estimate, "lambda")
    assert_same_provenance(lines, e, "lyapunov")
    assert stdout.strip() == (
        f"lambda = {e.exponent:.4f} ± {e.uncertainty:.4f} 1/s "
        f"(drift over the second half {e.drift:.4f} 1/s)"
    )


def test_lyapunov_history_and_units():
    e = linkdyn.load(MODEL).lyapunov(revs=6, transient=2, formulation="reduced")
    T = 60 / 250
    # One estimate per renormalisation, every turn after the transient: t_k = (2 + k)·T.
    assert e.t.shape == e.estimate.shape == (4,)
    assert np.max(np.abs(e.t - (2 + np.arange(1, 5)) * T)) < 1e-9, e.t
    # λ is the last running estimate; the drift is |λ_K − λ_{K/2}|.
    assert e.exponent == e.estimate[-1]
    assert e.drift == pytest.approx(abs(e.estimate[-1] - e.estimate[1]), rel=1e-12)
    assert math.isfinite(e.uncertainty) and e.uncertainty >= 0
    assert e.stats["steps"] > 0


BIFURCATION = dict(param="joints.B.clearance", observe="coupler.phi")
SWEEP_ARGS = ["--param", "joints.B.clearance", "--from", "0.0002", "--to", "0.0005",
              "--steps", "3", "--revs", "8", "--transient", "4", "--observe", "coupler.phi",
              "--formulation", "reduced", *FAST_SET]
SWEEP_KWARGS = dict(from_=0.0002, to=0.0005, steps=3, revs=8, transient=4,
                    formulation="reduced", progress=False)


@pytest.mark.parametrize("threads", [1, 2])
def test_bifurcation_is_the_cli_s(cli, tmp_path, threads):
    out, stdout = run_cli(cli, tmp_path, "bifurcation", *SWEEP_ARGS, "--threads", "2")
    b = linkdyn.load(MODEL, set=FAST).bifurcation(
        "joints.B.clearance", "coupler.phi", threads=threads, **SWEEP_KWARGS)
    lines, names, csv = read(out)
    assert names == ["index", "joints.B.clearance", "turn", "coupler.phi"]
    assert_same(csv["index"], b.index, "index")
    assert_same(csv["joints.B.clearance"], b.parameter, "parameter")
    assert_same(csv["turn"], b.turn, "turn")
    assert_same(csv["coupler.phi"], b.value, "value")
    assert_same_provenance(lines, b, "bifurcation")
    vlines, vnames, verdicts = read(out.with_suffix(".verdicts.csv"))
    assert vnames == ["index", "joints.B.clearance", "verdict", "k", "message"]
    assert_same(verdicts["index"], b.point_index, "point index")
    assert_same(verdicts["joints.B.clearance"], b.point_parameter, "point parameter")
    assert verdicts["verdict"] == b.verdict
    assert_same(verdicts["k"], b.k, "k")
    assert verdicts["message"] == b.message == [""] * 4
    assert without_version(vlines) == without_version(lines)


def test_bifurcation_shapes_values_and_shards():
    model = linkdyn.load(MODEL, set=FAST)
    b = model.bifurcation(**BIFURCATION, **SWEEP_KWARGS)
    # 4 points (3 intervals, both ends) × 4 recorded turns, in index order.
    assert b.index.dtype == b.turn.dtype == b.k.dtype == np.int64
    assert b.value.shape == b.parameter.shape == (16,)
    assert list(b.index) == [i for i in range(4) for _ in range(4)]
    assert list(b.turn) == list(range(4, 8)) * 4
    # The grid p_i = from + (to − from)·(i/steps), the last point exactly `to`.
    assert list(b.point_parameter) == [0.0002 + (0.0005 - 0.0002) * (i / 3) for i in range(3)] + [
        0.0005]
    assert np.array_equal(b.parameter, np.repeat(b.point_parameter, 4))
    assert set(b.verdict) <= {"period", "no_period", "not_settled"}
    assert all((k > 0) == (v == "period") for v, k in zip(b.verdict, b.k))
    assert b.provenance["settings"]["parameter"] == "joints.B.clearance"
    # Explicit values give the same points as the grid did (same values, same numbers).
    v = model.bifurcation(**BIFURCATION, values=b.point_parameter[[3, 1]],
                          **{k: w for k, w in SWEEP_KWARGS.items()
                             if k not in ("from_", "to", "steps")})
    assert list(v.point_index) == [0, 1] and list(v.point_parameter) == list(
        b.point_parameter[[3, 1]])
    assert same_bits(v.value[:4], b.value[12:]) and same_bits(v.value[4:], b.value[4:8])
    # Shards partition the grid: shard 2/2 is points 1 and 3.
    s = model.bifurcation(**BIFURCATION, shard="2/2", **SWEEP_KWARGS)
    assert list(s.point_index) == [1, 3]
    assert same_bits(s.value, b.value[np.isin(b.index, [1, 3])])
    if _pandas():
        df = b.to_pandas()
        assert list(df.columns) == ["index", "joints.B.clearance", "turn", "coupler.phi"]
    assert re.match(r"<linkdyn.Bifurcation: 4 points of joints.B.clearance, 16 rows", repr(b))


WARM_ARGS = ["--param", "joints.B.clearance", "--from", "0.0001", "--to", "0.0003",
             "--steps", "5", "--revs", "16", "--transient", "12", "--observe", "coupler.phi",
             "--formulation", "reduced", "--method", "radau5", "--rtol", "1e-6", "--atol",
             "1e-9", "--settle", "--transient-min", "3", "--warm-start", "--chunks", "2",
             *FAST_SET]
WARM_KWARGS = dict(from_=0.0001, to=0.0003, steps=5, revs=16, transient=12,
                   formulation="reduced", method="radau5", rtol=1e-6, atol=1e-9,
                   settle=True, transient_min=3, warm_start=True, chunks=2, progress=False)


@pytest.mark.parametrize("direction", ["up", "both"])
def test_warm_started_settled_bifurcation_is_the_cli_s(cli, tmp_path, direction):
    """The fast Fig. 6a settings (docs/sweeps.md) from Python: the same points, the same
    transient turns and starts as `linkdyn bifurcation --settle --warm-start`, each branch."""
    out, _ = run_cli(cli, tmp_path, "bifurcation", *WARM_ARGS, "--direction", direction)
    b = linkdyn.load(MODEL, set=FAST).bifurcation(
        **BIFURCATION, direction=direction, **WARM_KWARGS)
    branches = ["up", "down"] if direction == "both" else ["up"]
    assert sorted(set(b.direction)) == sorted(branches)
    for branch in branches:
        path = out.with_suffix(f".{branch}.csv") if direction == "both" else out
        lines, names, csv = read(path)
        rows = np.array([d == branch for d in b.direction])
        assert_same(csv["index"], b.index[rows], f"{branch} index")
        assert_same(csv["turn"], b.turn[rows], f"{branch} turn")
        assert_same(csv["coupler.phi"], b.value[rows], f"{branch} value")
        # The same settings; a branch file names its own direction, the record both.
        settings = provenance_lines(b.provenance)
        assert f"direction = {','.join(branches)}" in settings
        assert without_version(lines) == [
            f"direction = {branch}" if line.startswith("direction = ") else line
            for line in settings]
        _, vnames, verdicts = read(path.with_suffix(".verdicts.csv"))
        points = [d == branch for d in b.point_direction]
        assert vnames[4:6] == ["transient_turns", "start"]
        assert_same(verdicts["index"], b.point_index[points], f"{branch} point index")
        assert verdicts["verdict"] == [v for v, p in zip(b.verdict, points) if p]
        assert_same(verdicts["transient_turns"], b.transient_turns[points], f"{branch} turns")
        assert verdicts["start"] == [s for s, p in zip(b.start, points) if p]
    # Settled early somewhere (period one here), never before transient_min.
    assert 3 <= b.transient_turns.min() and b.transient_turns.max() <= 12
    assert b.transient_turns.min() < 12
    # Each chunk's first point starts cold, the others warm.
    assert b.start.count("cold") == 2 * len(branches)


def test_warm_start_needs_the_reduced_formulation():
    with pytest.raises(linkdyn.SettingsError, match="needs `formulation` reduced"):
        linkdyn.load(MODEL).bifurcation(**BIFURCATION, from_=1e-4, to=3e-4, steps=1, revs=3,
                                        transient=1, warm_start=True, progress=False)
    with pytest.raises(linkdyn.SettingsError, match="direction"):
        linkdyn.load(MODEL).bifurcation(**BIFURCATION, from_=1e-4, to=3e-4, steps=1, revs=3,
                                        transient=1, formulation="reduced", warm_start=True,
                                        direction="sideways", progress=False)
