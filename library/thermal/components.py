"""Lumped thermal elements (Modelica.Thermal.HeatTransfer.Components)."""

from __future__ import annotations

from acausal.errors import ParameterError
from acausal.language import Component, Eq, Parameter, RealInput, RealOutput, Variable, der
from acausal.components.adaptors import FlowToPotentialAdaptor, PotentialToFlowAdaptor
from acausal.components.thermal import Element1D, HeatPort_a, HeatPort_b

__all__ = ["HeatCapacitor", "ThermalConductor", "ThermalResistor", "Convection",
           "GeneralHeatFlowToTemperatureAdaptor", "GeneralTemperatureToHeatFlowAdaptor"]


class HeatCapacitor(Component):
    """Lumped thermal element storing heat (Modelica.Thermal.HeatTransfer.Components.HeatCapacitor).

    ``C*der(T) = port.Q_flow`` with ``T = port.T``; ``der_T`` is the time
    derivative of the temperature.  ``C`` has no default.
    """

    modelica_name = "Modelica.Thermal.HeatTransfer.Components.HeatCapacitor"

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

    modelica_name = "Modelica.Thermal.HeatTransfer.Components.ThermalConductor"

    G = Parameter(None, unit="W/K", description="Constant thermal conductance of material")

    def equations(self):
        return [Eq(self.Q_flow, self.G * self.dT)]


class ThermalResistor(Element1D):
    """Lumped thermal element transporting heat without storing it (Modelica.Thermal.HeatTransfer.Components.ThermalResistor).

    ``dT = R*Q_flow``.
    """

    modelica_name = "Modelica.Thermal.HeatTransfer.Components.ThermalResistor"

    R = Parameter(None, unit="K/W", description="Constant thermal resistance of material")

    def equations(self):
        return [Eq(self.dT, self.R * self.Q_flow)]


class Convection(Component):
    """Lumped thermal element for heat convection (Modelica.Thermal.HeatTransfer.Components.Convection).

    ``Q_flow = Gc*dT`` from ``solid`` to ``fluid`` with ``dT = solid.T -
    fluid.T``; the convective thermal conductance ``Gc`` is an input.
    """

    modelica_name = "Modelica.Thermal.HeatTransfer.Components.Convection"

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


def _no_second_derivative(adaptor: Component) -> None:
    """The thermal adaptors fix use_pder2 = false (final in the MSL)."""
    if adaptor.use_pder2:
        where = adaptor.path or type(adaptor).__name__
        raise ParameterError(f"{where}.use_pder2 is final false in the thermal adaptors",
                             hint="the second derivative of the temperature is not an interface signal here")


class GeneralHeatFlowToTemperatureAdaptor(FlowToPotentialAdaptor):
    """Signal adaptor for a HeatTransfer port with temperature and derivative of temperature as outputs and heat flow as input (Modelica.Thermal.HeatTransfer.Components.GeneralHeatFlowToTemperatureAdaptor).

    For wrapping a thermal model as an input/output block (e.g. an FMU):
    the heat flow input ``f`` enters the model through ``heatPort``
    (``heatPort.Q_flow = f``), and the port's temperature ``p = heatPort.T``
    and its derivative ``pder = der(p)`` (if ``use_pder``) are outputs.
    Modelica.Blocks.Interfaces.Adaptors.FlowToPotentialAdaptor
    (:class:`acausal.components.adaptors.FlowToPotentialAdaptor`) with the
    MSL's final settings ``use_pder2 = use_fder = use_fder2 = false``.
    """

    modelica_name = "Modelica.Thermal.HeatTransfer.Components.GeneralHeatFlowToTemperatureAdaptor"

    use_pder2 = Parameter(False, structural=True,
                          description="Use output for 2nd derivative of potential (final false)")
    p = RealOutput(unit="K", description="Output for potential (temperature)")
    pder = RealOutput(unit="K/s", condition="use_pder", description="Optional output for der(potential)")
    f = RealInput(unit="W", description="Input for flow (heat flow)")
    heatPort = HeatPort_a(description="Heat port whose temperature is output and whose heat flow is input")  # noqa: N815

    def build(self) -> None:
        _no_second_derivative(self)

    def equations(self):
        return [Eq(self.y, self.heatPort.T),        # output = potential = temperature
                Eq(self.u, self.heatPort.Q_flow)]   # input = flow = heat flow


class GeneralTemperatureToHeatFlowAdaptor(PotentialToFlowAdaptor):
    """Signal adaptor for a HeatTransfer port with heat flow as output and temperature and derivative of temperature as input (Modelica.Thermal.HeatTransfer.Components.GeneralTemperatureToHeatFlowAdaptor).

    For wrapping a thermal model as an input/output block (e.g. an FMU):
    the port follows the temperature input (``heatPort.T = p``) and the heat
    flow it takes is the output ``f = -heatPort.Q_flow``.  The optional input
    ``pder`` (if ``use_pder``) must be ``der(p)``; it replaces the
    derivative of ``p`` where the model needs it (a heat capacitor on the
    port does), so ``p`` itself is never differentiated
    (:func:`acausal.prescribed`, the MSL's ``state1``).
    Modelica.Blocks.Interfaces.Adaptors.PotentialToFlowAdaptor
    (:class:`acausal.components.adaptors.PotentialToFlowAdaptor`) with the
    MSL's final settings ``use_pder2 = use_fder = use_fder2 = false``.
    """

    modelica_name = "Modelica.Thermal.HeatTransfer.Components.GeneralTemperatureToHeatFlowAdaptor"

    pder_hint = "enable use_pder and connect der(T) to pder"
    use_pder2 = Parameter(False, structural=True,
                          description="Use input for 2nd derivative of potential (final false)")
    p = RealInput(unit="K", description="Input for potential (temperature)")
    pder = RealInput(unit="K/s", condition="use_pder", description="Optional input for der(potential)")
    f = RealOutput(unit="W", description="Output for flow (heat flow)")
    heatPort = HeatPort_b(description="Heat port that follows the temperature input")  # noqa: N815

    def build(self) -> None:
        _no_second_derivative(self)

    def equations(self):
        return [Eq(self.y, self.heatPort.Q_flow),   # output = flow = heat flow
                Eq(self.u, self.heatPort.T)]        # input = potential = temperature
