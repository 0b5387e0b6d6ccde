"""strandkit.dna (issue 17): the duplex builder from Python — exact
geometry read back from a world, sequences checked with their position,
mismatches flagged, H-bonds that break in tension taking their stacking
with them."""
import math

import numpy as np
import pytest

import strandkit as sk
from conftest import end_pair_pulled


def built(seq, **kw):
    d = sk.dna.duplex(seq, **kw)
    w = sk.World(units="molecular")
    ins = w.insert(d.assembly)
    return d, w, ins


def test_geometry_read_back_from_the_world():
    d, w, ins = built("gattacaGATTACAgattacaGATTACA")
    a, b = (ins.rods[i] for i in d.strands)
    pa = np.array([a.position(u) for u in d.abscissae[0]])
    pb = np.array([b.position(d.abscissae[1][j]) for j in d.partner])
    assert np.allclose(np.hypot(pa[:, 0], pa[:, 1]), 1.0, atol=1e-9)
    assert np.allclose(np.diff(pa[:, 2]), 0.34, atol=1e-9)
    assert np.allclose(pb[:, 2], pa[:, 2], atol=1e-9)
    assert np.allclose(np.linalg.norm(pb - pa, axis=1), d.rung_length, atol=1e-9)
    assert d.rung_length == pytest.approx(2 * math.sin(math.pi * 12 / 34), abs=1e-12)
    assert d.grooves == pytest.approx([12 / 34 * 3.57, 22 / 34 * 3.57], abs=1e-9)
    assert d.sequences == ["GATTACAGATTACAGATTACAGATTACA", "TGTAATCTGTAATCTGTAATCTGTAATC"]
    assert len(w.group("hbond").forces) == 28
    assert "28 bp" in repr(d)
    # The calibration's own measurement: B-DNA at zero temperature (0.2 %).
    kt = 1.380649e-2 * 298.15
    m = d.measured
    assert m["stretch_modulus"] == pytest.approx(1100.0, rel=2e-3)
    assert m["twist_stretch"] == pytest.approx(-90.0, rel=2e-3)
    assert m["twist_stiffness"] == pytest.approx(100.0 * kt, rel=2e-3)
    assert m["bending_stiffness"] == pytest.approx(50.0 * kt, rel=2e-3)


def test_bad_sequences_name_the_position():
    with pytest.raises(sk.InvalidInputError, match="position 5"):
        sk.dna.duplex("GATTNCA")
    with pytest.raises(sk.InvalidInputError, match="empty"):
        sk.dna.duplex("")
    with pytest.raises(sk.InvalidInputError, match="break_forces"):
        sk.dna.duplex("GATTACA", break_forces=[1.0] * 6)
    with pytest.raises(sk.InvalidInputError, match="strands soft enough"):
        sk.dna.duplex("GATTACA", strand_stretch_modulus=800.0)
    with pytest.raises(sk.InvalidInputError, match="twist_stretch"):
        sk.dna.duplex("GATTACA", twist_stretch=-2000.0)
    d = sk.dna.duplex("AACGTG", complement="CACTTT")
    assert d.mismatches == [2] and d.hbonds[2] is None and d.stacks[1] is None


def test_unzipping_the_end_pair_removes_its_stacking():
    n = 16
    d, w, ins, a, b = end_pair_pulled("GC" * (n // 2), [5.0] + [math.inf] * (n - 1))
    events = []
    for _ in range(5):
        events += list(w.step().events)
    broken = [(e.label, e.force) for e in events if e.kind == "ConstraintBroken"]
    assert broken[0][0] == "hbond[0]" and broken[0][1] > 5.0
    # Steps 0 and 1 both read pair 0 (step 1's frame at pair 1 takes its
    # axis from pairs 0 and 2): both go, step 2 stays.
    assert broken[1:] == [("stack[0]", 0.0), ("stack[1]", 0.0)]
