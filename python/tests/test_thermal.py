"""Thermal noise from Python (issue 16): world settings with units, the
molecular unit system, bit-exact restarts, typed errors, and a statistical
check (harmonic trap: the trapped point's variance is kT/k per axis)."""
import math

import numpy as np
import pytest

import strandkit as sk

KT = sk.units.kT(298.15, "molecular")  # pN·nm


def dna(length=10.0, n=6, roll=False):
    """Radius 1 nm, bending persistence 50 nm, twist persistence 100 nm."""
    i = math.pi / 4
    e, g = 50 * KT / i, 100 * KT / (2 * i)
    return sk.straight((0, 0, 0), (length, 0, 0), section=1.0, n_control_points=n, with_roll=roll,
                       material=sk.Material("dna", e, e / (2 * g) - 1, 1.7e-3),
                       model="reference" if roll else "frenet")


def thermal_world(**kw):
    params = dict(units="molecular", temperature=298.15, viscosity=0.01, dt=1e-3, scheme="trapezoidal", seed=3)
    params.update(kw)
    return sk.World(**params)


def test_units_module():
    assert sk.units.kT(298.0, "molecular") == pytest.approx(4.114, abs=1e-3)
    assert sk.units.kT(298.15, "si") == pytest.approx(4.1164e-21, rel=1e-4)
    assert sk.units.to_molecular(1e-3, "viscosity") == pytest.approx(1.0)
    assert sk.units.to_si(1.0, "force") == 1e-12
    assert sk.units.to_molecular(1700.0, "density") == pytest.approx(1.7e-3)
    with pytest.raises(ValueError, match="unknown quantity"):
        sk.units.to_si(1.0, "furlongs")
    with pytest.raises(ValueError, match="units"):
        sk.units.kT(300, "cgs")
    with pytest.raises(ValueError, match="temperature"):
        sk.units.kT(-1, "si")


def test_resistive_force_drag_and_rod_drag():
    perp, par, roll = sk.resistive_force_drag(1.0, 1.0, 1000.0)
    assert perp == pytest.approx(4 * math.pi / (math.log(1000) + 0.5))
    assert par == pytest.approx(perp / 2) and roll == pytest.approx(4 * math.pi)
    w = thermal_world(viscosity=1.0)
    rod = w.add_rod(dna(1000.0, 10, roll=True))
    d = rod.drag()
    assert d["trans"] == pytest.approx(perp) and d["roll_r2"] == pytest.approx(4 * math.pi) and d["roll"] == 0
    assert rod.drag(viscosity=0.0)["trans"] == 0.0
    with pytest.raises(sk.InvalidInputError, match="slender"):
        sk.resistive_force_drag(1.0, 1.0, 1.5)


def test_bad_thermal_settings_are_typed_errors():
    for bad in [dict(temperature=-1.0), dict(temperature=float("nan")), dict(viscosity=-1e-3),
                dict(seed=1.5), dict(seed=-1), dict(seed="one"), dict(units="cgs")]:
        with pytest.raises(sk.InvalidInputError):
            sk.World(**bad)
    # Noise without drag: refused, the world unchanged.
    w = thermal_world(viscosity=0.0)
    rod = w.add_rod(dna())
    before = rod.control_points.copy()
    with pytest.raises(sk.InvalidInputError, match="without drag"):
        w.step()
    assert w.time == 0.0 and np.array_equal(rod.control_points, before)
    w2 = thermal_world(scheme="tr_bdf2")
    w2.add_rod(dna())
    with pytest.raises(sk.InvalidInputError, match="TR-BDF2"):
        w2.step()
    # A Frenet rod with roll: its roll is undefined where the rod is straight.
    w3 = thermal_world()
    w3.add_rod(sk.straight((0, 0, 0), (10, 0, 0), section=1.0, material=sk.Material("dna", 262.0, -0.5, 1.7e-3),
                           n_control_points=6, model="frenet"))
    with pytest.raises(sk.InvalidInputError, match="model='reference'"):
        w3.step()
    # Brownian dynamics needs drag even at T = 0.
    w4 = thermal_world(temperature=0.0, viscosity=0.0, overdamped=True)
    w4.add_rod(dna())
    with pytest.raises(sk.InvalidInputError, match="without drag"):
        w4.step()


def test_world_repr_shows_the_bath():
    w = thermal_world(overdamped=True, isotropic_drag=True)
    text = repr(w)
    assert "units='molecular'" in text and "temperature=298.15 K" in text and "overdamped=True" in text
    assert "isotropic_drag=True" in text
    assert "temperature" not in repr(sk.World())


def test_restart_under_noise_is_bit_exact():
    w = thermal_world()
    rod = w.add_rod(dna(50.0, 10, roll=True))
    for _ in range(10):
        w.step()
    text = w.to_json()
    for _ in range(10):
        w.step()
    again = sk.World.from_json(text)
    for _ in range(10):
        again.step()
    assert np.array_equal(again.rods()[0].control_points, rod.control_points)
    # Another seed, another trajectory.
    other = sk.World.from_json(text)
    other.set_params(seed=4)
    for _ in range(10):
        other.step()
    assert not np.array_equal(other.rods()[0].control_points, rod.control_points)


def test_trap_variance_is_kt_over_k():
    """A trap of stiffness k on the end of free rods: ⟨δx²⟩ = kT/k per axis
    (exact whatever the rod does). 16 rods × 3 axes × 6000 steps of 1 ps;
    measured 0.99 (σ ≈ 3 %), tolerance 10 %."""
    k = 1.0  # pN/nm
    w = thermal_world(seed=11)
    rods = []
    for i in range(16):
        rod = w.add_rod(dna())
        anchor = (0.0, 20.0 * i, 0.0)
        rod.control_points = rod.control_points + np.array(anchor)
        w.add_load(sk.trap(rod, u=rod.u_start, anchor=anchor, stiffness=k))
        rods.append((rod, np.array(anchor)))
    samples = []
    for s in range(6000):
        w.step()
        if s >= 1000:
            samples.append([rod.position(rod.u_start) - a for rod, a in rods])
    x = np.asarray(samples)
    ratio = float(np.mean(x**2)) / (KT / k)
    print(f"<dx²>/(kT/k) = {ratio:.4f}")
    assert abs(ratio - 1) < 0.1


def test_greville_stretch_option():
    """`stretch_at_greville=True` (the locking cure): a pulled rod still
    stretches by F L / EA; the Poisson update (which reads the Gauss
    samples' stretch) is refused with it."""
    rod = sk.straight((0, 0, 0), (1, 0, 0), section=1e-3, material=sk.Material("steel", 2e11, 0.3, 7800.0),
                      n_control_points=12, with_roll=False, stretch_at_greville=True)
    assert rod.options["stretch_at_greville"] is True
    w = sk.World()
    rod = w.add_rod(rod)
    sk.clamp(w, rod)
    w.add_load(sk.point_force(rod, rod.u_end, (100.0, 0, 0)))
    w.relax()
    ea = 2e11 * math.pi * 1e-6
    assert rod.position(rod.u_end)[0] - 1 == pytest.approx(100.0 / ea, rel=1e-6)
    with pytest.raises(sk.InvalidInputError, match="poisson_update"):
        sk.straight((0, 0, 0), (1, 0, 0), section=1e-3, material="steel", poisson_update=True, stretch_at_greville=True)


def test_sampling_length_option():
    """`sampling_length=` (length unit): heavier short modes for equilibrium
    sampling; a rigid translation keeps the physical mass (its kinetic
    energy is unchanged), negative or non-finite lengths are refused."""
    def rod(ell):
        return sk.straight((0, 0, 0), (50.0, 0, 0), section=1.0, material=sk.Material("dna", 350.0, 0.3, 1.7e-3),
                           n_control_points=20, with_roll=False, sampling_length=ell)
    plain, heavy = rod(0.0), rod(5.0)
    assert heavy.options["sampling_length"] == 5.0
    v = np.tile([1.0, -2.0, 0.5], (20, 1))
    plain.velocities = v
    heavy.velocities = v
    assert heavy.kinetic_energy == pytest.approx(plain.kinetic_energy, rel=1e-9)
    wiggle = np.zeros((20, 3))
    wiggle[0::2, 1] = 1.0
    wiggle[1::2, 1] = -1.0
    plain.velocities = wiggle
    heavy.velocities = wiggle
    assert heavy.kinetic_energy > 10 * plain.kinetic_energy
    for bad in (-1.0, float("nan"), float("inf")):
        with pytest.raises(sk.InvalidInputError, match="sampling.length"):
            rod(bad)


def test_anisotropic_drag_from_python():
    """Resistive-force drag is anisotropic (γ_∥ = γ_⊥/2 along the rod) unless
    `isotropic_drag=True`; a rod pulled along itself drifts twice as fast as
    across; Brownian dynamics needs the isotropic drag."""
    w = sk.World(units="molecular", viscosity=1.0, dt=0.01)
    rods = [w.add_rod(dna(50.0, 8)) for _ in range(2)]
    d = rods[0].drag()
    assert d["axial"] == pytest.approx(-0.5 * d["trans"], rel=1e-12)
    w.add_load(sk.distributed(rods[0], (0.04, 0.0, 0.0)))
    w.add_load(sk.distributed(rods[1], (0.0, 0.04, 0.0)))
    for _ in range(200):
        w.step()
    v_par = rods[0].velocities.reshape(-1, 3)[:, 0].mean()
    v_perp = rods[1].velocities.reshape(-1, 3)[:, 1].mean()
    assert v_par == pytest.approx(0.04 / (d["trans"] + d["axial"]), rel=1e-6)
    assert v_perp == pytest.approx(0.04 / d["trans"], rel=1e-6)
    iso = sk.World(units="molecular", viscosity=1.0, isotropic_drag=True)
    assert iso.add_rod(dna(50.0, 8)).drag()["axial"] == 0.0
    w2 = thermal_world(overdamped=True)
    w2.add_rod(dna())
    with pytest.raises(sk.InvalidInputError, match="isotropic_drag=True"):
        w2.step()
    w3 = thermal_world(overdamped=True, isotropic_drag=True)
    w3.add_rod(dna())
    w3.step()
