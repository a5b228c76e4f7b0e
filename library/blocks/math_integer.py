"""Integer blocks (Modelica.Blocks.MathInteger).

:class:`Sum` and :class:`Product` take a vector ``u[nu]`` (the MSL sizes it
by connecting to it, ``connectorSizing``; acausal needs ``nu`` given),
:class:`MultiSwitch` picks the expression of the first true Boolean input,
:class:`TriggeredAdd` adds its input to its output at each rising edge of
``trigger``.  Sum, Product and MultiSwitch share their names with blocks of
Modelica.Blocks.Math, so import them from this module (``from
acausal.library.blocks import math_integer``, ``math_integer.Sum(nu=3)``).
"""

from __future__ import annotations

from typing import Any

import sympy as sp

from acausal.arrays import distribute
from acausal.arrays import product as array_product
from acausal.arrays import sum as array_sum
from acausal.components.blocks import BooleanInput, IntegerInput, IntegerOutput
from acausal.hybrid import When
from acausal.language import Component, Eq, Integer, Parameter, pre

from .logical import _fix_pre
from .math import _with_declared_value

__all__ = ["PartialIntegerMISO", "PartialIntegerSISO", "MultiSwitch", "Sum", "Product", "TriggeredAdd"]


class PartialIntegerMISO(Component):
    """Partial block with an IntegerVectorInput and an IntegerOutput signal
    (Modelica.Blocks.Interfaces.PartialIntegerMISO): ``u[nu]`` and ``y``."""

    modelica_name = "Modelica.Blocks.Interfaces.PartialIntegerMISO"

    nu = Parameter(0, structural=True, min=0, description="Number of input connections")
    u = IntegerInput(shape="nu", description="Vector of Integer input signals")
    y = IntegerOutput(description="Integer output signal")


class PartialIntegerSISO(Component):
    """Partial block with an IntegerInput and an IntegerOutput signal
    (Modelica.Blocks.Interfaces.PartialIntegerSISO): ``u`` and ``y``."""

    modelica_name = "Modelica.Blocks.Interfaces.PartialIntegerSISO"

    u = IntegerInput(description="Integer input signal")
    y = IntegerOutput(description="Integer output signal")


class Sum(PartialIntegerMISO):
    """Sum of Integers: y = k[1]*u[1] + k[2]*u[2] + ... + k[n]*u[n] (Modelica.Blocks.MathInteger.Sum).

    ``y = 0`` for ``nu = 0``.
    """

    modelica_name = "Modelica.Blocks.MathInteger.Sum"

    k = Parameter(1, shape="nu", description="Input gains")

    def __init__(self, **modifiers: Any) -> None:
        super().__init__(**_with_declared_value(type(self), modifiers, "k"))

    def equations(self):
        return [Eq(self.y, array_sum(self.k * self.u) if self.nu > 0 else sp.Integer(0))]


class Product(PartialIntegerMISO):
    """Product of Integer: y = u[1]*u[2]* ... *u[n] (Modelica.Blocks.MathInteger.Product).

    ``y = 0`` for ``nu = 0`` (as in the MSL, not the empty product 1).
    """

    modelica_name = "Modelica.Blocks.MathInteger.Product"

    def equations(self):
        return [Eq(self.y, array_product(self.u) if self.nu > 0 else sp.Integer(0))]


class MultiSwitch(Component):
    """Set Integer expression that is associated with the first active input signal
    (Modelica.Blocks.MathInteger.MultiSwitch).

    ``y = expr[i]`` for the first ``i`` with ``u[i]`` true; if none is,
    ``y`` keeps its last value (``pre(y)``, ``y_default`` at
    initialization) or, with ``use_pre_as_default=False``, is ``y_default``.
    The MSL's ``expr`` is a vector of time-varying Integer inputs bound by a
    modifier; here it is a list of ``nu`` values, each an integer or an
    Integer expression of the model's signals, structural because it is part
    of the equations.  ``firstActiveIndex`` is that ``i`` (0 if none).
    """

    modelica_name = "Modelica.Blocks.MathInteger.MultiSwitch"

    expr = Parameter(0, structural=True,
                     description="y = if u[i] then expr[i] elseif use_pre_as_default then pre(y) else y_default "
                                 "(time varying); one per input")
    y_default = Parameter(0, structural=True,
                          description="Default value of output y if use_pre_as_default=false, as well as pre(y) "
                                      "at initial time")
    use_pre_as_default = Parameter(True, structural=True,
                                   description="= true, y holds its last value if all u[i]=false, otherwise "
                                               "y=y_default")
    nu = Parameter(0, structural=True, min=0, description="Number of input connections")
    u = BooleanInput(shape="nu", description="Set y = expr[i], if u[i] = true")
    y = IntegerOutput(description="Output depending on expression")
    firstActiveIndex = Integer(description="Index of the first true input, 0 if none is")  # noqa: N815

    def __init__(self, **modifiers: Any) -> None:
        super().__init__(**modifiers)
        _fix_pre(self, "y", lambda block: int(block.y_default))  # initial equation pre(y) = y_default

    def equations(self):
        expressions = distribute(self.expr, (self.nu,), f"{self.path or type(self).__name__}.expr")
        default = pre(self.y) if self.use_pre_as_default else sp.Integer(int(self.y_default))
        chosen = [(sp.sympify(value), active) for value, active in zip(expressions, self.u)]
        first = [(sp.Integer(i), active) for i, active in enumerate(self.u, start=1)]
        return [Eq(self.firstActiveIndex, sp.Piecewise(*first, (sp.Integer(0), True))),
                Eq(self.y, sp.Piecewise(*chosen, (default, True)))]


class TriggeredAdd(PartialIntegerSISO):
    """Add input to previous value of output, if rising edge of trigger port
    (Modelica.Blocks.MathInteger.TriggeredAdd).

    At every rising edge of ``trigger``, ``y = pre(y) + u``.  With
    ``use_reset``, a rising edge of ``reset`` sets ``y`` to ``set`` (with
    ``use_set``) or to ``y_start``, and wins over a trigger at the same
    instant.  ``y`` starts at ``y_start``.
    """

    modelica_name = "Modelica.Blocks.MathInteger.TriggeredAdd"

    use_reset = Parameter(False, structural=True, description="= true, if reset port enabled")
    use_set = Parameter(False, structural=True,
                        description="= true, if set port enabled and used as default value when reset")
    y_start = Parameter(0, structural=True, description="Initial and reset value of y if set port is not used")
    trigger = BooleanInput(description="Rising edge of trigger adds u to y")
    reset = BooleanInput(condition="use_reset", description="Rising edge of reset sets y to set or y_start")
    set = IntegerInput(condition="use_set", description="Value of y at a reset (if use_reset)")

    def __init__(self, **modifiers: Any) -> None:
        super().__init__(**modifiers)
        _fix_pre(self, "y", lambda block: int(block.y_start))  # initial equation pre(y) = y_start

    def equations(self):
        if not self.use_reset:  # the MSL's local_reset = false: only the trigger counts
            return [When(self.trigger, Eq(self.y, pre(self.y) + self.u))]
        value = self.set if self.use_set else sp.Integer(int(self.y_start))
        return [When([self.trigger, self.reset],
                     Eq(self.y, sp.Piecewise((value, self.reset), (pre(self.y) + self.u, True))))]
