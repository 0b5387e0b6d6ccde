"""Sweeps (issue 19): an 8-point sweep on a 2-worker Dask LocalCluster gives
the local run's numbers, also when one worker is killed mid-sweep; an
interrupted sweep recomputes only its missing points; seeds depend on a
point's values alone; bad grids are refused before any point runs."""
import os
import signal

import numpy as np
import pytest

import strandkit as sk
from strandkit.sweeps import grid_points, point_seed

pd = pytest.importorskip("pandas")
pytest.importorskip("pyarrow")

DNA = sk.Material("dna", 300.0, 0.5, 1.7e-3)  # molecular units: E 300 pN/nm² (300 MPa), 1700 kg/m³
GRID = {"temperature": [0.5, 1.0], "length": [1.0, 2.0], "steps": [20, 40]}  # 8 points


def jiggle(temperature, length, steps, seed):
    """A free rod in a viscous fluid with thermal noise (molecular units):
    where its end went depends on the seed, so any mix-up of seeds or
    points shows in the numbers."""
    w = sk.World(units="molecular", dt=0.01, viscosity=1.0, temperature=temperature * 298.15, seed=seed)
    rod = w.add_rod(sk.straight((0, 0, 0), (length * 10, 0, 0), section=1.0, material=DNA, n_control_points=8,
                                with_roll=False))
    for _ in range(steps):
        w.step()
    end = rod.position(rod.u_end)
    return {"end_y": float(end[1]), "end_z": float(end[2]), "pid": os.getpid()}


def kill_once(temperature, length, steps, seed, marker):
    """jiggle, but the first worker to reach the point (1.0, 1.0, 40) dies
    there (SIGKILL of its own process: a crashed node)."""
    if (temperature, length, steps) == (1.0, 1.0, 40) and not os.path.exists(marker):
        with open(marker, "w") as f:
            f.write(str(os.getpid()))
        os.kill(os.getpid(), signal.SIGKILL)
    return jiggle(temperature, length, steps, seed)


def results(df):
    return df.drop(columns=["elapsed", "pid"]).sort_values("point").reset_index(drop=True)


def test_dask_local_cluster_matches_local_processes_and_survives_a_killed_worker(tmp_path):
    distributed = pytest.importorskip("distributed")
    local = sk.sweep(jiggle, GRID, workers=2, progress_bar=False, seed=11)
    assert len(local) == 8 and local["end_y"].nunique() == 8
    marker = str(tmp_path / "killed")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        worker_pids = set(client.run(os.getpid).values())
        df = sk.sweep(lambda **kw: kill_once(marker=marker, **kw), GRID, client=client, progress_bar=False,
                      seed=11, out=tmp_path / "dask")
    assert os.path.exists(marker)  # a worker did die mid-sweep, in the middle of a point
    killed = int(open(marker).read())
    redone = df[(df["temperature"] == 1.0) & (df["length"] == 1.0) & (df["steps"] == 40)]
    assert killed in worker_pids and len(redone) == 1 and np.isfinite(redone["end_y"]).all()
    assert results(df).equals(results(local))
    assert pd.read_parquet(tmp_path / "dask" / "results.parquet")["point"].tolist() == df["point"].tolist()


def test_interrupted_sweep_recomputes_only_missing_points(tmp_path):
    calls = tmp_path / "calls"
    calls.mkdir()
    stop_after = {"n": 3}

    def counted(temperature, length, steps, seed):
        done = len(os.listdir(calls))
        if stop_after["n"] is not None and done == stop_after["n"]:
            raise KeyboardInterrupt  # Ctrl-C during the 4th point
        (calls / f"{done}-{temperature}-{length}-{steps}").write_text("")
        return jiggle(temperature, length, steps, seed)

    out = tmp_path / "sweep"
    with pytest.raises(sk.Interrupted) as e:
        sk.sweep(counted, GRID, out=out, workers=0, progress_bar=False, seed=3)
    assert e.value.done == 3 and len(list((out / "points").iterdir())) == 3
    stop_after["n"] = None
    df = sk.sweep(counted, GRID, out=out, workers=0, progress_bar=False, seed=3)
    assert len(os.listdir(calls)) == 8  # 3 before, 5 after: none twice
    full = sk.sweep(jiggle, GRID, workers=0, progress_bar=False, seed=3)
    assert results(df).equals(results(full))
    assert pd.read_parquet(out / "results.parquet")["point"].tolist() == df["point"].tolist()
    with pytest.raises(sk.SceneError) as e:  # the directory belongs to that sweep
        sk.sweep(jiggle, GRID, out=out, workers=0, progress_bar=False, seed=4)
    assert e.value.key == "out"


def test_scene_sweep_in_processes_equals_in_process(tmp_path):
    scene = sk.Scene.from_builder("necklace", n_beads=4, world={"gravity": [0, -9.81, 0], "temperature": 0.0},
                                  protocol=[{"step": {"steps": 20}}], outputs={"every": 10})
    grid = {"structure.args.n_beads": [3, 5], "world.dt": [1e-3, 2e-3]}
    a = sk.sweep(scene, grid, workers=2, progress_bar=False, out=tmp_path / "a")
    b = sk.sweep(scene, grid, workers=0, progress_bar=False)
    cols = [c for c in a.columns if c != "elapsed"]
    assert a[cols].equals(b[cols])
    assert a["final_time"].tolist() == pytest.approx([0.02, 0.04, 0.02, 0.04], rel=1e-12)
    assert sorted(os.listdir(tmp_path / "a" / "runs")) == sorted(a["point"])
    one = scene.with_values({"structure.args.n_beads": 5, "world.dt": 2e-3, "world.seed": int(a["seed"].iloc[3])})
    assert one.run(progress_bar=False).summary()["final_total"] == a["final_total"].iloc[3]


def test_point_seeds_depend_on_the_point_alone():
    pts = grid_points({"a": [1, 2, 3]})
    more = grid_points({"a": [1, 2, 3, 4]})
    assert [point_seed(0, p) for p in pts] == [point_seed(0, p) for p in more[:3]]
    assert len({point_seed(0, p) for p in more}) == 4 and point_seed(1, pts[0]) != point_seed(0, pts[0])
    assert all(0 <= point_seed(0, p) < 2**63 for p in more)


@pytest.mark.parametrize("grid,key", [
    ({}, "grid"),
    ({"temperature": []}, "grid.temperature"),
    ([], "grid"),
    ({"temperature": [1.0, float("nan")], "length": [1.0], "steps": [5]}, "grid.temperature"),
    ({"temperature": 1.0}, "grid.temperature"),
    ({"colour": [1]}, "grid.colour"),
    ([{"temperature": 1.0}, {"length": 2.0}], "grid[1]"),
    ({"temperature": [1.0, 1.0], "length": [1.0], "steps": [5]}, "grid"),
])
def test_bad_grids_are_refused_before_any_point(grid, key):
    ran = []
    with pytest.raises(sk.SceneError) as e:
        sk.sweep(lambda temperature=0, length=0, steps=0: ran.append(1) or {}, grid, workers=0, progress_bar=False)
    assert e.value.key == key and not ran, str(e.value)


def test_bad_scene_grid_and_directory(tmp_path):
    scene = sk.Scene.from_builder("necklace", n_beads=4, protocol=[{"step": {"steps": 2}}])
    with pytest.raises(sk.SceneError) as e:
        sk.sweep(scene, {"world.dt": [1e-3, -1.0]}, workers=0, progress_bar=False)
    assert e.value.key == "grid[1]" and "world.dt" in str(e.value)
    with pytest.raises(sk.SceneError) as e:
        sk.sweep(scene, {"structure.args.beads": [3]}, workers=0, progress_bar=False)
    assert "structure.args.beads" in str(e.value)
    (tmp_path / "file").write_text("x")
    with pytest.raises(sk.SceneError) as e:
        sk.sweep(scene, {"world.dt": [1e-3]}, out=tmp_path / "file" / "out", workers=0, progress_bar=False)
    assert e.value.key == "out"
    with pytest.raises(sk.SceneError):
        sk.sweep(scene, {"world.dt": [1e-3]}, seed=-1, workers=0, progress_bar=False)
    assert np.isfinite(sk.sweep(scene, {"world.dt": [1e-3]}, workers=0, progress_bar=False)["final_total"]).all()


def test_a_failing_simulation_is_that_points_result(tmp_path):
    """A point whose run fails (here: relax of a rod held at no point, a
    free rigid motion: SingularError) gets an error; the other points run."""
    def sag(held):
        w = sk.World(gravity=(0, -9.81, 0))
        rod = w.add_rod(sk.straight((0, 0, 0), (1, 0, 0), section=0.01, material="carbon_steel", n_control_points=8))
        if held:
            sk.clamp(w, rod)
        w.relax()
        return {"tip_y": float(rod.position(rod.u_end)[1])}
    df = sk.sweep(sag, {"held": [True, False]}, workers=0, progress_bar=False, out=tmp_path)
    assert df["error"].isna().tolist() == [True, False]
    assert df["error"].iloc[1].startswith("SingularError")
    assert df["tip_y"].iloc[0] < 0 and np.isnan(df["tip_y"].iloc[1])


def test_grid_values_normalised_and_typed(tmp_path):
    """Tuples and numpy values read back as the manifest writes them (a
    resumed sweep recognises its grid); a key mixing types is refused."""
    def f(x, v, seed):
        return {"s": float(sum(v)) + x}
    grid = {"x": np.array([1.0, 2.0]), "v": [(1, 2), (3, 4)]}
    a = sk.sweep(f, grid, out=tmp_path, workers=0, progress_bar=False)
    b = sk.sweep(f, grid, out=tmp_path, workers=0, progress_bar=False)
    assert a.equals(b) and list(a["v"].iloc[0]) == [1, 2]
    with pytest.raises(sk.SceneError) as e:
        sk.sweep(f, {"x": [1.0, "one"], "v": [[1]]}, workers=0, progress_bar=False)
    assert e.value.key == "grid.x" and "mixes" in str(e.value)


def test_a_seed_in_the_grid_is_the_one_used_and_none_mixes():
    def f(x, seed, cap=None):
        return {"seed_seen": seed, "capped": cap is not None}
    df = sk.sweep(f, [{"x": 1, "seed": 5, "cap": None}, {"x": 2, "seed": 6, "cap": 2.5}], workers=0,
                  progress_bar=False)
    assert df["seed_seen"].tolist() == [5, 6] and df["seed"].tolist() == [5, 6]
    assert df["capped"].tolist() == [False, True]


def test_a_changed_function_does_not_mix_with_old_results(tmp_path):
    def f(x):
        return {"y": x}
    sk.sweep(f, {"x": [1, 2]}, out=tmp_path, workers=0, progress_bar=False)

    def f(x):  # noqa: F811  (same name, another body)
        return {"y": 2 * x}
    with pytest.raises(sk.SceneError) as e:
        sk.sweep(f, {"x": [1, 2]}, out=tmp_path, workers=0, progress_bar=False)
    assert e.value.key == "out"


def test_ctrl_c_in_a_scene_sweep_stops_it(tmp_path):
    """A real SIGINT while a scene point runs in the sweep's own process:
    the sweep stops (exit 130) without recording that point, and running it
    again completes every point, none with an error."""
    import subprocess
    import sys
    import time
    # Points long enough (over a second each) that the SIGINT sent once the
    # first is written lands in a later one: with 1500 steps a loaded CI
    # machine once ran the other three before it arrived (exit 0).
    scene = sk.Scene.from_builder("rope_bridge", n_planks=4, span=5.0, sag=0.5,
                                  world={"gravity": [0, -9.81, 0], "dt": 2e-3},
                                  protocol=[{"step": {"steps": 6000}}], outputs={"every": 200})
    path = scene.save(tmp_path / "bridge.json")
    out = tmp_path / "sweep"
    args = [sys.executable, "-m", "strandkit", "sweep", str(path), "--vary", "structure.args.n_planks=3,4,5,6",
            "--out", str(out), "--workers", "0", "--no-progress"]
    p = subprocess.Popen(args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)

    def finished():  # the points written (not a point's temporary file being written)
        return len(list((out / "points").glob("*.parquet"))) if (out / "points").is_dir() else 0
    deadline = time.time() + 120
    while time.time() < deadline and finished() == 0:
        time.sleep(0.02)
    p.send_signal(signal.SIGINT)
    _, err = p.communicate(timeout=120)
    done = finished()
    assert p.returncode == 130 and "interrupted" in err, err
    assert 1 <= done < 4
    r = subprocess.run(args, capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    df = pd.read_parquet(out / "results.parquet")
    assert len(df) == 4 and ("error" not in df or df["error"].isna().all())
