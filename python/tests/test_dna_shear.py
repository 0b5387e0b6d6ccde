"""Shear (3′–3′) of a duplex with position rungs (``hbond="position"``)
against de Gennes' ladder (issue 17, SPEC §9.1): F_c(N) = 2 f₁ κ⁻¹
tanh(κN/2), κ⁻² = Q/(2R), with the model's own numbers — f₁ the stagger's
break force, R = 1/stagger_compliance and Q = EA h²/ℓ³, the strand's
stiffness per pair along the axis (EA its stretch modulus, ℓ the helix arc
per nucleotide, h the rise). The hydrogen bonds' distances are unbreakable
here, so that the rungs fail in shear as the ladder's do.

Measured (zero temperature, quasi-static): F_c(16, 24, 40) 4.4, 2.6 and
4.0 % below the law, saturating; the short duplexes (N ≤ 12) rupture 9–12 %
above it, where a tenth of the load bypasses the staggers (the strands
are helices pulled off the axis, and the ends' rungs tilt)."""
import math

import numpy as np
import pytest

import strandkit as sk
from strandkit.dna import experiments as ex

F1 = 0.5          # pN: small, so that the stagger stays ≪ the rung (linear ladder)
COMPLIANCE = 0.5  # nm/pN: R = 2 pN/nm, κ⁻¹ ≈ 6 bp (Hatch et al. 2008 fit 6.1)


def ladder_kappa(d):
    """κ (1/bp) from the duplex's own backbone Q and rung R."""
    p = d.params
    arc = math.hypot(2 * math.pi * p["radius"] / p["bp_per_turn"], p["rise"])
    q = p["strand_stretch_modulus"] * p["rise"] ** 2 / arc ** 3
    return math.sqrt(2.0 / COMPLIANCE / q)


def sheared(n):
    return sk.dna.duplex(("GATTACA" * 6)[:n], hbond="position", stagger_compliance=COMPLIANCE,
                         break_forces=[math.inf] * n, stagger_break_forces=[F1] * n)


@pytest.fixture(scope="module")
def ruptures():
    out = {}
    for n in (4, 8, 12, 16, 24, 40):
        d = sheared(n)
        r = ex.shear(d, speed=0.05, trap_stiffness=5.0, viscosity=0.1, dt=0.01, distance=3.0,
                     stop_when_open=False, progress_bar=False)
        first = [b for b in r.breaks if b["bond"] == "stagger" and b["force"] > 0]
        assert first, f"{n} bp: no stagger broke"
        # The first break is an end pair's (de Gennes: the ends carry the
        # most), when its stagger force passed f₁ (by one step's overshoot).
        assert first[0]["pair"] in (0, n - 1) or n <= 4, first[0]
        assert F1 <= first[0]["force"] < 1.05 * F1
        out[n] = (first[0]["trap_force"], 2 * F1 / ladder_kappa(d) * math.tanh(ladder_kappa(d) * n / 2))
    return out


def test_the_staggers_carry_the_shear():
    """A 40 bp duplex under a 3 pN shear: the stagger rows' forces add up
    to the pull (every pair's share goes through its rung), end pairs
    loaded most and alike."""
    n, f = 40, 3.0
    d = sheared(n)
    w = sk.World(units="molecular", dt=0.01, viscosity=0.1)
    ins = w.insert(d.assembly)
    a, b = (ins.rods[i] for i in d.strands)
    ua, ub = float(d.abscissae[0][-1]), float(d.abscissae[1][-1])
    w.add_load(sk.trap(b, ub, np.asarray(b.position(ub)), 10.0))
    w.add_load(sk.point_force(a, ua, [0.0, 0.0, f]))
    for _ in range(4000):
        w.step()
    st = np.array([w.multipliers(ins.constraints[h])[0] for h in d.staggers])
    assert st.sum() == pytest.approx(f, rel=0.01)
    assert st[0] == pytest.approx(st[-1], rel=0.01) and max(st[0], st[-1]) == st.max()
    # de Gennes' end share κ/2 (continuum) with the model's Q and R: 6 %.
    assert st[0] / f == pytest.approx(ladder_kappa(d) / 2, rel=0.06)


def test_rupture_follows_de_gennes_and_saturates(ruptures):
    for n in (16, 24, 40):
        measured, law = ruptures[n]
        assert measured == pytest.approx(law, rel=0.05), f"{n} bp: {measured:.3f} pN vs {law:.3f}"
    f = {n: v[0] for n, v in ruptures.items()}
    # Grows, then saturates at 2 f₁ κ⁻¹.
    assert f[4] < f[8] < f[12] and f[16] < f[24]
    assert f[40] == pytest.approx(f[24], rel=0.03)
    assert f[4] < 0.45 * f[40]
    # Short duplexes: above the law, by less than a fifth (stated in the module).
    for n in (4, 8, 12):
        assert 1.0 < f[n] / ruptures[n][1] < 1.2
