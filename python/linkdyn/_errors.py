"""Exceptions raised by linkdyn, with the messages the ``linkdyn`` command prints.

Every exception is a :class:`LinkdynError`; each also derives from the built-in exception a
caller would expect, so ``except ValueError`` catches bad input without knowing linkdyn.

=====================  ==========================================  ==========  =============
exception              raised for                                  also a      CLI exit code
=====================  ==========================================  ==========  =============
:class:`ModelError`    a model file that cannot be read, parsed,   ValueError  2
                       validated or assembled; a bad ``set=``
:class:`SettingsError` a run setting out of range or not fitting   ValueError  2
                       the model (``dt``, ``t_end``, ``rtol`` ...)
:class:`SolverError`   a failed integration (in an analysis too);  RuntimeError  3
                       no periodic orbit found (``orbit``)
:class:`AnalysisError` an analysis that cannot be done on the      ValueError  2
                       given data (too few samples, a bad
                       parameter grid or shard)
:class:`OutputError`   a result file or sink that cannot be        OSError     4
                       written
=====================  ==========================================  ==========  =============

A failed point of a sweep (``Model.bifurcation``) raises the class of its error with the
message prefixed ``point I (PARAM = VALUE): `` and the attributes ``point`` (0-based index)
and ``parameter`` (the value).
"""

from typing import List, Optional


class LinkdynError(Exception):
    """Base class of every linkdyn error. ``str(e)`` is the message ``linkdyn`` prints after
    ``error: `` for the same input."""


class ModelError(LinkdynError, ValueError):
    """A model file that cannot be read, parsed, validated or assembled, or an override
    (``set=``) that cannot be applied.

    Attributes (None where the error has no single place): ``file`` (path), ``line`` and
    ``column`` (1-based), ``field`` (dotted path, array entries by name, as ``set=`` takes it).
    """

    file: Optional[str] = None
    line: Optional[int] = None
    column: Optional[int] = None
    field: Optional[str] = None


class SettingsError(LinkdynError, ValueError):
    """A run setting that is out of range or does not fit the model; raised before any work.

    Attribute ``option``: the setting by its keyword name (``dt``, ``t_end``, ``revs``,
    ``rtol``, ``atol``, ``method``, ``formulation``, ``energy``, ``max_steps``).
    """

    option: Optional[str] = None


class SolverError(LinkdynError, RuntimeError):
    """A failed integration, or no periodic orbit found (``Model.orbit``,
    ``Model.continuation``). Attribute ``time``: the time reached (s), where known; for a
    periodic orbit not found, ``residual_history``: the Newton residual of each iterate (units
    of the integration tolerance), as in the message."""

    time: Optional[float] = None
    residual_history: Optional[List[float]] = None


class AnalysisError(LinkdynError, ValueError):
    """An analysis that cannot be done with the data or options given: a window with too few
    samples, a non-finite value, a parameter grid whose ends are not finite or that has 0
    steps between different ends, a bad shard."""


class OutputError(LinkdynError, OSError):
    """A result file (or a sample sink) that cannot be written. Attribute ``time``: the time
    of the sample being written (s), where known."""

    time: Optional[float] = None


__all__ = [
    "LinkdynError",
    "ModelError",
    "SettingsError",
    "SolverError",
    "AnalysisError",
    "OutputError",
]
