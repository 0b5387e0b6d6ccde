"""Scene files (issue 19): saved and loaded scenes run bit-identically to
the in-memory ones, for every builder; a quasi-static stretch through the
protocol gives a rod's EA·ε; the shipped JSON Schema is the generated one
and accepts what we write; bad scenes are refused naming the key, before
any work."""
import json
import math
import os
import pathlib

import numpy as np
import pytest

import strandkit as sk
from strandkit.scene import BUILDERS

SMALL = {  # builder → (arguments, world): scenes of a few milliseconds a step
    "rope_bridge": ({"n_planks": 4, "span": 5.0, "sag": 0.5}, {"gravity": [0, -9.81, 0], "dt": 2e-3}),
    "necklace": ({"n_beads": 4}, {"gravity": [0, -9.81, 0]}),
    "beads_on_spring": ({}, {"gravity": [0, -9.81, 0]}),
    "cable_on_clips": ({}, {"gravity": [0, -9.81, 0], "dt": 3e-3}),
    "harness": ({}, {"gravity": [0, -9.81, 0], "dt": 3e-3}),
    "dna.duplex": ({"sequence": "GATTACAGC"}, {"dt": 0.01, "viscosity": 1.0}),
    "knit.fabric": ({"wales": 3, "courses": 3}, {"dt": 1e-8, "overdamped": True, "viscosity": 1.0}),
}


def same(a: dict, b: dict) -> bool:
    """Observables equal bit for bit (NaN where the other has NaN)."""
    if a.keys() != b.keys():
        return False
    for k in a:
        x, y = a[k], b[k]
        if x.dtype == object:
            if x.tolist() != y.tolist():
                return False
        elif not np.array_equal(x, y, equal_nan=True):
            return False
    return True


def bridge_scene(**outputs):
    return sk.Scene.from_builder(
        "rope_bridge", name="bridge", n_planks=4, span=5.0, sag=0.5,
        world={"gravity": [0, -9.81, 0], "dt": 2e-3},
        protocol=[{"relax": {}}, {"step": {"duration": 0.02}},
                  {"pull": {"constraints": "anchor[0,1]", "velocity": [0, 0, 0.1], "duration": 0.04}}],
        outputs={"every": 5, "groups": ["plank"], **outputs})


def test_every_builder_is_covered():
    assert sorted(SMALL) == sorted(BUILDERS)


@pytest.mark.parametrize("fmt", ["json", "toml"])
def test_saved_scene_runs_bit_identically(tmp_path, fmt):
    scene = bridge_scene()
    mem = scene.run(progress_bar=False)
    path = scene.save(tmp_path / f"bridge.{fmt}")
    loaded = sk.load_scene(path)
    assert loaded.to_dict() == scene.to_dict() and loaded.digest == scene.digest
    disk = loaded.run(tmp_path / "out", progress_bar=False)
    assert disk.world.to_json() == mem.world.to_json()
    assert same(disk.observables, mem.observables)
    assert mem.observables["operation"].tolist()[:3] == ["start", "relax", "step"]
    assert np.isfinite(mem.observables["drive_force"][-1])


@pytest.mark.parametrize("name", sorted(SMALL))
def test_builder_output_saved_as_scene_reruns_identically(tmp_path, name):
    args, world = SMALL[name]
    by_name = sk.Scene.from_builder(name, world=world, protocol=[{"step": {"steps": 4}}], outputs={"every": 2}, **args)
    made = sk.scene.structures.builder_function(name)(**args)
    inline = sk.Scene.from_assembly(made, world=dict(world, units=by_name.data["world"]["units"]),
                                    protocol=[{"step": {"steps": 4}}], outputs={"every": 2})
    a = by_name.run(progress_bar=False)
    b = sk.load_scene(inline.save(tmp_path / "inline.json")).run(progress_bar=False)
    c = sk.load_scene(inline.save(tmp_path / "inline.toml")).run(progress_bar=False)
    assert a.world.to_json() == b.world.to_json() == c.world.to_json()
    assert same(a.observables, b.observables) and same(a.observables, c.observables)


def test_quasi_static_stretch_gives_EA_strain(tmp_path):
    """A straight rod held at both ends and stretched through the protocol:
    the drive force is EA·ε (the exact stretch energy ½EAε² of SPEC §2)."""
    E, R, L = 2e9, 1e-3, 1.0
    asm = sk.Assembly()
    asm.add_rod(sk.straight((0, 0, 0), (L, 0, 0), section=R, material=sk.Material("test", E, 0.3, 1000.0),
                            n_control_points=8, with_roll=False), label="wire")
    scene = sk.Scene.from_assembly(asm, protocol=[
        {"hold": {"rod": "wire", "at": "start", "label": "left"}},
        {"hold": {"rod": "wire", "at": "end", "label": "right"}},
        {"stretch": {"constraints": "right", "about": "left", "strain": 0.01, "increments": 4}}])
    r = sk.load_scene(scene.save(tmp_path / "wire.json")).run(progress_bar=False)
    o = r.observables
    quasi = o["operation"] == "stretch"
    strain = o["drive_displacement"][quasi] / L
    ea = E * math.pi * R**2
    assert np.allclose(strain, [0.0025, 0.005, 0.0075, 0.01], rtol=1e-12)
    np.testing.assert_allclose(o["drive_force"][quasi], ea * strain, rtol=1e-6)


def test_rotate_records_the_torque_of_a_twisted_rod():
    """A straight rod clamped at one end, its other end's roll turned
    quasi-statically: torque GJ·Φ/L (reference-frame twist, SPEC §2.3)."""
    E, nu, R, L = 1e7, 0.5, 2e-3, 1.0
    asm = sk.Assembly()
    asm.add_rod(sk.straight((0, 0, 0), (L, 0, 0), section=R, material=sk.Material("rubber", E, nu, 1000.0),
                            n_control_points=10, model="reference"), label="rod")
    scene = sk.Scene.from_assembly(asm, protocol=[
        {"hold": {"rod": "rod", "at": "start", "axes": "xyzr", "label": "base"}},
        {"hold": {"rod": "rod", "at": "end", "axes": "xyzr", "label": "top"}},
        {"rotate": {"constraints": "top", "turns": 0.25, "increments": 2}}])
    # the tangent at both ends is left free: a straight rod stays straight below Greenhill's threshold
    o = scene.run(progress_bar=False).observables
    rot = o["operation"] == "rotate"
    gj = E / (2 * (1 + nu)) * math.pi * R**4 / 2
    np.testing.assert_allclose(o["drive_torque"][rot], gj * 2 * math.pi * o["drive_turns"][rot] / L, rtol=1e-6)


def test_shipped_schema_is_current_and_accepts_our_scenes(tmp_path):
    jsonschema = pytest.importorskip("jsonschema")
    shipped = pathlib.Path(sk.scene.__file__).resolve().parent.parent / "scene.schema.json"
    schema = sk.scene.schema()
    assert json.loads(shipped.read_text(encoding="utf-8")) == schema
    jsonschema.Draft202012Validator.check_schema(schema)
    for name, (args, world) in SMALL.items():
        jsonschema.validate(sk.Scene.from_builder(name, world=world, **args).to_dict(), schema)
    jsonschema.validate(bridge_scene().to_dict(), schema)
    bad = bridge_scene().to_dict()
    bad["protocol"][0] = {"relax": {"perturbation": 1.0}}
    with pytest.raises(jsonschema.ValidationError):
        jsonschema.validate(bad, schema)


def base():
    return bridge_scene().to_dict()


def edit(path, value):
    d = base()
    sk.scene.set_key(d, path, value)
    return d


BAD = [
    (dict(base(), version=2), "version", "unknown version 2"),
    ({k: v for k, v in base().items() if k != "version"}, "version", "missing"),
    (dict(base(), colour="red"), "colour", "unknown key"),
    (edit("world.timestep", 1e-3), "world.timestep", "unknown setting"),
    (edit("world.dt", -1.0), "world.dt", "dt must be finite and > 0"),
    (edit("world.gravity", [0, float("nan"), 0]), "world.gravity[1]", "not a finite value"),
    (edit("structure.args.n_plonks", 3), "structure.args.n_plonks", "unknown argument"),
    (edit("structure.args.n_planks", -3), "structure.args", "n_planks"),
    (edit("structure.args.n_planks", 3.7), "structure.args.n_planks", "an integer"),
    (edit("structure.args.sag", True), "structure.args.sag", "a finite number"),
    (edit("structure.builder", ["rope_bridge"]), "structure.builder", "not a builder name"),
    (edit("world.seed", 2**70), "world.seed", "not valid"),
    (edit("world.seed", 1.5), "world.seed", "not valid"),
    (edit("world.units", "imperial"), "world.units", "units"),
    (edit("world.scheme", "rk4"), "world.scheme", "scheme"),
    (edit("structure.args.span", float("nan")), "structure.args.span", "not a finite value"),
    (edit("structure.args.span", object()), "structure.args.span", "cannot be written"),
    (edit("structure.builder", "castle"), "structure.builder", "unknown builder"),
    (edit("protocol.1", {"jump": {}}), "protocol[1].jump", "unknown operation"),
    (edit("protocol.1.step.duration", float("inf")), "protocol[1].step.duration", "not a finite value"),
    (edit("protocol.1.step.steps", 3), "protocol[1].step", "exactly one of duration and steps"),
    (edit("protocol.2.pull.constraints", "anchor[9,9]"), "protocol[2].pull", "no object labelled"),
    (edit("protocol.2.pull.velocity", [0, 0, 0]), "protocol[2].pull.velocity", "is zero"),
    (edit("outputs.every", 0), "outputs.every", "not valid"),
    (edit("outputs.groups", ["rung"]), "outputs.groups", "no group 'rung'"),
    (edit("obstacles", [{"mesh": {"path": "missing.stl"}}]), "obstacles[0].mesh.path", "no such file"),
    (edit("obstacles", [{"sphere": {"center": [0, 0, 0], "radius": -1}}]), "obstacles[0].sphere.radius", "not valid"),
    (edit("contact", {"margin": 0.01, "friction": -0.3}), "contact.friction", "not valid"),
    (dict(base(), structure={"assembly_file": "nowhere.json"}), "structure.assembly_file", "no such file"),
    (dict(base(), structure={"assembly": {"rods": 3}}), "structure.assembly", "not an Assembly"),
]


@pytest.mark.parametrize("data,key,words", BAD, ids=[b[1] + ":" + b[2] for b in BAD])
def test_bad_scene_is_refused_naming_the_key(tmp_path, data, key, words):
    with pytest.raises(sk.SceneError) as e:
        sk.Scene(data, tmp_path)
    assert e.value.key == key and words in str(e.value), str(e.value)
    assert isinstance(e.value, sk.InvalidInputError)


def test_bad_files_and_directories(tmp_path):
    (tmp_path / "broken.json").write_text("{not json", encoding="utf-8")
    with pytest.raises(sk.FileError):
        sk.load_scene(tmp_path / "broken.json")
    with pytest.raises(sk.FileError):
        sk.load_scene(tmp_path / "absent.json")
    (tmp_path / "file").write_text("x")
    scene = bridge_scene()
    with pytest.raises(sk.SceneError) as e:
        scene.run(tmp_path / "file" / "out", progress_bar=False)
    assert e.value.key == "out"
    assert not (tmp_path / "file" / "out").exists()
    with pytest.raises(sk.SceneError) as e:
        scene.with_values({"protocol.7.step.steps": 3})
    assert e.value.key == "protocol.7"


def test_numpy_values_and_paths_survive_saving_elsewhere(tmp_path):
    """numpy numbers become plain ones; a scene whose Assembly is a file is
    saved into another directory with the path rebased, and the copy a run
    writes into its directory loads and resumes as the same scene."""
    asm_dir = tmp_path / "data"
    asm_dir.mkdir()
    (asm_dir / "bridge.assembly.json").write_text(sk.builders.rope_bridge(n_planks=3, span=4.0, sag=0.4).assembly.to_json())
    src = {"version": 1, "structure": {"assembly_file": "bridge.assembly.json"},
           "world": {"gravity": np.array([0.0, -9.81, 0.0]), "dt": np.float64(2e-3), "seed": np.int64(3)},
           "protocol": [{"step": {"steps": np.int64(6)}}], "outputs": {"every": 3}}
    scene = sk.Scene(src, asm_dir)
    assert scene.data["world"]["seed"] == 3 and type(scene.data["world"]["seed"]) is int
    moved = sk.load_scene(scene.save(tmp_path / "elsewhere" / "scene.toml") if (tmp_path / "elsewhere").mkdir() is None else None)
    assert moved.data["structure"]["assembly_file"] == os.path.join("..", "data", "bridge.assembly.json")
    assert moved.digest == scene.digest
    r = moved.run(tmp_path / "out", progress_bar=False)
    copy = sk.load_scene(tmp_path / "out" / "scene.json")
    assert copy.digest == scene.digest
    again = copy.run(tmp_path / "out", resume=True, progress_bar=False)
    assert same(again.observables, r.observables)


def test_resume_refuses_another_scene(tmp_path):
    bridge_scene().run(tmp_path, progress_bar=False)
    other = bridge_scene().with_values({"world.dt": 1e-3})
    with pytest.raises(sk.SceneError) as e:
        other.run(tmp_path, resume=True, progress_bar=False)
    assert "another scene" in str(e.value)
    again = bridge_scene().run(tmp_path, resume=True, progress_bar=False)  # finished: read back
    assert len(again.observables["time"]) == len(bridge_scene().run(progress_bar=False).observables["time"])


def necklace(protocol, **outputs):
    return {"version": 1, "structure": {"builder": "necklace", "args": {"n_beads": 4}},
            "protocol": protocol, "outputs": outputs}


@pytest.mark.parametrize("protocol,outputs,key,words", [
    ([{"hold": {"rod": "bead"}}], {}, "protocol[0].hold", "names 0 rods"),
    ([{"hold": {"rod": "string", "at": 99.0}}], {}, "protocol[0].hold", "outside the rod"),
    ([{"hold": {"rod": "string", "label": "held[a]"}}], {}, "protocol[0].hold.label", "not a label"),
    ([{"rotate": {"constraints": "peg", "turns": 1, "duration": 0.01}}], {}, "protocol[0].rotate", "roll"),
    ([{"hold": {"rod": "string", "at": 1.0, "label": "h"}},
      {"stretch": {"constraints": "h", "about": "h", "strain": 0.1, "duration": 0.01}}], {},
     "protocol[1].stretch", "centroids coincide"),
    ([{"hold": {"rod": "string", "at": 1.0, "label": "h"}}], {"groups": ["h", "nothing"]}, "outputs.groups", "'nothing'"),
])
def test_protocol_walked_before_any_work(tmp_path, protocol, outputs, key, words):
    """What only shows when the protocol runs (a hold on no rod, a drive on
    constraints it cannot move) is refused when the scene loads."""
    with pytest.raises(sk.SceneError) as e:
        sk.Scene(necklace(protocol, **outputs), tmp_path)
    assert e.value.key == key and words in str(e.value), str(e.value)


def test_a_drive_goes_on_when_one_of_its_constraints_breaks():
    """Two wires stretched quasi-statically through their end pins; the
    first pin breaks at 1.2 N (breaks are events of the relax): the second
    keeps its own target, and the force is the one left's, EA·ε."""
    E, R = 1e9, 1e-3
    ea = E * math.pi * R**2
    asm = sk.Assembly()
    for k in range(2):
        i = asm.add_rod(sk.straight((0, k, 0), (1, k, 0), section=R, material=sk.Material("m", E, 0.3, 1000.0),
                                    n_control_points=6, with_roll=False), label=f"wire[{k}]")
        rod = asm.rod(i)
        asm.constrain(i, sk.position(rod.u_start, (0, k, 0)), label=f"left[{k}]")
        asm.constrain(i, sk.tangent(rod.u_start, (1, 0, 0)))  # clamped: still defined once its pin breaks
        # the first member breaks: the second must keep its own target, not take over the first's
        asm.constrain(i, sk.position(rod.u_end, (1, k, 0)), label=f"right[{k}]", break_force=None if k else 1.2)
    scene = sk.Scene.from_assembly(asm, protocol=[
        {"pull": {"constraints": "right", "velocity": [1e-3, 0, 0], "increments": 4, "time": 1.0}}],
        outputs={"groups": ["right"]})
    r = scene.run(progress_bar=False)
    o = r.observables
    strain = np.array([0.25, 0.5, 0.75, 1.0]) * 1e-3
    np.testing.assert_allclose(o["drive_force"][1:], ea * strain * [2, 1, 1, 1], rtol=1e-6)
    assert o["right.broken"].tolist() == [0, 0, 1, 1, 1]
    assert [e["kind"] for e in r.events] == ["ConstraintBroken"]
    ends = [rod.position(rod.u_end) for rod in r.world.rods()]
    assert ends[1] == pytest.approx([1 + 1e-3, 1.0, 0.0], abs=1e-12) and ends[0][0] < 1 + 1e-6  # the free one sprang back


def test_shipped_scene_files_load_and_follow_the_schema():
    jsonschema = pytest.importorskip("jsonschema")
    scenes = sorted((pathlib.Path(__file__).resolve().parents[2] / "examples" / "scenes").iterdir())
    assert [p.name for p in scenes] == ["bridge_pull.json", "dna_stretch.toml"]
    for p in scenes:
        s = sk.load_scene(p)
        assert s.data.get("description")
        jsonschema.validate(json.loads(json.dumps(s.to_dict())), sk.scene.schema())
