"""Clips (algorithms 4–5) and the coplanar relative clamp from Python."""
import pytest

import strandkit as sk


def propped(force_up):
    """Cantilever (1 m nylon rod, clamped at x = 0) whose tip enters a clip
    with an upward exit axis; then an upward tip force pulls it."""
    w = sk.World()
    rod = w.add_rod(sk.straight((0, 0, 0), (1, 0, 0), section=0.005, material="nylon", n_control_points=12))
    sk.clamp(w, rod)
    clip = w.add_clip((1.0, 0.0, 0.0), 0.02, (0, 1, 0), 1.0)
    captured = w.relax().events
    load = w.add_load(sk.point_force(rod, rod.u_end, (0, force_up, 0)))
    released = w.relax().events
    return w, rod, clip, captured, released, load


def test_clip_holds_below_its_resistance_and_releases_above():
    w, rod, clip, captured, released, _ = propped(0.5)
    assert [e.kind for e in captured] == ["ClipCaptured"]
    assert captured[0].clip == clip and captured[0].rod == rod
    assert released == [] and clip.held == rod and clip.constraint.alive
    # The clip carries the whole tip load: its force on the rod is −0.5 N along y.
    assert clip.constraint.reaction().force[1] == pytest.approx(-0.5, rel=1e-6)
    assert "holding rod" in repr(clip)

    w, rod, clip, _, released, _ = propped(2.0)
    assert [e.kind for e in released] == ["ClipReleased"]
    assert released[0].force == pytest.approx(2.0, rel=1e-6)
    assert clip.held is None and clip.disarmed


def test_clip_bad_input():
    w = sk.World()
    with pytest.raises(ValueError, match="clip radius"):
        w.add_clip((0, 0, 0), 0.0, (0, 1, 0), 1.0)
    with pytest.raises(ValueError, match="resistance"):
        w.add_clip((0, 0, 0), 0.1, (0, 1, 0), -1.0)


def test_coplanar_clamp():
    w = sk.World()
    a = w.add_rod(sk.straight((0, 0, 0), (1, 0, 0), section=0.005, material="nylon"))
    b = w.add_rod(sk.straight((1, 0, 0), (1, 1, 0), section=0.005, material="nylon"))
    c = w.add_coplanar_clamp(a, a.u_end, b, b.u_start)
    assert "CoplanarClamp" in repr(c)
    p = w.add_rod(sk.straight((0, 1, 0), (1, 1, 0), section=0.005, material="nylon"))
    with pytest.raises(ValueError, match="parallel"):
        w.add_coplanar_clamp(a, a.u_start, p, p.u_start)
