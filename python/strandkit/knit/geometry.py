"""Measures on a knit's yarn: dense points, the clearance between yarns
(is any yarn inside another?) and the edge curl of a swatch."""
from __future__ import annotations

import numpy as np

__all__ = ["yarn_points", "clearance", "curl", "Interlocks"]


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


def _projected_crossings(a, b):
    """Crossings of the 2-D polylines a (n, 2) and b (m, 2): indices of the
    segments (i in a, j in b) and the fractions along them (t, u)."""
    p, r = a[:-1, None], (a[1:] - a[:-1])[:, None]
    q, s = b[None, :-1], (b[1:] - b[:-1])[None]
    den = r[..., 0] * s[..., 1] - r[..., 1] * s[..., 0]
    qp = q - p
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (qp[..., 0] * s[..., 1] - qp[..., 1] * s[..., 0]) / den
        u = (qp[..., 0] * r[..., 1] - qp[..., 1] * r[..., 0]) / den
    i, j = np.nonzero((den != 0) & (t >= 0) & (t < 1) & (u >= 0) & (u < 1))
    return i, t[i, j], j, u[i, j]


class Interlocks:
    """Every loop's interlock with the loop pulled through it, tracked as
    the yarn slides (``relax`` keeps one; ``Relaxed.interlocks``).

    A loop U pulled through the loop L below crosses it four times: U's
    legs pass in front of L's head on U's stitch side and U's sinkers
    behind L's legs the other way (the loop model's crossings). They are
    found once, as the projections of L and U on L's own plane cross, each
    kept as a pair of yarn abscissae and its handedness det[t_L, t_U,
    p_U − p_L] (which side of L U passes, independent of any frame). Each
    :meth:`update` follows every crossing downhill to the nearest pair of
    points, in four moves of up to a 24th of a loop along each yarn (the
    yarn slides through loops, so abscissae are not material marks of a
    loop; a search of a whole window would jump to the next crossing). A
    crossing is lost when its yarns are more than two diameters apart
    there, when its handedness flips (U slipped round L) or when two
    crossings of one interlock meet (U's legs slid off L's head, or its
    sinker off L's leg). An interlock holds while it keeps a crossing of
    each side: a loop that came out of the one below, or that lies wholly
    on one side of it, has none on the other. Call :meth:`update` often
    enough that no yarn slides a sixth of a loop between calls (``relax``
    does every 10 steps: at most 2.5 radii at its default step cap). A
    tube's abscissae wrap round, so two crossings either side of a ring's
    seam are not seen to meet."""

    def __init__(self, world, fabric, *, samples: int = 60):
        self.fabric = fabric
        rods = world.rods()
        lp = fabric.loops
        nw, nc = fabric.wales, fabric.courses
        self.shape = (nc - 1, nw)
        rows = []  # (interlock, rod L, u L, rod U, u U, handedness, side: +1 U in front of L along L's normal)
        for j in range(nc - 1):
            for i in range(nw):
                lo, up = lp[j * nw + i], lp[(j + 1) * nw + i]
                rl, ru = rods[int(lo["rod"])], rods[int(up["rod"])]
                ua = np.linspace(lo["u_start"], lo["u_end"], samples)
                ub = np.linspace(up["u_start"], up["u_end"], samples)
                a, b = rl.position(ua), ru.position(ub)
                head, feet = a[samples // 2], 0.5 * (a[0] + a[-1])
                ey = (head - feet) / np.linalg.norm(head - feet)
                ex = a[-1] - a[0]
                ex = ex - ey * (ex @ ey)
                ex /= np.linalg.norm(ex)
                n = np.cross(ex, ey)
                plane = lambda x: np.stack([x @ ex, x @ ey], axis=1)  # noqa: E731
                ia, t, ib, u = _projected_crossings(plane(a), plane(b))
                sa = ua[ia] + t * (ua[ia + 1] - ua[ia])
                sb = ub[ib] + u * (ub[ib + 1] - ub[ib])
                pa, pb = rl.position(sa), ru.position(sb)
                ta, tb = rl.tangent(sa), ru.tangent(sb)
                hand = np.sign(np.einsum("ij,ij->i", np.cross(ta, tb), pb - pa))
                side = np.sign((pb - pa) @ n)
                for k in range(len(sa)):
                    rows.append((j * nw + i, int(lo["rod"]), sa[k], int(up["rod"]), sb[k], hand[k], side[k]))
        arr = np.array(rows, dtype=float).reshape(-1, 7)
        self.owner = arr[:, 0].astype(int)
        self.rod_a, self.rod_b = arr[:, 1].astype(int), arr[:, 3].astype(int)
        self.u_a, self.u_b = arr[:, 2].copy(), arr[:, 4].copy()
        self.hand, self.side = arr[:, 5], arr[:, 6]
        # Abscissa per loop: a 24th of a loop is a descent's move.
        self._window = {int(r): fabric.loop_length / 24.0 * (rods[int(r)].domain[1] - rods[int(r)].domain[0])
                        / rods[int(r)].rest_length for r in np.unique(lp["rod"])}
        self.present = np.ones(len(self.owner), dtype=bool)
        self.held = self._held()
        self.ever_parted = ~self.held

    def _held(self) -> np.ndarray:
        n = self.shape[0] * self.shape[1]
        front = np.bincount(self.owner, weights=(self.present & (self.side > 0)), minlength=n)
        back = np.bincount(self.owner, weights=(self.present & (self.side < 0)), minlength=n)
        return ((front > 0) & (back > 0)).reshape(self.shape)

    @staticmethod
    def _positions(rods, which, u):
        """Points (..., 3) of the yarns ``which`` (one per row of u) at u."""
        out = np.empty(u.shape + (3,))
        for r in np.unique(which):
            sel = which == r
            uu = u[sel]
            out[sel] = rods[int(r)].position(uu.ravel()).reshape(uu.shape + (3,))
        return out

    def _clip(self, rods, which, u):
        """u kept in each open yarn's domain (a tube's rings wrap round)."""
        if self.fabric.tube_radius > 0:
            return u
        lo = np.array([rods[int(r)].domain[0] for r in which]).reshape((-1,) + (1,) * (u.ndim - 1))
        hi = np.array([rods[int(r)].domain[1] for r in which]).reshape((-1,) + (1,) * (u.ndim - 1))
        return np.clip(u, lo, hi)

    def update(self, world) -> np.ndarray:
        """Follow every crossing in ``world`` now; returns ``held``, a
        (courses − 1, wales) boolean array: loop (i, j)'s interlock with
        loop (i, j + 1) at [j, i]. ``ever_parted`` accumulates."""
        rods = world.rods()
        wa = np.array([self._window[int(r)] for r in self.rod_a])
        wb = np.array([self._window[int(r)] for r in self.rod_b])
        g = np.linspace(-1.0, 1.0, 9)
        ua, ub = self.u_a, self.u_b
        rows = np.arange(len(ua))
        # A local descent, not a search of the window: another crossing
        # a few radii along would capture a window's minimum. Four moves
        # of up to a 24th of a loop, then one of a 192nd.
        for shrink in (1.0, 1.0, 1.0, 1.0, 0.125):
            sa = self._clip(rods, self.rod_a, ua[:, None] + shrink * wa[:, None] * g)
            sb = self._clip(rods, self.rod_b, ub[:, None] + shrink * wb[:, None] * g)
            pa, pb = self._positions(rods, self.rod_a, sa), self._positions(rods, self.rod_b, sb)
            d = np.linalg.norm(pa[:, :, None] - pb[:, None, :], axis=3)
            ka, kb = np.divmod(d.reshape(len(d), -1).argmin(axis=1), len(g))
            ua, ub = sa[rows, ka], sb[rows, kb]
        dist = d[rows, ka, kb]
        ua, ub = self._clip(rods, self.rod_a, ua), self._clip(rods, self.rod_b, ub)
        self.u_a, self.u_b = ua, ub
        pa, pb = self._positions(rods, self.rod_a, ua), self._positions(rods, self.rod_b, ub)
        ta, tb = self._tangents(rods, self.rod_a, ua), self._tangents(rods, self.rod_b, ub)
        hand = np.sign(np.einsum("ij,ij->i", np.cross(ta, tb), pb - pa))
        present = (dist <= 4.0 * self.fabric.yarn_radius) & (hand == self.hand)
        # Two crossings that met are gone: U's legs slid off L's head, or
        # its sinker off L's leg.
        for o in np.unique(self.owner):
            idx = np.nonzero(self.owner == o)[0]
            for x in range(len(idx)):
                for y in range(x + 1, len(idx)):
                    p, q = idx[x], idx[y]
                    if abs(ua[p] - ua[q]) < 0.25 * wa[p] and abs(ub[p] - ub[q]) < 0.25 * wb[p]:
                        present[p] = present[q] = False
        self.present = present
        self.held = self._held()
        self.ever_parted |= ~self.held
        return self.held

    def _tangents(self, rods, which, u):
        out = np.empty(u.shape + (3,))
        for r in np.unique(which):
            sel = which == r
            out[sel] = rods[int(r)].tangent(u[sel])
        return out

    @property
    def parted(self) -> list:
        """(wale, course) of the loops whose interlock with the loop above
        has come apart at some update."""
        j, i = np.nonzero(self.ever_parted)
        return [(int(a), int(b)) for a, b in zip(i, j)]

    def __repr__(self) -> str:
        return (f"Interlocks({self.held.sum()} of {self.held.size} holding, "
                f"{int(self.ever_parted.sum())} parted at some update)")
