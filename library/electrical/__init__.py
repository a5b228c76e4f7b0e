"""Modelica.Electrical.Analog: analog electrical circuits (basic components, sources, sensors).

The pins and partial models are in :mod:`acausal.components.electrical`
(Modelica.Electrical.Analog.Interfaces); a resistive element's losses reach a
thermal network (:mod:`acausal.library.thermal`) through its conditional
heat port, an electromotive force couples a circuit to a rotational or
translational flange.
"""

from acausal.components.electrical import NegativePin, Pin, PositivePin

from .basic import (
    CCC,
    CCV,
    VCC,
    VCV,
    Capacitor,
    Conductor,
    Ground,
    Gyrator,
    Inductor,
    M_Transformer,
    OpAmp,
    OpAmpDetailed,
    Potentiometer,
    Resistor,
    RotationalEMF,
    SaturatingInductor,
    Transformer,
    TranslationalEMF,
    VariableCapacitor,
    VariableConductor,
    VariableInductor,
    VariableResistor,
)
from .sensors import CurrentSensor, MultiSensor, PotentialSensor, PowerSensor, VoltageSensor
from .sources import (
    ConstantCurrent,
    ConstantVoltage,
    CosineCurrent,
    CosineCurrentVariableFrequencyAndAmplitude,
    CosineVoltage,
    CosineVoltageVariableFrequencyAndAmplitude,
    ExponentialsCurrent,
    ExponentialsVoltage,
    ExpSineCurrent,
    ExpSineVoltage,
    PulseCurrent,
    PulseVoltage,
    RampCurrent,
    RampVoltage,
    SawToothCurrent,
    SawToothVoltage,
    SignalCurrent,
    SignalVoltage,
    SineCurrent,
    SineCurrentVariableFrequencyAndAmplitude,
    SineVoltage,
    SineVoltageVariableFrequencyAndAmplitude,
    StepCurrent,
    StepVoltage,
    SupplyVoltage,
    TableCurrent,
    TableVoltage,
    TrapezoidCurrent,
    TrapezoidVoltage,
)

__all__ = [
    "Pin", "PositivePin", "NegativePin",
    # Basic
    "Ground", "Resistor", "Conductor", "Capacitor", "Inductor", "SaturatingInductor", "Transformer", "Gyrator",
    "RotationalEMF", "TranslationalEMF", "VCV", "VCC", "CCV", "CCC", "OpAmp", "OpAmpDetailed", "M_Transformer",
    "VariableResistor", "VariableConductor", "VariableCapacitor", "VariableInductor", "Potentiometer",
    # Sources
    "SignalVoltage", "ConstantVoltage", "StepVoltage", "RampVoltage", "SineVoltage", "CosineVoltage",
    "ExpSineVoltage", "ExponentialsVoltage", "PulseVoltage", "SawToothVoltage", "TrapezoidVoltage",
    "TableVoltage", "SineVoltageVariableFrequencyAndAmplitude", "CosineVoltageVariableFrequencyAndAmplitude",
    "SupplyVoltage",
    "SignalCurrent", "ConstantCurrent", "StepCurrent", "RampCurrent", "SineCurrent", "CosineCurrent",
    "ExpSineCurrent", "ExponentialsCurrent", "PulseCurrent", "SawToothCurrent", "TrapezoidCurrent",
    "TableCurrent", "SineCurrentVariableFrequencyAndAmplitude", "CosineCurrentVariableFrequencyAndAmplitude",
    # Sensors
    "PotentialSensor", "VoltageSensor", "CurrentSensor", "PowerSensor", "MultiSensor",
]

from .machines import (  # noqa: E402 - Modelica.Electrical.Machines (DC machines)
    AirGapDC,
    Brush,
    CompoundDCExcitation,
    Core,
    DC_ElectricalExcited,
    DC_PermanentMagnet,
    DC_SeriesExcited,
    Friction,
    InductorDC,
    StrayLoad,
)

__all__ += ["DC_PermanentMagnet", "DC_ElectricalExcited", "DC_SeriesExcited", "AirGapDC", "InductorDC",
            "CompoundDCExcitation", "Friction", "Brush", "Core", "StrayLoad"]

# Ideal (op-amps)
from .ideal_opamps import IdealizedOpAmpLimited, IdealOpAmp, IdealOpAmp3Pin, IdealOpAmpLimited  # noqa: E402

__all__ += ["IdealOpAmp", "IdealOpAmp3Pin", "IdealOpAmpLimited", "IdealizedOpAmpLimited"]

# Ideal (switching elements, transformer, idle and short)
from .ideal import *  # noqa: E402,F401,F403
from .ideal import __all__ as _ideal_all  # noqa: E402

__all__ += _ideal_all

# Semiconductors
from .semiconductors import NMOS, NPN, PMOS, PNP, Diode, Diode2, SimpleTriac, Thyristor, ZDiode  # noqa: E402

__all__ += ["Diode", "Diode2", "ZDiode", "NMOS", "PMOS", "NPN", "PNP", "Thyristor", "SimpleTriac"]

# Sources: lightning impulses, DC power supply.  The LightningImpulse block (a Blocks signal
# source: amplitude and offset without unit) and its enumeration are importable, not in __all__.
from .sources import (  # noqa: E402,F401
    DCPowerSupply,
    ImpulseApproximation,
    LightningImpulse,
    LightningImpulseCurrent,
    LightningImpulseVoltage,
)

__all__ += ["LightningImpulseVoltage", "LightningImpulseCurrent", "DCPowerSupply"]

# Basic: the general signal adaptors (a oneport as an input/output block)
from .basic import GeneralCurrentToVoltageAdaptor, GeneralVoltageToCurrentAdaptor  # noqa: E402

__all__ += ["GeneralCurrentToVoltageAdaptor", "GeneralVoltageToCurrentAdaptor"]
