"""Translational force and motion sources (Modelica.Mechanics.Translational.Sources).

Force sources (``Force``, ``ConstantForce``, the speed-dependent forces, ...)
push the flange with a force relative to the optional support; motion
sources (``Position``, ``Speed``, ``Accelerate``, ``Move``) prescribe how the
flange moves relative to the support and take whatever force that needs.

Sign convention: the sources derived from PartialForce have ``f =
flange.f``, the force the flange exerts on the source; the flange is pushed
by ``-f``.  So ``ConstantForce(f_constant=10)`` (``f = -10``) accelerates
the flange in its positive direction, and a speed-dependent force with a
positive ``f_nominal`` brakes a flange moving forwards.
"""

from __future__ import annotations

import sympy as sp

from acausal.functions import prescribed
from acausal.hybrid import smooth
from acausal.language import (
    Component,
    Eq,
    If,
    Parameter,
    RealInput,
    StateSelect,
    Variable,
    der,
    time,
)
from acausal.components.checks import where
from acausal.components.declarations import VectorBlock
from acausal.components.thermal import PartialElementaryConditionalHeatPort
from acausal.components.translational import EPS, PartialElementaryOneFlangeAndSupport2, PartialForce, PartialTwoFlanges
from acausal.library.blocks.types import Regularization, regularized_sign

__all__ = [
    "Regularization",
    "Force",
    "Force2",
    "ConstantForce",
    "ForceStep",
    "Position",
    "Speed",
    "Accelerate",
    "Move",
    "ConstantSpeed",
    "LinearSpeedDependentForce",
    "QuadraticSpeedDependentForce",
    "InverseSpeedDependentForce",
    "SignForce",
    "EddyCurrentForce",
]


# --------------------------------------------------------------------------
# forces


class Force(PartialElementaryOneFlangeAndSupport2):
    """Input signal acting as external force on a flange (Modelica.Mechanics.Translational.Sources.Force).

    ``flange.f = -f``: a positive input drives the flange in its positive
    direction; with ``useSupport`` the reaction force acts on the support.
    """

    modelica_name = "Modelica.Mechanics.Translational.Sources.Force"

    f = RealInput(unit="N", description="Driving force as input signal")

    def equations(self):
        return [Eq(self.flange.f, -self.f)]


class Force2(PartialTwoFlanges):
    """Input signal acting as a force pair on two flanges (Modelica.Mechanics.Translational.Sources.Force2).

    ``flange_a.f = f`` and ``flange_b.f = -f``: a positive input pushes the
    two flanges apart (flange_b forwards, flange_a backwards).
    """

    modelica_name = "Modelica.Mechanics.Translational.Sources.Force2"

    f = RealInput(unit="N", description="Driving force as input signal")

    def equations(self):
        return [Eq(self.flange_a.f, self.f), Eq(self.flange_b.f, -self.f)]


class ConstantForce(PartialForce):
    """Constant force, independent of the speed (Modelica.Mechanics.Translational.Sources.ConstantForce).

    ``f = -f_constant``: a positive ``f_constant`` accelerates the flange in
    its positive direction whichever way it moves (a negative value acts as
    a load while it moves forwards).
    """

    modelica_name = "Modelica.Mechanics.Translational.Sources.ConstantForce"

    f_constant = Parameter(None, unit="N",
                           description="Nominal force (if negative, force is acting as load in positive "
                                       "direction of motion)")

    def equations(self):
        return [Eq(self.f, -self.f_constant)]


class ForceStep(PartialForce):
    """Constant force with a step at ``startTime`` (Modelica.Mechanics.Translational.Sources.ForceStep).

    ``f = -offsetForce - (0 if time < startTime else stepForce)``; the step
    is a time event.
    """

    modelica_name = "Modelica.Mechanics.Translational.Sources.ForceStep"

    stepForce = Parameter(1.0, unit="N",  # noqa: N815 - Modelica name
                          description="Height of force step (if negative, force is acting as load)")
    offsetForce = Parameter(0.0, unit="N", description="Offset of force")  # noqa: N815 - Modelica name
    startTime = Parameter(0.0, unit="s", description="Force = offset for time < startTime")  # noqa: N815

    def equations(self):
        return [Eq(self.f, -self.offsetForce - If(time < self.startTime, 0, self.stepForce))]


class _SpeedDependentForce(PartialForce):
    """What the speed-dependent forces share: ``f_nominal``, ``ForceDirection``, ``v_nominal`` and
    ``v = der(s)``, the speed of the flange relative to the support."""

    f_nominal = Parameter(None, unit="N",
                          description="Nominal force (if negative, force is acting as load in positive "
                                      "direction of motion)")
    ForceDirection = Parameter(True, structural=True,  # noqa: N815 - Modelica name
                               description="Same direction of force in both directions of motion")
    v_nominal = Parameter(None, unit="m/s", min=EPS, description="Nominal speed")
    v = Variable(unit="m/s", description="Velocity of flange with respect to support (= der(s))")

    def equations(self):
        return [Eq(self.v, der(self.s))]


class LinearSpeedDependentForce(_SpeedDependentForce):
    """Force growing linearly with the speed (Modelica.Mechanics.Translational.Sources.LinearSpeedDependentForce).

    ``f = -f_nominal*|v/v_nominal|`` if ``ForceDirection`` (the same
    direction whichever way the flange moves), else ``f =
    -f_nominal*v/v_nominal`` (with ``f_nominal < 0`` a linear damper to the
    support).  The flange is pushed by ``-f``.
    """

    modelica_name = "Modelica.Mechanics.Translational.Sources.LinearSpeedDependentForce"

    def equations(self):
        ratio = self.v / self.v_nominal
        return [Eq(self.f, -self.f_nominal * (sp.Abs(ratio) if self.ForceDirection else ratio))]


class QuadraticSpeedDependentForce(_SpeedDependentForce):
    """Force growing with the square of the speed (Modelica.Mechanics.Translational.Sources.QuadraticSpeedDependentForce).

    ``f = -f_nominal*(v/v_nominal)^2`` if ``ForceDirection``; otherwise the
    force changes sign with the speed, ``f = -f_nominal*(v/v_nominal)*|v/v_nominal|``
    (the MSL's ``smooth(1, if v >= 0 then ... else ...)``, which makes no
    events).  The flange is pushed by ``-f``; a negative ``f_nominal`` with
    ``ForceDirection = false`` is an air drag.
    """

    modelica_name = "Modelica.Mechanics.Translational.Sources.QuadraticSpeedDependentForce"

    def equations(self):
        ratio = self.v / self.v_nominal
        if self.ForceDirection:
            return [Eq(self.f, -self.f_nominal * ratio ** 2)]
        return [Eq(self.f, -self.f_nominal * smooth(1, If(self.v >= 0, ratio ** 2, -ratio ** 2)))]


class InverseSpeedDependentForce(_SpeedDependentForce):
    """Force inversely proportional to the speed (Modelica.Mechanics.Translational.Sources.InverseSpeedDependentForce).

    A constant-power characteristic, regularized below ``v0``:

    * ``ForceDirection``: ``f = -f_nominal*v_nominal/v0`` if ``|v| < v0``,
      else ``f = -f_nominal*v_nominal/|v|``;
    * otherwise: ``f = -f_nominal*v/v0`` if ``|v| < v0``, else
      ``f = -f_nominal*v_nominal/v``.

    The switch at ``|v| = v0`` is a state event.  (The MSL writes
    ``v/v0`` in the second case, not ``v_nominal*v/v0``, so that branch is
    continuous only for ``v_nominal = v0``; kept as is.)
    """

    modelica_name = "Modelica.Mechanics.Translational.Sources.InverseSpeedDependentForce"

    v0 = Parameter(0.1, unit="m/s", min=EPS, description="Regularization below v0")

    def equations(self):
        slow = sp.Abs(self.v) < self.v0
        if self.ForceDirection:
            law = If(slow, -self.f_nominal * self.v_nominal / self.v0,
                     -self.f_nominal * self.v_nominal / sp.Abs(self.v))
        else:
            law = If(slow, -self.f_nominal * self.v / self.v0, -self.f_nominal * self.v_nominal / self.v)
        return [Eq(self.f, law)]


class SignForce(PartialForce):
    """Constant force changing its sign with the speed (Modelica.Mechanics.Translational.Sources.SignForce).

    ``f = -f_nominal*sign_reg(v)`` with ``v = der(s)`` and ``sign_reg`` the
    sign function smoothed below ``v0`` as
    :func:`acausal.library.blocks.types.regularized_sign` says
    (``reg``: Exp, the default, Sine, Linear or Cosine).  A positive
    ``f_nominal`` drives the flange in the direction it moves; a negative
    one is a (regularized) Coulomb friction.
    """

    modelica_name = "Modelica.Mechanics.Translational.Sources.SignForce"

    f_nominal = Parameter(None, unit="N", description="Nominal force (if negative, force is acting as load)")
    reg = Parameter(Regularization.Exp, structural=True, description="Type of regularization")
    v0 = Parameter(0.1, unit="m/s", min=EPS, description="Regularization below v0")
    v = Variable(unit="m/s", description="Velocity of flange with respect to support (= der(s))")

    def equations(self):
        return [
            Eq(self.v, der(self.s)),
            Eq(self.f, -self.f_nominal * regularized_sign(self, self.v, self.v0, self.reg)),
        ]


class EddyCurrentForce(PartialForce, PartialElementaryConditionalHeatPort):
    """Simple translational eddy current brake (Modelica.Mechanics.Translational.Sources.EddyCurrentForce).

    The force of an eddy current brake grows linearly at low speed, peaks at
    ``v_nominal`` and falls off above it::

        v_normalized = v/(v_nominal*(1 + alpha*(TheatPort - TRef)))
        f = 2*f_nominal*excitation^2*v_normalized/(1 + v_normalized^2)
        lossPower = f*v

    with ``v = der(s)``, ``alpha = alpha20/(1 + alpha20*(TRef - 293.15))``
    (the temperature coefficient ``alpha20`` given at 20 degC, converted to
    ``TRef``, as Modelica.Electrical.Machines.Thermal.linearTemperatureDependency
    does) and ``excitation`` the optional input (``useExcitationInput``) or
    ``constantExcitation``.  ``f = flange.f``, so the flange is always braked;
    at ``TheatPort = TRef`` and full excitation, ``|f| = f_nominal`` at
    ``|v| = v_nominal``, its maximum.  The temperature is the optional heat
    port's (``useHeatPort``) or the parameter ``T``; the loss power leaves
    through the heat port.
    """

    modelica_name = "Modelica.Mechanics.Translational.Sources.EddyCurrentForce"

    useExcitationInput = Parameter(False, structural=True,  # noqa: N815 - Modelica name
                                   description="Enable signal input for excitation")
    constantExcitation = Parameter(1.0, description="Excitation=1 to reach maximum force")  # noqa: N815
    f_nominal = Parameter(None, unit="N", description="Constant maximum force (always braking)")
    v_nominal = Parameter(None, unit="m/s", min=EPS,
                          description="Nominal speed (leads to maximum force) at reference temperature")
    TRef = Parameter(293.15, unit="K", description="Reference temperature")
    alpha20 = Parameter(0.0, unit="1/K", description="Temperature coefficient of material")
    v = Variable(unit="m/s", description="Velocity of flange with respect to support (= der(s))")
    v_normalized = Variable(description="Relative speed v/v_nominal")
    excitation = RealInput(condition="useExcitationInput", description="Excitation")
    excitationInternal = Variable(description="Excitation (protected)")  # noqa: N815

    def equations(self):
        alpha_ref = self.alpha20 / (1 + self.alpha20 * (self.TRef - 293.15))
        v_scale = self.v_nominal * (1 + alpha_ref * (self.TheatPort - self.TRef))
        excitation = self.excitation if self.useExcitationInput else self.constantExcitation
        return [
            Eq(self.excitationInternal, excitation),
            Eq(self.v, der(self.s)),
            Eq(self.v_normalized, self.v / v_scale),
            Eq(self.f, 2 * self.f_nominal * self.excitationInternal ** 2 * self.v_normalized
               / (1 + self.v_normalized ** 2)),
            Eq(self.lossPower, self.f * self.v),
        ]


# --------------------------------------------------------------------------
# motion


def _preferred_unless_exact(component: Component) -> StateSelect:
    """stateSelect of the filter states: prefer when filtering, default when exact."""
    return StateSelect.default if component.exact else StateSelect.prefer


class Position(PartialElementaryOneFlangeAndSupport2):
    """Flange moved along a reference position (Modelica.Mechanics.Translational.Sources.Position).

    ``s = flange.s - s_support`` follows the input ``s_ref``:

    * ``exact = True``: ``s = s_ref`` exactly (``v = a = 0`` are dummies);
      a mass on the flange then needs the second derivative of ``s_ref``,
      which index reduction takes from the input's equations.
    * ``exact = False`` (default): ``s_ref`` through a critically damped
      second-order (Bessel) filter of cut-off ``w_crit = 2*pi*f_crit``::

          v = der(s), a = der(v)
          a = ((s_ref - s)*w_crit - af*v)*(w_crit/bf),  af = 1.3617, bf = 0.6180

      i.e. ``s = s_ref/(1 + (af/w_crit) p + (bf/w_crit^2) p^2)``, with
      the initial equation ``s = s_ref``; ``v`` starts at its start value.
    """

    modelica_name = "Modelica.Mechanics.Translational.Sources.Position"

    #: s coefficient of the Bessel filter
    af = 1.3617
    #: s^2 coefficient of the Bessel filter
    bf = 0.6180

    exact = Parameter(False, structural=True,
                      description="Is true/false for exact treatment/filtering of the input signal, respectively")
    f_crit = Parameter(50.0, unit="Hz", description="If exact=false, critical frequency of filter to filter input signal")
    s = Variable(unit="m", state_select=_preferred_unless_exact,
                 description="Distance between flange and support (= flange.s - support.s)")
    v = Variable(start=0.0, unit="m/s", state_select=_preferred_unless_exact,
                 description="If exact=false, absolute velocity of flange else dummy")
    a = Variable(start=0.0, unit="m/s2", description="If exact=false, absolute acceleration of flange else dummy")
    s_ref = RealInput(unit="m", description="Reference position of flange as input signal")

    def equations(self):
        if self.exact:
            return [Eq(self.s, self.s_ref), Eq(self.v, 0), Eq(self.a, 0)]
        w_crit = 2 * sp.pi * self.f_crit
        return [
            Eq(self.v, der(self.s)),
            Eq(self.a, der(self.v)),
            Eq(self.a, ((self.s_ref - self.s) * w_crit - self.af * self.v) * (w_crit / self.bf)),
        ]

    def initial_equations(self):
        return [] if self.exact else [Eq(self.s, self.s_ref)]


class Speed(PartialElementaryOneFlangeAndSupport2):
    """Flange moved at a reference speed (Modelica.Mechanics.Translational.Sources.Speed).

    ``v = der(s)`` follows the input ``v_ref``; ``s`` starts at 0 (fixed):

    * ``exact = True``: ``v = v_ref`` (``a = 0`` is a dummy);
    * ``exact = False`` (default): first-order filter of cut-off
      ``w_crit = 2*pi*f_crit``, ``a = der(v) = (v_ref - v)*w_crit``, with the
      initial equation ``v = v_ref``.
    """

    modelica_name = "Modelica.Mechanics.Translational.Sources.Speed"

    exact = Parameter(False, structural=True,
                      description="Is true/false for exact treatment/filtering of the input signal, respectively")
    f_crit = Parameter(50.0, unit="Hz", description="If exact=false, critical frequency of filter to filter input signal")
    s = Variable(start=0.0, fixed=True, unit="m", state_select=StateSelect.prefer,
                 description="Distance between flange and support (= flange.s - support.s)")
    v = Variable(unit="m/s", state_select=_preferred_unless_exact, description="Absolute velocity of flange")
    a = Variable(unit="m/s2", description="If exact=false, absolute acceleration of flange else dummy")
    v_ref = RealInput(unit="m/s", description="Reference speed of flange as input signal")

    def equations(self):
        if self.exact:
            return [Eq(self.v, der(self.s)), Eq(self.v, self.v_ref), Eq(self.a, 0)]
        return [
            Eq(self.v, der(self.s)),
            Eq(self.a, der(self.v)),
            Eq(self.a, (self.v_ref - self.v) * (2 * sp.pi * self.f_crit)),
        ]

    def initial_equations(self):
        return [] if self.exact else [Eq(self.v, self.v_ref)]


class Accelerate(PartialElementaryOneFlangeAndSupport2):
    """Flange moved with a reference acceleration (Modelica.Mechanics.Translational.Sources.Accelerate).

    ``v = der(s)``, ``a = der(v)``, ``a = a_ref``; ``s`` and ``v`` start at
    0 (both fixed), so for a constant input ``s = a_ref*t^2/2``.
    """

    modelica_name = "Modelica.Mechanics.Translational.Sources.Accelerate"

    s = Variable(start=0.0, fixed=True, unit="m", state_select=StateSelect.prefer,
                 description="Distance between flange and support (= flange.s - support.s)")
    v = Variable(start=0.0, fixed=True, unit="m/s", state_select=StateSelect.prefer,
                 description="Absolute velocity of flange")
    a = Variable(unit="m/s2", description="Absolute acceleration of flange")
    a_ref = RealInput(unit="m/s2", description="Absolute acceleration of flange as input signal")

    def equations(self):
        return [Eq(self.v, der(self.s)), Eq(self.a, der(self.v)), Eq(self.a, self.a_ref)]


#: What to do when a model needs the third derivative of a Move source's position.
_MOVE_HINT = ("Move's inputs give the position and its first two derivatives only (u[1], u[2], u[3]); "
              "no equation may need der() of the flange's acceleration")


class Move(VectorBlock, PartialElementaryOneFlangeAndSupport2):
    """Flange moved by given position, speed and acceleration signals (Modelica.Mechanics.Translational.Sources.Move).

    ``s = u[1]`` where the input ``u[2]`` is taken as ``der(u[1])`` and
    ``u[3]`` as ``der(u[2])``: when index reduction differentiates the
    position, it uses ``u[2]`` and ``u[3]`` instead of differentiating the
    inputs (:func:`acausal.prescribed`, the MSL function ``position`` with
    its derivative annotations); a model that needs a third derivative is
    refused with a StructuralError.  The three signals must be consistent;
    nothing checks that.
    """

    modelica_name = "Modelica.Mechanics.Translational.Sources.Move"

    @classmethod
    def arrays(cls, value):
        return {"u": (3, lambda i: RealInput(description="Position, velocity and acceleration of flange "
                                                         "as input signals"))}

    def equations(self):
        u1, u2, u3 = self.vector("u")
        return [Eq(self.s, prescribed(u1, u2, u3, name=f"{where(self)}.s", hint=_MOVE_HINT))]


class ConstantSpeed(PartialForce):
    """Flange moving at a constant speed, whatever the force (Modelica.Mechanics.Translational.Sources.ConstantSpeed).

    ``v = der(s) = v_fixed`` (speed relative to the support).
    """

    modelica_name = "Modelica.Mechanics.Translational.Sources.ConstantSpeed"

    v_fixed = Parameter(None, unit="m/s", description="Fixed speed (if negative, force is acting as load)")
    v = Variable(unit="m/s", description="Velocity of flange with respect to support (= der(s))")

    def equations(self):
        return [Eq(self.v, der(self.s)), Eq(self.v, self.v_fixed)]
