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
    assert functions == {"candidate_motions", "generate", "placement_map", "pose_matrix", "read_grasps", "record_columns", "result_cache", "robot_mjcf", "select", "select_batch", "select_pairs", "time_path", "train", "world_mjcf"}
    assert functions == {n for n in graspath.__all__ if callable(getattr(graspath, n)) and n[0].islower()}
    assert (STUB.parent / "py.typed").is_file()


def test_signatures_show_their_defaults():
    """Every default is a value Python can show (no ``...``), and the task defaults in
    ``Task.from_arrays``'s signature are the library's (``graspath.DEFAULTS``)."""
    import inspect

    callables = [graspath.select, graspath.select_batch, graspath.select_pairs, graspath.pose_matrix]
    for cls in (graspath.Robot, graspath.Task, graspath.Selection):
        callables += [getattr(cls, n) for n in dir(cls) if not n.startswith("_") and callable(getattr(cls, n))]
    for f in callables:
        try:
            signature = inspect.signature(f)
        except ValueError:
            continue
        for p in signature.parameters.values():
            assert p.default is not Ellipsis, f"{f.__qualname__}({p.name}=...)"
    parameters = inspect.signature(graspath.Task.from_arrays).parameters
    assert graspath.DEFAULTS, "no defaults exposed"
    for name, value in graspath.DEFAULTS.items():
        assert parameters[name].default == value, name


def test_the_exceptions_are_exported_with_their_bases():
    """The exception classes are typed Python (``_errors.py``), not declared in the native
    module's stub, and keep ``GraspathError`` as the common base."""
    from graspath import _errors

    names = {"GraspathError", "GraspathFileError", "GraspathFileNotFoundError", "GraspathValueError"}
    assert names == set(_errors.__all__)
    assert names <= set(graspath.__all__)
    tree = ast.parse(STUB.read_text())
    assert not names & {n.name for n in tree.body if isinstance(n, ast.ClassDef)}
    assert issubclass(graspath.GraspathFileNotFoundError, graspath.GraspathFileError)
    assert issubclass(graspath.GraspathFileNotFoundError, FileNotFoundError)
    assert issubclass(graspath.GraspathFileError, OSError)
    assert issubclass(graspath.GraspathValueError, ValueError)
    for name in names:
        assert issubclass(getattr(graspath, name), graspath.GraspathError)
    assert not issubclass(graspath.GraspathError, ValueError)
