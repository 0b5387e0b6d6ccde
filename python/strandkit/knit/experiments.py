"""Knit experiments (SPEC §9.3): dry relaxation to equilibrium, uniaxial
stretch along the course or the wale, edge curl.

The fabric is relaxed by overdamped (Brownian, T = 0) dynamics — every
yarn moves at drag⁻¹ × its net force, a gradient flow of the elastic
energy under the contacts — with implicit Euler steps whose length adapts
after each step towards moving the farthest control point by
``step_fraction`` yarn radii. A step carrying a yarn farther than the
contact margin could pass it through another between two detections: the
fabric's world refuses such a step (``max_move`` = margin; without it
single steps were measured to reach 4× the aim, about one radius, twice
the default margin), and the flow retries it a quarter as long. Friction
acts at the contacts as in any step. The drag (the world's ``viscosity``) sets the time scale only: the equilibrium
does not depend on it, and the first step, 100 ηr⁴/B, makes the flow's
steps the same for every yarn stiffness and scale (``examples/knit_sweep.py``).
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Optional
import numpy as np

from .. import errors
from . import Fabric, _check
from .geometry import Interlocks, clearance, curl

__all__ = ["Relaxed", "relax", "Stretched", "stretch"]


# What a refused step raises (the world unchanged): the flow retries it
# shorter (a singular one too: a cell stretched with friction met one).
_REFUSED = (errors.DivergedError, errors.ConvergenceError, errors.NonFiniteError, errors.SingularError)


# A step moving no point farther than this fraction of the step cap does
# not lengthen the next (see _Flow.step).
STUCK = 1e-3

# A forced step (a constraint's correction, see _Flow._forced_step) moves
# no point farther than this many yarn radii: a diameter.
FORCED_MOVE = 2.0


class _Flow:
    """Adaptive overdamped steps on a world: dt grows while steps move
    little, shrinks when one moves too much, quarters when one fails."""

    def __init__(self, world, radius: float, step_fraction: float, dt: float, longest: float = np.inf):
        dt = min(dt, longest)
        self.world, self.radius, self.cap, self.dt, self.first = world, radius, step_fraction * radius, dt, dt
        self.longest = longest
        self.fails = 0
        self.forced = 0
        self._reach = None  # the last refusal's move over max_move
        world.set_params(dt=dt, overdamped=True)

    def _coords(self):
        return [r.control_points.copy() for r in self.world.rods()]

    def step(self) -> Optional[float]:
        """One step; returns the largest control-point move (m), or None
        when the step was refused (the world unchanged, dt shortened)."""
        before = self._coords()
        try:
            self.world.step()
        except _REFUSED as e:
            # The world is unchanged by a refused step: retry shorter.
            self.fails += 1
            reach = e.factor if isinstance(e, errors.DivergedError) and "max_move" in str(e) else None
            limit = self.world.params["max_move"]
            if (reach is not None and self._reach is not None and 0.5 * self._reach < reach <= 2.0 * self._reach
                    and 1.5 * reach * limit <= FORCED_MOVE * self.radius and self._forced_step(reach, limit)):
                # A quarter of the step moved about as far: the move is a
                # constraint's correction (contacts pushing yarns that sag
                # into each other apart, a clamp's drift), which no shorter
                # step shortens: taken once with the guard let out to it.
                # Farther than the whole step is no such correction (a seed
                # swatch's first quarter step reached 121 max_moves where
                # the whole reached 20): shortened again. Nor is one
                # farther than a diameter (FORCED_MOVE): a stretched cell's
                # quarter steps all reached 140 max_moves, a near-free
                # mode, and the step forced through moved a yarn 7 mm,
                # through the yarns about it.
                pass
            else:
                self._reach = reach
                if self.dt < 1e-12 * self.first:
                    raise
                self.dt *= 0.25
                self.world.set_params(dt=self.dt)
                return None
        self._reach = None
        move = max(float(np.linalg.norm(a - b, axis=1).max()) for a, b in zip(self._coords(), before))
        grow = min(2.0, max(0.5, np.sqrt(self.cap / max(move, 1e-300))))
        if move < STUCK * self.cap:
            # Held by friction (or settled), a longer step moves no more:
            # grown on, dt doubled every step (to 5e7 s in 50 steps of a
            # settling stretch, measured), and the next grip move was
            # refused and quartered twenty times over.
            grow = min(grow, 1.0)
        self.dt = min(self.dt * grow, self.longest)
        self.world.set_params(dt=self.dt)
        return move

    def _forced_step(self, reach: float, limit: float) -> bool:
        """One step with the reach guard let out to 1.5 × the refused
        ``reach`` (the step's farthest move over ``limit``, the world's max_move, m); False if
        refused. Not lifted altogether: the step may move other points
        farther than the correction that triggered it (measured: a seed
        swatch's first steps, taken unguarded, moved a yarn 120 max_moves,
        its energy 0.16 → 8.6 J)."""
        self.world.set_params(max_move=1.5 * reach * limit)
        try:
            self.world.step()
        except _REFUSED:
            return False
        finally:
            self.world.set_params(max_move=limit)
        self.forced += 1
        return True


@dataclass
class Relaxed:
    """Result of :func:`relax`: the world at the end, whether the energy
    and the stitch dimensions had settled with every interlock holding
    (``converged``), the number of steps, ``history`` (arrays ``step``,
    ``energy`` J, ``k_c``, ``k_w``, from step 0, the start), the final ``dimensions`` (see :meth:`Fabric.dimensions`), the smallest
    yarn ``clearance`` (distance/2r) the relaxation reached (every tenth
    record and the end; the start's own is ``start_clearance``), the edge
    ``curl`` (m; None for a tube or a swatch under 3 × 3), the wall
    time (s) and ``interlocks`` (:class:`~strandkit.knit.geometry.Interlocks`,
    followed every 10 steps: ``interlocks.parted`` lists the loops (wale,
    course) that came out of the loop above at some point — a swatch
    unravelling from an edge — and ``dimensions`` then measure a tangle)."""

    world: object
    fabric: Fabric
    converged: bool
    steps: int
    history: dict
    dimensions: dict
    clearance: float
    curl: dict
    wall_time: float
    fails: int = 0
    interlocks: Optional[Interlocks] = field(default=None, repr=False)
    start_clearance: float = float("nan")

    def __repr__(self) -> str:
        d = self.dimensions
        parted = len(self.interlocks.parted) if self.interlocks is not None else 0
        return (f"Relaxed({'converged' if self.converged else 'NOT converged'} after {self.steps} steps, "
                f"k_c={d['k_c']:.3f}, k_w={d['k_w']:.3f}, courses/cm={d['courses_per_cm']:.2f}, "
                f"wales/cm={d['wales_per_cm']:.2f}, clearance={self.clearance:.3f}"
                f"{f', {parted} interlocks parted' if parted else ''})")


def _first_dt(fabric: Fabric, viscosity: float) -> float:
    """The first step (s): 100 × η r⁴/B, the overdamped relaxation time of a
    bend one radius long, so that a stiffer or a scaled fabric takes the
    same steps through the same shapes (the flow's steps adapt from here)."""
    return 100.0 * viscosity * fabric.yarn_radius ** 4 / fabric.bending_stiffness


def _longest_dt(fabric: Fabric, viscosity: float) -> float:
    """The longest step (s): 1000 × η L⁴/B, L the yarn length of the
    longest row or column of stitches, past the overdamped relaxation time
    of the swatch's slowest bend. Longer steps are static ones, in which
    nothing but the drag holds the swatch's rigid motions: a cell held by
    friction grew its steps to 1e8 s, its systems turned singular for the
    sparse solver, and each step took the dense band's (3 s against 0.1 s)."""
    length = fabric.loop_length * max(fabric.wales, fabric.courses)
    return 1e3 * viscosity * length ** 4 / fabric.bending_stiffness


def relax(fabric: Fabric, *, friction: float = 0.0, max_steps: int = 2000, tol: float = 2e-4, window: int = 100,
          step_fraction: float = 0.25, viscosity: float = 1.0, record_every: int = 10, world=None,
          interlocks: Optional[Interlocks] = None, progress_bar: bool = False) -> Relaxed:
    """Dry relaxation of ``fabric`` (free of loads) to equilibrium.

    friction: Coulomb μ at yarn–yarn contacts; max_steps: step budget;
    converged when, over the last ``window`` steps, the elastic energy
    fell by less than ``tol`` of itself and k_c, k_w moved by less than
    ``tol``; step_fraction: largest control-point move per step in yarn
    radii; viscosity: the fluid's (Pa·s), the drag of the gradient flow;
    world: continue relaxing this world (made by ``fabric.world``; given
    with its ``interlocks``, a relaxation's world goes on with its last
    step) instead of a new one, with ``interlocks`` the ones followed so far
    (``Relaxed.interlocks``; without, they are found anew in ``world``,
    which needs the yarn not to have slid far from where it was built).
    Records every ``record_every`` steps. Not ``converged`` once an
    interlock has parted, however settled the energy.
    """
    max_steps = _check("max_steps", max_steps, integer=True)
    window = _check("window", window, integer=True)
    record_every = _check("record_every", record_every, integer=True)
    tol, step_fraction = _check("tol", tol), _check("step_fraction", step_fraction)
    viscosity = _check("viscosity", viscosity)
    dt = _first_dt(fabric, viscosity)
    if world is None:
        world = fabric.world(friction=_check("friction", friction, inclusive=True), viscosity=viscosity)
    else:
        # A relaxation continued (its world and interlocks) goes on with its
        # last step (the world's dt under the flow): a new flow's first step is far from the one the
        # flow had adapted to (refused and shortened several times over, or
        # a fraction of it).
        if interlocks is not None and world.params["overdamped"] and world.params["viscosity"] == viscosity:
            dt = world.params["dt"]
        world.set_params(viscosity=viscosity)
    flow = _Flow(world, fabric.yarn_radius, step_fraction, dt=dt, longest=_longest_dt(fabric, viscosity))
    if interlocks is None:
        interlocks = Interlocks(world, fabric)
    elif not isinstance(interlocks, Interlocks) or interlocks.fabric is not fabric:
        raise errors.InvalidInputError("interlocks: the Relaxed.interlocks of a relaxation of this fabric")
    hist = {"step": [], "energy": [], "k_c": [], "k_w": []}

    def record(k):
        d = fabric.dimensions(world)
        hist["step"].append(k), hist["energy"].append(world.energy()["elastic"])
        hist["k_c"].append(d["k_c"]), hist["k_w"].append(d["k_w"])

    # The start too: an energy rise in the first steps shows.
    record(0)
    # The start's apart: a start built narrow had yarns 16 % of a diameter
    # into each other, gone within 150 steps, and read as the relaxation's.
    start_clearance, least = clearance(world, fabric), np.inf
    t0 = time.perf_counter()
    converged, k = False, 0
    bar = None
    if progress_bar:
        from .._progress import progress
        bar = progress(total=max_steps, desc="knit relax")
    for k in range(1, max_steps + 1):
        flow.step()
        if bar is not None:
            bar.update(1)
        if k % 10 == 0:
            interlocks.update(world)
        if k % record_every == 0:
            record(k)
            if k % (10 * record_every) == 0:
                least = min(least, clearance(world, fabric))
            back = window // record_every
            if len(hist["step"]) > back:
                e, kc, kw = (np.array(hist[x][-back - 1:]) for x in ("energy", "k_c", "k_w"))
                if (abs(e[-1] - e[0]) <= tol * abs(e[-1]) and abs(kc[-1] - kc[0]) <= tol * kc[-1]
                        and abs(kw[-1] - kw[0]) <= tol * kw[-1]) and not interlocks.ever_parted.any():
                    converged = True
                    break
    if bar is not None:
        bar.close()
    if k % 10:
        interlocks.update(world)
    least = min(least, clearance(world, fabric))
    flat = fabric.tube_radius == 0 and fabric.courses >= 3 and fabric.wales >= 3
    return Relaxed(world=world, fabric=fabric, converged=converged, steps=k,
                   history={key: np.array(v) for key, v in hist.items()}, dimensions=fabric.dimensions(world),
                   clearance=least, curl=curl(world, fabric) if flat else None,
                   wall_time=time.perf_counter() - t0, fails=flow.fails, interlocks=interlocks,
                   start_clearance=start_clearance)


@dataclass
class Stretched:
    """Result of :func:`stretch`: per increment ``strain`` (grip
    displacement over the initial grip distance), ``force`` (N, the pulled
    grips' reaction along the stretch), ``lateral_strain`` (change of the
    width across the stretch over its initial value, at mid-length),
    ``loading`` (True while the grips move apart); ``work_loading``,
    ``work_unloading`` (J, ∫F du on each branch); ``clearance`` (smallest
    seen); ``settled`` (per increment, after the first point: whether its
    force had stopped changing, by less than ``tol`` over 20 steps, before
    ``steps_per_increment`` ran out; unsettled, the force lags the
    equilibrium's, above it on loading, while the yarn still slides);
    ``interlocks`` followed through the settling and every
    increment (``interlocks.parted``: loops that came out of the loop
    above, with a relaxed source counting from its relaxation's)."""

    direction: str
    strain: np.ndarray
    force: np.ndarray
    lateral_strain: np.ndarray
    loading: np.ndarray
    work_loading: float
    work_unloading: float
    clearance: float
    settled: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=bool))
    world: object = field(repr=False, default=None)
    interlocks: Optional[Interlocks] = field(default=None, repr=False)

    def __repr__(self) -> str:
        parted = len(self.interlocks.parted) if self.interlocks is not None else 0
        return (f"Stretched({self.direction}, {len(self.strain)} increments to strain {self.strain.max():.3f}, "
                f"peak force {self.force.max():.4g} N, work loading {self.work_loading:.4g} J / "
                f"unloading {self.work_unloading:.4g} J, {int(self.settled.sum())} of {len(self.settled)} increments "
                f"settled{f', {parted} interlocks parted' if parted else ''})")


def _grips(fabric: Fabric, direction: str):
    """(held, pulled) lists of (rod, u) and the unit vector of the stretch."""
    lp = fabric.loops
    nw, nc = fabric.wales, fabric.courses
    grid = lp.reshape(nc, nw)
    if direction == "wale":
        held = [(int(x["rod"]), float(x["u_start"])) for x in grid[0]]
        pulled = [(int(x["rod"]), float(x["u_head"])) for x in grid[-1]]
        axis = np.array([0.0, 1.0, 0.0])
    elif direction == "course":
        if fabric.tube_radius > 0:
            raise errors.InvalidInputError("direction: a tube (periodic boundary) is stretched along the wale only")
        # A continuous yarn runs right to left along its odd courses.
        back = lambda j: fabric.continuous and j % 2 == 1  # noqa: E731
        held = [(int(x["rod"]), float(x["u_end"] if back(j) else x["u_start"])) for j, x in enumerate(grid[:, 0])]
        pulled = [(int(x["rod"]), float(x["u_start"] if back(j) else x["u_end"])) for j, x in enumerate(grid[:, -1])]
        axis = np.array([1.0, 0.0, 0.0])
    else:
        raise errors.InvalidInputError(f"direction: 'wale' or 'course', got {direction!r}")
    return held, pulled, axis


def stretch(source, *, direction: str = "wale", strain: float = 0.3, increments: int = 10, unload: bool = True,
            friction: Optional[float] = None, settle_steps: int = 300, steps_per_increment: int = 200, tol: float = 1e-3,
            step_fraction: float = 0.25, viscosity: float = 1.0) -> Stretched:
    """Uniaxial stretch under displacement control between two clamped
    bars: along the wale (cast-on sinkers held, bound-off heads pulled) or
    the course (first and last stitch of every course). A cell (periodic
    both ways) has no edge: along the wale its period is held instead
    (link ``period``; the force is the tension the whole tube carries, the
    lateral strain that of its wale spacing).

    source: a :class:`Fabric` (stretched as built, ``friction`` μ at its
    contacts, 0 if None) or a :class:`Relaxed` (a copy of its world
    continues, with its contact settings, or if ``friction`` μ is given
    with it and the default margin: relaxed frictionless, stretched with
    friction); the bars grip where the yarn is, then the
    fabric settles between them for ``settle_steps`` (the rest state
    between bars; the bars replace the fabric's cast-on, bind-off and
    selvedge links, its yarn ends stay fastened); strain: largest grip strain; increments: steps of grip
    displacement up (and down again if ``unload``), the bar moving by at
    most half the step cap per step; each increment relaxes for at most
    ``steps_per_increment`` steps, stopping once the pulled force changed
    by less than ``tol`` of itself over 20 steps. The first point is the
    force after settling (the bars' pull at zero strain).
    """
    strain = _check("strain", strain)
    if strain > 10.0:
        raise errors.InvalidInputError(f"strain: at most 10 (a knit is not stretched 11×), got {strain!r}")
    increments = _check("increments", increments, integer=True)
    steps_per_increment = _check("steps_per_increment", steps_per_increment, integer=True)
    settle_steps = _check("settle_steps", settle_steps, integer=True, inclusive=True)
    tol, step_fraction = _check("tol", tol), _check("step_fraction", step_fraction)
    if isinstance(source, Relaxed):
        # A copy: the relaxed world stays as it was (stretch adds bars).
        fabric, world = source.fabric, source.world.copy()
        world.set_params(viscosity=_check("viscosity", viscosity))
        if friction is not None:
            fabric.set_contact(world, friction=_check("friction", friction, inclusive=True))
    elif isinstance(source, Fabric):
        fabric = source
        mu = 0.0 if friction is None else _check("friction", friction, inclusive=True)
        world = fabric.world(friction=mu, viscosity=_check("viscosity", viscosity))
    else:
        raise errors.InvalidInputError(f"source: a strandkit.knit Fabric or Relaxed, got {type(source).__name__}")
    if fabric.boundary == "clamped_edges":
        raise errors.InvalidInputError("source: a fabric with boundary='clamped_edges' is held already; stretch adds its "
                                       "own bars to a 'free' one")
    from .. import position
    cell = fabric.image is not None
    if cell:
        return _stretch_cell(fabric, world, source, direction, strain, increments, unload, settle_steps,
                             steps_per_increment, tol, step_fraction)
    held, pulled, axis = _grips(fabric, direction)
    rods = world.rods()
    hold = lambda pts: [(rods[r], u, tuple(rods[r].position(u))) for r, u in pts]  # noqa: E731
    held, pulled = hold(held), hold(pulled)
    # The edge links are rigid chords: a stretch would load them, not the
    # knit (measured on a 4 × 4 at 10 % wale strain: the selvedge's
    # reactions 0.25–0.57 N each against a bar force of 1.2 N), the
    # bind-off and cast-on chains pull taut across a course stretch (the
    # step turns singular at a few %), and along the wale the bars grip
    # their points. The bars replace them; the yarn ends stay fastened.
    for group in ("bindoff", "caston", "selvedge"):
        for h in list(world.group(group).constraints if group in world.groups else []):
            if h.alive:
                world.remove_constraint(h)
    interlocks = _interlocks(source, world, fabric)
    for i, (rod, u, p) in enumerate(held):
        world.add_constraint(rod, position(u, target=p), label=f"grip[{i}]")
    pulls = [world.add_constraint(rod, position(u, target=p), label=f"pull[{i}]") for i, (rod, u, p) in enumerate(pulled)]
    start = np.array([p for _, _, p in pulled])
    gap = float(np.mean(start @ axis) - np.mean(np.array([p for _, _, p in held]) @ axis))
    across = np.array([1.0, 0.0, 0.0]) if direction == "wale" else np.array([0.0, 1.0, 0.0])

    def width():
        h = fabric.heads(world)
        mid = h[h.shape[0] // 2] if direction == "wale" else h[:, h.shape[1] // 2]
        return float(np.ptp(mid @ across))

    def force():
        # The pulled bar's force on the fabric along the stretch.
        return float(sum(np.dot(np.asarray(h.reaction().force), axis) for h in pulls))

    def place(e):
        for (rod, u, p), h in zip(pulled, pulls):
            world.set_constraint(h, position(u, target=tuple(np.asarray(p) + e * gap * axis)))

    return _increments(world, fabric, interlocks, direction, strain, increments, unload, settle_steps,
                       steps_per_increment, tol, step_fraction, gap, place, force, width)


def _stretch_cell(fabric, world, source, direction, strain, increments, unload, settle_steps, steps_per_increment,
                  tol, step_fraction) -> Stretched:
    """:func:`stretch` of a cell along the wale: no bars, its period held.
    The image is the yarn translated by a free vector; one more link
    (``period``) holds that vector's wale component, P₀(1 + strain), P₀
    the period where the stretch starts. Its reaction is the tension the
    whole tube carries along the wale; the lateral strain is that of the
    wale spacing (the tube's circumference), free in the cell."""
    if direction != "wale":
        raise errors.InvalidInputError(f"direction: a cell is stretched along the wale only (along the course its "
                                       f"period is the tube's free circumference), got {direction!r}")
    from .. import constraints
    rods = world.rods()
    yarn, image = rods[int(fabric.loops["rod"][0])], rods[fabric.image]
    u0 = yarn.domain[0]
    axis = np.array([0.0, 1.0, 0.0])
    gap = float((image.position(u0) - yarn.position(u0)) @ axis)
    held = lambda e: constraints.relative_position(u0, u0, offset=(0.0, -gap * (1.0 + e), 0.0), axes="y")  # noqa: E731
    link = world.add_link(yarn, image, held(0.0), label="period")
    interlocks = _interlocks(source, world, fabric)

    def force():
        # The link's force on the image along the wale: the image pulled
        # back towards the yarn, the tube's tension.
        return float(-np.dot(np.asarray(link.reaction().force), axis))

    return _increments(world, fabric, interlocks, direction, strain, increments, unload, settle_steps,
                       steps_per_increment, tol, step_fraction, gap, lambda e: world.set_constraint(link, held(e)), force,
                       lambda: fabric.dimensions(world)["wale_spacing"])


def _interlocks(source, world, fabric):
    """A relaxation's interlocks (a copy), else found anew in ``world``."""
    if isinstance(source, Relaxed) and source.interlocks is not None:
        return source.interlocks.copy()
    return Interlocks(world, fabric)


def _increments(world, fabric, interlocks, direction, strain, increments, unload, settle_steps, steps_per_increment,
                tol, step_fraction, gap, place, force, width) -> Stretched:
    """The fabric settled between its grips for ``settle_steps``, then the
    stretch's increments up (and down) to ``strain`` of ``gap`` (m), the
    grips moved by ``place(e)``; ``force()`` and ``width()`` read."""
    viscosity = world.params["viscosity"]
    flow = _Flow(world, fabric.yarn_radius, step_fraction, dt=_first_dt(fabric, viscosity), longest=_longest_dt(fabric, viscosity))
    for k in range(int(settle_steps)):
        flow.step()
        if k % 10 == 9:
            interlocks.update(world)
    w0 = width()
    levels = list(np.linspace(0.0, strain, increments + 1)[1:])
    if unload:
        levels += list(np.linspace(strain, 0.0, increments + 1)[1:])
    out = {"strain": [0.0], "force": [force()], "lateral": [0.0], "loading": [True], "settled": []}
    least = clearance(world, fabric)
    previous = 0.0
    for n, e in enumerate(levels):
        # The bar moves by at most half the step cap per step: the control
        # points about a grip move up to twice as far as the grip (measured
        # 2.1×), and no shorter step makes up for a constraint's jump
        # beyond the world's max_move (the contact margin, twice the cap).
        # The grip moves on only after a step taken: moved on through
        # refused ones, it jumped by the whole increment (a cell stretched
        # with friction, 23 refusals in a row).
        moves = max(1, int(np.ceil(abs(e - previous) * abs(gap) / (0.5 * flow.cap))))
        last, done, k, settled = None, 0, 0, False
        while done < moves or k < steps_per_increment:
            if done < moves:
                place(previous + (e - previous) * (done + 1) / moves)
            taken = flow.step() is not None
            k += 1
            if k % 10 == 0:
                interlocks.update(world)
            if done < moves:
                done += taken
                continue
            if k % 20 == 0:
                f = force()
                if last is not None and abs(f - last) <= tol * max(abs(f), 1e-300):
                    settled = True
                    break
                last = f
        previous = e
        out["settled"].append(settled)
        out["strain"].append(e), out["force"].append(force()), out["lateral"].append(width() / w0 - 1.0)
        out["loading"].append(n < increments)
        least = min(least, clearance(world, fabric))
        interlocks.update(world)
    s, f, ld = np.array(out["strain"]), np.array(out["force"]), np.array(out["loading"])
    trap = lambda x, y: float(np.sum(0.5 * (y[1:] + y[:-1]) * np.diff(x)))  # noqa: E731
    up = slice(0, increments + 1)
    down = slice(increments, None)
    return Stretched(direction=direction, strain=s, force=f, lateral_strain=np.array(out["lateral"]), loading=ld,
                     work_loading=trap(s[up] * gap, f[up]),
                     work_unloading=-trap(s[down] * gap, f[down]) if unload else float("nan"),
                     clearance=least, settled=np.array(out["settled"], dtype=bool), world=world,
                     interlocks=interlocks)
