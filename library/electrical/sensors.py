"""Analog electrical sensors (Modelica.Electrical.Analog.Sensors).

Ideal sensors: the voltage path draws no current, the current path has no
voltage drop, so a sensor never changes the circuit it measures.
"""

from __future__ import annotations

from acausal.language import Component, Eq, RealOutput
from acausal.components.electrical import NegativePin, PositivePin
from acausal.library.blocks.math import Product

__all__ = ["PotentialSensor", "VoltageSensor", "CurrentSensor", "PowerSensor", "MultiSensor"]


class PotentialSensor(Component):
    """Sensor to measure the potential (Modelica.Electrical.Analog.Sensors.PotentialSensor).

    ``phi = p.v``, ``p.i = 0``.
    """

    modelica_name = "Modelica.Electrical.Analog.Sensors.PotentialSensor"

    p = PositivePin(description="Pin to be measured")
    phi = RealOutput(unit="V", description="Absolute voltage potential as output signal")

    def equations(self):
        return [Eq(self.p.i, 0), Eq(self.phi, self.p.v)]


class VoltageSensor(Component):
    """Sensor to measure the voltage between two pins (Modelica.Electrical.Analog.Sensors.VoltageSensor).

    ``v = p.v - n.v``, no current through the sensor.
    """

    modelica_name = "Modelica.Electrical.Analog.Sensors.VoltageSensor"

    p = PositivePin(description="Positive pin")
    n = NegativePin(description="Negative pin")
    v = RealOutput(unit="V", description="Voltage between pin p and n (= p.v - n.v) as output signal")

    def equations(self):
        return [Eq(self.p.i, 0), Eq(self.n.i, 0), Eq(self.v, self.p.v - self.n.v)]


class CurrentSensor(Component):
    """Sensor to measure the current in a branch (Modelica.Electrical.Analog.Sensors.CurrentSensor).

    ``i = p.i = -n.i``, no voltage drop (``p.v = n.v``).
    """

    modelica_name = "Modelica.Electrical.Analog.Sensors.CurrentSensor"

    p = PositivePin(description="Positive pin")
    n = NegativePin(description="Negative pin")
    i = RealOutput(unit="A", description="Current in the branch from p to n as output signal")

    def equations(self):
        return [Eq(self.p.v, self.n.v), Eq(self.p.i, self.i), Eq(self.n.i, -self.i)]


class PowerSensor(Component):
    """Sensor to measure the power (Modelica.Electrical.Analog.Sensors.PowerSensor).

    As the MSL builds it: a VoltageSensor ``voltageSensor`` between ``pv``
    and ``nv``, a CurrentSensor ``currentSensor`` between ``pc`` and ``nc``
    and a Product ``product`` of their readings, ``power = v*i``.
    """

    modelica_name = "Modelica.Electrical.Analog.Sensors.PowerSensor"

    pc = PositivePin(description="Positive pin, current path")
    nc = NegativePin(description="Negative pin, current path")
    pv = PositivePin(description="Positive pin, voltage path")
    nv = NegativePin(description="Negative pin, voltage path")
    power = RealOutput(unit="W", description="Instantaneous power as output signal")

    def build(self) -> None:
        self.voltageSensor = VoltageSensor()  # noqa: N815 - Modelica name
        self.currentSensor = CurrentSensor()  # noqa: N815 - Modelica name
        self.product = Product()
        self.connect(self.pv, self.voltageSensor.p)
        self.connect(self.voltageSensor.n, self.nv)
        self.connect(self.pc, self.currentSensor.p)
        self.connect(self.currentSensor.n, self.nc)
        self.connect(self.currentSensor.i, self.product.u2)
        self.connect(self.voltageSensor.v, self.product.u1)

    def equations(self):
        # the MSL connects product.y to power; an inner output to the sensor's own output is
        # the same flat equation
        return [Eq(self.power, self.product.y)]


class MultiSensor(Component):
    """Sensor to measure current, voltage and power (Modelica.Electrical.Analog.Sensors.MultiSensor).

    Current path ``pc``-``nc`` without voltage drop (``i = pc.i``), voltage
    path ``pv``-``nv`` without current (``v = pv.v - nv.v``), ``power = v*i``.
    """

    modelica_name = "Modelica.Electrical.Analog.Sensors.MultiSensor"

    pc = PositivePin(description="Positive pin, current path")
    nc = NegativePin(description="Negative pin, current path")
    pv = PositivePin(description="Positive pin, voltage path")
    nv = NegativePin(description="Negative pin, voltage path")
    i = RealOutput(unit="A", description="Current as output signal")
    v = RealOutput(unit="V", description="Voltage as output signal")
    power = RealOutput(unit="W", description="Instantaneous power as output signal")

    def equations(self):
        return [Eq(self.pc.i + self.nc.i, 0), Eq(self.pc.v - self.nc.v, 0),
                Eq(self.pv.i, 0), Eq(self.nv.i, 0),
                Eq(self.i, self.pc.i), Eq(self.v, self.pv.v - self.nv.v),
                Eq(self.power, self.v * self.i)]
