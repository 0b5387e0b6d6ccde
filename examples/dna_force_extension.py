"""Force–extension of DNA (SPEC §9.1, issue 16): the curve every tweezers
experiment starts from. Free 100 nm DNA chains (radius 1 nm, bending
persistence A = 50 nm) in molecular units (nm, pN, ns) at 25 °C, pulled at
their two ends by ±F along x at 1, 3 and 10 pN; Langevin dynamics with the
trapezoidal rule, the stretch at the Greville points (no locking at this
resolution) and a 5 nm sampling length (heavier short modes: 10 ps steps
without changing the equilibrium). Checks the mean extension against the
exact worm-like chain of the chains' mean contour (3 %: a short run), and
saves dna_force_extension.png: the points against that chain and Bouchiat's
long-chain interpolation.

    python examples/dna_force_extension.py [--out DIR]    # default: $STRANDKIT_OUT, else ./out
"""
import math

import numpy as np

import strandkit as sk
from _common import Checks, output_dir
from strandkit.polymer import bouchiat_extension, wlc_extension

T = 298.15  # K
KT = sk.units.kT(T, "molecular")  # pN·nm
A = 50.0  # nm, bending persistence
LENGTH = 100.0  # nm
FORCES = (1.0, 3.0, 10.0)  # pN
CHAINS = 3  # per force


def dna_chain():
    i = math.pi / 4  # nm⁴, radius 1 nm
    young = A * KT / i  # B = A kT
    dna = sk.Material("dna", young, 0.3, 1.7e-3)  # density 1700 kg/m³ in ag/nm³
    return sk.straight((0, 0, 0), (LENGTH, 0, 0), section=1.0, material=dna, n_control_points=40, with_roll=False,
                       stretch_at_greville=True, sampling_length=5.0)


def contour(rod):
    p = rod.position(np.linspace(rod.u_start, rod.u_end, 800))
    return float(np.sum(np.linalg.norm(np.diff(p, axis=0), axis=1)))


def main():
    out = output_dir(__doc__)
    checks = Checks()
    # η = 0.002 pN·ns/nm² (a fifth of a percent of water's) lets the chains
    # move almost freely between kicks, so the statistics converge in a few
    # tens of ns; the equilibrium does not depend on it.
    world = sk.World(units="molecular", temperature=T, viscosity=0.002, dt=0.01, scheme="trapezoidal", seed=7,
                     adaptive_dt=True)
    groups = []
    for k, force in enumerate(FORCES):
        rods = []
        for j in range(CHAINS):
            rod = world.add_rod(dna_chain())
            rod.control_points = rod.control_points + np.array([0.0, 40.0 * (CHAINS * k + j), 0.0])
            world.add_load(sk.point_force(rod, rod.u_start, (-force, 0.0, 0.0)))
            world.add_load(sk.point_force(rod, rod.u_end, (force, 0.0, 0.0)))
            rods.append(rod)
        groups.append(rods)
    steps, burn = 5000, 1000
    z = np.zeros((len(FORCES), steps - burn))
    lc = np.zeros(len(FORCES))
    for step in range(steps):
        world.step()
        if step < burn:
            continue
        for k, rods in enumerate(groups):
            z[k, step - burn] = np.mean([rod.position(rod.u_end)[0] - rod.position(rod.u_start)[0] for rod in rods])
            if step % 50 == 0:
                lc[k] += np.mean([contour(rod) for rod in rods]) / ((steps - burn) / 50)
    means = z.mean(axis=1)
    for k, force in enumerate(FORCES):
        exact = lc[k] * wlc_extension(force, A, lc[k], kT=KT)
        checks.close(f"<z> at {force:g} pN (nm) vs the worm-like chain of the mean contour", float(means[k]), exact, rtol=0.03)

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    f = np.geomspace(0.05, 20, 80)
    fig, ax = plt.subplots(figsize=(6, 4.5))
    ax.plot([bouchiat_extension(x, A, KT) for x in f], f, "k", label="Bouchiat (long chain)")
    ax.plot([wlc_extension(x, A, LENGTH, KT) for x in f], f, "k--", label=f"exact worm-like chain, L = {LENGTH:g} nm")
    ax.plot(means / lc, FORCES, "o", color="C3", label="strandkit, Langevin (z / mean contour)")
    ax.set_yscale("log")
    ax.set_xlabel("relative extension z / L")
    ax.set_ylabel("force (pN)")
    ax.set_title(f"DNA, A = {A:g} nm, {T:.0f} K")
    ax.legend(loc="upper left")
    fig.tight_layout()
    fig.savefig(out / "dna_force_extension.png", dpi=100)
    checks.finish()


if __name__ == "__main__":
    main()
