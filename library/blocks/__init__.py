"""Modelica.Blocks: sources, math, continuous, discrete, nonlinear, logical and Boolean blocks.

Every block is importable from here (``from acausal.library.blocks import
Sine, Sampler``); the modules follow the MSL's sub-packages.  The partial
classes of the discrete blocks (DiscreteBlock, DiscreteSISO, DiscreteMIMO)
are in :mod:`acausal.library.blocks.discrete`.
"""

from .booleans import (BooleanConstant, BooleanPulse, BooleanStep, BooleanTable, BooleanToReal, RealToBoolean,
                       SampleTrigger)
from .continuous import Der, FirstOrder, Init, Integrator, LimIntegrator
from .discrete import (FirstOrderHold, Sampler, StateSpace, TransferFunction, TriggeredMax, TriggeredSampler,
                       UnitDelay, ZeroOrderHold)
from .logical import (And, AssertCondition, Change, Edge, FallingEdge, Greater, GreaterEqual, GreaterEqualThreshold,
                      GreaterThreshold, Hysteresis, Less, LessEqual, LessEqualThreshold, LessThreshold,
                      LogicalSwitch, Nand, Nor, Not, OnDelay, OnOffController, Or, Pre, RSFlipFlop, Switch,
                      TerminateSimulation, Timer, TriggeredTrapezoid, Xor, ZeroCrossing)
from .math import Add, Atan, Feedback, Gain, Product, RealToInteger, Sin
from .math import LinearDependency, MatrixGain, Max, Min, MinMax, MultiProduct, MultiSum, MultiSwitch, Sum
from .routing import (BooleanPassThrough, BooleanReplicator, DeMultiplex, DeMultiplex2, DeMultiplex3, DeMultiplex4,
                      DeMultiplex5, DeMultiplex6, Extractor, ExtractSignal, IntegerPassThrough, IntegerReplicator,
                      Multiplex, Multiplex2, Multiplex3, Multiplex4, Multiplex5, Multiplex6, RealPassThrough,
                      Replicator)
from .nonlinear import DeadZone, Limiter, LimiterHomotopy, SlewRateLimiter, VariableLimiter, VariableLimiterHomotopy
from .tables import CombiTable1Ds, CombiTable1Dv, CombiTable2Ds, CombiTable2Dv
from .types import Regularization
from .filters import AnalogFilter, CriticalDamping, Filter, FilterType, LowpassButterworth
from .sources import (CosineVariableFrequencyAndAmplitude, Exponentials, IntegerConstant, IntegerExpression,
                      IntegerStep, KinematicPTP, KinematicPTP2, LogFrequencySweep, RealExpression, Sinc,
                      SineVariableFrequencyAndAmplitude)
from .booleans import BooleanExpression, RadioButtonSource
from .nonlinear import PadeDelay
from .sources import (CombiTimeTable, Constant, ContinuousClock, Cosine, IntegerTable, ExpSine, Extrapolation, Pulse, Ramp, SawTooth, Sine,
                      Smoothness, Step, TimeEvents, TimeTable, Trapezoid)

__all__ = ["Constant", "ContinuousClock", "Step", "Ramp", "Sine", "Cosine", "ExpSine", "Pulse", "SawTooth", "Trapezoid", "TimeTable",
           "CombiTimeTable", "Smoothness", "Extrapolation", "TimeEvents",
           "CombiTable1Ds", "CombiTable1Dv", "CombiTable2Ds", "CombiTable2Dv", "IntegerTable", "RealToInteger",
           "Gain", "Product", "Add", "Feedback", "Atan", "Sin", "Regularization",
           "Init", "Integrator", "LimIntegrator", "FirstOrder", "Der",
           "Sampler", "ZeroOrderHold", "FirstOrderHold", "UnitDelay", "TransferFunction", "StateSpace",
           "TriggeredSampler", "TriggeredMax",
           "LimiterHomotopy", "VariableLimiterHomotopy", "Limiter", "VariableLimiter", "DeadZone", "SlewRateLimiter",
           "BooleanConstant", "BooleanPulse", "BooleanStep", "BooleanTable", "BooleanToReal", "RealToBoolean",
           "SampleTrigger",
           "And", "AssertCondition", "Change", "Edge", "FallingEdge", "Greater", "GreaterEqual",
           "GreaterEqualThreshold", "GreaterThreshold", "Hysteresis", "Less", "LessEqual", "LessEqualThreshold",
           "LessThreshold", "LogicalSwitch", "Nand", "Nor", "Not", "OnDelay", "OnOffController", "Or", "Pre",
           "RSFlipFlop", "Switch", "TerminateSimulation", "Timer", "TriggeredTrapezoid", "Xor", "ZeroCrossing"]
__all__ += ["MatrixGain", "MultiSum", "MultiProduct", "MultiSwitch", "Sum", "Max", "Min", "MinMax",
            "LinearDependency"]
__all__ += ["Replicator", "IntegerReplicator", "BooleanReplicator", "ExtractSignal", "Extractor",
            "Multiplex", "Multiplex2", "Multiplex3", "Multiplex4", "Multiplex5", "Multiplex6",
            "DeMultiplex", "DeMultiplex2", "DeMultiplex3", "DeMultiplex4", "DeMultiplex5", "DeMultiplex6",
            "RealPassThrough", "IntegerPassThrough", "BooleanPassThrough"]
__all__ += ["IntegerConstant", "IntegerStep", "RealExpression", "IntegerExpression", "BooleanExpression", "Sinc",
            "Exponentials", "LogFrequencySweep", "SineVariableFrequencyAndAmplitude",
            "CosineVariableFrequencyAndAmplitude", "KinematicPTP", "KinematicPTP2", "PadeDelay",
            "RadioButtonSource"]
from .noise import BandLimitedWhiteNoise, NormalNoise, TruncatedNormalNoise, UniformNoise  # noqa: E402
__all__ += ["UniformNoise", "NormalNoise", "TruncatedNormalNoise", "BandLimitedWhiteNoise"]
from .continuous import PI, PID, Derivative, LimPID, SecondOrder, SimpleController  # noqa: E402
__all__ += ["Derivative", "SecondOrder", "PI", "PID", "LimPID", "SimpleController"]
__all__ += ["CriticalDamping", "LowpassButterworth", "Filter", "AnalogFilter", "FilterType"]
from .math import (Abs, Acos, Add3, Asin, Atan2, BooleanChange, BooleanToInteger, ContinuousMean,  # noqa: E402
                   ContinuousSignalExtrema, Cos, Cosh, Division, Exp, Exponentiation, Harmonic, IntegerChange,
                   IntegerToBoolean, IntegerToReal, Log, Log10, Mean, PolarToRectangular, Power, Pythagoras,
                   RectangularToPolar, RectifiedMean, RootMeanSquare, Sign, SignalExtrema, Sinh, Sqrt,
                   StandardDeviation, Tan, Tanh, Variance, WrapAngle)
from .math_boolean import ChangingEdge, RisingEdge  # noqa: E402
from .math_integer import TriggeredAdd  # noqa: E402
from .logical import LogicalDelay  # noqa: E402
from .interaction import BooleanValue, IntegerValue, RealValue  # noqa: E402
from . import interaction, math_boolean, math_integer, unit_conversions  # noqa: E402,F401 - MSL sub-packages
__all__ += ["Add3", "Division", "Abs", "Sign", "Sqrt", "Cos", "Tan", "Asin", "Acos", "Atan2", "Sinh", "Cosh", "Tanh",
            "Exp", "Power", "Exponentiation", "Log", "Log10", "WrapAngle", "IntegerToReal", "BooleanToInteger",
            "IntegerToBoolean", "RectangularToPolar", "PolarToRectangular", "Mean", "RectifiedMean", "RootMeanSquare",
            "Harmonic", "ContinuousMean", "Variance", "StandardDeviation", "SignalExtrema", "ContinuousSignalExtrema",
            "Pythagoras", "BooleanChange", "IntegerChange", "RisingEdge", "ChangingEdge", "TriggeredAdd",
            "LogicalDelay", "RealValue", "IntegerValue", "BooleanValue"]

from .nonlinear import FixedDelay, VariableDelay  # noqa: E402 - the exact delays (delay() operator)
__all__ += ["FixedDelay", "VariableDelay"]
from .math import RealFFT  # noqa: E402
from .noise import ImpureRandom  # noqa: E402

__all__ += ["RealFFT", "ImpureRandom"]
