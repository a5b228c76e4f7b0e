"""Initialization as Modelica tools do it: relations guessed from start values, der() of aliases."""

from __future__ import annotations

import math

import pytest
import sympy as sp

from acausal import Component, Eq, Experiment, If, Model, Variable, der, simulate
from acausal.components.translational import Flange_b
from acausal.library.translational import Mass


class InverseLaw(Model):
    """der(w) = tau - 0.4*w with tau = 20 below |w| = 0.5, else 10/|w|: from rest, the first branch."""

    experiment = Experiment(stop_time=1.0)
    w = Variable(start=0.0, fixed=True)
    tau = Variable()

    def equations(self):
        return [Eq(self.tau, If(sp.Abs(self.w) < 0.5, 20.0, 10.0 / sp.Abs(self.w))),
                Eq(der(self.w), self.tau - 0.4 * self.w)]


def test_relations_guessed_from_start_values_when_the_all_false_guess_cannot_be_evaluated():
    result = simulate(InverseLaw(), rtol=1e-10)
    assert result.success, result.message
    assert result["tau"][0] == 20.0
    # until |w| = 0.5: w = 50*(1 - exp(-0.4 t)), so the switch is at t = -ln(1 - 0.01)/0.4
    t_switch = -math.log(1 - 0.5 / 50) / 0.4
    switch = [e.time for e in result.events if e.kind == "state"]
    assert switch[0] == pytest.approx(t_switch, abs=1e-8)


class SpeedSetter(Component):
    """Sets the initial speed of what its flange is connected to: der(x) = v0 with x = flange.s."""

    flange = Flange_b()
    x = Variable()

    def equations(self):
        return [Eq(self.flange.f, 0), Eq(self.x, self.flange.s)]

    def initial_equations(self):
        return [Eq(der(self.x), 2.0)]


class Coasting(Model):
    experiment = Experiment(stop_time=1.0)

    def build(self):
        self.setter = SpeedSetter()
        self.mass = Mass(s=dict(start=0.5, fixed=True))
        self.connect(self.setter.flange, self.mass.flange_a)


def test_der_of_an_alias_in_an_initial_equation_is_der_of_its_representative():
    result = simulate(Coasting())
    assert result.success, result.message
    assert result["mass.v"][0] == 2.0
    assert result.final("mass.s") == pytest.approx(0.5 + 2.0 * 1.0, rel=1e-9)
