"""Translational sensors (Modelica.Mechanics.Translational.Sensors).

Absolute sensors read one flange and take no force (``flange.f = 0``);
relative sensors sit between two flanges and either take no force (position,
speed, acceleration) or join the flanges rigidly and read the force through
them (force, power, multi).
"""

from __future__ import annotations

from acausal.language import Eq, RealOutput, Variable, der
from acausal.components.translational import PartialAbsoluteSensor, PartialRelativeSensor

__all__ = [
    "PositionSensor",
    "SpeedSensor",
    "AccSensor",
    "ForceSensor",
    "RelPositionSensor",
    "RelSpeedSensor",
    "RelAccSensor",
    "PowerSensor",
    "MultiSensor",
]


class PositionSensor(PartialAbsoluteSensor):
    """Ideal sensor of the absolute flange position (Modelica.Mechanics.Translational.Sensors.PositionSensor).

    ``s = flange.s``.
    """

    modelica_name = "Modelica.Mechanics.Translational.Sensors.PositionSensor"

    s = RealOutput(unit="m", description="Absolute position of flange as output signal")

    def equations(self):
        return [Eq(self.s, self.flange.s)]


class SpeedSensor(PartialAbsoluteSensor):
    """Ideal sensor of the absolute flange velocity (Modelica.Mechanics.Translational.Sensors.SpeedSensor).

    ``v = der(flange.s)``.
    """

    modelica_name = "Modelica.Mechanics.Translational.Sensors.SpeedSensor"

    v = RealOutput(unit="m/s", description="Absolute velocity of flange as output signal")

    def equations(self):
        return [Eq(self.v, der(self.flange.s))]


class AccSensor(PartialAbsoluteSensor):
    """Ideal sensor of the absolute flange acceleration (Modelica.Mechanics.Translational.Sensors.AccSensor).

    ``v = der(flange.s)``, ``a = der(v)``.
    """

    modelica_name = "Modelica.Mechanics.Translational.Sensors.AccSensor"

    v = Variable(unit="m/s", description="Absolute velocity of flange")
    a = RealOutput(unit="m/s2", description="Absolute acceleration of flange as output signal")

    def equations(self):
        return [Eq(self.v, der(self.flange.s)), Eq(self.a, der(self.v))]


class ForceSensor(PartialRelativeSensor):
    """Ideal sensor of the force passed between two flanges (Modelica.Mechanics.Translational.Sensors.ForceSensor).

    The flanges are joined rigidly (``flange_a.s = flange_b.s``) and
    ``f = flange_a.f`` (= ``-flange_b.f``).
    """

    modelica_name = "Modelica.Mechanics.Translational.Sensors.ForceSensor"

    f = RealOutput(unit="N",
                   description="Force in flange_a and flange_b (f = flange_a.f = -flange_b.f) as output signal")

    def equations(self):
        return [Eq(self.flange_a.s, self.flange_b.s), Eq(self.flange_a.f, self.f)]


class RelPositionSensor(PartialRelativeSensor):
    """Ideal sensor of the relative position of two flanges (Modelica.Mechanics.Translational.Sensors.RelPositionSensor).

    ``s_rel = flange_b.s - flange_a.s``; no force (``flange_a.f = 0``).
    """

    modelica_name = "Modelica.Mechanics.Translational.Sensors.RelPositionSensor"

    s_rel = RealOutput(unit="m",
                       description="Relative distance between two flanges (= flange_b.s - flange_a.s) "
                                   "as output signal")

    def equations(self):
        return [Eq(self.s_rel, self.flange_b.s - self.flange_a.s), Eq(0, self.flange_a.f)]


class RelSpeedSensor(PartialRelativeSensor):
    """Ideal sensor of the relative velocity of two flanges (Modelica.Mechanics.Translational.Sensors.RelSpeedSensor).

    ``s_rel = flange_b.s - flange_a.s``, ``v_rel = der(s_rel)``; no force.
    """

    modelica_name = "Modelica.Mechanics.Translational.Sensors.RelSpeedSensor"

    s_rel = Variable(unit="m", description="Relative distance between two flanges (flange_b.s - flange_a.s)")
    v_rel = RealOutput(unit="m/s",
                       description="Relative velocity between two flanges (= der(flange_b.s) - der(flange_a.s)) "
                                   "as output signal")

    def equations(self):
        return [
            Eq(self.s_rel, self.flange_b.s - self.flange_a.s),
            Eq(self.v_rel, der(self.s_rel)),
            Eq(0, self.flange_a.f),
        ]


class RelAccSensor(PartialRelativeSensor):
    """Ideal sensor of the relative acceleration of two flanges (Modelica.Mechanics.Translational.Sensors.RelAccSensor).

    ``s_rel = flange_b.s - flange_a.s``, ``v_rel = der(s_rel)``,
    ``a_rel = der(v_rel)``; no force.
    """

    modelica_name = "Modelica.Mechanics.Translational.Sensors.RelAccSensor"

    s_rel = Variable(unit="m", description="Relative distance between two flanges (flange_b.s - flange_a.s)")
    v_rel = Variable(unit="m/s",
                     description="Relative velocity between two flanges (der(flange_b.s) - der(flange_a.s))")
    a_rel = RealOutput(unit="m/s2",
                       description="Relative acceleration between two flanges (= der(v_rel)) as output signal")

    def equations(self):
        return [
            Eq(self.s_rel, self.flange_b.s - self.flange_a.s),
            Eq(self.v_rel, der(self.s_rel)),
            Eq(self.a_rel, der(self.v_rel)),
            Eq(0, self.flange_a.f),
        ]


class PowerSensor(PartialRelativeSensor):
    """Ideal sensor of the power passed between two flanges (Modelica.Mechanics.Translational.Sensors.PowerSensor).

    Rigid connection (``flange_a.s = flange_b.s``);
    ``power = flange_a.f*der(flange_a.s)``.
    """

    modelica_name = "Modelica.Mechanics.Translational.Sensors.PowerSensor"

    power = RealOutput(unit="W", description="Power in flange flange_a as output signal")

    def equations(self):
        return [
            Eq(self.flange_a.s, self.flange_b.s),
            Eq(self.power, self.flange_a.f * der(self.flange_a.s)),
        ]


class MultiSensor(PartialRelativeSensor):
    """Ideal sensor of velocity, force and power at once (Modelica.Mechanics.Translational.Sensors.MultiSensor).

    Rigid connection (``flange_a.s = flange_b.s``); ``f = flange_a.f``,
    ``v = der(flange_a.s)`` and ``power = f*v``.
    """

    modelica_name = "Modelica.Mechanics.Translational.Sensors.MultiSensor"

    power = RealOutput(unit="W", description="Power in flange flange_a as output signal")
    f = RealOutput(unit="N",
                   description="Force in flange_a and flange_b (f = flange_a.f = -flange_b.f) as output signal")
    v = RealOutput(unit="m/s", description="Absolute velocity of flange as output signal")

    def equations(self):
        return [
            Eq(self.flange_a.s, self.flange_b.s),
            Eq(self.f, self.flange_a.f),
            Eq(self.v, der(self.flange_a.s)),
            Eq(self.power, self.f * self.v),
        ]
