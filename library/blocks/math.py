"""Mathematical blocks (Modelica.Blocks.Math)."""

from __future__ import annotations

import sympy as sp

from acausal.language import Eq, Parameter
from acausal.components.blocks import SI2SO, SISO

__all__ = ["Gain", "Product", "Add", "Feedback", "Atan", "Sin"]


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
