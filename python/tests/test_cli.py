"""The command line (issue 19) end to end on a small scene: outputs exist,
load in mdtraj and pandas and match the Python API's; Ctrl-C stops cleanly
and --resume finishes with the uninterrupted run's files, byte for byte;
info, validate, sweep and schema; exit status 2 naming the key on a bad
scene."""
import json
import os
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

import strandkit as sk

pd = pytest.importorskip("pandas")


def cli(*args, cwd=None, timeout=300):
    return subprocess.run([sys.executable, "-m", "strandkit", *map(str, args)], capture_output=True, text=True,
                          cwd=cwd, timeout=timeout)


def pull_scene(duration=0.2, **outputs):
    return sk.Scene.from_builder(
        "rope_bridge", name="bridge pull", n_planks=4, span=5.0, sag=0.5,
        world={"gravity": [0, -9.81, 0], "dt": 2e-3},
        protocol=[{"relax": {}}, {"pull": {"constraints": "anchor[0,1]", "velocity": [0, 0, 0.1], "duration": duration}}],
        outputs={"every": 5, "groups": ["plank"], "snapshot_every": 50, **outputs})


def test_run_writes_outputs_that_mdtraj_and_pandas_read(tmp_path):
    md = pytest.importorskip("mdtraj")
    path = pull_scene().save(tmp_path / "bridge.json")
    r = cli("run", path, "--out", tmp_path / "out", "--no-progress")
    assert r.returncode == 0, r.stderr
    out = tmp_path / "out"
    names = sorted(os.listdir(out))
    assert names == sorted(["scene.json", "observables.csv", "observables.parquet", "observables.png", "events.jsonl",
                            "trajectory.pdb", "trajectory.psf", "trajectory.dcd", "snapshot.json", "state.json"])
    api = sk.load_scene(path).run(progress_bar=False)
    csv = pd.read_csv(out / "observables.csv")
    pq = pd.read_parquet(out / "observables.parquet")
    for df in (csv, pq):
        for col, values in api.observables.items():
            assert df[col].tolist() == values.tolist() or np.array_equal(df[col].to_numpy(float), values.astype(float),
                                                                          equal_nan=True), col
    traj = md.load(str(out / "trajectory.dcd"), top=str(out / "trajectory.psf"))
    frames = 1 + 1 + 100 // 50  # start, relax, every 10 × every = 50 steps
    assert traj.n_frames == frames
    beads = sk._native.bead_positions(api.world)
    np.testing.assert_allclose(traj.xyz[-1], beads, atol=1e-5)  # written at 10 Å per m, read by mdtraj in nm
    assert open(out / "observables.png", "rb").read(8) == b"\x89PNG\r\n\x1a\n"


def test_ctrl_c_then_resume_gives_the_uninterrupted_files(tmp_path):
    path = pull_scene(duration=1.6).save(tmp_path / "bridge.json")
    whole = cli("run", path, "--out", tmp_path / "whole", "--no-progress")
    assert whole.returncode == 0, whole.stderr
    out = tmp_path / "cut"
    p = subprocess.Popen([sys.executable, "-m", "strandkit", "run", str(path), "--out", str(out), "--no-progress"],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.time() + 120
    while time.time() < deadline:  # wait until the pull is under way
        csv = out / "observables.csv"
        if csv.exists() and csv.read_text().count("\n") > 20:
            break
        time.sleep(0.05)
    p.send_signal(signal.SIGINT)
    _, err = p.communicate(timeout=120)
    assert p.returncode == 130, err
    assert "interrupted" in err and "--resume" in err
    state = json.loads((out / "state.json").read_text())
    assert not state["done"] and 0 < state["n_steps"] < 800
    assert len(pd.read_csv(out / "observables.csv")) >= state["rows"]  # what is on disk is valid
    r = cli("run", path, "--out", out, "--resume", "--no-progress")
    assert r.returncode == 0, r.stderr
    for name in ("observables.csv", "events.jsonl", "trajectory.dcd", "snapshot.json"):
        assert (out / name).read_bytes() == (tmp_path / "whole" / name).read_bytes(), name


def test_resume_after_a_hard_kill_cuts_what_followed_the_snapshot(tmp_path):
    path = pull_scene(duration=1.6).save(tmp_path / "bridge.json")
    whole = cli("run", path, "--out", tmp_path / "whole", "--no-progress")
    assert whole.returncode == 0
    out = tmp_path / "killed"
    p = subprocess.Popen([sys.executable, "-m", "strandkit", "run", str(path), "--out", str(out), "--no-progress"],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    deadline = time.time() + 120
    while time.time() < deadline:
        csv = out / "observables.csv"
        if csv.exists() and csv.read_text().count("\n") > 30:
            break
        time.sleep(0.02)
    p.kill()  # SIGKILL: no snapshot at the stop, rows and frames past the last one
    p.communicate()
    assert p.returncode == -signal.SIGKILL
    assert not json.loads((out / "state.json").read_text())["done"]
    r = cli("run", path, "--out", out, "--resume", "--no-progress")
    assert r.returncode == 0, r.stderr
    for name in ("observables.csv", "trajectory.dcd"):
        assert (out / name).read_bytes() == (tmp_path / "whole" / name).read_bytes(), name


def test_info_validate_sweep_and_schema(tmp_path):
    path = pull_scene(duration=0.02).save(tmp_path / "bridge.toml")
    info = cli("info", path)
    assert info.returncode == 0, info.stderr
    assert "builder rope_bridge" in info.stdout and "[1] pull" in info.stdout and "10 steps" in info.stdout
    ok = cli("validate", path, "--set", "world.dt=1e-3")
    assert ok.returncode == 0 and "valid" in ok.stdout
    sw = cli("sweep", path, "--vary", "structure.args.n_planks=3,4", "--out", tmp_path / "sw", "--workers", "0",
             "--no-progress")
    assert sw.returncode == 0, sw.stderr
    df = pd.read_parquet(tmp_path / "sw" / "results.parquet")
    assert df["structure.args.n_planks"].tolist() == [3, 4]
    for n, total in zip([3, 4], df["final_total"]):
        one = sk.load_scene(path).with_values({"structure.args.n_planks": n,
                                               "world.seed": int(df.loc[df["structure.args.n_planks"] == n, "seed"].iloc[0])})
        assert one.run(progress_bar=False).summary()["final_total"] == total
    schema = cli("schema")
    assert schema.returncode == 0 and json.loads(schema.stdout) == sk.scene.schema()


@pytest.mark.parametrize("args,words", [
    (["validate", "{scene}", "--set", "world.dt=-1"], "world.dt"),
    (["run", "{scene}", "--out", "{tmp}/o", "--set", "protocol.1.pull.velocity=[0,0]"], "protocol[1].pull.velocity"),
    (["run", "{scene}", "--out", "{tmp}/file/o"], "output directory"),
    (["info", "{tmp}/missing.json"], "missing.json"),
    (["sweep", "{scene}", "--out", "{tmp}/s", "--vary", "world.dt=[]"], "grid"),
    (["sweep", "{scene}", "--out", "{tmp}/s"], "--grid"),
])
def test_bad_input_exits_2_naming_it(tmp_path, args, words):
    scene = pull_scene(duration=0.02).save(tmp_path / "bridge.json")
    (tmp_path / "file").write_text("x")
    r = cli(*[a.format(scene=scene, tmp=tmp_path) for a in args])
    assert r.returncode == 2 and words in r.stderr, r.stderr
    assert "Traceback" not in r.stderr


def test_set_without_a_value_and_sigterm(tmp_path):
    scene = pull_scene(duration=4.0).save(tmp_path / "bridge.json")
    r = cli("validate", scene, "--set", "world.dt")
    assert r.returncode == 2 and "--set" in r.stderr and "KEY=VALUE" in r.stderr
    out = tmp_path / "out"
    p = subprocess.Popen([sys.executable, "-m", "strandkit", "run", str(scene), "--out", str(out), "--no-progress"],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.time() + 120
    while time.time() < deadline and not ((out / "observables.csv").exists()
                                           and (out / "observables.csv").read_text().count("\n") > 10):
        time.sleep(0.05)
    p.terminate()
    _, err = p.communicate(timeout=120)
    assert p.returncode == 130 and "interrupted" in err


def test_sweep_from_a_grid_file_on_a_local_cluster(tmp_path):
    """`strandkit sweep --grid FILE --local-cluster 2` gives the numbers of
    the same sweep run in process."""
    pytest.importorskip("distributed")
    path = pull_scene(duration=0.02).save(tmp_path / "bridge.json")
    grid = tmp_path / "grid.json"
    grid.write_text(json.dumps([{"structure.args.n_planks": n, "world.dt": dt} for n in (3, 5) for dt in (1e-3, 2e-3)]))
    runs = {}
    for name, extra in (("dask", ["--local-cluster", "2"]), ("here", ["--workers", "0"])):
        r = cli("sweep", path, "--grid", grid, "--out", tmp_path / name, "--no-progress", *extra)
        assert r.returncode == 0, r.stderr
        runs[name] = pd.read_parquet(tmp_path / name / "results.parquet").drop(columns=["elapsed"])
    assert len(runs["here"]) == 4 and runs["dask"].equals(runs["here"])
