"""Measures on a knit's yarn: dense points, the clearance between yarns
(is any yarn inside another?) and the edge curl of a swatch."""
from __future__ import annotations

import numpy as np

__all__ = ["yarn_points", "clearance", "curl"]


def yarn_points(world, fabric, per_loop: int = 40):
    """Points along every yarn now, about ``per_loop`` per stitch: a list
    of (n, 3) arrays (m), one per yarn."""
    out = []
    for rod in world.rods()[: len(np.unique(fabric.loops["rod"]))]:
        u0, u1 = rod.domain
        n = max(8, int(round(per_loop * rod.rest_length / fabric.loop_length)))
        out.append(rod.position(np.linspace(u0, u1, n, endpoint=not fabric.tube_radius > 0)))
    return out


def clearance(world, fabric, *, exclude: float = 4.0) -> float:
    """Smallest distance between yarn centrelines over the yarn diameter
    2r, points closer than ``exclude`` radii along one yarn left out:
    ≥ 1 when no yarn enters another, < 0.5 only if one has passed through
    (the centreline of one inside the other). A cell hash keeps it
    O(points)."""
    r = fabric.yarn_radius
    ring = fabric.tube_radius > 0
    pts, yarn, s, total = [], [], [], []
    for k, p in enumerate(yarn_points(world, fabric)):
        arc = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(p, axis=0), axis=1))])
        # A ring's length includes its closing segment (its last point
        # neighbours its first along the yarn).
        length = arc[-1] + (np.linalg.norm(p[0] - p[-1]) if ring else np.inf)
        pts.append(p), yarn.append(np.full(len(p), k)), s.append(arc), total.append(np.full(len(p), length))
    p, yarn, s, total = (np.concatenate(x) for x in (pts, yarn, s, total))
    cell = 2.0 * r
    key = np.floor(p / cell).astype(np.int64)
    order = np.lexsort(key.T[::-1])
    key, p, yarn, s, total = key[order], p[order], yarn[order], s[order], total[order]
    # Group points by cell; compare each cell with its 13 "forward" neighbours and itself.
    uniq, start, counts = np.unique(key, axis=0, return_index=True, return_counts=True)
    index = {tuple(k): (a, a + c) for k, a, c in zip(uniq.tolist(), start.tolist(), counts.tolist())}
    offsets = [(dx, dy, dz) for dx in (-1, 0, 1) for dy in (-1, 0, 1) for dz in (-1, 0, 1) if (dx, dy, dz) >= (0, 0, 0)]
    best = np.inf
    for k, (a, b) in index.items():
        for o in offsets:
            nb = index.get((k[0] + o[0], k[1] + o[1], k[2] + o[2]))
            if nb is None:
                continue
            c, d = nb
            dist = np.linalg.norm(p[a:b, None] - p[None, c:d], axis=2)
            gap = np.abs(s[a:b, None] - s[None, c:d])
            gap = np.minimum(gap, total[a:b, None] - gap)
            same = (yarn[a:b, None] == yarn[None, c:d]) & (gap < exclude * r)
            dist[same] = np.inf
            best = min(best, float(dist.min()))
    return best / (2.0 * r)


def curl(world, fabric) -> dict:
    """Edge curl of a flat swatch relative to its mid-plane: the mean z of
    the head points in the outer course/wale of each edge minus that of
    the interior (m; + is towards the technical face, +z). Plain jersey
    curls its sides to the back (left, right < 0) and its top and bottom
    to the front (> 0)."""
    from ..errors import InvalidInputError
    h = fabric.heads(world)
    nc, nw = h.shape[:2]
    if nc < 3 or nw < 3 or fabric.tube_radius > 0:
        raise InvalidInputError(f"curl: a flat swatch of at least 3 × 3 stitches (edges and an interior), got {nw} × {nc}"
                                f"{' (a tube)' if fabric.tube_radius > 0 else ''}")
    inner = h[1:-1, 1:-1, 2].mean()
    return {"bottom": float(h[0, 1:-1, 2].mean() - inner), "top": float(h[-1, 1:-1, 2].mean() - inner),
            "left": float(h[1:-1, 0, 2].mean() - inner), "right": float(h[1:-1, -1, 2].mean() - inner)}
