"""Type stubs of the compiled core ``linkdyn._linkdyn`` (re-exported by ``linkdyn``)."""

from typing import Any, Dict, List, Optional

import numpy as np
import numpy.typing as npt

FloatArray = npt.NDArray[np.float64]

def load(path: str, overrides: List[str] = ...) -> "Model":
    """Reads and validates a model file, applying ``"KEY=VALUE"`` overrides in order (as
    ``--set``). Raises ``ModelError``. Use ``linkdyn.load``, which also takes a dict."""

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
        """The model file as given to ``load``."""
    @property
    def overrides(self) -> List[str]:
        """The overrides applied at load time (``"KEY=VALUE"``, in order)."""
    @property
    def notes(self) -> List[str]:
        """Things to know that are not errors (the CLI's ``note:`` lines), one sentence each."""
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
    ) -> "Result":
        """Integrates the model and keeps every sample in memory; the arguments and defaults
        are those of ``linkdyn run`` (end time ``t_end`` in s, or ``revs`` turns of the single
        driver, default 2 turns; output interval ``dt`` in s; ``formulation`` ``"dae"`` or
        ``"reduced"``; ``method`` ``"dop853"`` or ``"dopri5"``; ``energy``: the energy
        bookkeeping, DAE only). The GIL is released for the whole run, so runs in other
        Python threads proceed in parallel. Same model and settings, same numbers as the
        command line, bit for bit.

        Raises ``SettingsError`` (before any work), ``ModelError`` (the linkage cannot be
        assembled or does not fit the formulation), ``SolverError`` (with ``time``)."""

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
        """Located events in time order: ``t`` (s), ``index``, ``joint`` (or None), ``kind``
        (``"impact"`` or ``"separation"``), ``restarted``."""
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
