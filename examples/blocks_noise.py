"""Modelica.Blocks.Examples.Noise: uniform and truncated normal noise, bit for bit.

``UniformNoise``: two UniformNoise blocks sampled every 0.02 s, one with the
default (automatic) local seed, one with ``fixedLocalSeed=10`` and the band
-1 .. 3.  ``Distributions``: a UniformNoise and a TruncatedNormalNoise with
the same seeds, so the same raw numbers mapped through two distributions.
``NormalNoiseProperties``: normal noise (mu = 3, sigma = 1) sampled every
millisecond for 20 s, and its running mean, variance and standard deviation
(Blocks.Math) against the theoretical values.
The xorshift128+ generator, the seeds and the quantiles are those of the MSL
(:mod:`acausal.library.blocks.noise`), so the values equal Dymola's.

Run ``acausal compare examples/blocks_noise.py`` to check them against the
MSL reference results.
"""

from acausal import Eq, Experiment, If, Integer, Model, Parameter, Variable, time
from acausal.library.blocks import Constant, Feedback, MultiProduct
from acausal.library.blocks.math import ContinuousMean, StandardDeviation, Variance
from acausal.library.blocks.noise import GlobalSeed, NormalNoise, TruncatedNormalNoise, UniformNoise


class UniformNoiseExample(Model):
    """Modelica.Blocks.Examples.Noise.UniformNoise."""

    modelica_class = "Modelica.Blocks.Examples.Noise.UniformNoise"
    experiment = Experiment(start_time=0.0, stop_time=2.0, interval=0.0004)

    uniformNoise2_y = Variable(description="Output of uniformNoise2 (Modelica's output Real)")  # noqa: N815

    def build(self):
        self.globalSeed = GlobalSeed()
        self.uniformNoise1 = UniformNoise(samplePeriod=0.02, y_min=-1, y_max=3)
        self.uniformNoise2 = UniformNoise(samplePeriod=0.02, y_min=-1, y_max=3, useAutomaticLocalSeed=False,
                                          fixedLocalSeed=10)

    def equations(self):
        return [Eq(self.uniformNoise2_y, self.uniformNoise2.y)]


class DistributionsExample(Model):
    """Modelica.Blocks.Examples.Noise.Distributions."""

    modelica_class = "Modelica.Blocks.Examples.Noise.Distributions"
    experiment = Experiment(start_time=0.0, stop_time=2.0, interval=0.0004)

    #: Modelica's ``Integer n = if time < 0.5 then 12 else 2`` (read by nothing)
    n = Integer(description="An Integer switching at t = 0.5")
    uniformNoise_y = Variable(description="Output of uniformNoise")  # noqa: N815
    truncatedNormalNoise_y = Variable(description="Output of truncatedNormalNoise")  # noqa: N815

    def build(self):
        samplePeriod, y_min, y_max = 0.02, -1, 3  # noqa: N806 - the MSL's parameters
        self.globalSeed = GlobalSeed(useAutomaticSeed=False)
        self.uniformNoise = UniformNoise(useAutomaticLocalSeed=False, fixedLocalSeed=1, samplePeriod=samplePeriod,
                                         y_min=y_min, y_max=y_max)
        self.truncatedNormalNoise = TruncatedNormalNoise(useAutomaticLocalSeed=False, fixedLocalSeed=1,
                                                         samplePeriod=samplePeriod, y_min=y_min, y_max=y_max)

    def equations(self):
        return [Eq(self.n, If(time < 0.5, 12, 2)),
                Eq(self.uniformNoise_y, self.uniformNoise.y),
                Eq(self.truncatedNormalNoise_y, self.truncatedNormalNoise.y)]


class NormalNoisePropertiesExample(Model):
    """Modelica.Blocks.Examples.Noise.NormalNoiseProperties."""

    modelica_class = "Modelica.Blocks.Examples.Noise.NormalNoiseProperties"
    experiment = Experiment(start_time=0.0, stop_time=20.0, interval=0.4e-2, tolerance=1e-9)

    mu = Parameter(3.0, description="Mean value for normal distribution")
    sigma = Parameter(1.0, description="Standard deviation for normal distribution")
    pMean = Parameter(3.0, description="Theoretical mean value of normal distribution (= mu)")  # noqa: N815
    std = Parameter(1.0, description="Theoretical standard deviation of normal distribution (= sigma)")
    meanError_y = Variable(description="Output of meanError")  # noqa: N815
    sigmaError_y = Variable(description="Output of sigmaError")  # noqa: N815

    def build(self):
        self.globalSeed = GlobalSeed()
        self.noise = NormalNoise(samplePeriod=0.001, mu=self.mu, sigma=self.sigma, useAutomaticLocalSeed=False)
        self.mean = ContinuousMean()
        self.variance = Variance()
        self.theoreticalVariance = MultiProduct(nu=2)
        self.meanError = Feedback()
        self.theoreticalMean = Constant(k=self.pMean)
        self.varianceError = Feedback()
        self.theoreticalSigma = Constant(k=self.std)
        self.standardDeviation = StandardDeviation()
        self.sigmaError = Feedback()
        self.connect(self.noise.y, self.mean.u)
        self.connect(self.noise.y, self.variance.u)
        self.connect(self.mean.y, self.meanError.u1)
        self.connect(self.theoreticalMean.y, self.meanError.u2)
        self.connect(self.theoreticalSigma.y, self.theoreticalVariance.u[1])
        self.connect(self.theoreticalSigma.y, self.theoreticalVariance.u[2])
        self.connect(self.variance.y, self.varianceError.u1)
        self.connect(self.theoreticalVariance.y, self.varianceError.u2)
        self.connect(self.noise.y, self.standardDeviation.u)
        self.connect(self.standardDeviation.y, self.sigmaError.u1)
        self.connect(self.theoreticalSigma.y, self.sigmaError.u2)

    def equations(self):
        return [Eq(self.meanError_y, self.meanError.y), Eq(self.sigmaError_y, self.sigmaError.y)]


if __name__ == "__main__":
    from acausal import simulate

    for model in (UniformNoiseExample(), DistributionsExample(), NormalNoisePropertiesExample()):
        print(simulate(model).summary())
