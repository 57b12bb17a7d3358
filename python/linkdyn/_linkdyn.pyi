"""Type stubs of the compiled core ``linkdyn._linkdyn`` (re-exported by ``linkdyn``)."""

from typing import Any, Callable, Dict, List, Mapping, Optional, Sequence, Union

import numpy as np
import numpy.typing as npt

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

FloatArray = npt.NDArray[np.float64]

def load(path: str, overrides: List[str] = ...) -> "Model":
    """Reads and validates a model file, applying ``"KEY=VALUE"`` overrides in order (as
    ``--set``). Raises ``ModelError``. Use ``linkdyn.load``, which also takes a dict."""

def loads(text: str, overrides: List[str] = ..., name: str = ...) -> "Model":
    """Reads and validates a model from TOML text, as ``load`` reads a file; ``name``
    (default ``"<string>"``) stands for the file in messages and provenance. Use
    ``linkdyn.loads``, which also takes a dict of overrides and issues the warnings."""

def dict_to_toml(document: Mapping[str, Any]) -> str:
    """A dict of the model file's tables as TOML text (``None`` values left out). Raises
    ``TypeError`` naming the dotted path of a value TOML cannot hold."""

def version() -> str:
    """linkdyn version and git commit of the compiled core."""

class Model:
    """A model read from a TOML file (SI units inside), ready to run any number of times.
    Immutable; safe to share between threads (each run works on its own copy)."""

    @property
    def name(self) -> str:
        """Model name (``name`` in the file)."""
    @property
    def description(self) -> str:
        """Model description (may be empty)."""
    @property
    def path(self) -> str:
        """The model file as given to ``load``, or the ``name`` of a model from ``loads``
        (``"<string>"``), ``from_dict`` (``"<dict>"``) or ``ModelBuilder.build``."""
    @property
    def overrides(self) -> List[str]:
        """The overrides applied at load time (``"KEY=VALUE"``, in order)."""
    def set(self, key: Union[str, Mapping[str, Any], Sequence[str]], value: Any = ...) -> "Model":
        """A copy with more overrides after the load-time ones, as more ``--set KEY=VALUE``
        would: ``model.set("joints.B.clearance", 4e-4)``, or one dict (or list of
        ``"KEY=VALUE"`` strings) of several. The model itself is unchanged. Raises
        ``ModelError``; issues a new warning as a ``UserWarning``."""
    def to_toml(self) -> str:
        """The model as TOML text that ``linkdyn`` (the command) and ``linkdyn.loads`` read to
        the same model, overrides included: the command gives this model's numbers bit for
        bit. Without overrides the text as loaded, comments and all; with them, written anew
        without comments. A model from a file needs the file unchanged since it was loaded."""
    def to_dict(self) -> Dict[str, Any]:
        """The model file's tables as a dict (``tomllib.loads(model.to_toml())``), to edit and
        hand to ``linkdyn.from_dict``."""
    @property
    def notes(self) -> List[str]:
        """Things to know that are not errors (the CLI's ``note:`` lines), one sentence each."""
    @property
    def warnings(self) -> List[str]:
        """Values that are valid but more likely a unit slip than meant (an angle field of more
        than a turn, a driver speed no linkage of the model's size runs at), one sentence each:
        the CLI's ``warning:`` lines; :func:`linkdyn.load` also issues each as a
        ``UserWarning``."""
    @property
    def parameters(self) -> Dict[str, float]:
        """The ``[parameters]`` table as evaluated after the load-time overrides
        (``set={"parameters.N": 5}``): name → value; empty without parameters."""
    @property
    def outputs(self) -> List[str]:
        """Names of the output points (``[[outputs]]``), in order; each adds the result
        columns ``P.x P.y P.vx P.vy P.ax P.ay`` (m, m/s, m/s², global frame)."""
    @property
    def sha256(self) -> str:
        """SHA-256 of the model file (hex), as recorded in every result's provenance."""
    @property
    def bodies(self) -> List[Dict[str, Any]]:
        """One dict per body: ``name``, ``mass`` (kg), ``inertia`` (kg·m² about the centre of
        mass), ``points`` (name → local ``[x, y]`` in m)."""
    @property
    def joints(self) -> List[Dict[str, Any]]:
        """One dict per joint: ``name``, ``type`` (``revolute``, ``prismatic``,
        ``clearance``), ``a`` and ``b`` (``"frame.point"``); a clearance joint also has
        ``clearance`` and ``journal_radius`` (m)."""
    @property
    def drivers(self) -> List[Dict[str, Any]]:
        """One dict per driver: ``name``, ``joint``, ``speed`` (rad/s), ``speed_rpm``,
        ``initial_angle`` (rad)."""
    @property
    def forces(self) -> List[Dict[str, Any]]:
        """One dict per force element: ``name``, ``type`` (``spring-damper``, ``torque``,
        ``force``)."""
    @property
    def clearance_joints(self) -> List[str]:
        """Names of the clearance joints in model order (the order of their events)."""
    @property
    def degrees_of_freedom(self) -> int:
        """Degrees of freedom of the assembled linkage (coordinates − constraint rank)."""
    def check(self) -> Dict[str, Any]:
        """What ``linkdyn check`` prints: ``coordinates``, ``constraint_rows``, ``rank``,
        ``degrees_of_freedom``, ``redundant_constraints``, ``assembly_iterations``,
        ``assembly_residual`` (max |Φ|) and ``assembled`` (body → ``[x, y, φ]``). Raises
        ``ModelError`` if the linkage cannot be assembled."""
    def run(
        self,
        *,
        t_end: Optional[float] = None,
        revs: Optional[float] = None,
        dt: float = 1e-4,
        formulation: str = "dae",
        method: str = "dop853",
        rtol: float = 1e-8,
        atol: float = 1e-10,
        energy: bool = False,
        max_steps: int = 10_000_000,
        max_wall: Optional[float] = None,
    ) -> "Result":
        """Integrates the model and keeps every sample in memory; the arguments and defaults
        are those of ``linkdyn run`` (end time ``t_end`` in s, or ``revs`` turns of the single
        driver, default 2 turns; output interval ``dt`` in s; ``formulation`` ``"dae"`` or
        ``"reduced"``; ``method`` ``"dop853"`` or ``"dopri5"``; ``energy``: the energy
        bookkeeping, DAE only; ``max_steps`` step attempts and ``max_wall`` seconds of
        integration at most). The GIL is released for the whole run, so runs in other
        Python threads proceed in parallel. Same model and settings, same numbers as the
        command line, bit for bit.

        Raises ``SettingsError`` (before any work), ``ModelError`` (the linkage cannot be
        assembled or does not fit the formulation), ``SolverError`` (with ``time``)."""

    # The analyses. Each takes the solve settings of ``run`` (``dt``, ``formulation``,
    # ``method``, ``rtol``, ``atol``, ``max_steps``, ``max_wall``: same names and defaults;
    # no ``t_end``: they count turns of the single driver, T = 2π/|ω|), checks everything
    # before any work in the order of the matching command, releases the GIL while Rust
    # computes, and gives the command's numbers bit for bit. Errors: ``SettingsError`` for an
    # option (``str(e)`` is the command's message with ``phase`` for ``--phase``),
    # ``ModelError`` (the linkage cannot be assembled or does not fit the formulation),
    # ``SolverError`` (the integration failed; ``time``), ``AnalysisError`` (e.g. a window
    # with too few samples).

    def poincare(
        self,
        *,
        revs: Optional[float] = None,
        transient: int = 0,
        phase: float = 0.0,
        observe: Union[str, Sequence[str], None] = None,
        dt: float = 1e-4,
        formulation: str = "dae",
        method: str = "dop853",
        rtol: float = 1e-8,
        atol: float = 1e-10,
        max_steps: int = 10_000_000,
        max_wall: Optional[float] = None,
    ) -> PoincareSection:
        """Poincaré section once per driver turn, with its period verdict (``linkdyn
        poincare``). Integrates ``revs`` turns (a whole number ≥ 1, default 2) and records, for
        turns k = ``transient`` … revs − 1, the ``observe`` columns (a list, or a string split
        at commas; default: each clearance joint's ``ex``, ``ey`` and each body's ``phi``, ``omega``,
        angles modulo whole turns) at the exact instants
        t_k = t0 + ``phase``/|ω| + k·T (``phase`` in rad, in [0, 2π)), from the dense output.
        The verdict (period-k, no period, not settled) compares points within 1000 times the
        integration tolerance carried to each column; see ``PoincareSection``."""
    def bifurcation(
        self,
        param: str,
        observe: str,
        *,
        from_: Optional[float] = None,
        to: Optional[float] = None,
        steps: Optional[int] = None,
        values: Optional[Sequence[float]] = None,
        revs: Optional[float] = None,
        transient: int = 100,
        phase: float = 0.0,
        threads: Optional[int] = None,
        shard: Optional[str] = None,
        progress: Union[bool, None, Callable[[int, int], Any]] = True,
        settle: bool = False,
        transient_min: Optional[int] = None,
        warm_start: bool = False,
        chunks: Optional[int] = None,
        direction: Optional[str] = None,
        dt: float = 1e-4,
        formulation: str = "dae",
        method: str = "dop853",
        rtol: float = 1e-8,
        atol: float = 1e-10,
        max_steps: int = 10_000_000,
        max_wall: Optional[float] = None,
    ) -> Bifurcation:
        """Bifurcation diagram (``linkdyn bifurcation``): the model field ``param`` (a ``set=``
        path, e.g. ``"joints.B.clearance"``, in the field's unit in the model file) takes each
        value of the grid ``from_`` … ``to`` in ``steps`` intervals (both ends included, as
        ``--from/--to/--steps``) or of the list ``values``; each point reloads the model file
        with the load-time overrides and ``param=value``, integrates ``revs`` turns (default
        150) and records ``observe`` once per turn after ``transient`` turns (default 100) at
        ``phase``, with the point's period verdict.

        Points run in parallel on ``threads`` rayon threads (default: one per core) without
        the GIL; ``shard="i/n"`` runs only shard i of n (1-based). ``progress``: ``True`` a
        tqdm bar (a line on stderr without tqdm), ``False``/``None`` nothing, or a callable
        ``progress(done, total)``; it is called from the calling thread between points, taking
        the GIL briefly. Ctrl-C or an exception from the callback stops the sweep (points in
        flight finish first). A point that fails does not stop the others: its rows are NaN, its
        verdict ``"failed"`` with the error in ``message`` (``failures`` maps index → message),
        and a ``RuntimeWarning`` names the failed points. Bad input (including a ``to`` the
        model refuses) raises before any point runs.

        ``settle=True`` ends each point's transient once its section has settled (after at
        least ``transient_min`` turns, default 5, and at most ``transient``; the turns used in
        ``transient_turns``). ``warm_start=True`` (``formulation="reduced"``) starts each point
        from the state the point before it ended in: the grid is split into ``chunks``
        contiguous chunks (default one per 25 points, at most 8), each swept in ``direction``
        (``"up"``, ``"down"`` or ``"both"``: two branches, which show coexisting attractors
        and hysteresis; ``direction``/``point_direction`` tell the rows apart). The command
        line's ``--settle``, ``--transient-min``, ``--warm-start``, ``--chunks`` and
        ``--direction``, with the same points.

        The model file must be unchanged since ``load`` (each point reads it again; a changed
        file is refused) and reachable by the path given to ``load`` from the current
        directory."""
    def spectrum(
        self,
        observe: str,
        *,
        revs: Optional[float] = None,
        transient: float = 0.0,
        dt: float = 1e-4,
        formulation: str = "dae",
        method: str = "dop853",
        rtol: float = 1e-8,
        atol: float = 1e-10,
        max_steps: int = 10_000_000,
        max_wall: Optional[float] = None,
    ) -> Spectrum:
        """One-sided amplitude spectrum of output column ``observe`` (``linkdyn spectrum``):
        ``revs`` turns (default transient + 10) sampled every ``dt`` s, the first
        ``transient`` turns dropped, Hann window, mean removed; the dominant peaks with their
        multiple of the driving frequency |ω|/2π. See ``Spectrum``."""
    def phase(
        self,
        observe: str,
        *,
        revs: Optional[float] = None,
        transient: float = 0.0,
        dt: float = 1e-4,
        formulation: str = "dae",
        method: str = "dop853",
        rtol: float = 1e-8,
        atol: float = 1e-10,
        max_steps: int = 10_000_000,
        max_wall: Optional[float] = None,
    ) -> PhasePortrait:
        """Phase-portrait data of output column ``observe`` (``linkdyn phase``): its samples
        after ``transient`` turns against its rate, from the rate column where the run has one
        (``B.phi`` → ``B.omega``, ``B.x`` → ``B.vx``), else second-order differences.
        ``revs`` defaults to transient + 10. See ``PhasePortrait``."""
    def lyapunov(
        self,
        *,
        revs: Optional[float] = None,
        transient: float = 0.0,
        d0: float = 1e-7,
        renormalise_every_revs: float = 1.0,
        dt: float = 1e-4,
        formulation: str = "dae",
        method: str = "dop853",
        rtol: float = 1e-8,
        atol: float = 1e-10,
        max_steps: int = 10_000_000,
        max_wall: Optional[float] = None,
    ) -> LyapunovExponent:
        """Largest Lyapunov exponent (``linkdyn lyapunov``, 1/s): a reference and a perturbed
        trajectory from turn ``transient``, separated by ``d0`` in the scaled norm (angles in
        rad, positions in units of the longest body arm, velocities × 1/|ω|; bookkeeping
        states neither perturbed nor measured) and renormalised every
        ``renormalise_every_revs`` turns up to ``revs`` (default transient + 10; at least 2
        intervals). Returns λ, its batch-means uncertainty and the running estimate; see
        ``LyapunovExponent``."""
    def orbit(
        self,
        *,
        period_turns: Optional[int] = None,
        period: Optional[float] = None,
        guess_from_turn: int = 3,
        dt: float = 1e-4,
        formulation: str = "reduced",
        method: str = "dop853",
        rtol: float = 1e-8,
        atol: float = 1e-10,
        max_steps: int = 10_000_000,
        max_wall: Optional[float] = None,
    ) -> PeriodicOrbit:
        """A periodic orbit by shooting, with its Floquet multipliers (``linkdyn orbit``):
        Newton's method on P^K(x) − x = 0 over ``period_turns`` driver turns (default 1; or
        ``period`` seconds), from the state after ``guess_from_turn`` periods of integration;
        the monodromy from the variational equations with saltation matrices. The reduced
        formulation (the default here, as on the command line) or ``"dae"`` (any linkage;
        not ``"generalized"``). The command's
        ``F.json`` keys and one period of the orbit (its ``F.csv``); see ``PeriodicOrbit``.
        Raises ``SolverError`` (with ``residual_history``) when no orbit is found."""
    def continuation(
        self,
        param: str,
        from_: float,
        to: float,
        *,
        step: Optional[float] = None,
        period_turns: int = 1,
        guess_from_turn: int = 3,
        follow_doublings: int = 0,
        progress: Union[bool, None, Callable[[Dict[str, Any]], Any]] = True,
        dt: float = 1e-4,
        formulation: str = "reduced",
        method: str = "dop853",
        rtol: float = 1e-8,
        atol: float = 1e-10,
        max_steps: int = 10_000_000,
        max_wall: Optional[float] = None,
    ) -> Continuation:
        """The periodic orbit continued in the model field ``param`` from ``from_`` to ``to``
        (``linkdyn continue``): pseudo-arclength steps of at most ``step`` (default
        |to − from_|/20), folds, period doublings, Neimark–Sacker points and grazings located;
        with ``follow_doublings`` N the period-2K branch from each located period doubling too,
        N doublings deep (rows' ``branch`` and ``turn``). The command's ``F.csv`` as arrays and
        its ``F.json``'s keys; see ``Continuation``. A branch that stops before ``to`` is
        returned with a ``RuntimeWarning``. ``progress``: ``True`` a line on stderr, ``False``
        or ``None`` nothing, or a callable ``progress(point)`` called after each point with a
        dict (``points``, ``branch``, ``parameter``, ``stable``, ``max_abs_mu``, ``special``);
        an exception from it, or Ctrl-C, ends the branch after the current point and is
        raised."""
    def wear(
        self,
        turns: int,
        *,
        update_every: int = 1,
        dt: float = 1e-4,
        formulation: str = "dae",
        method: str = "dop853",
        rtol: float = 1e-8,
        atol: float = 1e-10,
        max_steps: int = 10_000_000,
        max_wall: Optional[float] = None,
    ) -> Wear:
        """Archard wear of the model's worn clearance joint (``[joints.wear]``) over ``turns``
        driver turns, the bearing profile updated every ``update_every`` turns (``linkdyn
        wear``; DAE only). The command's ``wear.csv`` as arrays (``depth_m`` by update and
        bin) and its ``wear.json``'s keys; see ``Wear``."""

class Result:
    """A finished run: times, one read-only float64 array per column, events, summary."""

    @property
    def t(self) -> FloatArray:
        """Sample times (s), read-only."""
    @property
    def names(self) -> List[str]:
        """Output column names in CSV order, without ``t``."""
    @property
    def constraint_violation(self) -> FloatArray:
        """Constraint violation max |Φ| at each sample (m or rad)."""
    @property
    def summary(self) -> Dict[str, Any]:
        """The run summary (the JSON file of ``linkdyn run``); a new dict on every access."""
    @property
    def events(self) -> List[Dict[str, Any]]:
        """The located contact events in time order: ``t`` (s), ``index``, ``joint``, ``kind``
        (``"impact"`` or ``"separation"``), ``restarted``. Events where the method only ended
        its steps (friction kinks, repartitions) are not listed."""
    def column(self, name: str) -> FloatArray:
        """A column by name (``"t"`` included); ``KeyError`` if there is none."""
    def __getitem__(self, name: str) -> FloatArray:
        """Same as ``column(name)``."""
    def __contains__(self, name: str) -> bool: ...
    def __len__(self) -> int:
        """Number of samples."""
    def to_pandas(self) -> Any:
        """The columns (``t`` first) as a ``pandas.DataFrame``; ``ImportError`` without
        pandas."""
