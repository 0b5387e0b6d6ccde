"""strandkit: geometrically exact dynamic splines for slender elastic rods.

Build rods, put them in a World with constraints and loads, then ``step``
(implicit dynamics) or ``relax`` (static equilibrium). numpy in, numpy out;
keyword arguments carry units in their docstrings. The core is
unit-agnostic: use any consistent system (SI for the presets).

>>> import strandkit as sk
>>> world = sk.World(dt=1e-3, gravity=(0, -9.81, 0))
>>> rod = world.add_rod(sk.straight((0, 0, 0), (1, 0, 0), section=0.01, material="nylon"))
>>> sk.clamp(world, rod)
>>> world.relax().iterations > 0
True
>>> rod.position(rod.u_end)           # tip (length unit)
"""
from __future__ import annotations

from . import _native
from ._native import (
    BeadHandle,
    ClipHandle,
    ConstraintHandle,
    DcdWriter,
    Event,
    FrameReport,
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
from ._progress import progress
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
)
from .constraints import (
    Kind,
    axis,
    clamp,
    contact,
    curvature,
    distance,
    kind,
    material_roll,
    plane,
    position,
    relative_distance,
    relative_orientation,
    relative_position,
    oriented_sliding_point,
    sliding_point,
    tangent,
)
from .loads import distributed, point_force, point_torque
from .recorder import Recorder
from .trajectory import TrajectoryWriter, write_trajectory

__version__ = _native.__version__

__all__ = [
    # world and rods
    "World", "Rod", "Section", "Material", "QuasiDynamic", "FrameReport", "straight", "helix", "curve", "through_points",
    "from_control_points", "rod_from_json",
    # constraints and loads
    "Kind", "kind", "position", "tangent", "material_roll", "distance", "plane", "axis", "curvature",
    "relative_position", "relative_orientation", "relative_distance", "sliding_point",
    "oriented_sliding_point", "contact", "clamp",
    "point_force", "point_torque", "distributed",
    # reports and handles
    "StepReport", "RelaxReport", "Event", "Reaction", "ConstraintHandle", "LoadHandle", "BeadHandle", "ClipHandle",
    # errors
    "StrandkitError", "InvalidInputError", "InvalidHandleError", "SolverError", "SingularError",
    "ConvergenceError", "NonFiniteError", "DivergedError", "FileError", "WorldBusyError",
    # output
    "Recorder", "TrajectoryWriter", "write_trajectory", "Topology", "DcdWriter", "read_dcd",
    "bead_positions", "write_pdb", "write_psf", "tube_mesh", "write_obj", "write_vtk", "write_gltf",
    "run", "progress",
]


def run(world, steps: int, *, progress_bar: bool = True, callback=None, desc: str = "steps"):
    """Steps ``world`` ``steps`` times with a progress bar; ``callback(world,
    report)`` after each step. Returns (last StepReport, list of events)."""
    events, report = [], None
    for _ in progress(range(steps), desc=desc, enable=progress_bar):
        report = world.step()
        if report.events:
            events.extend(report.events)
        if callback is not None:
            callback(world, report)
    return report, events
