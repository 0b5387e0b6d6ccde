"""Trajectories for molecular viewers (SPEC §8), written by the Rust core.

``<prefix>.pdb`` (first frame + CONECT bonds; with ``bfactors``, rewritten
at the frame where they change), ``<prefix>.psf`` (topology) and
``<prefix>.dcd`` (coordinates per frame): one bead per rod sample point,
one chain per rod (or the beads of a given topology, e.g. one per
nucleotide: ``strandkit.dna.trajectory``). Load them with mdtraj::

    md.load("run.dcd", top="run.psf")      # or md.load("run.pdb")

``scale`` is Å per length unit: 10 for a world in nm (DNA); for an SI world
(m) the default 10 shows a 4 m rod as 40 Å, which viewers display well.
"""
from __future__ import annotations

import os

from . import _native
from ._progress import progress
from .errors import _invalid

__all__ = ["TrajectoryWriter", "write_trajectory"]


class TrajectoryWriter:
    """Writes topology files once and appends DCD frames.

    >>> import os, tempfile
    >>> import strandkit as sk
    >>> world = sk.World(gravity=(0, -9.81, 0))
    >>> rod = world.add_rod(sk.straight((0, 0, 0), (1, 0, 0), section=0.01, material="nylon", n_control_points=6))
    >>> prefix = os.path.join(tempfile.mkdtemp(), "run")
    >>> with TrajectoryWriter(world, prefix) as tw:
    ...     for _ in range(3):
    ...         report = world.step()
    ...         tw.write()
    >>> tw.n_frames, sorted(os.listdir(os.path.dirname(prefix)))
    (4, ['run.dcd', 'run.pdb', 'run.psf'])

    The current state is written as frame 0 on creation (``initial=True``).
    ``every``: steps between frames (stored as NSAVC). ``append=True``
    continues an existing DCD (e.g. after reloading a snapshot).
    ``topology`` (a ``_native.Topology.of_beads``) with ``positions`` (a
    function returning its (n_beads, 3) positions) writes other beads than
    the rods' sample points, e.g. one per nucleotide
    (``strandkit.dna.trajectory``); ``bfactors``: a function returning one
    value per bead for the PDB's temperature-factor column.
    """

    def __init__(self, world, prefix: str, *, scale: float = 10.0, every: int = 1, pdb: bool = True,
                 psf: bool = True, initial: bool = True, append: bool = False, topology=None, positions=None,
                 bfactors=None):
        self.world = world
        self.scale = float(scale)
        self.prefix = str(prefix)
        d = os.path.dirname(os.path.abspath(self.prefix))
        os.makedirs(d, exist_ok=True)
        if (topology is None) != (positions is None):
            raise _invalid("topology and positions go together: a Topology.of_beads and a function giving "
                           "its (n_beads, 3) positions")
        self.topology = _native.Topology(world) if topology is None else topology
        self._positions = (lambda: _native.bead_positions(world)) if positions is None else positions
        self._bfactors = bfactors
        self._marks = None if bfactors is None else list(bfactors())
        self.paths = {"dcd": self.prefix + ".dcd"}
        if pdb:
            self.paths["pdb"] = self.prefix + ".pdb"
            self._write_pdb()
        if psf:
            self.paths["psf"] = self.prefix + ".psf"
            self.topology.write_psf(self.paths["psf"])
        if append and os.path.exists(self.paths["dcd"]):
            self.dcd = _native.DcdWriter.append(self.paths["dcd"])
            if self.dcd.n_atoms != self.topology.n_beads:
                self.dcd.close()
                raise _invalid(f"{self.paths['dcd']} has {self.dcd.n_atoms} atoms, "
                               f"the world has {self.topology.n_beads} beads")
        else:
            self.dcd = _native.DcdWriter(self.paths["dcd"], self.topology.n_beads, dt=world.dt, nsavc=every,
                                         istart=world.n_steps)
            if initial:
                self.write()

    def _write_pdb(self) -> None:
        self.topology.write_pdb(self.paths["pdb"], self._positions(), scale=self.scale, bfactors=self._marks)

    def write(self) -> None:
        """Appends the current bead positions as one frame. With
        ``bfactors``, the PDB is rewritten (atomically, at this frame) when
        they change, so a viewer colours e.g. broken bonds as they break."""
        self.dcd.write_frame(self._positions(), scale=self.scale)
        if self._bfactors is not None:
            marks = list(self._bfactors())
            if marks != self._marks:
                self._marks = marks
                if "pdb" in self.paths:
                    self._write_pdb()

    @property
    def n_frames(self) -> int:
        return self.dcd.n_frames

    def close(self) -> None:
        self.dcd.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
        return False

    def __repr__(self) -> str:
        return f"TrajectoryWriter({self.prefix!r}, {self.topology.n_beads} beads, {self.n_frames} frames)"


def write_trajectory(world, prefix: str, steps: int, *, every: int = 1, scale: float = 10.0,
                     progress_bar: bool = True, recorder=None) -> dict:
    """Steps ``world`` ``steps`` times writing PDB + PSF and a DCD frame
    every ``every`` steps (plus the initial state). A ``Recorder`` given as
    ``recorder`` records every step. Returns the paths written."""
    with TrajectoryWriter(world, prefix, scale=scale, every=every) as tw:
        if recorder is not None and len(recorder) == 0:
            recorder.record()
        for k in progress(range(steps), desc="trajectory", enable=progress_bar):
            report = world.step()
            if recorder is not None:
                recorder.record(report)
            if (k + 1) % every == 0:
                tw.write()
        return dict(tw.paths)
