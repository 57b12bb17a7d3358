"""Results of the analyses (``Model.poincare``, ``bifurcation``, ``spectrum``, ``phase``,
``lyapunov``): plain, frozen records of NumPy arrays, built by the compiled core.

Each holds the numbers the matching ``linkdyn`` command writes to its CSV file, bit for bit,
and the ``provenance`` dict of that file's ``#`` lines (version, model file and hash,
overrides, every setting). Times are in s, frequencies in Hz, the exponent in 1/s, a column's
values in its SI unit, a swept parameter in the unit of its field in the model file.
"""

from dataclasses import dataclass, field
from typing import Any, Dict, List, Optional

import numpy as np
import numpy.typing as npt

FloatArray = npt.NDArray[np.float64]
IntArray = npt.NDArray[np.int64]


def _frame(columns: Dict[str, Any], what: str) -> Any:
    try:
        import pandas
    except ImportError as e:
        raise ImportError(
            f"{what}.to_pandas() needs pandas, which cannot be imported ({e}); install it "
            "with `pip install pandas`, or use the NumPy arrays"
        ) from e
    return pandas.DataFrame(columns)


@dataclass(frozen=True, repr=False)
class PoincareSection:
    """A Poincaré section once per driver turn, with its period verdict
    (``linkdyn poincare``: the CSV ``turn,t,<names>`` and the printed verdict).

    ``section["B.ex"]`` is one column's points; ``section["turn"]`` and ``section["t"]``
    work too.
    """

    #: Recorded columns (without ``observe``: each clearance joint's ``ex``, ``ey`` and each
    #: body's ``phi``, ``omega``, angles modulo whole turns).
    names: List[str]
    #: Turn number k of each point (transient, …, revs − 1), int64.
    turn: IntArray
    #: Exact section instants t_k = t0 + phase/|ω| + k·T (s).
    t: FloatArray
    #: Points, shape (len(turn), len(names)), in the columns' units.
    points: FloatArray
    #: The verdict as ``linkdyn poincare`` prints it: ``"period-1"``,
    #: ``"no period found up to k_max = 8"``, ``"not settled: 3 points, 9 needed"``.
    verdict: str
    #: k of a period-k verdict, else None.
    period: Optional[int]
    #: The verdict's fields: ``{"verdict": "period", "k": 1, "mismatch": μ}``,
    #: ``{"verdict": "no_period", "k_max", "closest_k", "mismatch"}`` or
    #: ``{"verdict": "not_settled", "points", "needed"}`` (μ: largest difference in units of
    #: the tolerance; ≤ 1 for a period).
    verdict_details: Dict[str, Any]
    #: Period tolerance per column in its unit (1000 × the integration tolerance carried to
    #: the column), as printed by the command.
    tolerance: FloatArray
    #: For a period-k verdict, the first turn from which every point repeats the one k turns
    #: before within the tolerance; else None.
    settled_at_turn: Optional[int]
    #: Driver period T = 2π/|ω| (s).
    driver_period: float
    #: Solver statistics of the integration (steps, rejections, RHS calls, events …).
    stats: Dict[str, Any]
    #: The provenance of the command's CSV: ``linkdyn_version``, ``model`` (path, sha256,
    #: overrides) and ``settings`` (name → text, as in the ``#`` lines).
    provenance: Dict[str, Any] = field(compare=False)

    def __getitem__(self, name: str) -> FloatArray:
        if name == "turn":
            return self.turn
        if name == "t":
            return self.t
        try:
            return self.points[:, self.names.index(name)]
        except ValueError:
            raise KeyError(
                f"no column \"{name}\" in the section (columns: turn, t, {', '.join(self.names)})"
            ) from None

    def __len__(self) -> int:
        return len(self.turn)

    def to_pandas(self) -> Any:
        """``turn``, ``t`` and the columns as a ``pandas.DataFrame`` (the command's CSV)."""
        data: Dict[str, Any] = {"turn": self.turn, "t": self.t}
        for k, n in enumerate(self.names):
            data[n] = self.points[:, k]
        return _frame(data, "PoincareSection")

    def __repr__(self) -> str:
        return (
            f"<linkdyn.PoincareSection: {len(self.turn)} points of {', '.join(self.names)}; "
            f"{self.verdict}>"
        )


@dataclass(frozen=True, repr=False)
class Bifurcation:
    """A bifurcation diagram (``linkdyn bifurcation``): one section of the observed column per
    parameter value.

    Rows (the command's ``F.csv``, ``index,<param>,turn,<observe>``, in index order; with
    ``direction="both"`` the up branch, then the down branch): ``index``, ``parameter``,
    ``turn``, ``value``, ``direction``. Points (its ``F.verdicts.csv``,
    ``index,<param>,verdict,k,message`` and with ``settle``/``warm_start``
    ``transient_turns,start``): ``point_index``, ``point_parameter``, ``verdict``, ``k``,
    ``message``, ``point_direction``, ``transient_turns``, ``start``. Without ``settle``,
    ``value.reshape(len(point_index), -1)`` is one row per point. A point that failed (its model, simulation or integration) has
    NaN values, the verdict ``"failed"`` and its error in ``message``; ``failures`` maps its
    index to that message.
    """

    #: The swept field (a ``set=`` path, e.g. ``joints.B.clearance``).
    parameter_name: str
    #: The observed output column.
    observe: str
    #: Point index of each row (0-based grid index), int64.
    index: IntArray
    #: Parameter value of each row (the unit of the field in the model file).
    parameter: FloatArray
    #: Turn number of each row, int64.
    turn: IntArray
    #: Observed value of each row (the column's unit).
    value: FloatArray
    #: Branch of each row of a warm-started sweep (``"up"`` or ``"down"``; ``""`` for
    #: independent starts).
    direction: List[str]
    #: Index of each point that ran, ascending, int64.
    point_index: IntArray
    #: Parameter value of each point.
    point_parameter: FloatArray
    #: Verdict of each point: ``"period"``, ``"no_period"``, ``"not_settled"`` or
    #: ``"failed"``.
    verdict: List[str]
    #: Period k of each point (0 unless ``"period"``), int64.
    k: IntArray
    #: Error message of each point (``""`` unless ``"failed"``).
    message: List[str]
    #: Branch of each point (as ``direction``).
    point_direction: List[str]
    #: Transient turns each point discarded (``transient`` unless ``settle=True`` ended it
    #: sooner), int64.
    transient_turns: IntArray
    #: How each point started: ``"warm"`` (from the point before it) or ``"cold"`` (from the
    #: model's initial state).
    start: List[str]
    #: The provenance of the command's files (settings include the sweep's).
    provenance: Dict[str, Any] = field(compare=False)

    def __len__(self) -> int:
        return len(self.index)

    @property
    def failures(self) -> Dict[int, str]:
        """Point index → error message of every failed point (empty if none failed)."""
        return {
            int(i): m for i, v, m in zip(self.point_index, self.verdict, self.message)
            if v == "failed"
        }

    def to_pandas(self) -> Any:
        """The rows as a ``pandas.DataFrame``: ``index``, the parameter (named by its path),
        ``turn`` and the observed column (the command's ``F.csv``)."""
        return _frame(
            {
                "index": self.index,
                self.parameter_name: self.parameter,
                "turn": self.turn,
                self.observe: self.value,
            },
            "Bifurcation",
        )

    def __repr__(self) -> str:
        counts: Dict[str, int] = {}
        for v, k in zip(self.verdict, self.k):
            name = f"period-{k}" if v == "period" else v
            counts[name] = counts.get(name, 0) + 1
        summary = ", ".join(f"{v}: {n}" for v, n in sorted(counts.items())) or "none"
        return (
            f"<linkdyn.Bifurcation: {len(self.point_index)} points of {self.parameter_name}, "
            f"{len(self.index)} rows of {self.observe}; verdicts {summary}>"
        )


@dataclass(frozen=True, repr=False)
class Spectrum:
    """One-sided amplitude spectrum of an output column after the transient
    (``linkdyn spectrum``: the CSV ``frequency_hz,amplitude`` and the printed peaks)."""

    #: The analysed column.
    observe: str
    #: Bin frequencies f_k = k/(N·Δt) (Hz), k = 0 … N/2.
    frequency: FloatArray
    #: Amplitudes A_k (the column's unit).
    amplitude: FloatArray
    #: Driving frequency f_d = |ω|/2π of the single driver (Hz).
    driving_frequency: float
    #: Dominant peaks, largest first: dicts with ``frequency`` (Hz, refined), ``amplitude``,
    #: ``bin`` and ``multiple`` (frequency / f_d).
    peaks: List[Dict[str, Any]]
    #: Sample interval of the analysed grid (s).
    dt: float
    #: Number of samples N.
    n_samples: int
    #: Mean of the signal (removed before the FFT).
    mean: float
    #: Whether the samples had to be interpolated onto a uniform grid.
    resampled: bool
    #: Window applied: ``"hann"`` or ``"rectangular"``.
    window: str
    #: The provenance of the command's CSV.
    provenance: Dict[str, Any] = field(compare=False)

    @property
    def peak_multiples(self) -> FloatArray:
        """Each peak's frequency as a multiple of the driving frequency."""
        return np.array([p["multiple"] for p in self.peaks], dtype=np.float64)

    def to_pandas(self) -> Any:
        """``frequency_hz`` and ``amplitude`` as a ``pandas.DataFrame`` (the command's CSV)."""
        return _frame({"frequency_hz": self.frequency, "amplitude": self.amplitude}, "Spectrum")

    def __repr__(self) -> str:
        top = ", ".join(f"{p['multiple']:.3f}×" for p in self.peaks[:5])
        return (
            f"<linkdyn.Spectrum of {self.observe}: {len(self.frequency)} bins, "
            f"f_d = {self.driving_frequency:.6g} Hz, peaks at {top or 'none'}>"
        )


@dataclass(frozen=True, repr=False)
class PhasePortrait:
    """Phase-portrait data of an output column after the transient (``linkdyn phase``: the CSV
    ``t,value,rate``)."""

    #: The column.
    observe: str
    #: Sample times (s).
    t: FloatArray
    #: The column's values (its unit).
    value: FloatArray
    #: Its rate (its unit per second).
    rate: FloatArray
    #: Where the rate comes from: the rate column's name (``"coupler.omega"``) or
    #: ``"central differences"``.
    rate_source: str
    #: The provenance of the command's CSV.
    provenance: Dict[str, Any] = field(compare=False)

    def __len__(self) -> int:
        return len(self.t)

    def to_pandas(self) -> Any:
        """``t``, ``value``, ``rate`` as a ``pandas.DataFrame`` (the command's CSV)."""
        return _frame({"t": self.t, "value": self.value, "rate": self.rate}, "PhasePortrait")

    def __repr__(self) -> str:
        return (
            f"<linkdyn.PhasePortrait of {self.observe}: {len(self.t)} points, "
            f"rate from {self.rate_source}>"
        )


@dataclass(frozen=True, repr=False)
class LyapunovExponent:
    """Largest Lyapunov exponent with its convergence (``linkdyn lyapunov``: the CSV
    ``t,lambda`` and the printed ``lambda = … ± …``)."""

    #: λ, the estimate after the last renormalisation (1/s).
    exponent: float
    #: Batch-means standard error of the last half's local exponents (1/s).
    uncertainty: float
    #: |λ_K − λ_{K/2}|: how much the estimate moved over the second half (1/s).
    drift: float
    #: Times of the renormalisations t_k (s).
    t: FloatArray
    #: The running estimate λ_k after each renormalisation (1/s).
    estimate: FloatArray
    #: Solver statistics of all integrations (transient and the pair), summed.
    stats: Dict[str, Any]
    #: The provenance of the command's CSV.
    provenance: Dict[str, Any] = field(compare=False)

    def to_pandas(self) -> Any:
        """``t`` and ``lambda`` as a ``pandas.DataFrame`` (the command's CSV)."""
        return _frame({"t": self.t, "lambda": self.estimate}, "LyapunovExponent")

    def __repr__(self) -> str:
        return (
            f"<linkdyn.LyapunovExponent: lambda = {self.exponent:.4f} ± {self.uncertainty:.4f} "
            f"1/s over {len(self.t)} renormalisations>"
        )


__all__ = ["PoincareSection", "Bifurcation", "Spectrum", "PhasePortrait", "LyapunovExponent"]
