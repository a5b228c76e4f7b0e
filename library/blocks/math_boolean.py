"""Boolean blocks with any number of inputs (Modelica.Blocks.MathBoolean).

The gates take a vector ``u[nu]`` (``And(nu=3)``): ``And`` is true where all
inputs are, ``Or`` where any is, ``Xor`` where exactly one is; ``Nand`` and
``Nor`` negate And and Or.  The MSL sizes ``u`` by connecting to it
(``connectorSizing``); acausal needs ``nu`` given.  The edge blocks and
:class:`MultiSwitch` hold their ``pre()`` values at initialization as the
MSL's initial equations say.  :class:`OnDelay` lives in
:mod:`acausal.library.blocks.logical` and is re-exported here.

Several names are those of Modelica.Blocks.Logical too (And, Or, Not,
FallingEdge ...), so these are imported from this module, not from
``acausal.library.blocks``: ``from acausal.library.blocks import math_boolean``
and ``math_boolean.And(nu=3)``.
"""

from __future__ import annotations

from typing import Any

import sympy as sp

from acausal.arrays import distribute
from acausal.components.blocks import BooleanInput, BooleanOutput
from acausal.components.logic import pre_boolean
from acausal.hybrid import change, edge
from acausal.language import Boolean, Component, Eq, Integer, Parameter

from .logical import OnDelay, _fix_pre

__all__ = ["PartialBooleanMISO", "PartialBooleanSISO_small", "MultiSwitch", "And", "Or", "Xor", "Nand", "Nor",
           "Not", "RisingEdge", "FallingEdge", "ChangingEdge", "OnDelay"]


class PartialBooleanMISO(Component):
    """Partial block with a BooleanVectorInput and a BooleanOutput signal
    (Modelica.Blocks.Interfaces.PartialBooleanMISO): ``u[nu]`` and ``y``."""

    modelica_name = "Modelica.Blocks.Interfaces.PartialBooleanMISO"

    nu = Parameter(0, structural=True, min=0, description="Number of input connections")
    u = BooleanInput(shape="nu", description="Vector of Boolean input signals")
    y = BooleanOutput(description="Boolean output signal")


class PartialBooleanSISO_small(Component):  # noqa: N801 - Modelica's name
    """Partial block with a BooleanInput and a BooleanOutput signal and a small block icon
    (Modelica.Blocks.Interfaces.PartialBooleanSISO_small): ``u`` and ``y``."""

    modelica_name = "Modelica.Blocks.Interfaces.PartialBooleanSISO_small"

    u = BooleanInput(description="Boolean input signal")
    y = BooleanOutput(description="Boolean output signal")


def _all(u: Any) -> sp.Basic:
    """Modelica.Math.BooleanVectors.andTrue: every element true (true for no element)."""
    return sp.And(*u)


def _any(u: Any) -> sp.Basic:
    """Modelica.Math.BooleanVectors.anyTrue: some element true (false for no element)."""
    return sp.Or(*u)


def _exactly_one(u: Any) -> sp.Basic:
    """Modelica.Math.BooleanVectors.oneTrue: exactly one element true."""
    elements = list(u)
    return sp.Or(*(sp.And(element, *(sp.Not(other) for other in elements if other is not element))
                   for element in elements))


class And(PartialBooleanMISO):
    """Logical 'and': y = u[1] and u[2] and ... and u[nu] (Modelica.Blocks.MathBoolean.And)."""

    modelica_name = "Modelica.Blocks.MathBoolean.And"

    def equations(self):
        return [Eq(self.y, _all(self.u))]


class Or(PartialBooleanMISO):
    """Logical 'or': y = u[1] or u[2] or ... or u[nu] (Modelica.Blocks.MathBoolean.Or)."""

    modelica_name = "Modelica.Blocks.MathBoolean.Or"

    def equations(self):
        return [Eq(self.y, _any(self.u))]


class Xor(PartialBooleanMISO):
    """Logical 'xor': y = oneTrue(u), true if exactly one element of u is true
    (Modelica.Blocks.MathBoolean.Xor)."""

    modelica_name = "Modelica.Blocks.MathBoolean.Xor"

    def equations(self):
        return [Eq(self.y, _exactly_one(self.u))]


class Nand(PartialBooleanMISO):
    """Logical 'nand': y = not ( u[1] and u[2] and ... and u[nu] ) (Modelica.Blocks.MathBoolean.Nand)."""

    modelica_name = "Modelica.Blocks.MathBoolean.Nand"

    def equations(self):
        return [Eq(self.y, sp.Not(_all(self.u)))]


class Nor(PartialBooleanMISO):
    """Logical 'nor': y = not ( u[1] or u[2] or ... or u[nu] ) (Modelica.Blocks.MathBoolean.Nor)."""

    modelica_name = "Modelica.Blocks.MathBoolean.Nor"

    def equations(self):
        return [Eq(self.y, sp.Not(_any(self.u)))]


class Not(PartialBooleanSISO_small):
    """Logical 'not': y = not u (Modelica.Blocks.MathBoolean.Not)."""

    modelica_name = "Modelica.Blocks.MathBoolean.Not"

    def equations(self):
        return [Eq(self.y, sp.Not(self.u))]


class _EdgeBlock(PartialBooleanSISO_small):
    """``pre_u_start``, the value of ``pre(u)`` at initialization."""

    pre_u_start = Parameter(False, structural=True, description="Value of pre(u) at initial time")

    def __init__(self, **modifiers: Any) -> None:
        super().__init__(**modifiers)
        _fix_pre(self, "u", lambda block: bool(block.pre_u_start))


class RisingEdge(_EdgeBlock):
    """Output y is true, if the input u has a rising edge, otherwise it is false (y = edge(u))
    (Modelica.Blocks.MathBoolean.RisingEdge)."""

    modelica_name = "Modelica.Blocks.MathBoolean.RisingEdge"

    def equations(self):
        return [Eq(self.y, edge(self.u))]


class FallingEdge(_EdgeBlock):
    """Output y is true, if the input u has a falling edge, otherwise it is false (y = edge(not u))
    (Modelica.Blocks.MathBoolean.FallingEdge)."""

    modelica_name = "Modelica.Blocks.MathBoolean.FallingEdge"

    not_u = Boolean(description="not u (protected)")

    def __init__(self, **modifiers: Any) -> None:
        super().__init__(**modifiers)
        _fix_pre(self, "not_u", lambda block: not block.pre_u_start)

    def equations(self):
        return [Eq(self.not_u, sp.Not(self.u)), Eq(self.y, edge(self.not_u))]


class ChangingEdge(_EdgeBlock):
    """Output y is true, if the input u has either a rising or a falling edge and otherwise it is
    false (y=change(u)) (Modelica.Blocks.MathBoolean.ChangingEdge)."""

    modelica_name = "Modelica.Blocks.MathBoolean.ChangingEdge"

    def equations(self):
        return [Eq(self.y, change(self.u))]


class MultiSwitch(Component):
    """Set Boolean expression that is associated with the first active input signal
    (Modelica.Blocks.MathBoolean.MultiSwitch).

    ``y = expr[i]`` for the first ``i`` with ``u[i]`` true; if none is,
    ``y`` keeps its last value (``pre(y)``, ``y_default`` at initialization)
    or, with ``use_pre_as_default=False``, is ``y_default``.  The MSL's
    ``expr`` is a vector of time-varying Boolean inputs bound by a modifier;
    here it is a list of ``nu`` values, each ``True``/``False`` or a Boolean
    expression of the model's signals, structural because it is part of the
    equations.  ``firstActiveIndex`` is that ``i`` (0 if no input is true).
    """

    modelica_name = "Modelica.Blocks.MathBoolean.MultiSwitch"

    expr = Parameter(False, structural=True,
                     description="Sets y = if u[i] then expr[i] else y_default (time varying); one per input")
    use_pre_as_default = Parameter(True, structural=True,
                                   description="Set true to hold last value as default (y_default = pre(y))")
    y_default = Parameter(False, structural=True, description="Default value of output y if all u[i] = false")
    nu = Parameter(0, structural=True, min=0, description="Number of input connections")
    u = BooleanInput(shape="nu", description="Set y = expr[i], if u[i] = true")
    y = BooleanOutput(description="Output depending on expression")
    firstActiveIndex = Integer(description="Index of the first true input, 0 if none is")  # noqa: N815

    def __init__(self, **modifiers: Any) -> None:
        super().__init__(**modifiers)
        _fix_pre(self, "y", lambda block: bool(block.y_default))  # initial equation pre(y) = y_default

    def equations(self):
        expressions = distribute(self.expr, (self.nu,), f"{self.path or type(self).__name__}.expr")
        chosen = pre_boolean(self.y) if self.use_pre_as_default else sp.sympify(bool(self.y_default))
        # from the last input to the first, so that the first true input decides
        for value, active in reversed(list(zip(expressions, self.u))):
            chosen = sp.Or(sp.And(active, sp.sympify(value)), sp.And(sp.Not(active), chosen))
        first = [(sp.Integer(i), active) for i, active in enumerate(self.u, start=1)]
        return [Eq(self.firstActiveIndex, sp.Piecewise(*first, (sp.Integer(0), True))),
                Eq(self.y, chosen)]
