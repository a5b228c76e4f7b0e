"""Analog voltage and current sources (Modelica.Electrical.Analog.Sources).

The signal sources take their value from an input, the constant ones from a
parameter.  The time-function sources are, as in the MSL, a one-port whose
voltage (current) is the output of a Modelica.Blocks source, ``signalSource``,
built with the source's own parameters plus ``offset`` and ``startTime``:
``sineVoltage.signalSource.y`` is in the result as in a Modelica tool's.
"""

from __future__ import annotations

import sympy as sp

from acausal.language import Component, Eq, Parameter, RealInput, Variable, der
from acausal.components.declarations import DerivedDefaults
from acausal.components.electrical import CurrentSource, NegativePin, OnePort, PositivePin, VoltageSource
from acausal.library.blocks import sources as blocks

__all__ = [
    "SignalVoltage", "ConstantVoltage", "StepVoltage", "RampVoltage", "SineVoltage", "CosineVoltage",
    "ExpSineVoltage", "ExponentialsVoltage", "PulseVoltage", "SawToothVoltage", "TrapezoidVoltage",
    "TableVoltage", "SineVoltageVariableFrequencyAndAmplitude", "CosineVoltageVariableFrequencyAndAmplitude",
    "SupplyVoltage",
    "SignalCurrent", "ConstantCurrent", "StepCurrent", "RampCurrent", "SineCurrent", "CosineCurrent",
    "ExpSineCurrent", "ExponentialsCurrent", "PulseCurrent", "SawToothCurrent", "TrapezoidCurrent",
    "TableCurrent", "SineCurrentVariableFrequencyAndAmplitude", "CosineCurrentVariableFrequencyAndAmplitude",
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
