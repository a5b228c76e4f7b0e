"""Rotational connectors and partial models (Modelica.Mechanics.Rotational.Interfaces)."""

from __future__ import annotations

import sympy as sp

from . import translational
from acausal.language import (
    Component,
    Connector,
    Eq,
    Flow,
    Parameter,
    Potential,
    StateSelect,
    Variable,
    der,
)

__all__ = [
    "Flange",
    "Flange_a",
    "Flange_b",
    "Support",
    "PartialTwoFlanges",
    "PartialCompliant",
    "PartialCompliantWithRelativeStates",
    "PartialElementaryOneFlangeAndSupport2",
    "PartialElementaryTwoFlangesAndSupport2",
    "PartialElementaryRotationalToTranslational",
    "PartialTorque",
    "PartialAbsoluteSensor",
    "PartialRelativeSensor",
]

#: Modelica.Constants.eps, the limit below which phi_nominal is ignored.
EPS = 1e-15


class Flange(Connector):
    """Rotational flange (Modelica.Mechanics.Rotational.Interfaces.Flange).

    A potential ``phi`` (absolute rotation angle, rad) and a flow ``tau`` (cut
    torque, N.m; positive when it acts on the component the flange belongs to).
    """

    modelica_name = "Modelica.Mechanics.Rotational.Interfaces.Flange"

    family = "rotational"
    phi = Potential(unit="rad", description="Absolute rotation angle of flange")
    tau = Flow(unit="N.m", description="Cut torque in the flange")


class Flange_a(Flange):  # noqa: N801 - Modelica name
    """Driving flange (Modelica.Mechanics.Rotational.Interfaces.Flange_a), identical to Flange."""

    modelica_name = "Modelica.Mechanics.Rotational.Interfaces.Flange_a"


class Flange_b(Flange):  # noqa: N801 - Modelica name
    """Driven flange (Modelica.Mechanics.Rotational.Interfaces.Flange_b), identical to Flange."""

    modelica_name = "Modelica.Mechanics.Rotational.Interfaces.Flange_b"


class Support(Flange):
    """Support/housing flange (Modelica.Mechanics.Rotational.Interfaces.Support), identical to Flange."""

    modelica_name = "Modelica.Mechanics.Rotational.Interfaces.Support"


class PartialTwoFlanges(Component):
    """Two flanges and no equations (Modelica.Mechanics.Rotational.Interfaces.PartialTwoFlanges)."""

    modelica_name = "Modelica.Mechanics.Rotational.Interfaces.PartialTwoFlanges"

    flange_a = Flange_a()
    flange_b = Flange_b()


class PartialCompliant(PartialTwoFlanges):
    """Compliant connection of two flanges (Modelica.Mechanics.Rotational.Interfaces.PartialCompliant).

    Declares the relative angle ``phi_rel = flange_b.phi - flange_a.phi`` and
    the torque ``tau`` transmitted from flange_a to flange_b
    (``flange_b.tau = tau``, ``flange_a.tau = -tau``).
    """

    modelica_name = "Modelica.Mechanics.Rotational.Interfaces.PartialCompliant"

    phi_rel = Variable(start=0.0, unit="rad",
                       description="Relative rotation angle (= flange_b.phi - flange_a.phi)")
    tau = Variable(unit="N.m", description="Torque between flanges (= flange_b.tau)")

    def equations(self):
        return [
            Eq(self.phi_rel, self.flange_b.phi - self.flange_a.phi),
            Eq(self.flange_b.tau, self.tau),
            Eq(self.flange_a.tau, -self.tau),
        ]


def _phi_rel_nominal(component):
    # nominal = phi_nominal if phi_nominal >= eps else 1 (phi_nominal is a parameter symbol)
    return sp.Piecewise((component.phi_nominal, component.phi_nominal >= EPS), (1, True))


class PartialCompliantWithRelativeStates(PartialTwoFlanges):
    """Compliant connection with relative states (Modelica.Mechanics.Rotational.Interfaces.PartialCompliantWithRelativeStates).

    Like PartialCompliant, plus ``w_rel = der(phi_rel)`` and ``a_rel =
    der(w_rel)``; ``phi_rel`` and ``w_rel`` carry ``stateSelect`` (prefer by
    default), so these relative quantities are chosen as states, and
    ``phi_nominal`` (1e-4 rad) scales the error control of ``phi_rel``.
    """

    modelica_name = "Modelica.Mechanics.Rotational.Interfaces.PartialCompliantWithRelativeStates"

    phi_nominal = Parameter(1e-4, unit="rad", min=0,
                            description="Nominal value of phi_rel (used for scaling)")
    stateSelect = Parameter(StateSelect.prefer, structural=True,  # noqa: N815 - Modelica name
                            description="Priority to use phi_rel and w_rel as states")
    phi_rel = Variable(start=0.0, unit="rad", nominal=_phi_rel_nominal,
                       state_select=lambda c: c.stateSelect,
                       description="Relative rotation angle (= flange_b.phi - flange_a.phi)")
    w_rel = Variable(start=0.0, unit="rad/s", state_select=lambda c: c.stateSelect,
                     description="Relative angular velocity (= der(phi_rel))")
    a_rel = Variable(start=0.0, unit="rad/s2", description="Relative angular acceleration (= der(w_rel))")
    tau = Variable(unit="N.m", description="Torque between flanges (= flange_b.tau)")

    def equations(self):
        return [
            Eq(self.phi_rel, self.flange_b.phi - self.flange_a.phi),
            Eq(self.w_rel, der(self.phi_rel)),
            Eq(self.a_rel, der(self.w_rel)),
            Eq(self.flange_b.tau, self.tau),
            Eq(self.flange_a.tau, -self.tau),
        ]


class PartialElementaryOneFlangeAndSupport2(Component):
    """One flange and an optional support (Modelica.Mechanics.Rotational.Interfaces.PartialElementaryOneFlangeAndSupport2).

    With ``useSupport`` the conditional ``support`` connector exists and takes
    the reaction torque (``support.phi = phi_support``, ``support.tau =
    -flange.tau``); without it the housing is grounded (``phi_support = 0``).
    """

    modelica_name = "Modelica.Mechanics.Rotational.Interfaces.PartialElementaryOneFlangeAndSupport2"

    useSupport = Parameter(False, structural=True,  # noqa: N815 - Modelica name
                           description="= true, if support flange enabled, otherwise implicitly grounded")
    flange = Flange_b(description="Flange of shaft")
    support = Support(condition="useSupport", description="Support/housing of component")
    phi_support = Variable(unit="rad", description="Absolute angle of support flange (protected)")

    def equations(self):
        if self.useSupport:
            return [Eq(self.support.phi, self.phi_support), Eq(self.support.tau, -self.flange.tau)]
        return [Eq(self.phi_support, 0)]


class PartialElementaryTwoFlangesAndSupport2(PartialTwoFlanges):
    """Two flanges and an optional support (Modelica.Mechanics.Rotational.Interfaces.PartialElementaryTwoFlangesAndSupport2).

    With ``useSupport`` the conditional ``support`` connector exists
    (``support.phi = phi_support``, ``support.tau = -flange_a.tau -
    flange_b.tau``); without it the housing is grounded (``phi_support = 0``).
    """

    modelica_name = "Modelica.Mechanics.Rotational.Interfaces.PartialElementaryTwoFlangesAndSupport2"

    useSupport = Parameter(False, structural=True,  # noqa: N815 - Modelica name
                           description="= true, if support flange enabled, otherwise implicitly grounded")
    support = Support(condition="useSupport", description="Support/housing of component")
    phi_support = Variable(unit="rad", description="Absolute angle of support flange (protected)")

    def equations(self):
        if self.useSupport:
            return [Eq(self.support.phi, self.phi_support),
                    Eq(self.support.tau, -self.flange_a.tau - self.flange_b.tau)]
        return [Eq(self.phi_support, 0)]


class PartialElementaryRotationalToTranslational(Component):
    """Rotational flange and translational flange, each with an optional support
    (Modelica.Mechanics.Rotational.Interfaces.PartialElementaryRotationalToTranslational).

    The MSL routes each housing through a protected InternalSupport, fixed to
    ground by a conditional Fixed when the support is disabled.  Here the
    housing positions are the variables ``phi_support`` and ``s_support``:

    * ``useSupportR``: ``supportR.phi = phi_support`` and ``supportR.tau =
      -flangeR.tau`` (the reaction torque goes to the housing); otherwise
      ``phi_support = 0``.
    * ``useSupportT``: ``supportT.s = s_support`` and ``supportT.f =
      -flangeT.f``; otherwise ``s_support = 0``.
    """

    modelica_name = "Modelica.Mechanics.Rotational.Interfaces.PartialElementaryRotationalToTranslational"

    useSupportR = Parameter(False, structural=True,  # noqa: N815 - Modelica name
                            description="= true, if rotational support flange enabled, otherwise implicitly grounded")
    useSupportT = Parameter(False, structural=True,  # noqa: N815 - Modelica name
                            description="= true, if translational support flange enabled, otherwise implicitly "
                                        "grounded")
    flangeR = Flange_a(description="Flange of rotational shaft")  # noqa: N815 - Modelica name
    flangeT = translational.Flange_b(description="Flange of translational rod")  # noqa: N815 - Modelica name
    supportR = Support(condition="useSupportR",  # noqa: N815 - Modelica name
                       description="Rotational support/housing of component")
    supportT = translational.Support(condition="useSupportT",  # noqa: N815 - Modelica name
                                     description="Translational support/housing of component")
    phi_support = Variable(unit="rad", description="Absolute angle of the rotational support (protected)")
    s_support = Variable(unit="m", description="Absolute position of the translational support (protected)")

    def equations(self):
        equations = []
        if self.useSupportR:
            equations += [Eq(self.supportR.phi, self.phi_support), Eq(self.supportR.tau, -self.flangeR.tau)]
        else:
            equations.append(Eq(self.phi_support, 0))
        if self.useSupportT:
            equations += [Eq(self.supportT.s, self.s_support), Eq(self.supportT.f, -self.flangeT.f)]
        else:
            equations.append(Eq(self.s_support, 0))
        return equations


class PartialTorque(PartialElementaryOneFlangeAndSupport2):
    """Base of the torque sources (Modelica.Mechanics.Rotational.Interfaces.PartialTorque).

    Adds the angle of the flange relative to the support, ``phi = flange.phi -
    phi_support``.
    """

    modelica_name = "Modelica.Mechanics.Rotational.Interfaces.PartialTorque"

    phi = Variable(unit="rad", description="Angle of flange with respect to support")

    def equations(self):
        return [Eq(self.phi, self.flange.phi - self.phi_support)]


class PartialAbsoluteSensor(Component):
    """Base of absolute sensors (Modelica.Mechanics.Rotational.Interfaces.PartialAbsoluteSensor).

    ``0 = flange.tau``.
    """

    modelica_name = "Modelica.Mechanics.Rotational.Interfaces.PartialAbsoluteSensor"

    flange = Flange_a(description="Flange to be measured")

    def equations(self):
        return [Eq(0, self.flange.tau)]


class PartialRelativeSensor(Component):
    """Base of relative sensors (Modelica.Mechanics.Rotational.Interfaces.PartialRelativeSensor).

    ``0 = flange_a.tau + flange_b.tau``.
    """

    modelica_name = "Modelica.Mechanics.Rotational.Interfaces.PartialRelativeSensor"

    flange_a = Flange_a()
    flange_b = Flange_b()

    def equations(self):
        return [Eq(0, self.flange_a.tau + self.flange_b.tau)]
