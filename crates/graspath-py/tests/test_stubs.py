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


def _literal_values(annotation):
    """The strings of every ``Literal[...]`` inside an annotation (through ``Optional``,
    ``Union`` and names of module-level aliases)."""
    tree = ast.parse(STUB.read_text())
    aliases = {
        n.targets[0].id: n.value
        for n in tree.body
        if isinstance(n, ast.Assign) and len(n.targets) == 1 and isinstance(n.targets[0], ast.Name)
    }
    values = []

    def walk(node):
        if isinstance(node, ast.Name) and node.id in aliases:
            walk(aliases[node.id])
        elif isinstance(node, ast.Subscript):
            if isinstance(node.value, ast.Name) and node.value.id == "Literal":
                elements = node.slice.elts if isinstance(node.slice, ast.Tuple) else [node.slice]
                values.extend(e.value for e in elements if isinstance(e.value, str))
            else:
                walk(node.slice)
        elif isinstance(node, ast.Tuple):
            for element in node.elts:
                walk(element)

    walk(annotation)
    return values


def test_literal_types_are_the_library_spellings():
    """Every stub parameter named after a setting (``norm=``, ``measure=``, ``format=`` of a
    grasp file, ...) offers exactly the spellings the library reads (``graspath.SPELLINGS``),
    in the library's order."""
    tree = ast.parse(STUB.read_text())
    checked = set()
    for function in ast.walk(tree):
        if not isinstance(function, ast.FunctionDef):
            continue
        arguments = function.args.args + function.args.kwonlyargs
        for argument in arguments:
            if argument.arg not in graspath.SPELLINGS or argument.annotation is None:
                continue
            if function.name == "parse" and argument.arg == "format":
                continue  # the task text's format (yaml / json), not a grasp-file format
            offered = _literal_values(argument.annotation)
            assert offered == graspath.SPELLINGS[argument.arg], f"{function.name}({argument.arg})"
            checked.add(argument.arg)
    # A setting that no stub parameter offers is a stub that lost its Literal.
    assert checked == set(graspath.SPELLINGS)


def test_a_wrong_spelling_lists_the_right_ones():
    import numpy as np
    import pytest

    robot = graspath.Robot.builtin("panda")
    q = np.zeros((1, robot.dof))
    with pytest.raises(graspath.GraspathValueError) as error:
        robot.indices(q, part="ful")
    for name in graspath.SPELLINGS["part"]:
        assert name in str(error.value)


def _stub_parameters(function):
    """``(name, kind, default)`` of a stub function's parameters, ``self``/``cls`` left out;
    ``kind`` is ``positional`` or ``keyword``, ``default`` the literal value or ``EMPTY``."""
    import inspect

    arguments = function.args
    positional = arguments.posonlyargs + arguments.args
    defaults = [inspect.Parameter.empty] * (len(positional) - len(arguments.defaults))
    defaults += [ast.literal_eval(d) for d in arguments.defaults]
    rows = [(a.arg, "positional", d) for a, d in zip(positional, defaults)]
    rows += [
        (a.arg, "keyword", inspect.Parameter.empty if d is None else ast.literal_eval(d))
        for a, d in zip(arguments.kwonlyargs, arguments.kw_defaults)
    ]
    if rows and rows[0][0] in ("self", "cls"):
        rows = rows[1:]
    return rows


def _runtime_parameters(function):
    import inspect

    kinds = {
        inspect.Parameter.POSITIONAL_ONLY: "positional",
        inspect.Parameter.POSITIONAL_OR_KEYWORD: "positional",
        inspect.Parameter.KEYWORD_ONLY: "keyword",
    }
    rows = [(p.name, kinds[p.kind], p.default) for p in inspect.signature(function).parameters.values()]
    if rows and rows[0][0] in ("self", "cls"):
        rows = rows[1:]
    return rows


def test_stub_signatures_are_the_runtime_signatures():
    """Every stubbed function and method takes the parameters the module takes: the same
    names in the same order, the same positional / keyword-only split and the same defaults
    (read from the native module's own text signatures)."""
    tree = ast.parse(STUB.read_text())
    checked, differ = 0, []
    for node in tree.body:
        if isinstance(node, ast.FunctionDef):
            pairs = [(node, getattr(graspath, node.name), node.name)]
        elif isinstance(node, ast.ClassDef) and node.name in ("Robot", "Task", "Selection"):
            cls = getattr(graspath, node.name)
            pairs = [
                (f, getattr(cls, f.name), f"{node.name}.{f.name}")
                for f in node.body
                if isinstance(f, ast.FunctionDef)
                and not f.name.startswith("_")
                and not any(isinstance(d, ast.Name) and d.id == "property" for d in f.decorator_list)
            ]
        else:
            continue
        for stub, runtime, name in pairs:
            stub_rows, runtime_rows = _stub_parameters(stub), _runtime_parameters(runtime)
            if stub_rows != runtime_rows:
                differ.append(f"{name}: stub {stub_rows} != module {runtime_rows}")
            checked += 1
    assert not differ, "\n".join(differ)
    assert checked >= 50
