"""Modelica.Mechanics.Rotational.Examples.Backlash: three oscillators, with and without backlash.

Three inertias (J = 5 kg.m2) start at rest, turned by pi/2 against their
fixed housings, and swing back through a spring-damper (c = 2e4 N.m/rad,
d = 50 N.m.s/rad):

* ``inertia1`` on a plain SpringDamper: a damped oscillation;
* ``inertia2`` on an ElastoBacklash with a 45 degree gap: no torque inside the
  gap, contact torque continuous at the gap edges (no pulling);
* ``inertia3`` on an ElastoBacklash2 with the same gap: the contact torque
  jumps by the damping torque when contact starts.

Run ``acausal compare examples/rotational_backlash.py`` to check it against
the MSL reference results.
"""

import math

from acausal import Experiment, Model
from acausal.library.rotational import ElastoBacklash, ElastoBacklash2, Fixed, Inertia, SpringDamper


class Backlash(Model):
    """Example to demonstrate backlash."""

    modelica_class = "Modelica.Mechanics.Rotational.Examples.Backlash"
    experiment = Experiment(start_time=0.0, stop_time=1.0, interval=0.001)

    def build(self):
        at_rest = dict(start=0, fixed=True)
        turned = dict(start=math.pi / 2, fixed=True)
        self.fixed1 = Fixed()
        self.springDamper = SpringDamper(c=20e3, d=50, phi_nominal=1)
        self.inertia1 = Inertia(J=5, w=at_rest, phi=turned)
        self.fixed2 = Fixed()
        self.elastoBacklash = ElastoBacklash(c=20e3, d=50, b=0.7853981633974483, phi_nominal=1)
        self.inertia2 = Inertia(J=5, w=at_rest, phi=turned)
        self.fixed3 = Fixed()
        self.elastoBacklash2 = ElastoBacklash2(c=20e3, d=50, phi_nominal=1, b=0.78539816339745)
        self.inertia3 = Inertia(J=5, w=at_rest, phi=turned)

        self.connect(self.springDamper.flange_b, self.inertia1.flange_a)
        self.connect(self.elastoBacklash.flange_b, self.inertia2.flange_a)
        self.connect(self.fixed1.flange, self.springDamper.flange_a)
        self.connect(self.fixed2.flange, self.elastoBacklash.flange_a)
        self.connect(self.elastoBacklash2.flange_b, self.inertia3.flange_a)
        self.connect(self.fixed3.flange, self.elastoBacklash2.flange_a)


if __name__ == "__main__":
    from acausal import simulate

    result = simulate(Backlash())
    print(result.summary())
