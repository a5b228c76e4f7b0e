"""Modelica.Mechanics.Translational.Examples.Accelerate: a mass moved by a prescribed acceleration.

An Accelerate source, fed by a constant 1 m/s2, drives a 1 kg mass of
length 1 m.  The source's position and speed start at 0 (fixed), so
``accelerate.s = t^2/2`` and ``accelerate.v = t``: the mass has no say, the
source pushes it with whatever force that takes (1 N).

Run ``acausal compare examples/translational_accelerate.py`` to check it
against the MSL reference results.
"""

from acausal import Experiment, Model
from acausal.library.blocks import Constant
from acausal.library.translational import Accelerate as AccelerateSource, Mass


class Accelerate(Model):
    """Use of the Accelerate source."""

    modelica_class = "Modelica.Mechanics.Translational.Examples.Accelerate"
    experiment = Experiment(start_time=0.0, stop_time=1.0, interval=0.001)

    def build(self):
        self.accelerate = AccelerateSource()
        self.mass = Mass(L=1, m=1)
        self.constantAcc = Constant(k=1)

        self.connect(self.accelerate.flange, self.mass.flange_a)
        self.connect(self.constantAcc.y, self.accelerate.a_ref)


if __name__ == "__main__":
    from acausal import simulate

    result = simulate(Accelerate())
    print(result.summary())
    print("accelerate.s(1) =", result.final("accelerate.s"), " (exact 0.5)")
