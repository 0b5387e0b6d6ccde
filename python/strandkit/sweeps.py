"""Parameter sweeps: one scene (or function) run over a grid of values, on
local processes or on a Dask cluster, each point persisted as it finishes so
that an interrupted sweep resumes where it stopped.

>>> import strandkit as sk
>>> def sag(span, n_planks, seed):
...     s = sk.Scene.from_builder("rope_bridge", span=span, n_planks=n_planks, sag=0.1 * span,
...                               world={"gravity": [0, -9.81, 0]}, protocol=[{"relax": {}}])
...     w = s.run(progress_bar=False).world
...     return {"lowest": float(min(r.sample_points()[:, 1].min() for r in w.rods()))}
>>> df = sk.sweep(sag, {"span": [4.0, 8.0], "n_planks": [3]}, workers=0, progress_bar=False)
>>> df["span"].tolist(), df["n_planks"].tolist(), bool((df["lowest"] < 0).all())
([4.0, 8.0], [3, 3], True)

Grid: ``{"key": [values…], …}`` (the Cartesian product, first key slowest)
or a list of points ``[{"key": value, …}, …]``. For a scene the keys are
dotted scene keys (``structure.args.sequence``, ``protocol.1.pull.velocity``,
``world.dt``); for a function, its keyword arguments. Every point gets a
seed derived from ``seed`` and the point's values alone (SHA-256), so adding
points never changes another's seed: a scene point gets it as
``world.seed`` unless the grid sets that, a function as ``seed=`` when it
takes one. A point's result is a dict of scalars (a scene's:
``SceneResult.summary()``); the sweep returns a pandas DataFrame, one row
per point in grid order: the point's values, ``point`` (its id), ``seed``,
the results, ``elapsed`` (s of wall clock), and ``error`` where the
simulation failed at that point (a solver error: the other points go on).

With ``out=DIR``: ``DIR/sweep.json`` (the grid), ``DIR/points/<id>.parquet``
written atomically as each point finishes, ``DIR/results.parquet`` at the
end, and for scenes each point's own outputs in ``DIR/runs/<id>/``. Run
again on the same DIR, only the missing points are computed.
"""
from __future__ import annotations

import hashlib
import inspect
import itertools
import json
import math
import os
import time
from typing import Any, Callable, Dict, List, Optional, Union

from ._files import temporary_for, write_text, writable_dir
from .errors import FileError, Interrupted, SolverError, StrandkitError, _scene_error

__all__ = ["sweep", "grid_points", "point_seed"]

MAX_POINTS = 1_000_000


def _kind(v) -> str:
    if isinstance(v, bool):
        return "boolean"
    if isinstance(v, (int, float)):
        return "number"
    if v is None:
        return "null"
    return {str: "string", list: "list", dict: "table"}.get(type(v), type(v).__name__)


def grid_points(grid) -> List[Dict[str, Any]]:
    """The points of ``grid`` (a dict of value lists, or a list of dicts),
    checked: at least one point, finite JSON-like values, the same keys in
    every point."""
    if isinstance(grid, dict):
        if not grid:
            raise _scene_error("grid", "has no keys: no point to run")
        for k, vals in grid.items():
            if not isinstance(k, str) or not k:
                raise _scene_error("grid", f"key {k!r} is not a name")
            if isinstance(vals, (str, bytes)) or not hasattr(vals, "__iter__"):
                raise _scene_error(f"grid.{k}", "expected a list of values", vals)
        lists = [list(v) for v in grid.values()]
        n = math.prod(len(v) for v in lists)
        if n == 0:
            empty = next(k for k, v in zip(grid, lists) if not v)
            raise _scene_error(f"grid.{empty}", "has no values: no point to run")
        if n > MAX_POINTS:
            raise _scene_error("grid", f"{n} points", n, f"at most {MAX_POINTS}")
        points = [dict(zip(grid, combo)) for combo in itertools.product(*lists)]
    elif isinstance(grid, (list, tuple)):
        if not grid:
            raise _scene_error("grid", "is empty: no point to run")
        if not all(isinstance(p, dict) and p for p in grid):
            raise _scene_error("grid", "expected non-empty dicts of values")
        points = [dict(p) for p in grid]
        keys = set(points[0])
        for i, p in enumerate(points):
            if set(p) != keys:
                raise _scene_error(f"grid[{i}]", f"keys {sorted(p)} differ from the first point's {sorted(keys)}")
    else:
        raise _scene_error("grid", f"expected a dict of value lists or a list of points, got {type(grid).__name__}")
    from .scene.format import _json_plain
    for i, p in enumerate(points):
        for k, v in p.items():
            try:  # plain JSON values (numpy → numbers, tuples → lists): as the manifest reads back
                p[k] = _json_plain(v, f"grid.{k}")
            except StrandkitError as e:
                raise _scene_error(f"grid.{k}", f"point {i}: {v!r} is not a finite value", v,
                                   "finite numbers, strings, booleans") from e
    for k in points[0]:  # one type per key: a results column has one type
        kinds = {_kind(p[k]) for p in points} - {"null"}  # None (a default) goes with any type
        if len(kinds) > 1:
            raise _scene_error(f"grid.{k}", f"mixes {' and '.join(sorted(kinds))} values", None,
                               "values of one type per key")
    ids = [point_id(p) for p in points]
    if len(set(ids)) != len(ids):
        raise _scene_error("grid", "repeats a point")
    return points


def point_id(point: Dict[str, Any]) -> str:
    """16 hex digits of the SHA-256 of the point's canonical JSON."""
    return hashlib.sha256(json.dumps(point, sort_keys=True).encode()).hexdigest()[:16]


def point_seed(seed: int, point: Dict[str, Any]) -> int:
    """The point's seed: 63 bits of SHA-256(seed, point), independent of the other points."""
    h = hashlib.sha256(f"{int(seed)}/{json.dumps(point, sort_keys=True)}".encode()).digest()
    return int.from_bytes(h[:8], "little") >> 1


def _source_digest(fn) -> str:
    """SHA-256 of the function's source (when Python has it): a sweep
    directory refuses a function whose code changed, so old and new results
    never mix. Values it reads from outside (defaults, closures, globals)
    are not covered — their repr may hold memory addresses, which would make
    every run a new sweep: change the directory when they change."""
    try:
        return hashlib.sha256(inspect.getsource(fn).encode()).hexdigest()[:16]
    except (OSError, TypeError):
        return ""


def _takes(fn, name: str) -> bool:
    params = inspect.signature(fn).parameters
    return name in params or any(p.kind == inspect.Parameter.VAR_KEYWORD for p in params.values())


def _scalars(result, where: str) -> Dict[str, Any]:
    if not isinstance(result, dict):
        raise TypeError(f"{where}: a sweep function must return a dict of scalars, got {type(result).__name__}")
    out = {}
    for k, v in result.items():
        v = v.item() if hasattr(v, "item") else v
        if not isinstance(k, str) or not isinstance(v, (int, float, str, bool)):
            raise TypeError(f"{where}: result {k!r} = {v!r} is not a scalar (number, string or bool)")
        out[k] = v
    return out


def _run_point(payload: dict) -> dict:
    """One point, in a worker (a process of the pool, or a Dask worker)."""
    t0 = time.perf_counter()
    try:
        result = _compute(payload)
    except SolverError as e:
        # A simulation that fails at one point (a refused step, no
        # convergence) is that point's result, not the sweep's end.
        result = {"error": f"{type(e).__name__}: {e}"}
    return {"result": result, "elapsed": time.perf_counter() - t0, "pid": os.getpid()}


def _compute(payload: dict) -> dict:
    point, seed = payload["point"], payload["seed"]
    if payload["kind"] == "scene":
        from .scene import Scene
        scene = Scene._checked(payload["scene"], payload["base_dir"])
        result = scene.run(payload.get("run_dir"), resume=payload.get("run_dir") is not None,
                           progress_bar=False).summary()
    else:
        fn = payload["function"]
        if isinstance(fn, bytes):
            import cloudpickle
            fn = cloudpickle.loads(fn)
        kwargs = dict(point)
        if payload["pass_seed"] and "seed" not in kwargs:
            kwargs["seed"] = seed
        result = _scalars(fn(**kwargs), f"point {point}")
    return result


class _Store:
    """Per-point Parquet files in ``out/points`` (or memory when out is None)."""

    def __init__(self, out: Optional[str], manifest: dict):
        self.out, self.rows = out, {}
        if out is None:
            return
        writable_dir(os.path.join(out, "points"), "sweep directory")
        path = os.path.join(out, "sweep.json")
        if os.path.exists(path):
            with open(path, encoding="utf-8") as f:
                try:
                    old = json.load(f)
                except ValueError:
                    old = None
            if old != manifest:
                raise _scene_error("out", f"{out} holds another sweep (other grid, seed or target): "
                                   "choose another directory")
        else:
            write_text(path, json.dumps(manifest, indent=1))

    def done(self, pid: str) -> Optional[dict]:
        if self.out is None:
            return self.rows.get(pid)
        path = os.path.join(self.out, "points", f"{pid}.parquet")
        if not os.path.exists(path):
            return None
        import pandas as pd
        return pd.read_parquet(path).iloc[0].to_dict()

    def put(self, pid: str, row: dict) -> None:
        self.rows[pid] = row
        if self.out is not None:
            import pandas as pd
            with temporary_for(os.path.join(self.out, "points", f"{pid}.parquet")) as tmp:
                pd.DataFrame([row]).to_parquet(tmp, index=False)


def sweep(target: Union[Callable, Any, str], grid, *, out: Optional[str] = None, client=None,
          workers: Optional[int] = None, seed: int = 0, progress_bar: bool = True, retries: int = 2,
          runs: bool = True):
    """Runs ``target`` — a function of the grid's keys, a :class:`~strandkit.Scene`
    or a scene file's path — at every point of ``grid`` and returns a pandas
    DataFrame (see the module's documentation).

    client: a ``distributed.Client`` (a LocalCluster's or a real cluster's):
    points are submitted as tasks, retried ``retries`` times on an error, and
    moved to another worker when theirs dies; None: local processes
    (``workers`` of them, default the CPU count; 0 runs in this process;
    the processes are spawned, so a script calling ``sweep`` needs the
    ``if __name__ == "__main__":`` guard, as for ``multiprocessing``).
    seed: the base of every point's seed. runs: with ``out``, each scene
    point's own outputs go to ``out/runs/<id>/`` (written by the worker that
    runs it: on a real cluster ``out`` must be on a filesystem the workers
    share; ``runs=False`` keeps only the results, which the driver writes). Everything is checked before any
    point runs (SceneError naming the key). Ctrl-C stops the sweep with
    :class:`~strandkit.Interrupted`, finished points kept."""
    import pandas as pd

    from .scene import Scene, load_scene
    if isinstance(target, (str, os.PathLike)):
        target = load_scene(target)
    points = grid_points(grid)
    if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
        raise _scene_error("seed", f"{seed!r} is not a seed", seed, "an integer >= 0")
    if workers is not None and (isinstance(workers, bool) or not isinstance(workers, int) or workers < 0):
        raise _scene_error("workers", f"{workers!r}", workers, "an integer >= 0")
    scenes = {}
    if isinstance(target, Scene):
        for i, p in enumerate(points):  # every point's scene is checked (and built once) before any runs
            try:
                values = dict(p)
                values.setdefault("world.seed", point_seed(seed, p))
                checked = target.with_values(values).data
                if out is None or not _persisted(out, point_id(p)):
                    scenes[point_id(p)] = checked  # kept only for points still to run
            except StrandkitError as e:
                raise _scene_error(f"grid[{i}]", f"{p}: {e}") from e
        kind, desc = "scene", {"scene": target.digest}
        base = {"kind": "scene", "base_dir": target.base_dir}
    elif callable(target):
        for k in points[0]:
            if not _takes(target, k):
                raise _scene_error(f"grid.{k}", f"is not an argument of {getattr(target, '__name__', target)}")
        kind = "function"
        desc = {"function": f"{getattr(target, '__module__', '')}.{getattr(target, '__qualname__', repr(target))}",
                "source": _source_digest(target)}
        try:
            import cloudpickle
            fn = cloudpickle.dumps(target)
        except ImportError:  # plain pickling: the function must be importable by the workers
            fn = target
        base = {"kind": "function", "function": fn, "pass_seed": _takes(target, "seed")}
    else:
        raise _scene_error("target", f"expected a Scene, a scene file or a function, got {type(target).__name__}")
    if out is not None:
        out = os.path.abspath(os.fspath(out))
    manifest = {"target": desc, "seed": seed, "points": points}
    store = _Store(out, manifest)
    ids = [point_id(p) for p in points]
    todo = [(pid, p) for pid, p in zip(ids, points) if store.done(pid) is None]
    payloads = {}
    for pid, p in todo:
        given = "world.seed" if kind == "scene" else "seed"  # a seed the grid sets is the one used
        pl = dict(base, point=p, seed=p[given] if given in p else point_seed(seed, p))
        if kind == "scene":
            pl["scene"] = scenes[pid]  # the point's own checked scene, its seed in it
        if kind == "scene" and out is not None and runs:
            pl["run_dir"] = os.path.join(out, "runs", pid)
        payloads[pid] = pl

    index = {pid: i for i, pid in enumerate(ids)}

    def row(pid, r):
        p = points[index[pid]]
        return {**p, "point": pid, "seed": payloads[pid]["seed"], **r["result"], "elapsed": r["elapsed"]}

    from ._progress import progress
    bar = progress(total=len(points), desc="sweep", enable=progress_bar)
    bar.update(len(points) - len(todo))
    try:
        if client is not None:
            tag = hashlib.sha256(json.dumps([manifest, out, runs], sort_keys=True, default=str).encode()).hexdigest()[:12]
            _on_dask(client, payloads, retries, tag, lambda pid, r: (store.put(pid, row(pid, r)), bar.update(1)))
        elif workers == 0 or (workers is None and len(todo) <= 1):
            for pid, pl in payloads.items():
                store.put(pid, row(pid, _run_point(pl)))
                bar.update(1)
        else:
            _on_processes(workers or os.cpu_count() or 1, payloads,
                          lambda pid, r: (store.put(pid, row(pid, r)), bar.update(1)))
    except KeyboardInterrupt as e:
        bar.close()
        n = sum(store.done(pid) is not None for pid in ids)
        err = Interrupted(f"sweep interrupted with {n} of {len(points)} points done"
                          + (f"; run it again on {out} to compute the rest" if out else ""))
        err.out, err.time, err.done = out, None, n
        raise err from e
    bar.close()
    df = pd.DataFrame([store.done(pid) for pid in ids])
    if out is not None:
        with temporary_for(os.path.join(out, "results.parquet")) as tmp:
            try:
                df.to_parquet(tmp, index=False)
            except (ValueError, TypeError, ImportError) as e:  # pyarrow's errors are ValueError/TypeError kinds
                raise FileError(f"i/o error: {out}/results.parquet: cannot write the results ({e})") from e
    return df


def _persisted(out, pid: str) -> bool:
    return os.path.exists(os.path.join(os.path.abspath(os.fspath(out)), "points", f"{pid}.parquet"))


def _one_thread() -> None:
    """Each worker process keeps the core to one thread: the processes are the parallelism."""
    os.environ.setdefault("RAYON_NUM_THREADS", "1")


def _on_processes(n: int, payloads: dict, done: Callable) -> None:
    """A pool of ``n`` spawned processes (not forked: the parent may hold the
    core's thread pool). On Ctrl-C or an error the queued points are
    cancelled and the workers told to stop (SIGINT: a scene run stops at its
    next step), instead of finishing what they had."""
    import multiprocessing as mp
    import signal
    from concurrent.futures import ProcessPoolExecutor, as_completed
    ex = ProcessPoolExecutor(max_workers=min(n, len(payloads)) or 1, mp_context=mp.get_context("spawn"),
                             initializer=_one_thread)
    futs = {ex.submit(_run_point, pl): pid for pid, pl in payloads.items()}
    try:
        for f in as_completed(futs):
            done(futs[f], f.result())
    except BaseException:
        for f in futs:
            f.cancel()
        for proc in list(getattr(ex, "_processes", {}).values()):  # the executor keeps no public list
            try:
                os.kill(proc.pid, signal.SIGINT)
            except OSError:
                pass  # already gone
        ex.shutdown(wait=True, cancel_futures=True)
        raise
    ex.shutdown(wait=True)


def _on_dask(client, payloads: dict, retries: int, tag: str, done: Callable) -> None:
    """Task keys name the sweep (its grid, seed and target) and the point, so
    two sweeps on one scheduler never share a result."""
    from distributed import as_completed
    futs = {client.submit(_run_point, pl, key=f"strandkit-{tag}-{pid}", pure=False, retries=retries): pid
            for pid, pl in payloads.items()}
    try:
        for f in as_completed(list(futs)):
            done(futs[f], f.result())
    except BaseException:
        client.cancel(list(futs))
        raise
