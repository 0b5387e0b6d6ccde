"""Argument checks shared by the DNA experiments: clear
``InvalidInputError``s, never a silent truncation or a bare ValueError."""
from __future__ import annotations

import math
import numbers

from ..errors import _invalid


def number(name: str, x, *, low: float = 0.0, strict: bool = True, allow_inf: bool = False) -> float:
    """``x`` as a float > ``low`` (≥ with ``strict=False``), finite unless
    ``allow_inf``."""
    try:
        v = float(x)
    except (TypeError, ValueError):
        raise _invalid(f"{name} must be a number, got {x!r}") from None
    if math.isnan(v) or (math.isinf(v) and not allow_inf) or not (v > low if strict else v >= low):
        raise _invalid(f"{name} must be a {'' if allow_inf else 'finite '}number {'>' if strict else '≥'} {low}, got {x}")
    return v


def integer(name: str, x, low: int) -> int:
    """``x`` as an int ≥ ``low``; a float only when it is a whole number."""
    if isinstance(x, bool) or not isinstance(x, numbers.Real) or not math.isfinite(x) or not float(x).is_integer() \
            or x < low:
        raise _invalid(f"{name} must be an integer ≥ {low}, got {x!r}")
    return int(x)


def noise_scheme(temperature: float, scheme):
    """The World scheme for a run at ``temperature`` (K): ``scheme`` as
    given, else the trapezoidal rule with noise and implicit Euler
    without. The trapezoidal rule keeps the Gibbs distribution of harmonic
    modes at any step where it averages the forces; the duplex's stacking
    and bonds are held at each step's end, which damps as implicit Euler
    does: at 5 ps a pulled 100 bp duplex keeps 0.88 of its exact axis tilt
    (implicit Euler 0.87; ``docs/dna_calibration.md``)."""
    if scheme is not None:
        return scheme
    return "trapezoidal" if temperature > 0 else "implicit_euler"


def check_bonds_under_noise(d, temperature: float) -> None:
    """With thermal noise a bond's instantaneous tension swings by tens of
    pN (|F| 58 pN on average at 1 ps steps): bonds that break on it all
    break in the first steps. Refused unless they break on an average."""
    if temperature <= 0 or d.params.get("break_averaging_time", 0.0) > 0:
        return
    staggers = d.params.get("stagger_break_forces") or []
    if any(math.isfinite(f) for f in list(d.break_forces) + list(staggers)):
        raise _invalid(f"at {temperature:g} K the duplex's bonds would all break in the first steps (their "
                       "instantaneous tension swings by tens of pN): build it with break_averaging_time (ns, "
                       "about 1) or with unbreakable bonds (break_forces=[math.inf] * n)")
