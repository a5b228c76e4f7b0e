"""The numpy crossings of the watched relations only, and the recorder's rows as blocks.

Between events a step's samples are checked for flips with a numpy crossing
function that gives the watched relations' sides only
(:meth:`~acausal.compiler.generated.CompiledFunctions.vectorised_crossings_for`),
made from the whole function's generated text without the statements the
watched sides do not need.  Its rows must equal the whole numpy function's
rows bit for bit, and the flip it finds must be the one the scalar
definition finds on the watched relations.
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
from acausal.compiler.generated import vectorised
from acausal.errors import SolverError
from acausal.runtime.recorder import Recorder
from generated_fixtures import (CROSSINGS, KNIFE, VALUE, Compiled, S, bit_identical, clutches_evaluator,
                                compiled_system, k, solve_steps, time, x1, x2)
from examples.benchmarks import StickSlip
from examples.coupled_clutches import CoupledClutches
from examples.friction import Friction

same = bit_identical


def rows_of(relations) -> list[int]:
    return [2 * j + side for j in relations for side in (0, 1)]


# -- the function: the whole function's rows, computed without the rest ---------------------------


@pytest.mark.parametrize("model", [StickSlip, Friction, CoupledClutches])
def test_watched_rows_equal_the_whole_numpy_functions_rows_on_a_run(model):
    translation = translate(model())
    result = simulate(translation)
    rng = np.random.default_rng(11)
    n = len(translation.data.relations)
    subsets = [(j,) for j in range(n)] + [tuple(sorted(rng.choice(n, size=rng.integers(1, n + 1),
                                                                  replace=False).tolist()))
                                          for _ in range(6)] + [tuple(range(n))]
    for system in translation.systems.values():
        X = np.array([result[s] for s in system.states])
        X = np.concatenate([X, X * rng.choice([0.0, -1.0, 1.0 + 1e-9], size=X.shape)], axis=1)
        t = np.concatenate([result.time, result.time])
        full = system.vectorised("crossings")
        with np.errstate(all="ignore"):
            whole = full(t, X)
            for relations in subsets:
                watched = system.vectorised_crossings_for(relations)
                assert watched is system.vectorised_crossings_for(relations)  # made once
                assert same(watched(t, X), whole[rows_of(relations)]), (system.description, relations)


@settings(max_examples=60, derandomize=True, deadline=None)
@given(xs=st.lists(st.tuples(VALUE, VALUE, st.floats(0, 3)), min_size=1, max_size=8),
       relations=st.lists(st.integers(0, len(CROSSINGS) // 2 - 1), min_size=1, max_size=5, unique=True))
def test_watched_rows_equal_the_whole_functions_rows_and_the_scalar_values(xs, relations):
    system = compiled_system(solve_steps(), CROSSINGS, ("a", "c", "d", "b"))
    relations = tuple(relations)
    t = np.array([p[2] for p in xs])
    X = np.array([[p[0] for p in xs], [p[1] for p in xs]])
    rows = rows_of(relations)

    def run(f):
        try:
            with np.errstate(all="ignore"):
                return f(t, X)
        except SolverError as exc:  # a guard: a singular solve at some column
            return exc

    whole = run(system.vectorised("crossings"))
    watched = run(system.vectorised_crossings_for(relations))
    if not isinstance(whole, Exception):
        # the same statements: the same values, and no guard the whole function passes raises
        assert not isinstance(watched, Exception) and same(watched, whole[rows])
    singular = []
    for j in range(len(t)):
        try:
            expected = np.array(system.crossings(t[j], X[:, j]), dtype=float)[rows]
        except (SolverError, ArithmeticError, ValueError):
            singular.append(j)
            continue
        if not isinstance(watched, Exception):
            assert same(watched[:, j], expected), j
    if isinstance(watched, Exception):
        assert singular  # a kept guard raises only where the scalar function does


def test_a_guard_goes_with_a_solve_no_watched_relation_needs():
    system = compiled_system(solve_steps(), CROSSINGS, ("a", "c", "d", "b"))
    t = np.zeros(2)
    X = np.array([[0.0, 2.0], [3.0, 4.0]])  # x1 = 0: the solve for c is singular in column 0
    with pytest.raises(SolverError):
        system.vectorised("crossings")(t, X)
    # relation 2 reads d alone (the second solve, whose temporary _a is assigned again)
    got = system.vectorised_crossings_for((2,))(t, X)
    assert same(got, [[(0.0 + 1.5) / (3.0 - 1), (2.0 + 1.5) / (4.0 - 1)], [1.5, 1.5]])
    # relation 1 reads c: its guard is kept, and raises as the scalar function does
    with pytest.raises(SolverError):
        system.vectorised_crossings_for((1,))(t, X)
    with pytest.raises(SolverError):
        system.crossings(0.0, X[:, 0])


def test_what_the_watched_rows_do_not_need_is_not_computed():
    system = compiled_system(solve_steps(), CROSSINGS, ("a", "c", "d", "b"))
    source = system.code.source
    only_k = vectorised(system.crossings, source, (5, 4))  # k, d: rows in the order asked
    assert only_k.__code__.co_names.count("_v_map") == 0  # no math.sin, no exp, no power
    got = only_k(np.zeros(1), np.array([[1.0], [3.0]]))
    assert same(got, [[1.5], [(1.0 + 1.5) / 2.0]])
    with_sine = vectorised(system.crossings, source, (0,))
    assert "_v_map" in with_sine.__code__.co_names


def test_no_numpy_version_for_any_rows_without_one_for_the_whole():
    z = [S(n) for n in ("z0", "z1", "z2")]
    zero, one, two = sp.Integer(0), sp.Integer(1), sp.Integer(2)
    steps = [LinearSolve(("z0", "z1", "z2"), ((two, one, zero), (one, two, one), (zero, one, two + x1 ** 2)),
                         (x1, x2, k), (), ("e0", "e1", "e2"))]
    system = compiled_system(steps, (z[0], x1, x2, k), ("z0", "z1", "z2"))
    assert system.vectorised("crossings") is None
    assert system.vectorised_crossings_for((1,)) is None  # relation 1 needs no solve, but still


# -- the samples of a step decided with it ----------------------------------------------------------

_EVALUATOR = clutches_evaluator()
_RELATIONS = _EVALUATOR.relations


def _definition_flips(raw, relations, watched):
    """flipped_relations as defined by Relation.holds_with_hysteresis."""
    out = []
    for j in watched:
        lhs, rhs = raw[2 * j], raw[2 * j + 1]
        eps = _RELATIONS[j].margin(lhs, rhs, _EVALUATOR.epsilon)
        if _RELATIONS[j].holds_with_hysteresis(lhs - rhs, relations[j], eps) != relations[j]:
            out.append(j)
    return tuple(out)


class _WatchedOnly(Compiled):
    """A stand-in whose scalar ``crossings_for`` computes the relations asked for only (NaN
    elsewhere, as a system of parts gives them): the scalar path's definition of the watch."""

    def crossings_for(self, relations):
        made = self.made  # (each relation's own generated function, made once)
        for j in relations:
            if j not in made:
                made[j] = compiled_system([], tuple(self.sides[2 * j:2 * j + 2]), ()).crossings
        own = {j: made[j] for j in relations}

        def crossings(t, x):
            out = [math.nan] * len(self.sides)
            for j, f in own.items():
                out[2 * j:2 * j + 2] = f(t, x)
            return out

        return crossings


@settings(max_examples=40, derandomize=True, deadline=None)
@given(data=st.data())
def test_first_flip_with_the_watched_crossings_equals_the_definition_on_the_watched(data):
    """Sides with poles and roots of negative numbers among the unwatched relations do not
    matter; among the watched ones, the scalar path decides from there on, as before."""
    n = len(_RELATIONS)
    pool = [x1 - time, 1 / x1, x2 ** 2 - k, sp.sqrt(x2), x1 * x2, -x2, sp.Float(0.5), time - 1, x1 / x2]
    sides = [pool[data.draw(st.integers(0, len(pool) - 1))] for _ in range(2 * n)]
    whole = compiled_system([], tuple(sides), ())
    system = _WatchedOnly(crossings=whole.crossings, outputs=whole.outputs, code=whole.code,
                          states=whole.states, sides=sides, made={})
    m = data.draw(st.integers(1, 30))
    states = np.array(data.draw(st.lists(st.tuples(KNIFE, KNIFE), min_size=m, max_size=m)),
                      dtype=float).reshape(m, 2)
    times = np.linspace(0.0, 2.0, m)
    relations = tuple(data.draw(st.lists(st.booleans(), min_size=n, max_size=n)))
    watched = tuple(sorted(data.draw(st.sets(st.integers(0, n - 1), min_size=1, max_size=6))))
    scalar = system.crossings_for(watched)
    expected = None
    with np.errstate(all="ignore"):
        try:
            for j in range(m):
                hit = _definition_flips(scalar(times[j], states[j]), relations, watched)
                if hit:
                    expected = (j, hit)
                    break
        except (ArithmeticError, ValueError) as exc:
            expected = exc
        try:
            got = _EVALUATOR.relation_evaluator.first_flip(system, times, states, relations, watched)
        except (ArithmeticError, ValueError) as exc:
            got = exc
    assert _EVALUATOR.relation_evaluator._watched_many(system, watched)[1]  # the watched rows only
    if isinstance(expected, Exception):
        assert type(got) is type(expected)
    else:
        assert got == expected


# -- the recorder: blocks only, rows on demand ------------------------------------------------------


def test_rows_set_and_read_back_and_the_last_row():
    recorder = Recorder(0.0, 1.0, 0.5)
    assert recorder.row_count == 0 and recorder.last_time is None and recorder.rows == []
    discrete = {"m": 1}
    recorder.add(0.0, "s", [1.0, 2.0], discrete)
    recorder.emit_rows(np.array([0.0, 0.5, 1.0]), np.arange(6.0).reshape(3, 2), "s", discrete)
    rows = recorder.rows
    assert [r[0] for r in rows] == [0.0, 0.5, 1.0] and recorder.row_count == 3 and recorder.last_time == 1.0
    assert same(rows[0][2], [1.0, 2.0]) and same(rows[2][2], [4.0, 5.0])
    assert rows[1][3] is rows[0][3] == discrete and rows[0][3] is not discrete  # one snapshot
    other = Recorder(0.0, 1.0, 0.5)
    other.rows = rows
    assert other.row_count == 3 and other.last_time == 1.0
    assert all(p[0] == q[0] and same(p[2], q[2]) and p[3] is q[3] for p, q in zip(other.rows, rows))
