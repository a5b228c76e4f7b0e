"""Modelica.Mechanics.Translational.Examples.InitialConditions: setting initial conditions.

Two chains of masses hang between springs and spring-dampers from fixed
points.  In the first chain (fixed1 - s1 - m1 - sd1 - m2) the initial state
is given by relative quantities: the spring s1 starts compressed to
``s_rel = 0.5`` m, the spring-damper sd1 starts at ``s_rel = 1`` m with
``v_rel = 0``, and m1 starts at rest; m2 follows from them.  In the second
chain (fixed2 - s2 - m3 - sd2 - m4) the absolute positions and velocities
of the masses are given instead.  Both chains then oscillate about their
equilibria.

Run ``acausal compare examples/translational_initial_conditions.py`` to
check it against the MSL reference results.
"""

from acausal import Experiment, Model
from acausal.library.translational import Fixed, Mass, Spring, SpringDamper


class InitialConditions(Model):
    """Setting of initial conditions."""

    modelica_class = "Modelica.Mechanics.Translational.Examples.InitialConditions"
    experiment = Experiment(start_time=0.0, stop_time=5.0, interval=0.001)

    def build(self):
        fixed = dict(fixed=True)
        # chain with absolute initial conditions
        self.fixed2 = Fixed(s0=1)
        self.s2 = Spring(s_rel0=2, c=1e3)
        self.m3 = Mass(L=3, s=dict(start=4.5, fixed=True), v=fixed, m=1)
        self.sd2 = SpringDamper(s_rel0=4, c=111, d=1)
        self.m4 = Mass(L=5, s=dict(start=12.5, fixed=True), v=fixed, m=1)
        # chain with relative initial conditions
        self.fixed1 = Fixed(s0=-1)
        self.s1 = Spring(s_rel0=1, c=1e3, s_rel=dict(start=0.5, fixed=True))
        self.m1 = Mass(L=1, v=fixed, m=1)
        self.sd1 = SpringDamper(s_rel0=1, c=111, s_rel=dict(start=1, fixed=True), v_rel=fixed, d=1)
        self.m2 = Mass(L=2, m=1)

        self.connect(self.s2.flange_a, self.fixed2.flange)
        self.connect(self.s1.flange_a, self.fixed1.flange)
        self.connect(self.m1.flange_a, self.s1.flange_b)
        self.connect(self.sd1.flange_a, self.m1.flange_b)
        self.connect(self.m2.flange_a, self.sd1.flange_b)
        self.connect(self.m4.flange_a, self.sd2.flange_b)
        self.connect(self.sd2.flange_a, self.m3.flange_b)
        self.connect(self.m3.flange_a, self.s2.flange_b)


if __name__ == "__main__":
    from acausal import simulate

    result = simulate(InitialConditions())
    print(result.summary())
    print("m1.s(5) =", result.final("m1.s"), " m3.s(5) =", result.final("m3.s"))
