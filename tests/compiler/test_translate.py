"""The translation driver: work shared between the discrete states of a model.

The systems of one model share what was derived from each equation (its
specialisation, time derivative, solution and printed code), and discrete
states with the same equations share one compiled system.  Neither may change
what a state's system is: these tests compile states in different orders and
compare with states compiled alone.
"""

import math

import numpy as np
import pytest
import sympy as sp

from acausal import Boolean, Eq, Experiment, If, Model, Variable, der, simulate, time, translate
from acausal.compiler.algebraic import LinearSolve, NewtonSolve
from acausal.compiler.codegen import compile_functions, python_identifiers
from acausal.tables import table_function
from examples.coupled_clutches import CoupledClutches


@pytest.fixture(scope="module")
def visited():
    """A CoupledClutches translation after a full simulation."""
    translation = translate(CoupledClutches(), cache=False)
    result = simulate(translation)
    assert result.success
    return translation


def test_states_with_equal_equations_share_one_system(visited):
    systems = visited.systems
    shared = [s for s in systems.values() if s.shares is not None]
    # pre(mode) of a clutch that slides on selects nothing: such states repeat
    assert shared, "CoupledClutches visits states that differ only in unused pre values"
    assert visited.compiled_systems == len(systems) - len(shared)
    for system in shared:
        twin = systems[system.shares]
        assert twin.shares is None
        assert [e.residual for e in system.equations] == [e.residual for e in twin.equations]
        assert system.key != twin.key


def test_states_with_different_equations_never_share(visited):
    compiled = [s for s in visited.systems.values() if s.shares is None]
    signatures = {tuple(e.residual for e in s.equations) for s in compiled}
    assert len(signatures) == len(compiled)


def test_code_does_not_depend_on_the_order_states_are_compiled(visited):
    """Each state compiled alone in a fresh translation gets the same code."""
    for key, system in list(visited.systems.items())[::-1]:
        alone = translate(CoupledClutches(), cache=False).system(key)
        source = visited.systems[system.shares].code.source if system.shares else system.code.source
        # the first line names the state the code was generated for
        assert alone.code.source.split("\n", 1)[1] == source.split("\n", 1)[1]
        # and it computes the same values
        x = np.linspace(0.1, 0.9, len(alone.states))
        assert np.allclose(alone.outputs(0.3, x), system.outputs(0.3, x), rtol=1e-14, atol=0)


def test_python_identifiers_are_readable_and_distinct():
    names = ["J1.w", "der(J1.w)", "J1_w", "t", "x", "if", "_private", "1st.value", "der(der(J1.phi))",
             "max", "abs"]
    identifiers = python_identifiers(names)
    assert identifiers["J1.w"] == "J1_w"
    assert identifiers["der(J1.w)"] == "der_J1_w"
    assert identifiers["der(der(J1.phi))"] == "der_der_J1_phi"
    values = list(identifiers.values())
    assert len(set(values)) == len(values)
    for ident in values:
        assert ident.isidentifier()
        assert ident not in {"t", "x", "p", "if", "max", "abs"} and not ident.startswith("_")


# -- regressions found in review ------------------------------------------------


def test_a_variable_named_like_a_temporary_is_not_taken_for_one():
    """Common subexpressions are named ``_y_0``...; a model variable may be too."""

    class Clash(Model):
        experiment = Experiment(start_time=0.0, stop_time=1.0, interval=0.5)
        x = Variable(start=0.3, fixed=True)
        _y_0 = Variable()
        y = Variable()

        def equations(self):
            s = self.x + 1
            return [Eq(der(self.x), 1.0), Eq(self._y_0, 100.0 + self.x),
                    Eq(self.y, sp.sin(s) * sp.cos(s) + s**3 + sp.exp(s))]

    result = simulate(Clash(), rtol=1e-10)
    s = result["x"] + 1
    expected = [math.sin(v) * math.cos(v) + v**3 + math.exp(v) for v in s]
    assert np.allclose(result["y"], expected, rtol=1e-12)
    assert np.allclose(result["_y_0"], 100.0 + result["x"], rtol=1e-12)


def test_a_shared_block_names_the_equations_of_its_own_state():
    """Two states can build the same block from different equations: errors name the right ones."""

    class Swap(Model):
        experiment = Experiment(start_time=0.0, stop_time=1.0, interval=0.1)
        x = Variable(start=0.0, fixed=True)
        u = Variable()
        w = Variable()
        q = Variable()
        b = Boolean()

        def equations(self):
            x, u, w, q = self.x, self.u, self.w, self.q
            r1 = u + 2 * w - x
            r2 = u * w + sp.sin(time) + 2
            s = q - x
            return [Eq(der(x), 1.0), Eq(0, If(self.b, r1, s)), Eq(0, If(self.b, r2, r1)),
                    Eq(0, If(self.b, s, r2)), Eq(self.b, time < 0.5)]

    translation = translate(Swap(), cache=False)
    simulate(translation)
    checked = 0
    for system in translation.systems.values():
        equations = system.structure.equations
        for block, step in zip(system.blt.blocks, system.algebraic.steps):
            if isinstance(step, (LinearSolve, NewtonSolve)):
                assert step.origins == tuple(str(equations[i].origin) for i in block.equations)
                checked += 1
    assert checked == 2  # one torn block in each of the two states


def test_a_relation_that_always_holds_is_no_event():
    class Always(Model):
        experiment = Experiment(start_time=0.0, stop_time=1.0, interval=0.5)
        x = Variable(start=1.0, fixed=True)
        y = Variable()

        def equations(self):
            return [Eq(der(self.x), -self.x), Eq(self.y, If(der(self.x) ** 2 + 1 > 0, 1.0, 2.0))]

    translation = translate(Always(), cache=False)
    assert translation.partitioned.relations == ()
    assert not translation.partitioned.is_hybrid
    assert list(simulate(translation)["y"]) == [1.0, 1.0, 1.0]


def test_two_tables_of_one_generated_name_stay_apart():
    """Table classes are named after their component path; a.b_c and a_b.c give one name."""
    first = table_function("a.b_c", [[0.0, 0.0], [1.0, 1.0]])
    second = table_function("a_b.c", [[0.0, 0.0], [1.0, 5.0]])
    assert first.__name__ == second.__name__
    x = sp.Symbol("x", real=True)
    f, g = compile_functions([["x"], ["x"]], [first(x), second(x)])
    assert (f(0.5), g(0.5)) == (0.5, 2.5)


def test_a_long_discrete_state_names_its_code_briefly():
    """The generated code of a state of many values is named by its first values and how
    many more there are (not 4000 values in every traceback); the system keeps them all."""
    from acausal import simulate
    from acausal.compiler.modes import BRIEF_DESCRIPTION, describe_key
    from examples.benchmarks import drive_train_model

    translation = translate(drive_train_model(30), cache=False)
    simulate(translation, stop_time=0.01)
    for system in [*translation.systems.values(), *translation.initial_systems.values()]:
        first_line = system.code.source.split("\n", 1)[0]
        assert len(first_line) < BRIEF_DESCRIPTION + 120
        assert "more)]" in first_line
    mode = next(iter(translation.systems.values()))
    assert mode.description == describe_key(translation.selectors, mode.key,
                                            {r.symbol.name: r.text for r in translation.partitioned.relations})
    assert mode.description.count("=") == len(translation.selectors)
    hidden = int(mode.code.source.split("\n", 1)[0].rsplit("(", 1)[1].split()[0])
    assert hidden + mode.code.source.split("\n", 1)[0].count("=") == len(translation.selectors)
