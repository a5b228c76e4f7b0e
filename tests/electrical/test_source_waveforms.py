"""Modelica.Electrical.Analog.Sources: the time-function sources' waveforms against the MSL's definitions.

Each source drives its own resistor (2 Ohm) and the waveform is read off
the resistor, the physical load, not off the source: a voltage source's
``v`` is ``2*R.i``, a current source's ``i`` is ``-R.v/2`` (the source's
current flows from p to n inside it, so from n to p through the load).

The expected waveforms are written here in numpy from the MSL 4.1.0 text
(Modelica.Blocks.Sources: ``SignalSource``, ``Step``, ``Sine``,
``Cosine``, ``ExpSine``, ``Pulse``, ``SawTooth``, ``Trapezoid``,
``TimeTable``), not from acausal's blocks:

- everything is ``offset`` before ``startTime``;
- the periodic sources count periods with ``count = integer((time -
  startTime)/period)`` and ``T_start = startTime + count*period``, also for
  a negative ``startTime`` (the wave is already running at t = 0);
- the table is shifted by ``startTime``, interpolated linearly, a repeated
  time is a jump to the later row, and after the last row it is
  extrapolated through the last two rows.

Every discontinuity (start, pulse and saw-tooth edges, table jumps) must be
a time event: the result has a row on each side of it, so its left and
right limits are checked against the definition's values just before and
just after it.  Two current sources charge capacitors: the capacitor
voltage is the integral of the waveform, in closed form, and its error is
the integrator's.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from acausal import Experiment, Model, simulate
from acausal.library.electrical import (
    Capacitor,
    CosineCurrent,
    CosineVoltage,
    ExpSineCurrent,
    Ground,
    PulseCurrent,
    PulseVoltage,
    Resistor,
    SawToothCurrent,
    SawToothVoltage,
    SineCurrent,
    StepCurrent,
    TableCurrent,
    TableVoltage,
    TrapezoidCurrent,
)

LOAD = 2.0          # Ohm, every source's resistor
STOP = 2.5          # s
INTERVAL = 2.5e-3   # s
C_CHARGE = 0.5      # F, the capacitors the two charging current sources fill


# --------------------------------------------------------------------------
# the MSL definitions, in numpy


def _started(t, start_time):
    return np.asarray(t) >= start_time


def step(t, height, offset=0.0, startTime=0.0):
    """Blocks.Sources.Step: offset, plus height from startTime on."""
    return offset + np.where(_started(t, startTime), height, 0.0)


def sine(t, amplitude, f, phase=0.0, offset=0.0, startTime=0.0):
    """Blocks.Sources.Sine (continuous = false)."""
    return offset + np.where(_started(t, startTime),
                             amplitude * np.sin(2 * np.pi * f * (t - startTime) + phase), 0.0)


def cosine(t, amplitude, f, phase=0.0, offset=0.0, startTime=0.0):
    """Blocks.Sources.Cosine (continuous = false)."""
    return offset + np.where(_started(t, startTime),
                             amplitude * np.cos(2 * np.pi * f * (t - startTime) + phase), 0.0)


def exp_sine(t, amplitude, f, phase=0.0, damping=1.0, offset=0.0, startTime=0.0):
    """Blocks.Sources.ExpSine."""
    return offset + np.where(_started(t, startTime),
                             amplitude * np.exp(-(t - startTime) * damping)
                             * np.sin(2 * np.pi * f * (t - startTime) + phase), 0.0)


def _period_start(t, period, startTime):
    """(count, T_start): the MSL's period counter, integer() being floor."""
    count = np.floor((np.asarray(t) - startTime) / period)
    return count, startTime + count * period


def pulse(t, amplitude, width, period, offset=0.0, startTime=0.0):
    """Blocks.Sources.Pulse (nperiod = -1): amplitude during the first width % of each period."""
    _, t_start = _period_start(t, period, startTime)
    on = _started(t, startTime) & (t < t_start + period * width / 100)
    return offset + np.where(on, amplitude, 0.0)


def saw_tooth(t, amplitude, period, offset=0.0, startTime=0.0):
    """Blocks.Sources.SawTooth (nperiod = -1): amplitude*(time - T_start)/period."""
    _, t_start = _period_start(t, period, startTime)
    return offset + np.where(_started(t, startTime), amplitude * (t - t_start) / period, 0.0)


def trapezoid(t, amplitude, rising, width, falling, period, nperiod=-1, offset=0.0, startTime=0.0):
    """Blocks.Sources.Trapezoid: rise, hold, fall, then zero, nperiod times (< 0: for ever)."""
    count, t_start = _period_start(t, period, startTime)
    tau = np.asarray(t) - t_start
    shape = np.select([tau < rising, tau < rising + width, tau < rising + width + falling],
                      [amplitude * tau / max(rising, 1e-300), amplitude,
                       amplitude * (rising + width + falling - tau) / max(falling, 1e-300)], 0.0)
    inactive = ~_started(t, startTime) | (nperiod == 0) | ((nperiod > 0) & (count >= nperiod))
    return offset + np.where(inactive, 0.0, shape)


def time_table(t, table, offset=0.0, startTime=0.0):
    """Blocks.Sources.TimeTable (timeScale = 1, shiftTime = startTime), right-continuous at jumps."""
    rows = np.asarray(table, dtype=float)
    times, values = rows[:, 0], rows[:, 1]
    t = np.atleast_1d(np.asarray(t, dtype=float))
    out = np.empty_like(t)
    for k, tk in enumerate(t):
        if tk < startTime:
            out[k] = offset
            continue
        x = tk - startTime
        # the interval [times[j], times[j+1]] that holds x, the later one at a shared time;
        # past the last row the last interval (the extrapolation through the last two rows)
        j = min(int(np.searchsorted(times, x, side="right")) - 1, len(times) - 2)
        t0, t1, y0, y1 = times[j], times[j + 1], values[j], values[j + 1]
        out[k] = offset + (y1 if t1 == t0 else y0 + (y1 - y0) / (t1 - t0) * (x - t0))
    return out


def _periodic_edges(period, startTime, *offsets_in_period, stop=STOP):
    """The instants startTime + k*period + offset (k = 0, 1, ... and earlier periods for a negative startTime)."""
    first_period = math.floor(-startTime / period) if startTime < 0 else 0
    out = []
    for k in range(first_period, int(stop / period) + 2):
        for offset in offsets_in_period:
            edge = startTime + k * period + offset
            if 0 < edge < stop:
                out.append(edge)
    return sorted(out)


# --------------------------------------------------------------------------
# the circuits: (name, the source's parameters, the expected waveform, its discontinuities)

VOLTAGE_CASES = {
    "cosine": (dict(V=2.0, f=2.5, phase=0.7, offset=0.3, startTime=0.2),
               lambda t: cosine(t, 2.0, 2.5, 0.7, 0.3, 0.2), [0.2]),
    "pulse": (dict(V=3.0, width=30, period=0.4, offset=-1.0, startTime=0.15),
              lambda t: pulse(t, 3.0, 30, 0.4, -1.0, 0.15), _periodic_edges(0.4, 0.15, 0.0, 0.12)),
    # started 0.1 s before the run: at t = 0 the first pulse (0.18 s long) is on, until 0.08 s
    "pulse_running": (dict(V=1.5, width=60, period=0.3, startTime=-0.1),
                      lambda t: pulse(t, 1.5, 60, 0.3, 0.0, -0.1), _periodic_edges(0.3, -0.1, 0.0, 0.18)),
    "sawtooth": (dict(V=2.0, period=0.35, offset=-0.5, startTime=0.1),
                 lambda t: saw_tooth(t, 2.0, 0.35, -0.5, 0.1), _periodic_edges(0.35, 0.1, 0.0)),
    "sawtooth_running": (dict(V=1.0, period=0.4, startTime=-0.1),
                         lambda t: saw_tooth(t, 1.0, 0.4, 0.0, -0.1), _periodic_edges(0.4, -0.1, 0.0)),
    # a jump at table time 0.2 (t = 0.5), extrapolated after table time 0.7 (t = 1.0)
    "table": (dict(table=[[0, 0], [0.2, 1], [0.2, 3], [0.5, -1], [0.7, 0]], offset=0.25, startTime=0.3),
              lambda t: time_table(t, [[0, 0], [0.2, 1], [0.2, 3], [0.5, -1], [0.7, 0]], 0.25, 0.3), [0.5]),
    # the MSL default table [0, 0; 1, 1; 2, 4], extrapolated after 2 s with slope 3
    "table_default": (dict(), lambda t: time_table(t, [[0, 0], [1, 1], [2, 4]]), []),
}

CURRENT_CASES = {
    "step": (dict(I=-2.0, offset=0.5, startTime=0.35), lambda t: step(t, -2.0, 0.5, 0.35), [0.35]),
    "sine": (dict(I=1.5, f=1.7, phase=-0.6, offset=0.2, startTime=0.25),
             lambda t: sine(t, 1.5, 1.7, -0.6, 0.2, 0.25), [0.25]),
    "cosine": (dict(I=2.0, f=1.3, phase=-1.1, offset=-0.4, startTime=0.1),
               lambda t: cosine(t, 2.0, 1.3, -1.1, -0.4, 0.1), [0.1]),
    "expsine": (dict(I=3.0, f=2.2, phase=0.5, damping=2.0, offset=0.1, startTime=0.3),
                lambda t: exp_sine(t, 3.0, 2.2, 0.5, 2.0, 0.1, 0.3), [0.3]),
    "pulse": (dict(I=2.0, width=25, period=0.5, offset=0.5, startTime=0.2),
              lambda t: pulse(t, 2.0, 25, 0.5, 0.5, 0.2), _periodic_edges(0.5, 0.2, 0.0, 0.125)),
    "sawtooth": (dict(I=-3.0, period=0.45, offset=1.0, startTime=0.3),
                 lambda t: saw_tooth(t, -3.0, 0.45, 1.0, 0.3), _periodic_edges(0.45, 0.3, 0.0)),
    # two periods from 0.2 s, then offset; rising 0.1 s, flat 0.15 s, falling 0.05 s, zero 0.1 s
    "trapezoid": (dict(I=2.0, rising=0.1, width=0.15, falling=0.05, period=0.4, nperiod=2, offset=-0.5,
                       startTime=0.2),
                  lambda t: trapezoid(t, 2.0, 0.1, 0.15, 0.05, 0.4, 2, -0.5, 0.2), []),
    # starts with a jump to offset + 1 at 0.5 s; a jump at table time 0.4 (t = 0.9); extrapolated after 1.5 s
    "table": (dict(table=[[0, 1], [0.4, -1], [0.4, 0.5], [1.0, 2.0]], offset=-0.2, startTime=0.5),
              lambda t: time_table(t, [[0, 1], [0.4, -1], [0.4, 0.5], [1.0, 2.0]], -0.2, 0.5), [0.5, 0.9]),
}


class _Loaded(Model):
    """Helpers: a source across (through) its own LOAD resistor to ground."""

    experiment = Experiment(stop_time=STOP, interval=INTERVAL)

    def _load(self, name, source):
        setattr(self, name, source)
        load = Resistor(R=LOAD)
        setattr(self, f"R_{name}", load)
        self.connect(source.p, load.p)
        self.connect(load.n, self.ground.p)
        self.connect(source.n, self.ground.p)


class VoltageWaveforms(_Loaded):
    """The voltage sources without a closed-form test elsewhere, each across 2 Ohm."""

    def build(self):
        self.ground = Ground()
        p = {name: case[0] for name, case in VOLTAGE_CASES.items()}
        self._load("cosine", CosineVoltage(**p["cosine"]))
        self._load("pulse", PulseVoltage(**p["pulse"]))
        self._load("pulse_running", PulseVoltage(**p["pulse_running"]))
        self._load("sawtooth", SawToothVoltage(**p["sawtooth"]))
        self._load("sawtooth_running", SawToothVoltage(**p["sawtooth_running"]))
        self._load("table", TableVoltage(**p["table"]))
        self._load("table_default", TableVoltage(**p["table_default"]))


class CurrentWaveforms(_Loaded):
    """The current sources through 2 Ohm each; two more charge a capacitor each."""

    def build(self):
        self.ground = Ground()
        p = {name: case[0] for name, case in CURRENT_CASES.items()}
        self._load("step", StepCurrent(**p["step"]))
        self._load("sine", SineCurrent(**p["sine"]))
        self._load("cosine", CosineCurrent(**p["cosine"]))
        self._load("expsine", ExpSineCurrent(**p["expsine"]))
        self._load("pulse", PulseCurrent(**p["pulse"]))
        self._load("sawtooth", SawToothCurrent(**p["sawtooth"]))
        self._load("trapezoid", TrapezoidCurrent(**p["trapezoid"]))
        self._load("table", TableCurrent(**p["table"]))
        # the charging sources: the current enters the capacitor at its p pin from the source's n pin
        self.pulse_charge = PulseCurrent(I=2.0, width=40, period=0.3, offset=-0.25, startTime=0.1)
        self.sawtooth_charge = SawToothCurrent(I=1.5, period=0.7, offset=0.1, startTime=-0.2)
        for name in ("pulse_charge", "sawtooth_charge"):
            source = getattr(self, name)
            capacitor = Capacitor(C=C_CHARGE, v=dict(start=0.0, fixed=True))
            setattr(self, f"C_{name}", capacitor)
            self.connect(source.p, self.ground.p)
            self.connect(source.n, capacitor.p)
            self.connect(capacitor.n, self.ground.p)


@pytest.fixture(scope="module")
def voltage_run():
    result = simulate(VoltageWaveforms(), rtol=1e-10, atol=1e-12)
    assert result.success, result.message
    return result


@pytest.fixture(scope="module")
def current_run():
    result = simulate(CurrentWaveforms(), rtol=1e-10, atol=1e-12)
    assert result.success, result.message
    return result


def _measured(result, kind, name):
    """The waveform as the load sees it."""
    if kind == "voltage":
        return LOAD * result[f"R_{name}.i"]
    return -result[f"R_{name}.v"] / LOAD


def _trapezoid_corners():
    corners = []
    for k in range(2):
        start = 0.2 + 0.4 * k
        corners += [start, start + 0.1, start + 0.25, start + 0.3]
    return corners


def _check(result, kind, name, expected, edges):
    t = result.time
    got = _measured(result, kind, name)
    # away from the discontinuities (each has two rows, one either side, compared below)
    away = np.ones_like(t, dtype=bool)
    for edge in edges:
        away &= np.abs(t - edge) > 1e-9
    np.testing.assert_allclose(got[away], expected(t[away]), rtol=0, atol=1e-9,
                               err_msg=f"{kind} source {name}")
    # the limits at each discontinuity: the result's rows just before and just after it
    for edge in edges:
        left = _measured_at(result, kind, name, edge, "left")
        right = _measured_at(result, kind, name, edge, "right")
        assert left == pytest.approx(float(expected(np.array([edge - 1e-9]))[0]), abs=1e-7), (name, edge, "left")
        assert right == pytest.approx(float(expected(np.array([edge + 1e-9]))[0]), abs=1e-7), (name, edge, "right")


def _measured_at(result, kind, name, t, side):
    if kind == "voltage":
        return LOAD * result.at(t, f"R_{name}.i", side=side)
    return -result.at(t, f"R_{name}.v", side=side) / LOAD


@pytest.mark.parametrize("name", list(VOLTAGE_CASES))
def test_voltage_source_waveform(voltage_run, name):
    """The voltage across the load is the MSL waveform at every row and on both sides of every jump."""
    _, expected, edges = VOLTAGE_CASES[name]
    _check(voltage_run, "voltage", name, expected, edges)


@pytest.mark.parametrize("name", list(CURRENT_CASES))
def test_current_source_waveform(current_run, name):
    """The current through the load is the MSL waveform at every row and on both sides of every jump."""
    _, expected, edges = CURRENT_CASES[name]
    _check(current_run, "current", name, expected, edges)


def test_discontinuities_are_time_events(voltage_run, current_run):
    """Every jump of every waveform is a time event at its exact instant; there are no state events."""
    for result, cases in ((voltage_run, VOLTAGE_CASES), (current_run, CURRENT_CASES)):
        event_times = np.array([e.time for e in result.events if e.kind == "time"])
        assert not [e for e in result.events if e.kind == "state"]
        for name, (_, _, edges) in cases.items():
            for edge in edges:
                assert np.min(np.abs(event_times - edge)) < 1e-12, (name, edge)


def test_trapezoid_corners_and_its_two_periods(current_run):
    """Offset after nperiod = 2 periods; the corners of the trapezoid at rising, width and falling."""
    t = current_run.time
    got = _measured(current_run, "current", "trapezoid")
    assert np.allclose(got[t >= 1.0 + 1e-9], -0.5, rtol=0, atol=1e-12)
    for corner, value in zip(_trapezoid_corners(), [-0.5, 1.5, 1.5, -0.5] * 2):
        assert _measured_at(current_run, "current", "trapezoid", corner, "right") == pytest.approx(value, abs=1e-9)


def test_negative_start_time_runs_from_the_first_instant(voltage_run):
    """A negative startTime: the counter starts inside a period that began before the run."""
    # the saw tooth of 0.4 s started at -0.1 s: a quarter of its height at t = 0
    assert voltage_run.at(0.0, "sawtooth_running.v") == pytest.approx(0.25, abs=1e-12)
    # the 60 % pulse of 0.3 s started at -0.1 s: on at t = 0, off from 0.08 s, on again from 0.2 s
    assert voltage_run.at(0.0, "pulse_running.v") == pytest.approx(1.5, abs=1e-12)
    assert voltage_run.at(0.08, "pulse_running.v", side="right") == pytest.approx(0.0, abs=1e-12)
    assert voltage_run.at(0.2, "pulse_running.v", side="right") == pytest.approx(1.5, abs=1e-12)


def test_table_extrapolates_through_its_last_two_rows(voltage_run, current_run):
    """After the table: the line through the last two rows, not the last value held."""
    # default table [0, 0; 1, 1; 2, 4]: 4 + 3*(2.5 - 2)
    assert voltage_run.final("table_default.v") == pytest.approx(5.5, abs=1e-9)
    # [.., 0.4, 0.5; 1.0, 2.0] shifted by 0.5 s, offset -0.2: -0.2 + 2 + 2.5*(2.5 - 1.5)
    assert -current_run.final("R_table.v") / LOAD == pytest.approx(4.3, abs=1e-9)


def _charge_of_pulse(t, amplitude, width, period, offset, startTime):
    """The integral from 0 of Blocks.Sources.Pulse (startTime >= 0): whole pulses, then the current one."""
    elapsed = np.maximum(np.asarray(t) - startTime, 0.0)
    whole = np.floor(elapsed / period)
    on = period * width / 100
    return offset * t + amplitude * (whole * on + np.minimum(elapsed - whole * period, on))


def _charge_of_saw_tooth(t, amplitude, period, offset, startTime):
    """The integral from 0 of Blocks.Sources.SawTooth, started at startTime <= 0."""
    def primitive(x):   # the integral of amplitude*(s - T_start)/period over s from startTime to x
        tau = np.asarray(x) - startTime
        whole = np.floor(tau / period)
        rest = tau - whole * period
        return amplitude / period * (whole * period ** 2 / 2 + rest ** 2 / 2)
    return offset * t + primitive(t) - primitive(0.0)


def test_current_sources_charge_capacitors(current_run):
    """C*dv/dt = i: the capacitor voltage is the closed-form integral of the pulse and the saw tooth.

    A pulse edge missed by one step would be off by I*step/C; the tolerance
    is the integrator's (rtol 1e-10).
    """
    t = current_run.time
    pulse_charge = _charge_of_pulse(t, 2.0, 40, 0.3, -0.25, 0.1) / C_CHARGE
    saw_charge = _charge_of_saw_tooth(t, 1.5, 0.7, 0.1, -0.2) / C_CHARGE
    np.testing.assert_allclose(current_run["C_pulse_charge.v"], pulse_charge, rtol=0, atol=1e-7)
    np.testing.assert_allclose(current_run["C_sawtooth_charge.v"], saw_charge, rtol=0, atol=1e-7)
