"""Lumped thermal elements (Modelica.Thermal.HeatTransfer.Components)."""

from __future__ import annotations

from acausal.language import Component, Eq, Parameter, RealInput, Variable, der
from acausal.components.thermal import Element1D, HeatPort_a, HeatPort_b

__all__ = ["HeatCapacitor", "ThermalConductor", "ThermalResistor", "Convection"]


class HeatCapacitor(Component):
    """Lumped thermal element storing heat (Modelica.Thermal.HeatTransfer.Components.HeatCapacitor).

    ``C*der(T) = port.Q_flow`` with ``T = port.T``; ``der_T`` is the time
    derivative of the temperature.  ``C`` has no default.
    """

    C = Parameter(None, unit="J/K", description="Heat capacity of element (= cp*m)")
    T = Variable(unit="K", start=293.15, description="Temperature of element")
    der_T = Variable(unit="K/s", start=0.0, description="Time derivative of temperature (= der(T))")
    port = HeatPort_a()

    def equations(self):
        return [
            Eq(self.T, self.port.T),
            Eq(self.der_T, der(self.T)),
            Eq(self.C * der(self.T), self.port.Q_flow),
        ]


class ThermalConductor(Element1D):
    """Lumped thermal element transporting heat without storing it (Modelica.Thermal.HeatTransfer.Components.ThermalConductor).

    ``Q_flow = G*dT``.
    """

    G = Parameter(None, unit="W/K", description="Constant thermal conductance of material")

    def equations(self):
        return [Eq(self.Q_flow, self.G * self.dT)]


class ThermalResistor(Element1D):
    """Lumped thermal element transporting heat without storing it (Modelica.Thermal.HeatTransfer.Components.ThermalResistor).

    ``dT = R*Q_flow``.
    """

    R = Parameter(None, unit="K/W", description="Constant thermal resistance of material")

    def equations(self):
        return [Eq(self.dT, self.R * self.Q_flow)]


class Convection(Component):
    """Lumped thermal element for heat convection (Modelica.Thermal.HeatTransfer.Components.Convection).

    ``Q_flow = Gc*dT`` from ``solid`` to ``fluid`` with ``dT = solid.T -
    fluid.T``; the convective thermal conductance ``Gc`` is an input.
    """

    Gc = RealInput(unit="W/K", description="Signal representing the convective thermal conductance")
    solid = HeatPort_a()
    fluid = HeatPort_b()
    Q_flow = Variable(unit="W", description="Heat flow rate from solid -> fluid")
    dT = Variable(unit="K", description="= solid.T - fluid.T")

    def equations(self):
        return [
            Eq(self.dT, self.solid.T - self.fluid.T),
            Eq(self.solid.Q_flow, self.Q_flow),
            Eq(self.fluid.Q_flow, -self.Q_flow),
            Eq(self.Q_flow, self.Gc * self.dT),
        ]
