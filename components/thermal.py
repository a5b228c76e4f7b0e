"""Heat-transfer connectors and partial models (Modelica.Thermal.HeatTransfer.Interfaces)."""

from __future__ import annotations

from acausal.language import Component, Connector, Eq, Flow, Parameter, Potential, Variable

__all__ = [
    "HeatPort",
    "HeatPort_a",
    "HeatPort_b",
    "Element1D",
    "PartialElementaryConditionalHeatPortWithoutT",
    "PartialElementaryConditionalHeatPort",
]


class HeatPort(Connector):
    """Thermal port (Modelica.Thermal.HeatTransfer.Interfaces.HeatPort).

    A potential ``T`` (port temperature, K) and a flow ``Q_flow`` (heat flow
    rate, W; positive when heat flows into the component).
    """

    modelica_name = "Modelica.Thermal.HeatTransfer.Interfaces.HeatPort"

    family = "thermal"
    T = Potential(unit="K", start=293.15, description="Port temperature")
    Q_flow = Flow(unit="W",
                  description="Heat flow rate (positive if flowing from outside into the component)")


class HeatPort_a(HeatPort):  # noqa: N801 - Modelica name
    """Thermal port (Modelica.Thermal.HeatTransfer.Interfaces.HeatPort_a, filled icon), identical to HeatPort."""

    modelica_name = "Modelica.Thermal.HeatTransfer.Interfaces.HeatPort_a"


class HeatPort_b(HeatPort):  # noqa: N801 - Modelica name
    """Thermal port (Modelica.Thermal.HeatTransfer.Interfaces.HeatPort_b, open icon), identical to HeatPort."""

    modelica_name = "Modelica.Thermal.HeatTransfer.Interfaces.HeatPort_b"


class Element1D(Component):
    """Lumped element between two ports (Modelica.Thermal.HeatTransfer.Interfaces.Element1D).

    ``dT = port_a.T - port_b.T`` and the heat flow ``Q_flow`` from port_a to
    port_b (``port_a.Q_flow = Q_flow``, ``port_b.Q_flow = -Q_flow``).
    """

    modelica_name = "Modelica.Thermal.HeatTransfer.Interfaces.Element1D"

    port_a = HeatPort_a()
    port_b = HeatPort_b()
    Q_flow = Variable(unit="W", description="Heat flow rate from port_a -> port_b")
    dT = Variable(unit="K", description="port_a.T - port_b.T")

    def equations(self):
        return [
            Eq(self.dT, self.port_a.T - self.port_b.T),
            Eq(self.port_a.Q_flow, self.Q_flow),
            Eq(self.port_b.Q_flow, -self.Q_flow),
        ]


class PartialElementaryConditionalHeatPortWithoutT(Component):
    """Optional heat port for losses (Modelica.Thermal.HeatTransfer.Interfaces.PartialElementaryConditionalHeatPortWithoutT).

    The component defines ``lossPower`` (W, positive when heat leaves it).
    With ``useHeatPort`` the conditional ``heatPort`` exists and carries
    ``heatPort.Q_flow = -lossPower``; its temperature is not used.
    """

    modelica_name = "Modelica.Thermal.HeatTransfer.Interfaces.PartialElementaryConditionalHeatPortWithoutT"

    useHeatPort = Parameter(False, structural=True,  # noqa: N815 - Modelica name
                            description="= true, if heatPort is enabled")
    heatPort = HeatPort_a(condition="useHeatPort",  # noqa: N815 - Modelica name
                          description="Optional port to which dissipated losses are transported")
    lossPower = Variable(unit="W",
                         description="Loss power leaving component via heatPort (> 0, if heat is flowing out of component)")  # noqa: N815

    def equations(self):
        if self.useHeatPort:
            return [Eq(self.heatPort.Q_flow, -self.lossPower)]
        return []


class PartialElementaryConditionalHeatPort(Component):
    """Optional heat port with temperature (Modelica.Thermal.HeatTransfer.Interfaces.PartialElementaryConditionalHeatPort).

    Like the WithoutT variant, plus ``TheatPort``: the port temperature when
    ``useHeatPort``, otherwise the fixed device temperature parameter ``T``.
    """

    modelica_name = "Modelica.Thermal.HeatTransfer.Interfaces.PartialElementaryConditionalHeatPort"

    useHeatPort = Parameter(False, structural=True,  # noqa: N815 - Modelica name
                            description="= true, if heatPort is enabled")
    T = Parameter(293.15, unit="K", description="Fixed device temperature if useHeatPort = false")
    heatPort = HeatPort_a(condition="useHeatPort",  # noqa: N815 - Modelica name
                          description="Optional port to which dissipated losses are transported")
    lossPower = Variable(unit="W", description="Loss power leaving component via heatPort")  # noqa: N815
    TheatPort = Variable(unit="K", start=293.15, description="Temperature of heatPort")  # noqa: N815

    def equations(self):
        if self.useHeatPort:
            return [Eq(self.heatPort.T, self.TheatPort), Eq(self.heatPort.Q_flow, -self.lossPower)]
        return [Eq(self.TheatPort, self.T)]
