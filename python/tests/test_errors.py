"""Errors raise the right exception class with the command line's message.

Each case runs ``linkdyn run`` with some bad input and the same input through Python, and
compares ``error: <message>`` on the CLI's stderr with ``str(exception)``. The messages are
the same text, except that the CLI spells settings as flags: Python's ``dt: …`` is the
CLI's ``--dt: …`` and a setting named in backticks (`` `t_end` ``) is ``--t-end``; an
output target is ``--out PATH: …`` on the command line and ``PATH: …`` in Python.
"""

import re

import pytest

import linkdyn

MODEL = "models/farahan2016.toml"


def cli_spelling(e: linkdyn.SettingsError) -> str:
    """The CLI's message for a settings error (src/cli/mod.rs, `message`)."""
    flag = lambda name: "--" + name.replace("_", "-")
    reason = str(e)[len(e.option) + 2:]
    parts = reason.split("`")
    text = "".join(flag(p) if k % 2 else p for k, p in enumerate(parts))
    return f"{flag(e.option)}: {text}"


def cli_error(cli, tmp_path, *args):
    code, _, err = cli("run", *args, "--out", str(tmp_path / "r.csv")) if "--out" not in args \
        else cli("run", *args)
    lines = [l for l in err.splitlines() if l.startswith("error: ")]
    assert len(lines) == 1, err
    return code, lines[0][len("error: "):]


@pytest.mark.parametrize(
    "args, kwargs",
    [
        (["--dt", "-1"], dict(dt=-1.0)),
        (["--rtol", "0"], dict(rtol=0.0)),
        (["--method", "rk4"], dict(method="rk4")),
        (["--energy", "--formulation", "reduced"], dict(energy=True, formulation="reduced")),
        (["--revs", "-2"], dict(revs=-2.0)),
    ],
)
def test_settings_errors(cli, tmp_path, args, kwargs):
    code, expected = cli_error(cli, tmp_path, MODEL, *args)
    assert code == 2
    model = linkdyn.load(MODEL)
    with pytest.raises(linkdyn.SettingsError) as info:
        model.run(**kwargs)
    e = info.value
    assert isinstance(e, linkdyn.LinkdynError) and isinstance(e, ValueError)
    assert cli_spelling(e) == expected
    assert not any(tmp_path.iterdir()), "no file written"


def test_model_error_with_its_place(cli, tmp_path):
    code, expected = cli_error(cli, tmp_path, MODEL, "--set", "drivers.motor.speed_rpm=x")
    assert code == 2
    with pytest.raises(linkdyn.ModelError) as info:
        linkdyn.load(MODEL, set={"drivers.motor.speed_rpm": "x"})
    e = info.value
    assert str(e) == expected
    assert isinstance(e, ValueError) and isinstance(e, linkdyn.LinkdynError)
    assert (e.file, e.line, e.column, e.field) == (MODEL, 93, 13, "drivers.motor.speed_rpm")


@pytest.mark.parametrize(
    "args, load, kwargs",
    [
        # An unknown field after an override: no line in the file, a did-you-mean list.
        (["models/farahan2016.toml", "--set", "bodies.crank.mas=1"],
         ("models/farahan2016.toml", {"bodies.crank.mas": 1}), None),
        (["models/no_such_model.toml"], ("models/no_such_model.toml", None), None),
        # The reduced formulation does not fit this model (prefixed with the file).
        (["models/fourbar_ideal.toml", "--formulation", "reduced"],
         ("models/fourbar_ideal.toml", None), dict(formulation="reduced")),
    ],
    ids=["unknown-field", "missing-file", "formulation-mismatch"],
)
def test_model_errors(cli, tmp_path, args, load, kwargs):
    code, expected = cli_error(cli, tmp_path, *args)
    assert code == 2
    with pytest.raises(linkdyn.ModelError) as info:
        model = linkdyn.load(load[0], set=load[1])
        model.run(**kwargs)
    assert str(info.value) == expected
    assert info.value.file == load[0]
    assert info.value.line is None


def test_solver_error_has_the_time(cli, tmp_path):
    code, expected = cli_error(cli, tmp_path, MODEL, "--max-steps", "10")
    assert code == 3
    with pytest.raises(linkdyn.SolverError) as info:
        linkdyn.load(MODEL).run(max_steps=10)
    e = info.value
    assert str(e) == expected
    assert isinstance(e, RuntimeError) and isinstance(e, linkdyn.LinkdynError)
    printed = float(re.search(r"t = ([0-9.]+) s", expected).group(1))
    # The message rounds t to 9 decimals.
    assert abs(e.time - printed) <= 5e-10, (e.time, printed)
    assert not any(tmp_path.iterdir()), "no file written"


@pytest.mark.parametrize("target", ["dir/", "r.json"])
def test_output_errors(cli, tmp_path, target):
    (tmp_path / "dir").mkdir()
    path = str(tmp_path / target)
    code, expected = cli_error(cli, tmp_path, MODEL, "--revs", "0.05", "--out", path)
    assert code == 2
    result = linkdyn.load(MODEL).run(revs=0.05)
    with pytest.raises(linkdyn.OutputError) as info:
        result.save(path)
    assert "--out " + str(info.value) == expected
    assert isinstance(info.value, OSError) and isinstance(info.value, linkdyn.LinkdynError)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["dir"], "nothing written"


def test_bad_override_values_are_refused_in_python():
    with pytest.raises(TypeError, match="set=: cannot write dict"):
        linkdyn.load(MODEL, set={"bodies.crank.mass": {"a": 1}})


def test_unknown_column_is_a_key_error():
    result = linkdyn.load(MODEL).run(t_end=1e-3)
    with pytest.raises(KeyError, match="coupler.phi"):
        result["coupler.ph"]


def test_notes_are_the_cli_s_note_lines(cli):
    # Switching the friction law by override drops the old law's fields, with a note.
    code, _, err = cli("check", MODEL, "--set", "joints.B.friction.law=none")
    assert code == 0, err
    expected = [l[len("note: "):] for l in err.splitlines() if l.startswith("note: ")]
    model = linkdyn.load(MODEL, set={"joints.B.friction.law": "none"})
    assert expected and model.notes == expected
    assert linkdyn.load(MODEL).notes == []


def test_unit_slips_are_the_cli_s_warning_lines_and_python_warnings(cli):
    # Degrees typed into a radian field: valid, but warned about, the same sentence both ways.
    code, _, err = cli("check", MODEL, "--set", "drivers.motor.initial_angle=90")
    assert code == 0, err
    expected = [l[len("warning: "):] for l in err.splitlines() if l.startswith("warning: ")]
    assert expected == [
        "drivers.motor.initial_angle = 90 rad is more than a turn (2π = 6.2832 rad); "
        "angles are in radians (90 degrees would be 1.5708 rad)"
    ]
    with pytest.warns(UserWarning) as caught:
        model = linkdyn.load(MODEL, set={"drivers.motor.initial_angle": 90})
    assert model.warnings == expected
    assert [str(w.message) for w in caught] == expected
    assert linkdyn.load(MODEL).warnings == []
