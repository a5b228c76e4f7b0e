"""ModelicaTest.Blocks.Hysteresis: a sine through a hysteresis block.

``u = sin(2*pi*t)``; ``hysteresis.y`` switches on where ``u`` rises above
``uHigh = 0.5`` (t = k + 1/12) and off where it falls below ``uLow = -0.5``
(t = k + 7/12).  The model has no continuous state: the switching instants
are state events of the relations ``u > uHigh`` and ``u >= uLow``.

Run ``acausal compare examples/blocks_hysteresis.py`` to check it against the
MSL reference results.
"""

from acausal import Experiment, Model
from acausal.library.blocks import Hysteresis, Sine


class HysteresisTest(Model):
    """Test of Modelica.Blocks.Logical.Hysteresis."""

    modelica_class = "ModelicaTest.Blocks.Hysteresis"
    experiment = Experiment(start_time=0.0, stop_time=3.0, interval=3.0 / 5000)

    def build(self):
        self.hysteresis = Hysteresis(uLow=-0.5, uHigh=0.5)
        self.Signal = Sine(f=1)  # the reference's capitalised name
        self.connect(self.Signal.y, self.hysteresis.u)


if __name__ == "__main__":
    from acausal import simulate

    result = simulate(HysteresisTest())
    print(result.summary())
    for event in result.events:
        print(event)
