"""The type stubs ship with the module and match it: every public name has a stub, every stub
a name, and each function's parameters are the module's, in order and with the same defaults."""

import ast
import inspect
from pathlib import Path

import numpy as np
import pytest
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


def is_typed_dict(node):
    return isinstance(node, ast.ClassDef) and any(
        isinstance(b, ast.Name) and b.id == "TypedDict" for b in node.bases
    )


def stub_parameters(node):
    """(name, kind, default) of a stubbed function's parameters, in order; default is
    inspect's empty marker where the stub gives none."""
    args = node.args
    empty = inspect.Parameter.empty
    plain = args.posonlyargs + args.args
    defaults = [empty] * (len(plain) - len(args.defaults)) + [
        ast.literal_eval(d) for d in args.defaults
    ]
    out = [(a.arg, "positional", d) for a, d in zip(plain, defaults)]
    out += [
        (a.arg, "keyword", empty if d is None else ast.literal_eval(d))
        for a, d in zip(args.kwonlyargs, args.kw_defaults)
    ]
    if args.kwarg is not None:
        out.append((args.kwarg.arg, "var_keyword", empty))
    return out


def real_parameters(function):
    kinds = {
        inspect.Parameter.POSITIONAL_OR_KEYWORD: "positional",
        inspect.Parameter.POSITIONAL_ONLY: "positional",
        inspect.Parameter.KEYWORD_ONLY: "keyword",
        inspect.Parameter.VAR_KEYWORD: "var_keyword",
    }
    return [
        (p.name, kinds[p.kind], p.default)
        for p in inspect.signature(function).parameters.values()
    ]


def test_the_stubs_match_the_module():
    tree, _ = stub_tree()
    stubbed = {
        n.name: n
        for n in tree.body
        if isinstance(n, (ast.FunctionDef, ast.ClassDef)) and not is_typed_dict(n)
    }
    # The package re-exports its native module's names (maturin's layout: rollphase.rollphase).
    public = {n for n in dir(rollphase) if not n.startswith("_")} - {"rollphase"}
    assert public == set(stubbed)
    for name, node in stubbed.items():
        real = getattr(rollphase, name)
        if isinstance(node, ast.FunctionDef):
            # Names, order, which are keyword-only, and defaults.
            assert real_parameters(real) == stub_parameters(node), name
            assert real.__doc__, f"{name} has a docstring"
            continue
        stub_bases = [b.id for b in node.bases if isinstance(b, ast.Name)]
        real_bases = [b.__name__ for b in real.__bases__]
        assert real_bases == (stub_bases or ["object"]), name
        members = {n.name for n in node.body if isinstance(n, ast.FunctionDef)}
        for member in members - {"__len__"}:
            assert hasattr(real, member), f"{name}.{member}"
        own = {n for n in vars(real) if not n.startswith("_")}
        assert own <= members, f"{name} lacks stubs for {own - members}"
        for member in members:
            stub = next(n for n in node.body if isinstance(n, ast.FunctionDef) and n.name == member)
            if not any(isinstance(d, ast.Name) and d.id == "property" for d in stub.decorator_list):
                if callable(getattr(real, member, None)) and member != "__len__":
                    # Methods as the class holds them: self first, as in the stub.
                    assert real_parameters(getattr(real, member)) == stub_parameters(stub), (
                        f"{name}.{member}"
                    )


def typed_dict_keys(tree):
    """Each TypedDict of the stubs: (required keys, optional keys)."""
    out = {}
    for node in tree.body:
        if not is_typed_dict(node):
            continue
        required, optional = set(), set()
        for item in node.body:
            if isinstance(item, ast.AnnAssign):
                annotation = item.annotation
                is_optional = (
                    isinstance(annotation, ast.Subscript)
                    and isinstance(annotation.value, ast.Name)
                    and annotation.value.id == "NotRequired"
                )
                (optional if is_optional else required).add(item.target.id)
        out[node.name] = (required, optional)
    return out


# Dicts that carry the run's drag law hold one float per registered drag parameter, which a
# TypedDict cannot list (the registry decides them): they are checked against the registry.
WITH_DRAG_LAW = {"RunSummary", "Prediction"}


def assert_keys(kind, d, keys):
    required, optional = keys[kind]
    if kind in WITH_DRAG_LAW:
        drag_keys = {p["key"] for p in rollphase.drag_parameters()}
        assert drag_keys <= set(d), (kind, drag_keys - set(d))
        assert all(isinstance(d[k], float) for k in drag_keys)
        d = {k: v for k, v in d.items() if k not in drag_keys}
    assert required <= set(d) <= required | optional, (kind, set(d) ^ required)


def test_every_returned_dict_has_its_typed_dicts_keys(repo):
    # Issue 37: five functions and Trajectory.summary returned Dict[str, Any].
    tree, _ = stub_tree()
    keys = typed_dict_keys(tree)
    sphere = rollphase.Body.paper_sphere(219)
    disk = rollphase.Body.paper_disk(84, sigma=0.12, modes=5)
    assert_keys("RunSummary", rollphase.simulate(sphere, 0.15, 5.0, samples=3).summary, keys)
    assert_keys("RunSummary", rollphase.simulate(disk, 0.3, 5.0, samples=3).summary, keys)
    dented = rollphase.Body.paper_disk(219, sigma=0.5, modes=9)
    tipped = rollphase.simulate(dented, 0.3, 20.0, mass_ratio=2.0, theta0=1.5, samples=3).summary
    assert "tips" in tipped
    assert_keys("RunSummary", tipped, keys)
    many = rollphase.simulate_many(sphere, 0.15, 5.0, q0s=[[1, 0, 0, 0]], samples=3)
    assert_keys("RunSummary", many.summaries[0], keys)
    assert_keys("CruisingFraction", rollphase.cruising_fraction(sphere, 0.3, orientations=2), keys)
    quick = dict(t_min=100.0, t_cap=2000.0)
    (orbit,) = rollphase.periodic_orbits(sphere, 0.3, orientations=1, **quick)
    assert_keys("PeriodicOrbit", orbit, keys)
    prediction = rollphase.predict(sphere, 0.3, starts=1, t_cap=2000.0)
    assert_keys("Prediction", prediction, keys)
    assert_keys("PredictedOrbit", prediction["orbits"][0], keys)
    counts = rollphase.period_counts(sphere, 0.3, mass_ratio=1.0, orientations=1, **quick)
    assert_keys("PeriodCounts", counts, keys)
    # Flip and PeriodTwoWindow: test_studies.py's orbit diagram, which has both.
    diagram = rollphase.mass_bifurcation(sphere, 0.15, masses=[0.0, 1.0, 2.0], starts=2, t_min=300.0)
    assert_keys("MassBifurcation", diagram, keys)
    assert_keys("ContinuedOrbit", diagram["orbits"][0], keys)
    with pytest.warns(UserWarning, match="triangle"):
        fitted = rollphase.Body.from_mesh(repo / "assets/data/printed-sphere.stl").mesh_fit
    assert_keys("MeshFitReport", fitted, keys)
    t = np.arange(600.0)
    w = 2 * np.pi / 37.5
    track = rollphase.measure_track(t, 0.5 * t + np.sin(w * t), np.cos(w * t))
    assert_keys("TrackMeasurement", track, keys)
    assert_keys("Significance", track["significance"], keys)
    compared = rollphase.compare_with_model(
        sphere, 0.15, period_s=8.0, advance_down_cm=6.0, advance_across_cm=0.0, scale_mm=10.0,
        starts=2,
    )
    assert_keys("ModelComparison", compared, keys)
    assert_keys("DegreeResidual", fitted["degree_residuals"][0], keys)


def test_help_shows_units_and_conventions():
    doc = rollphase.simulate.__doc__
    assert "mass_ratio" in doc and "rad" in doc and "last digit" in doc
    assert "(w, x, y, z)" in rollphase.__doc__
