"""linkdyn: dynamics of planar linkages whose revolute joints may have clearance.

Python bindings of the ``linkdyn`` Rust library: the same model files, the same numbers (bit
for bit) as the ``linkdyn`` command, results as NumPy arrays.

>>> import linkdyn
>>> model = linkdyn.load("models/farahan2016.toml", set={"drivers.motor.speed_rpm": 3500})
>>> result = model.run(revs=2)                    # the GIL is released while Rust integrates
>>> result.t.shape == result["B.ex"].shape        # float64 arrays, one per column
True

The analyses take the options of the matching ``linkdyn`` command and give its numbers as
NumPy arrays (records in :mod:`linkdyn._analyses`):

>>> s = model.poincare(revs=40, transient=10, observe=["B.ex", "B.ey"])
>>> s["B.ex"].shape                               # one point per turn; s.verdict: 'period-1' …
(30,)
>>> b = model.bifurcation("joints.B.clearance", "coupler.phi", from_=2e-4, to=5e-4, steps=30,
...                       revs=150, transient=100, formulation="reduced")   # rayon threads
>>> rows = (b.parameter, b.turn, b.value)         # one row per recorded turn and point

Models can be written in Python too: :func:`loads` reads TOML text, :func:`from_dict` a dict
of the file's tables, :class:`ModelBuilder` adds bodies, joints and drivers one call at a
time; ``model.set("joints.B.clearance", 4e-4)`` is an edited copy, and ``model.to_toml()``
the file the command line reads to the same numbers.

``model.spectrum(observe)``, ``model.phase(observe)`` and ``model.lyapunov()`` likewise.

Errors are :class:`LinkdynError` subclasses (:class:`ModelError`, :class:`SettingsError`,
:class:`SolverError`, :class:`AnalysisError`, :class:`OutputError`) whose messages are the
command line's.
"""

from typing import Any, Iterable, Mapping, Optional, Union
import os
import warnings

from . import _linkdyn
from ._analyses import (
    Bifurcation,
    Continuation,
    LyapunovExponent,
    PeriodicOrbit,
    PhasePortrait,
    PoincareSection,
    Spectrum,
    Wear,
)
from ._errors import (
    AnalysisError,
    LinkdynError,
    ModelError,
    OutputError,
    SettingsError,
    SolverError,
)
from ._linkdyn import Model, Result
from ._builder import ModelBuilder

__version__ = _linkdyn.version()

Overrides = Union[Mapping[str, Any], Iterable[str], None]


def _toml_value(value: Any) -> str:
    """A Python value as TOML text for an override (``True`` → ``true``, lists → arrays);
    a string is passed as written (a bare word is taken as a string, as on the command line).
    """
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (int, float)):
        # repr gives the shortest round-trip digits; TOML reads 'inf' and 'nan' too.
        return repr(value)
    if isinstance(value, str):
        return value
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_toml_value(v) for v in value) + "]"
    if hasattr(value, "item"):  # a NumPy scalar
        return _toml_value(value.item())
    raise TypeError(
        f"set=: cannot write {type(value).__name__} {value!r} as a model value "
        "(expected a number, bool, string or list)"
    )


def _overrides(set: Overrides) -> "list[str]":
    if set is None:
        return []
    if isinstance(set, Mapping):
        return [f"{k}={_toml_value(v)}" for k, v in set.items()]
    if isinstance(set, str):
        return [set]
    return [str(s) for s in set]


def load(path: Union[str, "os.PathLike[str]"], set: Overrides = None) -> Model:
    """Reads and validates a model file (TOML).

    ``set`` overrides fields before validation, as ``linkdyn run --set KEY=VALUE`` does: a
    dict ``{"drivers.motor.speed_rpm": 3500}`` (dotted paths, array entries by name; values
    are numbers, bools, strings or lists) or a list of ``"KEY=VALUE"`` strings, applied in
    order. The overrides are recorded in every result's provenance.

    Raises :class:`ModelError` (with ``file``, ``line``, ``column``, ``field`` where known).
    Values that are valid but more likely a unit slip (``Model.warnings``: an angle of more
    than a turn, rpm written as rad/s) are issued as ``UserWarning``.
    """
    model = _linkdyn.load(os.fspath(path), _overrides(set))
    for text in model.warnings:
        warnings.warn(text, UserWarning, stacklevel=2)
    return model


def loads(text: str, set: Overrides = None, name: str = "<string>") -> Model:
    """Reads and validates a model from TOML text, as :func:`load` reads a file: the same
    checks and messages, with ``name`` in place of the file name (``<string>:12:3: …``) and in
    every result's provenance. ``set`` as for :func:`load`.

    >>> text = open("models/farahan2016.toml").read()
    >>> linkdyn.loads(text.replace("speed_rpm = 250.0", "speed_rpm = 3500.0")).drivers[0]["speed_rpm"]
    3500.0
    """
    model = _linkdyn.loads(text, _overrides(set), name)
    for message in model.warnings:
        warnings.warn(message, UserWarning, stacklevel=2)
    return model


def from_dict(document: Mapping[str, Any], name: str = "<dict>") -> Model:
    """Builds a model from a dict of the model file's tables, laid out as ``tomllib`` reads a
    model file (``{"model": {"name": …}, "bodies": [{…}, …], "joints": [...], …}``; see
    docs/model_format.md). ``None`` values are left out, as unwritten optional fields. The
    document is written as TOML and read by :func:`loads`, so it is checked as a file is; the
    line numbers in a :class:`ModelError` are those of ``model.to_toml()``. :class:`ModelBuilder`
    builds such a dict one element at a time; ``Model.to_dict()`` gives one to edit.
    """
    return loads(_linkdyn.dict_to_toml(document), name=name)


def version() -> str:
    """linkdyn version and git commit of the compiled core."""
    return _linkdyn.version()


__all__ = [
    "load",
    "loads",
    "from_dict",
    "ModelBuilder",
    "version",
    "Model",
    "Result",
    "PoincareSection",
    "Bifurcation",
    "Spectrum",
    "PhasePortrait",
    "LyapunovExponent",
    "PeriodicOrbit",
    "Continuation",
    "Wear",
    "LinkdynError",
    "ModelError",
    "SettingsError",
    "SolverError",
    "AnalysisError",
    "OutputError",
]
