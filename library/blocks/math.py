"""Mathematical blocks (Modelica.Blocks.Math).

The vector blocks (:class:`MultiSum`, :class:`MultiProduct`, :class:`Sum`,
:class:`MinMax`, :class:`MatrixGain`, :class:`MultiSwitch`) have vector
connectors sized by structural Integer parameters (``MultiSum(nu=3)``); the
MSL sizes those of MultiSum, MultiProduct, MinMax and MultiSwitch by
connecting to them (``connectorSizing``), which acausal does not: give
``nu``.  Their elements are named as in Modelica (``sum1.u[2]``).
"""

from __future__ import annotations

from typing import Any

import sympy as sp

from acausal.arrays import Array, distribute, is_array_value
from acausal.arrays import max as array_max
from acausal.arrays import min as array_min
from acausal.arrays import product as array_product
from acausal.arrays import sum as array_sum
from acausal.errors import ArraySizeError, ModifierError
from acausal.hybrid import ceil, floor
from acausal.language import Component, Eq, If, Integer, Parameter, RealInput, RealOutput
from acausal.components.blocks import MIMO, MISO, SI2SO, SISO, BooleanInput, IntegerOutput, PartialRealMISO

__all__ = ["Gain", "Product", "Add", "Feedback", "Atan", "Sin", "RealToInteger", "MatrixGain", "MultiSum",
           "MultiProduct", "MultiSwitch", "Sum", "Max", "Min", "MinMax", "LinearDependency"]


class Gain(SISO):
    """Output the product of a gain value with the input signal (Modelica.Blocks.Math.Gain): ``y = k*u``."""

    modelica_name = "Modelica.Blocks.Math.Gain"

    k = Parameter(1.0, description="Gain value multiplied with input signal")

    def equations(self):
        return [Eq(self.y, self.k * self.u)]


class Product(SI2SO):
    """Output product of the two inputs (Modelica.Blocks.Math.Product): ``y = u1*u2``."""

    modelica_name = "Modelica.Blocks.Math.Product"

    def equations(self):
        return [Eq(self.y, self.u1 * self.u2)]


class Add(SI2SO):
    """Output the sum of the two inputs (Modelica.Blocks.Math.Add): ``y = k1*u1 + k2*u2``."""

    modelica_name = "Modelica.Blocks.Math.Add"

    k1 = Parameter(1.0, description="Gain of input signal 1")
    k2 = Parameter(1.0, description="Gain of input signal 2")

    def equations(self):
        return [Eq(self.y, self.k1 * self.u1 + self.k2 * self.u2)]


class Feedback(SI2SO):
    """Output difference between commanded and feedback input (Modelica.Blocks.Math.Feedback).

    ``y = u1 - u2``.
    """

    modelica_name = "Modelica.Blocks.Math.Feedback"

    def equations(self):
        return [Eq(self.y, self.u1 - self.u2)]


class Atan(SISO):
    """Output the arc tangent of the input (Modelica.Blocks.Math.Atan): ``y = atan(u)``."""

    modelica_name = "Modelica.Blocks.Math.Atan"

    def equations(self):
        return [Eq(self.y, sp.atan(self.u))]


class Sin(SISO):
    """Output the sine of the input (Modelica.Blocks.Math.Sin): ``y = sin(u)``."""

    modelica_name = "Modelica.Blocks.Math.Sin"

    def equations(self):
        return [Eq(self.y, sp.sin(self.u))]


class RealToInteger(Component):
    """Convert Real to Integer signal (Modelica.Blocks.Math.RealToInteger): the nearest
    Integer, halves away from zero: ``y = floor(u + 0.5)`` if ``u > 0``, else ``ceil(u - 0.5)``
    (event-generating, as Modelica's ``integer``)."""

    modelica_name = "Modelica.Blocks.Math.RealToInteger"

    u = RealInput(description="Connector of Real input signal")
    y = IntegerOutput(description="Connector of Integer output signal")

    def equations(self):
        return [Eq(self.y, If(self.u > 0, floor(self.u + 0.5), ceil(self.u - 0.5)))]


# -- vector blocks --------------------------------------------------------------------------


def _with_declared_value(klass: type, modifiers: dict[str, Any], name: str) -> dict[str, Any]:
    """``modifiers`` with the array parameter ``name`` given its declared default when absent.

    A work-around: an instance sized like an earlier one shares that one's
    sized class, whose element declarations hold the earlier instance's
    values as their defaults; giving the value every time keeps the
    declared default the default.
    """
    if name in modifiers:
        return modifiers
    unsized = vars(klass).get("_unsized", klass)
    return {**modifiers, name: unsized.declarations()[name].default}


class MatrixGain(MIMO):
    """Output the product of a gain matrix with the input signal vector
    (Modelica.Blocks.Math.MatrixGain): ``y = K*u``.

    The sizes follow ``K`` (the MSL's ``final nin=size(K, 2), final
    nout=size(K, 1)``): ``MatrixGain(K=[[1, 2, 3], [4, 5, 6]])`` has
    ``u[3]`` and ``y[2]``.  The elements of ``K`` are tunable parameters
    (``K[1,2]``); its shape is fixed where the block is made.
    """

    modelica_name = "Modelica.Blocks.Math.MatrixGain"

    K = Parameter([[1.0, 0.0], [0.0, 1.0]], description="Gain matrix which is multiplied with the input")
    nin = Parameter(2, structural=True, description="Number of inputs (= size(K, 2), set from K)")
    nout = Parameter(2, structural=True, description="Number of outputs (= size(K, 1), set from K)")

    def __new__(cls, *args: Any, **modifiers: Any):
        return super().__new__(cls, *args, **cls._with_sizes(modifiers))

    def __init__(self, **modifiers: Any) -> None:
        super().__init__(**type(self)._with_sizes(modifiers))

    @classmethod
    def _with_sizes(cls, modifiers: dict[str, Any]) -> dict[str, Any]:
        """``modifiers`` with ``K`` (its default if not given), ``nin`` and ``nout`` from its shape."""
        modifiers = _with_declared_value(cls, modifiers, "K")
        gain = modifiers["K"]
        if not is_array_value(gain):
            raise ModifierError(f"{cls.__name__}.K = {gain!r}: the gain is a matrix",
                                hint="MatrixGain(K=[[1, 0], [0, 1]])")
        shape = Array(gain).shape
        if len(shape) != 2:
            raise ArraySizeError(f"{cls.__name__}.K has size [{', '.join(map(str, shape))}]: it is a matrix",
                                 hint="give K as a list of rows, [[k11, k12], [k21, k22]]")
        sizes = {"nout": shape[0], "nin": shape[1]}
        for name, size in sizes.items():
            if name in modifiers and modifiers[name] != size:
                raise ArraySizeError(f"{cls.__name__}: {name} = {modifiers[name]!r}, but K has size "
                                     f"[{shape[0]}, {shape[1]}]", hint=f"{name} is set from K; leave it out")
        return {**modifiers, **sizes}

    def equations(self):
        return [Eq(self.y, self.K @ self.u)]


class MultiSum(PartialRealMISO):
    """Sum of Reals: y = k[1]*u[1] + k[2]*u[2] + ... + k[n]*u[n] (Modelica.Blocks.Math.MultiSum).

    ``y = 0`` for ``nu = 0``.
    """

    modelica_name = "Modelica.Blocks.Math.MultiSum"

    k = Parameter(1.0, shape="nu", description="Input gains")

    def __init__(self, **modifiers: Any) -> None:
        super().__init__(**_with_declared_value(type(self), modifiers, "k"))

    def equations(self):
        return [Eq(self.y, array_sum(self.k * self.u))]


class MultiProduct(PartialRealMISO):
    """Product of Reals: y = u[1]*u[2]* ... *u[n] (Modelica.Blocks.Math.MultiProduct).

    ``y = 0`` for ``nu = 0`` (as in the MSL, not the empty product 1).
    """

    modelica_name = "Modelica.Blocks.Math.MultiProduct"

    def equations(self):
        return [Eq(self.y, array_product(self.u) if self.nu > 0 else sp.Integer(0))]


class MultiSwitch(Component):
    """Set Real expression that is associated with the first active input signal
    (Modelica.Blocks.Math.MultiSwitch).

    ``y = expr[i]`` for the first ``i`` with ``u[i]`` true, ``y_default``
    if none is.  The MSL's ``expr`` is a vector of time-varying input
    expressions bound by a modifier; here it is a list of ``nu`` values,
    each a number or an expression of the model's signals
    (``MultiSwitch(nu=2, expr=[self.sine.y, 3])`` in ``build()``),
    structural because it is part of the equations.  ``firstActiveIndex``
    is that ``i`` (0 if no input is true).  The MSL's ``precision`` (digits
    shown in a diagram) is kept for its modifiers.
    """

    modelica_name = "Modelica.Blocks.Math.MultiSwitch"

    expr = Parameter(0.0, structural=True,
                     description="y = if u[i] then expr[i] else y_default (time varying); one per input")
    y_default = Parameter(0.0, description="Default value of output y if all u[i] = false")
    nu = Parameter(0, structural=True, min=0, description="Number of input connections")
    precision = Parameter(3, structural=True, min=0,
                          description="Number of significant digits to be shown in dynamic diagram layer for y")
    u = BooleanInput(shape="nu", description="Set y = expr[i], if u[i] = true")
    y = RealOutput(description="Output depending on expression")
    firstActiveIndex = Integer(description="Index of the first true input, 0 if none is")  # noqa: N815

    def equations(self):
        expressions = distribute(self.expr, (self.nu,), f"{self.path or type(self).__name__}.expr")
        first = [(sp.Integer(i), active) for i, active in enumerate(self.u, start=1)]
        chosen = [(sp.sympify(value), active) for value, active in zip(expressions, self.u)]
        return [Eq(self.firstActiveIndex, sp.Piecewise(*first, (sp.Integer(0), True))),
                Eq(self.y, sp.Piecewise(*chosen, (self.y_default, True)))]


class Sum(MISO):
    """Output the sum of the elements of the input vector (Modelica.Blocks.Math.Sum): ``y = k*u``
    (the scalar product)."""

    modelica_name = "Modelica.Blocks.Math.Sum"

    k = Parameter(1.0, shape="nin", description="Optional: sum coefficients")

    def __init__(self, **modifiers: Any) -> None:
        super().__init__(**_with_declared_value(type(self), modifiers, "k"))

    def equations(self):
        return [Eq(self.y, array_sum(self.k * self.u))]


class Max(SI2SO):
    """Pass through the largest signal (Modelica.Blocks.Math.Max): ``y = max(u1, u2)``."""

    modelica_name = "Modelica.Blocks.Math.Max"

    def equations(self):
        return [Eq(self.y, sp.Max(self.u1, self.u2))]


class Min(SI2SO):
    """Pass through the smallest signal (Modelica.Blocks.Math.Min): ``y = min(u1, u2)``."""

    modelica_name = "Modelica.Blocks.Math.Min"

    def equations(self):
        return [Eq(self.y, sp.Min(self.u1, self.u2))]


class MinMax(Component):
    """Output the minimum and the maximum element of the input vector (Modelica.Blocks.Math.MinMax):
    ``yMax = max(u)``, ``yMin = min(u)``.

    ``nu`` must be at least 1.  The MSL sizes ``u`` by connecting to it
    (``connectorSizing``, from a default of 0); acausal needs ``nu`` given,
    and its default is 1.
    """

    modelica_name = "Modelica.Blocks.Math.MinMax"

    nu = Parameter(1, structural=True, min=0, description="Number of input connections")
    u = RealInput("nu", description="Connector of Real input signals")
    yMax = RealOutput(description="Maximum of the input signals")  # noqa: N815 - Modelica's name
    yMin = RealOutput(description="Minimum of the input signals")  # noqa: N815

    def equations(self):
        if self.nu < 1:
            raise ArraySizeError(f"{self.path or type(self).__name__}: max() and min() of u of size [{self.nu}]",
                                 hint="give the number of inputs, MinMax(nu=3)")
        return [Eq(self.yMax, array_max(self.u)), Eq(self.yMin, array_min(self.u))]


class LinearDependency(SI2SO):
    """Output a linear combination of the two inputs (Modelica.Blocks.Math.LinearDependency):
    ``y = y0 + k1*u1 + k2*u2``."""

    modelica_name = "Modelica.Blocks.Math.LinearDependency"

    y0 = Parameter(0.0, description="Initial value")
    k1 = Parameter(0.0, description="Gain of u1")
    k2 = Parameter(0.0, description="Gain of u2")

    def equations(self):
        return [Eq(self.y, self.y0 + self.k1 * self.u1 + self.k2 * self.u2)]
