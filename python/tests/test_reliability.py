"""Reliability regressions from ../shared/repro (the Rust side is in
tests/reliability.rs): a step never returns garbage — it runs, or stops
with a typed error leaving the world as it was."""
import numpy as np
import pytest

import strandkit as sk

L, R, NU = 1.0, 0.005, 0.5


def twisted_ring(tw, model="frenet", **world):
    """repro_twisted_ring_blowup.py: a ring with rest twist 2π Tw / L
    (Tw = 4.5 > Michell's 2.6), slightly perturbed out of plane."""
    rad = L / (2 * np.pi)
    mat = sk.Material("m", young=1 / (np.pi * R**4 / 4), poisson=NU, density=1 / (np.pi * R * R))  # EI = 1, μ = 1
    rod = sk.curve(lambda s: (rad * np.cos(s / rad), rad * np.sin(s / rad), 0.0), L, section=R, material=mat,
                   n_control_points=40, knots="periodic", model=model)
    rest = rod.strains()
    off = np.zeros_like(rest)
    off[:, 1:3] = -rest[:, 1:3]
    off[:, 3] = -rest[:, 3] + 2 * np.pi * tw / L
    rod.plastic_offsets = off
    q = rod.control_points.copy()
    phi = np.arctan2(q[:, 1], q[:, 0])
    q[:, 2] += 1e-5 * (np.cos(2 * phi) + np.sin(2 * phi))
    rod.control_points = q
    w = sk.World(dt=2e-4, **world)
    return w, w.add_rod(rod)


@pytest.mark.parametrize("adaptive", [False, True])
def test_over_twisted_ring_runs_or_stops_cleanly(adaptive):
    w, rod = twisted_ring(4.5, adaptive_dt=adaptive, max_halvings=4)
    e0 = rod.energy
    for k in range(3000):
        q, v, t = rod.control_points.copy(), rod.velocities.copy(), w.time
        try:
            w.step()
        except sk.DivergedError as e:
            # Refused: the world is exactly as before the step, and finite.
            assert e.rod == 0 and e.factor > w.params["divergence_factor"] and e.step > w.n_steps
            assert np.array_equal(rod.control_points, q) and np.array_equal(rod.velocities, v) and w.time == t
            assert np.isfinite(q).all()
            return
        # Accepted: finite, and the energy growth stays within what the
        # guard allows (its run-growth factor 10, at most twice over: the
        # blow-up without the guard reached 1e10 × initial).
        assert np.isfinite(rod.control_points).all()
        assert rod.energy <= 100 * e0, f"step {k}: energy {rod.energy / e0:.3e} × initial"
    # Ran to the end without blowing up.


def test_divergence_guard_bad_parameters():
    with pytest.raises(sk.InvalidInputError, match="divergence_factor"):
        sk.World(divergence_factor=0.5)
    with pytest.raises(sk.InvalidInputError, match="max_halvings"):
        sk.World(max_halvings=100)


def test_relax_reports_stability():
    """A clamped cantilever under a tip load is a stable equilibrium; a
    column straight under 1.03 P_cr is not (one unstable direction) —
    tests/reliability.rs checks the buckled branch too."""
    mat = sk.Material("m", young=1 / (np.pi * R**4 / 4), poisson=0.3, density=1.0)  # EI = 1
    for load, stable, k in ((-0.5, True, 0), (1.03, False, 1)):
        w = sk.World()
        rod = w.add_rod(sk.straight((0, 0, 0), (L, 0, 0), section=R, material=mat, n_control_points=20, with_roll=False))
        sk.clamp(w, rod, target=(0, 0, 0), direction=(1, 0, 0))
        w.add_constraint(rod, sk.plane(rod.u_end, (0, 0, 0), (0, 0, 1)))
        w.add_load(sk.point_force(rod, rod.u_end, (-load * np.pi**2 / 4, 0, 0)))
        report = w.relax()
        assert (report.stable, report.unstable_directions) == (stable, k), report


def test_relax_perturb_leaves_an_unstable_column_buckled():
    mat = sk.Material("m", young=1 / (np.pi * R**4 / 4), poisson=0.3, density=1.0)
    w = sk.World()
    rod = sk.straight((0, 0, 0), (L, 0, 0), section=R, material=mat, n_control_points=20, with_roll=False)
    q = rod.control_points.copy()
    q[:, 1] = 1e-6 * (1 - np.cos(np.pi * q[:, 0] / (2 * L)))
    rod.control_points = q
    rod = w.add_rod(rod)
    sk.clamp(w, rod, target=(0, 0, 0), direction=(1, 0, 0))
    w.add_constraint(rod, sk.plane(rod.u_end, (0, 0, 0), (0, 0, 1)))
    w.add_load(sk.point_force(rod, rod.u_end, (-1.03 * np.pi**2 / 4, 0, 0)))
    assert w.relax().stable is False
    report = w.relax(perturb=1e-3)
    assert report.stable is True
    assert abs(abs(rod.position(rod.u_end)[1]) - 0.30112) < 2e-3   # elastica tip deflection / L
    with pytest.raises(sk.InvalidInputError, match="perturb"):
        w.relax(perturb=-1.0)


def _snapshot_world():
    w = sk.World()
    a = w.add_rod(sk.straight((0, 0, 0), (1, 0, 0), n_control_points=8, section=0.01, material="nylon"))
    b = w.add_rod(sk.curve(lambda s: (1 + 0.3 * s, 0.2 * s, 0), 1.0, n_control_points=10, section=0.01,
                           material="nylon", with_roll=False))
    sk.clamp(w, a)
    w.add_link(a, b, sk.relative_distance(a.u_end, b.u_end, 0.5), break_force=1e3, tension_only=True)
    w.add_load(sk.point_torque(a, a.u_end, 1e-3))
    w.step()
    return w


def _rod(d, i=0):
    return d["world"]["rods"]["slots"][i]["item"]


@pytest.mark.parametrize("name, edit", [
    # repro/snapshot_panics.py and abort_snapshot_n_ctrl.py, on the versioned envelope.
    ("n_ctrl of 10**15", lambda d: _rod(d)["knots"].update(kind="Clamped", knots=[0.0] * 8, n_ctrl=10**15)),
    ("3 sections for 8 control points", lambda d: _rod(d).update(sections=_rod(d)["sections"][:3])),
    ("dofs 5", lambda d: _rod(d).update(dofs=5)),
    ("velocities one short", lambda d: _rod(d).update(v=_rod(d)["v"][:-1])),
    ("a link without multipliers", lambda d: next(s["item"] for s in d["world"]["constraints"]["slots"]
                                                  if s.get("item") and "RelativeDistance" in s["item"]["kind"]).update(multipliers=[])),
    ("point torque on the 3-DOF rod", lambda d: d["world"]["loads"]["slots"][0]["item"]["PointTorque"].update(
        rod={"index": 1, "generation": 0}, u=_rod(d, 1)["knots"]["knots"][-1])),
    ("negative Young's modulus", lambda d: _rod(d)["material"].update(young=-1e9)),
])
def test_corrupt_snapshots_are_refused_cleanly(name, edit):
    import json
    d = json.loads(_snapshot_world().to_json())
    edit(d)
    with pytest.raises(sk.StrandkitError):
        sk.World.from_json(json.dumps(d))


def test_arc_length_coordinates():
    """rod.arc_length(u) (rest) and rod.u_at_arc_length(s) are inverses;
    on a circular arc the point at s is at angle s/R."""
    rad = 0.3
    arc = lambda s: (rad * np.sin(s / rad), rad * (1 - np.cos(s / rad)), 0.0)  # noqa: E731
    rod = sk.curve(arc, 1.0, section=0.005, material="nylon", n_control_points=40)
    s = np.linspace(0, rod.rest_length, 11)
    u = rod.u_at_arc_length(s)
    np.testing.assert_allclose(rod.arc_length(u), s, atol=1e-12)
    np.testing.assert_allclose(rod.position(u), np.array([arc(x) for x in s]), atol=1e-6)
    assert isinstance(rod.u_at_arc_length(0.5), float)
    with pytest.raises(sk.InvalidInputError, match="arc length"):
        rod.u_at_arc_length(2.0)


def _squashed_ring(solver, hold):
    """repro_relax_spin_mode.py: a straight rod bent into a (squashed)
    circle, closed by relative position + orientation and clamped."""
    rad = L / (2 * np.pi)
    mat = sk.Material("m", young=1 / (np.pi * R**4 / 4), poisson=0.3, density=1.0)
    circ = sk.curve(lambda s: (rad * np.sin(s / rad), 1.15 * rad * (1 - np.cos(s / rad)), 0.0), L, section=R,
                    material=mat, n_control_points=40, with_roll=False)
    rod = sk.straight((0, 0, 0), (L, 0, 0), section=R, material=mat, n_control_points=40, with_roll=False)
    rod.control_points = circ.control_points
    w = sk.World(relax_max_iterations=2000)
    w.set_params(linear_solver=solver)
    rod = w.add_rod(rod)
    u0, u1 = rod.domain
    w.add_link(rod, rod, sk.relative_position(u0, u1))
    w.add_link(rod, rod, sk.relative_orientation(u0, u1))
    sk.clamp(w, rod)
    if hold:
        w.add_constraint(rod, sk.plane(0.5 * (u0 + u1), (0, 0, 0), (0, 0, 1)))
    return w, rod


@pytest.mark.parametrize("solver", ["Auto", "Band", "Sparse"])
def test_relax_names_a_free_spin_on_every_solver(solver):
    """The ring's spin about the clamp tangent is free (hidden at the start
    by the squashed shape's violation): every solver names it, and the
    world is left as it was; held by a plane, it relaxes to 2π² EI/L."""
    w, rod = _squashed_ring(solver, hold=False)
    q = rod.control_points.copy()
    with pytest.raises(sk.SingularError, match="rotation about x is held by no constraint"):
        w.relax()
    assert np.array_equal(rod.control_points, q)
    w, rod = _squashed_ring(solver, hold=True)
    rep = w.relax()
    assert rep.iterations < 50
    assert rod.elastic_energy == pytest.approx(2 * np.pi**2, rel=5e-4)


def test_material_frame_at_u_and_s():
    """The Frenet model's material frame of a helix (roll 0): d3 = tangent,
    d1 = principal normal (pointing to the axis), d2 = binormal; rows of a
    (3, 3) array, (m, 3, 3) for arrays; by abscissa or by rest arc length."""
    a, pitch = 0.1, 0.05
    rod = sk.helix(a, pitch, 2.0, section=0.005, material="nylon", n_control_points=60, model="frenet")
    s = np.linspace(0.1, 0.9, 5) * rod.rest_length
    f = rod.material_frame(s=s)
    assert f.shape == (5, 3, 3)
    np.testing.assert_allclose(np.einsum("mij,mkj->mik", f, f), np.broadcast_to(np.eye(3), (5, 3, 3)), atol=1e-14)
    u = rod.u_at_arc_length(s)
    np.testing.assert_allclose(rod.material_frame(u), f, atol=1e-15)
    np.testing.assert_allclose(f[:, 2], rod.tangent(u), atol=1e-14)
    p = rod.position(u)
    to_axis = -p[:, :2] / np.linalg.norm(p[:, :2], axis=1)[:, None]
    np.testing.assert_allclose(f[:, 0, :2], to_axis, atol=1e-4)
    assert rod.material_frame(u[0]).shape == (3, 3)
    with pytest.raises(sk.InvalidInputError, match="exactly one"):
        rod.material_frame(u[0], s=0.1)
    straight = sk.straight((0, 0, 0), (1, 0, 0), section=0.005, material="nylon", model="frenet")
    with pytest.raises(sk.SingularError, match="straight"):
        straight.material_frame(0.5 * sum(straight.domain))
    # The reference model (the default): the transported director, defined
    # on the straight rod too, orthonormal with d3 the tangent.
    ref = sk.straight((0, 0, 0), (1, 0, 0), section=0.005, material="nylon")
    g = ref.material_frame(0.5 * sum(ref.domain))
    np.testing.assert_allclose(g @ g.T, np.eye(3), atol=1e-14)
    np.testing.assert_allclose(g[2], [1.0, 0.0, 0.0], atol=1e-14)


def test_excess_link_on_a_ring():
    """An imposed excess link ΔLk on a circular ring with roll: twist ΔLk,
    writhe 0, link ΔLk, twist energy ½ GJ (2π ΔLk / L)² L; kept by a
    snapshot; refused on open rods and rings without roll."""
    rad = L / (2 * np.pi)
    mat = sk.Material("m", young=1 / (np.pi * R**4 / 4), poisson=NU, density=1.0)  # EI = 1, GJ = 1/(1+ν)
    ring = lambda **kw: sk.curve(lambda s: (rad * np.cos(s / rad), rad * np.sin(s / rad), 0.0), L, section=R,  # noqa: E731
                                 material=mat, n_control_points=40, knots="periodic", **kw)
    rod = ring()
    rod.excess_link = 1.5
    gj, ls = 1 / (1 + NU), rod.rest_length  # the spline ring's length (L to 1e-6)
    assert rod.elastic_energy == pytest.approx(0.5 * gj * (2 * np.pi * 1.5 / ls) ** 2 * ls, rel=1e-12)
    assert rod.twist() == pytest.approx(1.5, abs=1e-12)
    assert abs(rod.writhe()) < 1e-12
    assert rod.link() == pytest.approx(1.5, abs=1e-12)
    w = sk.World()
    h = w.add_rod(rod)
    back = sk.World.from_json(w.to_json())
    assert back.rods()[0].excess_link == 1.5
    with pytest.raises(sk.InvalidInputError, match="closed rod"):
        sk.straight((0, 0, 0), (1, 0, 0), section=R, material=mat).excess_link = 1.0
    with pytest.raises(sk.InvalidInputError, match="roll"):
        ring(with_roll=False).excess_link = 1.0
    with pytest.raises(sk.InvalidInputError):
        h.excess_link = float("nan")
    assert h.excess_link == 1.5
