"""External loads (III.1–III.10) as dicts for ``World.add_load``.
Gravity is a world parameter (``World(gravity=...)``)."""
from __future__ import annotations

from typing import Sequence

from .constraints import Kind, _vec

__all__ = ["point_force", "point_torque", "distributed"]


def point_force(rod, u: float, force: Sequence[float]) -> Kind:
    """Force (force unit, 3 values) applied at r(u) of ``rod`` (a rod in the world)."""
    return Kind({"PointForce": {"rod": rod, "u": float(u), "force": _vec(force, 3, "force")}})


def point_torque(rod, u: float, torque: float) -> Kind:
    """Torque (force × length) about the tangent at u, on the roll (rods with roll)."""
    return Kind({"PointTorque": {"rod": rod, "u": float(u), "torque": float(torque)}})


def distributed(rod, force_per_length: Sequence[float]) -> Kind:
    """Uniform force per unit rest length (force/length, 3 values) along the whole rod."""
    return Kind({"Distributed": {"rod": rod, "force_per_length": _vec(force_per_length, 3, "force_per_length")}})
