"""DNA double helix (SPEC §9.1, issue 17), in molecular units: nm, pN, ns,
ag, K — use ``World(units="molecular")``.

>>> import strandkit as sk
>>> d = sk.dna.duplex("GATTACA")
>>> world = sk.World(units="molecular")
>>> ins = world.insert(d.assembly)
>>> [r.label for r in ins.rods]
['strand[0]', 'strand[1]']

- ``duplex``: the builder (two backbone strands, breakable hydrogen bonds,
  calibrated stacking);
- ``trajectory``: PDB/PSF/DCD with one bead per nucleotide, residues named
  by base, backbone and hydrogen bonds, broken pairs in the B-factor column;
- ``experiments``: trap pulling, unzipping, shear, stretching, and the
  thermal elasticity measured from fluctuations (``thermal_elasticity``).
"""
from .duplex import Duplex, duplex
from .viewer import trajectory
from . import experiments  # noqa: E402

__all__ = ["Duplex", "duplex", "experiments", "trajectory"]
