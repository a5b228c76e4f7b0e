"""Analog voltage and current sources (Modelica.Electrical.Analog.Sources).

The signal sources take their value from an input, the constant ones from a
parameter.  The time-function sources are, as in the MSL, a one-port whose
voltage (current) is the output of a Modelica.Blocks source, ``signalSource``,
built with the source's own parameters plus ``offset`` and ``startTime``:
``sineVoltage.signalSource.y`` is in the result as in a Modelica tool's.
"""

from __future__ import annotations

import enum
import math

import numpy as np
import sympy as sp

from acausal.hybrid import Assert
from acausal.language import Boolean, Component, Eq, If, Parameter, RealInput, Variable, der, time
from acausal.components.blocks import SignalSource
from acausal.components.declarations import DerivedDefaults
from acausal.components.electrical import EPS, CurrentSource, NegativePin, OnePort, PositivePin, VoltageSource
from acausal.library.blocks import sources as blocks

__all__ = [
    "SignalVoltage", "ConstantVoltage", "StepVoltage", "RampVoltage", "SineVoltage", "CosineVoltage",
    "ExpSineVoltage", "ExponentialsVoltage", "PulseVoltage", "SawToothVoltage", "TrapezoidVoltage",
    "TableVoltage", "SineVoltageVariableFrequencyAndAmplitude", "CosineVoltageVariableFrequencyAndAmplitude",
    "SupplyVoltage", "LightningImpulseVoltage",
    "SignalCurrent", "ConstantCurrent", "StepCurrent", "RampCurrent", "SineCurrent", "CosineCurrent",
    "ExpSineCurrent", "ExponentialsCurrent", "PulseCurrent", "SawToothCurrent", "TrapezoidCurrent",
    "TableCurrent", "SineCurrentVariableFrequencyAndAmplitude", "CosineCurrentVariableFrequencyAndAmplitude",
    "LightningImpulseCurrent", "LightningImpulse", "ImpulseApproximation", "DCPowerSupply",
]

#: Modelica.Constants.small, the lower bound of periods and time constants.
SMALL = 1e-60


# --------------------------------------------------------------------------
# signal and constant sources
# --------------------------------------------------------------------------


class SignalVoltage(Component):
    """Generic voltage source using the input signal as source voltage (Modelica.Electrical.Analog.Sources.SignalVoltage).

    ``p.v - n.v = v``, the input; ``i`` flows from p to n through the source.
    """

    modelica_name = "Modelica.Electrical.Analog.Sources.SignalVoltage"

    p = PositivePin(description="Positive electrical pin")
    n = NegativePin(description="Negative electrical pin")
    v = RealInput(unit="V", description="Voltage between pin p and n (= p.v - n.v) as input signal")
    i = Variable(unit="A", description="Current flowing from pin p to pin n")

    def equations(self):
        return [Eq(self.v, self.p.v - self.n.v), Eq(0, self.p.i + self.n.i), Eq(self.i, self.p.i)]


class SignalCurrent(Component):
    """Generic current source using the input signal as source current (Modelica.Electrical.Analog.Sources.SignalCurrent).

    ``p.i = i``, the input, flows from p to n through the source; ``v = p.v - n.v``.
    """

    modelica_name = "Modelica.Electrical.Analog.Sources.SignalCurrent"

    p = PositivePin(description="Positive electrical pin")
    n = NegativePin(description="Negative electrical pin")
    i = RealInput(unit="A", description="Current flowing from pin p to pin n as input signal")
    v = Variable(unit="V", description="Voltage drop between the two pins (= p.v - n.v)")

    def equations(self):
        return [Eq(self.v, self.p.v - self.n.v), Eq(0, self.p.i + self.n.i), Eq(self.i, self.p.i)]


class ConstantVoltage(OnePort):
    """Source for constant voltage (Modelica.Electrical.Analog.Sources.ConstantVoltage).

    ``v = V``.
    """

    modelica_name = "Modelica.Electrical.Analog.Sources.ConstantVoltage"

    V = Parameter(1.0, unit="V", description="Value of constant voltage")

    def equations(self):
        return [Eq(self.v, self.V)]


class ConstantCurrent(OnePort):
    """Source for constant current (Modelica.Electrical.Analog.Sources.ConstantCurrent).

    ``i = I``.
    """

    modelica_name = "Modelica.Electrical.Analog.Sources.ConstantCurrent"

    I = Parameter(1.0, unit="A", description="Value of constant current")  # noqa: E741 - Modelica name

    def equations(self):
        return [Eq(self.i, self.I)]


# --------------------------------------------------------------------------
# time-function sources: the parameters of each signal shape (without its
# amplitude, named V or I by the voltage and current source) and the block
# --------------------------------------------------------------------------


def _common(source) -> dict:
    # MSL: signalSource(final offset=offset, final startTime=startTime)
    return dict(offset=source.offset, startTime=source.startTime)


class _Ramp:
    duration = Parameter(2.0, unit="s", min=SMALL, description="Duration of ramp")

    def _block(self, height):
        return blocks.Ramp(height=height, duration=self.duration, **_common(self))


class _Harmonic:
    phase = Parameter(0.0, unit="rad", description="Phase of the wave")
    f = Parameter(1.0, unit="Hz", description="Frequency of the wave")


class _ExpSine:
    f = Parameter(2.0, unit="Hz", description="Frequency of sine wave")
    phase = Parameter(0.0, unit="rad", description="Phase of sine wave")
    damping = Parameter(1.0, unit="1/s", description="Damping coefficient of sine wave")

    def _block(self, amplitude):
        return blocks.ExpSine(amplitude=amplitude, f=self.f, phase=self.phase, damping=self.damping,
                              **_common(self))


class _Exponentials(DerivedDefaults):
    riseTime = Parameter(0.5, unit="s", min=0, description="Rise time")  # noqa: N815 - Modelica name
    riseTimeConst = Parameter(0.1, unit="s", min=SMALL, description="Rise time constant")  # noqa: N815
    fallTimeConst = Parameter(None, unit="s", min=SMALL,  # noqa: N815
                              description="Fall time constant (default riseTimeConst)")

    # MSL: fallTimeConst(start=riseTimeConst)
    derived_defaults = {"fallTimeConst": lambda source: source.riseTimeConst}

    def _block(self, height):
        return blocks.Exponentials(outMax=height, riseTime=self.riseTime, riseTimeConst=self.riseTimeConst,
                                   fallTimeConst=self.fallTimeConst, **_common(self))


class _Pulse:
    width = Parameter(50.0, min=SMALL, max=100, description="Width of pulse in % of period")
    period = Parameter(1.0, unit="s", min=SMALL, description="Time for one period")

    def _block(self, amplitude):
        return blocks.Pulse(amplitude=amplitude, width=self.width, period=self.period, **_common(self))


class _SawTooth:
    period = Parameter(1.0, unit="s", min=SMALL, description="Time for one period")

    def _block(self, amplitude):
        return blocks.SawTooth(amplitude=amplitude, period=self.period, **_common(self))


class _Trapezoid:
    rising = Parameter(0.0, unit="s", min=0, description="Rising duration of trapezoid")
    width = Parameter(0.5, unit="s", min=0, description="Width duration of trapezoid")
    falling = Parameter(0.0, unit="s", min=0, description="Falling duration of trapezoid")
    period = Parameter(1.0, unit="s", min=SMALL, description="Time for one period")
    nperiod = Parameter(-1, structural=True, description="Number of periods (< 0 means infinite number of periods)")

    def _block(self, amplitude):
        return blocks.Trapezoid(amplitude=amplitude, rising=self.rising, width=self.width, falling=self.falling,
                                period=self.period, nperiod=self.nperiod, **_common(self))


class _Table:
    def _block(self, _amplitude=None):
        return blocks.TimeTable(table=self.table, **_common(self))


# -- voltage ----------------------------------------------------------------


class StepVoltage(VoltageSource):
    """Step voltage source (Modelica.Electrical.Analog.Sources.StepVoltage).

    ``v = offset`` before ``startTime``, ``offset + V`` from it on (a Blocks.Sources.Step).
    """

    modelica_name = "Modelica.Electrical.Analog.Sources.StepVoltage"

    V = Parameter(1.0, unit="V", description="Height of step")

    def signal_source(self):
        return blocks.Step(height=self.V, **_common(self))


class RampVoltage(_Ramp, VoltageSource):
    """Ramp voltage source (Modelica.Electrical.Analog.Sources.RampVoltage).

    ``v`` rises linearly by ``V`` in ``duration`` from ``startTime`` on (a Blocks.Sources.Ramp).
    """

    modelica_name = "Modelica.Electrical.Analog.Sources.RampVoltage"

    V = Parameter(1.0, unit="V", description="Height of ramp")

    def signal_source(self):
        return self._block(self.V)


class SineVoltage(_Harmonic, VoltageSource):
    """Sine voltage source (Modelica.Electrical.Analog.Sources.SineVoltage).

    ``v = offset + V*sin(2*pi*f*(time - startTime) + phase)`` from
    ``startTime`` on, ``offset`` before (a Blocks.Sources.Sine).
    """

    modelica_name = "Modelica.Electrical.Analog.Sources.SineVoltage"

    V = Parameter(1.0, unit="V", description="Amplitude of sine wave")

    def signal_source(self):
        return blocks.Sine(amplitude=self.V, f=self.f, phase=self.phase, **_common(self))


class CosineVoltage(_Harmonic, VoltageSource):
    """Cosine voltage source (Modelica.Electrical.Analog.Sources.CosineVoltage).

    ``v = offset + V*cos(2*pi*f*(time - startTime) + phase)`` from
    ``startTime`` on, ``offset`` before (a Blocks.Sources.Cosine).
    """

    modelica_name = "Modelica.Electrical.Analog.Sources.CosineVoltage"

    V = Parameter(1.0, unit="V", description="Amplitude of cosine wave")

    def signal_source(self):
        return blocks.Cosine(amplitude=self.V, f=self.f, phase=self.phase, **_common(self))


class ExpSineVoltage(_ExpSine, VoltageSource):
    """Exponentially damped sine voltage source (Modelica.Electrical.Analog.Sources.ExpSineVoltage).

    ``v = offset + V*exp(-damping*(time - startTime))*sin(2*pi*f*(time -
    startTime) + phase)`` from ``startTime`` on (a Blocks.Sources.ExpSine).
    """

    modelica_name = "Modelica.Electrical.Analog.Sources.ExpSineVoltage"

    V = Parameter(1.0, unit="V", description="Amplitude of sine wave")

    def signal_source(self):
        return self._block(self.V)


class ExponentialsVoltage(_Exponentials, VoltageSource):
    """Rising and falling exponential voltage source (Modelica.Electrical.Analog.Sources.ExponentialsVoltage).

    ``vMax*(1 - exp(-t/riseTimeConst))`` for ``riseTime`` after
    ``startTime``, then decaying with ``fallTimeConst`` (a Blocks.Sources.Exponentials).
    """

    modelica_name = "Modelica.Electrical.Analog.Sources.ExponentialsVoltage"

    vMax = Parameter(1.0, unit="V", description="Upper bound for rising edge")  # noqa: N815 - Modelica name

    def signal_source(self):
        return self._block(self.vMax)


class PulseVoltage(_Pulse, VoltageSource):
    """Pulse voltage source (Modelica.Electrical.Analog.Sources.PulseVoltage).

    ``offset + V`` during the first ``width`` percent of every period from
    ``startTime`` on, ``offset`` otherwise (a Blocks.Sources.Pulse).
    """

    modelica_name = "Modelica.Electrical.Analog.Sources.PulseVoltage"

    V = Parameter(1.0, unit="V", description="Amplitude of pulse")

    def signal_source(self):
        return self._block(self.V)


class SawToothVoltage(_SawTooth, VoltageSource):
    """Saw tooth voltage source (Modelica.Electrical.Analog.Sources.SawToothVoltage).

    Rises from ``offset`` to ``offset + V`` in every period from ``startTime`` on (a Blocks.Sources.SawTooth).
    """

    modelica_name = "Modelica.Electrical.Analog.Sources.SawToothVoltage"

    V = Parameter(1.0, unit="V", description="Amplitude of saw tooth")

    def signal_source(self):
        return self._block(self.V)


class TrapezoidVoltage(_Trapezoid, VoltageSource):
    """Trapezoidal voltage source (Modelica.Electrical.Analog.Sources.TrapezoidVoltage).

    In every period from ``startTime`` on: a rise to ``offset + V`` in
    ``rising``, ``width`` at it, a fall in ``falling`` (a Blocks.Sources.Trapezoid).
    """

    modelica_name = "Modelica.Electrical.Analog.Sources.TrapezoidVoltage"

    V = Parameter(1.0, unit="V", description="Amplitude of trapezoid")

    def signal_source(self):
        return self._block(self.V)


class TableVoltage(_Table, VoltageSource):
    """Voltage source by linear interpolation in a table (Modelica.Electrical.Analog.Sources.TableVoltage).

    ``table`` rows are ``[time, voltage]`` (a Blocks.Sources.TimeTable).
    """

    modelica_name = "Modelica.Electrical.Analog.Sources.TableVoltage"

    table = Parameter(((0.0, 0.0), (1.0, 1.0), (2.0, 4.0)), structural=True,
                      description="Table matrix (time = first column, voltage = second column)")

    def signal_source(self):
        return self._block()


# -- current ----------------------------------------------------------------


class StepCurrent(CurrentSource):
    """Step current source (Modelica.Electrical.Analog.Sources.StepCurrent).

    ``i = offset`` before ``startTime``, ``offset + I`` from it on (a Blocks.Sources.Step).
    """

    modelica_name = "Modelica.Electrical.Analog.Sources.StepCurrent"

    I = Parameter(1.0, unit="A", description="Height of step")  # noqa: E741 - Modelica name

    def signal_source(self):
        return blocks.Step(height=self.I, **_common(self))


class RampCurrent(_Ramp, CurrentSource):
    """Ramp current source (Modelica.Electrical.Analog.Sources.RampCurrent).

    ``i`` rises linearly by ``I`` in ``duration`` from ``startTime`` on (a Blocks.Sources.Ramp).
    """

    modelica_name = "Modelica.Electrical.Analog.Sources.RampCurrent"

    I = Parameter(1.0, unit="A", description="Height of ramp")  # noqa: E741 - Modelica name

    def signal_source(self):
        return self._block(self.I)


class SineCurrent(_Harmonic, CurrentSource):
    """Sine current source (Modelica.Electrical.Analog.Sources.SineCurrent).

    ``i = offset + I*sin(2*pi*f*(time - startTime) + phase)`` from
    ``startTime`` on, ``offset`` before (a Blocks.Sources.Sine).
    """

    modelica_name = "Modelica.Electrical.Analog.Sources.SineCurrent"

    I = Parameter(1.0, unit="A", description="Amplitude of sine wave")  # noqa: E741 - Modelica name

    def signal_source(self):
        return blocks.Sine(amplitude=self.I, f=self.f, phase=self.phase, **_common(self))


class CosineCurrent(_Harmonic, CurrentSource):
    """Cosine current source (Modelica.Electrical.Analog.Sources.CosineCurrent).

    ``i = offset + I*cos(2*pi*f*(time - startTime) + phase)`` from
    ``startTime`` on, ``offset`` before (a Blocks.Sources.Cosine).
    """

    modelica_name = "Modelica.Electrical.Analog.Sources.CosineCurrent"

    I = Parameter(1.0, unit="A", description="Amplitude of cosine wave")  # noqa: E741 - Modelica name

    def signal_source(self):
        return blocks.Cosine(amplitude=self.I, f=self.f, phase=self.phase, **_common(self))


class ExpSineCurrent(_ExpSine, CurrentSource):
    """Exponentially damped sine current source (Modelica.Electrical.Analog.Sources.ExpSineCurrent).

    ``i = offset + I*exp(-damping*(time - startTime))*sin(2*pi*f*(time -
    startTime) + phase)`` from ``startTime`` on (a Blocks.Sources.ExpSine).
    """

    modelica_name = "Modelica.Electrical.Analog.Sources.ExpSineCurrent"

    I = Parameter(1.0, unit="A", description="Amplitude of sine wave")  # noqa: E741 - Modelica name

    def signal_source(self):
        return self._block(self.I)


class ExponentialsCurrent(_Exponentials, CurrentSource):
    """Rising and falling exponential current source (Modelica.Electrical.Analog.Sources.ExponentialsCurrent).

    ``iMax*(1 - exp(-t/riseTimeConst))`` for ``riseTime`` after
    ``startTime``, then decaying with ``fallTimeConst`` (a Blocks.Sources.Exponentials).
    """

    modelica_name = "Modelica.Electrical.Analog.Sources.ExponentialsCurrent"

    iMax = Parameter(1.0, unit="A", description="Upper bound for rising edge")  # noqa: N815 - Modelica name

    def signal_source(self):
        return self._block(self.iMax)


class PulseCurrent(_Pulse, CurrentSource):
    """Pulse current source (Modelica.Electrical.Analog.Sources.PulseCurrent).

    ``offset + I`` during the first ``width`` percent of every period from
    ``startTime`` on, ``offset`` otherwise (a Blocks.Sources.Pulse).
    """

    modelica_name = "Modelica.Electrical.Analog.Sources.PulseCurrent"

    I = Parameter(1.0, unit="A", description="Amplitude of pulse")  # noqa: E741 - Modelica name

    def signal_source(self):
        return self._block(self.I)


class SawToothCurrent(_SawTooth, CurrentSource):
    """Saw tooth current source (Modelica.Electrical.Analog.Sources.SawToothCurrent).

    Rises from ``offset`` to ``offset + I`` in every period from ``startTime`` on (a Blocks.Sources.SawTooth).
    """

    modelica_name = "Modelica.Electrical.Analog.Sources.SawToothCurrent"

    I = Parameter(1.0, unit="A", description="Amplitude of saw tooth")  # noqa: E741 - Modelica name

    def signal_source(self):
        return self._block(self.I)


class TrapezoidCurrent(_Trapezoid, CurrentSource):
    """Trapezoidal current source (Modelica.Electrical.Analog.Sources.TrapezoidCurrent).

    In every period from ``startTime`` on: a rise to ``offset + I`` in
    ``rising``, ``width`` at it, a fall in ``falling`` (a Blocks.Sources.Trapezoid).
    """

    modelica_name = "Modelica.Electrical.Analog.Sources.TrapezoidCurrent"

    I = Parameter(1.0, unit="A", description="Amplitude of trapezoid")  # noqa: E741 - Modelica name

    def signal_source(self):
        return self._block(self.I)


class TableCurrent(_Table, CurrentSource):
    """Current source by linear interpolation in a table (Modelica.Electrical.Analog.Sources.TableCurrent).

    ``table`` rows are ``[time, current]`` (a Blocks.Sources.TimeTable).
    """

    modelica_name = "Modelica.Electrical.Analog.Sources.TableCurrent"

    table = Parameter(((0.0, 0.0), (1.0, 1.0), (2.0, 4.0)), structural=True,
                      description="Table matrix (time = first column, current = second column)")

    def signal_source(self):
        return self._block()


# --------------------------------------------------------------------------
# variable frequency and amplitude
# --------------------------------------------------------------------------


class _VariableHarmonic(OnePort):
    """The phase ``der(phi) = 2*pi*f`` and the switches between inputs and constants.

    The amplitude and frequency are inputs, or with ``useConstantAmplitude``
    / ``useConstantFrequency`` the parameters ``constantAmplitude`` /
    ``constantFrequency`` (the MSL feeds those through a Constant block into
    a protected connector; here the parameter enters the equation directly).
    ``phi`` starts at 0, not fixed, as in the MSL (give ``phi=dict(fixed=True)``).
    """

    useConstantAmplitude = Parameter(False, structural=True, description="Enable constant amplitude")  # noqa: N815
    useConstantFrequency = Parameter(False, structural=True, description="Enable constant frequency")  # noqa: N815
    constantFrequency = Parameter(1.0, unit="Hz", description="Constant frequency")  # noqa: N815
    phi = Variable(start=0.0, unit="rad", description="Phase of the sine wave")
    f = RealInput(unit="Hz", condition=lambda c: not c.useConstantFrequency, description="Frequency")

    def _wave(self, amplitude_input: str, wave) -> list:
        amplitude = self.constantAmplitude if self.useConstantAmplitude else getattr(self, amplitude_input)
        frequency = self.constantFrequency if self.useConstantFrequency else self.f
        return [Eq(der(self.phi), 2 * sp.pi * frequency), self.offset + amplitude * wave(self.phi)]


class SineVoltageVariableFrequencyAndAmplitude(_VariableHarmonic):
    """Sine voltage source with variable frequency and amplitude
    (Modelica.Electrical.Analog.Sources.SineVoltageVariableFrequencyAndAmplitude).

    ``v = offset + V*sin(phi)``, ``der(phi) = 2*pi*f``.
    """

    modelica_name = "Modelica.Electrical.Analog.Sources.SineVoltageVariableFrequencyAndAmplitude"

    constantAmplitude = Parameter(1.0, unit="V", description="Constant amplitude")  # noqa: N815
    offset = Parameter(0.0, unit="V", description="Offset of the sine wave")
    V = RealInput(unit="V", condition=lambda c: not c.useConstantAmplitude, description="Amplitude")

    def equations(self):
        phase, value = self._wave("V", sp.sin)
        return [phase, Eq(self.v, value)]


class CosineVoltageVariableFrequencyAndAmplitude(_VariableHarmonic):
    """Cosine voltage source with variable frequency and amplitude
    (Modelica.Electrical.Analog.Sources.CosineVoltageVariableFrequencyAndAmplitude).

    ``v = offset + V*cos(phi)``, ``der(phi) = 2*pi*f``.
    """

    modelica_name = "Modelica.Electrical.Analog.Sources.CosineVoltageVariableFrequencyAndAmplitude"

    constantAmplitude = Parameter(1.0, unit="V", description="Constant amplitude")  # noqa: N815
    offset = Parameter(0.0, unit="V", description="Offset of the sine wave")
    V = RealInput(unit="V", condition=lambda c: not c.useConstantAmplitude, description="Amplitude")

    def equations(self):
        phase, value = self._wave("V", sp.cos)
        return [phase, Eq(self.v, value)]


class SineCurrentVariableFrequencyAndAmplitude(_VariableHarmonic):
    """Sine current source with variable frequency and amplitude
    (Modelica.Electrical.Analog.Sources.SineCurrentVariableFrequencyAndAmplitude).

    ``i = offset + I*sin(phi)``, ``der(phi) = 2*pi*f``.
    """

    modelica_name = "Modelica.Electrical.Analog.Sources.SineCurrentVariableFrequencyAndAmplitude"

    constantAmplitude = Parameter(1.0, unit="A", description="Constant amplitude")  # noqa: N815
    offset = Parameter(0.0, unit="A", description="Offset of the sine wave")
    I = RealInput(unit="A", condition=lambda c: not c.useConstantAmplitude, description="Amplitude")  # noqa: E741

    def equations(self):
        phase, value = self._wave("I", sp.sin)
        return [phase, Eq(self.i, value)]


class CosineCurrentVariableFrequencyAndAmplitude(_VariableHarmonic):
    """Cosine current source with variable frequency and amplitude
    (Modelica.Electrical.Analog.Sources.CosineCurrentVariableFrequencyAndAmplitude).

    ``i = offset + I*cos(phi)``, ``der(phi) = 2*pi*f``.
    """

    modelica_name = "Modelica.Electrical.Analog.Sources.CosineCurrentVariableFrequencyAndAmplitude"

    constantAmplitude = Parameter(1.0, unit="A", description="Constant amplitude")  # noqa: N815
    offset = Parameter(0.0, unit="A", description="Offset of the sine wave")
    I = RealInput(unit="A", condition=lambda c: not c.useConstantAmplitude, description="Amplitude")  # noqa: E741

    def equations(self):
        phase, value = self._wave("I", sp.cos)
        return [phase, Eq(self.i, value)]


# --------------------------------------------------------------------------
# composite
# --------------------------------------------------------------------------


class SupplyVoltage(Component):
    """Supply voltage, positive and negative (Modelica.Electrical.Analog.Sources.SupplyVoltage).

    Two ConstantVoltage sources in series around the pin ``ground``:
    ``pin_p`` is ``Vps`` above it, ``pin_n`` at ``Vns`` (negative).
    """

    modelica_name = "Modelica.Electrical.Analog.Sources.SupplyVoltage"

    Vps = Parameter(15.0, unit="V", description="Positive supply")
    Vns = Parameter(-15.0, unit="V", description="Negative supply")
    pin_p = PositivePin(description="Positive supply pin")
    pin_n = NegativePin(description="Negative supply pin")
    ground = NegativePin(description="Ground pin")

    def build(self) -> None:
        self.positiveSupply = ConstantVoltage(V=self.Vps)  # noqa: N815 - Modelica name
        self.negativeSupply = ConstantVoltage(V=-self.Vns)  # noqa: N815 - Modelica name
        self.connect(self.pin_p, self.positiveSupply.p)
        self.connect(self.negativeSupply.n, self.pin_n)
        self.connect(self.positiveSupply.n, self.ground)
        self.connect(self.ground, self.negativeSupply.p)


# --------------------------------------------------------------------------
# lightning impulse
# --------------------------------------------------------------------------


class ImpulseApproximation(enum.IntEnum):
    """Approximation of the impulse trajectory (Modelica.Electrical.Analog.Types.ImpulseApproximation)."""

    DoubleExp = 1
    Heidler = 2


# set after the body: in an IntEnum's body a str would become a member
ImpulseApproximation.modelica_name = "Modelica.Electrical.Analog.Types.ImpulseApproximation"


def _impulse_start_guesses(source: Component) -> dict[str, float]:
    """Start values of the impulse's parameters found at initialization: Newton's first guesses.

    The MSL's start values (``T0`` and the time constants ``T1``, ``T2``)
    lie too far from the solution for a plain Newton iteration on times of
    microseconds; from them scipy solves the same five equations, the times
    scaled by ``T1``, and the initialization starts from there.  Where that
    fails (the assert on ``T1`` rejects the parameters) the MSL's start
    values stay.
    """
    hints = getattr(source, "_start_hints", {})

    def number(name: str, default: float) -> float:
        value = source._modifiers.get(name, default)
        if not isinstance(value, (int, float)):
            value = hints.get(name, default)  # bound to an enclosing source's parameter
        return float(value)

    t1, t2, m = number("T1", 10e-6), number("T2", 350e-6), int(source.m)
    double_exp = source.approximation == ImpulseApproximation.DoubleExp
    if double_exp:
        t0 = t2 * t1 / (t2 - t1) * math.log(t2 / t1)
        msl = {"T0": t0, "T": t0, "T10": 0.01 * t0, "tau1": t2, "tau2": t1, "eta": 1.0}
    else:
        t0 = t1 * (m * t2 / t1) ** (1 / (m + 1))
        msl = {"T0": t0, "T": t0, "T10": 0.1 * t0, "tau1": t1, "tau2": t2, "eta": 1.0}

    def shape(t, tau1, tau2):
        if double_exp:
            return np.exp(-t / tau1) - np.exp(-t / tau2)
        ratio = (t / tau1) ** m
        return ratio / (1 + ratio) * np.exp(-t / tau2)

    def residuals(x):
        eta, (t_max, t10, tau1, tau2) = x[0], x[1:] * t1
        maximum = ((np.exp(-t_max / tau1) / tau1 - np.exp(-t_max / tau2) / tau2) * t1 if double_exp
                   else tau2 / t_max * m - 1 - (t_max / tau1) ** m)
        return [maximum, eta - shape(t_max, tau1, tau2), 0.1 * eta - shape(t10, tau1, tau2),
                0.9 * eta - shape(t10 + 0.8 * t1, tau1, tau2), 0.5 * eta - shape(t10 - 0.1 * t1 + t2, tau1, tau2)]

    from scipy.optimize import fsolve  # only here: a model without impulses does not load it

    guess = np.array([msl["eta"], msl["T"] / t1, msl["T10"] / t1, msl["tau1"] / t1, msl["tau2"] / t1])
    with np.errstate(all="ignore"):
        solution, _, found, _ = fsolve(residuals, guess, full_output=True, xtol=1e-13)
    if found != 1 or not np.all(np.isfinite(solution)) or np.min(solution) <= 0:
        return msl
    eta, t_max, t10, tau1, tau2 = solution[0], *(solution[1:] * t1)
    return {"T0": msl["T0"], "T": t_max, "T10": t10, "tau1": tau1, "tau2": tau2, "eta": eta}


class LightningImpulse(SignalSource):
    """Lightning impulse voltage or current trajectory (Modelica.Electrical.Analog.Sources.LightningImpulse).

    From ``startTime`` on, with ``t = time - startTime``, the double
    exponential ``y = offset + amplitude/eta*(exp(-t/tau1) - exp(-t/tau2))``
    or the Heidler function ``y = offset + amplitude/eta*(t/tau1)^m/(1 +
    (t/tau1)^m)*exp(-t/tau2)``; ``offset`` before.  The shape's parameters
    are found at initialization from the data sheet's rise time ``T1``
    (10 % to 90 % of the peak in ``0.8*T1``, from ``T10`` on) and decay
    time to half value ``T2`` (from the virtual start ``T10 - 0.1*T1``):
    ``T`` where the maximum lies, ``eta`` scaling it to ``amplitude``,
    the 10 % instant ``T10`` and the time constants ``tau1``, ``tau2`` —
    five initial equations, as in the MSL.  ``T0`` is Newton's first guess
    of ``T``.
    """

    modelica_name = "Modelica.Electrical.Analog.Sources.LightningImpulse"

    approximation = Parameter(ImpulseApproximation.Heidler, structural=True,
                              description="Approximation of impulse")
    amplitude = Parameter(1.0, description="Amplitude (MSL: no default)")
    T1 = Parameter(10e-6, unit="s", description="Rise time")
    T2 = Parameter(350e-6, unit="s", description="Decay time to half value")
    m = Parameter(5, structural=True, min=2, description="Integer exponent of Heidler-function 5..10")
    eta = Parameter(None, unit="1", min=SMALL, fixed=False, description="Amplitude parameter (protected)")
    T0 = Parameter(None, unit="s", description="Initial value of time parameter (protected)")
    T = Parameter(None, unit="s", min=SMALL, fixed=False, description="Time when maximum occurs (protected)")
    T10 = Parameter(None, unit="s", min=SMALL, fixed=False, description="Time to 10% (protected)")
    tau1 = Parameter(None, unit="s", min=SMALL, fixed=False, description="Time constant 1 (protected)")
    tau2 = Parameter(None, unit="s", min=SMALL, fixed=False, description="Time constant 2 (protected)")

    def parameter_binding(self, name: str):
        # the MSL's bindings (T0) and start values (fixed=false parameters) computed from T1, T2, m
        if name in ("eta", "T0", "T", "T10", "tau1", "tau2") and name not in self._modifiers:
            return _impulse_start_guesses(self)[name]
        return super().parameter_binding(name)

    def _shape(self, t: sp.Expr) -> sp.Expr:
        """The unscaled trajectory at ``t`` after the start."""
        if self.approximation == ImpulseApproximation.DoubleExp:
            return sp.exp(-t / self.tau1) - sp.exp(-t / self.tau2)
        ratio = (t / self.tau1) ** self.m
        return ratio / (1 + ratio) * sp.exp(-t / self.tau2)

    def initial_equations(self):
        rise_end = self.T10 + 0.8 * self.T1
        half = self.T10 - 0.1 * self.T1 + self.T2
        if self.approximation == ImpulseApproximation.DoubleExp:
            maximum = Eq(sp.exp(-self.T / self.tau1) / self.tau1, sp.exp(-self.T / self.tau2) / self.tau2)
        else:
            maximum = Eq(self.tau2 / self.T * self.m, 1 + (self.T / self.tau1) ** self.m)
        return [maximum,
                Eq(self.eta, self._shape(self.T)),         # amplitude reached at T
                Eq(0.1 * self.eta, self._shape(self.T10)),  # 10 % at T10
                Eq(0.9 * self.eta, self._shape(rise_end)),  # 90 % at T10 + 0.8*T1
                Eq(0.5 * self.eta, self._shape(half))]      # 50 % at T2 from the virtual start

    def equations(self):
        t = time - self.startTime
        return [Assert(sp.Or(sp.true if self.approximation == ImpulseApproximation.Heidler else sp.false,
                             self.T1 < 0.2 * self.T2),
                       "Rise time has to be smaller than 0.2*decay time!"),
                Eq(self.y, If(time < self.startTime, self.offset,
                              self.offset + self.amplitude / self.eta * self._shape(t)))]


class _LightningShape:
    """The impulse's own parameters, handed to the LightningImpulse block (signalSource)."""

    approximation = Parameter(ImpulseApproximation.Heidler, structural=True,
                              description="Approximation of impulse")
    T1 = Parameter(10e-6, unit="s", description="Rise time")
    T2 = Parameter(350e-6, unit="s", description="Decay time to half value")
    m = Parameter(5, structural=True, min=2, description="Integer exponent of Heidler-function 5..10")

    def _block(self, amplitude) -> LightningImpulse:
        block = LightningImpulse(approximation=self.approximation, amplitude=amplitude, T1=self.T1, T2=self.T2,
                                 m=self.m, **_common(self))
        # the numbers of T1, T2 seed Newton's guesses of the block's parameters found at initialization
        block._start_hints = {name: self._modifiers[name] for name in ("T1", "T2")
                              if isinstance(self._modifiers.get(name), (int, float))}
        return block


class LightningImpulseVoltage(_LightningShape, VoltageSource):
    """Lightning impulse voltage (Modelica.Electrical.Analog.Sources.LightningImpulseVoltage).

    ``v`` is a LightningImpulse of amplitude ``V`` (see there).
    """

    modelica_name = "Modelica.Electrical.Analog.Sources.LightningImpulseVoltage"

    V = Parameter(1.0, unit="V", description="Amplitude (MSL: no default)")

    def signal_source(self):
        return self._block(self.V)


class LightningImpulseCurrent(_LightningShape, CurrentSource):
    """Lightning impulse current (Modelica.Electrical.Analog.Sources.LightningImpulseCurrent).

    ``i`` is a LightningImpulse of amplitude ``I`` (see there).
    """

    modelica_name = "Modelica.Electrical.Analog.Sources.LightningImpulseCurrent"

    I = Parameter(1.0, unit="A", description="Amplitude (MSL: no default)")  # noqa: E741 - Modelica name

    def signal_source(self):
        return self._block(self.I)


# --------------------------------------------------------------------------
# DC power supply
# --------------------------------------------------------------------------


def _power_limited(source: Component) -> sp.Expr:
    """The MSL's ``cp``: the corner of the cv and cc lines, ``vLim*iLim``, lies above ``P0``."""
    return _corner_voltage(source) * _corner_current(source) > source.P0


def _corner_voltage(source: Component) -> sp.Expr:
    return (source.V0 - source.Rcv * source.I0) / (1 - source.Rcv * source.Gcc)


def _corner_current(source: Component) -> sp.Expr:
    return (source.I0 - source.Gcc * source.V0) / (1 - source.Gcc * source.Rcv)


class DCPowerSupply(DerivedDefaults, Component):
    """Simple model of a DC power supply cv - cp - cc (Modelica.Electrical.Analog.Sources.DCPowerSupply).

    Constant voltage (cv): ``v = V0 - Rcv*(-i)`` while the delivered
    current ``-i`` is at most ``iLim``; constant current (cc): ``-i = I0 -
    Gcc*v`` while ``v`` is at most ``vLim``; and, when the corner of these
    two lines delivers more than ``P0`` (``cp``), constant power ``P0 =
    v*(-i)`` between them, the limits then being where the cv and cc lines
    deliver ``P0``.  The two operating Booleans ``cv`` and ``cc`` switch by
    state events.  The MSL's protected ``vLim``, ``iLim`` and ``cp``
    (computed in an initial algorithm from the parameters alone) are here
    bindings of the parameters.  The three laws are one residual in volts:
    the current law is multiplied by ``V0/I0`` and the power law divided by
    ``I0`` (positive factors: the same solutions), as the branches of an if
    share a unit.
    """

    modelica_name = "Modelica.Electrical.Analog.Sources.DCPowerSupply"

    derived_defaults = {
        "vLim": lambda c: sp.Piecewise(((c.I0 - sp.sqrt(c.I0 ** 2 - 4 * c.Gcc * c.P0)) / (2 * c.Gcc),
                                        _power_limited(c)), (_corner_voltage(c), True)),
        "iLim": lambda c: sp.Piecewise(((c.V0 - sp.sqrt(c.V0 ** 2 - 4 * c.Rcv * c.P0)) / (2 * c.Rcv),
                                        _power_limited(c)), (_corner_current(c), True)),
    }

    V0 = Parameter(60.0, unit="V", min=EPS, description="No-load voltage")
    I0 = Parameter(50.0, unit="A", min=EPS, description="Short-circuit current")
    P0 = Parameter(1200.0, unit="W", min=EPS, description="Maximum power")
    Rcv = Parameter(1e-3, unit="Ohm", min=EPS, description="Inner resistance in constant voltage region")
    Gcc = Parameter(1e-3, unit="S", min=EPS, description="Inner conductance in constant current region")
    iBack = Parameter(1e-3, unit="A", description="Allowed back current")  # noqa: N815 - Modelica name
    vLim = Parameter(None, unit="V", description="Voltage limit for cc (protected)")  # noqa: N815
    iLim = Parameter(None, unit="A", description="Current limit for cv (protected)")  # noqa: N815
    v = Variable(unit="V", start=lambda c: c.V0, description="Terminal voltage")
    # no start in the MSL; a small delivered current keeps the constant-power law (singular at
    # i = 0) solvable when initialization first tries it
    i = Variable(unit="A", start=lambda c: -1e-3 * c.I0, description="Current (delivered < 0)")
    P = Variable(unit="W", description="Power (delivered < 0)")
    p = PositivePin(description="Positive electrical pin")
    n = NegativePin(description="Negative electrical pin")
    cp = Boolean(description="Is cp present? (protected)")
    cv = Boolean(start=True, description="Operation in cv, otherwise cc (or cp) (protected)")
    cc = Boolean(start=False, description="Operation in cc, otherwise cv (or cp) (protected)")

    def equations(self):
        delivered = -self.i
        voltage_law = self.v - (self.V0 - self.Rcv * delivered)
        current_law = (delivered - (self.I0 - self.Gcc * self.v)) * (self.V0 / self.I0)
        power_law = (self.P0 - self.v * delivered) / self.I0
        power_limited = _power_limited(self)
        return [
            Assert(self.Rcv < self.V0 / self.I0, "Rcv too high!"),
            Assert(self.Gcc < self.I0 / self.V0, "Gcc too high!"),
            Assert(sp.Or(sp.Not(power_limited), self.Rcv < self.V0 ** 2 / (4 * self.P0)), "Rcv too high!"),
            Assert(sp.Or(sp.Not(power_limited), self.Gcc < self.I0 ** 2 / (4 * self.P0)), "Gcc too high!"),
            Eq(self.v, self.p.v - self.n.v),
            Eq(self.i, self.p.i),
            Eq(self.P, self.v * self.i),
            Eq(self.p.i + self.n.i, 0),
            Assert(self.v >= 0, "Only voltage >= 0 allowed"),
            Assert(self.i <= self.iBack, "Back current exceeded!"),
            Eq(self.cp, power_limited),
            Eq(self.cv, delivered <= self.iLim),
            Eq(self.cc, self.v <= self.vLim),
            # MSL: if cp then (if cv .. elseif cc .. else P0 = v*(-i)) else (if cv .. else ..)
            Eq(0, If(self.cv, voltage_law, If(sp.Or(self.cc, sp.Not(self.cp)), current_law, power_law))),
        ]
