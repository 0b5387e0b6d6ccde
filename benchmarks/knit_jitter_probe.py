"""Why the frictionless knit cell's relaxation stalls (issue 18): after
PRE steps of `experiments.relax`, POST more steps of the same flow, each
printed with its time step, its largest control-point move, the cosine
between this step's whole move and the last one's, the contacts found
again (same rods, within 20 µm of a point of the last step's) or new, the
cosine between successive changes of the found-again contacts' normal
forces, and the elastic energy's change.

Usage: python3 knit_jitter_probe.py [PRE] [POST]   (defaults 400, 40)
The cell: jersey, 16 wales × 4 courses, periodic both ways, 3.8 mm loops,
r = 0.1 mm nylon, no friction, `contact_recheck`. Measured (2026-12-02):
the README's "Knitted fabrics", the stall paragraph.
"""
import sys
import time

import numpy as np

import strandkit as sk
from strandkit.knit import experiments as ex

pre = int(sys.argv[1]) if len(sys.argv) > 1 else 400
post = int(sys.argv[2]) if len(sys.argv) > 2 else 40
f = sk.knit.fabric("jersey", wales=16, courses=4, loop_length=3.8e-3, yarn_radius=1e-4, boundary="cell")
t0 = time.time()
r = ex.relax(f, friction=0.0, max_steps=pre, record_every=50,
             world=f.world(friction=0.0, viscosity=1.0, contact_recheck=True))
print(r, f"{time.time() - t0:.0f} s", flush=True)
w = r.world
flow = ex._Flow(w, f.yarn_radius, 0.25, dt=w.params["dt"])


def coords():
    return np.concatenate([rod.control_points for rod in w.rods()])


def cos(a, b):
    return float(a @ b / (np.linalg.norm(a) * np.linalg.norm(b) + 1e-300))


last = w.contacts()
last_df = np.full(len(last["normal_force"]), np.nan)  # each contact's last force change (N)
last_move = None
e_last = w.energy()["elastic"]
print("step  dt (s)   largest move (µm)  cos(moves)  contacts (again, new)  cos(force changes)  dE/E")
for k in range(post):
    dt = flow.dt
    x0 = coords()
    moved = flow.step()
    move = (coords() - x0).ravel()
    c = w.contacts()
    # Contacts found again: same rods, a point within 20 µm of one of the
    # last step's; their force changes now and at the last step.
    n = len(c["normal_force"])
    df = np.full(n, np.nan)
    now, before, nearest = [], [], []
    for i in range(n):
        same = np.flatnonzero((last["rod_a"] == c["rod_a"][i]) & (last["rod_b"] == c["rod_b"][i]))
        if len(same) == 0:
            continue
        d = np.linalg.norm(last["points"][same] - c["points"][i], axis=1)
        j = same[int(np.argmin(d))]
        nearest.append(d.min())
        if d.min() < 20e-6:
            df[i] = c["normal_force"][i] - last["normal_force"][j]
            if np.isfinite(last_df[j]):
                now.append(df[i])
                before.append(last_df[j])
    e = w.energy()["elastic"]
    if moved is None:
        print(f"{k:4d}  {dt:.2e}  refused", flush=True)
        continue
    cm = cos(move, last_move) if last_move is not None else float("nan")
    cf = cos(np.array(now), np.array(before)) if now else float("nan")
    again = int(np.isfinite(df).sum())
    print(f"{k:4d}  {dt:.2e}  {moved * 1e6:6.2f}  {cm:+.3f}  {n:4d} ({again}, {n - again})  {cf:+.3f}  {(e - e_last) / e_last:+.2e}"
          f"  nearest last point: median {np.median(nearest) * 1e6:.0f} µm, 90 % {np.percentile(nearest, 90) * 1e6:.0f} µm", flush=True)
    last, last_df, last_move, e_last = c, df, move, e
