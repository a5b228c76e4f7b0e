"""Rotational sources (Modelica.Mechanics.Rotational.Sources).

Torque sources (an input or a law of the speed relative to the support) and
motion sources (a flange forced to follow an angle, speed or acceleration).
All of them have a flange and an optional support (``useSupport``); a
disabled support is the grounded housing, ``phi_support = 0``.
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
from acausal.components.checks import check_positive, where
from acausal.components.declarations import VectorBlock
from acausal.components.rotational import (
    EPS,
    PartialElementaryOneFlangeAndSupport2,
    PartialTorque,
    PartialTwoFlanges,
)
from acausal.components.thermal import PartialElementaryConditionalHeatPort
from acausal.library.blocks.types import Regularization, regularization, regularized_sign

__all__ = [
    "Regularization",
    "Position",
    "Speed",
    "Accelerate",
    "Move",
    "Torque",
    "Torque2",
    "ConstantTorque",
    "ConstantSpeed",
    "TorqueStep",
    "LinearSpeedDependentTorque",
    "QuadraticSpeedDependentTorque",
    "InverseSpeedDependentTorque",
    "SignTorque",
    "EddyCurrentTorque",
]


def _state_select(component: Component) -> StateSelect:
    # the filtered motion sources want their own phi and w as states; the exact
    # ones leave the choice to index reduction (their w and a are dummies)
    return StateSelect.default if component.exact else StateSelect.prefer


_F_CRIT_HINT = ("f_crit is the cut-off frequency of the filter smoothing the reference signal; "
                "choose it above the essential frequencies of the signal (default 50 Hz)")


# --------------------------------------------------------------------------
# motion sources
# --------------------------------------------------------------------------


class Position(PartialElementaryOneFlangeAndSupport2):
    """Flange forced to follow a reference angle (Modelica.Mechanics.Rotational.Sources.Position).

    ``phi = flange.phi - phi_support`` is the angle relative to the support.

    * ``exact = True``: ``phi = phi_ref``; index reduction differentiates the
      input twice, so it must come from a twice differentiable signal.
      ``w = 0`` and ``a = 0`` are dummies.
    * ``exact = False`` (default): the reference is smoothed by a
      second-order Bessel filter with cut-off ``w_crit = 2*pi*f_crit``, whose
      second derivative drives the flange::

          w = der(phi),  a = der(w),
          a = ((phi_ref - phi)*w_crit - af*w)*(w_crit/bf),  af = 1.3617, bf = 0.6180

      that is ``phi/phi_ref = 1/(1 + (af/w_crit)*s + (bf/w_crit^2)*s^2)``
      (natural frequency ``w_crit/sqrt(bf)``, damping ratio
      ``af/(2*sqrt(bf))`` = 0.866, a step overshoots by 0.4 %), started on the
      reference: initial equation ``phi = phi_ref``.

    Like the MSL, the filter fixes only ``phi`` initially; Modelica tools take
    ``w`` from its start value (0).  acausal does not fill in start values of
    unfixed states, so give ``w=dict(fixed=True)`` (or another initial
    condition) to start the filter at rest.
    """

    modelica_name = "Modelica.Mechanics.Rotational.Sources.Position"

    #: s coefficient of the Bessel filter (MSL constant af)
    af = 1.3617
    #: s^2 coefficient of the Bessel filter (MSL constant bf)
    bf = 0.6180

    exact = Parameter(False, structural=True,
                      description="Is true/false for exact treatment/filtering of the input signal, respectively")
    f_crit = Parameter(50.0, unit="Hz",
                       description="If exact=false, critical frequency of filter to filter input signal")
    phi = Variable(unit="rad", state_select=_state_select,
                   description="Rotation angle of flange with respect to support")
    w = Variable(start=0.0, unit="rad/s", state_select=_state_select,
                 description="If exact=false, Angular velocity of flange with respect to support else dummy")
    a = Variable(start=0.0, unit="rad/s2",
                 description="If exact=false, Angular acceleration of flange with respect to support else dummy")
    phi_ref = RealInput(unit="rad", description="Reference angle of flange with respect to support as input signal")

    def build(self) -> None:
        check_positive(self, "f_crit", _F_CRIT_HINT)

    def initial_equations(self):
        if self.exact:
            return []
        return [Eq(self.phi, self.phi_ref)]

    def equations(self):
        eqs = [Eq(self.phi, self.flange.phi - self.phi_support)]
        if self.exact:
            return eqs + [Eq(self.phi, self.phi_ref), Eq(self.w, 0), Eq(self.a, 0)]
        w_crit = 2 * sp.pi * self.f_crit
        return eqs + [
            Eq(self.w, der(self.phi)),
            Eq(self.a, der(self.w)),
            Eq(self.a, ((self.phi_ref - self.phi) * w_crit - self.af * self.w) * (w_crit / self.bf)),
        ]


class Speed(PartialElementaryOneFlangeAndSupport2):
    """Flange forced to follow a reference angular velocity (Modelica.Mechanics.Rotational.Sources.Speed).

    ``phi = flange.phi - phi_support`` (start 0, fixed) and ``w = der(phi)``.

    * ``exact = True``: ``w = w_ref``; index reduction differentiates the
      input once.  ``a = 0`` is a dummy.
    * ``exact = False`` (default): a first-order filter with cut-off
      ``w_crit = 2*pi*f_crit``, ``a = der(w) = (w_ref - w)*w_crit``, started on
      the reference (initial equation ``w = w_ref``).
    """

    modelica_name = "Modelica.Mechanics.Rotational.Sources.Speed"

    exact = Parameter(False, structural=True,
                      description="Is true/false for exact treatment/filtering of the input signal, respectively")
    f_crit = Parameter(50.0, unit="Hz",
                       description="If exact=false, critical frequency of filter to filter input signal")
    phi = Variable(start=0.0, fixed=True, unit="rad", state_select=StateSelect.prefer,
                   description="Rotation angle of flange with respect to support")
    w = Variable(unit="rad/s", state_select=_state_select,
                 description="Angular velocity of flange with respect to support")
    a = Variable(unit="rad/s2",
                 description="If exact=false, angular acceleration of flange with respect to support else dummy")
    w_ref = RealInput(unit="rad/s",
                      description="Reference angular velocity of flange with respect to support as input signal")

    def build(self) -> None:
        check_positive(self, "f_crit", _F_CRIT_HINT)

    def initial_equations(self):
        return [] if self.exact else [Eq(self.w, self.w_ref)]

    def equations(self):
        eqs = [Eq(self.phi, self.flange.phi - self.phi_support), Eq(self.w, der(self.phi))]
        if self.exact:
            return eqs + [Eq(self.w, self.w_ref), Eq(self.a, 0)]
        w_crit = 2 * sp.pi * self.f_crit
        return eqs + [Eq(self.a, der(self.w)), Eq(self.a, (self.w_ref - self.w) * w_crit)]


class Accelerate(PartialElementaryOneFlangeAndSupport2):
    """Flange forced to move with a given angular acceleration (Modelica.Mechanics.Rotational.Sources.Accelerate).

    ``phi = flange.phi - phi_support``, ``w = der(phi)``, ``a = der(w)`` and
    ``a = a_ref``; ``phi`` and ``w`` start at 0 (fixed), so they are the
    integrals of the input.
    """

    modelica_name = "Modelica.Mechanics.Rotational.Sources.Accelerate"

    phi = Variable(start=0.0, fixed=True, unit="rad", state_select=StateSelect.prefer,
                   description="Rotation angle of flange with respect to support")
    w = Variable(start=0.0, fixed=True, unit="rad/s", state_select=StateSelect.prefer,
                 description="Angular velocity of flange with respect to support")
    a = Variable(unit="rad/s2", description="Angular acceleration of flange with respect to support")
    a_ref = RealInput(unit="rad/s2",
                      description="Absolute angular acceleration of flange with respect to support as input signal")

    def equations(self):
        return [
            Eq(self.phi, self.flange.phi - self.phi_support),
            Eq(self.w, der(self.phi)),
            Eq(self.a, der(self.w)),
            Eq(self.a, self.a_ref),
        ]


#: What to do when a model needs the third derivative of a Move source's angle.
_MOVE_HINT = ("Move's inputs give the angle and its first two derivatives only (u[1], u[2], u[3]); "
              "no equation may need der() of the flange's acceleration")


class Move(VectorBlock, PartialElementaryOneFlangeAndSupport2):
    """Flange forced to follow a given angle, speed and acceleration (Modelica.Mechanics.Rotational.Sources.Move).

    ``phi = flange.phi - phi_support = u[1]``; where index reduction needs the
    derivatives of ``phi`` it takes ``der(phi) = u[2]`` and ``der(der(phi)) =
    u[3]`` instead of differentiating the inputs (:func:`acausal.prescribed`,
    the MSL function ``position`` with its derivative annotations); a model
    that needs a third derivative is refused with a StructuralError.  The
    three inputs are meant to be consistent (``u[2]`` the derivative of
    ``u[1]``, ``u[3]`` of ``u[2]``), but need not be (e.g. an angle with zero
    speed and acceleration to compute position-dependent terms only).
    Connect to ``move.u[1]``.
    """

    modelica_name = "Modelica.Mechanics.Rotational.Sources.Move"

    phi = Variable(unit="rad", description="Rotation angle of flange with respect to support")

    _input_descriptions = ("Angle of flange with respect to support as input signal",
                           "Angular velocity of flange with respect to support as input signal",
                           "Angular acceleration of flange with respect to support as input signal")

    @classmethod
    def arrays(cls, value):
        return {"u": (3, lambda i: RealInput(description=cls._input_descriptions[i - 1]))}

    def equations(self):
        angle, speed, acceleration = self.vector("u")
        return [
            Eq(self.phi, self.flange.phi - self.phi_support),
            Eq(self.phi, prescribed(angle, speed, acceleration, name=f"{where(self)}.phi", hint=_MOVE_HINT)),
        ]


# --------------------------------------------------------------------------
# torque sources
# --------------------------------------------------------------------------


class Torque(PartialElementaryOneFlangeAndSupport2):
    """Input signal acting as external torque on a flange (Modelica.Mechanics.Rotational.Sources.Torque).

    ``flange.tau = -tau``: a positive input accelerates the flange; with
    ``useSupport`` the reaction torque ``tau`` acts on the support.
    """

    modelica_name = "Modelica.Mechanics.Rotational.Sources.Torque"

    tau = RealInput(unit="N.m", description="Accelerating torque acting at flange (= -flange.tau)")

    def equations(self):
        return [Eq(self.flange.tau, -self.tau)]


class Torque2(PartialTwoFlanges):
    """Input signal acting as torque on two flanges (Modelica.Mechanics.Rotational.Sources.Torque2).

    ``flange_a.tau = tau`` and ``flange_b.tau = -tau``: a positive ``tau``
    accelerates flange_b and decelerates flange_a (an actuator between two
    shafts, no housing).
    """

    modelica_name = "Modelica.Mechanics.Rotational.Sources.Torque2"

    tau = RealInput(unit="N.m", description="Torque driving the two flanges (a positive value accelerates the flange)")

    def equations(self):
        return [Eq(self.flange_a.tau, self.tau), Eq(self.flange_b.tau, -self.tau)]


class ConstantTorque(PartialTorque):
    """Constant torque, not dependent on speed (Modelica.Mechanics.Rotational.Sources.ConstantTorque).

    ``tau = tau_constant`` with ``tau = -flange.tau`` (a negative value acts
    as a load); ``w = der(phi)`` is the speed relative to the support.
    """

    modelica_name = "Modelica.Mechanics.Rotational.Sources.ConstantTorque"

    tau_constant = Parameter(None, unit="N.m",
                             description="Constant torque (if negative, torque is acting as load in positive "
                                         "direction of rotation)")
    tau = Variable(unit="N.m", description="Accelerating torque acting at flange (= -flange.tau)")
    w = Variable(unit="rad/s", description="Angular velocity of flange with respect to support (= der(phi))")

    def equations(self):
        return [
            Eq(self.w, der(self.phi)),
            Eq(self.tau, -self.flange.tau),
            Eq(self.tau, self.tau_constant),
        ]


class ConstantSpeed(PartialTorque):
    """Constant speed, not dependent on torque (Modelica.Mechanics.Rotational.Sources.ConstantSpeed).

    ``w = der(phi) = w_fixed``, ``phi`` the angle relative to the support.
    """

    modelica_name = "Modelica.Mechanics.Rotational.Sources.ConstantSpeed"

    w = Variable(unit="rad/s", description="Angular velocity of flange with respect to support (= der(phi))")
    w_fixed = Parameter(None, unit="rad/s", description="Fixed speed")

    def equations(self):
        return [Eq(self.w, der(self.phi)), Eq(self.w, self.w_fixed)]


class TorqueStep(PartialTorque):
    """Constant torque with a step at ``startTime`` (Modelica.Mechanics.Rotational.Sources.TorqueStep).

    ``tau = offsetTorque + (0 if time < startTime else stepTorque)`` with
    ``tau = -flange.tau``; the step is a time event.
    """

    modelica_name = "Modelica.Mechanics.Rotational.Sources.TorqueStep"

    stepTorque = Parameter(1.0, unit="N.m",
                           description="Height of torque step (if negative, torque is acting as load)")  # noqa: N815
    offsetTorque = Parameter(0.0, unit="N.m", description="Offset of torque")  # noqa: N815
    startTime = Parameter(0.0, unit="s", description="Torque = offset for time < startTime")  # noqa: N815
    tau = Variable(unit="N.m", description="Accelerating torque acting at flange (= -flange.tau)")

    def equations(self):
        return [
            Eq(self.tau, -self.flange.tau),
            Eq(self.tau, self.offsetTorque + If(time < self.startTime, 0, self.stepTorque)),
        ]


class _SpeedDependentTorque(PartialTorque):
    """Declarations and ``w = der(phi)``, ``tau = -flange.tau`` shared by the speed-dependent torques."""

    tau_nominal = Parameter(None, unit="N.m",
                            description="Nominal torque (if negative, torque is acting as load in positive "
                                        "direction of rotation)")
    TorqueDirection = Parameter(True, structural=True,  # noqa: N815 - Modelica name
                                description="Same direction of torque in both directions of rotation")
    w_nominal = Parameter(None, unit="rad/s", min=EPS, description="Nominal speed")
    w = Variable(unit="rad/s", description="Angular velocity of flange with respect to support (= der(phi))")
    tau = Variable(unit="N.m", description="Accelerating torque acting at flange (= -flange.tau)")

    def equations(self):
        return [Eq(self.w, der(self.phi)), Eq(self.tau, -self.flange.tau)]


class LinearSpeedDependentTorque(_SpeedDependentTorque):
    """Torque linear in the speed (Modelica.Mechanics.Rotational.Sources.LinearSpeedDependentTorque).

    ``tau = tau_nominal*abs(w/w_nominal)`` with ``TorqueDirection`` (the
    same direction for both directions of rotation), else ``tau =
    tau_nominal*w/w_nominal``.  ``tau = -flange.tau``, ``w = der(phi)``.
    """

    modelica_name = "Modelica.Mechanics.Rotational.Sources.LinearSpeedDependentTorque"

    def equations(self):
        ratio = self.w / self.w_nominal
        return [Eq(self.tau, self.tau_nominal * (sp.Abs(ratio) if self.TorqueDirection else ratio))]


class QuadraticSpeedDependentTorque(_SpeedDependentTorque):
    """Torque quadratic in the speed (Modelica.Mechanics.Rotational.Sources.QuadraticSpeedDependentTorque).

    ``tau = tau_nominal*(w/w_nominal)^2`` with ``TorqueDirection``, else
    ``tau = tau_nominal*sign(w)*(w/w_nominal)^2`` (written with ``smooth(1,
    ...)``: it is continuously differentiable, so no event).  ``tau =
    -flange.tau``, ``w = der(phi)``.
    """

    modelica_name = "Modelica.Mechanics.Rotational.Sources.QuadraticSpeedDependentTorque"

    def equations(self):
        square = (self.w / self.w_nominal) ** 2
        if self.TorqueDirection:
            return [Eq(self.tau, self.tau_nominal * square)]
        return [Eq(self.tau, self.tau_nominal * smooth(1, If(self.w >= 0, square, -square)))]


class InverseSpeedDependentTorque(_SpeedDependentTorque):
    """Torque inversely proportional to the speed (Modelica.Mechanics.Rotational.Sources.InverseSpeedDependentTorque).

    A constant-power characteristic, limited below the speed ``w0``::

        TorqueDirection:      tau = tau_nominal*w_nominal/w0        if abs(w) < w0
                              tau = tau_nominal*w_nominal/abs(w)    otherwise
        not TorqueDirection:  tau = tau_nominal*w/w0                if abs(w) < w0
                              tau = tau_nominal*w_nominal/w         otherwise

    ``tau = -flange.tau``, ``w = der(phi)``; the switch at ``abs(w) = w0``
    is a state event.  As in MSL 4.1.0, the second law jumps at ``abs(w) =
    w0`` unless ``w_nominal = w0``.
    """

    modelica_name = "Modelica.Mechanics.Rotational.Sources.InverseSpeedDependentTorque"

    w0 = Parameter(0.1, unit="rad/s", min=EPS, description="Regularization below w0")

    def equations(self):
        slow = sp.Abs(self.w) < self.w0
        if self.TorqueDirection:
            law = If(slow, self.tau_nominal * self.w_nominal / self.w0,
                     self.tau_nominal * self.w_nominal / sp.Abs(self.w))
        else:
            law = If(slow, self.tau_nominal * self.w / self.w0, self.tau_nominal * self.w_nominal / self.w)
        return [Eq(self.tau, law)]


class SignTorque(PartialTorque):
    """Constant torque changing sign with the speed (Modelica.Mechanics.Rotational.Sources.SignTorque).

    ``tau = tau_nominal*s(w)`` with ``s`` a regularized ``sign(w)``, chosen by
    ``reg``::

        Exp:     s = 2/(1 + exp(-w/(0.01*w0))) - 1
        Sine:    s = sign(w) if abs(w) >= w0 else sin(pi/2*w/w0)            (smooth, no event)
        Linear:  s = sign(w) if abs(w) >= w0 else w/w0
        Cosine:  s = sign(w) if abs(w) >= w0 else sign(w)*(1 - cos(pi/2*w/w0))

    (:func:`acausal.library.blocks.types.regularized_sign`); ``tau =
    -flange.tau``, ``w = der(phi)``.
    """

    modelica_name = "Modelica.Mechanics.Rotational.Sources.SignTorque"

    tau_nominal = Parameter(None, unit="N.m", description="Nominal torque (if negative, torque is acting as load)")
    reg = Parameter(Regularization.Exp, structural=True, description="Type of regularization")
    w0 = Parameter(0.1, unit="rad/s", min=EPS, description="Regularization below w0")
    w = Variable(unit="rad/s", description="Angular velocity of flange with respect to support (= der(phi))")
    tau = Variable(unit="N.m", description="Accelerating torque acting at flange (= -flange.tau)")

    def build(self) -> None:
        regularization(self, self.reg)

    def equations(self):
        shape = regularized_sign(self, self.w, self.w0, self.reg)
        return [Eq(self.w, der(self.phi)), Eq(self.tau, -self.flange.tau), Eq(self.tau, self.tau_nominal * shape)]


class EddyCurrentTorque(PartialTorque, PartialElementaryConditionalHeatPort):
    """Simple model of a rotational eddy current brake (Modelica.Mechanics.Rotational.Sources.EddyCurrentTorque).

    The braking torque (``tau = flange.tau``, positive against positive
    rotation) follows the Kloss-like law of an eddy current brake::

        w = der(phi)
        w_normalized = w/(w_nominal*(1 + alpha*(TheatPort - TRef)))
        alpha = alpha20/(1 + alpha20*(TRef - 293.15))      (alpha20 converted to TRef)
        tau = 2*tau_nominal*excitation^2*w_normalized/(1 + w_normalized^2)
        lossPower = tau*w

    so ``tau`` peaks at ``tau_nominal`` (full excitation) where
    ``w_normalized = 1``; a warmer brake (higher resistance) moves the peak to
    higher speeds.  The whole mechanical power is dissipated
    (``lossPower``, to the optional heat port).  The excitation is
    ``constantExcitation``, or the input ``excitation`` with
    ``useExcitationInput``.
    """

    modelica_name = "Modelica.Mechanics.Rotational.Sources.EddyCurrentTorque"

    useExcitationInput = Parameter(False, structural=True,  # noqa: N815 - Modelica name
                                   description="Enable signal input for excitation")
    constantExcitation = Parameter(1.0, description="Excitation=1 to reach maximum torque")  # noqa: N815
    tau_nominal = Parameter(None, unit="N.m", description="Maximum torque (always braking)")
    w_nominal = Parameter(None, unit="rad/s", min=EPS,
                          description="Nominal speed (leads to maximum torque) at reference temperature")
    TRef = Parameter(293.15, unit="K", description="Reference temperature")
    alpha20 = Parameter(0.0, unit="1/K", description="Temperature coefficient of material")
    tau = Variable(unit="N.m", description="Accelerating torque acting at flange (= flange.tau)")
    w = Variable(unit="rad/s", description="Angular velocity of flange with respect to support (= der(phi))")
    w_normalized = Variable(description="Relative speed w/w_nominal")
    excitation = RealInput(condition="useExcitationInput", description="Excitation")
    excitationInternal = Variable(description="Excitation (protected)")  # noqa: N815

    def equations(self):
        if self.useExcitationInput:
            excitation = [Eq(self.excitation, self.excitationInternal)]
        else:
            excitation = [Eq(self.excitationInternal, self.constantExcitation)]
        # Modelica.Electrical.Machines.Thermal.linearTemperatureDependency(1, TRef, alpha20, TheatPort)
        alpha = self.alpha20 / (1 + self.alpha20 * (self.TRef - 293.15))
        temperature_factor = 1 + alpha * (self.TheatPort - self.TRef)
        return excitation + [
            Eq(self.tau, self.flange.tau),
            Eq(self.w, der(self.phi)),
            Eq(self.w_normalized, self.w / (self.w_nominal * temperature_factor)),
            Eq(self.tau, 2 * self.tau_nominal * self.excitationInternal ** 2 * self.w_normalized
               / (1 + self.w_normalized * self.w_normalized)),
            Eq(self.lossPower, self.tau * self.w),
        ]
