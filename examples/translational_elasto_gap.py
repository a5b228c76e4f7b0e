"""Modelica.Mechanics.Translational.Examples.ElastoGap: a mass between two contacts that can lift off.

The walls are the free ends of two 2 m rods on both sides of a fixed point
at 0, i.e. at -2 m and +2 m.  Two 1 kg point masses start at rest at the
right wall (s = 2 m).  mass1 hangs between two spring-dampers (c = 10 N/m,
d = 1.5 N.s/m, unstretched length 1 m): it starts 4 m from the left wall and
0 m from the right one, is pulled and pushed to the left and oscillates,
damped, about the centre.  mass2 sits between two ElastoGap contacts with
the same constants and an unstretched length of 1.5 m, which push only
while compressed below 1.5 m and let go otherwise: the right contact throws
mass2 off (lift-off at 0.58 s), it flies through the gap, hits the left
contact (0.88 s), bounces back, and so on, losing energy in each contact.
Each contact opening and closing is a state event (6 in 5 s).  The initial
spring lengths are computed (``s_rel(fixed=false)``); their start values
only guess them.

Run ``acausal compare examples/translational_elasto_gap.py`` to check it
against the MSL reference results.
"""

from acausal import Experiment, Model, Parameter
from acausal.library.translational import ElastoGap as ElastoGapElement, Fixed, Mass, Rod, SpringDamper


class ElastoGap(Model):
    """Demonstrate usage of ElastoGap."""

    modelica_class = "Modelica.Mechanics.Translational.Examples.ElastoGap"
    experiment = Experiment(start_time=0.0, stop_time=5.0, interval=0.01)

    d = Parameter(1.5, unit="N.s/m", description="Damping constant")

    def build(self):
        self.fixed = Fixed()
        self.rod1 = Rod(L=2)
        self.rod2 = Rod(L=2)
        self.springDamper1 = SpringDamper(c=10, s_rel0=1, s_rel=dict(fixed=False, start=1), d=1.5)
        self.springDamper2 = SpringDamper(c=10, s_rel0=1, s_rel=dict(fixed=False, start=1), d=1.5)
        self.mass1 = Mass(s=dict(fixed=True, start=2), L=0, m=1, v=dict(fixed=True))
        self.elastoGap1 = ElastoGapElement(c=10, s_rel=dict(fixed=False, start=1.5), s_rel0=1.5, d=1.5)
        self.elastoGap2 = ElastoGapElement(c=10, s_rel=dict(fixed=False, start=1.5), s_rel0=1.5, d=1.5)
        self.mass2 = Mass(s=dict(fixed=True, start=2), L=0, m=1, v=dict(fixed=True))

        self.connect(self.rod1.flange_b, self.fixed.flange)
        self.connect(self.fixed.flange, self.rod2.flange_a)
        self.connect(self.springDamper1.flange_a, self.rod1.flange_a)
        self.connect(self.springDamper2.flange_b, self.rod2.flange_b)
        self.connect(self.springDamper1.flange_b, self.mass1.flange_a)
        self.connect(self.mass1.flange_b, self.springDamper2.flange_a)
        self.connect(self.rod1.flange_a, self.elastoGap1.flange_a)
        self.connect(self.rod2.flange_b, self.elastoGap2.flange_b)
        self.connect(self.elastoGap1.flange_b, self.mass2.flange_a)
        self.connect(self.mass2.flange_b, self.elastoGap2.flange_a)


if __name__ == "__main__":
    from acausal import simulate

    result = simulate(ElastoGap())
    print(result.summary())
    print("mass1.s(5) =", result.final("mass1.s"), " mass2.s(5) =", result.final("mass2.s"))
