"""Modelica.Mechanics.Translational.Examples.Brake: braking a moving mass to rest.

Two masses start at 1 m/s.  At t = 0.1 s a step of the normalized normal
force to 2 engages a Brake on each (mu = 0.5, fn_max = 1, so a friction force
of 1 N): the masses decelerate at 1 m/s², stop at t = 1.1 s and stay at rest.
``brake`` is implicitly grounded, ``brake1`` has its support connected to a
Fixed flange; both give the same motion.
"""

from acausal import Experiment, Model
from acausal.library.blocks import Step
from acausal.library.translational import Brake as BrakeElement, Fixed, Mass


class Brake(Model):
    """Demonstrate braking of a translational moving mass."""

    modelica_class = "Modelica.Mechanics.Translational.Examples.Brake"
    experiment = Experiment(start_time=0.0, stop_time=2.0, interval=0.001)

    def build(self):
        self.brake = BrakeElement(fn_max=1, useSupport=False)
        self.mass1 = Mass(m=1, s=dict(fixed=True), v=dict(start=1, fixed=True))
        self.step = Step(startTime=0.1, height=2)
        self.brake1 = BrakeElement(fn_max=1, useSupport=True)
        self.mass2 = Mass(m=1, s=dict(fixed=True), v=dict(start=1, fixed=True))
        self.fixed = Fixed()

        self.connect(self.mass1.flange_b, self.brake.flange_a)
        self.connect(self.step.y, self.brake.f_normalized)
        self.connect(self.mass2.flange_b, self.brake1.flange_a)
        self.connect(self.step.y, self.brake1.f_normalized)
        self.connect(self.fixed.flange, self.brake1.support)


if __name__ == "__main__":
    from acausal import simulate

    result = simulate(Brake())
    print(result.summary())
    for event in result.events:
        print(" ", event)
    print("mass1.s(2) =", result.final("mass1.s"), " mass2.s(2) =", result.final("mass2.s"))
