"""No keyword or field is silently dropped: an unknown one is an error that
lists the accepted ones (before, a `label` or a misspelt field inside a
constraint or load kind was ignored by the core's deserialiser), and the
recorder keeps every field of an event (a broken constraint's kind was
overwritten by the event's name)."""
import csv
import json

import pytest

import strandkit as sk


@pytest.fixture
def world_rod():
    w = sk.World(gravity=(0, -9.81, 0))
    rod = w.add_rod(sk.straight((0, 0, 0), (1, 0, 0), section=0.01, material="nylon", n_control_points=8))
    return w, rod


POSITION = {"Position": {"u": 0.0, "target": [0, 0, 0, 0], "axes": [True, True, True, False]}}


def with_field(kind, key, value):
    (name, fields), = kind.items()
    return {name: {**fields, key: value}}


@pytest.mark.parametrize("key", ["label", "targett", "compliance"])
def test_unknown_constraint_field_is_an_error_listing_the_fields(world_rod, key):
    w, rod = world_rod
    bad = with_field(POSITION, key, 1.0 if key == "compliance" else "x")
    as_kind = sk.kind("Position", **bad["Position"])
    for given in (bad, as_kind, json.dumps(bad)):
        with pytest.raises(sk.InvalidInputError, match=f'unknown constraint Position field "{key}"') as e:
            w.add_constraint(rod, given)
        assert e.value.expected == "one of u, target, axes"
        if key in ("label", "compliance"):
            assert f"{key}= is a keyword of add_constraint" in str(e.value)
    assert w.n_constraints == 0
    # The same through an Assembly, and when replacing a constraint's kind.
    asm = sk.Assembly()
    asm.add_rod(rod)
    with pytest.raises(sk.InvalidInputError, match=f'field "{key}"'):
        asm.constrain(0, bad)
    assert asm.n_constraints == 0
    c = w.add_constraint(rod, POSITION)
    with pytest.raises(sk.InvalidInputError, match=f'field "{key}"'):
        w.set_constraint(c, bad)
    assert c.kind == {"Position": {"u": 0.0, "target": [0.0, 0.0, 0.0, 0.0], "axes": [True, True, True, False]}}


def test_unknown_load_field_is_an_error_listing_the_fields(world_rod):
    w, rod = world_rod
    bad = {"PointForce": {"rod": rod, "u": 1.0, "force": [0, 0, 1], "label": "pull"}}
    with pytest.raises(sk.InvalidInputError, match=r'unknown load PointForce field "label" \(label= is a keyword of '
                                                   r"add_load.*expected one of rod, u, force"):
        w.add_load(bad)
    assert w.loads() == []
    load = w.add_load(sk.point_force(rod, 1.0, (0, 0, 1)), label="pull")
    with pytest.raises(sk.InvalidInputError, match='field "forse"'):
        w.set_load(load, {"PointForce": {"rod": rod, "u": 1.0, "forse": [0, 0, 2]}})
    assert load.force == [0.0, 0.0, 1.0] and load.label == "pull"
    asm = sk.Assembly()
    asm.add_rod(sk.straight((0, 0, 0), (1, 0, 0), section=0.01, material="nylon"))
    with pytest.raises(sk.InvalidInputError, match='unknown load Trap field "stiffnes"'):
        asm.add_load(0, {"Trap": {"rod": None, "u": 0.0, "anchor": [0, 0, 0], "stiffnes": 1.0}})
    assert asm.n_loads == 0


def test_every_kind_a_world_serves_back_is_accepted_as_given(world_rod):
    """The field check does not refuse what the core itself writes: each
    catalogue helper's kind, read back from the world, sets the constraint."""
    w, rod = world_rod
    c = w.add_constraint(rod, sk.sliding_point(0.5, (0.5, 0, 0), friction=0.1))
    w.set_constraint(c, c.kind)
    load = w.add_load(sk.trap(rod, 0.0, anchor=(0, 0, 0), stiffness=2.0))
    w.set_load(load, load.kind)
    assert load.stiffness == 2.0 and c.kind["SlidingPoint"]["friction"] == 0.1


@pytest.mark.parametrize("call, accepted", [
    (lambda: sk.World(lable=1), "dt, gravity, isotropic_drag, linear_solver"),
    (lambda: sk.World().set_params(dtt=1.0), "dt, gravity, isotropic_drag, linear_solver"),
    (lambda: sk.straight((0, 0, 0), (1, 0, 0), section=0.01, material="nylon", label="x"),
     "curvature_threshold, drag, model"),
    (lambda: sk.QuasiDynamic(sk.World(), dt=1e-3), "dt0"),
])
def test_unknown_keywords_of_parameter_structs_list_the_accepted_ones(call, accepted):
    with pytest.raises(sk.InvalidInputError, match=f"expected one of .*{accepted}"):
        call()


def test_helpers_name_their_parameters_on_an_unknown_keyword(world_rod):
    _, rod = world_rod
    with pytest.raises(TypeError, match=r"point_force\(rod: .*, u: .*, force: .*\).*unexpected keyword argument 'label'"):
        sk.point_force(rod, 1.0, (0, 0, 1), label="x")
    with pytest.raises(TypeError, match=r"position\(u: .*target.*axes.*roll.*unexpected keyword argument 'lable'"):
        sk.position(0.0, lable="x")


def test_recorder_keeps_a_broken_constraints_kind(tmp_path):
    w = sk.World(dt=1e-3, gravity=(0, -9.81, 0))
    rod = w.add_rod(sk.straight((0, 0, 0), (1, 0, 0), section=0.01, material="nylon", n_control_points=8,
                                with_roll=False))
    kind = sk.distance(rod.u_start, point=(0, 0.1, 0), distance=0.1)
    c = w.add_constraint(rod, kind, break_force=0.5, tension_only=True, label="hanger")
    rec = sk.Recorder(w)
    rec.run(50, progress_bar=False)
    assert not c.alive and len(rec.events) == 1
    e = rec.events[0]
    assert e["kind"] == "ConstraintBroken" and e["label"] == "hanger" and e["policy"] == "tension"
    assert e["constraint_kind"] == {"Distance": {"u": 0.0, "point": [0.0, 0.1, 0.0], "distance": 0.1}}
    assert e["force"] > 0.5 and e["time"] == e["time_recorded"] == pytest.approx(e["step"] * 1e-3)
    rec.to_csv(str(tmp_path / "run.csv"))
    rows = list(csv.DictReader(open(tmp_path / "run.events.csv")))
    assert len(rows) == 1 and rows[0]["kind"] == "ConstraintBroken" and "Distance" in rows[0]["constraint_kind"]
