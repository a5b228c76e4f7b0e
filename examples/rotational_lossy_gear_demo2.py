"""Modelica.Mechanics.Rotational.Examples.LossyGearDemo2: LossyGear and BearingFriction combined.

LossyGearDemo1 with a bearing friction (0.5 N.m at rest, rising to 1 N.m
at 1 rad/s) between the sine drive and Inertia1.  Both friction elements
pass through all their modes within 0.5 s.

When both are stuck at once the split of the holding torque between
them is not determined by the model: both constrain the acceleration of
Inertia1.  As Modelica tools do, acausal then picks a split (one element's
share is zero, with a RedundantConstraintWarning; see hard case 5 in
docs/hard-cases.md), and the event iteration settles where the gear holds
the shaft while the bearing rests at its sliding torque, as in the
reference.

``PowerLoss``, the power flowing into the gear through its flanges, must
equal ``gear.lossPower``.
"""

from acausal import Eq, Experiment, Model, Variable, der
from acausal.library.blocks import Ramp, Sine
from acausal.library.rotational import BearingFriction, Fixed, Inertia, LossyGear, Torque


class LossyGearDemo2(Model):
    """Example to show combination of LossyGear and BearingFriction."""

    modelica_class = "Modelica.Mechanics.Rotational.Examples.LossyGearDemo2"
    experiment = Experiment(start_time=0.0, stop_time=0.5, interval=0.001)

    PowerLoss = Variable(unit="W", description="Power lost in the gear")

    def build(self):
        self.gear = LossyGear(ratio=2, lossTable=[[0, 0.5, 0.5, 0, 0]], useSupport=True)
        self.Inertia1 = Inertia(J=1)
        self.Inertia2 = Inertia(J=1.5, phi=dict(start=0, fixed=True, nominal=1e-4),
                                w=dict(start=0, fixed=True, nominal=0.001))
        self.torque1 = Torque(useSupport=True)
        self.torque2 = Torque(useSupport=True)
        self.DriveSine = Sine(amplitude=10, f=1)
        self.load = Ramp(height=5, duration=2, offset=-10)
        self.bearingFriction = BearingFriction(tau_pos=[[0, 0.5], [1, 1]], useSupport=True)
        self.fixed = Fixed()

        self.connect(self.torque2.flange, self.Inertia2.flange_b)
        self.connect(self.Inertia2.flange_a, self.gear.flange_b)
        self.connect(self.gear.flange_a, self.Inertia1.flange_b)
        self.connect(self.Inertia1.flange_a, self.bearingFriction.flange_b)
        self.connect(self.bearingFriction.flange_a, self.torque1.flange)
        self.connect(self.DriveSine.y, self.torque1.tau)
        self.connect(self.load.y, self.torque2.tau)
        self.connect(self.gear.support, self.fixed.flange)
        self.connect(self.fixed.flange, self.torque2.support)
        self.connect(self.fixed.flange, self.bearingFriction.support)
        self.connect(self.torque1.support, self.fixed.flange)

    def equations(self):
        gear = self.gear
        return [Eq(self.PowerLoss, gear.flange_a.tau * der(gear.flange_a.phi)
                   + gear.flange_b.tau * der(gear.flange_b.phi))]


if __name__ == "__main__":
    from acausal import simulate

    result = simulate(LossyGearDemo2())
    print(result.summary())
    for event in result.events:
        print(" ", event)
