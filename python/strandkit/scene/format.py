"""The scene file: a versioned JSON (or TOML) document holding the
structure (a builder and its arguments, or an Assembly), the world's
settings, contact and obstacles, the experiment protocol and the outputs.

A scene is checked whole when it is loaded or made — unknown version or
key, a value out of range, a missing file, a label the protocol uses that
the structure does not have — and the error names the key
(``SceneError.key``), before any work starts.
"""
from __future__ import annotations

import copy
import functools
import hashlib
import json
import math
import os
from typing import Any, Dict, List, Optional

from ..errors import FileError, StrandkitError, _scene_error
from .fields import Field, check_table, finite, one_key_tables
from .protocol import check_labels, check_protocol
from .structures import build, check_structure, default_units

FORMAT = "strandkit-scene"
VERSION = 1

TOP_KEYS = ("format", "version", "name", "description", "world", "structure", "contact", "obstacles",
            "protocol", "outputs")

CONTACT_FIELDS = [
    Field("margin", "positive", "length", "contacts are detected this far before the surfaces touch"),
    Field("self_contact", "bool", "", "a rod against itself", True),
    Field("between_rods", "bool", "", "rods against each other", True),
    Field("friction", "nonneg", "", "Coulomb coefficient μ", 0.0),
]

_OBSTACLE_COMMON = [Field("margin", "nonneg", "length", "detection margin", 0.0),
                    Field("friction", "nonneg", "", "Coulomb coefficient μ against the rods", 0.0)]
OBSTACLE_FIELDS = {
    "plane": [Field("origin", "vec3", "length", "a point of the plane", [0.0, 0.0, 0.0]),
              Field("normal", "vec3", "", "outward normal (not zero)", [0.0, 0.0, 1.0])] + _OBSTACLE_COMMON,
    "sphere": [Field("center", "vec3", "length", "centre"),
               Field("radius", "positive", "length", "radius")] + _OBSTACLE_COMMON,
    "capsule": [Field("a", "vec3", "length", "one end of the axis"), Field("b", "vec3", "length", "the other end"),
                Field("radius", "positive", "length", "radius")] + _OBSTACLE_COMMON,
    "mesh": [Field("path", "string", "", "an .obj or .stl file, relative to the scene file")] + _OBSTACLE_COMMON,
}

OUTPUT_FIELDS = [
    Field("every", "count", "steps", "steps between observable records", 10),
    Field("trajectory", "bool", "", "write trajectory.pdb/.psf/.dcd (one bead per rod sample)", True),
    Field("frame_every", "count", "steps", "steps between trajectory frames (default: 10 × every)", None),
    Field("scale", "positive", "Å per length unit", "trajectory scale (default 10: nm → Å, or m shown ×10)", 10.0),
    Field("groups", "labels", "", "groups whose broken count, summed tension and largest force are recorded", []),
    Field("parquet", "bool", "", "also write observables.parquet (needs pandas and pyarrow)", True),
    Field("plots", "bool", "", "write observables.png (needs matplotlib)", True),
    Field("snapshot_every", "count", "steps", "steps between resume snapshots", 1000),
]


def world_settings() -> Dict[str, Any]:
    """The world's settings and their defaults (World().params, a copy)."""
    return copy.deepcopy(_default_params())


@functools.lru_cache(maxsize=1)
def _default_params() -> Dict[str, Any]:
    from .._native import World
    return World().params


def _check_world(world, units_default: str) -> dict:
    if world is None:
        world = {}
    if not isinstance(world, dict):
        raise _scene_error("world", "expected a table of settings", world)
    known = world_settings()
    out = {}
    for k, v in world.items():
        if k not in known:
            raise _scene_error(f"world.{k}", "unknown setting", None, "one of " + ", ".join(sorted(known)))
        d = known[k]
        if isinstance(d, bool):
            ok = isinstance(v, bool)
        elif isinstance(d, int):
            if isinstance(v, float) and v.is_integer():  # 10.0 is an integer to JSON Schema too
                v = int(v)
            ok = isinstance(v, int) and not isinstance(v, bool) and 0 <= v < 2**63
        elif isinstance(d, float):
            ok = finite(v)
        elif isinstance(d, list):
            ok = isinstance(v, (list, tuple)) and len(v) == len(d) and all(finite(x) for x in v)
        else:
            ok = isinstance(v, str)
        if not ok:
            raise _scene_error(f"world.{k}", f"{v!r} is not valid", v, f"a value like {d!r}")
        out[k] = list(v) if isinstance(v, tuple) else v
    out.setdefault("units", units_default)
    return out


def _failing_setting(settings: dict, e: Exception) -> str:
    """The key of the setting World refused: its own ``what``, else the one
    that fails alone."""
    from .._native import World
    what = getattr(e, "what", "") or ""
    if what in settings:
        return f"world.{what}"
    for k, v in settings.items():
        try:
            World(**{k: v})
        except (StrandkitError, ValueError, TypeError, OverflowError):
            return f"world.{k}"
    return "world"


def _json_plain(x, key: str):
    """The scene as plain JSON values: numpy scalars and arrays become
    numbers and lists; anything else that JSON cannot hold, and NaN or
    infinity, is a SceneError naming its key."""
    if hasattr(x, "tolist") and not isinstance(x, (list, dict, str)):
        x = x.tolist()
    if isinstance(x, dict):
        out = {}
        for k, v in x.items():
            if not isinstance(k, str):
                raise _scene_error(key, f"key {k!r} is not a string")
            out[k] = _json_plain(v, f"{key}.{k}" if key else k)
        return out
    if isinstance(x, (list, tuple)):
        return [_json_plain(v, f"{key}[{i}]") for i, v in enumerate(x)]
    if isinstance(x, float) and not math.isfinite(x):
        raise _scene_error(key, f"{x!r} is not a finite value", x, "a finite number")
    if x is None or isinstance(x, (bool, int, float, str)):
        return x
    raise _scene_error(key, f"a {type(x).__name__} cannot be written in a scene file", None,
                       "numbers, strings, booleans, lists and tables")


def _check_obstacles(obstacles, base_dir: str) -> List[dict]:
    out = []
    for key, kind, args in one_key_tables(obstacles, "obstacles", OBSTACLE_FIELDS, "obstacle", "a list"):
        args = check_table(OBSTACLE_FIELDS[kind], args, f"{key}.{kind}")
        if kind == "mesh":
            full = args["path"] if os.path.isabs(args["path"]) else os.path.join(base_dir, args["path"])
            if not os.path.isfile(full):
                raise _scene_error(f"{key}.mesh.path", f"no such file: {full}", args["path"])
        out.append({kind: args})
    return out


def check_scene(data, base_dir: str = ".") -> dict:
    """The scene checked and completed with defaults (a SceneError naming the
    key otherwise). Does not build anything (see ``Scene.world``)."""
    if not isinstance(data, dict):
        raise _scene_error("", f"a scene is a table of keys, got {type(data).__name__}")
    for k in data:
        if k not in TOP_KEYS:
            raise _scene_error(k, "unknown key", None, "one of " + ", ".join(TOP_KEYS))
    if data.get("format", FORMAT) != FORMAT:
        raise _scene_error("format", f"{data.get('format')!r} is not a strandkit scene", data.get("format"), repr(FORMAT))
    version = data.get("version")
    if version is None:
        raise _scene_error("version", "missing", None, f"{VERSION}")
    if version != VERSION or isinstance(version, bool):
        raise _scene_error("version", f"unknown version {version!r} (this strandkit reads version {VERSION})",
                           version, f"{VERSION}")
    if "structure" not in data:
        raise _scene_error("structure", "missing", None, "builder + args, assembly or assembly_file")
    structure = check_structure(data["structure"], base_dir)
    out = {"format": FORMAT, "version": VERSION}
    for k in ("name", "description"):
        if k in data:
            if not isinstance(data[k], str):
                raise _scene_error(k, "expected a string", data[k])
            out[k] = data[k]
    out["world"] = _check_world(data.get("world"), default_units(structure))
    out["structure"] = structure
    if data.get("contact") is not None:
        out["contact"] = check_table(CONTACT_FIELDS, data["contact"], "contact")
    out["obstacles"] = _check_obstacles(data.get("obstacles"), base_dir)
    out["protocol"] = check_protocol(data.get("protocol"))
    out["outputs"] = check_table(OUTPUT_FIELDS, data.get("outputs") or {}, "outputs")
    return out


def _strip_none(x):
    """TOML has no null: absent keys stand for the defaults."""
    if isinstance(x, dict):
        return {k: _strip_none(v) for k, v in x.items() if v is not None}
    if isinstance(x, list):
        return [_strip_none(v) for v in x]
    return x


class Scene:
    """A checked scene: ``Scene(data, base_dir)`` from a dict in the file
    format, or :func:`load_scene`, :meth:`from_builder`, :meth:`from_assembly`.

    >>> import strandkit as sk
    >>> s = sk.Scene.from_builder("necklace", n_beads=4, world={"gravity": [0, -9.81, 0], "dt": 1e-3},
    ...                           protocol=[{"step": {"steps": 20}}], outputs={"every": 5})
    >>> s
    Scene(builder necklace, 1 operation: step; world dt=0.001 units=si)
    >>> r = s.run(progress_bar=False)
    >>> len(r.observables["time"]), round(r.world.time, 6)
    (5, 0.02)
    """

    def __init__(self, data: dict, base_dir: str = "."):
        self.base_dir = os.path.abspath(base_dir)
        self.data = check_scene(_json_plain(data, ""), self.base_dir)
        self._check_built()

    @classmethod
    def _checked(cls, data: dict, base_dir: str) -> "Scene":
        """A scene from data a Scene has already checked and built (a sweep's
        point, checked in the driver before it was sent): not built again."""
        scene = cls.__new__(cls)
        scene.base_dir, scene.data = base_dir, data
        return scene

    # -- construction -------------------------------------------------------------------------
    @classmethod
    def from_builder(cls, builder: str, *, world: Optional[dict] = None, protocol=(), outputs: Optional[dict] = None,
                     contact: Optional[dict] = None, obstacles=(), name: Optional[str] = None, **args) -> "Scene":
        """A scene of a registered builder (``strandkit.scene.BUILDERS``) called with ``args``."""
        return cls._made({"builder": builder, "args": args}, world, protocol, outputs, contact, obstacles, name)

    @classmethod
    def from_assembly(cls, assembly, *, world: Optional[dict] = None, protocol=(), outputs: Optional[dict] = None,
                      contact: Optional[dict] = None, obstacles=(), name: Optional[str] = None) -> "Scene":
        """A scene of an Assembly (or a builder's result holding one, ``.assembly``), written inline."""
        asm = getattr(assembly, "assembly", assembly)
        return cls._made({"assembly": json.loads(asm.to_json())}, world, protocol, outputs, contact, obstacles, name)

    @classmethod
    def _made(cls, structure, world, protocol, outputs, contact, obstacles, name) -> "Scene":
        data = {"format": FORMAT, "version": VERSION, "structure": structure, "world": world or {},
                "protocol": list(protocol), "outputs": outputs or {}, "obstacles": list(obstacles)}
        if contact is not None:
            data["contact"] = contact
        if name is not None:
            data["name"] = name
        return cls(data)

    # -- building -------------------------------------------------------------------------------
    def world(self):
        """A new World with the structure inserted, contact and obstacles set
        (the protocol is not run). Returns (world, inserted)."""
        from .. import obstacles as obs
        from .._native import World
        settings = self.data["world"]
        try:
            w = World(**settings)
        except (StrandkitError, ValueError, TypeError, OverflowError) as e:
            raise _scene_error(_failing_setting(settings, e), str(e)) from e
        ins = w.insert(build(self.data["structure"], self.base_dir))
        c = self.data.get("contact")
        if c is not None:
            w.contact(margin=c["margin"], self_contact=c["self_contact"], between_rods=c["between_rods"],
                      friction=c["friction"])
        for i, entry in enumerate(self.data["obstacles"]):
            kind, a = next(iter(entry.items()))
            try:
                if kind == "plane":
                    o = obs.plane(a["origin"], a["normal"])
                elif kind == "sphere":
                    o = obs.sphere(a["center"], a["radius"])
                elif kind == "capsule":
                    o = obs.capsule(a["a"], a["b"], a["radius"])
                else:
                    p = a["path"] if os.path.isabs(a["path"]) else os.path.join(self.base_dir, a["path"])
                    o = obs.mesh(p)
            except (StrandkitError, ValueError) as e:
                raise _scene_error(f"obstacles[{i}].{kind}", str(e)) from e
            w.add_obstacle(o, margin=a["margin"], friction=a["friction"])
        return w, ins

    def _check_built(self) -> None:
        """Builds the world once and walks the protocol on it without
        stepping: holds are made, drives find and check the constraints
        they move (existing, movable, holding a roll to turn), so a scene
        that loads runs; then the recorded groups must exist."""
        from .protocol import Hold, op_of, world_labels
        w, _ = self.world()
        check_labels(self.data["protocol"], world_labels(w))
        for i, entry in enumerate(self.data["protocol"]):
            op, args = op_of(entry)
            try:
                if isinstance(op, Hold):
                    op.at_once(w, args)
                elif op.steps(args, w.dt) > 0:
                    op.begin(w, args)
            except StrandkitError as e:
                raise _scene_error(f"protocol[{i}].{op.name}", getattr(e, "problem", str(e))) from e
        known = world_labels(w)
        for g in self.data["outputs"]["groups"]:
            if g not in known:
                raise _scene_error("outputs.groups", f"no group {g!r} in the scene", g,
                                   "one of " + ", ".join(sorted(w.groups)))

    # -- values ---------------------------------------------------------------------------------
    def to_dict(self) -> dict:
        """The scene as a dict in the file format (defaults filled in)."""
        return copy.deepcopy(self.data)

    @property
    def digest(self) -> str:
        """SHA-256 of the scene's canonical JSON, files it names by their
        content: what a resumed run or a sweep directory checks it continues."""
        return hashlib.sha256(json.dumps(_identity(self), sort_keys=True).encode()).hexdigest()

    def with_values(self, values: Dict[str, Any]) -> "Scene":
        """A copy with ``{"dotted.key": value}`` set (``world.dt``,
        ``structure.args.n_planks``, ``protocol.1.pull.velocity``), checked again."""
        data = copy.deepcopy(self.data)
        for key, value in values.items():
            set_key(data, key, value)
        return Scene(data, self.base_dir)

    def save(self, path: str) -> str:
        """Writes the scene atomically as JSON (``.json``) or TOML (``.toml``); returns the path."""
        return save_scene(self, path)

    def run(self, out: Optional[str] = None, *, resume: bool = False, progress_bar: bool = True):
        """Runs the protocol (see :func:`strandkit.scene.run_scene`)."""
        from .runner import run_scene
        return run_scene(self, out, resume=resume, progress_bar=progress_bar)

    def __repr__(self) -> str:
        s = self.data["structure"]
        what = (f"builder {s['builder']}" if "builder" in s else
                "inline assembly" if "assembly" in s else f"assembly file {s['assembly_file']}")
        ops = [next(iter(e)) for e in self.data["protocol"]]
        name = f"{self.data['name']!r}: " if "name" in self.data else ""
        n = len(ops)
        return (f"Scene({name}{what}, {n} operation{'s' if n != 1 else ''}"
                f"{': ' + ', '.join(ops) if ops else ''}; world dt={self.data['world'].get('dt', world_settings()['dt'])}"
                f" units={self.data['world']['units']})")


def set_key(data: dict, key: str, value) -> None:
    """Sets ``data[a][b][i]…`` from the dotted ``key`` ``a.b.i`` (a list index
    must exist; a missing table key is created, and checked afterwards)."""
    parts = key.split(".")
    if not key or any(p == "" for p in parts):
        raise _scene_error(key, "not a dotted key such as world.dt or structure.args.n_planks")
    node = data
    for i, p in enumerate(parts):
        last = i == len(parts) - 1
        where = ".".join(parts[: i + 1])
        if isinstance(node, list):
            if not p.isdigit() or int(p) >= len(node):
                raise _scene_error(where, f"no item {p} in a list of {len(node)}")
            p = int(p)
        elif isinstance(node, dict):
            if not last and p not in node:
                node[p] = {}
        else:
            raise _scene_error(where, f"cannot set a key inside {type(node).__name__}")
        if last:
            node[p] = value
        else:
            node = node[p]


def parse_value(text: str):
    """A command-line value: JSON when it parses (numbers, lists, true/false), else the string."""
    try:
        return json.loads(text)
    except ValueError:
        return text


def load_scene(path: str) -> Scene:
    """Reads a scene file (``.json`` or ``.toml``) and checks it (files it
    names are relative to it). FileError when it cannot be read or parsed,
    SceneError naming the key when it cannot run."""
    path = os.fspath(path)
    try:
        with open(path, "rb") as f:
            raw = f.read()
    except OSError as e:
        from .._files import file_error
        raise file_error(path, e) from e
    try:
        if path.endswith(".toml"):
            data = _toml_load(raw)
            s = data.get("structure") if isinstance(data, dict) else None
            if isinstance(s, dict) and isinstance(s.get("assembly"), str):
                s["assembly"] = json.loads(s["assembly"])
        else:
            data = json.loads(raw.decode("utf-8"))
    except (ValueError, UnicodeDecodeError) as e:
        err = FileError(f"i/o error: {path}: not a scene file ({e})")
        err.kind, err.path, err.message = "Io", path, f"not a scene file ({e})"
        raise err from e
    return Scene(data, os.path.dirname(os.path.abspath(path)))


def _toml_load(raw: bytes):
    try:
        import tomllib
    except ImportError:  # Python < 3.11
        import tomli as tomllib
    return tomllib.loads(raw.decode("utf-8"))


def _file_paths(data: dict):
    """(table, key) of every file path in scene data (assembly file, meshes)."""
    if "assembly_file" in data["structure"]:
        yield data["structure"], "assembly_file"
    for entry in data["obstacles"]:
        if "mesh" in entry:
            yield entry["mesh"], "path"


def _rebased(scene: Scene, target_dir: str) -> dict:
    """The scene's data with its relative file paths made relative to
    ``target_dir``, where the scene is being written (real paths on both
    sides: ``..`` is resolved by the system on the real path, so a symlinked
    directory must not be taken literally)."""
    data = scene.to_dict()
    for table, key in _file_paths(data):
        p = table[key]
        if not os.path.isabs(p):
            table[key] = os.path.relpath(os.path.realpath(os.path.join(scene.base_dir, p)),
                                         os.path.realpath(target_dir))
    return data


def _identity(scene: Scene) -> dict:
    """The scene's data with each file path replaced by the SHA-256 of the
    file's content: a moved scene is the same scene, an edited file is not."""
    data = scene.to_dict()
    for table, key in _file_paths(data):
        p = table[key]
        full = p if os.path.isabs(p) else os.path.join(scene.base_dir, p)
        try:
            with open(full, "rb") as f:
                table[key] = "sha256:" + hashlib.sha256(f.read()).hexdigest()
        except OSError:
            table[key] = "missing:" + os.path.realpath(full)
    return data


def scene_text(scene: Scene, fmt: str, target_dir: Optional[str] = None) -> str:
    data = _rebased(scene, target_dir or scene.base_dir)
    if fmt == "toml":
        import tomli_w
        s = data["structure"]
        if "assembly" in s:  # the Assembly's JSON has nulls, which TOML cannot hold: kept as JSON text
            s["assembly"] = json.dumps(s["assembly"])
        return tomli_w.dumps(_strip_none(data))
    return json.dumps(data, indent=1) + "\n"


def save_scene(scene: Scene, path: str) -> str:
    """Writes ``scene`` atomically to ``path`` (``.toml`` → TOML, else JSON)."""
    from .._files import write_text
    path = os.fspath(path)
    write_text(path, scene_text(scene, "toml" if path.endswith(".toml") else "json",
                                os.path.dirname(os.path.abspath(path))))
    return path
