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


def clipped_cantilever_assembly(resistance):
    """The cantilever of `propped` as an assembly whose tip is inserted
    already held by a clip with an upward exit axis."""
    asm = sk.Assembly()
    r = asm.add_rod(sk.straight((0, 0, 0), (1, 0, 0), section=0.005, material="nylon", n_control_points=12, with_roll=False), "rod")
    u0, u1 = asm.rod(r).domain
    asm.constrain(r, sk.position(u0, (0, 0, 0)))
    asm.constrain(r, sk.tangent(u0, (1, 0, 0)))
    c = asm.add_clip((1.0, 0.0, 0.0), radius=0.02, axis=(0, 1, 0), resistance=resistance, label="clip")
    k = asm.hold_in_clip(c, r, u1)
    return asm, c, k


def test_assembly_clips_are_inserted_holding_and_release_above_their_resistance():
    asm, c, k = clipped_cantilever_assembly(1.0)
    assert (asm.n_clips, c, k) == (1, 0, 2)
    for force_up, released in [(0.5, False), (2.0, True)]:
        w = sk.World()
        ins = w.insert(asm)
        (clip,) = ins.clips
        rod = ins.rods[0]
        assert clip.held == rod  # held from the start, no capture needed
        w.add_load(sk.point_force(rod, rod.u_end, (0, force_up, 0)))
        events = w.relax().events
        if released:
            assert [e.kind for e in events] == ["ClipReleased"]
            assert events[0].force == pytest.approx(force_up, rel=1e-6)
            assert clip.held is None
        else:
            assert events == [] and clip.held == rod
            assert clip.constraint.reaction().force[1] == pytest.approx(-force_up, rel=1e-6)


def test_assembly_clip_bad_input_names_the_argument_and_leaves_the_world_unchanged():
    asm, c, _ = clipped_cantilever_assembly(1.0)
    with pytest.raises(sk.InvalidInputError, match="clip") as e:
        asm.hold_in_clip(3, 0, 0.0)
    assert e.value.what == "clip"
    with pytest.raises(sk.InvalidInputError, match="rod"):
        asm.hold_in_clip(c, 4, 0.0)
    with pytest.raises(sk.InvalidInputError, match="u"):
        asm.hold_in_clip(c, 0, float("nan"))
    with pytest.raises((ValueError, TypeError), match="clip axis"):
        asm.add_clip((0, 0, 0), radius=0.1, axis=(0, 1), resistance=1.0)
    assert asm.n_clips == 1 and asm.n_constraints == 3  # nothing half-added
    w = sk.World()
    for bad, match in [(dict(radius=0.0, resistance=1.0), "radius"), (dict(radius=0.1, resistance=-1.0), "resistance")]:
        b = asm.copy()
        b.add_clip((0.5, 0, 0), axis=(0, 1, 0), **bad)
        with pytest.raises(ValueError, match=match):
            w.insert(b)
        assert (w.n_rods, w.n_constraints, len(w.clips())) == (0, 0, 0)
