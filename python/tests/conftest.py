import os
import sys

import numpy as np
import pytest

# Run against the installed package (pip install ./python): drop the source
# tree from sys.path unless an in-place build (maturin develop) put _native there.
_src = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
if not any(f.startswith("_native") for f in os.listdir(os.path.join(_src, "strandkit"))):
    sys.path[:] = [p for p in sys.path if os.path.abspath(p or os.curdir) != _src]

import strandkit as sk  # noqa: E402


def cantilever(force, n=20, samples=5):
    """SPEC §10 cantilever: L = 4 m, R = 0.05 m, E = 200 GPa, clamped at x = 0, tip force (N)."""
    steel = sk.Material("steel", young=200e9, poisson=0.3, density=7800.0)
    w = sk.World()
    rod = w.add_rod(sk.straight((0, 0, 0), (4, 0, 0), section=sk.Section.circle(0.05), material=steel,
                                n_control_points=n, samples_per_segment=samples))
    clamp, clamp_t = sk.clamp(w, rod)
    w.add_load(sk.point_force(rod, rod.u_end, force))
    return w, rod, clamp, clamp_t


def end_pair_pulled(sequence, break_forces, force=8.0, dt=1e-3):
    """A duplex in a molecular world, strand a clamped at its far end and
    the two nucleotides of pair 0 pulled apart along their rung by
    ``force`` (pN each): returns (duplex, world, inserted, strand a, strand b)."""
    d = sk.dna.duplex(sequence, break_forces=break_forces)
    w = sk.World(units="molecular", dt=dt)
    ins = w.insert(d.assembly)
    a, b = (ins.rods[i] for i in d.strands)
    w.clamp(a, d.abscissae[0][-1])
    ua, ub = d.abscissae[0][0], d.abscissae[1][-1]
    x = np.asarray(b.position(ub)) - np.asarray(a.position(ua))
    x /= np.linalg.norm(x)
    w.add_load(sk.point_force(a, ua, -force * x))
    w.add_load(sk.point_force(b, ub, force * x))
    return d, w, ins, a, b


@pytest.fixture
def two_rod_world():
    """A dynamic two-rod scene: a clamped straight rod and a clamped helix under gravity."""
    w = sk.World(dt=1e-3, gravity=(0.0, -9.81, 0.0))
    a = w.add_rod(sk.straight((0, 0, 0), (1, 0, 0), section=0.01, material="nylon", n_control_points=8))
    b = w.add_rod(sk.helix(0.2, 0.1, 2.0, section=0.01, material="nylon", n_control_points=12))
    sk.clamp(w, a)
    sk.clamp(w, b)
    return w, a, b


def tip_angle(rod):
    t = rod.tangent(rod.u_end)
    return float(np.arctan2(-t[1], t[0]))
