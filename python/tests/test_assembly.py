"""Assemblies built in Python, inserted in one batch, and group queries on
what they labelled (forces, tensions, positions, broken flags, events)."""
import json

import numpy as np
import pytest

import strandkit as sk

G = 9.81


def rail(y, n=10):
    return sk.straight((0, y, 0), (1, y, 0), section=0.005, material="nylon", n_control_points=n, with_roll=False)


def cantilever_ladder(break_force=None, policy="magnitude", rungs=4):
    """Rail 0 clamped at x = 0; rail 1, 0.1 below, held only by welded rungs
    (relative positions with an offset) labelled rung[i]."""
    asm = sk.Assembly()
    a = asm.add_rod(rail(0.0), "rail[0]")
    b = asm.add_rod(rail(-0.1), "rail[1]")
    u0, u1 = asm.rod(a).domain
    asm.constrain(a, sk.position(u0, (0, 0, 0)), label="support[0]")
    asm.constrain(a, sk.tangent(u0, (1, 0, 0)), label="support[1]")
    us = [u0 + (u1 - u0) * (i + 1) / rungs for i in range(rungs)]
    for i, u in enumerate(us):
        asm.link(a, b, sk.relative_position(u, u, (0, 0.1, 0)), break_force=break_force, policy=policy,
                 label=f"rung[{i}]")
    return asm, us


def hanging_ladder(break_force=None, policy="magnitude", rungs=4):
    """Rail 0 pinned at both ends; rail 1 hangs 0.1 below it from
    relative_distance rungs (in tension under gravity) labelled rung[i]."""
    asm = sk.Assembly()
    a = asm.add_rod(rail(0.0), "rail[0]")
    b = asm.add_rod(rail(-0.1), "rail[1]")
    u0, u1 = asm.rod(a).domain
    asm.constrain(a, sk.position(u0, (0, 0, 0)), label="support[0]")
    asm.constrain(a, sk.position(u1, (1, 0, 0)), label="support[1]")
    for i in range(rungs):
        u = u0 + (u1 - u0) * (i + 0.5) / rungs
        asm.link(a, b, sk.relative_distance(u, u, 0.1), break_force=break_force, policy=policy, label=f"rung[{i}]")
    return asm


def test_assembly_builds_and_prints():
    asm, _ = cantilever_ladder(break_force=5.0, policy="tension")
    assert (asm.n_rods, asm.n_constraints, asm.n_loads, asm.n_beads) == (2, 6, 0, 0)
    assert asm.groups == ["rail", "rung", "support"]
    assert asm.labels[:3] == ["rail[0]", "rail[1]", "support[0]"]
    assert repr(asm) == "Assembly(rods=2, constraints=6, loads=0, beads=0, groups=['rail', 'rung', 'support'])"
    c = asm.constraint(2)
    assert c["rod"] == 0 and c["other"] == 1 and c["label"] == "rung[0]"
    assert c["breaking"] == {"force": 5.0, "policy": "tension"}
    assert c["kind"]["RelativePosition"]["offset"] == [0.0, 0.1, 0.0, 0.0]
    load = asm.add_load(1, sk.point_force(None, 5.0, (0, -1, 0)), label="pull")
    bead = asm.add_bead(1, 2.5, mass=1e-3, friction=0.1, label="ring[0]")
    assert (load, bead, asm.n_loads, asm.n_beads) == (0, 0, 1, 1)
    assert asm.groups == ["pull", "rail", "ring", "rung", "support"]


def test_insert_returns_live_objects_and_groups_answer():
    asm, us = cantilever_ladder()
    w = sk.World(gravity=(0, -G, 0))
    ins = w.insert(asm)
    assert len(ins.rods) == 2 and len(ins.constraints) == 6 and ins.loads == [] and ins.beads == []
    assert ins.bandwidth > 0 and "Inserted(rods=2, constraints=6" in repr(ins)
    a, b = ins.rods
    assert a.label == "rail[0]" and b.label == "rail[1]" and a.world is w
    assert (w.n_rods, w.n_constraints) == (2, 6)
    assert w.groups == ["rail", "rung", "support"]
    report = w.relax()
    assert report.violation < 1e-8

    g = w.group("rung")
    assert len(g) == 4 and g.name == "rung"
    assert g.labels == [f"rung[{i}]" for i in range(4)]
    assert g.constraints == ins.constraints[2:]
    # The group's arrays are the handles' reactions, tensions and points.
    assert g.forces.shape == (4, 3) and g.torques.shape == (4, 3)
    np.testing.assert_array_equal(g.forces, [h.reaction().force for h in ins.constraints[2:]])
    np.testing.assert_array_equal(g.torques, [h.reaction().torque for h in ins.constraints[2:]])
    np.testing.assert_array_equal(g.tensions, [w.tension(h) for h in ins.constraints[2:]])
    np.testing.assert_allclose(g.positions, a.position(np.array(us)), rtol=0, atol=1e-15)
    for m, h in zip(g.multipliers, ins.constraints[2:]):
        np.testing.assert_array_equal(m, h.multipliers)
    # Rail 1 hangs on the rungs only: their vertical forces on rail 0 carry its weight.
    assert g.forces[:, 1].sum() == pytest.approx(-b.mass * G, rel=1e-9)
    assert g.alive.all() and not g.broken.any()
    assert np.isnan(g.broken_time).all() and np.isnan(g.broken_force).all()
    assert "4 constraints (4 alive, 0 broken" in repr(g)

    rails = w.group("rail")
    assert rails.rods == [a, b] and rails.labels == [] and rails.forces.shape == (0, 3)
    assert [label for label, _ in rails.members] == ["rail[0]", "rail[1]"]
    assert "2 rods" in repr(rails)
    # One exact label is a group of one.
    one = w.group("rung[2]")
    assert one.labels == ["rung[2]"] and one.constraints == [ins.constraints[4]]
    with pytest.raises(sk.InvalidInputError, match="group"):
        w.group("nothing")


def test_compression_policy_breaks_only_the_compressed_rung():
    # Welded rungs of a cantilever ladder: rung[0] is compressed (1.41 N),
    # rung[1] pulled (2.76 N); only compression above 1 N may break one.
    ref = sk.World(gravity=(0, -G, 0))
    ref.insert(cantilever_ladder()[0])
    ref.relax()
    t = ref.group("rung").tensions
    assert t[0] < -1.0 and t[1] > 1.0  # compressed and pulled beyond 1 N in the same solve
    asm, us = cantilever_ladder(break_force=1.0, policy="compression")
    w = sk.World(gravity=(0, -G, 0))
    ins = w.insert(asm)
    events = w.relax().events
    assert [e.kind for e in events] == ["ConstraintBroken"]
    e = events[0]
    assert e.label == "rung[0]" and e.policy == "compression" and e.constraint == ins.constraints[2]
    assert e.force > 1.0 and "RelativePosition" in e.constraint_kind
    assert w.relax().events == []  # the other three hold the new equilibrium
    g = w.group("rung")
    np.testing.assert_array_equal(g.broken, [True, False, False, False])
    np.testing.assert_array_equal(g.alive, [False, True, True, True])
    assert g.broken_force[0] == e.force and g.broken_time[0] == e.time
    assert np.isnan(g.broken_force[1:]).all()
    assert np.isnan(g.positions[0]).all() and np.isnan(g.tensions[0])
    assert (g.forces[0] == 0).all() and g.multipliers[0].size == 0
    np.testing.assert_allclose(g.positions[1:], ins.rods[0].position(np.array(us[1:])), atol=1e-15)
    assert (g.tensions[1:] > -1.0).all()  # no survivor compressed beyond the threshold
    assert not ins.constraints[2].alive and ins.constraints[3].alive


def test_tension_policy_breaks_hanging_rungs_and_labels_the_events():
    w = sk.World(dt=1e-3, gravity=(0, -G, 0))
    w.insert(hanging_ladder(break_force=0.15, policy="tension"))
    events = []
    for _ in range(50):
        events += w.step().events
    g = w.group("rung")
    assert sorted(e.label for e in events) == g.labels  # every rung broke, once
    assert all(e.kind == "ConstraintBroken" and e.policy == "tension" and e.force > 0.15 for e in events)
    assert g.broken.all() and not g.alive.any()
    by_label = {e.label: e for e in events}
    for i, label in enumerate(g.labels):
        assert g.broken_time[i] == by_label[label].time > 0
        assert g.broken_force[i] == by_label[label].force
        assert by_label[label].constraint == g.constraints[i]
    # The same rungs under a compression policy hold (they are pulled, at
    # up to 0.8 N, far above the threshold).
    w2 = sk.World(dt=1e-3, gravity=(0, -G, 0))
    w2.insert(hanging_ladder(break_force=0.15, policy="compression"))
    assert not any(w2.step().events for _ in range(50))
    g2 = w2.group("rung")
    assert not g2.broken.any() and g2.tensions.max() > 0.5


def test_assembly_json_round_trip():
    asm, _ = cantilever_ladder(break_force=3.0, policy="tension")
    asm.add_bead(1, 2.0, mass=1e-3, radius=1e-3, label="ring[0]")
    asm.add_load(1, sk.point_force(None, 5.0, (0, -0.1, 0)), label="pull")
    text = asm.to_json()
    back = sk.Assembly.from_json(text)
    assert back.to_json() == text
    assert repr(back) == repr(asm)
    assert json.loads(text)["constraints"][2]["breaking"] == {"force": 3.0, "policy": "tension"}
    worlds = []
    for a in (asm, back):
        w = sk.World(gravity=(0, -G, 0))
        ins = w.insert(a)
        assert ins.loads[0].label == "pull" and ins.beads[0].label == "ring[0]"
        for _ in range(5):
            w.step()
        worlds.append(ins.rods)
    for r, s in zip(*worlds):
        assert r.control_points.tobytes() == s.control_points.tobytes()


def test_bad_assemblies_raise_and_leave_the_world_unchanged():
    w = sk.World(gravity=(0, -G, 0))
    rod = w.add_rod(rail(1.0))
    sk.clamp(w, rod)
    before = (w.n_rods, w.n_constraints, w.groups, rod.control_points.tobytes())

    def unchanged():
        assert (w.n_rods, w.n_constraints, w.groups, rod.control_points.tobytes()) == before

    asm, _ = cantilever_ladder()
    # Caught while building: rod index, policy, label.
    with pytest.raises(sk.InvalidInputError, match="rod") as e:
        asm.link(0, 5, sk.relative_distance(0.0, 0.0, 0.1))
    assert e.value.what == "constraint other rod" and e.value.value == "5"
    with pytest.raises(sk.InvalidInputError, match="policy") as e:
        asm.constrain(0, sk.position(1.0), break_force=1.0, policy="sideways")
    assert e.value.what == "policy" and "tension" in e.value.expected
    with pytest.raises(sk.InvalidInputError, match="label") as e:
        asm.add_rod(rail(2.0), label="bad label")
    assert e.value.what == "label"
    with pytest.raises(sk.InvalidInputError, match="needs break_force"):
        asm.constrain(0, sk.position(1.0), policy="tension")
    assert asm.n_rods == 2 and asm.n_constraints == 6  # nothing half-added

    # Caught at insertion, against the rods: the world is untouched.
    bad_u = asm.copy()
    bad_u.constrain(1, sk.position(99.0))
    with pytest.raises(sk.InvalidInputError, match="outside the rod's parameter domain"):
        w.insert(bad_u)
    unchanged()
    no_line = asm.copy()
    no_line.constrain(1, sk.position(1.0), break_force=1.0, policy="tension")
    with pytest.raises(sk.InvalidInputError, match="policy") as e:
        w.insert(no_line)
    assert e.value.value == "tension"
    unchanged()
    dup = asm.copy()
    dup.constrain(0, sk.position(0.0, (0, 0, 0)))
    with pytest.raises(sk.InvalidInputError, match="duplicate"):
        w.insert(dup)
    unchanged()
    # A hand-edited JSON assembly: rod index and label checked at insertion.
    doc = json.loads(asm.to_json())
    doc["constraints"][2]["other"] = 7
    with pytest.raises(sk.InvalidInputError, match="rod") as e:
        w.insert(sk.Assembly.from_json(json.dumps(doc)))
    assert e.value.value == "7"
    unchanged()
    doc = json.loads(asm.to_json())
    doc["constraints"][2]["label"] = "rung[x]"
    with pytest.raises(sk.InvalidInputError, match="label"):
        w.insert(sk.Assembly.from_json(json.dumps(doc)))
    unchanged()
    with pytest.raises(sk.FileError, match="assembly"):
        sk.Assembly.from_json('{"rods": [], "bogus": 1}')
    # The valid assembly still goes in afterwards.
    ins = w.insert(asm)
    assert (w.n_rods, w.n_constraints) == (before[0] + 2, before[1] + 6) and len(ins.rods) == 2


def test_labels_on_world_objects():
    w = sk.World(gravity=(0, -G, 0))
    rod = w.add_rod(rail(0.0))
    other = sk.World().add_rod(rail(0.0))
    c = w.add_constraint(rod, sk.position(rod.u_start), label="pin[0]")
    d = w.add_constraint(rod, sk.position(rod.u_end, (1, 0, 0)))
    load = w.add_load(sk.distributed(rod, (0, -0.1, 0)), label="wind")
    bead = w.add_bead(rod, 2.0, mass=1e-3, label="ring[0]")
    w.set_label(rod, "strand[0]")
    w.set_label(d, "pin[1]")
    assert (c.label, d.label, load.label, bead.label, rod.label) == ("pin[0]", "pin[1]", "wind", "ring[0]", "strand[0]")
    assert w.groups == ["pin", "ring", "strand", "wind"]
    assert 'ConstraintHandle(0 "pin[0]": Position(' in repr(c) and '"strand[0]"' in repr(rod)
    assert w.group("wind").loads == [load] and w.group("ring").beads == [bead] and w.group("strand").rods == [rod]
    w.step()
    np.testing.assert_array_equal(w.group("pin").forces, [c.reaction().force, d.reaction().force])
    n = w.n_constraints
    with pytest.raises(sk.InvalidInputError, match="label"):
        w.set_label(c, "two words")
    with pytest.raises(sk.InvalidInputError, match="label"):
        w.add_constraint(rod, sk.position(2.0), label="[3]")
    assert w.n_constraints == n and w.groups == ["pin", "ring", "strand", "wind"]
    with pytest.raises(sk.InvalidInputError, match="another world"):
        w.set_label(other, "x")
    with pytest.raises(sk.InvalidInputError, match="a Rod or a handle"):
        w.set_label("rod", "x")
