"""Probe (issue 17): how much a noisy duplex shortens under a force, against
a plain worm-like-chain rod of the same persistence pulled the same way,
and the free duplex's tangent correlations by scale. Not a test: the runs
take minutes and their figures are recorded in README ("Not yet") and the
session notes.

    python benchmarks/dna_force_extension_probe.py duplex  N F STEPS [T [averaged|brownian]]   # N bp, F pN
    python benchmarks/dna_force_extension_probe.py rod     L F STEPS pin|clamp
    python benchmarks/dna_force_extension_probe.py free    N STEPS

duplex: N bp (break forces infinite) held at pair 0 by two traps, pulled
at the last pair by F along the axis, Langevin noise at T K (trapezoidal,
5 ps, viscosity 0.1; with ``averaged``, the stacking averaged over each
step at 0.25 ps, framed every 20 steps; with ``brownian``, overdamped with
isotropic drag at water's viscosity and the stacking averaged, 5 ps;
``DT``, ``ETA`` (viscosity, pN·ns/nm²), ``SEED`` and ``SCHEME`` (e.g.
``implicit_euler``) in the environment override); every 5 steps the pairs are framed as
``fluctuations.pair_frames`` frames them and, for interior spans (pairs
m … N−1−m), the span z along the pull and the contour Lc (the rises along
the local axis, summed) are read: z/Lc against Bouchiat's long chain.
rod: a rod of A = 50 nm and length L nm, pinned (or clamped) at one end
and pulled at the other, z/Lc over [5.1, L − 5.1] nm (viscosity 0.01,
10 ps, sampling length 3 nm). free: a free duplex's 1 − ⟨z_i·z_{i+k}⟩
against the worm-like chain's 1 − e^{−k·rise/A}.

Measured 2026-11-29 (first fifth of each run dropped, 8 blocks):
- duplex 100 bp, 10 pN, 4000 steps: z/Lc 0.9689 ± 0.0014 (m = 15),
  0.9689 ± 0.0024 (m = 30); Bouchiat 0.9546: shortening 3.1 % against
  4.5 %. At 3 pN, 14000 steps: 0.9534 ± 0.0059 (m = 15), 0.9565 ±
  0.0065 (m = 30), Bouchiat 0.9171 (4.7 % against 8.3 %; 5000 steps read
  0.9613 ± 0.0017: the slowest modes relax in ~8 ns there). Zero
  temperature: z/Lc 1.0000, Lc 23.635 nm (m = 15) against 23.694 nm with
  noise.
- duplex 100 bp, 10 pN, averaged stacking, 48000 steps of 0.25 ps: z/Lc
  0.9660 ± 0.0029 (m = 15), 0.9685 ± 0.0022 (m = 30), 48 ms/step: within
  the error of the held stacking's (2026-11-29, thirty-fourth session).
- duplex 100 bp, 10 pN, brownian, 4000 steps (2026-11-30): ⟨θ²⟩ 0.0587 ±
  0.0024, z/Lc 0.9709 ± 0.0013 (m = 15) at water's viscosity; with
  ETA=0.1 0.0780 ± 0.0057 and 0.9599 ± 0.0031 (exact tilt 0.0898), 424
  ms/step; SEED=7: 0.0726 ± 0.0061 and 0.9629 ± 0.0033.
- duplex, brownian, SCHEME=implicit_euler (2026-11-30): 100 bp, 10 pN,
  ETA=0.1, 8000 steps: ⟨θ²⟩ 0.0743 ± 0.0054, z/Lc 0.9611 ± 0.0030 (m =
  15), 13.6 ms/step. 300 bp, 40000 steps, ETA=0.03: 3 pN z/Lc 0.9329 ±
  0.0059 (Bouchiat 0.9171), ⟨θ²⟩ 0.124 (exact 0.166); 10 pN 0.9637 ±
  0.0020 (0.9546), ⟨θ²⟩ 0.069 (0.091); 5 pN, 30000 steps: 0.9474 ±
  0.0049 (0.9358); 30 pN, 20000 steps: 0.9821 ± 0.0004 (0.9738); 42
  ms/step. 3 pN at ETA=0.1, 30000 steps: 0.9412 ± 0.0051, ⟨θ²⟩ 0.109
  (docs/dna_calibration.md).
- rod 34 nm, 10 pN, 20000 steps: 0.9564 ± 0.0008 pinned, 0.9572 ± 0.0008
  clamped (shortening 4.4 %, 4.3 %); 3 pN clamped 0.9235 ± 0.0023 (7.7 %
  against Bouchiat's 8.3 %): finite length and ends take 5–8 % of the
  shortening, not the duplex's 30–50 %.
- free 60 bp, 8000 steps (stacking held): 1 − ⟨cos⟩ at k = 2, 5, 10,
  20, 30, 40 bp: 0.0047, 0.0216, 0.0564, 0.126, 0.199, 0.262 against
  0.0135, 0.0334, 0.0657, 0.127, 0.185, 0.238 (A_eff 144, 78, 59, 50,
  46, 45 nm): the held stacking's stiff modes cooled by the step; the
  model's exact values (`examples/dna_harmonic.rs`) are a worm-like
  chain's (A_eff 51 nm at 2 bp), and the averaged stacking samples them.
"""
import math
import os
import sys
import time

import numpy as np

import strandkit as sk
from strandkit.dna._checks import noise_scheme
from strandkit.dna.fluctuations import _steps, pair_frames, standard_error
from strandkit.loads import point_force, trap
from strandkit.polymer import bouchiat_extension

T = 298.15
KT = sk.units.kT(T, "molecular")  # pN·nm
A = 50.0  # nm


def blocks(x, n=8):
    """Mean and standard error of ``x`` from ``n`` consecutive blocks."""
    return float(np.mean(x)), standard_error([b.mean() for b in np.array_split(np.asarray(x), n)])


def duplex_run(n, force, steps, temperature=T, averaged=False, brownian=False, spans=(15, 30)):
    spans = [m for m in spans if n - 1 - 2 * m >= 4]  # interior spans of at least 4 steps
    averaged = averaged or brownian
    d = sk.dna.duplex(("GATTACA" * (n // 7 + 1))[:n], break_forces=[math.inf] * n, averaged_stacking=averaged)
    noisy = temperature > 0
    every = 5 if brownian or not averaged else 20
    dt = float(os.environ["DT"]) if "DT" in os.environ else 0.005 if brownian else 0.00025 if averaged else 0.005 if noisy else 0.05
    eta = float(os.environ["ETA"]) if "ETA" in os.environ else 0.1 if noisy and not brownian else 1.0
    w = sk.World(units="molecular", dt=dt, viscosity=eta,
                 temperature=temperature, seed=int(os.environ.get("SEED", 3)), scheme=noise_scheme(temperature, os.environ.get("SCHEME")),
                 adaptive_dt=True, overdamped=brownian, isotropic_drag=brownian)
    ins = w.insert(d.assembly)
    a, b = (ins.rods[i] for i in d.strands)
    ends = lambda k: ((a, float(d.abscissae[0][k])), (b, float(d.abscissae[1][int(d.partner[k])])))  # noqa: E731
    origin = pair_frames(d, a, b)[0]
    e = origin[-1] - origin[0]
    e /= np.linalg.norm(e)
    for rod, u in ends(0):
        w.add_load(trap(rod, u, rod.position(u), 10.0))
    for rod, u in ends(n - 1):
        w.add_load(point_force(rod, u, 0.5 * force * e))
    rows, start = [], time.time()
    for step in range(steps):
        w.step()
        if step % every == 0 and step >= steps // 5:
            o, x, z = pair_frames(d, a, b)
            rise = _steps(o, x, z)[1]
            tilt = 1.0 - (z @ e) ** 2  # θ² of each pair's axis from the pull
            rows.append([v for m in spans
                         for v in (float(np.dot(o[n - 1 - m] - o[m], e)), float(rise[m:n - 1 - m].sum()),
                                   float(tilt[m:n - m].mean()))])
    r = np.array(rows)
    print(f"duplex {n} bp, {force:g} pN, {temperature:g} K, {'Brownian, ' if brownian else ''}{'averaged' if averaged else 'held'} stacking, "
          f"dt {dt * 1e3:g} ps: {(time.time() - start) / steps * 1e3:.1f} ms/step; "
          f"Bouchiat {bouchiat_extension(force, A, KT):.4f}")
    for j, m in enumerate(spans):
        q = blocks(r[:, 3 * j] / r[:, 3 * j + 1])
        t = blocks(r[:, 3 * j + 2])
        print(f"  pairs {m}…{n - 1 - m}: Lc {r[:, 3 * j + 1].mean():.3f} nm, z/Lc {q[0]:.4f} ± {q[1]:.4f}, "
              f"axis tilt ⟨θ²⟩ {t[0]:.4f} ± {t[1]:.4f}")


def rod_run(length, force, steps, clamped):
    dna = sk.Material("dna", A * KT / (math.pi / 4), 0.3, 1.7e-3)  # B = A kT at radius 1 nm
    rod = sk.straight((0, 0, 0), (length, 0, 0), section=1.0, material=dna, n_control_points=int(length) + 4,
                      with_roll=False, stretch_at_greville=True, sampling_length=3.0)
    w = sk.World(units="molecular", temperature=T, viscosity=0.01, dt=0.01, scheme=noise_scheme(T, None), seed=11,
                 adaptive_dt=True)
    r = w.add_rod(rod)
    w.add_constraint(r, sk.position(r.u_start, (0, 0, 0)))
    if clamped:
        w.add_constraint(r, sk.tangent(r.u_start, (1, 0, 0)))
    w.add_load(sk.point_force(r, r.u_end, (force, 0, 0)))
    # A straight rod at rest: arc length is proportional to u.
    u = np.linspace(*(r.u_start + (r.u_end - r.u_start) * s / length for s in (5.1, length - 5.1)), 400)
    q = []
    for step in range(steps):
        w.step()
        if step % 5 == 0 and step >= steps // 5:
            p = r.position(u)
            q.append((p[-1, 0] - p[0, 0]) / np.sum(np.linalg.norm(np.diff(p, axis=0), axis=1)))
    m, se = blocks(q)
    print(f"rod {length:g} nm, {force:g} pN, {'clamped' if clamped else 'pinned'}: z/Lc {m:.4f} ± {se:.4f}; "
          f"Bouchiat {bouchiat_extension(force, A, KT):.4f}")


def free_run(n, steps, ks=(2, 5, 10, 20, 30, 40)):
    ks = [k for k in ks if n - 10 - k > 0]  # windows between pairs 5 … n − 5
    d = sk.dna.duplex(("GATTACA" * (n // 7 + 1))[:n], break_forces=[math.inf] * n)
    w = sk.World(units="molecular", dt=0.005, viscosity=0.1, temperature=T, seed=5, scheme=noise_scheme(T, None),
                 adaptive_dt=True)
    ins = w.insert(d.assembly)
    a, b = (ins.rods[i] for i in d.strands)
    acc = {k: [] for k in ks}
    for step in range(steps):
        w.step()
        if step % 10 == 0 and step > steps // 5:
            z = pair_frames(d, a, b)[2]
            for k in ks:
                i = np.arange(5, n - 5 - k)
                acc[k].append(np.mean(np.sum(z[i] * z[i + k], axis=1)))
    for k in ks:
        m, se = blocks(acc[k])
        span = k * 0.34
        print(f"k = {k:3d} bp: 1 − <cos> {1 - m:.5f} ± {se:.5f} (A_eff {-span / math.log(m):.1f} nm); "
              f"worm-like chain {1 - math.exp(-span / A):.5f}")


if __name__ == "__main__":
    mode, args = sys.argv[1], sys.argv[2:]
    if mode == "duplex":
        duplex_run(int(args[0]), float(args[1]), int(args[2]), float(args[3]) if len(args) > 3 else T,
                   averaged=len(args) > 4 and args[4] == "averaged", brownian=len(args) > 4 and args[4] == "brownian")
    elif mode == "rod":
        rod_run(float(args[0]), float(args[1]), int(args[2]), args[3] == "clamp")
    elif mode == "free":
        free_run(int(args[0]), int(args[1]))
    else:
        sys.exit(__doc__)
