"""stateSelect = prefer/always on a variable no equation differentiates (issue 22, item 2).

Dymola and OpenModelica take such a variable as a state candidate: they
introduce its derivative and differentiate what determines it.  The
translational SpringDamper declares ``v_rel`` with ``stateSelect=prefer`` but
(unlike the rotational one) has no relative acceleration, so ``v_rel`` occurs
only undifferentiated; acausal used to pick the masses' positions and speeds
instead, and at a hard stop ``reinit(v, 0)`` of the stopped mass made
``v_rel`` jump, where Dymola keeps it continuous.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from acausal import Eq, Experiment, Model, Variable, der, simulate, translate
from acausal.language import StateSelect
from acausal.library.translational import ConstantForce, Mass, MassWithStopAndFriction, SpringDamper


class PreferredButUndifferentiated(Model):
    """x' = v, v' = -x: with w = 2*v declared prefer, w is a state (and x)."""

    experiment = Experiment(stop_time=1.0)
    select = StateSelect.prefer
    x = Variable(start=1.0, fixed=True)
    v = Variable(start=0.0)
    w = Variable(start=0.0, fixed=True, state_select=lambda m: m.select)

    def equations(self):
        return [Eq(der(self.x), self.v), Eq(der(self.v), -self.x), Eq(self.w, 2 * self.v)]


@pytest.mark.parametrize("select, states", [
    (StateSelect.prefer, {"x", "w"}),
    (StateSelect.always, {"x", "w"}),
    (StateSelect.default, {"x", "v"}),
])
def test_a_preferred_variable_is_a_state_candidate(select, states):
    model = PreferredButUndifferentiated()
    model.select = select
    assert set(translate(model).system(()).states) == states
    result = simulate(model, rtol=1e-9, atol=1e-12)
    assert result.success, result.message
    t = result.time
    np.testing.assert_allclose(result["x"], np.cos(t), atol=1e-7)
    np.testing.assert_allclose(result["w"], -2 * np.sin(t), atol=1e-7)


class MassAgainstStop(Model):
    """A force pushes a mass with a hard stop; a second mass hangs on a spring-damper."""

    experiment = Experiment(stop_time=2.0, interval=0.001)

    def build(self):
        self.force = ConstantForce(f_constant=10)
        self.stopMass = MassWithStopAndFriction(
            m=1, L=0, smax=0.5, smin=-1, F_prop=0, F_Coulomb=0, F_Stribeck=0,
            s=dict(start=0, fixed=True), v=dict(start=0, fixed=True))
        self.springDamper = SpringDamper(c=100, d=5)
        self.mass = Mass(m=1, s=dict(start=0, fixed=True), v=dict(start=0, fixed=True))
        self.connect(self.force.flange, self.stopMass.flange_a)
        self.connect(self.stopMass.flange_b, self.springDamper.flange_a)
        self.connect(self.springDamper.flange_b, self.mass.flange_a)


def test_spring_damper_relative_states_are_chosen():
    from acausal.runtime.initialization import start_system

    states = set(start_system(translate(MassAgainstStop())).states)
    assert {"springDamper.s_rel", "springDamper.v_rel", "stopMass.s", "stopMass.v"} <= states
    assert not {"mass.s", "mass.v"} & states


def test_relative_speed_stays_continuous_at_the_stop():
    result = simulate(MassAgainstStop(), rtol=1e-9, atol=1e-11)
    assert result.success, result.message
    stops = [e for e in result.events if e.kind == "state"]
    assert stops, "the mass never reached its stop"
    t_stop = stops[0].time
    at = np.flatnonzero(result.time == t_stop)
    assert len(at) == 2, "the event is recorded with its left and right limits"
    left, right = at
    # the relative states are continuous; the stopped mass's speed is reset to 0
    assert result["springDamper.v_rel"][right] == pytest.approx(result["springDamper.v_rel"][left], abs=1e-9)
    assert result["springDamper.s_rel"][right] == pytest.approx(result["springDamper.s_rel"][left], abs=1e-9)
    assert result["stopMass.v"][right] == 0.0
    # afterwards: a damped oscillator about the stop, from the relative state at the event
    # m x'' + d x' + c x = 0 with x = s_rel, x(0) = s_rel(t_stop), x'(0) = v_rel(t_stop)
    m, c, d = 1.0, 100.0, 5.0
    x0, v0 = result["springDamper.s_rel"][right], result["springDamper.v_rel"][right]
    alpha, omega = d / (2 * m), math.sqrt(c / m - (d / (2 * m)) ** 2)
    after = result.time > t_stop
    tau = result.time[after] - t_stop
    x = np.exp(-alpha * tau) * (x0 * np.cos(omega * tau) + (v0 + alpha * x0) / omega * np.sin(omega * tau))
    stays = np.all(result["stopMass.s"][after] == pytest.approx(0.5, abs=1e-9))
    assert stays, "the mass pushed against its stop stays there (the spring force is below the push)"
    np.testing.assert_allclose(result["springDamper.s_rel"][after], x, atol=1e-6)
