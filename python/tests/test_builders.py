"""strandkit.builders (issue 12): the rope bridge from Python — built,
inserted, relaxed, read by group; bad input refused naming the argument."""
import numpy as np
import pytest

import strandkit as sk

G = 9.81


def test_rope_bridge_relaxes_and_reads_by_group():
    bridge = sk.builders.rope_bridge(span=6.0, n_planks=5, plank_mass=3.0, sag=0.6)
    assert "n_planks=5" in repr(bridge)
    w = sk.World(gravity=(0, -G, 0))
    ins = w.insert(bridge.assembly)
    w.relax()
    # Two pins per plank, each carrying half a plank's weight (the ropes
    # pull along the span, the planks hang straight down from them).
    pins = w.group("plank").forces
    assert pins.shape == (10, 3)
    np.testing.assert_allclose(np.linalg.norm(pins, axis=1), 0.5 * 3.0 * G, rtol=1e-3)
    # The anchors carry the whole weight.
    weight = sum(r.mass for r in w.rods()) * G
    assert w.group("anchor").forces[:, 1].sum() == pytest.approx(weight, rel=1e-9)
    assert len(bridge.stations) == 5 and len(bridge.planks) == 5 and len(ins.rods) == 4 + 5


def test_rope_bridge_bad_input_names_the_argument():
    with pytest.raises(sk.InvalidInputError, match="span"):
        sk.builders.rope_bridge(span=-1.0)
    with pytest.raises(sk.InvalidInputError, match="n_planks"):
        sk.builders.rope_bridge(n_planks=80)
    with pytest.raises(sk.InvalidInputError, match="n_planks"):
        sk.builders.rope_bridge(n_planks=-3)
    with pytest.raises(sk.InvalidInputError, match="plank_break_force"):
        sk.builders.rope_bridge(plank_break_force=0.0)
    with pytest.raises(sk.InvalidInputError, match="bending_stifness|accepted"):
        sk.builders.rope_bridge(rope={"bending_stifness": 1.0})
    with pytest.raises(sk.InvalidInputError, match="plank_model"):
        sk.builders.rope_bridge(plank_model="steel")


def test_necklace_one_bead_matches_the_reference():
    """SPEC §9.4 from Python: one frictionless 0.1 kg bead on a light 1.2 m
    string between level supports 1 m apart: 56.44° from the vertical,
    tension 0.8874 N, sag 0.3317 m, within 0.5 %."""
    one = sk.builders.necklace(n_beads=1, bead_mass=0.1, bead_radius=0.01, length=1.2, closed=False,
                               hang="two_points", supports=((0, 0, 0), (1, 0, 0)), friction=0.0,
                               string=dict(linear_density=1e-7, axial_stiffness=1e4, bending_stiffness=5.5e-6),
                               control_points=1001)
    w = sk.World(gravity=(0, -G, 0), relax_max_iterations=3000)
    ins = w.insert(one.assembly)
    w.relax()
    f = w.group("support").forces
    theta = np.degrees(np.arctan2(np.abs(f[:, 0]), np.abs(f[:, 1])))
    np.testing.assert_allclose(theta, 56.44, rtol=5e-3)
    np.testing.assert_allclose(np.linalg.norm(f, axis=1), 0.8874, rtol=5e-3)
    assert -ins.beads[0].position[1] == pytest.approx(0.3317, rel=5e-3)


def test_necklace_over_a_peg_swings_down_and_keeps_its_beads():
    n = sk.builders.necklace()
    assert "n_beads=12" in repr(n) and "hang='peg'" in repr(n)
    w = sk.World(gravity=(0, -G, 0), dt=8e-4)
    ins = w.insert(n.assembly)
    e0 = w.energy()["total"]
    for _ in range(400):
        w.step()
    e = w.energy()
    assert e["total"] < e0 and set(e) == {"kinetic", "elastic", "external", "total"}
    assert len(w.beads()) == 12 and len(w.group("bead").beads) == 12
    # Knotted beads do not slide.
    k = sk.builders.necklace(knotted=True, hang="two_points", supports=((-0.05, 0, 0), (0.05, 0, 0)))
    w2 = sk.World(gravity=(0, -G, 0), dt=8e-4)
    ins2 = w2.insert(k.assembly)
    u0 = [repr(b) for b in ins2.beads]
    for _ in range(50):
        w2.step()
    assert [repr(b) for b in ins2.beads] == u0 and "fixed" in u0[0]


@pytest.mark.parametrize("bad,name", [
    (dict(n_beads=60), "n_beads"), (dict(n_beads=-1), "n_beads"), (dict(bead_mass=float("nan")), "bead_mass"),
    (dict(hang="nail"), "hang"), (dict(closed=False), "hang"), (dict(string=dict(colour=1)), "colour"),
    (dict(hang="two_points", supports=((0, 0, 0), (1, 0, 0))), "support distance"),
])
def test_necklace_bad_input_names_the_argument(bad, name):
    with pytest.raises(sk.InvalidInputError, match=name):
        sk.builders.necklace(**bad)


def test_beads_on_spring_slide_off_and_a_bead_on_a_rigid_helix_reaches_its_terminal_speed():
    spring = sk.builders.beads_on_spring()
    assert "close_coiled_rate" in repr(spring) and len(spring.beads) == 4
    w = sk.World(gravity=(0, -G, 0), dt=1e-3)
    ins = w.insert(spring.assembly)
    left = []
    for _ in range(2000):
        left += [e for e in w.step().events if e.kind == "BeadLeft"]
    assert [e.bead for e in left] == ins.beads  # all leave, bead[0] first
    assert ins.rods[0].model == "reference"  # the rods' default
    # The thesis' Frenet model on request: the same scene, the same sequence.
    frenet = sk.builders.beads_on_spring(model="frenet")
    w = sk.World(gravity=(0, -G, 0), dt=1e-3)
    ins = w.insert(frenet.assembly)
    assert ins.rods[0].model == "frenet"
    left = []
    for _ in range(2000):
        left += [e for e in w.step().events if e.kind == "BeadLeft"]
    assert [e.bead for e in left] == ins.beads
    # A thick wire (rigid track), viscous friction c: speed m g sin α / c.
    stiff = sk.builders.beads_on_spring(wire_radius=4e-3, pitch=0.03, n_beads=1, bead_mass=1e-3, friction=0.05)
    w = sk.World(gravity=(0, -G, 0), dt=1e-3)
    ins = w.insert(stiff.assembly)
    for _ in range(300):
        w.step()
    terminal = 1e-3 * G * np.sin(stiff.helix_angle) / 0.05
    assert ins.beads[0].velocity == pytest.approx(terminal, rel=0.02)


def test_cable_on_clips_is_inserted_clipped_and_pulls_out_above_the_resistance():
    cable = sk.builders.cable_on_clips()
    w = sk.World(gravity=(0, -G, 0))
    ins = w.insert(cable.assembly)
    assert all(c.held is not None for c in ins.clips) and len(ins.clips) == 4
    w.relax()
    weight = sum(r.mass for r in w.rods()) * G
    carried = w.group("clip").forces[:, 1].sum() + w.group("connector[0]").forces[:, 1].sum()
    assert carried == pytest.approx(weight, rel=1e-6)
    # Pull the free end out of the door (+z) well past what the last clip holds.
    rod = ins.rods[cable.cable]
    w.add_load(sk.point_force(rod, rod.u_end, (0, 0, 30.0)))
    released = w.relax().events
    assert [e.kind for e in released] == ["ClipReleased"] and released[0].force > 20.0
    assert released[0].clip == ins.clips[3]


def test_harness_branches_balance_and_bad_input():
    h = sk.builders.harness()
    w = sk.World(gravity=(0, -G, 0))
    ins = w.insert(h.assembly)
    w.relax()
    # A leaf branch: its junction and its connector carry its weight.
    leaf = ins.rods[h.branches[4]]
    (main, other, pos, _orient) = h.junctions[1][1]
    assert other == 4
    junction = -np.asarray(ins.constraints[pos].reaction().force)  # rod b gets −Λ
    connector = w.group("connector[3]").forces.sum(axis=0)
    np.testing.assert_allclose(junction + connector, [0, leaf.mass * G, 0], atol=1e-9 * leaf.mass * G + 1e-15)
    with pytest.raises(sk.InvalidInputError, match="junctions"):
        sk.builders.harness(junctions=[[(0, "start"), (1, "end"), (2, "end")], [(0, "end"), (3, "start")]])
    with pytest.raises(sk.InvalidInputError, match='"middle"'):
        sk.builders.harness(connectors=[(1, "middle")])


@pytest.mark.parametrize("builder, bad, name", [
    ("beads_on_spring", dict(pitch=1e-4), "pitch"),
    ("beads_on_spring", dict(n_beads=-1), "n_beads"),
    ("beads_on_spring", dict(model="bishop"), "model"),
    ("cable_on_clips", dict(clip_positions=[(5.0, 5.0, 5.0)]), r"clip_positions\[0\]"),
    ("cable_on_clips", dict(path=[(0, 0, 0)]), "path"),
    ("harness", dict(radii=[0.003]), "radii"),
])
def test_cable_and_spring_bad_input_names_the_argument(builder, bad, name):
    with pytest.raises(sk.InvalidInputError, match=name):
        getattr(sk.builders, builder)(**bad)
