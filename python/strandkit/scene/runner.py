"""Runs a scene's protocol, streaming its outputs to a directory:

- ``observables.csv``: one row every ``outputs.every`` steps and after each
  operation (time, step, operation, energies, the drive's displacement /
  force / turns / torque, per-group broken count, summed tension, largest
  force), floats written to round-trip exactly; ``observables.parquet`` and
  ``observables.png`` at the end;
- ``trajectory.pdb/.psf/.dcd`` (mdtraj: ``md.load("trajectory.dcd",
  top="trajectory.psf")``), ``events.jsonl`` (breaks, ruptures, releases);
- ``snapshot.json`` (the world, for ``World.load``) and ``state.json``
  (where the protocol stands, with the world): every
  ``outputs.snapshot_every`` steps and after each operation. A Ctrl-C or
  SIGTERM stops the run at the next step boundary; ``resume=True``
  continues from the last snapshot, cutting the rows, events and frames
  written after it, so a resumed run's outputs are those of an
  uninterrupted one, bit for bit.
"""
from __future__ import annotations

import csv
import json
import math
import os
from dataclasses import dataclass, field
from typing import Dict, List, Optional

import numpy as np

from ..errors import FileError, Interrupted, _scene_error
from .._files import temporary_for, write_text, writable_dir
from .._progress import progress
from .format import Scene, save_scene
from .protocol import DRIVE_COLUMNS, measure_nan, op_of, world_labels

BASE_COLUMNS = ("time", "step", "operation", "op", "kinetic", "elastic", "external", "total") + DRIVE_COLUMNS
STATE, SNAPSHOT, CSV, EVENTS, TRAJ = "state.json", "snapshot.json", "observables.csv", "events.jsonl", "trajectory"
STATE_VERSION = 1
#: Bytes of a DCD header and of one frame of n atoms (core/src/io/trajectory.rs: unit cell + x, y, z blocks).
DCD_HEADER = 276


def _dcd_frame_bytes(n: int) -> int:
    return 56 + 3 * (8 + 4 * n)


@dataclass
class SceneResult:
    """What a scene run produced: ``observables`` (column → numpy array),
    ``events`` (dicts), ``world`` (its final state), ``paths`` (files written)."""

    scene: Scene
    world: object
    observables: Dict[str, np.ndarray]
    events: List[dict] = field(default_factory=list)
    paths: Dict[str, str] = field(default_factory=dict)

    def summary(self) -> Dict[str, float]:
        """Scalars of the run, for sweeps: the last record's values, the drive
        force's extremes, and the number of events."""
        out = {}
        for k, v in self.observables.items():
            if k in ("operation", "op") or len(v) == 0:
                continue
            out[f"final_{k}"] = float(v[-1])
        f = self.observables.get("drive_force")
        if f is not None and np.isfinite(f).any():
            out["max_drive_force"] = float(np.nanmax(f))
            out["min_drive_force"] = float(np.nanmin(f))
        out["n_events"] = float(len(self.events))
        return out

    def dataframe(self):
        """The observables as a pandas DataFrame."""
        import pandas as pd
        return pd.DataFrame(self.observables)

    def __repr__(self) -> str:
        n = len(self.observables.get("time", []))
        t = float(self.observables["time"][-1]) if n else 0.0
        return f"SceneResult({n} records to t = {t:.6g}, {len(self.events)} events, {len(self.paths)} files)"


def _columns(scene: Scene) -> List[str]:
    cols = list(BASE_COLUMNS)
    for g in scene.data["outputs"]["groups"]:
        cols += [f"{g}.broken", f"{g}.tension", f"{g}.max_force"]
    return cols


def _fmt(v) -> str:
    if isinstance(v, str):
        return v
    if isinstance(v, (int, np.integer)) and not isinstance(v, bool):
        return str(int(v))
    return repr(float(v))


def _parse(col: str, text: str):
    return text if col == "operation" else int(text) if col in ("step", "op") else float(text)


class _Outputs:
    """The files of a run (or nothing when ``out`` is None): observables in
    memory and in CSV, events, trajectory, snapshots."""

    def __init__(self, scene: Scene, out: Optional[str], world, resume_state: Optional[dict]):
        self.scene, self.out, self.world = scene, out, world
        self.cols = _columns(scene)
        self.rows: List[list] = []
        self.events: List[dict] = []
        self.traj = None
        self.snapshot_step = world.n_steps
        o = scene.data["outputs"]
        self.every = o["every"]
        self.frame_every = o["frame_every"] or 10 * o["every"]
        self.snapshot_every = o["snapshot_every"]
        if out is None:
            return
        self.paths = {"scene": os.path.join(out, "scene.json"), "observables": os.path.join(out, CSV),
                      "events": os.path.join(out, EVENTS)}
        if resume_state is None:
            save_scene(scene, self.paths["scene"])
            self.csv = open(self.paths["observables"], "w", newline="", encoding="utf-8")
            self.csv.write(",".join(self.cols) + "\n")
            self.ev = open(self.paths["events"], "w", encoding="utf-8")
        else:
            self._restore(resume_state)
        self.writer = csv.writer(self.csv, lineterminator="\n")
        if o["trajectory"]:
            from ..trajectory import TrajectoryWriter
            prefix = os.path.join(out, TRAJ)
            if resume_state is not None:
                self._cut_dcd(prefix + ".dcd", resume_state["frames"])
            from .._native import Topology, bead_positions
            self.traj = TrajectoryWriter(world, prefix, scale=o["scale"], every=self.frame_every,
                                         initial=resume_state is None, append=resume_state is not None,
                                         pdb=resume_state is None, psf=resume_state is None,
                                         topology=Topology(world), positions=lambda: bead_positions(self.world))
            self.paths.update(dcd=prefix + ".dcd", pdb=prefix + ".pdb", psf=prefix + ".psf")

    def _restore(self, state: dict) -> None:
        """Reads back the rows and events the snapshot had written, cutting what came after."""
        with open(self.paths["observables"], encoding="utf-8") as f:
            lines = f.read().split("\n")
        header = lines[0].split(",")
        if header != self.cols:
            raise _scene_error("outputs", f"{self.paths['observables']} has other columns than this scene's")
        kept = lines[1:1 + state["rows"]]
        if len(kept) != state["rows"]:
            raise FileError(f"i/o error: {self.paths['observables']}: {len(kept)} rows, the snapshot wrote {state['rows']}")
        self.rows = [[_parse(c, x) for c, x in zip(self.cols, line.split(","))] for line in kept]
        write_text(self.paths["observables"], "\n".join(lines[:1 + state["rows"]]) + "\n")
        self.csv = open(self.paths["observables"], "a", newline="", encoding="utf-8")
        with open(self.paths["events"], encoding="utf-8") as f:
            # only the lines the snapshot counted: a kill may have cut the one after
            lines = f.read().split("\n")[: state["events"]]
        try:
            ev = [json.loads(x) for x in lines]
        except ValueError as e:
            raise FileError(f"i/o error: {self.paths['events']}: fewer or other events than the snapshot counted ({e})") from e
        self.events = ev
        write_text(self.paths["events"], "".join(x + "\n" for x in lines))
        self.ev = open(self.paths["events"], "a", encoding="utf-8")

    def _cut_dcd(self, path: str, frames: int) -> None:
        from .._native import Topology
        n = Topology(self.world).n_beads
        size = DCD_HEADER + frames * _dcd_frame_bytes(n)
        if os.path.getsize(path) < size:
            raise FileError(f"i/o error: {path}: shorter than the {frames} frames the snapshot wrote")
        with open(path, "r+b") as f:
            f.truncate(size)

    # -- records ------------------------------------------------------------------------------
    def record(self, op_index: int, op_name: str, drive: Dict[str, float]) -> None:
        w = self.world
        e = w.energy()
        row = [w.time, w.n_steps, op_name, op_index, e["kinetic"], e["elastic"], e["external"], e["total"]]
        row += [drive.get(c, math.nan) for c in DRIVE_COLUMNS]
        for g in self.scene.data["outputs"]["groups"]:
            if g not in w.groups and g not in world_labels(w):
                row += [0, math.nan, math.nan]  # a group a later hold makes: nothing in it yet
                continue
            grp = w.group(g)
            if not len(grp.constraints):  # a group of rods or loads only: no constraint to measure
                row += [0, math.nan, math.nan]
                continue
            t = np.asarray(grp.tensions, dtype=float)
            alive = np.asarray(grp.alive, dtype=bool)
            mags = np.linalg.norm(np.asarray(grp.forces, dtype=float).reshape(-1, 3)[alive], axis=1)
            row += [int(np.asarray(grp.broken, dtype=bool).sum()),
                    float(np.nansum(t)) if np.isfinite(t).any() else math.nan,
                    float(mags.max()) if len(mags) else math.nan]
        self.rows.append(row)
        if self.out is not None:
            self.writer.writerow([_fmt(v) for v in row])
            self.csv.flush()

    def frame(self) -> None:
        if self.traj is not None:
            self.traj.write()

    def add_events(self, events) -> None:
        for ev in events:
            d = {k: (v if isinstance(v, (int, float, str, bool, type(None))) else str(v))
                 for k, v in ev.to_dict().items()}
            self.events.append(d)
            if self.out is not None:
                self.ev.write(json.dumps(d) + "\n")
                self.ev.flush()

    def snapshot(self, state: dict) -> None:
        """Writes the world (``snapshot.json``, for ``World.load``) and the
        resume state with it (both atomic), and continues from the snapshot
        itself: the solver's caches (the sparse
        pattern, which factorisation it trusts) depend on the steps since a
        world was built or loaded, so a run that carries on with its old
        world and one resumed from the file would part at rounding level.
        Reloading here (also when nothing is written) makes every run, cut
        or not, take the same path."""
        from .._native import World
        text = self.world.to_json()
        self.world = World.from_json(text)
        self.snapshot_step = self.world.n_steps
        if self.out is None:
            return
        write_text(os.path.join(self.out, SNAPSHOT), text)
        # The resume state carries the world too: one atomic write, so a kill
        # can never leave a state and a world of different steps.
        state = dict(state, rows=len(self.rows), events=len(self.events),
                     frames=self.traj.n_frames if self.traj is not None else 0, n_steps=self.world.n_steps,
                     world=text)
        write_text(os.path.join(self.out, STATE), json.dumps(state))

    def observables(self) -> Dict[str, np.ndarray]:
        cols = list(zip(*self.rows)) if self.rows else [[] for _ in self.cols]
        out = {}
        for c, v in zip(self.cols, cols):
            out[c] = np.asarray(v, dtype=object if c == "operation" else int if c in ("step", "op") else float)
        return out

    def close(self) -> None:
        if self.out is None:
            return
        for f in (self.csv, self.ev):
            f.close()
        if self.traj is not None:
            self.traj.close()

    def finish(self) -> None:
        """Parquet and the plot, once the run is complete."""
        if self.out is None:
            return
        o = self.scene.data["outputs"]
        obs = self.observables()
        if o["parquet"]:
            try:
                import pandas as pd
                import pyarrow  # noqa: F401  (pandas' Parquet engine)
            except ImportError:
                import warnings
                warnings.warn("observables.parquet not written: it needs pandas and pyarrow "
                              '(pip install "strandkit[study]"); observables.csv has the same data', stacklevel=3)
            else:
                path = os.path.join(self.out, "observables.parquet")
                with temporary_for(path) as tmp:
                    pd.DataFrame(obs).to_parquet(tmp, index=False)
                self.paths["parquet"] = path
        if o["plots"]:
            try:
                import matplotlib
            except ImportError:
                import warnings
                warnings.warn('observables.png not drawn: it needs matplotlib (pip install "strandkit[plot]")',
                              stacklevel=3)
                return
            matplotlib.use("Agg")
            from .plots import plot_observables
            self.paths["plot"] = plot_observables(obs, os.path.join(self.out, "observables.png"),
                                                  self.scene.data.get("name", ""), self.scene.data["world"]["units"])


#: Files a run writes in its directory (a fresh run removes them first, so
#: none is left over from an earlier run).
OUTPUT_FILES = ("scene.json", STATE, SNAPSHOT, CSV, EVENTS, "observables.parquet", "observables.png",
                TRAJ + ".pdb", TRAJ + ".psf", TRAJ + ".dcd")


def _load_state(scene: Scene, out: str) -> Optional[dict]:
    path = os.path.join(out, STATE)
    if not os.path.exists(path):
        return None
    try:
        with open(path, encoding="utf-8") as f:
            state = json.load(f)
    except ValueError as e:
        raise FileError(f"i/o error: {path}: corrupt resume state ({e})") from e
    keys = {"state_version", "digest", "op", "k", "drive", "done", "rows", "events", "frames", "n_steps", "world"}
    if not isinstance(state, dict) or state.get("state_version") != STATE_VERSION or not keys <= set(state):
        raise FileError(f"i/o error: {path}: not a resume state of this strandkit (version {STATE_VERSION}); "
                        "run without resume")
    if state.get("digest") != scene.digest:
        raise _scene_error("out", f"{out} holds a run of another scene (or of this one with other values): "
                           "choose another directory or run without resume")
    return state


class _StopFlag:
    """Ctrl-C and SIGTERM only set a flag while a run is in progress; the
    loop stops at the next step boundary (``check``), so the snapshot never
    falls between a step and the bookkeeping of it. Outside the main thread
    (no signal handlers there) KeyboardInterrupt is left as it is."""

    def __init__(self):
        self.flag = False
        self.saved = {}

    def __enter__(self):
        import signal
        import threading
        if threading.current_thread() is threading.main_thread():
            for sig in (signal.SIGINT, signal.SIGTERM):
                self.saved[sig] = signal.signal(sig, self._set)
        return self

    def _set(self, signum, frame):
        if self.flag:  # a second signal: stop now (the snapshot on disk is still the last one)
            raise KeyboardInterrupt
        self.flag = True

    def check(self):
        if self.flag:
            raise KeyboardInterrupt

    def __exit__(self, *exc):
        import signal
        for sig, h in self.saved.items():
            signal.signal(sig, h if h is not None else signal.SIG_DFL)
        return False


def run_scene(scene, out: Optional[str] = None, *, resume: bool = False, progress_bar: bool = True) -> SceneResult:
    """Runs ``scene`` (a :class:`Scene` or a path) to the end of its protocol.

    ``out``: directory for the outputs (None: nothing written, observables in
    memory); ``resume``: continue the run recorded in ``out`` (a fresh run
    when there is none; a finished one is read back). A Ctrl-C or SIGTERM
    stops the run at the next step boundary and raises
    :class:`~strandkit.Interrupted`; the last snapshot (every
    ``outputs.snapshot_every`` steps and after each operation) is where
    ``resume`` continues. A solver error ends the run and is raised: the
    rows and frames written so far stay, with the last snapshot."""
    from .._native import World
    from .format import load_scene
    if not isinstance(scene, Scene):
        scene = load_scene(scene)
    state = None
    if out is not None:
        out = os.path.abspath(os.fspath(out))
        writable_dir(out, "output directory")
        state = _load_state(scene, out) if resume else None
        if state is None:
            for name in OUTPUT_FILES:  # a fresh run: nothing of an earlier one stays beside it
                if os.path.exists(os.path.join(out, name)):
                    os.remove(os.path.join(out, name))
    if state is not None:
        try:
            world = World.from_json(state["world"])
        except (KeyError, TypeError, FileError) as e:
            raise FileError(f"i/o error: {os.path.join(out, STATE)}: corrupt resume state ({e})") from e
    else:
        world, _ = scene.world()
    outputs = _Outputs(scene, out, world, state)
    protocol = scene.data["protocol"]
    if state is None:
        state = {"state_version": STATE_VERSION, "digest": scene.digest, "op": 0, "k": 0, "drive": None,
                 "done": False}
        outputs.record(-1, "start", measure_nan())
        outputs.snapshot(state)
    total = sum(op_of(e)[0].steps(op_of(e)[1], world.dt) for e in protocol)
    done_before = sum(op_of(e)[0].steps(op_of(e)[1], world.dt) for e in protocol[: state["op"]]) + state["k"]
    stop = _StopFlag()
    bar = progress(total=total, desc=scene.data.get("name") or "scene", enable=progress_bar and total > 0)
    if done_before:
        bar.update(done_before)
    try:
        with stop:
            _run_protocol(outputs, protocol, state, stop, bar)
        outputs.finish()
    except KeyboardInterrupt as e:
        # No snapshot here: the last one (every snapshot_every steps and
        # after each operation) is where the uninterrupted run reloaded too;
        # resume cuts the rows and frames written after it.
        bar.close()
        outputs.close()
        world = outputs.world
        err = Interrupted(f"interrupted at t = {world.time:.6g} (step {world.n_steps}); "
                          + (f"resume with resume=True / --resume on {out} (from its last snapshot, "
                             f"step {outputs.snapshot_step})" if out else "nothing written (out=None)"))
        err.out, err.time, err.done = out, world.time, None
        raise err from e
    except BaseException:
        bar.close()
        outputs.close()
        raise
    bar.close()
    outputs.close()
    return SceneResult(scene, outputs.world, outputs.observables(), outputs.events, dict(getattr(outputs, "paths", {})))


def _run_protocol(outputs, protocol, state, stop, bar) -> None:
    """Runs the operations from ``state`` on; the state is advanced right
    after each step, so a snapshot always matches the world (which a
    snapshot replaces: ``outputs.world`` is read afresh)."""
    while state["op"] < len(protocol):
        i = state["op"]
        world = outputs.world
        op, args = op_of(protocol[i])
        n = op.steps(args, world.dt)
        if n == 0:
            outputs.add_events(op.at_once(world, args) or [])
            outputs.record(i, op.name, measure_nan())
            outputs.frame()
        else:
            if state["drive"] is None:
                state["drive"] = op.begin(world, args)
            quasi = op.quasi_static(args)
            while state["k"] < n:
                k = state["k"] + 1
                op.before(world, args, state["drive"], k, n)
                if quasi:
                    outputs.add_events(world.relax().events)
                else:
                    outputs.add_events(world.step().events)
                state["k"] = k
                bar.update(1)
                if quasi or world.n_steps % outputs.every == 0 or k == n:
                    outputs.record(i, op.name, {**measure_nan(), **op.measure(world, args, state["drive"], k, n)})
                if quasi or world.n_steps % outputs.frame_every == 0:
                    outputs.frame()
                if k < n and (k if quasi else world.n_steps) % outputs.snapshot_every == 0:
                    outputs.snapshot(state)
                    world = outputs.world
                stop.check()
        state.update(op=i + 1, k=0, drive=None)
        outputs.snapshot(state)
        stop.check()
    state["done"] = True
    outputs.snapshot(state)
