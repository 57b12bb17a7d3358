"""Model.parameters (after set= overrides), [[outputs]] columns in run results, and the solve
settings taken as keywords by every method (one parser, Python's own TypeError on a typo)."""

import math

import numpy as np
import pytest

import linkdyn

CHAIN = "models/parallel_fourbar_chain.toml"


def test_parameters_are_the_evaluated_values_after_overrides(root):
    model = linkdyn.load(root / CHAIN, set={"parameters.N": 2, "parameters.L": 0.4})
    p = model.parameters
    assert isinstance(p, dict)
    # Overridden values, and the derived ones evaluated from them (m_link = rho_lin·L).
    assert p["N"] == 2.0 and p["L"] == 0.4, p
    assert p["m_link"] == pytest.approx(2.0 * 0.4, rel=1e-15), p
    assert p["phi0"] == pytest.approx(-math.pi / 2 + 0.6, rel=1e-15), p
    # N = 2: links 0..2 and couplers 1..2, five bodies.
    assert len(model.bodies) == 5
    # Without overrides: the file's values.
    assert linkdyn.load(root / CHAIN).parameters["N"] == 4.0


def test_a_model_without_parameters_has_an_empty_dict(root):
    assert linkdyn.load(root / "models/fourbar_ideal.toml").parameters == {}


def test_output_points_appear_as_result_columns(root):
    model = linkdyn.load(root / CHAIN, set={"parameters.N": 1})
    assert model.outputs == ["tip"]
    run = model.run(t_end=0.05, dt=1e-3)
    cols = [f"tip.{c}" for c in ("x", "y", "vx", "vy", "ax", "ay")]
    assert all(c in run.names for c in cols), run.names
    # tip = T = [L/2, 0] on link0: r + (L/2)(cos φ, sin φ), its rate from the body's own
    # rates; the same formula on the same samples, so to round-off (1e-15 m on 0.3 m).
    half = model.parameters["L"] / 2
    x, y, phi = run["link0.x"], run["link0.y"], run["link0.phi"]
    vx, omega = run["link0.vx"], run["link0.omega"]
    assert np.max(np.abs(run["tip.x"] - (x + half * np.cos(phi)))) < 1e-14
    assert np.max(np.abs(run["tip.y"] - (y + half * np.sin(phi)))) < 1e-14
    assert np.max(np.abs(run["tip.vx"] - (vx - half * omega * np.sin(phi)))) < 1e-13


def test_solve_keywords_default_as_written_and_typos_raise_type_error(root):
    model = linkdyn.load(root / "models/fourbar_ideal.toml")
    a = model.run(t_end=0.01)
    b = model.run(t_end=0.01, dt=1e-4, formulation="dae", method="dop853", rtol=1e-8,
                  atol=1e-10, max_steps=10_000_000, max_wall=None)
    assert a.names == b.names and len(a) == len(b) == 101
    for name in a.names:
        assert np.array_equal(a[name], b[name]), name
    g = model.run(t_end=0.01, formulation="generalized", rtol=1e-10, atol=1e-12)
    # The generalized formulation against the DAE at rtol 1e-8: both within ~1e-8 rad.
    assert np.max(np.abs(g["coupler.phi"] - a["coupler.phi"])) < 1e-6
    with pytest.raises(TypeError, match=r"^run\(\) got an unexpected keyword argument 'dtt'$"):
        model.run(t_end=0.01, dtt=1e-3)
    with pytest.raises(TypeError, match=r"^dt=: expected a number \(s\), got str$"):
        model.run(t_end=0.01, dt="fast")
    with pytest.raises(TypeError, match=r"^spectrum\(\) got an unexpected keyword argument 'rtl'$"):
        model.spectrum("coupler.phi", rtl=1e-6)
    # Settings are still checked by the library, naming the option.
    with pytest.raises(linkdyn.SettingsError, match="rtol"):
        model.run(t_end=0.01, rtol=-1.0)
