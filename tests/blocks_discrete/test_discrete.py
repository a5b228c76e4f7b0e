"""Modelica.Blocks Discrete, Nonlinear and the hybrid Continuous/Sources blocks, simulated.

The two ModelicaTest examples against the MSL reference results (tube test);
then each block against its closed form: a zero-order hold of a ramp, the
sample instants over 10^4 periods, the integrator reset, the limiters on a
ramp, the slew-rate bound, the periodic and table sources, and the array
naming of the vector blocks.
"""

from __future__ import annotations

import importlib
import math

import numpy as np
import pytest

from acausal import Experiment, Model, simulate
from acausal.library.blocks.booleans import BooleanStep
from acausal.library.blocks.continuous import Der, FirstOrder, Init, Integrator, LimIntegrator
from acausal.library.blocks.discrete import Sampler, StateSpace, TransferFunction, UnitDelay, ZeroOrderHold
from acausal.library.blocks.nonlinear import DeadZone, Limiter, SlewRateLimiter, VariableLimiter
from acausal.library.blocks.sources import (
    CombiTimeTable,
    Constant,
    Extrapolation,
    Pulse,
    Ramp,
    SawTooth,
    Smoothness,
    TimeTable,
    Trapezoid,
)
from acausal.tools.compare import compare_signals, load_reference, reference_dir

def _reference_or_skip(modelica_class: str):
    """The reference (bundled, or from $ACAUSAL_REFERENCE_DIR), or a skip saying where it was looked for."""
    if not (reference_dir() / modelica_class).is_dir():
        pytest.skip(f"MSL reference results of {modelica_class} not found in {reference_dir()} "
                    f"(ACAUSAL_REFERENCE_DIR)")
    return load_reference(modelica_class)


def _row_at(result, t: float) -> int:
    """The index of the last row at time ``t`` (the right limit of an event there)."""
    return int(np.searchsorted(result.time, t, side="right")) - 1


def _event_times(result, kind: str | None = None) -> np.ndarray:
    return np.array([float(e.time) for e in result.events
                     if e.kind != "initial" and (kind is None or e.kind == kind)])


# --------------------------------------------------------------------------
# the ModelicaTest examples


@pytest.mark.parametrize("module, name", [("blocks_discrete", "Discrete"),
                                          ("blocks_reset_integrator", "ResetHoldIntegrator")])
def test_example_matches_reference(module, name):
    """Every compared signal of the example lies in the csv-compare tube of the reference."""
    model_class = getattr(importlib.import_module(f"examples.{module}"), name)
    reference = _reference_or_skip(model_class.modelica_class)
    result = simulate(model_class())
    assert result.success, result.message
    comparison = compare_signals(reference, result.time, result.columns)
    assert comparison.passed, comparison.table()


def test_discrete_example_values_at_the_first_samples():
    """The reference's values at t = 0, 0.02, 0.04 (docs/msl-blocks-hybrid.md, 8.3), to round-off."""
    from examples.blocks_discrete import Discrete

    r = simulate(Discrete())
    u1, u2 = math.sin(0.12 * math.pi), math.sin(0.24 * math.pi)
    at0, at1, at2 = _row_at(r, 0.0), _row_at(r, 0.02), _row_at(r, 0.04)
    for block in ("sampler", "zeroOrderHold", "firstOrderHold", "unitDelay", "transferFunction",
                  "stateSpace"):
        # the sample at t = 0 fires right after initialization; the second one ends the first
        assert r[f"{block}.firstTrigger"][at0] == 1 and r[f"{block}.firstTrigger"][at1] == 0
    assert r["triggeredSampler.y"][at0] == 2  # its trigger is already true at t = 0: no firing
    assert r["unitDelay.y"][at1] == pytest.approx(u1, abs=1e-14)  # pre(u) of a continuous u: u(t_k)
    assert r["firstOrderHold.c"][at1] == pytest.approx(u1 / 0.02, rel=1e-12)
    assert r["firstOrderHold.c"][at2] == pytest.approx((u2 - u1) / 0.02, rel=1e-12)
    assert r["transferFunction.x1"][at2] == pytest.approx(u2 - 0.1 * u1, rel=1e-12)
    assert r["transferFunction.y"][at2] == pytest.approx(u1, rel=1e-12)
    assert r["stateSpace.x[2]"][at1] == pytest.approx(2 * u1, rel=1e-12)
    assert r["stateSpace.y[1]"][at1] == pytest.approx(0.1 * u1, rel=1e-12)
    assert r["stateSpace.y[1]"][at2] == pytest.approx(2 * 0 + 3 * 2 * u1 + 0.1 * u2, rel=1e-12)
    # the last sample is at the stop time, and is processed
    assert r.time[-1] == pytest.approx(1.1) and r["sampler.y"][-1] == pytest.approx(math.sin(6.6 * math.pi))


def test_reset_hold_integrator_resets_at_each_falling_edge():
    """y = 2 (t - k) on [k, k + 0.5), reset to 0 at k + 0.5 and held there until k + 1."""
    from examples.blocks_reset_integrator import ResetHoldIntegrator

    r = simulate(ResetHoldIntegrator())
    t, y = r.time, r["integrator.y"]
    phase = t - np.floor(t)
    rising = phase < 0.5 - 1e-9
    expected = np.where(rising, 2 * phase, 0.0)
    plain = np.ones_like(t, dtype=bool)
    for e in _event_times(r):
        plain &= np.abs(t - e) > 1e-9
    np.testing.assert_allclose(y[plain], expected[plain], atol=1e-8)
    # one reset per falling edge, from 1 to 0; the pulse's end ``time < pulseStart + Twidth`` is a
    # relation with a discrete variable, located as a state event (to 1e-10 relative, see the report)
    resets = [(e.time, before, after) for e in r.events for name, before, after in e.changes
              if name == "reinit(integrator.y)"]
    np.testing.assert_allclose([te for te, _, _ in resets], np.arange(5) + 0.5, rtol=0, atol=1e-9)
    for te, before, after in resets:
        assert before == pytest.approx(1.0, abs=1e-8) and after == 0.0
        rows = np.flatnonzero(t == te)
        assert len(rows) == 2 and y[rows[0]] == before and y[rows[1]] == 0.0


# --------------------------------------------------------------------------
# discrete blocks against closed forms


class RampHold(Model):
    """A ramp u = t sampled and held every 0.1 s from 0.05 s on."""

    experiment = Experiment(stop_time=1.0, interval=0.01)

    def build(self):
        self.ramp = Ramp(height=1e4, duration=1e4)
        self.zoh = ZeroOrderHold(samplePeriod=0.1, startTime=0.05)
        self.sampler = Sampler(samplePeriod=0.1, startTime=0.05)
        self.connect(self.ramp.y, self.zoh.u)
        self.connect(self.ramp.y, self.sampler.u)


def test_zero_order_hold_of_a_ramp_equals_the_ramp_at_the_samples_and_is_constant_between():
    r = simulate(RampHold())
    assert r.success, r.message
    t, held, sampled = r.time, r["zoh.ySample"], r["sampler.y"]
    ticks = 0.05 + 0.1 * np.arange(10)
    np.testing.assert_array_equal(_event_times(r, "time"), ticks)
    for k, tick in enumerate(ticks):
        rows = np.flatnonzero(t == tick)
        assert len(rows) == 2, f"an event gives a left and a right limit at {tick}"
        assert held[rows[-1]] == pytest.approx(tick, abs=1e-15)  # the ramp at the sample
        # the left limit holds the previous sample (0 = u(0) from the initialization)
        assert held[rows[0]] == pytest.approx(ticks[k - 1] if k else 0.0, abs=1e-15)
    # between the samples: constant, the ramp's value at the last sample
    between = ~np.isin(t, ticks)
    last = np.searchsorted(ticks, t[between], side="right") - 1
    expected = np.where(last >= 0, ticks[np.maximum(last, 0)], 0.0)
    np.testing.assert_allclose(held[between], expected, rtol=0, atol=1e-15)
    np.testing.assert_allclose(sampled[between], expected, rtol=0, atol=1e-15)
    # ZeroOrderHold.y = pre(ySample): equal to ySample outside the event iterations
    np.testing.assert_allclose(r["zoh.y"][between], held[between], rtol=0, atol=1e-15)


def test_sample_instants_are_exact_over_ten_thousand_periods():
    """Each tick is start + i*T, computed from i (never by adding up periods)."""
    start, period, n = 0.05, 0.1, 10_000
    r = simulate(RampHold(), stop_time=start + n * period, interval=start + n * period,
                 method="Euler", max_step=period)
    assert r.success, r.message
    found = _event_times(r, "time")
    expected = start + period * np.arange(n + 1)
    assert len(found) == n + 1
    np.testing.assert_array_equal(found, expected)
    # a sum of periods drifts: after 10^4 additions it is many ulps off the exact ticks
    drifted = np.cumsum(np.r_[start, np.full(n, period)])
    assert np.max(np.abs(drifted - expected)) > 10 * np.spacing(expected[-1])
    assert r["zoh.ySample"][-1] == expected[-1]  # the last tick at the stop time is processed


class DelayAndFilters(Model):
    """UnitDelay, TransferFunction and StateSpace of a constant input."""

    experiment = Experiment(stop_time=0.55, interval=0.01)

    def build(self):
        self.u = Constant(k=1.0)
        self.delay = UnitDelay(samplePeriod=0.1, y_start=-1.0)
        self.tf = TransferFunction(samplePeriod=0.1, b=(1.0, 0.0), a=(1.0, -0.5))  # z/(z - 0.5)
        self.ss = StateSpace(samplePeriod=0.1, A=[[0.5]], B=[[1.0, 2.0]], C=[[1.0], [3.0]],
                             D=[[0.0, 0.0], [1.0, 0.0]], x=dict(start=0, fixed=True))
        self.two = Constant(k=2.0)
        for target in (self.delay.u, self.tf.u, getattr(self.ss, "u[1]")):
            self.connect(self.u.y, target)
        self.connect(self.two.y, getattr(self.ss, "u[2]"))


def test_unit_delay_transfer_function_and_state_space_follow_their_recursions():
    r = simulate(DelayAndFilters())
    assert r.success, r.message
    assert {"ss.u[1]", "ss.u[2]", "ss.x[1]", "ss.y[1]", "ss.y[2]", "tf.x[1]", "tf.xext[2]"} <= set(r.names)
    assert r["delay.y"][0] == 1.0  # the t = 0 sample: pre(u) of the constant input
    # z/(z - 0.5) of a unit step sampled from k = 0: y_k = 2 - 0.5^k
    # state space: x_k = 0.5 x_{k-1} + 1 + 2*2 (x_0 = 5 at the first sample), y1 = x_{k-1}, y2 = 3 x_{k-1} + 1
    x_prev = 0.0
    for k in range(6):
        row = _row_at(r, 0.1 * k + 1e-9)
        assert r["tf.y"][row] == pytest.approx(2 - 0.5 ** k, rel=1e-13)
        x = 0.5 * x_prev + 5.0
        assert r["ss.x[1]"][row] == pytest.approx(x, rel=1e-13)
        assert r["ss.y[1]"][row] == pytest.approx(x_prev, abs=1e-13)
        assert r["ss.y[2]"][row] == pytest.approx(3 * x_prev + 1, rel=1e-13)
        x_prev = x


# --------------------------------------------------------------------------
# continuous blocks with hybrid parts


class ResetIntegrators(Model):
    """u = 1; a reset at t = 0.3 (rising edge of a BooleanStep) to y_start, or to the set input."""

    experiment = Experiment(stop_time=1.0, interval=0.01)

    def build(self):
        self.one = Constant(k=1.0)
        self.minus = Constant(k=-1.0)
        self.step = BooleanStep(startTime=0.3)
        self.toStart = Integrator(use_reset=True, y_start=0.5)
        self.toSet = Integrator(k=2.0, use_reset=True, use_set=True, y_start=0.25)
        self.plain = Integrator(y_start=0.5)
        self.limited = LimIntegrator(outMax=0.4, use_reset=True, y_start=2.0)  # reinit clamped to 0.4
        for block in (self.toStart, self.toSet, self.plain, self.limited):
            self.connect(self.one.y, block.u)
        for block in (self.toStart, self.toSet, self.limited):
            self.connect(self.step.y, block.reset)
        self.connect(self.minus.y, self.toSet.set)


def test_integrator_reset_returns_to_y_start_at_the_trigger():
    r = simulate(ResetIntegrators())
    assert r.success, r.message
    t = r.time
    before, after = t < 0.3 - 1e-12, t > 0.3 + 1e-12
    np.testing.assert_allclose(r["toStart.y"][before], 0.5 + t[before], atol=1e-9)
    np.testing.assert_allclose(r["toStart.y"][after], 0.5 + (t[after] - 0.3), atol=1e-9)
    np.testing.assert_allclose(r["toSet.y"][before], 0.25 + 2 * t[before], atol=1e-9)
    np.testing.assert_allclose(r["toSet.y"][after], -1.0 + 2 * (t[after] - 0.3), atol=1e-9)
    np.testing.assert_allclose(r["plain.y"], 0.5 + t, atol=1e-9)  # no reset input: the old Integrator
    rows = np.flatnonzero(t == 0.3)
    assert len(rows) == 2
    assert r["toStart.y"][rows[0]] == pytest.approx(0.8) and r["toStart.y"][rows[1]] == 0.5
    assert r["toSet.y"][rows[1]] == -1.0
    # the reset input stays true: no second reset
    assert sum(1 for e in r.events if any(n.startswith("reinit(toStart") for n, _, _ in e.changes)) == 1
    # the LimIntegrator starts at y_start = 2 above outMax (no limit at the start), rises no more,
    # is reset to the clamped value 0.4 and stays at its upper limit
    assert r["limited.y"][0] == 2.0 and r["limited.y"][rows[0]] == pytest.approx(2.0, abs=1e-9)
    np.testing.assert_allclose(r["limited.y"][after], 0.4, atol=1e-9)


class Lag(Model):
    """A first order lag of a unit step (initType = InitialState) and the derivative of its output."""

    experiment = Experiment(stop_time=1.0, interval=0.01)

    def build(self):
        self.one = Constant(k=1.0)
        self.lag = FirstOrder(k=2.0, T=0.2, initType=Init.InitialState, y_start=0.5)
        self.derivative = Der()
        self.connect(self.one.y, self.lag.u)
        self.connect(self.lag.y, self.derivative.u)


def test_first_order_and_der_follow_the_closed_form():
    r = simulate(Lag(), rtol=1e-9, atol=1e-12)
    t = r.time
    y = 2 + (0.5 - 2) * np.exp(-t / 0.2)
    np.testing.assert_allclose(r["lag.y"], y, atol=1e-7)
    np.testing.assert_allclose(r["derivative.y"], (2 - y) / 0.2, atol=1e-6)


# --------------------------------------------------------------------------
# nonlinear blocks


class Limiters(Model):
    """A ramp u = -2 + 2t through the limiters and the dead zone."""

    experiment = Experiment(stop_time=2.0, interval=0.01)

    def build(self):
        self.ramp = Ramp(height=4.0, duration=2.0, offset=-2.0)
        self.limiter = Limiter(uMax=1.0, uMin=-0.5)
        self.symmetric = Limiter(uMax=1.5)  # uMin = -uMax by default
        self.strict = Limiter(uMax=1.0, uMin=-0.5, strict=True)
        self.deadZone = DeadZone(uMax=0.5, uMin=-1.0)
        self.upper = Constant(k=0.5)
        self.lower = Constant(k=-1.0)
        self.variable = VariableLimiter()
        for block in (self.limiter, self.symmetric, self.strict, self.deadZone, self.variable):
            self.connect(self.ramp.y, block.u)
        self.connect(self.upper.y, self.variable.limit1)
        self.connect(self.lower.y, self.variable.limit2)


def test_limiter_and_dead_zone_follow_their_closed_form_on_a_ramp():
    r = simulate(Limiters())
    assert r.success, r.message
    u = r["ramp.y"]
    np.testing.assert_allclose(u, -2 + 2 * np.clip(r.time, 0, 2), atol=1e-12)
    np.testing.assert_allclose(r["limiter.y"], np.clip(u, -0.5, 1.0), atol=1e-9)
    np.testing.assert_allclose(r["strict.y"], np.clip(u, -0.5, 1.0), atol=1e-12)
    np.testing.assert_allclose(r["symmetric.y"], np.clip(u, -1.5, 1.5), atol=1e-9)
    np.testing.assert_allclose(r["variable.y"], np.clip(u, -1.0, 0.5), atol=1e-9)
    dead = np.where(u > 0.5, u - 0.5, np.where(u < -1.0, u + 1.0, 0.0))
    np.testing.assert_allclose(r["deadZone.y"], dead, atol=1e-9)
    # without strict the limits are state events (at u = -0.5 and 1.0: t = 0.75 and 1.5)
    limiter_events = [e.time for e in r.events if e.kind == "state"
                      and any("limiter" in rel for rel in e.relations)]
    assert any(abs(te - 0.75) < 1e-8 for te in limiter_events)
    assert any(abs(te - 1.5) < 1e-8 for te in limiter_events)


class Slew(Model):
    """A pulse 0 -> 1 at 0.1 s, back to 0 at 1.1 s through slew-rate limiters."""

    experiment = Experiment(stop_time=2.0, interval=0.005)

    def build(self):
        self.pulse = Pulse(period=2.0, width=50.0, startTime=0.1)
        self.slew = SlewRateLimiter(Rising=2.0, Falling=-1.0, Td=1e-3)
        self.symmetric = SlewRateLimiter(Rising=4.0, Td=1e-3)
        self.connect(self.pulse.y, self.slew.u)
        self.connect(self.pulse.y, self.symmetric.u)


def test_slew_rate_limiter_keeps_its_slope_within_the_bounds():
    r = simulate(Slew())
    assert r.success, r.message
    t = r.time
    for name, rising, falling in (("slew.y", 2.0, -1.0), ("symmetric.y", 4.0, -4.0)):
        y = r[name]
        dt, dy = np.diff(t), np.diff(y)
        steps = dt > 1e-9
        slope = dy[steps] / dt[steps]
        assert slope.max() <= rising * (1 + 1e-6) and slope.min() >= falling * (1 + 1e-6), name
        assert slope.max() == pytest.approx(rising, rel=1e-6)
        assert slope.min() == pytest.approx(falling, rel=1e-6)
        assert y[0] == 0.0  # initType = SteadyState: y = u at the start
    y = r["slew.y"]
    # the rate limit holds until y is within Rising*Td of the input: the closed form there
    assert y[_row_at(r, 0.3)] == pytest.approx(2.0 * 0.2, abs=1e-6)
    assert y[_row_at(r, 1.5)] == pytest.approx(1.0 - 0.4, abs=1e-6)


# --------------------------------------------------------------------------
# periodic and table sources


class Sources(Model):
    experiment = Experiment(stop_time=3.0, interval=0.01)

    def build(self):
        self.pulse = Pulse(amplitude=2.0, width=30.0, period=0.5, offset=1.0, startTime=0.2)
        self.saw = SawTooth(amplitude=3.0, period=0.4, nperiod=3)
        self.trapezoid = Trapezoid(rising=0.2, width=0.3, falling=0.1, period=1.0)
        self.square = Trapezoid(period=1.0)  # rising = falling = 0: no division by zero
        self.timeTable = TimeTable(table=[[0, 0], [1, 1], [1, 3], [2, 4]], startTime=0.5)
        self.combi = CombiTimeTable(table=[[0, 0, 1], [1, 1, 2], [1, 3, 0], [2, 4, 5]], offset=[0, 10])
        self.held = CombiTimeTable(table=[[0.5, 1], [1.5, 3]], extrapolation=Extrapolation.HoldLastPoint,
                                   smoothness=Smoothness.ConstantSegments)


def test_periodic_and_table_sources_follow_their_closed_forms():
    r = simulate(Sources())
    assert r.success, r.message
    t = r.time
    event = np.zeros_like(t, dtype=bool)
    for e in _event_times(r):
        event |= np.abs(t - e) < 1e-8
    ok = ~event

    def check(name, expected):
        np.testing.assert_allclose(r[name][ok], expected[ok], atol=1e-9, err_msg=name)

    phase = np.mod(t - 0.2, 0.5)
    check("pulse.y", np.where((t >= 0.2) & (phase < 0.15), 3.0, 1.0))
    check("saw.y", np.where(t < 1.2, 3.0 * np.mod(t, 0.4) / 0.4, 0.0))
    tau = np.mod(t, 1.0)
    check("trapezoid.y", np.interp(tau, [0, 0.2, 0.5, 0.6, 1.0], [0, 1, 1, 0, 0]))
    check("square.y", np.where(tau < 0.5, 1.0, 0.0))
    s = t - 0.5  # TimeTable: shiftTime = startTime = 0.5
    check("timeTable.y", np.where(t < 0.5, 0.0, np.where(s < 1, s, 3 + (s - 1))))
    check("combi.y[1]", np.where(t < 1, t, 3 + (t - 1)))
    check("combi.y[2]", 10 + np.where(t < 1, 1 + t, 5 * (t - 1)))
    check("held.y[1]", np.where(t < 1.5, 1.0, 3.0))
    # the table times and the period starts are exact time events
    times = set(_event_times(r, "time").tolist())
    assert {0.2, 0.7, 1.2, 1.0, 1.5, 2.0, 2.5} <= times
