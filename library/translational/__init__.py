"""Modelica.Mechanics.Translational: 1D translational mechanics (components, sources, sensors)."""

from acausal.components.translational import Flange, Flange_a, Flange_b, Support

from .components import (
    Damper,
    ElastoGap,
    Fixed,
    GeneralForceToPositionAdaptor,
    GeneralPositionToForceAdaptor,
    IdealGearR2T,
    IdealRollingWheel,
    InitializeFlange,
    Mass,
    RelativeStates,
    Rod,
    Spring,
    SpringDamper,
)
from .friction import Brake, MassWithStopAndFriction, SupportFriction
from .sensors import (
    AccSensor,
    ForceSensor,
    MultiSensor,
    PositionSensor,
    PowerSensor,
    RelAccSensor,
    RelPositionSensor,
    RelSpeedSensor,
    SpeedSensor,
)
from .sources import (
    Accelerate,
    ConstantForce,
    ConstantSpeed,
    EddyCurrentForce,
    Force,
    Force2,
    ForceStep,
    InverseSpeedDependentForce,
    LinearSpeedDependentForce,
    Move,
    Position,
    QuadraticSpeedDependentForce,
    Regularization,
    SignForce,
    Speed,
)
from .vehicle import G_N, RollingResistance, Vehicle

__all__ = [
    "Flange", "Flange_a", "Flange_b", "Support",
    # Components
    "Fixed", "Mass", "Rod", "Spring", "Damper", "SpringDamper", "ElastoGap", "SupportFriction", "Brake",
    "IdealGearR2T", "IdealRollingWheel", "RollingResistance", "Vehicle", "InitializeFlange",
    "MassWithStopAndFriction", "RelativeStates", "GeneralForceToPositionAdaptor",
    "GeneralPositionToForceAdaptor",
    # Sources
    "Position", "Speed", "Accelerate", "Move", "Force", "Force2", "InverseSpeedDependentForce",
    "LinearSpeedDependentForce", "QuadraticSpeedDependentForce", "ConstantForce", "SignForce",
    "ConstantSpeed", "ForceStep", "EddyCurrentForce", "Regularization",
    # Sensors
    "PositionSensor", "SpeedSensor", "AccSensor", "RelPositionSensor", "RelSpeedSensor", "RelAccSensor",
    "ForceSensor", "PowerSensor", "MultiSensor",
    # Modelica.Constants.g_n, as the vehicle uses it
    "G_N",
]
