"""strandkit.polymer: the worm-like chain references against each other
and against their limits."""
import math

import numpy as np
import pytest

import strandkit as sk
from strandkit.polymer import bouchiat_extension, buckling_torque, wlc_extension, wlc_r2

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


def _fd_buckling_torque(b, f, length, n):
    """The same threshold by an independent route: the twisted rod's
    second variation ½∫ B|w″|² + F|w′|² − M Im(w̄′ w″) on n finite
    differences, clamped (w = 0 on two nodes at each end); M_c is where
    K − M G first loses definiteness, 1 / the largest eigenvalue of G on K
    (first order in the spacing)."""
    h = length / n
    eye = np.eye(n + 1)
    free = np.arange(2, n - 1)
    d1 = ((eye[1:] - eye[:-1]) / h)[:, free]
    d2 = ((eye[2:] - 2 * eye[1:-1] + eye[:-2]) / h ** 2)[:, free]
    c1 = ((eye[2:] - eye[:-2]) / (2 * h))[:, free]
    k = b * d2.T @ d2 * h + f * d1.T @ d1 * h
    g = (c1.T @ d2 - d2.T @ c1) * h / 2j
    chol = np.linalg.cholesky(k)
    inv = np.linalg.inv(chol)
    return 1.0 / np.linalg.eigvalsh(inv @ g @ inv.conj().T).max()


def test_buckling_torque_of_a_twisted_rod_under_tension():
    b = 205.8  # pN·nm², DNA
    # Greenhill (no tension): 2.8606 π B / L.
    assert buckling_torque(b, 0.0, 100.0) == pytest.approx(2.8606 * math.pi * b / 100.0, rel=2e-5)
    # Long under tension: 2√(BF), approached from above.
    m = 2 * math.sqrt(b * 5.0)
    assert buckling_torque(b, 5.0, 3000.0) == pytest.approx(m, rel=1e-4)
    assert buckling_torque(b, 5.0, 102.0) > buckling_torque(b, 5.0, 150.0) > m
    # Very long: the first root, just above 2√(BF) (not a later one).
    assert 0 < buckling_torque(b, 5.0, 6e4) / m - 1 < 1e-6
    # Against the finite differences, Richardson-extrapolated from 400 and 800 nodes.
    for f, length in ((5.0, 68.0), (1.0, 100.0), (0.0, 100.0)):
        fd = 2 * _fd_buckling_torque(b, f, length, 800) - _fd_buckling_torque(b, f, length, 400)
        assert buckling_torque(b, f, length) == pytest.approx(fd, rel=5e-4)
    for bad in ((-1.0, 1.0, 10.0), (b, -1.0, 10.0), (b, 1.0, 0.0), (b, math.nan, 10.0)):
        with pytest.raises(sk.InvalidInputError):
            buckling_torque(*bad)
