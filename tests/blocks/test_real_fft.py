"""Modelica.Blocks.Math.RealFFT and the engine's finish hook (Component.finished).

The block samples its input into a buffer during the run and, once the run
has ended, computes the FFT and writes it to a MAT file.  The spectrum is
checked against ``numpy.fft.rfft`` of the sampled signal computed here from
the signal's closed form (with the MSL's scaling: ``|X|/(ns/2 + 1)``, phases
in degrees, the mean as the first amplitude) and against the amplitudes and
phases of the sines themselves; the file is read back with
``scipy.io.loadmat``.  The sample counts and the MSL's rule for ``ns``
(``realFFTsamplePoints``) are computed independently by brute force.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.io
import sympy as sp

from acausal import Assert, Component, Eq, Experiment, Model, RealOutput, simulate, translate
from acausal.errors import AssertionViolation, ModifierError, ParameterError, SimulationError
from acausal.language import finish_hooks, time
from acausal.library.blocks import RealFFT
from acausal.library.blocks.math import real_fft_sample_points
from library_checks import check_declarations

#: the test signal: mean, then (frequency, amplitude, phase of the cosine) of each part
MEAN = 1.5
PARTS = ((1.0, 2.0, -math.pi / 2), (3.0, 0.7, 0.4))  # 2 sin(2 pi t) + 0.7 cos(6 pi t + 0.4)


def signal(t):
    return MEAN + sum(a * np.cos(2 * np.pi * f * t + p) for f, a, p in PARTS)


class Signal(Component):
    """The test signal as an output (its closed form in time)."""

    y = RealOutput()

    def equations(self):
        return [Eq(self.y, MEAN + sum(a * sp.cos(2 * sp.pi * f * time + p) for f, a, p in PARTS))]


def fft_model(path: str, **block):
    """A model sampling :func:`signal` into a RealFFT with the modifiers ``block``."""

    class FFTModel(Model):
        experiment = Experiment(stop_time=1.21)

        def build(self):
            self.src = Signal()
            self.fft = RealFFT(resultFileName=str(path), **block)
            self.connect(self.src.y, self.fft.u)

    return FFTModel()


def smooth_even(n: int) -> int:
    """The smallest even number >= n whose only prime factors are 2, 3 and 5 (by trial)."""
    k = n + (n % 2)
    while True:
        rest = k
        for p in (2, 3, 5):
            while rest % p == 0:
                rest //= p
        if rest == 1:
            return k
        k += 2


# -- the sizes ----------------------------------------------------------------------------


@pytest.mark.parametrize("f_max, f_res", [(4, 0.2), (4, 1), (7, 1), (3.3, 0.7), (1.1, 1.0), (50, 0.3)])
def test_sample_points_are_the_smallest_even_2_3_5_number_above_the_msl_bound(f_max, f_res):
    assert real_fft_sample_points(f_max, f_res) == smooth_even(2 * math.ceil(f_max * 5 / f_res))


def test_sample_points_of_the_msl_example_and_the_asserts():
    assert real_fft_sample_points(4, 0.2) == 200  # Modelica.Math.FastFourierTransform.Examples.RealFFT1
    assert real_fft_sample_points(7, 1) == 72  # 70 = 2*5*7 is not a 2-3-5 number
    with pytest.raises(ParameterError, match="f_resolution > 0"):
        real_fft_sample_points(4, 0)
    with pytest.raises(ParameterError, match="f_max > f_resolution"):
        real_fft_sample_points(1, 1)


def test_final_parameters_follow_f_max_and_f_res():
    block = RealFFT(f_max=3.5, f_res=1)
    ns = smooth_even(2 * math.ceil(3.5 * 5 / 1))
    assert block.ns == ns == 36
    assert block.nf == max(1, min(math.ceil(3.5) + 1, ns // 2)) == 5
    assert block.samplePeriod == pytest.approx(1 / (2 * 1 * (ns // 2)), rel=1e-15)
    assert len(block.buf) == ns
    with pytest.raises(ModifierError, match="final"):
        RealFFT(samplePeriod=0.1)
    check_declarations(RealFFT(f_max=4, f_res=1))


# -- the spectrum -------------------------------------------------------------------------


def msl_spectrum(samples: np.ndarray, nf: int):
    """The MSL's realFFT, here from numpy.fft: amplitudes |X|/(ns/2 + 1), phases in degrees,
    the mean first, phases of amplitudes below 1e-4 of the largest set to 0."""
    ns = samples.size
    mean = samples.mean()
    x = np.fft.rfft(samples - mean)[:nf]
    amplitudes = np.abs(x) / (ns // 2 + 1)
    phases = np.degrees(np.angle(x))
    small = amplitudes < 1e-4 * amplitudes.max()
    amplitudes[0], phases[0] = mean, 0.0
    phases[1:][small[1:]] = 0.0
    return amplitudes, phases


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    """One run sampling from t = 0.05 (f_max = 4, f_res = 1: ns = 40, Ts = 1/40)."""
    path = tmp_path_factory.mktemp("fft") / "spectrum.mat"
    model = fft_model(path, f_max=4, f_res=1, startTime=0.05)
    return model, simulate(model), path


def test_the_buffer_holds_the_first_ns_samples_from_start_time(run):
    model, result, _ = run
    assert result.status == 0, result.message
    ns, ts = 40, 1 / 40
    t_samples = 0.05 + np.arange(ns) * ts
    np.testing.assert_allclose(result.final("fft.buf"), signal(t_samples), rtol=0, atol=1e-12)
    # ticks at 0.05 + i/40 up to the stop time 1.21: i = 0 ... 46
    assert result.final("fft.iTick") == math.floor((1.21 - 0.05) * 40) + 1 == 47


def test_spectrum_is_numpy_fft_of_the_samples_with_the_msl_scaling(run):
    model, result, _ = run
    f, amplitudes, phases = model.fft.spectrum(result)
    samples = signal(0.05 + np.arange(40) / 40)
    expected_a, expected_p = msl_spectrum(samples, 5)
    np.testing.assert_allclose(f, [0, 1, 2, 3, 4], rtol=0, atol=1e-15)
    np.testing.assert_allclose(amplitudes, expected_a, rtol=0, atol=1e-10)
    np.testing.assert_allclose(phases, expected_p, rtol=0, atol=1e-8)


def test_spectrum_gives_the_sines_amplitudes_and_phases(run):
    model, result, _ = run
    _, amplitudes, phases = model.fft.spectrum(result)
    ns = 40
    scale = ns / (ns + 2)  # the MSL divides |X| by ns/2 + 1, not ns/2
    # phases with respect to a cosine, at the first sample (t = 0.05)
    expected_a = [MEAN, 2.0 * scale, 0.0, 0.7 * scale, 0.0]
    expected_p = [0.0, math.degrees(2 * math.pi * 1 * 0.05 - math.pi / 2), 0.0,
                  math.degrees(2 * math.pi * 3 * 0.05 + 0.4), 0.0]
    np.testing.assert_allclose(amplitudes, expected_a, rtol=0, atol=1e-10)
    np.testing.assert_allclose(phases, expected_p, rtol=0, atol=1e-8)


def test_the_file_has_the_layout_of_real_fft_write_to_file(run):
    model, result, path = run
    assert scipy.io.matlab.matfile_version(str(path))[0] == 0  # MATLAB v4, as writeRealMatrix's default
    matrix = scipy.io.loadmat(str(path))["FFT"]
    amplitudes, phases = msl_spectrum(signal(0.05 + np.arange(40) / 40), 5)
    assert matrix.shape == (15, 3)
    f = 4 * np.arange(5) / 4  # f_max*(i - 1)/(nf - 1)
    np.testing.assert_allclose(matrix[:, 0], np.repeat(f, 3), rtol=0, atol=1e-15)
    np.testing.assert_array_equal(matrix[0::3, 1:], 0)
    np.testing.assert_array_equal(matrix[2::3, 1:], 0)
    np.testing.assert_allclose(matrix[1::3, 1], amplitudes, rtol=0, atol=1e-10)
    np.testing.assert_allclose(matrix[1::3, 2], phases, rtol=0, atol=1e-8)


def test_the_file_labels_frequencies_as_the_msl_does_when_f_max_is_no_multiple_of_f_res(tmp_path):
    # nf = ceil(3.5) + 1 = 5 points at 0, 1, ..., 4 Hz; the file spreads them over 0 ... f_max
    path = tmp_path / "odd.mat"
    model = fft_model(path, f_max=3.5, f_res=1)
    result = simulate(model)
    assert result.status == 0, result.message
    f, amplitudes, _ = model.fft.spectrum(result)
    np.testing.assert_allclose(f, [0, 1, 2, 3, 4], rtol=0, atol=1e-15)
    matrix = scipy.io.loadmat(str(path))["FFT"]
    np.testing.assert_allclose(matrix[1::3, 0], 3.5 * np.arange(5) / 4, rtol=0, atol=1e-15)
    expected, _ = msl_spectrum(signal(np.arange(36) / 36), 5)
    np.testing.assert_allclose(matrix[1::3, 1], expected, rtol=0, atol=1e-10)


# -- too short a run ----------------------------------------------------------------------


def test_a_run_too_short_to_take_ns_samples_fails_and_writes_no_file(tmp_path):
    path = tmp_path / "short.mat"
    model = fft_model(path, f_max=4, f_res=1, startTime=0.05)
    needed = 0.05 + 39 / 40  # startTime + (ns - 1)*samplePeriod
    result = simulate(model, stop_time=1.01)
    assert result.status == -1 and not result.success
    assert isinstance(result.error, AssertionViolation) and result.error.result is result
    assert f"Sampling time not sufficient! stopTime>= {needed:.12g}" in result.message
    assert result.final("fft.iTick") == math.floor((1.01 - 0.05) * 40) + 1 == 39
    assert not path.exists()
    with pytest.raises(ValueError, match="39 of 40 samples"):
        model.fft.spectrum(result)


def test_the_last_sample_at_the_stop_time_is_enough(tmp_path):
    path = tmp_path / "edge.mat"
    model = fft_model(path, f_max=4, f_res=1, startTime=0.05)
    # the engine's tick: start + i*interval, i = ns - 1, interval = 1/(2*f_res*div(ns, 2))
    result = simulate(model, stop_time=0.05 + 39 * (1 / (2 * 1 * 20)))
    assert result.status == 0, result.message
    assert result.final("fft.iTick") == 40 and path.exists()


def test_start_time_given_at_run_time_moves_the_samples_and_the_message(tmp_path):
    model = fft_model(tmp_path / "late.mat", f_max=4, f_res=1)
    result = simulate(model, parameters={"fft.startTime": 0.3})
    assert result.status == -1
    assert f"stopTime>= {0.3 + 39 / 40:.12g}" in result.message


def test_a_file_that_cannot_be_written_fails_the_run(tmp_path):
    model = fft_model(tmp_path / "missing" / "folder" / "x.mat", f_max=4, f_res=1)
    result = simulate(model)
    assert result.status == -1 and isinstance(result.error, SimulationError)
    assert "could not be written" in result.message


# -- the engine's hook --------------------------------------------------------------------


class Recording(Component):
    """Records the results its finish hook is given."""

    y = RealOutput()

    def __init__(self, **modifiers):
        super().__init__(**modifiers)
        object.__setattr__(self, "seen", [])

    def equations(self):
        return [Eq(self.y, time)]

    def finished(self, result) -> None:
        self.seen.append(result)


class Refusing(Recording):
    def finished(self, result) -> None:
        super().finished(result)
        raise AssertionViolation("refused at the end")


class Hooked(Model):
    experiment = Experiment(stop_time=1.0)
    fail_at = 2.0

    def build(self):
        self.a = Recording()
        self.b = Recording()

    def equations(self):
        return [Assert(time < self.fail_at, "too late")]


def test_the_hook_gets_the_result_of_a_successful_run_once_per_component():
    model = Hooked()
    result = simulate(model)
    assert result.status == 0
    assert finish_hooks(model) == [model.a, model.b]
    assert len(model.a.seen) == 1 and model.a.seen[0] is result
    assert len(model.b.seen) == 1 and model.b.seen[0] is result


def test_the_hook_is_not_called_for_a_failed_run_nor_for_a_translation():
    class Failing(Hooked):
        fail_at = 0.5

    model = Failing()
    failed = simulate(model)
    assert failed.status == -1 and model.a.seen == []
    ok = Hooked()
    assert simulate(translate(ok)).status == 0 and ok.a.seen == []


def test_a_simulation_error_from_the_hook_fails_the_run_and_stops_later_hooks():
    class Refused(Hooked):
        def build(self):
            self.a = Refusing()
            self.b = Recording()

    model = Refused()
    result = simulate(model)
    assert result.status == -1 and result.message == "refused at the end"
    assert isinstance(result.error, AssertionViolation) and result.error.result is result
    assert len(model.a.seen) == 1 and model.b.seen == []
    np.testing.assert_allclose(result.final("a.y"), 1.0)  # the run's values are kept
