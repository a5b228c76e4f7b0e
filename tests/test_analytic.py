"""Simulations checked against closed-form solutions and conserved quantities.

Each model is small enough to solve by hand: a damped oscillator, Newton's
law under a constant torque, two heat capacitors exchanging heat, an
undamped oscillator whose energy is conserved, and a torque step that is a
time event.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from acausal import Event, Model, simulate
from examples.two_masses import TwoMasses
from acausal.library.blocks import Step
from acausal.library.rotational import ConstantTorque, Fixed, Inertia, Spring, SpringDamper, Torque

# --------------------------------------------------------------------------
# damped spring-inertia oscillator

J_OSC, C_OSC, D_OSC, PHI0, W0 = 2.0, 50.0, 4.0, 0.5, 1.0


class DampedOscillator(Model):
    def build(self):
        self.fixed = Fixed()
        self.spring = SpringDamper(c=C_OSC, d=D_OSC)
        self.inertia = Inertia(J=J_OSC, phi=dict(start=PHI0, fixed=True), w=dict(start=W0, fixed=True))
        self.connect(self.fixed.flange, self.spring.flange_a)
        self.connect(self.spring.flange_b, self.inertia.flange_a)


def damped_solution(t):
    """J phi'' + d phi' + c phi = 0 (underdamped): phi = e^{-s t}(A cos wd t + B sin wd t)."""
    sigma = D_OSC / (2 * J_OSC)
    wd = math.sqrt(C_OSC / J_OSC - sigma**2)
    A = PHI0
    B = (W0 + sigma * PHI0) / wd
    e = np.exp(-sigma * t)
    phi = e * (A * np.cos(wd * t) + B * np.sin(wd * t))
    w = e * ((B * wd - sigma * A) * np.cos(wd * t) - (A * wd + sigma * B) * np.sin(wd * t))
    return phi, w


@pytest.mark.parametrize("method", ["DOP853", "RK45", "Radau", "BDF", "LSODA"])
def test_damped_oscillator_matches_closed_form(method):
    """Inertia on a SpringDamper to ground (zeta = 0.2) follows the underdamped closed form to 1e-6 at rtol 1e-9."""
    assert D_OSC**2 < 4 * C_OSC * J_OSC  # underdamped
    result = simulate(DampedOscillator(), stop_time=3.0, interval=0.01, method=method, rtol=1e-9)
    assert result.success, result.message
    phi, w = damped_solution(result.time)
    assert np.max(np.abs(result["inertia.phi"] - phi)) <= 1e-6
    assert np.max(np.abs(result["inertia.w"] - w)) <= 1e-6
    # the spring's relative angle is the inertia's angle (flange_a is grounded at 0)
    np.testing.assert_allclose(result["spring.phi_rel"], result["inertia.phi"], rtol=0, atol=1e-12)


# --------------------------------------------------------------------------
# TwoMasses


def test_two_masses_temperature_difference_decays_exponentially():
    """C dT1/dt = -G(T1-T2), C dT2/dt = G(T1-T2) with C=15, G=10: dT = 100 exp(-4t/3) about 323.15 K, to 1e-6."""
    result = simulate(TwoMasses(), rtol=1e-10)
    assert result.success, result.message
    t = result.time
    delta = 100.0 * np.exp(-(4.0 / 3.0) * t)
    assert np.max(np.abs(result["mass1.T"] - (323.15 + delta / 2))) <= 1e-6
    assert np.max(np.abs(result["mass2.T"] - (323.15 - delta / 2))) <= 1e-6
    # energy is conserved (equal capacities): the mean temperature stays 323.15 K
    assert np.max(np.abs((result["mass1.T"] + result["mass2.T"]) / 2 - 323.15)) <= 1e-9
    # the fixed=False parameter comes from the initial equation: the mixing temperature
    np.testing.assert_allclose(result["T_final_K"], 323.15, rtol=0, atol=1e-12)
    # the Celsius sensors read T - 273.15
    np.testing.assert_allclose(result["Tsensor1.T"], result["mass1.T"] - 273.15, rtol=0, atol=1e-9)


# --------------------------------------------------------------------------
# constant torque on a free inertia


def test_constant_torque_on_free_inertia_gives_parabola():
    """J*a = T from rest at 0: phi = T t^2/(2J), w = T t/J exactly (a quadratic is integrated without error)."""
    T, J = 3.0, 1.5

    class Free(Model):
        def build(self):
            self.src = ConstantTorque(tau_constant=T)
            self.inertia = Inertia(J=J, phi=dict(start=0.0, fixed=True), w=dict(start=0.0, fixed=True))
            self.connect(self.src.flange, self.inertia.flange_a)

    result = simulate(Free(), stop_time=2.0, interval=0.05, rtol=1e-8)
    assert result.success, result.message
    t = result.time
    np.testing.assert_allclose(result["inertia.phi"], T * t**2 / (2 * J), rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(result["inertia.w"], T * t / J, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(result["inertia.a"], T / J, rtol=1e-14, atol=0)


# --------------------------------------------------------------------------
# energy conservation


def test_undamped_oscillator_conserves_energy():
    """Inertia on an ideal Spring: J w^2/2 + c phi_rel^2/2 stays constant to 1e-8 relative at rtol 1e-10."""
    J, c, phi0 = 0.8, 20.0, 1.0

    class Undamped(Model):
        def build(self):
            self.fixed = Fixed()
            self.spring = Spring(c=c)
            self.inertia = Inertia(J=J, phi=dict(start=phi0, fixed=True), w=dict(start=0.0, fixed=True))
            self.connect(self.fixed.flange, self.spring.flange_a)
            self.connect(self.spring.flange_b, self.inertia.flange_a)

    result = simulate(Undamped(), stop_time=3.0, interval=0.01, method="DOP853", rtol=1e-10)
    assert result.success, result.message
    energy = 0.5 * J * result["inertia.w"] ** 2 + 0.5 * c * result["spring.phi_rel"] ** 2
    e0 = 0.5 * c * phi0**2
    assert np.max(np.abs(energy - e0)) / e0 <= 1e-8
    # and the motion is the cosine it must be
    omega = math.sqrt(c / J)
    assert np.max(np.abs(result["inertia.phi"] - phi0 * np.cos(omega * result.time))) <= 1e-8


# --------------------------------------------------------------------------
# time events


def test_step_torque_is_a_time_event_with_left_and_right_limits():
    """Step(startTime=0.5) into a Torque: w = 0 before 0.5, (t-0.5)*height/J after; two rows and a time Event at 0.5."""
    J, height, t_step = 2.0, 3.0, 0.5

    class Stepped(Model):
        def build(self):
            self.step = Step(startTime=t_step, height=height)
            self.torque = Torque()
            self.inertia = Inertia(J=J, phi=dict(start=0.0, fixed=True), w=dict(start=0.0, fixed=True))
            self.connect(self.step.y, self.torque.tau)
            self.connect(self.torque.flange, self.inertia.flange_a)

    result = simulate(Stepped(), stop_time=1.0, interval=0.1, rtol=1e-10)
    assert result.success, result.message
    t = result.time
    rows = np.flatnonzero(t == t_step)
    assert len(rows) == 2 and rows[1] == rows[0] + 1
    left, right = rows
    # the torque jumps at the event, the speed does not
    assert result["torque.tau"][left] == 0.0 and result["torque.tau"][right] == height
    assert result["inertia.a"][left] == 0.0 and result["inertia.a"][right] == height / J
    assert result["inertia.w"][left] == result["inertia.w"][right] == 0.0
    expected_w = np.where(t < t_step, 0.0, (t - t_step) * height / J)
    np.testing.assert_allclose(result["inertia.w"], expected_w, rtol=0, atol=1e-10)
    expected_phi = np.where(t < t_step, 0.0, (t - t_step) ** 2 * height / (2 * J))
    np.testing.assert_allclose(result["inertia.phi"], expected_phi, rtol=0, atol=1e-10)
    assert np.all(np.diff(t) >= 0)
    time_events = [e for e in result.events if e.kind == "time"]
    assert len(time_events) == 1
    assert isinstance(time_events[0], Event)
    assert time_events[0].time == t_step
    assert result.events[0].kind == "initial"
