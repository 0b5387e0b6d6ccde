"""Pictures and meshes."""
import numpy as np
import pytest

import strandkit as sk

pytest.importorskip("matplotlib")


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
