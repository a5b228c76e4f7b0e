"""An input may be given its value by an equation of an enclosing component instead of a
connection (Modelica's hierarchical inputs), whatever its type."""

from __future__ import annotations

import numpy as np
import pytest

from acausal import Component, Eq, If, Model, Variable, simulate, time
from acausal.components.blocks import BooleanInput, IntegerInput, RealInput
from acausal.errors import ConnectorError


class Inner(Component):
    b = BooleanInput()
    n = IntegerInput()
    u = RealInput()
    y = Variable()

    def equations(self):
        return [Eq(self.y, If(self.b, 1.0, 0.0) + self.n + self.u)]


class Outer(Model):
    def build(self):
        self.inner = Inner()

    def equations(self):
        return [Eq(self.inner.b, time > 0.5), Eq(self.inner.n, 2), Eq(self.inner.u, 0.25)]


def test_real_integer_and_boolean_inputs_given_by_an_enclosing_equation():
    result = simulate(Outer(), stop_time=1.0)
    t = np.asarray(result.time)
    np.testing.assert_array_equal(result["inner.y"][t < 0.5], 2.25)
    np.testing.assert_array_equal(result["inner.y"][t > 0.5], 3.25)


def test_an_input_nothing_gives_a_value_is_reported():
    class Forgotten(Model):
        def build(self):
            self.inner = Inner()

        def equations(self):
            return [Eq(self.inner.n, 2), Eq(self.inner.u, 0.25)]

    with pytest.raises(ConnectorError, match="input inner.b of Inner is not connected"):
        simulate(Forgotten(), stop_time=1.0)
