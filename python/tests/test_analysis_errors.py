"""Analysis errors raise the right exception class with the command line's message.

Each case runs a ``linkdyn`` analysis command with some bad input and the same input through
``Model``, and compares ``error: <message>`` on the CLI's stderr with ``str(exception)`` after
the one documented respelling: the CLI names settings as flags (``--phase``, and
``--t-end`` for `` `t_end` `` in a reason) and the swept field as ``--param PATH``, where
Python says ``phase``, ``t_end`` and ``param PATH``. The exit code gives the class: 2 is a
``ValueError`` (``SettingsError``, ``ModelError``, ``AnalysisError``), 3 a ``SolverError``.
"""

import re

import numpy as np
import pytest

import linkdyn

MODEL = "models/farahan2016.toml"
POINT = re.compile(r"^point \d+ \([^)]*\): ")
PARAM = re.compile(r"^param [^ :]+: ")


def flag(name: str) -> str:
    return "--" + name.replace("_", "-")


def cli_spelling(e: linkdyn.LinkdynError) -> str:
    """The CLI's message for the Python exception `e` (src/cli/mod.rs, `message`)."""
    text = str(e)
    m = POINT.match(text)
    prefix, text = (m.group(0), text[m.end():]) if m else ("", text)
    m = PARAM.match(text)
    if m:
        prefix, text = prefix + "--" + m.group(0), text[m.end():]
    if isinstance(e, linkdyn.SettingsError):
        reason = text[len(e.option) + 2:]
        parts = reason.split("`")
        text = flag(e.option) + ": " + "".join(
            flag(p) if k % 2 else p for k, p in enumerate(parts))
    return prefix + text


SWEEP = ["--param", "joints.B.clearance", "--from", "0.0002", "--to", "0.0003", "--steps",
         "1", "--revs", "3", "--transient", "1", "--observe", "coupler.phi", "--threads", "1"]
SWEEP_KW = dict(from_=0.0002, to=0.0003, steps=1, revs=3, transient=1, threads=1,
                progress=False)


def sweep(args):
    """SWEEP with the flags in `args` replaced (or added)."""
    out = list(SWEEP)
    for k in range(0, len(args), 2):
        if args[k] in out:
            out[out.index(args[k]) + 1] = args[k + 1]
        else:
            out += args[k:k + 2]
    return out


def bif(param="joints.B.clearance", observe="coupler.phi", model=MODEL, **changes):
    kw = dict(SWEEP_KW)
    kw.update(changes)
    return lambda: linkdyn.load(model).bifurcation(param, observe, **kw)


def m(name, **kw):
    return lambda: getattr(linkdyn.load(MODEL), name)(**kw)


CASES = [
    # (id, CLI arguments after the command's model, the Python call, class, exit code)
    ("poincare-phase", ["poincare", MODEL, "--phase", "7"], m("poincare", phase=7.0),
     linkdyn.SettingsError, 2),
    ("poincare-fractional-revs", ["poincare", MODEL, "--revs", "2.5"],
     m("poincare", revs=2.5), linkdyn.SettingsError, 2),
    ("poincare-revs-not-past-transient", ["poincare", MODEL, "--revs", "3", "--transient", "3"],
     m("poincare", revs=3, transient=3), linkdyn.SettingsError, 2),
    ("poincare-unknown-column", ["poincare", MODEL, "--observe", "B.ex,B.exx"],
     m("poincare", observe=["B.ex", "B.exx"]), linkdyn.SettingsError, 2),
    ("poincare-method", ["poincare", MODEL, "--method", "rk4"], m("poincare", method="rk4"),
     linkdyn.SettingsError, 2),
    ("poincare-solver", ["poincare", MODEL, "--max-steps", "10"], m("poincare", max_steps=10),
     linkdyn.SolverError, 3),
    ("poincare-max-wall", ["poincare", MODEL, "--max-wall", "-1"], m("poincare", max_wall=-1.0),
     linkdyn.SettingsError, 2),
    ("run-max-wall", ["run", MODEL, "--max-wall", "0"], m("run", max_wall=0.0),
     linkdyn.SettingsError, 2),
    ("spectrum-transient", ["spectrum", MODEL, "--observe", "B.fn", "--transient", "-1"],
     m("spectrum", observe="B.fn", transient=-1.0), linkdyn.SettingsError, 2),
    ("spectrum-revs", ["spectrum", MODEL, "--observe", "B.fn", "--revs", "1", "--transient", "2"],
     m("spectrum", observe="B.fn", revs=1, transient=2), linkdyn.SettingsError, 2),
    ("spectrum-too-few-samples", ["spectrum", MODEL, "--observe", "B.fn", "--revs", "0.0002"],
     m("spectrum", observe="B.fn", revs=0.0002), linkdyn.AnalysisError, 2),
    ("phase-unknown-column", ["phase", MODEL, "--observe", "B.fnn"],
     m("phase", observe="B.fnn"), linkdyn.SettingsError, 2),
    ("phase-reduced-does-not-fit", ["phase", "models/fourbar_ideal.toml", "--observe",
                                    "coupler.phi", "--formulation", "reduced"],
     lambda: linkdyn.load("models/fourbar_ideal.toml").phase("coupler.phi",
                                                            formulation="reduced"),
     linkdyn.ModelError, 2),
    ("lyapunov-renormalise", ["lyapunov", MODEL, "--renormalise-every-revs", "0"],
     m("lyapunov", renormalise_every_revs=0.0), linkdyn.SettingsError, 2),
    ("lyapunov-intervals", ["lyapunov", MODEL, "--revs", "3", "--transient", "2"],
     m("lyapunov", revs=3, transient=2), linkdyn.SettingsError, 2),
    ("lyapunov-d0", ["lyapunov", MODEL, "--d0", "-1", "--revs", "3"],
     m("lyapunov", d0=-1.0, revs=3), linkdyn.AnalysisError, 2),
    ("bifurcation-grid", ["bifurcation", MODEL, *sweep(["--from", "1", "--to", "2",
                                                        "--steps", "0"])],
     bif(from_=1.0, to=2.0, steps=0), linkdyn.AnalysisError, 2),
    ("bifurcation-revs", ["bifurcation", MODEL, *sweep(["--transient", "3"])],
     bif(transient=3), linkdyn.SettingsError, 2),
    ("bifurcation-unknown-param", ["bifurcation", MODEL, *sweep(["--param",
                                                                 "joints.B.clearanc"])],
     bif(param="joints.B.clearanc"), linkdyn.ModelError, 2),
    ("bifurcation-unknown-column", ["bifurcation", MODEL, *sweep(["--observe", "coupler.ph"])],
     bif(observe="coupler.ph"), linkdyn.SettingsError, 2),
    ("bifurcation-threads", ["bifurcation", MODEL, *sweep(["--threads", "0"])],
     bif(threads=0), linkdyn.SettingsError, 2),
    # A last point whose value the model refuses (a clearance beyond the journal radius): both
    # ends of the grid are checked before any point runs.
    ("bifurcation-point-model", ["bifurcation", MODEL, *sweep(["--to", "0.02"])],
     bif(to=0.02), linkdyn.ModelError, 2),
    # A last point whose driver stops: a section needs a turning driver.
    ("bifurcation-point-settings", ["bifurcation", MODEL, *sweep([
        "--param", "drivers.motor.speed_rpm", "--from", "250", "--to", "0"])],
     bif(param="drivers.motor.speed_rpm", from_=250.0, to=0.0), linkdyn.SettingsError, 2),
    ("bifurcation-phase", ["bifurcation", MODEL, *sweep(["--phase", "7"])],
     bif(phase=7.0), linkdyn.SettingsError, 2),
    ("bifurcation-steps", ["bifurcation", MODEL, *sweep(["--steps", "1000000000"])],
     bif(steps=1000000000), linkdyn.AnalysisError, 2),
]


@pytest.mark.parametrize("args, call, cls, code", [c[1:] for c in CASES],
                         ids=[c[0] for c in CASES])
def test_analysis_errors_are_the_cli_s(cli, tmp_path, args, call, cls, code):
    got, _, err = cli(*args, "--out", str(tmp_path / "a.csv"))
    lines = [l for l in err.splitlines() if l.startswith("error: ")]
    assert got == code and len(lines) == 1, err
    with pytest.raises(linkdyn.LinkdynError) as info:
        call()
    e = info.value
    assert type(e) is cls, f"{type(e).__name__}: {e}"
    assert isinstance(e, RuntimeError if code == 3 else ValueError)
    assert cli_spelling(e) == lines[0][len("error: "):]


def test_solver_error_of_an_analysis_has_the_time():
    with pytest.raises(linkdyn.SolverError) as info:
        linkdyn.load(MODEL).poincare(max_steps=10)
    e = info.value
    printed = float(re.search(r"t = ([0-9.]+) s", str(e)).group(1))
    # The message rounds t to 9 decimals.
    assert abs(e.time - printed) <= 5e-10, (e.time, printed)


def test_a_grid_end_the_model_refuses_is_bad_input():
    with pytest.raises(linkdyn.ModelError) as info:
        bif(to=0.02)()
    e = info.value
    assert str(e).startswith("param joints.B.clearance: models/farahan2016.toml:64:13:")
    # The model error keeps its place in the file.
    assert (e.file, e.line, e.column, e.field) == (MODEL, 64, 13, "joints.B.clearance")


# The crank speed over −3500, 0, 3500 rpm: the middle point's driver does not turn, so its
# end time of 6 turns does not exist and it fails; the ends run.
SPEED_SWEEP = ["--formulation", "reduced", "--param", "drivers.motor.speed_rpm", "--from",
               "-3500", "--to", "3500", "--steps", "2", "--revs", "6", "--transient", "3",
               "--observe", "coupler.phi", "--threads", "2"]
STOPPED = 'revs: driver "motor" has zero speed: give `t_end` instead'


def test_a_failed_sweep_point_is_nan_with_its_message_as_on_the_command_line(cli, tmp_path):
    out = tmp_path / "b.csv"
    code, _, err = cli("bifurcation", MODEL, *SPEED_SWEEP, "--out", str(out))
    assert code == 5, err
    with pytest.warns(RuntimeWarning) as caught:
        b = linkdyn.load(MODEL).bifurcation(
            "drivers.motor.speed_rpm", "coupler.phi", from_=-3500.0, to=3500.0, steps=2,
            revs=6, transient=3, formulation="reduced", threads=2, progress=False)
    assert [str(w.message) for w in caught] == [
        "2 of 3 points; point 1 (drivers.motor.speed_rpm = 0) failed: " + STOPPED
        + " (their rows are NaN, their verdict \"failed\", the messages in `message`)"]
    assert b.verdict == ["period", "failed", "period"]
    assert b.message == ["", STOPPED, ""]
    assert b.failures == {1: STOPPED}
    values = b.value.reshape(3, -1)
    assert np.isnan(values[1]).all() and np.isfinite(values[[0, 2]]).all(), values
    # The command line's files hold the same: NaN rows, the verdict and the message (spelled
    # with the flag), and the same numbers for the points that ran.
    rows = [l.split(",") for l in out.read_text().splitlines()[1:] if not l.startswith("#")]
    assert np.array_equal(np.array([float(r[3]) for r in rows]), b.value, equal_nan=True)
    verdicts = [l for l in out.with_suffix(".verdicts.csv").read_text().splitlines()[1:]
                if not l.startswith("#")]
    assert verdicts[1] == '1,0,failed,0,"--revs: driver ""motor"" has zero speed: give --t-end instead"'


@pytest.mark.parametrize(
    "kwargs, cls, message",
    [
        (dict(values=[1e-4], from_=1e-4), linkdyn.SettingsError,
         "values: give `values` or `from_`, `to` and `steps`, not both"),
        (dict(values=[]), linkdyn.SettingsError, "values: expected at least one value"),
        (dict(values=[2e-4, float("nan")]), linkdyn.SettingsError,
         "values: expected finite values, got NaN at position 1"),
        (dict(from_=1e-4, to=2e-4), linkdyn.SettingsError,
         "steps: give the grid as `from_`, `to` and `steps` (or the points as `values`)"),
        (dict(from_=1e-4, to=2e-4, steps=-1), linkdyn.SettingsError,
         "steps: expected a whole number ≥ 0, got -1"),
        (dict(from_=1e-4, to=2e-4, steps=1, shard="3/2"), linkdyn.AnalysisError,
         "invalid --shard: expected i/n with 1 ≤ i ≤ n (i is 1-based), got 3/2"),
        (dict(from_=1e-4, to=2e-4, steps=1, transient=-1), linkdyn.SettingsError,
         "transient: expected a whole number of turns ≥ 0, got -1"),
    ],
    ids=["values-and-grid", "no-values", "nan-value", "no-steps", "negative-steps", "shard",
         "negative-transient"],
)
def test_sweep_options_only_python_has(kwargs, cls, message):
    model = linkdyn.load(MODEL)
    kw = dict(revs=3, transient=1, progress=False)
    kw.update(kwargs)
    with pytest.raises(cls) as info:
        model.bifurcation("joints.B.clearance", "coupler.phi", **kw)
    assert str(info.value) == message


def test_bad_observe_and_progress_types():
    model = linkdyn.load(MODEL)
    with pytest.raises(TypeError, match="observe=: expected a column name"):
        model.poincare(observe=3)
    with pytest.raises(TypeError, match=r"progress=: expected True, False, None or a callable"):
        model.bifurcation("joints.B.clearance", "coupler.phi", values=[2e-4], revs=3,
                          transient=1, progress="yes")


def test_a_changed_model_file_is_refused(tmp_path, root):
    path = tmp_path / "m.toml"
    path.write_text((root / MODEL).read_text())
    model = linkdyn.load(str(path))
    path.write_text((root / MODEL).read_text().replace("crank at 250 rpm", "edited"))
    with pytest.raises(linkdyn.SettingsError, match="changed since it was loaded"):
        model.bifurcation("joints.B.clearance", "coupler.phi", values=[2e-4], revs=3,
                          transient=1, progress=False)
