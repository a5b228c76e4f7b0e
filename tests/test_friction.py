"""Friction elements (BearingFriction, Clutch, Brake) and the hybrid-simulation failure modes.

Every expected value below is derived by hand from the equations of motion
(Coulomb friction with constant characteristics gives piecewise-polynomial or
closed-form trigonometric motion) or from a conserved quantity (energy,
angular momentum); none comes from running the code under test.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import sympy as sp

from acausal import Model, simulate
from acausal.errors import ChatteringError, EventIterationError, ParameterError
from acausal.language import Boolean, Eq, If, Integer, Variable, der, pre
from acausal.language import time as time_symbol
from acausal.compiler.translate import translate
from acausal.components.friction import Forward, Free, Stuck
from acausal.components.logic import pre_boolean
from acausal.library.blocks import Constant, Sine, Step
from acausal.library.rotational import (
    BearingFriction,
    Brake,
    Clutch,
    ConstantTorque,
    Fixed,
    IdealGear,
    Inertia,
    Torque,
)
from acausal.library.thermal import HeatCapacitor

REST = dict(start=0, fixed=True)
METHODS = ("DOP853", "RK45")


# --------------------------------------------------------------------------
# helpers


def mode_events(result, name, old, new):
    """Events whose changes include ``name: old -> new``."""
    return [e for e in result.events if (name, old, new) in e.changes]


def right_limit_index(result, t_event):
    """Index of the last output row at ``t_event`` (the right limit of the event)."""
    rows = np.flatnonzero(result.time == t_event)
    assert rows.size >= 1, f"no output row at the event time {t_event!r}"
    return int(rows[-1])


# --------------------------------------------------------------------------
# 1. coast-down against constant Coulomb friction


J_C, W0_C, TAU0_C = 2.0, 3.0, 1.5
T_STOP_C = J_C * W0_C / TAU0_C  # = 4 s


class CoastDown(Model):
    """An inertia spinning at w0 decelerated by a constant bearing friction torque tau0."""

    def build(self):
        self.inertia = Inertia(J=J_C, phi=REST, w=dict(start=W0_C, fixed=True))
        self.bearingFriction = BearingFriction(tau_pos=[[0, TAU0_C]])
        self.connect(self.inertia.flange_b, self.bearingFriction.flange_a)


@pytest.mark.parametrize("method", METHODS)
def test_coast_down_stops_at_exact_time_and_stays_stuck(method):
    """w = w0 - tau0 t/J until t* = J w0/tau0, the 1->0 mode event is located at t*, then it stays stuck."""
    result = simulate(CoastDown(), stop_time=2 * T_STOP_C, interval=T_STOP_C / 100, method=method,
                      rtol=1e-10)
    assert result.status == 0, result.message
    stops = mode_events(result, "bearingFriction.mode", Forward, Stuck)
    assert len(stops) == 1, [str(e) for e in result.events]
    t_e = stops[0].time
    assert abs(t_e - T_STOP_C) <= 1e-9
    assert stops[0].kind == "state"

    t, w, phi = result.time, result["inertia.w"], result["inertia.phi"]
    mode = result["bearingFriction.mode"]
    before = t < t_e
    assert before.sum() >= 100
    np.testing.assert_allclose(w[before], W0_C - TAU0_C * t[before] / J_C, rtol=0, atol=1e-8)
    np.testing.assert_allclose(phi[before], W0_C * t[before] - TAU0_C * t[before] ** 2 / (2 * J_C),
                               rtol=0, atol=1e-8)
    assert np.all(mode[before] == Forward)

    after = slice(right_limit_index(result, t_e), None)
    assert t[-1] == pytest.approx(2 * T_STOP_C)
    assert np.max(np.abs(w[after])) <= 1e-8
    assert np.all(mode[after] == Stuck)
    # stopping angle J w0^2 / (2 tau0) = 6 rad, held to the end
    np.testing.assert_allclose(phi[after], J_C * W0_C ** 2 / (2 * TAU0_C), rtol=0, atol=1e-8)
    # no discrete change after the stop
    assert not [e for e in result.events if e.time > t_e and e.changes]


# --------------------------------------------------------------------------
# 2. breakaway from rest under a constant torque


def breakaway_model(T, tau0, peak, J):
    class Breakaway(Model):
        """An inertia at rest, a constant torque T against BearingFriction(tau0, peak)."""

        def build(self):
            self.torque = ConstantTorque(tau_constant=T)
            self.inertia = Inertia(J=J, phi=REST, w=REST)
            self.bearingFriction = BearingFriction(tau_pos=[[0, tau0]], peak=peak)
            self.connect(self.torque.flange, self.inertia.flange_a)
            self.connect(self.inertia.flange_b, self.bearingFriction.flange_a)

    return Breakaway()


@pytest.mark.parametrize("T, tau0, peak", [(1.4, 1.0, 1.5), (1.0, 1.0, 1.0), (-1.4, 1.0, 1.5)],
                         ids=["below-peak", "exactly-tau0-peak1", "below-peak-negative"])
def test_torque_below_static_limit_never_moves(T, tau0, peak):
    """|T| <= peak*tau0 (strict start condition sa > tau0_max): the inertia stays exactly at rest, mode Stuck."""
    result = simulate(breakaway_model(T, tau0, peak, J=2.0), stop_time=2.0, interval=0.01,
                      method="DOP853", rtol=1e-10)
    assert result.status == 0, result.message
    assert np.max(np.abs(result["inertia.w"])) < 1e-12
    assert np.max(np.abs(result["inertia.phi"])) < 1e-12
    assert np.all(result["bearingFriction.mode"] == Stuck)
    assert not any(e.changes for e in result.events if e.kind == "state")
    # the friction torque holds the load: sa = T exactly (J*a = T - sa with a = 0)
    np.testing.assert_allclose(result["bearingFriction.sa"], T, rtol=0, atol=1e-12)


@pytest.mark.parametrize("T", [2.0, -2.0])
def test_torque_above_static_limit_breaks_away_at_once(T):
    """|T| > peak*tau0: sliding starts at t = 0 and w = (T - sign(T) tau0) t / J exactly."""
    tau0, peak, J = 1.0, 1.5, 2.0
    result = simulate(breakaway_model(T, tau0, peak, J), stop_time=2.0, interval=0.01,
                      method="DOP853", rtol=1e-10)
    assert result.status == 0, result.message
    start = "bearingFriction.startForward" if T > 0 else "bearingFriction.startBackward"
    sliding = Forward if T > 0 else -1
    assert mode_events(result, start, False, True)[0].time == 0.0
    entered = mode_events(result, "bearingFriction.mode", Stuck, sliding)
    assert len(entered) == 1 and entered[0].time < 1e-9
    t = result.time
    np.testing.assert_allclose(result["inertia.w"], (T - math.copysign(tau0, T)) * t / J, rtol=0,
                               atol=1e-8)
    after = slice(right_limit_index(result, entered[0].time), None)
    assert np.all(result["bearingFriction.mode"][after] == sliding)


# --------------------------------------------------------------------------
# 3. breakaway under a sine torque


def sine_breakaway_model(A, f, tau0, peak, J):
    class SineBreakaway(Model):
        """An inertia at rest driven by A sin(2 pi f t) against BearingFriction(tau0, peak)."""

        def build(self):
            self.sine = Sine(amplitude=A, f=f)
            self.torque = Torque()
            self.inertia = Inertia(J=J, phi=REST, w=REST)
            self.bearingFriction = BearingFriction(tau_pos=[[0, tau0]], peak=peak)
            self.connect(self.sine.y, self.torque.tau)
            self.connect(self.torque.flange, self.inertia.flange_a)
            self.connect(self.inertia.flange_b, self.bearingFriction.flange_a)

    return SineBreakaway()


def check_sine_breakaway(A, f, tau0, peak, J, method):
    result = simulate(sine_breakaway_model(A, f, tau0, peak, J), stop_time=0.5, interval=1e-3,
                      method=method, rtol=1e-10)
    assert result.status == 0, result.message
    t_b = math.asin(peak * tau0 / A) / (2 * math.pi * f)
    starts = mode_events(result, "bearingFriction.startForward", False, True)
    assert starts, [str(e) for e in result.events]
    assert abs(starts[0].time - t_b) <= 1e-9
    # before t_b nothing moves
    t, w = result.time, result["inertia.w"]
    assert np.max(np.abs(w[t < t_b])) < 1e-12
    # then J dw/dt = A sin(2 pi f t) - tau0 until the next mode change:
    # w(t) = [A (cos(2 pi f t_b) - cos(2 pi f t)) / (2 pi f) - tau0 (t - t_b)] / J
    later = [e.time for e in result.events if e.time > starts[0].time and e.changes
             and any(n == "bearingFriction.mode" and b != Forward for n, _, b in e.changes)]
    t_end = later[0] if later else np.inf
    sel = (t > starts[0].time) & (t < t_end)
    assert sel.sum() > 50
    wf = 2 * math.pi * f
    exact = (A * (math.cos(wf * t_b) - np.cos(wf * t[sel])) / wf - tau0 * (t[sel] - t_b)) / J
    np.testing.assert_allclose(w[sel], exact, rtol=0, atol=1e-8)


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("peak, J", [(1.0, 1.0), (1.0, 0.5), (1.5, 1.0), (1.5, 2.0)])
def test_sine_breakaway_time(peak, J, method):
    """A sin(2 pi f t) first exceeds peak*tau0 at t_b = asin(peak tau0/A)/(2 pi f); motion then follows the exact integral."""
    check_sine_breakaway(A=10.0, f=1.0, tau0=1.0, peak=peak, J=J, method=method)


def test_sine_breakaway_time_peak1_heavy_inertia():
    """Same as test_sine_breakaway_time with the default peak = 1 and J = 2: must break away at t_b."""
    check_sine_breakaway(A=10.0, f=1.0, tau0=1.0, peak=1.0, J=2.0, method="DOP853")


# --------------------------------------------------------------------------
# 4. energy balance with the heat port


C_HEAT, T_HEAT0, J_E = 2.0, 300.0, 1.0


class FrictionEnergy(Model):
    """Sine torque on an inertia against bearing friction whose losses heat a capacitor.

    ``W`` integrates the power of the torque source exactly, inside the model.
    """

    W = Variable(start=0.0, fixed=True, unit="J", description="Work done by the torque source")

    def build(self):
        self.sine = Sine(amplitude=5, f=1)
        self.torque = Torque()
        self.inertia = Inertia(J=J_E, phi=REST, w=REST)
        self.bearingFriction = BearingFriction(useHeatPort=True, tau_pos=[[0, 1], [10, 2]])
        self.heatCapacitor = HeatCapacitor(C=C_HEAT, T=dict(start=T_HEAT0, fixed=True))
        self.connect(self.sine.y, self.torque.tau)
        self.connect(self.torque.flange, self.inertia.flange_a)
        self.connect(self.inertia.flange_b, self.bearingFriction.flange_a)
        self.connect(self.bearingFriction.heatPort, self.heatCapacitor.port)

    def equations(self):
        return [Eq(der(self.W), self.torque.tau * self.inertia.w)]


@pytest.mark.parametrize("method", METHODS)
def test_energy_balance_with_heat_port(method):
    """Work of the source = kinetic energy + heat stored in the capacitor, at every output point."""
    result = simulate(FrictionEnergy(), stop_time=3.0, interval=0.01, method=method, rtol=1e-10)
    assert result.status == 0, result.message
    W = result["W"]
    kinetic = 0.5 * J_E * result["inertia.w"] ** 2
    heat = C_HEAT * (result["heatCapacitor.T"] - T_HEAT0)
    scale = np.max(np.abs(W))
    assert scale > 1.0  # the inertia really moved and the bearing really dissipated
    assert np.max(np.abs(W - kinetic - heat)) <= 1e-6 * scale
    assert abs(W[-1] - kinetic[-1] - heat[-1]) <= 1e-6 * scale
    # friction only dissipates: the capacitor temperature never decreases
    assert np.all(np.diff(result["heatCapacitor.T"]) >= -1e-12)
    # several slip reversals happened, so the balance is checked across events
    reversals = [e for e in result.events if any(n == "bearingFriction.mode" for n, _, _ in e.changes)]
    assert len(reversals) >= 4


# --------------------------------------------------------------------------
# 5. knife edge: ModelicaTest.Rotational.ForUsersGuide.SupportTorque1


class SupportTorque1(Model):
    """ModelicaTest.Rotational.ForUsersGuide.SupportTorque1 (spec section 6.3)."""

    modelica_class = "ModelicaTest.Rotational.ForUsersGuide.SupportTorque1"

    def build(self):
        self.sine2 = Sine(f=1)
        self.torque2 = Torque(useSupport=True)
        self.fixed1 = Fixed()
        self.inertia3 = Inertia(J=1, phi=REST, w=REST)
        self.idealGear2 = IdealGear(ratio=1, useSupport=True)
        self.inertia4 = Inertia(J=1)
        self.bearingFriction1 = BearingFriction(useSupport=True)
        self.connect(self.sine2.y, self.torque2.tau)
        self.connect(self.torque2.support, self.fixed1.flange)
        self.connect(self.torque2.flange, self.inertia3.flange_a)
        self.connect(self.fixed1.flange, self.idealGear2.support)
        self.connect(self.inertia3.flange_b, self.idealGear2.flange_a)
        self.connect(self.idealGear2.flange_b, self.bearingFriction1.flange_a)
        self.connect(self.bearingFriction1.flange_b, self.inertia4.flange_a)
        self.connect(self.fixed1.flange, self.bearingFriction1.support)


@pytest.mark.parametrize("method, rtol", [("RK45", 1e-6), ("DOP853", 1e-10)])
def test_support_torque1_knife_edge_never_slips(method, rtol):
    """sa = sin(2 pi t) touches tau0_max = 1 exactly at t = 0.25 (and -1 at 0.75); the strict start condition never fires."""
    result = simulate(SupportTorque1(), stop_time=1.1, interval=2.2e-4, method=method, rtol=rtol)
    assert result.status == 0, result.message
    assert not [e for e in result.events if e.kind == "state"]
    assert not [e for e in result.events if e.changes]
    assert np.all(result["bearingFriction1.mode"] == Stuck)
    assert np.all(result["bearingFriction1.startForward"] == 0)
    assert np.all(result["bearingFriction1.startBackward"] == 0)
    assert np.max(np.abs(result["inertia4.w"])) < 1e-12
    assert np.max(np.abs(result["inertia4.phi"])) < 1e-12
    # the whole input torque reaches the locked bearing
    np.testing.assert_allclose(result["bearingFriction1.sa"], np.sin(2 * np.pi * result.time),
                               rtol=0, atol=1e-12)


# --------------------------------------------------------------------------
# 6. event-iteration limit


class FlipFlop(Model):
    """From t = 0.5 on, b = not pre(b): event iteration can never reach a fixed point."""

    x = Variable(start=0.0, fixed=True)
    b = Boolean(start=False, fixed=True)

    def equations(self):
        return [Eq(der(self.x), 1),
                Eq(self.b, sp.And(time_symbol >= 0.5, sp.Not(pre_boolean(self.b))))]


@pytest.mark.parametrize("limit", [20, 5])
def test_event_iteration_limit_reported_with_partial_result(limit):
    """A discrete variable that flips on every iteration ends the run at t = 0.5 with EventIterationError naming it."""
    result = simulate(FlipFlop(), stop_time=1.0, interval=0.1, max_event_iterations=limit)
    assert result.status == -1
    assert isinstance(result.error, EventIterationError)
    assert result.error.result is result
    assert "still changing: b" in result.message
    assert f"in {limit} iterations" in result.message
    assert "t = 0.5 " in result.message
    # rows up to the failure are kept, and they are right: x = t, b = False
    assert result.time.size >= 6
    assert result.time[-1] == pytest.approx(0.5, abs=1e-12)
    np.testing.assert_allclose(result["x"], result.time, rtol=0, atol=1e-12)
    assert np.all(result["b"] == 0)
    with pytest.raises(EventIterationError):
        result.raise_for_status()


class Counter(Model):
    """At t = 0.5 event iteration increments n until it reaches 7 (7 changes, then a confirming pass)."""

    x = Variable(start=0.0, fixed=True)
    n = Integer(start=0, fixed=True)

    def equations(self):
        return [Eq(der(self.x), 1),
                Eq(self.n, If(sp.And(time_symbol >= 0.5, pre(self.n) < 7), pre(self.n) + 1, pre(self.n)))]


def test_max_event_iterations_is_honoured():
    """A fixed point 7 iterations away is reached with a limit of 20 and refused with limits of 3 and 6."""
    ok = simulate(Counter(), stop_time=1.0, interval=0.25, max_event_iterations=20)
    assert ok.status == 0, ok.message
    (event,) = [e for e in ok.events if e.changes]
    assert event.time == 0.5 and event.changes == (("n", 0, 7),)
    assert ok.final("n") == 7
    np.testing.assert_array_equal(ok["n"][ok.time < 0.5], 0)
    for limit in (3, 6):
        bad = simulate(Counter(), stop_time=1.0, interval=0.25, max_event_iterations=limit)
        assert bad.status == -1
        assert isinstance(bad.error, EventIterationError)
        assert "still changing: n" in bad.message and f"in {limit} iterations" in bad.message
        assert bad.time[-1] == 0.5 and np.all(bad["n"] == 0)


class AlgebraicLoop(Model):
    """When x > 0.5: a = not b and b = a, a discrete algebraic loop with no solution."""

    x = Variable(start=0.0, fixed=True)
    a = Boolean()
    b = Boolean()

    def equations(self):
        return [Eq(der(self.x), 1), Eq(self.a, sp.And(self.x > 0.5, sp.Not(self.b))), Eq(self.b, self.a)]


def test_discrete_algebraic_loop_without_solution_fails():
    """a = not b, b = a has no solution once x > 0.5: status -1 with EventIterationError near t = 0.5."""
    result = simulate(AlgebraicLoop(), stop_time=1.0, interval=0.1)
    assert result.status == -1
    assert isinstance(result.error, EventIterationError)
    assert result.time[-1] == pytest.approx(0.5, abs=1e-9)
    np.testing.assert_allclose(result["x"], result.time, rtol=0, atol=1e-12)


def test_discrete_algebraic_loop_message_names_variables():
    """The EventIterationError of the a/b loop lists a and b as the variables still changing."""
    result = simulate(AlgebraicLoop(), stop_time=1.0, interval=0.1)
    assert "still changing: a, b" in result.message


# --------------------------------------------------------------------------
# 7. chattering


def chatter_model(slope):
    class Chatter(Model):
        """der(x) = -slope if x > 0 else slope, from x = 0: Zeno switching at x = 0."""

        x = Variable(start=0.0, fixed=True)

        def equations(self):
            return [Eq(der(self.x), If(self.x > 0, -slope, slope))]

    return Chatter()


def test_chattering_detected_with_partial_result():
    """Fast sign switching of der(x) around x = 0 stops with ChatteringError naming 'x > 0'; x stayed at 0."""
    result = simulate(chatter_model(1000.0), stop_time=1.0, interval=0.1, chattering_events=50)
    assert result.status == -1
    assert isinstance(result.error, ChatteringError)
    assert result.error.result is result
    assert "x > 0" in result.message
    state_events = [e for e in result.events if e.kind == "state"]
    # the run stops at the 50th crossing (that one may or may not be recorded)
    assert 49 <= len(state_events) <= 50
    assert all(e.relations == ("x > 0",) for e in state_events)
    assert result.time.size > 2 and result.time[-1] < 1e-9
    # the trajectory is pinned to the switching surface (within the relation hysteresis)
    assert np.max(np.abs(result["x"])) < 1e-9


def test_chattering_detected_at_unit_slope():
    """der(x) = -1 if x > 0 else 1: 500 state events in 1e-7 s must be reported as chattering."""
    result = simulate(chatter_model(1.0), stop_time=1e-7, interval=1e-8, chattering_events=50)
    assert result.status == -1
    assert isinstance(result.error, ChatteringError)


# --------------------------------------------------------------------------
# 8. parameter errors


def bearing_model(**modifiers):
    class Bearing(Model):
        def build(self):
            self.inertia = Inertia(J=1, phi=REST, w=dict(start=1, fixed=True))
            self.bearingFriction = BearingFriction(**modifiers)
            self.connect(self.inertia.flange_b, self.bearingFriction.flange_a)

    return Bearing()


def normal_force_model(element, name, **modifiers):
    class WithNormalForce(Model):
        def build(self):
            self.inertia = Inertia(J=1, phi=REST, w=dict(start=1, fixed=True))
            setattr(self, name, element(**modifiers))
            part = getattr(self, name)
            self.const = Constant(k=1)
            self.connect(self.inertia.flange_b, part.flange_a)
            self.connect(self.const.y, part.f_normalized)
            if element is Clutch:
                self.inertia2 = Inertia(J=1, phi=REST, w=REST)
                self.connect(part.flange_b, self.inertia2.flange_a)

    return WithNormalForce()


@pytest.mark.parametrize("modifiers, words", [
    (dict(tau_pos=[]), ["bearingFriction.tau_pos", "empty"]),
    (dict(tau_pos=[[0, 1, 2]]), ["bearingFriction.tau_pos", "n x 2"]),
    (dict(tau_pos=[[0, 1], [0, 2]]), ["bearingFriction.tau_pos", "strictly increasing"]),
    (dict(tau_pos=[[0, 1], [2, 1], [1, 1]]), ["bearingFriction.tau_pos", "strictly increasing"]),
    (dict(tau_pos=[[-1, 1], [1, 1]]), ["bearingFriction.tau_pos", "-1"]),
    (dict(tau_pos=[[0, float("nan")]]), ["bearingFriction.tau_pos", "non-finite"]),
    (dict(peak=0.5), ["bearingFriction.peak", "0.5"]),
], ids=["empty", "not-n-by-2", "repeated-w", "decreasing-w", "negative-w", "nan", "peak"])
def test_bearing_friction_parameter_errors(modifiers, words):
    """Malformed tau_pos tables and peak < 1 raise ParameterError naming the component and parameter."""
    with pytest.raises(ParameterError) as info:
        translate(bearing_model(**modifiers))
    for word in words:
        assert word in str(info.value)


@pytest.mark.parametrize("element, name, modifiers, words", [
    (Clutch, "clutch", dict(fn_max=-1), ["clutch.fn_max", "-1"]),
    (Brake, "brake", dict(fn_max=-1), ["brake.fn_max", "-1"]),
    (Clutch, "clutch", dict(peak=0.5), ["clutch.peak", "0.5"]),
    (Brake, "brake", dict(mu_pos=[[0, 0.5], [0, 0.4]]), ["brake.mu_pos", "strictly increasing"]),
])
def test_clutch_and_brake_parameter_errors(element, name, modifiers, words):
    """fn_max < 0, peak < 1 and bad mu_pos raise ParameterError (from translate and from simulate)."""
    for run in (translate, simulate):
        with pytest.raises(ParameterError) as info:
            run(normal_force_model(element, name, **modifiers))
        for word in words:
            assert word in str(info.value)
    assert issubclass(ParameterError, ValueError)


def test_parameter_error_through_bound_expression():
    """peak bound to a model parameter of value 0.5 is caught as well, naming bearingFriction.peak."""
    from acausal import Parameter

    class Bound(Model):
        p = Parameter(0.5)

        def build(self):
            self.inertia = Inertia(J=1, phi=REST, w=dict(start=1, fixed=True))
            self.bearingFriction = BearingFriction(peak=self.p)
            self.connect(self.inertia.flange_b, self.bearingFriction.flange_a)

    with pytest.raises(ParameterError, match=r"bearingFriction\.peak"):
        translate(Bound())


# --------------------------------------------------------------------------
# 9. Clutch and Brake are free when fn <= 0


class FreeClutch(Model):
    """Two inertias at different speeds joined by a clutch whose normal force is zero."""

    def build(self):
        self.inertia1 = Inertia(J=1, phi=REST, w=dict(start=3, fixed=True))
        self.clutch = Clutch(fn_max=100)
        self.inertia2 = Inertia(J=2, phi=REST, w=dict(start=-1, fixed=True))
        self.const = Constant(k=0)
        self.connect(self.inertia1.flange_b, self.clutch.flange_a)
        self.connect(self.clutch.flange_b, self.inertia2.flange_a)
        self.connect(self.const.y, self.clutch.f_normalized)


class FreeBrake(Model):
    """A spinning inertia with a brake whose normalized force is negative (fn < 0)."""

    def build(self):
        self.inertia1 = Inertia(J=1, phi=REST, w=dict(start=3, fixed=True))
        self.brake = Brake(fn_max=100)
        self.const = Constant(k=-0.5)
        self.connect(self.inertia1.flange_b, self.brake.flange_a)
        self.connect(self.const.y, self.brake.f_normalized)


def test_clutch_with_zero_normal_force_is_free():
    """fn = 0: the clutch transmits nothing, both speeds stay constant, mode == Free throughout."""
    result = simulate(FreeClutch(), stop_time=2.0, interval=0.01, rtol=1e-10)
    assert result.status == 0, result.message
    t = result.time
    np.testing.assert_allclose(result["inertia1.w"], 3.0, rtol=0, atol=1e-12)
    np.testing.assert_allclose(result["inertia2.w"], -1.0, rtol=0, atol=1e-12)
    np.testing.assert_allclose(result["inertia1.phi"], 3.0 * t, rtol=0, atol=1e-10)
    np.testing.assert_allclose(result["inertia2.phi"], -1.0 * t, rtol=0, atol=1e-10)
    np.testing.assert_allclose(result["clutch.tau"], 0.0, rtol=0, atol=0)
    assert np.all(result["clutch.mode"] == Free)
    assert np.all(result["clutch.free"] == 1)
    assert not [e for e in result.events if e.kind == "state"]


def test_brake_with_negative_normal_force_is_free():
    """fn < 0: the brake is free (tau = 0), the inertia keeps its speed, mode == Free throughout."""
    result = simulate(FreeBrake(), stop_time=2.0, interval=0.01, rtol=1e-10)
    assert result.status == 0, result.message
    np.testing.assert_allclose(result["inertia1.w"], 3.0, rtol=0, atol=1e-12)
    np.testing.assert_allclose(result["brake.tau"], 0.0, rtol=0, atol=0)
    assert np.all(result["brake.mode"] == Free)


class EngagingClutch(Model):
    """The clutch of FreeClutch engaged by a unit step of f_normalized at t = 0.5."""

    def build(self):
        self.inertia1 = Inertia(J=1, phi=REST, w=dict(start=3, fixed=True))
        self.clutch = Clutch(fn_max=100)  # mu = 0.5: sliding torque 50 N.m
        self.inertia2 = Inertia(J=2, phi=REST, w=dict(start=-1, fixed=True))
        self.step = Step(startTime=0.5)
        self.connect(self.inertia1.flange_b, self.clutch.flange_a)
        self.connect(self.clutch.flange_b, self.inertia2.flange_a)
        self.connect(self.step.y, self.clutch.f_normalized)


@pytest.mark.parametrize("method", METHODS)
def test_clutch_engagement_conserves_momentum_and_locks_on_time(method):
    """Free until 0.5 s, then 50 N.m slip torque: lock at 0.5 + 4/75 s at the common speed 1/3, momentum J1 w1 + J2 w2 = 1 throughout."""
    result = simulate(EngagingClutch(), stop_time=1.0, interval=0.01, method=method, rtol=1e-10)
    assert result.status == 0, result.message
    t, w1, w2 = result.time, result["inertia1.w"], result["inertia2.w"]
    np.testing.assert_allclose(1.0 * w1 + 2.0 * w2, 1.0, rtol=0, atol=1e-9)
    engaged = mode_events(result, "clutch.mode", Free, -1)
    assert len(engaged) == 1 and engaged[0].time == 0.5 and engaged[0].kind == "time"
    locks = mode_events(result, "clutch.mode", -1, Stuck)
    assert len(locks) == 1
    t_lock = 0.5 + 4.0 / 75.0  # w_rel = -4 closes at (1/J1 + 1/J2)*50 = 75 rad/s^2
    assert abs(locks[0].time - t_lock) <= 1e-9
    slipping = (t > 0.5) & (t < locks[0].time)
    np.testing.assert_allclose(w1[slipping], 3.0 - 50.0 * (t[slipping] - 0.5), rtol=0, atol=1e-8)
    after = slice(right_limit_index(result, locks[0].time), None)
    np.testing.assert_allclose(w1[after], 1.0 / 3.0, rtol=0, atol=1e-8)
    np.testing.assert_allclose(w2[after], 1.0 / 3.0, rtol=0, atol=1e-8)
    assert np.all(result["clutch.mode"][after] == Stuck)
