"""Thermal sources (Modelica.Thermal.HeatTransfer.Sources)."""

from __future__ import annotations

from acausal.language import Component, Eq, Parameter, RealInput
from acausal.components.thermal import HeatPort_b

__all__ = ["FixedTemperature", "PrescribedTemperature", "FixedHeatFlow", "PrescribedHeatFlow"]


class FixedTemperature(Component):
    """Fixed temperature boundary condition in kelvin (Modelica.Thermal.HeatTransfer.Sources.FixedTemperature).

    ``port.T = T``.
    """

    modelica_name = "Modelica.Thermal.HeatTransfer.Sources.FixedTemperature"

    T = Parameter(None, unit="K", description="Fixed temperature at port")
    port = HeatPort_b()

    def equations(self):
        return [Eq(self.port.T, self.T)]


class PrescribedTemperature(Component):
    """Variable temperature boundary condition in kelvin (Modelica.Thermal.HeatTransfer.Sources.PrescribedTemperature).

    ``port.T = T`` (input).
    """

    modelica_name = "Modelica.Thermal.HeatTransfer.Sources.PrescribedTemperature"

    T = RealInput(unit="K")
    port = HeatPort_b()

    def equations(self):
        return [Eq(self.port.T, self.T)]


class FixedHeatFlow(Component):
    """Fixed heat flow boundary condition (Modelica.Thermal.HeatTransfer.Sources.FixedHeatFlow).

    ``port.Q_flow = -Q_flow*(1 + alpha*(port.T - T_ref))``: a positive
    ``Q_flow`` is injected into the connected component.
    """

    modelica_name = "Modelica.Thermal.HeatTransfer.Sources.FixedHeatFlow"

    Q_flow = Parameter(None, unit="W", description="Fixed heat flow rate at port")
    T_ref = Parameter(293.15, unit="K", description="Reference temperature")
    alpha = Parameter(0.0, unit="1/K", description="Temperature coefficient of heat flow rate")
    port = HeatPort_b()

    def equations(self):
        return [Eq(self.port.Q_flow, -self.Q_flow * (1 + self.alpha * (self.port.T - self.T_ref)))]


class PrescribedHeatFlow(Component):
    """Prescribed heat flow boundary condition (Modelica.Thermal.HeatTransfer.Sources.PrescribedHeatFlow).

    ``port.Q_flow = -Q_flow*(1 + alpha*(port.T - T_ref))`` with the input
    ``Q_flow``: a positive value is injected into the connected component.
    """

    modelica_name = "Modelica.Thermal.HeatTransfer.Sources.PrescribedHeatFlow"

    T_ref = Parameter(293.15, unit="K", description="Reference temperature")
    alpha = Parameter(0.0, unit="1/K", description="Temperature coefficient of heat flow rate")
    Q_flow = RealInput(unit="W")
    port = HeatPort_b()

    def equations(self):
        return [Eq(self.port.Q_flow, -self.Q_flow * (1 + self.alpha * (self.port.T - self.T_ref)))]
