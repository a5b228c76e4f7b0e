"""Modelica.Blocks.Math: the statistics over a period, the functions, conversions and unit conversions.

Each block is checked against a closed form or an independent computation:
the Mean of a sine over periods that do not match its own against the
integral, the RectifiedMean and RootMeanSquare of a sine against 2A/pi and
sqrt(offset^2 + A^2/2), the Harmonic against numpy's FFT of the sampled
signal, Variance/StandardDeviation/ContinuousMean against numpy over the
recorded input, the function blocks against numpy, and the 26 unit
conversions against the SI definitions of the units.  The two ModelicaTest
examples (Mean, ConversionBlocks) lie in the csv-compare tube.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from acausal import Experiment, Model, simulate
from acausal.library.blocks import BooleanConstant, Constant, Cosine, IntegerConstant, Sine
from acausal.library.blocks import math as blocks_math
from acausal.library.blocks import unit_conversions
from acausal.tools.compare import compare_signals, load_reference, reference_dir
from examples.blocks_conversion import ConversionBlocks
from examples.blocks_mean import MeanTest


def _value_at(result, name: str, t: float) -> float:
    """The value of ``name`` at the output point nearest ``t`` (choose a ``t`` that is no event)."""
    k = int(np.argmin(np.abs(result.time - t)))
    return float(result[name][k])


# --------------------------------------------------------------------------
# the MSL reference results


@pytest.mark.parametrize("model_class", [MeanTest, ConversionBlocks])
def test_examples_match_reference(model_class):
    if not (reference_dir() / model_class.modelica_class).is_dir():
        pytest.skip(f"no reference results for {model_class.modelica_class} in {reference_dir()}")
    result = simulate(model_class())
    assert result.success, result.message
    comparison = compare_signals(load_reference(model_class.modelica_class), result.time, result.columns)
    assert comparison.passed, comparison.table()


# --------------------------------------------------------------------------
# means over a period


class _Statistics(Model):
    """A sine (amplitude 2, 1 Hz, offset 0.5) into every statistics block; the Mean's period
    (f = 1.5 Hz) is not the sine's, the others average over whole sine periods (f = 1 Hz)."""

    experiment = Experiment(stop_time=3.2, interval=1e-3)

    def build(self):
        self.sine = Sine(amplitude=2.0, f=1.0, offset=0.5)
        self.mean = blocks_math.Mean(f=1.5, y0=-7.0)
        self.rectified = blocks_math.RectifiedMean(f=1.0)
        self.rms = blocks_math.RootMeanSquare(f=1.0)
        self.clipped = blocks_math.Mean(f=1.0, yGreaterOrEqualZero=True)
        self.negative = blocks_math.Gain(k=-1)
        for block in (self.mean, self.rectified, self.rms):
            self.connect(self.sine.y, block.u)
        self.connect(self.sine.y, self.negative.u)
        self.connect(self.negative.y, self.clipped.u)


@pytest.fixture(scope="module")
def statistics():
    # the RectifiedMean's Abs makes no event at its kink (as in the MSL): the integrator steps
    # over it, and a tolerance below the default keeps that error below the checks' 1e-5
    result = simulate(_Statistics(), rtol=1e-9)
    assert result.success, result.message
    return result


def _sine_integral(a: float, b: float, amplitude=2.0, f=1.0, offset=0.5) -> float:
    """The integral of ``offset + amplitude*sin(2*pi*f*t)`` over [a, b]."""
    w = 2 * math.pi * f
    return offset * (b - a) + amplitude * (math.cos(w * a) - math.cos(w * b)) / w


def test_mean_is_the_integral_over_the_last_period(statistics):
    period = 1 / 1.5
    assert _value_at(statistics, "mean.y", 0.5 * period) == -7.0  # y0 until the first period ends
    for i in (1, 2, 3, 4):
        expected = _sine_integral((i - 1) * period, i * period) / period
        assert _value_at(statistics, "mean.y", (i + 0.5) * period) == pytest.approx(expected, abs=1e-5)


def test_mean_samples_at_the_period_ends(statistics):
    ticks = sorted({e.time for e in statistics.events if e.time > 0})
    assert [t for t in ticks if abs(t * 1.5 - round(t * 1.5)) < 1e-9] == pytest.approx(
        [1 / 1.5, 2 / 1.5, 3 / 1.5, 4 / 1.5], abs=1e-12)


def test_mean_periods_start_at_the_start_time():
    class Late(Model):
        experiment = Experiment(start_time=0.3, stop_time=1.5, interval=1e-3)

        def build(self):
            self.sine = Sine(amplitude=2.0, f=1.0, offset=0.5)
            self.mean = blocks_math.Mean(f=2.0, x0=0.25)
            self.connect(self.sine.y, self.mean.u)

    result = simulate(Late())
    assert result.success, result.message
    # the periods are [0.3, 0.8), [0.8, 1.3): the first integral starts from x0
    assert _value_at(result, "mean.y", 0.7) == 0.0
    assert _value_at(result, "mean.y", 1.0) == pytest.approx(2.0 * (0.25 + _sine_integral(0.3, 0.8)), abs=1e-5)
    assert _value_at(result, "mean.y", 1.4) == pytest.approx(2.0 * _sine_integral(0.8, 1.3), abs=1e-5)


def test_rectified_mean_of_a_sine(statistics):
    # |0.5 + 2 sin(w t)| over a period, split where the sine crosses -0.25
    t1 = 0.5 + math.asin(0.25) / (2 * math.pi)
    t2 = 1.0 - math.asin(0.25) / (2 * math.pi)
    expected = _sine_integral(0, t1) - _sine_integral(t1, t2) + _sine_integral(t2, 1.0)
    for t in (1.5, 2.5):
        assert _value_at(statistics, "rectified.y", t) == pytest.approx(expected, abs=1e-5)


def test_root_mean_square_of_a_sine(statistics):
    assert _value_at(statistics, "rms.y", 0.5) == 0.0
    for t in (1.5, 2.5):
        assert _value_at(statistics, "rms.y", t) == pytest.approx(math.sqrt(0.5 ** 2 + 2.0 ** 2 / 2), abs=1e-5)


def test_mean_clipped_at_zero(statistics):
    # the mean of -u over a period is -0.5: yGreaterOrEqualZero clips it
    assert _value_at(statistics, "clipped.y", 1.5) == 0.0


class _HarmonicOf(Model):
    """A signal with a known 2nd harmonic into Harmonic(k=2), and into one with the conjugate."""

    experiment = Experiment(stop_time=1.1, interval=1e-3)

    def build(self):
        # u = 0.3 + 1.5 cos(2 pi 2 t + 0.7) + 0.4 cos(2 pi 6 t - 1.1)  (base f = 1 Hz)
        self.c0 = Constant(k=0.3)
        self.c2 = Cosine(amplitude=1.5, f=2.0, phase=0.7)
        self.c6 = Cosine(amplitude=0.4, f=6.0, phase=-1.1)
        self.sum = blocks_math.Add3()
        self.harmonic = blocks_math.Harmonic(f=1.0, k=2)
        self.conjugate = blocks_math.Harmonic(f=1.0, k=2, useConjugateComplex=True)
        self.connect(self.c0.y, self.sum.u1)
        self.connect(self.c2.y, self.sum.u2)
        self.connect(self.c6.y, self.sum.u3)
        self.connect(self.sum.y, self.harmonic.u)
        self.connect(self.sum.y, self.conjugate.u)


def test_harmonic_against_the_fft():
    result = simulate(_HarmonicOf())
    assert result.success, result.message
    # the 2nd harmonic over the first period [0, 1): numpy's FFT of the signal sampled there
    n = 1000
    t = np.arange(n) / n
    u = 0.3 + 1.5 * np.cos(2 * np.pi * 2 * t + 0.7) + 0.4 * np.cos(2 * np.pi * 6 * t - 1.1)
    coefficient = 2 * np.fft.rfft(u)[2] / n  # amplitude * exp(i*phase)
    assert _value_at(result, "harmonic.y_rms", 1.05) == pytest.approx(abs(coefficient) / math.sqrt(2), abs=1e-5)
    assert _value_at(result, "harmonic.y_arg", 1.05) == pytest.approx(-np.angle(coefficient), abs=1e-5)
    assert _value_at(result, "conjugate.y_arg", 1.05) == pytest.approx(np.angle(coefficient), abs=1e-5)
    assert _value_at(result, "harmonic.y_rms", 0.5) == 0.0  # y0Cos = y0Sin = 0 before


# --------------------------------------------------------------------------
# running statistics from the start


class _Running(Model):
    experiment = Experiment(start_time=0.5, stop_time=3.5, interval=1e-3)

    def build(self):
        self.sine = Sine(amplitude=2.0, f=1.3, offset=0.5)
        self.variance = blocks_math.Variance()
        self.deviation = blocks_math.StandardDeviation()
        self.mean = blocks_math.ContinuousMean()
        self.later = blocks_math.ContinuousMean(startTime=1.5)
        self.extrema = blocks_math.SignalExtrema(Ts=0.05)
        for block in (self.variance, self.deviation, self.mean, self.later, self.extrema):
            self.connect(self.sine.y, block.u)


@pytest.fixture(scope="module")
def running():
    result = simulate(_Running())
    assert result.success, result.message
    return result


def _sine(t):
    return 0.5 + 2.0 * np.sin(2 * np.pi * 1.3 * t)


def test_continuous_mean_is_the_mean_since_the_start(running):
    w = 2 * math.pi * 1.3
    for t in (1.0, 2.0, 3.5):
        # from the start time 0.5 of the run, and from startTime = 1.5
        expected = 0.5 + 2.0 * (math.cos(w * 0.5) - math.cos(w * t)) / w / (t - 0.5)
        assert _value_at(running, "mean.y", t) == pytest.approx(expected, abs=1e-5)
    assert _value_at(running, "later.y", 1.2) == pytest.approx(float(_sine(1.2)), abs=1e-9)  # u before startTime
    t = 3.0
    expected = 0.5 + 2.0 * (math.cos(w * 1.5) - math.cos(w * t)) / w / (t - 1.5)
    assert _value_at(running, "later.y", t) == pytest.approx(expected, abs=1e-5)


def test_variance_and_standard_deviation_approach_the_empirical_ones(running):
    # the MSL's running variance weighs (u - running mean)^2: it converges to numpy's variance
    # of the signal since the start
    samples = _sine(np.linspace(0.5, 3.5, 300001))
    assert running.final("variance.y") == pytest.approx(np.var(samples), rel=2e-2)
    assert running.final("deviation.y") == pytest.approx(np.std(samples), rel=1e-2)
    assert np.allclose(running["deviation.y"] ** 2, running["variance.y"], atol=1e-9)


def test_signal_extrema_of_the_samples(running):
    samples_t = 0.5 + 0.05 * np.arange(0, 61)
    values = _sine(samples_t)
    assert running.final("extrema.y_min") == pytest.approx(values.min(), abs=1e-9)
    assert running.final("extrema.y_max") == pytest.approx(values.max(), abs=1e-9)
    assert running.final("extrema.t_min") == pytest.approx(samples_t[np.argmin(values)], abs=1e-9)
    assert running.final("extrema.t_max") == pytest.approx(samples_t[np.argmax(values)], abs=1e-9)


# --------------------------------------------------------------------------
# functions


_SISO_FUNCTIONS = [
    ("Abs", {}, -0.3, 0.3), ("Sign", {}, -0.3, -1.0), ("Sqrt", {}, 0.3, math.sqrt(0.3)),
    ("Cos", {}, 0.3, math.cos(0.3)), ("Tan", {}, 0.3, math.tan(0.3)),
    ("Asin", {}, 0.3, math.asin(0.3)), ("Acos", {}, 0.3, math.acos(0.3)),
    ("Sinh", {}, 0.3, math.sinh(0.3)), ("Cosh", {}, 0.3, math.cosh(0.3)), ("Tanh", {}, 0.3, math.tanh(0.3)),
    ("Exp", {}, 0.3, math.exp(0.3)), ("Log", {}, 0.3, math.log(0.3)), ("Log", {"base": 2.0}, 0.3, math.log2(0.3)),
    ("Log10", {}, 0.3, math.log10(0.3)),
    ("Power", {"base": 3.0}, 0.3, 3.0 ** 0.3), ("Power", {"base": 3.0, "useExp": False}, 0.3, 3.0 ** 0.3),
    ("Exponentiation", {"exponent": 3.0}, -0.3, -0.027),
    ("WrapAngle", {}, 7.5, 7.5 - 2 * math.pi), ("WrapAngle", {}, 3.5, 3.5 - 2 * math.pi),
    ("WrapAngle", {"positiveRange": True}, 3.5, 3.5), ("WrapAngle", {}, -3.5, -3.5 + 2 * math.pi),
]


class _Functions(Model):
    experiment = Experiment(stop_time=0.01, interval=0.01)

    def build(self):
        for i, (name, modifiers, value, _) in enumerate(_SISO_FUNCTIONS):
            source = Constant(k=value)
            block = getattr(blocks_math, name)(**modifiers)
            setattr(self, f"source{i}", source)
            setattr(self, f"block{i}", block)
            self.connect(source.y, block.u)
        self.a = Constant(k=-0.4)
        self.b = Constant(k=-1.2)
        self.c = Constant(k=2.5)
        self.add3 = blocks_math.Add3(k1=2, k2=-3, k3=0.5)
        self.division = blocks_math.Division()
        self.atan2 = blocks_math.Atan2()
        self.toPolar = blocks_math.RectangularToPolar()
        self.toRectangular = blocks_math.PolarToRectangular()
        self.hypotenuse = blocks_math.Pythagoras()
        self.leg = blocks_math.Pythagoras(u1IsHypotenuse=True)
        self.noLeg = blocks_math.Pythagoras(u1IsHypotenuse=True)
        for u1, u2, block in ((self.a, self.b, self.division), (self.a, self.b, self.atan2),
                              (self.c, self.b, self.hypotenuse), (self.c, self.b, self.leg),
                              (self.b, self.c, self.noLeg)):
            self.connect(u1.y, block.u1)
            self.connect(u2.y, block.u2)
        self.connect(self.a.y, self.add3.u1)
        self.connect(self.b.y, self.add3.u2)
        self.connect(self.c.y, self.add3.u3)
        self.connect(self.a.y, self.toPolar.u_re)
        self.connect(self.b.y, self.toPolar.u_im)
        self.connect(self.toPolar.y_abs, self.toRectangular.u_abs)
        self.connect(self.toPolar.y_arg, self.toRectangular.u_arg)
        self.integer = IntegerConstant(k=3)
        self.toReal = blocks_math.IntegerToReal()
        self.toBoolean = blocks_math.IntegerToBoolean(threshold=3)
        self.below = blocks_math.IntegerToBoolean(threshold=4)
        self.true = BooleanConstant(k=True)
        self.toInteger = blocks_math.BooleanToInteger(integerTrue=7, integerFalse=-2)
        self.connect(self.integer.y, self.toReal.u)
        self.connect(self.integer.y, self.toBoolean.u)
        self.connect(self.integer.y, self.below.u)
        self.connect(self.true.y, self.toInteger.u)


def test_function_blocks_against_numpy():
    result = simulate(_Functions())
    assert result.success, result.message
    for i, (name, modifiers, value, expected) in enumerate(_SISO_FUNCTIONS):
        assert result.final(f"block{i}.y") == pytest.approx(expected, rel=1e-12, abs=1e-14), (name, modifiers, value)
    assert result.final("add3.y") == pytest.approx(2 * -0.4 - 3 * -1.2 + 0.5 * 2.5)
    assert result.final("division.y") == pytest.approx(-0.4 / -1.2)
    assert result.final("atan2.y") == pytest.approx(np.arctan2(-0.4, -1.2))  # third quadrant
    assert result.final("toPolar.y_abs") == pytest.approx(np.hypot(-0.4, -1.2))
    assert result.final("toPolar.y_arg") == pytest.approx(np.angle(-0.4 - 1.2j))
    assert result.final("toRectangular.y_re") == pytest.approx(-0.4)
    assert result.final("toRectangular.y_im") == pytest.approx(-1.2)
    assert result.final("hypotenuse.y") == pytest.approx(np.hypot(2.5, 1.2))
    assert result.final("leg.y") == pytest.approx(math.sqrt(2.5 ** 2 - 1.2 ** 2))
    assert result.final("leg.valid") and result.final("hypotenuse.valid")
    assert result.final("noLeg.y") == 0.0 and not result.final("noLeg.valid")
    assert result.final("toReal.y") == 3.0
    assert result.final("toBoolean.y") and not result.final("below.y")
    assert result.final("toInteger.y") == 7


def test_abs_and_sign_make_events_only_when_asked():
    class Crossing(Model):
        experiment = Experiment(stop_time=1.0, interval=0.01)

        def build(self):
            self.sine = Sine(f=1.0, phase=0.3)
            self.quiet = blocks_math.Abs()
            self.loud = blocks_math.Sign(generateEvent=True)
            self.connect(self.sine.y, self.quiet.u)
            self.connect(self.sine.y, self.loud.u)

    result = simulate(Crossing())
    crossings = sorted(e.time for e in result.events if e.kind == "state")
    # the Sign crosses at sin(2 pi t + 0.3) = 0 (each relation u > 0, u < 0 once); the Abs makes none
    expected = [(math.pi - 0.3) / (2 * math.pi), (2 * math.pi - 0.3) / (2 * math.pi)]
    assert sorted({round(t, 6) for t in crossings}) == pytest.approx(expected, abs=1e-6)
    assert np.allclose(result["quiet.y"], np.abs(np.sin(2 * np.pi * result.time + 0.3)), atol=1e-9)


# --------------------------------------------------------------------------
# unit conversions against the SI definitions


#: (unit, value of one unit in SI, SI value of zero in the unit): y_SI = scale*y_unit + zero
_SI_DEFINITIONS = {
    "degC": (1.0, 273.15), "degF": (5 / 9, 273.15 - 32 * 5 / 9), "degRk": (5 / 9, 0.0),
    "deg": (math.pi / 180, 0.0), "rpm": (2 * math.pi / 60, 0.0), "kmh": (1000 / 3600, 0.0),
    "day": (24 * 3600, 0.0), "hour": (3600, 0.0), "minute": (60, 0.0), "litre": (1e-3, 0.0),
    "kWh": (1000 * 3600, 0.0), "bar": (1e5, 0.0), "gps": (1e-3, 0.0),
}


class _Conversions(Model):
    experiment = Experiment(stop_time=0.01, interval=0.01)

    def build(self):
        self.value = Constant(k=312.5)
        for row in unit_conversions.CONVERSIONS:
            for direction in ("To", "From"):
                block = getattr(unit_conversions, f"{direction}_{row.name}")()
                setattr(self, f"{direction.lower()}_{row.name}", block)
                self.connect(self.value.y, block.u)


def test_unit_conversions_against_si_definitions():
    assert {row.name for row in unit_conversions.CONVERSIONS} == set(_SI_DEFINITIONS)
    result = simulate(_Conversions())
    assert result.success, result.message
    x = 312.5
    for unit, (scale, zero) in _SI_DEFINITIONS.items():
        assert result.final(f"to_{unit}.y") == pytest.approx((x - zero) / scale, rel=1e-14), unit
        assert result.final(f"from_{unit}.y") == pytest.approx(scale * x + zero, rel=1e-14), unit


def test_unit_conversion_blocks_declare_the_msl_units_and_names():
    assert unit_conversions.To_degC.modelica_name == "Modelica.Blocks.Math.UnitConversions.To_degC"
    block = unit_conversions.From_rpm()
    assert (type(block).u.unit, type(block).y.unit) == ("rev/min", "rad/s")
    assert (unit_conversions.To_kWh.u.unit, unit_conversions.To_kWh.y.unit) == ("J", "kW.h")
    names = [name for name in unit_conversions.__all__ if name.startswith(("To_", "From_"))]
    assert len(names) == 26


class _Distorted(Model):
    """u = 2 sin(2 pi t) + 0.5 sin(6 pi t) + 0.3 into the THD, against the first harmonic and the RMS."""

    experiment = Experiment(stop_time=1.5, interval=1e-3)

    def build(self):
        self.first = Sine(amplitude=2.0, f=1.0, offset=0.3)
        self.third = Sine(amplitude=0.5, f=3.0)
        self.sum = blocks_math.Add()
        self.thd = blocks_math.TotalHarmonicDistortion(f=1.0)
        self.thdRms = blocks_math.TotalHarmonicDistortion(f=1.0, useFirstHarmonic=False)
        self.connect(self.first.y, self.sum.u1)
        self.connect(self.third.y, self.sum.u2)
        self.connect(self.sum.y, self.thd.u)
        self.connect(self.sum.y, self.thdRms.u)


def test_total_harmonic_distortion():
    result = simulate(_Distorted(), rtol=1e-9)
    assert result.success, result.message
    # everything but the first harmonic: the offset and the third harmonic
    rest = math.sqrt(0.3 ** 2 + 0.5 ** 2 / 2)
    first = 2.0 / math.sqrt(2)
    total = math.sqrt(0.3 ** 2 + (2.0 ** 2 + 0.5 ** 2) / 2)
    assert _value_at(result, "thd.y", 1.2) == pytest.approx(rest / first, abs=1e-6)
    assert _value_at(result, "thdRms.y", 1.2) == pytest.approx(rest / total, abs=1e-6)
    assert _value_at(result, "thd.valid", 1.2) and not _value_at(result, "thd.valid", 0.5)


def test_continuous_signal_extrema_of_a_sine():
    class Extrema(Model):
        experiment = Experiment(stop_time=1.6, interval=1e-3)

        def build(self):
            self.sine = Sine(amplitude=2.0, f=1.0, offset=0.5)
            self.extrema = blocks_math.ContinuousSignalExtrema()
            self.connect(self.sine.y, self.extrema.u)

    result = simulate(Extrema(), method="Radau")  # T = 1e-6: stiff
    assert result.success, result.message
    # the extrema of 0.5 + 2 sin(2 pi t) at t = 0.25 and 0.75
    assert result.final("extrema.y_max") == pytest.approx(2.5, abs=1e-6)
    assert result.final("extrema.y_min") == pytest.approx(-1.5, abs=1e-6)
    assert result.final("extrema.t_max") == pytest.approx(0.25, abs=1e-3)
    assert result.final("extrema.t_min") == pytest.approx(0.75, abs=1e-3)
    # between the events the stored values hold: never beyond what the input has been
    assert 0.5 <= _value_at(result, "extrema.y_max", 0.1) <= 0.5 + 2 * math.sin(0.2 * math.pi)
