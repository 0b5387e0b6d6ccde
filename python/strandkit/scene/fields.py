"""Typed fields of the scene format: one table drives validation (with the
offending key named), the defaults, and the generated JSON Schema."""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Dict, Sequence, Tuple

from ..errors import _scene_error

REQUIRED = object()

#: JSON Schema fragment of each field type.
SCHEMA = {
    "number": {"type": "number"},
    "positive": {"type": "number", "exclusiveMinimum": 0},
    "nonneg": {"type": "number", "minimum": 0},
    "count": {"type": "integer", "minimum": 1},
    "integer": {"type": "integer"},
    "bool": {"type": "boolean"},
    "string": {"type": "string", "minLength": 1},
    "vec3": {"type": "array", "items": {"type": "number"}, "minItems": 3, "maxItems": 3},
    "labels": {"oneOf": [{"type": "string", "minLength": 1},
                         {"type": "array", "items": {"type": "string", "minLength": 1}}]},
    "abscissa": {"oneOf": [{"type": "number"}, {"enum": ["start", "end"]}]},
    "object": {"type": "object"},
}

_EXPECTED = {
    "number": "a finite number",
    "positive": "a finite number > 0",
    "nonneg": "a finite number >= 0",
    "count": "an integer >= 1",
    "integer": "an integer",
    "bool": "true or false",
    "string": "a non-empty string",
    "vec3": "3 finite numbers",
    "labels": "a list of labels",
    "abscissa": '"start", "end" or a finite spline parameter',
    "object": "a table of keys",
}


@dataclass(frozen=True)
class Field:
    """One key: its type (a key of ``SCHEMA``), unit, documentation and default
    (``REQUIRED`` when it must be given; ``None``: optional, absent)."""

    name: str
    ty: str
    unit: str
    doc: str
    default: Any = REQUIRED
    choices: Tuple[str, ...] = ()

    def schema(self) -> dict:
        s = dict({"enum": list(self.choices)} if self.choices else SCHEMA[self.ty])
        unit = f" [{self.unit}]" if self.unit else ""
        s["description"] = self.doc + unit
        if self.default is None:  # optional, absent: null in the written scene
            return {"anyOf": [s, {"type": "null"}], "description": s.pop("description")}
        if self.default is not REQUIRED:
            s["default"] = self.default
        return s


def finite(x) -> bool:
    return isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x)


def check_value(f: Field, value, key: str):
    """``value`` checked against ``f`` (ints accepted for numbers); a
    SceneError naming ``key`` otherwise."""
    bad = lambda: _scene_error(key, f"{value!r} is not valid", value, _EXPECTED[f.ty])  # noqa: E731
    if f.choices:
        if value not in f.choices:
            raise _scene_error(key, f"unknown value {value!r}", value, "one of " + ", ".join(map(repr, f.choices)))
        return value
    t = f.ty
    if t in ("number", "positive", "nonneg"):
        if not finite(value) or (t == "positive" and value <= 0) or (t == "nonneg" and value < 0):
            raise bad()
        return float(value)
    if t in ("count", "integer"):
        if isinstance(value, float) and value.is_integer():  # 10.0 is an integer to JSON Schema too
            value = int(value)
        if isinstance(value, bool) or not isinstance(value, int) or (t == "count" and value < 1):
            raise bad()
        return value
    if t == "bool":
        if not isinstance(value, bool):
            raise bad()
        return value
    if t == "string":
        if not isinstance(value, str) or not value:
            raise bad()
        return value
    if t == "vec3":
        if not isinstance(value, (list, tuple)) or len(value) != 3 or not all(finite(x) for x in value):
            raise bad()
        return [float(x) for x in value]
    if t == "labels":
        if isinstance(value, str):
            value = [value]
        if not isinstance(value, (list, tuple)) or not all(isinstance(x, str) and x for x in value):
            raise bad()
        return list(value)
    if t == "abscissa":
        if value in ("start", "end") or finite(value):
            return value
        raise bad()
    if t == "object":
        if not isinstance(value, dict):
            raise bad()
        return value
    raise AssertionError(f"field type {t}")  # the tables below use only the types above


def check_table(fields: Sequence[Field], table, key: str) -> Dict[str, Any]:
    """A table (dict) checked key by key: unknown keys and missing required
    ones are named; absent optional keys take their defaults."""
    if not isinstance(table, dict):
        raise _scene_error(key, f"expected a table of keys, got {type(table).__name__}", table)
    known = {f.name: f for f in fields}
    for k in table:
        if k not in known:
            raise _scene_error(f"{key}.{k}" if key else k, "unknown key", None,
                               "one of " + ", ".join(sorted(known)))
    out = {}
    for f in fields:
        sub = f"{key}.{f.name}" if key else f.name
        if f.name in table and table[f.name] is not None:
            out[f.name] = check_value(f, table[f.name], sub)
        elif f.default is REQUIRED:
            raise _scene_error(sub, "missing", None, f"{_EXPECTED[f.ty] if not f.choices else 'one of ' + ', '.join(map(repr, f.choices))}")
        else:
            out[f.name] = f.default
    return out


def one_key_tables(value, key: str, names, what: str, expected: str):
    """(key[i], name, arguments) of a list of one-key tables ``{name: {…}}``
    whose names are in ``names``; None is an empty list. The errors name the
    entry (an unknown name: ``key[i].name``)."""
    if value is None:
        return []
    if not isinstance(value, list):
        raise _scene_error(key, f"expected {expected}", value)
    out = []
    for i, entry in enumerate(value):
        sub = f"{key}[{i}]"
        if not isinstance(entry, dict) or len(entry) != 1:
            raise _scene_error(sub, f"expected one {what} as {{name: {{…}}}}", entry, "one of " + ", ".join(names))
        name, args = next(iter(entry.items()))
        if name not in names:
            raise _scene_error(f"{sub}.{name}", f"unknown {what}", None, "one of " + ", ".join(names))
        out.append((sub, name, args if args is not None else {}))
    return out


def table_schema(fields: Sequence[Field], doc: str = "") -> dict:
    """The JSON Schema of a table of ``fields`` (no other keys)."""
    s = {"type": "object", "additionalProperties": False,
         "properties": {f.name: f.schema() for f in fields},
         "required": [f.name for f in fields if f.default is REQUIRED]}
    if doc:
        s["description"] = doc
    return s
