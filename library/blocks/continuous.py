"""Continuous blocks (Modelica.Blocks.Continuous)."""

from __future__ import annotations

from acausal.language import Eq, Parameter, der
from acausal.components.blocks import SISO

__all__ = ["Integrator"]


class Integrator(SISO):
    """Output the integral of the input (Modelica.Blocks.Continuous.Integrator).

    ``der(y) = k*u`` with ``y(start=y_start, fixed=true)`` (MSL's default
    ``initType = InitialState``).  Integrating a power signal gives the work
    done, which is how energy audits are written inside a model.
    """

    k = Parameter(1.0, unit="1", description="Integrator gains")
    y_start = Parameter(0.0, description="Initial value of the output")

    def __init__(self, **modifiers) -> None:
        super().__init__(**modifiers)
        # y(start = y_start, fixed = true) unless the user modifies y itself
        attributes = self._attribute_modifiers.setdefault("y", {})
        attributes.setdefault("start", lambda block: block.y_start)
        attributes.setdefault("fixed", True)

    def equations(self):
        return [Eq(der(self.y), self.k * self.u)]
