"""Unit tests of code generation (:func:`acausal.compiler.codegen.generate`).

Solution steps are made by hand (an assignment, a 2x2 linear solve, a Newton
problem), compiled, and the generated functions evaluated against the
analytic expressions they stand for.
"""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
import sympy as sp

from acausal.compiler.algebraic import Assign, LinearSolve, NewtonSolve
from acausal.compiler.codegen import GeneratedCode, generate
from acausal.errors import SolverError
from acausal.language import real_symbol, time

S = real_symbol

STATES = ("body.x1", "body.x2")
DERIVATIVES = ("der(body.x1)", "der(body.x2)")
PARAMETERS = ("k", "m")


def oscillator_steps():
    """a, b from [[2, 1], [1, 3]] (a, b) = 5 (x1, x2), i.e. a = 3*x1 - x2, b = 2*x2 - x1;
    z from z^3 = x1^3, i.e. z = x1 (the only real root);
    der(x1) = a + z, der(x2) = -k/m*b + sin(time); power = k*x2^2 (an output only)."""
    x1, x2, k, m, a, b, z = (S(n) for n in ("body.x1", "body.x2", "k", "m", "a", "b", "z"))
    two, one, three = sp.Integer(2), sp.Integer(1), sp.Integer(3)
    return [
        LinearSolve(("a", "b"), ((two, one), (one, three)), (5 * x1, 5 * x2), (), ("e0", "e1")),
        NewtonSolve(("z",), (), (z**3 - x1**3,), ("e2",)),
        Assign("der(body.x1)", a + z, None),
        Assign("der(body.x2)", -k / m * b + sp.sin(time), None),
        Assign("power", k * x2**2, None),
    ]


UNKNOWNS = ("a", "b", "z", "der(body.x1)", "der(body.x2)", "power")


def oscillator_code(name: str = "oscillator") -> GeneratedCode:
    x1 = S("body.x1")
    return generate(oscillator_steps(), STATES, DERIVATIVES, UNKNOWNS, PARAMETERS,
                    crossings=(x1 - 2 * time,), name=name, guesses={"z": 0.5})


def analytic(t, x1, x2, k, m):
    a, b, z = 3 * x1 - x2, 2 * x2 - x1, x1
    return {"a": a, "b": b, "z": z, "der(body.x1)": a + z, "der(body.x2)": -k / m * b + math.sin(t),
            "power": k * x2**2}


POINTS = [(0.0, 1.0, 2.0), (0.3, -0.7, 0.25), (2.5, 3.0, -1.5), (10.0, 0.1, 0.0)]


@pytest.mark.parametrize("t, x1, x2", POINTS)
def test_generated_derivatives_equal_the_analytic_expression(t, x1, x2):
    k, m = 2.0, 4.0
    derivatives, crossings, outputs = oscillator_code().make((k, m))
    expected = analytic(t, x1, x2, k, m)
    got = derivatives(t, np.array([x1, x2]))
    assert len(got) == 2
    assert got[0] == pytest.approx(expected["der(body.x1)"], rel=1e-9, abs=1e-12)
    assert got[1] == pytest.approx(expected["der(body.x2)"], rel=1e-12, abs=1e-14)
    assert crossings(t, np.array([x1, x2])) == pytest.approx((x1 - 2 * t,), abs=1e-15)
    values = dict(zip(UNKNOWNS, outputs(t, np.array([x1, x2]))))
    for name in UNKNOWNS:
        assert values[name] == pytest.approx(expected[name], rel=1e-9, abs=1e-12), name


def test_parameters_are_bound_when_the_factory_is_called():
    """One source, two parameter vectors: der(x2) = -k/m*b + sin(t) follows k/m."""
    code = oscillator_code()
    t, x = 0.3, np.array([1.0, 2.0])  # b = 3
    slow, _, _ = code.make((1.0, 4.0))
    fast, _, _ = code.make((8.0, 4.0))
    assert slow(t, x)[1] == pytest.approx(-0.75 + math.sin(t), abs=1e-14)
    assert fast(t, x)[1] == pytest.approx(-6.0 + math.sin(t), abs=1e-14)


def test_derivatives_compute_only_the_steps_they_need():
    """power is read by nothing the derivatives need: 4 of the 5 steps in derivatives, all 5 in outputs."""
    code = oscillator_code()
    assert (code.n_derivative_steps, code.n_steps) == (4, 5)
    derivatives_source = code.source.split("def derivatives(t, x):")[1].split("def crossings")[0]
    crossings_source = code.source.split("def crossings(t, x):")[1].split("def outputs")[0]
    assert "power" not in derivatives_source
    assert "_newton" not in crossings_source and "_det" not in crossings_source


def identifier_system():
    """Model names t, x, p, max, body.w and body_w (names the generated code also uses, or that clash).

    t = 2*x, body_w = body.w + 1, max = p*t, der(x) = max + time - x, der(body.w) = k*body_w.
    """
    x, bw, t, b_w, mx, p, k = (S(n) for n in ("x", "body.w", "t", "body_w", "max", "p", "k"))
    steps = [Assign("t", 2 * x, None), Assign("body_w", bw + 1, None), Assign("max", p * t, None),
             Assign("der(x)", mx + time - x, None), Assign("der(body.w)", k * b_w + sp.sin(time), None)]
    unknowns = ("t", "body_w", "max", "der(x)", "der(body.w)")
    return generate(steps, ("x", "body.w"), ("der(x)", "der(body.w)"), unknowns, ("p", "k"),
                    name="identifiers")


def _tuple_line(source: str, pattern: str) -> list[str]:
    """The names of the first line matching ``pattern`` (a regex with one group holding a tuple)."""
    match = re.search(pattern, source, re.MULTILINE)
    assert match, pattern
    return [n.strip() for n in match.group(1).split(",") if n.strip()]


def test_identifiers_are_readable_and_distinct_and_never_shadow_the_code_names():
    """The code keeps the model's t, x, p and max apart from time, the state vector, the parameter
    vector and the builtin, and body.w apart from body_w, so the values are right.

    At x = 1.5, body.w = 0.5, time = 0.25, p = 3, k = 2: t = 3, body_w = 1.5, max = 9,
    der(x) = 9 + 0.25 - 1.5 = 7.75, der(body.w) = 2*1.5 + sin(0.25).
    """
    code = identifier_system()
    derivatives, _, outputs = code.make((3.0, 2.0))
    d_bw = 3.0 + math.sin(0.25)
    assert derivatives(0.25, (1.5, 0.5)) == pytest.approx((7.75, d_bw), abs=1e-15)
    assert outputs(0.25, (1.5, 0.5)) == pytest.approx((3.0, 1.5, 9.0, 7.75, d_bw), abs=1e-15)
    outputs_source = code.source.split("def outputs(t, x):")[1]
    parameters = _tuple_line(code.source, r"^\s*(.*) = p$")
    states = _tuple_line(outputs_source, r"^\s*(.*) = x$")
    unknowns = _tuple_line(outputs_source, r"^\s*return \((.*)\)$")
    identifiers = dict(zip(("p", "k", "x", "body.w", "t", "body_w", "max", "der(x)", "der(body.w)"),
                           parameters + states + unknowns))
    assert len(identifiers) == 9
    values = list(identifiers.values())
    assert len(set(values)) == len(values)  # distinct
    for ident in values:
        assert ident.isidentifier() and ident not in {"t", "x", "p", "max"}
    # readable: the words of the model name survive
    assert identifiers["der(body.w)"] == "der_body_w"
    assert identifiers["der(x)"] == "der_x"
    assert identifiers["k"] == "k"
    assert identifiers["body.w"].startswith("body_w") and identifiers["body_w"].startswith("body_w")
    assert "max" in identifiers["max"] and "x" in identifiers["x"]


def test_the_source_is_kept_and_is_the_code_that_runs():
    """code.source compiled afresh gives the same functions; generating twice gives the same text."""
    code = identifier_system()
    assert code.source.splitlines()[0] == "# generated by acausal for identifiers"
    assert code.source == identifier_system().source
    assert oscillator_code().source == oscillator_code().source
    namespace = {"math": math, "np": np}
    exec(compile(code.source, "<kept source>", "exec"), namespace)
    fresh = namespace["make"]((3.0, 2.0))
    original = code.make((3.0, 2.0))
    for t, x, w in POINTS:
        for f_fresh, f_original in zip(fresh, original):
            assert f_fresh(t, (x, w)) == f_original(t, (x, w))


def test_a_singular_linear_block_raises_a_solver_error_naming_its_equations():
    """[[1, k], [1, k]] is singular for every k: the generated 2x2 solve raises, naming e0 and e1."""
    x1, k = S("body.x1"), S("k")
    one = sp.Integer(1)
    steps = [LinearSolve(("a", "b"), ((one, k), (one, k)), (x1, 2 * x1), (), ("e0", "e1")),
             Assign("der(body.x1)", S("a"), None), Assign("der(body.x2)", S("b"), None)]
    code = generate(steps, STATES, DERIVATIVES, ("a", "b", *DERIVATIVES), PARAMETERS)
    derivatives, _, _ = code.make((2.0, 4.0))
    with pytest.raises(SolverError) as info:
        derivatives(0.0, (1.0, 1.0))
    assert "e0" in str(info.value) and "e1" in str(info.value)


def test_equal_expressions_are_printed_once_per_shape_with_the_same_text():
    """functions_source prints the first copy of a shape and renames the text for the
    others: each function's text equals the text of that expression printed alone."""
    from acausal.compiler.codegen import functions_source

    def unit(k: int):
        w, tau, peak = (real_symbol(f"bearing{k}.{n}") for n in ("w", "tau", "peak"))
        started = sp.Symbol(f"pre(bearing{k}.startForward)")
        return (sp.Piecewise((1, sp.And(started, w > 0)), (-1, tau < -peak * 2), (0, True)),
                sp.sin(2 * sp.pi * tau * time) + sp.exp(w) / peak)

    expressions = [e for k in (1, 2, 13) for e in unit(k)]
    arguments = [sorted(s.name for s in e.free_symbols) for e in expressions]
    together, _ = functions_source(arguments, expressions)
    bodies = together.split("\n")[1:]
    for k, (args, expr) in enumerate(zip(arguments, expressions)):
        alone, _ = functions_source([args], [expr])
        # (the identifiers are made from all arguments: these names give the same ones)
        assert bodies[2 * k + 1] == alone.split("\n")[2]
    # and each renamed copy computes what its own expression says
    from acausal.compiler.generated import load_functions

    functions = load_functions(together, len(expressions), "test", {})
    values = {"time": 0.25}
    for k in (1, 2, 13):
        values.update({f"bearing{k}.w": 0.3 * k, f"bearing{k}.tau": 1.5 / k, f"bearing{k}.peak": 0.7 + k})
    for k in (3, 5):  # the second expression of units 2 and 13: printed from unit 1's text
        expected = float(expressions[k].subs({real_symbol(n) if n != "time" else time: v
                                              for n, v in values.items()}))
        assert functions[k](*[values[a] for a in arguments[k]]) == pytest.approx(expected, rel=1e-14)


def _tree_of_whole_source(source: str, name: str):
    """The function ``name`` of ``make`` from a parse of the whole source."""
    import ast

    make = next(n for n in ast.parse(source).body if isinstance(n, ast.FunctionDef) and n.name == "make")
    return next(n for n in make.body if isinstance(n, ast.FunctionDef) and n.name == name)


def _translated_sources():
    """Generated sources of models with Newton solves, linear solves and tables: the oscillator
    here, CoupledClutches' discrete states, an op-amp circuit (limiters in torn loops)."""
    from acausal import simulate, translate
    from examples.coupled_clutches import CoupledClutches
    from examples.electrical_opamps import Adder

    yield oscillator_code().source
    for model in (CoupledClutches(), Adder()):
        translation = translate(model, cache=False)
        simulate(translation)
        for system in translation.systems.values():
            code = getattr(system, "code", None)
            if code is not None:
                yield code.source


def test_a_function_parsed_from_its_own_lines_is_the_one_parsed_from_the_whole_source():
    """function_tree parses only a function's lines (a large model's source holds three of
    some megabytes each): the tree, line numbers included, is the whole parse's."""
    import ast

    from acausal.compiler.generated import function_tree

    count = 0
    for source in _translated_sources():
        for name in ("derivatives", "crossings", "outputs"):
            whole = _tree_of_whole_source(source, name)
            own = function_tree(source, name)
            assert ast.dump(own, include_attributes=True) == ast.dump(whole, include_attributes=True)
            count += 1
    assert count >= 9
    assert function_tree(oscillator_code().source, "no_such_function") is None


def test_a_function_whose_lines_do_not_parse_alone_is_taken_from_the_whole_source():
    """A line of the function indented as ``make``'s own (here inside a string) ends its
    lines early; the source is then parsed whole."""
    import ast

    from acausal.compiler.generated import function_tree

    source = ('def make(p):\n    def crossings(t, x):\n        s = """\nx"""\n        return (s,)\n'
              '    def outputs(t, x):\n        return (t,)\n    return crossings, outputs\n')
    found = function_tree(source, "crossings")
    assert ast.dump(found, include_attributes=True) == ast.dump(_tree_of_whole_source(source, "crossings"),
                                                                include_attributes=True)
    assert isinstance(found.body[-1], ast.Return)


def test_a_bounded_memo_keeps_the_newest_and_bears_another_thread_dropping_too():
    """generated.remember keeps the last ``limit`` entries in the order they came; the
    threads of a sweep share its memos, so an entry another thread dropped first is no error."""
    from acausal.compiler.generated import remember

    memo: dict = {}
    for k in range(10):
        assert remember(memo, k, k * k, 4) == k * k
    assert list(memo.items()) == [(6, 36), (7, 49), (8, 64), (9, 81)]

    class DroppedMeanwhile(dict):
        def pop(self, key, *default):
            super().pop(key, None)  # the other thread's drop, just before this one's
            return super().pop(key, *default)

    shared = DroppedMeanwhile({k: k for k in range(4)})
    remember(shared, 4, 4, 4)
    assert list(shared) == [1, 2, 3, 4]
