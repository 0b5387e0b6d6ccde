"""Weft-knit fabrics at the yarn level (SPEC §9.3).

>>> import strandkit as sk
>>> f = sk.knit.fabric("jersey", wales=6, courses=6, loop_length=5e-3,
...                    yarn="nylon", yarn_radius=1e-4)
>>> f
Fabric(jersey 6 × 6 stitches, loop_length=5 mm, nylon yarn r=0.1 mm, continuous, free)
>>> world = f.world(friction=0.3)           # contact on, yarn held by nothing else
>>> f.dimensions(world)["k_c"]               # doctest: +SKIP

Every length is in metres, forces in newtons. The fabric lies in the
(x, y) plane: x along the course (wales side by side), y along the wale
(courses stacked, cast-on at the bottom), z out of the technical face
(the side the knit stitches' legs show on). A knit stitch pulls its loop
through the loop below towards +z, a purl towards −z.

The yarn is a naturally straight rod (``straight_rest``) wound along a
harmonic loop model; the loops are held together only by yarn–yarn
contact (``World.contact``), so yarn slides through loops. Experiments
(relax, stretch, curl) are in :mod:`strandkit.knit.experiments`.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Optional, Sequence, Union

import numpy as np

from .. import _native

__all__ = ["YARNS", "PATTERNS", "Fabric", "fabric", "MUNDEN"]


def _check(name, x, low=0.0, integer=False, inclusive=False):
    """x as a float (or int) > low (≥ low if ``inclusive``), else
    InvalidInputError naming it."""
    from ..errors import InvalidInputError

    try:
        ok = not isinstance(x, bool) and bool(np.isfinite(x)) and (x >= low if inclusive else x > low)
        ok = ok and (not integer or int(x) == x)
    except (TypeError, ValueError):
        ok = False
    if not ok:
        raise InvalidInputError(f"{name}: {'an integer' if integer else 'a finite number'} {'≥' if inclusive else '>'} {low:g}, "
                                f"got {x!r}")
    return int(x) if integer else float(x)


#: Fibre values of the yarn presets (SPEC §9.3): density kg/m³, Young's
#: modulus Pa (nylon 6,6 "< 5 GPa": 3 GPa; aramid 70–135: 100 GPa).
YARNS = {
    "cotton": {"density": 1540.0, "young": 8e9},
    "wool": {"density": 1300.0, "young": 2e9},
    "polyester": {"density": 1380.0, "young": 15e9},
    "nylon": {"density": 1140.0, "young": 3e9},
    "aramid": {"density": 1450.0, "young": 100e9},
}

PATTERNS = ("jersey", "rib1x1", "rib2x2", "garter", "seed")

#: Munden's constants for plain jersey (k_c = courses/cm × l, k_w =
#: wales/cm × l, k_s = k_c k_w, l in cm): fully, dry and wet relaxed.
MUNDEN = {
    "full": {"k_c": 5.5, "k_w": 4.2, "k_s": 23.1},
    "dry": {"k_c": 5.0, "k_w": 3.8, "k_s": 19.0},
    "wet": {"k_c": 5.3, "k_w": 4.1, "k_s": 21.6},
}


@dataclass(frozen=True)
class Fabric:
    """A built fabric: the assembly to insert, its stitch grid and where
    each loop lies on its yarn.

    ``rows``: the stitch grid, bottom course first ('K'/'P');
    ``loops``: structured array (course-major, loop (i, j) at j·wales + i)
    with fields ``wale``, ``course``, ``rod`` (index into the inserted
    rods), ``u_start``, ``u_head``, ``u_end`` (abscissae of the sinker
    before it, its head, its end); ``model``: the loop model's initial
    wale_spacing, course_spacing, loop_height, overhang and depth (m);
    ``clearance``: smallest centreline distance over 2r as built;
    ``loop_length``: the built yarn length per stitch (m, within 1e-4 of
    the one asked for); ``bind_off``, ``cast_on``, ``selvedge``,
    ``yarn_ends``, ``clamps``: the assembly's constraint indices of each
    edge's links (see :func:`fabric`); ``image``: the cell boundary's
    image rod (the yarn one period up; None otherwise), ``image_ties`` its
    ``EqualOffsets`` ties and ``junction`` the yarn end's ties to the
    image's start (position, tangent); ``contact_stiffness``: the
    distributed contact rows' stiffness per length (N/m²; None: one rigid
    row per place of contact), see :func:`fabric`."""

    assembly: object
    rows: tuple
    loops: np.ndarray
    model: dict
    loop_length: float
    yarn: str
    yarn_radius: float
    bending_stiffness: float
    continuous: bool
    boundary: str
    clearance: float
    bind_off: tuple
    clamps: tuple
    tube_radius: float
    params: dict = field(default_factory=dict)
    cast_on: tuple = ()
    selvedge: tuple = ()
    yarn_ends: tuple = ()
    image: Optional[int] = None
    image_ties: tuple = ()
    junction: tuple = ()
    contact_stiffness: Optional[float] = None

    @property
    def wales(self) -> int:
        return len(self.rows[0])

    @property
    def courses(self) -> int:
        return len(self.rows)

    @property
    def pattern(self) -> str:
        return self.params.get("pattern") or "custom"

    def __repr__(self) -> str:
        return (f"Fabric({self.pattern} {self.wales} × {self.courses} stitches, "
                f"loop_length={self.params.get('loop_length', self.loop_length) * 1e3:.4g} mm, {self.yarn} yarn r={self.yarn_radius * 1e3:.4g} mm, "
                f"{'continuous' if self.continuous else 'one yarn per course'}, {self.boundary}"
                f"{'' if self.contact_stiffness is None else f', distributed contact k={self.contact_stiffness:.3g} N/m²'})")

    def world(self, *, friction: float = 0.3, margin: Optional[float] = None, **params):
        """A new World (gravity off unless given in ``params``) with this
        fabric inserted and yarn–yarn contact on (rows as
        ``contact_stiffness`` says, see :func:`fabric`): Coulomb
        ``friction`` μ (dimensionless), detection ``margin`` (m, default
        half the yarn radius). Steps that would move the yarn farther than
        the margin are refused (``max_move``, so no yarn passes through
        another between two detections; the relaxation retries them
        shorter). Other keywords are World parameters."""
        from .. import World

        margin = 0.5 * self.yarn_radius if margin is None else margin
        params.setdefault("gravity", (0.0, 0.0, 0.0))
        w = World(**params)
        w.insert(self.assembly)
        self.set_contact(w, friction=friction, margin=margin)
        if "max_move" not in params:
            w.set_params(max_move=margin)
        return w

    def set_contact(self, world, *, friction: float, margin: Optional[float] = None) -> None:
        """(Re)sets yarn–yarn contact in ``world`` (made by :meth:`world`):
        Coulomb ``friction`` μ (dimensionless), detection ``margin`` (m,
        default half the yarn radius), rows as the fabric's
        ``contact_stiffness`` says. Replaces the world's contact
        detectors, so a relaxed fabric can be stretched with another μ."""
        from ..errors import InvalidInputError

        # Checked before the world's contact is cleared: a refusal leaves it as it was.
        friction = _check("friction", friction, inclusive=True)
        margin = _check("margin", 0.5 * self.yarn_radius if margin is None else margin)
        if self.image is not None and len(world.rods()) <= self.image:
            raise InvalidInputError("world: a world made by this fabric's world()")
        world.clear_contact()
        if self.image is None:
            world.contact(margin=margin, friction=friction, self_contact=True, between_rods=True,
                          line_stiffness=self.contact_stiffness)
        else:
            # The image repeats the yarn's own contacts; the yarn runs on
            # into it at the junction.
            yarn, image = world.rods()[int(self.loops["rod"][0])], world.rods()[self.image]
            world.contact(margin=margin, friction=friction, self_contact=True, between_rods=True,
                          no_self_contact=[image], joined=[(yarn, image)], line_stiffness=self.contact_stiffness)

    def heads(self, world) -> np.ndarray:
        """Positions of the loops' heads now, shape (courses, wales, 3) (m)."""
        rods = world.rods()
        out = np.empty((len(self.loops), 3))
        for r in np.unique(self.loops["rod"]):
            sel = self.loops["rod"] == r
            out[sel] = rods[int(r)].position(self.loops["u_head"][sel])
        return out.reshape(self.courses, self.wales, 3)

    def dimensions(self, world, *, margin: int = 1) -> dict:
        """Stitch dimensions now, from the heads of loops at least
        ``margin`` stitches from every edge (less on a swatch too small to
        leave two heads each way): ``wale_spacing`` w and
        ``course_spacing`` c (m, mean distances between neighbouring
        heads, measured in space so a curled swatch is measured along
        itself), ``wales_per_cm``, ``courses_per_cm``, ``stitch_density``
        (stitches/cm²), and Munden's ``k_w`` = w⁻¹·l, ``k_c``, ``k_s`` (l in
        cm, as Munden's constants). A cell has no edge: every head counts
        (``margin`` is not used), the last course's against the image's
        first, and w is measured head to head along the spiral."""
        from ..errors import InvalidInputError
        if isinstance(margin, bool) or not isinstance(margin, (int, np.integer)) or margin < 0:
            raise InvalidInputError(f"margin: a number of stitches ≥ 0, got {margin!r}")
        h = self.heads(world)
        nc, nw = self.courses, self.wales
        if self.image is not None:
            # The cell has no edge: every course, and the last against the
            # image of the first.
            up = world.rods()[self.image].position(self.loops["u_head"][:nw])
            h = np.concatenate([h, up[None]], axis=0)
            margin, nc = 0, nc + 1
        # At most the margin that leaves two heads each way to measure.
        limit = (nc - 2) // 2 if self.tube_radius > 0 else (min(nc, nw) - 2) // 2  # a ring has no side edges
        m = min(int(margin), limit)
        rows = slice(m, max(nc - m, m + 1))
        cols = slice(m, max(nw - m, m + 1))
        if self.image is not None:
            # Head to head along the spiral, the last into the image's first.
            w = np.linalg.norm(np.diff(h.reshape(-1, 3), axis=0), axis=1)[:self.courses * nw].mean()
        elif self.tube_radius > 0:
            ring = np.roll(h, -1, axis=1) - h
            w = np.linalg.norm(ring[rows], axis=2).mean()
        else:
            dw = np.linalg.norm(np.diff(h, axis=1), axis=2)[rows, m:max(nw - m - 1, m + 1)]
            w = dw.mean()
        dc = np.linalg.norm(np.diff(h, axis=0), axis=2)[m:max(nc - m - 1, m + 1), cols]
        c = dc.mean()
        w, c = float(w), float(c)
        l_cm = self.loop_length * 100.0
        wpc, cpc = 0.01 / w, 0.01 / c
        return {"wale_spacing": w, "course_spacing": c, "wales_per_cm": wpc, "courses_per_cm": cpc,
                "stitch_density": wpc * cpc, "k_w": wpc * l_cm, "k_c": cpc * l_cm, "k_s": wpc * cpc * l_cm ** 2}


def fabric(pattern: Union[str, Sequence[str]] = "jersey", *, wales: int = 10, courses: int = 10,
           loop_length: float = 5e-3, yarn: str = "nylon", yarn_radius: float = 1e-4,
           bending_stiffness: Optional[float] = None, continuous: Optional[bool] = None,
           boundary: str = "free", spacing: Optional[Sequence[float]] = None,
           control_points_per_loop: int = 12, bind_off: bool = True, cast_on: bool = True,
           selvedge: bool = True, fasten_ends: bool = True,
           contact_stiffness: Union[float, str, None] = None) -> Fabric:
    """A weft-knit fabric (SPEC §9.3).

    pattern: "jersey", "rib1x1", "rib2x2", "garter", "seed", or a custom
    stitch grid — a list of strings, one per course, bottom course first,
    'K' (knit) or 'P' (purl) per stitch (then ``wales``/``courses`` come
    from the grid); wales, courses: stitches across and along;
    loop_length: yarn length per stitch ℓ (m); yarn: preset ("cotton",
    "wool", "polyester", "nylon", "aramid"; fibre values in ``YARNS``);
    yarn_radius: m (the contact radius); bending_stiffness: measured yarn
    B (N·m²) overriding the solid-rod value E·πr⁴/4 (the modulus becomes
    B/I, so EA = 4B/r² follows); continuous: one yarn turning round at the
    sides (default for flat swatches) or one yarn per course (with free
    tails); boundary: "free", "periodic" (a tube knitted in the round,
    one ring per course), "cell" (periodic both ways, no edge: one yarn
    spiralling round a tube, a course a turn, whose end runs on into its
    image one period up, tied to be the yarn translated by a free vector;
    yarn and image carry half the modulus and density each, and the
    period along the wale is the equilibrium's) or "clamped_edges" (cast-on sinkers and bound-off
    heads held where built: groups ``bottom_edge``, ``top_edge``);
    spacing: initial (wale spacing, course spacing) in m (default: the
    loop model's proportions w : c = 4 : 3 scaled to ℓ);
    control_points_per_loop: spline control points per stitch;
    Edges (each a set of distance links between points of the yarn as
    built; a plain jersey unravels from any open edge — frictionless, under
    its own curl):
    bind_off: tie the last course's heads to their neighbours (group
    ``bindoff``) so its loops cannot run back; cast_on: tie the first
    course's neighbouring sinkers (group ``caston``, the chain a cast-on
    knits its first loops through); selvedge: tie the two ends of each
    turn of a continuous yarn at the sides (group ``selvedge``);
    fasten_ends: tie each free yarn end to the head of the loop it begins
    or ends (group ``yarn_end``). A tube has no sides and no ends; clamped
    edges hold the first sinkers and last heads instead of cast-on and
    bind-off links.
    contact_stiffness: how the worlds of :meth:`Fabric.world` hold the
    yarns apart. None (default): one rigid row where two yarns come
    closest. A stiffness k (N/m², per length of contact) or "yarn"
    (k = E/2, E = B/I the yarn's modulus): distributed rows
    (``World.contact(line_stiffness=k)``), a penalty row at every sample
    of a yarn near another, two yarns pressed side by side with q (N/m)
    sinking by q/k — the yarn's own transverse give (a monofilament's
    Hertz line contact is softer, about E/7 at a knit's loads; a
    multifilament yarn softer still). Where a loop's head wraps round the
    leg above it, the rigid row moves wherever the last step pressed
    deepest and a relaxation's steps alternate; distributed rows hold the
    whole wrap, and a 16 × 4 cell relaxes in 270 steps where rigid rows
    had not settled after 400 (README, knitted fabrics). Their friction
    is a spring per row trimmed to μ N each step: within μ N at rest,
    above it while a step slides (README).

    Errors (``InvalidInputError``, before anything is built): a grid that
    cannot be knitted (ragged courses, letters other than K/P, zero wales,
    fewer than 2 courses), a loop too short for the yarn radius (the yarns
    would overlap in the initial path), non-finite or negative sizes,
    absurd sizes (over 200 000 stitches or 4 million control points).
    """
    from ..errors import InvalidInputError

    rows = None
    if isinstance(pattern, str):
        name = pattern
    else:
        rows = [str(r) for r in pattern]
        name = None
    if continuous is None:
        continuous = boundary != "periodic"
    if spacing is not None:
        try:
            spacing = [float(x) for x in spacing]
        except (TypeError, ValueError):
            raise InvalidInputError(f"spacing: (wale spacing, course spacing) in m, got {spacing!r}") from None
        if len(spacing) != 2:
            raise InvalidInputError(f"spacing: give (wale spacing, course spacing) in m, got {len(spacing)} values")
    for k, v in (("wales", wales), ("courses", courses), ("control_points_per_loop", control_points_per_loop)):
        if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or not 0 <= v <= 10 ** 9:
            raise InvalidInputError(f"{k}: an integer from 0 to 1e9, got {v!r}")
    for k, v in (("loop_length", loop_length), ("yarn_radius", yarn_radius)):
        if isinstance(v, bool) or not isinstance(v, (int, float, np.floating, np.integer)):
            raise InvalidInputError(f"{k}: a length in m, got {v!r}")
    if isinstance(contact_stiffness, str):
        if contact_stiffness != "yarn":
            raise InvalidInputError(f"contact_stiffness: a stiffness (N/m²), \"yarn\" or None, got {contact_stiffness!r}")
    elif contact_stiffness is not None:
        contact_stiffness = _check("contact_stiffness", contact_stiffness)
    asm, d = _native.build_knit_fabric(
        pattern=name or "jersey", rows=rows, wales=int(wales), courses=int(courses), loop_length=float(loop_length),
        yarn=str(yarn), yarn_radius=float(yarn_radius),
        bending_stiffness=None if bending_stiffness is None else float(bending_stiffness),
        continuous=bool(continuous), boundary=str(boundary), spacing=spacing,
        control_points_per_loop=int(control_points_per_loop), bind_off=bool(bind_off),
        cast_on=bool(cast_on), selvedge=bool(selvedge), fasten_ends=bool(fasten_ends))
    loops = np.zeros(len(d["loop_wale"]), dtype=[("wale", "i8"), ("course", "i8"), ("rod", "i8"),
                                                  ("u_start", "f8"), ("u_head", "f8"), ("u_end", "f8")])
    for k in loops.dtype.names:
        loops[k] = d["loop_" + k]
    params = dict(pattern=name, wales=int(wales), courses=int(courses), loop_length=float(loop_length), yarn=yarn,
                  yarn_radius=float(yarn_radius), bending_stiffness=bending_stiffness, continuous=bool(continuous),
                  boundary=boundary, spacing=spacing, control_points_per_loop=int(control_points_per_loop),
                  bind_off=bool(bind_off), cast_on=bool(cast_on), selvedge=bool(selvedge),
                  fasten_ends=bool(fasten_ends), contact_stiffness=contact_stiffness)
    if contact_stiffness == "yarn":
        # E/2 of the yarn's modulus E = B/I (B as built: a preset's or the override).
        contact_stiffness = 0.5 * float(d["bending_stiffness"]) / (np.pi * float(yarn_radius) ** 4 / 4.0)
    return Fabric(assembly=asm, rows=tuple(d["rows"]), loops=loops, model=dict(d["model"]),
                  loop_length=float(d["loop_length"]), yarn=d["yarn"], yarn_radius=float(yarn_radius),
                  bending_stiffness=float(d["bending_stiffness"]), continuous=bool(continuous), boundary=boundary,
                  clearance=float(d["clearance"]), bind_off=tuple(d["bind_off"]), clamps=tuple(d["clamps"]),
                  tube_radius=float(d["tube_radius"]), params=params, cast_on=tuple(d["cast_on"]),
                  selvedge=tuple(d["selvedge"]), yarn_ends=tuple(d["yarn_ends"]), image=d["image"],
                  image_ties=tuple(d["image_ties"]), junction=tuple(d["junction"]),
                  contact_stiffness=contact_stiffness)
