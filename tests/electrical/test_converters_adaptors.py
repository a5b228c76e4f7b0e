"""AD/DA converters (Analog.Ideal) and the general signal adaptors (Analog.Basic) against closed forms.

A ramp voltage is converted at known trigger instants: the bits of the AD
converter are those of ``k = floor((u - VRefLow)/(VRefHigh - VRefLow)*(2^N - 1) + 1/2)``
(0 at or below ``VRefLow``; above the range the lowest ``N`` bits and the
rest left in ``z``), computed here with Python integers from the ramp's
value at the instant.  The DA converter fed with those bits gives back the
voltage within half an LSB (a round trip at several instants).  Only
``'1'``/``'H'`` triggers, a ``'Z'`` on the trigger line does nothing.

GeneralVoltageToCurrentAdaptor around a capacitor and
GeneralCurrentToVoltageAdaptor around an inductor, driven by a sine and
its derivative: current and voltage with their derivatives in closed form
(the derivative inputs replace differentiating the inputs, the second
derivative is that of the derivative input).  Voltage -> current ->
voltage through both at ``w = 1/sqrt(L*C)`` gives the input back.  Two
circuits coupled through the adaptors (an FMU-style split, algebraic loop
through ``pder``) behave as the one circuit they form: the RC charging
curve of the parallel connection.
"""

from __future__ import annotations

import numpy as np
import pytest
from library_checks import check_declarations

from acausal import Experiment, Model, simulate
from acausal.library.blocks import Cosine, IntegerTable, Sine
from acausal.library.electrical import (
    Capacitor,
    ConstantCurrent,
    GeneralCurrentToVoltageAdaptor,
    GeneralVoltageToCurrentAdaptor,
    Ground,
    Inductor,
    RampVoltage,
    Resistor,
)
from acausal.library.electrical.ideal import AD_Converter, DA_Converter, Logic

L = Logic


@pytest.mark.parametrize("component", [AD_Converter(), DA_Converter(), AD_Converter(N=3), DA_Converter(N=2)],
                         ids=lambda c: f"{type(c).__name__}-{c.N}")
def test_declarations(component):
    check_declarations(component)


def _converter_chain(N, VRefLow, VRefHigh, Vref, ramp_height, trigger_rows):
    """A ramp 0 -> ramp_height V over 1 s into an AD converter, its bits into a DA converter loaded by 1 kOhm."""

    class Chain(Model):
        experiment = Experiment(stop_time=1.0, interval=1e-2)

        def build(self):
            self.g = Ground()
            self.ramp = RampVoltage(V=ramp_height, duration=1.0)
            self.ad = AD_Converter(N=N, VRefLow=VRefLow, VRefHigh=VRefHigh, Rin=1e6)
            self.da = DA_Converter(N=N, Vref=Vref)
            self.load = Resistor(R=1e3)
            self.trigger = IntegerTable(table=trigger_rows)
            self.connect(self.ramp.p, self.ad.p)
            self.connect(self.ramp.n, self.g.p)
            self.connect(self.ad.n, self.g.p)
            self.connect(self.da.p, self.load.p)
            self.connect(self.da.n, self.g.p)
            self.connect(self.load.n, self.g.p)
            self.connect(self.trigger.y, self.ad.trig)
            self.connect(self.trigger.y, self.da.trig)
            self.connect(self.ad.y, self.da.x)
    return Chain()


def _code(u, N, VRefLow, VRefHigh):
    """The MSL's code, with Python's exact integer floor."""
    return int(np.floor((u - VRefLow) / (VRefHigh - VRefLow) * (2**N - 1) + 0.5)) if u > VRefLow else 0


def _bits(result, name, N, t):
    return np.array([int(result.at(t, f"{name}[{i}]")) for i in range(1, N + 1)])


def test_ad_codes_of_a_ramp():
    """Bits at each trigger instant are the closed-form code of the ramp's value; 'X' before the first."""
    N, VRefLow, VRefHigh, height = 4, 1.0, 10.0, 12.0
    # rising to '1' or 'H' triggers; 'Z' (and the falls to '0'/'L') do not
    rows = [(0.0, L.Zero), (0.05, L.One), (0.07, L.Zero), (0.237, L.H), (0.25, L.L), (0.4, L.Z), (0.42, L.Zero),
            (0.613, L.One), (0.63, L.Zero), (0.95, L.One), (0.97, L.Zero)]
    r = simulate(_converter_chain(N, VRefLow, VRefHigh, VRefHigh, height, [(t, int(v)) for t, v in rows]))
    assert r.success
    # before the first trigger: every bit 'X', z = 0, the DA output 0
    assert np.all(_bits(r, "ad.y", N, 0.03) == L.X)
    assert r.at(0.03, "da.vout") == 0.0
    expected_z = 0
    for t_trig in (0.05, 0.237, 0.613, 0.95):
        u = height * t_trig
        k = _code(u, N, VRefLow, VRefHigh)
        want = np.array([L.One if (k >> (i - 1)) & 1 else L.Zero for i in range(1, N + 1)])
        for t in (t_trig + 1e-3, t_trig + 0.1):  # just after the trigger, and held later
            if t < 1.0:
                assert np.array_equal(_bits(r, "ad.y", N, t), want), (t_trig, k)
        expected_z = k >> N
        assert r.at(t_trig + 1e-3, "ad.z") == expected_z
        # the DA converter reads the new bits at the same instant: y is k's lowest N bits
        assert r.at(t_trig + 1e-3, "da.y") == k % 2**N
    # the cases covered: below VRefLow (0.6 V -> 0), in range, above it (11.4 V -> 17: bits 0001, z = 1)
    assert _code(height * 0.05, N, VRefLow, VRefHigh) == 0
    assert _code(height * 0.95, N, VRefLow, VRefHigh) == 17 and expected_z == 1
    # the 'Z' at 0.4 s did not convert: still the code of 0.613 s's predecessor (0.237 s)
    k = _code(height * 0.237, N, VRefLow, VRefHigh)
    assert r.at(0.5, "da.y") == k
    # input resistance: i = u/Rin
    t = np.array([0.3, 0.8])
    assert np.allclose(r.at(t, "ad.p.i"), height * t / 1e6, rtol=1e-9)


@pytest.mark.parametrize("N", [3, 8])
def test_round_trip_within_half_an_lsb(N):
    """DA(AD(u)) = k*Vref/(2^N - 1) exactly, and within half an LSB of the sampled u."""
    VRefHigh = 10.0
    instants = [0.11, 0.29, 0.377, 0.52, 0.666, 0.81, 0.93]
    rows = [(0.0, int(L.Zero))]
    for t in instants:
        rows += [(t, int(L.One)), (t + 0.01, int(L.Zero))]
    r = simulate(_converter_chain(N, 0.0, VRefHigh, VRefHigh, VRefHigh, rows))
    assert r.success
    lsb = VRefHigh / (2**N - 1)
    for t_trig, t_next in zip(instants, instants[1:] + [1.0]):
        u = VRefHigh * t_trig
        k = _code(u, N, 0.0, VRefHigh)
        held = np.linspace(t_trig + 1e-3, t_next - 1e-3, 5)
        vout = r.at(held, "da.vout")
        assert np.allclose(vout, k * VRefHigh / (2**N - 1), rtol=1e-12, atol=1e-12)
        assert np.all(np.abs(vout - u) <= lsb / 2 + 1e-12)
        # the ideal source drives the load: p.v - n.v = vout
        assert np.allclose(r.at(held, "load.v"), vout, rtol=1e-9, atol=1e-12)


# --------------------------------------------------------------------------
# general adaptors (Modelica.Electrical.Analog.Basic)


@pytest.mark.parametrize("component", [
    GeneralCurrentToVoltageAdaptor(), GeneralVoltageToCurrentAdaptor(),
    GeneralCurrentToVoltageAdaptor(use_pder=False, use_fder=False),
    GeneralVoltageToCurrentAdaptor(use_pder=False, use_fder=False),
], ids=lambda c: f"{type(c).__name__}-{c.use_pder}-{c.use_fder}")
def test_adaptor_declarations(component):
    check_declarations(component)


AMPLITUDE, FREQUENCY = 2.0, 3.0  # the driving sine: A*sin(w*t), w = 2*pi*f
OMEGA = 2 * np.pi * FREQUENCY
C_VALUE = 1e-3
L_VALUE = 1 / (OMEGA**2 * C_VALUE)  # resonance: L*C*w^2 = 1


def _sine_with_derivative(model):
    """``model.s`` = A*sin(w t) and ``model.ds`` = A*w*cos(w t), its derivative."""
    model.s = Sine(amplitude=AMPLITUDE, f=FREQUENCY)
    model.ds = Cosine(amplitude=AMPLITUDE * OMEGA, f=FREQUENCY)


def _voltage_to_current_on_capacitor(model):
    model.gA = Ground()
    model.C = Capacitor(C=C_VALUE)
    model.v2c = GeneralVoltageToCurrentAdaptor()
    model.connect(model.v2c.pin_p, model.C.p)
    model.connect(model.v2c.pin_n, model.C.n)
    model.connect(model.C.n, model.gA.p)


def _current_to_voltage_on_inductor(model):
    model.gB = Ground()
    model.L = Inductor(L=L_VALUE)
    model.c2v = GeneralCurrentToVoltageAdaptor()
    model.connect(model.c2v.pin_p, model.L.p)
    model.connect(model.c2v.pin_n, model.L.n)
    model.connect(model.L.n, model.gB.p)


def test_voltage_to_current_on_a_capacitor():
    """p = A sin(wt) across C: f = C*A*w*cos(wt), fder = -C*A*w^2*sin(wt), i = -f."""

    class Model_(Model):
        experiment = Experiment(stop_time=1.0, interval=1e-3)

        def build(self):
            _sine_with_derivative(self)
            _voltage_to_current_on_capacitor(self)
            self.connect(self.s.y, self.v2c.p)
            self.connect(self.ds.y, self.v2c.pder)

    r = simulate(Model_())
    assert r.success
    t = r.time
    assert np.allclose(r["C.v"], AMPLITUDE * np.sin(OMEGA * t), atol=1e-9)
    assert np.allclose(r["v2c.f"], C_VALUE * AMPLITUDE * OMEGA * np.cos(OMEGA * t), atol=1e-9)
    assert np.allclose(r["v2c.fder"], -C_VALUE * AMPLITUDE * OMEGA**2 * np.sin(OMEGA * t), atol=1e-8)
    assert np.allclose(r["v2c.i"], -r["v2c.f"], atol=1e-12)


def test_current_to_voltage_on_an_inductor():
    """f = A sin(wt) into pin_p, L between the pins carries -f: v = -L*A*w*cos(wt), dv = L*A*w^2*sin(wt)."""

    class Model_(Model):
        experiment = Experiment(stop_time=1.0, interval=1e-3)

        def build(self):
            _sine_with_derivative(self)
            _current_to_voltage_on_inductor(self)
            self.connect(self.s.y, self.c2v.f)
            self.connect(self.ds.y, self.c2v.fder)

    r = simulate(Model_())
    assert r.success
    t = r.time
    assert np.allclose(r["L.i"], -AMPLITUDE * np.sin(OMEGA * t), atol=1e-9)
    assert np.allclose(r["c2v.p"], -L_VALUE * AMPLITUDE * OMEGA * np.cos(OMEGA * t), atol=1e-9)
    assert np.allclose(r["c2v.pder"], L_VALUE * AMPLITUDE * OMEGA**2 * np.sin(OMEGA * t), atol=1e-8)


def test_round_trip_voltage_current_voltage():
    """v -> (capacitor) -> i, di -> (inductor) -> v' = L*C*w^2 * v = v at resonance, dv' = dv."""

    class Model_(Model):
        experiment = Experiment(stop_time=1.0, interval=1e-3)

        def build(self):
            _sine_with_derivative(self)
            _voltage_to_current_on_capacitor(self)
            _current_to_voltage_on_inductor(self)
            self.connect(self.s.y, self.v2c.p)
            self.connect(self.ds.y, self.v2c.pder)
            self.connect(self.v2c.f, self.c2v.f)
            self.connect(self.v2c.fder, self.c2v.fder)

    r = simulate(Model_())
    assert r.success
    t = r.time
    assert np.allclose(r["c2v.p"], AMPLITUDE * np.sin(OMEGA * t), atol=1e-9)
    assert np.allclose(r["c2v.pder"], AMPLITUDE * OMEGA * np.cos(OMEGA * t), atol=1e-7)


def test_split_circuit_behaves_as_one():
    """I0 into C2||R2 (current -> voltage side) coupled to C1||R1 (voltage -> current side):
    (C1 + C2)*dv/dt = I0 - v*(1/R1 + 1/R2), v(0) = 0, so v = I0*R*(1 - exp(-t/(R*C))) with R = R1||R2, C = C1 + C2.
    """
    I0, C1, C2, R1, R2 = 0.5, 2e-3, 3e-3, 100.0, 400.0

    class Model_(Model):
        experiment = Experiment(stop_time=2.0, interval=1e-3)

        def build(self):
            # circuit B: the source, C2 and R2, exported as current in / voltage out
            self.gB = Ground()
            self.I = ConstantCurrent(I=I0)
            self.C2 = Capacitor(C=C2, v=dict(fixed=True))
            self.R2 = Resistor(R=R2)
            self.c2v = GeneralCurrentToVoltageAdaptor(use_fder=False)
            self.connect(self.I.n, self.C2.p)  # the source pushes I0 into the node
            self.connect(self.I.p, self.gB.p)
            self.connect(self.R2.p, self.C2.p)
            self.connect(self.R2.n, self.gB.p)
            self.connect(self.C2.n, self.gB.p)
            self.connect(self.c2v.pin_p, self.C2.p)
            self.connect(self.c2v.pin_n, self.gB.p)
            # circuit A: C1 and R1, exported as voltage in / current out
            self.gA = Ground()
            self.C1 = Capacitor(C=C1)
            self.R1 = Resistor(R=R1)
            self.v2c = GeneralVoltageToCurrentAdaptor(use_fder=False)
            for part in (self.C1, self.R1):
                self.connect(part.p, self.v2c.pin_p)
                self.connect(part.n, self.gA.p)
            self.connect(self.v2c.pin_n, self.gA.p)
            # the coupling: B's voltage and its derivative to A, A's current back to B
            self.connect(self.c2v.p, self.v2c.p)
            self.connect(self.c2v.pder, self.v2c.pder)
            self.connect(self.v2c.f, self.c2v.f)

    r = simulate(Model_())
    assert r.success
    t = r.time
    R, C = R1 * R2 / (R1 + R2), C1 + C2
    v = I0 * R * (1 - np.exp(-t / (R * C)))
    assert np.allclose(r["C2.v"], v, rtol=1e-5, atol=1e-6)
    assert np.allclose(r["C1.v"], v, rtol=1e-5, atol=1e-6)
    # A draws f = C1*dv/dt + v/R1
    assert np.allclose(r["v2c.f"], C1 * I0 / C * np.exp(-t / (R * C)) + v / R1, rtol=1e-5, atol=1e-6)
