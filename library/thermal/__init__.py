"""Modelica.Thermal.HeatTransfer: lumped heat transfer (components, sources, sensors, Celsius)."""

from acausal.components.thermal import HeatPort, HeatPort_a, HeatPort_b

from . import celsius as Celsius  # noqa: N812 - Modelica package name
from .celsius import CelsiusFixedTemperature, CelsiusTemperatureSensor
from .components import (Convection, GeneralHeatFlowToTemperatureAdaptor, GeneralTemperatureToHeatFlowAdaptor,
                         HeatCapacitor, ThermalConductor, ThermalResistor)
from .sensors import HeatFlowSensor, TemperatureSensor
from .sources import FixedHeatFlow, FixedTemperature, PrescribedHeatFlow, PrescribedTemperature

__all__ = [
    "HeatPort", "HeatPort_a", "HeatPort_b",
    "HeatCapacitor", "ThermalConductor", "ThermalResistor", "Convection",
    "GeneralHeatFlowToTemperatureAdaptor", "GeneralTemperatureToHeatFlowAdaptor",
    "FixedTemperature", "PrescribedTemperature", "FixedHeatFlow", "PrescribedHeatFlow",
    "TemperatureSensor", "HeatFlowSensor",
    "Celsius", "CelsiusFixedTemperature", "CelsiusTemperatureSensor",
]
