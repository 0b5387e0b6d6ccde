"""SPEC §9.3 knit patterns: 6 × 6 swatches of jersey, 1×1 rib, 2×2 rib,
garter and seed (0.1 mm nylon monofilament, loop length 5 mm), each
relaxed for 150 steps of the overdamped flow, drawn side by side (front
view coloured by depth: red towards the technical face, blue away).

Checks: the elastic energy of each swatch falls while it relaxes, no
yarn enters another by more than a quarter of its diameter (clearance >
0.75: the contact rows sit at sample points and yarns sag into each other
between them; measured 0.85–0.94), and every loop is still through the
one below (``Relaxed.interlocks``). The
stiffness ordering of Singal et al. 2024 needs converged stretch curves
(see the README). Writes knit_patterns.png.

    python examples/knit_patterns.py [--out DIR]    # default: $STRANDKIT_OUT, else ./out
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

    fig, axes = plt.subplots(1, len(sk.knit.PATTERNS), figsize=(4 * len(sk.knit.PATTERNS), 4.6))
    for ax, pattern in zip(axes, sk.knit.PATTERNS):
        fabric = sk.knit.fabric(pattern, wales=6, courses=6, loop_length=5e-3, yarn="nylon", yarn_radius=1e-4)
        r = ex.relax(fabric, max_steps=150, record_every=10)
        e = r.history["energy"]
        print(f"{pattern:7s} {r}  energy {e[0]:.4e} → {e[-1]:.4e} J")
        checks.true(f"{pattern}: elastic energy falls", bool(np.all(np.diff(e) <= 1e-12 * e[0]) and e[-1] < e[0]),
                    f"{e[0]:.4e} → {e[-1]:.4e} J")
        checks.true(f"{pattern}: no yarn inside another (clearance > 0.75)", r.clearance > 0.75, f"{r.clearance:.3f}")
        checks.true(f"{pattern}: every loop still through the one below", r.interlocks.parted == [],
                    f"{r.interlocks}")
        draw_front(ax, r.world, fabric, point_size=1.2,
                   title=f"{pattern}: {' '.join(fabric.rows[0][:4])}… / {' '.join(fabric.rows[1][:4])}…")
    fig.tight_layout()
    fig.savefig(out / "knit_patterns.png", dpi=100)
    checks.finish()


if __name__ == "__main__":
    main()
