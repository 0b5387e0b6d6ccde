"""Worm-like chain references (SPEC §9.1) for thermal rods and DNA.

All lengths in one unit (nm for DNA), forces in force units with ``kT`` in
the matching energy unit (pN and pN·nm in molecular units: ``kT =
strandkit.units.kT(298.15, "molecular")``).

- :func:`wlc_r2` — mean squared end-to-end distance of a free chain.
- :func:`wlc_extension` — exact mean extension of a chain of finite (or
  infinite) contour pulled at its ends, from the transfer matrix of the
  tangent's diffusion on the sphere (Legendre basis), the end tangents free.
- :func:`bouchiat_extension` — Bouchiat et al. (1999)'s interpolation of the
  long chain, solved for the extension (it reproduces the transfer matrix
  to 4e-4).
- :func:`buckling_torque` — the end torque at which a straight elastic rod
  under tension, clamped at both ends, buckles (2√(BF) when long;
  Greenhill's 2.8606 π B / L without tension).
"""
from __future__ import annotations

import math

import numpy as np

from .errors import ConvergenceError, InvalidInputError

__all__ = ["wlc_r2", "wlc_extension", "bouchiat_extension", "buckling_torque"]

_BOUCHIAT = (-0.5164228, -2.737418, 16.07497, -38.87607, 39.49944, -14.17718)


def _positive(name: str, value: float) -> float:
    value = float(value)
    if not (value > 0 and math.isfinite(value)):
        raise InvalidInputError(f"{name} must be positive and finite, got {value}")
    return value


def wlc_r2(persistence: float, contour: float) -> float:
    """⟨R²⟩ = 2AL[1 − (A/L)(1 − e^{−L/A})] of a free worm-like chain of
    persistence length A and contour L (length², same unit)."""
    a, l = _positive("persistence", persistence), _positive("contour", contour)
    return 2 * a * l * (1 - a / l * (-math.expm1(-l / a)))


def _log_partition(f: float, a: float, l: float, lmax: int) -> float:
    """ln Z / L for H = −∇²/(2a) − f cos θ (free end tangents)."""
    j = np.arange(lmax + 1, dtype=float)
    off = -f * (j[:-1] + 1) / np.sqrt((2 * j[:-1] + 1) * (2 * j[:-1] + 3))
    h = np.diag(j * (j + 1) / (2 * a)) + np.diag(off, 1) + np.diag(off, -1)
    w, v = np.linalg.eigh(h)
    e0 = w[0]
    if math.isinf(l):
        return -e0
    return (-l * e0 + math.log(float(np.sum(v[0] ** 2 * np.exp(-l * (w - e0)))))) / l


def wlc_extension(force: float, persistence: float, contour: float = math.inf, kT: float = 1.0, lmax: int = 80) -> float:
    """Mean extension ⟨z⟩/L of an inextensible worm-like chain (persistence
    A, contour L, default infinite) pulled at its ends by ``force``, at
    temperature energy ``kT``: ⟨z⟩/L = ∂(ln Z/L)/∂f with f = F/kT, from the
    transfer matrix in ``lmax + 1`` Legendre states (at least enough to
    resolve the tangent's spread 1/√(fA)). Add F/S for an
    extensible chain of stretch modulus S."""
    a = _positive("persistence", persistence)
    l = float(contour)
    if not (l > 0):
        raise InvalidInputError(f"contour must be positive, got {contour}")
    f = float(force) / _positive("kT", kT)
    if not math.isfinite(f) or f < 0:
        raise InvalidInputError(f"force must be finite and >= 0, got {force}")
    # The tangent's spread about the force is ≈ 1/√(fA): the basis must
    # resolve it (ten states per unit of √(fA)).
    need = int(10 * math.sqrt(f * a)) + 20
    if need > 2000:
        raise InvalidInputError(f"force × persistence / kT = {f * a:.3g} is too large for the transfer matrix (> 4e4); use bouchiat_extension")
    lmax = max(int(lmax), need)
    # Central differences (ln Z is even in f, so z(0) = 0 exactly).
    d = 1e-4 * max(f, 1e-3)
    return (_log_partition(f + d, a, l, lmax) - _log_partition(f - d, a, l, lmax)) / (2 * d)


def bouchiat_extension(force: float, persistence: float, kT: float = 1.0) -> float:
    """⟨z⟩/L of a long worm-like chain from Bouchiat et al. (1999):
    F A/kT = 1/(4(1 − z)²) − 1/4 + z + Σᵢ aᵢ zⁱ (i = 2…7), solved for z."""
    target = float(force) * _positive("persistence", persistence) / _positive("kT", kT)
    if not math.isfinite(target) or target < 0:
        raise InvalidInputError(f"force must be finite and >= 0, got {force}")

    def g(z: float) -> float:
        return 0.25 / (1 - z) ** 2 - 0.25 + z + sum(c * z ** (i + 2) for i, c in enumerate(_BOUCHIAT))

    lo, hi = 0.0, 1.0 - 1e-12
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if g(mid) < target:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def _clamped_determinant(m: float, b: float, f: float, length: float) -> float:
    """The clamped–clamped determinant of B w⁗ − i M w‴ − F w″ = 0
    (w = x + i y the lateral deflection) at torque ``m``, as a real number: w = c₁ + c₂ z + c₃ e^{i k₁ z} + c₄ e^{i k₂ z},
    k₁,₂ = (M ± √(M² − 4BF)) / 2B, with w = w′ = 0 at z = 0 and L."""
    root = math.sqrt(max(m * m - 4.0 * b * f, 0.0))
    k1, k2 = (m + root) / (2.0 * b), (m - root) / (2.0 * b)
    e1, e2 = np.exp(1j * k1 * length), np.exp(1j * k2 * length)
    a = np.array([[1, 0, 1, 1], [0, 1, 1j * k1, 1j * k2], [1, length, e1, e2], [0, 1, 1j * k1 * e1, 1j * k2 * e2]])
    # Imaginary up to round-off once the phase e^{i(k₁+k₂)L/2} is taken out;
    # divided by its trivial zero at k₁ = k₂ (M = 2√(BF)), so that a sign
    # change is a root (the factor (k₁k₂)² = (F/B)² only scales it).
    d = np.linalg.det(a) * np.exp(-0.5j * (k1 + k2) * length)
    return float(d.imag / ((k1 - k2) * (k1 * k2) ** 2))


def buckling_torque(bending_stiffness: float, tension: float, length: float) -> float:
    """End torque M_c (force × length) at which a straight rod of bending
    stiffness B (force × length²), clamped at both ends a ``length`` apart
    (the far end free to slide along the axis) and pulled by ``tension`` F
    (≥ 0), buckles: the smallest M > 2√(BF) with a non-trivial clamped
    solution of B w⁗ − i M w‴ − F w″ = 0 (the twisted rod's linear
    stability). It tends to 2√(BF) when L √(F/B) ≫ 1 (1.9 % above it at
    16, 4.5 % at 10.6) and to Greenhill's 2.8606 π B / L at F = 0. Found by
    bracketing the determinant's first sign change on a grid of the torque,
    then bisection (relative 1e-10)."""
    b, length = _positive("bending_stiffness", bending_stiffness), _positive("length", length)
    f = float(tension)
    if not (math.isfinite(f) and f >= 0):
        raise InvalidInputError(f"tension must be finite and >= 0, got {tension}")
    # At F = 0 a root k is 0 for every M; a tension of 1e-8 B/L² moves M_c
    # by ~1e-8 relative.
    f = max(f, 1e-8 * b / length ** 2)
    m0 = 2.0 * math.sqrt(b * f)
    # Above 2√(BF) the first root lies at ≈ (πB/L)²/(2√(BF)) for long rods and
    # below Greenhill's 2.86π B/L for short ones: a grid geometric in M − m0
    # from well below the former to past the latter.
    first = min((math.pi * b / length) ** 2 / (2.0 * m0), math.pi * b / length)
    grid = m0 + np.geomspace(1e-3 * first, 12.0 * math.pi * b / length, 4001)
    values = np.array([_clamped_determinant(m, b, f, length) for m in grid])
    change = np.nonzero(np.sign(values[1:]) != np.sign(values[:-1]))[0]
    if not len(change):  # not for valid input: the grid spans past the first root
        raise ConvergenceError(f"no buckling torque found below {grid[-1]} (B {b}, F {f}, L {length})")
    lo, hi = grid[change[0]], grid[change[0] + 1]
    flo = _clamped_determinant(lo, b, f, length)
    while hi - lo > 1e-10 * hi:
        mid = 0.5 * (lo + hi)
        fm = _clamped_determinant(mid, b, f, length)
        if (fm > 0) == (flo > 0):
            lo, flo = mid, fm
        else:
            hi = mid
    return 0.5 * (lo + hi)
