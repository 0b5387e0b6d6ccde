"""A duplex's trajectory (issue 17): mdtraj reads what strandkit.dna
writes — one bead per nucleotide, two chains, residues named by base,
backbone and hydrogen bonds — and measures between paired beads the
model's own rung lengths; VMD's B-factor column marks the broken pairs."""
import math

import mdtraj as md
import numpy as np
import pytest

import strandkit as sk
from conftest import end_pair_pulled

SEQ = "GCGATTACAGCG"


def pulled_apart(tmp_path, steps=6):
    """A 12 bp duplex whose end pair is pulled open (its bond breaks at
    5 pN; the others cannot), one frame per step."""
    n = len(SEQ)
    d, w, ins, a, b = end_pair_pulled(SEQ, [5.0] + [math.inf] * (n - 1))
    prefix = str(tmp_path / "pull")
    rungs = []  # the model's rung lengths per frame (nm)

    def rung_lengths():
        pa = a.position(d.abscissae[0])
        pb = b.position(d.abscissae[1][d.partner])
        return np.linalg.norm(pb - pa, axis=1)

    with sk.dna.trajectory(w, d, ins, prefix) as tw:
        rungs.append(rung_lengths())
        for _ in range(steps):
            w.step()
            tw.write()
            rungs.append(rung_lengths())
    return d, prefix, np.array(rungs)


def test_mdtraj_reads_one_bead_per_nucleotide(tmp_path):
    d, prefix, rungs = pulled_apart(tmp_path)
    n = len(d)
    t = md.load(prefix + ".dcd", top=prefix + ".psf")
    top = t.topology
    assert t.n_frames == 7 and t.n_atoms == 2 * n
    assert top.n_chains == 2 and top.n_residues == 2 * n
    names = [r.name for r in top.residues]
    assert names == ["D" + c for c in d.sequences[0]] + ["D" + c for c in d.sequences[1]]
    bonds = {tuple(sorted((x.index, y.index))) for x, y in top.bonds}
    backbone = {(i, i + 1) for i in range(n - 1)} | {(n + i, n + i + 1) for i in range(n - 1)}
    hbonds = {(k, n + int(d.partner[k])) for k in range(n)}
    assert bonds == backbone | hbonds
    # mdtraj's distances (nm, float32 coordinates in Å) are the model's.
    pairs = np.array(sorted(hbonds))
    dist = md.compute_distances(t, pairs)
    assert np.allclose(dist, rungs[:, pairs[:, 0]], atol=2e-5)
    # Rigid bonds hold their length (the step linearises them: 1.4e-4 nm
    # drift under this pull); the pulled end pair opened.
    assert np.allclose(dist[:, 1:], d.rung_length, atol=3e-4)
    assert dist[-1, 0] > d.rung_length + 0.05
    # The PDB reads the same topology (HETATM CONECT records kept).
    p = md.load(prefix + ".pdb")
    assert {tuple(sorted((x.index, y.index))) for x, y in p.topology.bonds} == bonds
    assert [r.name for r in p.topology.residues] == names


def test_broken_pairs_are_marked_in_the_b_factor_column(tmp_path):
    d, prefix, _ = pulled_apart(tmp_path)
    n = len(d)
    with open(prefix + ".pdb") as f:
        beta = np.array([float(l[60:66]) for l in f if l.startswith("HETATM")])
    broken = np.zeros(2 * n)
    broken[[0, n + int(d.partner[0])]] = 1.0
    assert np.array_equal(beta, broken)


def test_mismatches_are_marked_and_bad_arguments_refused(tmp_path):
    d = sk.dna.duplex("AACGTG", complement="CACTTT")
    w = sk.World(units="molecular")
    ins = w.insert(d.assembly)
    prefix = str(tmp_path / "mm")
    with sk.dna.trajectory(w, d, ins, prefix):
        pass
    with open(prefix + ".pdb") as f:
        beta = [float(l[60:66]) for l in f if l.startswith("HETATM")]
    assert beta[2] == 0.5 and beta[6 + int(d.partner[2])] == 0.5 and beta.count(0.5) == 2
    t = md.load(prefix + ".pdb")
    assert t.topology.n_bonds == 2 * 5 + 5  # no hydrogen bond for the mismatch
    other = sk.World(units="molecular")
    with pytest.raises(sk.InvalidInputError, match="another world"):
        sk.dna.trajectory(other, d, ins, prefix)
    with pytest.raises(sk.InvalidInputError, match="positions go together"):
        sk.TrajectoryWriter(w, prefix, topology=sk._native.Topology(w))
