"""Single-molecule experiments on a duplex (issue 17) in a viscous fluid, at
zero temperature or with thermal noise (``temperature=`` K, ``seed=``):
optical-trap pulling at constant velocity, force clamps and ramps, and the
unzipping, shear and stretching set-ups built on them. Units: nm, pN, ns.

Each experiment holds some strand ends in fixed stiff traps and pulls
others with a trap moving at constant speed, F = k (x_trap − x_end) along
the pulling direction, and returns a ``PullResult``: arrays of time,
trap position, extension and force, the number of open base pairs, and
every hydrogen bond that broke (when, which pair, at what tension).

>>> import strandkit as sk
>>> from strandkit.dna import experiments as ex
>>> r = ex.unzip("GCGCGC", distance=8.0, progress_bar=False, **ex.QUASI_STATIC)
>>> r
PullResult(unzip of 6 bp: 401 records over 40 ns, peak 20 pN, 4 pairs open)
>>> b = r.breaks[0]
>>> b["label"], round(b["force"], 1)      # the bond's tension: its break force
('hbond[0]', 20.0)

The unzipping force is a share of the break force, affine in it: the fork
is a Y of the two pulled strands and the next pair's backbone, so the
trap pulls with F ≈ 0.77 f_b − 2.1 pN when the fork's bond breaks (at the
default duplex, quasi-static: ``QUASI_STATIC``; tests in
python/tests/test_dna_experiments.py). ``break_forces_for_unzipping``
inverts it: A·T and G·C bonds of 14.4 and 28.6 pN unzip at the 9 and 20
pN measured by AFM.

Ends are named by strand and extremity: ``"a5'"``, ``"a3'"``, ``"b5'"``,
``"b3'"`` (strand a runs 5′→3′ from pair 0; strand b's 3′ end pairs with
pair 0). With ``out=prefix`` the records go to ``prefix.csv`` as they are
taken (flushed, so an interrupted run keeps what it gathered) and the
trajectory to ``prefix.pdb/.psf/.dcd`` (``strandkit.dna.trajectory``).

The far end of the molecule is free: the duplex turns about the pulling
line as it opens, as a tethered molecule does on its swivel (clamping it
would make the fork twist the remaining duplex, which then carries the
pull instead of the fork's bond).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable, List, Optional, Sequence

import numpy as np

from ..errors import _invalid
from .._native import World
from .._progress import progress
from ..loads import point_force, trap
from ._checks import check_bonds_under_noise, integer, noise_scheme, number
from .duplex import Duplex, as_duplex, duplex as build_duplex
from ._records import Records
from .fluctuations import ThermalElasticity, thermal_elasticity
from .tweezers import TwistResult, buckling, magnetic_tweezers

__all__ = ["PullResult", "ThermalElasticity", "TwistResult", "thermal_elasticity", "magnetic_tweezers", "buckling", "pull", "unzip", "shear", "stretch", "force_clamp", "force_ramp", "unzipping_plateau",
           "break_forces_for_unzipping", "ENDS", "GEOMETRIES"]

ENDS = ("a5'", "a3'", "b5'", "b3'")
# Held and pulled ends of each set-up.
GEOMETRIES = {
    "unzip": (["a5'"], ["b3'"]),
    "shear": (["b3'"], ["a3'"]),
    "stretch": (["a5'", "b3'"], ["a3'", "b5'"]),
}
COLUMNS = ("time", "trap", "extension", "force", "open", "span")


@dataclass
class PullResult:
    """Records of a pulling run: ``time`` (ns), ``trap`` (the moving trap's
    displacement along ``direction``, nm), ``extension`` (pulled minus held
    ends' mean position along ``direction``, nm, 0 at the start), ``force``
    (the moving traps' pull along ``direction``, pN), ``open`` (broken base
    pairs), ``span`` (distance along ``direction`` between the midpoints of
    pairs ``span_pairs``, nm: the duplex's own length away from the ends
    where the traps pull); ``breaks``: one dict per bond that broke (``time``,
    ``pair``, ``label``, ``bond`` — "hbond", or "stagger" for a position
    rung's stagger: broken under its load it opens its pair (the "hbond"
    follows at force 0), removed with a neighbour's bond (force 0) it
    leaves the pair held by its distance alone —, ``force`` its tension
    (a stagger's force) in pN, 0 for one removed with another,
    ``trap_force``);
    ``paths``: files written."""

    experiment: str
    n_bp: int
    direction: np.ndarray
    time: np.ndarray
    trap: np.ndarray
    extension: np.ndarray
    force: np.ndarray
    open: np.ndarray
    span: np.ndarray
    span_pairs: tuple
    breaks: List[dict] = field(default_factory=list)
    paths: dict = field(default_factory=dict)

    def __repr__(self) -> str:
        peak = float(self.force.max()) if len(self.force) else float("nan")
        last = int(self.open[-1]) if len(self.open) else 0
        return (f"PullResult({self.experiment} of {self.n_bp} bp: {len(self.time)} records over "
                f"{self.time[-1] if len(self.time) else 0:.3g} ns, peak {peak:.3g} pN, {last} pairs open)")


def _end(d: Duplex, name: str):
    """(strand index 0/1, abscissa) of a named end."""
    if name not in ENDS:
        raise _invalid(f"unknown end {name!r}: the ends are {', '.join(ENDS)}")
    s = 0 if name[0] == "a" else 1
    u = d.abscissae[s]
    return s, float(u[0] if name[1] == "5" else u[-1])


def pull(d: Duplex, *, held: Sequence[str], pulled: Sequence[str], speed: float = 0.2, distance: float = 10.0,
         direction: Optional[Sequence[float]] = None, trap_stiffness: float = 1.0, hold_stiffness: float = 10.0,
         viscosity: float = 1.0, dt: float = 0.01, record_every: int = 10, out: Optional[str] = None,
         frame_every: int = 100, stop_when_open: bool = True, progress_bar: bool = True,
         span_pairs: Optional[Sequence[int]] = None, force: Optional[Callable[[float], float]] = None,
         duration: Optional[float] = None, temperature: float = 0.0, seed: int = 0,
         scheme: Optional[str] = None, brownian: bool = False, experiment: str = "pull") -> PullResult:
    """Pulls the ``pulled`` ends of duplex ``d`` with traps moving at
    ``speed`` (nm/ns) for ``distance`` (nm) while fixed traps hold the
    ``held`` ends (each trap starts on its end: no initial force). With
    ``force`` (a function of time in ns giving pN) the pulled ends are
    pulled by that force instead (shared equally, along ``direction``) for
    ``duration`` ns: a force clamp or ramp (``trap`` is then NaN).

    direction: the pulling direction, a 3-vector or ``"axis"`` (the duplex's
    helix axis, from the first pair to the last; default: from the held ends'
    mean to the pulled ends' mean); trap_stiffness, hold_stiffness: pN/nm;
    viscosity: the fluid's, pN·ns/nm² (water: 1; it sets the drag that the
    pulling speed works against — the quasi-static limit is speed → 0);
    dt: ns (the step adapts when a break needs it); record_every: steps
    between records; out: file prefix for the CSV and trajectory;
    frame_every: steps between trajectory frames; stop_when_open: stop once
    every pair is open; span_pairs: the two pairs whose midpoints ``span``
    follows (default: the 4th from each end, or the end pairs below 10 bp);
    temperature: K (0: no noise; above it Langevin noise of the fluid's
    drag, drawn from ``seed``: a run is reproducible); scheme: the World's
    (default: the trapezoidal rule with noise, implicit Euler without;
    with the stacking held at each step's end the trapezoidal rule damps
    the stiff modes too: at 5 ps a pulled 100 bp duplex keeps 0.88 of its
    exact axis tilt, implicit Euler 0.87, ``docs/dna_calibration.md``). With
    noise a rigid bond's instantaneous tension swings by tens of pN: the
    duplex needs ``break_averaging_time`` (``duplex``), so that bonds break
    on the averaged force, or unbreakable bonds (refused otherwise).
    brownian: overdamped (Brownian) dynamics with isotropic drag, as DNA in
    water moves on these scales: with the duplex built with
    ``averaged_stacking=True`` the trapezoidal rule then samples its exact
    statistics at 5 ps steps (a free 20 bp duplex within 2.5 % at 2 and
    5 bp, ``tests/dna.rs``), where with inertia it needs ~0.25 ps.
    """
    if not isinstance(d, Duplex):
        raise _invalid(f"expected a strandkit.dna.Duplex, got {type(d).__name__}")
    held, pulled = list(held), list(pulled)
    if not pulled:
        raise _invalid("pull: no end to pull")
    if set(held) & set(pulled):
        raise _invalid(f"an end cannot be both held and pulled: {sorted(set(held) & set(pulled))}")
    ends_h = [_end(d, e) for e in held]
    ends_p = [_end(d, e) for e in pulled]
    speed = number("speed (nm/ns)", speed)
    distance = number("distance (nm)", distance)
    k, kh = number("trap_stiffness (pN/nm)", trap_stiffness), number("hold_stiffness (pN/nm)", hold_stiffness)
    viscosity, dt = number("viscosity (pN·ns/nm²)", viscosity), number("dt (ns)", dt)
    record_every, frame_every = integer("record_every", record_every, 1), integer("frame_every", frame_every, 1)
    temperature, seed = number("temperature (K)", temperature, strict=False), integer("seed", seed, 0)
    scheme = noise_scheme(temperature, scheme)
    check_bonds_under_noise(d, temperature)
    n = len(d)
    if span_pairs is None:
        span_pairs = (3, n - 4) if n >= 10 else (0, n - 1)
    span_pairs = tuple(int(i) for i in span_pairs)
    if len(span_pairs) != 2 or not all(0 <= i < n for i in span_pairs) or span_pairs[0] == span_pairs[1]:
        raise _invalid(f"span_pairs must be two distinct pairs of the {n}, got {span_pairs}")
    if force is not None:
        if not callable(force):
            raise _invalid(f"force must be a function of time (ns) giving pN, got {type(force).__name__}")
        if duration is None:
            raise _invalid("a force protocol needs its duration (ns)")
        duration = number("duration (ns)", duration)
        n_steps = math.ceil(duration / dt)
    else:
        n_steps = math.ceil(distance / speed / dt)
    if n_steps > 50_000_000:
        raise _invalid(f"{n_steps} steps: raise speed or dt")

    if not isinstance(brownian, bool):
        raise _invalid(f"brownian must be True or False, got {brownian!r}")
    world = World(units="molecular", dt=dt, viscosity=viscosity, adaptive_dt=True, temperature=temperature, seed=seed,
                  scheme=scheme, overdamped=brownian, isotropic_drag=brownian)
    ins = world.insert(d.assembly)
    rods = [ins.rods[i] for i in d.strands]
    pos = lambda e: np.asarray(rods[e[0]].position(e[1]), dtype=float)  # noqa: E731

    def pair_points(i):
        return pos((0, float(d.abscissae[0][i]))), pos((1, float(d.abscissae[1][int(d.partner[i])])))

    def pair_midpoint(i):
        """Midpoint (nm) of pair i's rung."""
        a, b = pair_points(i)
        return 0.5 * (a + b)

    def helix_axis():
        """The duplex's axis, first pair to last: the rung midpoints lie
        R cos(φ/2) off it (⟂ the rung), at the helix's phase, so the line
        between the end midpoints leans by up to ~20° on a short duplex;
        the pairs' axis points (midpoint moved back toward the axis) do not."""
        off = 0.5 * d.rung_length / math.tan(0.5 * d.phase)
        ends = [pair_points(0), pair_points(len(d) - 1)]
        z = pair_midpoint(len(d) - 1) - pair_midpoint(0)
        for _ in range(3):
            o = [0.5 * (a + b) + off * np.cross(z, b - a) / np.linalg.norm(np.cross(z, b - a)) for a, b in ends]
            z = o[1] - o[0]
        return z

    x_h = np.mean([pos(e) for e in ends_h], axis=0) if ends_h else None
    x_p0 = np.mean([pos(e) for e in ends_p], axis=0)
    if isinstance(direction, str):
        if direction != "axis":
            raise _invalid(f"direction {direction!r}: a 3-vector or 'axis'")
        direction = helix_axis()
    elif direction is None:
        if x_h is None:
            raise _invalid("pull: give a direction when no end is held")
        direction = x_p0 - x_h
    direction = np.asarray(direction, dtype=float)
    norm = float(np.linalg.norm(direction)) if direction.shape == (3,) else float("nan")
    if not (norm > 0 and math.isfinite(norm)):
        raise _invalid(f"direction must be a finite non-zero 3-vector, got {direction.tolist()}")
    e = direction / norm
    for s, u in ends_h:
        world.add_load(trap(rods[s], u, pos((s, u)), kh))
    starts = [pos(p) for p in ends_p]

    def applied(t):
        """The force protocol at time t (pN), checked."""
        f = float(force(t))
        if not math.isfinite(f):
            raise _invalid(f"force({t:g} ns) = {f}: expected a finite number of pN")
        return f

    if force is None:
        for (s, u), x0 in zip(ends_p, starts):
            world.add_load(trap(rods[s], u, x0, k, velocity=speed * e))
    else:
        share = 1.0 / len(ends_p)
        pushes = [world.add_load(point_force(rods[s], u, applied(0.0) * share * e)) for s, u in ends_p]

    def trap_force(t, pulled_x):
        if force is not None:
            return applied(t)
        return sum(k * float(np.dot(x0 + speed * t * e - x, e)) for x0, x in zip(starts, pulled_x))
    hbonds = {h: kk for kk, h in enumerate(d.hbonds) if h is not None}
    labels = {ins.constraints[h].label: kk for h, kk in hbonds.items()}
    n_pairs = len(hbonds)
    # Position rungs: a pair's stagger can break first (sheared, still bonded).
    labels.update({ins.constraints[h].label: kk for kk, h in enumerate(d.staggers) if h is not None})

    breaks = []
    opened = [0]  # pairs whose hydrogen bond broke (a cell: record() reads it)
    x_h0 = float(np.dot(x_h, e)) if x_h is not None else 0.0
    ext0 = float(np.dot(x_p0, e)) - x_h0
    protocol = (f"speed {speed} nm/ns, trap {k} pN/nm" if force is None
                else f"force protocol over {duration} ns (trap_nm: NaN)")
    if temperature > 0:
        protocol += f", {temperature:g} K (seed {seed}, {scheme})"
    if brownian:
        protocol += ", Brownian"
    records = Records(COLUMNS, ["time_ns", "trap_nm", "extension_nm", "force_pN", "open_bp", "span_nm"], out,
                      f"strandkit.dna.experiments.{experiment}: {d!r}; held {held}, pulled {pulled}, {protocol}, "
                      f"direction {e.tolist()}", world, d, ins, frame_every)

    def record():
        t = world.time
        pulled_x = [pos(p) for p in ends_p]
        f = trap_force(t, pulled_x)
        held_x = float(np.dot(np.mean([pos(h) for h in ends_h], axis=0), e)) if ends_h else x_h0
        extension = float(np.dot(np.mean(pulled_x, axis=0), e)) - held_x - ext0
        records.add((t, speed * t if force is None else math.nan, extension, f, opened[0],
                     abs(float(np.dot(pair_midpoint(span_pairs[1]) - pair_midpoint(span_pairs[0]), e)))))
        return f

    with records:
        record()
        for step in progress(range(n_steps), desc=experiment, enable=progress_bar):
            if force is not None:
                # Held over the step: implicit Euler weighs the step's end,
                # the second-order schemes its middle.
                f_next = applied(world.time + (dt if scheme == "implicit_euler" else 0.5 * dt)) * share
                for h, (s, u) in zip(pushes, ends_p):
                    world.set_load(h, point_force(rods[s], u, f_next * e))
            report = world.step()
            for ev in report.events:
                if ev.kind == "ConstraintBroken" and ev.label in labels:
                    f_trap = trap_force(world.time, [pos(p) for p in ends_p])
                    breaks.append(dict(time=world.time, pair=labels[ev.label], label=ev.label,
                                       bond=ev.label.split("[")[0], force=ev.force, trap_force=f_trap))
                    opened[0] += breaks[-1]["bond"] == "hbond"
            if (step + 1) % record_every == 0:
                record()
            records.step(step + 1)
            if stop_when_open and n_pairs and opened[0] == n_pairs:
                if (step + 1) % record_every:
                    record()
                break
    arr = records.arrays()
    return PullResult(experiment, len(d), e, arr["time"], arr["trap"], arr["extension"], arr["force"],
                      arr["open"].astype(int), arr["span"], span_pairs, breaks, records.paths)


def unzip(sequence_or_duplex, *, speed: float = 0.2, distance: Optional[float] = None, duplex_options=None,
          **options) -> PullResult:
    """Unzipping: holds strand a's 5′ end and pulls strand b's 3′ end (the
    two strands of pair 0) apart along pair 0's rung. ``distance``
    defaults to the length of both opened strands (1.5 × rise × 2 per bp).
    At zero temperature each opening comes when the fork's bond tension
    reaches its break force f_b: the trap force is a sawtooth peaking at
    ≈ 0.77 f_b − 2.1 pN, pair by pair in the order of the sequence. Other
    options: ``pull``'s."""
    d = as_duplex(sequence_or_duplex, duplex_options)
    if distance is None:
        distance = 2.0 * 1.5 * d.params["rise"] * len(d) + 2.0
    return pull(d, held=["a5'"], pulled=["b3'"], speed=speed, distance=distance, experiment="unzip", **options)


def shear(sequence_or_duplex, *, speed: float = 0.2, distance: Optional[float] = None, duplex_options=None,
          **options) -> PullResult:
    """Shear: holds strand b's 3′ end (at pair 0) and pulls strand a's 3′
    end (at the last pair) along the axis, so the hydrogen bonds carry the
    load between the two strands in parallel (de Gennes' ladder); the
    pulling direction defaults to the duplex's helix axis. ``distance`` defaults to twice the duplex
    length. Other options: ``pull``'s."""
    d = as_duplex(sequence_or_duplex, duplex_options)
    if distance is None:
        distance = 2.0 * d.params["rise"] * len(d) + 5.0
    options.setdefault("direction", "axis")
    return pull(d, held=["b3'"], pulled=["a3'"], speed=speed, distance=distance, experiment="shear", **options)


def stretch(sequence_or_duplex, *, speed: float = 0.05, distance: float = 1.0, duplex_options=None,
            **options) -> PullResult:
    """Stretching: holds both strands at pair 0 (a5′, b3′) and pulls both
    at the last pair (a3′, b5′) along the axis (last pair's rung midpoint
    minus the first's). Other options: ``pull``'s."""
    d = as_duplex(sequence_or_duplex, duplex_options)
    options.setdefault("direction", "axis")
    return pull(d, held=["a5'", "b3'"], pulled=["a3'", "b5'"], speed=speed, distance=distance,
                experiment="stretch", **options)


def _geometry(name):
    if name not in GEOMETRIES:
        raise _invalid(f"unknown geometry {name!r}: one of {', '.join(GEOMETRIES)}")
    return GEOMETRIES[name]


def force_clamp(sequence_or_duplex, force: float, duration: float, *, geometry: str = "unzip",
                duplex_options=None, **options) -> PullResult:
    """Force clamp: the ``geometry``'s pulled ends (``GEOMETRIES``: unzip,
    shear, stretch) pulled by a constant ``force`` (pN) for ``duration``
    (ns), its held ends in fixed traps. Other options: ``pull``'s."""
    f = float(force)
    if not (f >= 0 and math.isfinite(f)):
        raise _invalid(f"force must be a finite number of pN ≥ 0, got {force}")
    held, pulled = _geometry(geometry)
    d = as_duplex(sequence_or_duplex, duplex_options)
    return pull(d, held=held, pulled=pulled, force=lambda t: f, duration=duration,
                experiment=f"{geometry} at {f:g} pN", **options)


def force_ramp(sequence_or_duplex, rate: float, max_force: float, *, geometry: str = "unzip",
               duplex_options=None, **options) -> PullResult:
    """Force ramp: the ``geometry``'s pulled ends pulled by a force growing
    at ``rate`` (pN/ns) from 0 up to ``max_force`` (pN), where the run
    ends. Other options: ``pull``'s."""
    rate = number("rate (pN/ns)", rate)
    max_force = number("max_force (pN)", max_force)
    held, pulled = _geometry(geometry)
    d = as_duplex(sequence_or_duplex, duplex_options)
    return pull(d, held=held, pulled=pulled, force=lambda t: min(rate * t, max_force), duration=max_force / rate,
                experiment=f"{geometry} ramp", **options)


# Quasi-static pulling (a slower pull changes the plateau by < 2 %,
# python/tests/test_dna_experiments.py).
QUASI_STATIC = dict(speed=0.2, trap_stiffness=5.0, viscosity=0.1)
_PROBES: dict = {}


def unzipping_plateau(result: PullResult, skip: int = 3) -> float:
    """Mean trap force (pN) at the openings after the first ``skip`` (the
    end pairs open at their own, higher force while the fork forms)."""
    f = [b["trap_force"] for b in result.breaks if b["bond"] == "hbond"][skip:]
    if not f:
        raise _invalid(f"unzipping_plateau: fewer than {skip + 1} pairs opened")
    return float(np.mean(f))


def break_forces_for_unzipping(unzip_at: float = 9.0, unzip_gc: float = 20.0, *, progress_bar: bool = False,
                               **duplex_options) -> tuple:
    """Hydrogen-bond break forces (pN: A·T, G·C) that make a duplex unzip
    at ``unzip_at`` / ``unzip_gc`` pN (defaults: Rief, Clausen-Schaumann &
    Gaub 1999's AFM values, SPEC §9.1), for ``duplex(**duplex_options)``.

    A bond breaks when its tension reaches its break force, but the fork
    is a Y of the two pulled strands and the next pair's backbone, so the
    trap force at an opening is a share of it, affine in it:
    F = α f_b − β (measured: α ≈ 0.77, β ≈ 2.1 pN at the defaults). Two
    quasi-static probes (12 bp, f_b = 10 and 30 pN; cached per option set,
    ~10 s) measure α and β; the result is (F + β)/α for each target."""
    for name, f in (("unzip_at", unzip_at), ("unzip_gc", unzip_gc)):
        number(f"{name} (pN)", f)
    fixed = {"sequence", "break_forces", "break_force_at", "break_force_gc"} & set(duplex_options)
    if fixed:
        raise _invalid(f"break_forces_for_unzipping sets {sorted(fixed)} itself (its probes' sequence and bonds)")
    key = repr(sorted(duplex_options.items()))
    if key not in _PROBES:
        probe = []
        for fb in (10.0, 30.0):
            d = build_duplex("AT" * 6, break_forces=[fb] * 12, **duplex_options)
            probe.append(unzipping_plateau(unzip(d, distance=12.0, progress_bar=progress_bar, **QUASI_STATIC)))
        alpha = (probe[1] - probe[0]) / 20.0
        if not alpha > 0:
            raise _invalid(f"unzipping probes gave plateaus {probe} pN for break forces 10 and 30 pN: "
                           "no break force sets the unzipping force of this duplex")
        _PROBES[key] = (alpha, alpha * 10.0 - probe[0])
    alpha, beta = _PROBES[key]
    return (float(unzip_at) + beta) / alpha, (float(unzip_gc) + beta) / alpha
