"""The type stubs ship with the module and match it: every public name has a stub, every stub
a name, and each function's parameters are the module's, in order and with the same defaults."""

import ast
import inspect
from pathlib import Path

import rollphase

STUB = Path(rollphase.__file__).with_name("__init__.pyi")


def stub_tree():
    candidates = [STUB, Path(rollphase.__file__).parent / "rollphase.pyi"]
    for c in candidates:
        if c.exists():
            return ast.parse(c.read_text()), c
    raise AssertionError(f"no stub file next to {rollphase.__file__}")


def test_the_package_is_typed():
    _, path = stub_tree()
    assert (path.parent / "py.typed").exists()


def test_the_stubs_match_the_module():
    tree, _ = stub_tree()
    stubbed = {n.name: n for n in tree.body if isinstance(n, (ast.FunctionDef, ast.ClassDef))}
    # The package re-exports its native module's names (maturin's layout: rollphase.rollphase).
    public = {n for n in dir(rollphase) if not n.startswith("_")} - {"rollphase"}
    assert public == set(stubbed) - {"_Path", "_Floats"}
    for name, node in stubbed.items():
        if isinstance(node, ast.FunctionDef):
            sig = inspect.signature(getattr(rollphase, name))
            stub_params = [a.arg for a in node.args.args]
            assert list(sig.parameters) == stub_params, name
            stub_defaults = [ast.literal_eval(d) for d in node.args.defaults]
            defaults = [p.default for p in sig.parameters.values() if p.default is not p.empty]
            assert defaults == stub_defaults, name
            assert getattr(rollphase, name).__doc__, f"{name} has a docstring"
    for cls in (rollphase.Body, rollphase.Trajectory):
        members = {n.name for n in stubbed[cls.__name__].body if isinstance(n, ast.FunctionDef)}
        for member in members - {"__len__"}:
            assert hasattr(cls, member), f"{cls.__name__}.{member}"
        real = {n for n in dir(cls) if not n.startswith("_")}
        assert real <= members, f"{cls.__name__} lacks stubs for {real - members}"


def test_help_shows_units_and_conventions():
    doc = rollphase.simulate.__doc__
    assert "mass_ratio" in doc and "rad" in doc and "last digit" in doc
    assert "(w, x, y, z)" in rollphase.__doc__
