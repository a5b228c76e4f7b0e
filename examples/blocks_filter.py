"""Modelica.Blocks.Examples.Filter and FilterWithDifferentiation: the analog filters of Continuous.Filter.

``Filter``: a step (0.1 -> 1.1 at t = 0.1 s) drives four low pass filters
of order 3 with the cut-off frequency 2 Hz that differ only in their
characteristics (critical damping, Bessel, Butterworth, Chebyshev I), all
initialized in steady state.  ``FilterWithDifferentiation``: the output of
a third order Bessel filter differentiated three times by ``Der`` blocks,
which index reduction turns into derivatives of the filter's states.

Run ``acausal compare examples/blocks_filter.py`` to check both against the
MSL reference results.
"""

from acausal import Experiment, Model
from acausal.library.blocks import AnalogFilter, Der, Filter, FilterType, Init, Step


class FilterExample(Model):
    """Modelica.Blocks.Examples.Filter (its parameters at their defaults: low pass, order 3, f_cut = 2 Hz)."""

    modelica_class = "Modelica.Blocks.Examples.Filter"
    experiment = Experiment(start_time=0.0, stop_time=0.9, interval=0.00018)

    def build(self):
        # the example's parameters (order, f_cut, filterType, init, normalized), at their defaults
        f_cut = 2.0
        options = dict(normalized=True, init=Init.SteadyState, filterType=FilterType.LowPass, order=3,
                       f_cut=f_cut, f_min=0.8 * f_cut)
        self.step = Step(startTime=0.1, offset=0.1)
        self.CriticalDamping = Filter(analogFilter=AnalogFilter.CriticalDamping, **options)
        self.Bessel = Filter(analogFilter=AnalogFilter.Bessel, **options)
        self.Butterworth = Filter(analogFilter=AnalogFilter.Butterworth, **options)
        self.ChebyshevI = Filter(analogFilter=AnalogFilter.ChebyshevI, **options)
        for block in (self.CriticalDamping, self.Bessel, self.Butterworth, self.ChebyshevI):
            self.connect(self.step.y, block.u)


class FilterWithDifferentiation(Model):
    """Modelica.Blocks.Examples.FilterWithDifferentiation: derivatives of a filter's output up to its order."""

    modelica_class = "Modelica.Blocks.Examples.FilterWithDifferentiation"
    experiment = Experiment(start_time=0.0, stop_time=0.9, interval=0.00018)

    def build(self):
        self.step = Step(startTime=0.1, offset=0.1)
        self.Bessel = Filter(f_cut=2.0, filterType=FilterType.LowPass, order=3, analogFilter=AnalogFilter.Bessel)
        self.der1 = Der()
        self.der2 = Der()
        self.der3 = Der()
        self.connect(self.step.y, self.Bessel.u)
        self.connect(self.Bessel.y, self.der1.u)
        self.connect(self.der1.y, self.der2.u)
        self.connect(self.der2.y, self.der3.u)


if __name__ == "__main__":
    from acausal import simulate

    for model in (FilterExample(), FilterWithDifferentiation()):
        print(simulate(model).summary())
