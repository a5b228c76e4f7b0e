"""Modelica.Mechanics.Translational.Examples.Oscillator: a forced oscillator, undamped and damped.

Two 1 kg masses hang on springs (c = 10000 N/m, unstretched length 1 m) from
fixed points at 1 m, start at s = -0.5 m at rest, and are driven by a 1 N
sine force at 15.9155 Hz, i.e. 100 rad/s, the natural frequency
sqrt(c/m) of the spring-mass system: the undamped mass1 is in resonance
and its amplitude grows linearly in time, while mass2, with a damper
(d = 10 N.s/m) parallel to its spring, settles to a bounded amplitude.

Run ``acausal compare examples/translational_oscillator.py`` to check it
against the MSL reference results.
"""

from acausal import Experiment, Model
from acausal.library.blocks import Sine
from acausal.library.translational import Damper, Fixed, Force, Mass, Spring


class Oscillator(Model):
    """Oscillator demonstrates the use of initial conditions."""

    modelica_class = "Modelica.Mechanics.Translational.Examples.Oscillator"
    experiment = Experiment(start_time=0.0, stop_time=1.0, interval=0.001)

    def build(self):
        at_rest = dict(s=dict(start=-0.5, fixed=True), v=dict(start=0, fixed=True))
        self.mass1 = Mass(L=1, m=1, **at_rest)
        self.spring1 = Spring(s_rel0=1, c=10000)
        self.fixed1 = Fixed(s0=1)
        self.force1 = Force()
        self.sine1 = Sine(f=15.9155)
        self.mass2 = Mass(L=1, m=1, **at_rest)
        self.spring2 = Spring(s_rel0=1, c=10000)
        self.fixed2 = Fixed(s0=1)
        self.force2 = Force()
        self.sine2 = Sine(f=15.9155)
        self.damper1 = Damper(d=10)

        self.connect(self.mass1.flange_b, self.spring1.flange_a)
        self.connect(self.spring2.flange_a, self.damper1.flange_a)
        self.connect(self.mass2.flange_b, self.spring2.flange_a)
        self.connect(self.damper1.flange_b, self.spring2.flange_b)
        self.connect(self.sine1.y, self.force1.f)
        self.connect(self.sine2.y, self.force2.f)
        self.connect(self.spring1.flange_b, self.fixed1.flange)
        self.connect(self.force2.flange, self.mass2.flange_a)
        self.connect(self.force1.flange, self.mass1.flange_a)
        self.connect(self.spring2.flange_b, self.fixed2.flange)


if __name__ == "__main__":
    from acausal import simulate

    result = simulate(Oscillator())
    print(result.summary())
    print("mass1.s(1) =", result.final("mass1.s"), " mass2.s(1) =", result.final("mass2.s"))
