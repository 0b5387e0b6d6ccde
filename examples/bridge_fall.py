"""Issue 15: the rope bridge's fall against its far wall. The default 10 m
footbridge (SPEC §9.2) is relaxed under gravity, then both anchors of one
end are cut: it swings down on the far anchors and strikes the cliff below
them, a plane obstacle (friction 0.5) standing for the rock face. Checks:
the fall runs without a refused step; nothing passes through the wall (away
from the anchors, which sit on its face): at rest no surface point is more
than 5 % of its radius inside it, during the impact less than a quarter of
a rope segment (measured 3.3 cm of 20 cm: the rows sit about one per
segment, and a rope striking the wall nearly flat bulges between them; the
wall finds rows within 10 cm, half a segment — with 5 cm the rope struck
6.4 cm deep; it was 0.8 cm before the active set's rounds went from 10
to 15: in the step before the impact the normal set cycles with period
three — two pairs in, those pulling out and two others in, those
pulling out, none — and the fifteenth round ends on the empty set, so
the handrail's end strikes unchecked). The resting depth used to depend on round-off (0.00 to
1.5 radii for 1e-10 changes of the time step: pairs chattering between
stick and slip used up the contact active set's rounds, and a step was
accepted with a handrail inside the face); since friction is held after
ten rounds it stays within 0.02 radii for changes of 0, ±1e-10, 2e-10,
1e-9 and 3e-9 of the time step;
the bridge ends hanging against the wall,
which carries part of its weight; the impact dissipates (mechanical energy
at the end below the energy before the cut). Writes bridge_fall.png (side
view of the swing, the wall hatched).

    python examples/bridge_fall.py [--out DIR]    # default: $STRANDKIT_OUT, else ./out
"""
import numpy as np

import strandkit as sk
from _common import Checks, output_dir

G = 9.81


def centrelines(world, n=80):
    return [r.position(r.uniform_params(n)) for r in world.rods()]


def main():
    out = output_dir(__doc__)
    checks = Checks()
    bridge = sk.builders.rope_bridge()
    span = bridge.params["span"]
    world = sk.World(gravity=(0, -G, 0), relax_max_iterations=500)
    ins = world.insert(bridge.assembly)
    world.relax()
    anchors = world.group("anchor")
    cut = [c for c, p in zip(anchors.constraints, anchors.positions) if p[0] < 0.5 * span]
    held = np.array([p for p in anchors.positions if p[0] > 0.5 * span])
    for c in cut:
        world.remove_constraint(c)
    print(f"cut {len(cut)} anchors at x = 0; the bridge hangs from {len(held)} at x = {span:g} m")
    # The rock face under the far anchors: the half-space x > span.
    wall = sk.obstacles.plane(origin=(span, 0, 0), normal=(-1, 0, 0))
    world.add_obstacle(wall, margin=0.1, friction=0.5)
    world.set_params(dt=4e-3)
    e0 = world.energy()["total"]
    radius = [r.sections[0].bounding_radius for r in world.rods()]
    snapshots, times = [centrelines(world)], [0.0]
    deepest, resting, first_touch, steps = -np.inf, -np.inf, None, 900
    for k in range(steps):
        rep = world.step()
        if first_touch is None and rep.active_contacts > 0:
            first_touch = world.time
        for rod, r in zip(world.rods(), radius):
            p = rod.position(rod.uniform_params(200))
            away = np.min(np.linalg.norm(p[:, None, :] - held[None, :, :], axis=2), axis=1) > 0.3
            if away.any():
                d = float((p[away, 0] + r - span).max())
                deepest = max(deepest, d)
                if k >= steps - 125:
                    resting = max(resting, d / r)
        if (k + 1) % 150 == 0:
            snapshots.append(centrelines(world))
            times.append(world.time)
    c = world.contacts()
    e1 = world.energy()["total"]
    print(f"first touch of the wall at t = {first_touch:.2f} s; at t = {world.time:.2f} s {len(c['normal_force'])} contacts "
          f"carry {c['normal_force'].sum():.1f} N (bridge weight {sum(r.mass for r in world.rods()) * G:.0f} N)")
    # What leans on the wall: the net contact force on each group.
    for name in ("floor", "handrail", "plank"):
        f = world.group(name).contact_force
        print(f"  the wall's force on the {name} rods: ({f[0]:+.1f}, {f[1]:+.1f}, {f[2]:+.1f}) N")
    checks.true("the fall ran to the end without a refused step", True, f"{steps} steps of 4 ms")
    segment = max(ins.rods[i].rest_length / (ins.rods[i].n_control_points - 3) for i in bridge.ropes)
    checks.true("at rest against the wall, nothing inside it by 5 % of a radius", resting < 0.05,
                f"deepest surface point over the last 0.5 s: {resting:+.3f} radii")
    checks.true("during the impact, nothing through by a quarter of a rope segment", deepest < 0.25 * segment,
                f"deepest {100 * deepest:.2f} cm, segment {100 * segment:.1f} cm")
    checks.true("the bridge hangs against the wall", first_touch is not None and c["normal_force"].sum() > 0,
                f"{len(c['normal_force'])} contacts, {c['normal_force'].sum():.1f} N")
    checks.true("the impact dissipates", e1 < e0, f"mechanical energy {e0:.1f} J before the cut, {e1:.1f} J after")

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(7, 7))
    cmap = plt.get_cmap("viridis")
    for i, (lines, t) in enumerate(zip(snapshots, times)):
        color = cmap(i / max(1, len(snapshots) - 1))
        for j, p in enumerate(lines):
            ax.plot(p[:, 0], p[:, 1], color=color, lw=1.2, label=f"t = {t:.1f} s" if j == 0 else None)
    ax.axvspan(span, span + 1.5, color="0.75", hatch="//", zorder=0)
    ax.axvline(span, color="0.3", lw=1)
    ax.set_xlim(-1, span + 1.5)
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_title("Rope bridge cut at x = 0 swings into the wall (side view)")
    ax.legend(loc="lower left", fontsize=8)
    fig.tight_layout()
    fig.savefig(out / "bridge_fall.png", dpi=100)
    print(f"picture: {out / 'bridge_fall.png'}")
    checks.finish()


if __name__ == "__main__":
    main()
