"""Modelica.Electrical.Analog.Sensors: ideal readings in a circuit whose answer is known.

A 12 V source feeds 2 Ohm and 4 Ohm in series (2 A): each sensor's reading
is checked against Ohm's law, and against the circuit without sensors (an
ideal sensor draws no current and drops no voltage).
"""

from __future__ import annotations

import pytest
from library_checks import check_declarations

from acausal import Model, simulate
from acausal.library.electrical import (
    ConstantVoltage,
    CurrentSensor,
    Ground,
    MultiSensor,
    PotentialSensor,
    PowerSensor,
    Resistor,
    VoltageSensor,
)


class Measured(Model):
    """12 V -> current sensor -> power sensor -> multi sensor -> R1 = 2 Ohm -> R2 = 4 Ohm -> ground."""

    def build(self):
        self.source = ConstantVoltage(V=12)
        self.ground = Ground()
        self.R1 = Resistor(R=2)
        self.R2 = Resistor(R=4)
        self.current = CurrentSensor()
        self.power = PowerSensor()
        self.multi = MultiSensor()
        self.potential = PotentialSensor()
        self.voltage = VoltageSensor()
        self.connect(self.source.n, self.ground.p)
        self.connect(self.source.p, self.current.p)
        self.connect(self.current.n, self.power.pc)
        self.connect(self.power.nc, self.multi.pc)
        self.connect(self.multi.nc, self.R1.p)
        self.connect(self.R1.n, self.R2.p)
        self.connect(self.R2.n, self.ground.p)
        # power and multi sensor measure the power into R1: voltage path across R1
        self.connect(self.power.pv, self.R1.p)
        self.connect(self.power.nv, self.R1.n)
        self.connect(self.multi.pv, self.R1.p)
        self.connect(self.multi.nv, self.R1.n)
        self.connect(self.potential.p, self.R1.n)
        self.connect(self.voltage.p, self.R2.p)
        self.connect(self.voltage.n, self.R2.n)


def test_sensor_readings():
    result = simulate(Measured(), stop_time=1, interval=0.5)
    assert result.success, result.message
    assert result.final("current.i") == pytest.approx(2.0, rel=1e-12)
    assert result.final("R1.i") == pytest.approx(2.0, rel=1e-12)       # the sensors take nothing
    assert result.final("potential.phi") == pytest.approx(8.0, rel=1e-12)
    assert result.final("voltage.v") == pytest.approx(8.0, rel=1e-12)
    assert result.final("power.power") == pytest.approx(4.0 * 2.0, rel=1e-12)
    assert result.final("multi.v") == pytest.approx(4.0, rel=1e-12)
    assert result.final("multi.i") == pytest.approx(2.0, rel=1e-12)
    assert result.final("multi.power") == pytest.approx(8.0, rel=1e-12)
    assert result.final("power.power") == pytest.approx(result.final("R1.LossPower"), rel=1e-12)
    # the parts of the power sensor, as the MSL builds it
    assert result.final("power.voltageSensor.v") == pytest.approx(4.0, rel=1e-12)
    assert result.final("power.currentSensor.i") == pytest.approx(2.0, rel=1e-12)
    # no voltage drop along the current paths
    assert result.final("current.p.v") == result.final("multi.nc.v") == pytest.approx(12.0)


@pytest.mark.parametrize("component", [
    PotentialSensor(), VoltageSensor(), CurrentSensor(), PowerSensor(), MultiSensor(),
], ids=lambda c: type(c).__name__)
def test_declarations(component):
    check_declarations(component)
