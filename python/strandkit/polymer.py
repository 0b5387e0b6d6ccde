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
"""
from __future__ import annotations

import math

import numpy as np

from .errors import InvalidInputError

__all__ = ["wlc_r2", "wlc_extension", "bouchiat_extension"]

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
