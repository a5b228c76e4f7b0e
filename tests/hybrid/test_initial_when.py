"""A discrete Real that a when-clause with initial() sets has that value in the initialization
too: Modelica solves the initial equations and the discrete equations together (MLS 8.6), so a
continuous initial equation that reads it sees the assigned value, not its start value."""

from __future__ import annotations

import numpy as np
import pytest

from acausal import Eq, Model, Parameter, Variable, der, simulate, time
from acausal.hybrid import When
from acausal.language import initial


def _decay(assign: bool):
    class Decay(Model):
        k = Parameter(2.5)
        r = Variable(discrete=True, start=1.0)
        x = Variable(start=0.0)

        def equations(self):
            # without initial() the clause is not active at the start (it fires at t = 10)
            condition = initial() if assign else time > 10
            return [Eq(der(self.x), -self.x), When(condition, Eq(self.r, 2 * self.k))]

        def initial_equations(self):
            return [Eq(self.x, self.r)]

    return Decay()


@pytest.mark.parametrize("assign, x0", [(True, 5.0), (False, 1.0)],
                         ids=["when initial() sets r", "r keeps its start"])
def test_the_initial_equation_sees_the_value_the_when_clause_assigns(assign, x0):
    result = simulate(_decay(assign), stop_time=1.0, rtol=1e-10, atol=1e-12)
    t = np.asarray(result.time)
    np.testing.assert_allclose(result["r"], x0)
    np.testing.assert_allclose(result["x"], x0 * np.exp(-t), rtol=1e-7)


def test_a_start_value_given_at_run_time_is_overridden_by_the_assignment_only():
    result = simulate(_decay(True), stop_time=0.5, start={"r": 3.0}, parameters={"k": 0.5})
    assert result["x"][0] == pytest.approx(1.0)  # 2*k, not the start 3
    result = simulate(_decay(False), stop_time=0.5, start={"r": 3.0})
    assert result["x"][0] == pytest.approx(3.0)
