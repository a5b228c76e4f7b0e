"""Modelica.Electrical.Analog.Ideal op-amps and the op-amp examples against closed forms.

The ideal op-amps (nullator-norator) in the classic circuits whose answers
follow from Kirchhoff's laws alone: the inverting amplifier ``-R2/R1*vin``,
the integrator's ramp ``-t/(R*C)``, the differentiator ``-R*C*der(vin)``,
the first-order low pass's step response; the limited forms clipping to
their supply (IdealOpAmpLimited's parametric curve, IdealizedOpAmpLimited's
finite gain, with and without events, and the power its supply pins
deliver); the voltage follower with finite gain ``V0/(V0 + 1)``; and the
examples (adder, integrator) against numpy/scipy computations of the same
circuits.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from library_checks import check_declarations

from acausal import Model, simulate
from acausal.library.electrical import (
    Capacitor,
    ConstantVoltage,
    Ground,
    RampVoltage,
    Resistor,
    SineVoltage,
    StepVoltage,
)
from acausal.library.electrical.ideal_opamps import (
    IdealizedOpAmpLimited,
    IdealOpAmp,
    IdealOpAmp3Pin,
    IdealOpAmpLimited,
)

# --------------------------------------------------------------------------
# declarations


@pytest.mark.parametrize("component", [
    IdealOpAmp(), IdealOpAmp3Pin(), IdealOpAmpLimited(),
    IdealizedOpAmpLimited(), IdealizedOpAmpLimited(strict=False), IdealizedOpAmpLimited(useSupply=True),
    IdealizedOpAmpLimited(useSupply=True, strict=False, V0=1e5),
], ids=lambda c: f"{type(c).__name__}({', '.join(f'{k}={v}' for k, v in c._modifiers.items())})")
def test_declarations(component):
    """Own names only, locally balanced."""
    check_declarations(component)


# --------------------------------------------------------------------------
# inverting amplifier: v_out = -R2/R1*v_in


class InvertingIdeal(Model):
    """A 4-pin IdealOpAmp: input through R1 to the inverting node, feedback R2; the port's n pins grounded."""

    def build(self):
        self.source = SineVoltage(V=2.0, f=5.0)
        self.opAmp = IdealOpAmp()
        self.r1 = Resistor(R=1000.0)
        self.r2 = Resistor(R=3000.0)
        self.ground = Ground()
        self.connect(self.source.p, self.r1.p)
        self.connect(self.source.n, self.ground.p)
        # the nullator between the inverting node (p1) and ground (n1): the node is a virtual ground
        self.connect(self.r1.n, self.opAmp.p1)
        self.connect(self.opAmp.n1, self.ground.p)
        self.connect(self.r2.n, self.opAmp.p1)
        self.connect(self.r2.p, self.opAmp.p2)
        self.connect(self.opAmp.n2, self.ground.p)


def test_inverting_amplifier_with_ideal_op_amp():
    result = simulate(InvertingIdeal(), stop_time=0.4, interval=0.01)
    t = result.time
    vin = 2.0 * np.sin(2 * np.pi * 5.0 * t)
    np.testing.assert_allclose(result["opAmp.v2"], -3.0 * vin, atol=1e-9)
    np.testing.assert_allclose(result["opAmp.v1"], 0.0, atol=1e-12)
    # the output takes the feedback current back: out.v/R2 = -vin/R1 leaves p2, so i2 = vin/R1
    np.testing.assert_allclose(result["opAmp.i2"], vin / 1000.0, atol=1e-12)


class InvertingLimited(Model):
    """IdealOpAmpLimited with gain -2 on a 10 V sine: clips at the supply potentials +12 V / -9 V."""

    def build(self):
        self.source = SineVoltage(V=10.0, f=1.0)
        self.opAmp = IdealOpAmpLimited()
        self.r1 = Resistor(R=1000.0)
        self.r2 = Resistor(R=2000.0)
        self.vMax = ConstantVoltage(V=12.0)
        self.vMin = ConstantVoltage(V=-9.0)
        self.ground = Ground()
        self.connect(self.source.p, self.r1.p)
        self.connect(self.source.n, self.ground.p)
        self.connect(self.r1.n, self.opAmp.in_n)
        self.connect(self.r2.n, self.opAmp.in_n)
        self.connect(self.r2.p, self.opAmp.out)
        self.connect(self.opAmp.in_p, self.ground.p)
        self.connect(self.vMax.p, self.opAmp.VMax)
        self.connect(self.vMin.p, self.opAmp.VMin)
        self.connect(self.vMax.n, self.ground.p)
        self.connect(self.vMin.n, self.ground.p)


def test_ideal_op_amp_limited_clips_at_its_supply():
    result = simulate(InvertingLimited(), stop_time=1.0, interval=0.005)
    vin = 10.0 * np.sin(2 * np.pi * result.time)
    np.testing.assert_allclose(result["opAmp.out.v"], np.clip(-2.0 * vin, -9.0, 12.0), atol=1e-8)
    # inside the limits the input is a virtual short; saturated, the divider sets it
    linear = np.abs(-2.0 * vin - np.clip(-2.0 * vin, -9.0, 12.0)) < 1e-12
    np.testing.assert_allclose(result["opAmp.vin"][linear], 0.0, atol=1e-8)
    out = np.clip(-2.0 * vin, -9.0, 12.0)
    in_n = (vin * 2000.0 + out * 1000.0) / 3000.0
    np.testing.assert_allclose(result["opAmp.vin"], -in_n, atol=1e-8)
    assert result["opAmp.out.v"].max() == pytest.approx(12.0, abs=1e-9)
    assert result["opAmp.out.v"].min() == pytest.approx(-9.0, abs=1e-9)


# --------------------------------------------------------------------------
# integrator, differentiator, low pass with IdealOpAmp3Pin

R, C = 1000.0, 1e-4  # R*C = 0.1 s


class IdealIntegrator(Model):
    def build(self):
        self.source = ConstantVoltage(V=1.5)
        self.opAmp = IdealOpAmp3Pin()
        self.r = Resistor(R=R)
        self.c = Capacitor(C=C, v=dict(start=0.0, fixed=True))
        self.ground = Ground()
        self.connect(self.source.p, self.r.p)
        self.connect(self.source.n, self.ground.p)
        self.connect(self.r.n, self.opAmp.in_n)
        self.connect(self.c.n, self.opAmp.in_n)
        self.connect(self.c.p, self.opAmp.out)
        self.connect(self.opAmp.in_p, self.ground.p)


def test_integrator_ramp():
    result = simulate(IdealIntegrator(), stop_time=1.0, interval=0.01)
    np.testing.assert_allclose(result["opAmp.out.v"], -1.5 * result.time / (R * C), atol=1e-9)


class IdealDifferentiator(Model):
    def build(self):
        self.source = RampVoltage(V=3.0, duration=0.5, startTime=0.2)
        self.opAmp = IdealOpAmp3Pin()
        self.r = Resistor(R=R)
        self.c = Capacitor(C=C)
        self.ground = Ground()
        self.connect(self.source.p, self.c.p)
        self.connect(self.source.n, self.ground.p)
        self.connect(self.c.n, self.opAmp.in_n)
        self.connect(self.r.n, self.opAmp.in_n)
        self.connect(self.r.p, self.opAmp.out)
        self.connect(self.opAmp.in_p, self.ground.p)


def test_differentiator_of_a_ramp():
    result = simulate(IdealDifferentiator(), stop_time=1.0, interval=0.01)
    slope = np.where((result.time > 0.2 + 1e-9) & (result.time < 0.7 - 1e-9), 3.0 / 0.5, 0.0)
    inside = np.abs(result.time - 0.2) > 1e-6
    inside &= np.abs(result.time - 0.7) > 1e-6
    np.testing.assert_allclose(result["opAmp.out.v"][inside], -R * C * slope[inside], atol=1e-8)


class IdealLowPass(Model):
    def build(self):
        self.source = StepVoltage(V=2.0, startTime=0.1)
        self.opAmp = IdealOpAmp3Pin()
        self.r1 = Resistor(R=R)
        self.r2 = Resistor(R=3 * R)
        self.c = Capacitor(C=C, v=dict(start=0.0, fixed=True))
        self.ground = Ground()
        self.connect(self.source.p, self.r1.p)
        self.connect(self.source.n, self.ground.p)
        for pin in (self.r1.n, self.r2.n, self.c.n):
            self.connect(pin, self.opAmp.in_n)
        self.connect(self.r2.p, self.opAmp.out)
        self.connect(self.c.p, self.opAmp.out)
        self.connect(self.opAmp.in_p, self.ground.p)


def test_low_pass_step_response():
    result = simulate(IdealLowPass(), stop_time=2.0, interval=0.01)
    t = result.time
    T = 3 * R * C
    expected = np.where(t >= 0.1, -3.0 * 2.0 * (1 - np.exp(-(t - 0.1) / T)), 0.0)
    np.testing.assert_allclose(result["opAmp.out.v"], expected, atol=1e-5)


# --------------------------------------------------------------------------
# IdealizedOpAmpLimited: finite gain, saturation, supply


class OpenLoop(Model):
    """An IdealizedOpAmpLimited driving 1 kOhm with a small sine between its inputs."""

    def __init__(self, strict=True, use_supply=False, **modifiers):
        self._strict, self._use_supply = strict, use_supply
        super().__init__(**modifiers)

    def build(self):
        self.source = SineVoltage(V=2e-3, f=1.0)
        self.opAmp = IdealizedOpAmpLimited(V0=15000.0, Vps=12.0, Vns=-10.0, strict=self._strict,
                                           useSupply=self._use_supply)
        self.load = Resistor(R=1000.0)
        self.ground = Ground()
        self.connect(self.source.p, self.opAmp.in_p)
        self.connect(self.source.n, self.ground.p)
        self.connect(self.opAmp.in_n, self.ground.p)
        self.connect(self.opAmp.out, self.load.p)
        self.connect(self.load.n, self.ground.p)
        if self._use_supply:
            self.sp = ConstantVoltage(V=12.0)
            self.sn = ConstantVoltage(V=-10.0)
            self.connect(self.sp.p, self.opAmp.s_p)
            self.connect(self.sn.p, self.opAmp.s_n)
            self.connect(self.sp.n, self.ground.p)
            self.connect(self.sn.n, self.ground.p)


@pytest.mark.parametrize("strict", [True, False])
def test_idealized_op_amp_saturates(strict):
    result = simulate(OpenLoop(strict=strict), stop_time=1.0, interval=0.002)
    vin = 2e-3 * np.sin(2 * np.pi * result.time)
    np.testing.assert_allclose(result["opAmp.v_out"], np.clip(15000.0 * vin, -10.0, 12.0), atol=1e-7)
    # without strict the limits are events: four crossings of each limit in one period
    if not strict:
        assert len([e for e in result.events if e.kind != "initial"]) >= 4


def test_idealized_op_amp_supply_pins_deliver_the_output_power():
    result = simulate(OpenLoop(use_supply=True), stop_time=1.0, interval=0.002)
    vout = np.clip(15000.0 * 2e-3 * np.sin(2 * np.pi * result.time), -10.0, 12.0)
    p_out = vout * -(vout / 1000.0)  # out.i flows into the op-amp: minus the load current
    np.testing.assert_allclose(result["opAmp.p_out"], p_out, atol=1e-9)
    np.testing.assert_allclose(result["opAmp.i_s"], -p_out / 22.0, atol=1e-12)
    np.testing.assert_allclose(result["opAmp.s_p.i"], -p_out / 22.0, atol=1e-12)
    np.testing.assert_allclose(result["opAmp.s_n.i"], p_out / 22.0, atol=1e-12)
    # the power the supply sources give equals the power the load takes
    supply_power = -(12.0 * result["sp.i"]) - (-10.0 * result["sn.i"])
    np.testing.assert_allclose(supply_power, vout ** 2 / 1000.0, atol=1e-9)


def test_voltage_follower_has_the_finite_gain_and_clips():
    from examples.electrical_opamps import VoltageFollower

    result = simulate(VoltageFollower(), stop_time=0.2, interval=0.001)
    t = result.time
    # the examples' trapezoid, computed independently: +-5 V at 10 Hz, mid-plateau at t = 0
    phase = np.mod(t + 0.035, 0.1)
    vin = -5 + 10 * np.interp(phase, [0, 0.02, 0.05, 0.07, 0.1], [0, 1, 1, 0, 0])
    # the input draws no current, so no drop across ri; out = V0/(V0 + 1)*vin
    np.testing.assert_allclose(result["opAmp.out.v"], vin * 15000.0 / 15001.0, atol=1e-7)


# --------------------------------------------------------------------------
# the examples against independent computations


def test_adder_example_adds():
    from examples.electrical_opamps import Adder

    result = simulate(Adder(), stop_time=0.3, interval=0.001)
    total = 5.0 * np.sin(2 * np.pi * 10.0 * result.time) + 5.0
    # vOut measures n2 - p2 = -v2; the finite gain V0 leaves the fraction 1/(1 + (1 + k1 + k2)/V0)
    np.testing.assert_allclose(result["vOut.v"], total / (1 + 3 / 15000.0), atol=1e-6)


def test_integrator_example_against_scipy():
    from examples.electrical_opamps import IntegratorExample

    result = simulate(IntegratorExample(), stop_time=0.3, interval=0.001, rtol=1e-9)

    def trapezoid(t):
        return -5 + 10 * np.interp(np.mod(t + 0.035, 0.1), [0, 0.02, 0.05, 0.07, 0.1], [0, 1, 1, 0, 0])

    Rr, V0 = 1000.0, 15000.0
    Cc = 1 / 2 / (2 * math.pi * 10.0 * Rr)
    # node equations with the finite gain: in_n = u, out = -V0*u, the capacitor's v = out - u;
    # KCL at in_n: (vin - u)/R = -C*der(out - u) = C*(V0 + 1)*der(u)
    sol = solve_ivp(lambda t, u: [(trapezoid(t) - u[0]) / (Rr * Cc * (V0 + 1))], (0, 0.3), [0.0],
                    dense_output=True, rtol=1e-10, atol=1e-12, max_step=1e-3)
    u = sol.sol(result.time)[0]
    np.testing.assert_allclose(result["integrator.opAmp.out.v"], -V0 * u, atol=1e-5)
    np.testing.assert_allclose(result["integrator.c.v"], -V0 * u - u, atol=1e-5)
