"""Mistakes in hybrid models give errors that name the place, and the engine bugs A and D."""

import pytest

from acausal import (Boolean, EquationError, Eq, EventIterationError, If, Integer, Model, ModelDefinitionError,
                     Variable, When, der, pre, reinit, sample, simulate, time, translate)


class Falling(Model):
    h = Variable(start=1.0, fixed=True)
    v = Variable(start=0.0, fixed=True)
    a = Variable()

    def equations(self):
        return [Eq(der(self.h), self.v), Eq(der(self.v), self.a), Eq(self.a, -9.81)]


def test_reinit_of_a_variable_that_is_not_a_state():
    class Bad(Falling):
        def equations(self):
            return [When(self.h <= 0, reinit(self.a, 0.0))]

    with pytest.raises(EquationError, match=r"reinit\(a\).*a is not a state") as info:
        translate(Bad())
    assert "Bad eq. 1" in str(info.value) and "continuous states" in str(info.value.hint)


def test_two_active_reinits_of_one_state_at_one_event():
    class Twice(Falling):
        def equations(self):
            return [When(self.h <= 0, reinit(self.v, 1.0)), When(self.v <= -1.0, reinit(self.v, 2.0))]

    class Same(Falling):
        def equations(self):
            # both conditions become true at the same event (h = 1 - 4.905 t^2 hits 0 when v = -4.43)
            return [When(self.h <= 0, reinit(self.v, 1.0)), When(self.h <= 0.0, reinit(self.v, 2.0))]

    result = simulate(Same(), stop_time=1.0)
    assert isinstance(result.error, EventIterationError)
    assert "two reinits of v" in result.message and "Same eq. 1" in result.message \
        and "Same eq. 2" in result.message
    # apart in time they are fine
    assert simulate(Twice(), stop_time=0.3).status == 0


def test_a_discrete_variable_assigned_in_two_when_clauses():
    class Double(Model):
        n = Integer(start=0)

        def equations(self):
            return [When(sample(0, 0.1), Eq(self.n, pre(self.n) + 1)),
                    When(time >= 0.5, Eq(self.n, 0))]

    with pytest.raises(ModelDefinitionError, match="n is assigned in two when-clauses") as info:
        translate(Double())
    assert "Double eq. 1" in str(info.value) and "Double eq. 2" in str(info.value)
    assert "single-assignment" in info.value.hint


def test_a_when_clause_inside_an_if_branch():
    class Inside(Falling):
        def equations(self):
            return [If(self.h > 0, When(self.h <= 0, reinit(self.v, 0.0)), 0)]

    with pytest.raises(EquationError, match="when-clause inside an expression") as info:
        translate(Inside())
    assert "top of equations" in info.value.hint


def test_an_algebraic_loop_through_a_when_clause():
    class Loop(Model):
        y = Variable(start=0.0)
        u = Variable()

        def equations(self):
            return [Eq(self.u, self.y + 1), When(sample(0, 0.1), Eq(self.y, self.u))]

    result = simulate(Loop(), stop_time=0.3)
    assert isinstance(result.error, EventIterationError)
    assert "algebraic loop through a when-clause" in result.message and "Loop eq. 2" in result.message
    assert "pre()" in result.error.hint


def test_bug_a_pre_of_an_integer_inside_a_relation():
    """Was: "generated code ...: pre(c.n) is not known here" and no output."""

    class Steps(Model):
        n = Integer(start=0, fixed=True)

        def equations(self):
            return [Eq(self.n, If(time >= 0.25 * (pre(self.n) + 1), pre(self.n) + 1, pre(self.n)))]

    result = simulate(Steps(), stop_time=1.1, interval=0.01)
    assert result.status == 0, result.message
    # n counts the quarters: n(t) = floor(4 t) (events within the relation margin, 1e-10)
    changes = [(ev.time, new) for ev in result.events for name, _, new in ev.changes if name == "n"]
    assert [n for _, n in changes] == [1, 2, 3, 4]
    assert [t for t, _ in changes] == pytest.approx([0.25, 0.5, 0.75, 1.0], abs=1e-9)


def test_bug_d_a_non_strict_relation_at_exactly_its_limit_is_true():
    """Was: b = (u <= 0) stayed false after u stepped to exactly 0 (the margin applied at events)."""

    class StepToZero(Model):
        u = Variable()
        b = Boolean()

        def equations(self):
            return [Eq(self.u, If(time >= 0.5, 0, 1)), Eq(self.b, self.u <= 0)]

    result = simulate(StepToZero(), stop_time=1.0, interval=0.1)
    assert result.status == 0
    t, b = result.time, result["b"]
    assert b[-1] == 1 and result["u"][-1] == 0
    assert all(b[t < 0.5] == 0) and all(b[t > 0.5] == 1)
