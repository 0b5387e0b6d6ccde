"""Magnetic tweezers on DNA (issue 17, SPEC §9.1): a 300 bp duplex held on
a surface at one end and by a bead at the other, pulled by the bead with
F = 12 pN along its axis and overwound by turning the bead, at zero
temperature (nm, pN, ns). The torque rises linearly with the turns
(slope C_eff / L), the duplex lengthens as it overwinds (DNA's
twist–stretch coupling g < 0), and at M_c it buckles: the extension
falls.

References: a straight elastic rod under tension buckles at M_c = 2√(BF);
clamped at both ends with a finite length L its threshold is a little
higher (``strandkit.polymer.buckling_torque``, +0.8 % at L√(F/B) = 24
here), with B = 50 nm kT the duplex's calibrated bending stiffness. The
bead turns fast to 80 % of the turns that torque needs and then slowly (a
slow passage keeps the buckling mode in step with the torque); the
elastic torque (``TwistResult.elastic_torque``: the bead's and the
surface's differ by the rotation's drag) is read at the extension's
peak. A lateral force of 1 % of F at the middle pair
stands for a real set-up's imperfections. The bonds are unbreakable here
(the elastic duplex). After the buckling the loop passes through itself
and the extension comes back: without self-contact there is no
plectoneme (contact is issue 15's; examples/plectoneme.py has it for a
plain rod).

Checks: the torque's slope within 3 % of (C − g²/S)/L from the
calibration, the extension growing with the overwinding as −g/S (10 %),
and the
buckling torque within 5 % of 2√(BF) and 2 % of the finite-length
threshold (measured: slope +1.7 %, lengthening +2.0 %, buckling +1.6 %
and +0.8 %).
Saves dna_twist.png (torque and extension against turns) and the run's
trajectory dna_twist.pdb/.psf/.dcd with its records in dna_twist.csv.
About two minutes.

    python examples/dna_twist.py [--out DIR]    # default: $STRANDKIT_OUT, else ./out
"""
import math
import time

import numpy as np

import strandkit as sk
from _common import Checks, output_dir
from strandkit.dna import experiments as ex
from strandkit.polymer import buckling_torque

N_BP = 300
FORCE = 12.0  # pN


def main():
    out = output_dir(__doc__)
    checks = Checks()
    t0 = time.perf_counter()
    d = sk.dna.duplex(("GATTACA" * 50)[:N_BP], break_forces=[math.inf] * N_BP)
    m = d.measured
    b_ = m["bending_stiffness"]
    free = (N_BP - 3) * d.params["rise"]  # between the held pairs' inner ends
    c_eff = m["twist_stiffness"] - m["twist_stretch"] ** 2 / m["stretch_modulus"]
    long_rod = 2 * math.sqrt(b_ * FORCE)
    finite = buckling_torque(b_, FORCE, free)
    expected = finite * free / c_eff / (2 * math.pi)  # turns to reach it
    r = ex.magnetic_tweezers(d, force=FORCE, turns=1.15 * expected, wait=5.0, dt=0.05, viscosity=0.01,
                             turns_per_ns=lambda turns: 0.02 if turns < 0.8 * expected else 0.004,
                             record_every=10, out=str(out / "dna_twist"), frame_every=200)
    b = ex.buckling(r)
    print(f"{N_BP} bp at {FORCE} pN: {time.perf_counter() - t0:.0f} s; free length {free:.2f} nm, "
          f"L√(F/B) = {free * math.sqrt(FORCE / b_):.1f}")

    torque = r.elastic_torque
    theta = 2 * math.pi * r.turns
    early = (r.turns > 0.1 * expected) & (r.turns < 0.7 * expected)
    slope, _ = np.polyfit(theta[early], torque[early], 1)
    rise, _ = np.polyfit(theta[early], r.extension[early], 1)
    checks.close("torque slope (pN·nm/rad) vs (C − g²/S)/L", slope, c_eff / free, rtol=0.03)
    checks.close("overwinding lengthens the duplex (nm/rad) vs −g/S", rise, -m["twist_stretch"] / m["stretch_modulus"],
                 rtol=0.10)
    if b is None:
        checks.true("buckled", False, "the extension never fell")
    else:
        print(f"buckles at {b['turns']:.3f} turns, torque {b['torque']:.2f} pN·nm (bead {b['bead_torque']:.2f}); "
              f"2√(BF) = {long_rod:.2f}, clamped L = {free:.1f} nm: {finite:.2f}")
        checks.close("buckling torque (pN·nm) vs 2√(BF)", b["torque"], long_rod, rtol=0.05)
        checks.close("buckling torque (pN·nm) vs the clamped finite rod", b["torque"], finite, rtol=0.02)

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.2))
    ax1.plot(r.turns, r.torque, lw=0.8, color="0.6", label="on the bead")
    ax1.plot(r.turns, torque, lw=1.2, label="elastic (averaged along the duplex)")
    ax1.axhline(long_rod, color="k", ls="--", lw=0.8, label=f"2√(BF) = {long_rod:.1f} pN·nm")
    ax1.axhline(finite, color="r", ls=":", lw=0.8, label=f"clamped, L = {free:.0f} nm: {finite:.1f}")
    if b is not None:
        ax1.plot([b["turns"]], [b["torque"]], "ko")
    ax1.set_xlabel("bead turns")
    ax1.set_ylabel("torque (pN·nm)")
    ax1.set_title(f"{N_BP} bp at {FORCE:g} pN, zero temperature")
    ax1.legend(loc="lower right", fontsize=8)
    ax2.plot(r.turns, r.extension, lw=1.2)
    if b is not None:
        ax2.axvline(b["turns"], color="k", ls="--", lw=0.8, label="buckling")
        ax2.legend()
    ax2.set_xlabel("bead turns")
    ax2.set_ylabel("extension (nm)")
    ax2.set_title("extension: overwinding lengthens, buckling shortens")
    fig.tight_layout()
    fig.savefig(out / "dna_twist.png", dpi=120)
    checks.finish()


if __name__ == "__main__":
    main()
