"""The Python API around the core: handles, reprs, kinds, loads, events, recorder."""
import numpy as np
import pytest

import strandkit as sk


def test_world_parameters_and_repr():
    w = sk.World(dt=2e-3, gravity=(0, 0, -9.81), relax_max_iterations=100)
    assert w.dt == 2e-3 and list(w.gravity) == [0, 0, -9.81]
    w.set_params(relax_tolerance=1e-9)
    assert w.params["relax_tolerance"] == 1e-9
    w.gravity = [0, -1, 0]
    assert "World(time=0" in repr(w)


def test_rod_views_are_live_and_handles_work():
    w = sk.World(dt=1e-3, gravity=(0, -9.81, 0))
    rod = sk.straight((0, 0, 0), (1, 0, 0), section=0.01, material="nylon", n_control_points=10)
    assert "free" in repr(rod) and rod.world is None
    same = w.add_rod(rod)
    assert same is rod and rod.world is w and rod.handle == (0, 0)
    assert w.rods()[0] == rod and w.n_rods == 1
    c = w.add_constraint(rod, sk.position(rod.u_start))
    assert "Position" in repr(c) and c.alive
    y0 = rod.position(rod.u_end)[1]
    w.step()
    assert rod.position(rod.u_end)[1] < y0  # the view follows the world
    assert rod.velocities.shape == (10, 4)
    assert rod.rest_length == pytest.approx(1.0)
    assert rod.mass == pytest.approx(np.pi * 0.01**2 * 1100.0)
    assert rod.energy == pytest.approx(rod.elastic_energy + rod.kinetic_energy)
    w.remove_constraint(c)
    assert not c.alive and "removed" in repr(c)


def test_builders():
    kw = dict(section=sk.Section.ellipse(0.02, 0.01), material=sk.Material.preset("copper"))
    h = sk.helix(0.5, 0.2, 3.0, n_control_points=30, **kw)
    assert h.rest_length == pytest.approx(3 * np.hypot(2 * np.pi * 0.5, 0.2), rel=1e-3)
    c = sk.curve(lambda s: (np.cos(s), np.sin(s), 0.0), np.pi, **kw)
    assert c.position(c.u_end) == pytest.approx([-1, 0, 0], abs=1e-6)
    pts = np.column_stack([np.linspace(0, 1, 7), np.zeros(7), np.zeros(7)])
    t = sk.through_points(pts, with_roll=False, **kw)
    assert t.dofs == 3 and t.n_control_points == 7
    q = np.column_stack([pts, np.linspace(0, 1, 7)])
    f = sk.from_control_points(q, knots="uniform", **kw)
    assert f.knots == "uniform" and f.control_points[:, 3] == pytest.approx(q[:, 3])
    ring = sk.curve(lambda s: (np.cos(s), np.sin(s), 0.0), 2 * np.pi, knots="periodic", n_control_points=16, **kw)
    assert ring.knots == "periodic"
    with pytest.raises(ZeroDivisionError):
        sk.curve(lambda s: 1 / 0, 1.0, **kw)
    assert sk.rod_from_json(h.to_json()).control_points.tobytes() == h.control_points.tobytes()
    assert "circle" in repr(sk.Section.circle(0.1)) and sk.Section.circle(0.1).area == pytest.approx(np.pi * 0.01)
    assert "copper" in sk.Material.presets()


def test_geometric_constraints_and_loads():
    w = sk.World(dt=1e-2, gravity=(0, -9.81, 0))
    rod = w.add_rod(sk.straight((0, 0, 0), (1, 0, 0), section=0.005, material="nylon", n_control_points=8,
                                with_roll=False))
    w.add_constraint(rod, sk.position(rod.u_start))
    w.add_constraint(rod, sk.plane(rod.u_end, origin=(0, 0, 0), normal=(0, 0, 1)))
    d = w.add_constraint(rod, sk.distance(rod.u_end, point=(0, 0, 0), distance=1.0))
    load = w.add_load(sk.point_force(rod, rod.u_end, (0, -0.01, 0)))
    for _ in range(50):
        w.step()
    tip = rod.position(rod.u_end)
    # Plane and distance rows are linearised each step: drift stays tiny.
    assert abs(tip[2]) < 1e-9 and np.linalg.norm(tip) == pytest.approx(1.0, abs=1e-3)
    assert d.multipliers.shape == (1,)

    def tip_after(world, steps=5):
        for _ in range(steps):
            world.step()
        return world.rods()[0].position(rod.u_end)

    # set_load acts like removing the load and adding the new one (another path).
    ref = w.copy()
    ref.remove_load(ref.loads()[0])
    ref.add_load(sk.point_force(ref.rods()[0], rod.u_end, (0, -0.02, 0)))
    w.set_load(load, sk.point_force(rod, rod.u_end, (0, -0.02, 0)))
    assert load.force == [0.0, -0.02, 0.0] and ref.loads()[0].force == load.force
    np.testing.assert_array_equal(tip_after(w), tip_after(ref))
    # remove_load acts like a zero force, and the handle is dead.
    ref = w.copy()
    ref.set_load(ref.loads()[0], sk.point_force(ref.rods()[0], rod.u_end, (0, 0, 0)))
    w.remove_load(load)
    assert w.loads() == [] and not load.alive
    np.testing.assert_allclose(tip_after(w), tip_after(ref), rtol=1e-13, atol=1e-15)
    # A moving target: the tip is pulled from 1 to the new distance (the
    # linearised rows leave a drift of ~1e-4 while the rod swings).
    w.set_constraint(d, sk.distance(rod.u_end, point=(0, 0, 0), distance=0.99))
    assert d.kind["Distance"]["distance"] == 0.99
    assert np.linalg.norm(tip_after(w, 50)) == pytest.approx(0.99, abs=5e-4)
    with pytest.raises(ValueError):
        w.set_constraint(d, sk.plane(rod.u_end, origin=(0, 0, 0), normal=(0, 1, 0)))
    assert d.kind["Distance"]["distance"] == 0.99  # the refused change left it as it was


def test_breaking_reports_an_event():
    w = sk.World(dt=1e-3, gravity=(0, -9.81, 0))
    rod = w.add_rod(sk.straight((0, 0, 0), (1, 0, 0), section=0.01, material="nylon", n_control_points=8,
                                with_roll=False))
    c = w.add_constraint(rod, sk.distance(rod.u_start, point=(0, 0.1, 0), distance=0.1),
                         break_force=0.5, tension_only=True)
    rec = sk.Recorder(w).reaction("link", c)
    report, events = sk.run(w, 50, progress_bar=False, callback=lambda w, r: rec.record(r))
    assert len(events) == 1 and events[0].kind == "ConstraintBroken"
    e = events[0]
    assert e.constraint == c and e.force > 0.5 and e.time > 0
    assert not c.alive
    assert len(rec.events) == 1 and rec.events[0]["kind"] == "ConstraintBroken"


def test_recorder_csv(tmp_path):
    w = sk.World(dt=1e-3, gravity=(0, -9.81, 0))
    rod = w.add_rod(sk.straight((0, 0, 0), (1, 0, 0), section=0.01, material="nylon", n_control_points=8))
    a, _ = sk.clamp(w, rod)
    rec = sk.Recorder(w, every=5).point("tip", rod, rod.u_end).reaction("clamp", a).extension("ext", rod)
    rec.run(20, progress_bar=False)
    assert len(rec) == 5 and rec["tip"].shape == (5, 3) and rec["clamp"].shape == (5, 6)
    path = rec.to_csv(str(tmp_path / "r.csv"))
    lines = open(path).read().splitlines()
    assert lines[0].split(",")[:3] == ["time", "step", "elastic_energy"]
    assert "tip_y" in lines[0] and "clamp_fy" in lines[0] and len(lines) == 6
    # Weight is carried by the clamp after damping-free motion starts: force along +y.
    assert rec["clamp"][-1, 1] > 0


def test_relative_distance_link_pulls_two_cantilevers_together():
    """Two clamped rods (L = 1 m, 0.1 m apart) whose tips a link holds
    0.05 m apart: each tip deflects δ = 0.025 m, so the link carries the
    cantilever force 3 E I δ / L³ (linear theory; the geometric correction
    is ~(δ/L)²) and each tip moves back by 3δ²/(5L)."""
    w = sk.World()
    a, b = (w.add_rod(sk.straight((0, y, 0), (1, y, 0), section=0.01, material="nylon", n_control_points=6,
                                  with_roll=False)) for y in (0.0, 0.1))
    clamp_a, clamp_b = w.clamp(a)[0], w.clamp(b)[0]
    link = w.add_link(a, b, sk.relative_distance(a.u_end, b.u_end, 0.05))
    assert "RelativeDistance" in repr(link) and link.rod == a and link.other == b
    w.relax()
    pa, pb = a.position(a.u_end), b.position(b.u_end)
    assert np.linalg.norm(pb - pa) == pytest.approx(0.05, abs=1e-12)
    delta = 0.025
    ei = a.material.young * np.pi * 0.01**4 / 4
    assert pa[1] == pytest.approx(delta, abs=1e-12) and pb[1] == pytest.approx(0.1 - delta, abs=1e-12)
    assert link.tension == pytest.approx(3 * ei * delta, rel=5e-3)
    assert 1 - pa[0] == pytest.approx(3 * delta**2 / 5, rel=1e-2)
    # The link pulls a towards b; each clamp holds its rod back with the same force.
    np.testing.assert_allclose(link.reaction().force, [0, link.tension, 0], atol=1e-9)
    np.testing.assert_allclose(clamp_a.reaction().force, [0, -link.tension, 0], atol=1e-9)
    np.testing.assert_allclose(clamp_b.reaction().force, [0, link.tension, 0], atol=1e-9)


def test_beads_and_sliding_points():
    w = sk.World(dt=1e-3, gravity=(0, -9.81, 0))
    rod = w.add_rod(sk.straight((0, 0, 0), (1, 0, 0), section=0.002, material="nylon", n_control_points=20,
                                with_roll=False))
    w.add_constraint(rod, sk.position(rod.u_start))
    w.add_constraint(rod, sk.position(rod.u_end, (1, 0, 0)))
    u0, u1 = rod.domain
    bead = w.add_bead(rod, 0.5 * (u0 + u1), mass=0.01, friction=0.1, radius=0.005)
    assert bead.rod == rod and bead.mass == 0.01 and "BeadHandle" in repr(bead)
    w.set_bead_force(bead, (0.05, 0, 0))
    for _ in range(20):
        w.step()
    assert bead.u > 0.5 * (u0 + u1) and bead.velocity > 0  # pushed along +x
    assert bead.position[1] < 0
    with pytest.raises(ValueError, match="bead mass must be finite and > 0"):
        w.add_bead(rod, u0, mass=-1.0)
    ring = w.add_constraint(rod, sk.sliding_point(0.3 * (u0 + u1), rod.position(0.3 * (u0 + u1))))
    w.step()
    assert "SlidingPoint" in ring.kind and np.isfinite(ring.kind["SlidingPoint"]["u"])


def test_slider_leaving_the_rod_is_an_event_with_a_live_handle():
    w = sk.World(dt=1e-3, gravity=(0, -9.81, 0))
    rope = w.add_rod(sk.straight((0, 0, 0), (0, -0.2, 0), section=0.002, material="nylon", n_control_points=8,
                                 with_roll=False))
    u0, u1 = rope.domain
    s = w.add_constraint(rope, sk.sliding_point(u0 + 0.01 * (u1 - u0), (0.0, -0.002, 0.0)))
    _, events = sk.run(w, 2000, progress_bar=False)
    assert [e.kind for e in events] == ["SliderLeft"]
    assert events[0].constraint == s and not s.alive
    assert "SliderLeft" in repr(events[0])
    assert rope.velocities[:, 1].mean() < 0


def test_world_takes_every_integration_parameter_by_keyword():
    defaults = sk.World().params
    assert set(defaults) >= {"dt", "gravity", "parallel", "relax_tolerance", "relax_max_iterations",
                             "plastic_tolerance", "linear_solver"}
    w = sk.World(**dict(defaults, plastic_tolerance=1e-5, linear_solver="BandLu", parallel=False))
    assert w.params == dict(defaults, plastic_tolerance=1e-5, linear_solver="BandLu", parallel=False)
    with pytest.raises(sk.InvalidInputError, match="unknown integration parameter") as e:
        sk.World(dtt=1.0)
    assert all(k in e.value.expected for k in defaults)
    with pytest.raises(sk.InvalidInputError, match="linear_solver"):
        sk.World(linear_solver="Cholesky")
    w.set_params(dt=5e-3)
    w.set_params(dt=None)  # None: back to the default
    assert w.dt == defaults["dt"] and w.params["parallel"] is False
    with pytest.raises(sk.InvalidInputError, match="dt must be finite and > 0"):
        w.set_params(dt=0.0)
    assert w.dt == defaults["dt"]  # unchanged by the rejected call


def test_quasi_dynamic_and_rod_options_by_keyword():
    w = sk.World()
    w.add_rod(sk.straight((0, 0, 0), (1, 0, 0), section=0.01, material="nylon"))
    qd = sk.QuasiDynamic(w, dt0=2e-3, newton_fraction=0.5)
    assert qd.params["dt0"] == 2e-3 and qd.params["newton_fraction"] == 0.5 and qd.params["time_budget"] is None
    with pytest.raises(sk.InvalidInputError, match="unknown quasi-dynamic parameter") as e:
        sk.QuasiDynamic(w, budget=1.0)
    assert "time_budget" in e.value.expected
    rod = sk.straight((0, 0, 0), (1, 0, 0), section=0.01, material="nylon", model="frenet", drag=0.5, twist=False,
                      samples_per_segment=3)
    o = rod.options
    assert rod.model == "frenet" and o["drag"] == 0.5 and o["samples_per_segment"] == 3
    assert o["terms"] == {"stretch": True, "bend": True, "twist": False}
    # Any RodOptions field also by name, including a partial dict for a struct field.
    assert sk.straight((0, 0, 0), (1, 0, 0), section=0.01, material="nylon",
                       terms={"bend": False}).options["terms"] == {"stretch": True, "bend": False, "twist": True}
    with pytest.raises(sk.InvalidInputError, match="rod option"):
        sk.straight((0, 0, 0), (1, 0, 0), section=0.01, material="nylon", model="cosserat")
    with pytest.raises(sk.InvalidInputError, match='unknown rod option "bogus"'):
        sk.straight((0, 0, 0), (1, 0, 0), section=0.01, material="nylon", bogus=1)
    with pytest.raises(sk.InvalidInputError, match="samples_per_segment"):
        sk.straight((0, 0, 0), (1, 0, 0), section=0.01, material="nylon", samples_per_segment=9)


def test_handles_read_fields_through_serde_and_check_ownership():
    w = sk.World(gravity=(0, -9.81, 0))
    rod = w.add_rod(sk.straight((0, 0, 0), (1, 0, 0), section=0.01, material="nylon", n_control_points=8,
                                with_roll=False))
    c = w.add_constraint(rod, sk.distance(rod.u_start, (0, 0.1, 0), 0.1), compliance=1e-3, break_force=9.0,
                         tension_only=True, label="hanger[0]")
    assert c.compliance == 1e-3 and c.breaking == {"force": 9.0, "policy": "tension"}
    assert c.rod == rod and c.other is None and c.label == "hanger[0]"
    assert c._handle == ("constraint", c.index, c.generation) and c.world is w
    assert {"compliance", "breaking", "kind", "rod"} <= set(dir(c))
    d = c.to_dict()
    assert d["rod"] == rod and d["kind"]["Distance"]["distance"] == 0.1
    assert 'ConstraintHandle(0 "hanger[0]": Distance(' in repr(c) and "breaks above 9 (tension)" in repr(c)
    load = w.add_load(sk.point_force(rod, rod.u_end, (0, -1, 0)))
    assert load.u == rod.u_end and load.force == [0.0, -1.0, 0.0] and list(load.kind) == ["PointForce"]
    w.step()
    assert c.tension == w.tension(c) and c.tension > 0  # the hanger pulls
    # Equal and hashable by (world, handle); a copy of the world is another world.
    same = w.constraints()[0]
    assert same == c and hash(same) == hash(c) and len({c, same, load}) == 2
    w2 = w.copy()
    c2 = w2.constraints()[0]
    assert c2 != c and c2.index == c.index
    with pytest.raises(sk.InvalidInputError, match="belongs to another world"):
        w2.remove_constraint(c)
    with pytest.raises(sk.InvalidInputError, match="belongs to another world"):
        w2.set_load(load, sk.point_force(w2.rods()[0], 0.0, (0, 1, 0)))
    with pytest.raises(AttributeError, match="no attribute 'nothing'"):
        c.nothing
    w.remove_constraint(c)
    assert not c.alive and "removed" in repr(c) and c.label == "hanger[0]"
    with pytest.raises(sk.InvalidHandleError):
        c.compliance
    with pytest.raises(sk.InvalidInputError, match="needs break_force"):
        w.add_link(rod, rod, sk.relative_distance(rod.u_start, rod.u_end, 1.0), policy="tension")


def test_break_policies_on_world_constraints():
    w = sk.World()
    rod = w.add_rod(sk.straight((0, 0, 0), (1, 0, 0), section=0.01, material="nylon", n_control_points=8,
                                with_roll=False))
    pos = w.add_constraint(rod, sk.position(rod.u_start))
    dist = w.add_constraint(rod, sk.distance(rod.u_end, (1, 0.1, 0), 0.1))
    w.set_breaking(dist, 2.0, policy="compression")
    assert dist.breaking == {"force": 2.0, "policy": "compression"}
    w.set_breaking(dist, 3.0, tension_only=True)
    assert dist.breaking["policy"] == "tension"
    w.set_breaking(dist)
    assert dist.breaking is None
    with pytest.raises(sk.InvalidInputError, match="no line of action"):
        w.set_breaking(pos, 1.0, policy="tension")
    with pytest.raises(sk.InvalidInputError, match="contradicts"):
        w.set_breaking(dist, 1.0, policy="compression", tension_only=True)
    with pytest.raises(sk.InvalidInputError, match="policy"):
        w.set_breaking(dist, 1.0, policy="shear")
    assert pos.breaking is None and w.tension(pos) is None


def test_clamp_follows_the_frame_model():
    w = sk.World()
    straight = w.add_rod(sk.straight((0, 0, 0), (1, 0, 0), section=0.01, material="nylon"))
    helix = w.add_rod(sk.helix(0.2, 0.1, 1.0, section=0.01, material="nylon", model="frenet"))
    ref_helix = w.add_rod(sk.helix(0.2, 0.1, 1.0, section=0.01, material="nylon"))
    no_roll = w.add_rod(sk.straight((0, 1, 0), (1, 1, 0), section=0.01, material="nylon", with_roll=False))
    kinds = lambda hs: [next(iter(h.kind)) for h in hs]  # noqa: E731
    s = sk.clamp(w, straight)
    assert kinds(s) == ["Position", "Tangent"] and s[0].kind["Position"]["axes"] == [True] * 4
    h = sk.clamp(w, helix)
    assert kinds(h) == ["Position", "Tangent", "MaterialRoll"] and h[0].kind["Position"]["axes"][3] is False
    # The reference model (the default) holds the section by θ, curved or not.
    assert ref_helix.model == "reference" and no_roll.model == "frenet"
    r = sk.clamp(w, ref_helix)
    assert kinds(r) == ["Position", "Tangent"] and r[0].kind["Position"]["axes"] == [True] * 4
    n = w.clamp(no_roll, no_roll.u_end, compliance=1e-6)
    assert kinds(n) == ["Position", "Tangent"] and n[0].compliance == 1e-6
    np.testing.assert_allclose(n[0].kind["Position"]["target"][:3], no_roll.position(no_roll.u_end))
    # Explicit target / direction: position + tangent where asked.
    e = sk.clamp(w, straight, straight.u_end, target=(1, 0, 0), direction=(1, 0, 0))
    assert kinds(e) == ["Position", "Tangent"] and e[1].kind["Tangent"]["direction"] == [1.0, 0.0, 0.0]
    assert w.relax().violation < 1e-8


def test_an_empty_world_steps():
    # Nothing to move: the divergence guard's 0/0 once refused it as Diverged (NaN).
    w = sk.World(dt=2e-3)
    for _ in range(3):
        w.step()
    assert w.n_steps == 3 and abs(w.time - 6e-3) < 1e-15
