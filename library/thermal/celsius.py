"""Components with temperatures in degree Celsius (Modelica.Thermal.HeatTransfer.Celsius).

Use it as a namespace, like Modelica: ``from acausal.library.thermal import Celsius``
then ``Celsius.FixedTemperature(T=25)`` and ``Celsius.TemperatureSensor()``.
"""

from __future__ import annotations

from acausal.language import Component, Eq, Parameter, RealOutput
from acausal.components.thermal import HeatPort_a, HeatPort_b

__all__ = ["CelsiusFixedTemperature", "CelsiusTemperatureSensor", "FixedTemperature", "TemperatureSensor"]

#: 0 degC in kelvin.
ZERO_CELSIUS = 273.15


class CelsiusFixedTemperature(Component):
    """Fixed temperature boundary condition in degC (Modelica.Thermal.HeatTransfer.Celsius.FixedTemperature).

    ``port.T = T + 273.15``.
    """

    modelica_name = "Modelica.Thermal.HeatTransfer.Celsius.FixedTemperature"

    T = Parameter(None, unit="degC", description="Fixed temperature at the port")
    port = HeatPort_b()

    def equations(self):
        return [Eq(self.port.T, self.T + ZERO_CELSIUS)]


class CelsiusTemperatureSensor(Component):
    """Absolute temperature sensor in degC (Modelica.Thermal.HeatTransfer.Celsius.TemperatureSensor).

    ``T = port.T - 273.15``, ``port.Q_flow = 0``.
    """

    modelica_name = "Modelica.Thermal.HeatTransfer.Celsius.TemperatureSensor"

    T = RealOutput(unit="degC", description="Absolute temperature in degree Celsius as output signal")
    port = HeatPort_a()

    def equations(self):
        return [Eq(self.T, self.port.T - ZERO_CELSIUS), Eq(self.port.Q_flow, 0)]


#: Modelica names inside the Celsius package.
FixedTemperature = CelsiusFixedTemperature
TemperatureSensor = CelsiusTemperatureSensor
