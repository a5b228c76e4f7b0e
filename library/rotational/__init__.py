"""Modelica.Mechanics.Rotational: 1D rotational mechanics (components, sources, sensors)."""

from acausal.components.rotational import Flange, Flange_a, Flange_b, Support

from .components import (
    AngleToTorqueAdaptor,
    BearingFriction,
    Brake,
    Clutch,
    Damper,
    Disc,
    ElastoBacklash,
    ElastoBacklash2,
    Fixed,
    GeneralAngleToTorqueAdaptor,
    GeneralTorqueToAngleAdaptor,
    IdealGear,
    IdealGearR2T,
    IdealPlanetary,
    IdealRollingWheel,
    Inertia,
    InitializeFlange,
    OneWayClutch,
    RelativeStates,
    Spring,
    SpringDamper,
    TorqueToAngleAdaptor,
)
from .lossy_gear import Gearbox, LossyGear
from .sensors import (
    AccSensor,
    AngleSensor,
    MultiSensor,
    PowerSensor,
    RelAccSensor,
    RelAngleSensor,
    RelSpeedSensor,
    SpeedSensor,
    TorqueSensor,
)
from .sources import (
    Accelerate,
    ConstantSpeed,
    ConstantTorque,
    EddyCurrentTorque,
    InverseSpeedDependentTorque,
    LinearSpeedDependentTorque,
    Move,
    Position,
    QuadraticSpeedDependentTorque,
    Regularization,
    SignTorque,
    Speed,
    Torque,
    Torque2,
    TorqueStep,
)

__all__ = [
    "Flange", "Flange_a", "Flange_b", "Support",
    # Components
    "Fixed", "Inertia", "Disc", "Spring", "Damper", "SpringDamper", "ElastoBacklash", "ElastoBacklash2",
    "BearingFriction", "Brake", "Clutch", "OneWayClutch", "IdealGear", "LossyGear", "IdealPlanetary",
    "Gearbox", "IdealGearR2T", "IdealRollingWheel", "InitializeFlange", "RelativeStates",
    "AngleToTorqueAdaptor", "TorqueToAngleAdaptor", "GeneralAngleToTorqueAdaptor",
    "GeneralTorqueToAngleAdaptor",
    # Sources
    "Position", "Speed", "Accelerate", "Move", "Torque", "Torque2", "InverseSpeedDependentTorque",
    "LinearSpeedDependentTorque", "QuadraticSpeedDependentTorque", "ConstantTorque", "SignTorque",
    "ConstantSpeed", "TorqueStep", "EddyCurrentTorque", "Regularization",
    # Sensors
    "AngleSensor", "SpeedSensor", "AccSensor", "RelAngleSensor", "RelSpeedSensor", "RelAccSensor",
    "TorqueSensor", "PowerSensor", "MultiSensor",
]
