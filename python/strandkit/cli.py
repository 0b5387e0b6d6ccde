"""The ``strandkit`` command line (installed with the package; also
``python -m strandkit``).

    strandkit run scene.json --out DIR [--set key=value …] [--resume]
    strandkit info scene.json [--set key=value …]
    strandkit validate scene.json [--set key=value …]
    strandkit sweep scene.json --vary key=v1,v2 … | --grid grid.json --out DIR
                   [--workers N | --local-cluster N | --scheduler ADDRESS] [--seed S]
    strandkit schema

Values after ``--set`` and ``--vary`` are JSON when they parse (numbers,
lists, true/false) and strings otherwise. Exit status: 0 done, 1 the
simulation failed (solver error), 2 the scene or the command is invalid
(the message names the key), 130 interrupted (Ctrl-C or SIGTERM; outputs so
far are valid, ``--resume`` continues).
"""
from __future__ import annotations

import argparse
import json
import sys
from typing import List, Optional

from .errors import FileError, Interrupted, SceneError, SolverError, StrandkitError


def _values(pairs: List[str], flag: str) -> dict:
    from .errors import _scene_error
    from .scene import parse_value
    out = {}
    for p in pairs or []:
        if "=" not in p:
            raise _scene_error(flag, f"{p!r}: expected KEY=VALUE")
        k, v = p.split("=", 1)
        out[k] = parse_value(v)
    return out


def _scene(args):
    from .scene import load_scene
    scene = load_scene(args.scene)
    sets = _values(args.set, "--set")
    return scene.with_values(sets) if sets else scene


def _info(scene) -> str:
    from .scene.protocol import op_of
    w, _ = scene.world()
    d = scene.data
    s = d["structure"]
    lines = [f"scene: {d.get('name', '(unnamed)')} (format {d['format']} version {d['version']})"]
    if d.get("description"):
        lines.append(f"  {d['description']}")
    lines.append("structure: " + (f"builder {s['builder']} {json.dumps(s['args'])}" if "builder" in s else
                                  "inline assembly" if "assembly" in s else f"assembly file {s['assembly_file']}"))
    rods = w.rods()
    lines.append(f"world: units {d['world']['units']}, dt {w.dt}, scheme {w.params['scheme']}, "
                 f"temperature {w.params['temperature']}, {len(rods)} rods, "
                 f"{sum(len(r.control_points) for r in rods)} control points, {w.n_constraints} constraints, "
                 f"groups {', '.join(w.groups) or '-'}")
    total = 0
    lines.append("protocol:")
    for i, e in enumerate(d["protocol"]):
        op, a = op_of(e)
        n = op.steps(a, w.dt)
        total += 0 if op.quasi_static(a) else n
        shown = {k: v for k, v in a.items() if v is not None}
        what = "at once" if n == 0 else f"{n} {'increments' if op.quasi_static(a) else 'steps'}"
        lines.append(f"  [{i}] {op.name} {json.dumps(shown)} ({what})")
    o = d["outputs"]
    lines.append(f"steps: {total} (simulated time {total * w.dt:.6g})")
    lines.append(f"outputs: a record every {o['every']} steps" + (", trajectory" if o["trajectory"] else "")
                 + (f", groups {', '.join(o['groups'])}" if o["groups"] else ""))
    return "\n".join(lines)


def _client(args):
    if args.scheduler:
        from distributed import Client
        return Client(args.scheduler), None
    if args.local_cluster:
        from distributed import Client, LocalCluster
        cluster = LocalCluster(n_workers=args.local_cluster, threads_per_worker=1, processes=True,
                               dashboard_address=None, env={"RAYON_NUM_THREADS": "1"})
        return Client(cluster), cluster
    return None, None


def main(argv: Optional[List[str]] = None) -> int:
    p = argparse.ArgumentParser(prog="strandkit", description="Run strandkit scenes and sweeps.")
    sub = p.add_subparsers(dest="command", required=True)
    for name, helptext in (("run", "run a scene's protocol"), ("info", "describe a scene"),
                           ("validate", "check a scene without running it"), ("sweep", "run a scene over a grid")):
        c = sub.add_parser(name, help=helptext)
        c.add_argument("scene", help="scene file (.json or .toml)")
        c.add_argument("--set", action="append", metavar="KEY=VALUE", help="override a scene value (dotted key)")
        if name in ("run", "sweep"):
            c.add_argument("--out", required=True, help="output directory")
            c.add_argument("--no-progress", action="store_true", help="no progress bar")
        if name == "run":
            c.add_argument("--resume", action="store_true", help="continue the run recorded in --out")
        if name == "sweep":
            c.add_argument("--vary", action="append", metavar="KEY=V1,V2", help="values of a key (a grid axis)")
            c.add_argument("--grid", help="JSON file: {key: [values]} or [{key: value}, …]")
            c.add_argument("--seed", type=int, default=0, help="base seed of the points' seeds")
            c.add_argument("--workers", type=int, default=None, help="local worker processes (0: in this process)")
            c.add_argument("--local-cluster", type=int, default=None, metavar="N",
                           help="run on a Dask LocalCluster of N worker processes")
            c.add_argument("--scheduler", default=None, help="address of a Dask scheduler")
    sub.add_parser("schema", help="print the scene format's JSON Schema")
    args = p.parse_args(argv)
    import signal
    import threading
    previous = None
    if threading.current_thread() is threading.main_thread():
        # SIGTERM as Ctrl-C: a scene run defers both to its next step, a sweep stops (exit 130)
        previous = signal.signal(signal.SIGTERM, signal.default_int_handler)
    try:
        return _command(args)
    finally:
        if previous is not None:
            signal.signal(signal.SIGTERM, previous)


def _command(args) -> int:
    try:
        if args.command == "schema":
            from .scene import schema
            print(json.dumps(schema(), indent=1))
            return 0
        scene = _scene(args)
        if args.command == "validate":
            print(f"{args.scene}: valid ({scene!r})")
            return 0
        if args.command == "info":
            print(_info(scene))
            return 0
        if args.command == "run":
            r = scene.run(args.out, resume=args.resume, progress_bar=not args.no_progress)
            print(f"{r!r}\n" + "\n".join(f"  {k}: {v}" for k, v in r.paths.items()))
            return 0
        return _sweep(scene, args)
    except Interrupted as e:
        print(f"strandkit: {e}", file=sys.stderr)
        return 130
    except KeyboardInterrupt:
        print("strandkit: interrupted", file=sys.stderr)
        return 130
    except (SceneError, FileError) as e:
        print(f"strandkit: {e}", file=sys.stderr)
        return 2
    except ImportError as e:
        print(f"strandkit: {e.name or e} is needed for this: pip install \"strandkit[study]\" "
              "(TOML scenes, Parquet outputs, sweeps on Dask)", file=sys.stderr)
        return 2
    except (SolverError, StrandkitError) as e:
        print(f"strandkit: the simulation failed: {e}", file=sys.stderr)
        return 1


def _sweep(scene, args) -> int:
    from .errors import _scene_error
    from .sweeps import sweep
    if bool(args.grid) == bool(args.vary):
        raise _scene_error("grid", "give the grid with --grid FILE or with --vary KEY=V1,V2 (one of the two)")
    if args.grid:
        try:
            with open(args.grid, encoding="utf-8") as f:
                grid = json.load(f)
        except (OSError, ValueError) as e:
            raise _scene_error("grid", f"cannot read {args.grid}: {e}") from e
    else:
        from .scene import parse_value
        grid = {}
        for v in args.vary:
            if "=" not in v:
                raise _scene_error("grid", f"--vary {v!r}: expected KEY=V1,V2,…")
            k, vals = v.split("=", 1)
            parsed = parse_value(f"[{vals}]")
            grid[k] = parsed if isinstance(parsed, list) else vals.split(",")
    client, cluster = _client(args)
    try:
        df = sweep(scene, grid, out=args.out, client=client, workers=args.workers, seed=args.seed,
                   progress_bar=not args.no_progress)
    finally:
        if client is not None:
            client.close()
        if cluster is not None:
            cluster.close()
    with_cols = [c for c in df.columns if c not in ("point", "seed")]
    print(df[with_cols].to_string(index=False, max_cols=12))
    print(f"{len(df)} points; results in {args.out}/results.parquet")
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
