"""The constraint and load helpers come from the core's catalogues: every
kind has one, and what a helper builds goes through the core unchanged."""
import inspect
import json

import numpy as np
import pytest

import strandkit as sk

# Values by field type (abscissae by field name, distinct so a swap shows).
ABSCISSA = {"u": 1.0, "ua": 1.5, "ub": 2.5, "driven": 3.0, "ua_next": 1.9, "ub_next": 2.1,
            "ua_prev": 1.2, "ub_prev": 2.8, "ua_after": 2.2, "ub_after": 1.8,
            "ua_first": 1.1, "ub_first": 2.9, "ua_last": 2.05, "ub_last": 1.95, "va": 0.6, "vb": 3.1}
# Fields whose generic value the kind refuses (stiffnesses must be > 0).
OVERRIDES = {"BasePairStep": {"translation_stiffness": (1.0, 2.0, 3.0), "rotation_stiffness": (1.5, 2.5, 3.5)}}
BY_TYPE = {
    "scalar": 0.25,
    "flag": True,
    "vec3": (0.1, -0.2, 0.3),
    "direction": (0.0, 0.6, 0.8),
    "vec2": (0.5, -0.25),
    "vec4": (0.1, 0.2, 0.3, 0.4),
    "axes": "xz",
    "weighted_abscissae": [(0.5, 0.25), (2.0, 0.75)],
}


def example_args(info, rod):
    """Keyword arguments for a helper, every field given (by its type)."""
    out = {}
    for f in info["fields"]:
        if f["ty"] == "abscissa":
            out[f["name"]] = ABSCISSA[f["name"]]
        elif f["ty"] == "rod":
            out[f["name"]] = rod
        else:
            out[f["name"]] = BY_TYPE[f["ty"]]
    out.update(OVERRIDES.get(info["name"], {}))
    return out


def plain(v):
    """A value as JSON data (tuples become lists, numpy values numbers)."""
    return json.loads(json.dumps(v, default=lambda x: x.tolist()))


def world_with_two_curved_rods():
    """Two helices with roll (curved: MaterialRoll applies in the Frenet model)."""
    w = sk.World()
    a = w.add_rod(sk.helix(0.2, 0.1, 1.0, section=0.01, material="nylon", n_control_points=8))
    b = w.add_rod(sk.helix(0.3, 0.1, 1.0, section=0.01, material="nylon", n_control_points=8))
    return w, a, b


def test_every_catalogue_kind_has_a_helper():
    kinds = {info["name"] for info in sk.constraints.CATALOGUE}
    assert kinds >= {"Position", "Tangent", "MaterialRoll", "Distance", "Plane", "Axis", "Curvature",
                     "RelativePosition", "RelativeOrientation", "RelativeDistance", "RelativeAxis", "SlidingPoint",
                     "OrientedSlidingPoint", "Contact", "CoplanarClamp", "Barycentric"}
    for info in sk.constraints.CATALOGUE + sk.loads.CATALOGUE:
        helper = getattr(sk, info["helper"])
        assert helper.__name__ == info["helper"] and info["helper"] in sk.__all__
        params = inspect.signature(helper).parameters
        for f in info["fields"]:
            assert f["name"] in params
            assert (params[f["name"]].default is inspect.Parameter.empty) == (f["default"] is None)
            if f["unit"] not in ("", "u"):
                assert f"({f['unit']})" in helper.__doc__, (info["helper"], f["name"])
        assert helper.__doc__.startswith(info["doc"])
    assert {info["name"] for info in sk.loads.CATALOGUE} >= {"PointForce", "PointTorque", "Distributed", "Trap"}


@pytest.mark.parametrize("info", sk.constraints.CATALOGUE, ids=lambda i: i["name"])
def test_constraint_helpers_round_trip_through_the_core(info):
    w, a, b = world_with_two_curved_rods()
    built = getattr(sk, info["helper"])(**example_args(info, None))
    assert list(built) == [info["name"]] and isinstance(built, sk.Kind)
    if info["rods"] == 2:
        h = w.add_link(a, b, built)
    else:
        h = w.add_constraint(a, built)
    assert h.alive and h.rod == a and h.other == (b if info["rods"] == 2 else None)
    assert plain(h.kind) == plain(dict(built)), info["name"]


@pytest.mark.parametrize("info", sk.loads.CATALOGUE, ids=lambda i: i["name"])
def test_load_helpers_round_trip_through_the_core(info):
    w, a, _ = world_with_two_curved_rods()
    built = getattr(sk, info["helper"])(**example_args(info, a))
    h = w.add_load(built)
    back = dict(h.kind[info["name"]])
    assert back.pop("rod") == a and h.rod == a
    sent = dict(built[info["name"]])
    assert sent.pop("rod") is a
    assert plain(back) == plain(sent), info["name"]


def test_todays_call_forms_keep_working():
    assert sk.position(1.0) == {"Position": {"u": 1.0, "target": [0.0] * 4, "axes": [True, True, True, False]}}
    p = sk.position(1.0, (1, 2, 3), axes="xy", roll=0.5)["Position"]
    assert p["target"] == [1.0, 2.0, 3.0, 0.5] and p["axes"] == [True, True, False, True]
    assert sk.position(0, np.array([1.0, 2, 3, 4]), axes=[1, 0, 0, 1])["Position"]["target"] == [1, 2, 3, 4]
    r = sk.relative_position(1.0, 2.0, (0, 0.1, 0), axes="xyz", roll_offset=0.2)["RelativePosition"]
    assert r["offset"] == [0.0, 0.1, 0.0, 0.2] and r["axes"] == [True, True, True, True]
    assert sk.material_roll(1.0, (1, 0, 0), 0.3)["MaterialRoll"]["angle"] == 0.3
    assert sk.sliding_point(1.0, (0, 0, 0), friction=0.1)["SlidingPoint"]["friction"] == 0.1
    assert sk.relative_orientation(1.0, 2.0, roll=True)["RelativeOrientation"]["roll"] is True
    assert sk.distance(1.0, point=(0, 0, 0), distance=2.0)["Distance"]["distance"] == 2.0
    assert sk.point_force(None, 1.0, (0, 1, 0)) == {"PointForce": {"rod": None, "u": 1.0, "force": [0.0, 1.0, 0.0]}}
    t = sk.trap(None, 1.0, (0, 0, 1), 5.0)["Trap"]
    assert t["velocity"] == [0.0, 0.0, 0.0] and t["t0"] == 0.0 and t["stiffness"] == 5.0
    assert sk.kind("Plane", u=0.0, origin=np.zeros(3), normal=(0, 0, 1)) == {
        "Plane": {"u": 0.0, "origin": [0.0, 0.0, 0.0], "normal": [0, 0, 1]}}


def test_bad_helper_arguments_are_invalid_input():
    with pytest.raises(sk.InvalidInputError, match="tangent direction must be 3 values") as e:
        sk.tangent(0.0, (1, 0))
    assert e.value.what == "tangent direction" and e.value.value == "2 values"
    with pytest.raises(sk.InvalidInputError, match="axes"):
        sk.position(0.0, axes="xq")
    with pytest.raises(sk.InvalidInputError, match="axes"):
        sk.position(0.0, axes=[True, False])
    with pytest.raises(sk.InvalidInputError, match="position target must be 3 or 4 values"):
        sk.position(0.0, (1, 2))
    with pytest.raises(sk.InvalidInputError, match="a number"):
        sk.plane("zero", (0, 0, 0), (0, 0, 1))
    with pytest.raises(sk.InvalidInputError, match="True or False"):
        sk.relative_orientation(0.0, 1.0, roll="yes")
    with pytest.raises(sk.InvalidInputError, match="a Rod"):
        sk.point_force("rod", 0.0, (0, 1, 0))
    with pytest.raises(TypeError, match="missing a required argument: 'direction'"):
        sk.tangent(0.0)
    with pytest.raises(TypeError, match="unexpected keyword argument 'bogus'"):
        sk.plane(0.0, (0, 0, 0), (0, 0, 1), bogus=1)


def test_loads_need_a_rod_of_the_world():
    w, a, _ = world_with_two_curved_rods()
    other = sk.World().add_rod(sk.straight((0, 0, 0), (1, 0, 0), section=0.01, material="nylon"))
    with pytest.raises(sk.InvalidInputError, match="expected a Rod of this world"):
        w.add_load(sk.point_force(None, 1.0, (0, 1, 0)))
    with pytest.raises(sk.InvalidInputError, match="belongs to another world"):
        w.add_load(sk.point_force(other, 1.0, (0, 1, 0)))
    free = sk.straight((0, 0, 0), (1, 0, 0), section=0.01, material="nylon")
    with pytest.raises(sk.InvalidInputError, match="not in a world yet"):
        w.add_load(sk.point_force(free, 1.0, (0, 1, 0)))
    assert w.loads() == []


def test_trap_pulls_towards_its_moving_centre():
    """The new load kind works end to end: a free rod in a stiff trap
    follows the trap centre moving at constant velocity."""
    w = sk.World(dt=1e-2)
    rod = w.add_rod(sk.straight((0, 0, 0), (1, 0, 0), section=0.01, material="nylon", n_control_points=6,
                                with_roll=False, drag=1.0))
    mid = 0.5 * sum(rod.domain)
    trap = w.add_load(sk.trap(rod, mid, anchor=rod.position(mid), stiffness=50.0, velocity=(0, 0.1, 0)))
    assert trap.velocity == [0.0, 0.1, 0.0] and trap.stiffness == 50.0
    for _ in range(200):
        w.step()
    centre = np.array([0.5, 0.1 * w.time, 0.0])
    assert np.linalg.norm(rod.position(mid) - centre) < 0.01
