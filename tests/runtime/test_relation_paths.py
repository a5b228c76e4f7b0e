"""The scalar and numpy relation paths agree (issue 22, item 5).

Event iteration decides relation values in plain Python for a few relations
and with numpy from 48 on (``relation_evaluator._VECTORISE_FROM``); the crossing
watch likewise (``_VECTORISE_FROM``, ``_MANY_FROM``), and the relevance analysis
finds relations that cross together with numpy from 48 on
(``relevance._TWINS_WITH_NUMPY_FROM``).  The numpy form used to keep a time
event's relation true at its own instant where the scalar one did not (a
table of 48 rows starting at t = 1 chattered, one of 47 ran).  Here the two
forms of :mod:`acausal.runtime.relations` are compared on random relation
sets -- the rules at an event, and the pieces of hysteresis every decision
goes through (the margin, the shifted ``g``, whether it holds, whether a
relation was decided clearly) -- and whole simulations must take the same
events with the same values whichever form runs.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from acausal import Eq, Experiment, If, Integer, Model, Variable, When, der, pre, simulate, time
from acausal.runtime import relation_evaluator, relevance
from acausal.runtime.relations import (ROUND_OFF, decide, decide_many, decided_clearly, decided_clearly_many, holds,
                                       holds_many, margin, margin_many, shifted, shifted_many, sides_many)

# -- the two forms of one rule, on random relation sets ---------------------------------

_SIDES = st.one_of(
    st.floats(-1e3, 1e3, allow_nan=False),
    st.sampled_from([0.0, -0.0, 1.0, 1e-10, -1e-10, 1e-14, 1e300, math.inf, -math.inf, math.nan]),
)


@st.composite
def relation_sets(draw):
    n = draw(st.integers(1, 12))
    kinds = [(draw(st.sampled_from([1.0, -1.0])), draw(st.booleans()), draw(st.booleans())) for _ in range(n)]
    raw = []
    for _ in range(n):
        lhs = draw(_SIDES)
        how = draw(st.sampled_from(["free", "equal", "round-off", "margin"]))
        if how == "equal":
            rhs = lhs
        elif how == "round-off" and math.isfinite(lhs):
            rhs = lhs + draw(st.floats(-1, 1)) * ROUND_OFF * max(1.0, abs(lhs))
        elif how == "margin" and math.isfinite(lhs):
            rhs = lhs + draw(st.floats(-2, 2)) * 1e-10 * max(1.0, abs(lhs))
        else:
            rhs = draw(_SIDES)
        raw += [lhs, rhs]
    previous = [draw(st.booleans()) for _ in range(n)]
    fired = frozenset(draw(st.sets(st.integers(0, n - 1))))
    clear = draw(st.one_of(st.none(), st.lists(st.booleans(), min_size=n, max_size=n)))
    exact = draw(st.booleans())
    if draw(st.booleans()):
        epsilon = draw(st.sampled_from([1e-10, 0.0, 1e-6]))
        floor = 1.0
    else:  # per relation: the crossing margin, or round-off relative to the sides (exact relations)
        pairs = draw(st.lists(st.sampled_from([(1e-10, 1.0), (1e-13, 0.0), (0.0, 1.0)]), min_size=n, max_size=n))
        epsilon, floor = [p[0] for p in pairs], [p[1] for p in pairs]
    return kinds, raw, previous, fired, clear, exact, epsilon, floor


@settings(max_examples=400, deadline=None)
@given(relation_sets())
def test_scalar_and_numpy_decisions_agree(case):
    kinds, raw, previous, fired, clear, exact, epsilon, floor = case
    scalar = decide(kinds, raw, previous, epsilon, floor=floor, exact=exact, fired=fired, clear=clear)
    vector = decide_many(kinds, raw, previous, epsilon, floor=floor, exact=exact, fired=fired, clear=clear)
    assert scalar == vector


@settings(max_examples=400, deadline=None)
@given(relation_sets())
def test_scalar_and_numpy_hysteresis_agree(case):
    """The pieces of hysteresis, one relation at a time against numpy on all at once: the
    same doubles (the shifted ``g`` to the sign of zero, as the flip search reads it)."""
    kinds, raw, previous, fired, clear, _exact, epsilon, floor = case
    n = len(kinds)
    eps = epsilon if isinstance(epsilon, list) else [epsilon] * n
    bottom = floor if isinstance(floor, list) else [floor] * n
    plain = [timed or k in fired for k, (_d, _s, timed) in enumerate(kinds)]
    d = np.array([k[0] for k in kinds])
    strict = np.array([k[1] for k in kinds])
    values = np.array(raw, dtype=float)
    lhs, rhs = values[0::2], values[1::2]
    with np.errstate(invalid="ignore", over="ignore"):
        margins = margin_many(np.array(eps), np.array(bottom), lhs, rhs)
        moved = shifted_many(d, np.array(previous), lhs, rhs, np.array(eps), np.array(bottom), np.array(plain))
        decided = holds_many(moved, strict)
    for k in range(n):
        lhs_k, rhs_k = raw[2 * k], raw[2 * k + 1]
        one = shifted(d[k], previous[k], lhs_k, rhs_k, eps[k], bottom[k], plain[k])
        if not (math.isnan(lhs_k) or math.isnan(rhs_k)):  # (Python's max may skip a NaN side)
            assert _same(margin(eps[k], bottom[k], lhs_k, rhs_k), margins[k])
        assert _same(one, moved[k])
        assert holds(one, bool(strict[k])) == decided[k]
    # whether each was decided beyond its margin, with and without the answer before
    assert decided_clearly(raw, eps, bottom, clear) == \
        decided_clearly_many(raw, np.array(eps, dtype=float), np.array(bottom, dtype=float), clear)


@settings(max_examples=400, deadline=None)
@given(relation_sets())
def test_shared_margins_decide_as_computed_ones(case):
    """A pass of event iteration with many relations computes their margins once
    (``sides_many``) for its decisions and for whether they were decided clearly: the
    same answers as each function computing its own."""
    kinds, raw, previous, fired, clear, exact, epsilon, floor = case
    n = len(kinds)
    eps = epsilon if isinstance(epsilon, list) else [epsilon] * n
    bottom = floor if isinstance(floor, list) else [floor] * n
    arrays = (np.array(eps, dtype=float), np.array(bottom, dtype=float))
    sides = sides_many(raw, *arrays)
    assert decide_many(kinds, raw, previous, eps, floor=bottom, exact=exact, fired=fired, clear=clear,
                       sides=sides) == decide_many(kinds, raw, previous, eps, floor=bottom, exact=exact,
                                                   fired=fired, clear=clear)
    assert decided_clearly_many(raw, *arrays, clear, sides=sides) == decided_clearly_many(raw, *arrays, clear)


def _same(a: float, b: float) -> bool:
    """The same double: equal with the same sign (of zero too), or both NaN."""
    if math.isnan(a) or math.isnan(b):
        return math.isnan(a) and math.isnan(b)
    return a == b and math.copysign(1.0, a) == math.copysign(1.0, b)


def test_a_time_event_at_its_instant_takes_its_own_value_in_both_forms():
    """``time < t1`` that fired at t1, sides equal up to round-off, kept 'clear' from the
    pass before: false at its instant (the bug: the numpy form kept it true)."""
    kinds = [(-1.0, True, True)]          # time < t1: d = -1, strict, a time event
    raw = [1.0, 1.0]                      # time == t1
    for form in (decide, decide_many):
        assert form(kinds, raw, [True], 1e-10, fired=frozenset({0}), clear=[True]) == (False,)


# -- whole simulations ---------------------------------------------------------------------


def _table_signal(times, values, start):
    """A piecewise linear signal through (times, values) from ``start`` on, one relation
    per row (time events), as a table without events of its own would be written."""
    t = time
    pieces = [(0.0, t < start)]
    for (t0, v0), (t1, v1) in zip(zip(times, values), zip(times[1:], values[1:])):
        pieces.append((v0 + (v1 - v0) * (t - t0) / (t1 - t0), t < t1))
    pieces.append((values[-1], True))
    return sp.Piecewise(*pieces, evaluate=False)


def _table_model(rows: int):
    times = [1.0 + 0.02 * i for i in range(rows)]
    values = [math.sin(3 * x) for x in times]

    class Rows(Model):
        experiment = Experiment(stop_time=2.5, interval=0.01)
        y = Variable()
        x = Variable(start=0.0, fixed=True)

        def equations(self):
            return [Eq(self.y, _table_signal(times, values, 1.0)), Eq(der(self.x), self.y)]

    return Rows(), times, values


def _mixed_model(seed: int, n_time: int, n_state: int):
    """Time events, state events on an oscillator, and a counter reading pre()."""
    rng = np.random.default_rng(seed)
    instants = np.sort(rng.uniform(0.05, 1.95, n_time))
    levels = rng.uniform(-0.9, 0.9, n_state)

    class Mixed(Model):
        experiment = Experiment(stop_time=2.0, interval=0.01)
        p = Variable(start=1.0, fixed=True)
        v = Variable(start=0.0, fixed=True)
        y = Variable()
        n = Integer(start=0)

        def equations(self):
            drive = sum(If(time >= float(c), 0.1 * (k % 3 - 1), 0.0) for k, c in enumerate(instants))
            kicks = sum(If(self.p > float(c), 0.05, -0.05) for c in levels)
            return [Eq(der(self.p), self.v),
                    Eq(der(self.v), -20 * self.p + drive + kicks),
                    Eq(self.y, self.p + 0.01 * self.n),
                    When(self.v > 0.5, Eq(self.n, pre(self.n) + 1))]

    return Mixed()


def _run_both(make, monkeypatch):
    runs = []
    for threshold in (1, 10**9):
        monkeypatch.setattr(relation_evaluator, "_VECTORISE_FROM", threshold)
        monkeypatch.setattr(relation_evaluator, "_MANY_FROM", threshold)
        monkeypatch.setattr(relevance, "_TWINS_WITH_NUMPY_FROM", threshold)
        runs.append(simulate(make()))
    return runs


@pytest.mark.parametrize("rows", [47, 48, 60])
def test_a_signal_of_many_rows_runs_the_same_on_both_paths(rows, monkeypatch):
    numpy_run, scalar_run = _run_both(lambda: _table_model(rows)[0], monkeypatch)
    _, times, values = _table_model(rows)
    for run in (numpy_run, scalar_run):
        assert run.success, run.message
        # the signal is the interpolation of its rows (closed form), before, in and after them
        expected = np.where(run.time < 1.0, 0.0, np.interp(run.time, times, values))
        at_start = run.time == 1.0          # the event: left limit 0, right limit the first row
        assert np.max(np.abs(run["y"] - expected)[~at_start]) < 1e-9
        assert list(run["y"][at_start]) == [0.0, pytest.approx(values[0], abs=1e-12)]
    assert [e.time for e in numpy_run.events] == [e.time for e in scalar_run.events]
    np.testing.assert_array_equal(numpy_run["x"], scalar_run["x"])


@settings(max_examples=6, deadline=None)
@given(seed=st.integers(0, 10**6), n_time=st.integers(1, 30), n_state=st.integers(1, 30))
def test_random_hybrid_models_take_the_same_events_on_both_paths(seed, n_time, n_state):
    with pytest.MonkeyPatch.context() as monkeypatch:
        numpy_run, scalar_run = _run_both(lambda: _mixed_model(seed, n_time, n_state), monkeypatch)
    assert numpy_run.status == scalar_run.status, (numpy_run.message, scalar_run.message)
    assert [(e.time, e.kind, e.changes) for e in numpy_run.events] == \
        [(e.time, e.kind, e.changes) for e in scalar_run.events]
    np.testing.assert_array_equal(numpy_run["y"], scalar_run["y"])


@settings(max_examples=60, derandomize=True, deadline=None)
@given(data=st.data())
def test_clear_decisions_with_numpy_equal_the_loop(data):
    """``RelationEvaluator.clearly_decided`` with numpy (from ``_VECTORISE_FROM`` relations)
    gives the loop's answers for the same doubles: sides within and beyond the margin, equal
    sides that inherit the answer before, NaN and infinite sides."""
    from acausal.compiler.translate import translate
    from acausal.runtime.events import evaluator_for
    from tests.compiler.test_clusters import storm

    evaluator = _STORM_EVALUATOR.get("e")
    if evaluator is None:
        translation = translate(storm(12), cache=False)
        evaluator = _STORM_EVALUATOR["e"] = evaluator_for(translation)
    n = len(evaluator.relations)
    assert n >= relation_evaluator._VECTORISE_FROM
    side = st.sampled_from([0.0, -0.0, 1.0, -1.0, 1.0 + 1e-10, 1.0 - 1e-10, 1e-12, math.nan, math.inf, -math.inf]) \
        | st.floats(-3, 3, allow_nan=False)
    raw = data.draw(st.lists(side, min_size=2 * n, max_size=2 * n))
    for i in data.draw(st.lists(st.integers(0, n - 1), max_size=n)):  # some exactly equal sides
        raw[2 * i + 1] = raw[2 * i]
    inherited = data.draw(st.none() | st.lists(st.booleans(), min_size=n, max_size=n))
    fast = evaluator.clearly_decided(list(raw), inherited)
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(relation_evaluator, "_VECTORISE_FROM", 10 ** 9)
        loop = evaluator.clearly_decided(list(raw), inherited)
    assert fast == loop


_STORM_EVALUATOR: dict = {}
