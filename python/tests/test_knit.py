"""strandkit.knit: the fabric builder, its measures and the experiments
(SPEC §9.3). The Munden/Poincloux/Singal reference checks need converged
relaxations of swatches far larger than a test can afford; the figures
measured so far are in the README (Known limitations) and issue 18."""
import math

import numpy as np
import pytest

import strandkit as sk
from strandkit.knit import experiments as ex
from strandkit.knit.geometry import clearance, curl


def test_fabric_prints_usefully_and_lays_out_every_loop():
    f = sk.knit.fabric("rib2x2", wales=8, courses=3, loop_length=6e-3, yarn="wool", yarn_radius=1.2e-4)
    assert repr(f) == "Fabric(rib2x2 8 × 3 stitches, loop_length=6 mm, wool yarn r=0.12 mm, continuous, free)"
    assert f.rows == ("KKPPKKPP",) * 3
    assert f.loops.shape == (24,) and list(f.loops["course"][:8]) == [0] * 8
    assert abs(f.loop_length - 6e-3) < 1e-4 * 6e-3
    assert f.clearance >= 1.02
    # B = E π r⁴ / 4 for the fibre's modulus (wool 2 GPa).
    assert math.isclose(f.bending_stiffness, 2e9 * math.pi * 1.2e-4 ** 4 / 4, rel_tol=1e-12)
    custom = sk.knit.fabric(["KP", "PK", "KK"], loop_length=5e-3, bending_stiffness=1e-9, continuous=False)
    assert (custom.wales, custom.courses, custom.pattern) == (2, 3, "custom")
    assert custom.bending_stiffness == 1e-9
    assert custom.assembly.n_rods == 3 if hasattr(custom.assembly, "n_rods") else True


def test_dimensions_read_the_built_spacings():
    f = sk.knit.fabric("jersey", wales=6, courses=6, spacing=(1.3e-3, 0.95e-3))
    d = f.dimensions(f.world())
    # Heads of one course are a wale apart, of one wale a course apart (to
    # the spline's fit of the path: heads are found by arc length).
    assert math.isclose(d["wale_spacing"], 1.3e-3, rel_tol=2e-3)
    assert math.isclose(d["course_spacing"], 0.95e-3, rel_tol=2e-3)
    assert math.isclose(d["k_w"], f.loop_length * 100 / (d["wale_spacing"] * 100), rel_tol=1e-12)
    assert math.isclose(d["k_s"], d["k_c"] * d["k_w"], rel_tol=1e-12)
    assert math.isclose(d["stitch_density"], d["wales_per_cm"] * d["courses_per_cm"], rel_tol=1e-12)
    # A tube's heads lie behind the legs, on a circle of radius R − d
    # (R: the mid-surface of circumference wales × w): chords apart.
    t = sk.knit.fabric("jersey", wales=10, courses=3, boundary="periodic", spacing=(1.3e-3, 0.95e-3))
    assert math.isclose(t.tube_radius, 10 * 1.3e-3 / (2 * math.pi), rel_tol=1e-12)
    w = t.dimensions(t.world(), margin=0)["wale_spacing"]
    chord = 2 * (t.tube_radius - t.model["depth"]) * math.sin(math.pi / 10)
    assert math.isclose(w, chord, rel_tol=2e-3), (w, chord)


def test_yarns_start_outside_each_other():
    for pattern, least in (("jersey", 1.0), ("rib1x1", 1.0), ("seed", 0.85)):
        f = sk.knit.fabric(pattern, wales=4, courses=4)
        c = clearance(f.world(), f)
        # Seed's sinkers turn from front to back between neighbours: its
        # yarn starts up to a tenth of a diameter inside (builder floor 0.9).
        assert c >= least, (pattern, c)
        assert f.clearance >= 0.9  # the builder's floor, on its loop model


@pytest.mark.parametrize("kwargs, match", [
    (dict(pattern=["KK", "K"]), "course 1"),
    (dict(pattern=["KX", "KK"]), "wale 1"),
    (dict(pattern="tweed"), "jersey"),
    (dict(wales=0), "wales"),
    (dict(courses=1), "courses"),
    (dict(wales=2.5), "wales"),
    (dict(loop_length=1e-3), "loop_length"),
    (dict(loop_length=1.7e-3), "overlap"),
    (dict(loop_length=float("nan")), "loop_length"),
    (dict(yarn_radius=-1e-4), "radius"),
    (dict(yarn="silk"), "cotton"),
    (dict(bending_stiffness=0.0), "bending_stiffness"),
    (dict(boundary="periodic", continuous=True), "continuous"),
    (dict(boundary="closed"), "boundary"),
    (dict(spacing=(1e-3,)), "spacing"),
    (dict(wales=1000, courses=1000), "at most"),
])
def test_fabrics_that_cannot_be_knitted_are_refused(kwargs, match):
    with pytest.raises(sk.InvalidInputError, match=match):
        sk.knit.fabric(**kwargs)


def test_relaxation_lowers_the_energy_without_yarn_passing_through():
    f = sk.knit.fabric("jersey", wales=4, courses=4)
    r = ex.relax(f, max_steps=80, record_every=10)
    e = r.history["energy"]
    assert len(e) == 8 and np.all(np.isfinite(e))
    # A gradient flow under contacts: the elastic energy only falls.
    assert np.all(np.diff(e) <= 1e-12 * e[0]), np.diff(e)
    assert e[-1] < 0.9 * f.world().energy()["elastic"]
    # No yarn inside another beyond the contact rows' sag (measured 0.95).
    assert r.clearance > 0.85, r.clearance
    d = r.dimensions
    assert all(math.isfinite(d[k]) and d[k] > 0 for k in ("k_c", "k_w", "k_s"))
    assert "NOT converged" in repr(r) and r.steps == 80
    assert set(r.curl) == {"bottom", "top", "left", "right"}


def test_stretch_pulls_back_and_reports_both_branches():
    f = sk.knit.fabric("jersey", wales=4, courses=4)
    s = ex.stretch(f, direction="wale", strain=0.1, increments=2, settle_steps=20, steps_per_increment=30)
    assert list(np.round(s.strain, 12)) == [0.0, 0.05, 0.1, 0.05, 0.0]
    assert list(s.loading) == [True, True, True, False, False]
    # Pulled apart, the fabric pulls the bar back (along +y on the top bar).
    assert s.force[2] > 0 and np.all(np.isfinite(s.force))
    assert math.isfinite(s.work_loading) and math.isfinite(s.work_unloading)
    assert s.clearance > 0.5


@pytest.mark.parametrize("kwargs, match", [
    (dict(direction="diagonal"), "direction"),
    (dict(strain=-0.1), "strain"),
    (dict(strain=float("nan")), "strain"),
    (dict(increments=0), "increments"),
])
def test_bad_stretch_requests_are_refused(kwargs, match):
    f = sk.knit.fabric("jersey", wales=3, courses=3)
    with pytest.raises(sk.InvalidInputError, match=match):
        ex.stretch(f, settle_steps=0, **kwargs)
    with pytest.raises(sk.InvalidInputError, match="source"):
        ex.stretch("not a fabric")
    with pytest.raises(sk.InvalidInputError, match="max_steps"):
        ex.relax(f, max_steps=0)
