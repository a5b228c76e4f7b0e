"""Translational connectors and partial models (Modelica.Mechanics.Translational.Interfaces).

The translational domain mirrors the rotational one: a flange carries a
position ``s`` (potential, m) and a cut force ``f`` (flow, N).  The partial
models follow the MSL 4.1.0 ``Interfaces`` package class by class; the
friction state machine is the one the rotational elements use
(:func:`acausal.components.friction.friction_state_machine`), as in the MSL,
where both ``PartialFriction`` classes hold the same equations.
"""

from __future__ import annotations

import sympy as sp

from acausal.language import (
    Boolean,
    Component,
    Connector,
    Eq,
    Flow,
    Integer,
    Parameter,
    Potential,
    StateSelect,
    Variable,
    der,
)

from .friction import Backward, Forward, Free, Stuck, Unknown, friction_state_machine

__all__ = [
    "Flange",
    "Flange_a",
    "Flange_b",
    "Support",
    "PartialTwoFlanges",
    "PartialRigid",
    "PartialCompliant",
    "PartialCompliantWithRelativeStates",
    "PartialElementaryOneFlangeAndSupport2",
    "PartialElementaryTwoFlangesAndSupport2",
    "PartialForce",
    "PartialAbsoluteSensor",
    "PartialRelativeSensor",
    "PartialFriction",
]

#: Modelica.Constants.eps, the limit below which s_nominal is ignored.
EPS = 1e-15


class Flange(Connector):
    """Translational flange (Modelica.Mechanics.Translational.Interfaces.Flange).

    A potential ``s`` (absolute position, m) and a flow ``f`` (cut force, N;
    positive when it is directed into the flange, i.e. acts on the component
    the flange belongs to).
    """

    modelica_name = "Modelica.Mechanics.Translational.Interfaces.Flange"

    family = "translational"
    s = Potential(unit="m", description="Absolute position of flange")
    f = Flow(unit="N", description="Cut force directed into flange")


class Flange_a(Flange):  # noqa: N801 - Modelica name
    """Left flange (Modelica.Mechanics.Translational.Interfaces.Flange_a), identical to Flange."""

    modelica_name = "Modelica.Mechanics.Translational.Interfaces.Flange_a"


class Flange_b(Flange):  # noqa: N801 - Modelica name
    """Right flange (Modelica.Mechanics.Translational.Interfaces.Flange_b), identical to Flange."""

    modelica_name = "Modelica.Mechanics.Translational.Interfaces.Flange_b"


class Support(Flange):
    """Support/housing flange (Modelica.Mechanics.Translational.Interfaces.Support), identical to Flange."""

    modelica_name = "Modelica.Mechanics.Translational.Interfaces.Support"


class PartialTwoFlanges(Component):
    """Two flanges and no equations (Modelica.Mechanics.Translational.Interfaces.PartialTwoFlanges)."""

    modelica_name = "Modelica.Mechanics.Translational.Interfaces.PartialTwoFlanges"

    flange_a = Flange_a(description="Flange of left end")
    flange_b = Flange_b(description="Flange of right end")


class PartialRigid(PartialTwoFlanges):
    """Rigid connection of two flanges (Modelica.Mechanics.Translational.Interfaces.PartialRigid).

    A body of length ``L`` with centre ``s``: ``flange_a.s = s - L/2``,
    ``flange_b.s = s + L/2``.
    """

    modelica_name = "Modelica.Mechanics.Translational.Interfaces.PartialRigid"

    L = Parameter(0.0, unit="m",
                  description="Length of component, from left flange to right flange (= flange_b.s - flange_a.s)")
    s = Variable(unit="m",
                 description="Absolute position of center of component (s = flange_a.s + L/2 = flange_b.s - L/2)")

    def equations(self):
        return [Eq(self.flange_a.s, self.s - self.L / 2), Eq(self.flange_b.s, self.s + self.L / 2)]


class PartialCompliant(PartialTwoFlanges):
    """Compliant connection of two flanges (Modelica.Mechanics.Translational.Interfaces.PartialCompliant).

    ``s_rel = flange_b.s - flange_a.s``; the force ``f`` acts on flange_b and
    its reaction on flange_a (``flange_b.f = f``, ``flange_a.f = -f``).
    """

    modelica_name = "Modelica.Mechanics.Translational.Interfaces.PartialCompliant"

    s_rel = Variable(start=0.0, unit="m", description="Relative distance (= flange_b.s - flange_a.s)")
    f = Variable(unit="N", description="Force between flanges (positive in direction of flange axis R)")

    def equations(self):
        return [
            Eq(self.s_rel, self.flange_b.s - self.flange_a.s),
            Eq(self.flange_b.f, self.f),
            Eq(self.flange_a.f, -self.f),
        ]


def _s_rel_nominal(component):
    # nominal = s_nominal (a parameter symbol); 1 when it is below eps
    return sp.Piecewise((component.s_nominal, component.s_nominal >= EPS), (1, True))


class PartialCompliantWithRelativeStates(PartialTwoFlanges):
    """Compliant connection with relative states (Modelica.Mechanics.Translational.Interfaces.PartialCompliantWithRelativeStates).

    Like PartialCompliant, plus ``v_rel = der(s_rel)``; ``s_rel`` and
    ``v_rel`` carry ``stateSelect`` (prefer by default) and ``s_nominal``
    (1e-4 m) scales the error control of ``s_rel``.  Unlike the rotational
    partial there is no relative acceleration.
    """

    modelica_name = "Modelica.Mechanics.Translational.Interfaces.PartialCompliantWithRelativeStates"

    stateSelect = Parameter(StateSelect.prefer, structural=True,  # noqa: N815 - Modelica name
                            description="Priority to use s_rel and v_rel as states")
    s_nominal = Parameter(1e-4, unit="m", min=0, description="Nominal value of s_rel (used for scaling)")
    s_rel = Variable(start=0.0, unit="m", nominal=_s_rel_nominal, state_select=lambda c: c.stateSelect,
                     description="Relative distance (= flange_b.s - flange_a.s)")
    v_rel = Variable(start=0.0, unit="m/s", state_select=lambda c: c.stateSelect,
                     description="Relative velocity (= der(s_rel))")
    f = Variable(unit="N", description="Forces between flanges (= flange_b.f)")

    def equations(self):
        return [
            Eq(self.s_rel, self.flange_b.s - self.flange_a.s),
            Eq(self.v_rel, der(self.s_rel)),
            Eq(self.flange_b.f, self.f),
            Eq(self.flange_a.f, -self.f),
        ]


class PartialElementaryOneFlangeAndSupport2(Component):
    """One flange and an optional support (Modelica.Mechanics.Translational.Interfaces.PartialElementaryOneFlangeAndSupport2).

    ``s = flange.s - s_support``.  With ``useSupport`` the conditional
    ``support`` connector exists and takes the reaction force
    (``support.s = s_support``, ``support.f = -flange.f``); without it the
    housing is grounded (``s_support = 0``).
    """

    modelica_name = "Modelica.Mechanics.Translational.Interfaces.PartialElementaryOneFlangeAndSupport2"

    useSupport = Parameter(False, structural=True,  # noqa: N815 - Modelica name
                           description="= true, if support flange enabled, otherwise implicitly grounded")
    flange = Flange_b(description="Flange of component")
    support = Support(condition="useSupport", description="Support/housing of component")
    s = Variable(unit="m", description="Distance between flange and support (= flange.s - support.s)")
    s_support = Variable(unit="m", description="Absolute position of support flange (protected)")

    def equations(self):
        equations = [Eq(self.s, self.flange.s - self.s_support)]
        if self.useSupport:
            return equations + [Eq(self.support.s, self.s_support), Eq(self.support.f, -self.flange.f)]
        return equations + [Eq(self.s_support, 0)]


class PartialElementaryTwoFlangesAndSupport2(PartialTwoFlanges):
    """Two flanges and an optional support (Modelica.Mechanics.Translational.Interfaces.PartialElementaryTwoFlangesAndSupport2).

    ``s_a = flange_a.s - s_support``, ``s_b = flange_b.s - s_support``.
    With ``useSupport`` the conditional ``support`` connector exists
    (``support.s = s_support``, ``support.f = -flange_a.f - flange_b.f``);
    without it the housing is grounded (``s_support = 0``).
    """

    modelica_name = "Modelica.Mechanics.Translational.Interfaces.PartialElementaryTwoFlangesAndSupport2"

    useSupport = Parameter(False, structural=True,  # noqa: N815 - Modelica name
                           description="= true, if support flange enabled, otherwise implicitly grounded")
    support = Support(condition="useSupport", description="Support/housing of component")
    s_a = Variable(unit="m", description="Distance between left flange and support")
    s_b = Variable(unit="m", description="Distance between right flange and support")
    s_support = Variable(unit="m", description="Absolute position of support flange (protected)")

    def equations(self):
        equations = [Eq(self.s_a, self.flange_a.s - self.s_support), Eq(self.s_b, self.flange_b.s - self.s_support)]
        if self.useSupport:
            return equations + [Eq(self.support.s, self.s_support),
                                Eq(self.support.f, -self.flange_a.f - self.flange_b.f)]
        return equations + [Eq(self.s_support, 0)]


class PartialForce(PartialElementaryOneFlangeAndSupport2):
    """Base of the force sources (Modelica.Mechanics.Translational.Interfaces.PartialForce).

    ``f = flange.f``: the force that accelerates the flange.
    """

    modelica_name = "Modelica.Mechanics.Translational.Interfaces.PartialForce"

    f = Variable(unit="N", description="Accelerating force acting at flange (= flange.f)")

    def equations(self):
        return [Eq(self.f, self.flange.f)]


class PartialAbsoluteSensor(Component):
    """Base of absolute sensors (Modelica.Mechanics.Translational.Interfaces.PartialAbsoluteSensor).

    ``0 = flange.f``.
    """

    modelica_name = "Modelica.Mechanics.Translational.Interfaces.PartialAbsoluteSensor"

    flange = Flange_a(description="Flange to be measured (flange axis directed into cut plane)")

    def equations(self):
        return [Eq(0, self.flange.f)]


class PartialRelativeSensor(PartialTwoFlanges):
    """Base of relative sensors (Modelica.Mechanics.Translational.Interfaces.PartialRelativeSensor).

    ``0 = flange_a.f + flange_b.f``.
    """

    modelica_name = "Modelica.Mechanics.Translational.Interfaces.PartialRelativeSensor"

    def equations(self):
        return [Eq(0, self.flange_a.f + self.flange_b.f)]


class PartialFriction(Component):
    """Coulomb friction state machine (Modelica.Mechanics.Translational.Interfaces.PartialFriction).

    The same state machine as the rotational
    :class:`acausal.components.friction.PartialFriction` (Otter, Elmqvist and
    Mattsson 1999; spec section 2.9, F1-F5), in translational names:
    ``v_relfric``, ``a_relfric``, ``f0`` (friction force at v = 0 when
    sliding), ``f0_max`` (static limit) and ``v_small``.  While locked,
    ``a_relfric = 0``.  The subclass defines ``v_relfric``, ``a_relfric``,
    ``f0``, ``f0_max`` and ``free`` by equations, plus its friction force
    (``sa`` when ``locked``).

    ``sa`` is declared in N, the unit of the forces it is compared with and
    stands for; the sliding and free branches of ``a_relfric`` multiply it
    by ``unitAcceleration/unitForce``, the MSL's two unit constants (both 1;
    the MSL declares ``sa`` with unit "1" and multiplies it by the constants
    instead).

    Parameters
    ----------
    v_small : float, default 1e-3 m/s
        Relative velocity near zero: a sliding element whose velocity jumps
        past ``-v_small`` (``+v_small``) by a ``reinit`` reverses directly.
    unitAcceleration : float, default 1 m/s2
        Unit constant (MSL ``constant unitAcceleration``); do not change.
    unitForce : float, default 1 N
        Unit constant (MSL ``constant unitForce``); do not change.

    Notes
    -----
    ``mode`` takes the values Unknown (3), Free (2), Forward (1), Stuck (0)
    and Backward (-1) of :mod:`acausal.components.friction`.

    References
    ----------
    .. [1] M. Otter, H. Elmqvist and S. E. Mattsson, "Hybrid Modeling in
       Modelica based on the Synchronous Data Flow Principle", CACSD'99,
       Hawaii, August 1999.
    """

    modelica_name = "Modelica.Mechanics.Translational.Interfaces.PartialFriction"

    Unknown = Unknown
    Free = Free
    Forward = Forward
    Stuck = Stuck
    Backward = Backward

    v_small = Parameter(1e-3, unit="m/s", description="Relative velocity near to zero (see model info text)")
    # Unit constants (MSL: constant ... = 1): sa*unitAcceleration/unitForce is sa, a force, read
    # as an acceleration.  The language has no "final"; a value other than 1 scales the dynamics.
    unitAcceleration = Parameter(1.0, unit="m/s2",  # noqa: N815 - Modelica name
                                 description="Unit constant 1 m/s2 (do not change)")
    unitForce = Parameter(1.0, unit="N",  # noqa: N815 - Modelica name
                          description="Unit constant 1 N (do not change)")

    # defined by the subclass
    v_relfric = Variable(unit="m/s", description="Relative velocity between frictional surfaces")
    a_relfric = Variable(unit="m/s2", description="Relative acceleration between frictional surfaces")
    f0 = Variable(unit="N", description="Friction force for v_relfric=0 and forward sliding")
    f0_max = Variable(unit="N", description="Maximum friction force for v_relfric=0 and locked")
    free = Boolean(description="= true, if frictional element is not active")

    # defined here
    sa = Variable(unit="N", description="Path parameter of friction characteristic f = f(a_relfric) "
                                        "(the friction force while locked)")
    startForward = Boolean(start=False, fixed=True,  # noqa: N815 - Modelica name
                           description="= true, if v_relfric=0 and start of forward sliding")
    startBackward = Boolean(start=False, fixed=True,  # noqa: N815 - Modelica name
                            description="= true, if v_relfric=0 and start of backward sliding")
    locked = Boolean(start=False, description="= true, if v_relfric=0 and not sliding")
    mode = Integer(start=Unknown, fixed=True, min=Backward, max=Unknown,
                   description="Mode of friction (-1: backward sliding, 0: stuck, 1: forward sliding, "
                               "2: inactive, 3: unknown)")

    def state_machine_options(self) -> dict:
        """Keyword options of :func:`friction_state_machine` (a subclass with stops restricts sliding)."""
        return {}

    def equations(self):
        return friction_state_machine(self, self.v_relfric, self.a_relfric, self.f0, self.f0_max, self.v_small,
                                      acceleration_per_force=self.unitAcceleration / self.unitForce,
                                      **self.state_machine_options())
