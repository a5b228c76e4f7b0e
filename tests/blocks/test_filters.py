"""Analog filters (Modelica.Blocks.Continuous.Filter, CriticalDamping, LowpassButterworth) and the inverse model.

The frequency responses of the blocks are those of their linearizations
(the engine's exact A, B, C, D of the equations the blocks write), compared
with scipy.signal's designs of the same filters (``butter``, ``cheby1``,
``bessel`` with ``analog=True``, and the band transformations ``lp2bp`` /
``lp2bs``) or with closed forms (critical damping: ``(1 + s/w)^-n``).  Where
the MSL's normalization differs from scipy's (-3 dB is ``10^(-3/20)`` in the
MSL, ``1/sqrt(2)`` in scipy) the reference frequency is found on scipy's
design with a root finder.  Step responses and the initialization options
are checked against closed forms by simulation.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
import scipy.signal as signal
from scipy.optimize import brentq

from acausal import Eq, Experiment, Model, simulate
from acausal.errors import ParameterError, StartValueWarning
from acausal.library.blocks import (AnalogFilter, Constant, CriticalDamping, Der, Filter, FilterType, Init,
                                    LowpassButterworth, Step)
from acausal.library.blocks.filters import base_bessel, bessel_base_coefficients
from acausal.library.blocks.math import InverseBlockConstraints
from acausal.tools.linearize import linearize

from library_checks import check_declarations

MINUS_3_DB = 10 ** (-3 / 20)
#: angular frequencies of the comparisons (rad/s), around the cut-offs used (1 .. 5 Hz)
W = np.logspace(-0.5, 2.5, 60)


def _responses(blocks: dict[str, object]) -> dict[str, np.ndarray]:
    """Frequency response ``y(jW)/u(jW)`` of each block, from one linearization of them side by side.

    The blocks' own initialization does not matter (a linear system's response is the same about every
    point); blocks without one warn that their states start from their start values.
    """

    class Bank(Model):
        experiment = Experiment(stop_time=1.0)

        def build(self):
            for name, block in blocks.items():
                setattr(self, f"src_{name}", Constant(k=0.0))
                setattr(self, name, block)
                self.connect(getattr(self, f"src_{name}").y, block.u)

    names = list(blocks)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", StartValueWarning)
        linear = linearize(Bank(), inputs=[f"src_{n}.y" for n in names],
                           outputs=[f"{n}.y" for n in names])
    a, b, c, d = linear.A, linear.B, linear.C, linear.D
    identity = np.eye(a.shape[0])
    found = {name: np.empty(len(W), dtype=complex) for name in names}
    for k, w in enumerate(W):
        h = c @ np.linalg.solve(1j * w * identity - a, b) + d
        for i, name in enumerate(names):
            found[name][k] = h[i, i]
    return found


def _scipy(b: np.ndarray, a: np.ndarray) -> np.ndarray:
    return signal.freqs(b, a, W)[1]


def _close(actual: np.ndarray, expected: np.ndarray, rtol: float = 1e-9) -> None:
    np.testing.assert_allclose(actual, expected, rtol=rtol, atol=rtol * np.max(np.abs(expected)))


def _minus_3_db_frequency(b: np.ndarray, a: np.ndarray) -> float:
    """The frequency where ``|H(jw)/H(0)|`` of scipy's low pass design crosses 10^(-3/20)."""
    reference = abs(np.polyval(b, 0) / np.polyval(a, 0))

    def excess(w: float) -> float:
        return abs(np.polyval(b, 1j * w) / np.polyval(a, 1j * w)) / reference - MINUS_3_DB

    return brentq(excess, 0.1, 10.0, xtol=1e-15, rtol=1e-15)


# --------------------------------------------------------------------------
# Prototypes
# --------------------------------------------------------------------------


@pytest.mark.parametrize("order", [1, 2, 3, 4, 5, 6, 7, 8, 12, 15])
def test_bessel_prototype_has_the_poles_of_scipys_delay_normalized_bessel_filter(order):
    cr, c0, c1 = base_bessel(order, normalized=False)
    poles = [-r for r in cr]
    for c0_i, c1_i in zip(c0, c1):
        poles += list(np.roots([1.0, c1_i, c0_i]))
    _, expected, _ = signal.besselap(order, norm="delay")
    np.testing.assert_allclose(np.sort_complex(np.array(poles, dtype=complex)), np.sort_complex(expected),
                               rtol=1e-12)


@pytest.mark.parametrize("order", [1, 2, 3, 5, 10])
def test_normalized_bessel_prototype_has_minus_3_db_at_one_rad_per_s(order):
    den1, den2, alpha = bessel_base_coefficients(order)
    polynomial = np.array([1.0])
    for a in den1:
        polynomial = np.polymul(polynomial, [a, 1.0])
    for b2, b1 in den2:
        polynomial = np.polymul(polynomial, [b2, b1, 1.0])
    assert abs(1 / np.polyval(polynomial, 1j)) == pytest.approx(MINUS_3_DB, rel=1e-13)
    # alpha is 1/w0 of the delay-normalized filter: scipy's design has -3 dB at 1/alpha
    b, a = signal.bessel(order, 1.0, norm="delay", analog=True)
    assert _minus_3_db_frequency(b, a) == pytest.approx(1 / alpha, rel=1e-12)
    # the pairs are listed most damped first, as in the MSL's table
    damping = [b1 / (2 * math.sqrt(b2)) for b2, b1 in den2]
    assert damping == sorted(damping, reverse=True)


# --------------------------------------------------------------------------
# Filter: frequency responses against scipy.signal
# --------------------------------------------------------------------------

F_CUT = 3.0
W_CUT = 2 * math.pi * F_CUT


def test_low_pass_filters_match_scipy_designs():
    blocks, expected = {}, {}
    for order in (1, 2, 3, 4, 5):
        for normalized in (True, False):  # a Butterworth filter is normalized either way
            name = f"butter{order}{'n' if normalized else 'u'}"
            blocks[name] = Filter(analogFilter=AnalogFilter.Butterworth, order=order, f_cut=F_CUT,
                                  normalized=normalized)
            expected[name] = _scipy(*signal.butter(order, W_CUT, analog=True))
        blocks[f"bessel{order}"] = Filter(analogFilter=AnalogFilter.Bessel, order=order, f_cut=F_CUT,
                                          normalized=False)
        expected[f"bessel{order}"] = _scipy(*signal.bessel(order, W_CUT, norm="delay", analog=True))
        # normalized: scipy's delay-normalized design moved so that 10^(-3/20) falls on f_cut
        b, a = signal.bessel(order, 1.0, norm="delay", analog=True)
        blocks[f"besseln{order}"] = Filter(analogFilter=AnalogFilter.Bessel, order=order, f_cut=F_CUT)
        expected[f"besseln{order}"] = _scipy(*signal.bessel(order, W_CUT / _minus_3_db_frequency(b, a),
                                                            norm="delay", analog=True))
        # Chebyshev: unit gain at s = 0 (scipy's even orders start at the bottom of the ripple)
        b, a = signal.cheby1(order, 0.5, W_CUT, analog=True)
        blocks[f"cheby{order}"] = Filter(analogFilter=AnalogFilter.ChebyshevI, order=order, f_cut=F_CUT,
                                         normalized=False)
        expected[f"cheby{order}"] = _scipy(b, a) * a[-1] / b[-1]
        b, a = signal.cheby1(order, 0.5, 1.0, analog=True)
        blocks[f"chebyn{order}"] = Filter(analogFilter=AnalogFilter.ChebyshevI, order=order, f_cut=F_CUT)
        b, a = signal.cheby1(order, 0.5, W_CUT / _minus_3_db_frequency(b, a), analog=True)
        expected[f"chebyn{order}"] = _scipy(b, a) * a[-1] / b[-1]
    responses = _responses(blocks)
    for name, response in responses.items():
        _close(response, expected[name])


def test_critical_damping_filter_is_n_equal_real_poles_with_minus_3_db_at_f_cut():
    blocks = {f"cd{n}": Filter(order=n, f_cut=F_CUT) for n in (1, 2, 3, 4)}
    blocks.update({f"cdu{n}": Filter(order=n, f_cut=F_CUT, normalized=False) for n in (1, 3)})
    responses = _responses(blocks)
    for n in (1, 2, 3, 4):
        alpha = math.sqrt(10 ** (3 / 10 / n) - 1)
        _close(responses[f"cd{n}"], (1 + 1j * W * alpha / W_CUT) ** -n)
        amplitude = abs((1 + 1j * alpha) ** -n)  # at f_cut
        assert amplitude == pytest.approx(MINUS_3_DB, rel=1e-12)
    for n in (1, 3):
        _close(responses[f"cdu{n}"], (1 + 1j * W / W_CUT) ** -n)


def test_high_pass_filters_match_scipy_designs():
    blocks, expected = {}, {}
    for order in (1, 2, 3, 4):
        blocks[f"butter{order}"] = Filter(analogFilter=AnalogFilter.Butterworth, filterType=FilterType.HighPass,
                                          order=order, f_cut=F_CUT)
        expected[f"butter{order}"] = _scipy(*signal.butter(order, W_CUT, btype="highpass", analog=True))
        blocks[f"bessel{order}"] = Filter(analogFilter=AnalogFilter.Bessel, filterType=FilterType.HighPass,
                                          order=order, f_cut=F_CUT, normalized=False)
        expected[f"bessel{order}"] = _scipy(*signal.bessel(order, W_CUT, btype="highpass", norm="delay",
                                                           analog=True))
        b, a = signal.cheby1(order, 1.0, W_CUT, btype="highpass", analog=True)
        blocks[f"cheby{order}"] = Filter(analogFilter=AnalogFilter.ChebyshevI, filterType=FilterType.HighPass,
                                         order=order, f_cut=F_CUT, A_ripple=1.0, normalized=False)
        expected[f"cheby{order}"] = _scipy(b, a) * a[0] / b[0]  # unit gain at infinite frequency
        blocks[f"cd{order}"] = Filter(filterType=FilterType.HighPass, order=order, f_cut=F_CUT, normalized=False)
        expected[f"cd{order}"] = (1 + W_CUT / (1j * W)) ** -order  # s -> w_cut/s in 1/(1 + s)^n
    for name, response in _responses(blocks).items():
        _close(response, expected[name])


F_MIN = 2.0
W_LOW, W_HIGH = 2 * math.pi * F_MIN, W_CUT
W_CENTRE = math.sqrt(W_LOW * W_HIGH)


def _at_centre(response: np.ndarray, b: np.ndarray | None = None, a: np.ndarray | None = None) -> np.ndarray:
    """``response`` divided by its value at the centre frequency (of the block: by simulation of W; of a
    scipy design: exactly, from ``b``, ``a``)."""
    if b is not None:
        return response / (np.polyval(b, 1j * W_CENTRE) / np.polyval(a, 1j * W_CENTRE))
    return response


def test_band_pass_filters_match_scipy_designs():
    """Butterworth: scipy's band pass as it is; the others up to a constant factor (the MSL's band pass
    sections have the numerator w_band*w_cut*s whatever the prototype's factor, see Filter)."""
    blocks, expected, up_to_factor = {}, {}, set()
    for order in (1, 2, 3):
        blocks[f"butter{order}"] = Filter(analogFilter=AnalogFilter.Butterworth, filterType=FilterType.BandPass,
                                          order=order, f_cut=F_CUT, f_min=F_MIN)
        expected[f"butter{order}"] = _scipy(*signal.butter(order, [W_LOW, W_HIGH], btype="bandpass",
                                                           analog=True))
        prototypes = {"bessel": (AnalogFilter.Bessel, signal.bessel(order, 1.0, norm="delay", analog=True)),
                      "cheby": (AnalogFilter.ChebyshevI, signal.cheby1(order, 0.5, 1.0, analog=True)),
                      "cd": (AnalogFilter.CriticalDamping, (np.array([1.0]), np.poly([-1.0] * order)))}
        for kind, (analog_filter, (b, a)) in prototypes.items():
            name = f"{kind}{order}"
            blocks[name] = Filter(analogFilter=analog_filter, filterType=FilterType.BandPass, order=order,
                                  f_cut=F_CUT, f_min=F_MIN, normalized=False)
            expected[name] = _scipy(*signal.lp2bp(b, a, W_CENTRE, W_HIGH - W_LOW))
            up_to_factor.add(name)
    for name, response in _responses(blocks).items():
        if name in up_to_factor:
            factor = response[0] / expected[name][0]
            assert abs(factor.imag) < 1e-9 * abs(factor)
            _close(response, factor.real * expected[name])
        else:
            _close(response, expected[name])


def test_band_stop_filters_with_real_prototype_poles_match_scipy_designs():
    """A real pole's section is scipy's band stop transformation exactly (unit gain at 0 and infinity)."""
    blocks = {"butter1": Filter(analogFilter=AnalogFilter.Butterworth, filterType=FilterType.BandStop,
                                order=1, f_cut=F_CUT, f_min=F_MIN),
              "cd2": Filter(filterType=FilterType.BandStop, order=2, f_cut=F_CUT, f_min=F_MIN, normalized=False)}
    responses = _responses(blocks)
    _close(responses["butter1"], _scipy(*signal.butter(1, [W_LOW, W_HIGH], btype="bandstop", analog=True)))
    _close(responses["cd2"], _scipy(*signal.lp2bs([1.0], np.poly([-1.0, -1.0]), W_CENTRE, W_HIGH - W_LOW)))


def test_band_stop_pair_sections_have_unit_gain_outside_and_a_notch_inside_the_band():
    responses = _responses({"bs": Filter(analogFilter=AnalogFilter.Butterworth, filterType=FilterType.BandStop,
                                         order=2, f_cut=F_CUT, f_min=F_MIN)})
    magnitude = np.abs(responses["bs"])
    assert magnitude[0] == pytest.approx(1.0, abs=1e-3) and magnitude[-1] == pytest.approx(1.0, abs=1e-3)
    inside = (W > W_LOW) & (W < W_HIGH)
    assert magnitude[inside].min() < 0.1


def test_gain_scales_the_response_and_u_nominal_does_not_change_it():
    responses = _responses({"plain": Filter(analogFilter=AnalogFilter.Bessel, order=3, f_cut=F_CUT),
                            "scaled": Filter(analogFilter=AnalogFilter.Bessel, order=3, f_cut=F_CUT, gain=2.5,
                                             u_nominal=40.0)})
    _close(responses["scaled"], 2.5 * responses["plain"])


# --------------------------------------------------------------------------
# Filter: initialization and parameter checks
# --------------------------------------------------------------------------


def _driven(block, u: float, stop_time: float = 0.5):
    class Driven(Model):
        experiment = Experiment(stop_time=stop_time, interval=stop_time / 100)

        def build(self):
            self.blk = block

        def equations(self):
            return [Eq(self.blk.u, u)]

    return simulate(Driven(), cache=False)


def test_filter_initialized_in_steady_state_holds_its_input():
    result = _driven(Filter(analogFilter=AnalogFilter.ChebyshevI, order=3, f_cut=F_CUT, gain=2.0), u=1.5)
    np.testing.assert_allclose(result["blk.y"], 3.0, rtol=1e-9)


def test_filter_initial_output_and_initial_state():
    result = _driven(Filter(analogFilter=AnalogFilter.Butterworth, order=3, f_cut=F_CUT,
                            init=Init.InitialOutput, y_start=0.4), u=1.0, stop_time=3.0)
    assert result["blk.y"][0] == pytest.approx(0.4, abs=1e-9)
    assert result["blk.y"][-1] == pytest.approx(1.0, abs=1e-3)
    result = _driven(Filter(order=2, f_cut=F_CUT, init=Init.InitialState, x_start=[0.0, 0.0],
                            normalized=False), u=1.0)
    t = result.time
    w = W_CUT
    np.testing.assert_allclose(result["blk.y"], 1 - np.exp(-w * t) * (1 + w * t), atol=1e-5)


@pytest.mark.parametrize("modifiers, fragment", [
    (dict(filterType=FilterType.BandPass, f_cut=2.0, f_min=0.0), "f_min = 0 must be > 0"),
    (dict(filterType=FilterType.BandStop, f_cut=2.0, f_min=3.0), "is empty"),
    (dict(f_cut=-1.0), "f_cut = -1 must be > 0"),
    (dict(f_cut=1.0, analogFilter=AnalogFilter.ChebyshevI, A_ripple=0.0), "A_ripple = 0 must be > 0"),
    (dict(f_cut=1.0, filterType=FilterType.BandPass, f_min=0.1), "real poles"),
])
def test_filter_rejects_the_parameters_the_msl_asserts_against(modifiers, fragment):
    with pytest.raises(ParameterError, match=fragment):
        _driven(Filter(**modifiers), u=1.0)


def test_filter_sizes_follow_type_and_order():
    assert len(Filter(order=3, filterType=FilterType.BandStop, f_cut=1.0).x) == 6
    assert len(Filter(order=3, analogFilter=AnalogFilter.Bessel, f_cut=1.0).x) == 3
    for block in (Filter(order=3, analogFilter=AnalogFilter.Bessel, filterType=FilterType.HighPass, f_cut=1.0),
                  Filter(order=2, filterType=FilterType.BandPass, f_cut=2.0, f_min=1.0),
                  CriticalDamping(n=3), LowpassButterworth(n=3)):
        check_declarations(block)


# --------------------------------------------------------------------------
# CriticalDamping and LowpassButterworth
# --------------------------------------------------------------------------


@pytest.mark.parametrize("n, normalized", [(1, True), (3, True), (3, False)])
def test_critical_damping_step_response_is_the_closed_form(n, normalized):
    f = 2.0
    result = _driven(CriticalDamping(n=n, f=f, normalized=normalized, initType=Init.InitialState), u=1.0,
                     stop_time=1.0)
    alpha = math.sqrt(2 ** (1 / n) - 1) if normalized else 1.0
    w = 2 * math.pi * f / alpha
    t = result.time
    expected = 1 - np.exp(-w * t) * sum((w * t) ** k / math.factorial(k) for k in range(n))
    np.testing.assert_allclose(result["blk.y"], expected, atol=2e-5)


def test_critical_damping_and_butterworth_blocks_have_their_frequency_responses():
    f = 1.5
    w_f = 2 * math.pi * f
    blocks = {f"cd{n}": CriticalDamping(n=n, f=f) for n in (1, 2, 4)}
    blocks.update({f"bw{n}": LowpassButterworth(n=n, f=f) for n in (1, 2, 3, 4, 5)})
    responses = _responses(blocks)
    for n in (1, 2, 4):
        alpha = math.sqrt(2 ** (1 / n) - 1)
        _close(responses[f"cd{n}"], (1 + 1j * W * alpha / w_f) ** -n)
    for n in (1, 2, 3, 4, 5):
        _close(responses[f"bw{n}"], _scipy(*signal.butter(n, w_f, analog=True)))


@pytest.mark.parametrize("init", [Init.SteadyState, Init.InitialOutput])
@pytest.mark.parametrize("n", [2, 3])
def test_lowpass_butterworth_initialization(init, n):
    result = _driven(LowpassButterworth(n=n, f=2.0, initType=init, y_start=0.5), u=1.0)
    y0 = 1.0 if init is Init.SteadyState else 0.5
    assert result["blk.y"][0] == pytest.approx(y0, abs=1e-9)
    if init is Init.SteadyState:
        np.testing.assert_allclose(result["blk.y"], 1.0, rtol=1e-9)


def test_critical_damping_initial_output_starts_at_y_start():
    result = _driven(CriticalDamping(n=3, f=2.0, initType=Init.InitialOutput, y_start=0.25), u=1.0)
    assert result["blk.y"][0] == pytest.approx(0.25, abs=1e-9)


# --------------------------------------------------------------------------
# Differentiating a filter's output; the inverse model
# --------------------------------------------------------------------------


def test_filter_output_can_be_differentiated_by_index_reduction():
    """Two Der blocks after a Bessel filter: the derivatives agree with the numerical ones of the output."""

    class Differentiated(Model):
        experiment = Experiment(stop_time=0.9, interval=0.0009)

        def build(self):
            self.step = Step(startTime=0.1, offset=0.1)
            self.filter = Filter(f_cut=2.0, order=3, analogFilter=AnalogFilter.Bessel)
            self.der1 = Der()
            self.der2 = Der()
            self.connect(self.step.y, self.filter.u)
            self.connect(self.filter.y, self.der1.u)
            self.connect(self.der1.y, self.der2.u)

    result = simulate(Differentiated(), cache=False)
    t = result.time
    after = t > 0.12  # away from the step (the second derivative jumps there; the event repeats t = 0.1)
    t = t[after]
    first = np.gradient(result["filter.y"][after], t)
    second = np.gradient(result["der1.y"][after], t)
    inner = slice(1, -1)  # central differences only
    np.testing.assert_allclose(result["der1.y"][after][inner], first[inner], atol=2e-3 * np.abs(first).max())
    np.testing.assert_allclose(result["der2.y"][after][inner], second[inner], atol=2e-3 * np.abs(second).max())


def test_inverse_model_computes_the_input_that_reproduces_the_filtered_signal():
    """InverseModel: firstOrder2, driven by the computed input, follows the filtered sine; the input is
    ``y + T*der(y)`` of the first order block with ``der(y)`` from the filter's equation."""
    from examples.blocks_inverse_model import InverseModel

    result = simulate(InverseModel(), cache=False)
    filtered = result["criticalDamping.y"]
    np.testing.assert_allclose(result["firstOrder2.y"], filtered, atol=1e-5)
    np.testing.assert_allclose(result["firstOrder1.y"], filtered, atol=1e-12)
    w = 2 * math.pi * 100.0 / math.sqrt(2 - 1)  # CriticalDamping(n=1, f=100): alpha = 1
    derivative = w * (result["sine.y"] - filtered)
    np.testing.assert_allclose(result["inverseBlockConstraints.y1"], filtered + 0.3 * derivative, atol=1e-6)


def test_inverse_block_constraints_is_balanced():
    check_declarations(InverseBlockConstraints())
