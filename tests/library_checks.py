"""Checks of a component's declarations and equations without a simulator, shared by the library tests.

``check_declarations(component)`` is what every library test module runs on
each of its components (with defaults and with modifiers): equations are
sympy equalities naming only the component's own declarations, the component
is locally balanced (Modelica's rule: equations = non-input variables +
connector potentials), and every Boolean or Integer is defined by exactly
one equation with it on the left.  Import it as ``from library_checks import
...`` (pytest puts ``tests/`` on the path).
"""

from __future__ import annotations

import sympy as sp

from acausal.hybrid import Assert, When
from acausal.language import Boolean, Connector, Integer, Model, Parameter, Potential, Variable, time



def attach(component, name="x"):
    m = Model()
    setattr(m, name, component)
    component.ensure_built()
    return component


def collect(component, method="equations"):
    """Equations of every class along the MRO, base first (as the flattener does)."""
    items = []
    for klass in reversed(type(component).__mro__):
        own = vars(klass).get(method)
        if own is not None:
            items.extend(_spliced(own(component)))
    return items


def _spliced(items) -> list:
    """An array equation (a list of element equations) counts as its elements, as flattening splices it."""
    out = []
    for item in items or ():
        out.extend(_spliced(item) if isinstance(item, (list, tuple)) else [item])
    return out


def enabled_declarations(component):
    return {k: d for k, d in component.declarations().items() if d.enabled(component)}


def own_names(component):
    """Every symbol name the component may use: its variables, parameters and connector variables."""
    names = set()
    for key, decl in enabled_declarations(component).items():
        path = component._path_of(key)
        if isinstance(decl, Connector):
            names.update(f"{path}.{v}" for v in type(decl).variables())
        elif isinstance(decl, (Variable, Parameter)):
            names.add(path)
    return names


def local_balance(component):
    """(equations, unknowns) with Modelica's local rule: unknowns = non-input variables + potentials."""
    unknowns = 0
    for decl in enabled_declarations(component).values():
        if isinstance(decl, Connector):
            unknowns += sum(isinstance(v, Potential) for v in type(decl).variables().values())
        elif isinstance(decl, Variable) and decl.causality != "input":
            unknowns += 1
    return sum(equation_count(item) for item in collect(component)), unknowns


def equation_count(item) -> int:
    """How many equations an item of equations() stands for (Modelica's counting rule).

    An equation is one; a when-clause as many as the variables it assigns (the
    same in every branch); an assertion none.
    """
    if isinstance(item, When):
        return len(assigned_in(item))
    if isinstance(item, Assert):
        return 0
    return 1


def assigned_in(clause: When) -> set:
    """The variables a when-clause assigns (the left sides of its first branch's equations)."""
    _conditions, items = clause.branches[0]
    return {item.lhs for item in items if isinstance(item, sp.Equality)}


def symbols_in(item) -> set:
    """The symbols an item of equations() uses, when-clauses and assertions included."""
    if isinstance(item, When):
        found = set()
        for conditions, items in item.branches:
            for part in (*conditions, *items):
                found |= symbols_in(part)
        return found
    if isinstance(item, sp.Basic):
        return set(item.free_symbols)
    # reinit, terminate, assert: the sympy values among their fields
    return {sym for value in vars(item).values() if isinstance(value, sp.Basic) for sym in value.free_symbols}


def value(expr, subs):
    """Evaluate a sympy expression after substitution."""
    return float(sp.sympify(expr).subs(subs))


def rhs_of(component, symbol, klass=None):
    """The right-hand side of the (unique) equation with ``symbol`` alone on the left.

    ``klass`` restricts the search to the equations that class itself writes.
    """
    equations = collect(component) if klass is None else vars(klass)["equations"](component)
    found = [e.rhs for e in equations if isinstance(e, sp.Equality) and e.lhs == symbol]
    assert len(found) == 1, f"expected one equation defining {symbol}, found {len(found)}"
    return found[0]


def params(component, **values):
    """Substitution dict for parameters given by their short names."""
    return {getattr(component, k): v for k, v in values.items()}


def connected_names(component) -> set[str]:
    """The names of the component's own connectors and signals its ``connect`` statements join."""
    ends = [end for pair in getattr(component, "_connections", ()) for end in pair]
    names = set()
    for key in enabled_declarations(component):
        mine = getattr(component, key, None)
        if any(end is mine or (isinstance(end, sp.Basic) and end == mine) for end in ends):
            names.add(key)
    return names


def check_declarations(component) -> None:
    """Assert the three structural rules above for one (unbuilt) component instance."""
    x = attach(component)
    name = type(x).__name__
    allowed = own_names(x)
    inner = tuple(f"{child.path}." for child in x.children.values())  # a composite reads its parts
    equations = collect(x)
    assert equations or x.children, f"{name} has no equations"
    for eq in equations:
        assert isinstance(eq, (sp.Equality, When, Assert)), f"{name}: {eq!r} is not a sympy equality"
        for sym in symbols_in(eq):
            assert sym is time or sym.name in allowed or sym.name.startswith(("pre(", "$", *inner)), \
                f"{name}: unknown name {sym.name} in {eq}"
    if not x.children:
        # a composite's equations are its parts' (each checked on its own) and its connections
        n_equations, n_unknowns = local_balance(x)
        assert n_equations == n_unknowns, f"{name}: {n_equations} equations, {n_unknowns} unknowns"
    lhs = [e.lhs for e in equations if isinstance(e, sp.Equality)]
    lhs += [v for e in equations if isinstance(e, When) for v in assigned_in(e)]
    for key, decl in enabled_declarations(x).items():
        if isinstance(decl, (Boolean, Integer)) and decl.causality != "input":
            if x.children and key in connected_names(x):
                continue  # a composite's output connected to a part's output: the part defines it
            assert lhs.count(getattr(x, key)) == 1, f"{name}.{key} needs exactly one defining equation"


def exported_classes() -> dict[str, type]:
    """Every component class the library packages export, by ``package.Name``."""
    from acausal.language import Component
    from acausal.library import blocks, electrical, rotational, thermal, translational

    found = {}
    for package in (rotational, translational, thermal, blocks, electrical):
        for name in package.__all__:
            value = getattr(package, name)
            if isinstance(value, type) and issubclass(value, Component) and not issubclass(value, Connector):
                found[f"{package.__name__.rsplit('.', 1)[-1]}.{name}"] = value
    return found



def msl_resources():
    """The MSL's table files laid out as a MODELICAPATH root (``Modelica/Resources/Data/Tables``):
    the first root of $MODELICAPATH that holds them, else ``shared/msl-resources`` beside the
    checkout; a path that may not exist (tests that need it skip)."""
    import os
    from pathlib import Path

    for root in os.environ.get("MODELICAPATH", "").split(os.pathsep):
        if root and (Path(root) / "Modelica" / "Resources" / "Data" / "Tables").is_dir():
            return Path(root)
    return Path(__file__).resolve().parents[2] / "shared" / "msl-resources"


def reference_or_skip(modelica_class: str, required: bool = True):
    """The reference result of ``modelica_class``; where the reference folder lacks it, a
    skip saying where it was looked for (or None if not ``required``)."""
    import pytest

    from acausal.tools.compare import load_reference, reference_dir

    directory = reference_dir()
    if not (directory / modelica_class).is_dir():
        if not required:
            return None
        pytest.skip(f"no reference result of {modelica_class} in {directory} (ACAUSAL_REFERENCE_DIR)")
    return load_reference(modelica_class)


def assert_in_the_tube(model_class, result=None):
    """Simulate ``model_class`` (unless ``result`` is given) and assert that every signal its
    reference compares lies in the csv-compare tube; returns the result."""
    from acausal import simulate
    from acausal.tools.compare import compare_signals

    reference = reference_or_skip(model_class.modelica_class)
    result = simulate(model_class()) if result is None else result
    assert result.success, result.message
    comparison = compare_signals(reference, result.time, result.columns)
    assert comparison.passed, comparison.table()
    return result


def assert_same_run(model_class, twin_class, names) -> None:
    """``twin_class`` (a table read another way) gives ``model_class``'s result: the same time
    points, the ``names`` equal to 1e-12, and so it lies in ``model_class``'s reference tube
    too (when the reference is there)."""
    import numpy as np

    from acausal import simulate
    from acausal.tools.compare import compare_signals

    first, twin = simulate(model_class()), simulate(twin_class())
    assert first.success and twin.success, (first.message, twin.message)
    np.testing.assert_array_equal(twin.time, first.time)
    for name in names:
        np.testing.assert_allclose(twin.columns[name], first.columns[name], rtol=0, atol=1e-12, err_msg=name)
    reference = reference_or_skip(model_class.modelica_class, required=False)
    if reference is not None:
        comparison = compare_signals(reference, twin.time, twin.columns)
        assert comparison.passed, comparison.table()
