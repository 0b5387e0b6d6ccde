"""Measures on a knit's yarn: dense points, the clearance between yarns
(is any yarn inside another?) and the edge curl of a swatch."""
from __future__ import annotations

import numpy as np

__all__ = ["yarn_points", "clearance", "curl", "Interlocks"]


def yarn_points(world, fabric, per_loop: int = 40, *, image: bool = False):
    """Points along every yarn now, about ``per_loop`` per stitch: a list
    of (n, 3) arrays (m), one per yarn (and with ``image`` the cell's
    image last)."""
    out = []
    rods = world.rods()
    chosen = rods[: len(np.unique(fabric.loops["rod"]))]
    if image and fabric.image is not None:
        chosen.append(rods[fabric.image])
    for rod in chosen:
        u0, u1 = rod.domain
        n = max(8, int(round(per_loop * rod.rest_length / fabric.loop_length)))
        out.append(rod.position(np.linspace(u0, u1, n, endpoint=not _rings(fabric))))
    return out


def _rings(fabric) -> bool:
    """Closed yarns: the tube's rings (the cell's spiral is open)."""
    return fabric.tube_radius > 0 and fabric.image is None


def clearance(world, fabric, *, exclude: float = 4.0) -> float:
    """Smallest distance between yarn centrelines over the yarn diameter
    2r, points closer than ``exclude`` radii along one yarn left out:
    ≥ 1 when no yarn enters another, < 0.5 only if one has passed through
    (the centreline of one inside the other); the cell's image counts (its
    first course holds the last), as one yarn with the yarn that runs on
    into it. A cell hash keeps it O(points)."""
    r = fabric.yarn_radius
    ring = _rings(fabric)
    lines = yarn_points(world, fabric, image=True)
    if fabric.image is not None:
        lines = [np.concatenate(lines)]
    pts, yarn, s, total = [], [], [], []
    for k, p in enumerate(lines):
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
    to the front (> 0). A swatch tilted as a whole moves opposite edges
    oppositely, a roll moves both the same way: ``sides`` = (left +
    right)/2 and ``ends`` = (top + bottom)/2 are the rolls with the tilt
    taken out."""
    from ..errors import InvalidInputError
    h = fabric.heads(world)
    nc, nw = h.shape[:2]
    if nc < 3 or nw < 3 or fabric.tube_radius > 0:
        raise InvalidInputError(f"curl: a flat swatch of at least 3 × 3 stitches (edges and an interior), got {nw} × {nc}"
                                f"{' (a tube)' if fabric.tube_radius > 0 else ''}")
    inner = h[1:-1, 1:-1, 2].mean()
    edge = {"bottom": float(h[0, 1:-1, 2].mean() - inner), "top": float(h[-1, 1:-1, 2].mean() - inner),
            "left": float(h[1:-1, 0, 2].mean() - inner), "right": float(h[1:-1, -1, 2].mean() - inner)}
    return {**edge, "sides": 0.5 * (edge["left"] + edge["right"]), "ends": 0.5 * (edge["top"] + edge["bottom"])}


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


def _crossings_of_fans(loops, arcs) -> np.ndarray:
    """For each k, how many segments of the polyline ``arcs[k]`` (m, 3)
    cross the fan of triangles spanning the closed polygon ``loops[k]``
    (n, 3) from its centroid (Möller–Trumbore, every segment against every
    triangle). loops (N, n, 3), arcs (N, m, 3); returns (N,) counts."""
    c = loops.mean(axis=1, keepdims=True)
    e1, e2 = loops - c, np.roll(loops, -1, axis=1) - c  # triangles (c, v0, v1)
    o, d = arcs[:, :-1], arcs[:, 1:] - arcs[:, :-1]
    pv = np.cross(d[:, :, None], e2[:, None])
    det = np.einsum("ntk,nstk->nst", e1, pv)
    ok = np.abs(det) > 1e-300  # a segment in the triangle's plane does not cross it
    inv = np.where(ok, 1.0 / np.where(ok, det, 1.0), 0.0)
    tv = o[:, :, None] - c[:, None]
    u = np.einsum("nstk,nstk->nst", tv, pv) * inv
    qv = np.cross(tv, e1[:, None])
    v = np.einsum("nsk,nstk->nst", d, qv) * inv
    t = np.einsum("ntk,nstk->nst", e2, qv) * inv
    hit = ok & (u >= 0) & (v >= 0) & (u + v <= 1) & (t >= 0) & (t < 1)
    return hit.sum(axis=(1, 2))


class Interlocks:
    """Every loop's interlock with the loop pulled through it, followed as
    the yarn slides (``relax`` keeps one; ``Relaxed.interlocks``).

    A loop U pulled through the loop L below crosses it four times (its
    legs in front of L's head, its sinkers behind L's legs, or the other
    way round). They are found once, where the projections of L and U on
    L's own plane cross, each kept as a pair of yarn abscissae. Each
    :meth:`update` follows every crossing to the nearest pair of points
    by a damped Gauss–Newton descent (the yarn slides through loops, so
    abscissae are not material marks of a loop), then asks whether U's
    yarn about its crossings still passes through L: whether the arc of
    U crosses a surface spanning the arc of L (a fan of triangles from its
    centroid, the arc closed by its chord), both arcs reaching a sixth of
    a loop beyond the outermost crossings. Held, U pierces it once or
    twice; a loop that came out of the one below, or that lies wholly on
    one side of it, not at all. (Counting the crossings instead fails:
    where yarns wrap round each other, as in a tight rib, two tracked
    crossings slide into one contact and the loops still hold.) Call
    :meth:`update` often enough that no yarn slides a sixth of a loop
    between calls (``relax`` does every 10 steps: at most 2.5 radii at
    its default step cap)."""

    def __init__(self, world, fabric, *, samples: int = 60):
        self.fabric = fabric
        rods = world.rods()
        lp = fabric.loops
        nw, nc = fabric.wales, fabric.courses
        # A periodic cell's last course holds the image of its first.
        cell = fabric.image is not None
        self.shape = (nc if cell else nc - 1, nw)
        rows = []  # (interlock, rod L, u L, rod U, u U)
        for j in range(self.shape[0]):
            for i in range(nw):
                lo, up = lp[j * nw + i], lp[((j + 1) % nc) * nw + i]
                up_rod = fabric.image if j + 1 == nc else int(up["rod"])
                rl, ru = rods[int(lo["rod"])], rods[up_rod]
                ua = np.linspace(lo["u_start"], lo["u_end"], samples)
                ub = np.linspace(up["u_start"], up["u_end"], samples)
                a, b = rl.position(ua), ru.position(ub)
                head, feet = a[samples // 2], 0.5 * (a[0] + a[-1])
                ey = (head - feet) / np.linalg.norm(head - feet)
                ex = a[-1] - a[0]
                ex = ex - ey * (ex @ ey)
                ex /= np.linalg.norm(ex)
                plane = lambda x: np.stack([x @ ex, x @ ey], axis=1)  # noqa: E731
                ia, t, ib, u = _projected_crossings(plane(a), plane(b))
                sa = ua[ia] + t * (ua[ia + 1] - ua[ia])
                sb = ub[ib] + u * (ub[ib + 1] - ub[ib])
                for k in range(len(sa)):
                    rows.append((j * nw + i, int(lo["rod"]), sa[k], up_rod, sb[k]))
        arr = np.array(rows, dtype=float).reshape(-1, 5)
        self.owner = arr[:, 0].astype(int)
        self.rod_a, self.rod_b = arr[:, 1].astype(int), arr[:, 3].astype(int)
        self.u_a, self.u_b = arr[:, 2].copy(), arr[:, 4].copy()
        # Per crossing, on each yarn: a descent's move (a 24th of a loop in
        # abscissa) and the domain an open yarn's abscissae stay in (a
        # tube's rings wrap round).
        per_loop = {int(r): fabric.loop_length / 24.0 * (rods[int(r)].domain[1] - rods[int(r)].domain[0])
                    / rods[int(r)].rest_length for r in np.unique(np.concatenate([lp["rod"], self.rod_b]))}
        ring = _rings(fabric)
        dom = {r: (-np.inf, np.inf) if ring else rods[r].domain for r in per_loop}
        self._wa, self._wb = (np.array([per_loop[int(r)] for r in x]) for x in (self.rod_a, self.rod_b))
        self._lo_a, self._hi_a = (np.array([dom[int(r)][e] for r in self.rod_a]) for e in (0, 1))
        self._lo_b, self._hi_b = (np.array([dom[int(r)][e] for r in self.rod_b]) for e in (0, 1))
        self.held = self._pierced(rods)
        self.ever_parted = ~self.held

    def _pierced(self, rods, samples: int = 48) -> np.ndarray:
        """Whether U's yarn passes through L's loop: the arc of U about its
        crossings with L against a surface spanning L's arc about them
        (closed by its chord; a fan of triangles from its centroid). Both
        arcs run a sixth of a loop beyond the outermost crossings, so they
        follow the yarn as it slides. A loop through the one below pierces
        it once or twice (in behind a leg, out in front of the head); one
        that came out, or lies on one side, not at all."""
        n = self.shape[0] * self.shape[1]
        first = np.full(n, -1)
        first[self.owner[::-1]] = np.arange(len(self.owner))[::-1]  # a crossing of each interlock
        lo_a, hi_a = np.full(n, np.inf), np.full(n, -np.inf)
        lo_b, hi_b = np.full(n, np.inf), np.full(n, -np.inf)
        np.minimum.at(lo_a, self.owner, self.u_a), np.maximum.at(hi_a, self.owner, self.u_a)
        np.minimum.at(lo_b, self.owner, self.u_b), np.maximum.at(hi_b, self.owner, self.u_b)
        some = np.nonzero(first >= 0)[0]
        k = first[some]
        g = np.linspace(0.0, 1.0, samples)
        # Each arc a sixth of a loop (4 descent moves) beyond its outermost crossings.
        pad_a, pad_b = 4.0 * self._wa[k], 4.0 * self._wb[k]
        ua = (lo_a[some] - pad_a)[:, None] + (hi_a[some] - lo_a[some] + 2 * pad_a)[:, None] * g
        ub = (lo_b[some] - pad_b)[:, None] + (hi_b[some] - lo_b[some] + 2 * pad_b)[:, None] * g
        loops = self._positions(rods, self.rod_a[k], self._clip(ua, self._lo_a[k], self._hi_a[k]))
        arcs = self._positions(rods, self.rod_b[k], self._clip(ub, self._lo_b[k], self._hi_b[k]))
        held = np.zeros(n, dtype=bool)
        held[some] = _crossings_of_fans(loops, arcs) > 0
        return held.reshape(self.shape)

    @staticmethod
    def _positions(rods, which, u, derivative: int = 0):
        """Points (..., 3) of the yarns ``which`` (one per row of u) at u,
        or their u-derivative dp/du (m per unit abscissa)."""
        out = np.empty(u.shape + (3,))
        for r in np.unique(which):
            sel = which == r
            uu = u[sel].ravel()
            p = rods[int(r)].position(uu) if derivative == 0 else rods[int(r)].eval(uu, derivative=derivative)[:, :3]
            out[sel] = p.reshape(u[sel].shape + (3,))
        return out

    @staticmethod
    def _clip(u, lo, hi):
        """u (one row per crossing) kept in its yarn's domain."""
        shape = (-1,) + (1,) * (u.ndim - 1)
        return np.clip(u, lo.reshape(shape), hi.reshape(shape))

    def update(self, world) -> np.ndarray:
        """Follow every crossing in ``world`` now; returns ``held``, a
        (courses − 1, wales) boolean array (a periodic cell: (courses,
        wales), the last course's with the image of the first): loop
        (i, j)'s interlock with loop (i, j + 1) at [j, i]. ``ever_parted``
        accumulates."""
        rods = world.rods()
        wa, wb = self._wa, self._wb
        ua, ub = self.u_a.copy(), self.u_b.copy()
        # Gauss–Newton on the closest points of the two centrelines from
        # where the crossing was (the nearest pair of the tangent lines),
        # each move at most a 24th of a loop along either yarn and halved
        # until the distance falls: a descent to the crossing's own minimum,
        # never across a barrier to the next crossing (a search of a window
        # jumps there: in contact, all lie 2r apart), nor to a saddle.
        pa, pb = self._positions(rods, self.rod_a, ua), self._positions(rods, self.rod_b, ub)
        dist = np.linalg.norm(pa - pb, axis=1)
        for _ in range(12):
            da, db = self._positions(rods, self.rod_a, ua, 1), self._positions(rods, self.rod_b, ub, 1)
            e = pa - pb
            aa, bb, ab = (np.einsum("ij,ij->i", x, y) for x, y in ((da, da), (db, db), (da, db)))
            ra, rb = -np.einsum("ij,ij->i", da, e), np.einsum("ij,ij->i", db, e)
            det = aa * bb - ab * ab
            ok = det > 1e-12 * aa * bb
            safe = np.where(ok, det, 1.0)
            step_a = np.clip(np.where(ok, (bb * ra + ab * rb) / safe, 0.0), -wa, wa)
            step_b = np.clip(np.where(ok, (ab * ra + aa * rb) / safe, 0.0), -wb, wb)
            todo = np.ones(len(ua), dtype=bool)
            for _ in range(6):
                na = self._clip(ua + step_a, self._lo_a, self._hi_a)
                nb = self._clip(ub + step_b, self._lo_b, self._hi_b)
                qa, qb = self._positions(rods, self.rod_a, na), self._positions(rods, self.rod_b, nb)
                nd = np.linalg.norm(qa - qb, axis=1)
                better = todo & (nd < dist)
                ua, ub, dist = np.where(better, na, ua), np.where(better, nb, ub), np.where(better, nd, dist)
                pa[better], pb[better] = qa[better], qb[better]
                todo &= ~better
                if not todo.any():
                    break
                step_a, step_b = 0.5 * step_a, 0.5 * step_b
        self.u_a, self.u_b = ua, ub
        self.held = self._pierced(rods)
        self.ever_parted |= ~self.held
        return self.held

    def copy(self) -> "Interlocks":
        """An independent copy (to follow another world made from the
        same state, e.g. a stretch of a relaxed swatch)."""
        import copy
        out = copy.copy(self)
        for k in ("u_a", "u_b", "held", "ever_parted"):
            setattr(out, k, getattr(self, k).copy())
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
