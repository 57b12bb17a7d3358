"""Models written in Python (``loads``, ``from_dict``, ``ModelBuilder``, ``Model.set``) are the
models of the files they stand for, and ``Model.to_toml()`` is a file the command line reads
to the same numbers.

"Same" is bit for bit throughout: a model from text, from a dict or from a builder goes
through the same parser and checks as a file, every float crosses as an f64 (TOML text holds
its shortest round-trip form), so any difference in a result is a lost or altered value.
"""

import pathlib
import tomllib

import numpy as np
import pytest

import linkdyn

MODEL = "models/farahan2016.toml"
PENDULUM = "models/pendulum.toml"


def same_bits(a, b) -> bool:
    """Equal as float64 bit patterns (tells 0.0 from -0.0; NaN equals itself)."""
    a = np.ascontiguousarray(a, dtype=np.float64)
    b = np.ascontiguousarray(b, dtype=np.float64)
    return a.shape == b.shape and np.array_equal(a.view(np.uint64), b.view(np.uint64))


def assert_same_run(a, b, case):
    assert a.names == b.names, f"{case}: columns {a.names} vs {b.names}"
    assert same_bits(a.t, b.t), f"{case}: times differ"
    for name in a.names:
        assert same_bits(a[name], b[name]), f"{case}: column {name} differs"


def data_lines(path: pathlib.Path):
    """A result CSV without its '#' provenance lines (the model's path, hash and overrides
    differ between the runs compared; every number may not)."""
    return [l for l in path.read_text().splitlines() if not l.startswith("#")]


def test_loads_is_load_of_the_same_text():
    text = pathlib.Path(MODEL).read_text()
    from_text = linkdyn.loads(text)
    from_file = linkdyn.load(MODEL)
    assert from_text.path == "<string>"
    # The provenance hash is the text's, so a result says which model it came from either way.
    assert from_text.sha256 == from_file.sha256
    assert_same_run(from_text.run(revs=0.25), from_file.run(revs=0.25), "loads vs load")


def test_loads_reports_errors_as_the_file_does_naming_the_string(tmp_path):
    # A misspelled field, a missing field and a bad value: each message is the file's with
    # "<string>" (or the given name) in place of the path, line and column included.
    text = pathlib.Path(PENDULUM).read_text()
    cases = {
        "misspelled": text.replace("inertia = ", "inertai = "),
        "missing": text.replace("mass = 1.0\n", ""),
        "negative": text.replace("mass = 1.0", "mass = -1.0"),
    }
    for case, bad in cases.items():
        path = tmp_path / f"{case}.toml"
        path.write_text(bad)
        with pytest.raises(linkdyn.ModelError) as from_file:
            linkdyn.load(str(path))
        with pytest.raises(linkdyn.ModelError) as from_text:
            linkdyn.loads(bad, name="my model")
        expected = str(from_file.value).replace(str(path), "my model")
        assert str(from_text.value) == expected, case
        assert from_text.value.file == "my model", case
        assert from_text.value.line == from_file.value.line, case
    with pytest.raises(linkdyn.ModelError, match=r'did you mean "inertia"'):
        linkdyn.loads(cases["misspelled"])


def test_set_is_an_edited_copy_equal_to_load_with_set():
    base = linkdyn.load(MODEL)
    edited = base.set("joints.B.clearance", 4e-4)
    # The original keeps its clearance: set returns a copy.
    assert base.joints[2]["clearance"] == 5e-4 and edited.joints[2]["clearance"] == 4e-4
    assert edited.overrides == ["joints.B.clearance=0.0004"]
    also = edited.set({"drivers.motor.speed_rpm": 3500})
    assert also.overrides == ["joints.B.clearance=0.0004", "drivers.motor.speed_rpm=3500"]
    direct = linkdyn.load(MODEL, set={"joints.B.clearance": 4e-4, "drivers.motor.speed_rpm": 3500})
    assert_same_run(also.run(revs=0.25), direct.run(revs=0.25), "set vs load(set=)")
    # An edit that the model refuses is the file's error, naming the field.
    with pytest.raises(linkdyn.ModelError, match="clearance"):
        base.set("joints.B.clearance", -1.0)
    # A model from text is edited from its text, not from a file.
    text_model = linkdyn.loads(pathlib.Path(MODEL).read_text()).set("joints.B.clearance", 4e-4)
    assert_same_run(text_model.run(revs=0.25), edited.run(revs=0.25), "loads().set")


def test_to_toml_is_a_file_the_command_line_runs_to_the_same_numbers(cli, tmp_path):
    base = linkdyn.load(MODEL)
    # Unedited: the file as written, comments and all.
    assert base.to_toml() == pathlib.Path(MODEL).read_text()
    edited = base.set({"joints.B.clearance": 3e-4, "drivers.motor.speed_rpm": 1000})
    written = tmp_path / "edited.toml"
    written.write_text(edited.to_toml())
    # The command line on the written file, and on the original file with the same --set.
    out_written, out_set = tmp_path / "written.csv", tmp_path / "set.csv"
    code, _, err = cli("run", str(written), "--revs", "0.5", "--out", str(out_written))
    assert code == 0, err
    code, _, err = cli("run", MODEL, "--revs", "0.5", "--out", str(out_set),
                       "--set", "joints.B.clearance=3e-4", "--set", "drivers.motor.speed_rpm=1000")
    assert code == 0, err
    assert data_lines(out_written) == data_lines(out_set)
    # And Python's own run of the edited model saves the same rows.
    mine = tmp_path / "python.csv"
    edited.run(revs=0.5).save(mine)
    assert data_lines(mine) == data_lines(out_written)
    # Read back, the written text is the edited model (no override left to apply).
    again = linkdyn.loads(edited.to_toml())
    assert again.overrides == [] and again.joints[2]["clearance"] == 3e-4


def test_to_dict_and_from_dict_round_trip():
    model = linkdyn.load(MODEL)
    doc = model.to_dict()
    assert doc == tomllib.loads(pathlib.Path(MODEL).read_text())
    doc["joints"][2]["clearance"] = 2e-4
    doc["joints"][2]["friction"]["coefficient"] = np.float64(0.05)  # NumPy scalars are fine
    rebuilt = linkdyn.from_dict(doc)
    assert rebuilt.path == "<dict>"
    direct = linkdyn.load(MODEL, set={"joints.B.clearance": 2e-4,
                                      "joints.B.friction.coefficient": 0.05})
    assert_same_run(rebuilt.run(revs=0.25), direct.run(revs=0.25), "from_dict(edited)")
    # A value TOML cannot hold is named by its path.
    doc["joints"][2]["clearance"] = object()
    with pytest.raises(TypeError, match=r"joints\[2\]\.clearance: cannot write a object"):
        linkdyn.from_dict(doc)


def build_pendulum() -> linkdyn.ModelBuilder:
    """models/pendulum.toml, written with the builder."""
    b = linkdyn.ModelBuilder(
        "pendulum", "Compound pendulum: uniform 1 m rod, pinned at one end, released at 60 degrees"
    )
    b.settings(gravity=[0.0, -9.81]).ground_point("O", [0.0, 0.0])
    b.body("rod", mass=1.0, inertia=0.08333333333333333,
           points={"O": [-0.5, 0.0], "tip": [0.5, 0.0]},
           initial={"x": 0.4330127018922193, "y": -0.25, "phi": -0.5235987755982988})
    b.joint("O", "revolute", body_a="ground", point_a="O", body_b="rod", point_b="O")
    return b


def test_builder_builds_the_shipped_pendulum(cli, tmp_path):
    b = build_pendulum()
    assert b.to_dict() == tomllib.loads(pathlib.Path(PENDULUM).read_text())
    built = b.build()
    assert_same_run(built.run(t_end=1.0), linkdyn.load(PENDULUM).run(t_end=1.0), "builder")
    # Physics, as a check that the builder's numbers reach the model: a uniform rod pinned at
    # one end has the small-amplitude period T0 = 2π√(2L/3g); released at θ0 = 60° from the
    # vertical its period is T0·2K(k)/π with k = sin(θ0/2) = 1/2 and the complete elliptic
    # integral K(1/2) = 1.685750354812596 (Abramowitz & Stegun, table 17.1). Released from
    # rest at its highest angle, it is at its lowest after half a period, where ω turns from
    # negative to positive.
    r = built.run(t_end=1.5, dt=1e-4)
    omega, t = r["rod.omega"], r.t
    k = int(np.nonzero((omega[:-1] < 0) & (omega[1:] >= 0))[0][0])
    half = t[k] - omega[k] * (t[k + 1] - t[k]) / (omega[k + 1] - omega[k])
    expected = 2 * np.pi * np.sqrt(2 * 1.0 / (3 * 9.81)) * 2 * 1.685750354812596 / np.pi
    # 1e-5 relative: the integration's default tolerances and the linear interpolation of ω
    # between samples 1e-4 s apart are both far below it.
    assert abs(2 * half - expected) < 1e-5 * expected, (2 * half, expected)
    # The builder's text is a file the command line reads.
    path = tmp_path / "built.toml"
    path.write_text(b.to_toml())
    code, out, err = cli("check", str(path))
    assert code == 0, err


def test_builder_errors_are_the_file_s():
    b = build_pendulum()
    b.joint("P", "revolute", body_a="ground", point_a="Q", body_b="rod", point_b="O")
    with pytest.raises(linkdyn.ModelError, match="Q") as e:
        b.build(name="my builder")
    assert e.value.file == "my builder"


def test_a_sweep_of_a_model_from_text_reads_the_text():
    # Each point of a bifurcation reloads the model with the swept value; a model from text
    # has no file to reload, so the points must load its text: the same diagram as the file's.
    kwargs = dict(from_=3e-4, to=5e-4, steps=2, revs=6, transient=3, formulation="reduced",
                  threads=2, progress=False)
    from_file = linkdyn.load(MODEL).bifurcation("joints.B.clearance", "B.ex", **kwargs)
    from_text = linkdyn.loads(pathlib.Path(MODEL).read_text()).bifurcation(
        "joints.B.clearance", "B.ex", **kwargs)
    assert same_bits(from_file.parameter, from_text.parameter)
    assert same_bits(from_file.value, from_text.value)
