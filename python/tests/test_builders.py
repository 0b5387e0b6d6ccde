"""strandkit.builders (issue 12): the rope bridge from Python — built,
inserted, relaxed, read by group; bad input refused naming the argument."""
import numpy as np
import pytest

import strandkit as sk

G = 9.81


def test_rope_bridge_relaxes_and_reads_by_group():
    bridge = sk.builders.rope_bridge(span=6.0, n_planks=5, plank_mass=3.0, sag=0.6)
    assert "n_planks=5" in repr(bridge)
    w = sk.World(gravity=(0, -G, 0))
    ins = w.insert(bridge.assembly)
    w.relax()
    # Two pins per plank, each carrying half a plank's weight (the ropes
    # pull along the span, the planks hang straight down from them).
    pins = w.group("plank").forces
    assert pins.shape == (10, 3)
    np.testing.assert_allclose(np.linalg.norm(pins, axis=1), 0.5 * 3.0 * G, rtol=1e-3)
    # The anchors carry the whole weight.
    weight = sum(r.mass for r in w.rods()) * G
    assert w.group("anchor").forces[:, 1].sum() == pytest.approx(weight, rel=1e-9)
    assert len(bridge.stations) == 5 and len(bridge.planks) == 5 and len(ins.rods) == 4 + 5


def test_rope_bridge_bad_input_names_the_argument():
    with pytest.raises(sk.InvalidInputError, match="span"):
        sk.builders.rope_bridge(span=-1.0)
    with pytest.raises(sk.InvalidInputError, match="n_planks"):
        sk.builders.rope_bridge(n_planks=80)
    with pytest.raises(sk.InvalidInputError, match="n_planks"):
        sk.builders.rope_bridge(n_planks=-3)
    with pytest.raises(sk.InvalidInputError, match="plank_break_force"):
        sk.builders.rope_bridge(plank_break_force=0.0)
    with pytest.raises(sk.InvalidInputError, match="bending_stifness|accepted"):
        sk.builders.rope_bridge(rope={"bending_stifness": 1.0})
    with pytest.raises(sk.InvalidInputError, match="plank_model"):
        sk.builders.rope_bridge(plank_model="steel")
