"""Modelica.Mechanics.Translational.Examples.Damper: the damper models.

Three 1 kg masses (length 1 m) start at s = 3 m with v = 10 m/s towards a
fixed point at 4.5 m: mass1 through a damper (d = 25 N.s/m), mass2 through
the same damper with a parallel spring (c = 1 N/m, unstretched length 1 m),
mass3 through a SpringDamper with the same constants.  The damper alone
brakes mass1 exponentially (time constant m/d = 0.04 s); mass2 and mass3
behave identically, showing that a Damper in parallel with a Spring is a
SpringDamper.

Run ``acausal compare examples/translational_damper.py`` to check it
against the MSL reference results.
"""

from acausal import Experiment, Model
from acausal.library.translational import Damper as DamperElement, Fixed, Mass, Spring, SpringDamper


class Damper(Model):
    """Use of damper models."""

    modelica_class = "Modelica.Mechanics.Translational.Examples.Damper"
    experiment = Experiment(start_time=0.0, stop_time=1.0, interval=0.001)

    def build(self):
        moving = dict(s=dict(start=3, fixed=True), v=dict(start=10, fixed=True))
        self.mass1 = Mass(L=1, m=1, **moving)
        self.damper1 = DamperElement(d=25)
        self.fixed1 = Fixed(s0=4.5)
        self.mass2 = Mass(L=1, m=1, **moving)
        self.damper2 = DamperElement(d=25)
        self.fixed2 = Fixed(s0=4.5)
        self.mass3 = Mass(L=1, m=1, **moving)
        self.fixed3 = Fixed(s0=4.5)
        self.spring2 = Spring(s_rel0=1, c=1)
        self.springDamper3 = SpringDamper(s_rel0=1, d=25, c=1)

        self.connect(self.mass1.flange_b, self.damper1.flange_a)
        self.connect(self.mass2.flange_b, self.damper2.flange_a)
        self.connect(self.damper2.flange_b, self.spring2.flange_b)
        self.connect(self.damper2.flange_a, self.spring2.flange_a)
        self.connect(self.mass3.flange_b, self.springDamper3.flange_a)
        self.connect(self.damper1.flange_b, self.fixed1.flange)
        self.connect(self.damper2.flange_b, self.fixed2.flange)
        self.connect(self.springDamper3.flange_b, self.fixed3.flange)


if __name__ == "__main__":
    from acausal import simulate

    result = simulate(Damper())
    print(result.summary())
    print("mass1.s(1) =", result.final("mass1.s"), " mass3.s(1) =", result.final("mass3.s"))
