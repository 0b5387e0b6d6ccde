"""Time schemes from Python: World(scheme=...) selects implicit Euler,
TR-BDF2 or the trapezoidal rule (SPEC §3; Rust checks in tests/schemes.rs)."""
import numpy as np
import pytest

import strandkit as sk
from conftest import cantilever


def _tip_amplitudes(scheme, per_period=20, periods=6):
    """The SPEC §10 cantilever released from a small static tip deflection
    (no gravity): tip |y| over the first and the last period."""
    w, rod, _, _ = cantilever((0.0, -1e3, 0.0), n=12, samples=4)
    w.relax()
    for load in w.loads():
        w.remove_load(load)
    # First bending mode of the clamped steel rod: ω = 1.8751² √(EI/μL⁴).
    r, length, e, rho = 0.05, 4.0, 200e9, 7800.0
    omega = 1.8751**2 * np.sqrt(e * np.pi * r**4 / 4 / (rho * np.pi * r**2 * length**4))
    w.set_params(dt=2 * np.pi / omega / per_period, scheme=scheme, parallel=False)
    ys = [rod.position(rod.u_end)[1]]
    for _ in range(per_period * periods):
        w.step()
        ys.append(rod.position(rod.u_end)[1])
    ys = np.abs(np.array(ys))
    return ys[: per_period + 1].max(), ys[-per_period - 1 :].max()


def test_tr_bdf2_keeps_the_vibration_that_implicit_euler_damps():
    a0, a1 = _tip_amplitudes("tr_bdf2")
    e0, e1 = _tip_amplitudes("implicit_euler")
    # 20 steps per period, 6 periods: TR-BDF2 keeps > 95 % (the static
    # shape is not purely the first mode; higher modes are damped), implicit
    # Euler < 5 %.
    assert a1 / a0 > 0.95, (a0, a1)  # measured 0.962
    assert e1 / e0 < 0.05, (e0, e1)


def test_scheme_is_a_parameter_and_survives_a_snapshot(tmp_path):
    w, rod, _, _ = cantilever((0.0, -1e3, 0.0), n=8, samples=4)
    w.set_params(scheme="trapezoidal", dt=1e-3)
    assert w.params["scheme"] == "trapezoidal"
    report = w.step()
    assert report.solves >= 2
    path = tmp_path / "w.json"
    w.save(str(path))
    copy_ = sk.World.load(str(path))
    assert copy_.params["scheme"] == "trapezoidal"
    w.step()
    copy_.step()
    assert rod.control_points.tobytes() == copy_.rods()[0].control_points.tobytes()
    assert sk.World().params["scheme"] == "implicit_euler"


def test_unknown_scheme_is_refused_by_name():
    with pytest.raises(sk.InvalidInputError, match="tr_bdf2"):
        sk.World(scheme="rk4")
    w = sk.World(scheme="tr_bdf2")
    with pytest.raises(sk.InvalidInputError):
        w.set_params(scheme=3)
    assert w.params["scheme"] == "tr_bdf2"
