"""Modelica's delay() operator (3.7.4.1) and the MSL's FixedDelay and VariableDelay.

Every result is compared with its analytic solution; before ``start + T`` the
delayed value is the expression's value at the start time.
"""

from __future__ import annotations

import math
import pickle

import numpy as np
import pytest
import sympy as sp

from acausal import (EquationError, Eq, Model, ModelDefinitionError, Parameter, Translation, Variable, When,
                     delay, der, simulate, time, translate)
from acausal.library.blocks import FixedDelay, Integrator, Ramp, Sine, Step, VariableDelay

W = 2 * math.pi  # the angular frequency of Sine(f=1)


class DelayedSine(Model):
    T = Parameter(0.5)
    y = Variable()

    def equations(self):
        return [Eq(self.y, delay(sp.sin(time + 0.3), self.T))]


def test_delayed_sine_is_the_start_value_then_the_shifted_sine():
    result = simulate(DelayedSine(), start_time=0.0, stop_time=3.0, interval=0.01)
    assert result.success
    t = result.time
    expected = np.where(t <= 0.5, math.sin(0.3), np.sin(t - 0.5 + 0.3))
    assert np.max(np.abs(result["y"] - expected)) < 1e-12


def test_start_time_other_than_zero_holds_the_value_at_the_start():
    result = simulate(DelayedSine(), start_time=1.0, stop_time=3.0, interval=0.01)
    t = result.time
    expected = np.where(t <= 1.5, math.sin(1.3), np.sin(t - 0.5 + 0.3))
    assert np.max(np.abs(result["y"] - expected)) < 1e-12


class IntegratedSineDelayed(Model):
    """A state delayed: x = (1 - cos(w t))/w, y = x(t - 0.25)."""

    def build(self):
        self.sine = Sine(f=1.0)
        self.integrator = Integrator()
        self.delay = FixedDelay(delayTime=0.25)
        self.connect(self.sine.y, self.integrator.u)
        self.connect(self.integrator.y, self.delay.u)


def test_fixed_delay_of_a_state_follows_the_dense_output():
    result = simulate(IntegratedSineDelayed(), start_time=0.0, stop_time=3.0, interval=0.01, rtol=1e-9)
    assert result.success
    t = result.time
    expected = np.where(t <= 0.25, 0.0, (1 - np.cos(W * (t - 0.25))) / W)
    error = np.max(np.abs(result["delay.y"] - expected))
    own = np.max(np.abs(result["integrator.y"] - (1 - np.cos(W * t)) / W))
    # the delay adds no error of its own to the integrator's
    assert error < 1e-8 and error <= 2 * own + 1e-12


class DelayedStep(Model):
    x = Variable(start=0.0, fixed=True)

    def build(self):
        self.step = Step(height=2.0, offset=1.0, startTime=0.3)
        self.delay = FixedDelay(delayTime=0.5)
        self.connect(self.step.y, self.delay.u)

    def equations(self):
        return [Eq(der(self.x), self.delay.y)]


def test_a_delayed_step_jumps_at_its_event_plus_the_delay():
    result = simulate(DelayedStep(), start_time=0.0, stop_time=2.0, interval=0.01)
    assert result.success
    t, y, x = result.time, result["delay.y"], result["x"]
    assert np.all(y[t < 0.8 - 1e-9] == 1.0) and np.all(y[t > 0.8 + 1e-9] == 3.0)
    # the integral has its kink at 0.8 exactly: the integrator restarts there
    expected = np.where(t <= 0.8, t, 0.8 + 3.0 * (t - 0.8))
    assert np.max(np.abs(x - expected)) < 1e-10
    # no event is added at 0.8: only the step's own
    assert [e.time for e in result.events if e.kind != "initial"] == [pytest.approx(0.3)]


def test_the_delay_time_is_tunable():
    simulate(DelayedStep(), stop_time=2.0, interval=0.01)
    result = simulate(DelayedStep(), stop_time=2.0, interval=0.01, parameters={"delay.delayTime": 0.7})
    t = result.time
    assert np.max(np.abs(result["x"] - np.where(t <= 1.0, t, 1.0 + 3.0 * (t - 1.0)))) < 1e-10


class DelayDifferential(Model):
    """x' = -x(t - 1), x(0) = 1 (x = 1 before the start: its value at the start)."""

    x = Variable(start=1.0, fixed=True)

    def equations(self):
        return [Eq(der(self.x), -delay(self.x, 1.0))]


def method_of_steps(intervals: int):
    """The exact solution on [k, k+1], k < intervals: polynomials by the method of steps."""
    s = sp.Symbol("s")
    pieces = []
    previous = sp.Integer(1)  # x on [-1, 0]
    start_value = sp.Integer(1)
    for k in range(intervals):
        # x(t) = x(k) - int_k^t x(s - 1) ds
        current = start_value - sp.integrate(previous.subs(s, s - 1), (s, k, s))
        pieces.append(sp.lambdify(s, sp.expand(current)))
        start_value = current.subs(s, k + 1)
        previous = current
    return lambda t: np.select([(t >= k) & (t <= k + 1) for k in range(intervals)],
                               [p(t) * np.ones_like(t) for p in pieces])


@pytest.mark.parametrize("method, rtol, bound", [("RK45", 1e-6, 2e-5), ("DOP853", 1e-10, 1e-12),
                                                 ("Radau", 1e-8, 1e-8)])
def test_delay_differential_equation_matches_the_method_of_steps(method, rtol, bound):
    result = simulate(DelayDifferential(), start_time=0.0, stop_time=5.0, interval=0.01, method=method, rtol=rtol)
    assert result.success
    exact = method_of_steps(5)(result.time)
    assert np.max(np.abs(result["x"] - exact)) < bound


class DelayedFeedback(Model):
    """x' = -x(t - 0.5) + y with y assigned by a when-clause: history across event restarts."""

    x = Variable(start=1.0, fixed=True)
    y = Variable(start=0.0)

    def equations(self):
        return [Eq(der(self.x), -delay(self.x, 0.5) + self.y), When(time >= 0.7, Eq(self.y, 1.0))]


def test_the_history_survives_events():
    result = simulate(DelayedFeedback(), start_time=0.0, stop_time=2.0, interval=0.01, rtol=1e-10)
    assert result.success
    # by hand: [0, .5]: x = 1 - t; [.5, .7]: x' = -(1 - (t - .5)) = t - 1.5;
    # [.7, 1]: x' = t - 0.5; [1, 1.2]: x' = -x(t - .5) + 1 with x(t-.5) = x on [.5, .7]
    s = sp.Symbol("s")
    pieces = [(0.0, 0.5, 1 - s)]
    x_05 = 0.5
    p2 = x_05 + sp.integrate(s - 1.5, (s, 0.5, s))
    pieces.append((0.5, 0.7, p2))
    x_07 = p2.subs(s, 0.7)
    p3 = x_07 + sp.integrate(s - 0.5, (s, 0.7, s))
    pieces.append((0.7, 1.0, p3))
    x_1 = p3.subs(s, 1.0)
    p4 = x_1 + sp.integrate(-p2.subs(s, s - 0.5) + 1, (s, 1.0, s))
    pieces.append((1.0, 1.2, p4))
    t = result.time
    for a, b, p in pieces:
        inside = (t > a + 1e-9) & (t < b - 1e-9)
        expected = sp.lambdify(s, p)(t[inside])
        assert np.max(np.abs(result["x"][inside] - expected)) < 1e-8, (a, b)


class VariableDelayOfAState(Model):
    """u = (1 - cos(w t))/w delayed by T(t) = 0.1 + 0.25 t."""

    def build(self):
        self.sine = Sine(f=1.0)
        self.integrator = Integrator()
        self.delay_time = Ramp(height=0.5, duration=2.0, offset=0.1)
        self.delay = VariableDelay(delayMax=1.0)
        self.connect(self.sine.y, self.integrator.u)
        self.connect(self.integrator.y, self.delay.u)
        self.connect(self.delay_time.y, self.delay.delayTime)


def test_variable_delay_with_a_time_varying_delay():
    result = simulate(VariableDelayOfAState(), start_time=0.0, stop_time=2.0, interval=0.01, rtol=1e-9)
    assert result.success
    t = result.time
    lag = t - (0.1 + 0.25 * t)
    expected = np.where(lag <= 0, 0.0, (1 - np.cos(W * lag)) / W)
    assert np.max(np.abs(result["delay.y"] - expected)) < 1e-7


def test_variable_delay_beyond_delay_max_stops_the_run():
    model = VariableDelayOfAState()
    result = simulate(model, start_time=0.0, stop_time=2.0, parameters={"delay.delayMax": 0.3})
    assert not result.success
    assert "delayMax" in result.message and "outside" in result.message
    assert result.time[-1] < 1.0  # T = 0.3 at t = 0.8: the result keeps the run until then


def test_translation_export_and_disk_cache_reproduce_the_run(tmp_path, monkeypatch):
    monkeypatch.setenv("ACAUSAL_CACHE_DIR", str(tmp_path))
    monkeypatch.setenv("ACAUSAL_DISK_CACHE", "on")
    first = simulate(DelayDifferential(), stop_time=3.0, cache=False)
    translation = translate(DelayDifferential(), cache=False)
    again = simulate(translation, stop_time=3.0)
    shipped = Translation.from_bundle(pickle.loads(pickle.dumps(translation.export())))
    third = simulate(shipped, stop_time=3.0)
    assert np.array_equal(first["x"], again["x"]) and np.array_equal(first["x"], third["x"])


# -- errors ---------------------------------------------------------------------------


def test_missing_delay_time_is_an_error():
    with pytest.raises(EquationError, match="needs a delay time"):
        delay(time)


@pytest.mark.parametrize("args", [(-1.0,), (0.5, -1.0), (2.0, 1.0)])
def test_negative_or_inconsistent_numbers_are_errors(args):
    with pytest.raises(EquationError, match="delay"):
        delay(time, *args)


class VariableWithoutMax(Model):
    T = Variable()
    y = Variable()

    def equations(self):
        return [Eq(self.T, 0.1 + 0.1 * time), Eq(self.y, delay(sp.sin(time), self.T))]


def test_variable_delay_time_without_delay_max_is_refused():
    with pytest.raises(ModelDefinitionError, match="delayMax"):
        translate(VariableWithoutMax(), cache=False)


def test_zero_fixed_delay_is_refused_when_the_run_starts():
    class Zero(Model):
        def build(self):
            self.sine = Sine(f=1.0)
            self.delay = FixedDelay(delayTime=0.0)
            self.connect(self.sine.y, self.delay.u)

    with pytest.raises(ModelDefinitionError, match="must be > 0"):
        simulate(Zero(), stop_time=1.0)


def test_delay_in_a_when_clause_is_refused():
    class InWhen(Model):
        x = Variable(start=0.0, fixed=True)
        y = Variable(start=0.0)

        def equations(self):
            return [Eq(der(self.x), 1.0), When(time >= 0.5, Eq(self.y, delay(self.x, 0.1)))]

    with pytest.raises(ModelDefinitionError, match="continuous equations only"):
        translate(InWhen(), cache=False)


def test_the_blocks_name_their_msl_classes():
    assert FixedDelay.modelica_name == "Modelica.Blocks.Nonlinear.FixedDelay"
    assert VariableDelay.modelica_name == "Modelica.Blocks.Nonlinear.VariableDelay"
