"""strandkit.polymer: the worm-like chain references against each other
and against their limits."""
import math

import pytest

import strandkit as sk
from strandkit.polymer import bouchiat_extension, wlc_extension, wlc_r2

KT = sk.units.kT(298.15, "molecular")


@pytest.mark.parametrize("force", [0.05, 0.1, 0.3, 1.0, 3.0, 10.0, 20.0])
def test_long_chain_transfer_matrix_matches_bouchiat(force):
    exact = wlc_extension(force, 50.0, kT=KT)
    assert exact == pytest.approx(bouchiat_extension(force, 50.0, kT=KT), rel=1e-3)


def test_linear_response_and_limits():
    # Small force: ⟨z⟩ = F ⟨R²⟩ / (3 kT) for any contour.
    for contour in (50.0, 250.0):
        f = 1e-4
        z = wlc_extension(f, 50.0, contour, kT=KT) * contour
        assert z == pytest.approx(f * wlc_r2(50.0, contour) / (3 * KT), rel=1e-3)
    assert wlc_r2(50.0, 1e-3) == pytest.approx(1e-6, rel=1e-4)  # rigid rod: L²
    assert wlc_r2(50.0, 1e5) == pytest.approx(2 * 50.0 * 1e5, rel=1e-3)  # coil: 2AL
    # A finite chain extends less than the long one at low force.
    assert wlc_extension(0.1, 50.0, 100.0, kT=KT) < wlc_extension(0.1, 50.0, kT=KT)
    assert wlc_extension(0.0, 50.0, kT=KT) == pytest.approx(0.0, abs=1e-6)


def test_high_force_keeps_enough_states():
    # F A/kT ≈ 1200: the basis grows with √(fA); the long-chain limit
    # z = 1 − 1/(2√(fA)) + … (Marko–Siggia's asymptote) holds.
    z = wlc_extension(100.0, 50.0, kT=KT)
    assert z == pytest.approx(bouchiat_extension(100.0, 50.0, kT=KT), rel=1e-4)
    assert 1 - z == pytest.approx(0.5 / math.sqrt(100.0 * 50.0 / KT), rel=0.02)
    with pytest.raises(sk.InvalidInputError, match="too large"):
        wlc_extension(1e6, 50.0, kT=KT)


def test_bad_input():
    for call in (lambda: wlc_r2(-1.0, 10.0), lambda: wlc_extension(math.nan, 50.0),
                 lambda: wlc_extension(1.0, 50.0, contour=-5.0), lambda: bouchiat_extension(-1.0, 50.0),
                 lambda: wlc_extension(1.0, 50.0, kT=0.0)):
        with pytest.raises(sk.InvalidInputError):
            call()
