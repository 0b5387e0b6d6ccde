"""mdtraj reads our PDB (+CONECT) and PSF + DCD for a two-rod world over several frames."""
import mdtraj as md  # a hard requirement of the tests (pip install "./python[test]")
import numpy as np
import pytest

import strandkit as sk


def _run(world, prefix, frames=6):
    """Writes a trajectory and returns our bead positions per frame (length unit)."""
    ours = [sk.bead_positions(world)]
    with sk.TrajectoryWriter(world, str(prefix), scale=10.0) as tw:
        for _ in range(frames - 1):
            for _ in range(3):
                world.step()
            tw.write()
            ours.append(sk.bead_positions(world))
        assert tw.n_frames == frames
    return np.array(ours)


def _check_topology(top, world):
    n = [len(r.sample_params()) for r in world.rods()]
    assert top.n_atoms == sum(n)
    assert top.n_chains == 2
    assert [c.n_atoms for c in top.chains] == n
    assert {a.element.symbol for a in top.atoms} == {"P"}
    assert {r.name for r in top.residues} == {"SKB"}
    bonds = sorted(tuple(sorted((b[0].index, b[1].index))) for b in top.bonds)
    expected = []
    start = 0
    for k in n:
        expected += [(start + i, start + i + 1) for i in range(k - 1)]
        start += k
    assert bonds == expected
    # No bond between the two chains.
    chain = {a.index: a.residue.chain.index for a in top.atoms}
    assert all(chain[i] == chain[j] for i, j in bonds)


def test_mdtraj_reads_pdb_psf_dcd(two_rod_world, tmp_path):
    w, a, b = two_rod_world
    ours = _run(w, tmp_path / "run", frames=6)
    assert np.ptp(ours[:, :, 1]) > 0  # the rods actually moved

    pdb = md.load(str(tmp_path / "run.pdb"))
    _check_topology(pdb.topology, w)
    # PDB: 3 decimals in Å → 5e-4 Å = 5e-5 nm; one length unit = 10 Å = 1 nm here.
    assert np.abs(pdb.xyz[0] - ours[0]).max() <= 5.1e-5

    traj = md.load(str(tmp_path / "run.dcd"), top=str(tmp_path / "run.psf"))
    _check_topology(traj.topology, w)
    assert traj.n_frames == 6
    # DCD: float32 in Å; mdtraj converts to nm (÷10): equal within float32 precision.
    expected = (ours * 10.0).astype(np.float32) / np.float32(10.0)
    assert np.allclose(traj.xyz, expected, rtol=2e-7, atol=1e-7)
    assert np.abs(traj.xyz - ours).max() < 1e-6 * max(1.0, np.abs(ours).max())

    # The same DCD against the PDB topology, and our own reader.
    traj2 = md.load(str(tmp_path / "run.dcd"), top=str(tmp_path / "run.pdb"))
    assert np.array_equal(traj2.xyz, traj.xyz)
    header, xyz = sk.read_dcd(str(tmp_path / "run.dcd"))
    assert header["n_frames"] == 6 and header["n_atoms"] == traj.n_atoms
    assert np.allclose(xyz / np.float32(10.0), traj.xyz, rtol=2e-7, atol=0)


def test_dcd_append_after_snapshot(two_rod_world, tmp_path):
    """A run continued from a snapshot appends to the same DCD."""
    w, _, _ = two_rod_world
    prefix = tmp_path / "cont"
    with sk.TrajectoryWriter(w, str(prefix)) as tw:
        w.step()
        tw.write()
    w.save(str(tmp_path / "snap.json"))
    w2 = sk.World.load(str(tmp_path / "snap.json"))
    with sk.TrajectoryWriter(w2, str(prefix), append=True, pdb=False, psf=False) as tw:
        w2.step()
        tw.write()
        assert tw.n_frames == 3
    t = md.load(str(prefix) + ".dcd", top=str(prefix) + ".psf")
    assert t.n_frames == 3
    assert np.allclose(t.xyz[-1], sk.bead_positions(w2), atol=1e-6)


def test_pdb_refuses_coordinates_beyond_its_columns(two_rod_world, tmp_path):
    w, _, _ = two_rod_world
    with pytest.raises(ValueError, match="PSF \\+ DCD"):
        sk.write_pdb(w, str(tmp_path / "big.pdb"), scale=1e10)
    sk.write_psf(w, str(tmp_path / "big.psf"))
    assert (tmp_path / "big.psf").exists() and not (tmp_path / "big.pdb").exists()


def test_dcd_refuses_values_beyond_float32_and_writes_nothing(tmp_path):
    """A finite 1e300 used to be stored as float32 inf without an error."""
    path = str(tmp_path / "ovf.dcd")
    good = np.array([[0.0, 0.0, 0.0], [1.0, 2.0, 3.0]])
    with sk.DcdWriter(path, 2) as d:
        d.write_frame(good, scale=1.0)
        size = (tmp_path / "ovf.dcd").stat().st_size
        with pytest.raises(sk.InvalidInputError, match=r"DCD atom 1 coordinate \(Å, float32\) must be within") as e:
            d.write_frame(np.array([[0.0, 0.0, 0.0], [1e300, 0.0, 0.0]]), scale=1.0)
        assert e.value.value == "1e300"
        # Finite positions that overflow only once scaled to Å.
        with pytest.raises(sk.InvalidInputError, match="float32"):
            d.write_frame(good * 1e38, scale=10.0)
        assert d.n_frames == 1 and (tmp_path / "ovf.dcd").stat().st_size == size
        d.write_frame(good * 2, scale=1.0)
    header, xyz = sk.read_dcd(path)
    assert header["n_frames"] == 2 and np.isfinite(xyz).all()
    np.testing.assert_array_equal(xyz, np.array([good, good * 2], dtype=np.float32))


def test_pdb_columns_hold_up_to_their_width_and_a_refused_write_keeps_the_old_file(two_rod_world, tmp_path):
    w, _, _ = two_rod_world
    topo = sk.Topology(w)
    p = sk.bead_positions(w)
    path = tmp_path / "edge.pdb"
    for x in (9999.999, -999.999):  # the extremes of PDB's 8.3 columns (Å)
        q = p.copy()
        q[3, 0] = x
        topo.write_pdb(str(path), q, scale=1.0)
        assert md.load(str(path)).xyz[0, 3, 0] == pytest.approx(x / 10.0, abs=1e-6)  # nm
    before = path.read_bytes()
    for x in (10000.0, -1000.0, 1e300):
        q = p.copy()
        q[3, 0] = x
        with pytest.raises(sk.InvalidInputError, match="bead 3 coordinate .* does not fit PDB columns"):
            topo.write_pdb(str(path), q, scale=1.0)
    assert path.read_bytes() == before and sorted(f.name for f in tmp_path.iterdir()) == ["edge.pdb"]
