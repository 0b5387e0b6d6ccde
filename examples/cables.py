"""SPEC §9.5 cables (thesis III.C.1–2). A 6 mm cable on a car door (the
thesis' scene: 18 control points, 4 clips, a connector) settles under its
weight, then its free end is pulled out of the door (+z) harder and harder
until the clips let go one after the other. Then a harness of six cables
of 2.5–6 mm (a trunk, two breakouts, five connectors) hangs under its
weight. Checks: the connector and clips carry the cable's weight (force
balance to 1e-6); the clip nearest the pull lets go first, above its 20 N
resistance, and the rest follow; every harness branch balances its weight
with the forces its junctions and connector report (1e-6). Writes
cables.png (the door before and after the pull-out, the harness),
cables.glb and harness.glb (tube meshes).

    python examples/cables.py [--out DIR]    # default: $STRANDKIT_OUT, else ./out
"""
import numpy as np

import strandkit as sk
from _common import Checks, output_dir

G = 9.81


def curve(rod, n=400):
    u0, u1 = rod.domain
    return np.array([rod.position(u) for u in np.linspace(u0, u1, n)])


def main():
    out = output_dir(__doc__)
    checks = Checks()
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    door = sk.builders.cable_on_clips()
    print(door)
    w = sk.World(gravity=(0, -G, 0), dt=3e-3)
    ins = w.insert(door.assembly)
    rod = ins.rods[door.cable]
    w.relax()
    weight = rod.mass * G
    carried = w.group("clip").forces[:, 1].sum() + w.group("connector[0]").forces[:, 1].sum()
    checks.close("connector + clips carry the weight [N]", carried, weight, rtol=1e-6)
    before = curve(rod)
    sk.write_gltf(w, str(out / "cables.glb"))
    # Pull-out: the free end pulled along +z in 0.5 N increments.
    load = w.add_load(sk.point_force(rod, rod.u_end, (0, 0, 0)))
    released = []
    for k in range(1, 121):
        f = 0.5 * k
        w.set_load(load, sk.point_force(rod, rod.u_end, (0, 0, f)))
        while True:  # a release ends a relax: solve again at this load
            ev = [e for e in w.relax().events if e.kind == "ClipReleased"]
            released += [(ins.clips.index(e.clip), f, e.force) for e in ev]
            if not ev:
                break
        if len(released) == len(ins.clips):
            break
    after = curve(rod)
    for c, f, force in released:
        print(f"clip[{c}] released at an end pull of {f:.1f} N (its pull-out force {force:.2f} N)")
    checks.true("the clip nearest the pull lets go first, above 20 N", released and released[0][0] == 3
                and released[0][2] > 20.0, f"{released[:1]}")
    checks.true("every clip lets go in the end", sorted(c for c, _, _ in released) == [0, 1, 2, 3], f"{released}")

    harness = sk.builders.harness()
    print(harness)
    wh = sk.World(gravity=(0, -G, 0))
    hi = wh.insert(harness.assembly)
    rep = wh.relax()
    print(f"harness relaxed in {rep.iterations} iterations")
    worst = 0.0
    for k, bi in enumerate(harness.branches):
        b = hi.rods[bi]
        total = np.zeros(3)
        for links in harness.junctions:
            for main, other, pos, _ in links:
                if k in (main, other):
                    total += (1 if k == main else -1) * np.asarray(hi.constraints[pos].reaction().force)
        total += sum((wh.group(f"connector[{c}]").forces.sum(axis=0) for c, (bb, _) in
                      enumerate(harness.params["connectors"]) if bb == k), np.zeros(3))
        worst = max(worst, float(np.linalg.norm(total - [0, b.mass * G, 0]) / (b.mass * G)))
    checks.true("every branch balances its weight", worst < 1e-6, f"worst relative residual {worst:.1e}")
    sk.write_gltf(wh, str(out / "harness.glb"))

    fig, axes = plt.subplots(1, 3, figsize=(13, 4.2))
    ax = axes[0]
    ax.plot(before[:, 0], before[:, 1], color="tab:blue", lw=2)
    clips = np.array(door.params["clip_positions"])
    ax.plot(clips[:, 0], clips[:, 1], "s", color="tab:red", ms=7, label="clips")
    ax.set_title("Cable on a door, on its clips (front)", fontsize=9)
    ax.set_aspect("equal")
    ax.legend(fontsize=8)
    ax = axes[1]
    ax.plot(before[:, 0], before[:, 2], color="tab:blue", lw=2, label="clipped")
    ax.plot(after[:, 0], after[:, 2], color="tab:orange", lw=2, label=f"pulled out ({released[-1][1]:.0f} N)")
    ax.plot(clips[:, 0], clips[:, 2], "s", color="tab:red", ms=7)
    ax.set_title("Pull-out along +z (top view: x–z)", fontsize=9)
    ax.legend(fontsize=8)
    ax = axes[2]
    for k, bi in enumerate(harness.branches):
        p = curve(hi.rods[bi])
        ax.plot(p[:, 0], p[:, 1], lw=2 + 400 * harness.params["radii"][k])
    ax.set_title("Harness: 6 cables of 2.5–6 mm, 2 junctions", fontsize=9)
    ax.set_aspect("equal")
    for a in axes:
        a.set_xlabel("x [m]")
    fig.tight_layout()
    fig.savefig(out / "cables.png", dpi=100)
    plt.close(fig)
    print(f"picture: {out / 'cables.png'}; meshes {out / 'cables.glb'}, {out / 'harness.glb'}")
    checks.finish()


if __name__ == "__main__":
    main()
