"""Modelica.Mechanics.Rotational.Examples.LossyGearDemo1: gear efficiency may lead to stuck motion.

Two inertias joined by a LossyGear (ratio 2, mesh efficiency 0.5 in both
power directions, no bearing friction).  A sine torque (10 N.m, 1 Hz)
drives Inertia1, a ramp load from -10 to -5 N.m over 2 s acts on
Inertia2.  Within 0.5 s the gear rolls backward, sticks, rolls forward,
sticks and rolls backward again: the efficiency alone makes it self-lock
while the drive and the load hold each other within its loss band.

``PowerLoss``, the power flowing into the gear through its flanges, must
equal ``gear.lossPower`` (Pelchen et al. 2002, equation 16).
"""

from acausal import Eq, Experiment, Model, Variable, der
from acausal.library.blocks import Ramp, Sine
from acausal.library.rotational import Fixed, Inertia, LossyGear, Torque


class LossyGearDemo1(Model):
    """Example to show that gear efficiency may lead to stuck motion."""

    modelica_class = "Modelica.Mechanics.Rotational.Examples.LossyGearDemo1"
    experiment = Experiment(start_time=0.0, stop_time=0.5, interval=0.001)

    PowerLoss = Variable(unit="W", description="Power lost in the gear")

    def build(self):
        self.gear = LossyGear(ratio=2, lossTable=[[0, 0.5, 0.5, 0, 0]], useSupport=True)
        self.Inertia1 = Inertia(J=1)
        self.Inertia2 = Inertia(J=1.5, phi=dict(start=0, fixed=True, nominal=0.001),
                                w=dict(start=0, fixed=True, nominal=0.01))
        self.torque1 = Torque(useSupport=True)
        self.torque2 = Torque(useSupport=True)
        self.DriveSine = Sine(amplitude=10, f=1)
        self.load = Ramp(height=5, duration=2, offset=-10)
        self.fixed = Fixed()

        self.connect(self.Inertia1.flange_b, self.gear.flange_a)
        self.connect(self.gear.flange_b, self.Inertia2.flange_a)
        self.connect(self.torque1.flange, self.Inertia1.flange_a)
        self.connect(self.torque2.flange, self.Inertia2.flange_b)
        self.connect(self.DriveSine.y, self.torque1.tau)
        self.connect(self.load.y, self.torque2.tau)
        self.connect(self.fixed.flange, self.gear.support)
        self.connect(self.fixed.flange, self.torque1.support)
        self.connect(self.fixed.flange, self.torque2.support)

    def equations(self):
        gear = self.gear
        return [Eq(self.PowerLoss, gear.flange_a.tau * der(gear.flange_a.phi)
                   + gear.flange_b.tau * der(gear.flange_b.phi))]


if __name__ == "__main__":
    from acausal import simulate

    result = simulate(LossyGearDemo1())
    print(result.summary())
    for event in result.events:
        print(" ", event)
