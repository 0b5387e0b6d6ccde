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
