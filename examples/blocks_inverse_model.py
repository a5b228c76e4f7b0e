"""Modelica.Blocks.Examples.InverseModel: the input of a first order block computed from its output.

``firstOrder1`` is inverted by an ``InverseBlockConstraints`` around it: a
sine (2 Hz, from t = 0.2 s), smoothed by a first order critical damping
filter of 100 Hz, is imposed on its output, and the input that produces it
leaves the constraints block.  The structural analysis differentiates
``firstOrder1``'s equation and the filter's (index reduction through the
block diagram).  ``firstOrder2``, driven by that input, reproduces the
filtered sine; ``feedback`` is its difference to the sine itself.

Run ``acausal compare examples/blocks_inverse_model.py`` to check it
against the MSL reference results.
"""

from acausal import Experiment, Model
from acausal.library.blocks import CriticalDamping, Feedback, FirstOrder, Init, Sine
from acausal.library.blocks.math import InverseBlockConstraints


class InverseModel(Model):
    """Modelica.Blocks.Examples.InverseModel."""

    modelica_class = "Modelica.Blocks.Examples.InverseModel"
    experiment = Experiment(start_time=0.0, stop_time=1.0, interval=0.0002)

    def build(self):
        self.firstOrder1 = FirstOrder(k=1, T=0.3, initType=Init.SteadyState)
        self.sine = Sine(f=2, offset=1, startTime=0.2)
        self.inverseBlockConstraints = InverseBlockConstraints()
        self.firstOrder2 = FirstOrder(k=1, T=0.3, initType=Init.SteadyState)
        self.feedback = Feedback()
        self.criticalDamping = CriticalDamping(n=1, f=50 * self.sine.f)
        self.connect(self.firstOrder1.y, self.inverseBlockConstraints.u2)
        self.connect(self.inverseBlockConstraints.y2, self.firstOrder1.u)
        self.connect(self.firstOrder2.y, self.feedback.u1)
        self.connect(self.sine.y, self.criticalDamping.u)
        self.connect(self.criticalDamping.y, self.inverseBlockConstraints.u1)
        self.connect(self.sine.y, self.feedback.u2)
        self.connect(self.inverseBlockConstraints.y1, self.firstOrder2.u)


if __name__ == "__main__":
    from acausal import simulate

    print(simulate(InverseModel()).summary())
