"""Pictures and meshes."""
import matplotlib  # noqa: F401  (a hard requirement of the tests: pip install "./python[test]")
import numpy as np
import pytest

import strandkit as sk


def test_png_has_expected_size_and_content(two_rod_world, tmp_path):
    from matplotlib.image import imread

    import strandkit.plot as skplot

    w, _, _ = two_rod_world
    for _ in range(20):
        w.step()
    path = tmp_path / "scene.png"
    skplot.plot_world(w, str(path), size=(640, 480), title="two rods")
    assert path.stat().st_size > 10_000
    img = imread(str(path))
    assert img.shape[:2] == (480, 640)
    rgb = img[..., :3]
    # Not blank: many non-white pixels, and both tube colours present.
    coloured = (rgb.max(axis=2) - rgb.min(axis=2)) > 0.15
    assert coloured.mean() > 0.01
    assert len(np.unique((rgb[coloured] * 8).astype(int), axis=0)) > 10


def test_curves_png(tmp_path):
    from matplotlib.image import imread

    import strandkit.plot as skplot

    rec = {"time": np.linspace(0, 1, 50), "y": np.sin(np.linspace(0, 6, 50))}
    p = tmp_path / "c.png"
    skplot.plot_curves(rec, "y", path=str(p), references={"zero": 0.0}, size=(500, 300))
    assert imread(str(p)).shape[:2] == (300, 500)


def test_mesh_arrays_and_files(two_rod_world, tmp_path):
    w, a, b = two_rod_world
    v, n, tri, part = sk.tube_mesh(w, rings_per_segment=3, points_per_ring=10)
    assert v.shape == n.shape and v.shape[1] == 3 and tri.shape[1] == 3
    assert tri.min() == 0 and tri.max() == len(v) - 1
    assert set(np.unique(part)) == {0, 1}
    assert np.allclose(np.linalg.norm(n, axis=1), 1.0)
    sk.write_obj(w, str(tmp_path / "w.obj"))
    sk.write_vtk(w, str(tmp_path / "w.vtk"))
    obj = (tmp_path / "w.obj").read_text()
    assert obj.count("\nv ") == len(sk.tube_mesh(w)[0])
    assert (tmp_path / "w.vtk").read_text().startswith("# vtk DataFile Version 3.0")


def test_frames_are_orthonormal(two_rod_world):
    _, _, helix = two_rod_world
    p, t, d1, d2 = helix.frames(n=50)
    for x, y in [(t, d1), (t, d2), (d1, d2)]:
        assert np.abs((x * y).sum(axis=1)).max() < 1e-12
    assert np.allclose(np.cross(d1, d2), t)
    assert np.allclose(p, helix.position(helix.uniform_params(50)))


def test_gltf_reads_back_with_trimesh(two_rod_world, tmp_path):
    """An independent reader (trimesh) loads our .glb: one named node per
    rod, the same vertices (float32) and triangles as tube_mesh."""
    import trimesh  # in the [test] extras

    w, a, b = two_rod_world
    path = tmp_path / "w.glb"
    sk.write_gltf(w, str(path), rings_per_segment=3, points_per_ring=10)
    scene = trimesh.load(str(path), force="scene")
    assert sorted(scene.geometry) == ["rod0", "rod1"]
    v, _, tri, part = sk.tube_mesh(w, rings_per_segment=3, points_per_ring=10)
    for p in (0, 1):
        g = scene.geometry[f"rod{p}"]
        mine = v[part == p]
        np.testing.assert_allclose(g.vertices, mine.astype(np.float32), rtol=0, atol=1e-6)
        assert len(g.faces) == int(np.sum(part[tri[:, 0]] == p))


@pytest.mark.parametrize("sizes", [
    dict(rings_per_segment=10**9, points_per_ring=10**9),   # used to abort on a 40 GB allocation
    dict(rings_per_segment=2**63),                          # used to panic: capacity overflow
    dict(rings_per_segment=2**64 - 1, points_per_ring=2**64 - 1),
    dict(rings_per_segment=200_000, points_per_ring=12),    # 5 segments: 1.2e7 vertices > 1e7
])
def test_absurd_mesh_sizes_are_errors_before_allocating(two_rod_world, tmp_path, sizes):
    w, rod, _ = two_rod_world
    for call in (lambda: sk.tube_mesh(w, **sizes), lambda: sk.tube_mesh(rod, **sizes), lambda: rod.mesh(**sizes),
                 lambda: sk.write_obj(w, str(tmp_path / "m.obj"), **sizes)):
        with pytest.raises(sk.InvalidInputError, match="tube mesh size must be at most 10000000 vertices") as e:
            call()
        assert isinstance(e.value, ValueError)
    assert list(tmp_path.iterdir()) == []


def test_mesh_size_cap_counts_vertices_as_built():
    rod = sk.straight((0, 0, 0), (1, 0, 0), section=0.01, material="nylon", n_control_points=4)  # 1 segment
    # (rings + 1) × points vertices, + 2 × (points + 1) for the caps.
    v, _, _ = rod.mesh(rings_per_segment=7, points_per_ring=10, caps=True)
    assert v.shape == ((7 + 1) * 10 + 2 * 11, 3)
    # One ring past the cap (10^7 vertices exactly is allowed: core io::mesh tests).
    with pytest.raises(sk.InvalidInputError, match="1 segments × 1000000 rings × 10 points per ring"):
        rod.mesh(rings_per_segment=1_000_000, points_per_ring=10, caps=False)


@pytest.mark.parametrize("n", [10**10, 2**64 - 1, 10**7 + 1])
def test_absurd_parameter_counts_are_errors_before_allocating(n):
    rod = sk.straight((0, 0, 0), (1, 0, 0), section=0.01, material="nylon", n_control_points=8)
    with pytest.raises(sk.InvalidInputError, match=f"uniform_params n must be at most 10000000, got {n}"):
        rod.uniform_params(n)
    with pytest.raises(sk.InvalidInputError, match="frames n must be at most 10000000"):
        rod.frames(n=n)
    u = rod.uniform_params(5)
    np.testing.assert_allclose(u, np.linspace(rod.u_start, rod.u_end, 5), rtol=0, atol=1e-15)
