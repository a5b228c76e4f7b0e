"""Modelica.Blocks: signal sources and mathematical blocks."""

from .continuous import Integrator
from .math import Add, Feedback, Gain, Product
from .sources import Constant, Cosine, ExpSine, Ramp, Sine, Step

__all__ = ["Constant", "Step", "Ramp", "Sine", "Cosine", "ExpSine", "Gain", "Product", "Add", "Feedback", "Integrator"]
