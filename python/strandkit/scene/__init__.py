"""Scenes: a structure, the world's settings and an experiment protocol in
one versioned file (JSON or TOML), run the same from Python, from the
command line (``strandkit run scene.json --out DIR``) and in sweeps.

>>> import strandkit as sk
>>> s = sk.Scene.from_builder(
...     "rope_bridge", n_planks=4, span=5.0, sag=0.5,
...     world={"gravity": [0, -9.81, 0], "dt": 2e-3},
...     protocol=[{"relax": {}}, {"step": {"duration": 0.02}}],
...     outputs={"every": 5, "groups": ["plank"]})
>>> r = s.run(progress_bar=False)
>>> r.observables["operation"][:3].tolist(), int(r.observables["step"][-1])
(['start', 'relax', 'step'], 10)

Format (version 1): ``format`` ("strandkit-scene"), ``version`` (1),
``name``, ``description``, ``world`` (World settings: dt, gravity, scheme,
units, temperature, viscosity, seed, …), ``structure`` (``builder`` +
``args``, ``assembly`` or ``assembly_file``), ``contact``, ``obstacles``,
``protocol`` (operations: relax, step, hold, pull, stretch, rotate),
``outputs``. :func:`schema` gives the JSON Schema (shipped as
``scene.schema.json``).
"""
from .format import FORMAT, VERSION, Scene, load_scene, save_scene, set_key, parse_value
from .protocol import OPS
from .runner import SceneResult, run_scene
from .schema import schema
from .structures import BUILDERS

__all__ = ["Scene", "SceneResult", "load_scene", "save_scene", "run_scene", "schema", "BUILDERS", "OPS",
           "FORMAT", "VERSION", "set_key", "parse_value"]
