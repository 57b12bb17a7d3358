"""``Model.wear`` gives ``linkdyn wear``'s numbers, bit for bit, and refuses bad input with the
command line's messages (docs/wear.md).

Both sides call ``linkdyn::studies::wear`` with the same settings and the files hold every
number in its shortest round-trip form, so any difference is a bug (a different default, a
lost override, a lossy conversion), never rounding. The case is the shipped
``models/wear_pin.toml``: a constant load fixed in the ground frame on a turning bushing, so
every bin of the bore wears to Archard's h = k_w F N / L after N turns.
"""

import json

import numpy as np
import pytest

import linkdyn
from cli_files import first_difference, read, same_bits
from test_analysis_errors import cli_spelling

MODEL = "models/wear_pin.toml"


def test_wear_is_the_cli_s_bit_for_bit(cli, tmp_path):
    code, stdout, err = cli("wear", MODEL, "--turns", "2", "--update-every", "1", "--out",
                            str(tmp_path))
    assert code == 0, err
    w = linkdyn.load(MODEL).wear(2)
    assert isinstance(w, linkdyn.Wear)
    provenance, names, columns = read(tmp_path / "wear.csv")
    assert names == ["update", "t", "turns", "bin", "theta_rad", "depth_m"]
    n, bins = w.depth_m.shape
    assert (n, bins) == (3, 360) == (len(w.t), len(w.theta_rad))
    # The long format, update by update.
    assert same_bits(columns["update"], np.repeat(np.arange(n), bins))
    assert same_bits(columns["bin"], np.tile(np.arange(bins), n))
    for name, got in [("t", np.repeat(w.t, bins)), ("turns", np.repeat(w.update_turns, bins)),
                      ("theta_rad", np.tile(w.theta_rad, n)), ("depth_m", w.depth_m.ravel())]:
        assert same_bits(columns[name], got), f"{name}: {first_difference(columns[name], got)}"
    # wear.json's keys, the solver's cost included; the provenance but for the version.
    js = json.loads((tmp_path / "wear.json").read_text())
    for key, value in js.items():
        if key == "provenance":
            mine = dict(w.provenance, linkdyn_version=None)
            assert dict(value, linkdyn_version=None) == mine
        else:
            assert getattr(w, key) == value, key
    assert same_bits(w.eccentricity_m, [u["eccentricity_m"] for u in js["updates"]])
    # Archard's closed form (tests/wear.rs checks it to 1e-5 over 4 turns): every bin has worn,
    # the mean to 1e-4 of k_w F N / L with F = 200 N, k_w = 1e-11 m²/N, L = 0.02 m.
    assert np.all(w.depth_m[0] == 0) and np.all(w.depth_m[-1] > 0)
    assert w.depth_m[-1].mean() == pytest.approx(1e-11 * 200 * 2 / 0.02, rel=1e-4)
    printed = stdout.split("deepest wear ")[1].split(" m")[0]
    assert float(printed) == w.summary["max_depth_m"]
    if _has_pandas():
        df = w.to_pandas()
        assert list(df.columns) == names
        assert same_bits(df["depth_m"].to_numpy(), columns["depth_m"])


def test_bad_requests_are_the_cli_s_refusals(cli, tmp_path):
    model = linkdyn.load(MODEL)
    cases = [
        (dict(turns=0), ["--turns", "0"]),
        (dict(turns=2, formulation="generalized"),
         ["--turns", "2", "--formulation", "generalized"]),
    ]
    for kw, flags in cases:
        with pytest.raises(linkdyn.SettingsError) as info:
            model.wear(**kw)
        code, _, err = cli("wear", MODEL, *flags, "--out", str(tmp_path / "bad"))
        assert code == 2, err
        assert err.strip() == "error: " + cli_spelling(info.value), kw
        assert not (tmp_path / "bad").exists()
    # A model without a worn joint: the study's message, naming how to add one.
    with pytest.raises(linkdyn.SettingsError, match=r"no clearance joint of the model has a "
                       r"\[joints.wear\] table"):
        linkdyn.load("models/farahan2016.toml").wear(1)
    with pytest.raises(linkdyn.SettingsError,
                       match="expected a whole number of driver turns ≥ 1, got -1"):
        model.wear(-1)


def _has_pandas() -> bool:
    try:
        import pandas  # noqa: F401
    except ImportError:
        return False
    return True
