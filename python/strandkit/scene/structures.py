"""What a scene simulates: a registered builder called with its keyword
arguments, an Assembly written inline, or an Assembly read from a file.
A builder is one entry of ``BUILDERS`` (module, function, the units its
arguments are in), so a new builder is one registration line here."""
from __future__ import annotations

import importlib
import inspect
import json
import math
import os

from ..errors import StrandkitError, _scene_error

#: name → (module, function, the world units its output is built in).
BUILDERS = {
    "rope_bridge": ("strandkit.builders", "rope_bridge", "si"),
    "necklace": ("strandkit.builders", "necklace", "si"),
    "beads_on_spring": ("strandkit.builders", "beads_on_spring", "si"),
    "cable_on_clips": ("strandkit.builders", "cable_on_clips", "si"),
    "harness": ("strandkit.builders", "harness", "si"),
    "dna.duplex": ("strandkit.dna", "duplex", "molecular"),
    "knit.fabric": ("strandkit.knit", "fabric", "si"),
}

KINDS = ("builder", "assembly", "assembly_file")


def builder_function(name: str, key: str = "structure.builder"):
    if name not in BUILDERS:
        raise _scene_error(key, f"unknown builder {name!r}", name, "one of " + ", ".join(sorted(BUILDERS)))
    module, fn, _ = BUILDERS[name]
    return getattr(importlib.import_module(module), fn)


def _check_like_default(default, value, key: str) -> None:
    """A builder argument of the type of its default: an integer where the
    default is one (3.7 planks would be cut to 3), a boolean where it is
    one, a finite number where it is a float."""
    bad = None
    if isinstance(default, bool):
        bad = not isinstance(value, bool) and "true or false"
    elif isinstance(default, int):
        bad = (isinstance(value, bool) or not (isinstance(value, int) or (isinstance(value, float) and value.is_integer()))) \
            and "an integer"
    elif isinstance(default, float):
        bad = (isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value)) \
            and "a finite number"
    if bad:
        raise _scene_error(key, f"{value!r} is not valid", value, bad)


def check_structure(structure, base_dir: str) -> dict:
    """The structure table checked: exactly one of ``builder`` (+ ``args``),
    ``assembly`` (inline, the Assembly's JSON) or ``assembly_file`` (a path,
    relative to the scene file)."""
    key = "structure"
    if not isinstance(structure, dict):
        raise _scene_error(key, "expected a table", structure, "builder + args, assembly or assembly_file")
    given = [k for k in KINDS if k in structure]
    extra = sorted(set(structure) - set(KINDS) - {"args"})
    if extra:
        raise _scene_error(f"{key}.{extra[0]}", "unknown key", None, "builder, args, assembly or assembly_file")
    if len(given) != 1:
        raise _scene_error(key, f"gives {' and '.join(given) or 'nothing'}", None,
                           "exactly one of builder, assembly, assembly_file")
    if "args" in structure and given != ["builder"]:
        raise _scene_error(f"{key}.args", "args go with a builder only")
    kind = given[0]
    if kind == "builder":
        name = structure["builder"]
        if not isinstance(name, str):
            raise _scene_error(f"{key}.builder", f"{name!r} is not a builder name", name,
                               "one of " + ", ".join(sorted(BUILDERS)))
        fn = builder_function(name)
        args = structure.get("args", {}) or {}
        if not isinstance(args, dict):
            raise _scene_error(f"{key}.args", "expected a table of keyword arguments", args)
        params = inspect.signature(fn).parameters
        for a in args:
            if a not in params or params[a].kind not in (inspect.Parameter.KEYWORD_ONLY,
                                                         inspect.Parameter.POSITIONAL_OR_KEYWORD):
                raise _scene_error(f"{key}.args.{a}", f"unknown argument of {name}", None,
                                   "one of " + ", ".join(p for p in params))
            _check_like_default(params[a].default, args[a], f"{key}.args.{a}")
        out = {}
        for k, v in args.items():
            d = params[k].default
            if v is None and d is None:
                continue  # the default spelled out: TOML cannot write None, so a scene never holds it
            if isinstance(d, int) and not isinstance(d, bool) and isinstance(v, float):
                v = int(v)  # an integral float (checked above), as JSON Schema's integers allow
            out[k] = v
        return {"builder": name, "args": out}
    if kind == "assembly":
        if not isinstance(structure["assembly"], dict):
            raise _scene_error(f"{key}.assembly", "expected the Assembly's JSON object", None)
        return {"assembly": structure["assembly"]}
    path = structure["assembly_file"]
    if not isinstance(path, str) or not path:
        raise _scene_error(f"{key}.assembly_file", "expected a path", path)
    full = path if os.path.isabs(path) else os.path.join(base_dir, path)
    if not os.path.isfile(full):
        raise _scene_error(f"{key}.assembly_file", f"no such file: {full}", path)
    return {"assembly_file": path}


def build(structure: dict, base_dir: str):
    """The Assembly of a checked structure table (a builder's errors and a
    corrupt assembly are SceneErrors naming the key)."""
    from .._native import Assembly
    if "builder" in structure:
        fn = builder_function(structure["builder"])
        args = structure["args"]
        try:
            made = fn(**args)
        except (StrandkitError, ValueError, TypeError, OverflowError) as e:
            what = getattr(e, "what", "") or ""
            key = f"structure.args.{what}" if what in args else "structure.args"
            raise _scene_error(key, f"{structure['builder']}: {e}") from e
        return made.assembly
    if "assembly" in structure:
        text, key = json.dumps(structure["assembly"]), "structure.assembly"
    else:
        path = structure["assembly_file"]
        full = path if os.path.isabs(path) else os.path.join(base_dir, path)
        key = "structure.assembly_file"
        try:
            with open(full, encoding="utf-8") as f:
                text = f.read()
        except OSError as e:
            raise _scene_error(key, f"cannot read {full}: {e.strerror or e}", path) from e
    try:
        return Assembly.from_json(text)
    except (StrandkitError, ValueError) as e:
        raise _scene_error(key, f"not an Assembly: {e}") from e


def default_units(structure: dict) -> str:
    return BUILDERS[structure["builder"]][2] if "builder" in structure else "si"

