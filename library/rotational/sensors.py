"""Rotational sensors (Modelica.Mechanics.Rotational.Sensors)."""

from __future__ import annotations

from acausal.language import Eq, RealOutput, Variable, der
from acausal.components.rotational import PartialAbsoluteSensor, PartialRelativeSensor

__all__ = ["AngleSensor", "SpeedSensor", "AccSensor", "TorqueSensor", "RelAngleSensor",
           "RelSpeedSensor", "RelAccSensor", "PowerSensor", "MultiSensor"]


class AngleSensor(PartialAbsoluteSensor):
    """Ideal sensor of the absolute flange angle (Modelica.Mechanics.Rotational.Sensors.AngleSensor).

    ``phi = flange.phi``.
    """

    modelica_name = "Modelica.Mechanics.Rotational.Sensors.AngleSensor"

    phi = RealOutput(unit="rad", description="Absolute angle of flange as output signal")

    def equations(self):
        return [Eq(self.phi, self.flange.phi)]


class SpeedSensor(PartialAbsoluteSensor):
    """Ideal sensor of the absolute angular velocity (Modelica.Mechanics.Rotational.Sensors.SpeedSensor).

    ``w = der(flange.phi)``.
    """

    modelica_name = "Modelica.Mechanics.Rotational.Sensors.SpeedSensor"

    w = RealOutput(unit="rad/s", description="Absolute angular velocity of flange as output signal")

    def equations(self):
        return [Eq(self.w, der(self.flange.phi))]


class AccSensor(PartialAbsoluteSensor):
    """Ideal sensor of the absolute angular acceleration (Modelica.Mechanics.Rotational.Sensors.AccSensor).

    ``a = der(w)``, ``w = der(flange.phi)``.
    """

    modelica_name = "Modelica.Mechanics.Rotational.Sensors.AccSensor"

    w = Variable(unit="rad/s", description="Absolute angular velocity of flange")
    a = RealOutput(unit="rad/s2", description="Absolute angular acceleration of flange as output signal")

    def equations(self):
        return [Eq(self.w, der(self.flange.phi)), Eq(self.a, der(self.w))]


class TorqueSensor(PartialRelativeSensor):
    """Ideal sensor of the torque in a flange (Modelica.Mechanics.Rotational.Sensors.TorqueSensor).

    ``tau = flange_a.tau``, rigid connection.
    """

    modelica_name = "Modelica.Mechanics.Rotational.Sensors.TorqueSensor"

    tau = RealOutput(unit="N.m",
                     description="Torque in flange flange_a and flange_b "
                                 "(tau = flange_a.tau = -flange_b.tau) as output signal")

    def equations(self):
        return [Eq(self.flange_a.phi, self.flange_b.phi), Eq(self.tau, self.flange_a.tau)]


class RelAngleSensor(PartialRelativeSensor):
    """Ideal sensor of the relative angle (Modelica.Mechanics.Rotational.Sensors.RelAngleSensor).

    ``phi_rel = flange_b.phi - flange_a.phi``.
    """

    modelica_name = "Modelica.Mechanics.Rotational.Sensors.RelAngleSensor"

    phi_rel = RealOutput(unit="rad",
                         description="Relative angle between two flanges (= flange_b.phi - flange_a.phi) "
                                     "as output signal")

    def equations(self):
        return [Eq(self.phi_rel, self.flange_b.phi - self.flange_a.phi), Eq(0, self.flange_a.tau)]


class RelSpeedSensor(PartialRelativeSensor):
    """Ideal sensor of the relative angular velocity (Modelica.Mechanics.Rotational.Sensors.RelSpeedSensor).

    ``w_rel = der(flange_b.phi - flange_a.phi)``.
    """

    modelica_name = "Modelica.Mechanics.Rotational.Sensors.RelSpeedSensor"

    w_rel = RealOutput(unit="rad/s",
                       description="Relative angular velocity between two flanges "
                                   "(= der(flange_b.phi) - der(flange_a.phi)) as output signal")
    phi_rel = Variable(unit="rad",
                       description="Relative angle between two flanges (flange_b.phi - flange_a.phi)")

    def equations(self):
        return [
            Eq(self.phi_rel, self.flange_b.phi - self.flange_a.phi),
            Eq(self.w_rel, der(self.phi_rel)),
            Eq(0, self.flange_a.tau),
        ]


class RelAccSensor(PartialRelativeSensor):
    """Ideal sensor of the relative angular acceleration (Modelica.Mechanics.Rotational.Sensors.RelAccSensor).

    ``phi_rel = flange_b.phi - flange_a.phi``, ``w_rel = der(phi_rel)``,
    ``a_rel = der(w_rel)`` and ``0 = flange_a.tau`` (it transmits no torque).
    """

    modelica_name = "Modelica.Mechanics.Rotational.Sensors.RelAccSensor"

    phi_rel = Variable(unit="rad", description="Relative angle between two flanges (flange_b.phi - flange_a.phi)")
    w_rel = Variable(unit="rad/s", description="Relative angular velocity between two flanges")
    a_rel = RealOutput(unit="rad/s2",
                       description="Relative angular acceleration between two flanges as output signal")

    def equations(self):
        return [
            Eq(self.phi_rel, self.flange_b.phi - self.flange_a.phi),
            Eq(self.w_rel, der(self.phi_rel)),
            Eq(self.a_rel, der(self.w_rel)),
            Eq(0, self.flange_a.tau),
        ]


class PowerSensor(PartialRelativeSensor):
    """Ideal sensor of the power through a flange (Modelica.Mechanics.Rotational.Sensors.PowerSensor).

    ``power = flange_a.tau*der(flange_a.phi)``.
    """

    modelica_name = "Modelica.Mechanics.Rotational.Sensors.PowerSensor"

    power = RealOutput(unit="W", description="Power in flange flange_a as output signal")

    def equations(self):
        return [Eq(self.flange_a.phi, self.flange_b.phi),
                Eq(self.power, self.flange_a.tau * der(self.flange_a.phi))]


class MultiSensor(PartialRelativeSensor):
    """Ideal sensor of power, torque and angular speed (Modelica.Mechanics.Rotational.Sensors.MultiSensor).

    Rigid connection of its flanges: ``w = der(flange_a.phi)``, ``tau =
    flange_a.tau`` and ``power = tau*w``.
    """

    modelica_name = "Modelica.Mechanics.Rotational.Sensors.MultiSensor"

    power = RealOutput(unit="W", description="Power in flange flange_a as output signal")
    w = RealOutput(unit="rad/s", description="Absolute angular velocity of flange_a as output signal")
    tau = RealOutput(unit="N.m",
                     description="Torque in flange flange_a and flange_b "
                                 "(tau = flange_a.tau = -flange_b.tau) as output signal")

    def equations(self):
        return [
            Eq(self.flange_a.phi, self.flange_b.phi),
            Eq(self.w, der(self.flange_a.phi)),
            Eq(self.tau, self.flange_a.tau),
            Eq(self.power, self.tau * self.w),
        ]
