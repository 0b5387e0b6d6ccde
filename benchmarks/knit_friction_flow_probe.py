"""The knit flow under friction: step attempts, refusals and forced steps
of a cell's stretch (BENCHMARKS §50, issue 18).

An 8 × 4 jersey cell (``boundary="cell"``, 3.8 mm loops, r = 0.1 mm
nylon) is relaxed 300 frictionless steps with ``contact_recheck``, then
stretched along the wale to 10 % in 5 increments with μ = 0.3 (no
unloading). Every step of the stretch's flow is counted: attempts,
refused (the world unchanged, dt quartered), forced (a constraint's
correction taken with the reach guard let out), and the yarns' closest
approach (diameters) after each step.

Usage: python3 knit_friction_flow_probe.py [WALES COURSES]
"""
import sys
import time

import strandkit as sk
from strandkit.knit import experiments as ex
from strandkit.knit.geometry import clearance

wales, courses = (int(x) for x in sys.argv[1:3]) if len(sys.argv) > 2 else (8, 4)
f = sk.knit.fabric("jersey", wales=wales, courses=courses, loop_length=3.8e-3, yarn_radius=1e-4, boundary="cell")
t0 = time.time()
r = ex.relax(f, max_steps=300, record_every=50, world=f.world(friction=0.0, viscosity=1.0, contact_recheck=True))
print(r, f"{time.time() - t0:.0f} s", flush=True)

step = ex._Flow.step
counts = {"attempts": 0, "closest": float("inf"), "flow": None}


def counted(flow):
    move = step(flow)
    counts["attempts"] += 1
    counts["flow"] = flow
    counts["closest"] = min(counts["closest"], clearance(flow.world, f))
    return move


ex._Flow.step = counted
t0 = time.time()
s = ex.stretch(r, strain=0.1, friction=0.3, increments=5, settle_steps=50, steps_per_increment=120, unload=False)
flow = counts["flow"]
print(s, f"{time.time() - t0:.0f} s")
print(f"step attempts {counts['attempts']}, refused {flow.fails}, forced {flow.forced}, "
      f"closest approach {counts['closest']:.3f} diameters")
for e, force, lat in zip(s.strain, s.force, s.lateral_strain):
    print(f"{e:6.3f} {force:9.4g} N  lateral {lat:8.5f}")
