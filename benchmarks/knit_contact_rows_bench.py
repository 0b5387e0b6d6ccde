"""Rigid against distributed contact rows on the knit cell (BENCHMARKS §52):
the 16 × 4 jersey cell (3.8 mm loops, r = 0.1 mm nylon, frictionless,
contact_recheck) relaxed from its default start with each kind of row,
alternated ROUNDS times in one run; prints steps, refused steps, wall
time, ms per step, rows at the end and whether it converged.

Usage: python3 knit_contact_rows_bench.py [MAX_STEPS] [ROUNDS]   (defaults 400, 2)
"""
import sys
import time

import strandkit as sk
from strandkit.knit import experiments as ex

max_steps = int(sys.argv[1]) if len(sys.argv) > 1 else 400
rounds = int(sys.argv[2]) if len(sys.argv) > 2 else 2
print(f"{'rows':12s} {'converged':9s} {'steps':>5s} {'refused':>7s} {'wall (s)':>8s} {'ms/step':>8s} {'rows at end':>11s} {'k_c':>6s} {'k_w':>6s}")
for _ in range(rounds):
    for stiffness in (None, "yarn"):
        f = sk.knit.fabric("jersey", wales=16, courses=4, loop_length=3.8e-3, yarn_radius=1e-4, boundary="cell",
                           contact_stiffness=stiffness)
        t = time.perf_counter()
        r = ex.relax(f, friction=0.0, max_steps=max_steps,
                     world=f.world(friction=0.0, viscosity=1.0, contact_recheck=True))
        wall = time.perf_counter() - t
        n = len(r.world.contacts()["normal_force"])
        print(f"{'rigid' if stiffness is None else 'distributed':12s} {str(r.converged):9s} {r.steps:5d} {r.fails:7d} {wall:8.1f} "
              f"{1e3 * wall / max(r.steps + r.fails, 1):8.1f} {n:11d} {r.dimensions['k_c']:6.3f} {r.dimensions['k_w']:6.3f}", flush=True)
