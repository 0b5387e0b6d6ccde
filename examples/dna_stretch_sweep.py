"""A helix-stretching sweep (issue 19): one scene — a B-DNA duplex held by
stiff springs at both strands' ends, one end pair pulled away from the other
at constant speed to 5 % strain in water (nm, pN, ns) — run over three
sequences (24, 36 and 48 bp) and three pulling speeds with
``strandkit.sweep``, each point's own outputs on disk.

From each run: the force at 5 % strain, and the end stiffness k = dF/dx
over the last 40 % of the stretch (past the toe where the off-axis strand
ends align with the pull). Checked:
1. Stokes: at low Reynolds number the drag adds a force linear in the
   speed, so the force at 5 % is affine in v (the worst residual of the
   line through the three speeds below 5 % of the drag force at the
   fastest), while k, the elastic part, does not depend on v (within 2 %);
2. the duplex is a spring of modulus S in series with end compliances:
   1/k = L/S + c; the slope over the three lengths gives S, checked within
   3 % of the calibration's bare stretch modulus (1100 pN: both end pairs
   are held by two points, so the twist cannot relax; with it free,
   S − g²/C = 1080 pN).
Saves dna_stretch_sweep.png (the force against speed per length; 1/k
against length with the fit) and the sweep in dna_stretch_sweep/ (results.parquet,
one Parquet row per point in points/, each run's observables and
trajectory in runs/). ``--dask`` runs it on a 2-worker Dask LocalCluster
(the numbers are the same). About 20 s.

    python examples/dna_stretch_sweep.py [--out DIR] [--dask]
"""
import sys

import numpy as np
import pandas as pd

import strandkit as sk
from _common import Checks, output_dir

SEQUENCE = "GATTACAGCGGCCGCTTATAATGCATGCATCGATCGTAGCATGACTGA"  # 48 bp; the shorter ones are its prefixes
LENGTHS = (24, 36, 48)            # bp
SPEEDS = (0.1, 0.2, 0.4)          # nm/ns
STRAIN = 0.05
RISE = 0.34                       # nm per bp
HOLD = 1e-3                       # nm/pN: each end point's spring (1000 pN/nm)


def scene():
    hold = lambda rod, at, label: {"hold": {"rod": rod, "at": at, "label": label, "compliance": HOLD}}  # noqa: E731
    return sk.Scene.from_builder(
        "dna.duplex", name="DNA stretch", sequence=SEQUENCE[:24], break_force_at=1e9, break_force_gc=1e9,
        world={"dt": 0.01, "viscosity": 1.0},
        protocol=[hold("strand[0]", "start", "held[0]"), hold("strand[1]", "end", "held[1]"),
                  hold("strand[0]", "end", "pulled[0]"), hold("strand[1]", "start", "pulled[1]"),
                  {"stretch": {"constraints": "pulled", "about": "held", "strain": STRAIN, "duration": 1.0}}],
        outputs={"every": 5, "frame_every": 50})


def main():
    argv = [a for a in sys.argv[1:] if a != "--dask"]
    dask = len(argv) != len(sys.argv) - 1
    sys.argv[1:] = argv
    out = output_dir(__doc__)
    checks = Checks()
    # Each point: a sequence and the duration that makes the pull's speed v (the strain is fixed).
    grid = [{"structure.args.sequence": SEQUENCE[:n], "protocol.4.stretch.duration": STRAIN * RISE * (n - 1) / v}
            for n in LENGTHS for v in SPEEDS]
    client = cluster = None
    if dask:
        from distributed import Client, LocalCluster
        cluster = LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None)
        client = Client(cluster)
    try:
        df = sk.sweep(scene(), grid, out=out / "dna_stretch_sweep", client=client, workers=2, progress_bar=False)
    finally:
        if client is not None:
            client.close()
            cluster.close()
    k, f_end = {}, {}
    for _, row in df.iterrows():
        n = len(row["structure.args.sequence"])
        v = round(STRAIN * RISE * (n - 1) / row["protocol.4.stretch.duration"], 6)
        o = pd.read_parquet(out / "dna_stretch_sweep" / "runs" / row["point"] / "observables.parquet")
        o = o[o["operation"] == "stretch"]
        x, f = o["drive_displacement"].to_numpy(), o["drive_force"].to_numpy()
        late = x >= 0.6 * x[-1]
        k[n, v], f_end[n, v] = np.polyfit(x[late], f[late], 1)[0], f[-1]
        print(f"{n} bp at {v:.2f} nm/ns: k = {k[n, v]:.3f} pN/nm, F = {f[-1]:.3f} pN at {100 * STRAIN:.0f} % "
              f"({row['elapsed']:.1f} s)")
    k0, drag, worst, spread = {}, {}, 0.0, 0.0
    for n in LENGTHS:
        fs = np.array([f_end[n, v] for v in SPEEDS])
        drag[n], f0 = np.polyfit(SPEEDS, fs, 1)
        worst = max(worst, float(np.max(np.abs(fs - (drag[n] * np.array(SPEEDS) + f0))) / (drag[n] * SPEEDS[-1])))
        ks = np.array([k[n, v] for v in SPEEDS])
        k0[n] = float(ks.mean())
        spread = max(spread, float(np.ptp(ks) / k0[n]))
    checks.true("drag force linear in the speed", worst < 0.05,
                f"worst residual {100 * worst:.2f} % of the drag at {SPEEDS[-1]} nm/ns "
                f"({', '.join(f'{drag[n]:.1f}' for n in LENGTHS)} pN·ns/nm at {', '.join(map(str, LENGTHS))} bp)")
    checks.true("stiffness independent of the speed", spread < 0.02, f"largest spread {100 * spread:.2f} %")
    lengths = np.array([RISE * (n - 1) for n in LENGTHS])
    inv = np.array([1 / k0[n] for n in LENGTHS])
    a, c = np.polyfit(lengths, inv, 1)
    cal = sk.dna.duplex(SEQUENCE).measured
    free = cal["stretch_modulus"] - cal["twist_stretch"] ** 2 / cal["twist_stiffness"]
    print(f"S = {1 / a:.1f} pN from the lengths (end compliance {c * 1e3:.2f} nm/nN); calibration: S = "
          f"{cal['stretch_modulus']:.1f} pN at fixed twist, {free:.1f} pN with the twist free")
    checks.close("stretch modulus from the length series", 1 / a, cal["stretch_modulus"], rtol=0.03)

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(1, 2, figsize=(10.5, 4.2))
    for n in LENGTHS:
        fs = [f_end[n, v] for v in SPEEDS]
        line = ax[0].plot(SPEEDS, fs, "o", label=f"{n} bp, k = {k0[n]:.1f} pN/nm")[0]
        f0 = np.mean(fs) - drag[n] * np.mean(SPEEDS)
        ax[0].plot([0, SPEEDS[-1]], [f0, f0 + drag[n] * SPEEDS[-1]], "--", lw=0.8, color=line.get_color())
    ax[0].set_xlabel("pulling speed (nm/ns)")
    ax[0].set_ylabel(f"force at {100 * STRAIN:.0f} % strain (pN)")
    ax[0].set_xlim(0, None)
    ax[0].legend()
    ax[1].plot(lengths, inv * 1e3, "o", label="1/k")
    ls = np.linspace(0, lengths[-1] * 1.05, 2)
    ax[1].plot(ls, (a * ls + c) * 1e3, "-", label=f"L/S + c: S = {1 / a:.0f} pN")
    ax[1].set_xlabel("contour length L (nm)")
    ax[1].set_ylabel("compliance 1/k (nm/nN)")
    ax[1].legend()
    fig.suptitle(f"DNA stretching sweep: {len(df)} runs ({'Dask LocalCluster' if dask else 'local processes'})")
    fig.tight_layout()
    fig.savefig(out / "dna_stretch_sweep.png", dpi=110)
    print(f"wrote {out / 'dna_stretch_sweep.png'} and {out / 'dna_stretch_sweep'}/")
    checks.finish()


if __name__ == "__main__":
    main()
