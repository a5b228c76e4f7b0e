"""Modelica.Mechanics.Rotational.Examples.First: a simple drive train.

A sinusoidal motor torque drives a motor inertia, which drives a load
through an ideal gear (ratio 10) and a spring; a damper to ground damps the
gear output.  Gear and motor torque are supported by a fixed housing.

Run ``acausal compare examples/first.py`` to check it against the MSL
reference results.
"""

from acausal import Experiment, Model, Parameter
from acausal.library.blocks import Sine
from acausal.library.rotational import Damper, Fixed, IdealGear, Inertia, Spring, Torque


class First(Model):
    """First example: a simple drive train."""

    modelica_class = "Modelica.Mechanics.Rotational.Examples.First"
    experiment = Experiment(start_time=0.0, stop_time=1.0, interval=0.001)

    amplitude = Parameter(10.0, unit="N.m", description="Amplitude of driving torque")
    f = Parameter(5.0, unit="Hz", description="Frequency of driving torque")
    Jmotor = Parameter(0.1, unit="kg.m2", description="Motor inertia")
    Jload = Parameter(2.0, unit="kg.m2", description="Load inertia")
    ratio = Parameter(10.0, description="Gear ratio")
    damping = Parameter(10.0, unit="N.m.s/rad", description="Damping in bearing of gear")

    def build(self):
        self.fixed = Fixed()
        self.torque = Torque(useSupport=True)
        self.inertia1 = Inertia(J=self.Jmotor)
        self.idealGear = IdealGear(ratio=self.ratio, useSupport=True)
        self.inertia2 = Inertia(J=2, phi=dict(start=0, fixed=True), w=dict(start=0, fixed=True))
        self.spring = Spring(c=1e4, phi_rel=dict(start=0, fixed=True))
        self.inertia3 = Inertia(J=self.Jload, w=dict(start=0, fixed=True))
        self.damper = Damper(d=self.damping)
        self.sine = Sine(amplitude=self.amplitude, f=self.f)

        self.connect(self.inertia1.flange_b, self.idealGear.flange_a)
        self.connect(self.idealGear.flange_b, self.inertia2.flange_a)
        self.connect(self.inertia2.flange_b, self.spring.flange_a)
        self.connect(self.spring.flange_b, self.inertia3.flange_a)
        self.connect(self.damper.flange_a, self.inertia2.flange_b)
        self.connect(self.damper.flange_b, self.fixed.flange)
        self.connect(self.sine.y, self.torque.tau)
        self.connect(self.torque.support, self.fixed.flange)
        self.connect(self.idealGear.support, self.fixed.flange)
        self.connect(self.torque.flange, self.inertia1.flange_a)


if __name__ == "__main__":
    from acausal import simulate

    result = simulate(First())
    print(result.summary())
    print("inertia3.w(1) =", result.final("inertia3.w"), " damper.phi_rel(1) =", result.final("damper.phi_rel"))
