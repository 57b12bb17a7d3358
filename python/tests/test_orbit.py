"""``Model.orbit`` and ``Model.continuation`` give ``linkdyn orbit`` and ``linkdyn continue``'s
numbers, bit for bit, and refuse bad input with the command line's messages.

Both sides call the same library functions (``linkdyn::studies::orbit`` and
``::continuation``) with the same settings, and the files hold every number in its shortest
round-trip form, so any difference is a bug (a different default, a lost override, a lossy
conversion), never rounding. The cases are those of docs/periodic_orbits.md: the reference
four-bar at 3500 rpm, c = 0.44 mm (a stable period-1 orbit with one impact per turn), and a
short branch in the clearance through its first period doubling (c ≈ 0.4150 mm).
"""

import json
import re

import numpy as np
import pytest

import linkdyn
from cli_files import first_difference, read, same_bits
from test_analysis_errors import cli_spelling

MODEL = "models/farahan2016.toml"
SPEED = {"drivers.motor.speed_rpm": 3500}
# The worked example of docs/periodic_orbits.md: 3500 rpm, c = 0.44 mm.
EXAMPLE = {"drivers.motor.speed_rpm": 3500, "joints.B.clearance": 0.00044}
TOL = ["--rtol", "1e-10", "--atol", "1e-12"]
TOL_KW = dict(rtol=1e-10, atol=1e-12)


def without_volatile(d):
    """The JSON minus what differs between two runs or two builds: wall times and the
    version string."""
    d = dict(d)
    d.pop("wall_time_s", None)
    d["provenance"] = dict(d["provenance"])
    d["provenance"].pop("linkdyn_version", None)
    return d


def assert_same_orbit(out, o):
    """The command's F.json (at `out`) and F.csv beside it against the Python orbit `o`."""
    js = json.loads(out.read_text())
    assert isinstance(o, linkdyn.PeriodicOrbit)
    # Every key of F.json is an attribute with the same value; the multipliers' [re, im]
    # pairs are complex numbers and the residual history an array.
    for key, value in js.items():
        got = getattr(o, key)
        if key == "floquet_multipliers":
            assert got.dtype == np.complex128
            assert same_bits(got.real, [z[0] for z in value]), key
            assert same_bits(got.imag, [z[1] for z in value]), key
        elif key == "residual_history":
            assert same_bits(got, value), key
        elif key not in ("wall_time_s", "provenance"):
            assert got == value, f"{key}: CLI {value!r} vs Python {got!r}"
    assert without_volatile(js)["provenance"] == without_volatile(
        {"provenance": o.provenance})["provenance"]
    assert o.wall_time_s > 0
    # The orbit over one period: the command's F.csv, column for column.
    _, names, columns = read(out.with_suffix(".csv"))
    assert names == ["t"] + o.names
    for n in names:
        assert same_bits(columns[n], o[n]), f"{n}: {first_difference(columns[n], o[n])}"
    assert o.samples.shape == (len(o.t), len(o.names))


def test_orbit_is_the_cli_s_bit_for_bit(cli, tmp_path):
    out = tmp_path / "o.json"
    code, _, err = cli("orbit", MODEL, "--set", "drivers.motor.speed_rpm=3500", "--set",
                       "joints.B.clearance=0.00044", *TOL, "--out", str(out))
    assert code == 0, err
    o = linkdyn.load(MODEL, set=EXAMPLE).orbit(**TOL_KW)
    assert_same_orbit(out, o)
    # What the numbers say (docs/periodic_orbits.md, worked example): period 60/3500 s, a
    # stable orbit with one impact per turn, closed to within the Newton tolerance.
    assert o.converged and o.stable and o.impacts_per_period == 1
    assert o.period_s == pytest.approx(60 / 3500, rel=1e-14)
    assert o.state["rocker.phi"] == pytest.approx(1.4529894458, abs=1e-8)
    assert np.all(np.abs(o.floquet_multipliers) < 1)
    assert o.closing_error < 1000


def test_a_dae_orbit_is_the_cli_s_bit_for_bit(cli, tmp_path):
    # The slider-crank with clearance at both rod pins, which only the DAE takes
    # (docs/periodic_orbits.md, "The DAE's orbits").
    model = "models/slider_crank_clearance.toml"
    out = tmp_path / "o.json"
    code, _, err = cli("orbit", model, "--formulation", "dae", *TOL, "--out", str(out))
    assert code == 0, err
    o = linkdyn.load(model).orbit(formulation="dae", **TOL_KW)
    assert_same_orbit(out, o)
    # Both journals in contact all period: no impact, 8 multipliers (4 degrees of freedom),
    # 2 x 5 constraint directions and the 2 kept stored impact velocities trivial.
    assert o.stable and o.impacts_per_period == 0
    assert len(o.floquet_multipliers) == 8 and o.trivial_multipliers == 12
    assert o.period_s == pytest.approx(0.1, rel=1e-14)


def test_continuation_is_the_cli_s_bit_for_bit(cli, tmp_path):
    out = tmp_path / "c.csv"
    args = ["--param", "joints.B.clearance", "--from", "0.0004155", "--to", "0.000414",
            "--step", "0.0000005"]
    code, stdout, err = cli("continue", MODEL, "--set", "drivers.motor.speed_rpm=3500",
                            *args, *TOL, "--out", str(out))
    assert code == 0, err
    b = linkdyn.load(MODEL, set=SPEED).continuation(
        "joints.B.clearance", 0.0004155, 0.000414, step=0.0000005, **TOL_KW)
    assert isinstance(b, linkdyn.Continuation)
    _, names, columns = read(out)
    assert names[0] == b.parameter_name == "joints.B.clearance"
    assert names[1:len(b.names) + 1] == b.names
    assert same_bits(columns[names[0]], b.parameter)
    for n in b.names:
        assert same_bits(columns[n], b[n]), f"{n}: {first_difference(columns[n], b[n])}"
    for n in ("period_s", "max_abs_mu", "min_gap_m", "residual"):
        assert same_bits(columns[n], b[n]), f"{n}: {first_difference(columns[n], b[n])}"
    assert b.stable.dtype == np.bool_
    assert list(columns["stable"]) == [1.0 if s else 0.0 for s in b.stable]
    assert same_bits(columns["impacts_per_period"], b.impacts_per_period)
    assert columns["special"] == b.special
    # F.json's keys.
    js = json.loads(out.with_suffix(".json").read_text())
    assert js["points"] == len(b)
    for key in ("special_points", "unlocated", "end", "period_turns", "solver_stats"):
        assert getattr(b, key) == js[key], key
    assert without_volatile(js)["provenance"] == without_volatile(
        {"provenance": b.provenance})["provenance"]
    # Each point's multipliers: the special points' are in the JSON; the largest modulus is
    # the CSV's max_abs_mu.
    for row in js["special_points"]:
        k = int(np.flatnonzero(b.parameter == row["parameter"])[0])
        mu = b.floquet_multipliers[k]
        assert same_bits(mu.real, [z[0] for z in row["floquet_multipliers"]])
        assert same_bits(mu.imag, [z[1] for z in row["floquet_multipliers"]])
    assert np.array_equal([np.abs(m).max() for m in b.floquet_multipliers], b.max_abs_mu)
    # The stretch holds the period doubling at 0.4150 mm (docs/periodic_orbits.md): stable
    # before it, unstable after, as the command printed.
    assert b.special.count("PD") == 1, b.special
    k = b.special.index("PD")
    assert b.stable[:k].all() and not b.stable[k + 1:].any()
    assert f"PD at joints.B.clearance = {float(b.parameter[k])!r}" in stdout
    assert b.end == {"reason": "reached"} and b.parameter[-1] == 0.000414
    df = b.to_pandas() if _has_pandas() else None
    if df is not None:
        assert list(df.columns) == names


def test_a_followed_period_doubling_is_the_cli_s_bit_for_bit(cli, tmp_path):
    # The period-1 branch across the whole bubble (docs/periodic_orbits.md, "Branch
    # switching"), and the period-2 branch from its first period doubling back to the other.
    out = tmp_path / "c.csv"
    args = ["--param", "joints.B.clearance", "--from", "0.0004155", "--to", "0.000407",
            "--step", "0.000002", "--follow-doublings", "1"]
    code, stdout, err = cli("continue", MODEL, "--set", "drivers.motor.speed_rpm=3500",
                            *args, *TOL, "--out", str(out))
    assert code == 0, err
    seen = []
    b = linkdyn.load(MODEL, set=SPEED).continuation(
        "joints.B.clearance", 0.0004155, 0.000407, step=0.000002, follow_doublings=1,
        progress=seen.append, **TOL_KW)
    _, names, columns = read(out)
    assert names[-2:] == ["branch", "turn"]
    # Progress: every point once, as it joined its branch, in the rows' order (a row per point
    # at turn 0), with its branch, parameter, stability and special point.
    first_turn = b.turn == 0
    assert [p["points"] for p in seen] == list(range(1, int(first_turn.sum()) + 1))
    assert [p["parameter"] for p in seen] == list(b.parameter[first_turn])
    assert [p["branch"] for p in seen] == list(b.branch[first_turn])
    assert [p["stable"] for p in seen] == list(b.stable[first_turn])
    assert [p["special"] for p in seen] == [s for s, t in zip(b.special, b.turn) if t == 0]
    assert same_bits([p["max_abs_mu"] for p in seen], b.max_abs_mu[first_turn])
    for n in [names[0], *b.names, "period_s", "max_abs_mu", "branch", "turn"]:
        assert same_bits(columns[n], b[n]), f"{n}: {first_difference(columns[n], b[n])}"
    assert columns["special"] == b.special
    js = json.loads(out.with_suffix(".json").read_text())
    for key in ("branches", "switch_failures", "end", "points"):
        assert (len(b.parameter[(b.branch == 0) & (b.turn == 0)]) if key == "points"
                else getattr(b, key)) == js[key], key
    # Two branches: the period-2 one starts at branch 0's first PD and rejoins it.
    assert [br["period_turns"] for br in b.branches] == [1, 2]
    two = b.branches[1]
    pds = [p for p, s, k, t in zip(b.parameter, b.special, b.branch, b.turn)
           if k == 0 and t == 0 and s == "PD"]
    assert len(pds) == 2
    assert two["switched_from"] == [0, float(pds[0])]
    assert two["end"]["reason"] == "rejoined"
    # Each of its points has a row per turn, the two section points apart inside the bubble.
    inner = (b.branch == 1) & np.array([s == "" for s in b.special])
    first, second = b["rocker.phi"][inner & (b.turn == 0)], b["rocker.phi"][inner & (b.turn == 1)]
    assert len(first) == len(second) == two["points"] - 2
    assert np.all(np.abs(first - second) > 1e-7)
    assert f"rejoined branch 0 at joints.B.clearance = {two['end']['parameter']!r}" in stdout


def test_ctrl_c_ends_a_continuation_with_keyboard_interrupt():
    import _thread
    import signal
    import threading
    import time

    # Python's own SIGINT handler (a background process may inherit SIGINT ignored; see
    # test_analysis_threads.py), and a signal 1 s into a continuation of several seconds.
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    timer = threading.Timer(1.0, _thread.interrupt_main)
    try:
        started = time.perf_counter()
        timer.start()
        with pytest.raises(KeyboardInterrupt):
            linkdyn.load(MODEL, set=SPEED).continuation(
                "joints.B.clearance", 0.00044, 0.0004, step=0.000002, follow_doublings=1,
                **TOL_KW)
        # Seen at the next point (a point takes well under a second here), not after the whole
        # run (about 8 s here): without the check per point the raise would come at its end.
        assert time.perf_counter() - started < 6.0
    finally:
        timer.cancel()
        signal.signal(signal.SIGINT, previous)


def test_an_exception_from_the_progress_callback_ends_the_continuation():
    calls = []

    def progress(point):
        calls.append(point["parameter"])
        if len(calls) == 3:
            raise ValueError("enough")

    with pytest.raises(ValueError, match="enough"):
        linkdyn.load(MODEL, set=SPEED).continuation(
            "joints.B.clearance", 0.00044, 0.0004, step=0.000002, progress=progress, **TOL_KW)
    # The branch ended at the point that raised: no further point was reported.
    assert len(calls) == 3
    with pytest.raises(TypeError, match=r"progress=: expected True, False, None or a callable "
                                        r"progress\(point\), got str"):
        linkdyn.load(MODEL, set=SPEED).continuation(
            "joints.B.clearance", 0.00044, 0.0004, progress="yes", **TOL_KW)


def test_progress_true_writes_a_line_on_stderr(capfd):
    b = linkdyn.load(MODEL, set=SPEED).continuation(
        "joints.B.clearance", 0.00044, 0.000438, step=0.000001, progress=True, **TOL_KW)
    err = capfd.readouterr().err
    # Not a terminal: a line for the first point, then at most one every 10 s, and the closing
    # line with the count and the last parameter.
    assert re.match(r"continuation joints\.B\.clearance: 1 points, \d+ s, last at 0\.00044\n",
                    err), err
    assert re.search(rf"continuation joints\.B\.clearance: {len(b)} points, \d+ s, "
                     r"last at 0\.000438\n$", err), err


def _has_pandas() -> bool:
    try:
        import pandas  # noqa: F401
    except ImportError:
        return False
    return True


def orbit_call(**kw):
    return lambda: linkdyn.load(MODEL, set=SPEED).orbit(**kw)


def branch_call(param="joints.B.clearance", from_=0.00044, to=0.00043, **kw):
    return lambda: linkdyn.load(MODEL, set=SPEED).continuation(param, from_, to, **kw)


ORBIT = ["orbit", MODEL, "--set", "drivers.motor.speed_rpm=3500"]
BRANCH = ["continue", MODEL, "--set", "drivers.motor.speed_rpm=3500", "--param",
          "joints.B.clearance", "--from", "0.00044", "--to", "0.00043"]

CASES = [
    ("orbit-generalized", ORBIT + ["--formulation", "generalized"], "json",
     orbit_call(formulation="generalized"), linkdyn.SettingsError),
    ("orbit-period-0", ORBIT + ["--period-turns", "0"], "json", orbit_call(period_turns=0),
     linkdyn.SettingsError),
    ("orbit-negative-period", ORBIT + ["--period", "-0.1"], "json",
     orbit_call(period=-0.1), linkdyn.SettingsError),
    ("orbit-not-found", ORBIT + ["--guess-from-turn", "0", "--rtol", "1e-10"], "json",
     orbit_call(guess_from_turn=0, rtol=1e-10), linkdyn.SolverError),
    ("branch-unknown-param", BRANCH[:5] + ["joints.Q.clearance"] + BRANCH[6:], "csv",
     branch_call(param="joints.Q.clearance"), linkdyn.ModelError),
    ("branch-step", BRANCH + ["--step=-1e-6"], "csv", branch_call(step=-1e-6),
     linkdyn.SettingsError),
    ("branch-generalized", BRANCH + ["--formulation", "generalized"], "csv",
     branch_call(formulation="generalized"), linkdyn.SettingsError),
]


@pytest.mark.parametrize("args, ext, call, cls", [c[1:] for c in CASES],
                         ids=[c[0] for c in CASES])
def test_bad_input_raises_the_cli_s_error(cli, tmp_path, args, ext, call, cls):
    code, _, err = cli(*args, "--out", str(tmp_path / f"a.{ext}"))
    lines = [l for l in err.splitlines() if l.startswith("error: ")]
    assert len(lines) == 1, err
    with pytest.raises(linkdyn.LinkdynError) as info:
        call()
    e = info.value
    assert type(e) is cls, f"{type(e).__name__}: {e}"
    assert code == (3 if isinstance(e, RuntimeError) else 2), err
    assert cli_spelling(e) == lines[0][len("error: "):]
    if isinstance(e, linkdyn.SolverError):
        # No orbit: the residual history of the message, as numbers.
        assert e.time is None and len(e.residual_history) >= 2
        shown = ", ".join(re.sub(r"e\+?(-?)0*(\d)", r"e\1\2", f"{r:.3e}")
                          for r in e.residual_history)
        assert shown in str(e), (shown, str(e))


def test_bad_arguments_of_the_python_methods():
    model = linkdyn.load(MODEL, set=SPEED)
    with pytest.raises(linkdyn.SettingsError) as info:
        model.continuation("joints.B.clearance", 4e-4, 4e-4)
    assert str(info.value) == (
        "to: expected a value other than from_ 0.0004 (a branch needs a range)")
    assert info.value.option == "to"
    with pytest.raises(linkdyn.SettingsError) as info:
        model.orbit(period_turns=1, period=0.01)
    assert str(info.value) == "period: give `period_turns` or `period`, not both"
    with pytest.raises(linkdyn.SettingsError) as info:
        model.orbit(guess_from_turn=-1)
    assert str(info.value) == (
        "guess_from_turn: expected a whole number of periods ≥ 0, got -1")
    with pytest.raises(TypeError) as info:
        model.orbit(revs=2)
    assert str(info.value) == "orbit() got an unexpected keyword argument 'revs'"
    with pytest.raises(TypeError) as info:
        model.continuation("joints.B.clearance", 4e-4, 3e-4, t_end=1.0)
    assert str(info.value) == "continuation() got an unexpected keyword argument 't_end'"
