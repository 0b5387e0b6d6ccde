"""A knit cell relaxed with Coulomb friction (μ = 0.3) on rigid contact
rows (stick/slip settled by active-set rounds) against distributed rows
(a spring per row trimmed to μN each step): steps, refusals, wall time,
ms per step and the largest |F_t|/(μN) of a row at the end, interleaved.

    PYTHONPATH=python python3 benchmarks/knit_friction_rows_bench.py [max_steps] [rounds] [wales] [courses]
"""
import sys
import time

import numpy as np

import strandkit as sk
from strandkit.knit import experiments as ex

max_steps = int(sys.argv[1]) if len(sys.argv) > 1 else 300
rounds = int(sys.argv[2]) if len(sys.argv) > 2 else 2
wales = int(sys.argv[3]) if len(sys.argv) > 3 else 8
courses = int(sys.argv[4]) if len(sys.argv) > 4 else 2
mu = 0.3
print(f"{wales} x {courses} cell, mu = {mu}, at most {max_steps} steps")
print(f"{'rows':12s} {'converged':9s} {'steps':>5s} {'refused':>7s} {'wall (s)':>8s} {'ms/step':>8s} {'rows at end':>11s} {'max Ft/muN':>10s} {'k_c':>6s} {'k_w':>6s}")
for _ in range(rounds):
    for stiffness in (None, "yarn"):
        f = sk.knit.fabric("jersey", wales=wales, courses=courses, loop_length=3.8e-3, yarn_radius=1e-4, boundary="cell",
                           contact_stiffness=stiffness)
        t = time.perf_counter()
        r = ex.relax(f, friction=mu, max_steps=max_steps, world=f.world(friction=mu, viscosity=1.0, contact_recheck=True))
        wall = time.perf_counter() - t
        c = r.world.contacts()
        n, ft = c["normal_force"], np.linalg.norm(c["friction_force"], axis=1)
        worst = float((ft[n > 0] / (mu * n[n > 0])).max()) if np.any(n > 0) else float("nan")
        print(f"{'rigid' if stiffness is None else 'distributed':12s} {str(r.converged):9s} {r.steps:5d} {r.fails:7d} {wall:8.1f} "
              f"{1e3 * wall / max(r.steps + r.fails, 1):8.1f} {len(n):11d} {worst:10.4f} {r.dimensions['k_c']:6.3f} {r.dimensions['k_w']:6.3f}", flush=True)
