"""Magnetic tweezers on a duplex (issue 17, SPEC §9.1): the first two base
pairs are held on the surface, the last two on the bead; the bead pulls
with a constant ``force`` along the duplex axis (z) and turns about it at a
steady rate, after ``wait`` ns at rest under the force. Records the bead's
turns, the extension (bead − surface, along z) and the torque the bead
exerts on the duplex about its axis — positive turns overwind the
right-handed helix and need a positive torque. Units: nm, pN, ns, pN·nm.

The bead holds each of its four nucleotides on a vertical line through
its rotated start (they slide along z together with the duplex: the pull
is shared F/4 each), so its end is clamped in tilt and turned about the
axis; the surface holds its four in place. The rungs of the held pairs
are taken out (the holders keep those pairs' geometry; a rung between
two held points would only repeat them).

A straight elastic rod under tension F buckles when the torque reaches
M_c = 2√(BF) (B the bending stiffness; ``polymer.buckling_torque`` gives
the clamped rod's finite-length value); the torque then drops and the
extension falls. ``buckling`` finds that point in a result.

>>> import strandkit as sk
>>> r = sk.dna.experiments.magnetic_tweezers("GATTACA" * 2, force=5.0, turns=0.05, wait=0.5, progress_bar=False)
>>> r
TwistResult(14 bp at 5 pN, 0 K: 101 records over 3 ns, 0.05 turns, torque ...)
"""
from __future__ import annotations

import csv
import math
import os
from dataclasses import dataclass, field
from typing import List, Optional

import numpy as np

from ..errors import _invalid
from .._native import World
from .._progress import progress
from ..constraints import position
from ..loads import point_force
from .duplex import Duplex, duplex as build_duplex
from .viewer import trajectory as duplex_trajectory

__all__ = ["TwistResult", "magnetic_tweezers", "buckling"]


@dataclass
class TwistResult:
    """Records of a magnetic-tweezers run: ``time`` (ns), ``turns`` of the
    bead, ``extension`` (nm, bead − surface along the axis), ``torque``
    (pN·nm, the bead's on the duplex about the axis); ``force`` (pN),
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
    torque: np.ndarray
    breaks: List[dict] = field(default_factory=list)
    paths: dict = field(default_factory=dict)

    def __repr__(self) -> str:
        peak = float(np.max(np.abs(self.torque))) if len(self.torque) else float("nan")
        return (f"TwistResult({self.n_bp} bp at {self.force:g} pN, {self.temperature:g} K: {len(self.time)} records "
                f"over {self.time[-1] if len(self.time) else 0:.3g} ns, {self.turns[-1] if len(self.turns) else 0:.3g} "
                f"turns, torque up to {peak:.3g} pN·nm)")


def _check(name, x, low=0.0, strict=True):
    x = float(x)
    if not (math.isfinite(x) and (x > low if strict else x >= low)):
        raise _invalid(f"{name} must be a finite number {'>' if strict else '≥'} {low}, got {x}")
    return x


def magnetic_tweezers(sequence_or_duplex, *, force: float = 5.0, turns: float = 3.0, turns_per_ns: float = 0.02,
                      wait: float = 20.0, dt: float = 0.01, viscosity: float = 1.0, temperature: float = 0.0,
                      seed: int = 0, held_pairs: int = 2, record_every: int = 10, out: Optional[str] = None,
                      frame_every: int = 100, progress_bar: bool = True, duplex_options=None) -> TwistResult:
    """Turns the bead end of a duplex by ``turns`` (negative: unwinding) at
    ``turns_per_ns`` under a constant ``force`` (pN) after ``wait`` ns at
    rest (see the module). dt: ns; viscosity: pN·ns/nm² (water: 1; with the
    rate it sets how far from quasi-static the run is: the duplex's twist
    relaxes over ~γ_θ L²/(π² C)); temperature: K (0: no noise; seed for the
    noise); held_pairs: pairs held at each end; record_every: steps between
    records; out: file prefix for ``.csv`` (streamed, so an interrupted run
    keeps its records) and the trajectory; frame_every: steps between
    frames. A sequence is built with ``duplex_options`` (``duplex``'s)."""
    if isinstance(sequence_or_duplex, Duplex):
        if duplex_options:
            raise _invalid(f"duplex options {sorted(duplex_options)} given with a built Duplex")
        d = sequence_or_duplex
    else:
        d = build_duplex(sequence_or_duplex, **dict(duplex_options or {}))
    force = _check("force (pN)", force)
    turns = float(turns)
    if not (math.isfinite(turns) and turns != 0.0):
        raise _invalid(f"turns must be a finite non-zero number, got {turns}")
    rate = _check("turns_per_ns", turns_per_ns)
    wait, dt = _check("wait (ns)", wait, strict=False), _check("dt (ns)", dt)
    viscosity, temperature = _check("viscosity (pN·ns/nm²)", viscosity), _check("temperature (K)", temperature,
                                                                                strict=False)
    held_pairs, record_every, frame_every = int(held_pairs), int(record_every), int(frame_every)
    if held_pairs < 1 or record_every < 1 or frame_every < 1:
        raise _invalid("held_pairs, record_every and frame_every must be ≥ 1")
    n = len(d)
    if n < 2 * held_pairs + 4:
        raise _invalid(f"a {n} bp duplex is too short to twist with {held_pairs} pairs held at each end: "
                       f"at least {2 * held_pairs + 4} bp")
    if any(k is None for k in d.hbonds[:held_pairs] + d.hbonds[n - held_pairs:]):
        raise _invalid("the held pairs must be paired (a mismatch at an end)")
    n_wait, n_turn = int(round(wait / dt)), int(math.ceil(abs(turns) / rate / dt))
    if n_wait + n_turn > 50_000_000:
        raise _invalid(f"{n_wait + n_turn} steps: raise turns_per_ns or dt")

    world = World(units="molecular", dt=dt, viscosity=viscosity, temperature=temperature, seed=int(seed))
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
    for p in points(surface):
        world.add_constraint(rods[p[0]], position(p[1], pos(p), axes="xyz"))
    bead_points = points(bead)
    starts = [pos(p) for p in bead_points]
    holders = [world.add_constraint(rods[s], position(u, x0, axes="xy")) for (s, u), x0 in zip(bead_points, starts)]
    for s, u in bead_points:
        world.add_load(point_force(rods[s], u, (0.0, 0.0, force / len(bead_points))))
    surface_z = float(np.mean([pos(p)[2] for p in points(surface)]))
    contour = float(np.mean([x[2] for x in starts])) - surface_z

    def angle(step):
        """The bead's angle (rad) after ``step`` steps."""
        t = max(step - n_wait, 0) * dt
        return math.copysign(min(rate * t, abs(turns)), turns) * 2.0 * math.pi

    def torque():
        total = 0.0
        for h, (s, u) in zip(holders, bead_points):
            x, f = pos((s, u)), np.asarray(world.reaction(h).force, dtype=float)
            total += x[0] * f[1] - x[1] * f[0]  # (r × f)·ẑ about the axis x = y = 0
        return total

    rec = {c: [] for c in ("time", "turns", "extension", "torque")}
    breaks, paths = [], {}
    writer = fh = tw = None

    def record(step):
        row = (world.time, angle(step) / (2.0 * math.pi),
               float(np.mean([pos(p)[2] for p in bead_points])) - surface_z, torque())
        for c, v in zip(rec, row):
            rec[c].append(v)
        if writer is not None:
            writer.writerow([f"{v:.9g}" for v in row])
            fh.flush()

    try:
        if out is not None:
            os.makedirs(os.path.dirname(os.path.abspath(out)), exist_ok=True)
            paths["csv"] = out + ".csv"
            fh = open(paths["csv"], "w", newline="")
            fh.write(f"# strandkit.dna.experiments.magnetic_tweezers: {d!r}; force {force} pN, {turns} turns at "
                     f"{rate} turns/ns after {wait} ns, {temperature} K\n")
            writer = csv.writer(fh)
            writer.writerow(["time_ns", "turns", "extension_nm", "torque_pNnm"])
            tw = duplex_trajectory(world, d, ins, out, every=frame_every)
            paths.update(tw.paths)
        world.step()  # a first solve, so that the first record has reactions
        record(1)
        for step in progress(range(2, n_wait + n_turn + 1), desc="magnetic tweezers", enable=progress_bar):
            c, s_ = math.cos(angle(step)), math.sin(angle(step))
            for h, (s, u), x0 in zip(holders, bead_points, starts):
                world.set_constraint(h, position(u, (c * x0[0] - s_ * x0[1], s_ * x0[0] + c * x0[1], 0.0), axes="xy"))
            report = world.step()
            for ev in report.events:
                if ev.kind == "ConstraintBroken":
                    breaks.append(dict(time=world.time, label=ev.label, force=ev.force))
            if step % record_every == 0:
                record(step)
            if tw is not None and step % frame_every == 0:
                tw.write()
    finally:
        if tw is not None:
            tw.close()
        if fh is not None:
            fh.close()
    arr = {c: np.asarray(v, dtype=float) for c, v in rec.items()}
    return TwistResult(n, force, temperature, contour, arr["time"], arr["turns"], arr["extension"], arr["torque"],
                       breaks, paths)


def buckling(result: TwistResult, drop: float = 0.02) -> dict:
    """The buckling point of a run: the record of largest |torque| before
    the extension first falls ``drop`` (relative) below its value at that
    record — ``turns``, ``torque`` (pN·nm), ``extension`` (nm) and
    ``index``; None if the extension never falls so."""
    tau, ext = np.abs(result.torque), result.extension
    for i in range(1, len(ext)):
        prior = int(np.argmax(tau[:i]))
        if ext[i] < (1.0 - drop) * ext[prior] and result.turns[i] != 0:
            return dict(index=prior, turns=float(result.turns[prior]), torque=float(result.torque[prior]),
                        extension=float(ext[prior]))
    return None
