"""Buckling of a twisted duplex with thermal noise (issue 17: "with noise,
buckling earlier, as Marko 2007 describes; report the value at 1 pN").

Turns the bead end of a duplex (``experiments.magnetic_tweezers``) at a
constant force with noise, in Brownian dynamics with implicit Euler (it
samples the slow bending and writhe modes; ``docs/dna_calibration.md``),
then bins the records by turns and prints, per bin, the mean elastic
torque and extension with their standard errors (from 10 blocks per bin),
and the references:

- the zero-temperature threshold: the clamped finite rod's
  ``polymer.buckling_torque`` (→ 2√(BF) for long rods);
- the extended state's twist stiffness softened by the bending
  fluctuations (Moroz & Nelson 1997, as Marko 2007 uses it):
  C_s = C (1 − C/(4A) √(kT/(A F))), so the torque rises as kT C_s/L per
  radian before buckling (zero temperature: C_eff = C − g²/S);
- Marko 2007's two-phase coexistence torque, τ_b = √(2 kT g P C_s /
  (C_s − P)) with g = F − √(kT F/A), for a plectoneme twist stiffness P
  (24 nm there): it needs a plectoneme, i.e. self-contact, which the
  duplex does not have (its strands pass through each other), so it is
  printed for scale, not compared.

Runs of 2026-11-30 (5 ps, 30 ns at rest; docs/dna_calibration.md): at
0.001 and 0.01 of water's drag the step diverged (steps 185 and 172; at
0.01 with adaptive sub-steps at step 7276). At 0.03, 0.01 turns/ns, 455 bp,
1 pN: torque slope 13.40 (seed 1) and 14.56 (seed 2) pN·nm per turn over
the first 0.65–0.85 turns, against C_s's 14.46 and C's 16.88; seed 1 to
2.2 turns reached 28.7 ± 1.4 pN·nm (0.96 of the zero-T threshold) with no
clear buckling. The slowest bending mode relaxes in ~450 ns there: these
runs are shorter than it.

Usage:
    python3 benchmarks/dna_thermal_buckling_probe.py [N_BP [F_PN [TURNS [RATE [ETA [SEED]]]]]]
(defaults 455 bp, 1 pN, 2.4 turns, 0.02 turns/ns, 0.03 of water's drag,
seed 1; 298.15 K, 5 ps steps, ``WAIT`` ns at rest first, default 10).
Writes ``buckle_<n>_<F>_<seed>.csv`` in the system's temporary directory
as it runs (``OUT`` overrides the prefix) and reads it back with
``ANALYSE=1`` (no run).
"""
import math
import os
import sys
import tempfile

import numpy as np

import strandkit as sk
from strandkit import polymer

KT = 4.114  # pN·nm at 298.15 K
A, C_ZERO_T = 50.0, 412.0 / KT  # nm: the duplex's calibrated bending and twist persistence (README, 80 bp)


def bins(turns, values, width, blocks=10):
    """Mean and standard error of ``values`` per ``width`` of turns, the
    error from ``blocks`` consecutive blocks of each bin (records are
    correlated)."""
    out = []
    edges = np.arange(0.0, turns.max() + width, width)
    for lo, hi in zip(edges[:-1], edges[1:]):
        sel = values[(turns >= lo) & (turns < hi)]
        if len(sel) < 2 * blocks:
            continue
        means = np.array([b.mean() for b in np.array_split(sel, blocks)])
        out.append((0.5 * (lo + hi), sel.mean(), means.std(ddof=1) / math.sqrt(blocks)))
    return np.array(out)


def main():
    args = sys.argv[1:]
    n = int(args[0]) if len(args) > 0 else 455
    force = float(args[1]) if len(args) > 1 else 1.0
    turns = float(args[2]) if len(args) > 2 else 2.4
    rate = float(args[3]) if len(args) > 3 else 0.02
    eta = float(args[4]) if len(args) > 4 else 0.03
    seed = int(args[5]) if len(args) > 5 else 1
    prefix = os.environ.get("OUT", os.path.join(tempfile.gettempdir(), f"buckle_{n}_{force:g}_{seed}"))
    if not os.environ.get("ANALYSE"):
        seq = "GATTACA" * (n // 7 + 1)
        d = sk.dna.duplex(seq[:n], break_averaging_time=1.0)
        sk.dna.experiments.magnetic_tweezers(
            d, force=force, turns=turns, turns_per_ns=rate, wait=float(os.environ.get("WAIT", 10.0)), dt=0.005, viscosity=eta,
            temperature=298.15, seed=seed, scheme="implicit_euler", brownian=True, record_every=10,
            out=prefix, frame_every=4000, progress_bar=False)
    rec = np.genfromtxt(prefix + ".csv", delimiter=",", names=True, skip_header=1)
    t, ext = rec["turns"], rec["extension_nm"]
    tq = rec["surface_torque_pNnm"] + (rec["torque_pNnm"] - rec["surface_torque_pNnm"]) / 3.0
    # The free pairs' span, nm; the twisted length (pair 1 to pair n − 2) is
    # one rise longer: the predicted slopes are 0.2 % high on 455 bp.
    length = 0.34 * (n - 4)
    b = A * KT
    zero_t = polymer.buckling_torque(b, force, length)
    c = C_ZERO_T
    c_s = c * (1.0 - c / (4.0 * A) * math.sqrt(KT / (A * force)))
    g = force - math.sqrt(KT * force / A)
    p = 24.0
    marko = math.sqrt(2.0 * KT * g * p * c_s / (c_s - p))
    print(f"{n} bp at {force} pN, seed {seed}: {len(t)} records, {t.max():.3f} turns; L {length:.1f} nm")
    print(f"zero temperature: 2√(BF) {2 * math.sqrt(b * force):.2f}, clamped finite rod {zero_t:.2f} pN·nm")
    print(f"torque slope per turn: zero-T C {2 * math.pi * KT * c / length:.2f}, "
          f"Moroz–Nelson C_s {2 * math.pi * KT * c_s / length:.2f} pN·nm (C_s/C {c_s / c:.3f})")
    print(f"Marko 2007 coexistence torque (P = 24 nm, not comparable: no self-contact): {marko:.2f} pN·nm")
    rest = t <= 0.0
    print(f"at rest: extension {ext[rest].mean():.2f} nm, torque {tq[rest].mean():.2f} pN·nm")
    bt, be = bins(t, tq, 0.1), bins(t, ext, 0.1)
    if len(bt) < 3:
        print("too few records to bin: run longer")
        return
    print(" turns   torque ± se      extension ± se")
    for (x, m, s), (_, e, es) in zip(bt, be):
        print(f" {x:5.2f}  {m:7.2f} ± {s:5.2f}  {e:8.2f} ± {es:5.2f}")
    # The slope before buckling: the bins below half the zero-T threshold's turns.
    early = bt[bt[:, 1] < 0.5 * zero_t]
    if len(early) >= 3:
        slope = np.polyfit(early[:, 0], early[:, 1], 1)[0]
        print(f"measured slope over {early[0, 0]:.2f}–{early[-1, 0]:.2f} turns: {slope:.2f} pN·nm per turn "
              f"(C_eff/C {slope * length / (2 * math.pi * KT * c):.3f})")
    peak = int(np.argmax(bt[:, 1]))
    print(f"highest binned torque {bt[peak, 1]:.2f} ± {bt[peak, 2]:.2f} pN·nm at {bt[peak, 0]:.2f} turns "
          f"({bt[peak, 1] / zero_t:.3f} of the zero-T threshold)")
    top = int(np.argmax(be[:, 1]))
    print(f"longest binned extension {be[top, 1]:.2f} nm at {be[top, 0]:.2f} turns")


if __name__ == "__main__":
    main()
