"""Modelica.Blocks.Examples.CompareSincExpSine: a sinc signal beside two damped sines.

``Sinc`` gives ``sin(x)/x`` with ``x = 2*pi*5*time`` (1 at the start, where
the quotient is 0/0); the two ``ExpSine`` blocks are sines of the same
frequency damped by ``exp(-5*time)``, the second shifted by pi/2 (so it
starts at 1, as the sinc does).

Run ``acausal compare examples/blocks_sinc.py`` to check it against the
MSL reference results.
"""

import math

from acausal import Experiment, Model
from acausal.library.blocks import ExpSine
from acausal.library.blocks.sources import Sinc


class CompareSincExpSine(Model):
    """Modelica.Blocks.Examples.CompareSincExpSine."""

    modelica_class = "Modelica.Blocks.Examples.CompareSincExpSine"
    experiment = Experiment(start_time=0.0, stop_time=1.0, interval=0.0001)

    def build(self):
        self.sinc = Sinc(f=5)
        self.expSine1 = ExpSine(f=5, damping=5)
        self.expSine2 = ExpSine(f=5, phase=math.pi / 2, damping=5)


if __name__ == "__main__":
    from acausal import simulate

    result = simulate(CompareSincExpSine())
    print(result.summary())
