"""Discontinuous or non-differentiable algebraic control blocks (Modelica.Blocks.Nonlinear).

Without ``strict`` the switching of a limiter is a state event (the relation
``u > uMax`` is watched and its crossing located); with ``strict = True`` it
is evaluated literally (``noEvent``), as Modelica's ``strict`` option says.
Modelica's ``homotopy(actual, simplified)`` is the actual expression here:
the engine has no homotopy-based initialization, so ``homotopyType`` is
accepted for compatibility and has no effect.
"""

from __future__ import annotations

import enum

import sympy as sp

from acausal.components.blocks import SISO
from acausal.components.declarations import DerivedDefaults
from acausal.hybrid import Assert, noEvent
from acausal.language import Eq, Parameter, RealInput, Variable, der

from .continuous import Init, _init_type
from .discrete import SMALL

__all__ = ["LimiterHomotopy", "VariableLimiterHomotopy", "Limiter", "VariableLimiter", "DeadZone",
           "SlewRateLimiter"]


class LimiterHomotopy(enum.IntEnum):
    """Homotopy type of Limiter (Modelica.Blocks.Types.LimiterHomotopy); no effect here."""

    NoHomotopy = 1
    Linear = 2
    UpperLimit = 3
    LowerLimit = 4


# set after the body: in an IntEnum's body a str would become a member
LimiterHomotopy.modelica_name = "Modelica.Blocks.Types.LimiterHomotopy"


class VariableLimiterHomotopy(enum.IntEnum):
    """Homotopy type of VariableLimiter (Modelica.Blocks.Types.VariableLimiterHomotopy); no effect here."""

    NoHomotopy = 1
    Linear = 2
    Fixed = 3


# set after the body: in an IntEnum's body a str would become a member
VariableLimiterHomotopy.modelica_name = "Modelica.Blocks.Types.VariableLimiterHomotopy"


def _literal(expr, strict: bool):
    """``expr`` under noEvent if ``strict`` (no events), else as is (state events)."""
    return noEvent(expr) if strict else expr


class Limiter(DerivedDefaults, SISO):
    """Limit the range of a signal (Modelica.Blocks.Nonlinear.Limiter).

    ``y = uMax`` if ``u > uMax``, ``uMin`` if ``u < uMin``, else ``u``.
    """

    modelica_name = "Modelica.Blocks.Nonlinear.Limiter"

    uMax = Parameter(1.0, description="Upper limits of input signals")  # noqa: N815
    uMin = Parameter(None, description="Lower limits of input signals (default -uMax)")  # noqa: N815
    strict = Parameter(False, structural=True, description="= true, if strict limits with noEvent(..)")
    homotopyType = Parameter(LimiterHomotopy.Linear, structural=True,  # noqa: N815
                             description="Simplified model for homotopy-based initialization (no effect here)")

    derived_defaults = {"uMin": lambda block: -block.uMax}

    def equations(self):
        limited = sp.Piecewise((self.uMax, self.u > self.uMax), (self.uMin, self.u < self.uMin),
                               (self.u, True))
        return [Assert(self.uMax >= self.uMin, "Limiter: Limits must be consistent. However, uMax < uMin"),
                Eq(self.y, _literal(limited, self.strict))]


class VariableLimiter(SISO):
    """Limit the range of a signal with variable limits (Modelica.Blocks.Nonlinear.VariableLimiter).

    ``y = limit1`` if ``u > limit1``, ``limit2`` if ``u < limit2``, else
    ``u``; the limits are inputs (``limit1 >= limit2`` is asserted).
    """

    modelica_name = "Modelica.Blocks.Nonlinear.VariableLimiter"

    strict = Parameter(False, structural=True, description="= true, if strict limits with noEvent(..)")
    homotopyType = Parameter(VariableLimiterHomotopy.Linear, structural=True,  # noqa: N815
                             description="Simplified model for homotopy-based initialization (no effect here)")
    ySimplified = Parameter(0.0, description="Fixed value of output in simplified model (no effect here)")  # noqa: N815
    limit1 = RealInput(description="Connector of Real input signal used as maximum of input u")
    limit2 = RealInput(description="Connector of Real input signal used as minimum of input u")

    def equations(self):
        limited = sp.Piecewise((self.limit1, self.u > self.limit1), (self.limit2, self.u < self.limit2),
                               (self.u, True))
        return [Assert(self.limit1 >= self.limit2, "Input signals are not consistent: limit1 < limit2"),
                Eq(self.y, _literal(limited, self.strict))]


class DeadZone(DerivedDefaults, SISO):
    """Provide a region of zero output (Modelica.Blocks.Nonlinear.DeadZone).

    ``y = u - uMax`` if ``u > uMax``, ``u - uMin`` if ``u < uMin``, else 0.
    """

    modelica_name = "Modelica.Blocks.Nonlinear.DeadZone"

    uMax = Parameter(1.0, description="Upper limits of dead zones")  # noqa: N815
    uMin = Parameter(None, description="Lower limits of dead zones (default -uMax)")  # noqa: N815

    derived_defaults = {"uMin": lambda block: -block.uMax}

    def equations(self):
        return [Assert(self.uMax >= self.uMin, "DeadZone: Limits must be consistent. However, uMax < uMin"),
                Eq(self.y, sp.Piecewise((self.u - self.uMax, self.u > self.uMax),
                                        (self.u - self.uMin, self.u < self.uMin), (0, True)))]


class SlewRateLimiter(DerivedDefaults, SISO):
    """Limit the slew rate of a signal (Modelica.Blocks.Nonlinear.SlewRateLimiter).

    ``der(y) = (u - y)/Td`` clipped to ``[Falling, Rising]``: ``y`` follows
    ``u`` with the time constant ``Td`` but never faster than the rates.  By
    default (``initType = SteadyState``) ``y = u`` at the start.
    """

    modelica_name = "Modelica.Blocks.Nonlinear.SlewRateLimiter"

    Rising = Parameter(1.0, min=SMALL, description="Maximum rising slew rate [+small..+inf) [1/s]")
    Falling = Parameter(None, max=-SMALL, description="Maximum falling slew rate (-inf..-small] [1/s] "
                                                      "(default -Rising)")
    Td = Parameter(0.001, unit="s", min=SMALL, description="Derivative time constant")
    initType = Parameter(Init.SteadyState, structural=True,  # noqa: N815
                         description="Type of initialization (SteadyState implies y = u)")
    y_start = Parameter(0.0, description="Initial or guess value of output (= state)")
    strict = Parameter(False, structural=True, description="= true, if strict limits with noEvent(..)")
    val = Variable(description="(u - y)/Td (protected)")

    derived_defaults = {"Falling": lambda block: -block.Rising}

    def __init__(self, **modifiers) -> None:
        super().__init__(**modifiers)
        self._attribute_modifiers.setdefault("y", {}).setdefault("start", lambda block: block.y_start)

    def equations(self):
        rate = _literal(sp.Piecewise((self.Falling, self.val < self.Falling),
                                     (self.Rising, self.val > self.Rising), (self.val, True)), self.strict)
        return [Eq(self.val, (self.u - self.y) / self.Td), Eq(der(self.y), rate)]

    def initial_equations(self):
        init = _init_type(self.initType)
        if init is Init.SteadyState:
            return [Eq(self.y, self.u)]
        if init in (Init.InitialState, Init.InitialOutput):
            return [Eq(self.y, self.y_start)]
        return []
