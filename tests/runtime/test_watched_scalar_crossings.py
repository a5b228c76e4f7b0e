"""The scalar crossings of the watched relations only.

Between events the crossing watch evaluates the relations at single instants:
a step's few samples, the step's end, each trial point of the search of a flip
instant.  A system of generated code offers a scalar function that computes
the watched relations' sides only
(:meth:`~acausal.compiler.generated.CompiledFunctions.crossings_of`), made
from the whole function's generated text without the statements those sides
do not need.  Its values must equal the whole function's bit for bit, and the
watch must decide with it what it decides with the whole function; a side
only unwatched relations read does not matter between events, even where it
cannot be computed.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from acausal import simulate, translate
from acausal.compiler.algebraic import LinearSolve
from acausal.compiler.generated import rows_function
from acausal.compiler.parts import PartSystem
from acausal.errors import SolverError
from acausal.runtime.relations import shifted
from examples.benchmarks import StickSlip, storm_model
from examples.coupled_clutches import CoupledClutches
from examples.friction import Friction
from generated_fixtures import (CROSSINGS, KNIFE, VALUE, S, bit_identical, clutches_evaluator, compiled_system, k,
                                solve_steps, time, x1, x2)

FAILURES = (SolverError, ArithmeticError, ValueError)


def same(p, q, types: bool = True) -> bool:
    """The same values bit for bit, and with ``types`` of the same Python types (a side
    that is the integer 0 stays one)."""
    if types and [type(v) for v in p] != [type(v) for v in q]:
        return False
    return bit_identical(p, q)


def sides_of(values, relations) -> list:
    """The sides of ``relations`` in the whole function's ``values``, in the watched layout."""
    return [values[2 * j + side] for j in relations for side in (0, 1)]


def outcome(f, *args):
    """``f(*args)``, or the exception it raises where a value cannot be computed."""
    try:
        return f(*args)
    except FAILURES as exc:
        return exc


def _subsets(n: int, rng) -> list[tuple[int, ...]]:
    """Each relation alone, some random sets (in random order), and all of them."""
    return ([(j,) for j in range(n)]
            + [tuple(rng.choice(n, size=rng.integers(1, n + 1), replace=False).tolist()) for _ in range(6)]
            + [tuple(range(n))])


# -- the function: the whole function's values, computed without the rest ----------------------------


@pytest.mark.parametrize("model", [StickSlip, Friction, CoupledClutches])
def test_watched_values_equal_the_whole_functions_on_a_run(model):
    translation = translate(model())
    result = simulate(translation)
    rng = np.random.default_rng(5)
    n = len(translation.data.relations)
    subsets = _subsets(n, rng)
    rows = range(0, len(result.time), 7)
    checked = 0
    for system in translation.systems.values():
        X = np.array([result[s] for s in system.states]).T
        for i in rows:
            t = float(result.time[i])
            for x in (X[i], X[i] * rng.choice([0.0, -1.0, 1.0 + 1e-9], size=X[i].shape)):
                whole = outcome(system.crossings, t, x)
                for relations in subsets:
                    watched = system.crossings_of(relations)
                    assert watched is system.crossings_of(relations)  # made once
                    got = outcome(watched, t, x)
                    if isinstance(whole, Exception):
                        continue  # the watched sides may or may not need what failed
                    assert not isinstance(got, Exception), (system.description, relations, got)
                    assert same(got, sides_of(whole, relations)), (system.description, relations, t)
                    checked += 1
    assert checked > 100


_CROSSINGS = (*CROSSINGS, sp.log(x1), 1 / x2)


@settings(max_examples=80, derandomize=True, deadline=None)
@given(x=st.tuples(VALUE, VALUE), t=st.floats(0, 3),
       relations=st.lists(st.integers(0, len(_CROSSINGS) // 2 - 1), min_size=1, max_size=6, unique=True))
def test_watched_values_equal_the_whole_functions_values(x, t, relations):
    system = compiled_system(solve_steps(), _CROSSINGS, ("a", "c", "d", "b"))
    relations = tuple(relations)
    x = np.array(x)
    whole = outcome(system.crossings, t, x)
    got = outcome(system.crossings_of(relations), t, x)
    if not isinstance(whole, Exception):
        # the same statements: the same values, and nothing raises that the whole function passes
        assert not isinstance(got, Exception) and same(got, sides_of(whole, relations))
    if isinstance(got, Exception):
        # a guard or a function kept for a watched side fails only where the whole function
        # does (not necessarily with the same error: at x1 = 0 the whole function stops at
        # the singular solve for c, which a watched log(x1) does not need, and the watched
        # function at the log)
        assert isinstance(whole, Exception)
        if len(relations) == len(_CROSSINGS) // 2:
            assert type(got) is type(whole)  # every statement kept: the same first failure


def test_what_only_unwatched_sides_need_is_neither_computed_nor_raising():
    system = compiled_system(solve_steps(), _CROSSINGS, ("a", "c", "d", "b"))
    # x1 = 0: the solve for c is singular and log(x1) fails, in the whole function
    x = np.array([0.0, 3.0])
    with pytest.raises(SolverError):
        system.crossings(0.0, x)
    # relation 2 reads d and k alone (the second solve, whose temporary _a is assigned again)
    only_d = system.crossings_of((2,))
    assert same(only_d(0.0, x), [(0.0 + 1.5) / (3.0 - 1), 1.5], types=False)
    names = only_d.__code__.co_names + only_d.__code__.co_freevars
    assert not {"sin", "_exp", "log", "_pow"} & set(names)  # no sine, exponential, logarithm, power
    # relation 1 reads c: its guard is kept, and raises as the whole function does
    with pytest.raises(SolverError):
        system.crossings_of((1,))(0.0, x)
    # a logarithm only relation 5 reads: it fails at x1 < 0, in the whole function too
    x = np.array([-1.0, 3.0])
    with pytest.raises(ValueError):
        system.crossings(0.0, x)
    with pytest.raises(ValueError):
        system.crossings_of((5,))(0.0, x)
    without_log = compiled_system(solve_steps(), _CROSSINGS[:10], ("a", "c", "d", "b"))
    assert same(system.crossings_of((4, 2))(0.0, x), sides_of(without_log.crossings(0.0, x), (4, 2)))


def test_the_values_are_bound_to_the_systems_own_parameters():
    system = compiled_system(solve_steps(), _CROSSINGS, ("a", "c", "d", "b"))
    other = system.code.make([-2.0])[1]  # the same code, another parameter vector
    source = system.code.source
    x = np.array([0.7, 2.5])
    for f, k_value in ((system.crossings, 1.5), (other, -2.0)):
        watched = rows_function(f, source, (5, 4))
        assert watched is not None
        assert same(watched(0.3, x), [f(0.3, x)[5], f(0.3, x)[4]])
        assert watched(0.3, x)[1] == (0.7 + k_value) / (2.5 - 1)


def test_no_watched_function_where_the_whole_is_not_straight_line_code():
    z = [S(n) for n in ("z0", "z1", "z2")]
    zero, one, two = sp.Integer(0), sp.Integer(1), sp.Integer(2)
    steps = [LinearSolve(("z0", "z1", "z2"), ((two, one, zero), (one, two, one), (zero, one, two + x1 ** 2)),
                         (x1, x2, k), (), ("e0", "e1", "e2"))]
    system = compiled_system(steps, (z[0], x1, x2, k), ("z0", "z1", "z2"))
    assert system.crossings_of((1,)) is None  # relation 1 needs no solve, but still
    evaluator = clutches_evaluator().relation_evaluator
    crossings, only_watched = evaluator._watched_scalar(system, (1,))
    assert not only_watched and crossings is system.crossings


# -- the watch decides with it what it decides with the whole function ------------------------------

_EVALUATOR = clutches_evaluator()
_RELATIONS = _EVALUATOR.relations


def _definition_flips(values, relations, watched):
    """flipped_relations as defined by Relation.holds_with_hysteresis, on each watched
    relation's own sides (``values(j)``)."""
    out = []
    for j in watched:
        lhs, rhs = values(j)
        eps = _RELATIONS[j].margin(lhs, rhs, _EVALUATOR.epsilon)
        if _RELATIONS[j].holds_with_hysteresis(lhs - rhs, relations[j], eps) != relations[j]:
            out.append(j)
    return tuple(out)


_POOL = [x1 - time, 1 / x1, x2 ** 2 - k, sp.sqrt(x2), x1 * x2, -x2, sp.Float(0.5), time - 1, x1 / x2,
         sp.log(x1)]


@settings(max_examples=40, derandomize=True, deadline=None)
@given(data=st.data())
def test_the_watch_decides_on_the_watched_sides_alone(data):
    """Sides with poles, logarithms and roots of negative numbers among the unwatched
    relations do not matter between events; the watched ones decide as defined."""
    n = len(_RELATIONS)
    sides = [_POOL[data.draw(st.integers(0, len(_POOL) - 1))] for _ in range(2 * n)]
    system = compiled_system([], tuple(sides), ())
    own = {}  # each relation's sides from a generated function of their own

    def values_at(t, x):
        def values(j):
            if j not in own:
                own[j] = compiled_system([], tuple(sides[2 * j:2 * j + 2]), ()).crossings
            return own[j](t, x)
        return values

    m = data.draw(st.integers(1, 6))
    states = np.array(data.draw(st.lists(st.tuples(KNIFE, KNIFE), min_size=m, max_size=m)),
                      dtype=float).reshape(m, 2)
    times = np.linspace(0.0, 2.0, m)
    relations = tuple(data.draw(st.lists(st.booleans(), min_size=n, max_size=n)))
    watched = tuple(sorted(data.draw(st.sets(st.integers(0, n - 1), min_size=1, max_size=5))))
    evaluator = _EVALUATOR.relation_evaluator
    with np.errstate(all="ignore"):
        expected, first = [], None
        for j in range(m):
            expected.append(outcome(_definition_flips, values_at(times[j], states[j]), relations, watched))
            if first is None and (isinstance(expected[-1], Exception) or expected[-1]):
                first = j
        for j in range(m):  # one instant: the step's end, a sample
            got = outcome(evaluator.flipped_relations, system, times[j], states[j], relations, watched)
            assert got == expected[j] if not isinstance(got, Exception) else type(got) is type(expected[j])
        # the samples of a step (few: decided one by one)
        got = outcome(evaluator.first_flip, system, times, states, relations, watched)
        if first is None:
            assert got is None
        elif isinstance(expected[first], Exception):
            assert type(got) is type(expected[first])
        else:
            assert got == (first, expected[first])
        # the search of the flip instant among some of them
        candidates = tuple(data.draw(st.permutations(watched)))[:data.draw(st.integers(1, len(watched)))]
        flipped, distance = evaluator.flip_search(system, relations, candidates)
        alone = evaluator.distance_to_first_flip(system, relations, candidates)
        for j in range(m):
            values = values_at(times[j], states[j])
            want = outcome(_definition_flips, values, relations, candidates)
            if isinstance(want, Exception):
                assert type(outcome(flipped, times[j], states[j])) is type(want)
                continue
            assert flipped(times[j], states[j]) == want
            best = -math.inf
            for k_ in candidates:
                dk, _strict, timed = evaluator.kinds[k_]
                previous = bool(relations[k_])
                value = (-1.0 if previous else 1.0) * shifted(dk, previous, *values(k_), evaluator.margins[k_],
                                                              evaluator.floors[k_], timed)
                best = max(best, value)
            for g in (distance(times[j], states[j]), alone(times[j], states[j])):
                assert g == best or (math.isnan(g) and math.isnan(best))
    assert evaluator._watched_scalar(system, watched)[1]  # the watched sides only


# -- a part's system ----------------------------------------------------------------------------------


def test_a_parts_system_offers_the_watched_crossings_of_the_relations_at_their_places():
    translation = translate(storm_model(3), cache=False)
    simulate(translation)
    models, _why = translation.part_models()
    found = 0
    for model in models:
        for system in model.systems.values():
            if not isinstance(system, PartSystem):
                continue
            n = len(model.relations)
            places = system._same_places
            x = np.array([0.3 + 0.1 * i for i in range(len(system.states))])
            for t in (0.0, 0.37, 1.9):
                whole = system.crossings(t, x)
                for relations in [(j,) for j in range(places)] + [tuple(range(places))[::-1]]:
                    if not relations:
                        continue
                    watched = system.crossings_of(relations)
                    assert watched is not None
                    assert same(watched(t, x), sides_of(whole, relations))
                    found += 1
            # a relation the mode does not compute at its place (one of time alone another
            # part computes, or after it): the whole function is used
            assert places == n or system.crossings_of((places,)) is None
    assert found
