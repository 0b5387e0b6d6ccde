"""Helper functions built from the core's catalogues of constraint and load
kinds (``_native.constraint_catalogue()``, ``_native.load_catalogue()``).

Each catalogue entry names a kind (its serde tag), the Python helper, and
its fields with type, unit, documentation and default. From it this module
makes the helper: its signature (fields up to and including the first one
with a default are positional-or-keyword, the rest keyword-only; a field of
type vec4 with a ``roll_keyword`` adds that keyword-only argument), its
docstring (units from the fields), and the coercion of every argument by
field type. ``tools/gen_stubs.py`` writes the type stubs from the same data.
"""
from __future__ import annotations

import inspect
import json
from typing import Any, Callable, Dict, List, Optional, Tuple

from .errors import _invalid

#: Python annotation (as text) of each field type, for signatures and stubs.
ANNOTATIONS = {
    "abscissa": "float",
    "scalar": "float",
    "flag": "bool",
    "vec3": "Sequence[float]",
    "direction": "Sequence[float]",
    "vec2": "Sequence[float]",
    "axes": "Union[str, Sequence[bool]]",
    "vec4": "Sequence[float]",
    "weighted_abscissae": "Sequence[Tuple[float, float]]",
    "rod": "Optional[Rod]",
}

#: How each field type is given, for docstrings.
_GIVEN = {
    "abscissa": "float (spline parameter)",
    "scalar": "float",
    "flag": "bool",
    "vec3": "3 floats",
    "direction": "3 floats, not all zero",
    "vec2": "2 floats",
    "axes": 'letters from "xyzr" (r: roll) or 4 bools',
    "vec4": "3 floats (x, y, z; roll 0) or 4",
    "weighted_abscissae": "(abscissa, weight) pairs",
    "rod": "Rod (in the world; None in an Assembly)",
}

_AXES = {"x": 0, "y": 1, "z": 2, "r": 3}


class Kind(dict):
    """A constraint (or load) kind: ``{"Name": {field: value}}``, as the core
    deserialises it. Printed as ``Name(field=value, ...)``.

    >>> k = Kind({"Plane": {"u": 0.0, "origin": [0, 0, 0], "normal": [0, 0, 1]}})
    >>> k.name, k.fields["normal"]
    ('Plane', [0, 0, 1])
    >>> k
    Plane(u=0.0, origin=[0, 0, 0], normal=[0, 0, 1])
    """

    @property
    def name(self) -> str:
        return next(iter(self))

    @property
    def fields(self) -> dict:
        return self[self.name]

    def __repr__(self) -> str:
        args = ", ".join(f"{k}={v!r}" for k, v in self.fields.items())
        return f"{self.name}({args})"


def plain(v):
    """numpy arrays/scalars → lists/floats; tuples → lists (other objects pass through)."""
    if hasattr(v, "_handle"):
        return v
    if hasattr(v, "tolist"):
        return v.tolist()
    if isinstance(v, tuple):
        return [plain(x) for x in v]
    return v


def _real(v, what: str) -> float:
    try:
        return float(v)
    except (TypeError, ValueError):
        raise _invalid(what, repr(v), "a number") from None


def _reals(v, n: Tuple[int, ...], what: str) -> List[float]:
    try:
        out = [float(x) for x in plain(v)]
    except (TypeError, ValueError):
        raise _invalid(what, repr(v), f"{' or '.join(map(str, n))} numbers") from None
    if len(out) not in n:
        raise _invalid(what, f"{len(out)} values", f"{' or '.join(map(str, n))} values")
    return out


def axes(v, what: str = "axes") -> List[bool]:
    """Axes selection from letters ("xyz", "xyzr", "r"; "roll"/"theta" also
    mean r) or 4 booleans (x, y, z, roll).

    >>> axes("xz"), axes("xyz roll")
    ([True, False, True, False], [True, True, True, True])
    """
    if isinstance(v, str):
        sel = [False] * 4
        for c in v.lower().replace("roll", "r").replace("theta", "r").replace("θ", "r"):
            if c in " ,":
                continue
            if c not in _AXES:
                raise _invalid(what, repr(v), 'letters from "xyz" and "r" (roll)')
            sel[_AXES[c]] = True
        return sel
    sel = list(plain(v))
    if len(sel) != 4 or not all(isinstance(a, (bool, int)) for a in sel):
        raise _invalid(what, repr(v), 'letters such as "xyz" or 4 booleans (x, y, z, roll)')
    return [bool(a) for a in sel]


def coerce(field: dict, v, what: str):
    """One argument → the JSON-able value of its field type."""
    ty = field["ty"]
    if ty in ("abscissa", "scalar"):
        return _real(v, what)
    if ty == "flag":
        if isinstance(v, (bool, int)) or type(v).__name__ == "bool_":
            return bool(v)
        raise _invalid(what, repr(v), "True or False")
    if ty in ("vec3", "direction"):
        return _reals(v, (3,), what)
    if ty == "vec2":
        return _reals(v, (2,), what)
    if ty == "vec4":
        out = _reals(v, (3, 4), what)
        return out + [0.0] if len(out) == 3 else out
    if ty == "axes":
        return axes(v, what)
    if ty == "weighted_abscissae":
        pairs = [_reals(p, (2,), f"{what}[{i}]") for i, p in enumerate(plain(v))]
        return pairs
    if ty == "rod":
        if v is None or isinstance(v, int) or hasattr(v, "_handle"):
            return v
        raise _invalid(what, type(v).__name__, "a Rod")
    return plain(v)


def default_value(field: dict):
    """The Python default of a field (shown in the signature), or
    ``inspect.Parameter.empty`` for a required one."""
    if field.get("default") is None:
        return inspect.Parameter.empty
    v = json.loads(field["default"])
    ty = field["ty"]
    if ty == "axes":
        return "".join(c for c, on in zip("xyzr", v) if on)
    if ty == "vec4" and float(v[3]) == 0.0:
        return tuple(float(x) for x in v[:3])
    if ty in ("vec3", "direction", "vec2", "vec4"):
        return tuple(float(x) for x in v)
    if ty in ("scalar", "abscissa"):
        return float(v)
    return v


def roll_unit(field: dict) -> str:
    """Unit of the roll component of a vec4 field ("length, rad" → "rad")."""
    return field["unit"].split(",")[-1].strip() if field["unit"] else ""


def parameters(info: dict) -> List[Tuple[str, Any, str, Optional[dict]]]:
    """(name, default, kind, field) of every parameter of the helper, in
    order; kind is "positional" or "keyword"; field is None for a roll keyword."""
    out, keyword = [], False
    for f in info["fields"]:
        d = default_value(f)
        out.append((f["name"], d, "keyword" if keyword else "positional", f))
        if d is not inspect.Parameter.empty:
            keyword = True
    for f in info["fields"]:
        if f.get("roll_keyword"):
            out.append((f["roll_keyword"], None, "keyword", None))
    return out


def signature(info: dict) -> inspect.Signature:
    ps = []
    for name, default, kind, f in parameters(info):
        ann = ANNOTATIONS[f["ty"]] if f else "Optional[float]"
        k = inspect.Parameter.POSITIONAL_OR_KEYWORD if kind == "positional" else inspect.Parameter.KEYWORD_ONLY
        ps.append(inspect.Parameter(name, k, default=default, annotation=ann))
    return inspect.Signature(ps, return_annotation="Kind")


def docstring(info: dict, use: str) -> str:
    """Docstring of a helper: the kind's documentation, then its parameters
    with how they are given, units and defaults."""
    lines = [info["doc"], "", "Parameters", "----------"]
    for name, default, _, f in parameters(info):
        if f is None:
            vec4 = next(x for x in info["fields"] if x.get("roll_keyword") == name)
            unit = roll_unit(vec4)
            lines.append(f"{name} : float, optional")
            lines.append(f"    Sets the roll component of ``{vec4['name']}`` ({unit}) and selects the roll axis.")
            continue
        head = f"{name} : {_GIVEN[f['ty']]}"
        if default is not inspect.Parameter.empty:
            head += f", default {default!r}"
        lines.append(head)
        unit = f["unit"] if f["unit"] not in ("", "u") else ""
        lines.append(f"    {f['doc'][:1].upper()}{f['doc'][1:]}" + (f" ({unit})." if unit else "."))
    lines += ["", "Returns", "-------", "Kind", f"    ``{{\"{info['name']}\": {{...}}}}`` for {use}."]
    return "\n".join(lines)


def make_helper(info: dict, module: str, use: str) -> Callable[..., Kind]:
    """The helper function of one catalogue entry."""
    sig = signature(info)
    params = parameters(info)
    name, helper = info["name"], info["helper"]
    fields = info["fields"]
    axes_fields = [f["name"] for f in fields if f["ty"] == "axes"]

    def build(*args, **kwargs) -> Kind:
        try:
            bound = sig.bind(*args, **kwargs)
        except TypeError as e:
            raise TypeError(f"{helper}{sig}: {e}") from None
        bound.apply_defaults()
        a = bound.arguments
        out: Dict[str, Any] = {}
        for pname, _, _, f in params:
            if f is not None:
                out[pname] = coerce(f, a[pname], f"{helper} {pname}")
        for f in fields:
            kw = f.get("roll_keyword")
            if kw and a.get(kw) is not None:
                out[f["name"]][3] = _real(a[kw], f"{helper} {kw}")
                for x in axes_fields:
                    out[x][3] = True
        return Kind({name: out})

    build.__name__ = build.__qualname__ = helper
    build.__module__ = module
    build.__doc__ = docstring(info, use)
    build.__signature__ = sig  # type: ignore[attr-defined]
    return build


def helpers(catalogue: List[dict], module: str, use: Callable[[dict], str]) -> Dict[str, Callable[..., Kind]]:
    """Every helper of a catalogue, by name."""
    return {info["helper"]: make_helper(info, module, use(info)) for info in catalogue}
