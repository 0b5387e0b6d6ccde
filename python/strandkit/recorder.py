"""Per-step logging of a world to numpy arrays and CSV.

>>> import os, tempfile
>>> import strandkit as sk
>>> world = sk.World(dt=1e-3, gravity=(0, -9.81, 0))
>>> rod = world.add_rod(sk.straight((0, 0, 0), (1, 0, 0), section=0.01, material="nylon", n_control_points=8))
>>> clamp, _ = sk.clamp(world, rod)
>>> rec = Recorder(world).point("tip", rod, rod.u_end)    # r(u) every record, length unit
>>> rec = rec.reaction("clamp", clamp)                    # force and torque
>>> report = rec.run(10, progress_bar=False)              # steps the world, records each step
>>> rec["tip"].shape, rec["clamp"].shape, rec["time"].shape
((11, 3), (11, 6), (11,))
>>> path = rec.to_csv(os.path.join(tempfile.mkdtemp(), "run.csv"))
>>> open(path).readline().split(",")[:4]
['time', 'step', 'elastic_energy', 'kinetic_energy']
"""
from __future__ import annotations

import csv
import os
from typing import Callable, Dict, List

import numpy as np

from ._files import file_error, temporary_for
from ._progress import progress
from .errors import _invalid

__all__ = ["Recorder"]

_SUFFIXES = {3: ("x", "y", "z"), 6: ("fx", "fy", "fz", "tx", "ty", "tz")}


class Recorder:
    """Records ``time`` plus named channels each time :meth:`record` is
    called (``run`` and ``relax`` call it), and keeps every event as a dict
    of its fields plus ``kind`` (the event's name, e.g. "ConstraintBroken"),
    ``step`` and ``time_recorded``.

    A channel is a function ``f(world) -> float or 1-D array``; helpers add
    the usual ones. ``rec[name]`` is a numpy array of shape (records,) or
    (records, width). ``every``: record one step in ``every`` during ``run``.
    """

    def __init__(self, world, *, every: int = 1, energies: bool = True):
        if every < 1:
            raise _invalid("every", repr(every), ">= 1")
        self.world = world
        self.every = int(every)
        self._channels: Dict[str, Callable] = {}
        self._data: Dict[str, List] = {"time": [], "step": []}
        self.events: List[dict] = []
        if energies:
            self.add("elastic_energy", lambda w: sum(r.elastic_energy for r in w.rods()))
            self.add("kinetic_energy", lambda w: sum(r.kinetic_energy for r in w.rods()))

    # -- channels -------------------------------------------------------
    def add(self, name: str, fn: Callable) -> "Recorder":
        """A custom channel ``fn(world)`` → float or 1-D array."""
        if name in self._data:
            raise _invalid(f"channel {name!r} exists already")
        self._channels[name] = fn
        self._data[name] = []
        if self._data["time"]:
            # Late channels start with NaN rows so that all columns align.
            self._data[name] = [np.nan] * len(self._data["time"])
        return self

    def _own(self, obj, what: str) -> None:
        """A rod or handle given to a channel must be of the recorded world
        (else the channel would silently record something else)."""
        owner = getattr(obj, "world", None)
        if owner is not self.world:
            where = "is not in a world" if owner is None else "belongs to another world"
            raise _invalid(f"Recorder.{what}: this {type(obj).__name__} {where} (record it with a Recorder of its world)")

    def point(self, name: str, rod, u: float) -> "Recorder":
        """Centreline point r(u) of ``rod`` (length unit): columns name_x, _y, _z."""
        self._own(rod, "point")
        return self.add(name, lambda w: rod.position(u))

    def tangent(self, name: str, rod, u: float) -> "Recorder":
        """Unit tangent at u."""
        self._own(rod, "tangent")
        return self.add(name, lambda w: rod.tangent(u))

    def reaction(self, name: str, constraint) -> "Recorder":
        """Force (force unit) and torque (force × length) of a constraint:
        columns name_fx … name_tz."""
        self._own(constraint, "reaction")

        def f(w):
            if not constraint.alive:  # removed or broken: NaN from then on
                return np.full(6, np.nan)
            r = constraint.reaction()
            return np.concatenate([r.force, r.torque])

        return self.add(name, f)

    def multipliers(self, name: str, constraint) -> "Recorder":
        """Raw multipliers of a constraint (force / torque units; NaN once it is gone)."""
        self._own(constraint, "multipliers")
        width = len(constraint.multipliers)
        return self.add(name, lambda w: constraint.multipliers if constraint.alive else np.full(width, np.nan))

    def extension(self, name: str, rod) -> "Recorder":
        """End-to-end distance |r(u_end) − r(u_start)| (length unit)."""
        self._own(rod, "extension")
        return self.add(name, lambda w: float(np.linalg.norm(rod.position(rod.u_end) - rod.position(rod.u_start))))

    # -- recording --------------------------------------------------------
    def record(self, report=None) -> None:
        """Appends one row: time and every channel; events of ``report``."""
        w = self.world
        self._data["time"].append(w.time)
        self._data["step"].append(w.n_steps)
        for name, fn in self._channels.items():
            v = fn(w)
            self._data[name].append(np.array(v, dtype=float) if np.ndim(v) else float(v))
        if report is not None:
            for e in report.events:
                # The event's own fields are kept as they are (a broken
                # constraint's kind is `constraint_kind`); the recorder's
                # keys never replace one: a clash is stored as event_<key>.
                d = {"kind": e.kind, "step": w.n_steps, "time_recorded": w.time}
                for k, v in e.data.items():
                    d[f"event_{k}" if k in d else k] = v
                self.events.append(d)

    def run(self, steps: int, *, progress_bar: bool = True, callback: Callable | None = None, desc: str = "steps"):
        """Steps the world ``steps`` times, recording the initial state (if
        nothing is recorded yet) and every ``every``-th step. ``callback(world,
        report)`` runs after each step. Returns the last StepReport."""
        if not self._data["time"]:
            self.record()
        report = None
        bar = progress(range(steps), desc=desc, enable=progress_bar)
        for k in bar:
            report = self.world.step()
            if callback is not None:
                callback(self.world, report)
            if report.events or (k + 1) % self.every == 0 or k + 1 == steps:
                self.record(report)
        return report

    def relax(self):
        """Relaxes the world to equilibrium and records the result."""
        report = self.world.relax()
        self.record(report)
        return report

    # -- output -------------------------------------------------------------
    @property
    def names(self) -> List[str]:
        return list(self._data)

    def __len__(self) -> int:
        return len(self._data["time"])

    def __getitem__(self, name: str) -> np.ndarray:
        rows = self._data[name]
        if rows and any(np.ndim(r) for r in rows):
            width = max(np.size(r) for r in rows)
            return np.array([np.full(width, np.nan) if np.ndim(r) == 0 and np.isnan(r) else r for r in rows], dtype=float)
        return np.array(rows, dtype=float)

    def __contains__(self, name: str) -> bool:
        return name in self._data

    def to_numpy(self) -> Dict[str, np.ndarray]:
        """Every channel as an array (time and step included)."""
        return {k: self[k] for k in self._data}

    def columns(self) -> Dict[str, np.ndarray]:
        """Flat columns: vector channels split as name_x/_y/_z, name_fx…, or name_0…"""
        out = {}
        for k in self._data:
            a = self[k]
            if a.ndim == 1:
                out[k] = a
            else:
                suf = _SUFFIXES.get(a.shape[1], tuple(str(i) for i in range(a.shape[1])))
                for i, s in enumerate(suf):
                    out[f"{k}_{s}"] = a[:, i]
        return out

    def to_csv(self, path: str) -> str:
        """Writes the columns as CSV (and events, if any, to
        ``<path without extension>.events.csv``), each atomically: on an
        error (a FileError) no temporary file is left and an existing
        file keeps its content."""
        path = os.fspath(path)
        self._make_parent(path)
        cols = self.columns()
        names = list(cols)
        with temporary_for(path) as tmp:
            with open(tmp, "x", newline="") as f:
                w = csv.writer(f)
                w.writerow(names)
                for i in range(len(self)):
                    w.writerow([repr(float(cols[n][i])) for n in names])
        if self.events:
            keys = sorted({k for e in self.events for k in e})
            with temporary_for(f"{os.path.splitext(path)[0]}.events.csv") as tmp:
                with open(tmp, "x", newline="") as f:
                    w = csv.writer(f)
                    w.writerow(keys)
                    for e in self.events:
                        w.writerow([e.get(k, "") for k in keys])
        return path

    def to_npz(self, path: str) -> str:
        """Writes every channel to a numpy .npz archive (atomically, like
        ``to_csv``); ``.npz`` is appended to a path without it, as numpy
        does. Returns the path written."""
        path = os.fspath(path)
        if not path.endswith(".npz"):
            path += ".npz"
        self._make_parent(path)
        with temporary_for(path) as tmp:
            with open(tmp, "xb") as f:
                np.savez(f, **self.to_numpy())
        return path

    @staticmethod
    def _make_parent(path: str) -> None:
        try:
            os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
        except OSError as e:
            raise file_error(path, e) from e

    def __repr__(self) -> str:
        return f"Recorder({len(self)} records, channels={[k for k in self._data if k not in ('time', 'step')]}, events={len(self.events)})"
