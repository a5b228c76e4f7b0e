"""acausal.prescribed: index reduction takes the given derivatives, not those of the value."""

from __future__ import annotations

import pytest

from acausal import Eq, Experiment, Model, Variable, der, prescribed, simulate, time
from acausal.errors import StructuralError


class Driven(Model):
    """s is prescribed with deliberately inconsistent derivatives: 3*t is not d/dt(t**2)."""

    experiment = Experiment(stop_time=1.0)
    s = Variable()
    v = Variable()
    f = Variable()

    def equations(self):
        return [Eq(self.s, prescribed(time**2, 3 * time, 7.0, name="driven.s")),
                Eq(self.v, der(self.s)),
                Eq(self.f, 2.0 * der(self.v))]


def test_index_reduction_uses_the_given_derivatives():
    result = simulate(Driven())
    assert result.success, result.message
    assert result.final("s") == pytest.approx(1.0)      # the value itself: t**2
    assert result.final("v") == pytest.approx(3.0)      # the first given derivative, not 2*t
    assert result.final("f") == pytest.approx(14.0)     # 2 * the second given derivative


class TooFew(Model):
    experiment = Experiment(stop_time=1.0)
    s = Variable()
    v = Variable()
    f = Variable()

    def equations(self):
        return [Eq(self.s, prescribed(time**2, 3 * time, name="driven.s")),
                Eq(self.v, der(self.s)),
                Eq(self.f, der(self.v))]


def test_a_derivative_beyond_those_given_is_an_error_naming_the_value():
    with pytest.raises(StructuralError, match=r"driven\.s"):
        simulate(TooFew())
