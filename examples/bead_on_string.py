"""SPEC §9.4: a frictionless bead (m = 0.1 kg) on a light, nearly
inextensible string of length 1.2 m between supports 1 m apart at equal
height. Reference: both halves at θ = 56.44° from the vertical
(sin θ = S/L), sag 0.3317 m, tension mg / (2 cos θ) = 0.887 N. The bead
starts off-centre and finds the middle by itself. Saves bead_on_string.png
in the output directory; exits with status 1 if a check against the
reference fails.

    python examples/bead_on_string.py [--out DIR]    # default: $STRANDKIT_OUT, else ./out
"""
import numpy as np

import strandkit as sk
import strandkit.plot as skplot
from _common import Checks, output_dir
SPAN, LENGTH, MASS, G = 1.0, 1.2, 0.1, 9.81


def main():
    out = output_dir(__doc__)
    checks = Checks()
    # EA = 1e4 N; EI = 2.2e-5 N m² gives the corner under the bead a
    # boundary layer √(EI/T) ≈ 5 mm that 721 control points resolve (a
    # spline cannot form the kink of a perfectly flexible string).
    ei = 2.2e-5
    r = np.sqrt(4 * ei / 1e4)
    string = sk.Material("string", young=1e4 / (np.pi * r * r), poisson=0.3, density=1.0)
    rod = sk.straight((0, 0, 0), (LENGTH, 0, 0), section=r, material=string, n_control_points=721, with_roll=False)
    s = rod.control_points[:, 0] / LENGTH
    rod.control_points = np.column_stack([s * SPAN, -0.3 * np.sin(np.pi * s), 0 * s])
    world = sk.World(gravity=(0, -G, 0), relax_max_iterations=3000)
    rod = world.add_rod(rod)
    a = world.add_constraint(rod, sk.position(rod.u_start, (0, 0, 0)))
    b = world.add_constraint(rod, sk.position(rod.u_end, (SPAN, 0, 0)))
    u0, u1 = rod.domain
    bead = world.add_bead(rod, u0 + 0.4 * (u1 - u0), mass=MASS)
    report = world.relax()

    theta_ref = np.degrees(np.arcsin(SPAN / LENGTH))
    sag_ref = 0.5 * SPAN / np.tan(np.radians(theta_ref))
    t_ref = MASS * G / (2 * np.cos(np.radians(theta_ref)))
    fa, fb = a.reaction().force, b.reaction().force
    p = bead.position
    theta = np.degrees(np.arctan2(abs(fa[0]), abs(fa[1])))
    print(f"relaxed in {report.iterations} iterations; bead at x = {p[0]:.4f} m (middle 0.5)")
    for name, got, ref in [("θ [deg]", theta, theta_ref), ("sag [m]", -p[1], sag_ref),
                           ("tension left [N]", np.linalg.norm(fa), t_ref),
                           ("tension right [N]", np.linalg.norm(fb), t_ref)]:
        print(f"{name:>18}: {got:.4f}   reference {ref:.4f}   ({100 * (got / ref - 1):+.2f} %)")
        # The string's bending layer under the bead and its stretch: ≤ 0.6 % here.
        checks.close(name, got, ref, rtol=1e-2)
    checks.close("bead x [m] (the middle)", p[0], 0.5 * SPAN, atol=1e-3)
    path = out / "bead_on_string.png"
    ring = p + 0.012 * np.array([[np.cos(t), np.sin(t), 0] for t in np.linspace(0, 2 * np.pi, 40)])
    skplot.plot_world(world, str(path), view="xy", size=(800, 600), min_radius=0.004,
                      title="Bead on a string (bead outlined in black)",
                      overlay=[(ring, dict(color="k", lw=2))])
    print(f"picture: {path}")
    checks.finish()


if __name__ == "__main__":
    main()
