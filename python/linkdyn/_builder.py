"""``ModelBuilder``: a model written one element at a time, as Exudyn's ``mbs.Add…`` and
PyChrono's ``system.Add(…)`` build theirs.

Each method adds one table of the model file (docs/model_format.md) with its fields as keyword
arguments, spelled as in the file; nothing is checked until :meth:`ModelBuilder.build`, which
reads the document through :func:`linkdyn.from_dict` and so gives the file's checks and
messages. Numbers are SI (``speed_rpm`` aside, as in the file); any number may be an expression
string of the parameters (``inertia="m*L^2/12"``).
"""

from typing import TYPE_CHECKING, Any, Dict, List, Mapping, Optional, Sequence, Union

if TYPE_CHECKING:
    from ._linkdyn import Model

Number = Union[float, int, str]
Vec2 = Sequence[Number]


class ModelBuilder:
    """A model file built in Python.

    ::

        b = linkdyn.ModelBuilder("pendulum", "a bar swinging about O")
        b.parameter("L", 0.5).ground_point("O", [0, 0])
        b.body("bar", mass=1.0, inertia="L^2/12", points={"O": ["-L/2", 0]},
               initial={"x": "L/2", "y": 0, "phi": 0})
        b.joint("O", "revolute", body_a="ground", point_a="O", body_b="bar", point_b="O")
        model = b.build()            # a linkdyn.Model, checked as a file is
        print(b.to_toml())           # the same model as a file for `linkdyn run`

    Every method returns the builder, so calls can be chained.
    """

    def __init__(self, name: str, description: str = "") -> None:
        self._doc: Dict[str, Any] = {"model": {"name": name, "description": description}}

    def _append(self, table: str, entry: Dict[str, Any]) -> "ModelBuilder":
        self._doc.setdefault(table, []).append(entry)
        return self

    def settings(
        self, gravity: Optional[Vec2] = None, baumgarte: Optional[Mapping[str, Number]] = None
    ) -> "ModelBuilder":
        """``[settings]``: gravity (m/s², default [0, -9.81]) and ``baumgarte`` (``alpha``,
        ``beta`` in 1/s, or ``omega`` in rad/s and ``zeta``)."""
        s = self._doc.setdefault("settings", {})
        if gravity is not None:
            s["gravity"] = list(gravity)
        if baumgarte is not None:
            s["baumgarte"] = dict(baumgarte)
        return self

    def parameter(self, name: str, value: Number) -> "ModelBuilder":
        """``[parameters]``: a named number or expression, usable in any numeric field."""
        self._doc.setdefault("parameters", {})[name] = value
        return self

    def ground_point(self, name: str, at: Vec2) -> "ModelBuilder":
        """``[ground] points``: a fixed point in the global frame (m)."""
        self._doc.setdefault("ground", {}).setdefault("points", {})[name] = list(at)
        return self

    def body(
        self,
        name: str,
        *,
        mass: Number,
        inertia: Number,
        initial: Mapping[str, Number],
        points: Optional[Mapping[str, Vec2]] = None,
        shapes: Optional[Sequence[Mapping[str, Any]]] = None,
    ) -> "ModelBuilder":
        """``[[bodies]]``: mass (kg), inertia about the centre of mass (kg·m²), named points in
        the body frame (m, origin at the centre of mass), the initial pose guess ``{"x", "y",
        "phi"}`` (and optionally ``vx``, ``vy``, ``omega``), and how it is drawn."""
        entry: Dict[str, Any] = {"name": name, "mass": mass, "inertia": inertia}
        if points is not None:
            entry["points"] = {k: list(v) for k, v in points.items()}
        entry["initial"] = dict(initial)
        if shapes is not None:
            entry["shapes"] = [dict(s) for s in shapes]
        return self._append("bodies", entry)

    def joint(self, name: str, type: str, **fields: Any) -> "ModelBuilder":
        """``[[joints]]`` of ``type`` "revolute", "prismatic", "clearance" or
        "prismatic-clearance", with the fields of that type (``body_a``, ``point_a``, … or
        ``bearing``, ``journal``, ``clearance``, ``contact={"law": …}``, ``friction={…}``, … or
        ``slider_length``, ``slider_width``, ``stiffness``, ``guide_start``, ``guide_end``;
        docs/model_format.md)."""
        return self._append("joints", {"name": name, "type": type, **fields})

    def driver(self, name: str, type: str, *, joint: str, **fields: Any) -> "ModelBuilder":
        """``[[drivers]]`` of ``type`` "constant-speed", "speed-ramp", "prescribed-angle" or
        "torque" on revolute joint ``joint`` (``speed_rpm=250``, ``initial_angle=0``, …)."""
        return self._append("drivers", {"name": name, "type": type, "joint": joint, **fields})

    def force(self, name: str, type: str, **fields: Any) -> "ModelBuilder":
        """``[[forces]]`` of ``type`` "spring-damper", "torque" or "force"."""
        return self._append("forces", {"name": name, "type": type, **fields})

    def output(self, name: str, body: str, **fields: Any) -> "ModelBuilder":
        """``[[outputs]]``: a point (``point="B"`` or ``local=[x, y]``) whose motion becomes
        the columns ``name.x`` … ``name.ay``."""
        return self._append("outputs", {"name": name, "body": body, **fields})

    def to_dict(self) -> Dict[str, Any]:
        """The document built so far (a copy to read; the builder keeps its own)."""
        import copy

        return copy.deepcopy(self._doc)

    def to_toml(self) -> str:
        """The document built so far as a model file's text."""
        from . import _linkdyn

        return _linkdyn.dict_to_toml(self._doc)

    def build(self, name: str = "<builder>") -> "Model":
        """The model, checked as a file is (raises :class:`ModelError`); ``name`` stands for
        the file in messages and provenance."""
        from . import from_dict

        return from_dict(self._doc, name=name)


__all__: List[str] = ["ModelBuilder"]
