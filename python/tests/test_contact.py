"""Contact from Python (issue 15): obstacles (plane, sphere, capsule, meshes
read from OBJ and STL), friction, the contacts as arrays, snapshots that
restart mid-contact bit for bit, and bad input."""
import json
import struct

import numpy as np
import pytest

import strandkit as sk

R = 0.01
G = 9.81


def _rod(z=0.05, tilt=0.02, n=10):
    return sk.straight((-0.25, 0.0, z), (0.25, 0.0, z + tilt), section=R, material="nylon", n_control_points=n, with_roll=False)


def _floor_obj(path, size=1.0):
    path.write_text(
        "# a square floor at z = 0, normals up\n"
        f"v {-size} {-size} 0\nv {size} {-size} 0\nv {size} {size} 0\nv {-size} {size} 0\n"
        "f 1 2 3\nf 1/1/1 3/3/3 4/4/4\n"
    )
    return path


def _floor_stl(path, size=1.0):
    tris = [[(-size, -size, 0), (size, -size, 0), (size, size, 0)], [(-size, -size, 0), (size, size, 0), (-size, size, 0)]]
    data = bytearray(b"binary floor".ljust(80, b" ")) + struct.pack("<I", len(tris))
    for t in tris:
        data += struct.pack("<3f", 0, 0, 1)
        for v in t:
            data += struct.pack("<3f", *v)
        data += struct.pack("<H", 0)
    path.write_bytes(bytes(data))
    return path


def _lowest(rod):
    return rod.position(rod.uniform_params(301))


def _drop(obstacle, steps=600, **kw):
    w = sk.World(dt=2e-3, gravity=(0, 0, -G))
    rod = w.add_rod(_rod())
    w.add_obstacle(obstacle, margin=0.01, **kw)
    for _ in range(steps):
        w.step()
    return w, rod


def test_obstacles_print_and_measure():
    assert repr(sk.obstacles.sphere((0, 0, 1), 0.5)) == "Obstacle.sphere(center=[0.0, 0.0, 1.0], radius=0.5)"
    d = sk.obstacles.sphere((0, 0, 1), 0.5).distance([[0, 0, 3], [0, 0, 1]])
    assert np.allclose(d, [1.5, -0.5])
    cap = sk.obstacles.cylinder(center=(0, 0, 0), axis=(0, 1, 0), radius=0.2, length=2.0)
    assert cap.kind == "capsule" and np.allclose(cap.distance([[0.5, 0.3, 0.0], [0.0, 1.5, 0.0]]), [0.3, 0.3])
    assert sk.obstacles.plane(normal=(0, 0, 2)).distance([[1, 2, -0.25]])[0] == -0.25


def test_a_rod_dropped_on_a_mesh_floor_rests_on_it_the_same_from_obj_and_stl(tmp_path):
    obj = sk.obstacles.mesh(_floor_obj(tmp_path / "floor.obj"))
    stl = sk.obstacles.mesh(_floor_stl(tmp_path / "floor.stl"))
    assert obj.kind == "mesh" and repr(obj) == "Obstacle.mesh(2 triangles)"
    w1, r1 = _drop(obj)
    w2, r2 = _drop(stl)
    # The same floor (exact in float32) gives the same motion bit for bit.
    assert r1.control_points.tobytes() == r2.control_points.tobytes()
    low = _lowest(r1)[:, 2].min() - R
    c = w1.contacts()
    weight = r1.mass * G
    print(f"mesh floor: surface {low / R:+.2e} R from the floor, {len(c['normal_force'])} contacts carry {c['normal_force'].sum():.5f} N of {weight:.5f} N")
    assert low > -0.01 * R and low < 0.01 * R
    assert abs(c["normal_force"].sum() / weight - 1) < 0.05
    assert c["points"].shape == (len(c["rod_a"]), 3) and np.allclose(c["normals"], [0, 0, 1])
    assert set(c["rod_a"]) == {0} and set(c["rod_b"]) == {-1} and np.isnan(c["u_b"]).all()


def test_a_rod_on_a_sphere_never_enters_it():
    w = sk.World(dt=2e-3, gravity=(0, 0, -G))
    rod = w.add_rod(_rod(z=0.22, tilt=0.0, n=14))
    ball = sk.obstacles.sphere((0.02, 0.0, 0.0), 0.2)
    w.add_obstacle(ball, margin=0.01)
    closest = np.inf
    for _ in range(300):
        w.step()
        closest = min(closest, ball.distance(_lowest(rod)).min())
    # Rows sit at the rod's probes (5 a segment): rolling over the ball, its
    # deepest point runs between two of them, about 1 % of R deeper.
    print(f"sphere: closest centreline {closest / R:.4f} R from the surface")
    assert closest > R * (1 - 0.02)
    assert len(w.contacts()["normal_force"]) > 0


def test_friction_holds_a_rod_on_a_slope_with_the_forces_readable():
    mu = 0.4
    alpha = np.arctan(0.5 * mu)
    n = np.array([np.sin(alpha), 0, np.cos(alpha)])
    w = sk.World(dt=2e-3, gravity=(0, 0, -G))
    rod = w.add_rod(sk.straight(n * R, n * R + 0.2 * np.array([0, 1.0, 0]), section=R, material="nylon", n_control_points=6, with_roll=False))
    w.add_obstacle(sk.obstacles.plane(normal=n), margin=0.005, friction=mu)
    start = rod.control_points.copy()
    for _ in range(200):
        w.step()
    c = w.contacts()
    moved = np.abs(rod.control_points - start).max()
    weight = rod.mass * G
    along = c["friction_force"].sum(axis=0)
    print(f"slope tan α = μ/2: moved {moved:.2e} m, friction {along} N (weight · sin α = {weight * np.sin(alpha):.5f} N)")
    assert moved < 1e-6
    assert not c["slipping"].any()
    # The friction holds the weight's component along the slope, uphill.
    assert np.allclose(along, -weight * np.sin(alpha) * np.array([np.cos(alpha), 0, -np.sin(alpha)]), rtol=0.02, atol=0.02 * weight * np.sin(alpha))
    assert abs(c["normal_force"].sum() / (weight * np.cos(alpha)) - 1) < 0.02


def test_a_snapshot_restarts_mid_contact_bit_for_bit(tmp_path):
    w = sk.World(dt=2e-3, gravity=(0, 0, -G))
    rod = w.add_rod(_rod())
    w.add_obstacle(sk.obstacles.plane(normal=(0.1, 0, 1)), margin=0.01, friction=0.2)
    w.add_obstacle(sk.obstacles.mesh(_floor_obj(tmp_path / "floor.obj")), margin=0.01, friction=0.3)
    w.contact(margin=0.005, friction=0.1)
    for _ in range(90):
        w.step()
    assert len(w.contacts()["normal_force"]) > 0  # resting on the tilted plane and the floor
    path = tmp_path / "w.json"
    w.save(str(path))
    again = sk.World.load(str(path))
    for _ in range(60):
        w.step()
        again.step()
    assert rod.control_points.tobytes() == again.rods()[0].control_points.tobytes()
    a, b = w.contacts(), again.contacts()
    assert all(a[k].tobytes() == b[k].tobytes() for k in a)


def test_bad_contact_input_is_refused(tmp_path):
    bad = [
        lambda: sk.obstacles.sphere((0, 0, 0), -1.0),
        lambda: sk.obstacles.sphere((0, np.nan, 0), 1.0),
        lambda: sk.obstacles.plane(normal=(0, 0, 0)),
        lambda: sk.obstacles.capsule((0, 0, 0), (1, 0, 0), np.inf),
        lambda: sk.obstacles.cylinder((0, 0, 0), (0, 0, 0), 1.0, 1.0),
        lambda: sk.obstacles.mesh_arrays([[0, 0, 0], [1, 0, 0], [2, 0, 0]], [[0, 1, 2]]),
        lambda: sk.obstacles.mesh_arrays([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 3]]),
        lambda: sk.obstacles.mesh(tmp_path / "floor.ply"),
    ]
    for f in bad:
        with pytest.raises(sk.InvalidInputError):
            f()
    w = sk.World()
    with pytest.raises(sk.InvalidInputError):
        w.add_obstacle(sk.obstacles.plane(), friction=-0.1)
    with pytest.raises(sk.InvalidInputError):
        w.add_obstacle(sk.obstacles.plane(), margin=np.nan)
    with pytest.raises(sk.InvalidInputError):
        w.contact(margin=0.01, friction=np.inf)
    # sk.plane is the plane *constraint*: the error points to the obstacle.
    with pytest.raises(TypeError, match=r"sk\.obstacles\.plane"):
        w.add_obstacle(sk.plane(0.0, (0, 0, 0), (0, 0, 1)), margin=0.01)
    # Missing, empty, or not a mesh: a FileError naming the file.
    (tmp_path / "empty.stl").write_bytes(b"")
    (tmp_path / "notes.obj").write_text("just some text\nv 1 2\n")
    (tmp_path / "junk.stl").write_bytes(b"\x00\xff" * 100)
    for name in ["missing.obj", "empty.stl", "notes.obj", "junk.stl"]:
        with pytest.raises(sk.FileError) as e:
            sk.obstacles.mesh(tmp_path / name)
        assert name in str(e.value)
    assert w.contacts()["points"].shape == (0, 3)


def test_contacts_that_cannot_be_met_are_named_and_leave_the_world_as_it_was():
    # A rod squeezed between two planes closer than its diameter.
    w = sk.World(dt=2e-3, gravity=(0, 0, -G))
    rod = w.add_rod(_rod(z=0.0, tilt=0.0, n=8))
    w.add_obstacle(sk.obstacles.plane(origin=(0, 0, -0.5 * R), normal=(0, 0, 1)), margin=0.005)
    w.add_obstacle(sk.obstacles.plane(origin=(0, 0, 0.5 * R), normal=(0, 0, -1)), margin=0.005)
    before = rod.control_points.copy()
    with pytest.raises(sk.SingularError) as e:
        w.step()
    assert "cannot all be met" in str(e.value) and "Contact" in e.value.unknown
    assert np.array_equal(rod.control_points, before) and w.n_steps == 0


def test_a_fast_rod_passes_through_a_bar_unless_its_steps_are_held_within_the_margin():
    # 50 m/s over 2 ms steps: 10 radii per step, past the bar (radius R,
    # margin R/2) between two detections. max_move = margin refuses such a
    # step (the world unchanged); adaptive_dt then takes it in sub-steps.
    def run(max_move, adaptive_dt=True):
        w = sk.World(dt=2e-3, gravity=(0, 0, 0), adaptive_dt=adaptive_dt, max_move=max_move)
        rod = w.add_rod(_rod(z=3 * R, tilt=0.0))
        w.add_obstacle(sk.obstacles.capsule(a=(0, -0.3, 0), b=(0, 0.3, 0), radius=R), margin=0.5 * R)
        rod.velocities = np.tile([0.0, 0.0, -50.0], (10, 1))
        substeps = [w.step().substeps for _ in range(5)]
        u0, u1 = rod.domain
        return w, rod, rod.position(0.5 * (u0 + u1))[2], substeps

    _, _, z, substeps = run(None)
    assert z < -40 * R and substeps == [1] * 5  # through the bar (measured -47 R)
    _, rod, z, substeps = run(0.5 * R)
    assert z > 2 * R and min(substeps) >= 16, (z, substeps)  # stopped on top of it, then bounced off (measured 6.6 R)
    w2 = sk.World(dt=2e-3, gravity=(0, 0, 0), max_move=0.5 * R)
    r2 = w2.add_rod(_rod(z=3 * R, tilt=0.0))
    r2.velocities = np.tile([0.0, 0.0, -50.0], (10, 1))
    before = r2.control_points.copy()
    with pytest.raises(sk.DivergedError, match="max_move"):
        w2.step()
    assert np.array_equal(r2.control_points, before) and w2.n_steps == 0
    with pytest.raises(sk.InvalidInputError, match="max_move"):
        sk.World(max_move=-1.0)
    # The refusal reports the step's farthest move (a retry is sized from
    # it), not the first control point past the limit: both ends of a rod
    # held and moved, by 1.2 and 5 max_moves.
    w3 = sk.World(gravity=(0, 0, 0), viscosity=1.0, overdamped=True, dt=1e-3, max_move=1e-4)
    r3 = w3.add_rod(sk.straight((0, 0, 0), (0.01, 0, 0), section=1e-4, material="nylon", n_control_points=6,
                                with_roll=False))
    u1 = r3.domain[1]
    w3.add_constraint(r3, sk.position(0.0, target=(0.0, 1.2e-4, 0.0)))
    w3.add_constraint(r3, sk.position(u1, target=(0.01, 5e-4, 0.0)))
    with pytest.raises(sk.DivergedError, match="control point 5 ") as e:
        w3.step()
    assert e.value.factor == pytest.approx(5.0, rel=1e-9)


def test_contact_forces_read_per_group_balance_the_weights():
    """Issue 15: contact forces per group. A rod lying across another on a
    frictional floor, at rest: the net contact force on each group (from
    obstacles and rods outside it) balances its weight — the floor and the
    upper rod together hold the lower rod up, the pair between the two rods
    acts and reacts inside the group of both — and each group sees the
    pairs from its own rods."""
    w = sk.World(dt=2e-3, gravity=(0, 0, -G))
    lower = w.add_rod(sk.straight((-0.25, 0, R), (0.25, 0, R), section=R, material="nylon", n_control_points=8, with_roll=False))
    upper = w.add_rod(sk.straight((0, -0.2, 3.1 * R), (0, 0.2, 3.1 * R), section=R, material="nylon", n_control_points=8, with_roll=False))
    w.add_obstacle(sk.obstacles.plane(), margin=0.005, friction=0.5)
    w.contact(margin=0.005, self_contact=False, friction=0.5)
    for rod, label in [(lower, "lower"), (upper, "upper"), (lower, "rods[0]"), (upper, "rods[1]")]:
        w.set_label(rod, label)
    for _ in range(600):
        w.step()
    weight = {name: rod.mass * G for name, rod in [("lower", lower), ("upper", upper)]}
    weight["rods"] = weight["lower"] + weight["upper"]
    for name, mg in weight.items():
        f = w.group(name).contact_force
        print(f"{name}: net contact force {f} N, weight {mg:.6f} N")
        assert f.shape == (3,)
        assert abs(f[2] / mg - 1) < 1e-9 and np.abs(f[:2]).max() < 1e-9 * mg  # measured 4e-14 and 7e-13
    # Seen from the upper rod: only the crossing, pushing it up, at its own
    # centreline point; from the lower rod the same pair turned, and the floor.
    up, low, both = w.group("upper").contacts, w.group("lower").contacts, w.contacts()
    i_low, i_up = 0, 1  # positions in w.rods(), the order they were added
    assert up["rod_a"].tolist() == [i_up] * len(up["rod_a"]) and (up["rod_b"] == i_low).all()
    assert (up["normals"][:, 2] > 0.99).all()
    assert np.allclose(up["points"], upper.position(up["u_a"]), atol=1e-12)
    crossing = low["rod_b"] == i_up
    assert crossing.sum() == len(up["rod_a"]) and (low["normals"][crossing, 2] < -0.99).all()
    assert np.allclose(low["normal_force"][crossing], up["normal_force"])
    assert len(w.group("rods").contacts["rod_a"]) == len(both["rod_a"])


def test_a_rod_pair_gets_its_own_friction_kept_in_snapshots():
    """Issue 15: friction per rod pair (`pair_friction`), instead of the
    detector's μ for that pair only; kept in snapshots; bad μ or a rod of
    another world refused. (Its physics: tests/contact_friction.rs, a rod
    pulled across another sticks and slides by the pair's μ.)"""
    w = sk.World()
    a, b, c = (w.add_rod(sk.straight((0, y, 0), (1, y, 0), section=R, material="nylon", with_roll=False)) for y in (0, 0.1, 0.2))
    w.contact(margin=0.005, friction=0.1, pair_friction=[(b, a, 0.5), (c, c, 0.3)])
    detector = next(d for d in json.loads(w.to_json())["world"]["detectors"] if "Rods" in d)["Rods"]
    assert sorted(mu for _, mu in detector["pair_friction"]) == [0.3, 0.5] and detector["friction"] == 0.1
    assert sk.World.from_json(w.to_json()).to_json() == w.to_json()
    for bad in [[(a, b, -0.2)], [(a, b, float("nan"))], [(a, b, 0.2), (b, a, 0.3)]]:
        with pytest.raises(sk.InvalidInputError):
            w.contact(margin=0.005, pair_friction=bad)
    stranger = sk.World().add_rod(sk.straight((0, 0, 0), (1, 0, 0), section=R, material="nylon", with_roll=False))
    with pytest.raises(sk.StrandkitError):
        w.contact(margin=0.005, pair_friction=[(a, stranger, 0.2)])
    assert len([d for d in json.loads(w.to_json())["world"]["detectors"] if "Rods" in d]) == 1
