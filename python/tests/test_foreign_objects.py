"""A rod or handle of another world is refused by every call that takes one,
with an error naming it, and the world is left as it was (before, add_load
turned a rod of world A into a bare index and pushed world B's rod with the
same index)."""
import numpy as np
import pytest

import strandkit as sk


def scene(y):
    w = sk.World(gravity=(0, -9.81, 0))
    r = w.add_rod(sk.straight((0, y, 0), (1, y, 0), n_control_points=8, section=0.01, material="nylon"))
    c, *_ = sk.clamp(w, r)
    load = w.add_load(sk.point_force(r, r.u_end, (0, -1.0, 0)))
    bead = w.add_bead(r, 0.5 * (r.u_start + r.u_end), mass=0.01)
    clip = w.add_clip((0.5, y + 1.0, 0), 0.01, (0, 1, 0), 1.0)
    return w, dict(rod=r, constraint=c, load=load, bead=bead, clip=clip)


# name → (object kind the error names, call taking world B, B's objects and
# the objects of world A): every entry point that takes a rod or a handle.
CALLS = {
    "add_constraint": ("rod", lambda wb, b, a: wb.add_constraint(a["rod"], sk.position(0.0))),
    "add_link a": ("rod", lambda wb, b, a: wb.add_link(a["rod"], b["rod"], sk.relative_distance(0.0, 0.0, 5.0))),
    "add_link b": ("rod", lambda wb, b, a: wb.add_link(b["rod"], a["rod"], sk.relative_distance(0.0, 0.0, 5.0))),
    "add_coplanar_clamp": ("rod", lambda wb, b, a: wb.add_coplanar_clamp(a["rod"], 1.0, b["rod"], 1.0)),
    "clamp": ("rod", lambda wb, b, a: wb.clamp(a["rod"])),
    "sk.clamp with a target": ("rod", lambda wb, b, a: sk.clamp(wb, a["rod"], target=(0, 0, 0))),
    "interleave": ("rod", lambda wb, b, a: wb.interleave([b["rod"], a["rod"]])),
    "remove_rod": ("rod", lambda wb, b, a: wb.remove_rod(a["rod"])),
    "add_load": ("rod", lambda wb, b, a: wb.add_load(sk.point_force(a["rod"], 1.0, (0, -1000.0, 0)))),
    "add_load trap": ("rod", lambda wb, b, a: wb.add_load(sk.trap(a["rod"], 0.0, anchor=(0, 0, 0), stiffness=1.0))),
    "set_load, foreign rod": ("rod", lambda wb, b, a: wb.set_load(b["load"], sk.point_force(a["rod"], 0.0, (0, 1, 0)))),
    "set_load, foreign load": ("load", lambda wb, b, a: wb.set_load(a["load"], sk.point_force(b["rod"], 0.0, (0, 1, 0)))),
    "remove_load": ("load", lambda wb, b, a: wb.remove_load(a["load"])),
    "add_bead": ("rod", lambda wb, b, a: wb.add_bead(a["rod"], 0.5, mass=0.01)),
    "remove_bead": ("bead", lambda wb, b, a: wb.remove_bead(a["bead"])),
    "set_bead_force": ("bead", lambda wb, b, a: wb.set_bead_force(a["bead"], (1, 0, 0))),
    "set_label rod": ("rod", lambda wb, b, a: wb.set_label(a["rod"], "x")),
    "set_label clip": ("clip", lambda wb, b, a: wb.set_label(a["clip"], "x")),
    "set_label bead": ("bead", lambda wb, b, a: wb.set_label(a["bead"], "x")),
    "set_constraint": ("constraint", lambda wb, b, a: wb.set_constraint(a["constraint"], sk.position(0.0))),
    "remove_constraint": ("constraint", lambda wb, b, a: wb.remove_constraint(a["constraint"])),
    "set_breaking": ("constraint", lambda wb, b, a: wb.set_breaking(a["constraint"], 1.0)),
    "reaction": ("constraint", lambda wb, b, a: wb.reaction(a["constraint"])),
    "tension": ("constraint", lambda wb, b, a: wb.tension(a["constraint"])),
    "multipliers": ("constraint", lambda wb, b, a: wb.multipliers(a["constraint"])),
    "Recorder.point": ("Rod", lambda wb, b, a: sk.Recorder(wb).point("tip", a["rod"], 1.0)),
    "Recorder.extension": ("Rod", lambda wb, b, a: sk.Recorder(wb).extension("ext", a["rod"])),
    "Recorder.reaction": ("ConstraintHandle", lambda wb, b, a: sk.Recorder(wb).reaction("c", a["constraint"])),
    "Recorder.multipliers": ("ConstraintHandle", lambda wb, b, a: sk.Recorder(wb).multipliers("c", a["constraint"])),
}


@pytest.mark.parametrize("name", CALLS)
def test_foreign_rod_or_handle_is_refused_and_the_world_unchanged(name):
    wa, a = scene(0.0)
    wb, b = scene(5.0)
    wb.step()
    kind, call = CALLS[name]
    before, before_a = wb.to_json(), wa.to_json()
    with pytest.raises(sk.InvalidInputError, match=f"this {kind} belongs to another world"):
        call(wb, b, a)
    assert wb.to_json() == before and wa.to_json() == before_a


def test_foreign_load_does_not_move_the_other_world():
    """The repro: the load meant for A's rod must not act on B's rod."""
    wa, a = scene(0.0)
    wb, b = scene(5.0)
    rb, ra = b["rod"], a["rod"]
    ref = wb.copy()
    with pytest.raises(sk.InvalidInputError, match="rod belongs to another world"):
        wb.add_load(sk.point_force(ra, ra.u_end, (0, -1000.0, 0)))
    for _ in range(10):
        wb.step()
        ref.step()
    np.testing.assert_array_equal(rb.control_points, ref.rods()[0].control_points)
    assert [lh.force for lh in wb.loads()] == [[0.0, -1.0, 0.0]]


def test_recorder_refuses_a_free_rod():
    w, _ = scene(0.0)
    free = sk.straight((0, 0, 0), (1, 0, 0), section=0.01, material="nylon")
    with pytest.raises(sk.InvalidInputError, match="Rod is not in a world"):
        sk.Recorder(w).point("p", free, 0.0)

