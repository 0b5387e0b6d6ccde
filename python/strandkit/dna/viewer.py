"""A duplex's trajectory for molecular viewers: one bead per nucleotide.

PDB + PSF + DCD (``strandkit.trajectory``'s writers) with two chains (A:
strand a, B: strand b, each 5′→3′), one residue per nucleotide named by its
base (DA, DC, DG, DT), bonds along each backbone and one hydrogen-bond
record per base pair (a PSF bond and a PDB CONECT between the paired
beads). Each bead is its nucleotide's point on the strand's centreline —
where the duplex's hydrogen bond attaches — so the distance between two
paired beads is the model's rung length. The PDB's B-factor column marks
each pair: 0 paired, 1 broken (its hydrogen bond is gone), 0.5 mismatched
(never paired); it is rewritten when a pair breaks, so VMD colours by
``Beta`` what has come apart.

>>> import os, tempfile
>>> import strandkit as sk
>>> d = sk.dna.duplex("GATTACA")
>>> world = sk.World(units="molecular")
>>> ins = world.insert(d.assembly)
>>> prefix = os.path.join(tempfile.mkdtemp(), "gattaca")
>>> with sk.dna.trajectory(world, d, ins, prefix) as tw:
...     tw.topology
Topology(14 beads in 2 chains, 19 bonds)
"""
from __future__ import annotations

import numpy as np

from .. import _native
from ..errors import _invalid
from ..trajectory import TrajectoryWriter

__all__ = ["trajectory"]

PAIRED, BROKEN, MISMATCHED = 0.0, 1.0, 0.5


def trajectory(world, duplex, inserted, prefix: str, *, every: int = 1, scale: float = 10.0,
               initial: bool = True) -> TrajectoryWriter:
    """A ``TrajectoryWriter`` of ``duplex`` as inserted in ``world``
    (``inserted = world.insert(duplex.assembly)``): ``prefix``.pdb/.psf/.dcd,
    one bead per nucleotide; ``every``: steps between frames (NSAVC);
    ``scale``: Å per nm (10). Call ``write()`` after the steps to record;
    use as a context manager or ``close()`` it."""
    n_c = len(inserted.constraints)
    if len(inserted.rods) <= max(duplex.strands) or any(
            h is not None and (h >= n_c or inserted.constraints[h].label != f"hbond[{k}]")
            for k, h in enumerate(duplex.hbonds)):
        raise _invalid("inserted is not what world.insert(duplex.assembly) returned for this duplex")
    rods = [inserted.rods[i] for i in duplex.strands]
    if any(r.world is not world for r in rods):
        raise _invalid("the duplex's strands belong to another world than the one given")
    us = [np.asarray(u, dtype=float) for u in duplex.abscissae]
    n_a, n_b = len(us[0]), len(us[1])
    residues = [["D" + c for c in s] for s in duplex.sequences]
    pairs = [(k, int(duplex.partner[k]), inserted.constraints[h]) for k, h in enumerate(duplex.hbonds)
             if h is not None]
    topology = _native.Topology.of_beads([n_a, n_b], residues=residues, links=[[k, n_a + j] for k, j, _ in pairs])

    def positions():
        return np.concatenate([rods[0].position(us[0]), rods[1].position(us[1])])

    def bfactors():
        marks = np.full(n_a + n_b, PAIRED)
        for k in duplex.mismatches:
            marks[k] = marks[n_a + int(duplex.partner[k])] = MISMATCHED
        for k, j, h in pairs:
            if not h.alive:
                marks[k] = marks[n_a + j] = BROKEN
        return marks

    return TrajectoryWriter(world, prefix, scale=scale, every=every, initial=initial, topology=topology,
                            positions=positions, bfactors=bfactors)
