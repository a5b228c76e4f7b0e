"""Value displays (Modelica.Blocks.Interaction.Show): their outputs, without the graphics.

A Modelica tool shows the value of ``RealValue``, ``IntegerValue`` and
``BooleanValue`` in the diagram as the simulation runs; acausal has no
diagram, so each is the signal it would show, as its output (``showNumber``,
``showActive``): from the input port by default, or, with
``use_numberPort=False`` (``use_activePort=False``), from ``number``
(``active``), an expression of the model's signals given where the block is
made (``RealValue(use_numberPort=False, number=self.gain.y)``).
"""

from __future__ import annotations

import sympy as sp

from acausal.components.blocks import BooleanInput, BooleanOutput, IntegerInput, IntegerOutput
from acausal.language import Component, Eq, Parameter, RealInput, RealOutput

__all__ = ["RealValue", "IntegerValue", "BooleanValue"]


class RealValue(Component):
    """Show Real value from numberPort or from number input field in diagram layer dynamically
    (Modelica.Blocks.Interaction.Show.RealValue): ``showNumber``, the value shown."""

    modelica_name = "Modelica.Blocks.Interaction.Show.RealValue"

    use_numberPort = Parameter(True, structural=True, description="= true, if numberPort enabled")  # noqa: N815
    number = Parameter(0.0, structural=True,
                       description="Number to visualize if use_numberPort=false (time varying)")
    significantDigits = Parameter(2, structural=True, min=1,  # noqa: N815
                                  description="Number of significant digits to be shown")
    numberPort = RealInput(condition="use_numberPort",  # noqa: N815
                           description="Number to be shown in diagram layer if use_numberPort = true")
    showNumber = RealOutput(description="The value shown")  # noqa: N815

    def equations(self):
        return [Eq(self.showNumber, self.numberPort if self.use_numberPort else sp.sympify(self.number))]


class IntegerValue(Component):
    """Show Integer value from numberPort or from number input field in diagram layer dynamically
    (Modelica.Blocks.Interaction.Show.IntegerValue): ``showNumber``, the value shown."""

    modelica_name = "Modelica.Blocks.Interaction.Show.IntegerValue"

    use_numberPort = Parameter(True, structural=True, description="= true, if numberPort enabled")  # noqa: N815
    number = Parameter(0, structural=True,
                       description="Number to visualize if use_numberPort=false (time varying)")
    numberPort = IntegerInput(condition="use_numberPort",  # noqa: N815
                              description="Number to be shown in diagram layer if use_numberPort = true")
    showNumber = IntegerOutput(description="The value shown")  # noqa: N815

    def equations(self):
        return [Eq(self.showNumber, self.numberPort if self.use_numberPort else sp.sympify(self.number))]


class BooleanValue(Component):
    """Show Boolean value from numberPort or from number input field in diagram layer dynamically
    (Modelica.Blocks.Interaction.Show.BooleanValue): ``showActive``, the value shown."""

    modelica_name = "Modelica.Blocks.Interaction.Show.BooleanValue"

    use_activePort = Parameter(True, structural=True, description="= true, if activePort enabled")  # noqa: N815
    active = Parameter(False, structural=True,
                       description="Boolean variable to visualize if use_activePort=false (time varying)")
    activePort = BooleanInput(condition="use_activePort",  # noqa: N815
                              description="Boolean variable to be shown in diagram layer if use_activePort = true")
    showActive = BooleanOutput(description="The value shown")  # noqa: N815

    def equations(self):
        return [Eq(self.showActive, self.activePort if self.use_activePort else sp.sympify(self.active))]
