"""`linkdyn schema` is a JSON Schema (draft 4, the newest Taplo reads) that every shipped model
satisfies and that refuses what the loader refuses for the same reason: an unknown
(misspelled) field, a wrong type, a missing required field, an unknown law name.

Each refusal is checked against the loader too (`linkdyn check` exits 2 naming the field), so
the schema does not mark as wrong what the loader accepts, nor accept what it refuses.
"""

import json
import pathlib
import tomllib

import pytest

jsonschema = pytest.importorskip("jsonschema", reason="the jsonschema package validates")

MODELS = sorted(pathlib.Path(__file__).resolve().parents[2].glob("models/*.toml"))


@pytest.fixture(scope="module")
def validator(cli):
    code, out, err = cli("schema")
    assert code == 0, err
    schema = json.loads(out)
    assert schema["$schema"] == "http://json-schema.org/draft-04/schema#"
    jsonschema.Draft4Validator.check_schema(schema)
    return jsonschema.Draft4Validator(schema)


def test_the_shipped_schema_is_the_command_s(cli, root):
    # linkdyn.schema.json at the repository root (for `#:schema ../linkdyn.schema.json` in
    # models/) is what `linkdyn schema` prints: regenerate it when the model format changes.
    code, out, err = cli("schema")
    assert code == 0, err
    assert (root / "linkdyn.schema.json").read_text() == out, (
        "linkdyn.schema.json is stale: run `linkdyn schema > linkdyn.schema.json`")


def test_shipped_models_are_valid(validator):
    assert len(MODELS) >= 10, MODELS
    for path in MODELS:
        doc = tomllib.loads(path.read_text())
        errors = [f"{'/'.join(map(str, e.absolute_path))}: {e.message}"
                  for e in validator.iter_errors(doc)]
        assert not errors, f"{path.name}: {errors}"


PENDULUM = "models/pendulum.toml"


@pytest.mark.parametrize(
    "case, old, new, where",
    [
        ("misspelled field", "inertia = ", "inertai = ", "bodies/0"),
        ("misspelled table", "[[joints]]", "[[joint]]", ""),
        ("wrong type", 'name = "rod"', "name = 3", "bodies/0/name"),
        ("missing required field", "mass = 1.0\n", "", "bodies/0"),
        ("unknown joint type", 'type = "revolute"', 'type = "hinge"', "joints/0/type"),
        ("three components", "gravity = [0.0, -9.81]", "gravity = [0.0, -9.81, 0.0]",
         "settings/gravity"),
    ],
)
def test_bad_fields_fail_validation_as_they_fail_loading(validator, cli, tmp_path, case, old,
                                                          new, where):
    text = (pathlib.Path(__file__).resolve().parents[2] / PENDULUM).read_text()
    assert old in text, case
    bad = text.replace(old, new, 1)
    errors = list(validator.iter_errors(tomllib.loads(bad)))
    assert errors, f"{case}: the schema accepts it"
    assert any("/".join(map(str, e.absolute_path)) == where for e in errors), (
        case, [("/".join(map(str, e.absolute_path)), e.message) for e in errors])
    path = tmp_path / "bad.toml"
    path.write_text(bad)
    code, _, err = cli("check", str(path))
    assert code == 2, f"{case}: the loader accepts what the schema refuses: {err}"


def test_the_directive_line_leaves_the_model_as_it_was(cli, root, tmp_path):
    # docs/model_format.md's one line, `#:schema …` at the top, is a comment to the loader:
    # the model checks as before and runs to the same numbers.
    text = (root / PENDULUM).read_text()
    path = tmp_path / "pendulum.toml"
    path.write_text("#:schema ../linkdyn.schema.json\n" + text)
    rows = []
    for model in (str(path), PENDULUM):
        out = tmp_path / f"run{len(rows)}.csv"
        code, _, err = cli("run", model, "--t-end", "0.1", "--out", str(out))
        assert code == 0, err
        rows.append([l for l in out.read_text().splitlines() if not l.startswith("#")])
    assert rows[0] == rows[1]
