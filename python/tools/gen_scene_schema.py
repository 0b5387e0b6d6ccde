"""Writes strandkit/scene.schema.json from strandkit.scene.schema() (the
field tables that check scenes). Run after changing an operation, an output
or a world setting; tests/test_scene.py checks the shipped file is current.

    python3 python/tools/gen_scene_schema.py
"""
import json
import pathlib

from strandkit.scene import schema

PATH = pathlib.Path(__file__).resolve().parents[1] / "strandkit" / "scene.schema.json"

if __name__ == "__main__":
    PATH.write_text(json.dumps(schema(), indent=1, ensure_ascii=False) + "\n", encoding="utf-8")
    print(f"wrote {PATH}")
