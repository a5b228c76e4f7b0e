"""Signal sources (Modelica.Blocks.Sources)."""

from __future__ import annotations

import sympy as sp

from acausal.language import Eq, If, Parameter, time
from acausal.components.blocks import SO, SignalSource

__all__ = ["Constant", "Step", "Ramp", "Sine", "Cosine", "ExpSine"]


class Constant(SO):
    """Generate a constant signal (Modelica.Blocks.Sources.Constant): ``y = k``."""

    k = Parameter(1.0, description="Constant output value")

    def equations(self):
        return [Eq(self.y, self.k)]


class Step(SignalSource):
    """Generate a step signal (Modelica.Blocks.Sources.Step).

    ``y = offset + (0 if time < startTime else height)``.
    """

    height = Parameter(1.0, description="Height of step")

    def equations(self):
        return [Eq(self.y, self.offset + If(time < self.startTime, 0, self.height))]


class Ramp(SignalSource):
    """Generate a ramp signal (Modelica.Blocks.Sources.Ramp).

    ``offset`` before ``startTime``, then rising linearly by ``height`` over
    ``duration`` seconds, then ``offset + height``.
    """

    height = Parameter(1.0, description="Height of ramps")
    duration = Parameter(2.0, unit="s", min=0, description="Duration of ramp (= 0.0 gives a Step)")

    def equations(self):
        t0, dt = self.startTime, self.duration
        return [Eq(self.y, self.offset + sp.Piecewise(
            (0, time < t0),
            ((time - t0) * self.height / dt, time < t0 + dt),
            (self.height, True)))]


class _Harmonic(SignalSource):
    """Declarations and output equation shared by Sine and Cosine."""

    amplitude = Parameter(1.0, description="Amplitude of sine wave")
    f = Parameter(1.0, unit="Hz", description="Frequency of sine wave")
    phase = Parameter(0.0, unit="rad", description="Phase of sine wave")
    continuous = Parameter(False, structural=True,
                           description="Make output continuous by starting at offset + amplitude*sin(phase)")

    def _output(self, g):
        wave = g(2 * sp.pi * self.f * (time - self.startTime) + self.phase)
        if self.continuous:
            return Eq(self.y, self.offset + self.amplitude * If(time < self.startTime, g(self.phase), wave))
        return Eq(self.y, self.offset + If(time < self.startTime, 0, self.amplitude * wave))


class Sine(_Harmonic):
    """Generate a sine signal (Modelica.Blocks.Sources.Sine).

    ``y = offset + amplitude*sin(2*pi*f*(time - startTime) + phase)`` from
    ``startTime`` on; before it ``offset``, or with ``continuous`` the value
    ``offset + amplitude*sin(phase)``.
    """

    def equations(self):
        return [self._output(sp.sin)]


class Cosine(_Harmonic):
    """Generate a cosine signal (Modelica.Blocks.Sources.Cosine).

    ``y = offset + amplitude*cos(2*pi*f*(time - startTime) + phase)`` from
    ``startTime`` on; before it ``offset``, or with ``continuous`` the value
    ``offset + amplitude*cos(phase)``.
    """

    def equations(self):
        return [self._output(sp.cos)]


class ExpSine(SignalSource):
    """Generate an exponentially damped sine signal (Modelica.Blocks.Sources.ExpSine).

    ``y = offset + amplitude*exp(-(time - startTime)*damping)*sin(2*pi*f*(time
    - startTime) + phase)`` from ``startTime`` on, ``offset`` before.
    """

    amplitude = Parameter(1.0, description="Amplitude of sine wave")
    f = Parameter(2.0, unit="Hz", description="Frequency of sine wave")
    phase = Parameter(0.0, unit="rad", description="Phase of sine wave")
    damping = Parameter(1.0, unit="1/s", description="Damping coefficient of sine wave")

    def equations(self):
        dt = time - self.startTime
        wave = self.amplitude * sp.exp(-dt * self.damping) * sp.sin(2 * sp.pi * self.f * dt + self.phase)
        return [Eq(self.y, self.offset + If(time < self.startTime, 0, wave))]
