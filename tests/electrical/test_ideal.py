"""Modelica.Electrical.Analog.Ideal: the switching elements against closed forms and scipy.

Declarations and units of every class; the diode characteristic (the
``Ron``/``Goff``/``Vknee`` lines) point by point; the switches' closed and
open states; the thyristor's latching; the arc voltage of a closer with arc
and its quench time against scipy's solution of the RL circuit; the ideal
transformer's ratios and magnetizing current.  The hard case: a half-wave
ideal-diode rectifier with an RC load over 1,000 periods, two events a
period, no drift from the periodic steady state computed independently
(scipy, the circuit's two linear modes), and the energy balanced.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
import sympy as sp
from scipy.integrate import solve_ivp
from scipy.optimize import brentq
from library_checks import check_declarations

from acausal import Eq, Experiment, Model, Variable, der, simulate
from acausal.compiler.flatten import flatten
from acausal.compiler.units import check_units
from acausal.errors import UnitWarning
from acausal.library.blocks import BooleanPulse, BooleanStep
from acausal.library.electrical import (
    Capacitor,
    ConstantVoltage,
    Ground,
    Inductor,
    Resistor,
    SineVoltage,
    StepVoltage,
)
from acausal.library.electrical.ideal import (
    CloserWithArc,
    ControlledCloserWithArc,
    ControlledIdealClosingSwitch,
    ControlledIdealIntermediateSwitch,
    ControlledIdealOpeningSwitch,
    ControlledIdealTwoWaySwitch,
    ControlledOpenerWithArc,
    IdealClosingSwitch,
    IdealDiode,
    IdealGTOThyristor,
    IdealIntermediateSwitch,
    IdealOpeningSwitch,
    IdealThyristor,
    IdealTransformer,
    IdealTriac,
    IdealTwoWaySwitch,
    Idle,
    OpenerWithArc,
    Short,
)

ALL = [IdealDiode, IdealThyristor, IdealGTOThyristor, IdealTriac, IdealOpeningSwitch, IdealClosingSwitch,
       ControlledIdealOpeningSwitch, ControlledIdealClosingSwitch, OpenerWithArc, CloserWithArc,
       ControlledOpenerWithArc, ControlledCloserWithArc, IdealTwoWaySwitch, ControlledIdealTwoWaySwitch,
       IdealIntermediateSwitch, ControlledIdealIntermediateSwitch, IdealTransformer, Idle, Short]

# --------------------------------------------------------------------------
# declarations and units


@pytest.mark.parametrize("component", [
    *(klass() for klass in ALL),
    IdealDiode(Ron=0, Goff=0, Vknee=0.7, useHeatPort=True), IdealTransformer(considerMagnetization=True, n=2),
    IdealOpeningSwitch(useHeatPort=True), ControlledIdealTwoWaySwitch(level=2, useHeatPort=True),
], ids=lambda c: f"{type(c).__name__}({', '.join(f'{k}={v}' for k, v in c._modifiers.items())})")
def test_declarations(component):
    """Own names only, locally balanced, every Boolean defined once."""
    check_declarations(component)


@pytest.mark.parametrize("klass", ALL, ids=lambda k: k.__name__)
def test_units(klass):
    """No equation mixes units (Boolean inputs fed by a BooleanStep, control pins by 1 V)."""
    class Harness(Model):
        def build(self):
            self.x = klass()
            self.x.ensure_built()
            for key in ("control", "fire", "fire1"):
                port = getattr(self.x, key, None)
                if port is None:
                    continue
                if hasattr(port, "v"):
                    self.c = ConstantVoltage(V=1)
                    self.g = Ground()
                    self.connect(self.c.p, port)
                    self.connect(self.c.n, self.g.p)
                else:
                    self.b = BooleanStep(startTime=0.5)
                    self.connect(self.b.y, port)

    with warnings.catch_warnings():
        warnings.simplefilter("error", UnitWarning)
        check_units(flatten(Harness()))


# --------------------------------------------------------------------------
# the diode characteristic


@pytest.mark.parametrize("Ron, Goff, Vknee", [(0.0, 0.0, 0.0), (0.1, 0.1, 0.0), (0.2, 0.2, 5.0), (1e-5, 1e-5, 0.7)])
def test_diode_characteristic(Ron, Goff, Vknee):
    """Every point lies on the two lines through the knee (Vknee, Goff*Vknee), and off = (v < Vknee)."""
    class Circuit(Model):
        experiment = Experiment(stop_time=1.0, interval=1e-3)

        def build(self):
            self.src = SineVoltage(V=10, f=1)
            self.d = IdealDiode(Ron=Ron, Goff=Goff, Vknee=Vknee)
            self.R = Resistor(R=1.0)
            self.g = Ground()
            self.connect(self.src.p, self.d.p)
            self.connect(self.d.n, self.R.p)
            self.connect(self.R.n, self.g.p)
            self.connect(self.src.n, self.g.p)

    r = simulate(Circuit())
    assert r.success
    t, v, i, off = r.time, r["d.v"], r["d.i"], r["d.off"]
    u = 10 * np.sin(2 * np.pi * t)
    # the independent solution: the source, 1 Ohm and the piecewise-linear characteristic
    knee_u = Vknee + Goff * Vknee * 1.0
    blocking = u < knee_u
    i_expected = np.where(blocking, Goff * u / (1 + Goff), (u - Vknee + Ron * Goff * Vknee) / (1 + Ron))
    assert np.allclose(i, i_expected, rtol=0, atol=1e-9)
    assert np.allclose(v, u - i, atol=1e-9)
    clear = np.abs(u - knee_u) > 1e-6
    assert np.array_equal(off[clear], blocking[clear])
    # one event per crossing of the knee after the start, no more
    fine = np.linspace(1e-9, 1 - 1e-9, 100001)
    crossings = np.count_nonzero(np.diff(np.sign(10 * np.sin(2 * np.pi * fine) - knee_u)) != 0)
    assert len([e for e in r.events if e.kind == "state"]) == crossings


# --------------------------------------------------------------------------
# switches


def _switch_circuit(switch, control=None):
    class Circuit(Model):
        experiment = Experiment(stop_time=1.0, interval=1e-3)

        def build(self):
            self.src = ConstantVoltage(V=10)
            self.s = switch
            self.R = Resistor(R=10)
            self.g = Ground()
            self.connect(self.src.p, self.s.p)
            self.connect(self.s.n, self.R.p)
            self.connect(self.R.n, self.g.p)
            self.connect(self.src.n, self.g.p)
            if control == "boolean":
                self.pulse = BooleanPulse(period=0.5, width=40)  # true on [0, 0.2) and [0.5, 0.7)
                self.connect(self.pulse.y, self.s.control)
            elif control == "pin":
                self.ctrl = SineVoltage(V=1, f=2)  # above 0.5 V on (1/24, 5/24) and (13/24, 17/24)
                self.connect(self.ctrl.p, self.s.control)
                self.connect(self.ctrl.n, self.g.p)
    return Circuit()


def _closed_open(Ron=1e-5, Goff=1e-5):
    return 10 / (10 + Ron), 10 * Goff / (1 + 10 * Goff)


@pytest.mark.parametrize("switch, control, closed_when", [
    (IdealOpeningSwitch(), "boolean", "not pulse"),
    (IdealClosingSwitch(), "boolean", "pulse"),
    (ControlledIdealOpeningSwitch(), "pin", "not above"),
    (ControlledIdealClosingSwitch(), "pin", "above"),
], ids=lambda x: type(x).__name__ if not isinstance(x, str) else x)
def test_switch_states(switch, control, closed_when):
    """Closed: i = V/(R + Ron); open: i = V*Goff/(1 + R*Goff).

    (The switches with arc need an inductive load: on a resistor the arc
    voltage ``V0*sign(i)`` above the source voltage has no solution, in the
    MSL model too; they are tested below.)
    """
    r = simulate(_switch_circuit(switch, control))
    assert r.success
    t, i = r.time, r["s.i"]
    pulse = ((t % 0.5) < 0.2)
    above = np.sin(4 * np.pi * t) > 0.5
    closed = {"pulse": pulse, "not pulse": ~pulse, "above": above, "not above": ~above}[closed_when]
    on, off = _closed_open()
    # away from the switching instants (rows at events carry both sides)
    edges = np.array([0.2, 0.5, 0.7, 1.0, 1 / 24, 5 / 24, 13 / 24, 17 / 24])
    away = np.min(np.abs(t[:, None] - edges[None, :]), axis=1) > 2e-3
    assert np.allclose(i[away & closed], on, rtol=1e-9)
    assert np.allclose(i[away & ~closed], off, rtol=1e-6)
    assert np.allclose(r["s.LossPower"], r["s.v"] * i)


@pytest.mark.parametrize("controlled", [False, True])
def test_two_way_and_intermediate_switch(controlled):
    """The two-way switch routes p to n1 or n2; the intermediate switch straight or crossed."""
    Ron, Goff = 1e-5, 1e-5

    class Circuit(Model):
        experiment = Experiment(stop_time=1.0, interval=1e-2)

        def build(self):
            self.g = Ground()
            self.src = ConstantVoltage(V=10)
            self.tw = ControlledIdealTwoWaySwitch() if controlled else IdealTwoWaySwitch()
            self.R1, self.R2 = Resistor(R=1), Resistor(R=2)
            self.connect(self.src.n, self.g.p)
            self.connect(self.src.p, self.tw.p)
            self.connect(self.tw.n1, self.R1.p)
            self.connect(self.tw.n2, self.R2.p)
            self.connect(self.R1.n, self.g.p)
            self.connect(self.R2.n, self.g.p)
            # intermediate: two sources 10 V and 20 V into p1, p2; n1, n2 through 1 Ohm and 2 Ohm
            self.srcA, self.srcB = ConstantVoltage(V=10), ConstantVoltage(V=20)
            self.im = ControlledIdealIntermediateSwitch() if controlled else IdealIntermediateSwitch()
            self.Ra, self.Rb = Resistor(R=1), Resistor(R=2)
            self.connect(self.srcA.n, self.g.p)
            self.connect(self.srcB.n, self.g.p)
            self.connect(self.srcA.p, self.im.p1)
            self.connect(self.srcB.p, self.im.p2)
            self.connect(self.im.n1, self.Ra.p)
            self.connect(self.im.n2, self.Rb.p)
            self.connect(self.Ra.n, self.g.p)
            self.connect(self.Rb.n, self.g.p)
            if controlled:
                self.ctrl = SineVoltage(V=1, f=1)  # control.v > 0.5 on (1/12, 5/12)
                self.connect(self.ctrl.n, self.g.p)
                self.connect(self.ctrl.p, self.tw.control)
                self.connect(self.ctrl.p, self.im.control)
            else:
                self.step = BooleanStep(startTime=0.5)
                self.connect(self.step.y, self.tw.control)
                self.connect(self.step.y, self.im.control)

    r = simulate(Circuit())
    assert r.success
    t = r.time
    switched = (np.sin(2 * np.pi * t) > 0.5) if controlled else (t >= 0.5)
    away = (np.abs(t - 0.5) > 1e-3) & (np.abs(t - 1 / 12) > 1e-3) & (np.abs(t - 5 / 12) > 1e-3)
    # the two-way switch: the closed path Ron in series with its resistor, the open one Goff
    i1 = np.where(switched, 10 * Goff / (1 + Goff), 10 / (1 + Ron))
    i2 = np.where(switched, 10 / (2 + Ron), 10 * Goff / (1 + 2 * Goff))
    assert np.allclose(r["R1.i"][away], i1[away], rtol=1e-6)
    assert np.allclose(r["R2.i"][away], i2[away], rtol=1e-6)
    # the intermediate switch, solved as a linear network (nodes a = n1, b = n2) with numpy
    for k in np.flatnonzero(away)[::10]:
        crossed = bool(switched[k])
        g_aa = 1 / Ron if not crossed else Goff    # p1--n1
        g_bb = 1 / Ron if not crossed else Goff    # p2--n2
        g_ab = 1 / Ron if crossed else Goff        # p1--n2
        g_ba = 1 / Ron if crossed else Goff        # p2--n1
        A = np.array([[g_aa + g_ba + 1, 0], [0, g_bb + g_ab + 1 / 2]])
        b = np.array([10 * g_aa + 20 * g_ba, 20 * g_bb + 10 * g_ab])
        va, vb = np.linalg.solve(A, b)
        assert math.isclose(r["Ra.v"][k], va, rel_tol=1e-8)
        assert math.isclose(r["Rb.v"][k], vb, rel_tol=1e-8)


def test_thyristor_latches_and_gto_turns_off():
    """A thyristor fired once conducts until its current reverses; a GTO only while fired."""
    class Circuit(Model):
        experiment = Experiment(stop_time=1.0, interval=1e-3)

        def build(self):
            self.g = Ground()
            self.src = SineVoltage(V=10, f=1)
            self.th, self.gto = IdealThyristor(Vknee=0.5), IdealGTOThyristor(Vknee=0.5)
            self.R1, self.R2 = Resistor(R=10), Resistor(R=10)
            self.fire = BooleanPulse(period=1, width=10, startTime=0.1)  # fired on [0.1, 0.2)
            for d, R in ((self.th, self.R1), (self.gto, self.R2)):
                self.connect(self.src.p, d.p)
                self.connect(d.n, R.p)
                self.connect(R.n, self.g.p)
                self.connect(self.fire.y, d.fire)
            self.connect(self.src.n, self.g.p)

    r = simulate(Circuit())
    assert r.success
    t = r.time
    u = 10 * np.sin(2 * np.pi * t)
    conducting = (u - 0.5) / (10 + 1e-5)
    th_on = (t > 0.1 + 1e-3) & (u > 0.5 + 1e-3)   # fired at 0.1, on until u falls below the knee
    gto_on = th_on & (t < 0.2 - 1e-3)
    th_off = (t < 0.1 - 1e-3) | (u < 0.5 - 1e-3)
    gto_off = th_off | (t > 0.2 + 1e-3)
    assert np.allclose(r["th.i"][th_on], conducting[th_on], rtol=1e-6)
    assert np.all(np.abs(r["th.i"][th_off]) < 2e-4)
    assert np.allclose(r["gto.i"][gto_on], conducting[gto_on], rtol=1e-6)
    assert np.all(np.abs(r["gto.i"][gto_off]) < 2e-4)


# --------------------------------------------------------------------------
# arc


@pytest.mark.parametrize("kind", ["CloserWithArc", "ControlledOpenerWithArc"])
def test_arc_voltage_and_quench_time(kind):
    """50 V on 0.1 H + 1 Ohm, opened at 0.5 s: v = min(Vmax, V0 + dVdt*(t - 0.5))*sign(i) until i = 0.

    The current is compared with the closed-form solution of L di/dt = 50 -
    R*i - v_arc(t), and the quench instant with its zero crossing.
    """
    V0, dVdt, Vmax, L, R = 30.0, 1e4, 60.0, 0.1, 1.0

    class Circuit(Model):
        experiment = Experiment(stop_time=0.9, interval=1e-4, method="BDF")

        def build(self):
            self.g = Ground()
            self.src = ConstantVoltage(V=50)
            arc = dict(V0=V0, dVdt=dVdt, Vmax=Vmax, off=dict(fixed=True))
            self.sw = CloserWithArc(**arc) if kind == "CloserWithArc" else ControlledOpenerWithArc(**arc)
            self.L = Inductor(L=L, i=dict(start=0, fixed=True))
            self.R = Resistor(R=R)
            if kind == "CloserWithArc":
                self.pulse = BooleanPulse(period=1)   # closed on [0, 0.5)
                self.connect(self.pulse.y, self.sw.control)
            else:
                self.step = StepVoltage(V=1, startTime=0.5)   # control.v > 0.5 V from 0.5 s: open
                self.connect(self.step.p, self.sw.control)
                self.connect(self.step.n, self.g.p)
            self.connect(self.src.p, self.sw.p)
            self.connect(self.sw.n, self.L.p)
            self.connect(self.L.n, self.R.p)
            self.connect(self.R.n, self.g.p)
            self.connect(self.src.n, self.g.p)

    r = simulate(Circuit(), rtol=1e-8)
    assert r.success
    # closed form: closed (Ron = 1e-5) up to 0.5 s; then the arc rising (linear ODE with a ramp)
    # until Vmax at t1 = 0.5 + (Vmax - V0)/dVdt; then L di/dt = 50 - Vmax - R*i, to i = 0
    i0 = 50 / (R + 1e-5) * (1 - math.exp(-(R + 1e-5) * 0.5 / L))
    a, b, t1 = 50 - V0, dVdt, 0.5 + (Vmax - V0) / dVdt
    slope = -b / R
    offset = (a - L * slope) / R

    def current(t):
        rising = offset + slope * (t - 0.5) + (i0 - offset) * np.exp(-R * (t - 0.5) / L)
        i1 = offset + slope * (t1 - 0.5) + (i0 - offset) * math.exp(-R * (t1 - 0.5) / L)
        settling = (50 - Vmax) / R + (i1 - (50 - Vmax) / R) * np.exp(-R * (t - t1) / L)
        return np.where(t < t1, rising, settling), i1

    i1 = current(t1)[1]
    t_quench = t1 + L / R * math.log((i1 - (50 - Vmax) / R) / (-(50 - Vmax) / R))
    t, i, v = r.time, r["L.i"], r["sw.v"]
    burning = (t > 0.5 + 1e-6) & (t < t_quench - 2e-5)   # it quenches some 6 us before i = 0 (below)
    assert np.allclose(i[burning], current(t[burning])[0], rtol=0, atol=1e-5)
    assert np.allclose(v[burning], np.minimum(Vmax, V0 + dVdt * (t[burning] - 0.5)), rtol=1e-9)
    quenched = [e.time for e in r.events if any("quenched" in name for name, *_ in e.changes)]
    # quenched where |i| <= Goff*|v| = 6e-4 A, some 6 us before i = 0 (di/dt = -100 A/s there)
    assert quenched and 0 < t_quench - quenched[-1] < 1e-5
    after = t > t_quench + 1e-4
    assert np.allclose(i[after], 1e-5 * v[after], rtol=1e-6, atol=1e-12)
    assert abs(r.at(0.9, "sw.v") - 50) < 1e-3   # the open switch takes the source voltage


# --------------------------------------------------------------------------
# transformer, idle, short


@pytest.mark.parametrize("magnetization", [False, True])
def test_ideal_transformer(magnetization):
    """v1 = n*v2; i1 + i2/n = 0, or with magnetization Lm1*der(i1 + i2/n) = v1."""
    n, Lm1 = 4.0, 2.0

    class Circuit(Model):
        experiment = Experiment(stop_time=1.0, interval=1e-3)

        def build(self):
            self.g, self.g2 = Ground(), Ground()
            self.src = ConstantVoltage(V=100)
            self.tr = IdealTransformer(n=n, considerMagnetization=magnetization, Lm1=Lm1,
                                       **({"im1": dict(start=0, fixed=True)} if magnetization else {}))
            self.load = Resistor(R=5)
            self.idle = Idle()
            self.short = Short()
            self.connect(self.src.p, self.tr.p1)
            self.connect(self.src.n, self.tr.n1)
            self.connect(self.src.n, self.g.p)
            self.connect(self.tr.p2, self.load.p)
            self.connect(self.load.n, self.short.p)
            self.connect(self.short.n, self.tr.n2)
            self.connect(self.tr.n2, self.g2.p)
            self.connect(self.tr.p2, self.idle.p)
            self.connect(self.idle.n, self.g2.p)

    r = simulate(Circuit())
    assert r.success
    t = r.time
    assert np.allclose(r["tr.v2"], 100 / n)
    assert np.allclose(r["load.i"], 100 / n / 5)
    expected_i1 = 100 / n / 5 / n + (100 * t / Lm1 if magnetization else 0)
    assert np.allclose(r["tr.i1"], expected_i1, rtol=1e-6)
    assert np.allclose(r["idle.i"], 0) and np.allclose(r["short.v"], 0)


def test_triac_conducts_both_half_waves():
    """Fired all the time, the triac conducts both half waves through 20 Ohm (minus the knee)."""
    class Circuit(Model):
        experiment = Experiment(stop_time=1.0, interval=1e-3)

        def build(self):
            self.g = Ground()
            self.V = SineVoltage(V=5, f=2)
            self.R = Resistor(R=20)
            self.fire = BooleanStep(startTime=0.0)
            self.triac = IdealTriac(capacitor=dict(v=dict(start=0, fixed=True)))
            self.connect(self.V.n, self.g.p)
            self.connect(self.R.p, self.V.p)
            self.connect(self.R.n, self.triac.n)
            self.connect(self.triac.p, self.g.p)
            self.connect(self.fire.y, self.triac.fire1)

    r = simulate(Circuit())
    assert r.success
    u = 5 * np.sin(4 * np.pi * r.time)
    conducting = np.abs(u) > 2.0   # away from the turn-on, where the snubber's capacitor settles
    # through the conducting thyristor: |i| = (|u| - Vknee)/(R + Ron), less what the snubber takes
    i = -r["R.i"]
    expected = -np.sign(u) * (np.abs(u) - 0.8) / 20
    assert np.allclose(i[conducting], expected[conducting], rtol=0, atol=2e-3)


# --------------------------------------------------------------------------
# the hard case: a half-wave rectifier over 1,000 periods


V_SRC, F_SRC, R_SRC, RON, GOFF, VKNEE, R_LOAD, C_LOAD = 10.0, 50.0, 1.0, 1e-3, 1e-6, 0.7, 100.0, 1e-4
PERIODS = 1000


class HalfWave(Model):
    """10 V, 50 Hz through 1 Ohm and an ideal diode into 100 Ohm || 100 uF; energy meters as states."""

    experiment = Experiment(stop_time=PERIODS / F_SRC, interval=1 / F_SRC / 20, method="DOP853")

    E_source = Variable(unit="J", start=0.0, fixed=True)
    E_losses = Variable(unit="J", start=0.0, fixed=True)

    def build(self):
        self.src = SineVoltage(V=V_SRC, f=F_SRC)
        self.Rs = Resistor(R=R_SRC)
        self.d = IdealDiode(Ron=RON, Goff=GOFF, Vknee=VKNEE)
        self.R = Resistor(R=R_LOAD)
        self.C = Capacitor(C=C_LOAD, v=dict(start=0, fixed=True))
        self.g = Ground()
        self.connect(self.src.p, self.Rs.p)
        self.connect(self.Rs.n, self.d.p)
        self.connect(self.d.n, self.R.p)
        self.connect(self.d.n, self.C.p)
        self.connect(self.R.n, self.g.p)
        self.connect(self.C.n, self.g.p)
        self.connect(self.src.n, self.g.p)

    def equations(self):
        return [Eq(der(self.E_source), self.src.v * self.Rs.i),
                Eq(der(self.E_losses), self.Rs.LossPower + self.d.LossPower + self.R.LossPower)]


def _independent_period(v0: float) -> tuple[float, list[float]]:
    """The capacitor voltage after one period from ``v0`` at t = 0, and the switching instants.

    Each mode is a linear ODE (scipy, rtol 1e-12): conducting,
    ``i = (u - vC - Vknee + Ron*Goff*Vknee)/(Rs + Ron)``; blocking,
    ``i = Goff*(u - vC)/(1 + Rs*Goff)``; the diode switches where
    ``u - vC = Vknee*(1 + Rs*Goff)`` (the knee seen through Rs).
    """
    w, T = 2 * np.pi * F_SRC, 1 / F_SRC

    def g(t, x):
        return V_SRC * np.sin(w * t) - x[0] - VKNEE * (1 + R_SRC * GOFF)

    def rhs(on):
        def f(t, x):
            u = V_SRC * np.sin(w * t)
            i = ((u - x[0] - VKNEE + RON * GOFF * VKNEE) / (R_SRC + RON) if on
                 else GOFF * (u - x[0]) / (1 + R_SRC * GOFF))
            return [(i - x[0] / R_LOAD) / C_LOAD]
        return f

    t, x, on, switches = 0.0, [v0], g(0.0, [v0]) > 0, []
    while t < T:
        event = lambda tt, xx: g(tt, xx)  # noqa: E731
        event.terminal, event.direction = True, (-1 if on else 1)
        sol = solve_ivp(rhs(on), (t, T), x, method="DOP853", rtol=1e-12, atol=1e-14, events=event)
        t, x = sol.t[-1], [sol.y[0, -1]]
        if sol.status == 1:
            on = not on
            switches.append(t)
    return x[0], switches


def test_half_wave_rectifier_thousand_periods():
    """Two events a period, no drift from the periodic steady state, energy balanced (see docs/hard-cases.md)."""
    T = 1 / F_SRC
    v_star = brentq(lambda v: _independent_period(v)[0] - v, 0.0, V_SRC, xtol=1e-13)
    _, switches = _independent_period(v_star)
    assert len(switches) == 2

    r = simulate(HalfWave())
    assert r.success, r.message
    state_events = [e for e in r.events if e.kind == "state"]
    assert len(state_events) == 2 * PERIODS   # one turn-on and one turn-off a period, exactly
    # no drift: the capacitor voltage at the start of each of the last 900 periods is the
    # independent fixed point, with no trend
    starts = np.array([r.at(k * T, "C.v") for k in range(100, PERIODS + 1)])
    assert np.max(np.abs(starts - v_star)) < 1e-5
    slope = np.polyfit(np.arange(len(starts)), starts, 1)[0]
    assert abs(slope) * len(starts) < 1e-6
    # the switching instants of the last period are the independent ones
    last = sorted(float(e.time) - (PERIODS - 1) * T for e in state_events[-2:])
    assert np.allclose(last, sorted(switches), rtol=0, atol=2e-7)
    # energy: what the source delivered = the losses + the change of the stored energy
    stored = C_LOAD / 2 * (r["C.v"][-1] ** 2 - r["C.v"][0] ** 2)
    source, losses = r["E_source"][-1], r["E_losses"][-1]
    assert source > 0 and abs(source - losses - stored) < 1e-6 * source


def test_half_wave_rectifier_without_source_resistance_is_stiff():
    """The diode straight on the capacitor: the conducting mode's time constant is Ron*C = 0.1 us.

    A stiff method (BDF) switches twice a period; the explicit method's error,
    amplified by 1/Ron in the diode current, would switch it back and forth
    (docs/hard-cases.md).
    """
    class Stiff(Model):
        experiment = Experiment(stop_time=10 / F_SRC, interval=1e-4, method="BDF")

        def build(self):
            self.src = SineVoltage(V=V_SRC, f=F_SRC)
            self.d = IdealDiode(Ron=RON, Goff=GOFF, Vknee=VKNEE)
            self.R = Resistor(R=R_LOAD)
            self.C = Capacitor(C=C_LOAD, v=dict(start=0, fixed=True))
            self.g = Ground()
            self.connect(self.src.p, self.d.p)
            self.connect(self.d.n, self.R.p)
            self.connect(self.d.n, self.C.p)
            self.connect(self.R.n, self.g.p)
            self.connect(self.C.n, self.g.p)
            self.connect(self.src.n, self.g.p)

    r = simulate(Stiff())
    assert r.success
    assert len([e for e in r.events if e.kind == "state"]) == 2 * 10
