"""Poincloux 2018's stretch of stockinette on a knit cell (issue 18).

A jersey cell periodic both ways (``boundary="cell"``, 16 wales × 4
courses, 3.8 mm loops, r = 0.1 mm nylon monofilament: Poincloux's
bending-dominated yarn, stretched by < 1 % at these loads) is relaxed
from a chosen start, then stretched along the wale by holding its period
(``experiments.stretch``), loaded and unloaded.
Printed: the force–strain curve, the lateral strain, the yarn-length
coefficient δ = −Δc/Δw (c the wale spacing, the stitch width; w the
course spacing, the stitch height: Poincloux's ⟨c⟩ + δ⟨w⟩ = const, δ =
0.86) and the Poisson ratio ν = −ε_c/ε_w (Poincloux: δ w*/c* = 0.46,
with their rest c*/w* = 3.93/2.08), the loading and unloading work.

Usage: python3 knit_cell_stretch_probe.py START FRICTION [LOOP_MM] [STEPS]
  START: default | narrow (``spacing`` built narrow, as in the README);
  FRICTION: μ during the stretch (the relaxation is frictionless);
  LOOP_MM: loop length in mm (3.8: ℓ/d = 19); STEPS: relaxation steps.
  STRAIN (environment, 0.2): the largest strain, in INCREMENTS (10)
  increments of at most PER_INCREMENT (300) steps each way.
  ROWS=yarn (environment): distributed contact rows
  (``contact_stiffness="yarn"``) instead of one rigid row per contact.
  HOLD=n (environment): instead of the cycle, one increment to STRAIN,
  then n more steps of the flow at that strain, the force and lateral
  strain printed every 100 (how far an increment is from equilibrium).
Writes a JSON into the system's temporary directory. Measured
(2026-12-01): the README's "Knitted fabrics", the table after the cell.
"""
import json
import os
import sys
import tempfile
import time

import numpy as np

import strandkit as sk
from strandkit.knit import experiments as ex

start = sys.argv[1] if len(sys.argv) > 1 else "narrow"
mu = float(sys.argv[2]) if len(sys.argv) > 2 else 0.0
loop = float(sys.argv[3]) * 1e-3 if len(sys.argv) > 3 else 3.8e-3
steps = int(sys.argv[4]) if len(sys.argv) > 4 else 2000
strain = float(os.environ.get("STRAIN", "0.2"))
# The narrow starts of the README's cell paragraph, scaled with the loop.
narrow = {3.8e-3: (0.8e-3, 0.86e-3), 5e-3: (1.0e-3, 1.1e-3)}
spacing = narrow.get(loop, (0.21 * loop, 0.226 * loop)) if start == "narrow" else None
f = sk.knit.fabric("jersey", wales=16, courses=4, loop_length=loop, yarn_radius=1e-4, boundary="cell",
                   spacing=spacing, contact_stiffness=os.environ.get("ROWS") or None)
t0 = time.time()
r = ex.relax(f, friction=0.0, max_steps=steps, record_every=50)
print(r, f"{time.time() - t0:.0f} s", flush=True)
d0 = r.dimensions
c0, w0 = d0["wale_spacing"], d0["course_spacing"]
hold = int(os.environ.get("HOLD", "0"))
if hold:
    s = ex.stretch(r, strain=strain, friction=mu, increments=1, unload=False, settle_steps=100,
                   steps_per_increment=100)
    w = s.world
    link = w.group("period").constraints[0]
    flow = ex._Flow(w, f.yarn_radius, 0.25, dt=w.params["dt"])
    print(f"after the increment: F {s.force[-1]:.4g} N, lateral {s.lateral_strain[-1]:.5f}", flush=True)
    for k in range(1, hold + 1):
        flow.step()
        if k % 100 == 0:
            lat = f.dimensions(w)["wale_spacing"] / c0 - 1.0
            F = -float(np.asarray(link.reaction().force)[1])
            print(f"{k:5d} F {F:.4g} N lateral {lat:.5f} nu {-lat / strain:.3f} delta {-lat * c0 / (strain * w0):.3f} "
                  f"E {w.energy()['elastic']:.6g} J", flush=True)
    sys.exit(0)
s = ex.stretch(r, direction="wale", strain=strain, friction=mu, increments=int(os.environ.get("INCREMENTS", "10")),
               settle_steps=200, steps_per_increment=int(os.environ.get("PER_INCREMENT", "300")))
print(s, f"{time.time() - t0:.0f} s", flush=True)
print(f"rest: c* = {c0 * 1e3:.4f} mm (wale spacing), w* = {w0 * 1e3:.4f} mm (course spacing), c*/w* = {c0 / w0:.3f}")
print(" strain  force(N)   lateral  delta    nu")
for e, F, lat in zip(s.strain, s.force, s.lateral_strain):
    dl = -lat * c0 / (e * w0) if e > 0 else float("nan")
    nu = -lat / e if e > 0 else float("nan")
    print(f"{e:7.3f} {F:10.4g} {lat:9.5f} {dl:7.3f} {nu:7.3f}")
print(f"work loading {s.work_loading:.4g} J, unloading {s.work_unloading:.4g} J, ratio {s.work_unloading / s.work_loading:.3f}")
print(f"clearance {s.clearance:.3f}, parted {len(s.interlocks.parted)}")
out = os.path.join(tempfile.gettempdir(), f"knit_cell_stretch_{start}_{mu}_{loop * 1e3:g}_{os.environ.get('ROWS', 'rigid')}.json")
with open(out, "w") as fh:
    json.dump({"rest": d0, "strain": s.strain.tolist(), "force": s.force.tolist(),
               "lateral": s.lateral_strain.tolist(), "loading": s.loading.tolist(),
               "work": [s.work_loading, s.work_unloading]}, fh)
print("wrote", out)
