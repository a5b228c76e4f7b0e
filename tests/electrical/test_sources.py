"""Modelica.Electrical.Analog.Sources: every source against the closed form of its signal.

One circuit holds every voltage source (each across its own 1 Ohm resistor)
and one every current source (each through its own 1 Ohm resistor), so one
run checks them all; the expected waveforms are written here with numpy from
the MSL's definitions, independently of the Blocks sources the electrical
sources are built on.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from library_checks import check_declarations

from acausal import Model, simulate
from acausal.library.blocks import Constant
from acausal.library.electrical import (
    ConstantCurrent,
    ConstantVoltage,
    CosineCurrent,
    CosineCurrentVariableFrequencyAndAmplitude,
    CosineVoltage,
    CosineVoltageVariableFrequencyAndAmplitude,
    ExponentialsCurrent,
    ExponentialsVoltage,
    ExpSineCurrent,
    ExpSineVoltage,
    Ground,
    PulseCurrent,
    PulseVoltage,
    RampCurrent,
    RampVoltage,
    Resistor,
    SawToothCurrent,
    SawToothVoltage,
    SignalCurrent,
    SignalVoltage,
    SineCurrent,
    SineCurrentVariableFrequencyAndAmplitude,
    SineVoltage,
    SineVoltageVariableFrequencyAndAmplitude,
    StepCurrent,
    StepVoltage,
    SupplyVoltage,
    TableCurrent,
    TableVoltage,
    TrapezoidCurrent,
    TrapezoidVoltage,
)


def _step(t, t0):
    return np.where(t < t0, 0.0, 1.0)


def _periodic(t, t0, period):
    """The time since the start of the current period (and 0 before t0)."""
    return np.where(t < t0, 0.0, np.mod(t - t0, period))


# (name, voltage class, current class, parameters with the amplitude as A, expected waveform of t)
CASES = [
    ("constant", ConstantVoltage, ConstantCurrent, dict(A=2.0), lambda t: np.full_like(t, 2.0)),
    ("step", StepVoltage, StepCurrent, dict(A=2.0, offset=0.5, startTime=0.3),
     lambda t: 0.5 + 2.0 * _step(t, 0.3)),
    ("ramp", RampVoltage, RampCurrent, dict(A=3.0, duration=0.5, offset=-1, startTime=0.2),
     lambda t: -1 + 3.0 * np.clip((t - 0.2) / 0.5, 0, 1)),
    ("sine", SineVoltage, SineCurrent, dict(A=2.0, f=3.0, phase=0.4, offset=0.1, startTime=0.1),
     lambda t: 0.1 + _step(t, 0.1) * 2.0 * np.sin(2 * np.pi * 3.0 * (t - 0.1) + 0.4)),
    ("cosine", CosineVoltage, CosineCurrent, dict(A=2.0, f=3.0, phase=0.4),
     lambda t: 2.0 * np.cos(2 * np.pi * 3.0 * t + 0.4)),
    ("expsine", ExpSineVoltage, ExpSineCurrent, dict(A=2.0, f=3.0, phase=0.2, damping=1.5, startTime=0.1),
     lambda t: _step(t, 0.1) * 2.0 * np.exp(-1.5 * (t - 0.1)) * np.sin(2 * np.pi * 3.0 * (t - 0.1) + 0.2)),
    ("pulse", PulseVoltage, PulseCurrent, dict(A=2.0, width=30, period=0.4, startTime=0.1),
     lambda t: 2.0 * ((t >= 0.1) & (_periodic(t, 0.1, 0.4) < 0.3 * 0.4))),
    ("sawtooth", SawToothVoltage, SawToothCurrent, dict(A=2.0, period=0.4, startTime=0.1),
     lambda t: 2.0 * _periodic(t, 0.1, 0.4) / 0.4),
    ("trapezoid", TrapezoidVoltage, TrapezoidCurrent,
     dict(A=2.0, rising=0.1, width=0.2, falling=0.1, period=0.5, offset=0.5),
     lambda t: 0.5 + 2.0 * np.interp(np.mod(t, 0.5), [0, 0.1, 0.3, 0.4, 0.5], [0, 1, 1, 0, 0])),
    ("table", TableVoltage, TableCurrent, dict(table=[[0, 0], [0.5, 1], [1.0, -1]]),
     lambda t: np.interp(t, [0, 0.5, 1.0], [0, 1, -1], right=np.nan)),
]


def _modifiers(klass, parameters, kind):
    out = dict(parameters)
    if "A" in out:
        name = "V" if kind == "voltage" else "I"
        out[name] = out.pop("A")
    return out


def _exponentials(t, height, rise, rise_tc, fall_tc, t0):
    y_rise = height * (1 - math.exp(-rise / rise_tc))
    return np.where(t < t0, 0.0, np.where(t < t0 + rise, height * (1 - np.exp(-(t - t0) / rise_tc)),
                                          y_rise * np.exp(-(t - t0 - rise) / fall_tc)))


class AllSources(Model):
    """Every source of one kind across (through) its own 1 Ohm resistor, all on one ground."""

    def __init__(self, kind: str, **modifiers):
        object.__setattr__(self, "kind", kind)
        super().__init__(**modifiers)

    def build(self):
        self.ground = Ground()
        index = 0 if self.kind == "voltage" else 1
        for name, *classes, parameters, _ in CASES:
            self._attach(name, classes[index](**_modifiers(classes[index], parameters, self.kind)))
        exponentials = ExponentialsVoltage if self.kind == "voltage" else ExponentialsCurrent
        height = "vMax" if self.kind == "voltage" else "iMax"
        self._attach("exponentials", exponentials(**{height: 2.0}, riseTime=0.4, riseTimeConst=0.1,
                                                  fallTimeConst=0.2, startTime=0.1))
        self._attach("exponentials_default", exponentials(**{height: 2.0}, riseTime=0.4, riseTimeConst=0.1))
        signal = SignalVoltage() if self.kind == "voltage" else SignalCurrent()
        self._attach("signal", signal)
        self.signal_value = Constant(k=-1.5)
        self.connect(self.signal_value.y, signal.v if self.kind == "voltage" else signal.i)

    def _attach(self, name, source):
        setattr(self, name, source)
        load = Resistor(R=1)
        setattr(self, f"R_{name}", load)
        self.connect(source.p, load.p)
        self.connect(load.n, self.ground.p)
        self.connect(source.n, self.ground.p)


def _value(result, kind, name):
    # a voltage source's v is across its load; a current source's current i flows from p to n
    # inside the source, so through the load from n to p: the load carries -i
    return result[f"{name}.v"] if kind == "voltage" else result[f"{name}.i"]


@pytest.fixture(scope="module", params=["voltage", "current"])
def run(request):
    result = simulate(AllSources(request.param), stop_time=1.0, interval=0.01, rtol=1e-9, atol=1e-12)
    assert result.success, result.message
    return request.param, result


@pytest.mark.parametrize("case", CASES, ids=[c[0] for c in CASES])
def test_source_gives_its_waveform(run, case):
    kind, result = run
    name, *_, expected = case
    t = result.time
    want = expected(t)
    got = _value(result, kind, name)
    # an event has two rows (before and after it); the waveforms give the value after, so leave
    # out the instants that have two rows
    times, counts = np.unique(t, return_counts=True)
    keep = np.isfinite(want) & ~np.isin(t, times[counts > 1])
    np.testing.assert_allclose(got[keep], want[keep], rtol=0, atol=1e-9)


def test_exponentials(run):
    kind, result = run
    t = result.time
    np.testing.assert_allclose(_value(result, kind, "exponentials"), _exponentials(t, 2.0, 0.4, 0.1, 0.2, 0.1),
                               rtol=0, atol=1e-9)
    # the fall time constant defaults to the rise time constant
    np.testing.assert_allclose(_value(result, kind, "exponentials_default"),
                               _exponentials(t, 2.0, 0.4, 0.1, 0.1, 0.0), rtol=0, atol=1e-9)


def test_signal_source_and_the_load(run):
    kind, result = run
    np.testing.assert_allclose(_value(result, kind, "signal"), -1.5, rtol=0, atol=1e-12)
    if kind == "voltage":
        # the source's current flows from p to n inside it: -v/R
        np.testing.assert_allclose(result["signal.i"], 1.5, rtol=0, atol=1e-12)
        np.testing.assert_allclose(result["R_sine.v"], result["sine.v"], rtol=0, atol=1e-12)
    else:
        np.testing.assert_allclose(result["R_signal.i"], 1.5, rtol=0, atol=1e-12)
        np.testing.assert_allclose(result["R_sine.i"], -result["sine.i"], rtol=0, atol=1e-12)


def test_sources_are_built_on_blocks_sources(run):
    kind, result = run
    np.testing.assert_allclose(result["sine.signalSource.y"], _value(result, kind, "sine"), rtol=0, atol=0)


# --------------------------------------------------------------------------
# variable frequency and amplitude


class VariableHarmonics(Model):
    def build(self):
        self.ground = Ground()
        self.frequency = Constant(k=5.0)
        self.amplitude = Constant(k=3.0)
        sources = dict(
            sv=SineVoltageVariableFrequencyAndAmplitude(offset=0.5, phi=dict(fixed=True)),
            cv=CosineVoltageVariableFrequencyAndAmplitude(useConstantAmplitude=True, constantAmplitude=3.0,
                                                          offset=0.5, phi=dict(fixed=True)),
            si=SineCurrentVariableFrequencyAndAmplitude(useConstantFrequency=True, constantFrequency=5.0,
                                                        offset=0.5, phi=dict(fixed=True)),
            ci=CosineCurrentVariableFrequencyAndAmplitude(useConstantAmplitude=True, constantAmplitude=3.0,
                                                          useConstantFrequency=True, constantFrequency=5.0,
                                                          offset=0.5, phi=dict(fixed=True)),
        )
        for name, source in sources.items():
            setattr(self, name, source)
            setattr(self, f"R_{name}", Resistor(R=2))
            self.connect(source.p, getattr(self, f"R_{name}").p)
            self.connect(getattr(self, f"R_{name}").n, self.ground.p)
            self.connect(source.n, self.ground.p)
            if not source.useConstantFrequency:
                self.connect(self.frequency.y, source.f)
            if not source.useConstantAmplitude:
                self.connect(self.amplitude.y, source.V if name.endswith("v") else source.I)


def test_variable_frequency_and_amplitude_sources():
    result = simulate(VariableHarmonics(), stop_time=1.0, interval=0.01, rtol=1e-10, atol=1e-12)
    t = result.time
    phase = 2 * np.pi * 5.0 * t
    np.testing.assert_allclose(result["sv.phi"], phase, rtol=1e-8, atol=1e-9)
    np.testing.assert_allclose(result["sv.v"], 0.5 + 3 * np.sin(phase), rtol=0, atol=1e-7)
    np.testing.assert_allclose(result["cv.v"], 0.5 + 3 * np.cos(phase), rtol=0, atol=1e-7)
    np.testing.assert_allclose(result["si.i"], 0.5 + 3 * np.sin(phase), rtol=0, atol=1e-7)
    np.testing.assert_allclose(result["ci.i"], 0.5 + 3 * np.cos(phase), rtol=0, atol=1e-7)


# --------------------------------------------------------------------------
# supply voltage


class Supply(Model):
    def build(self):
        self.supply = SupplyVoltage(Vps=12, Vns=-5)
        self.ground = Ground()
        self.up = Resistor(R=4)
        self.down = Resistor(R=5)
        self.connect(self.supply.ground, self.ground.p)
        self.connect(self.supply.pin_p, self.up.p)
        self.connect(self.up.n, self.ground.p)
        self.connect(self.supply.pin_n, self.down.n)
        self.connect(self.down.p, self.ground.p)


def test_supply_voltage():
    result = simulate(Supply(), stop_time=1, interval=0.5)
    assert result.final("supply.pin_p.v") == pytest.approx(12)
    assert result.final("supply.pin_n.v") == pytest.approx(-5)
    assert result.final("up.i") == pytest.approx(3) and result.final("down.i") == pytest.approx(1)
    assert result.final("supply.ground.i") == pytest.approx(3 - 1)


@pytest.mark.parametrize("component", [
    SignalVoltage(), SignalCurrent(), ConstantVoltage(), ConstantCurrent(),
    SineVoltageVariableFrequencyAndAmplitude(), SineVoltageVariableFrequencyAndAmplitude(useConstantAmplitude=True),
    CosineCurrentVariableFrequencyAndAmplitude(useConstantFrequency=True),
    StepVoltage(), TrapezoidCurrent(nperiod=2), SupplyVoltage(),
], ids=lambda c: f"{type(c).__name__}({', '.join(f'{k}={v}' for k, v in c._modifiers.items())})")
def test_declarations(component):
    check_declarations(component)
