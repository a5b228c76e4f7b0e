"""Modelica.Mechanics.Rotational.Examples.Friction: drive train with clutch and brake.

A motor torque 200·sin(100 t), switched off at t = 0.5 s, drives inertia3,
coupled by a clutch (always engaged) to inertia2, a spring-damper, and a
brake (engaged at t = 0.5 s) on inertia1.  The clutch starts slipping
backward (w_rel = -10 rad/s), sticks, breaks away and sticks again; the
brake stops the train.
"""

import math

from acausal import Experiment, Model, Parameter
from acausal.library.blocks import Constant, Product, Sine, Step
from acausal.library.rotational import Brake, Clutch, Fixed, Inertia, SpringDamper, Torque


class Friction(Model):
    """Drive train with clutch and brake."""

    modelica_class = "Modelica.Mechanics.Rotational.Examples.Friction"
    experiment = Experiment(start_time=0.0, stop_time=3.0, interval=0.001)

    startTime = Parameter(0.5, unit="s", description="Start time of step")

    def build(self):
        self.torque = Torque(useSupport=True)
        self.inertia3 = Inertia(J=1, phi=dict(start=0, fixed=True), w=dict(start=100, fixed=True))
        self.clutch = Clutch(fn_max=160)
        self.inertia2 = Inertia(J=0.05, phi=dict(start=0, fixed=True), w=dict(start=90, fixed=True))
        self.spring = SpringDamper(c=160, d=1)
        self.brake = Brake(fn_max=1600, useSupport=True)
        self.inertia1 = Inertia(J=1, phi=dict(start=0, fixed=True), w=dict(start=90, fixed=True))
        self.const = Constant(k=1)
        self.step = Step(startTime=self.startTime)
        self.step2 = Step(height=-1, offset=1, startTime=self.startTime)
        self.sine = Sine(amplitude=200, f=50 / math.pi)
        self.product = Product()
        self.fixed = Fixed()

        self.connect(self.torque.flange, self.inertia3.flange_a)
        self.connect(self.inertia3.flange_b, self.clutch.flange_a)
        self.connect(self.clutch.flange_b, self.inertia2.flange_a)
        self.connect(self.inertia2.flange_b, self.spring.flange_a)
        self.connect(self.spring.flange_b, self.brake.flange_a)
        self.connect(self.brake.flange_b, self.inertia1.flange_a)
        self.connect(self.sine.y, self.product.u1)
        self.connect(self.step2.y, self.product.u2)
        self.connect(self.product.y, self.torque.tau)
        self.connect(self.const.y, self.clutch.f_normalized)
        self.connect(self.step.y, self.brake.f_normalized)
        self.connect(self.torque.support, self.fixed.flange)
        self.connect(self.brake.support, self.fixed.flange)


if __name__ == "__main__":
    from acausal import simulate

    result = simulate(Friction())
    print(result.summary())
    for event in result.events:
        print(" ", event)
    print("inertia3.w(3) =", result.final("inertia3.w"), " clutch.phi_rel(3) =", result.final("clutch.phi_rel"))
