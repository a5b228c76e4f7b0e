"""Translational components (Modelica.Mechanics.Translational.Components)."""

from __future__ import annotations

from acausal.language import Component, Eq, Parameter, StateSelect, Variable, der
from acausal.components.translational import Flange_b, PartialRigid

__all__ = [
    "Fixed",
    "Mass",
]


class Fixed(Component):
    """Flange fixed in the housing at a position (Modelica.Mechanics.Translational.Components.Fixed).

    ``flange.s = s0``.
    """

    s0 = Parameter(0.0, unit="m", description="Fixed offset position of housing")
    flange = Flange_b(description="Flange fixed in housing at a given position")

    def equations(self):
        return [Eq(self.flange.s, self.s0)]


class Mass(PartialRigid):
    """Sliding mass with inertia (Modelica.Mechanics.Translational.Components.Mass).

    A rigid body of length ``L`` (default 0) and mass ``m`` whose centre is
    at ``s``: ``v = der(s)``, ``a = der(v)``, ``m*a = flange_a.f + flange_b.f``.
    ``s`` and ``v`` carry the ``stateSelect`` hint (default StateSelect.default).
    """

    m = Parameter(1.0, unit="kg", min=0, description="Mass of the sliding mass")
    stateSelect = Parameter(StateSelect.default, structural=True,  # noqa: N815 - Modelica name
                            description="Priority to use s and v as states")
    s = Variable(start=0.0, unit="m", state_select=lambda c: c.stateSelect,
                 description="Absolute position of center of component (s = flange_a.s + L/2 = flange_b.s - L/2)")
    v = Variable(start=0.0, unit="m/s", state_select=lambda c: c.stateSelect,
                 description="Absolute velocity of component")
    a = Variable(start=0.0, unit="m/s2", description="Absolute acceleration of component")

    def equations(self):
        return [
            Eq(self.v, der(self.s)),
            Eq(self.a, der(self.v)),
            Eq(self.m * self.a, self.flange_a.f + self.flange_b.f),
        ]
