"""The duplex's thermal elasticity, measured from its own fluctuations
(issue 17's calibration): a free duplex is stepped with thermal noise and
its base-pair frames are read every few steps. Units: nm, pN, ns, K.

Each pair is framed as the stacking frames it: x along the rung, z the
local axis (the central difference of the rung midpoints, made ⟂ x), the
origin on the helix axis (midpoint + ½ rung / tan(φ/2) along z × x). Over
every window of k steps between pairs away from the ends (contour
L = k × rise):

- the twist Tw (rung rotations about the local axis, summed) and the
  contour Lc (rises along the local axis, summed) fluctuate as
  Cov(Lc, Tw) = L kT [[S, g], [g, C]]⁻¹: the slopes over L give the
  stretch modulus with twist free S_eff = kT / slope(var Lc) = S − g²/C
  (what force–extension measures), the twist stiffness with stretch free
  C_eff = kT / slope(var Tw) = C − g²/S (what rotation at fixed force
  measures) and, inverting the 2×2 slopes, S, C and the twist–stretch
  coupling g (g < 0: the duplex overwinds when stretched);
- the axes' correlation ⟨z_i·z_{i+k}⟩ = e^{−L/A} gives the bending
  persistence A (the slope of −ln⟨cos⟩ over L).

Fitting slopes leaves each pair's own local wobble in the intercepts. The
default trapezoidal rule keeps the stationary covariance of the harmonic
modes exact at any step (Crank–Nicolson on an Ornstein–Uhlenbeck
process), so the 10 ps step measures what a finer one would; implicit
Euler makes the stiff modes cold (BENCHMARKS §19). Standard errors come
from ``blocks`` consecutive blocks of the run.

>>> import strandkit as sk
>>> m = sk.dna.experiments.thermal_elasticity("GATTACA" * 3, duration=1.0, equilibration=0.0,
...                                          progress_bar=False)   # a 1 ns glimpse; ~150 ns to measure
>>> m.samples, sorted(m.errors)
(40, ['bending_persistence', 'stretch_modulus', 'twist_persistence', 'twist_stretch'])
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Optional

import numpy as np

from ..errors import _invalid
from .._native import World
from .._progress import progress
from .. import units
from ._checks import integer, number
from .duplex import Duplex, as_duplex

__all__ = ["ThermalElasticity", "thermal_elasticity", "pair_frames"]

MAX_STEPS = 5_000_000  # a longer run is a mistake in its parameters
FIELDS = ("bending_persistence", "stretch_modulus", "twist_persistence", "twist_stretch")


@dataclass
class ThermalElasticity:
    """Elastic constants measured from thermal fluctuations:
    ``bending_persistence`` A (nm), ``stretch_modulus`` S_eff (pN, twist
    free), ``twist_persistence`` C_eff/kT (nm, stretch free),
    ``twist_stretch`` g (pN·nm), ``stiffness`` the 2×2 [[S, g], [g, C]]
    (pN, pN·nm, pN·nm²); ``errors``: standard error of each of the four
    from the run's blocks; ``contour`` the windows' lengths (nm) and
    ``variances`` their var(Lc) (nm²), var(Tw) (rad²), cov(Lc, Tw) (nm·rad)
    and 1 − ⟨cos θ⟩, for plotting the fits."""

    n_bp: int
    temperature: float
    duration: float
    samples: int
    bending_persistence: float
    stretch_modulus: float
    twist_persistence: float
    twist_stretch: float
    stiffness: np.ndarray
    errors: dict = field(default_factory=dict)
    contour: np.ndarray = field(default_factory=lambda: np.zeros(0))
    variances: dict = field(default_factory=dict)

    def __repr__(self) -> str:
        e = self.errors
        return (f"ThermalElasticity({self.n_bp} bp at {self.temperature:g} K over {self.duration:g} ns: "
                f"A {self.bending_persistence:.1f} ± {e.get('bending_persistence', math.nan):.1f} nm, "
                f"S {self.stretch_modulus:.0f} ± {e.get('stretch_modulus', math.nan):.0f} pN, "
                f"C/kT {self.twist_persistence:.1f} ± {e.get('twist_persistence', math.nan):.1f} nm, "
                f"g {self.twist_stretch:.0f} ± {e.get('twist_stretch', math.nan):.0f} pN·nm)")


def standard_error(block_values) -> float:
    """The standard error of the mean of a run from its blocks' values
    (one estimate per block, blocks long against the correlation time)."""
    v = np.asarray(block_values, dtype=float)
    return float(np.std(v, ddof=1) / math.sqrt(len(v)))


def pair_frames(d: Duplex, a, b):
    """Each pair's frame (origin on the helix axis, x along the rung, z the
    local axis), read from the inserted strands ``a`` and ``b``: arrays
    (n, 3) origin, x, z."""
    pa, pb = a.position(d.abscissae[0]), b.position(d.abscissae[1][d.partner])
    m = 0.5 * (pa + pb)
    x = pb - pa
    x /= np.linalg.norm(x, axis=1)[:, None]
    c = np.empty_like(m)
    c[1:-1] = m[2:] - m[:-2]
    # One-sided second-order differences at the ends.
    c[0] = 4 * m[1] - 3 * m[0] - m[2]
    c[-1] = 3 * m[-1] - 4 * m[-2] + m[-3]
    z = c - x * np.sum(x * c, axis=1)[:, None]
    z /= np.linalg.norm(z, axis=1)[:, None]
    # The rung's midpoint lies ½ rung / tan(φ/2) off the axis (φ: the
    # strands' phase offset), along z × x.
    origin = m + 0.5 * d.rung_length / math.tan(0.5 * d.phase) * np.cross(z, x)
    return origin, x, z


def _steps(origin, x, z):
    """Per base-pair step: twist (rad) and rise (nm) about/along the mean
    axis of its two pairs."""
    zz = z[:-1] + z[1:]
    zz /= np.linalg.norm(zz, axis=1)[:, None]
    p0 = x[:-1] - zz * np.sum(x[:-1] * zz, axis=1)[:, None]
    p1 = x[1:] - zz * np.sum(x[1:] * zz, axis=1)[:, None]
    twist = np.arctan2(np.sum(np.cross(p0, p1) * zz, axis=1), np.sum(p0 * p1, axis=1))
    rise = np.sum((origin[1:] - origin[:-1]) * zz, axis=1)
    return twist, rise


def _estimate(twist, rise, z, skip, rise0, kt):
    """Slopes over the windows' contour → the constants (see the module)."""
    n = z.shape[1]
    ks = np.arange(4, n - 2 * skip)
    ctw, cri = np.cumsum(twist, axis=1), np.cumsum(rise, axis=1)
    vt, vs, cv, bend = [], [], [], []
    for k in ks:
        i = np.arange(skip, n - skip - k)
        tw = ctw[:, i + k - 1] - ctw[:, i - 1]
        lc = cri[:, i + k - 1] - cri[:, i - 1]
        tw = tw - tw.mean(0)
        lc = lc - lc.mean(0)
        vt.append(np.mean(tw * tw))
        vs.append(np.mean(lc * lc))
        cv.append(np.mean(tw * lc))
        bend.append(1.0 - np.mean(np.sum(z[:, i] * z[:, i + k], axis=2)))
    contour = ks * rise0
    st, ss, sc = (np.polyfit(contour, v, 1)[0] for v in (vt, vs, cv))
    stiffness = kt * np.linalg.inv([[ss, sc], [sc, st]])
    sb = np.polyfit(contour, -np.log(1.0 - np.asarray(bend)), 1)[0]
    # A variance that does not grow with the window (a run far too short)
    # measures nothing: NaN, not a negative or infinite stiffness.
    inverse = lambda slope, scale: scale / slope if slope > 0 else math.nan  # noqa: E731
    values = dict(bending_persistence=inverse(sb, 1.0), stretch_modulus=inverse(ss, kt),
                  twist_persistence=inverse(st, 1.0), twist_stretch=stiffness[0, 1])
    return values, stiffness, contour, dict(contour=np.asarray(vs), twist=np.asarray(vt),
                                            covariance=np.asarray(cv), bend=np.asarray(bend))


def thermal_elasticity(sequence_or_duplex, *, temperature: float = 298.15, duration: float = 150.0,
                       dt: float = 0.005, viscosity: float = 0.1, scheme: str = "trapezoidal",
                       equilibration: float = 5.0, every: int = 5, skip: int = 4, blocks: int = 8, seed: int = 1,
                       progress_bar: bool = True, duplex_options=None, brownian: bool = False) -> ThermalElasticity:
    """Measures A, S, C and g of a duplex from its thermal fluctuations
    (see the module): a free duplex at ``temperature`` (K) in a fluid of
    ``viscosity`` (pN·ns/nm²; water is 1) stepped for ``equilibration`` +
    ``duration`` ns with steps ``dt`` (ns), framed every ``every`` steps
    after the equilibration; ``skip`` pairs at each end are left out (their
    ends are floppier). The defaults are the tested run's (40 bp: A, S, C
    within 2–5 %, ``errors`` in the result; at water's viscosity the
    bending modes decorrelate ~10× slower and 200–400 ns gave ±12–16 % on
    A). A sequence is built with unbreakable bonds (the elasticity alone;
    ``duplex_options`` go to ``duplex``); a built Duplex is used as given,
    and a bond breaking during the run is an error. ``brownian``:
    overdamped dynamics with isotropic drag (see ``experiments.pull``);
    with ``duplex_options=dict(averaged_stacking=True)`` it samples the
    duplex's exact statistics at 5 ps steps."""
    temperature, duration = number("temperature (K)", temperature), number("duration (ns)", duration)
    dt, viscosity = number("dt (ns)", dt), number("viscosity (pN·ns/nm²)", viscosity)
    equilibration = number("equilibration (ns)", equilibration, strict=False)
    every, skip = integer("every", every, 1), integer("skip", skip, 1)
    blocks, seed = integer("blocks", blocks, 2), integer("seed", seed, 0)
    n_eq, n_run = int(round(equilibration / dt)), int(round(duration / dt))
    if n_eq + n_run > MAX_STEPS:
        raise _invalid(f"{n_eq + n_run} steps: raise dt or shorten the run (at most {MAX_STEPS:.0e})")
    if n_run // every < 2 * blocks:
        raise _invalid(f"duration {duration} ns gives {n_run // every} samples: at least {2 * blocks} "
                       f"(blocks={blocks}) needed")
    unbreakable = {} if isinstance(sequence_or_duplex, Duplex) else {"break_forces": [math.inf] * len(str(sequence_or_duplex))}
    d = as_duplex(sequence_or_duplex, duplex_options, unbreakable)
    if len(d) < 2 * skip + 8:
        raise _invalid(f"a {len(d)} bp duplex is too short to measure with skip={skip}: at least {2 * skip + 8} bp")
    if not isinstance(brownian, bool):
        raise _invalid(f"brownian must be True or False, got {brownian!r}")
    # adaptive_dt: a step whose Newton iterations diverge is retried in
    # halves (the Brownian path kept) instead of ending the run.
    world = World(units="molecular", dt=dt, viscosity=viscosity, temperature=temperature, seed=seed, scheme=scheme,
                  overdamped=brownian, isotropic_drag=brownian, adaptive_dt=True)
    ins = world.insert(d.assembly)
    a, b = (ins.rods[i] for i in d.strands)
    twist, rise, axes = [], [], []
    for s in progress(range(n_eq + n_run), desc="thermal elasticity", enable=progress_bar):
        report = world.step()
        broken = [ev.label for ev in report.events if ev.kind == "ConstraintBroken"]
        if broken:
            named = ", ".join(broken[:3]) + (f" and {len(broken) - 3} more" if len(broken) > 3 else "")
            raise _invalid(f"{named} broke at t = {world.time:.4g} ns: the fluctuations of a breaking "
                           f"duplex are not its elasticity (build it with unbreakable bonds)")
        if s >= n_eq and (s - n_eq) % every == 0:
            origin, x, z = pair_frames(d, a, b)
            tw, ri = _steps(origin, x, z)
            twist.append(tw)
            rise.append(ri)
            axes.append(z)
    twist, rise, axes = np.asarray(twist), np.asarray(rise), np.asarray(axes)
    kt = units.kT(temperature, "molecular")
    rise0 = float(d.params["rise"])
    values, stiffness, contour, variances = _estimate(twist, rise, axes, skip, rise0, kt)
    size = len(twist) // blocks
    parts = [_estimate(twist[j * size:(j + 1) * size], rise[j * size:(j + 1) * size],
                       axes[j * size:(j + 1) * size], skip, rise0, kt)[0] for j in range(blocks)]
    errors = {f: standard_error([p[f] for p in parts]) for f in FIELDS}
    return ThermalElasticity(len(d), float(temperature), n_run * dt, len(twist), stiffness=stiffness, errors=errors,
                             contour=contour, variances=variances, **{f: float(values[f]) for f in FIELDS})
