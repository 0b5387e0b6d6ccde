"""Sweep overhead and scale-out (issue 19), measured in one run:

1. overhead per point: a sweep of N points, each a fixed amount of
   strandkit work (a rope bridge stepped for a fixed number of steps, about
   POINT seconds), run in this process (workers=0), against the same points
   called directly in a loop; the difference per point over the point's time;
2. throughput: the same points on a Dask LocalCluster of 1 worker and of 2
   workers (one thread each), points per second, and their ratio.

    python3 benchmarks/sweep_bench.py [--points 8] [--steps 1500]

Needs the study extra (pip install "./python[study]")."""
import argparse
import os
import platform
import time

import strandkit as sk


def work(n_planks, steps, seed):
    s = sk.Scene.from_builder("rope_bridge", n_planks=n_planks, span=10.0, sag=1.0,
                              world={"gravity": [0, -9.81, 0], "dt": 2e-3, "seed": seed},
                              protocol=[{"step": {"steps": steps}}], outputs={"every": 100, "trajectory": False})
    return {"total": s.run(progress_bar=False).summary()["final_total"]}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--points", type=int, default=8)
    ap.add_argument("--steps", type=int, default=1500)
    a = ap.parse_args()
    grid = {"n_planks": list(range(6, 6 + a.points)), "steps": [a.steps]}
    from strandkit.sweeps import grid_points, point_seed
    pts = grid_points(grid)
    print(f"{platform.node()}, {os.cpu_count()} cores, {time.strftime('%Y-%m-%d %H:%M')}; "
          f"{a.points} points of a rope bridge stepped {a.steps} times")
    t0 = time.perf_counter()
    for p in pts:
        work(seed=point_seed(0, p), **p)
    direct = time.perf_counter() - t0
    t0 = time.perf_counter()
    sk.sweep(work, grid, workers=0, progress_bar=False)
    swept = time.perf_counter() - t0
    per_point = direct / len(pts)
    print(f"direct loop {direct:.2f} s ({per_point:.2f} s a point); sweep in-process {swept:.2f} s; "
          f"overhead {(swept - direct) / len(pts) * 1e3:.1f} ms a point = {100 * (swept - direct) / direct:.2f} %")
    from distributed import Client, LocalCluster
    rates = {}
    for n in (1, 2):
        with LocalCluster(n_workers=n, threads_per_worker=1, processes=True, dashboard_address=None) as c, Client(c) as cl:
            cl.submit(work, 6, 1, 0).result()  # warm the workers (imports)
            t0 = time.perf_counter()
            sk.sweep(work, grid, client=cl, progress_bar=False)
            rates[n] = len(pts) / (time.perf_counter() - t0)
        print(f"LocalCluster {n} worker(s): {rates[n]:.3f} points/s")
    print(f"2 workers / 1 worker: {rates[2] / rates[1]:.2f}x")


if __name__ == "__main__":
    main()
