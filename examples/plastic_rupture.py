"""Thesis II.D.1.f: plasticity and rupture (SPEC §6).

1. A copper wire (1 m, R = 1 mm) clamped at one end is bent into a hook by
   turning its end tangent through 3π/2, then released: it keeps the
   plastic curvature beyond its yield curvature (perfect plasticity,
   algorithm 1) and springs back by the elastic part only.
2. A nylon strand with a thin spot is pulled until its stretch passes the
   rupture strain: it splits at the most strained sample into two rods
   (knot of multiplicity 4, algorithms 2–3) and the pieces fly apart.

Prints the figures and saves plastic_rupture.png in the output directory;
exits with status 1 if a check fails.

    python examples/plastic_rupture.py [--out DIR]    # default: $STRANDKIT_OUT, else ./out
"""
import numpy as np

import strandkit as sk
import strandkit.plot as skplot
from _common import Checks, output_dir


def hook(checks):
    # Copper: E = 124 GPa; yield strain ≈ 0.05 % → yield curvature ε_y / R = 0.5 1/m.
    copper = sk.Material.preset("copper").with_yield(bend=0.5, stretch=5e-4)
    # EA/EI = 4/R² = 4e6 m⁻²: Newton increments bottom out near 1e-9 m.
    world = sk.World(parallel=False, relax_tolerance=1e-8)
    rod = world.add_rod(sk.straight((0, 0, 0), (1, 0, 0), section=1e-3, material=copper,
                                    n_control_points=24, with_roll=False))
    sk.clamp(world, rod)
    # The wire lies on a frictionless table (z = 0 at its end): a rod
    # without roll coordinate could otherwise spin about its clamp.
    world.add_constraint(rod, sk.plane(rod.u_end, (0, 0, 0), (0, 0, 1)))
    end = world.add_constraint(rod, sk.tangent(rod.u_end, (1, 0, 0)))
    phi = 1.5 * np.pi
    for a in np.linspace(0, phi, 31)[1:]:
        world.set_constraint(end, sk.tangent(rod.u_end, (np.cos(a), np.sin(a), 0)))
        world.relax()
    loaded = rod.copy()
    world.remove_constraint(end)
    world.relax()
    kappa_p = rod.plastic_offsets[:, 2].mean()
    kappa = rod.strains()[:, 2].mean()
    t = rod.tangent(rod.u_end)
    turned = np.degrees(np.arctan2(t[1], t[0]) % (2 * np.pi))
    print(f"hook: imposed curvature {phi:.4f} 1/m, yield 0.5 1/m -> plastic offset {kappa_p:.4f} 1/m "
          f"(expected {phi - 0.5:.4f}); after release curvature {kappa:.4f} 1/m, "
          f"end tangent at {turned:.1f} deg (270 deg loaded)")
    # Perfect plasticity: the offset is the imposed curvature beyond yield,
    # and the released wire keeps it (springs back by the elastic 0.5 1/m).
    checks.close("hook plastic curvature [1/m]", kappa_p, phi - 0.5, rtol=5e-3)
    checks.close("hook curvature after release [1/m]", kappa, kappa_p, rtol=5e-3)
    return loaded, rod


def rupture(checks):
    nylon = sk.Material.preset("nylon").with_rupture(stretch=0.05)
    world = sk.World(parallel=False)
    radii = [2e-3 if i != 14 else 1.6e-3 for i in range(24)]
    rod = world.add_rod(sk.straight((0, 0.6, 0), (1, 0.6, 0), sections=[sk.Section.circle(r) for r in radii],
                                    material=nylon, n_control_points=24, with_roll=False, drag=5.0))
    sk.clamp(world, rod)
    end = world.add_constraint(rod, sk.position(rod.u_end, (1, 0.6, 0)))
    event = None
    for k in range(1, 2000):
        world.set_constraint(end, sk.position(rod.u_end, (1 + 2e-4 * k, 0.6, 0)))
        hits = [e for e in world.step().events if e.kind == "RodRuptured"]
        if hits:
            event = hits[0]
            break
    if not checks.true("the strand breaks", event is not None, "RodRuptured" if event else "no RodRuptured event in 2000 steps"):
        return [rod]
    x = rod.position(event.u)[0]
    print(f"rupture: at t = {event.time * 1e3:.1f} ms, x = {x:.4f} m (thin spot at control point 14), "
          f"stretch {event.strain:.5f} > {event.limit}; pieces on u in {rod.domain} and {event.new_rod.domain}")
    for _ in range(100):
        world.step()
    gap = np.linalg.norm(event.new_rod.position(event.u) - rod.position(event.u))
    print(f"rupture: 0.1 s later the ends are {gap * 1e3:.1f} mm apart")
    # The thin spot is control point 14 of a clamped cubic: its Greville
    # abscissa is u = 13 (segments of unit length); the cut is within a segment.
    checks.close("rupture abscissa u (thin spot)", event.u, 13.0, atol=1.0)
    checks.true("rupture strain beyond the limit", event.strain >= event.limit, f"{event.strain} >= {event.limit}")
    checks.true("the pieces separate", gap > 5e-3, f"{gap * 1e3:.1f} mm after 0.1 s")
    return [rod, event.new_rod]


def main():
    out = output_dir(__doc__)
    checks = Checks()
    loaded, released = hook(checks)
    pieces = rupture(checks)
    skplot.plot_world([released] + pieces, str(out / "plastic_rupture.png"), view="xy",
                      overlay=[(loaded.sample_points(), {"color": "0.6", "linestyle": "--"})],
                      title="plastic hook (dashed: loaded) and a broken strand")
    print(f"saved {out / 'plastic_rupture.png'}")
    checks.finish()


if __name__ == "__main__":
    main()
