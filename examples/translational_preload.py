"""Modelica.Mechanics.Translational.Examples.PreLoad: preload of a valve spool with ElastoGap contacts.

A hydraulic valve spool (150 g) shall stay in place while the working force
on it is below a threshold and move in proportion to the force above it.
One preloaded spring (20 kN/m) between two spring plates does this: the
plates rest against outer contacts on the housing and inner contacts on the
spool (all ElastoGap elements, 1000 kN/m and 250 N.s/m, which push only
while compressed).  A force pushing the spool to the right lifts the left
plate off its outer contact and compresses the spring further, one pushing
to the left does the same with the right plate; in between the preload holds
the spool.  Viscous friction (a Damper named ``friction``, 2500 N.s/m)
damps the spool against the housing.  The force is a slow sine (150 N,
0.01 Hz) over one period; plot ``spool.s`` against ``force.f`` to see the
dead band and the linear parts.

The stiff contacts (1000 kN/m and 250 N.s/m on 10 g spring plates give
time constants of about 40 microseconds) make the model stiff: an explicit
method (``--method RK45``) takes minutes, the implicit one its experiment
names (BDF, as Dymola's DASSL is) well under a second.  Run
``acausal compare examples/translational_preload.py`` to check it against the
MSL reference results (it passes at RK45 too).
"""

from acausal import Experiment, Model
from acausal.library.blocks import Sine
from acausal.library.translational import Damper, ElastoGap, Fixed, Force, Mass, Rod, Spring


class PreLoad(Model):
    """Preload of a spool using ElastoGap models."""

    modelica_class = "Modelica.Mechanics.Translational.Examples.PreLoad"
    experiment = Experiment(start_time=0.0, stop_time=100.0, interval=0.1, method="BDF")  # stiff

    def build(self):
        contact = dict(c=1000e3, d=250)
        self.innerContactA = ElastoGap(s_rel0=0.001, **contact)
        self.innerContactB = ElastoGap(s_rel0=0.001, **contact)
        self.spool = Mass(L=0.19, m=0.150, s=dict(start=0.01475, fixed=True), v=dict(fixed=True))
        self.fixedLe = Fixed(s0=-0.0955)
        self.springPlateA = Mass(m=10e-3, L=0.002, s=dict(start=-0.093, fixed=True), v=dict(fixed=True))
        self.springPlateB = Mass(m=10e-3, s=dict(start=-0.06925, fixed=True), L=0.002, v=dict(fixed=True))
        self.spring = Spring(c=20e3, s_rel0=0.025)
        self.outerContactA = ElastoGap(s_rel0=0.0015, **contact)
        self.outerContactB = ElastoGap(s_rel0=0.0015, **contact)
        self.rod1 = Rod(L=0.007)
        self.friction = Damper(d=2500)
        self.force = Force()
        self.housing = Rod(L=0.0305)
        self.rod3 = Rod(L=0.00575)
        self.rod4 = Rod(L=0.00575)
        self.rod2 = Rod(L=0.007)
        self.sineForce = Sine(amplitude=150, f=0.01)

        self.connect(self.outerContactA.flange_b, self.springPlateA.flange_a)
        self.connect(self.springPlateA.flange_b, self.spring.flange_a)
        self.connect(self.spring.flange_b, self.springPlateB.flange_a)
        self.connect(self.springPlateB.flange_b, self.outerContactB.flange_a)
        self.connect(self.outerContactB.flange_b, self.housing.flange_b)
        self.connect(self.springPlateA.flange_b, self.rod1.flange_a)
        self.connect(self.innerContactA.flange_a, self.rod3.flange_a)
        self.connect(self.innerContactA.flange_b, self.rod1.flange_b)
        self.connect(self.rod2.flange_a, self.innerContactB.flange_a)
        self.connect(self.rod4.flange_b, self.innerContactB.flange_b)
        self.connect(self.friction.flange_b, self.rod3.flange_a)
        self.connect(self.rod3.flange_b, self.rod4.flange_a)
        self.connect(self.rod2.flange_b, self.springPlateB.flange_a)
        self.connect(self.spool.flange_a, self.rod4.flange_a)
        self.connect(self.sineForce.y, self.force.f)
        self.connect(self.force.flange, self.spool.flange_a)
        self.connect(self.outerContactA.flange_a, self.fixedLe.flange)
        self.connect(self.housing.flange_a, self.fixedLe.flange)
        self.connect(self.friction.flange_a, self.fixedLe.flange)


if __name__ == "__main__":
    from acausal import simulate

    result = simulate(PreLoad())
    print(result.summary())
    for event in result.events:
        print(" ", event)
