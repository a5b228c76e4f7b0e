"""Modelica.Blocks: sources, math, continuous, discrete, nonlinear, logical and Boolean blocks."""

from .booleans import (BooleanConstant, BooleanPulse, BooleanStep, BooleanTable, BooleanToReal, RealToBoolean,
                       SampleTrigger)
from .continuous import Integrator
from .logical import (And, AssertCondition, Change, Edge, FallingEdge, Greater, GreaterEqual, GreaterEqualThreshold,
                      GreaterThreshold, Hysteresis, Less, LessEqual, LessEqualThreshold, LessThreshold,
                      LogicalSwitch, Nand, Nor, Not, OnDelay, OnOffController, Or, Pre, RSFlipFlop, Switch,
                      TerminateSimulation, Timer, TriggeredTrapezoid, Xor, ZeroCrossing)
from .math import Add, Atan, Feedback, Gain, Product, Sin
from .types import Regularization
from .sources import Constant, Cosine, ExpSine, Ramp, Sine, Step

__all__ = ["Constant", "Step", "Ramp", "Sine", "Cosine", "ExpSine", "Gain", "Product", "Add", "Feedback", "Atan", "Sin", "Regularization", "Integrator",
           "BooleanConstant", "BooleanPulse", "BooleanStep", "BooleanTable", "BooleanToReal", "RealToBoolean",
           "SampleTrigger",
           "And", "AssertCondition", "Change", "Edge", "FallingEdge", "Greater", "GreaterEqual",
           "GreaterEqualThreshold", "GreaterThreshold", "Hysteresis", "Less", "LessEqual", "LessEqualThreshold",
           "LessThreshold", "LogicalSwitch", "Nand", "Nor", "Not", "OnDelay", "OnOffController", "Or", "Pre",
           "RSFlipFlop", "Switch", "TerminateSimulation", "Timer", "TriggeredTrapezoid", "Xor", "ZeroCrossing"]
