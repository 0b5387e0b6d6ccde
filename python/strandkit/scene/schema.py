"""The JSON Schema of the scene format (draft 2020-12), generated from the
same field tables that check scenes; ``tools/gen_scene_schema.py`` writes it
to ``strandkit/scene.schema.json`` (a test keeps the shipped file equal)."""
from __future__ import annotations

from .fields import table_schema
from .format import CONTACT_FIELDS, FORMAT, OBSTACLE_FIELDS, OUTPUT_FIELDS, VERSION, world_settings
from .protocol import OPS
from .structures import BUILDERS


def _world_schema() -> dict:
    props = {}
    for k, d in world_settings().items():
        if isinstance(d, bool):
            props[k] = {"type": "boolean", "default": d}
        elif isinstance(d, (int, float)):
            props[k] = {"type": "number" if isinstance(d, float) else "integer", "default": d}
        elif d is None:  # an optional number (max_move), off unless given
            props[k] = {"type": ["number", "null"], "exclusiveMinimum": 0, "default": None}
        elif isinstance(d, list):
            props[k] = {"type": "array", "items": {"type": "number"}, "minItems": len(d), "maxItems": len(d),
                        "default": d}
        else:
            props[k] = {"type": "string", "default": d}
    props["units"]["enum"] = ["si", "molecular"]
    return {"type": "object", "additionalProperties": False, "properties": props,
            "description": "strandkit.World settings (see World's docstring for units)"}


def _one_of_tables(tables: dict) -> dict:
    return {"oneOf": [{"type": "object", "additionalProperties": False, "required": [name],
                       "properties": {name: schema}} for name, schema in tables.items()]}


def schema() -> dict:
    """The scene format's JSON Schema as a dict."""
    structure = {"oneOf": [
        {"type": "object", "additionalProperties": False, "required": ["builder"],
         "properties": {"builder": {"enum": sorted(BUILDERS)},
                        "args": {"type": "object", "description": "the builder's keyword arguments (SI units, "
                                 "nm-pN-ns for dna.duplex)"}}},
        {"type": "object", "additionalProperties": False, "required": ["assembly"],
         "properties": {"assembly": {"type": ["object", "string"],
                                     "description": "an Assembly's JSON (a string of it in TOML)"}}},
        {"type": "object", "additionalProperties": False, "required": ["assembly_file"],
         "properties": {"assembly_file": {"type": "string", "description": "path relative to the scene file"}}},
    ]}
    ops = {name: table_schema(op.fields, op.doc) for name, op in OPS.items()}
    obstacles = {name: table_schema(fields) for name, fields in OBSTACLE_FIELDS.items()}
    return {
        "$schema": "https://json-schema.org/draft/2020-12/schema",
        "$id": f"strandkit-scene-v{VERSION}",
        "title": "strandkit scene",
        "type": "object",
        "additionalProperties": False,
        "required": ["version", "structure"],
        "properties": {
            "format": {"const": FORMAT},
            "version": {"const": VERSION},
            "name": {"type": "string"},
            "description": {"type": "string"},
            "world": _world_schema(),
            "structure": structure,
            "contact": table_schema(CONTACT_FIELDS, "rod–rod and self-contact (World.contact)"),
            "obstacles": {"type": "array", "items": _one_of_tables(obstacles)},
            "protocol": {"type": "array", "items": _one_of_tables(ops)},
            "outputs": table_schema(OUTPUT_FIELDS, "files written by a run"),
        },
    }
