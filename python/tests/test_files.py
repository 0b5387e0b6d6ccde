"""Every writer is atomic: when the final rename fails (the target is a
directory) the call raises a FileError naming the target and leaves no
temporary file behind (before, a full-size `.target.tmp<pid>` stayed)."""
import os

import numpy as np
import pytest

import strandkit as sk
import strandkit.plot


@pytest.fixture
def world():
    w = sk.World(gravity=(0, -9.81, 0))
    rod = w.add_rod(sk.straight((0, 0, 0), (1, 0, 0), n_control_points=8, section=0.01, material="nylon"))
    sk.clamp(w, rod)
    w.step()
    return w


def recorder(w, events=False):
    rec = sk.Recorder(w)
    rec.record()
    if events:
        rec.events.append({"kind": "Test", "time": 0.0})
    return rec


# name → (call writing to `target`, path that must be a directory to fail).
WRITERS = {
    "World.save": lambda w, t: w.save(t),
    "write_pdb": lambda w, t: sk.write_pdb(w, t),
    "write_psf": lambda w, t: sk.write_psf(w, t),
    "write_obj": lambda w, t: sk.write_obj(w, t),
    "write_vtk": lambda w, t: sk.write_vtk(w, t),
    "write_gltf": lambda w, t: sk.write_gltf(w, t),
    "Topology.write_pdb": lambda w, t: sk.Topology(w).write_pdb(t, sk.bead_positions(w)),
    "Topology.write_psf": lambda w, t: sk.Topology(w).write_psf(t),
    "DcdWriter": lambda w, t: sk.DcdWriter(t, 3),
    "Recorder.to_csv": lambda w, t: recorder(w).to_csv(t),
    "Recorder.to_csv events": lambda w, t: recorder(w, events=True).to_csv(t.replace(".events.csv", ".csv")),
    "Recorder.to_npz": lambda w, t: recorder(w).to_npz(t),
    "plot_world": lambda w, t: strandkit.plot.plot_world(w, t, size=(64, 48)),
    "plot_curves": lambda w, t: strandkit.plot.plot_curves(recorder(w), "elastic_energy", path=t),
    "TrajectoryWriter": lambda w, t: sk.TrajectoryWriter(w, t[: -len(".pdb")]),
}
TARGETS = {"Recorder.to_csv events": "target.events.csv", "Recorder.to_npz": "target.npz",
           "TrajectoryWriter": "target.pdb", "plot_world": "target.png", "plot_curves": "target.png"}


@pytest.mark.parametrize("name", WRITERS)
def test_target_is_a_directory_clean_error_and_no_temporary(world, tmp_path, name):
    target = tmp_path / TARGETS.get(name, "target")
    target.mkdir()
    (tmp_path / "other.txt").write_text("untouched")
    before = sorted(os.listdir(tmp_path))
    with pytest.raises(sk.FileError) as e:
        WRITERS[name](world, str(target))
    assert isinstance(e.value, OSError) and e.value.kind == "Io"
    assert e.value.path.endswith(target.name) and target.name in str(e.value)
    left = sorted(os.listdir(tmp_path))
    # The CSV of the events case is written before its events file fails.
    assert [f for f in left if f not in before and f != "target.csv"] == [], left
    assert not any(".tmp" in f for f in left)
    assert os.listdir(target) == [] and (tmp_path / "other.txt").read_text() == "untouched"


def test_recorder_files_round_trip_and_replace_whole(world, tmp_path):
    rec = recorder(world)
    world.step()
    rec.record()
    path = rec.to_npz(str(tmp_path / "run"))  # numpy's suffix rule, but atomic
    assert path.endswith("run.npz") and os.listdir(tmp_path) == ["run.npz"]
    data = np.load(path)
    np.testing.assert_array_equal(data["time"], [world.time - world.dt, world.time])
    csv = rec.to_csv(str(tmp_path / "run.csv"))
    first = open(csv).read()
    rec.record()
    rec.to_csv(csv)
    assert open(csv).read().startswith(first.splitlines()[0]) and len(open(csv).read().splitlines()) == 4
    assert sorted(os.listdir(tmp_path)) == ["run.csv", "run.npz"]
