"""Modelica.Mechanics.Rotational: 1D rotational mechanics (components, sources, sensors)."""

from acausal.components.rotational import Flange, Flange_a, Flange_b, Support

from .components import (
    BearingFriction,
    Brake,
    Clutch,
    Damper,
    Fixed,
    IdealGear,
    IdealPlanetary,
    Inertia,
    OneWayClutch,
    Spring,
    SpringDamper,
)
from .sensors import (
    AccSensor,
    AngleSensor,
    MultiSensor,
    PowerSensor,
    RelAngleSensor,
    RelSpeedSensor,
    SpeedSensor,
    TorqueSensor,
)
from .sources import ConstantTorque, Torque, TorqueStep

__all__ = [
    "Flange", "Flange_a", "Flange_b", "Support",
    "Inertia", "Fixed", "Spring", "Damper", "SpringDamper", "IdealGear", "IdealPlanetary",
    "BearingFriction", "Clutch", "Brake", "OneWayClutch",
    "Torque", "ConstantTorque", "TorqueStep",
    "AngleSensor", "SpeedSensor", "AccSensor", "TorqueSensor", "RelAngleSensor", "RelSpeedSensor",
    "PowerSensor", "MultiSensor",
]
