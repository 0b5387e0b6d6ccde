"""Constraint kinds (SPEC §4) as plain dicts ``{"Kind": {fields}}``.

The core deserialises them with serde, so any kind the Rust core knows can
be built with :func:`kind` even before a helper exists here. Abscissae ``u``
are spline parameters: see ``Rod.domain`` / ``Rod.u_start`` / ``Rod.u_end``.
Lengths are in the world's length unit, angles in radians.
"""
from __future__ import annotations

from typing import Iterable, Sequence, Union

__all__ = [
    "Kind",
    "kind",
    "position",
    "tangent",
    "material_roll",
    "distance",
    "plane",
    "axis",
    "curvature",
    "relative_position",
    "relative_orientation",
    "relative_distance",
    "sliding_point",
    "oriented_sliding_point",
    "contact",
    "clamp",
]


class Kind(dict):
    """A constraint (or load) kind: ``{"Name": {field: value}}``."""

    @property
    def name(self) -> str:
        return next(iter(self))

    @property
    def fields(self) -> dict:
        return self[self.name]

    def __repr__(self) -> str:
        args = ", ".join(f"{k}={v!r}" for k, v in self.fields.items())
        return f"{self.name}({args})"


def kind(name: str, **fields) -> Kind:
    """Any core constraint kind by its Rust name, e.g.
    ``kind("Plane", u=0.0, origin=[0, 0, 0], normal=[0, 0, 1])``."""
    return Kind({name: {k: _plain(v) for k, v in fields.items()}})


def _plain(v):
    """numpy arrays/scalars → lists/floats (Rod objects pass through)."""
    if hasattr(v, "tolist"):
        return v.tolist()
    if isinstance(v, tuple):
        return [_plain(x) for x in v]
    return v


def _vec(v, n: int, what: str) -> list:
    out = [float(x) for x in _plain(v)]
    if len(out) != n:
        raise ValueError(f"invalid input: {what} needs {n} values, got {len(out)}")
    return out


_AXES = {"x": 0, "y": 1, "z": 2, "r": 3, "θ": 3, "t": 3}


def _axes(axes: Union[str, Sequence[bool]]) -> list:
    if isinstance(axes, str):
        sel = [False] * 4
        for c in axes.lower().replace("roll", "r").replace("theta", "r"):
            if c in " ,":
                continue
            if c not in _AXES:
                raise ValueError(f"invalid input: axes letters are x, y, z and r (roll), got {axes!r}")
            sel[_AXES[c]] = True
        return sel
    sel = [bool(a) for a in axes]
    if len(sel) != 4:
        raise ValueError(f"invalid input: axes needs 4 booleans (x, y, z, roll), got {len(sel)}")
    return sel


def position(u: float, target: Sequence[float] = (0.0, 0.0, 0.0), *, axes: Union[str, Sequence[bool]] = "xyz",
             roll: float | None = None) -> Kind:
    """Fix r(u) to ``target`` (length) on the selected ``axes`` (letters
    from "xyz", plus "r" for the roll coordinate θ). ``roll`` (rad) also
    fixes θ(u) (relative to the Frenet frame; use :func:`material_roll` for
    an absolute clamp). Multipliers: force (x, y, z), torque about the tangent."""
    sel = _axes(axes)
    t = [float(x) for x in _plain(target)]
    if len(t) == 3:
        t.append(0.0)
    if len(t) != 4:
        raise ValueError(f"invalid input: position target needs 3 (x, y, z) or 4 values, got {len(t)}")
    if roll is not None:
        sel[3] = True
        t[3] = float(roll)
    return kind("Position", u=float(u), axes=sel, target=t)


def tangent(u: float, direction: Sequence[float]) -> Kind:
    """Tangent r'(u) parallel to ``direction`` (two rows). Multiplier: the
    moment (force × length) ⟂ the tangent."""
    return kind("Tangent", u=float(u), direction=_vec(direction, 3, "tangent direction"))


def material_roll(u: float, reference: Sequence[float], angle: float = 0.0) -> Kind:
    """Absolute roll of the cross-section: director d1 at ``angle`` (rad)
    from ``reference`` about the tangent (needs a curved rod at u in the
    Frenet model). Multiplier: torque about the tangent."""
    return kind("MaterialRoll", u=float(u), reference=_vec(reference, 3, "reference"), angle=float(angle))


def distance(u: float, point: Sequence[float], distance: float) -> Kind:
    """|r(u) − point| = ``distance`` (length, > 0). Multiplier: force along
    (r − point)/|r − point|, negative in tension."""
    return kind("Distance", u=float(u), point=_vec(point, 3, "point"), distance=float(distance))


def plane(u: float, origin: Sequence[float], normal: Sequence[float]) -> Kind:
    """r(u) stays on the plane through ``origin`` with ``normal``. Multiplier: normal force."""
    return kind("Plane", u=float(u), origin=_vec(origin, 3, "origin"), normal=_vec(normal, 3, "normal"))


def axis(u: float, origin: Sequence[float], direction: Sequence[float]) -> Kind:
    """r(u) stays on the line through ``origin`` along ``direction`` (two rows)."""
    return kind("Axis", u=float(u), origin=_vec(origin, 3, "origin"), direction=_vec(direction, 3, "direction"))


def curvature(u: float, target: Sequence[float]) -> Kind:
    """r''(u) = ``target`` (length per u², three rows)."""
    return kind("Curvature", u=float(u), target=_vec(target, 3, "curvature target"))


def relative_position(ua: float, ub: float, offset: Sequence[float] = (0.0, 0.0, 0.0), *,
                      axes: Union[str, Sequence[bool]] = "xyz", roll_offset: float | None = None) -> Kind:
    """Two points (rods a and b of ``World.add_link``): q_a(ua) − q_b(ub) =
    ``offset`` (length) on the selected axes ("r": roll). Multiplier: force
    on rod a (rod b gets the opposite)."""
    sel = _axes(axes)
    o = [float(x) for x in _plain(offset)]
    if len(o) == 3:
        o.append(0.0)
    if roll_offset is not None:
        sel[3] = True
        o[3] = float(roll_offset)
    return kind("RelativePosition", ua=float(ua), ub=float(ub), axes=sel, offset=_vec(o, 4, "offset"))


def relative_orientation(ua: float, ub: float, *, roll: bool = False) -> Kind:
    """Tangents of rod a at ua and rod b at ub aligned (+ equal roll)."""
    return kind("RelativeOrientation", ua=float(ua), ub=float(ub), roll=bool(roll))


def relative_distance(ua: float, ub: float, distance: float) -> Kind:
    """|r_a(ua) − r_b(ub)| = ``distance`` (length, > 0). Multiplier: force
    on rod a, negative in tension."""
    return kind("RelativeDistance", ua=float(ua), ub=float(ub), distance=float(distance))


def sliding_point(u: float, point: Sequence[float], *, friction: float = 0.0) -> Kind:
    """The rod passes through ``point`` (length) at a free abscissa that
    starts at ``u`` and slides (a ring; III.37–III.42); ``friction`` is
    viscous (force per sliding speed). The current abscissa is in
    ``handle.kind``; a slider that leaves the rod is removed with a
    ``SliderLeft`` event. Multiplier: the ring force."""
    return kind("SlidingPoint", u=float(u), point=_vec(point, 3, "point"), friction=float(friction))


def oriented_sliding_point(u: float, point: Sequence[float], direction: Sequence[float], *,
                           friction: float = 0.0) -> Kind:
    """A sliding point that also holds the tangent along ``direction`` (a
    guide tube; III.43–III.49)."""
    return kind("OrientedSlidingPoint", u=float(u), point=_vec(point, 3, "point"),
                direction=_vec(direction, 3, "direction"), friction=float(friction))


def contact(ua: float, ub: float, distance: float) -> Kind:
    """Sliding contact between rods a and b of ``World.add_link``:
    |r_a(ua) − r_b(ub)| = ``distance`` (length) with both abscissae free."""
    return kind("Contact", ua=float(ua), ub=float(ub), distance=float(distance))


def clamp(world, rod, u: float | None = None, *, target: Iterable[float] | None = None,
          direction: Iterable[float] | None = None, roll: bool = True, compliance: float = 0.0):
    """Clamp ``rod`` at ``u`` (default: its start): position (+ roll
    coordinate if the rod has one and ``roll``) and tangent direction,
    defaulting to the current point and tangent. Returns the two handles
    (position, tangent)."""
    if u is None:
        u = rod.u_start
    p = rod.position(u) if target is None else target
    d = rod.tangent(u) if direction is None else direction
    with_roll = roll and rod.dofs == 4
    r = float(rod.eval(u)[3]) if with_roll else None
    a = world.add_constraint(rod, position(u, p, roll=r), compliance=compliance)
    b = world.add_constraint(rod, tangent(u, d), compliance=compliance)
    return a, b

