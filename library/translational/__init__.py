"""Modelica.Mechanics.Translational: 1D translational mechanics (components, sources, sensors)."""

from acausal.components.translational import Flange, Flange_a, Flange_b, Support

from .components import Fixed, Mass

__all__ = [
    "Flange", "Flange_a", "Flange_b", "Support",
    "Fixed", "Mass",
]
