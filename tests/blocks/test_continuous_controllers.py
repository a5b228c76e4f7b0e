"""Modelica.Blocks.Continuous Derivative, SecondOrder, PI, PID and LimPID: closed forms and every initType.

The blocks are driven by constant inputs from given initial states, so their
responses are sums of exponentials written out here by hand (and, for
SecondOrder, computed independently by scipy.signal).  The initialization of
each initType is checked at t = 0 against what MSL 4.1.0 prescribes; the
steady states of closed loops are solved by hand.  LimPID's limiter and
anti-windup compensation are checked against the piecewise closed form of a
saturating PI controller.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy import signal

from acausal import Eq, Experiment, Model, simulate
from acausal.errors import StartValueWarning
from acausal.library.blocks import Constant
from acausal.library.blocks.continuous import (PI, PID, Derivative, FirstOrder, Init, Integrator, LimPID,
                                               SecondOrder)
from acausal.library.blocks.types import SimpleController


def _driven(block_factory, inputs: dict[str, float], stop_time: float = 2.0) -> Model:
    """A model holding ``block_factory()`` as ``blk``, its inputs (``"u"``, ``"u_s"`` ...) held at ``inputs``."""

    class Driven(Model):
        experiment = Experiment(stop_time=stop_time, interval=stop_time / 400)

        def build(self):
            self.blk = block_factory()

        def equations(self):
            return [Eq(getattr(self.blk, name), value) for name, value in inputs.items()]

    return Driven()


def _loop(controller_factory, setpoint: float, stop_time: float = 2.0, plant_gain: float = 1.0) -> Model:
    """``blk`` (a SISO controller) acting on the error of the plant ``plant_gain/(s + 1)``, all in steady state."""

    class Loop(Model):
        experiment = Experiment(stop_time=stop_time, interval=stop_time / 200)

        def build(self):
            self.blk = controller_factory()
            self.plant = FirstOrder(k=plant_gain, T=1.0, initType=Init.SteadyState)
            self.connect(self.blk.y, self.plant.u)

        def equations(self):
            return [Eq(self.blk.u, setpoint - self.plant.y)]

    return Loop()


# --------------------------------------------------------------------------
# Derivative: k*s/(T*s + 1)
# --------------------------------------------------------------------------


def test_derivative_step_response_is_the_decaying_exponential():
    k, T = 2.0, 0.2
    r = simulate(_driven(lambda: Derivative(k=k, T=T, initType=Init.InitialState, x_start=0.0), {"u": 1.5}))
    t = r.time
    np.testing.assert_allclose(r["blk.x"], 1.5 * (1 - np.exp(-t / T)), atol=2e-6)
    np.testing.assert_allclose(r["blk.y"], k / T * 1.5 * np.exp(-t / T), atol=2e-5)


def test_derivative_of_a_ramp_approaches_k_times_its_slope():
    k, T, slope = 3.0, 0.05, 0.5

    class RampDriven(Model):
        experiment = Experiment(stop_time=1.0, interval=0.005)

        def build(self):
            self.blk = Derivative(k=k, T=T, initType=Init.InitialState)
            self.clock = Integrator(initType=Init.InitialState)  # u = slope*t
            self.slope = Constant(k=slope)
            self.connect(self.slope.y, self.clock.u)
            self.connect(self.clock.y, self.blk.u)

    r = simulate(RampDriven())
    # x' = (slope*t - x)/T from 0: x = slope*(t - T*(1 - exp(-t/T))); y = k/T*(u - x), where
    # k/T = 60 magnifies the integration error of u - x
    np.testing.assert_allclose(r["blk.y"], k * slope * (1 - np.exp(-r.time / T)), atol=1e-4)


def test_derivative_init_types():
    u = 0.7
    steady = simulate(_driven(lambda: Derivative(initType=Init.SteadyState), {"u": u}))
    assert steady["blk.x"][0] == pytest.approx(u, abs=1e-10)
    np.testing.assert_allclose(steady["blk.y"], 0.0, atol=1e-9)

    k, T = 2.0, 0.5
    output = simulate(_driven(lambda: Derivative(k=k, T=T, initType=Init.InitialOutput, y_start=2.0), {"u": u}))
    # y = k/T*(u - x) = y_start
    assert output["blk.y"][0] == pytest.approx(2.0, abs=1e-10)
    assert output["blk.x"][0] == pytest.approx(u - 2.0 * T / k, abs=1e-10)

    state = simulate(_driven(lambda: Derivative(initType=Init.InitialState, x_start=0.25), {"u": u}))
    assert state["blk.x"][0] == pytest.approx(0.25, abs=1e-12)


def test_derivative_with_zero_gain_outputs_zero_and_starts_on_its_input():
    r = simulate(_driven(lambda: Derivative(k=0.0, initType=Init.InitialOutput, y_start=2.0), {"u": 0.7}))
    np.testing.assert_allclose(r["blk.y"], 0.0, atol=1e-12)
    np.testing.assert_allclose(r["blk.x"], 0.7, atol=1e-12)  # x = u initially, and der(x) = 0 after


# --------------------------------------------------------------------------
# SecondOrder: k*w^2/(s^2 + 2*D*w*s + w^2)
# --------------------------------------------------------------------------


@pytest.mark.parametrize("damping", [0.3, 1.0, 2.0])
def test_second_order_step_response_matches_scipy(damping):
    k, w = 1.5, 4.0
    r = simulate(_driven(lambda: SecondOrder(k=k, w=w, D=damping, initType=Init.InitialState), {"u": 1.0},
                         stop_time=3.0))
    system = signal.lti([k * w**2], [1.0, 2 * damping * w, w**2])
    _, y = signal.step(system, T=r.time)
    np.testing.assert_allclose(r["blk.y"], y, atol=3e-5)
    _, yd = signal.impulse(system, T=r.time)  # the derivative of the step response
    np.testing.assert_allclose(r["blk.yd"], yd, atol=3e-4)


def test_second_order_critically_damped_closed_form_from_initial_output():
    # D = 1, u = 0, y(0) = y0, yd(0) = v0: y = (y0 + (v0 + w*y0)*t)*exp(-w*t)
    w, y0, v0 = 2.0, 2.0, -1.0
    r = simulate(_driven(lambda: SecondOrder(w=w, D=1.0, initType=Init.InitialOutput, y_start=y0, yd_start=v0),
                         {"u": 0.0}))
    t = r.time
    np.testing.assert_allclose(r["blk.y"], (y0 + (v0 + w * y0) * t) * np.exp(-w * t), atol=2e-5)


def test_second_order_steady_state_sits_at_k_times_u():
    r = simulate(_driven(lambda: SecondOrder(k=3.0, w=2.0, D=0.4, initType=Init.SteadyState), {"u": 0.5}))
    np.testing.assert_allclose(r["blk.y"], 1.5, atol=1e-9)
    np.testing.assert_allclose(r["blk.yd"], 0.0, atol=1e-9)


# --------------------------------------------------------------------------
# PI: k*(1 + 1/(T*s))
# --------------------------------------------------------------------------


def test_pi_step_response_is_proportional_plus_ramp():
    k, T, u = 2.0, 0.5, 0.8
    r = simulate(_driven(lambda: PI(k=k, T=T, initType=Init.InitialState, x_start=0.1), {"u": u}))
    t = r.time
    np.testing.assert_allclose(r["blk.x"], 0.1 + u * t / T, atol=1e-8)
    np.testing.assert_allclose(r["blk.y"], k * (0.1 + u * t / T + u), atol=1e-8)


def test_pi_initial_output_and_steady_state_in_a_loop():
    output = simulate(_driven(lambda: PI(k=2.0, T=1.0, initType=Init.InitialOutput, y_start=2.0), {"u": 0.5}))
    assert output["blk.y"][0] == pytest.approx(2.0, abs=1e-10)
    assert output["blk.x"][0] == pytest.approx(2.0 / 2.0 - 0.5, abs=1e-10)  # y = k*(x + u)

    # steady state of PI + plant 2/(s + 1) at set point 1: error 0, plant output 1 = 2*PI.y, so x = 0.5/k
    loop = simulate(_loop(lambda: PI(k=4.0, T=0.3, initType=Init.SteadyState), 1.0, plant_gain=2.0))
    np.testing.assert_allclose(loop["blk.x"], 0.5 / 4.0, atol=1e-9)
    np.testing.assert_allclose(loop["plant.y"], 1.0, atol=1e-9)


# --------------------------------------------------------------------------
# PID: k*(1 + 1/(Ti*s) + Td*s/(Td/Nd*s + 1))
# --------------------------------------------------------------------------


def test_pid_step_response_closed_form():
    k, Ti, Td, Nd, u = 2.0, 0.5, 0.1, 10.0, 1.0
    r = simulate(_driven(lambda: PID(k=k, Ti=Ti, Td=Td, Nd=Nd), {"u": u}))  # InitialState, states from 0
    t = r.time
    integral = u * t / Ti
    derivative = Nd * u * np.exp(-t * Nd / Td)  # (Td/T)*(u - x) with T = Td/Nd
    np.testing.assert_allclose(r["blk.I.y"], integral, atol=1e-8)
    np.testing.assert_allclose(r["blk.D.y"], derivative, atol=2e-4)
    np.testing.assert_allclose(r["blk.y"], k * (u + integral + derivative), atol=4e-4)


def test_pid_initial_states_and_initial_output():
    r = simulate(_driven(lambda: PID(xi_start=0.3, xd_start=-0.2), {"u": 1.0}))
    assert r["blk.I.y"][0] == pytest.approx(0.3)
    assert r["blk.D.x"][0] == pytest.approx(-0.2)

    k, u = 2.0, 0.5
    out = simulate(_driven(lambda: PID(k=k, initType=Init.InitialOutput, y_start=2.0), {"u": u}))
    assert out["blk.y"][0] == pytest.approx(2.0, abs=1e-10)
    assert out["blk.D.x"][0] == pytest.approx(u, abs=1e-10)  # derivative block in steady state
    assert out["blk.I.y"][0] == pytest.approx(2.0 / k - u, abs=1e-10)  # y = k*(u + I.y + 0)


def test_pid_steady_state_in_a_loop():
    # error 0 at the steady state; plant 1/(s + 1) at 1 needs PID.y = 1 = k*I.y
    r = simulate(_loop(lambda: PID(k=4.0, Ti=0.5, Td=0.1, initType=Init.SteadyState), 1.0))
    np.testing.assert_allclose(r["blk.I.y"], 0.25, atol=1e-9)
    np.testing.assert_allclose(r["blk.D.x"], 0.0, atol=1e-9)


# --------------------------------------------------------------------------
# LimPID
# --------------------------------------------------------------------------


def test_lim_pid_p_controller_limits_and_weights():
    cases = [  # (u_s, u_m, wp, expected y): k = 2, limits -1..1
        (0.2, 0.0, 1.0, 0.4),
        (1.0, 0.0, 1.0, 1.0),
        (-1.0, 0.5, 1.0, -1.0),
        (1.0, 0.5, 0.5, 0.0),
    ]
    for u_s, u_m, wp, expected in cases:
        r = simulate(_driven(lambda: LimPID(controllerType=SimpleController.P, k=2.0, wp=wp),
                             {"u_s": u_s, "u_m": u_m}, stop_time=0.5))
        np.testing.assert_allclose(r["blk.y"], expected, atol=1e-12)
        np.testing.assert_allclose(r["blk.controlError"], u_s - u_m, atol=1e-12)


def test_lim_pid_p_controller_has_no_integrator_nor_derivative():
    r = simulate(_driven(lambda: LimPID(controllerType="P"), {"u_s": 0.1, "u_m": 0.0}, stop_time=0.1))
    assert not any(name.startswith(("blk.I.", "blk.D.")) for name in r.names)
    assert "blk.Izero.y" in r.names and "blk.Dzero.y" in r.names and "blk.FFzero.y" in r.names


def test_lim_pid_feed_forward_adds_before_the_limiter():
    r = simulate(_driven(lambda: LimPID(controllerType=SimpleController.P, k=1.0, yMax=10.0,
                                        withFeedForward=True, kFF=2.0),
                         {"u_s": 0.5, "u_m": 0.2, "u_ff": 0.1}, stop_time=0.5))
    np.testing.assert_allclose(r["blk.y"], 0.3 + 0.2, atol=1e-12)


def test_lim_pid_pd_derivative_kick_with_setpoint_weight():
    k, Td, Nd, wd, u_s, u_m = 0.5, 0.2, 5.0, 0.5, 1.0, 0.2
    r = simulate(_driven(lambda: LimPID(controllerType=SimpleController.PD, k=k, Td=Td, Nd=Nd, wd=wd, yMax=100.0),
                         {"u_s": u_s, "u_m": u_m}, stop_time=0.5))
    derivative = Nd * (wd * u_s - u_m) * np.exp(-r.time * Nd / Td)
    np.testing.assert_allclose(r["blk.y"], k * (u_s - u_m + derivative), atol=2e-5)


def test_lim_pid_anti_windup_holds_the_integrator_while_saturated():
    # PI, k = 1, Ti = 1, Ni = 0.9, limits -1..1, control error e = 0.5 from I(0) = 0:
    # unsaturated v = e + I with I = e*t until v = 1 at t1 = 1; then y = 1 and
    # I' = e + (1 - e - I)/Ni, which settles at I = e*Ni + 1 - e = 0.95 with time constant Ni.
    e, Ni = 0.5, 0.9
    r = simulate(_driven(lambda: LimPID(controllerType=SimpleController.PI, k=1.0, Ti=1.0, Ni=Ni, yMax=1.0),
                         {"u_s": e, "u_m": 0.0}, stop_time=4.0))
    t = r.time
    t1 = (1.0 - e) / e
    settled = e * Ni + 1.0 - e
    expected = np.where(t <= t1, e * t, settled - (settled - e * t1) * np.exp(-(t - t1) / Ni))
    np.testing.assert_allclose(r["blk.I.y"], expected, atol=2e-5)
    np.testing.assert_allclose(r["blk.y"], np.minimum(e + e * t, 1.0), atol=2e-5)
    assert any(abs(event.time - t1) < 1e-6 for event in r.events)  # the limiter engages at a state event
    # without the compensation the integrator would keep ramping; with it the limiter's input
    # approaches e + settled = 1.45 instead of growing without bound
    np.testing.assert_allclose(r["blk.limiter.u"], e + expected, atol=2e-5)


def test_lim_pid_steady_state_saturated_loop():
    # ModelicaTest.Blocks.LimPID's second loop: set point 2, plant 1/(s + 1), output limited to 0..1.
    # At the steady state the plant sits at y = 1, and I' = 0 means e + (1 - v)/(k*Ni) = 0 with e = 1,
    # so v = 1 + k*Ni = 1.9 = k*(e + I): I = 0.9.
    class Saturated(Model):
        experiment = Experiment(stop_time=1.0, interval=0.01)

        def build(self):
            self.pid = LimPID(Ti=1.0, yMax=1.0, yMin=0.0, initType=Init.SteadyState,
                              controllerType=SimpleController.PI)
            self.plant = FirstOrder(T=1.0, initType=Init.SteadyState)
            self.setpoint = Constant(k=2.0)
            self.connect(self.setpoint.y, self.pid.u_s)
            self.connect(self.plant.y, self.pid.u_m)
            self.connect(self.pid.y, self.plant.u)

    r = simulate(Saturated())
    np.testing.assert_allclose(r["pid.I.y"], 0.9, atol=1e-9)
    np.testing.assert_allclose(r["plant.y"], 1.0, atol=1e-9)


def test_lim_pid_initial_output_sets_the_output_before_the_limiter():
    k, u_s, u_m = 2.0, 1.0, 0.25
    r = simulate(_driven(lambda: LimPID(k=k, yMax=3.0, initType=Init.InitialOutput, y_start=2.0),
                         {"u_s": u_s, "u_m": u_m}, stop_time=0.1))
    assert r["blk.gainPID.y"][0] == pytest.approx(2.0, abs=1e-10)
    assert r["blk.D.x"][0] == pytest.approx(0.0 * u_s - u_m, abs=1e-10)  # wd = 0: D in steady state on -u_m
    assert r["blk.I.y"][0] == pytest.approx(2.0 / k - (u_s - u_m), abs=1e-10)


def test_lim_pid_initial_output_outside_the_limits_fails():
    r = simulate(_driven(lambda: LimPID(yMax=1.0, initType=Init.InitialOutput, y_start=2.0),
                         {"u_s": 0.0, "u_m": 0.0}, stop_time=0.1))
    assert r.status != "ok"
    assert "y_start" in r.message


def test_no_init_starts_the_states_from_their_start_values():
    class Unset(Model):
        experiment = Experiment(stop_time=0.5, interval=0.01)

        def build(self):
            self.der = Derivative(initType=Init.NoInit, x_start=0.3)
            self.pi = PI(initType=Init.NoInit, x_start=0.4)
            self.pid = PID(initType=Init.NoInit, xi_start=0.2, xd_start=0.1)

        def equations(self):
            return [Eq(self.der.u, 0.3), Eq(self.pi.u, 0.0), Eq(self.pid.u, 0.0)]

    # as a Modelica tool does, with a warning naming the states nothing else determines
    with pytest.warns(StartValueWarning, match="without fixed=True"):
        r = simulate(Unset())
    for name, value in [("der.x", 0.3), ("pi.x", 0.4), ("pid.I.y", 0.2)]:
        np.testing.assert_allclose(r[name], value, atol=1e-9)  # inputs chosen to keep them constant
    np.testing.assert_allclose(r["pid.D.x"], 0.1 * np.exp(-r.time / 0.01), atol=1e-5)  # T = Td/Nd
