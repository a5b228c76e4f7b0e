"""ModelicaTest.Blocks.Mean: the mean, rectified mean, RMS and first harmonic of one cosine.

A cosine ``0.5 + cos(4*pi*t + pi/4)`` (f = 2 Hz) drives a Mean, a
RectifiedMean, a RootMeanSquare and a Harmonic, all over the period 0.5 s.
Each output holds its start value (0) until the first period ends, then the
value over the period that ended: the mean 0.5, the RMS sqrt(0.25 + 0.5),
and the harmonic's RMS value 1/sqrt(2) at the angle -pi/4, which a
PolarToRectangular and back a RectangularToPolar turn into the real and
imaginary parts and back.

Run ``acausal compare examples/blocks_mean.py`` to check it against the MSL
reference results (the reference compares ``mean.x`` and ``mean.y``).
"""

import math

from acausal import Eq, Experiment, Model, RealOutput
from acausal.library.blocks import Cosine
from acausal.library.blocks.math import (Harmonic, Mean, PolarToRectangular, RectangularToPolar, RectifiedMean,
                                         RootMeanSquare)


class MeanTest(Model):
    """ModelicaTest.Blocks.Mean."""

    modelica_class = "ModelicaTest.Blocks.Mean"
    experiment = Experiment(start_time=0.0, stop_time=1.1, interval=1.1 / 5000)

    yMean = RealOutput()  # noqa: N815 - the MSL model's names
    yRectifiedMean = RealOutput()  # noqa: N815
    yRootMeanSquare = RealOutput()  # noqa: N815
    yHarmonicCos = RealOutput()  # noqa: N815
    yHarmonicSin = RealOutput()  # noqa: N815
    yHarmonicAbs = RealOutput()  # noqa: N815
    yHarmonicArg = RealOutput()  # noqa: N815

    def build(self):
        self.mean = Mean(f=2)
        self.cosine = Cosine(offset=0.5, f=2, amplitude=1, phase=math.pi / 4)
        self.rectifiedMean = RectifiedMean(f=2)
        self.rootMeanSquare = RootMeanSquare(f=2)
        self.harmonic = Harmonic(f=2, k=1)
        self.polarToRectangular = PolarToRectangular()
        self.rectangularToPolar = RectangularToPolar()
        self.connect(self.cosine.y, self.mean.u)
        self.connect(self.cosine.y, self.rectifiedMean.u)
        self.connect(self.cosine.y, self.rootMeanSquare.u)
        self.connect(self.cosine.y, self.harmonic.u)
        self.connect(self.harmonic.y_rms, self.polarToRectangular.u_abs)
        self.connect(self.harmonic.y_arg, self.polarToRectangular.u_arg)
        self.connect(self.polarToRectangular.y_re, self.rectangularToPolar.u_re)
        self.connect(self.polarToRectangular.y_im, self.rectangularToPolar.u_im)

    def equations(self):
        return [Eq(self.yMean, self.mean.y),
                Eq(self.yRectifiedMean, self.rectifiedMean.y),
                Eq(self.yRootMeanSquare, self.rootMeanSquare.y),
                Eq(self.yHarmonicCos, self.polarToRectangular.y_re),
                Eq(self.yHarmonicSin, self.polarToRectangular.y_im),
                Eq(self.yHarmonicAbs, self.rectangularToPolar.y_abs),
                Eq(self.yHarmonicArg, self.rectangularToPolar.y_arg)]


if __name__ == "__main__":
    from acausal import simulate

    result = simulate(MeanTest())
    print(result.summary())
    for name in ("yMean", "yRectifiedMean", "yRootMeanSquare", "yHarmonicAbs", "yHarmonicArg"):
        print(f"{name}(1.1) = {result.final(name)}")
