"""The examples in the docstrings of every strandkit module run and give
what they show."""
import doctest
import importlib
import pkgutil

import pytest

import strandkit

MODULES = ["strandkit"] + sorted(m.name for m in pkgutil.walk_packages(strandkit.__path__, "strandkit."))
# Modules whose docstrings carry examples (a module losing all of them fails).
WITH_EXAMPLES = {"strandkit", "strandkit._catalogue", "strandkit._native", "strandkit.constraints", "strandkit.dna",
                 "strandkit.dna.duplex", "strandkit.dna.fluctuations", "strandkit.dna.tweezers",
                 "strandkit.dna.viewer",
                 "strandkit.errors", "strandkit.loads", "strandkit.recorder", "strandkit.trajectory",
                 "strandkit.scene", "strandkit.scene.format", "strandkit.sweeps",
                 "strandkit.units"}


@pytest.mark.parametrize("name", MODULES)
def test_docstring_examples(name, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # examples that write files write here or in temp dirs
    module = importlib.import_module(name)
    finder = doctest.DocTestFinder(exclude_empty=True)
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    tests = finder.find(module, name)
    for t in tests:
        runner.run(t)
    result = runner.summarize(verbose=False)
    assert result.failed == 0, f"{result.failed} docstring example(s) of {name} failed (output above)"
    if name in WITH_EXAMPLES:
        assert result.attempted > 0, f"{name} lost its docstring examples"
