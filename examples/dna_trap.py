"""Thermal fluctuations (SPEC §3, issue 16): 16 short DNA fragments (20 nm,
radius 1 nm, bending persistence 50 nm, twist persistence 100 nm) in water at
25 °C, one end of each held by an optical trap of stiffness k = 0.5 pN/nm,
the rest free, in molecular units (nm, pN, ns). The energy is translation
invariant but for the trap, so the trapped end is Gaussian with variance
kT/k on each axis whatever the fragment does — the equipartition
calibration of every optical-tweezers lab. Checks that variance (10 %) and
the kinetic energy per coordinate (½ kT, 3 %); saves dna_trap.png (the
trapped end's histogram against the Gaussian, and a few fragments).

    python examples/dna_trap.py [--out DIR]    # default: $STRANDKIT_OUT, else ./out
"""
import math

import numpy as np

import strandkit as sk
from _common import Checks, output_dir

T = 298.15  # K
KT = sk.units.kT(T, "molecular")  # pN·nm
K_TRAP = 0.5  # pN/nm
N_RODS, LENGTH = 16, 20.0  # nm


def dna_fragment():
    i = math.pi / 4  # nm⁴, radius 1 nm
    young = 50.0 * KT / i  # B = A kT with A = 50 nm
    shear = 100.0 * KT / (2 * i)  # C = 100 nm × kT
    dna = sk.Material("dna", young, young / (2 * shear) - 1, 1.7e-3)  # density 1700 kg/m³ in ag/nm³
    return sk.straight((0, 0, 0), (LENGTH, 0, 0), section=1.0, material=dna, n_control_points=8, model="reference")


def main():
    out = output_dir(__doc__)
    checks = Checks()
    # η = 0.01 pN·ns/nm² (a hundredth of water's) damps the trapped fragment
    # about critically, so the statistics converge in a few ns of simulated
    # time; the equilibrium does not depend on it.
    world = sk.World(units="molecular", temperature=T, viscosity=0.01, dt=1e-3, scheme="trapezoidal", seed=2026,
                     adaptive_dt=True)
    rods = []
    for i in range(N_RODS):
        rod = world.add_rod(dna_fragment())
        anchor = np.array([0.0, 30.0 * i, 0.0])
        rod.control_points = rod.control_points + np.append(anchor, 0.0)
        world.add_load(sk.trap(rod, u=rod.u_start, anchor=anchor, stiffness=K_TRAP))
        rods.append((rod, anchor))
    n_coords = sum(r.control_points.size for r, _ in rods)
    ends, kinetic = [], []
    # The fragments start straight; as they bend they shorten about their
    # centre of drag, which pulls the trapped ends along the fragment (≈ 1 nm)
    # until the traps bring them back: 4 ns are left out.
    for step in range(12000):
        world.step()
        if step >= 4000 and step % 4 == 0:
            ends.append([rod.position(rod.u_start) - a for rod, a in rods])
            kinetic.append(world.energy()["kinetic"])
    ends = np.asarray(ends)  # (samples, rods, 3), nm
    var = float(np.mean(ends**2))
    checks.close("trapped end variance (nm²) = kT/k", var, KT / K_TRAP, rtol=0.10)
    checks.close("trapped end mean (nm)", float(np.mean(ends)), 0.0, atol=0.5)
    checks.close("kinetic energy per coordinate / (kT/2)", float(np.mean(kinetic)) / (0.5 * KT * n_coords), 1.0, rtol=0.03)

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4))
    x = ends.reshape(-1)
    ax1.hist(x, bins=60, density=True, alpha=0.6, label="trapped end (x, y, z)")
    s = np.linspace(x.min(), x.max(), 200)
    sigma2 = KT / K_TRAP
    ax1.plot(s, np.exp(-s**2 / (2 * sigma2)) / math.sqrt(2 * math.pi * sigma2), "k", label="Gaussian, variance kT/k")
    ax1.set_xlabel("displacement from the trap (nm)")
    ax1.set_ylabel("probability density (1/nm)")
    ax1.legend()
    for rod, a in rods[:6]:
        u = np.linspace(rod.u_start, rod.u_end, 60)
        p = np.array([rod.position(v) for v in u])
        ax2.plot(p[:, 0], p[:, 1], lw=2)
        ax2.plot([a[0]], [a[1]], "k+")
    ax2.set_aspect("equal")
    ax2.set_xlabel("x (nm)")
    ax2.set_ylabel("y (nm)")
    ax2.set_title(f"DNA fragments at {T:.0f} K (trap centres +)")
    fig.tight_layout()
    fig.savefig(out / "dna_trap.png", dpi=100)
    checks.finish()


if __name__ == "__main__":
    main()
