"""Relations of time switch at their time event, whichever operator is written.

A time event is hit exactly, so at its instant ``g = 0``; ``time > c`` and
``time <= c`` have there the value they had before, and a relation frozen
between events would never change (the bug this guards against).  Modelica
tools switch them at the event: after the instant each relation has its
mathematical value.
"""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

from acausal import Eq, If, Model, Parameter, Variable, simulate, time

OPERATORS = {
    "<": lambda a, b: a < b, "<=": lambda a, b: a <= b,
    ">": lambda a, b: a > b, ">=": lambda a, b: a >= b,
}


def _model(relation):
    class Switched(Model):
        y = Variable()

        def equations(self):
            return [Eq(self.y, If(relation, 1.0, 0.0))]

    return Switched()


@pytest.mark.parametrize("op", sorted(OPERATORS))
@pytest.mark.parametrize("rising", [True, False], ids=["time-c", "c-time"])
def test_a_relation_of_time_has_its_value_on_both_sides_of_its_instant(op, rising):
    c = 0.75
    relation = OPERATORS[op](time, c) if rising else OPERATORS[op](c, time)
    result = simulate(_model(relation), stop_time=2.0, interval=0.25)
    t = np.asarray(result.time)
    away = np.abs(t - c) > 1e-12
    expected = (OPERATORS[op](t, c) if rising else OPERATORS[op](c, t)).astype(float)
    np.testing.assert_array_equal(result["y"][away], expected[away])
    # one event at c: the rows there hold the values before and after it
    at = np.flatnonzero(t == c)
    assert len(at) == 2
    before = OPERATORS[op](c - 1e-9, c) if rising else OPERATORS[op](c, c - 1e-9)
    after = OPERATORS[op](c + 1e-9, c) if rising else OPERATORS[op](c, c + 1e-9)
    assert result["y"][at[0]] == float(before) and result["y"][at[-1]] == float(after)


def test_homotopy_simulates_its_actual_expression():
    """MLS 3.7.4.4: after initialization ``homotopy(actual, simplified)`` is ``actual``:
    y = 2*x with x = 1 - exp(-t)."""
    from acausal import der, homotopy

    class Lag(Model):
        x = Variable(start=0.0, fixed=True)
        y = Variable()

        def equations(self):
            return [Eq(der(self.x), 1 - self.x), Eq(self.y, homotopy(2 * self.x, self.x))]

    result = simulate(Lag(), stop_time=1.0, rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(result["y"], 2 * (1 - np.exp(-np.asarray(result.time))), rtol=1e-7, atol=1e-12)


class _Bistable(Model):
    """y = limit(10*y + u) in [-1, 1] (events): three solutions for |u| < 1 (y = -1, y = 1 and
    the unstable y = -u/9); :meth:`simplified` gives homotopy's simplified expression (None:
    no homotopy)."""

    u = Parameter(0.5)
    y = Variable()

    def simplified(self):
        return None

    def equations(self):
        from acausal import homotopy

        gained = 10 * self.y + self.u
        actual = sp.Piecewise((1, gained > 1), (-1, gained < -1), (gained, True))
        simplified = self.simplified()
        return [Eq(self.y, actual if simplified is None else homotopy(actual, simplified))]


class _FromLowerLimit(_Bistable):
    def simplified(self):
        return -1


class _Unsolvable(_Bistable):
    def simplified(self):
        return self.y + 1  # y = y + 1: no solution


def test_without_homotopy_initialization_keeps_the_first_consistent_branch():
    """Every relation false first: the linear branch, whose solution y = -u/9 is consistent."""
    result = simulate(_Bistable(), stop_time=0.1)
    assert result["y"][0] == pytest.approx(-0.5 / 9, rel=1e-12)


def test_homotopy_starts_initialization_from_the_simplified_expression():
    """simplified = -1 decides the lower limit; the actual expression holds there
    (10*(-1) + 0.5 < -1), so y = -1 (the stable solution a circuit tool finds)."""
    result = simulate(_FromLowerLimit(), stop_time=0.1)
    assert result["y"][0] == -1.0 and result["y"][-1] == -1.0
    assert any("homotopy" in note for note in result.notes)


def test_homotopy_whose_simplified_problem_has_no_solution_uses_the_actual_expression():
    """simplified = y + 1 (y = y + 1 has no solution): the actual problem alone, as MLS allows."""
    result = simulate(_Unsolvable(), stop_time=0.1)
    assert result["y"][0] == pytest.approx(-0.5 / 9, rel=1e-12)
