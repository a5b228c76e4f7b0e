"""Thermal sensors (Modelica.Thermal.HeatTransfer.Sensors)."""

from __future__ import annotations

from acausal.language import Component, Eq, RealOutput
from acausal.components.thermal import HeatPort_a, HeatPort_b

__all__ = ["TemperatureSensor", "HeatFlowSensor"]


class TemperatureSensor(Component):
    """Absolute temperature sensor in kelvin (Modelica.Thermal.HeatTransfer.Sensors.TemperatureSensor).

    ``T = port.T``, ``port.Q_flow = 0``.
    """

    modelica_name = "Modelica.Thermal.HeatTransfer.Sensors.TemperatureSensor"

    T = RealOutput(unit="K", description="Absolute temperature as output signal")
    port = HeatPort_a()

    def equations(self):
        return [Eq(self.T, self.port.T), Eq(self.port.Q_flow, 0)]


class HeatFlowSensor(Component):
    """Heat flow rate sensor (Modelica.Thermal.HeatTransfer.Sensors.HeatFlowSensor).

    ``Q_flow = port_a.Q_flow`` through equal temperatures.
    """

    modelica_name = "Modelica.Thermal.HeatTransfer.Sensors.HeatFlowSensor"

    Q_flow = RealOutput(unit="W", description="Heat flow from port_a to port_b as output signal")
    port_a = HeatPort_a()
    port_b = HeatPort_b()

    def equations(self):
        return [
            Eq(self.port_a.T, self.port_b.T),
            Eq(self.port_a.Q_flow + self.port_b.Q_flow, 0),
            Eq(self.Q_flow, self.port_a.Q_flow),
        ]
