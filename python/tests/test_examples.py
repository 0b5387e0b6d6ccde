"""Every example script runs, passes its checks against its reference
(it exits with status 1 when one fails) and writes only to the output
directory it is given."""
import os
import pathlib
import subprocess
import sys

import pytest

EXAMPLES_DIR = pathlib.Path(__file__).resolve().parents[2] / "examples"
# Scripts (not the helper module _common.py) and the files each writes.
OUTPUTS = {
    "bead_on_string.py": ["bead_on_string.png"],
    "bridge_fall.py": ["bridge_fall.png"],
    "cables.py": ["cables.glb", "cables.png", "harness.glb"],
    "cantilever.py": ["cantilever.png"],
    "catenary.py": ["catenary.png"],
    "dna_force_extension.py": ["dna_force_extension.png"],
    "dna_trap.py": ["dna_trap.png"],
    "dna_twist.py": ["dna_twist.csv", "dna_twist.dcd", "dna_twist.pdb", "dna_twist.png", "dna_twist.psf"],
    "dna_stretch_sweep.py": ["dna_stretch_sweep", "dna_stretch_sweep.png"],
    "dna_shear.py": ["dna_shear.csv", "dna_shear.dcd", "dna_shear.pdb", "dna_shear.png", "dna_shear.psf"],
    "dna_unzip.py": ["dna_unzip.csv", "dna_unzip.dcd", "dna_unzip.pdb", "dna_unzip.png", "dna_unzip.psf"],
    "knit_jersey.py": ["knit_jersey.glb", "knit_jersey.png", "knit_jersey.vtk", "knit_jersey_stretch.png"],
    "knit_patterns.py": ["knit_patterns.png"],
    "knit_sweep.py": ["knit_sweep", "knit_sweep.png"],
    "necklace.py": ["necklace.dcd", "necklace.pdb", "necklace.png", "necklace.psf", "necklace_energy.png"],
    "rope_bridge.py": ["rope_bridge.dcd", "rope_bridge.pdb", "rope_bridge.png", "rope_bridge.psf", "rope_bridge_walk.png"],
    "pendulum.py": ["pendulum.csv", "pendulum.dcd", "pendulum.pdb", "pendulum.png", "pendulum.psf", "pendulum_tip.png"],
    "plastic_rupture.py": ["plastic_rupture.png"],
    "plectoneme.py": ["plectoneme.png"],
    "quasi_dynamic.py": ["quasi_dynamic.png"],
    "sliding_points.py": ["sliding_points.png"],
    "spring.py": ["spring.dcd", "spring.glb", "spring.pdb", "spring.png", "spring.psf", "spring_end.png"],
}


def run(args, cwd, env=None):
    e = dict(os.environ)
    e.pop("STRANDKIT_OUT", None)
    e["PYTHONDONTWRITEBYTECODE"] = "1"  # no __pycache__ in the examples directory
    e.update(env or {})
    return subprocess.run([sys.executable, *map(str, args)], capture_output=True, text=True, timeout=300, cwd=cwd, env=e)


def test_every_example_is_listed():
    assert sorted(p.name for p in EXAMPLES_DIR.glob("[!_]*.py")) == sorted(OUTPUTS)


@pytest.mark.parametrize("name", sorted(OUTPUTS))
def test_example_passes_its_checks(name, tmp_path):
    out = tmp_path / "results"
    work = tmp_path / "cwd"
    work.mkdir()
    r = run([EXAMPLES_DIR / name, "--out", out], cwd=work)
    assert r.returncode == 0, r.stdout[-3000:] + r.stderr[-2000:]
    assert "all checks passed" in r.stdout and "check FAIL" not in r.stdout
    assert sorted(f.name for f in out.iterdir()) == OUTPUTS[name]
    assert list(work.iterdir()) == []  # nothing written beside


def test_output_directory_from_the_environment_or_the_current_directory(tmp_path):
    env_out = tmp_path / "env"
    r = run([EXAMPLES_DIR / "catenary.py"], cwd=tmp_path, env={"STRANDKIT_OUT": str(env_out)})
    assert r.returncode == 0, r.stderr[-2000:]
    assert [f.name for f in env_out.iterdir()] == ["catenary.png"] and not (tmp_path / "out").exists()
    r = run([EXAMPLES_DIR / "catenary.py"], cwd=tmp_path)
    assert r.returncode == 0, r.stderr[-2000:]
    assert [f.name for f in (tmp_path / "out").iterdir()] == ["catenary.png"]


def test_a_failed_check_exits_with_status_1(tmp_path):
    code = ("from _common import Checks\n"
            "c = Checks()\n"
            "c.close('within', 1.0005, 1.0, rtol=1e-3)\n"
            "c.close('off by 2 %', 1.02, 1.0, rtol=1e-3)\n"
            "c.close('NaN', float('nan'), 1.0, rtol=1.0)\n"
            "c.finish()\n"
            "print('not reached')\n")
    r = run(["-c", code], cwd=tmp_path, env={"PYTHONPATH": str(EXAMPLES_DIR)})
    assert r.returncode == 1
    assert "check OK   within" in r.stdout and "check FAIL off by 2 %" in r.stdout and "check FAIL NaN" in r.stdout
    assert "not reached" not in r.stdout and "FAILED 2 check(s): off by 2 %, NaN" in r.stderr
