"""The experiment protocol of a scene: a list of operations run in order,
each a one-key table ``{"pull": {...}}``. An operation is a class in
``OPS`` (one class plus its registration line): its fields (checked and
documented by ``fields.py``, exported to the JSON Schema), how many steps it
takes, and what it does before each one.

Driven operations (pull, stretch, rotate) move the targets of constraints
that a label selects (a group name such as ``"anchor"`` or one label such as
``"anchor[0,1]"``): the targets are a function of the operation's own clock,
t_k = k·duration/n, recomputed from the targets at its start, so a run
resumed from a snapshot moves them exactly as an uninterrupted one. With
``increments`` instead of ``duration`` the targets move in that many
quasi-static increments, each brought to equilibrium by ``relax``.
"""
from __future__ import annotations

import copy
import math
import re
from typing import Dict, List

import numpy as np

from ..errors import _scene_error
from .fields import Field, check_table, one_key_tables

#: Constraint kinds whose point a drive moves, and the field holding it
#: (the first three components of a Position's target are the point).
POINT_FIELDS = {"Position": "target", "Distance": "point", "Plane": "origin", "Axis": "origin",
                "SlidingPoint": "point", "OrientedSlidingPoint": "point"}


#: What World.set_label accepts (core: labels name groups, "name[i]" / "name[i,j]").
LABEL = re.compile(r"[A-Za-z0-9_\-.:/]+(\[\d+(,\d+)?\])?")


class Op:
    name = ""
    doc = ""
    fields: List[Field] = []

    def check(self, args: dict, key: str) -> dict:
        return args

    def steps(self, args: dict, dt: float) -> int:
        """World steps (or relax increments) the operation takes; 0: done at once."""
        return 0

    def quasi_static(self, args: dict) -> bool:
        return False

    def labels_added(self, args: dict) -> List[str]:
        return []

    def labels_used(self, args: dict) -> List[str]:
        return []

    def begin(self, world, args: dict) -> dict:
        """JSON-serialisable state taken at the start (kept in the resume state)."""
        return {}

    def at_once(self, world, args: dict):
        """What a zero-step operation does; returns its events (or None)."""

    def before(self, world, args: dict, drive: dict, k: int, n: int) -> None:
        """Sets the targets for the end of step (or increment) k of n."""

    def measure(self, world, args: dict, drive: dict, k: int, n: int) -> Dict[str, float]:
        return {}


def _steps_for(duration: float, dt: float) -> int:
    """Steps of ``dt`` that cover ``duration`` (at least one; a duration that
    is a whole number of steps up to rounding takes that number)."""
    return max(1, math.ceil(duration / dt - 1e-9))


def world_labels(world) -> set:
    """Every name the world answers for: group names and full labels."""
    names = set(world.groups)
    for g in world.groups:
        names.update(label for label, _ in world.group(g).members)
    return names


def _members(world, label: str, drive: dict):
    """(handle, kind at the start) of the driven constraints still alive: a
    drive keeps each member's position in the group (which lists gone
    members too), so a break removes that member only."""
    hs = world.group(label).constraints
    return [(hs[i], kind) for i, kind in zip(drive["members"], drive["kinds"]) if hs[i].alive]


def _point(kind: dict) -> np.ndarray:
    name = next(iter(kind))
    return np.asarray(kind[name][POINT_FIELDS[name]][:3], dtype=float)


def _moved(kind: dict, shift: np.ndarray) -> dict:
    name = next(iter(kind))
    k = copy.deepcopy(kind)
    field = k[name][POINT_FIELDS[name]]
    for i in range(3):
        field[i] = float(field[i] + shift[i])
    return k


def _drive_state(world, label: str, accept, what: str) -> dict:
    """The members a drive moves (positions in the group) and their kinds
    at its start; ``accept(kind)`` says whether the drive can move one."""
    members, kinds = [], []
    for i, h in enumerate(world.group(label).constraints):
        if not h.alive:
            continue
        kind = h.kind
        if not accept(kind):
            raise _scene_error("protocol", f"constraint {h.label!r} is a {next(iter(kind))}: {what}")
        members.append(i)
        kinds.append(kind)
    if not members:
        raise _scene_error("protocol", f"no live constraint labelled {label!r} to drive")
    return {"members": members, "kinds": kinds}


def _movable(world, label: str) -> dict:
    return _drive_state(world, label, lambda kind: next(iter(kind)) in POINT_FIELDS,
                        "a drive moves " + ", ".join(sorted(POINT_FIELDS)) + " constraints")


def _force_along(world, label: str, drive: dict, direction) -> float:
    """Σ of the reactions of the driven constraints still alive on their rods
    along ``direction`` (force unit); NaN once none is left."""
    d = np.asarray(direction, dtype=float)
    alive = _members(world, label, drive)
    if not alive:
        return math.nan
    return float(sum(np.dot(world.reaction(h).force, d) for h, _ in alive))


#: How long a drive runs: one of the two (``Drive.check``).
DURATION = Field("duration", "positive", "time", "how long (dynamic)", None)
INCREMENTS = Field("increments", "count", "", "quasi-static increments (instead of duration)", None)


class Drive(Op):
    """An operation moving the labelled constraints over ``duration`` (dynamic
    steps) or ``increments`` (quasi-static, each relaxed)."""

    def check(self, args, key):
        if (args["duration"] is None) == (args["increments"] is None):
            raise _scene_error(key, "give exactly one of duration (dynamic) and increments (quasi-static)")
        return args

    def steps(self, args, dt):
        return args["increments"] if args["increments"] is not None else _steps_for(args["duration"], dt)

    def quasi_static(self, args):
        return args["increments"] is not None

    def labels_used(self, args):
        return [args["constraints"]]

    @staticmethod
    def shift(world, args, drive, shift) -> None:
        """Moves every driven constraint's point from where it was at the start by ``shift``."""
        for h, kind in _members(world, args["constraints"], drive):
            world.set_constraint(h, _moved(kind, shift))


class Relax(Op):
    name = "relax"
    doc = "Static equilibrium (World.relax): Newton's method with a line search."
    fields = [Field("perturb", "nonneg", "length", "leave an unstable equilibrium along a descent direction "
                    "by this amplitude (0: no)", 0.0)]

    def at_once(self, world, args):
        return world.relax(perturb=args["perturb"] or None).events


class Step(Op):
    name = "step"
    doc = "Dynamic steps of the world's dt for a duration (or a number of steps)."
    fields = [Field("duration", "positive", "time", "simulated time to run", None),
              Field("steps", "count", "", "number of steps (instead of duration)", None)]

    def check(self, args, key):
        if (args["duration"] is None) == (args["steps"] is None):
            raise _scene_error(key, "give exactly one of duration and steps")
        return args

    def steps(self, args, dt):
        return args["steps"] if args["steps"] is not None else _steps_for(args["duration"], dt)


class Hold(Op):
    name = "hold"
    doc = "Holds a rod's point where it is now with a Position constraint (labelled, so a drive can move it)."
    fields = [Field("rod", "string", "", "label of the rod (e.g. \"strand[0]\")"),
              Field("at", "abscissa", "u", "where: \"start\", \"end\" or a spline parameter", "start"),
              Field("axes", "string", "", "held axes: letters of \"xyzr\" (r: the roll coordinate)", "xyz"),
              Field("label", "string", "", "label of the new constraint", "held"),
              Field("compliance", "nonneg", "length/force", "0: rigid; > 0: a spring of stiffness 1/compliance "
                    "(holding both ends of a rigid rung would repeat it)", 0.0)]

    def check(self, args, key):
        if not LABEL.fullmatch(args["label"]) or len(args["label"]) > 256:
            raise _scene_error(f"{key}.label", f"{args['label']!r} is not a label", args["label"],
                               "letters, digits, _-.:/ optionally followed by [i] or [i,j]")
        if not set(args["axes"]) <= set("xyzr") or len(set(args["axes"])) != len(args["axes"]):
            raise _scene_error(f"{key}.axes", f"{args['axes']!r} is not valid", args["axes"], 'letters of "xyzr"')
        return args

    def labels_added(self, args):
        return [args["label"]]

    def labels_used(self, args):
        return [args["rod"]]

    def at_once(self, world, args):
        from ..constraints import position
        rods = world.group(args["rod"]).rods
        if len(rods) != 1:
            raise _scene_error("protocol", f"hold: {args['rod']!r} names {len(rods)} rods, expected one")
        rod = rods[0]
        u = rod.u_start if args["at"] == "start" else rod.u_end if args["at"] == "end" else float(args["at"])
        if not rod.u_start <= u <= rod.u_end:
            raise _scene_error("protocol", f"hold: u = {u} is outside the rod's [{rod.u_start}, {rod.u_end}]")
        world.add_constraint(rod, position(u, rod.position(u), axes=args["axes"]), label=args["label"],
                             compliance=args["compliance"])


class Pull(Drive):
    name = "pull"
    doc = ("Moves the points of the labelled constraints at a constant velocity; records their "
           "displacement along it and the force they exert on their rods along it.")
    fields = [Field("constraints", "string", "", "label or group of the driven constraints"),
              Field("velocity", "vec3", "length/time", "velocity of the targets"), DURATION,
              Field("increments", "count", "", "quasi-static increments over the distance "
                    "velocity × time (instead of a dynamic pull)", None),
              Field("time", "positive", "time", "with increments: the time the distance corresponds to", None)]

    def check(self, args, key):
        super().check(args, key)
        if args["increments"] is not None and args["time"] is None:
            raise _scene_error(f"{key}.time", "missing: increments move the targets by velocity × time")
        if args["increments"] is None and args["time"] is not None:
            raise _scene_error(f"{key}.time", "time goes with increments; a dynamic pull runs for duration")
        if not any(args["velocity"]):
            raise _scene_error(f"{key}.velocity", "is zero", args["velocity"], "a non-zero velocity")
        return args

    def _total(self, args):
        return args["duration"] if args["duration"] is not None else args["time"]

    def begin(self, world, args):
        return _movable(world, args["constraints"])

    def before(self, world, args, drive, k, n):
        self.shift(world, args, drive, np.asarray(args["velocity"]) * (self._total(args) * (k / n)))

    def measure(self, world, args, drive, k, n):
        v = np.asarray(args["velocity"])
        d = v / np.linalg.norm(v)
        return {"drive_displacement": float(np.linalg.norm(v) * self._total(args) * (k / n)),
                "drive_force": _force_along(world, args["constraints"], drive, d)}


class Stretch(Drive):
    name = "stretch"
    doc = ("Moves the labelled constraints away from (strain > 0) or toward the `about` constraints "
           "until the distance between their centroids has changed by the strain; records the "
           "displacement and the force along that line.")
    fields = [Field("constraints", "string", "", "label or group of the moved constraints"),
              Field("about", "string", "", "label or group of the constraints held still"),
              Field("strain", "number", "", "relative change of the centroids' distance"), DURATION, INCREMENTS]

    def check(self, args, key):
        super().check(args, key)
        if args["strain"] <= -1:
            raise _scene_error(f"{key}.strain", f"{args['strain']} would cross the held end", args["strain"],
                               "a strain > -1")
        return args

    def labels_used(self, args):
        return [args["constraints"], args["about"]]

    def begin(self, world, args):
        drive = _movable(world, args["constraints"])
        fixed = _movable(world, args["about"])
        a = np.mean([_point(k) for k in fixed["kinds"]], axis=0)
        b = np.mean([_point(k) for k in drive["kinds"]], axis=0)
        length = float(np.linalg.norm(b - a))
        if not length > 0:
            raise _scene_error("protocol", "stretch: the two groups' centroids coincide")
        return dict(drive, direction=((b - a) / length).tolist(), length=length)

    def _extension(self, args, drive, k, n):
        return args["strain"] * drive["length"] * (k / n)

    def before(self, world, args, drive, k, n):
        self.shift(world, args, drive, np.asarray(drive["direction"]) * self._extension(args, drive, k, n))

    def measure(self, world, args, drive, k, n):
        return {"drive_displacement": self._extension(args, drive, k, n),
                "drive_force": _force_along(world, args["constraints"], drive, drive["direction"])}


class Rotate(Drive):
    name = "rotate"
    doc = ("Turns the roll of the labelled constraints (Position constraints holding the roll 'r', "
           "or MaterialRoll) by a number of turns; records the turns and the torque about the rod's tangent.")
    fields = [Field("constraints", "string", "", "label or group of the turned constraints"),
              Field("turns", "number", "turns", "turns added to the roll (positive: right-handed about the tangent)"),
              DURATION, INCREMENTS]

    def begin(self, world, args):
        return _drive_state(world, args["constraints"],
                            lambda kind: "MaterialRoll" in kind or ("Position" in kind and kind["Position"]["axes"][3]),
                            "rotate needs a roll to turn (a Position holding 'r', or a MaterialRoll)")

    def before(self, world, args, drive, k, n):
        angle = 2 * math.pi * args["turns"] * (k / n)
        for h, kind in _members(world, args["constraints"], drive):
            k2 = copy.deepcopy(kind)
            if "MaterialRoll" in k2:
                k2["MaterialRoll"]["angle"] = float(kind["MaterialRoll"]["angle"] + angle)
            else:
                k2["Position"]["target"][3] = float(kind["Position"]["target"][3] + angle)
            world.set_constraint(h, k2)

    def measure(self, world, args, drive, k, n):
        alive = _members(world, args["constraints"], drive)
        torque = 0.0 if alive else math.nan
        for h, kind in alive:
            u = next(iter(kind.values()))["u"]
            t = np.asarray(h.rod.tangent(u), dtype=float)
            torque += float(np.dot(world.reaction(h).torque, t / np.linalg.norm(t)))
        return {"drive_turns": args["turns"] * (k / n), "drive_torque": torque}


#: The operations by name: one line per operation.
OPS: Dict[str, Op] = {op.name: op for op in (Relax(), Step(), Hold(), Pull(), Stretch(), Rotate())}

#: Observables a drive may fill (NaN otherwise).
DRIVE_COLUMNS = ("drive_displacement", "drive_force", "drive_turns", "drive_torque")


def check_protocol(protocol) -> List[dict]:
    """The protocol checked: a list of one-key tables naming an operation."""
    out = []
    for key, name, args in one_key_tables(protocol, "protocol", OPS, "operation", "a list of operations"):
        op = OPS[name]
        out.append({name: op.check(check_table(op.fields, args, f"{key}.{name}"), f"{key}.{name}")})
    return out


def op_of(entry: dict):
    name, args = next(iter(entry.items()))
    return OPS[name], args


def check_labels(protocol: List[dict], labels: set) -> None:
    """Every label a protocol uses exists when it runs (labels added by earlier holds count)."""
    known = set(labels)
    for i, entry in enumerate(protocol):
        op, args = op_of(entry)
        for label in op.labels_used(args):
            if label not in known:
                raise _scene_error(f"protocol[{i}].{op.name}", f"no object labelled {label!r} in the scene", label,
                                   "a label or group of the structure, or of an earlier hold")
        known.update(op.labels_added(args))
        for label in op.labels_added(args):
            known.add(label.split("[")[0])


def measure_nan() -> Dict[str, float]:
    return {c: math.nan for c in DRIVE_COLUMNS}
