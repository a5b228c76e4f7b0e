"""ModelicaTest.Blocks.Discrete: the discrete blocks fed by one sine.

A sine (3 Hz) is sampled every 0.02 s by a Sampler, a ZeroOrderHold, a
FirstOrderHold, a UnitDelay, a discrete TransferFunction ``1/(z + 0.1)`` and
a discrete StateSpace system; a BooleanPulse (period 0.2 s) triggers a
TriggeredSampler and a TriggeredMax.  There are no continuous states: only
sample instants (time events), the first at t = 0 right after
initialization, the last at the stop time.

Run ``acausal compare examples/blocks_discrete.py`` to check it against the
MSL reference results (ModelicaTest.Blocks.Discrete).
"""

from acausal import Experiment, Model, Parameter
from acausal.library.blocks import (
    BooleanPulse,
    FirstOrderHold,
    Sampler,
    Sine,
    StateSpace,
    TransferFunction,
    TriggeredMax,
    TriggeredSampler,
    UnitDelay,
    ZeroOrderHold,
)


class Discrete(Model):
    """Test of the Modelica.Blocks.Discrete blocks."""

    modelica_class = "ModelicaTest.Blocks.Discrete"
    experiment = Experiment(start_time=0.0, stop_time=1.1, interval=1.1 / 5000)

    samplePeriod = Parameter(0.02, unit="s", description="Sample period of the discrete blocks")  # noqa: N815

    def build(self):
        self.sine = Sine(f=3)
        self.sampler = Sampler(samplePeriod=self.samplePeriod)
        self.zeroOrderHold = ZeroOrderHold(samplePeriod=self.samplePeriod)
        self.firstOrderHold = FirstOrderHold(samplePeriod=self.samplePeriod)
        self.unitDelay = UnitDelay(samplePeriod=self.samplePeriod)
        self.transferFunction = TransferFunction(samplePeriod=self.samplePeriod, a=(1, 0.1),
                                                 y=dict(start=0, fixed=True))
        self.stateSpace = StateSpace(A=[[0, 1], [-1, -0.1]], B=[[0], [2]], C=[[2, 3]], D=[[0.1]],
                                     samplePeriod=self.samplePeriod,
                                     y=dict(start=0, fixed=True), x=dict(start=0, fixed=True))
        self.triggeredSampler = TriggeredSampler(y_start=2)
        self.booleanPulse = BooleanPulse(period=0.2)
        self.triggeredMax = TriggeredMax()

        self.connect(self.sine.y, self.sampler.u)
        self.connect(self.sine.y, self.zeroOrderHold.u)
        self.connect(self.sine.y, self.firstOrderHold.u)
        self.connect(self.sine.y, self.unitDelay.u)
        self.connect(self.sine.y, self.transferFunction.u)
        self.connect(self.sine.y, getattr(self.stateSpace, "u[1]"))
        self.connect(self.sine.y, self.triggeredSampler.u)
        self.connect(self.booleanPulse.y, self.triggeredSampler.trigger)
        self.connect(self.sine.y, self.triggeredMax.u)
        self.connect(self.booleanPulse.y, self.triggeredMax.trigger)


if __name__ == "__main__":
    from acausal import simulate

    result = simulate(Discrete())
    print(result.summary())
    for name in ("sampler.y", "firstOrderHold.c", "stateSpace.y[1]", "transferFunction.y",
                 "triggeredSampler.y", "triggeredMax.y"):
        print(f"{name}(1.1) = {result.final(name)}")
