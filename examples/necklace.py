"""SPEC §9.4 bead necklace (thesis III.C.5, fig. III.16): 12 glass beads
(2 g, radius 6 mm) on a 60 cm nylon loop hung over a peg, released from a
circle with the beads spread round it; they slide down, pile up at the
bottom and the loop swings into its hanging shape (3 s at the thesis'
0.8 ms step, low friction). Then the closed form of one frictionless bead
on a string (1.2 m string, supports 1 m apart, 0.1 kg). Checks: no bead is
lost and no two come closer than 2r along the string (chord ≥ 2r − 0.1 mm);
the energy falls (friction, inelastic bead contacts, implicit damping)
and never rises above an earlier low (by more than 1e-12 J); the beads end gathered below the peg; the
one-bead angle and tension within 0.5 % of 56.44° and 0.8874 N. Writes
necklace.png (side views at several times), necklace_energy.png and a
trajectory (necklace.pdb/.psf/.dcd).

    python examples/necklace.py [--out DIR]    # default: $STRANDKIT_OUT, else ./out
"""
import numpy as np

import strandkit as sk
from _common import Checks, output_dir

G = 9.81


def side_view(ax, world, string, beads, radius, title):
    """The string and the beads in the x–y plane (y up)."""
    u0, u1 = string.domain
    us = np.linspace(u0, u1, 400)
    p = np.array([string.position(u) for u in us])
    ax.plot(p[:, 0], p[:, 1], color="0.35", lw=1)
    for b in beads:
        x = b.position
        ax.add_patch(__import__("matplotlib").patches.Circle((x[0], x[1]), radius, color="tab:red", alpha=0.8))
    ax.plot([0], [0], marker="o", color="k", ms=5)
    ax.set_aspect("equal")
    ax.set_xlim(-0.2, 0.2)
    ax.set_ylim(-0.33, 0.03)
    ax.set_title(title, fontsize=9)
    ax.axis("off")


def main():
    out = output_dir(__doc__)
    checks = Checks()
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    neck = sk.builders.necklace()
    print(neck)
    r = neck.params["bead_radius"]
    dt = 8e-4
    world = sk.World(gravity=(0, -G, 0), dt=dt)
    ins = world.insert(neck.assembly)
    string, beads = ins.rods[neck.string], ins.beads
    snap_times = [0.0, 0.1, 0.2, 0.4, 3.0]
    fig, axes = plt.subplots(1, len(snap_times), figsize=(12, 3.4))
    times, energy = [], []
    min_gap, rise, e_min = np.inf, 0.0, np.inf
    steps = int(round(3.0 / dt))
    with sk.TrajectoryWriter(world, str(out / "necklace"), every=1) as tw:
        for k in range(steps + 1):
            if k:
                world.step()
            t = k * dt
            e = world.energy()["total"]
            times.append(t)
            energy.append(e)
            e_min = min(e_min, e)
            rise = max(rise, e - e_min)
            x = np.array([b.position for b in beads])
            order = np.argsort([float(repr(b).split("u=")[1].split(",")[0]) for b in beads])
            x = x[order]
            gaps = np.linalg.norm(np.roll(x, -1, axis=0) - x, axis=1)
            min_gap = min(min_gap, float(gaps.min()))
            for j, ts in enumerate(snap_times):
                if abs(t - ts) < 0.5 * dt:
                    side_view(axes[j], world, string, beads, r, f"t = {ts:g} s")
            if k % 50 == 0:
                tw.write()
        frames = tw.n_frames
    fig.suptitle("Necklace over a peg: 12 beads of 2 g sliding down a 60 cm loop", fontsize=11)
    fig.tight_layout()
    fig.savefig(out / "necklace.png", dpi=100)
    plt.close(fig)
    print(f"picture: {out / 'necklace.png'}; {frames} trajectory frames")
    checks.true("every bead still on the string", len(world.beads()) == 12, f"{len(world.beads())}")
    checks.true("no two beads closer than 2r (chord, -0.1 mm)", min_gap > 2 * r - 1e-4, f"min {min_gap * 1e3:.2f} mm")
    drop = energy[0] - energy[-1]
    print(f"energy {energy[0]:.5f} → {energy[-1]:.5f} J; largest rise above an earlier low {rise:.2e} J")
    checks.true("energy falls and never rises", drop > 0 and rise < 1e-12,
                f"drop {drop:.4f} J, rise {rise:.1e} J")
    ys = np.array([b.position[1] for b in beads])
    checks.true("beads gathered below the peg", bool((ys < -0.15).all()), f"highest bead at y = {ys.max():.3f} m")

    fig, ax = plt.subplots(figsize=(7, 3.5))
    ax.plot(times, energy)
    ax.set_xlabel("time [s]")
    ax.set_ylabel("mechanical energy [J]")
    ax.set_title("Energy of the necklace (beads included)")
    fig.tight_layout()
    fig.savefig(out / "necklace_energy.png", dpi=100)
    plt.close(fig)
    print(f"picture: {out / 'necklace_energy.png'}")

    one = sk.builders.necklace(n_beads=1, bead_mass=0.1, bead_radius=0.01, length=1.2, closed=False,
                               hang="two_points", supports=((0, 0, 0), (1, 0, 0)), friction=0.0,
                               string=dict(linear_density=1e-7, axial_stiffness=1e4, bending_stiffness=5.5e-6),
                               control_points=1001)
    w = sk.World(gravity=(0, -G, 0), relax_max_iterations=3000)
    w.insert(one.assembly)
    w.relax()
    f = w.group("support").forces
    theta = float(np.degrees(np.arctan2(abs(f[0, 0]), abs(f[0, 1]))))
    checks.close("one bead: angle from the vertical [deg]", theta, 56.44, rtol=5e-3)
    checks.close("one bead: string tension [N]", float(np.linalg.norm(f[0])), 0.8874, rtol=5e-3)
    checks.finish()


if __name__ == "__main__":
    main()
