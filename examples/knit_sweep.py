"""A knit sweep (issues 18 and 19): 5 × 5 plain jersey swatches relaxed for
120 steps of the overdamped flow, then pulled along the wale to 5 % between
bars (two increments of 40 steps), over three yarn fibres (nylon 3 GPa,
polyester 15 GPa, aramid 100 GPa: bending stiffness B over 30×) and three
loop lengths ℓ (4, 5 and 6 mm, the yarn radius ℓ/50 with it), run with
``strandkit.sweep`` on two local processes, each point a function call
returning the swatch's Munden constants and energy.

Checked — scale invariance of an elastic knit (SPEC §9.3: the rigidity
scales as B/ℓ², Poincloux 2018; Singal 2024's collapse of Y·L·A/B): at a
fixed ℓ/r the energy of a yarn is B/ℓ × a function of the shape alone (its
stretch too: EA ℓ²/B = 4ℓ²/r²), and the flow's first step is 100 ηr⁴/B, so
the relaxation passes through the same shapes for every B and ℓ: k_c, k_w,
Eℓ/B and the bar force in units of B/ℓ² agree across the nine points
within 1e-6 (measured 1e-9). This is the identity of the runs, not yet the
collapse of converged stretch curves. Saves knit_sweep.png (the four per
point) and the sweep's results in knit_sweep/ (results.parquet, one row
per point in points/).

    python examples/knit_sweep.py [--out DIR]
"""
import numpy as np

import strandkit as sk
from _common import Checks, output_dir

YARNS = ("nylon", "polyester", "aramid")
LOOPS = (4e-3, 5e-3, 6e-3)  # m


def relaxed(yarn, loop_length):
    from strandkit.knit import experiments as ex
    f = sk.knit.fabric("jersey", wales=5, courses=5, loop_length=loop_length, yarn=yarn, yarn_radius=loop_length / 50)
    r = ex.relax(f, max_steps=120, record_every=10)
    d = r.dimensions
    energy = r.history["energy"][-1] * loop_length / f.bending_stiffness
    s = ex.stretch(r, direction="wale", strain=0.05, increments=2, unload=False, settle_steps=20,
                   steps_per_increment=40)
    return {"k_c": d["k_c"], "k_w": d["k_w"], "E_l_over_B": energy,
            "F_l2_over_B": s.force[-1] * loop_length ** 2 / f.bending_stiffness,
            "clearance": min(r.clearance, s.clearance)}


def main():
    out = output_dir(__doc__)
    checks = Checks()
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    df = sk.sweep(relaxed, {"yarn": list(YARNS), "loop_length": list(LOOPS)}, out=out / "knit_sweep", workers=2,
                  progress_bar=False)
    print(df[["yarn", "loop_length", "k_c", "k_w", "E_l_over_B", "F_l2_over_B", "clearance", "elapsed"]].to_string())
    checks.true("every point ran", bool(df["error"].isna().all()) if "error" in df else True)
    for key in ("k_c", "k_w", "E_l_over_B", "F_l2_over_B"):
        v = df[key].to_numpy()
        spread = float((v.max() - v.min()) / abs(np.mean(v)))
        checks.true(f"{key} the same for every B and ℓ at ℓ/r = 50", spread < 1e-6, f"spread {spread:.2e} of {np.mean(v):.4g}")
    checks.true("no yarn inside another (clearance > 0.75)", bool((df["clearance"] > 0.75).all()),
                f"least {df['clearance'].min():.3f}")
    fig, ax = plt.subplots(1, 4, figsize=(15, 3.6))
    labels = [f"{y}\n{l * 1e3:g} mm" for y, l in zip(df["yarn"], df["loop_length"])]
    for a, key in zip(ax, ("k_c", "k_w", "E_l_over_B", "F_l2_over_B")):
        a.plot(range(len(df)), df[key], "o")
        a.set_xticks(range(len(df)), labels, fontsize=6, rotation=90)
        a.set_title(key)
    fig.tight_layout()
    fig.savefig(out / "knit_sweep.png", dpi=100)
    checks.finish()


if __name__ == "__main__":
    main()
