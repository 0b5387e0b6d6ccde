"""Constraint kinds (SPEC §4) as plain dicts ``{"Kind": {fields}}``.

One helper per kind the Rust core registers (``position``, ``tangent``, …,
``barycentric``), generated from its catalogue (``CATALOGUE``): names,
signatures, docstrings with units, defaults and the coercion of arguments
all come from the core, so a kind added there appears here. Any kind can
also be built by name with :func:`kind`. Abscissae ``u`` are spline
parameters (see ``Rod.domain`` / ``Rod.u_start`` / ``Rod.u_end``); lengths
are in the world's length unit, angles in radians.

>>> import strandkit as sk
>>> sk.position(0.0, (1, 2, 3))
Position(u=0.0, target=[1.0, 2.0, 3.0, 0.0], axes=[True, True, True, False])
>>> sk.position(0.0, axes="xz", roll=0.25)["Position"]["axes"]
[True, False, True, True]
>>> sk.relative_distance(1.0, 2.0, 0.5)
RelativeDistance(ua=1.0, ub=2.0, distance=0.5)
>>> sorted(c["helper"] for c in sk.constraints.CATALOGUE)[:3]
['axis', 'barycentric', 'base_pair_step']
"""
from __future__ import annotations

from typing import Iterable, Optional

from . import _native
from ._catalogue import Kind, helpers as _helpers, plain as _plain

#: The core's constraint catalogue: one dict per kind (name, helper, rods,
#: doc, fields with ty, unit, doc, default, roll_keyword).
CATALOGUE = _native.constraint_catalogue()


def _use(info: dict) -> str:
    return "World.add_link(a, b, kind)" if info["rods"] == 2 else "World.add_constraint(rod, kind)"


_HELPERS = _helpers(CATALOGUE, __name__, _use)
globals().update(_HELPERS)

__all__ = ["Kind", "kind", "clamp", *_HELPERS]


def kind(name: str, **fields) -> Kind:
    """Any core constraint kind by its Rust name, fields as given (numpy
    values become lists), e.g.

    >>> kind("Plane", u=0.0, origin=(0, 0, 0), normal=(0, 0, 1))
    Plane(u=0.0, origin=[0, 0, 0], normal=[0, 0, 1])
    """
    return Kind({name: {k: _plain(v) for k, v in fields.items()}})


def clamp(world, rod, u: Optional[float] = None, *, target: Optional[Iterable[float]] = None,
          direction: Optional[Iterable[float]] = None, roll: bool = True, compliance: float = 0.0):
    """Clamp ``rod`` at ``u`` (default: its start).

    Without ``target`` and ``direction`` this is ``World.clamp``: position,
    tangent and the cross-section held where they are now, as the rod's frame
    model says (the roll coordinate on a straight stretch, an absolute
    material roll on a curved one) — a tuple of 2 or 3 handles. With
    ``target`` (length) or ``direction``, or ``roll=False``: a position
    constraint (with the roll coordinate if the rod has one and ``roll``)
    and a tangent constraint, defaulting to the current point and tangent —
    the tuple (position, tangent). ``compliance``: length/force (0 = hard).

    >>> import strandkit as sk
    >>> w = sk.World()
    >>> rod = w.add_rod(sk.straight((0, 0, 0), (1, 0, 0), section=0.01, material="nylon"))
    >>> [h.kind.popitem()[0] for h in sk.clamp(w, rod)]
    ['Position', 'Tangent']
    """
    if target is None and direction is None and roll:
        return world.clamp(rod, u, compliance=compliance)
    if u is None:
        u = rod.u_start
    p = rod.position(u) if target is None else target
    d = rod.tangent(u) if direction is None else direction
    r = float(rod.eval(u)[3]) if roll and rod.dofs == 4 else None
    a = world.add_constraint(rod, position(u, p, roll=r), compliance=compliance)  # noqa: F821 (generated)
    b = world.add_constraint(rod, tangent(u, d), compliance=compliance)  # noqa: F821 (generated)
    return a, b
