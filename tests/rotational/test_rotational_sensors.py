"""The rotational sensors read the closed-form motion of an inertia under a constant torque.

A constant torque T drives an inertia J from rest: phi = T t^2/(2J),
w = T t/J, a = T/J, and the cut torque between the source and the inertia
is T.  Each sensor is connected where it measures that motion.
"""

from __future__ import annotations

import numpy as np
import pytest

from acausal import Experiment, Model, simulate
from acausal.library.rotational import (AccSensor, AngleSensor, ConstantTorque, Fixed, Inertia, MultiSensor,
                                        PowerSensor, RelAccSensor, RelAngleSensor, RelSpeedSensor, SpeedSensor,
                                        TorqueSensor)

T, J = 2.0, 0.5


class Measured(Model):
    experiment = Experiment(stop_time=1.0, interval=0.01)

    def build(self):
        self.source = ConstantTorque(tau_constant=T)
        self.torque = TorqueSensor()
        self.power = PowerSensor()
        self.multi = MultiSensor()
        self.inertia = Inertia(J=J, phi=dict(start=0, fixed=True), w=dict(start=0, fixed=True))
        self.angle = AngleSensor()
        self.speed = SpeedSensor()
        self.acc = AccSensor()
        self.ground = Fixed()
        self.relAngle = RelAngleSensor()
        self.relSpeed = RelSpeedSensor()
        self.relAcc = RelAccSensor()
        # source -> torque sensor -> power sensor -> multi sensor -> inertia
        self.connect(self.source.flange, self.torque.flange_a)
        self.connect(self.torque.flange_b, self.power.flange_a)
        self.connect(self.power.flange_b, self.multi.flange_a)
        self.connect(self.multi.flange_b, self.inertia.flange_a)
        for sensor in (self.angle, self.speed, self.acc):
            self.connect(self.inertia.flange_b, sensor.flange)
        for sensor in (self.relAngle, self.relSpeed, self.relAcc):
            self.connect(self.ground.flange, sensor.flange_a)
            self.connect(self.inertia.flange_b, sensor.flange_b)


@pytest.fixture(scope="module")
def result():
    run = simulate(Measured(), rtol=1e-10)
    assert run.success, run.message
    return run


def test_absolute_and_relative_motion_sensors(result):
    t = result.time
    phi, w, a = T * t**2 / (2 * J), T * t / J, np.full_like(t, T / J)
    for name, expected in (("angle.phi", phi), ("speed.w", w), ("acc.a", a),
                           ("relAngle.phi_rel", phi), ("relSpeed.w_rel", w), ("relAcc.a_rel", a),
                           ("multi.w", w)):
        np.testing.assert_allclose(result[name], expected, rtol=1e-8, atol=1e-10, err_msg=name)


def test_torque_and_power_sensors(result):
    t = result.time
    for name in ("torque.tau", "multi.tau"):
        np.testing.assert_allclose(result[name], T, rtol=1e-12, err_msg=name)
    for name in ("power.power", "multi.power"):
        np.testing.assert_allclose(result[name], T * T * t / J, rtol=1e-8, atol=1e-10, err_msg=name)
