"""Structure builders (SPEC §9): pure functions from parameters in SI units
to an :class:`~strandkit.Assembly`, and experiments that take a world.

>>> import strandkit as sk
>>> bridge = sk.builders.rope_bridge(span=10.0, n_planks=12)
>>> w = sk.World(gravity=(0, -9.81, 0))
>>> ins = w.insert(bridge.assembly)
>>> report = w.relax()
>>> len(w.group("plank").forces)       # two pins per plank
24

Axes: x along the span, y up, z across.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Optional

import numpy as np

from . import _native

__all__ = ["RopeBridge", "rope_bridge", "walk_across", "Necklace", "necklace", "BeadsOnSpring", "beads_on_spring",
           "CableOnClips", "cable_on_clips", "Harness", "harness"]


@dataclass(frozen=True)
class RopeBridge:
    """A built rope bridge: the assembly to insert, and where its parts are.

    ``ropes``: assembly rod indices of floor[0], floor[1], handrail[0],
    handrail[1]; ``planks``: rod index of each plank (``plank_model="body"``);
    ``stations``: each plank's abscissa u on the ropes; ``station_x``: its
    horizontal position in the design shape (m)."""

    assembly: object
    ropes: list
    planks: list
    stations: np.ndarray
    station_x: np.ndarray
    params: dict = field(default_factory=dict)

    def __repr__(self):
        p = self.params
        return (f"RopeBridge(span={p['span']} m, n_planks={p['n_planks']}, plank_mass={p['plank_mass']} kg, "
                f"sag={p['sag']} m, width={p['width']} m, handrail_height={p['handrail_height']} m, "
                f"plank_model={p['plank_model']!r}, rods={len(self.ropes) + len(self.planks)})")


def rope_bridge(*, span: float = 10.0, n_planks: int = 12, plank_mass: float = 4.0, sag: float = 1.0,
                width: float = 1.0, handrail_height: float = 1.0, rope: Optional[dict] = None,
                plank_depth: float = 0.2, plank_thickness: float = 0.03, plank_young: float = 1e10,
                plank_model: str = "body", plank_break_force: Optional[float] = None,
                rope_control_points: Optional[int] = None) -> RopeBridge:
    """Rope bridge (SPEC §9.2, thesis III.C.4): two floor ropes and two
    handrails anchored at both ends, planks held by the floor ropes,
    verticals from handrails to floor ropes.

    span: m between anchors; n_planks: planks at equal horizontal spacing
    span/(n_planks+1); plank_mass: kg; sag: m, mid-span sag of the floor
    ropes' design shape (their rest length is that of the funicular polygon
    of the planks' weights with this sag, or of the catenary without
    planks); width: m between the floor ropes (plank length);
    handrail_height: m above the floor ropes (0: no handrails);
    rope: {'linear_density': kg/m, 'axial_stiffness': N (EA),
    'bending_stiffness': N·m² (EI)} (default: 20 mm polyamide rope, 0.25
    kg/m, 2e5 N, 0.05 N·m²); plank_depth, plank_thickness: m;
    plank_young: Pa; plank_model: "body" (a wooden rod pinned to both
    floor ropes) or "link" (the thesis' distance constraint plus its weight
    as point loads, m·9.81 N along −y); plank_break_force: N above which a
    plank's pin (link) breaks; rope_control_points: per rope (default 4
    per plank spacing, at least 8).

    Labels: "floor[0|1]", "handrail[0|1]", "plank[i]" (rod and pins),
    "vertical[i]", "anchor[k,e]" (rope k, end e). Use gravity (0, −9.81, 0).
    """
    params = dict(span=float(span), n_planks=int(n_planks), plank_mass=float(plank_mass), sag=float(sag),
                  width=float(width), handrail_height=float(handrail_height), rope=rope,
                  plank_depth=float(plank_depth), plank_thickness=float(plank_thickness),
                  plank_young=float(plank_young), plank_model=plank_model, plank_break_force=plank_break_force,
                  rope_control_points=rope_control_points)
    if int(n_planks) < 0:
        from .errors import InvalidInputError
        raise InvalidInputError(f"invalid input: n_planks = {n_planks}, expected >= 0")
    asm, layout = _native.build_rope_bridge(**params)
    return RopeBridge(asm, list(layout["ropes"]), list(layout["planks"]), np.asarray(layout["stations"]),
                      np.asarray(layout["station_x"]), params)


def walk_across(world, bridge: RopeBridge, inserted, *, mass: float = 80.0, speed: float = 1.0,
                dt: float = 2e-3, g: float = 9.81, record_every: int = 10, callback=None):
    """Experiment: a walker of ``mass`` (kg) crosses the bridge at ``speed``
    (m/s), its weight shared between the two planks it stands between
    (linearly in x) as point loads on their middles. Steps ``world`` with
    time step ``dt`` (s) until the walker is off the far end; a break or a
    refused step ends the walk early.

    Returns a dict of arrays sampled every ``record_every`` steps: ``time``
    (s), ``walker_x`` (m), ``deflection`` (m, the floor's height under the
    walker relative to the design shape, negative down), ``max_pin_force``
    (N, the largest plank pin reaction), and ``events`` (the list of events
    of the walk) and ``stopped`` (None, or the error that stopped it).
    ``callback(step, world)``, if given, runs after every step (e.g. a
    ``TrajectoryWriter.write``)."""
    from . import point_force
    if not bridge.planks:
        raise ValueError("walk_across needs plank bodies (plank_model='body' and n_planks >= 1)")
    if not (mass > 0 and speed > 0 and dt > 0):
        raise ValueError(f"mass, speed and dt must be > 0, got {mass}, {speed}, {dt}")
    world.set_params(dt=dt)
    rods = inserted.rods
    planks = [rods[i] for i in bridge.planks]
    floor = rods[bridge.ropes[0]]
    xs = np.asarray(bridge.station_x)
    span, sag = bridge.params["span"], bridge.params["sag"]
    n = len(planks)
    mids = [0.5 * (p.domain[0] + p.domain[1]) for p in planks]
    loads = [world.add_load(point_force(p, mids[i], (0.0, 0.0, 0.0))) for i, p in enumerate(planks)]
    out = {k: [] for k in ("time", "walker_x", "deflection", "max_pin_force")}
    events, stopped = [], None
    steps = int(np.ceil(span / speed / dt))
    try:
        for k in range(steps + 1):
            x = speed * k * dt
            weights = np.zeros(n)
            j = int(np.searchsorted(xs, x))
            if 0 < j < n:
                t = (x - xs[j - 1]) / (xs[j] - xs[j - 1])
                weights[j - 1], weights[j] = 1 - t, t
            elif j == 0 and n:
                weights[0] = x / xs[0]
            elif j >= n and n:
                weights[-1] = max(0.0, (span - x) / (span - xs[-1]))
            for i, h in enumerate(loads):
                world.set_load(h, point_force(planks[i], mids[i], (0.0, -mass * g * weights[i], 0.0)))
            rep = world.step()
            events += list(rep.events)
            if callback is not None:
                callback(k, world)
            if k % record_every == 0:
                u = floor.u_at_arc_length(min(floor.rest_length, max(0.0, x / span * floor.rest_length)))
                p = floor.position(u)
                design = -4 * sag * p[0] * (span - p[0]) / span**2
                forces = world.group("plank").forces
                out["time"].append(world.time)
                out["walker_x"].append(x)
                out["deflection"].append(p[1] - design)
                out["max_pin_force"].append(float(np.linalg.norm(forces, axis=1).max()) if len(forces) else 0.0)
    except Exception as e:  # noqa: BLE001  (a refused step ends the walk; it is reported)
        stopped = e
    result = {k: np.asarray(v) for k, v in out.items()}
    result["events"] = events
    result["stopped"] = stopped
    return result


@dataclass(frozen=True)
class Necklace:
    """A built necklace: the assembly to insert, and where its parts are.

    ``string``: assembly rod index of the string; ``beads``: assembly bead
    indices in order along it; ``supports``: constraint indices of the peg
    (one) or the two supports; ``bead_arc_lengths``: each bead's starting
    place along the string (m of rest length)."""

    assembly: object
    string: int
    beads: list
    supports: list
    bead_arc_lengths: np.ndarray
    params: dict = field(default_factory=dict)

    def __repr__(self):
        p = self.params
        return (f"Necklace(n_beads={p['n_beads']}, bead_mass={p['bead_mass']} kg, bead_radius={p['bead_radius']} m, "
                f"length={p['length']} m, closed={p['closed']}, hang={p['hang']!r}, friction={p['friction']} N·s/m, "
                f"knotted={p['knotted']})")


def necklace(*, n_beads: int = 12, bead_mass: float = 0.002, bead_radius: float = 0.006,
             string: Optional[dict] = None, length: float = 0.6, closed: bool = True, hang: str = "peg",
             peg=(0.0, 0.0, 0.0), supports=((-0.1, 0.0, 0.0), (0.1, 0.0, 0.0)), friction: float = 1e-3,
             peg_friction: float = 0.0, knotted: bool = False, control_points: int = 16) -> Necklace:
    """Bead necklace (SPEC §9.4, thesis III.C.5): beads threaded on a
    string — sliding-abscissa particles of finite size that never pass each
    other, with viscous friction — a closed string over a peg (the string
    runs freely through it) or a string held at two points.

    n_beads; bead_mass: kg; bead_radius: m (centres stay 2r apart along
    the string); string: {'linear_density': kg/m, 'axial_stiffness': N,
    'bending_stiffness': N·m²} (default a 0.5 mm nylon thread: 2e-4 kg/m,
    600 N, 9e-6 N·m²); length: m of string; closed: a loop (tied: straight
    at rest) or an open string; hang: "peg" (closed only; ``peg`` the point,
    m) or "two_points" (``supports``, two points in m: an open string's
    ends, or two points of the loop); friction: N·s/m of a bead sliding on
    the string; peg_friction: N·s/m of the string running over the peg;
    knotted: beads held in place (knots either side); control_points: of
    the string (16, the thesis' scene).

    The string starts on a circle in the vertical plane of its supports
    and the beads spread evenly along it. Labels: "string", "bead[i]",
    "peg" or "support[0|1]". Use gravity (0, −9.81, 0). Over a peg the
    necklace can turn about the vertical and run round the peg freely, so
    it is a scene for ``step`` (``relax`` names those free motions)."""
    params = dict(n_beads=int(n_beads), bead_mass=float(bead_mass), bead_radius=float(bead_radius), string=string,
                  length=float(length), closed=bool(closed), hang=hang, friction=float(friction),
                  peg_friction=float(peg_friction), knotted=bool(knotted), control_points=int(control_points))
    from .errors import InvalidInputError
    for k in ("n_beads", "control_points"):
        if params[k] < 0:
            raise InvalidInputError(f"invalid input: {k} = {params[k]}, expected >= 0")
    peg3 = tuple(float(x) for x in peg)
    sup = tuple(tuple(float(x) for x in p) for p in supports)
    if len(peg3) != 3 or len(sup) != 2 or any(len(p) != 3 for p in sup):
        raise InvalidInputError("invalid input: peg is one point (x, y, z) and supports two points, in m")
    asm, layout = _native.build_necklace(peg=peg3, supports=sup, **params)
    params.update(peg=peg3, supports=sup)
    return Necklace(asm, int(layout["string"]), list(layout["beads"]), list(layout["supports"]),
                    np.asarray(layout["bead_arc_lengths"]), params)


def _non_negative_ints(**kw):
    from .errors import InvalidInputError
    for k, x in kw.items():
        if int(x) < 0:
            raise InvalidInputError(f"invalid input: {k} = {x}, expected >= 0")


def _points(value, what):
    """A list of (x, y, z) points in m, or InvalidInputError naming `what`."""
    from .errors import InvalidInputError
    try:
        pts = [tuple(float(c) for c in p) for p in value]
    except (TypeError, ValueError) as e:
        raise InvalidInputError(f"invalid input: {what} must be a list of (x, y, z) points in m ({e})") from None
    if any(len(p) != 3 for p in pts):
        raise InvalidInputError(f"invalid input: {what} must be a list of (x, y, z) points in m")
    return pts


@dataclass(frozen=True)
class BeadsOnSpring:
    """A built spring with beads: the assembly, and where its parts are.

    ``spring``: assembly rod index; ``clamp``: constraint indices of the
    clamp at the top; ``beads``: bead indices (bead[0] lowest);
    ``bead_arc_lengths``: m of wire from the clamp; ``wire_length``: m;
    ``helix_angle``: rad above the horizontal; ``close_coiled_rate``: N/m,
    the textbook G d⁴/(8 D³ N)."""

    assembly: object
    spring: int
    clamp: list
    beads: list
    bead_arc_lengths: np.ndarray
    wire_length: float
    helix_angle: float
    close_coiled_rate: float
    params: dict = field(default_factory=dict)

    def __repr__(self):
        p = self.params
        return (f"BeadsOnSpring(coil_radius={p['coil_radius']} m, pitch={p['pitch']} m, turns={p['turns']}, "
                f"wire_radius={p['wire_radius']} m, n_beads={p['n_beads']}, bead_mass={p['bead_mass']} kg, "
                f"wire_length={self.wire_length:.4g} m, close_coiled_rate={self.close_coiled_rate:.4g} N/m)")


def beads_on_spring(*, coil_radius: float = 0.03, pitch: float = 0.02, turns: float = 4.0,
                    wire_radius: float = 5e-4, young_modulus: float = 2e11, poisson_ratio: float = 0.3,
                    density: float = 7800.0, n_beads: int = 4, bead_mass: float = 0.01, bead_radius: float = 0.004,
                    bead_spacing: float = 0.012, friction: float = 0.0, top=(0.0, 0.0, 0.0),
                    control_points: int = 61, model: Optional[str] = None) -> BeadsOnSpring:
    """Particles on a spring (SPEC §9.4, thesis fig. III.17): a helical steel
    spring hanging from a clamp (rest curvature and twist: it keeps its
    shape), beads threaded on its wire near the top. Stepped, the beads
    slide down the coils, stretch the spring, and leave it at its free end
    (``BeadLeft`` events); the spring springs back.

    coil_radius: m (axis to wire centre); pitch: m per turn (> 0,
    right-handed); turns; wire_radius: m; young_modulus: Pa; poisson_ratio;
    density: kg/m³; n_beads; bead_mass: kg; bead_radius: m (centres stay 2r
    apart along the wire); bead_spacing: m of wire between beads at the
    start; friction: N·s/m of a bead sliding on the wire; top: m, the top
    of the coil's vertical axis (the clamp is at top + (0, 0, R));
    control_points: of the wire (61 = 15 per turn: compliance within 2 %
    of Castigliano's; the thesis' 31 is 5–28 % too stiff); model: the
    wire's frame model, None for the rods' default ("reference") or
    "frenet" (the thesis'; the wire is curved everywhere, so it measures
    the twist too, and steps faster).

    Labels: "spring", "clamp", "bead[i]". Use gravity (0, −9.81, 0)."""
    _non_negative_ints(n_beads=n_beads, control_points=control_points)
    top3 = tuple(_points([top], "top")[0])
    params = dict(coil_radius=float(coil_radius), pitch=float(pitch), turns=float(turns),
                  wire_radius=float(wire_radius), young_modulus=float(young_modulus),
                  poisson_ratio=float(poisson_ratio), density=float(density), n_beads=int(n_beads),
                  bead_mass=float(bead_mass), bead_radius=float(bead_radius), bead_spacing=float(bead_spacing),
                  friction=float(friction), top=top3, control_points=int(control_points),
                  model=None if model is None else str(model))
    asm, l = _native.build_beads_on_spring(**params)
    return BeadsOnSpring(asm, int(l["spring"]), list(l["clamp"]), list(l["beads"]), np.asarray(l["bead_arc_lengths"]),
                         float(l["wire_length"]), float(l["helix_angle"]), float(l["close_coiled_rate"]), params)


_DOOR_PATH = ((0.0, 1.0, 0.0), (0.6, 1.0, 0.0), (0.9, 0.7, 0.0), (0.9, 0.2, 0.0), (1.2, 0.0, 0.0))
_DOOR_CLIPS = ((0.25, 1.0, 0.0), (0.9, 0.55, 0.0), (0.9, 0.35, 0.0), (1.14, 0.04, 0.0))


@dataclass(frozen=True)
class CableOnClips:
    """A built cable on clips: the assembly, and where its parts are.

    ``cable``: assembly rod index; ``clips``: assembly clip indices;
    ``clamps``: constraint indices of the connectors' clamps;
    ``clip_abscissae``: u of the cable point each clip holds;
    ``clip_distances``: m from the laid cable to each clip's centre;
    ``length``: m of cable."""

    assembly: object
    cable: int
    clips: list
    clamps: list
    clip_abscissae: np.ndarray
    clip_distances: np.ndarray
    length: float
    params: dict = field(default_factory=dict)

    def __repr__(self):
        p = self.params
        return (f"CableOnClips(length={self.length:.4g} m, clips={len(self.clips)}, "
                f"clip_resistance={p['clip_resistance']} N, cable_radius={p['cable_radius']} m, "
                f"clamp_start={p['clamp_start']}, clamp_end={p['clamp_end']})")


def cable_on_clips(*, path=_DOOR_PATH, clip_positions=_DOOR_CLIPS, clip_radius: float = 0.01,
                   clip_axis=(0.0, 0.0, 1.0), clip_resistance: float = 20.0, cable_radius: float = 0.003,
                   young_modulus: float = 1e8, density: float = 2000.0, bend_radius: float = 0.15,
                   clamp_start: bool = True, clamp_end: bool = False, control_points: int = 18) -> CableOnClips:
    """A cable on clips (SPEC §9.5, thesis III.C.1): a cable laid along
    ``path`` (points in m; its corners rounded to ``bend_radius``, m),
    inserted clipped: every clip holds the cable's point nearest its centre
    and lets go when the cable pulls out along ``clip_axis`` harder than
    ``clip_resistance`` (N; ``ClipReleased`` event); a released clip
    catches whatever cable enters its sphere (``clip_radius``, m) again.

    clip_positions: points in m, each within clip_radius of the laid cable
    (else an error naming it); cable_radius: m; young_modulus: Pa;
    density: kg/m³ (default a 6 mm PVC-insulated cable, EI = 6.4e-3 N·m²,
    0.057 kg/m); clamp_start / clamp_end: connectors at the ends;
    control_points: 18, the thesis' door scene. The cable is straight at
    rest and has no torsion here.

    Labels: "cable", "clip[k]" (the clip and its hold), "connector[0|1]".
    Use gravity (0, −9.81, 0); the default door is the plane z = 0."""
    _non_negative_ints(control_points=control_points)
    params = dict(path=_points(path, "path"), clip_positions=_points(clip_positions, "clip_positions"),
                  clip_radius=float(clip_radius), clip_axis=tuple(_points([clip_axis], "clip_axis")[0]),
                  clip_resistance=float(clip_resistance), cable_radius=float(cable_radius),
                  young_modulus=float(young_modulus), density=float(density), bend_radius=float(bend_radius),
                  clamp_start=bool(clamp_start), clamp_end=bool(clamp_end), control_points=int(control_points))
    asm, l = _native.build_cable_on_clips(**params)
    return CableOnClips(asm, int(l["cable"]), list(l["clips"]), list(l["clamps"]), np.asarray(l["clip_abscissae"]),
                        np.asarray(l["clip_distances"]), float(l["length"]), params)


_HARNESS_BRANCHES = (
    ((0.0, 0.0, 0.0), (0.5, 0.0, 0.0)),
    ((-0.4, 0.15, 0.0), (-0.1, 0.0, 0.0), (0.0, 0.0, 0.0)),
    ((-0.4, -0.15, 0.0), (-0.1, 0.0, 0.0), (0.0, 0.0, 0.0)),
    ((0.5, 0.0, 0.0), (0.6, 0.0, 0.0), (0.9, 0.2, 0.0)),
    ((0.5, 0.0, 0.0), (0.6, 0.0, 0.0), (0.9, 0.0, 0.0)),
    ((0.5, 0.0, 0.0), (0.6, 0.0, 0.0), (0.9, -0.2, 0.0)),
)
_HARNESS_RADII = (0.006, 0.0035, 0.0035, 0.004, 0.003, 0.0025)
_HARNESS_JUNCTIONS = (((0, "start"), (1, "end"), (2, "end")), ((0, "end"), (3, "start"), (4, "start"), (5, "start")))
_HARNESS_CONNECTORS = ((1, "start"), (2, "start"), (3, "end"), (4, "end"), (5, "end"))


@dataclass(frozen=True)
class Harness:
    """A built harness: the assembly, and where its parts are.

    ``branches``: assembly rod index of each branch; ``junctions``: per
    junction, its links (main branch, other branch, RelativePosition
    constraint index, RelativeOrientation constraint index);
    ``connectors``: constraint indices of each connector's clamp;
    ``lengths``: m of each branch."""

    assembly: object
    branches: list
    junctions: list
    connectors: list
    lengths: np.ndarray
    params: dict = field(default_factory=dict)

    def __repr__(self):
        p = self.params
        return (f"Harness(branches={len(self.branches)}, junctions={len(self.junctions)}, "
                f"connectors={len(self.connectors)}, radii={list(p['radii'])} m, length={self.lengths.sum():.4g} m)")


def harness(*, branches=_HARNESS_BRANCHES, radii=_HARNESS_RADII, junctions=_HARNESS_JUNCTIONS,
            connectors=_HARNESS_CONNECTORS, bend_radius: float = 0.1, young_modulus: float = 1e8,
            density: float = 2000.0, control_points_per_metre: float = 12.0) -> Harness:
    """A wiring harness (SPEC §9.5, thesis III.C.2, fig. III.13): cables
    ("branches", each a route of points in m, with its own radius in m)
    joined at junctions — taped breakouts where branch ends share a point
    and a direction (relative position + relative orientation) — and
    connectors clamping ends.

    junctions: per junction, the (branch, "start"|"end") ends meeting
    there: at one point, tangents the same way (else an error naming the
    junction), every branch joined to the others (else an error naming
    ``junctions``); connectors: (branch, "start"|"end") ends clamped;
    bend_radius: m, corners of the routes rounded to it; young_modulus: Pa;
    density: kg/m³; control_points_per_metre (at least 4 per branch).
    Branches have no torsion: give every leaf a connector for ``relax``.

    Labels: "branch[k]", "junction[j]", "connector[c]". Use gravity
    (0, −9.81, 0)."""
    from .errors import InvalidInputError

    def ends(value, what):
        try:
            out = [(int(b), str(e)) for b, e in value]
        except (TypeError, ValueError):
            raise InvalidInputError(f"invalid input: {what} must be (branch, 'start'|'end') pairs") from None
        if any(b < 0 for b, _ in out):
            raise InvalidInputError(f"invalid input: {what}: branch indices must be >= 0")
        return out

    params = dict(branches=[_points(b, f"branches[{k}]") for k, b in enumerate(branches)],
                  radii=[float(r) for r in radii],
                  junctions=[ends(j, f"junctions[{k}]") for k, j in enumerate(junctions)],
                  connectors=ends(connectors, "connectors"), bend_radius=float(bend_radius),
                  young_modulus=float(young_modulus), density=float(density),
                  control_points_per_metre=float(control_points_per_metre))
    asm, l = _native.build_harness(**params)
    return Harness(asm, list(l["branches"]), [list(j) for j in l["junctions"]], list(l["connectors"]),
                   np.asarray(l["lengths"]), params)
