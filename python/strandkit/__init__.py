"""strandkit: geometrically exact dynamic splines for slender elastic rods.

Build rods, put them in a World with constraints and loads, then ``step``
(implicit dynamics) or ``relax`` (static equilibrium). numpy in, numpy out;
keyword arguments carry units in their docstrings. The core is
unit-agnostic: use any consistent system (SI for the presets).

>>> import strandkit as sk
>>> world = sk.World(dt=1e-3, gravity=(0, -9.81, 0))
>>> rod = world.add_rod(sk.straight((0, 0, 0), (1, 0, 0), section=0.01, material="nylon"))
>>> handles = sk.clamp(world, rod)            # position, tangent (+ roll) at u = 0
>>> report = world.relax()
>>> report.violation < 1e-8
True
>>> tip = rod.position(rod.u_end)            # tip (length unit)
>>> print(f"tip sags by {-tip[1]:.3f}")
tip sags by 0.020

Structures are described first and inserted in one batch (:class:`Assembly`),
with labels that make groups the world answers for (:meth:`World.group`).
"""
from __future__ import annotations

from . import _native
from ._native import (
    Assembly,
    BeadHandle,
    ClipHandle,
    ConstraintHandle,
    DcdWriter,
    Event,
    FrameReport,
    Group,
    Inserted,
    LoadHandle,
    Material,
    QuasiDynamic,
    Reaction,
    RelaxReport,
    Rod,
    Section,
    StepReport,
    Topology,
    World,
    bead_positions,
    curve,
    from_control_points,
    helix,
    read_dcd,
    resistive_force_drag,
    rod_from_json,
    straight,
    through_points,
    tube_mesh,
    write_gltf,
    write_obj,
    write_pdb,
    write_psf,
    write_vtk,
)
from . import constraints, loads, obstacles, polymer, units
from ._progress import progress
from .constraints import *  # noqa: F401,F403  (Kind, kind, clamp and one helper per constraint kind)
from .errors import (
    ConvergenceError,
    DivergedError,
    FileError,
    InvalidHandleError,
    InvalidInputError,
    NonFiniteError,
    SingularError,
    SolverError,
    StrandkitError,
    WorldBusyError,
    SceneError,
    Interrupted,
)
from .loads import *  # noqa: F401,F403  (one helper per load kind)
from .recorder import Recorder
from .trajectory import TrajectoryWriter, write_trajectory
from . import builders  # noqa: E402  (strandkit.builders: structure builders)
from . import dna  # noqa: E402  (strandkit.dna: the DNA duplex)
from . import knit  # noqa: E402  (strandkit.knit: weft-knit fabrics)
from . import scene  # noqa: E402  (strandkit.scene: scene files)
from .scene import Scene, load_scene, save_scene, run_scene  # noqa: E402
from .sweeps import sweep  # noqa: E402

__version__ = _native.__version__

__all__ = [
    # world and rods
    "World", "Rod", "Section", "Material", "QuasiDynamic", "FrameReport", "straight", "helix", "curve",
    "through_points", "from_control_points", "rod_from_json",
    # structures and groups
    "Assembly", "Inserted", "Group",
    # reports and handles
    "StepReport", "RelaxReport", "Event", "Reaction", "ConstraintHandle", "LoadHandle", "BeadHandle", "ClipHandle",
    # errors
    "StrandkitError", "InvalidInputError", "InvalidHandleError", "SolverError", "SingularError",
    "ConvergenceError", "NonFiniteError", "DivergedError", "FileError", "WorldBusyError",
    "SceneError", "Interrupted",
    # scenes and sweeps
    "Scene", "load_scene", "save_scene", "run_scene", "sweep",
    # output
    "Recorder", "TrajectoryWriter", "write_trajectory", "Topology", "DcdWriter", "read_dcd",
    "bead_positions", "write_pdb", "write_psf", "tube_mesh", "write_obj", "write_vtk", "write_gltf",
    "run", "progress",
]
# constraint and load helpers (generated from the core's catalogues)
__all__ += constraints.__all__
__all__ += loads.__all__


def run(world, steps: int, *, progress_bar: bool = True, callback=None, desc: str = "steps"):
    """Steps ``world`` ``steps`` times with a progress bar; ``callback(world,
    report)`` after each step. Returns (last StepReport, list of events).

    >>> import strandkit as sk
    >>> w = sk.World(gravity=(0, -9.81, 0))
    >>> rod = w.add_rod(sk.straight((0, 0, 0), (1, 0, 0), section=0.01, material="nylon", n_control_points=6))
    >>> report, events = sk.run(w, 3, progress_bar=False)
    >>> round(w.time, 6), events
    (0.003, [])
    """
    events, report = [], None
    for _ in progress(range(steps), desc=desc, enable=progress_bar):
        report = world.step()
        if report.events:
            events.extend(report.events)
        if callback is not None:
            callback(world, report)
    return report, events
