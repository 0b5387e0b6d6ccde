"""External loads (III.1–III.10) as dicts for ``World.add_load``: one helper
per load kind the core registers (``point_force``, ``point_torque``,
``distributed``, ``trap``), generated from its catalogue (``CATALOGUE``)
like the constraint helpers. Gravity is a world parameter
(``World(gravity=...)``). In an Assembly a load's ``rod`` is the index given
to ``Assembly.add_load``, so the helper's ``rod`` may be None there.

>>> import strandkit as sk
>>> w = sk.World()
>>> rod = w.add_rod(sk.straight((0, 0, 0), (1, 0, 0), section=0.01, material="nylon"))
>>> load = w.add_load(sk.point_force(rod, rod.u_end, (0, -1, 0)))
>>> load.force, load.rod == rod
([0.0, -1.0, 0.0], True)
>>> sk.trap(None, 0.0, anchor=(0, 0, 1), stiffness=10.0)["Trap"]["velocity"]
[0.0, 0.0, 0.0]
"""
from __future__ import annotations

from . import _native
from ._catalogue import helpers as _helpers

#: The core's load catalogue: one dict per kind (name, helper, doc, fields).
CATALOGUE = _native.load_catalogue()

_HELPERS = _helpers(CATALOGUE, __name__, lambda info: "World.add_load(load) or Assembly.add_load(rod_index, load)")
globals().update(_HELPERS)

__all__ = [*_HELPERS]
