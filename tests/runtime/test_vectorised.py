"""The vectorised paths of event detection and output, checked against their scalar definitions.

A step's dense output is evaluated once for all its samples and output points
(:func:`~acausal.runtime.crossings.states_at`), the crossing functions and the
outputs for many instants in one numpy call
(:func:`~acausal.compiler.codegen.vectorised`), and the watched relations are
decided for all samples at once
(:meth:`~acausal.runtime.relation_evaluator.RelationEvaluator.first_flip`).  Each must give
exactly -- bit for bit, knife edges included -- what the scalar definition
gives one instant at a time, and a simulation must not change by a bit when
they are switched off.
"""

from __future__ import annotations

import math
import types

import numpy as np
import pytest
import scipy.integrate as integrate
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from acausal import simulate, translate
from acausal.compiler.algebraic import Assign, LinearSolve
from acausal.compiler.clusters import ComposedSystem
from acausal.compiler.codegen import generate
from acausal.compiler.generated import vectorised, vectorised_of
from acausal.compiler.modes import ModeSystem
from acausal.compiler.timing import time_event_roots
from acausal.language import real_symbol, time
from acausal.runtime import crossings as crossings_module
from acausal.runtime.crossings import (locate_flip, sample_states, sample_times, state_at,
                                       states_at, step_samples)
from acausal.runtime.events import evaluator_for
from acausal.runtime.recorder import Recorder
from examples.benchmarks import StickSlip
from examples.coupled_clutches import CoupledClutches
from examples.friction import Friction

S = real_symbol
SCIPY_METHODS = (integrate.RK23, integrate.RK45, integrate.DOP853, integrate.Radau, integrate.BDF,
                 integrate.LSODA)


def same(a, b) -> bool:
    """Bit for bit (NaN equal to NaN, -0.0 not equal to 0.0)."""
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    return a.shape == b.shape and np.array_equal(a.view(np.int64), b.view(np.int64))


# -- the dense output ----------------------------------------------------------------------------


@settings(max_examples=30, derandomize=True, deadline=None)
@given(method=st.sampled_from(SCIPY_METHODS), n=st.integers(1, 12), seed=st.integers(0, 2**16),
       m=st.integers(1, 70))
def test_states_at_is_the_dense_output_at_each_instant(method, n, seed, m):
    rng = np.random.default_rng(seed)
    A = rng.normal(size=(n, n))
    solver = method(lambda t, y: 0.4 * (A @ y) + np.sin(3 * t), 0.0, rng.normal(size=n), 2.0)
    for _ in range(4):
        solver.step()
        dense = solver.dense_output()
        times = np.sort(rng.uniform(solver.t_old, solver.t, m))
        times[0] = solver.t_old  # the step's ends (and beyond) as well
        if m > 2:
            times[-1] = solver.t
        expected = np.array([dense(t) for t in times])
        assert same(states_at(dense, times), expected)
        for t in times[:3]:
            assert same(state_at(dense, t), dense(t))
        if solver.status != "running":
            break


def test_states_at_calls_an_unknown_dense_output_per_instant():
    calls = []

    class Line(integrate.DenseOutput):
        def _call_impl(self, t):
            calls.append(np.ndim(t))
            return np.array([2.0 * t, -t])

    dense = Line(0.0, 1.0)
    got = states_at(dense, np.array([0.25, 0.5]))
    assert same(got, [[0.5, -0.25], [1.0, -0.5]]) and calls == [0, 0]
    assert states_at(dense, np.array([])).shape == (0, 2)


# -- numpy versions of generated functions ----------------------------------------------------------


def _system(steps, crossings, unknowns, states=("x1", "x2"), parameters=("k",), name="v"):
    """A compiled stand-in for a ModeSystem: its crossings and outputs, and the code's text."""
    code = generate(steps, states, (), unknowns, parameters, crossings=crossings, name=name)
    _derivatives, crossing_fn, outputs = code.make([1.5])
    return _Compiled(crossings=crossing_fn, outputs=outputs, code=code, states=states)


class _Compiled(types.SimpleNamespace):
    """The stand-in's numpy forms, as a ModeSystem gives them (from its generated text)."""

    parts = None

    def crossings_for(self, relations):
        return self.crossings

    def vectorised(self, name):
        return vectorised_of(self, name)


x1, x2, k, a, b = (S(n) for n in ("x1", "x2", "k", "a", "b"))
KNIFE = st.sampled_from([0.0, -0.0, 1.0, -1.0, 2.0, 0.5, 1e-300, -1e-300, 3.0, math.pi])
VALUE = KNIFE | st.floats(-5, 5, allow_nan=False, allow_infinity=False)


@settings(max_examples=60, derandomize=True, deadline=None)
@given(xs=st.lists(st.tuples(VALUE, VALUE, st.floats(0, 3)), min_size=1, max_size=12))
def test_numpy_versions_of_generated_functions_equal_them_bit_for_bit(xs):
    # every construct the printer emits: powers, math functions, Abs, sign (copysign), Min/Max
    # (ties, signed zeros), Piecewise (both branches evaluated), and/or/not, a 1x1 linear solve
    steps = [
        Assign("a", sp.Piecewise((x1 ** 2 + sp.sin(time), sp.And(x1 > 0, x2 <= 1)), (sp.exp(-x2), True)),
               None),
        Assign("b", sp.Max(x1, x2, 0) - sp.Min(x1, -x2) + sp.Abs(x1) * sp.sign(x2) + sp.sqrt(k + x2 ** 2),
               None),
        LinearSolve(("c",), ((k + x1 ** 2,),), (a - b,), (), ("e",)),
    ]
    c = S("c")
    crossings = (a, b, c * time, x1 ** 3 - x2 / 3, sp.Float(2.5), k, time,
                 sp.Piecewise((x2, sp.Or(x1 < -1, sp.Not(x2 > 0))), (-x2, True)))
    system = _system(steps, crossings, ("a", "b", "c"))
    t = np.array([p[2] for p in xs])
    X = np.array([[p[0] for p in xs], [p[1] for p in xs]])
    for name in ("crossings", "outputs"):
        scalar = getattr(system, name)
        many = vectorised(scalar, system.code.source)
        assert many is not None, name
        with np.errstate(all="ignore"):
            got = many(t, X)
        for j in range(len(t)):
            assert same(got[:, j], np.array(scalar(t[j], X[:, j]), dtype=float)), (name, j)


def test_python_min_max_and_signed_zeros_are_kept():
    steps = [Assign("a", sp.Max(x1, x2), None), Assign("b", sp.Min(x1, x2), None)]
    system = _system(steps, (a, b), ("a", "b"))
    many = vectorised(system.crossings, system.code.source)
    t = np.zeros(4)
    X = np.array([[0.0, -0.0, 1.0, -0.0], [-0.0, 0.0, 1.0, -0.0]])
    got = many(t, X)
    for j in range(4):
        assert same(got[:, j], system.crossings(t[j], X[:, j]))


def test_an_untranslated_construct_gives_no_numpy_version():
    # a linear system of three unknowns solves with np.linalg: left to the scalar code
    z = [S(n) for n in ("z0", "z1", "z2")]
    zero, one, two = sp.Integer(0), sp.Integer(1), sp.Integer(2)
    steps = [LinearSolve(("z0", "z1", "z2"), ((two, one, zero), (one, two, one), (zero, one, two + x1 ** 2)),
                         (x1, x2, k), (), ("e0", "e1", "e2"))]
    system = _system(steps, (z[0],), ("z0", "z1", "z2"))
    assert vectorised(system.crossings, system.code.source) is None
    assert vectorised_of(system, "crossings") is None  # and the runtime asks once
    assert vectorised_of(types.SimpleNamespace(crossings=len), "crossings") is None


def test_a_singular_column_raises_in_the_numpy_version_and_the_scalar_code_decides():
    steps = [LinearSolve(("c",), ((x1,),), (x2,), (), ("e",))]
    system = _system(steps, (S("c"),), ("c",))
    many = vectorised(system.crossings, system.code.source)
    with pytest.raises(Exception):
        many(np.zeros(2), np.array([[1.0, 0.0], [2.0, 3.0]]))
    assert same(many(np.zeros(2), np.array([[1.0, 4.0], [2.0, 3.0]])), [[2.0, 0.75]])


EXAMPLES = {"StickSlip": StickSlip, "Friction": Friction, "CoupledClutches": CoupledClutches}


@pytest.mark.parametrize("name", sorted(EXAMPLES))
def test_numpy_versions_of_every_compiled_system_on_its_run(name):
    translation = translate(EXAMPLES[name]())
    result = simulate(translation)
    rng = np.random.default_rng(7)
    for system in translation.systems.values():
        # the run's states, some perturbed, some exactly zero (the sign() branches)
        X = np.array([result[s] for s in system.states])
        X = np.concatenate([X, X * rng.choice([0.0, -1.0, 1.0 + 1e-9], size=X.shape)], axis=1)
        t = np.concatenate([result.time, result.time])
        for fname in ("crossings", "outputs"):
            many = system.vectorised(fname)
            assert many is not None, (system.description, fname)
            with np.errstate(all="ignore"):
                got = many(t, X)
            scalar = getattr(system, fname)
            for j in range(0, len(t), 7):
                assert same(got[:, j], np.array(scalar(t[j], X[:, j]), dtype=float))


# -- deciding the relations ---------------------------------------------------------------------

_EVALUATOR = evaluator_for(translate(CoupledClutches()))
_RELATIONS = _EVALUATOR.relations
_SIDE = st.sampled_from([0.0, -0.0, 1.0, -1.0, 1e-10, -1e-10, 2e-10, 1.5, 1e12, -3.0, math.inf, math.nan]) | \
    st.floats(-10, 10)
_OFFSET = st.sampled_from([0.0, 1e-10, -1e-10, 5e-11, -5e-11, 1.0, -1.0, 1e-16])


def _definition_flips(raw, relations, watched):
    """flipped_relations as defined by Relation.holds_with_hysteresis."""
    out = []
    for k in watched:
        lhs, rhs = raw[2 * k], raw[2 * k + 1]
        eps = _RELATIONS[k].margin(lhs, rhs, _EVALUATOR.epsilon)
        if _RELATIONS[k].holds_with_hysteresis(lhs - rhs, relations[k], eps) != relations[k]:
            out.append(k)
    return tuple(out)


class _Fixed:
    """Stands in for a compiled system: fixed relation sides, one column per instant."""

    def __init__(self, columns):
        self.columns = np.asarray(columns, dtype=float)

    def crossings(self, t, x):
        return tuple(self.columns[:, int(t)].tolist())

    def crossings_for(self, relations):
        return self.crossings

    parts = None

    def vectorised(self, name):
        return None  # the relations are decided from the scalar function's values, collected


def _columns(data, n, m):
    cols = []
    for _ in range(m):
        lhs = data.draw(st.lists(_SIDE, min_size=n, max_size=n))
        offsets = data.draw(st.lists(_OFFSET, min_size=n, max_size=n))
        col = []
        for s, d in zip(lhs, offsets):
            col += [s, s + d]
        cols.append(col)
    return np.array(cols).T


@settings(max_examples=60, derandomize=True, deadline=None)
@given(data=st.data())
def test_relations_decided_at_once_equal_the_definition(data):
    n = len(_RELATIONS)
    m = data.draw(st.integers(1, 6))
    raw = _columns(data, n, m)
    relations = tuple(data.draw(st.lists(st.booleans(), min_size=n, max_size=n)))
    watched = tuple(sorted(data.draw(st.sets(st.integers(0, n - 1), min_size=1))))
    system = _Fixed(raw)
    with np.errstate(all="ignore"):
        w, flips = _EVALUATOR.relation_evaluator._flips(raw, relations, watched)
    for j in range(m):
        expected = _definition_flips(raw[:, j].tolist(), relations, watched)
        assert _EVALUATOR.flipped_relations(system, j, (), relations, watched) == expected
        assert tuple(w[flips[:, j]].tolist()) == expected
    # the first instant with a flip, as the scalar loop finds it
    expected_first = next(((j, hit) for j in range(m)
                           if (hit := _definition_flips(raw[:, j].tolist(), relations, watched))), None)
    assert _EVALUATOR.first_flip(system, np.arange(m), np.zeros((m, 0)), relations, watched) == expected_first


@settings(max_examples=60, derandomize=True, deadline=None)
@given(data=st.data())
def test_relation_values_equal_the_definition(data):
    n = len(_RELATIONS)
    raw = _columns(data, n, 1)[:, 0].tolist()
    previous = tuple(data.draw(st.lists(st.booleans(), min_size=n, max_size=n)))
    fired = frozenset(data.draw(st.sets(st.integers(0, n - 1))))
    exact = data.draw(st.booleans())
    expected = []
    for k, rel in enumerate(_RELATIONS):
        lhs, rhs = raw[2 * k], raw[2 * k + 1]
        # at events, an argument exactly at its limit takes the relation's own value (bug D)
        if exact or k in fired or lhs == rhs:
            expected.append(rel.holds(lhs - rhs))
        else:
            eps = rel.margin(lhs, rhs, _EVALUATOR.epsilon)
            expected.append(rel.holds_with_hysteresis(lhs - rhs, previous[k], eps))
    got = _EVALUATOR.relation_values(_Fixed(np.array(raw)[:, None]), 0, (), previous, exact=exact,
                                     fired=fired)
    assert got == tuple(expected)


def _scalar_first_flip(system, times, states, relations, watched):
    for j in range(len(times)):
        hit = _EVALUATOR.flipped_relations(system, times[j], states[j], relations, watched)
        if hit:
            return j, hit
    return None


@settings(max_examples=40, derandomize=True, deadline=None)
@given(data=st.data())
def test_first_flip_on_generated_crossings_with_poles_equals_the_scalar_loop(data):
    """Crossing values that are not finite (1/x at x = 0) or cannot be computed
    (sqrt of a negative number) are decided by the scalar function from there on:
    the same first flip, or the same error."""
    n = len(_RELATIONS)
    pool = [x1 - time, 1 / x1, x2 ** 2 - k, sp.sqrt(x2), x1 * x2, -x2, sp.Float(0.5), time - 1, x1 / x2]
    exprs = [pool[(3 * j) % len(pool)] for j in range(2 * n)]
    system = _system([], tuple(exprs), ())
    m = data.draw(st.integers(1, 30))
    cols = data.draw(st.lists(st.tuples(KNIFE, KNIFE), min_size=m, max_size=m))
    states = np.array(cols, dtype=float).reshape(m, 2)
    times = np.linspace(0.0, 2.0, m)
    relations = tuple(data.draw(st.lists(st.booleans(), min_size=n, max_size=n)))
    watched = tuple(sorted(data.draw(st.sets(st.integers(0, n - 1), min_size=1))))
    with np.errstate(all="ignore"):
        try:
            expected = _scalar_first_flip(system, times, states, relations, watched)
        except (ArithmeticError, ValueError) as exc:
            expected = exc
        try:
            got = _EVALUATOR.first_flip(system, times, states, relations, watched)
        except (ArithmeticError, ValueError) as exc:
            got = exc
    if isinstance(expected, Exception):
        assert type(got) is type(expected)
    else:
        assert got == expected


def test_first_flip_raises_where_the_scalar_loop_does_and_only_there():
    """A crossing function that raises at the 5th sample: after a flip at the 3rd, nothing
    is raised; without a flip before it, the error comes."""
    class Raising:
        def __init__(self, flip_at):
            self.flip_at = flip_at

        def crossings(self, t, x):
            if t >= 4:
                raise ZeroDivisionError("at the 5th sample")
            value = 1.0 if t >= self.flip_at else -1.0
            return tuple([value, 0.0] * len(_RELATIONS))

        def crossings_for(self, relations):
            return self.crossings

        parts = None

        def vectorised(self, name):
            return None

    relations = tuple(r.op in ("<", "<=") for r in _RELATIONS)  # each holds at -1 (g < 0)
    watched = tuple(k for k, r in enumerate(_RELATIONS) if not r.is_time_event)
    times, states = np.arange(8.0), np.zeros((8, 0))
    found = _EVALUATOR.first_flip(Raising(2), times, states, relations, watched)
    assert found == _scalar_first_flip(Raising(2), times, states, relations, watched) and found[0] == 2
    with pytest.raises(ZeroDivisionError):
        _EVALUATOR.first_flip(Raising(6), times, states, relations, watched)


def test_first_flip_with_the_numpy_crossings_equals_the_scalar_loop():
    """On a real system, at the samples of real steps: the same first flip, the same relations."""
    translation = translate(CoupledClutches())
    result = simulate(translation)
    evaluator = evaluator_for(translation)
    rng = np.random.default_rng(3)
    checked = 0
    for system in translation.systems.values():
        X = np.array([result[s] for s in system.states]).T
        for relations in {tuple(rng.random(len(_RELATIONS)) < 0.5) for _ in range(6)}:
            watched = tuple(range(len(_RELATIONS)))
            for start in range(0, len(X) - 20, 97):
                times, states = result.time[start:start + 20], X[start:start + 20]
                expected = next(((j, hit) for j in range(len(times))
                                 if (hit := evaluator.flipped_relations(system, times[j], states[j],
                                                                        relations, watched))), None)
                assert evaluator.first_flip(system, times, states, relations, watched) == expected
                checked += expected is not None
    assert checked > 10


# -- samples, bisection, rows -------------------------------------------------------------------


@settings(max_examples=60, derandomize=True, deadline=None)
@given(a=st.lists(st.sampled_from([0.0, -0.0, 0.1, 0.2, 0.30000000000000004, 1.0]) | st.floats(-2, 2),
                  min_size=1, max_size=8),
       b=st.lists(st.sampled_from([0.0, -0.0, 0.1, 0.3, 1.0]) | st.floats(-2, 2), max_size=8))
def test_union_is_numpys(a, b):
    a, b = np.sort(np.array(a)), np.sort(np.array(b, dtype=float))
    assert same(crossings_module._union(a, b), np.union1d(a, b))


@settings(max_examples=40, derandomize=True, deadline=None)
@given(t_old=st.floats(0, 0.9), h=st.sampled_from([1e-15, 1e-9, 3e-4, 0.0123, 0.2, 0.5]),
       interval=st.sampled_from([0.001, 0.01, 0.1]), rows=st.integers(0, 3))
def test_step_samples_are_the_samples_and_their_states(t_old, h, interval, rows):
    solver = integrate.RK45(lambda t, y: np.array([y[1], -y[0] + math.sin(t)]), t_old, np.array([1.0, 0.0]),
                            t_old + h)
    solver.step()
    dense, t_new, y_new = solver.dense_output(), solver.t, solver.y
    grid = np.arange(0.0, 1.0 + interval / 2, interval)
    first = int(np.searchsorted(grid, t_old, side="right")) - (1 if rows == 3 else 0)
    stop = int(np.searchsorted(grid, t_new, side="right" if rows else "left"))
    samples, at_samples, at_rows = step_samples(t_old, t_new, interval, grid, dense, y_new, first, stop)
    assert same(samples, sample_times(t_old, t_new, interval, grid))
    expected = np.array([dense(s) if s < t_new else y_new for s in samples])
    assert same(at_samples, expected) and same(sample_states(dense, samples, y_new), expected)
    assert same(at_rows, np.array([dense(g) for g in grid[first:stop]]).reshape(-1, 2))


def test_locate_flip_with_samples_decided_at_once_equals_the_loop():
    """A bouncing ball's floor contact: the same instant, state and relation either way."""
    solver = integrate.RK45(lambda t, y: np.array([y[1], -9.81]), 0.0, np.array([1.0, 0.0]), 2.0,
                            max_step=0.2)
    while solver.y[0] >= 0:
        solver.step()
    dense = solver.dense_output()
    samples = sample_times(solver.t_old, solver.t, 0.01, np.arange(0, 2.001, 0.01))

    def flipped(t, x):
        return (0,) if x[0] < 0 else ()

    def first(times, states):
        hits = np.flatnonzero(states[:, 0] < 0)
        return (int(hits[0]), (0,)) if len(hits) else None

    loop = locate_flip(solver.t_old, samples, dense, solver.y, flipped)
    at_once = locate_flip(solver.t_old, samples, dense, solver.y, flipped, first,
                          sample_states(dense, samples, solver.y))
    assert loop is not None and loop[0] == at_once[0] and same(loop[1], at_once[1]) and loop[2] == at_once[2]
    # the instant to a few ulps: flipped there, not just before
    t_e = loop[0]
    assert dense(t_e)[0] < 0 <= dense(t_e - 8 * np.finfo(float).eps * t_e)[0]
    assert abs(t_e - math.sqrt(2 / 9.81)) < 1e-6


def test_rows_written_as_a_block_equal_rows_added_one_by_one():
    class ByRow(Recorder):
        def add(self, t, system, x, discrete):
            super().add(t, system, x, discrete)

    discrete = {"m": 1}
    states = np.arange(12.0).reshape(6, 2)
    recorders = []
    for cls in (Recorder, ByRow):
        r = cls(0.0, 1.0, 0.2)
        r.add(0.0, "system", [9.0, 9.0], discrete)
        r.skip_grid_through(0.0, round_off=False)
        times = r.pending(1.0, True)
        r.emit_rows(times, states[:len(times)], "system", discrete)
        recorders.append(r)
    (a, b) = recorders
    assert a.next_grid == b.next_grid == 6
    assert [row[0] for row in a.rows] == [row[0] for row in b.rows]
    assert all(same(p[2], q[2]) and p[3] == q[3] and p[3] is a.rows[0][3] for p, q in zip(a.rows, b.rows))


def test_time_event_roots_are_kept_and_recomputed_when_a_value_changes():
    translation = translate(CoupledClutches())
    relations, symbols = translation.partitioned.relations, dict(translation.cache.parameters.symbols)
    first = time_event_roots(relations, symbols)
    assert time_event_roots(relations, symbols) is first
    start = next(s for s in symbols if s.name == "sin1.startTime")
    symbols[start] = sp.Float(0.25)
    changed = time_event_roots(relations, symbols)
    assert changed != first and 0.25 in [root for _, root in changed]


# -- a whole run, with and without the vectorised paths ------------------------------------------


def _scalar_only(monkeypatch):
    """Every vectorised path off: one dense output call, crossing and output call per instant."""
    monkeypatch.setattr(crossings_module, "_BATCHED", {})
    monkeypatch.setattr(crossings_module, "_POINT", {})
    monkeypatch.setattr(ModeSystem, "vectorised", lambda system, name: None)
    monkeypatch.setattr(ComposedSystem, "vectorised", lambda system, name: None)


@pytest.mark.parametrize("name, method", [("StickSlip", "RK45"), ("Friction", "DOP853"),
                                          ("CoupledClutches", "RK45"), ("CoupledClutches", "Radau"),
                                          ("CoupledClutches", "LSODA")])
def test_a_run_does_not_change_by_a_bit_without_the_vectorised_paths(name, method, monkeypatch):
    translation = translate(EXAMPLES[name]())
    fast = simulate(translation, method=method)
    with monkeypatch.context() as patch:
        _scalar_only(patch)
        slow = simulate(translation, method=method)
    assert fast.status == slow.status == 0
    assert [(e.time, e.kind, e.relations, e.changes) for e in fast.events] == \
        [(e.time, e.kind, e.relations, e.changes) for e in slow.events]
    assert same(fast.time, slow.time)
    assert sorted(fast.names) == sorted(slow.names)
    for n in fast.names:
        assert same(fast[n], slow[n]), n
