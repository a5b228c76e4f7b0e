"""An assertion in a when-clause with terminal() is checked once, at the end of the run."""

from __future__ import annotations

import numpy as np
import pytest

from acausal import Assert, Eq, Model, Variable, When, der, simulate
from acausal.hybrid import terminal


def _ramp(bound: float, level: str = "error"):
    class Ramp(Model):
        x = Variable(start=0.0, fixed=True)

        def equations(self):
            return [Eq(der(self.x), 1), When(terminal(), Assert(self.x > bound, "x too small at the end",
                                                                 level=level))]

    return Ramp()


def test_a_terminal_assertion_that_holds_lets_the_run_succeed():
    result = simulate(_ramp(0.5), stop_time=1.0)
    assert result.success
    np.testing.assert_allclose(result["x"][-1], 1.0)


def test_a_terminal_assertion_that_fails_fails_the_run_and_keeps_the_rows():
    result = simulate(_ramp(5.0), stop_time=1.0)
    assert not result.success
    assert "x too small at the end" in result.message and "t = 1" in result.message
    np.testing.assert_allclose(result["x"][-1], 1.0)  # the run up to its end is kept


def test_a_terminal_warning_is_a_note():
    result = simulate(_ramp(5.0, level="warning"), stop_time=1.0)
    assert result.success
    assert any("x too small at the end" in note for note in result.notes)
