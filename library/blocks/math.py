"""Mathematical blocks (Modelica.Blocks.Math)."""

from __future__ import annotations

import sympy as sp

from acausal.hybrid import ceil, floor
from acausal.language import Component, Eq, If, Parameter, RealInput
from acausal.components.blocks import SI2SO, SISO, IntegerOutput

__all__ = ["Gain", "Product", "Add", "Feedback", "Atan", "Sin", "RealToInteger"]


class Gain(SISO):
    """Output the product of a gain value with the input signal (Modelica.Blocks.Math.Gain): ``y = k*u``."""

    k = Parameter(1.0, description="Gain value multiplied with input signal")

    def equations(self):
        return [Eq(self.y, self.k * self.u)]


class Product(SI2SO):
    """Output product of the two inputs (Modelica.Blocks.Math.Product): ``y = u1*u2``."""

    def equations(self):
        return [Eq(self.y, self.u1 * self.u2)]


class Add(SI2SO):
    """Output the sum of the two inputs (Modelica.Blocks.Math.Add): ``y = k1*u1 + k2*u2``."""

    k1 = Parameter(1.0, description="Gain of input signal 1")
    k2 = Parameter(1.0, description="Gain of input signal 2")

    def equations(self):
        return [Eq(self.y, self.k1 * self.u1 + self.k2 * self.u2)]


class Feedback(SI2SO):
    """Output difference between commanded and feedback input (Modelica.Blocks.Math.Feedback).

    ``y = u1 - u2``.
    """

    def equations(self):
        return [Eq(self.y, self.u1 - self.u2)]


class Atan(SISO):
    """Output the arc tangent of the input (Modelica.Blocks.Math.Atan): ``y = atan(u)``."""

    def equations(self):
        return [Eq(self.y, sp.atan(self.u))]


class Sin(SISO):
    """Output the sine of the input (Modelica.Blocks.Math.Sin): ``y = sin(u)``."""

    def equations(self):
        return [Eq(self.y, sp.sin(self.u))]


class RealToInteger(Component):
    """Convert Real to Integer signal (Modelica.Blocks.Math.RealToInteger): the nearest
    Integer, halves away from zero: ``y = floor(u + 0.5)`` if ``u > 0``, else ``ceil(u - 0.5)``
    (event-generating, as Modelica's ``integer``)."""

    u = RealInput(description="Connector of Real input signal")
    y = IntegerOutput(description="Connector of Integer output signal")

    def equations(self):
        return [Eq(self.y, If(self.u > 0, floor(self.u + 0.5), ceil(self.u - 0.5)))]
