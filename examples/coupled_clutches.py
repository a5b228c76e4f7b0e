"""Modelica.Mechanics.Rotational.Examples.CoupledClutches: three dynamically coupled clutches.

Four inertias in a row, joined by three clutches.  Clutch 1's normal force
follows cos(0.4·pi·t) and frees the clutch at t = 1.25 s; clutches 2 and 3
engage by steps at 0.4 s and 0.9 s.  A 10 N.m sine torque drives J1, which
starts at 10 rad/s.
"""

import math

from acausal import Experiment, Model, Parameter
from acausal.library.blocks import Sine, Step
from acausal.library.rotational import Clutch, Fixed, Inertia, Torque


class CoupledClutches(Model):
    """Drive train with three dynamically coupled clutches."""

    modelica_class = "Modelica.Mechanics.Rotational.Examples.CoupledClutches"
    experiment = Experiment(start_time=0.0, stop_time=1.5, interval=0.001)

    f = Parameter(0.2, unit="Hz", description="Frequency of sine function to invoke clutch1")
    T2 = Parameter(0.4, unit="s", description="Time when clutch2 is invoked")
    T3 = Parameter(0.9, unit="s", description="Time when clutch3 is invoked")

    def build(self):
        rest = dict(start=0, fixed=True)
        self.J1 = Inertia(J=1, phi=rest, w=dict(start=10, fixed=True))
        self.torque = Torque(useSupport=True)
        self.clutch1 = Clutch(peak=1.1, fn_max=20)
        self.sin1 = Sine(amplitude=10, f=5)
        self.step1 = Step(startTime=self.T2)
        self.J2 = Inertia(J=1, phi=rest, w=rest)
        self.clutch2 = Clutch(peak=1.1, fn_max=20)
        self.J3 = Inertia(J=1, phi=rest, w=rest)
        self.clutch3 = Clutch(peak=1.1, fn_max=20)
        self.J4 = Inertia(J=1, phi=rest, w=rest)
        self.sin2 = Sine(amplitude=1, f=self.f, phase=math.pi / 2)
        self.step2 = Step(startTime=self.T3)
        self.fixed = Fixed()

        self.connect(self.torque.flange, self.J1.flange_a)
        self.connect(self.J1.flange_b, self.clutch1.flange_a)
        self.connect(self.clutch1.flange_b, self.J2.flange_a)
        self.connect(self.J2.flange_b, self.clutch2.flange_a)
        self.connect(self.clutch2.flange_b, self.J3.flange_a)
        self.connect(self.J3.flange_b, self.clutch3.flange_a)
        self.connect(self.clutch3.flange_b, self.J4.flange_a)
        self.connect(self.sin1.y, self.torque.tau)
        self.connect(self.sin2.y, self.clutch1.f_normalized)
        self.connect(self.step1.y, self.clutch2.f_normalized)
        self.connect(self.step2.y, self.clutch3.f_normalized)
        self.connect(self.fixed.flange, self.torque.support)


if __name__ == "__main__":
    from acausal import simulate

    result = simulate(CoupledClutches())
    print(result.summary())
    for event in result.events:
        print(" ", event)
