"""Mathematical blocks (Modelica.Blocks.Math).

The vector blocks (:class:`MultiSum`, :class:`MultiProduct`, :class:`Sum`,
:class:`MinMax`, :class:`MatrixGain`, :class:`MultiSwitch`) have vector
connectors sized by structural Integer parameters (``MultiSum(nu=3)``); the
MSL sizes those of MultiSum, MultiProduct, MinMax and MultiSwitch by
connecting to them (``connectorSizing``), which acausal does not: give
``nu``.  Their elements are named as in Modelica (``sum1.u[2]``).
"""

from __future__ import annotations

import math
import sys
from typing import Any

import sympy as sp

from acausal.arrays import Array, distribute, is_array_value
from acausal.arrays import max as array_max
from acausal.arrays import min as array_min
from acausal.arrays import product as array_product
from acausal.arrays import sum as array_sum
from acausal.errors import ArraySizeError, ModifierError
from acausal.hybrid import When, ceil, change, edge, floor, mod, noEvent, reinit, terminal
from acausal.language import (Component, Eq, If, Integer, Parameter, RealInput, RealOutput, Variable, der, initial,
                              pre, time)
from acausal.components.blocks import (MIMO, MISO, SI2SO, SISO, BooleanInput, BooleanOutput, IntegerInput,
                                       IntegerOutput, PartialRealMISO)

from .logical import And, GreaterThreshold

__all__ = ["Gain", "Product", "Add", "Feedback", "Atan", "Sin", "RealToInteger", "MatrixGain", "MultiSum",
           "MultiProduct", "MultiSwitch", "Sum", "Max", "Min", "MinMax", "LinearDependency",
           "Add3", "Division", "Abs", "Sign", "Sqrt", "Cos", "Tan", "Asin", "Acos", "Atan2", "Sinh", "Cosh", "Tanh",
           "Exp", "Power", "Exponentiation", "Log", "Log10", "WrapAngle", "IntegerToReal", "BooleanToInteger",
           "IntegerToBoolean", "RectangularToPolar", "PolarToRectangular", "Mean", "RectifiedMean", "RootMeanSquare",
           "Harmonic", "ContinuousMean", "Variance", "StandardDeviation", "SignalExtrema",
           "ContinuousSignalExtrema", "Pythagoras", "TotalHarmonicDistortion", "Edge", "BooleanChange", "IntegerChange"]


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


# -- more arithmetic ------------------------------------------------------------------------


class Add3(Component):
    """Output the sum of the three inputs (Modelica.Blocks.Math.Add3): ``y = k1*u1 + k2*u2 + k3*u3``."""

    modelica_name = "Modelica.Blocks.Math.Add3"

    k1 = Parameter(1.0, description="Gain of input signal 1")
    k2 = Parameter(1.0, description="Gain of input signal 2")
    k3 = Parameter(1.0, description="Gain of input signal 3")
    u1 = RealInput(description="Connector of Real input signal 1")
    u2 = RealInput(description="Connector of Real input signal 2")
    u3 = RealInput(description="Connector of Real input signal 3")
    y = RealOutput(description="Connector of Real output signal")

    def equations(self):
        return [Eq(self.y, self.k1 * self.u1 + self.k2 * self.u2 + self.k3 * self.u3)]


class Division(SI2SO):
    """Output first input divided by second input (Modelica.Blocks.Math.Division): ``y = u1/u2``."""

    modelica_name = "Modelica.Blocks.Math.Division"

    def equations(self):
        return [Eq(self.y, self.u1 / self.u2)]


class Abs(SISO):
    """Output the absolute value of the input (Modelica.Blocks.Math.Abs): ``y = abs(u)``.

    ``generateEvent=True`` makes the switch at ``u = 0`` an event (``if u >= 0
    then u else -u``); by default it is evaluated literally, without one.
    """

    modelica_name = "Modelica.Blocks.Math.Abs"

    generateEvent = Parameter(False, structural=True,  # noqa: N815 - Modelica's name
                              description="Choose whether events shall be generated")

    def equations(self):
        if self.generateEvent:
            return [Eq(self.y, If(self.u >= 0, self.u, -self.u))]
        return [Eq(self.y, sp.Abs(self.u))]  # abs() makes no events


class Sign(SISO):
    """Output the sign of the input (Modelica.Blocks.Math.Sign): ``y = sign(u)`` (1, -1 or 0).

    ``generateEvent=True`` makes the switches events; by default they are
    evaluated literally, without events.
    """

    modelica_name = "Modelica.Blocks.Math.Sign"

    generateEvent = Parameter(False, structural=True,  # noqa: N815
                              description="Choose whether events shall be generated")

    def equations(self):
        sign = sp.Piecewise((1, self.u > 0), (-1, self.u < 0), (0, True))
        return [Eq(self.y, sign if self.generateEvent else noEvent(sign))]


class Sqrt(SISO):
    """Output the square root of the input (input >= 0 required) (Modelica.Blocks.Math.Sqrt): ``y = sqrt(u)``."""

    modelica_name = "Modelica.Blocks.Math.Sqrt"

    def equations(self):
        return [Eq(self.y, sp.sqrt(self.u))]


def _function_block(name: str, function: Any, text: str, *, u_unit: str = "", y_unit: str = "") -> type:
    """A SISO block ``y = function(u)`` named ``Modelica.Blocks.Math.<name>``.

    ``u_unit``/``y_unit`` are the units the MSL gives the connectors (``rad``
    for the argument of a trigonometric function and the result of an inverse
    one).
    """
    namespace: dict[str, Any] = {
        "__doc__": f"Output the {text} of the input (Modelica.Blocks.Math.{name}): ``y = {name.lower()}(u)``.",
        "__module__": __name__,
        "__qualname__": name,
        "modelica_name": f"Modelica.Blocks.Math.{name}",
        "equations": lambda self: [Eq(self.y, function(self.u))],
    }
    if u_unit:
        namespace["u"] = RealInput(unit=u_unit, description="Connector of Real input signal")
    if y_unit:
        namespace["y"] = RealOutput(unit=y_unit, description="Connector of Real output signal")
    return type(name, (SISO,), namespace)


Cos = _function_block("Cos", sp.cos, "cosine", u_unit="rad")
Tan = _function_block("Tan", sp.tan, "tangent", u_unit="rad")
Asin = _function_block("Asin", sp.asin, "arc sine", y_unit="rad")
Acos = _function_block("Acos", sp.acos, "arc cosine", y_unit="rad")
Sinh = _function_block("Sinh", sp.sinh, "hyperbolic sine")
Cosh = _function_block("Cosh", sp.cosh, "hyperbolic cosine")
Tanh = _function_block("Tanh", sp.tanh, "hyperbolic tangent")
Exp = _function_block("Exp", sp.exp, "exponential (base e)")
Log10 = _function_block("Log10", lambda u: sp.log(u, 10), "base 10 logarithm (input > 0 required)")


class Atan2(SI2SO):
    """Output atan(u1/u2) of the inputs u1 and u2 (Modelica.Blocks.Math.Atan2): ``y = atan2(u1, u2)``,
    the angle in ]-pi, pi] with the quadrant from the signs of both inputs."""

    modelica_name = "Modelica.Blocks.Math.Atan2"

    y = RealOutput(unit="rad", description="Connector of Real output signal")

    def equations(self):
        return [Eq(self.y, sp.atan2(self.u1, self.u2))]


class Power(SISO):
    """Output the power to a base of the input (Modelica.Blocks.Math.Power): ``y = base^u``.

    With ``useExp`` (the default) written ``exp(u*log(base))``, as the MSL does.
    """

    modelica_name = "Modelica.Blocks.Math.Power"

    base = Parameter(math.e, description="Base of power")
    useExp = Parameter(True, structural=True, description="Use exp function in implementation")  # noqa: N815

    def equations(self):
        if self.useExp:
            return [Eq(self.y, sp.exp(self.u * sp.log(self.base)))]
        return [Eq(self.y, self.base ** self.u)]


class Exponentiation(SISO):
    """Output the input raised to an exponent (Modelica.Blocks.Math.Exponentiation): ``y = u^exponent``."""

    modelica_name = "Modelica.Blocks.Math.Exponentiation"

    exponent = Parameter(2.0, description="Exponent of power")

    def equations(self):
        return [Eq(self.y, self.u ** self.exponent)]


class Log(SISO):
    """Output the logarithm (default base e) of the input (input > 0 required) (Modelica.Blocks.Math.Log):
    ``y = log(u)/log(base)``."""

    modelica_name = "Modelica.Blocks.Math.Log"

    base = Parameter(math.e, description="Base of logarithm")

    def equations(self):
        return [Eq(self.y, sp.log(self.u) / sp.log(self.base))]


class WrapAngle(SISO):
    """Wrap angle to interval ]-pi,pi] or [0,2*pi[ (Modelica.Blocks.Math.WrapAngle).

    ``y = mod(u, 2*pi)``, less ``2*pi`` where that exceeds pi unless
    ``positiveRange``.  The MSL computes it in a function
    (Modelica.Math.wrapAngle), whose relations make no events: so here under
    ``noEvent``.
    """

    modelica_name = "Modelica.Blocks.Math.WrapAngle"

    positiveRange = Parameter(False, structural=True,  # noqa: N815
                              description="Use only positive output range, if true")
    u = RealInput(unit="rad", description="Connector of Real input signal")
    y = RealOutput(unit="rad", description="Connector of Real output signal")

    def equations(self):
        wrapped = mod(self.u, 2 * sp.pi)
        if not self.positiveRange:
            wrapped = sp.Piecewise((wrapped - 2 * sp.pi, wrapped > sp.pi), (wrapped, True))
        return [Eq(self.y, noEvent(wrapped))]


# -- conversions ----------------------------------------------------------------------------


class IntegerToReal(Component):
    """Convert Integer to Real signals (Modelica.Blocks.Math.IntegerToReal): ``y = u``."""

    modelica_name = "Modelica.Blocks.Math.IntegerToReal"

    u = IntegerInput(description="Connector of Integer input signal")
    y = RealOutput(description="Connector of Real output signal")

    def equations(self):
        return [Eq(self.y, self.u)]


class BooleanToInteger(Component):
    """Convert Boolean to Integer signal (Modelica.Blocks.Math.BooleanToInteger):
    ``y = integerTrue if u else integerFalse``."""

    modelica_name = "Modelica.Blocks.Math.BooleanToInteger"

    integerTrue = Parameter(1, description="Output signal for true Boolean input")  # noqa: N815
    integerFalse = Parameter(0, description="Output signal for false Boolean input")  # noqa: N815
    u = BooleanInput(description="Connector of Boolean input signal")
    y = IntegerOutput(description="Connector of Integer output signal")

    def equations(self):
        return [Eq(self.y, If(self.u, self.integerTrue, self.integerFalse))]


class IntegerToBoolean(Component):
    """Convert Integer to Boolean signal (Modelica.Blocks.Math.IntegerToBoolean): ``y = u >= threshold``."""

    modelica_name = "Modelica.Blocks.Math.IntegerToBoolean"

    threshold = Parameter(1, description="Output signal y is true, if input u >= threshold")
    u = IntegerInput(description="Connector of Integer input signal")
    y = BooleanOutput(description="Connector of Boolean output signal")

    def equations(self):
        return [Eq(self.y, self.u >= self.threshold)]


class RectangularToPolar(Component):
    """Convert rectangular coordinates to polar coordinates (Modelica.Blocks.Math.RectangularToPolar):
    ``y_abs = sqrt(u_re^2 + u_im^2)``, ``y_arg = atan2(u_im, u_re)``."""

    modelica_name = "Modelica.Blocks.Math.RectangularToPolar"

    u_re = RealInput(description="Real part of rectangular representation")
    u_im = RealInput(description="Imaginary part of rectangular representation")
    y_abs = RealOutput(description="Length of polar representation")
    y_arg = RealOutput(unit="rad", description="Angle of polar representation")

    def equations(self):
        return [Eq(self.y_abs, sp.sqrt(self.u_re * self.u_re + self.u_im * self.u_im)),
                Eq(self.y_arg, sp.atan2(self.u_im, self.u_re))]


class PolarToRectangular(Component):
    """Convert polar coordinates to rectangular coordinates (Modelica.Blocks.Math.PolarToRectangular):
    ``y_re = u_abs*cos(u_arg)``, ``y_im = u_abs*sin(u_arg)``."""

    modelica_name = "Modelica.Blocks.Math.PolarToRectangular"

    u_abs = RealInput(description="Length of polar representation")
    u_arg = RealInput(unit="rad", description="Angle of polar representation")
    y_re = RealOutput(description="Real part of rectangular representation")
    y_im = RealOutput(description="Imaginary part of rectangular representation")

    def equations(self):
        return [Eq(self.y_re, self.u_abs * sp.cos(self.u_arg)),
                Eq(self.y_im, self.u_abs * sp.sin(self.u_arg))]


# -- statistics over a period ---------------------------------------------------------------


class Mean(SISO):
    """Calculate mean over period 1/f (Modelica.Blocks.Math.Mean).

    ``x`` integrates ``u``; at the end of every period (``t0 + i/f``, ``t0``
    the start time of the simulation) ``y`` takes ``f*x``, the mean over the
    period that ended, and ``x`` restarts from 0.  Before the first period
    ends ``y = y0``.  ``yGreaterOrEqualZero`` clips the result at 0 (for a
    quantity that is never negative, as the square in RootMeanSquare).

    The MSL samples with ``sample(t0 + 1/f, 1/f)``, where ``t0`` is a
    parameter fixed at initialization (``t0 = time``); acausal's ``sample``
    takes a start known when translating, so the period ends are written as
    the time events ``time >= t0 + (periods + 1)/f`` on the discrete
    ``t0`` and count of ``periods`` (the same instants, each computed from
    its index).
    """

    modelica_name = "Modelica.Blocks.Math.Mean"

    f = Parameter(50.0, unit="Hz", description="Base frequency")
    x0 = Parameter(0.0, description="Start value of integrator state")
    y0 = Parameter(0.0, description="Start value of output")
    yGreaterOrEqualZero = Parameter(False, structural=True,  # noqa: N815
                                    description="= true, if output y is guaranteed to be >= 0 for the exact "
                                                "solution")
    x = Variable(description="Integrator state (protected)")
    y_last = Variable(discrete=True, description="Last sampled mean value (protected)")
    t0 = Variable(discrete=True, unit="s", description="Start time of simulation (protected)")
    periods = Variable(discrete=True, description="Number of periods ended (protected)")

    def equations(self):
        mean = self.f * pre(self.x)
        if self.yGreaterOrEqualZero:
            mean = sp.Max(0, mean)
        return [
            Eq(der(self.x), self.u),
            When(initial(), Eq(self.t0, time), Eq(self.periods, 0), Eq(self.y_last, self.y0))
            .elsewhen(time >= self.t0 + (self.periods + 1) / self.f,
                      Eq(self.t0, pre(self.t0)), Eq(self.periods, pre(self.periods) + 1),
                      Eq(self.y_last, mean), reinit(self.x, 0)),
            Eq(self.y, self.y_last),
        ]

    def initial_equations(self):
        return [Eq(self.x, self.x0)]


class RectifiedMean(SISO):
    """Calculate rectified mean over period 1/f (Modelica.Blocks.Math.RectifiedMean): the
    :class:`Mean` of ``abs(u)``, as the MSL builds it (an :class:`Abs` ``abs1`` into a Mean ``mean``)."""

    modelica_name = "Modelica.Blocks.Math.RectifiedMean"

    f = Parameter(50.0, unit="Hz", description="Base frequency")
    x0 = Parameter(0.0, description="Start value of integrator state")
    y0 = Parameter(0.0, min=0, description="Start value of output")

    def build(self) -> None:
        self.mean = Mean(f=self.f, x0=self.x0, y0=self.y0)
        self.abs1 = Abs()
        self.connect(self.u, self.abs1.u)
        self.connect(self.abs1.y, self.mean.u)

    def equations(self):
        # the MSL connects mean.y to y; the engine takes an inner output to the block's own
        # output as an equation (the same flat equation)
        return [Eq(self.y, self.mean.y)]


class RootMeanSquare(SISO):
    """Calculate root mean square over period 1/f (Modelica.Blocks.Math.RootMeanSquare).

    As the MSL builds it: ``u*u`` (a :class:`MultiProduct` ``product``) into a
    :class:`Mean` ``mean`` (clipped at 0, starting from ``y0^2``), then a
    :class:`Sqrt` ``sqrt1``.
    """

    modelica_name = "Modelica.Blocks.Math.RootMeanSquare"

    f = Parameter(50.0, unit="Hz", description="Base frequency")
    x0 = Parameter(0.0, description="Start value of integrator state")
    y0 = Parameter(0.0, min=0, description="Start value of output")

    def build(self) -> None:
        self.product = MultiProduct(nu=2)
        self.mean = Mean(f=self.f, y0=self.y0 ** 2, yGreaterOrEqualZero=True, x0=self.x0)
        self.sqrt1 = Sqrt()
        self.connect(self.product.y, self.mean.u)
        self.connect(self.mean.y, self.sqrt1.u)
        self.connect(self.u, self.product.u[1])
        self.connect(self.u, self.product.u[2])

    def equations(self):
        return [Eq(self.y, self.sqrt1.y)]


class Harmonic(Component):
    """Calculate harmonic over period 1/f (Modelica.Blocks.Math.Harmonic).

    The ``k``-th harmonic of ``u`` over each period ``1/f``: the means of
    ``u*sqrt(2)*cos(2*pi*k*f*t)`` (``mean1``) and ``u*sqrt(2)*sin(2*pi*k*f*t)``
    (``mean2``) are its real and imaginary parts, which a
    :class:`RectangularToPolar` turns into the RMS value ``y_rms`` and the
    angle ``y_arg`` (negated for ``useConjugateComplex``).  So ``u =
    A*cos(2*pi*k*f*t + phi)`` gives ``y_rms = A/sqrt(2)`` and ``y_arg = -phi``.

    The MSL takes the two carriers from a Cosine ``sin1`` and a Sine ``sin2``
    source (start time 0); here they are the equations ``carrierCos`` and
    ``carrierSin``, the same functions of time.
    """

    modelica_name = "Modelica.Blocks.Math.Harmonic"

    f = Parameter(50.0, unit="Hz", description="Base frequency")
    k = Parameter(1, description="Order of harmonic")
    useConjugateComplex = Parameter(False, structural=True,  # noqa: N815
                                    description="Gives conjugate complex result if true")
    x0Cos = Parameter(0.0, description="Start value of cos integrator state")  # noqa: N815
    x0Sin = Parameter(0.0, description="Start value of sin integrator state")  # noqa: N815
    y0Cos = Parameter(0.0, description="Start value of cos result")  # noqa: N815
    y0Sin = Parameter(0.0, description="Start value of sin result")  # noqa: N815
    u = RealInput(description="Connector of Real input signal")
    y_rms = RealOutput(description="Root mean square of polar representation")
    y_arg = RealOutput(unit="rad", description="Angle of polar representation")
    carrierCos = Variable(description="sqrt(2)*cos(2*pi*k*f*time) (protected)")  # noqa: N815
    carrierSin = Variable(description="sqrt(2)*sin(2*pi*k*f*time) (protected)")  # noqa: N815

    def build(self) -> None:
        self.product1 = MultiProduct(nu=2)
        self.product2 = MultiProduct(nu=2)
        self.mean1 = Mean(f=self.f, x0=self.x0Cos, y0=self.y0Cos)
        self.mean2 = Mean(f=self.f, x0=self.x0Sin, y0=self.y0Sin)
        self.rectangularToPolar = RectangularToPolar()
        self.gain = Gain(k=-1 if self.useConjugateComplex else 1)
        self.connect(self.product2.y, self.mean2.u)
        self.connect(self.product1.y, self.mean1.u)
        self.connect(self.mean1.y, self.rectangularToPolar.u_re)
        self.connect(self.mean2.y, self.rectangularToPolar.u_im)
        self.connect(self.u, self.product1.u[2])
        self.connect(self.u, self.product2.u[1])
        self.connect(self.rectangularToPolar.y_arg, self.gain.u)

    def equations(self):
        angle = 2 * sp.pi * self.k * self.f * time
        return [Eq(self.carrierCos, sp.sqrt(2) * sp.cos(angle)),
                Eq(self.carrierSin, sp.sqrt(2) * sp.sin(angle)),
                Eq(self.product1.u[1], self.carrierCos),
                Eq(self.product2.u[2], self.carrierSin),
                Eq(self.y_rms, self.rectangularToPolar.y_abs),
                Eq(self.y_arg, self.gain.y)]


class ContinuousMean(Component):
    """Calculates the empirical expectation (mean) value of its input signal
    (Modelica.Blocks.Math.ContinuousMean).

    ``y`` is the mean of ``u`` from ``max(t_0, startTime)`` (``t_0`` the start
    time of the simulation) up to now, ``mu/(time - start)`` with ``der(mu) =
    u`` from the start on; for the first ``t_eps`` seconds (and before
    ``startTime``) ``y = u``.  The MSL's ``t_0`` is a parameter fixed at
    initialization (``t_0 = time``); here it is a discrete Real set then,
    so that the start of the averaging is a time event.
    """

    modelica_name = "Modelica.Blocks.Math.ContinuousMean"

    t_eps = Parameter(1e-7, unit="s", min=0, description="Mean value calculation starts at startTime + t_eps")
    startTime = Parameter(-math.inf, finite=False,  # noqa: N815
                          description="Starting point for mean if after simulation start-point")
    u = RealInput(description="Noisy input signal")
    y = RealOutput(description="Expectation (mean) value of the input signal")
    mu = Variable(start=0.0, fixed=True, description="Internal integrator variable (protected)")
    t_0 = Variable(discrete=True, unit="s", description="Start time (protected)")

    def equations(self):
        start = sp.Max(self.t_0, self.startTime)
        return [When(initial(), Eq(self.t_0, time)),
                Eq(der(self.mu), If(time >= start, self.u, 0)),
                Eq(self.y, noEvent(sp.Piecewise((self.mu / (time - start), time > start + self.t_eps),
                                                (self.u, True))))]


class Variance(Component):
    """Calculates the empirical variance of its input signal (Modelica.Blocks.Math.Variance).

    ``mu`` follows the running mean and ``var`` the running variance from the
    start of the simulation ``t_0``: ``der(mu) = (u - mu)/(time - t_0)``,
    ``der(var) = ((u - mu)^2 - var)/(time - t_0)``, both 0 (and ``y = 0``)
    for the first ``t_eps`` seconds; ``y = max(var, 0)``.  The MSL's ``t_0``
    is a parameter fixed at initialization; here a discrete Real set then.
    """

    modelica_name = "Modelica.Blocks.Math.Variance"

    t_eps = Parameter(1e-7, unit="s", min=100 * 2.220446049250313e-16,
                      description="Variance calculation starts at startTime + t_eps")
    u = RealInput(description="Noisy input signal")
    y = RealOutput(description="Variance of the input signal")
    mu = Variable(description="Mean value (state variable) (protected)")
    var = Variable(description="Variance (state variable) (protected)")
    t_0 = Variable(discrete=True, unit="s", description="Start time (protected)")

    def equations(self):
        running = time >= self.t_0 + self.t_eps
        elapsed = time - self.t_0
        return [When(initial(), Eq(self.t_0, time)),
                Eq(der(self.mu), noEvent(sp.Piecewise(((self.u - self.mu) / elapsed, running), (0, True)))),
                Eq(der(self.var), noEvent(sp.Piecewise((((self.u - self.mu) ** 2 - self.var) / elapsed, running),
                                                       (0, True)))),
                Eq(self.y, noEvent(sp.Piecewise((sp.Max(self.var, 0), running), (0, True))))]

    def initial_equations(self):
        return [Eq(self.mu, self.u), Eq(self.var, 0)]


class StandardDeviation(Component):
    """Calculates the empirical standard deviation of its input signal
    (Modelica.Blocks.Math.StandardDeviation): the square root (a :class:`Sqrt` ``sqrt1``) of a
    :class:`Variance` ``variance``, as the MSL builds it."""

    modelica_name = "Modelica.Blocks.Math.StandardDeviation"

    t_eps = Parameter(1e-7, unit="s", min=100 * 2.220446049250313e-16,
                      description="Standard deviation calculation starts at startTime + t_eps")
    u = RealInput(description="Noisy input signal")
    y = RealOutput(description="Standard deviation of the input signal")

    def build(self) -> None:
        self.variance = Variance(t_eps=self.t_eps)
        self.sqrt1 = Sqrt()
        self.connect(self.variance.u, self.u)
        self.connect(self.sqrt1.u, self.variance.y)

    def equations(self):
        return [Eq(self.y, self.sqrt1.y)]


class SignalExtrema(Component):
    """Calculate min and max of a signal (Modelica.Blocks.Math.SignalExtrema).

    ``u`` is sampled every ``Ts`` seconds from the start time ``t0`` of the
    simulation on; ``y_min``/``y_max`` are the smallest and largest samples
    so far (``u`` at the start), ``t_min``/``t_max`` the instants they were
    taken.  The MSL samples with ``sample(t0 + Ts, Ts)``, ``t0`` a parameter
    fixed at initialization; here the sample instants are the time events
    ``time >= t0 + (samples + 1)*Ts`` on the discrete ``t0`` and count of
    ``samples`` (the same instants).
    """

    modelica_name = "Modelica.Blocks.Math.SignalExtrema"

    Ts = Parameter(0.01, unit="s", description="Sample time")
    u = RealInput(description="Connector of Real input signal")
    y_min = RealOutput(description="Min of input signal")
    y_max = RealOutput(description="Max of input signal")
    t_min = Variable(discrete=True, description="Sample time of last found minimum")
    t_max = Variable(discrete=True, description="Sample time of last found maximum")
    t0 = Variable(discrete=True, unit="s", description="Start time of simulation (protected)")
    samples = Variable(discrete=True, description="Number of samples taken (protected)")

    def equations(self):
        new_min = self.u < pre(self.y_min)
        new_max = sp.And(sp.Not(new_min), self.u > pre(self.y_max))
        return [
            When(initial(), Eq(self.t0, time), Eq(self.samples, 0), Eq(self.y_min, self.u), Eq(self.y_max, self.u),
                 Eq(self.t_min, time), Eq(self.t_max, time))
            .elsewhen(time >= self.t0 + (self.samples + 1) * self.Ts,
                      Eq(self.t0, pre(self.t0)), Eq(self.samples, pre(self.samples) + 1),
                      Eq(self.y_min, sp.Min(self.u, pre(self.y_min))), Eq(self.y_max, sp.Max(self.u, pre(self.y_max))),
                      Eq(self.t_min, If(new_min, time, pre(self.t_min))),
                      Eq(self.t_max, If(new_max, time, pre(self.t_max)))),
        ]


class ContinuousSignalExtrema(Component):
    """Store the minimum and maximum values of the input signal
    (Modelica.Blocks.Math.ContinuousSignalExtrema).

    A first-order lag ``x`` of ``u`` (time constant ``T``) follows it; where
    ``u`` crosses ``x`` (the derivative of ``u`` changes sign, a local
    extremum, or just before and after a step) and at the end of the run,
    ``y_min``/``y_max`` take the smallest/largest of their last value, ``u``
    and ``pre(u)``, and ``t_min``/``t_max`` the instant where they changed.

    With the default ``T = 1e-6`` the lag makes the model stiff, and ``u -
    x`` stays within the integration error of zero around an extremum:
    simulate with an implicit method (``method="Radau"``); an explicit one
    sees ``u <= x`` flip ever faster there and stops with a ZenoError.
    """

    modelica_name = "Modelica.Blocks.Math.ContinuousSignalExtrema"

    T = Parameter(1e-6, unit="s", min=2.2250738585072014e-308, description="Derivative time constant")
    u = RealInput(description="Connector of Real input signal")
    y_min = RealOutput(description="Min of input signal")
    y_max = RealOutput(description="Max of input signal")
    t_min = RealOutput(unit="s", description="Time instant of last found minimum")
    t_max = RealOutput(unit="s", description="Time instant of last found maximum")
    x = Variable(description="Aux.state (protected)")

    def equations(self):
        smallest = sp.Min(pre(self.y_min), self.u, pre(self.u))
        largest = sp.Max(pre(self.y_max), self.u, pre(self.u))
        return [
            Eq(der(self.x), (self.u - self.x) / self.T),
            When(initial(), Eq(self.y_min, self.u), Eq(self.y_max, self.u), Eq(self.t_min, time),
                 Eq(self.t_max, time))
            .elsewhen([self.u <= self.x, self.u >= self.x, terminal()],
                      Eq(self.y_min, smallest), Eq(self.y_max, largest),
                      Eq(self.t_min, If(smallest < pre(self.y_min), time, pre(self.t_min))),
                      Eq(self.t_max, If(largest > pre(self.y_max), time, pre(self.t_max)))),
        ]

    def initial_equations(self):
        return [Eq(self.x, self.u)]


class Pythagoras(SI2SO):
    """Determine the hypotenuse or leg of a right triangle (Modelica.Blocks.Math.Pythagoras).

    ``y = sqrt(u1^2 + u2^2)`` (always valid), or with ``u1IsHypotenuse`` the
    other leg ``y = sqrt(u1^2 - u2^2)``, valid where ``u1^2 >= u2^2`` (else
    ``y = 0``).
    """

    modelica_name = "Modelica.Blocks.Math.Pythagoras"

    u1IsHypotenuse = Parameter(False, structural=True,  # noqa: N815
                               description="= true, if u1 is the hypotenuse and y is one leg")
    valid = BooleanOutput(description="= true, if y is a valid result")
    y2 = Variable(description="Square of y (protected)")

    def equations(self):
        if not self.u1IsHypotenuse:
            return [Eq(self.y2, self.u1 ** 2 + self.u2 ** 2), Eq(self.y, sp.sqrt(self.y2)),
                    Eq(self.valid, sp.true)]
        return [Eq(self.y2, self.u1 ** 2 - self.u2 ** 2), Eq(self.valid, self.y2 >= 0),
                Eq(self.y, noEvent(sp.Piecewise((sp.sqrt(self.y2), self.y2 >= 0), (0, True))))]


class TotalHarmonicDistortion(SISO):
    """Output the total harmonic distortion (THD) (Modelica.Blocks.Math.TotalHarmonicDistortion).

    Over each period ``1/f``: the RMS value of everything but the first
    harmonic, ``sqrt(rms^2 - h1^2)`` (a :class:`Pythagoras` of the
    :class:`RootMeanSquare` ``rootMeanSquare`` and the RMS value of the
    :class:`Harmonic` ``harmonic``), divided by the first harmonic's RMS
    value ``h1`` or, with ``useFirstHarmonic=False``, by the total RMS value.
    ``valid`` is true where the result means something: the first harmonic
    is not zero and ``rms >= h1``.

    As the MSL builds it, except for the choice of the denominator and the
    limiter: the MSL switches between the two RMS values with a Switch
    driven by a BooleanExpression ``not useFirstHarmonic``, then keeps the
    denominator above machine epsilon with a Limiter; here the parameter,
    being structural, picks the signal, and the equation ``division.u2 =
    max(denominator, eps)`` (without events, as the Limiter) limits it.
    """

    modelica_name = "Modelica.Blocks.Math.TotalHarmonicDistortion"

    f = Parameter(1.0, unit="Hz", description="Base frequency")
    useFirstHarmonic = Parameter(True, structural=True,  # noqa: N815
                                 description="THD with respect to first harmonic, if true; otherwise with respect "
                                             "to total RMS")
    valid = BooleanOutput(description="True, if output y is valid")

    def build(self) -> None:
        self.harmonic = Harmonic(f=self.f, k=1, x0Cos=0, x0Sin=0, y0Cos=0, y0Sin=0)
        self.rootMeanSquare = RootMeanSquare(f=self.f, x0=0, y0=0)
        self.greaterThreshold = GreaterThreshold()
        self.division = Division()
        self.pythagoras = Pythagoras(u1IsHypotenuse=True)
        self.andValid = And()
        self.connect(self.u, self.rootMeanSquare.u)
        self.connect(self.u, self.harmonic.u)
        self.connect(self.harmonic.y_rms, self.greaterThreshold.u)
        self.connect(self.pythagoras.u1, self.rootMeanSquare.y)
        self.connect(self.pythagoras.y, self.division.u1)
        self.connect(self.pythagoras.valid, self.andValid.u1)
        self.connect(self.greaterThreshold.y, self.andValid.u2)
        self.connect(self.harmonic.y_rms, self.pythagoras.u2)

    def equations(self):
        eps = sys.float_info.epsilon  # Modelica.Constants.eps
        denominator = self.harmonic.y_rms if self.useFirstHarmonic else self.rootMeanSquare.y
        return [Eq(self.division.u2, noEvent(sp.Piecewise((eps, denominator < eps), (denominator, True)))),
                Eq(self.y, self.division.y),
                Eq(self.valid, self.andValid.y)]


# -- Boolean and Integer changes ------------------------------------------------------------


class Edge(Component):
    """Indicates rising edge of Boolean signal (Modelica.Blocks.Math.Edge): ``y = edge(u)``.

    The same as Modelica.Blocks.Logical.Edge, without its ``pre_u_start``
    (``pre(u)`` starts false); import it from this module.
    """

    modelica_name = "Modelica.Blocks.Math.Edge"

    u = BooleanInput(description="Connector of Boolean input signal")
    y = BooleanOutput(description="Connector of Boolean output signal")

    def equations(self):
        return [Eq(self.y, edge(self.u))]


class BooleanChange(Component):
    """Indicates Boolean signal changing (Modelica.Blocks.Math.BooleanChange): ``y = change(u)``."""

    modelica_name = "Modelica.Blocks.Math.BooleanChange"

    u = BooleanInput(description="Connector of Boolean input signal")
    y = BooleanOutput(description="Connector of Boolean output signal")

    def equations(self):
        return [Eq(self.y, change(self.u))]


class IntegerChange(Component):
    """Indicates integer signal changing (Modelica.Blocks.Math.IntegerChange): ``y = change(u)``."""

    modelica_name = "Modelica.Blocks.Math.IntegerChange"

    u = IntegerInput(description="Connector of Integer input signal")
    y = BooleanOutput(description="Connector of Boolean output signal")

    def equations(self):
        return [Eq(self.y, change(self.u))]


class InverseBlockConstraints(Component):
    """Construct inverse model by requiring that two inputs and two outputs are identical
    (Modelica.Blocks.Math.InverseBlockConstraints): ``u1 = u2``, ``y1 = y2``.

    Connected around a block (``y2`` to its input, ``u2`` to its output), it
    exchanges the block's input and output: the desired output enters at
    ``u1``, the input that produces it leaves at ``y1``.  Inverting a block
    with states makes its output a constraint; index reduction then
    differentiates the block's equations (and those of what drives ``u1``,
    which must be smooth enough: a filter of sufficient order).
    """

    modelica_name = "Modelica.Blocks.Math.InverseBlockConstraints"

    u1 = RealInput(description="Input signal 1 (u1 = u2)")
    u2 = RealInput(description="Input signal 2 (u1 = u2)")
    y1 = RealOutput(description="Output signal 1 (y1 = y2)")
    y2 = RealOutput(description="Output signal 2 (y1 = y2)")

    def equations(self):
        return [Eq(self.u1, self.u2), Eq(self.y1, self.y2)]


# --------------------------------------------------------------------------
# RealFFT: sampling into a buffer, the FFT when the run has ended
# --------------------------------------------------------------------------

import os  # noqa: E402 - the RealFFT section keeps its imports with it
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

from acausal.errors import AssertionViolation, ParameterError, SimulationError  # noqa: E402
from acausal.fileio import atomic_write  # noqa: E402

from .discrete import DiscreteBlock  # noqa: E402

__all__ += ["RealFFT", "real_fft_sample_points", "real_fft"]


def real_fft_sample_points(f_max: float, f_resolution: float, f_max_factor: int = 5) -> int:
    """The number of sample points of a real FFT
    (Modelica.Math.FastFourierTransform.realFFTsamplePoints).

    The smallest even ``ns >= 2*ceil(f_max*f_max_factor/f_resolution)`` that is a
    product of powers of 2, 3 and 5 (for which the FFT is fastest).

    Parameters
    ----------
    f_max : float
        Maximum frequency of interest, Hz; more than ``f_resolution``.
    f_resolution : float
        Frequency resolution, Hz; more than 0.
    f_max_factor : int
        The largest FFT frequency is at least ``f_max*f_max_factor``.

    Returns
    -------
    int

    Raises
    ------
    ParameterError
        For ``f_resolution <= 0`` or ``f_max <= f_resolution`` (the MSL's asserts).
    """
    if not f_resolution > 0:
        raise ParameterError(f"f_resolution = {f_resolution!r}: f_resolution > 0 required",
                             hint="the frequency resolution of the FFT, e.g. 0.2 (Hz)")
    if not f_max > f_resolution:
        raise ParameterError(f"f_max = {f_max!r}, f_resolution = {f_resolution!r}: f_max > f_resolution required",
                             hint="the largest frequency of interest must exceed the resolution")
    if int(f_max_factor) < 1:
        raise ParameterError(f"f_max_factor = {f_max_factor!r} must be >= 1")
    # the same floating-point operations as the MSL, so that ns agrees with a Modelica tool's
    wanted = 2 * int(math.ceil(f_max * int(f_max_factor) / f_resolution))
    ns = wanted if wanted % 2 == 0 else wanted + 1
    while True:
        rest = ns
        for factor in (2, 3, 5):
            while rest % factor == 0:
                rest //= factor
        if rest <= 1:
            return ns
        ns += 2


def real_fft(u: Any, nfi: int) -> tuple[int, np.ndarray, np.ndarray]:
    """Amplitudes and phases of a real FFT (Modelica.Math.FastFourierTransform.realFFT).

    As the MSL computes them (``ModelicaFFT_kiss_fftr``): the FFT of ``u`` less
    its mean; amplitude ``i`` is ``|X[i]|/(nu/2 + 1)`` for ``nu = len(u)`` (so a
    sine of amplitude A at a frequency of the FFT shows as ``A*nu/(nu + 2)``),
    the phase is ``atan2(Im X[i], Re X[i])`` in degrees, with respect to a
    cosine; the first amplitude is the mean of ``u`` (phase 0), and the phases
    of amplitudes below ``1e-4`` times the largest are set to 0 (numerical noise).

    Parameters
    ----------
    u : sequence of float
        Equidistant samples; their number must be even.
    nfi : int
        Number of frequency points returned, ``1 <= nfi <= len(u)//2 + 1``.

    Returns
    -------
    info : int
        0: computed; 1: ``len(u)`` is odd (amplitudes and phases are then 0).
    amplitudes, phases : ndarray
        ``nfi`` values each; the phases in degrees.

    Raises
    ------
    ParameterError
        For ``nfi`` out of range (the MSL's assert).
    """
    u = np.asarray(u, dtype=float)
    nu = u.size
    if not 0 < nfi <= nu // 2 + 1:
        raise ParameterError(f"real_fft: nfi = {nfi} is out of range 1 ... {nu // 2 + 1}",
                             hint="nfi = max(1, min(ceil(f_max/f_resolution) + 1, len(u)//2 + 1))")
    if nu % 2 != 0:
        return 1, np.zeros(nfi), np.zeros(nfi)
    mean = float(np.sum(u)) / nu
    spectrum = np.fft.rfft(u - mean)[:nfi]
    amplitudes = np.abs(spectrum) / (nu // 2 + 1)  # the MSL's C code divides by nf, not nu/2
    phases = np.degrees(np.arctan2(spectrum.imag, spectrum.real))
    # the threshold before the mean replaces amplitude 1 (of u less its mean, about 0)
    noise = 0.0001 * float(np.max(amplitudes))
    amplitudes[0] = mean
    phases[0] = 0.0
    phases[1:][amplitudes[1:] < noise] = 0.0
    return 0, amplitudes, phases


def _ns(value) -> int:
    """The buffer size ``ns`` from the structural ``f_max`` and ``f_res`` (a shape read from the sizes)."""
    return real_fft_sample_points(value("f_max"), value("f_res"))


_ns.text = "ns"  # how show writes the buffer's size


class RealFFT(DiscreteBlock):
    """Sampling and FFT of input u (Modelica.Blocks.Math.RealFFT).

    The input is sampled every ``samplePeriod = 1/(2*f_res*div(ns, 2))`` from
    ``startTime`` on into the buffer ``buf[ns]``, ``ns =
    real_fft_sample_points(f_max, f_res, 5)``; the first ``ns`` samples are
    kept.  When the run has ended successfully, the FFT of the buffer
    (:func:`real_fft`: ``nf = max(1, min(ceil(f_max/f_res) + 1, div(ns, 2)))``
    amplitudes, and phases in degrees) is written to ``resultFileName`` as
    ``realFFTwriteToFile`` does (a MATLAB v4 MAT file holding the matrix
    ``FFT`` of ``3*nf`` rows ``[f, 0, 0; f, abs, arg; f, 0, 0]``, ``f =
    f_max*(i - 1)/(nf - 1)``, so that it plots as frequency lines).
    :meth:`spectrum` gives the same from a result in Python.

    A run too short to take ``ns`` samples (``stopTime < startTime + (ns -
    1)*samplePeriod``) fails at its end, as the MSL's assert at ``terminal()``
    does: the result has status -1 and an
    :class:`~acausal.errors.AssertionViolation` ("Sampling time not
    sufficient! stopTime>= ..."), and no file is written.

    Differences from the MSL: ``f_max``, ``f_res`` and ``resultFileName``
    are structural (they size the buffer; Modelica evaluates them too) and
    have defaults (those of Modelica.Math.FastFourierTransform.Examples.RealFFT1,
    the MSL has none); the FFT is computed after the run (the engine's
    :meth:`~acausal.language.Component.finished` hook) rather than in a
    ``when terminal()`` algorithm, so the protected ``abs`` and ``arg`` and the
    output ``info`` are not variables of the model: :meth:`spectrum` returns
    them.  The file is written whole or not at all; a failure to write it
    makes the run fail (a :class:`~acausal.errors.SimulationError`), as the
    MSL's writeRealMatrix raises an error; the MSL's message naming the file
    is not printed.  Only ``simulate(model)`` writes the file (a run of a
    translation, or of a sweep, has no component to call).
    """

    modelica_name = "Modelica.Blocks.Math.RealFFT"

    f_max = Parameter(4.0, unit="Hz", structural=True, description="Maximum frequency of interest")
    f_res = Parameter(0.2, unit="Hz", structural=True, description="Frequency resolution")
    resultFileName = Parameter("realFFT.mat", structural=True,  # noqa: N815 - Modelica's name
                               description="Result file: f, abs, arg")
    samplePeriod = Parameter(None, unit="s", structural=True,  # noqa: N815
                             description="Sample period of component (final: 1/(2*f_res*div(ns, 2)))")
    u = RealInput(description="Connector of Real input signal")
    buf = Variable(shape=_ns, start=0.0, fixed=True, discrete=True, description="Input buffer (protected)")
    iTick = Integer(start=0, fixed=True, description="Sample ticks (protected)")  # noqa: N815

    def __init__(self, **modifiers: Any) -> None:
        if "samplePeriod" in modifiers:
            raise ModifierError(f"{type(self).__name__}: samplePeriod is final, 1/(2*f_res*div(ns, 2))",
                                hint="give f_max and f_res; the sample period follows from them")
        declarations = type(self).declarations()
        f_max = modifiers.get("f_max", declarations["f_max"].default)
        f_res = modifiers.get("f_res", declarations["f_res"].default)
        ns = real_fft_sample_points(f_max, f_res)
        super().__init__(**modifiers, samplePeriod=1 / (2 * f_res * (ns // 2)))

    @property
    def ns(self) -> int:
        """Number of samples (the MSL's final parameter ``ns``)."""
        return real_fft_sample_points(self.f_max, self.f_res)

    @property
    def nf(self) -> int:
        """Number of frequency points (the MSL's final parameter ``nf``)."""
        return max(1, min(int(math.ceil(self.f_max / self.f_res)) + 1, self.ns // 2))

    def _column(self, name: str) -> str:
        return f"{self.path}.{name}" if self.path else name

    def _sampled_until(self, result) -> float:
        """``startTime + (ns - 1)*samplePeriod``: when the last sample is taken (startTime as the run had it)."""
        start = self._column("startTime")
        t_start = float(result.final(start)) if start in result else float(self.parameter_binding("startTime"))
        return t_start + (self.ns - 1) * self.samplePeriod

    def equations(self):
        ns = self.ns
        taken = [Eq(self.buf[i], If(sp.Eq(self.iTick, i), self.u, pre(self.buf[i]))) for i in range(1, ns + 1)]
        # the MSL's algorithm: iTick := pre(iTick) + 1; if iTick <= ns then buf[iTick] := u.  Its
        # assert at terminal() (enough samples) is checked by finished(), with the FFT.
        return [When(self.sampleTrigger, Eq(self.iTick, pre(self.iTick) + 1), *taken)]

    def spectrum(self, result) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The FFT of the samples a run of the model took: ``(f, abs, arg)``, ``nf`` values each.

        ``f = (i - 1)*f_res`` are the frequencies of the FFT (Hz; the file's
        ``f_max*(i - 1)/(nf - 1)`` are the same when ``f_max`` is a multiple
        of ``f_res``), ``abs`` the amplitudes (``abs[1]`` the mean of the
        samples), ``arg`` the phases in degrees (see :func:`real_fft`).

        Raises
        ------
        ValueError
            When the run took fewer than ``ns`` samples.
        KeyError
            When the result lacks the buffer (a run with ``outputs=`` that left it out).
        """
        ticks = int(result.final(self._column("iTick")))
        if ticks < self.ns:
            raise ValueError(f"{self.path or type(self).__name__}: {ticks} of {self.ns} samples taken; sampling "
                             f"time not sufficient! stopTime >= {self._sampled_until(result):.12g}")
        samples = np.asarray(result.final(self._column("buf")), dtype=float)
        info, amplitudes, phases = real_fft(samples, self.nf)
        if info != 0:  # pragma: no cover - ns is even by construction
            raise ValueError(f"{self.path}: Error in FFT (info = {info})")
        return np.arange(self.nf) * float(self.f_res), amplitudes, phases

    def fft_matrix(self, result) -> np.ndarray:
        """The matrix ``FFT`` realFFTwriteToFile writes: ``3*nf`` rows ``[f, 0, 0; f, abs, arg; f, 0, 0]``
        with ``f = f_max*(i - 1)/(nf - 1)``."""
        _, amplitudes, phases = self.spectrum(result)
        n = amplitudes.size
        f = float(self.f_max) * np.arange(n) / (n - 1) if n > 1 else np.full(n, np.nan)  # the MSL's 0/0
        matrix = np.zeros((3 * n, 3))
        matrix[:, 0] = np.repeat(f, 3)
        matrix[1::3, 1] = amplitudes
        matrix[1::3, 2] = phases
        return matrix

    def finished(self, result) -> None:
        """Write the FFT to ``resultFileName`` (MAT v4, the matrix ``FFT``) after a successful run."""
        import scipy.io  # only for a run that has a RealFFT

        ticks = int(result.final(self._column("iTick")))
        if ticks < self.ns:
            # the MSL's assert in its when terminal() clause: the run fails, no file is written
            raise AssertionViolation(f"{self.path or type(self).__name__}: Sampling time not sufficient! "
                                     f"stopTime>= {self._sampled_until(result):.12g}",
                                     hint=f"{ticks} of ns = {self.ns} samples were taken; simulate longer, or "
                                          f"raise f_res or lower f_max",
                                     components=(self.path,) if self.path else ())
        matrix = self.fft_matrix(result)
        path = Path(os.fspath(self.resultFileName))
        try:
            atomic_write(path, lambda handle: scipy.io.savemat(handle, {"FFT": matrix}, format="4"), mode="wb")
        except OSError as exc:
            raise SimulationError(f"{self.path or type(self).__name__}: the FFT could not be written to "
                                  f"{path}: {exc}", hint="give resultFileName a path in a folder that exists "
                                                         "and may be written", components=(self.path,)) from exc
