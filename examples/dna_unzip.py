"""The DNA story (issue 17, the showcase): build a B-DNA duplex from its
sequence, stretch it, then unzip it, at zero temperature in the
quasi-static limit (nm, pN, ns).

1. Stretch: a 60 bp duplex held at one end's two strands and pulled at the
   other's by traps moving at 0.05 nm/ns. Away from the ends (between the
   4th pairs from each end) its length grows as F/S: the stretch modulus
   from the slope must be DNA's, S = 1100 pN (±10 %; the SPEC's range is
   1000–1500 pN).
2. Unzip: a 30 bp sequence with a G·C-rich block in the middle, strand a's
   5′ end held and strand b's 3′ end pulled apart. The hydrogen bonds'
   break forces are set so that a duplex unzips at the forces measured by
   AFM (Rief, Clausen-Schaumann & Gaub 1999: A·T 9 pN, G·C 20 pN); the
   force must follow the sequence: the A·T regions at 9 pN and the G·C
   block at 20 pN (±15 %).

Saves dna_unzip.png (both curves against their references) and the
unzipping trajectory dna_unzip.pdb/.psf/.dcd with its records in
dna_unzip.csv (VMD: colour by Beta to see the broken pairs).

    python examples/dna_unzip.py [--out DIR]    # default: $STRANDKIT_OUT, else ./out
"""
import time

import numpy as np

import strandkit as sk
from _common import Checks, output_dir
from strandkit.dna import experiments as ex

STRETCH_SEQ = ("GATTACA" * 9)[:60]
UNZIP_SEQ = "ATTATAAATTT" + "GCGGCCGC" + "TATAAATTTAT"
S_DNA = 1100.0  # pN


def main():
    out = output_dir(__doc__)
    checks = Checks()
    t0 = time.perf_counter()

    # 1. Stretching.
    d = sk.dna.duplex(STRETCH_SEQ)
    print(d)
    st = ex.stretch(d, speed=0.05, distance=2.5, trap_stiffness=5.0, viscosity=0.1)
    strain = (st.span - st.span[0]) / st.span[0]
    half = len(st.force) // 4  # past the start-up transient of the traps
    s_fit = float(np.polyfit(strain[half:], st.force[half:], 1)[0])
    checks.close("stretch modulus S (pN) from the force-strain slope", s_fit, S_DNA, rtol=0.10)

    # 2. Unzipping.
    f_at, f_gc = ex.break_forces_for_unzipping(9.0, 20.0)
    print(f"hydrogen bonds break at {f_at:.1f} pN (A·T) and {f_gc:.1f} pN (G·C) to unzip at 9 and 20 pN")
    dz = sk.dna.duplex(UNZIP_SEQ, break_force_at=f_at, break_force_gc=f_gc)
    uz = ex.unzip(dz, distance=52.0, out=str(out / "dna_unzip"), frame_every=200, **ex.QUASI_STATIC)
    pairs = np.array([b["pair"] for b in uz.breaks])
    fb = np.array([b["trap_force"] for b in uz.breaks])
    gc = np.array([c in "GC" for c in UNZIP_SEQ])
    # Pairs at least 2 from a block boundary and from the ends (the fork
    # needs two pairs to settle into a block's force).
    edge = np.flatnonzero(np.diff(gc.astype(int))) + 0.5
    inner = np.array([min(abs(p - edge).min(), p, len(gc) - 1 - p) >= 2.5 for p in pairs])
    at_force = float(np.mean(fb[inner & ~gc[pairs]]))
    gc_force = float(np.mean(fb[inner & gc[pairs]]))
    checks.true("every pair opened, in order", list(pairs) == list(range(len(dz))), f"{len(pairs)} of {len(dz)}")
    checks.close("unzipping force in the A·T regions (pN)", at_force, 9.0, rtol=0.15)
    checks.close("unzipping force in the G·C block (pN)", gc_force, 20.0, rtol=0.15)
    print(f"{time.perf_counter() - t0:.0f} s")

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.2))
    ax1.plot(st.force, (st.span - st.span[0]) * 1e3, lw=2, label="duplex (between pairs 4 and 57)")
    f = np.linspace(0, st.force.max(), 50)
    ax1.plot(f, f / S_DNA * st.span[0] * 1e3, "k--", label=f"F/S × L, S = {S_DNA:.0f} pN")
    ax1.set_xlabel("force (pN)")
    ax1.set_ylabel("elongation (pm)")
    ax1.set_title(f"stretching {len(d)} bp: S = {s_fit:.0f} pN")
    ax1.legend()
    ax2.plot(uz.trap, uz.force, lw=1, label="trap force")
    ax2.plot([b["time"] * ex.QUASI_STATIC["speed"] for b in uz.breaks], fb, "o", ms=3, label="openings")
    for level, name in ((9.0, "A·T 9 pN"), (20.0, "G·C 20 pN")):
        ax2.axhline(level, color="k", ls="--", lw=0.8)
        ax2.text(1, level + 0.4, name + " (AFM)", fontsize=8)
    ax2.set_xlabel("trap displacement (nm)")
    ax2.set_ylabel("force (pN)")
    ax2.set_title(f"unzipping {UNZIP_SEQ[:10]}…: follows the G·C block")
    ax2.legend(loc="upper right")
    fig.tight_layout()
    fig.savefig(out / "dna_unzip.png", dpi=120)
    checks.finish()


if __name__ == "__main__":
    main()
