"""A rod through a sliding point (III.37–III.42): a pre-tensioned nylon rod
pinned at both ends passes through a frictionless ring that is dragged off
the line between the pins (a moving target, then relax). A frictionless
ring transmits the axial force unchanged: equal tension on both sides, no
tangential ring force, and the three forces balance. Saves sliding_points.png
in the output directory; exits with status 1 if a check fails.

    python examples/sliding_points.py [--out DIR]    # default: $STRANDKIT_OUT, else ./out
"""
import numpy as np

import strandkit as sk
import strandkit.plot as skplot
from _common import Checks, output_dir


def main():
    out = output_dir(__doc__)
    checks = Checks()
    world = sk.World()
    # r = 3 cm: its bending boundary layer √(EI/T) ≈ 0.1 m is resolved by 60 control points.
    rod = world.add_rod(sk.straight((-1, 0, 0), (1, 0, 0), section=0.03, material="nylon", n_control_points=60,
                                    with_roll=False))
    a = world.add_constraint(rod, sk.position(rod.u_start, (-1, 0, 0)))
    b = world.add_constraint(rod, sk.position(rod.u_end, (1, 0, 0)))
    u0, u1 = rod.domain
    ring_target = np.array([0.3, -0.2, 0.0])
    ring = world.add_constraint(rod, sk.sliding_point(u0 + 0.65 * (u1 - u0), (0.3, 0.0, 0.0)))
    for k in range(1, 11):  # drag the ring down gradually
        u = ring.kind["SlidingPoint"]["u"]
        world.set_constraint(ring, sk.sliding_point(u, ring_target * [1, k / 10, 1]))
        world.relax()
    u = ring.kind["SlidingPoint"]["u"]
    fa, fb, fr = a.reaction().force, b.reaction().force, ring.reaction().force
    t, p = rod.tangent(u), rod.position(u)
    # Axial force EA ε at the samples 0.15 m either side of the ring.
    ea = rod.material.young * rod.sections[0].area
    xs = rod.position(rod.sample_params())[:, 0]
    eps = rod.strains()[:, 0]
    nl, nr = (ea * eps[np.argmin(np.abs(xs - x))] for x in (p[0] - 0.15, p[0] + 0.15))
    print(f"rod passes through the ring: |r(u) - ring| = {np.linalg.norm(p - ring_target):.2e} m at u = {u:.4f}")
    print(f"axial force left {nl:.3f} N, right {nr:.3f} N (equal: {100 * (nr / nl - 1):+.3f} %)")
    print(f"ring force {np.round(fr, 3)} N, tangential part {fr @ t:.2e} N (reference 0)")
    print(f"balance |F_a + F_b + F_ring| = {np.linalg.norm(fa + fb + fr):.2e} N")
    scale = np.linalg.norm(fr)
    checks.close("rod through the ring |r(u) - ring| [m]", np.linalg.norm(p - ring_target), 0.0, atol=1e-9)
    # Equal up to the bending boundary layer at the ring (0.02 % here).
    checks.close("axial force right / left", nr / nl, 1.0, rtol=1e-3)
    checks.close("tangential ring force [N]", fr @ t, 0.0, atol=1e-9 * scale)
    checks.close("force balance [N]", np.linalg.norm(fa + fb + fr), 0.0, atol=1e-9 * scale)
    path = out / "sliding_points.png"
    skplot.plot_world(world, str(path), view="xy", size=(900, 450), title="Rod through a frictionless ring (circle)",
                      overlay=[(ring_target[None, :], dict(ls="none", marker="o", ms=14, mfc="none", mec="k", mew=2))])
    print(f"picture: {path}")
    checks.finish()


if __name__ == "__main__":
    main()
