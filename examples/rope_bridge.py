"""SPEC §9.2 rope bridge (thesis III.C.4): the default 10 m footbridge (12
planks of 4 kg, floor ropes sagging 1 m, handrails 1 m above) relaxed under
gravity, then crossed by an 80 kg walker at 1.5 m/s. Checks: the anchors
carry the whole weight (ropes + planks) to 1e-6; the floor sags within 5 %
of its design shape under the planks alone; every plank pin force at rest
is ≈ half a plank's weight plus what the ropes press in; the walk runs
without a refused step; standing on a plank, the walker and the plank hang
from its two pins ((M + m) g / 2 each, within 5 %); the floor dips most off
centre (a cable's antisymmetric mode is the soft one), alike on both halves
(10 %). Writes rope_bridge.png (the relaxed bridge), rope_bridge_walk.png
(deflection and pin forces along the walk) and a trajectory
(rope_bridge.pdb/.psf/.dcd, read by VMD and mdtraj).

    python examples/rope_bridge.py [--out DIR]    # default: $STRANDKIT_OUT, else ./out
"""
import numpy as np

import strandkit as sk
import strandkit.plot as skplot
from _common import Checks, output_dir

G = 9.81


def main():
    out = output_dir(__doc__)
    checks = Checks()
    bridge = sk.builders.rope_bridge()
    print(bridge)
    world = sk.World(gravity=(0, -G, 0), relax_max_iterations=500)
    ins = world.insert(bridge.assembly)
    rep = world.relax()
    rods = world.rods()
    print(f"relaxed in {rep.iterations} iterations: {sum(r.n_control_points for r in rods)} control points, "
          f"{rep.n_unknowns} unknowns, bandwidth {rep.bandwidth}")
    weight = sum(r.mass for r in rods) * G
    anchors = world.group("anchor").forces
    checks.close("anchors carry the weight [N]", float(anchors[:, 1].sum()), weight, rtol=1e-6)
    floor = ins.rods[bridge.ropes[0]]
    u0, u1 = floor.domain
    mid = floor.position(0.5 * (u0 + u1))
    checks.close("floor mid-span sag [m]", -float(mid[1]), bridge.params["sag"], rtol=0.05)
    pins = np.linalg.norm(world.group("plank").forces, axis=1)
    print(f"plank pin forces at rest: {pins.min():.1f} … {pins.max():.1f} N (half a plank: {0.5 * 4.0 * G:.1f} N)")
    checks.true("pin forces at rest", bool((pins > 0.4 * 4.0 * G).all() and (pins < 10 * 4.0 * G).all()),
                f"{pins.min():.1f} … {pins.max():.1f} N")
    path = out / "rope_bridge.png"
    # The verticals are constraints, not rods: draw them as lines.
    verticals = []
    for k in (0, 1):
        f, r = ins.rods[bridge.ropes[k]], ins.rods[bridge.ropes[2 + k]]
        for u in bridge.stations:
            verticals.append((np.array([f.position(u), r.position(u)]), dict(color="0.3", lw=1.5)))
    skplot.plot_world(world, str(path), view="iso", elev=15, azim=-40, size=(1000, 600), min_radius=0.004,
                      vertical_axis="y", overlay=verticals,
                      title="Rope bridge: 10 m, 12 planks, relaxed under gravity")
    print(f"picture: {path}")

    with sk.TrajectoryWriter(world, str(out / "rope_bridge"), every=25) as tw:
        walk = sk.builders.walk_across(world, bridge, ins, mass=80.0, speed=1.5, dt=4e-3,
                                       callback=lambda k, w: tw.write() if k % 25 == 0 else None)
        frames = tw.n_frames
    checks.true("the walk ran to the end", walk["stopped"] is None, repr(walk["stopped"]))
    x, d = walk["walker_x"], walk["deflection"]
    worst = int(np.argmin(d))
    print(f"walk: {len(x)} samples, deepest {d[worst]:.3f} m at x = {x[worst]:.2f} m; "
          f"largest pin force {walk['max_pin_force'].max():.0f} N; {frames} trajectory frames")
    # Standing on a plank, the walker and the plank hang from its two pins.
    checks.close("largest pin force [N] vs (M + m) g / 2", float(walk["max_pin_force"].max()), (80.0 + 4.0) * G / 2,
                 rtol=0.05)
    # A cable under a moving point load dips most off-centre (its
    # antisymmetric mode is the soft one), symmetrically on both halves.
    half = x < 5.0
    checks.close("deepest dip, first half vs second half [m]", float(d[half].min()), float(d[~half].min()), rtol=0.1)
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(2, 1, figsize=(8, 6), sharex=True)
    ax[0].plot(x, 100 * d)
    ax[0].set_ylabel("floor under walker vs design [cm]")
    ax[1].plot(x, walk["max_pin_force"])
    ax[1].set_ylabel("largest plank pin force [N]")
    ax[1].set_xlabel("walker position [m]")
    fig.suptitle("80 kg walker crossing at 1.5 m/s")
    fig.tight_layout()
    fig.savefig(out / "rope_bridge_walk.png", dpi=100)
    print(f"picture: {out / 'rope_bridge_walk.png'}")
    checks.finish()


if __name__ == "__main__":
    main()
