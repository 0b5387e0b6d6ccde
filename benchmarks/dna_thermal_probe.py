"""Thermal elasticity of the calibrated duplex (issue 17), measured from
its own fluctuations at 298.15 K in water — a probe, not a test (the
figures are in the issue notes; runs of ~1 min give ±10 % between seeds).

A free duplex of N bp (bonds unbreakable: the elasticity alone) is
stepped with thermal noise; every 5 steps, between pair 4 and pairs
8, 10, …, each pair framed as the stacking frames it (x: rung, z: the
central difference of the rung midpoints ⟂ x, origin: midpoint + R
cos(φ/2) y), it records the twist (rung rotations about the local axis,
summed), the contour length (rises along the local axis, summed) and the
squared angle between the two pairs' axes. Against the contour length L
between the pairs: var(twist) = L kT / C_eff, var(contour) = L kT / S_eff,
⟨θ²⟩ = 2 L / A (slopes of linear fits, so the pairs' own local wobble
goes into the intercepts). Expected from the zero-temperature
calibration: C_eff = C − g²/S ≈ 405 pN·nm², S_eff = S − g²/C ≈ 1080 pN,
A = 50 nm. (The end-to-end distance instead of the contour mixes in the
bending's L⁴/45A² and the midpoints instead of the axis points add
the pairs' tilt: both halve S.)

    python benchmarks/dna_thermal_probe.py N_BP DT_NS STEPS [SEED]
    # e.g. 40 0.001 60000 5  → C 411, S 962, A 64.8 (seed 6: 464, 957, 55.6)
"""
import sys, time, math, numpy as np, strandkit as sk
n = int(sys.argv[1]); dt = float(sys.argv[2]); steps = int(sys.argv[3]); every = 5
kT = 1.380649e-2 * 298.15
d = sk.dna.duplex(("GATTACA" * 40)[:n], break_forces=[math.inf] * n)
w = sk.World(units="molecular", dt=dt, viscosity=1.0, temperature=298.15, seed=int(sys.argv[4]) if len(sys.argv) > 4 else 5)
ins = w.insert(d.assembly)
a, b = (ins.rods[i] for i in d.strands)
ua, ub = d.abscissae[0], d.abscissae[1][d.partner]
def frames():
    A, B = a.position(ua), b.position(ub)
    m = 0.5 * (A + B); x = B - A; x /= np.linalg.norm(x, axis=1)[:, None]
    c = np.empty_like(m); c[1:-1] = m[2:] - m[:-2]; c[0] = 4*m[1]-3*m[0]-m[2]; c[-1] = 3*m[-1]-4*m[-2]+m[-3]
    z = c - x * np.sum(x*c, axis=1)[:, None]; z /= np.linalg.norm(z, axis=1)[:, None]
    y = np.cross(z, x); off = 0.5 * d.rung_length / math.tan(0.5 * d.phase)
    return m + off * y, x, z
i0 = 4
ends = list(range(i0 + 4, n - 4, 2))
def observables():
    m, x, z = frames()
    zz = z[:-1] + z[1:]; zz /= np.linalg.norm(zz, axis=1)[:, None]
    p0 = x[:-1] - zz * np.sum(x[:-1]*zz, axis=1)[:, None]; p1 = x[1:] - zz * np.sum(x[1:]*zz, axis=1)[:, None]
    steps_tw = np.arctan2(np.sum(np.cross(p0, p1) * zz, axis=1), np.sum(p0 * p1, axis=1))
    cum = np.cumsum(steps_tw)
    tw = [cum[j-1] - cum[i0-1] for j in ends]
    rise = np.sum((m[1:] - m[:-1]) * zz, axis=1); crise = np.cumsum(rise)
    span = [crise[j-1] - crise[i0-1] for j in ends]
    ang = [math.acos(np.clip(z[i0] @ z[j], -1, 1)) ** 2 for j in ends]
    return tw + span + ang
t = time.time(); obs = []
for s in range(steps):
    w.step()
    if s > steps // 10 and s % every == 0:
        obs.append(observables())
obs = np.array(obs); k = len(ends)
L = np.array([(j - i0) * 0.34 for j in ends])
vt, vs, th2 = obs[:, :k].var(0), obs[:, k:2*k].var(0), obs[:, 2*k:].mean(0)
ct = np.polyfit(L, vt, 1); cs = np.polyfit(L, vs, 1); cb = np.polyfit(L, th2, 1)
print(f"{n} bp dt {dt} ns {steps} steps {time.time()-t:.0f} s; L {L[0]:.2f}..{L[-1]:.2f} nm")
print(f"  twist var slope -> C_eff {kT/ct[0]:.0f} pN nm² (405), intercept {ct[1]:.4f}")
print(f"  span  var slope -> S_eff {kT/cs[0]:.0f} pN (1080), intercept {cs[1]:.5f} nm²")
print(f"  bend <θ²> slope -> A {2/cb[0]:.1f} nm (50), intercept {cb[1]:.4f}")
