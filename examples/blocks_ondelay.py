"""ModelicaTest.Blocks.OnDelay: three OnDelay blocks (delayTime = 1) on Boolean sources.

* ``onDelay1`` follows ``booleanTable`` (toggling at 1, 4, 6, 8, 9, 9.5):
  its output is true on [2, 4) and [7, 8), never in [9, 9.5) (the input
  falls before the delay has passed).
* ``onDelay2`` follows a step to true at 2: true from 3 on.
* ``onDelay3`` follows a step from true to false at 2: true on [0, 2), with
  no delay at initialization.

Every switching instant is a time event.  Run ``acausal compare
examples/blocks_ondelay.py`` to check it against the MSL reference results.
"""

from acausal import Experiment, Model
from acausal.library.blocks import BooleanStep, BooleanTable, OnDelay


class OnDelayTest(Model):
    """Test of Modelica.Blocks.MathBoolean.OnDelay."""

    modelica_class = "ModelicaTest.Blocks.OnDelay"
    experiment = Experiment(start_time=0.0, stop_time=11.0, interval=11.0 / 5000)

    def build(self):
        self.onDelay1 = OnDelay(delayTime=1)
        self.booleanTable = BooleanTable(table=(1, 4, 6, 8, 9, 9.5))
        self.onDelay2 = OnDelay(delayTime=1)
        self.booleanStep2 = BooleanStep(startTime=2, startValue=False)
        self.onDelay3 = OnDelay(delayTime=1)
        self.booleanStep3 = BooleanStep(startValue=True, startTime=2)
        self.connect(self.booleanTable.y, self.onDelay1.u)
        self.connect(self.booleanStep3.y, self.onDelay3.u)
        self.connect(self.booleanStep2.y, self.onDelay2.u)


if __name__ == "__main__":
    from acausal import simulate

    result = simulate(OnDelayTest())
    print(result.summary())
    for event in result.events:
        print(event)
