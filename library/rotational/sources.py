"""Rotational torque sources (Modelica.Mechanics.Rotational.Sources)."""

from __future__ import annotations

from acausal.language import Eq, If, Parameter, RealInput, Variable, der, time
from acausal.components.rotational import PartialElementaryOneFlangeAndSupport2, PartialTorque

__all__ = ["Torque", "ConstantTorque", "TorqueStep"]


class Torque(PartialElementaryOneFlangeAndSupport2):
    """Input signal acting as external torque on a flange (Modelica.Mechanics.Rotational.Sources.Torque).

    ``flange.tau = -tau``: a positive input accelerates the flange; with
    ``useSupport`` the reaction torque ``tau`` acts on the support.
    """

    tau = RealInput(unit="N.m", description="Accelerating torque acting at flange (= -flange.tau)")

    def equations(self):
        return [Eq(self.flange.tau, -self.tau)]


class ConstantTorque(PartialTorque):
    """Constant torque, not dependent on speed (Modelica.Mechanics.Rotational.Sources.ConstantTorque).

    ``tau = tau_constant`` with ``tau = -flange.tau`` (a negative value acts
    as a load); ``w = der(phi)`` is the speed relative to the support.
    """

    tau_constant = Parameter(None, unit="N.m",
                             description="Constant torque (if negative, torque is acting as load)")
    tau = Variable(unit="N.m", description="Accelerating torque acting at flange (= -flange.tau)")
    w = Variable(unit="rad/s", description="Angular velocity of flange with respect to support (= der(phi))")

    def equations(self):
        return [
            Eq(self.w, der(self.phi)),
            Eq(self.tau, -self.flange.tau),
            Eq(self.tau, self.tau_constant),
        ]


class TorqueStep(PartialTorque):
    """Constant torque with a step at ``startTime`` (Modelica.Mechanics.Rotational.Sources.TorqueStep).

    ``tau = offsetTorque + (0 if time < startTime else stepTorque)`` with
    ``tau = -flange.tau``; the step is a time event.
    """

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
