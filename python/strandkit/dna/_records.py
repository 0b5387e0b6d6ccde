"""The records of a DNA experiment: columns kept in memory and, with an
``out`` prefix, streamed to ``out.csv`` row by row (flushed, so that an
interrupted run keeps what it gathered) beside the run's trajectory
(``out.pdb/.psf/.dcd``, one frame every ``frame_every`` steps)."""
from __future__ import annotations

import csv
import os
from typing import Optional, Sequence

import numpy as np

from .viewer import trajectory as duplex_trajectory


class Records:
    """Use as a context manager: ``add(row)`` after each record,
    ``step(k)`` after each step (writes the frames), ``arrays()`` at the
    end; files are closed on leaving, also on an error."""

    def __init__(self, columns: Sequence[str], headers: Sequence[str], out: Optional[str], comment: str,
                 world=None, duplex=None, inserted=None, frame_every: int = 100):
        self.columns = list(columns)
        self.rows = {c: [] for c in self.columns}
        self.paths = {}
        self._fh = self._writer = self._trajectory = None
        self._frame_every = frame_every
        if out is None:
            return
        try:
            os.makedirs(os.path.dirname(os.path.abspath(out)), exist_ok=True)
            self.paths["csv"] = out + ".csv"
            self._fh = open(self.paths["csv"], "w", newline="")
            self._fh.write(f"# {comment}\n")
            self._writer = csv.writer(self._fh)
            self._writer.writerow(list(headers))
            self._trajectory = duplex_trajectory(world, duplex, inserted, out, every=frame_every)
            self.paths.update(self._trajectory.paths)
        except BaseException:
            self.close()
            raise

    def __enter__(self) -> "Records":
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def add(self, row: Sequence[float]) -> None:
        for c, v in zip(self.columns, row):
            self.rows[c].append(v)
        if self._writer is not None:
            self._writer.writerow([f"{v:.9g}" for v in row])
            self._fh.flush()

    def step(self, k: int) -> None:
        """After step ``k`` (1-based): a trajectory frame every ``frame_every``."""
        if self._trajectory is not None and k % self._frame_every == 0:
            self._trajectory.write()

    def arrays(self) -> dict:
        return {c: np.asarray(v, dtype=float) for c, v in self.rows.items()}

    def close(self) -> None:
        if self._trajectory is not None:
            self._trajectory.close()
            self._trajectory = None
        if self._fh is not None:
            self._fh.close()
            self._fh = None
