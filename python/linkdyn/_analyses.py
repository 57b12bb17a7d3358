"""Results of the analyses (``Model.poincare``, ``bifurcation``, ``spectrum``, ``phase``,
``lyapunov``, ``orbit``, ``continuation``) and of ``Model.wear``: plain, frozen records of NumPy arrays, built by
the compiled core.

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
BoolArray = npt.NDArray[np.bool_]
ComplexArray = npt.NDArray[np.complex128]


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


@dataclass(frozen=True, repr=False)
class PeriodicOrbit:
    """A periodic orbit found by shooting, with its Floquet multipliers (``linkdyn orbit``:
    the keys of its ``F.json`` as attributes, and one period of the orbit, its ``F.csv``, as
    ``t`` and ``samples``).

    ``orbit["rocker.phi"]`` is one column over the period; ``orbit["t"]`` works too.
    """

    #: Always True: an orbit that is not found raises ``AnalysisError``.
    converged: bool
    #: max_i |P(x)_i − x_i|/ε_i of each Newton iterate (ε_i = atol + rtol·|x_i|, units of the
    #: integration tolerance), the last one the orbit's.
    residual_history: FloatArray
    #: Newton iterations done.
    newton_iterations: int
    #: The output columns at the section (name → value, SI units).
    state: Dict[str, float]
    #: Time of the section (s): the start of the period.
    t_section_s: float
    #: Period (s).
    period_s: float
    #: Period in driver turns (None without a single driver).
    period_turns: Optional[float]
    #: Nontrivial Floquet multipliers by decreasing modulus (the JSON's ``[re, im]`` pairs as
    #: complex numbers).
    floquet_multipliers: ComplexArray
    #: Multipliers removed as trivial (inactive bookkeeping states).
    trivial_multipliers: int
    #: Every nontrivial |μ| < 1.
    stable: bool
    #: Largest |μ|.
    spectral_radius: float
    #: Impacts (contact onsets) over one period, all clearance joints.
    impacts_per_period: int
    #: Smallest gap c − |e| over the period (m; negative: the deepest penetration); None
    #: without clearance joints.
    min_gap_m: Optional[float]
    #: |P^K(x) − x| of the orbit re-integrated over one period (units of the integration
    #: tolerance).
    closing_error: float
    #: Wall time of the guess, the shooting and the samples (s).
    wall_time_s: float
    #: Solver statistics of every integration, summed.
    solver_stats: Dict[str, Any]
    #: Output column names of the samples (the CSV's header after ``t``).
    names: List[str]
    #: Sample times over one period from the section (s), every ``dt``.
    t: FloatArray
    #: The orbit's samples, shape (len(t), len(names)).
    samples: FloatArray
    #: The provenance of the command's files.
    provenance: Dict[str, Any] = field(compare=False)

    def __getitem__(self, name: str) -> FloatArray:
        if name == "t":
            return self.t
        try:
            return self.samples[:, self.names.index(name)]
        except ValueError:
            raise KeyError(
                f"no column \"{name}\" in the orbit (columns: t, {', '.join(self.names)})"
            ) from None

    def __len__(self) -> int:
        return len(self.t)

    def to_pandas(self) -> Any:
        """``t`` and the columns over one period as a ``pandas.DataFrame`` (the command's
        ``F.csv``)."""
        data: Dict[str, Any] = {"t": self.t}
        for k, n in enumerate(self.names):
            data[n] = self.samples[:, k]
        return _frame(data, "PeriodicOrbit")

    def __repr__(self) -> str:
        mu = ", ".join(f"{abs(m):.4g}" for m in self.floquet_multipliers[:3])
        return (
            f"<linkdyn.PeriodicOrbit: period {self.period_s:.9g} s, "
            f"{'stable' if self.stable else 'unstable'} (|mu| {mu}), "
            f"{self.impacts_per_period} impacts per period>"
        )


@dataclass(frozen=True, repr=False)
class Continuation:
    """Branches of periodic orbits continued in one model field (``linkdyn continue``: its
    ``F.csv``, one row per point and driver turn of its period in the order of each branch,
    as arrays, and its ``F.json``'s keys).

    ``branch["rocker.phi"]`` is one state column along the rows; the CSV's other columns
    (``parameter`` or the field's path, ``period_s``, ``max_abs_mu``, ``stable``,
    ``impacts_per_period``, ``min_gap_m``, ``residual``, ``special``, ``branch``, ``turn``)
    work too. Without ``follow_doublings`` and with one turn per period, every row is a point
    of branch 0 at turn 0.
    """

    #: The continued field (a ``set=`` path, e.g. ``joints.B.clearance``).
    parameter_name: str
    #: Output column names at the section (the CSV's columns after the parameter).
    names: List[str]
    #: Parameter value of each point (the field's unit in the model file).
    parameter: FloatArray
    #: The output columns at the section, shape (len(parameter), len(names)).
    state: FloatArray
    #: Period of each point (s).
    period_s: FloatArray
    #: Largest |μ| of each point.
    max_abs_mu: FloatArray
    #: Every nontrivial |μ| < 1, per point.
    stable: BoolArray
    #: Impacts per period of each point, int64.
    impacts_per_period: IntArray
    #: Smallest gap of each point (m; NaN without clearance joints).
    min_gap_m: FloatArray
    #: Closing error of each point (units of the integration tolerance).
    residual: FloatArray
    #: Special point of each row: ``"fold"``, ``"PD"``, ``"NS"``, ``"grazing"`` or ``""``.
    special: List[str]
    #: Branch of each row, int64: 0 the one from ``from_``, then those switched to at period
    #: doublings (``branches``).
    branch: IntArray
    #: Driver turn of each row within its point's period, int64 (0: the section).
    turn: IntArray
    #: The nontrivial Floquet multipliers of each row (complex arrays).
    floquet_multipliers: List[ComplexArray]
    #: The located special points: the JSON's rows (``parameter``, ``state``, ``period_s``,
    #: ``max_abs_mu``, ``floquet_multipliers`` as ``[re, im]``, ``stable``, …, ``special``).
    special_points: List[Dict[str, Any]]
    #: Special points detected between two points but not located: ``[kind, parameter,
    #: why]``.
    unlocated: List[Any]
    #: Why the branch ended: ``{"reason": "reached"}``, ``"turned_back"``, ``"max_points"``
    #: or ``"failed"`` (with ``message``).
    end: Dict[str, Any]
    #: Period in driver turns (branch 0).
    period_turns: int
    #: Every branch: ``branch``, ``period_turns``, ``switched_from`` (``[branch, parameter]``
    #: of the period doubling, or None), ``points``, ``special_points``, ``unlocated``,
    #: ``end`` (also ``{"reason": "rejoined", "parameter": p}``).
    branches: List[Dict[str, Any]]
    #: Period doublings where no period-2K branch was found: ``[branch, parameter, why]``.
    switch_failures: List[Any]
    #: Wall time (s).
    wall_time_s: float
    #: Solver statistics of every integration, summed.
    solver_stats: Dict[str, Any]
    #: The provenance of the command's files (settings include the continuation's).
    provenance: Dict[str, Any] = field(compare=False)

    def __len__(self) -> int:
        return len(self.parameter)

    def __getitem__(self, name: str) -> Any:
        if name in ("parameter", self.parameter_name):
            return self.parameter
        if name in self.names:
            return self.state[:, self.names.index(name)]
        if name in ("period_s", "max_abs_mu", "stable", "impacts_per_period", "min_gap_m",
                    "residual", "special", "branch", "turn"):
            return getattr(self, name)
        raise KeyError(
            f"no column \"{name}\" in the branch (columns: {self.parameter_name}, "
            f"{', '.join(self.names)}, period_s, max_abs_mu, stable, impacts_per_period, "
            "min_gap_m, residual, special, branch, turn)"
        )

    def to_pandas(self) -> Any:
        """The command's ``F.csv`` as a ``pandas.DataFrame`` (``stable`` as 1/0 there,
        booleans here)."""
        data: Dict[str, Any] = {self.parameter_name: self.parameter}
        for k, n in enumerate(self.names):
            data[n] = self.state[:, k]
        for n in ("period_s", "max_abs_mu", "stable", "impacts_per_period", "min_gap_m",
                  "residual", "special", "branch", "turn"):
            data[n] = getattr(self, n)
        return _frame(data, "Continuation")

    def __repr__(self) -> str:
        kinds = ", ".join(
            f"{k} at {p:.6g}"
            for k, p, t in zip(self.special, self.parameter, self.turn) if k and t == 0
        )
        return (
            f"<linkdyn.Continuation in {self.parameter_name}: {len(self.parameter)} rows, "
            f"{len(self.branches)} branch(es); special points: {kinds or 'none'}; "
            f"end: {self.end.get('reason')}>"
        )


@dataclass(frozen=True, repr=False)
class Wear:
    """Archard wear of a clearance joint's bearing (``linkdyn wear``: its ``wear.csv`` as
    arrays, the depth by update and bin, and its ``wear.json``'s keys; docs/wear.md).

    ``w.depth_m[-1]`` is the final profile, bin ``i`` centred at ``w.theta_rad[i]`` in the
    bearing frame; row 0 is the unworn bearing.
    """

    #: The worn joint.
    joint: str
    #: Driver turns run in all.
    turns: int
    #: Profile update interval (driver turns).
    update_every: int
    #: Angular bins of the profile.
    bins: int
    #: Radial clearance of the unworn bearing (m).
    clearance_m: float
    #: The wear law's data: ``coefficient_m2_per_n``, ``length_m``, ``bearing_radius_m``,
    #: ``hertz_factor_m2_per_n``.
    archard: Dict[str, Any]
    #: The final profile: ``max_depth_m``, ``max_depth_angle_rad``, ``mean_depth_m``,
    #: ``worn_area_m2``, ``worn_volume_m3``.
    summary: Dict[str, Any]
    #: Per update: ``index``, ``t``, ``turns``, ``eccentricity_m``, ``max_depth_m``.
    updates: List[Dict[str, Any]]
    #: Solver statistics of all intervals together.
    stats: Dict[str, Any]
    #: Bin centres (rad, bearing frame).
    theta_rad: FloatArray
    #: Time of each update (s; 0: the start).
    t: FloatArray
    #: Driver turns at each update.
    update_turns: FloatArray
    #: The journal's distance from the bearing centre after each update (m).
    eccentricity_m: FloatArray
    #: Wear depth (m), shape (updates + 1, bins).
    depth_m: FloatArray
    #: The provenance of the command's files (settings include the study's).
    provenance: Dict[str, Any] = field(compare=False)

    def to_pandas(self) -> Any:
        """The command's ``wear.csv`` as a ``pandas.DataFrame`` (long format
        ``update,t,turns,bin,theta_rad,depth_m``)."""
        n, bins = self.depth_m.shape
        return _frame({
            "update": np.repeat(np.arange(n), bins),
            "t": np.repeat(self.t, bins),
            "turns": np.repeat(self.update_turns, bins),
            "bin": np.tile(np.arange(bins), n),
            "theta_rad": np.tile(self.theta_rad, n),
            "depth_m": self.depth_m.ravel(),
        }, "Wear")

    def __repr__(self) -> str:
        s = self.summary
        return (
            f"<linkdyn.Wear of joint {self.joint}: {self.turns} turns, {len(self.t) - 1} "
            f"updates; deepest {s['max_depth_m']:.3g} m at "
            f"{np.degrees(s['max_depth_angle_rad']):.3g} deg>"
        )


__all__ = ["PoincareSection", "Bifurcation", "Spectrum", "PhasePortrait", "LyapunovExponent",
           "PeriodicOrbit", "Continuation", "Wear"]
