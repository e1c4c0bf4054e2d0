"""The type stubs list exactly the public methods and properties of the native classes."""

import ast
from pathlib import Path

import graspath

STUB = Path(graspath.__file__).with_name("_graspath.pyi")


def test_stubs_match_the_module():
    tree = ast.parse(STUB.read_text())
    classes = {n.name: n for n in tree.body if isinstance(n, ast.ClassDef)}
    for name in ("Robot", "Task", "Selection"):
        stub = {i.name for i in classes[name].body if isinstance(i, ast.FunctionDef) and not i.name.startswith("_")}
        runtime = {n for n in dir(getattr(graspath, name)) if not n.startswith("_")}
        assert stub == runtime, name
    functions = {n.name for n in tree.body if isinstance(n, ast.FunctionDef)}
    assert functions == {"select", "read_grasps"}
    assert (STUB.parent / "py.typed").is_file()
