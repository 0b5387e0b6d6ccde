"""Plasticity, rupture and quasi-dynamics from Python (SPEC §6, IV.B)."""
import math
import numpy as np
import pytest

import strandkit as sk


def wire(material, n=8, **kw):
    return sk.straight((0, 0, 0), (1, 0, 0), section=0.005, material=material, n_control_points=n,
                       with_roll=False, **kw)


def test_stretch_past_yield_leaves_a_permanent_elongation():
    m = sk.Material("wire", young=1e9, poisson=0.3, density=8000.0).with_yield(stretch=0.01)
    w = sk.World()
    rod = w.add_rod(wire(m))
    sk.clamp(w, rod)
    end = w.add_constraint(rod, sk.position(rod.u_end, (1.0, 0, 0)))
    for k in range(1, 5):
        w.set_constraint(end, sk.position(rod.u_end, (1.0 + 0.005 * k, 0, 0)))
        report = w.relax()
    assert report.plastic_samples == len(rod.sample_points())  # every sample yielded again
    offsets = rod.plastic_offsets
    assert offsets.shape == (len(rod.sample_points()), 4)
    np.testing.assert_allclose(offsets[:, 0], 0.01, atol=1e-6)
    w.remove_constraint(end)
    w.relax()
    assert rod.position(rod.u_end)[0] == pytest.approx(1.01, abs=1e-4)
    # Offsets can be reset by hand (shape and finiteness checked).
    rod.plastic_offsets = np.zeros_like(offsets)
    with pytest.raises(ValueError, match="one per sample"):
        rod.plastic_offsets = np.zeros((3, 4))


def test_rupture_event_gives_both_pieces():
    m = sk.Material("rubber", young=1e6, poisson=0.45, density=1000.0).with_rupture(stretch=0.05)
    w = sk.World(parallel=False)
    rod = w.add_rod(wire(m, n=12, drag=20.0))
    sk.clamp(w, rod)
    u1 = rod.u_end
    end = w.add_constraint(rod, sk.position(u1, (1.0, 0, 0)))
    bead = w.add_bead(rod, u=rod.u_start + 0.9 * (u1 - rod.u_start), mass=1e-3)
    event = None
    for k in range(1, 400):
        w.set_constraint(end, sk.position(u1, (1.0 + 5e-4 * k, 0, 0)))
        events = [e for e in w.step().events if e.kind == "RodRuptured"]
        if events:
            event = events[0]
            break
    assert event is not None, "the strand never broke"
    assert event.rod == rod and event.mode == "Stretch" and event.strain > event.limit == 0.05
    piece = event.new_rod
    assert isinstance(piece, sk.Rod) and piece.domain == (pytest.approx(event.u), pytest.approx(u1))
    assert rod.domain[1] == pytest.approx(event.u)
    np.testing.assert_allclose(rod.position(event.u), piece.position(event.u), atol=1e-12)
    assert "RodRuptured" in repr(event)
    w.remove_bead(bead)
    with pytest.raises(ValueError, match="does not exist"):
        w.remove_bead(bead)


def test_quasi_dynamic_switches_on_an_injected_clock():
    w = sk.World(parallel=False)
    rod = w.add_rod(sk.straight((0, 0, 0), (4, 0, 0), section=0.05, material="carbon_steel", n_control_points=10))
    sk.clamp(w, rod)
    w.add_load(sk.point_force(rod, rod.u_end, (0, -1e4, 0)))
    qd = sk.QuasiDynamic(w, dt0=1e-3, time_budget=0.01)
    costs = [0.005] * 5 + [0.01] * 5 + [0.005] * 5  # seconds per frame
    t = {"now": 0.0, "calls": 0}

    def clock():
        if t["calls"] % 2 == 1:
            t["now"] += costs[t["calls"] // 2]
        t["calls"] += 1
        return t["now"]

    modes = [qd.step(clock).mode for _ in range(15)]
    assert modes == ["dynamic"] * 6 + ["quasi_static"] * 5 + ["dynamic"] * 4
    assert "QuasiDynamic(mode=dynamic" in repr(qd)
    r = qd.step()  # the wall clock
    assert r.dt == pytest.approx(1e-3) and r.free_length == pytest.approx(4.0)


def test_quasi_dynamic_bad_input():
    w = sk.World()
    w.add_rod(sk.straight((0, 0, 0), (1, 0, 0), section=0.01, material="nylon"))
    with pytest.raises(ValueError, match="dt0"):
        sk.QuasiDynamic(w, dt0=-1.0)
    with pytest.raises(ValueError, match="hysteresis"):
        sk.QuasiDynamic(w, to_static=0.5, to_dynamic=0.9)
    qd = sk.QuasiDynamic(w)

    def broken():
        raise RuntimeError("clock failed")

    with pytest.raises(RuntimeError, match="clock failed"):
        qd.step(broken)


def _ramp_break_time(tau, r=100.0, f=10.0, dt=1e-3):
    """A rod clamped at its start, a second rod hanging from its end by a
    distance link (breaking in tension at f, averaged over tau), the
    second rod's far end pulled by F = r t (N): when does the link go?"""
    w = sk.World(dt=dt)
    nylon = dict(section=0.01, material="nylon", n_control_points=6)
    a = w.add_rod(sk.straight((0, 0, 0), (1, 0, 0), **nylon))
    b = w.add_rod(sk.straight((1.1, 0, 0), (2.1, 0, 0), **nylon))
    sk.clamp(w, a)
    link = w.add_link(a, b, sk.relative_distance(a.u_end, b.u_start, 0.1))
    w.set_breaking(link, f, policy="tension", averaging_time=tau)
    load = w.add_load(sk.point_force(b, b.u_end, (0, 0, 0)))
    for k in range(1, 10_000):
        w.set_load(load, sk.point_force(b, b.u_end, (r * k * dt, 0, 0)))
        broken = [e for e in w.step().events if e.kind == "ConstraintBroken"]
        if broken:
            return k * dt, broken[0].force
    raise AssertionError("the link never broke")


def test_averaged_breaking_lags_a_ramp_by_its_averaging_time():
    # Instantaneous: the link carries F = r t and lets go at t = f/r. The
    # moving average of a ramp from m = 0 is r (t − τ (1 − e^(−t/τ))), so
    # it reaches f at the root of that (0.1475 s here): within 2 steps.
    t0, f0 = _ramp_break_time(0.0)
    assert t0 == pytest.approx(0.1, abs=1.5e-3) and f0 == pytest.approx(10.0, rel=1e-3)
    tau = 0.05
    t = 0.15
    for _ in range(50):  # Newton on t − τ(1 − e^(−t/τ)) = f/r
        t -= (t - tau * (1 - math.exp(-t / tau)) - 0.1) / (1 - math.exp(-t / tau))
    t1, f1 = _ramp_break_time(tau)
    assert t1 == pytest.approx(t, abs=2e-3) and f1 == pytest.approx(10.0, rel=2e-2)
    w = sk.World()
    rod = w.add_rod(sk.straight((0, 0, 0), (1, 0, 0), section=0.01, material="nylon", n_control_points=6))
    pin = w.add_constraint(rod, sk.position(rod.u_start, (0, 0, 0)))
    with pytest.raises(sk.InvalidInputError, match="averaging time"):
        w.set_breaking(pin, 1.0, averaging_time=-1.0)
    with pytest.raises(sk.InvalidInputError, match="averaging_time needs"):
        w.set_breaking(pin, None, averaging_time=1.0)
    # |F| of a noisy force does not average down: refused.
    with pytest.raises(sk.InvalidInputError, match="policy magnitude"):
        w.set_breaking(pin, 1.0, averaging_time=1.0)


def test_thermal_duplex_keeps_its_bonds_with_averaged_breaking():
    # 25 °C in water at dt = 1 ps: the rigid bonds' instantaneous tensions
    # fluctuate by tens of pN, so 14 pN thresholds on them melt the duplex
    # at once; averaged over 1 ns (noise ~ √(h/2τ) of it) no pair breaks.
    def broken(tau):
        d = sk.dna.duplex("GATTACAGATTA", break_force_at=14.4, break_force_gc=28.6, break_averaging_time=tau)
        w = sk.World(units="molecular", dt=1e-3, viscosity=1.0, temperature=298.15, seed=11)
        w.insert(d.assembly)
        n = 0
        for _ in range(1500):
            n += sum(e.kind == "ConstraintBroken" and e.label.startswith("hbond") for e in w.step().events)
        return n

    assert broken(0.0) == 12  # all of them, at the first step
    assert broken(1.0) == 0


def test_averaged_break_measure_survives_a_snapshot():
    # Mid-ramp (the average below the threshold, the force above it), a
    # JSON round trip: both worlds break the link at the same step.
    w = sk.World(dt=1e-3)
    nylon = dict(section=0.01, material="nylon", n_control_points=6)
    a = w.add_rod(sk.straight((0, 0, 0), (1, 0, 0), **nylon))
    b = w.add_rod(sk.straight((1.1, 0, 0), (2.1, 0, 0), **nylon))
    sk.clamp(w, a)
    link = w.add_link(a, b, sk.relative_distance(a.u_end, b.u_start, 0.1))
    w.set_breaking(link, 10.0, policy="tension", averaging_time=0.05)
    w.add_load(sk.point_force(b, b.u_end, (0, 0, 0)))

    def ramp(world, k):
        rod = world.rods()[1]
        world.set_load(world.loads()[0], sk.point_force(rod, rod.u_end, (0.1 * k, 0, 0)))
        return any(e.kind == "ConstraintBroken" for e in world.step().events)

    for k in range(1, 121):
        assert not ramp(w, k)
    copy = sk.World.from_json(w.to_json())
    when = []
    for world in (w, copy):
        when.append(next(k for k in range(121, 400) if ramp(world, k)))
    assert when[0] == when[1] and when[0] > 130  # not at 101: the average lags
