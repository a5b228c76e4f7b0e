"""ModelicaTest.Rotational.TestFriction: the four friction elements side by side.

Four independent drive trains, each driven by a torque 10·sin(2·pi·t):

1. an inertia against a BearingFriction (defaults: 1 N.m, breaks away when
   the torque reaches 1 N.m at t = asin(0.1)/(2 pi));
2. an inertia against a Brake whose normal force steps to 100 N at 0.5 s;
3. an inertia driving a second inertia through a Clutch engaged at 0.5 s;
4. an inertia behind a OneWayClutch (freewheel) engaged at 0.5 s.
"""

from acausal import Experiment, Model
from acausal.library.blocks import Sine, Step
from acausal.library.rotational import BearingFriction, Brake, Clutch, Inertia, OneWayClutch, Torque


class TestFriction(Model):
    """Test of the friction elements BearingFriction, Brake, Clutch and OneWayClutch."""

    modelica_class = "ModelicaTest.Rotational.TestFriction"
    experiment = Experiment(start_time=0.0, stop_time=1.1, interval=2.2e-4)

    def build(self):
        rest = dict(start=0, fixed=True)
        # 1. bearing friction
        self.torque = Torque(useSupport=False)
        self.sine = Sine(amplitude=10, f=1)
        self.inertia = Inertia(J=1, phi=rest, w=rest)
        self.bearingFriction = BearingFriction(useSupport=False)
        self.connect(self.sine.y, self.torque.tau)
        self.connect(self.torque.flange, self.inertia.flange_a)
        self.connect(self.inertia.flange_b, self.bearingFriction.flange_a)
        # 2. brake
        self.torque1 = Torque(useSupport=False)
        self.sine1 = Sine(amplitude=10, f=1)
        self.inertia1 = Inertia(J=1, phi=rest, w=rest)
        self.brake = Brake(useSupport=False, fn_max=1)
        self.step = Step(height=100, startTime=0.5)
        self.connect(self.sine1.y, self.torque1.tau)
        self.connect(self.torque1.flange, self.inertia1.flange_a)
        self.connect(self.inertia1.flange_b, self.brake.flange_a)
        self.connect(self.step.y, self.brake.f_normalized)
        # 3. clutch
        self.torque2 = Torque(useSupport=False)
        self.sine2 = Sine(amplitude=10, f=1)
        self.inertia2 = Inertia(J=1, phi=rest, w=rest)
        self.clutch = Clutch(fn_max=1, phi_rel=rest, w_rel=rest)
        self.inertia3 = Inertia(J=1)
        self.step1 = Step(height=100, startTime=0.5)
        self.connect(self.sine2.y, self.torque2.tau)
        self.connect(self.torque2.flange, self.inertia2.flange_a)
        self.connect(self.inertia2.flange_b, self.clutch.flange_a)
        self.connect(self.clutch.flange_b, self.inertia3.flange_a)
        self.connect(self.step1.y, self.clutch.f_normalized)
        # 4. one-way clutch
        self.torque3 = Torque(useSupport=False)
        self.sine3 = Sine(amplitude=10, f=1)
        self.inertia4 = Inertia(J=1, phi=rest, w=rest)
        self.oneWayClutch = OneWayClutch(fn_max=1, phi_rel=rest, w_rel=rest,
                                         startForward=dict(start=False, fixed=True),
                                         stuck=dict(start=False, fixed=True))
        self.inertia5 = Inertia(J=1)
        self.step2 = Step(height=100, startTime=0.5)
        self.connect(self.sine3.y, self.torque3.tau)
        self.connect(self.torque3.flange, self.inertia4.flange_a)
        self.connect(self.oneWayClutch.flange_b, self.inertia4.flange_b)
        self.connect(self.oneWayClutch.flange_a, self.inertia5.flange_a)
        self.connect(self.step2.y, self.oneWayClutch.f_normalized)


if __name__ == "__main__":
    from acausal import simulate

    result = simulate(TestFriction())
    print(result.summary())
    for event in result.events:
        if event.changes:
            print(" ", event)
