"""The shipped type stubs are what tools/gen_stubs.py generates from the
built package (rerun it after changing the bindings or the catalogues)."""
import ast
import importlib.util
import pathlib

import strandkit as sk

PYTHON = pathlib.Path(__file__).resolve().parents[1]


def _generator():
    spec = importlib.util.spec_from_file_location("gen_stubs", PYTHON / "tools" / "gen_stubs.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_shipped_stubs_are_up_to_date(tmp_path):
    gen = _generator()
    assert gen.main(["--out", str(tmp_path)]) == 0
    written = sorted(p.name for p in tmp_path.iterdir())
    assert written == ["_native.pyi", "constraints.pyi", "loads.pyi"]
    for name in written:
        shipped = (PYTHON / "strandkit" / name).read_text(encoding="utf-8")
        fresh = (tmp_path / name).read_text(encoding="utf-8")
        assert fresh == shipped, f"strandkit/{name} is stale: run python python/tools/gen_stubs.py"
    assert (PYTHON / "strandkit" / "py.typed").exists()


def test_stubs_parse_and_cover_the_api():
    stubs = {n: ast.parse(t) for n, t in _generator().generate().items()}
    native = {node.name for node in stubs["_native.pyi"].body if isinstance(node, (ast.ClassDef, ast.FunctionDef))}
    public = {n for n in dir(sk._native) if not n.startswith("_")}
    assert public <= native, public - native
    helpers = {node.name: node for node in stubs["constraints.pyi"].body if isinstance(node, ast.FunctionDef)}
    for info in sk.constraints.CATALOGUE:
        fn = helpers[info["helper"]]
        # Every catalogue field is a typed parameter of the helper's stub.
        args = {a.arg: a for a in fn.args.args + fn.args.kwonlyargs}
        for f in info["fields"]:
            assert args[f["name"]].annotation is not None, (info["helper"], f["name"])
        assert ast.get_docstring(fn)
    loads = {node.name for node in stubs["loads.pyi"].body if isinstance(node, ast.FunctionDef)}
    assert loads == {info["helper"] for info in sk.loads.CATALOGUE}
    # Classes serving fields by name keep __getattr__ for editors.
    report = next(n for n in stubs["_native.pyi"].body if isinstance(n, ast.ClassDef) and n.name == "StepReport")
    assert "__getattr__" in {m.name for m in report.body if isinstance(m, ast.FunctionDef)}
