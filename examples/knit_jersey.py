"""SPEC §9.3 knitted fabric: a 10 × 10 plain jersey swatch of 0.1 mm-radius
nylon monofilament, loop length 5 mm, one continuous yarn held together
only by yarn–yarn contact, relaxed by an overdamped gradient flow, then
stretched along the wale between two bars and released.

Checks (what this short run can show; the Munden and Poincloux references
need far longer relaxations of larger swatches, see the README): the
elastic energy only falls during the relaxation; no yarn enters another by
more than a quarter of its diameter (clearance > 0.75) at any record;
every loop is still through the one below (its tied edges hold); the
stretched fabric pulls the bars back, and no yarn enters another while
stretched. The stretch is short (150 steps per increment): the yarn has
not finished sliding through the loops when the force is read, so the
force is far above the equilibrium one and the width barely changes (it
is printed, not checked) — a picture of the workflow, not a force–strain
measurement. Writes knit_jersey.png (the swatch relaxed and stretched), knit_jersey.glb and
knit_jersey.vtk (tube meshes of the relaxed swatch, for ParaView or a glTF
viewer) and knit_jersey_stretch.png (force and lateral strain against
strain).

    python examples/knit_jersey.py [--out DIR]    # default: $STRANDKIT_OUT, else ./out
"""
import numpy as np

import strandkit as sk
from _common import Checks, output_dir
from strandkit.knit import experiments as ex
from strandkit.knit.plots import draw_front


def main():
    out = output_dir(__doc__)
    checks = Checks()
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fabric = sk.knit.fabric("jersey", wales=10, courses=10, loop_length=5e-3, yarn="nylon", yarn_radius=1e-4)
    print(fabric)
    print("built:", fabric.dimensions(fabric.world()))
    relaxed = ex.relax(fabric, friction=0.0, max_steps=300, record_every=10)
    print(relaxed)
    e = relaxed.history["energy"]
    checks.true("elastic energy only falls", bool(np.all(np.diff(e) <= 1e-12 * e[0])),
                f"{e[0]:.4e} → {e[-1]:.4e} J over {relaxed.steps} steps")
    checks.true("no yarn inside another (clearance > 0.75)", relaxed.clearance > 0.75, f"{relaxed.clearance:.3f}")
    checks.true("every loop still through the one below", relaxed.interlocks.parted == [], f"{relaxed.interlocks}")
    print("curl [m]:", relaxed.curl)
    sk.write_gltf(relaxed.world, str(out / "knit_jersey.glb"))
    sk.write_vtk(relaxed.world, str(out / "knit_jersey.vtk"))

    fig, axes = plt.subplots(1, 2, figsize=(12, 6))
    draw_front(axes[0], relaxed.world, fabric, title=f"relaxed ({relaxed.steps} steps): k_c = {relaxed.dimensions['k_c']:.2f}, "
                                         f"k_w = {relaxed.dimensions['k_w']:.2f}")
    s = ex.stretch(relaxed, direction="wale", strain=0.1, increments=2, settle_steps=100, steps_per_increment=150)
    print(s)
    top = int(np.argmax(s.strain))
    checks.true("the stretched fabric pulls the bars back", s.force[top] > 0, f"{s.force[top]:.4g} N at strain {s.strain[top]:.2f}")
    print(f"lateral strain at strain {s.strain[top]:.2f}: {s.lateral_strain[top]:.4f}")
    checks.true("no yarn inside another while stretched (clearance > 0.75)", s.clearance > 0.75, f"{s.clearance:.3f}")
    draw_front(axes[1], s.world, fabric, title="back to zero strain after the stretch")
    fig.tight_layout()
    fig.savefig(out / "knit_jersey.png", dpi=110)

    fig, ax = plt.subplots(1, 2, figsize=(10, 4))
    ld = s.loading
    ax[0].plot(s.strain[ld], s.force[ld], "o-", label="loading")
    ax[0].plot(s.strain[~ld | (np.arange(len(ld)) == top)], s.force[~ld | (np.arange(len(ld)) == top)], "s--", label="unloading")
    ax[0].set_xlabel("grip strain")
    ax[0].set_ylabel("force on the top bar [N]")
    ax[0].legend()
    ax[1].plot(s.strain, s.lateral_strain, "o-")
    ax[1].set_xlabel("grip strain")
    ax[1].set_ylabel("lateral strain at mid-length")
    fig.tight_layout()
    fig.savefig(out / "knit_jersey_stretch.png", dpi=110)
    checks.finish()


if __name__ == "__main__":
    main()
