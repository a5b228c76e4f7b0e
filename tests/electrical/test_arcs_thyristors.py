"""Switches with arc, the Thyristor and the SimpleTriac against closed forms and independent computations.

**Arcs** (Modelica.Electrical.Analog.Interfaces.IdealSwitchWithArc): when
the switch opens at ``t0`` the current is not interrupted; an arc burns with
the voltage ``min(Vmax, V0 + dVdt*(t - t0))``, opposing the current, until
``|i| <= Goff*|v|`` (quenched), from then on ``i = Goff*v``.  A source ``U``
driving an inductor ``L`` and a resistor ``R`` through the switch gives,
while the arc burns, the linear ODE ``L di/dt = U - R*i - v_arc(t)``: with a
ramp (or constant) right-hand side, ``i`` is a line plus a decaying
exponential, in closed form, and the quench instant is the root of
``i(t) = Goff*v_arc(t)``.  One case reaches ``Vmax`` before it quenches
(``OpenerWithArc``, a Boolean control), one quenches on the ramp
(``ControlledCloserWithArc``, opening when its control pin falls below
``level``).

**Thyristor** (Modelica.Electrical.Analog.Semiconductors.Thyristor): its
static characteristics, ``Anode.i = vAK/Roff`` while ``vControl < Voff``
(``Roff = VDRM^2/VTM/IH``) and ``vAK/Ron`` once ``vControl > Von`` (``Ron =
(VTM - 0.7)/ITM``), and the first-order dynamics of ``vControl`` towards
``vContot``, time constant ``1.87*TON`` rising and ``0.638*TOFF`` falling.

**SimpleTriac**: two thyristors in antiparallel, their gates fed through
ideal diodes: blocking, the same conductance in both directions (computed
here from the network); fired, it conducts both half waves alike.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq

from acausal import Experiment, Model, simulate
from acausal.library.blocks import BooleanStep
from acausal.library.electrical import (
    ConstantVoltage,
    Ground,
    Inductor,
    PulseCurrent,
    RampVoltage,
    Resistor,
    SimpleTriac,
    SineVoltage,
    StepVoltage,
    Thyristor,
)
from acausal.library.electrical.ideal import ControlledCloserWithArc, OpenerWithArc

RON_SWITCH = 1e-5    # Ohm, the switches' default closed resistance
GOFF_SWITCH = 1e-5   # S, their default open conductance


# --------------------------------------------------------------------------
# arcs


def arc_voltage(t, t_open, V0, dVdt, Vmax):
    """The MSL arc voltage magnitude after opening at t_open."""
    return np.minimum(Vmax, V0 + dVdt * (np.asarray(t) - t_open))


def rl_arc_current(t, t_open, i_open, U, R, L, V0, dVdt, Vmax):
    """The closed-form current of L di/dt = U - R*i - v_arc(t) from i(t_open) = i_open (i > 0).

    On the ramp, v_arc = V0 + dVdt*s (s = t - t_open): i = c0 + c1*s + (i_open - c0)*exp(-s/tau),
    c1 = -dVdt/R, c0 = (U - V0 - L*c1)/R, tau = L/R.  After Vmax (at s1 = (Vmax - V0)/dVdt): the
    first-order decay towards (U - Vmax)/R from i(s1).
    """
    tau = L / R
    s = np.asarray(t, dtype=float) - t_open
    c1 = -dVdt / R
    c0 = (U - V0 - L * c1) / R
    s1 = (Vmax - V0) / dVdt

    def on_ramp(x):
        return c0 + c1 * x + (i_open - c0) * np.exp(-x / tau)

    i1 = on_ramp(s1)
    flat = (U - Vmax) / R
    return np.where(s < s1, on_ramp(s), flat + (i1 - flat) * np.exp(-(s - s1) / tau))


def quench_time(t_open, i_open, U, R, L, V0, dVdt, Vmax, t_max):
    """The first instant after t_open with i = Goff*v_arc: the arc's extinction condition |i| <= Goff*|v|."""
    def margin(t):
        return (rl_arc_current(t, t_open, i_open, U, R, L, V0, dVdt, Vmax)
                - GOFF_SWITCH * arc_voltage(t, t_open, V0, dVdt, Vmax))
    return brentq(margin, t_open + 1e-9, t_max, xtol=1e-14)


def _quench_events(result, switch):
    return [e.time for e in result.events
            if any(name == f"{switch}.quenched" and new for name, _, new in e.changes)]


# the opener: 50 V on 1 Ohm + 0.1 H, opened at 0.5 s by a Boolean step (i = 49.7 A); the arc reaches
# Vmax = 60 V after 3 ms and the current decays towards -10 A, crossing zero some 0.18 s later
OPENER = dict(U=50.0, R=1.0, L=0.1, V0=30.0, dVdt=1e4, Vmax=60.0, t_open=0.5)
# the controlled closer: 20 V on 2 Ohm + 50 mH, opened when its control pin (a ramp 1 V -> 0 V over
# 1 s) falls below level = 0.3 V, at 0.7 s; the arc (25 V + 2000 V/s) quenches before its Vmax
CLOSER = dict(U=20.0, R=2.0, L=0.05, V0=25.0, dVdt=2000.0, Vmax=1000.0, t_open=0.7, level=0.3)


class OpenerCircuit(Model):
    """U -> OpenerWithArc -> L -> R -> ground; the switch opens (control true) at t_open."""

    experiment = Experiment(stop_time=0.8, interval=1e-4, method="BDF")

    def build(self):
        c = OPENER
        self.ground = Ground()
        self.source = ConstantVoltage(V=c["U"])
        self.switch = OpenerWithArc(V0=c["V0"], dVdt=c["dVdt"], Vmax=c["Vmax"], off=dict(fixed=True))
        self.inductor = Inductor(L=c["L"], i=dict(start=0.0, fixed=True))
        self.resistor = Resistor(R=c["R"])
        self.opening = BooleanStep(startTime=c["t_open"])
        self.connect(self.opening.y, self.switch.control)
        self.connect(self.source.p, self.switch.p)
        self.connect(self.switch.n, self.inductor.p)
        self.connect(self.inductor.n, self.resistor.p)
        self.connect(self.resistor.n, self.ground.p)
        self.connect(self.source.n, self.ground.p)


class CloserCircuit(Model):
    """U -> ControlledCloserWithArc -> L -> R -> ground; the control pin ramps from 1 V down to 0 V."""

    experiment = Experiment(stop_time=0.8, interval=1e-4, method="BDF")

    def build(self):
        c = CLOSER
        self.ground = Ground()
        self.source = ConstantVoltage(V=c["U"])
        self.switch = ControlledCloserWithArc(V0=c["V0"], dVdt=c["dVdt"], Vmax=c["Vmax"], level=c["level"],
                                              off=dict(fixed=True))
        self.inductor = Inductor(L=c["L"], i=dict(start=0.0, fixed=True))
        self.resistor = Resistor(R=c["R"])
        self.control = RampVoltage(V=-1.0, duration=1.0, offset=1.0)
        self.connect(self.control.p, self.switch.control)
        self.connect(self.control.n, self.ground.p)
        self.connect(self.source.p, self.switch.p)
        self.connect(self.switch.n, self.inductor.p)
        self.connect(self.inductor.n, self.resistor.p)
        self.connect(self.resistor.n, self.ground.p)
        self.connect(self.source.n, self.ground.p)


def _check_arc(result, c, t_stop):
    U, R, L = c["U"], c["R"], c["L"]
    arc = dict(V0=c["V0"], dVdt=c["dVdt"], Vmax=c["Vmax"])
    t_open = c["t_open"]
    # closed (Ron) from i = 0: the RL charging curve up to the opening
    R_closed = R + RON_SWITCH
    i_open = U / R_closed * (1 - math.exp(-R_closed * t_open / L))
    t_quench = quench_time(t_open, i_open, U, R, L, t_max=t_stop, **arc)
    t, i, v = result.time, result["inductor.i"], result["switch.v"]

    closed = t < t_open - 1e-9
    np.testing.assert_allclose(i[closed], U / R_closed * (1 - np.exp(-R_closed * t[closed] / L)),
                               rtol=0, atol=1e-7 * U / R)
    burning = (t > t_open + 1e-9) & (t < t_quench - 1e-6)
    assert np.count_nonzero(burning) > 50
    np.testing.assert_allclose(v[burning], arc_voltage(t[burning], t_open, **arc), rtol=1e-9)
    np.testing.assert_allclose(i[burning], rl_arc_current(t[burning], t_open, i_open, U, R, L, **arc),
                               rtol=0, atol=1e-5 * i_open)
    # the arc goes out once, where i = Goff*v_arc
    quenched = _quench_events(result, "switch")
    assert len(quenched) == 1
    assert quenched[0] == pytest.approx(t_quench, abs=2e-8)
    # then the open switch: i = Goff*v, and the source's voltage across it
    after = t > t_quench + 1e-3
    np.testing.assert_allclose(i[after], GOFF_SWITCH * v[after], rtol=1e-6, atol=1e-12)
    assert result.final("switch.v") == pytest.approx(U / (1 + R * GOFF_SWITCH), rel=1e-6)
    return t_quench, i_open


def test_opener_with_arc_rises_to_vmax_and_quenches():
    """OpenerWithArc: the arc voltage ramps from V0 to Vmax, the current follows the closed form, zero at the quench."""
    c = OPENER
    result = simulate(OpenerCircuit(), rtol=1e-8)
    assert result.success, result.message
    t_quench, _ = _check_arc(result, c, 0.8)
    # this case runs into Vmax before it quenches: the flat part is exercised
    assert t_quench > c["t_open"] + (c["Vmax"] - c["V0"]) / c["dVdt"] + 1e-3
    assert result.at(t_quench - 1e-4, "switch.v") == pytest.approx(c["Vmax"], rel=1e-9)
    # the opening is the Boolean step's time event, the arc starts exactly there
    assert result.at(c["t_open"], "switch.v", side="left") == pytest.approx(RON_SWITCH * result.at(
        c["t_open"], "inductor.i"), rel=1e-6)
    assert result.at(c["t_open"], "switch.v", side="right") == pytest.approx(c["V0"], rel=1e-9)


def test_controlled_closer_with_arc_opens_below_level_and_quenches_on_the_ramp():
    """ControlledCloserWithArc: closed while control.v >= level, opened where the ramp crosses it; quenched before Vmax."""
    c = CLOSER
    result = simulate(CloserCircuit(), rtol=1e-8)
    assert result.success, result.message
    # control.v = 1 - t crosses level at 1 - level: a state event there, to the locator's precision
    openings = [e.time for e in result.events
                if any(name == "switch.off" and new for name, _, new in e.changes)]
    assert len(openings) == 1 and openings[0] == pytest.approx(1 - c["level"], abs=1e-9)
    t_quench, _ = _check_arc(result, c, 0.8)
    assert c["V0"] + c["dVdt"] * (t_quench - c["t_open"]) < c["Vmax"]
    # the control pin draws no current
    np.testing.assert_allclose(result["switch.control.i"], 0.0, atol=0)


# --------------------------------------------------------------------------
# Thyristor

# non-default data, so that a default slipping in (or a wrong formula) shows
THYRISTOR = dict(VDRM=200.0, VRRM=150.0, VTM=1.5, IH=0.01, ITM=40.0, TON=2e-6, TOFF=10e-6)
ROFF = 200.0 ** 2 / 1.5 / 0.01     # VDRM^2/VTM/IH = 2.667 MOhm
RON = (1.5 - 0.7) / 40.0           # (VTM - 0.7)/ITM = 20 mOhm
ROFF_DEFAULT = 100.0 ** 2 / 1.7 / 6e-3   # the MSL defaults: 980 kOhm
VON = 5.0                          # the control voltage of the conducting state (default)


class ThyristorRamps(Model):
    """Slow ramps through 100 kOhm: forward to 180 V (below VDRM), reverse to -140 V (above -VRRM),
    and a thyristor with the MSL's default data to 90 V; the gates open (no gate current)."""

    experiment = Experiment(stop_time=1.0, interval=1e-3)

    def build(self):
        self.ground = Ground()
        for name, height, data in (("forward", 180.0, THYRISTOR), ("reverse", -140.0, THYRISTOR),
                                   ("defaults", 90.0, {})):
            source = RampVoltage(V=height, duration=1.0)
            series = Resistor(R=1e5)
            thyristor = Thyristor(**data, vControl=dict(fixed=True))
            setattr(self, f"source_{name}", source)
            setattr(self, f"R_{name}", series)
            setattr(self, name, thyristor)
            self.connect(source.p, series.p)
            self.connect(series.n, thyristor.Anode)
            self.connect(thyristor.Cathode, self.ground.p)
            self.connect(source.n, self.ground.p)


def test_thyristor_blocks_with_roff_in_both_directions():
    """No gate current, |vAK| below the breakthrough voltages: Anode.i = vAK/Roff, Roff = VDRM^2/VTM/IH."""
    result = simulate(ThyristorRamps(), rtol=1e-10, atol=1e-12)
    assert result.success, result.message
    t = result.time
    for name, height, roff in (("forward", 180.0, ROFF), ("reverse", -140.0, ROFF), ("defaults", 90.0, ROFF_DEFAULT)):
        v_ak, i = result[f"{name}.vAK"], result[f"{name}.Anode.i"]
        # the divider 100 kOhm : Roff, computed here
        np.testing.assert_allclose(v_ak, height * t * roff / (roff + 1e5), rtol=1e-9, atol=1e-9)
        np.testing.assert_allclose(i, v_ak / roff, rtol=1e-9, atol=1e-15)
        # it never starts to turn on: below the holding current and VDRM, no control voltage
        np.testing.assert_allclose(result[f"{name}.vControl"], 0.0, atol=1e-12)
        np.testing.assert_allclose(result[f"{name}.vConmain"], 0.0, atol=0)


def _gated(gate_current: float, width: float, stop: float, U: float = 10.0, R: float = 10.0):
    """U -> R -> Thyristor -> ground; a gate current pulse from 10 us on, width us long."""
    class Gated(Model):
        experiment = Experiment(stop_time=stop, interval=1e-7, method="BDF")

        def build(self):
            self.ground = Ground()
            self.source = ConstantVoltage(V=U)
            self.load = Resistor(R=R)
            self.thyristor = Thyristor(**THYRISTOR, vControl=dict(fixed=True))
            # the pulse's current flows from its p to its n, into the gate, out of the cathode
            self.gate = PulseCurrent(I=gate_current, width=width, period=100e-6, startTime=10e-6)
            self.connect(self.source.p, self.load.p)
            self.connect(self.load.n, self.thyristor.Anode)
            self.connect(self.thyristor.Cathode, self.ground.p)
            self.connect(self.source.n, self.ground.p)
            self.connect(self.gate.p, self.ground.p)
            self.connect(self.gate.n, self.thyristor.Gate)
    return Gated()


def test_thyristor_fired_conducts_with_ron_and_latches():
    """10 V on 10 Ohm; 10 mA into the gate for 20 us: once vControl > Von, Anode.i = vAK/Ron, held after the gate.

    Before the gate pulse it blocks (vAK/Roff); after it the anode current
    (about 1 A) stays above the holding current, so it keeps conducting.
    """
    U, R = 10.0, 10.0
    result = simulate(_gated(10e-3, 20, 100e-6, U, R), rtol=1e-8)
    assert result.success, result.message
    t, v_ak, i, v_control = result.time, result["thyristor.vAK"], result["thyristor.Anode.i"], \
        result["thyristor.vControl"]
    before = t < 10e-6
    np.testing.assert_allclose(i[before], U / (R + ROFF), rtol=1e-9)
    on = v_control > VON + 1e-9
    assert on.any() and np.all(t[on] > 10e-6)
    np.testing.assert_allclose(i[on], v_ak[on] / RON, rtol=1e-9)
    np.testing.assert_allclose(i[on], U / (R + RON), rtol=1e-7)
    # latched: conducting to the end, 70 us after the gate current stopped
    assert result.final("thyristor.Anode.i") == pytest.approx(U / (R + RON), rel=1e-9)
    assert np.all(on[t > 30e-6])


def test_thyristor_control_voltage_is_first_order_with_ton_and_toff():
    """A gate current just above 0.95*IGT, 50 us long: vContot = 10000*(iGK - 0.95*IGT)*vAK stays below Voff.

    The thyristor keeps blocking, and vControl rises towards vContot with the
    time constant 1.87*TON, then falls to 0 with 0.638*TOFF: both
    exponentials in closed form.
    """
    U, R, IGT = 10.0, 10.0, 5e-3
    i_gate = 0.95 * IGT + 1e-5
    result = simulate(_gated(i_gate, 50, 100e-6, U, R), rtol=1e-10, atol=1e-12)
    assert result.success, result.message
    t, v_control = result.time, result["thyristor.vControl"]
    v_ak = U * ROFF / (ROFF + R)
    target = 10000 * (i_gate - 0.95 * IGT) * v_ak     # about 1 V, below Voff = 1.5 V
    tau_on, tau_off = 1.87 * THYRISTOR["TON"], 0.638 * THYRISTOR["TOFF"]
    t_on, t_off = 10e-6, 60e-6
    peak = target * (1 - math.exp(-(t_off - t_on) / tau_on))
    expected = np.select([t < t_on, t < t_off],
                         [0.0, target * (1 - np.exp(-(t - t_on) / tau_on))],
                         peak * np.exp(-(t - t_off) / tau_off))
    away = (np.abs(t - t_on) > 1e-12) & (np.abs(t - t_off) > 1e-12)
    np.testing.assert_allclose(v_control[away], expected[away], rtol=0, atol=1e-6 * target)
    np.testing.assert_allclose(result["thyristor.Anode.i"], result["thyristor.vAK"] / ROFF, rtol=1e-9)


# --------------------------------------------------------------------------
# SimpleTriac


class TriacBlocking(Model):
    """80 V, 1 Hz through 1 kOhm across a SimpleTriac with its gate open."""

    experiment = Experiment(stop_time=1.0, interval=1e-3, method="BDF")

    def build(self):
        self.ground = Ground()
        self.source = SineVoltage(V=80.0, f=1.0)
        self.load = Resistor(R=1e3)
        self.triac = SimpleTriac(thyristor=dict(vControl=dict(fixed=True)),
                                 thyristor1=dict(vControl=dict(fixed=True)))
        self.connect(self.source.p, self.load.p)
        self.connect(self.load.n, self.triac.p)
        self.connect(self.triac.n, self.ground.p)
        self.connect(self.source.n, self.ground.p)


def test_simple_triac_blocks_alike_in_both_directions():
    """Blocking, the triac is linear and symmetric: both thyristors' Roff in parallel, plus the gate path.

    With the gate open, the gate network (thyristor gate, VGT/IGT = 140 Ohm;
    a reverse ideal diode, Goff; a forward one, Ron; the other gate, 140
    Ohm) leaks from p to n: G = 2/Roff + 1/(1/Goff + 2*VGT/IGT + Ron).
    """
    result = simulate(TriacBlocking(), rtol=1e-10, atol=1e-12)
    assert result.success, result.message
    t = result.time
    v = result["triac.p.v"] - result["triac.n.v"]
    i = result["triac.p.i"]
    conductance = 2 / ROFF_DEFAULT + 1 / (1 / 1e-5 + 2 * 0.7 / 5e-3 + 1e-5)
    u = 80.0 * np.sin(2 * np.pi * t)
    # (about 1 mA at the crest; 1 nA for the ideal diodes' switching at the zero crossings)
    np.testing.assert_allclose(i, u * conductance / (1 + 1e3 * conductance), rtol=1e-8, atol=1e-9)
    np.testing.assert_allclose(i, v * conductance, rtol=1e-8, atol=1e-9)
    # symmetric: the second half wave is the first one negated
    first, second = t <= 0.5, t >= 0.5
    np.testing.assert_allclose(np.interp(t[first] + 0.5, t[second], i[second]), -i[first], rtol=0, atol=1e-9)
    assert np.max(np.abs(i)) > 0.9e-3


class TriacFired(Model):
    """20 V, 50 Hz through 10 Ohm across a SimpleTriac fired from 1 ms on (5 V through 100 Ohm into g)."""

    experiment = Experiment(stop_time=0.04, interval=1e-5, method="BDF")

    def build(self):
        self.ground = Ground()
        self.source = SineVoltage(V=20.0, f=50.0)
        self.load = Resistor(R=10.0)
        self.triac = SimpleTriac(thyristor=dict(vControl=dict(fixed=True)),
                                 thyristor1=dict(vControl=dict(fixed=True)))
        self.gate_source = StepVoltage(V=5.0, startTime=1e-3)
        self.gate_resistor = Resistor(R=100.0)
        self.connect(self.source.p, self.load.p)
        self.connect(self.load.n, self.triac.p)
        self.connect(self.triac.n, self.ground.p)
        self.connect(self.source.n, self.ground.p)
        self.connect(self.gate_source.n, self.ground.p)
        self.connect(self.gate_source.p, self.gate_resistor.p)
        self.connect(self.gate_resistor.n, self.triac.g)


def test_simple_triac_fired_conducts_both_half_waves_alike():
    """Fired, the forward-biased thyristor conducts each half wave: i = u/(R + Ron||Roff), the same in both."""
    result = simulate(TriacFired(), rtol=1e-8)
    assert result.success, result.message
    t = result.time
    u = 20.0 * np.sin(2 * np.pi * 50.0 * t)
    ron = (1.7 - 0.7) / 25.0
    r_conducting = 1 / (1 / ron + 1 / ROFF_DEFAULT)
    conducting = (np.abs(u) > 2.0) & (t > 2e-3)
    # the gate circuit reaches p through the other gate's reverse-biased ideal diode too: its
    # Goff = 1e-5 S leaks at most Goff*(5 V + 20 V) = 2.5e-4 A into the main current
    leakage = 1e-5 * (5.0 + 20.0)
    np.testing.assert_allclose(result["triac.p.i"][conducting], u[conducting] / (10.0 + r_conducting),
                               rtol=1e-4, atol=leakage)
