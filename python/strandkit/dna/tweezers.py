"""Magnetic tweezers on a duplex (issue 17, SPEC §9.1): the first two base
pairs are held on the surface, the last two on the bead; the bead pulls
with a constant ``force`` along the duplex axis (z) and turns about it at a
steady rate, after ``wait`` ns at rest under the force. Records the bead's
turns, the extension (bead − surface, along z), the free pairs'
deflection from the axis and the torques about the axis on the bead and
the surface — positive turns overwind the right-handed helix and need a
positive torque. Units: nm, pN, ns, pN·nm.

The bead holds each of its four nucleotides on a vertical line through
its rotated start (they slide along z together with the duplex: the pull
is shared F/4 each), so its end is clamped in tilt and turned about the
axis; the surface holds its four in place. A lateral force of
``imperfection`` × force (along x, at the middle pair) stands for the
imperfections of a real set-up: without it a zero-temperature duplex
stays straight past its buckling torque (a perfect bifurcation waits for
round-off). The rungs of the held pairs are taken out (the holders keep
those pairs' geometry; a rung between two held points would only repeat
them).

A straight elastic rod under tension F buckles when the torque reaches
M_c = 2√(BF) (B the bending stiffness; ``polymer.buckling_torque`` gives
the clamped rod's finite-length value); the extension, which grew with
the overwinding (twist–stretch coupling), then falls. ``buckling`` finds
that point: the extension's peak, and the elastic torque there
(``TwistResult.elastic_torque``: the bead's and the surface's torques
differ by the rotation's drag).
Turned slowly enough that the buckling mode keeps up (its relaxation
slows near the threshold), the peak is the threshold.

>>> import strandkit as sk
>>> r = sk.dna.experiments.magnetic_tweezers("GATTACA" * 2, force=5.0, turns=0.05, wait=0.5, progress_bar=False)
>>> r
TwistResult(14 bp at 5 pN, 0 K: 31 records over 3.01 ns, 0.05 turns, torque up to ... pN·nm)
>>> print(sk.dna.experiments.buckling(r))   # 0.05 turns: far from buckling
None
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable, List, Optional, Union

import numpy as np

from ..errors import _invalid
from .._native import World
from .._progress import progress
from ..constraints import position
from ..loads import point_force
from ._checks import check_bonds_under_noise, integer, noise_scheme, number
from .duplex import as_duplex
from .fluctuations import pair_frames
from ._records import Records

__all__ = ["TwistResult", "magnetic_tweezers", "buckling"]

MAX_STEPS = 5_000_000  # a run longer than this is a mistake in its parameters


@dataclass
class TwistResult:
    """Records of a magnetic-tweezers run: ``time`` (ns), ``turns`` of the
    bead, ``extension`` (nm, bead − surface along the axis), ``deflection``
    (nm, rms over the free pairs of their axis points' distance from the
    line of the clamps), ``torque`` (pN·nm, the bead's on the duplex about
    the axis), ``surface_torque`` (pN·nm, the duplex's on the surface: equal
    to ``torque`` at rest; turning, they differ by the rotation's drag);
    ``force`` (pN),
    ``temperature`` (K), ``contour`` (nm, between the held pairs at rest);
    ``breaks``: one dict per constraint that broke (``time``, ``label``,
    ``force``); ``paths``: files written."""

    n_bp: int
    force: float
    temperature: float
    contour: float
    time: np.ndarray
    turns: np.ndarray
    extension: np.ndarray
    deflection: np.ndarray
    torque: np.ndarray
    surface_torque: np.ndarray
    breaks: List[dict] = field(default_factory=list)
    paths: dict = field(default_factory=dict)

    @property
    def elastic_torque(self) -> np.ndarray:
        """The torque averaged along the duplex (pN·nm), C_eff × twist / L:
        turning steadily, each section's drag grows with its rotation speed,
        ∝ its distance from the surface, so the torque grows quadratically
        from the surface's to the bead's and its mean is the surface's + ⅓
        of the difference (its slope against the turns: 1.1 % above
        (C − g²/S)/L at 40 bp, tests/test_dna_twist.py, 3 %; 1.7 % at 300 bp,
        examples/dna_twist.py, 3 %)."""
        return self.surface_torque + (self.torque - self.surface_torque) / 3.0

    def __repr__(self) -> str:
        peak = float(np.max(np.abs(self.torque))) if len(self.torque) else float("nan")
        return (f"TwistResult({self.n_bp} bp at {self.force:g} pN, {self.temperature:g} K: {len(self.time)} records "
                f"over {self.time[-1] if len(self.time) else 0:.3g} ns, {self.turns[-1] if len(self.turns) else 0:.3g} "
                f"turns, torque up to {peak:.3g} pN·nm)")


def magnetic_tweezers(sequence_or_duplex, *, force: float = 5.0, turns: float = 3.0,
                      turns_per_ns: Union[float, Callable[[float], float]] = 0.02,
                      wait: float = 20.0, dt: float = 0.01, viscosity: float = 1.0, temperature: float = 0.0,
                      seed: int = 0, scheme: Optional[str] = None, brownian: bool = False, held_pairs: int = 2,
                      imperfection: float = 0.01,
                      record_every: int = 10, out: Optional[str] = None, frame_every: int = 100,
                      progress_bar: bool = True, duplex_options=None) -> TwistResult:
    """Turns the bead end of a duplex by ``turns`` (negative: unwinding) at
    ``turns_per_ns`` (a number, or a function of the turns done giving the
    rate: fast, then slow near the buckling) under a constant ``force``
    (pN) after ``wait`` ns at rest (see the module). dt: ns (a step refused
    as diverged is retried in sub-steps); viscosity: pN·ns/nm² (water: 1;
    with the rate it sets how far from quasi-static the run is: the duplex's twist
    relaxes over ~γ_θ L²/(π² C)); temperature: K (0: no noise; seed for the
    noise; the duplex's bonds must then break on an averaged tension,
    ``duplex(break_averaging_time=…)``, or not at all); scheme: the World's
    (default: trapezoidal with noise, implicit Euler without); brownian:
    overdamped (Brownian) dynamics with isotropic drag, as in
    ``experiments.pull`` (with implicit Euler it samples the slow bending
    and writhe modes that buckling is made of at a fraction of the
    trapezoidal rule's cost, ``docs/dna_calibration.md``); held_pairs:
    pairs held at each end; imperfection: the lateral
    force at the middle pair as a fraction of ``force``; record_every: steps between
    records; out: file prefix for ``.csv`` (streamed, so an interrupted run
    keeps its records) and the trajectory; frame_every: steps between
    frames. A sequence is built with ``duplex_options`` (``duplex``'s)."""
    force = number("force (pN)", force)
    turns = number("turns", turns, low=-math.inf)
    if turns == 0.0:
        raise _invalid("turns must be non-zero (negative: unwinding)")
    if callable(turns_per_ns):
        rate_at = turns_per_ns
    else:
        fixed = number("turns_per_ns", turns_per_ns)
        rate_at = lambda _: fixed  # noqa: E731
    wait, dt = number("wait (ns)", wait, strict=False), number("dt (ns)", dt)
    viscosity = number("viscosity (pN·ns/nm²)", viscosity)
    temperature = number("temperature (K)", temperature, strict=False)
    imperfection = number("imperfection", imperfection, strict=False)
    held_pairs, record_every = integer("held_pairs", held_pairs, 1), integer("record_every", record_every, 1)
    if not isinstance(brownian, bool):
        raise _invalid(f"brownian must be True or False, got {brownian!r}")
    frame_every, seed = integer("frame_every", frame_every, 1), integer("seed", seed, 0)
    n_wait = int(round(wait / dt))
    if n_wait > MAX_STEPS:
        raise _invalid(f"{n_wait} steps to wait {wait} ns: raise dt (at most {MAX_STEPS:.0e} steps)")
    if not callable(turns_per_ns) and n_wait + abs(turns) / fixed / dt > MAX_STEPS:  # before the schedule is built
        raise _invalid(f"{abs(turns) / fixed / dt:.3g} steps to turn {turns} turns: raise turns_per_ns or dt")
    d = as_duplex(sequence_or_duplex, duplex_options)
    check_bonds_under_noise(d, temperature)
    n = len(d)
    if n < 2 * held_pairs + 4:
        raise _invalid(f"a {n} bp duplex is too short to twist with {held_pairs} pairs held at each end: "
                       f"at least {2 * held_pairs + 4} bp")
    if any(k is None for k in d.hbonds[:held_pairs] + d.hbonds[n - held_pairs:]):
        raise _invalid("the held pairs must be paired (a mismatch at an end)")
    # The bead's turns after each turning step (the rate may depend on them).
    schedule = [0.0]
    while schedule[-1] < abs(turns):
        r = float(rate_at(schedule[-1]))
        if not (math.isfinite(r) and r > 0):
            raise _invalid(f"turns_per_ns({schedule[-1]:g}) = {r}: expected a positive number of turns per ns")
        schedule.append(min(schedule[-1] + r * dt, abs(turns)))
        if n_wait + len(schedule) > MAX_STEPS:
            raise _invalid(f"more than {MAX_STEPS:.0e} steps to turn {turns} turns: raise turns_per_ns or dt")
    n_turn = len(schedule) - 1

    # adaptive_dt: a step refused (a kick too large for one step) is retried
    # in sub-steps, as in experiments.pull.
    world = World(units="molecular", dt=dt, viscosity=viscosity, temperature=temperature, seed=seed,
                  scheme=noise_scheme(temperature, scheme), overdamped=brownian, isotropic_drag=brownian,
                  adaptive_dt=True)
    ins = world.insert(d.assembly)
    rods = [ins.rods[i] for i in d.strands]
    surface = list(range(held_pairs))
    bead = list(range(n - held_pairs, n))
    # The holders replace the held pairs' rungs (and staggers).
    for k in surface + bead:
        for h in (d.hbonds[k], d.staggers[k] if d.staggers else None):
            if h is not None:
                world.remove_constraint(ins.constraints[h])
    points = lambda pairs: [(0, float(d.abscissae[0][k])) for k in pairs] + [  # noqa: E731
        (1, float(d.abscissae[1][int(d.partner[k])])) for k in pairs]
    pos = lambda p: np.asarray(rods[p[0]].position(p[1]), dtype=float)  # noqa: E731
    surface_points = points(surface)
    anchors = [world.add_constraint(rods[p[0]], position(p[1], pos(p), axes="xyz")) for p in surface_points]
    bead_points = points(bead)
    starts = [pos(p) for p in bead_points]
    holders = [world.add_constraint(rods[s], position(u, x0, axes="xy")) for (s, u), x0 in zip(bead_points, starts)]
    for s, u in bead_points:
        world.add_load(point_force(rods[s], u, (0.0, 0.0, force / len(bead_points))))
    if imperfection > 0:
        for s, u in points([n // 2]):
            world.add_load(point_force(rods[s], u, (0.5 * imperfection * force, 0.0, 0.0)))
    surface_z = float(np.mean([pos(p)[2] for p in surface_points]))
    contour = float(np.mean([x[2] for x in starts])) - surface_z

    def angle(step):
        """The bead's angle (rad) at turning step ``step`` (0: the first
        solve, at rest)."""
        return math.copysign(schedule[min(max(step - n_wait, 0), n_turn)], turns) * 2.0 * math.pi

    def torque(handles, where):
        """Torque (pN·nm) about the axis x = y = 0 of the holders' forces."""
        total = 0.0
        for h, p in zip(handles, where):
            x, f = pos(p), np.asarray(world.reaction(h).force, dtype=float)
            total += x[0] * f[1] - x[1] * f[0]  # (r × f)·ẑ
        return total

    breaks = []
    rate_text = "a rate profile" if callable(turns_per_ns) else f"{turns_per_ns} turns/ns"
    records = Records(("time", "turns", "extension", "deflection", "torque", "surface_torque"),
                      ["time_ns", "turns", "extension_nm", "deflection_nm", "torque_pNnm", "surface_torque_pNnm"], out,
                      f"strandkit.dna.experiments.magnetic_tweezers: {d!r}; force {force} pN, {turns} turns at "
                      f"{rate_text} after {wait} ns, {temperature} K{', Brownian' if brownian else ''}", world, d, ins, frame_every)

    def record(step):
        free = pair_frames(d, rods[0], rods[1])[0][held_pairs:n - held_pairs, :2]
        records.add((world.time, angle(step) / (2.0 * math.pi),
                     float(np.mean([pos(p)[2] for p in bead_points])) - surface_z,
                     float(np.sqrt(np.mean(np.sum(free ** 2, axis=1)))),
                     torque(holders, bead_points), -torque(anchors, surface_points)))

    with records:
        world.step()  # a first solve at rest, so that the first record has reactions
        record(0)
        for step in progress(range(1, n_wait + n_turn + 1), desc="magnetic tweezers", enable=progress_bar):
            c, s_ = math.cos(angle(step)), math.sin(angle(step))
            for h, (s, u), x0 in zip(holders, bead_points, starts):
                world.set_constraint(h, position(u, (c * x0[0] - s_ * x0[1], s_ * x0[0] + c * x0[1], 0.0), axes="xy"))
            report = world.step()
            for ev in report.events:
                if ev.kind == "ConstraintBroken":
                    breaks.append(dict(time=world.time, label=ev.label, force=ev.force))
            if step % record_every == 0:
                record(step)
            records.step(step)
    arr = records.arrays()
    return TwistResult(n, force, temperature, contour, arr["time"], arr["turns"], arr["extension"], arr["deflection"],
                       arr["torque"], arr["surface_torque"], breaks, records.paths)


def buckling(result: TwistResult) -> Optional[dict]:
    """The buckling of a run: where the extension peaks once the bead
    turns — ``turns``, ``torque`` (pN·nm: ``elastic_torque`` there),
    ``bead_torque``, ``extension``
    (nm) and ``index`` of the record. None if the extension has not
    fallen past its peak by the end of the run, and for an unwinding run
    (DNA shortens as it unwinds, so its extension has no peak to find)."""
    ext = result.extension
    turning = np.nonzero(result.turns > 0)[0]
    if not len(turning) or result.turns[-1] < 0:
        return None
    peak = int(turning[0] + np.argmax(ext[turning]))
    if peak == turning[0]:
        return None
    if peak >= len(ext) - 1 or ext[-1] >= ext[peak] - 1e-3 * abs(ext[peak]):
        return None
    return dict(index=peak, turns=float(result.turns[peak]),
                torque=float(result.elastic_torque[peak]),
                bead_torque=float(result.torque[peak]), extension=float(ext[peak]))
