"""SPEC §9.4 particles on a spring (thesis fig. III.17): a 4-turn steel
spring (coil radius 30 mm, pitch 20 mm, wire 1 mm) hangs from a clamp;
four 10 g beads threaded near the top slide down the coils, stretch the
spring as they go and leave it at its free end; the spring then springs
back (3.5 s at 1 ms). Checks: the beads leave in order; while they ride
down the spring's end drops by more than half the static stretch their
weight would give at the end (Castigliano, computed here on the exact
helix); after they leave, the end returns to its unloaded equilibrium
within 1 % of that stretch. Writes spring.png (side views), spring_end.png
(height of the free end against time), a trajectory (spring.pdb/.psf/.dcd)
and the last frame's tube mesh (spring.glb).

    python examples/spring.py [--out DIR]    # default: $STRANDKIT_OUT, else ./out
"""
import numpy as np

import strandkit as sk
from _common import Checks, output_dir

G = 9.81


def castigliano(p, n=4000):
    """Vertical compliance (m/N) of the helix's end under a vertical end
    force: (1/F²) ∫ |M⊥|²/EI + (M·t)²/GJ ds, M = (r(ℓ) − r(s)) × F."""
    R, c, r, E, nu = p["coil_radius"], p["pitch"] / (2 * np.pi), p["wire_radius"], p["young_modulus"], p["poisson_ratio"]
    rho = np.hypot(R, c)
    length = p["turns"] * 2 * np.pi * rho
    s = np.linspace(0.0, length, n + 1)
    phi = -s / rho
    x = np.stack([R * np.sin(phi), c * phi, R * np.cos(phi)], axis=1)
    t = np.stack([-R * np.cos(phi), -c * np.ones_like(phi), R * np.sin(phi)], axis=1) / rho
    m = np.cross(x[-1] - x, np.array([0.0, -1.0, 0.0]))
    mt = np.sum(m * t, axis=1)
    ei, gj = E * np.pi * r**4 / 4, E / (2 * (1 + nu)) * np.pi * r**4 / 2
    return float(np.trapezoid((np.sum(m * m, axis=1) - mt**2) / ei + mt**2 / gj, s))


def view(ax, rod, world, title):
    u0, u1 = rod.domain
    p = np.array([rod.position(u) for u in np.linspace(u0, u1, 600)])
    ax.plot(p[:, 0], p[:, 1], color="0.3", lw=1)
    for b in world.beads():
        ax.plot(*b.position[:2], "o", color="tab:red", ms=7)
    ax.set_aspect("equal")
    ax.set_xlim(-0.09, 0.09)
    ax.set_ylim(-0.2, 0.01)
    ax.set_title(title, fontsize=9)
    ax.axis("off")


def main():
    out = output_dir(__doc__)
    checks = Checks()
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    spring = sk.builders.beads_on_spring()
    print(spring)
    p = spring.params
    unloaded = sk.World(gravity=(0, -G, 0))
    i0 = unloaded.insert(sk.builders.beads_on_spring(n_beads=0).assembly)
    unloaded.relax()
    rest_end = unloaded.rods()[0].position(unloaded.rods()[0].u_end)
    static = castigliano(p) * p["n_beads"] * p["bead_mass"] * G
    dt = 1e-3
    world = sk.World(gravity=(0, -G, 0), dt=dt)
    ins = world.insert(spring.assembly)
    rod = ins.rods[spring.spring]
    snaps = [0.0, 0.8, 1.4, 1.65, 3.5]
    fig, axes = plt.subplots(1, len(snaps), figsize=(12, 4.2))
    times, heights, left = [], [], []
    with sk.TrajectoryWriter(world, str(out / "spring"), every=1) as tw:
        for k in range(int(round(3.5 / dt)) + 1):
            if k:
                left += [e for e in world.step().events if e.kind == "BeadLeft"]
            t = k * dt
            times.append(t)
            heights.append(rod.position(rod.u_end)[1] - rest_end[1])
            for j, ts in enumerate(snaps):
                if abs(t - ts) < 0.5 * dt:
                    view(axes[j], rod, world, f"t = {ts:g} s")
            if k % 20 == 0:
                tw.write()
    fig.suptitle("Four 10 g beads sliding down a hanging steel spring", fontsize=11)
    fig.tight_layout()
    fig.savefig(out / "spring.png", dpi=100)
    plt.close(fig)
    sk.write_gltf(world, str(out / "spring.glb"))
    print(f"pictures: {out / 'spring.png'}, {out / 'spring_end.png'}; mesh {out / 'spring.glb'}")

    fig, ax = plt.subplots(figsize=(7, 3.5))
    ax.plot(times, 1e3 * np.asarray(heights))
    ax.axhline(-1e3 * static, ls="--", color="0.5", label="static stretch, all beads at the end")
    ax.set_xlabel("time [s]")
    ax.set_ylabel("free end height − unloaded [mm]")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out / "spring_end.png", dpi=100)
    plt.close(fig)

    checks.true("beads leave in order", [e.bead for e in left] == ins.beads, f"{[e.time for e in left]}")
    drop = -min(heights)
    checks.true("the beads stretch the spring", drop > 0.5 * static, f"drop {drop * 1e3:.1f} mm, static {static * 1e3:.1f} mm")
    checks.true("the spring comes back", abs(heights[-1]) < 0.01 * static, f"{heights[-1] * 1e3:.3f} mm")
    checks.finish()


if __name__ == "__main__":
    main()
