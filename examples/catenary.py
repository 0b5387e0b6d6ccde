"""SPEC §10 catenary (annex E): a 1.2 m rope of 1 N/m hung between supports
1 m apart. Reference y = a cosh(x/a): a = 0.4695 m, sag 0.2923 m,
H = 0.4695 N, T_max = 0.762 N. Saves catenary.png in the output directory;
exits with status 1 if a check against the reference fails.

    python examples/catenary.py [--out DIR]    # default: $STRANDKIT_OUT, else ./out
"""
import numpy as np

import strandkit as sk
import strandkit.plot as skplot
from _common import Checks, output_dir
SPAN, LENGTH, WEIGHT = 1.0, 1.2, 1.0


def catenary_parameter():
    """a with 2 a sinh(S / 2a) = L (bisection)."""
    lo, hi = 0.05, 10.0
    for _ in range(200):
        a = 0.5 * (lo + hi)
        lo, hi = (a, hi) if 2 * a * np.sinh(SPAN / (2 * a)) > LENGTH else (lo, a)
    return 0.5 * (lo + hi)


def main():
    out = output_dir(__doc__)
    checks = Checks()
    # A nearly inextensible (EA = 1e4 N), nearly perfectly flexible rope.
    r = 2e-5
    rope = sk.Material("rope", young=1e4 / (np.pi * r * r), poisson=0.3, density=1000.0)
    rod = sk.straight((0, 0, 0), (LENGTH, 0, 0), section=r, material=rope, n_control_points=30, with_roll=False)
    s = rod.control_points[:, 0] / LENGTH
    rod.control_points = np.column_stack([s * SPAN, -0.3 * np.sin(np.pi * s), 0 * s])  # start sagging
    world = sk.World()
    rod = world.add_rod(rod)
    left = world.add_constraint(rod, sk.position(rod.u_start, (0, 0, 0)))
    right = world.add_constraint(rod, sk.position(rod.u_end, (SPAN, 0, 0)))
    world.add_load(sk.distributed(rod, (0, -WEIGHT, 0)))
    report = world.relax()

    a = catenary_parameter()
    sag_ref = a * (np.cosh(SPAN / (2 * a)) - 1)
    pts = rod.sample_points()
    sag = -min(pts[:, 1].min(), rod.position(0.5 * sum(rod.domain))[1])
    fl, fr = left.reaction().force, right.reaction().force
    h, tmax = abs(fr[0]), max(np.linalg.norm(fl), np.linalg.norm(fr))
    tmax_ref = WEIGHT * a * np.cosh(SPAN / (2 * a))
    print(f"relaxed in {report.iterations} iterations")
    for name, got, ref in [("a = H/w [m]", h / WEIGHT, a), ("sag [m]", sag, sag_ref), ("H [N]", h, WEIGHT * a),
                           ("T_max [N]", tmax, tmax_ref), ("vertical reactions [N]", fl[1] + fr[1], WEIGHT * LENGTH)]:
        print(f"{name:>24}: {got:.5f}   reference {ref:.5f}   ({100 * (got / ref - 1):+.3f} %)")
        # The rope stretches (EA = 1e4 N) and bends a little: 0.02 % here.
        checks.close(name, got, ref, rtol=1e-3)
    x = np.linspace(0, SPAN, 200)
    ref_curve = np.column_stack([x, a * (np.cosh((x - SPAN / 2) / a) - np.cosh(SPAN / (2 * a))), 0 * x])
    path = out / "catenary.png"
    skplot.plot_world(world, str(path), view="xy", size=(900, 600), min_radius=0.008,
                      title="Catenary: rod (tube) and y = a cosh(x/a) (dashed)",
                      overlay=[(ref_curve, dict(ls="--", color="k", lw=1))])
    print(f"picture: {path}")
    checks.finish()


if __name__ == "__main__":
    main()
