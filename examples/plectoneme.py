"""A magnetic-tweezers experiment on an elastic rod (SPEC §9.1): a rod held
along x under tension F (its far end slides along the axis, L√(F/B) = 20)
has that end turned at a steady rate with the reference-frame twist model
and self-contact. It stays straight, the torque rising as GJ Φ/L, until it
buckles past M_c = 2√(BF); it then winds a plectoneme held open by
self-contact: the extension falls linearly with the turns while the torque
stays on a plateau. Checks: straight up to M_c (within 3 %, dynamic
loading may overshoot it), a plateau within ±10 % below M_c, the extension
linear within 5 % of its fall, the strands at least 0.9 diameter apart.
Writes plectoneme.png (extension and torque against turns, and the
plectoneme seen from the side). About a minute.

    python examples/plectoneme.py [--out DIR]    # default: $STRANDKIT_OUT, else ./out
"""
import numpy as np

import strandkit as sk
from _common import Checks, output_dir

L, R, E, NU = 1.0, 0.002, 1e7, 0.5          # m, m, Pa
B = E * np.pi * R**4 / 4                     # bending stiffness, N m²
F = 400 * B / L**2                           # tension, N (L √(F/B) = 20)
M_C = 2 * np.sqrt(B * F)                     # buckling torque of a long rod, N m


def main():
    out = output_dir(__doc__)
    checks = Checks()
    rod = sk.straight((0, 0, 0), (L, 0, 0), section=R, material=sk.Material("rubber", E, NU, 1000.0),
                      n_control_points=80, model="reference", drag=0.05)
    w = sk.World(dt=1e-3)
    w.add_rod(rod)
    w.add_constraint(rod, sk.position(rod.u_start, (0, 0, 0), axes="xyz", roll=0.0))
    w.add_constraint(rod, sk.tangent(rod.u_start, (1, 0, 0)))
    end = w.add_constraint(rod, sk.position(rod.u_end, (L, 0, 0), axes="yz", roll=0.0))
    w.add_constraint(rod, sk.tangent(rod.u_end, (1, 0, 0)))
    w.add_load(sk.point_force(rod, rod.u_end, (F, 0, 0)))
    w.contact(margin=10 * R, self_contact=True, between_rods=False)
    q = rod.control_points.copy()
    q[:, 1] += 1e-6 * np.sin(0.7 * np.arange(len(q)))   # a direction to buckle in
    rod.control_points = q

    # The snap's turn (11–12) moves with round-off (a bifurcation); the
    # plectoneme reaches the clamps 4–6 turns after it, so the run stops
    # 2.5 turns after the snap and the linear stretch is measured from 1.0
    # (beyond 2.5 turns the growth depended on round-off: relative changes
    # of the tension by 1e-12 moved the extension at 3.5 turns by 14 %).
    steps_per_turn, turns = 800, 20
    rows = []
    for k in range(1, turns * steps_per_turn + 1):
        snapped = next((r[0] for r in rows if r[1] < 0.99 * L), None)
        if snapped is not None and k / steps_per_turn > snapped + 2.5:
            turns = k / steps_per_turn
            break
        w.set_constraint(end, sk.position(rod.u_end, (L, 0, 0), axes="yz", roll=2 * np.pi * k / steps_per_turn))
        w.step()
        if k % (steps_per_turn // 2) == 0:
            p = rod.sample_points
            p = p() if callable(p) else p
            n = len(p)
            d = np.linalg.norm(p[:, None] - p[None], axis=2)
            far = np.abs(np.arange(n)[:, None] - np.arange(n)[None]) >= n // 20
            rows.append((k / steps_per_turn, rod.position(rod.u_end)[0], abs(w.reaction(end).torque[0]), d[far].min()))
            print(f"{rows[-1][0]:5.1f} turns: extension {rows[-1][1]:.4f} m, torque {rows[-1][2]:.3e} N m")
    t, x, tau, gap = map(np.array, zip(*rows))

    snap = int(np.argmax(x < 0.99 * L))
    checks.true("straight up to M_c", tau[snap - 1] > 0.97 * M_C, f"{tau[snap - 1]:.4e} N m before the snap, 2√(BF) = {M_C:.4e}")
    post = (t >= t[snap] + 1.0) & (t <= t[snap] + 2.5)
    slope, icpt = np.polyfit(t[post], x[post], 1)
    fall = abs(slope) * (t[post][-1] - t[post][0])
    dev = np.abs(x[post] - (slope * t[post] + icpt)).max()
    checks.true("extension linear in the turns", slope < 0 and dev < 0.05 * fall, f"{slope * 100:.2f} cm per turn, worst deviation {dev * 1e3:.2f} mm")
    plateau = tau[post].mean()
    checks.true("torque plateau below M_c", np.abs(tau[post] / plateau - 1).max() < 0.1 and plateau < M_C,
                f"{plateau:.3e} N m ± {100 * np.abs(tau[post] / plateau - 1).max():.1f} %")
    checks.true("strands held one diameter apart", gap[post].min() > 0.9 * 2 * R, f"closest {gap[post].min() / (2 * R):.3f} diameters")

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(1, 3, figsize=(15, 4.2))
    ax[0].plot(t, x, "o-")
    ax[0].plot(t[post], slope * t[post] + icpt, "k--", label=f"{slope * 100:.2f} cm/turn")
    ax[0].set(xlabel="turns", ylabel="extension (m)", title="extension")
    ax[0].legend()
    ax[1].plot(t, tau * 1e3, "o-")
    ax[1].axhline(M_C * 1e3, color="r", ls="--", label="2√(BF)")
    ax[1].set(xlabel="turns", ylabel="torque (mN m)", title="end torque")
    ax[1].legend()
    u = np.linspace(rod.u_start, rod.u_end, 2000)
    pts = np.array([rod.position(v) for v in u])
    ax[2].plot(pts[:, 0], pts[:, 1], lw=1)
    ax[2].set(xlabel="x (m)", ylabel="y (m)", title=f"after {turns:g} turns", aspect="equal")
    fig.tight_layout()
    fig.savefig(out / "plectoneme.png", dpi=110)
    print(f"wrote {out / 'plectoneme.png'}")
    checks.finish()


if __name__ == "__main__":
    main()
