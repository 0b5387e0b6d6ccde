"""Bad input raises Python exceptions with the core's clear messages; no panic crosses."""
import json

import numpy as np
import pytest

import strandkit as sk


@pytest.fixture
def world_rod():
    w = sk.World()
    rod = w.add_rod(sk.straight((0, 0, 0), (1, 0, 0), section=0.01, material="nylon", n_control_points=8))
    return w, rod


def test_negative_radius():
    with pytest.raises(ValueError, match=r"section radius must be finite and > 0, got -0.1"):
        sk.Section.circle(-0.1)
    with pytest.raises(ValueError, match=r"section radius must be finite and > 0, got -0.1"):
        sk.straight((0, 0, 0), (1, 0, 0), section=-0.1, material="nylon")
    with pytest.raises(ValueError, match=r"inner_radius must be < outer_radius"):
        sk.Section.tube(0.1, 0.2)


def test_nan_coordinates(world_rod):
    w, rod = world_rod
    pts = [[0, 0, 0], [1, np.nan, 0], [2, 0, 0], [3, 0, 0]]
    with pytest.raises(ValueError, match=r"points\[1\] has a non-finite coordinate \(NaN\)"):
        sk.through_points(pts, section=0.01, material="nylon")
    with pytest.raises(ValueError, match=r"start must be finite, got NaN"):
        sk.straight((0, 0, np.nan), (1, 0, 0), section=0.01, material="nylon")
    q = rod.control_points
    q[2, 1] = np.inf
    with pytest.raises(ValueError, match=r"control_points\[2\] has a non-finite coordinate \(inf\)"):
        rod.control_points = q
    with pytest.raises(ValueError, match=r"target\[0\] must be finite, got NaN"):
        w.add_constraint(rod, sk.position(rod.u_start, (np.nan, 0, 0)))
    with pytest.raises(ValueError, match=r"must be finite"):
        w.add_load(sk.point_force(rod, rod.u_end, (0, np.nan, 0)))
    # The rod is unchanged by the rejected assignment.
    assert np.isfinite(rod.control_points).all()


def test_abscissa_out_of_range(world_rod):
    w, rod = world_rod
    msg = r"abscissa u = 99 is outside the rod's parameter domain \[0, 5\]"
    with pytest.raises(ValueError, match=msg):
        w.add_constraint(rod, sk.position(99.0))
    with pytest.raises(ValueError, match=msg):
        rod.position(99.0)
    with pytest.raises(ValueError, match=msg):
        w.add_load(sk.point_force(rod, 99.0, (0, 1, 0)))
    with pytest.raises(ValueError, match=r"outside the rod's parameter domain"):
        rod.frames(u=[0.0, 1.0, 7.0])


def test_solver_errors_are_subclasses():
    w = sk.World()
    w.add_rod(sk.straight((0, 0, 0), (1, 0, 0), section=0.01, material="nylon", n_control_points=6))
    with pytest.raises(sk.SingularError, match=r"not statically defined") as e:
        w.relax()
    assert isinstance(e.value, sk.SolverError) and isinstance(e.value, RuntimeError)
    assert issubclass(sk.ConvergenceError, sk.SolverError)


def test_misuse_is_an_exception_not_a_crash(world_rod, tmp_path):
    w, rod = world_rod
    free = sk.straight((0, 0, 0), (1, 0, 0), section=0.01, material="nylon")
    with pytest.raises(ValueError, match="not in the world"):
        w.add_constraint(free, sk.position(0.0))
    with pytest.raises(ValueError, match="already in a world"):
        w.add_rod(rod)
    with pytest.raises(ValueError, match="unknown variant `Bogus`"):
        w.add_constraint(rod, sk.kind("Bogus", u=0.0))
    w.add_constraint(rod, sk.position(rod.u_start))
    with pytest.raises(ValueError, match="duplicate constraint"):
        w.add_constraint(rod, sk.position(rod.u_start))
    with pytest.raises(ValueError, match="unknown material preset"):
        sk.Material.preset("unobtainium")
    with pytest.raises(ValueError, match=r"dt must be finite and > 0"):
        sk.World(dt=-1.0)
    with pytest.raises(ValueError, match="unknown integration parameter"):
        w.set_params(dtt=1.0)
    with pytest.raises(OSError, match="snapshot"):
        p = tmp_path / "bad.json"
        p.write_text("{ not json")
        sk.World.load(str(p))
    with pytest.raises(ValueError, match=r"expected shape \(n, 3 or 4\)"):
        rod.control_points = np.zeros((8, 2))
    with pytest.raises(ValueError, match="expected 32 values"):
        rod.control_points = np.zeros((7, 4))
    removed = w.remove_rod(rod)
    assert removed.world is None
    with pytest.raises(ValueError, match="not in the world"):
        w.add_constraint(removed, sk.position(0.0))
    dcd = sk.DcdWriter(str(tmp_path / "x.dcd"), 3)
    dcd.close()
    with pytest.raises(ValueError, match="closed"):
        dcd.write_frame(np.zeros((3, 3)))


def test_exception_classes_and_attributes(tmp_path):
    assert issubclass(sk.InvalidInputError, ValueError) and issubclass(sk.InvalidInputError, sk.StrandkitError)
    assert issubclass(sk.InvalidHandleError, ValueError)
    assert issubclass(sk.SingularError, sk.SolverError) and issubclass(sk.SingularError, RuntimeError)
    assert issubclass(sk.FileError, OSError) and issubclass(sk.FileError, sk.StrandkitError)
    with pytest.raises(sk.InvalidInputError) as e:
        sk.Section.circle(-0.1)
    assert (e.value.kind, e.value.what, e.value.value, e.value.expected) == (
        "InvalidInput", "section radius", "-0.1", "finite and > 0")
    w = sk.World()
    w.add_rod(sk.straight((0, 0, 0), (1, 0, 0), section=0.01, material="nylon", n_control_points=6))
    with pytest.raises(sk.SingularError) as e:
        w.relax()
    assert e.value.kind == "Singular" and isinstance(e.value.constraints, list) and "statically" in e.value.detail
    # Snapshots of another format, another version or no envelope are FileErrors.
    good = w.to_json()
    other = tmp_path / "other.json"
    other.write_text(json.dumps({"format": "other-tool", "version": 2, "world": {}}))
    with pytest.raises(sk.FileError, match="not a strandkit world snapshot") as e:
        sk.World.load(str(other))
    assert e.value.path == str(other) and isinstance(e.value, OSError)
    newer = json.loads(good)
    newer["version"] = 99
    with pytest.raises(sk.FileError, match="version Some\\(99\\) is not supported|version 99"):
        sk.World.from_json(json.dumps(newer))
    with pytest.raises(sk.FileError, match="not a strandkit world snapshot"):
        sk.World.from_json(json.dumps(json.loads(good)["world"]))
    assert sk.World.from_json(good).n_rods == 1
