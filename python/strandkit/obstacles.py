"""Fixed obstacles for contact (SPEC §7), added with ``World.add_obstacle``.

>>> import strandkit as sk
>>> floor = sk.obstacles.plane(origin=(0, 0, 0), normal=(0, 0, 1))
>>> floor
Obstacle.plane(origin=[0.0, 0.0, 0.0], normal=[0.0, 0.0, 1.0])
>>> float(floor.distance([[0, 0, 0.5]])[0])
0.5

The rods' surfaces cannot enter them; ``World.add_obstacle(obstacle,
margin=…, friction=…)`` sets how early contact is detected (length) and the
Coulomb coefficient against the rods. Lengths are in the world's unit.
(``strandkit.plane`` is the Plane *constraint* helper, hence this module.)
"""
from __future__ import annotations

import os
from typing import Sequence

from . import _native
from ._native import Obstacle

__all__ = ["Obstacle", "plane", "sphere", "capsule", "cylinder", "mesh", "mesh_arrays"]


def plane(origin: Sequence[float] = (0.0, 0.0, 0.0), normal: Sequence[float] = (0.0, 0.0, 1.0)) -> Obstacle:
    """The half-space behind the plane through ``origin`` (length) whose ``normal`` points out of it."""
    return _native.obstacle_plane(origin, normal)


def sphere(center: Sequence[float], radius: float) -> Obstacle:
    """A ball of ``radius`` (length) about ``center`` (length)."""
    return _native.obstacle_sphere(center, radius)


def capsule(a: Sequence[float], b: Sequence[float], radius: float) -> Obstacle:
    """The points within ``radius`` (length) of the segment ``a``–``b`` (length): a cylinder with round ends."""
    return _native.obstacle_capsule(a, b, radius)


def cylinder(center: Sequence[float], axis: Sequence[float], radius: float, length: float) -> Obstacle:
    """A cylinder of ``radius`` and ``length`` (length) about ``center`` along ``axis``, as a capsule
    (round ends): a rod meeting it away from its ends sees a cylinder."""
    import numpy as np

    from .errors import InvalidInputError

    c, d = np.asarray(center, float), np.asarray(axis, float)
    n = float(np.linalg.norm(d)) if d.shape == (3,) else float("nan")
    if not (n > 0 and np.isfinite(n)):
        raise InvalidInputError(f"cylinder axis: expected a finite, non-zero 3-vector, got {axis!r}")
    if not (float(length) >= 0 and np.isfinite(float(length))):
        raise InvalidInputError(f"cylinder length: expected a finite length ≥ 0, got {length!r}")
    half = 0.5 * float(length) * d / n
    return _native.obstacle_capsule(c - half, c + half, radius)


def mesh(path: str | os.PathLike) -> Obstacle:
    """A triangle mesh read from an ``.obj`` or ``.stl`` file (outside where the faces' normals point)."""
    return _native.obstacle_mesh_file(os.fspath(path))


def mesh_arrays(vertices, triangles) -> Obstacle:
    """A triangle mesh from (n, 3) ``vertices`` (length) and (m, 3) ``triangles`` (vertex indices,
    counter-clockwise seen from outside)."""
    return _native.obstacle_mesh_arrays(vertices, triangles)
