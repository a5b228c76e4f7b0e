"""Analog filters of Modelica.Blocks.Continuous: CriticalDamping, LowpassButterworth and Filter.

:class:`CriticalDamping` and :class:`LowpassButterworth` are the two fixed
low pass filters of the MSL; :class:`Filter` is the general one: low, high,
band pass or band stop (:class:`FilterType`) with critical damping, Bessel,
Butterworth or Chebyshev I characteristics (:class:`AnalogFilter`).

The coefficients of :class:`Filter` follow the MSL's functions
(``Modelica.Blocks.Continuous.Internal.Filter``), written here as Python:

* ``base``: the prototype low pass with cut-off 1 rad/s, factored into first
  order terms ``s + cr`` and second order terms ``s^2 + c1*s + c0``
  (:func:`base_critical_damping`, :func:`base_bessel`,
  :func:`base_butterworth`, :func:`base_chebyshev`).  The Bessel factors are
  computed as the MSL documents its table: the roots of the Bessel
  polynomial, evaluated with 40 digits, after scaling its -3 dB frequency to
  1 rad/s (:func:`bessel_base_coefficients`).
* ``roots``: the transformation to the cut-off frequency and filter type,
  as the real eigenvalues ``r``, the complex pairs ``a +- j*b`` and the
  gains ``ku``, ``k1``, ``k2`` of the block's equations
  (:func:`roots_low_pass`, :func:`roots_high_pass`, :func:`roots_band_pass`,
  :func:`roots_band_stop`).

The prototype depends on the structural parameters only (order, analog
filter, normalized, A_ripple), so it is computed once, in Python, when the
block is built.  The ``roots`` are expressions of the cut-off frequencies,
which therefore stay tunable parameters: the MSL finds the band transformation's
``alpha`` with a root finder, here it is the closed-form root of the same
(palindromic) quartic.
"""

from __future__ import annotations

import enum
import functools
import math
from typing import Any, Callable

import mpmath
import numpy as np
import sympy as sp

from acausal.components.blocks import SISO
from acausal.components.checks import parameter_number, where
from acausal.components.declarations import DerivedDefaults
from acausal.errors import ParameterError
from acausal.language import Component, Eq, Parameter, RealOutput, der

from .continuous import Init, _init_type, _SizedByValues
from .types import initial_equations_for

__all__ = ["AnalogFilter", "FilterType", "CriticalDamping", "LowpassButterworth", "Filter",
           "base_critical_damping", "base_bessel", "base_butterworth", "base_chebyshev",
           "bessel_base_coefficients", "to_highest_power_one", "normalization_factor", "band_pass_alpha",
           "prototype", "roots_low_pass", "roots_high_pass", "roots_band_pass", "roots_band_stop", "filter_roots"]

#: Amplitude of a -3 dB cut-off as the MSL defines it: 10^(-3/20) (not 1/sqrt(2)).
MINUS_3_DB = 10 ** (-3 / 20)


class AnalogFilter(enum.IntEnum):
    """Analog filter characteristics (Modelica.Blocks.Types.AnalogFilter); the values are Modelica's ordinals."""

    CriticalDamping = 1  #: filter with critical damping (real poles only)
    Bessel = 2  #: Bessel filter (nearly constant group delay)
    Butterworth = 3  #: Butterworth filter (maximally flat pass band)
    ChebyshevI = 4  #: Chebyshev I filter (ripple in the pass band, steeper roll-off)


class FilterType(enum.IntEnum):
    """Type of an analog filter (Modelica.Blocks.Types.FilterType); the values are Modelica's ordinals."""

    LowPass = 1  #: low pass filter
    HighPass = 2  #: high pass filter
    BandPass = 3  #: band pass filter
    BandStop = 4  #: band stop / notch filter


# set after the body: in an IntEnum's body a str would become a member
AnalogFilter.modelica_name = "Modelica.Blocks.Types.AnalogFilter"
FilterType.modelica_name = "Modelica.Blocks.Types.FilterType"


def _enum_value(klass: type[enum.IntEnum], value: Any) -> enum.IntEnum:
    """``value`` as a member of ``klass`` (also accepts its name)."""
    return klass[value] if isinstance(value, str) else klass(value)


# --------------------------------------------------------------------------
# Prototype low pass filters (w_cut = 1 rad/s): Internal.Filter.base and Utilities
# --------------------------------------------------------------------------

#: One prototype: (cr, c0, c1) with factors s + cr[i] and s^2 + c1[i]*s + c0[i].
Prototype = tuple[np.ndarray, np.ndarray, np.ndarray]


def to_highest_power_one(den1: np.ndarray, den2: np.ndarray) -> Prototype:
    """Factors ``den1[i]*s + 1`` and ``den2[i,0]*s^2 + den2[i,1]*s + 1`` as monic ones.

    Parameters
    ----------
    den1 : array of shape (n1,)
        Coefficients of the first order factors ``den1[i]*s + 1``.
    den2 : array of shape (n2, 2)
        Coefficients ``[s^2, s]`` of the second order factors.

    Returns
    -------
    cr, c0, c1 : ndarray
        ``s + cr[i]`` and ``s^2 + c1[i]*s + c0[i]`` (times constants that the
        unit gain at s = 0 absorbs).
    """
    den1 = np.asarray(den1, dtype=float).reshape(-1)
    den2 = np.asarray(den2, dtype=float).reshape(-1, 2)
    return 1 / den1, 1 / den2[:, 0], den2[:, 1] / den2[:, 0]


def _scaled(den1: np.ndarray, den2: np.ndarray, alpha: float) -> tuple[np.ndarray, np.ndarray]:
    """The factors with ``s`` replaced by ``alpha*s`` (a frequency scaling by 1/alpha)."""
    den2 = np.array(den2, dtype=float).reshape(-1, 2)
    den2[:, 0] *= alpha**2
    den2[:, 1] *= alpha
    return np.asarray(den1, dtype=float) * alpha, den2


def normalization_factor(den1: np.ndarray, den2: np.ndarray) -> float:
    """The ``alpha`` for which the low pass ``1/prod(factors(alpha*s))`` has -3 dB at 1 rad/s.

    As MSL's ``Utilities.normalizationFactor``: the amplitude is
    ``10^(-3/20)``, the root is bracketed by growing ``alpha`` from 1 by 10 %
    steps and found by Brent's method.

    Parameters
    ----------
    den1, den2 : array
        The factors ``den1[i]*s + 1`` and ``den2[i,0]*s^2 + den2[i,1]*s + 1``.
    """
    den1 = np.asarray(den1, dtype=float).reshape(-1)
    den2 = np.asarray(den2, dtype=float).reshape(-1, 2)

    def residue(alpha: float) -> float:
        alpha2 = alpha * alpha
        squared_amplitude = np.prod(1 + den1**2 * alpha2)
        squared_amplitude *= np.prod(1 + (den2[:, 1]**2 - 2 * den2[:, 0]) * alpha2 + den2[:, 0]**2 * alpha2**2)
        return 1 / math.sqrt(squared_amplitude) - MINUS_3_DB

    alpha_max = 1.0
    while residue(alpha_max) >= 0:
        alpha_max *= 1.1
    from scipy.optimize import brentq  # only here: most models have no such filter

    return brentq(residue, 0.0, alpha_max, xtol=1e-300, rtol=4 * np.finfo(float).eps, maxiter=500)


@functools.lru_cache(maxsize=None)
def bessel_base_coefficients(order: int) -> tuple[tuple[float, ...], tuple[tuple[float, float], ...], float]:
    """Factors of the Bessel low pass normalized to -3 dB at 1 rad/s (MSL's ``BesselBaseCoefficients``).

    The Bessel polynomial ``Bn(p) = sum_k (2n-k)!/((n-k)! k! 2^(n-k)) p^k``
    has the amplitude ``|Bn(0)/Bn(j*w0)| = 10^(-3/20)`` at one frequency
    ``w0``; the roots of ``Bn(w0*p)`` give the factors ``a*p + 1`` (the real
    root of an odd order) and ``b2*p^2 + b1*p + 1`` (each complex pair,
    the most damped first, as the MSL's table lists them).  The MSL stores the
    results of this computation for orders 1..41; it is done here with 40
    digits (mpmath) and agrees with that table to the last digit.

    Parameters
    ----------
    order : int
        Order of the filter, >= 1.

    Returns
    -------
    den1 : tuple of float
        ``a`` of the first order factor (empty for an even order).
    den2 : tuple of (float, float)
        ``(b2, b1)`` of each second order factor.
    alpha : float
        ``1/w0``: replacing ``p`` by ``alpha*p`` gives the filter whose
        group delay at low frequencies is 1 s (the unnormalized Bessel filter).
    """
    if order < 1:
        raise ParameterError(f"a Bessel filter of order {order}", hint="the order must be at least 1")
    with mpmath.workdps(40):
        coefficients = [mpmath.factorial(2 * order - k)
                        / (mpmath.factorial(order - k) * mpmath.factorial(k) * mpmath.mpf(2) ** (order - k))
                        for k in range(order + 1)]
        target = coefficients[0] ** 2 * mpmath.mpf(10) ** (mpmath.mpf(3) / 10)

        def excess(w):  # |Bn(jw)|^2 - |Bn(0)|^2 * 10^(3/10): increases with w, one root
            return abs(mpmath.polyval(coefficients[::-1], 1j * w)) ** 2 - target

        low, high = mpmath.mpf(0), mpmath.mpf(1)
        while excess(high) < 0:
            high *= 2
        for _ in range(140):  # bisection to below the working precision
            middle = (low + high) / 2
            low, high = (middle, high) if excess(middle) < 0 else (low, middle)
        w0 = (low + high) / 2
        scaled = [c * w0**k for k, c in enumerate(coefficients)]
        roots = mpmath.polyroots(scaled[::-1], maxsteps=300, extraprec=200)
        tiny = mpmath.mpf(10) ** -30
        real = [root for root in roots if abs(mpmath.im(root)) < tiny]
        upper = sorted((root for root in roots if mpmath.im(root) >= tiny), key=lambda root: mpmath.im(root))
        den1 = tuple(float(-1 / mpmath.re(root)) for root in real)
        den2 = tuple((float(1 / abs(root) ** 2), float(-2 * mpmath.re(root) / abs(root) ** 2)) for root in upper)
        return den1, den2, float(1 / w0)


def base_critical_damping(order: int, normalized: bool = True) -> Prototype:
    """Prototype of the critically damped low pass: ``order`` equal real poles (MSL ``base.CriticalDamping``).

    Normalized, the poles are at ``1/alpha`` with ``alpha = sqrt(10^(3/10/order) - 1)``
    (-3 dB at 1 rad/s); otherwise at 1.
    """
    alpha = math.sqrt(10 ** (3 / 10 / order) - 1) if normalized else 1.0
    return to_highest_power_one(np.full(order, alpha), np.zeros((0, 2)))


def base_bessel(order: int, normalized: bool = True) -> Prototype:
    """Prototype of the Bessel low pass (MSL ``base.Bessel``): -3 dB at 1 rad/s, or unit delay if not normalized."""
    den1, den2, alpha = bessel_base_coefficients(order)
    if not normalized:
        return to_highest_power_one(*_scaled(np.array(den1), np.array(den2), alpha))
    return to_highest_power_one(np.array(den1), np.array(den2))


def base_butterworth(order: int, normalized: bool = True) -> Prototype:
    """Prototype of the Butterworth low pass (MSL ``base.Butterworth``): poles on the unit circle.

    Its amplitude at 1 rad/s is ``1/sqrt(2)`` whether ``normalized`` or not
    (the MSL leaves the normalization to -3 dB out for this filter).
    """
    pairs = order // 2
    den2 = np.array([[1.0, -2 * math.cos(math.pi * (0.5 + (i - 0.5) / order))] for i in range(1, pairs + 1)])
    return to_highest_power_one(np.ones(order % 2), den2.reshape(-1, 2))


def base_chebyshev(order: int, A_ripple: float = 0.5, normalized: bool = True) -> Prototype:  # noqa: N803
    """Prototype of the Chebyshev I low pass with pass band ripple ``A_ripple`` dB (MSL ``base.ChebyshevI``).

    Not normalized, the amplitude is ``10^(-A_ripple/20)`` at 1 rad/s (the
    edge of the ripple band); normalized, -3 dB there.
    """
    epsilon = math.sqrt(10 ** (A_ripple / 10) - 1)
    fac = math.asinh(1 / epsilon) / order
    den1 = np.full(order % 2, 1 / math.sinh(fac))
    # the angles of the pairs' poles: (2i-1)*pi/(2n) for an even order, i*pi/n for an odd one
    angle = ((lambda i: (2 * i - 1) * math.pi / (2 * order)) if order % 2 == 0
             else (lambda i: i * math.pi / order))
    den2 = np.zeros((order // 2, 2))
    for i in range(1, order // 2 + 1):
        den2[i - 1, 0] = 1 / (math.cosh(fac) ** 2 - math.cos(angle(i)) ** 2)
        den2[i - 1, 1] = 2 * den2[i - 1, 0] * math.sinh(fac) * math.cos(angle(i))
    if normalized:
        den1, den2 = _scaled(den1, den2, normalization_factor(den1, den2))
    return to_highest_power_one(den1, den2)


def prototype(analog_filter: AnalogFilter, order: int, normalized: bool = True,
              A_ripple: float = 0.5) -> Prototype:  # noqa: N803 - Modelica's name
    """The prototype low pass (``cr``, ``c0``, ``c1``) of ``analog_filter``, as Filter's initial equations choose it."""
    analog_filter = _enum_value(AnalogFilter, analog_filter)
    if analog_filter is AnalogFilter.CriticalDamping:
        return base_critical_damping(order, normalized)
    if analog_filter is AnalogFilter.Bessel:
        return base_bessel(order, normalized)
    if analog_filter is AnalogFilter.Butterworth:
        return base_butterworth(order, normalized)
    return base_chebyshev(order, A_ripple, normalized)


# --------------------------------------------------------------------------
# Transformation to the block's roots: Internal.Filter.coefficients and roots
# --------------------------------------------------------------------------


def _is_symbolic(*values: Any) -> bool:
    return any(isinstance(v, sp.Basic) and not v.is_number for v in values)


def _sqrt(value: Any) -> Any:
    """Square root of a number or of a sympy expression (of tunable parameters)."""
    return sp.sqrt(value) if isinstance(value, sp.Basic) else math.sqrt(value)


def band_pass_alpha(a: Any, b: Any, w: Any) -> Any:
    """MSL's ``Utilities.bandPassAlpha``: the ``alpha`` splitting the band transform of ``s^2 + a*s + b``.

    The band transformation ``s -> (s + 1/s)/w`` makes the pair a fourth
    order polynomial, written as the product of two pairs with the roots
    scaled by ``alpha`` and ``1/alpha``; ``z = alpha^2`` is the root in
    ``(0, 1]`` of ``z^2 + (a*w*z/(1+z))^2 - (2 + b*w^2)*z + 1 = 0``.  Times
    ``(1+z)^2`` the equation is a palindromic quartic, so with
    ``t = z + 1/z`` it is the quadratic ``t^2 - b*w^2*t + a^2*w^2 - 4 - 2*b*w^2 = 0``,
    whose larger root is the ``t >= 2`` of the ``z`` in (0, 1] (the MSL
    solves the quartic numerically).  Works on numbers and on sympy
    expressions of parameters.

    Parameters
    ----------
    a, b : number or sympy expression
        Coefficients of ``s`` and ``s^0`` of the pair (``a^2/4 <= b``).
    w : number or sympy expression
        Relative band width.
    """
    if not _is_symbolic(a, b, w) and a * a / 4 - b > 0:
        raise ParameterError("the band transformation of a factor with real roots cannot be split into pairs",
                             hint="use another analog filter for the band pass / band stop")
    bw2 = b * w**2
    t = (bw2 + _sqrt((bw2 + 4) ** 2 - 4 * a**2 * w**2)) / 2
    z = 2 / (t + _sqrt(t**2 - 4))  # = (t - sqrt(t^2-4))/2, without the cancellation
    return _sqrt(z)


#: The roots of a filter: r (real eigenvalues), a, b (complex pairs a +- j*b), ku, k1, k2 (gains).
Roots = dict[str, list[Any]]


def roots_low_pass(cr: np.ndarray, c0: np.ndarray, c1: np.ndarray, f_cut: Any) -> Roots:
    """Low pass with cut-off ``f_cut`` (MSL ``roots.lowPass``): ``r``, ``a``, ``b``, ``ku``.

    The prototype's ``s`` becomes ``s/w_cut``; a real pole gives
    ``der(x) = r*(x - u)``, a pair ``der(x1) = a*x1 - b*x2 + ku*u``,
    ``der(x2) = b*x1 + a*x2`` with output ``x2`` (unit gain at s = 0).
    """
    w = 2 * sp.pi * f_cut if _is_symbolic(f_cut) else 2 * math.pi * f_cut
    result: Roots = {"r": [-w * float(c) for c in cr], "a": [], "b": [], "ku": []}
    for c0_i, c1_i in zip(c0, c1):
        a = -float(c1_i) / 2
        b = math.sqrt(c0_i - a * a)
        result["a"].append(w * a)
        result["b"].append(w * b)
        result["ku"].append(w * float(c0_i) / b)
    return result


def roots_high_pass(cr: np.ndarray, c0: np.ndarray, c1: np.ndarray, f_cut: Any) -> Roots:
    """High pass with cut-off ``f_cut`` (MSL ``roots.highPass``): ``r``, ``a``, ``b``, ``ku``, ``k1``, ``k2``.

    The prototype's ``s`` becomes ``w_cut/s``; a real pole's output is
    ``u - x``, a pair's ``k1*x1 + k2*x2 + u``.
    """
    w = 2 * sp.pi * f_cut if _is_symbolic(f_cut) else 2 * math.pi * f_cut
    result: Roots = {"r": [-w / float(c) for c in cr], "a": [], "b": [], "ku": [], "k1": [], "k2": []}
    for c0_i, c1_i in zip(c0, c1):
        c0_h, c1_h = 1 / float(c0_i), float(c1_i) / float(c0_i)  # s -> 1/s, per unit w_cut
        a = -c1_h / 2
        b = math.sqrt(c0_h - a * a)
        ku = c0_h / b
        ba2 = (b / a) ** 2
        result["a"].append(w * a)
        result["b"].append(w * b)
        result["ku"].append(w * ku)
        result["k1"].append(2 * a / ku)
        result["k2"].append((1 - ba2) / (1 + ba2))
    return result


def _band_pairs(cr: np.ndarray, c0: np.ndarray, c1: np.ndarray, f_min: Any, f_max: Any,
                stop: bool) -> tuple[list[Any], list[Any], Any, Any]:
    """The pairs ``s^2 + c1u*s + c0u`` (per unit ``w_cut``) of the band transformation, ``w_cut``, ``w_band``.

    MSL ``coefficients.bandPass`` / ``bandStop``: a real pole gives one pair,
    a pair two (split with :func:`band_pass_alpha`).
    """
    symbolic = _is_symbolic(f_min, f_max)
    f0 = _sqrt(f_min * f_max)
    w_cut = 2 * (sp.pi if symbolic else math.pi) * f0
    w_band = (f_max - f_min) / f0
    c0_unit: list[Any] = []
    c1_unit: list[Any] = []
    for cr_i in cr:
        c1_unit.append(w_band / float(cr_i) if stop else float(cr_i) * w_band)
        c0_unit.append(1)
    for c0_i, c1_i in zip(c0, c1):
        ww = w_band / float(c0_i) if stop else w_band
        alpha = band_pass_alpha(float(c1_i), float(c0_i), ww)
        c = float(c1_i) * ww / (alpha + 1 / alpha)
        c1_unit += [c / alpha, c * alpha]
        c0_unit += [1 / alpha**2, alpha**2]
    return c0_unit, c1_unit, w_cut, w_band


def _check_complex(bb: Any, kind: str) -> None:
    if not _is_symbolic(bb) and bb < 0:
        raise ParameterError(f"the {kind} transformation of this filter gives real poles, not conjugate "
                             f"complex ones", hint=f"use another analog filter for the {kind} (or a narrower band)")


def roots_band_pass(cr: np.ndarray, c0: np.ndarray, c1: np.ndarray, f_min: Any, f_max: Any) -> Roots:
    """Band pass from ``f_min`` to ``f_max`` (MSL ``roots.bandPass``): pairs ``a``, ``b``, ``ku``, ``k1``, ``k2``.

    Each pair is ``cn*s/(s^2 + c1*s + c0)`` with ``cn = w_band*w_cut``,
    realized as ``der(x1) = a*x1 - b*x2 + ku*u``, ``der(x2) = b*x1 + a*x2``,
    ``y = k1*x1 + k2*x2``.
    """
    c0_unit, c1_unit, w_cut, w_band = _band_pairs(cr, c0, c1, f_min, f_max, stop=False)
    result: Roots = {"r": [], "a": [], "b": [], "ku": [], "k1": [], "k2": []}
    for c0_u, c1_u in zip(c0_unit, c1_unit):
        a_u = -c1_u / 2
        bb_u = c0_u - a_u * a_u
        _check_complex(bb_u, "band pass")
        b_u = _sqrt(bb_u)
        ku = w_cut * c0_u / b_u
        result["a"].append(w_cut * a_u)
        result["b"].append(w_cut * b_u)
        result["ku"].append(ku)
        result["k1"].append(w_band * w_cut / ku)
        result["k2"].append(w_band * w_cut * a_u / (b_u * ku))
    return result


def roots_band_stop(cr: np.ndarray, c0: np.ndarray, c1: np.ndarray, f_min: Any, f_max: Any) -> Roots:
    """Band stop from ``f_min`` to ``f_max`` (MSL ``roots.bandStop``): pairs ``a``, ``b``, ``ku``, ``k1``, ``k2``.

    Each pair is ``(s^2 + c0)/(s^2 + c1*s + c0)``, realized as the band
    pass's states with ``y = k1*x1 + k2*x2 + u``.
    """
    c0_unit, c1_unit, w_cut, _ = _band_pairs(cr, c0, c1, f_min, f_max, stop=True)
    result: Roots = {"r": [], "a": [], "b": [], "ku": [], "k1": [], "k2": []}
    for c0_u, c1_u in zip(c0_unit, c1_unit):
        a_u = -c1_u / 2
        bb_u = c0_u - a_u * a_u
        _check_complex(bb_u, "band stop")
        b_u = _sqrt(bb_u)
        ku_u = c0_u / b_u
        result["a"].append(w_cut * a_u)
        result["b"].append(w_cut * b_u)
        result["ku"].append(w_cut * ku_u)
        result["k1"].append(2 * a_u / ku_u)
        result["k2"].append((c0_u + a_u**2 - b_u**2) / (b_u * ku_u))
    return result


def filter_roots(analog_filter: AnalogFilter, filter_type: FilterType, order: int, f_cut: Any,
                 f_min: Any = 0.0, normalized: bool = True, A_ripple: float = 0.5) -> Roots:  # noqa: N803
    """The roots and gains of :class:`Filter` for its parameters (numbers, or f_cut/f_min as expressions).

    Returns
    -------
    dict
        ``r``: real eigenvalues; ``a``, ``b``: real and imaginary parts of
        the complex pairs; ``ku``: their input gains; ``k1``, ``k2``: the
        output gains of a pair (high pass, band pass, band stop).
    """
    cr, c0, c1 = prototype(analog_filter, order, normalized, A_ripple)
    filter_type = _enum_value(FilterType, filter_type)
    if filter_type is FilterType.LowPass:
        return roots_low_pass(cr, c0, c1, f_cut)
    if filter_type is FilterType.HighPass:
        return roots_high_pass(cr, c0, c1, f_cut)
    if filter_type is FilterType.BandPass:
        return roots_band_pass(cr, c0, c1, f_min, f_cut)
    return roots_band_stop(cr, c0, c1, f_min, f_cut)


# --------------------------------------------------------------------------
# Blocks
# --------------------------------------------------------------------------


def _critical_damping_alpha(block: Component) -> Any:
    """Frequency correction of CriticalDamping: ``sqrt(2^(1/n) - 1)`` normalized (-3.01 dB at f), else 1."""
    return sp.sqrt(2 ** sp.Rational(1, block.n) - 1) if block.normalized else sp.Integer(1)


class CriticalDamping(_SizedByValues, DerivedDefaults, SISO):
    """Output the input signal filtered with an n-th order filter with critical damping
    (Modelica.Blocks.Continuous.CriticalDamping).

    ``y = u/(s/w + 1)^n``: ``n`` first order filters in series, states
    ``x[1..n]``, ``y = x[n]``, with ``w = 2*pi*f/alpha``.  ``normalized``
    (the default) sets ``alpha = sqrt(2^(1/n) - 1)`` so that the amplitude
    at ``f`` is ``1/sqrt(2)`` whatever the order; otherwise ``alpha = 1``.
    The step response has no overshoot, which is why the MSL recommends it
    to filter the input of an inverse model.

    ``initType`` (``NoInit`` by default): ``SteadyState``: ``der(x) = 0``;
    ``InitialState``: ``x = x_start``; ``InitialOutput``: ``y = y_start``
    and ``der(x[1:n-1]) = 0``.
    """

    modelica_name = "Modelica.Blocks.Continuous.CriticalDamping"

    n = Parameter(2, structural=True, min=1, description="Order of filter")
    f = Parameter(1.0, unit="Hz", description="Cut-off frequency")
    normalized = Parameter(True, structural=True,
                           description="= true, if amplitude at f_cut is 3 dB, otherwise unmodified filter")
    initType = Parameter(Init.NoInit, structural=True,  # noqa: N815 - Modelica's name
                         description="Type of initialization (1: no init, 2: steady state, 3: initial state, "
                                     "4: initial output)")
    x_start = Parameter(0.0, shape="n", description="Initial or guess values of states")
    y_start = Parameter(0.0, description="Initial value of output (remaining states are in steady state)")
    alpha = Parameter(None, description="Frequency correction factor for normalized filter")
    w = Parameter(None, unit="rad/s", description="2*pi*f/alpha: the corner frequency of each stage")
    x = RealOutput("n", start=lambda block: block.x_start, description="Filter states")

    derived_defaults = {"alpha": _critical_damping_alpha,
                        "w": lambda block: 2 * sp.pi * block.f / block.alpha}

    @classmethod
    def derived_sizes(cls, value: Callable[[str], Any]) -> dict[str, tuple[int, str]]:
        """None: ``n`` is given; checked to be at least 1."""
        if int(value("n")) < 1:
            raise ParameterError(f"{cls.__name__}.n = {value('n')}", hint="the order of the filter is at least 1")
        return {}

    def equations(self) -> list:
        x, w, n = self.x, self.w, self.n
        equations = [Eq(der(x[1]), (self.u - x[1]) * w)]
        equations += [Eq(der(x[i]), (x[i - 1] - x[i]) * w) for i in range(2, n + 1)]
        equations.append(Eq(self.y, x[n]))
        return equations

    def initial_equations(self) -> list:
        return initial_equations_for(self.initType, [Eq(der(self.x), 0)], [Eq(self.x, self.x_start)],
                                     [Eq(self.y, self.y_start)] + [Eq(der(self.x[i]), 0) for i in range(1, self.n)])


class LowpassButterworth(_SizedByValues, SISO):
    """Output the input signal filtered with a low pass Butterworth filter of any order
    (Modelica.Blocks.Continuous.LowpassButterworth).

    A series of ``m = n div 2`` second order sections (states ``x1[i]``,
    ``x2[i] = der(x1[i])``, output ``x1[i]``) and, for an odd order, a first
    order filter (state ``xr``; for an even order ``xr = 0``).  The poles lie
    on the circle of radius ``w = 2*pi*f``, so the amplitude at ``f`` is
    ``1/sqrt(2)`` for every order.

    ``initType`` (``NoInit`` by default): ``SteadyState``: all state
    derivatives zero; ``InitialState``: ``x1 = x1_start``, ``x2 = x2_start``
    (and ``xr = xr_start``); ``InitialOutput``: ``y = y_start`` with the
    sections in steady state: ``der(x1) = 0`` and, for an even order,
    ``der(x2[1:m-1]) = 0``; for an odd order ``der(x2) = 0`` (MSL 4.1.0 states
    ``der(x1) = 0`` twice there, a singular system; its count says ``der(x2)``
    was meant).
    """

    modelica_name = "Modelica.Blocks.Continuous.LowpassButterworth"

    n = Parameter(2, structural=True, min=1, description="Order of filter")
    f = Parameter(1.0, unit="Hz", description="Cut-off frequency")
    initType = Parameter(Init.NoInit, structural=True,  # noqa: N815 - Modelica's name
                         description="Type of initialization (1: no init, 2: steady state, 3: initial state, "
                                     "4: initial output)")
    x1_start = Parameter(0.0, shape="m", description="Initial or guess values of states 1 (der(x1)=x2)")
    x2_start = Parameter(0.0, shape="m", description="Initial or guess values of states 2")
    xr_start = Parameter(0.0, description="Initial or guess value of real pole for uneven order otherwise dummy")
    y_start = Parameter(0.0, description="Initial value of output (states are initialized in steady state if "
                                         "possible)")
    m = Parameter(1, structural=True, description="Number of second order sections, n div 2 (set from n)")
    x1 = RealOutput("m", start=lambda block: block.x1_start,
                    description="States 1 of second order filters (der(x1) = x2)")
    x2 = RealOutput("m", start=lambda block: block.x2_start, description="States 2 of second order filters")
    xr = RealOutput(start=lambda block: block.xr_start,
                    description="State of real pole for uneven order otherwise dummy")

    @classmethod
    def derived_sizes(cls, value: Callable[[str], Any]) -> dict[str, tuple[int, str]]:
        """``m = n div 2``, the number of complex pole pairs."""
        n = int(value("n"))
        if n < 1:
            raise ParameterError(f"{cls.__name__}.n = {n}", hint="the order of the filter is at least 1")
        return {"m": (n // 2, "n div 2")}

    @property
    def _even(self) -> bool:
        return self.n % 2 == 0

    def equations(self) -> list:
        n, m = self.n, self.m
        w = 2 * sp.pi * self.f
        equations = []
        stage_input = self.u  # MSL's z[i]: the input of section i
        for i in range(1, m + 1):
            angle = math.pi / 2 + math.pi / n * (i - 0.5)
            pole_real, pole_imag = math.cos(angle), math.sin(angle)
            w0 = (pole_real**2 + pole_imag**2) * w
            damping = -pole_real / (pole_real**2 + pole_imag**2)  # D[i] = -polereal/w0*w
            x1, x2 = self.x1[i], self.x2[i]
            equations += [Eq(der(x1), x2),
                          Eq(der(x2), w0**2 * stage_input - 2 * damping * w0 * x2 - w0**2 * x1)]
            stage_input = x1
        if self._even:
            equations += [Eq(self.xr, 0), Eq(self.y, stage_input)]
        else:
            equations += [Eq(der(self.xr), (stage_input - self.xr) * w), Eq(self.y, self.xr)]
        return equations

    def initial_equations(self) -> list:
        init = _init_type(self.initType)
        m = self.m
        x1 = [self.x1[i] for i in range(1, m + 1)]
        x2 = [self.x2[i] for i in range(1, m + 1)]
        if init is Init.SteadyState:
            states = x1 + x2 + ([] if self._even else [self.xr])
            return [Eq(der(x), 0) for x in states]
        if init is Init.InitialState:
            equations = [Eq(self.x1[i], self.x1_start[i]) for i in range(1, m + 1)]
            equations += [Eq(self.x2[i], self.x2_start[i]) for i in range(1, m + 1)]
            if not self._even:
                equations.append(Eq(self.xr, self.xr_start))
            return equations
        if init is Init.InitialOutput:
            steady = x1 + (x2[:-1] if self._even else x2)
            return [Eq(self.y, self.y_start)] + [Eq(der(x), 0) for x in steady]
        return []


def _filter_sizes(analog_filter: Any, filter_type: Any, order: int) -> dict[str, int]:
    """The sizes of Filter's arrays: ``nx`` states, ``ncr``/``nc0`` real poles/pairs of the prototype,
    ``nr``/``na`` real poles/pairs of the filter, ``nk`` output gains (none for a low pass)."""
    critical = _enum_value(AnalogFilter, analog_filter) is AnalogFilter.CriticalDamping
    filter_type = _enum_value(FilterType, filter_type)
    band = filter_type in (FilterType.BandPass, FilterType.BandStop)
    ncr = order if critical else order % 2
    nc0 = 0 if critical else order // 2
    na = order if band else nc0
    return {"nx": 2 * order if band else order, "ncr": ncr, "nc0": nc0, "na": na,
            "nr": 0 if band else ncr, "nk": 0 if filter_type is FilterType.LowPass else na}


#: Filter's coefficient parameters, computed from its other parameters (Modelica's fixed=false parameters).
_COMPUTED = ("cr", "c0", "c1", "r", "a", "b", "ku", "k1", "k2")


class Filter(_SizedByValues, SISO):
    """Continuous low pass, high pass, band pass or band stop IIR-filter of type CriticalDamping, Bessel,
    Butterworth or ChebyshevI (Modelica.Blocks.Continuous.Filter).

    ``analogFilter`` chooses the characteristics, ``filterType`` the type;
    ``order`` is the order of the low pass prototype (a band filter has
    ``2*order`` states).  ``f_cut`` is the cut-off frequency (band filters:
    the band is ``f_min .. f_cut``), ``gain`` the amplitude at zero
    frequency.  ``normalized`` (the default) scales the prototype so that the
    amplitude at ``f_cut`` is -3 dB (``10^(-3/20)``); a Butterworth filter is
    always normalized (``1/sqrt(2)`` at ``f_cut``), an unnormalized Bessel
    filter has the group delay ``1/(2*pi*f_cut)`` at low frequencies, an
    unnormalized Chebyshev filter the amplitude ``10^(-A_ripple/20)`` at
    ``f_cut``.

    The block is a chain of first order sections ``der(x) = r*(x - uu)``
    (real poles) and second order sections ``der(x1) = a*x1 - b*x2 +
    ku*uu``, ``der(x2) = b*x1 + a*x2`` (pairs ``a +- j*b``); each section's
    output (``x``, ``x2``, or with ``k1``, ``k2`` and the section's input)
    is the next one's input ``uu``, and ``y = gain*u_nominal*uu[end]``
    with ``uu[1] = u/u_nominal``.  Its output can be differentiated up to
    ``order`` times (index reduction differentiates the sections' equations).

    As in the MSL, a band pass section has the numerator ``w_band*w_cut*s``
    whatever the prototype's factor, so only a Butterworth band pass has the
    gain 1 at its centre frequency; a band stop section made from a
    prototype pair has its zeros at its own natural frequency, not at the
    centre frequency (the MSL's transformations, kept as they are).

    The prototype's coefficients ``cr``, ``c0``, ``c1`` are computed when the
    block is built, from the structural parameters ``analogFilter``,
    ``filterType``, ``order``, ``normalized`` and ``A_ripple`` (Modelica
    computes them in the initial equations of ``fixed=false`` parameters);
    the block's ``r``, ``a``, ``b``, ``ku``, ``k1``, ``k2`` are parameters
    bound to expressions of ``f_cut`` and ``f_min``, which stay tunable.

    ``init`` (``SteadyState`` by default): ``InitialState``: ``x = x_start``;
    ``SteadyState``: ``der(x) = 0``; ``InitialOutput``: ``y = y_start`` and
    ``der(x[1:nx-1]) = 0``; ``NoInit``: ``x_start`` is a guess.
    """

    modelica_name = "Modelica.Blocks.Continuous.Filter"

    analogFilter = Parameter(AnalogFilter.CriticalDamping, structural=True,  # noqa: N815 - Modelica's name
                             description="Analog filter characteristics (CriticalDamping/Bessel/Butterworth/"
                                         "ChebyshevI)")
    filterType = Parameter(FilterType.LowPass, structural=True,  # noqa: N815
                           description="Type of filter (LowPass/HighPass/BandPass/BandStop)")
    order = Parameter(2, structural=True, min=1, description="Order of filter")
    f_cut = Parameter(None, unit="Hz", description="Cut-off frequency")
    gain = Parameter(1.0, description="Gain (= amplitude of frequency response at zero frequency)")
    A_ripple = Parameter(0.5, unit="dB", structural=True,  # noqa: N815
                         description="Pass band ripple for Chebyshev filter (otherwise not used); > 0 required")
    f_min = Parameter(0.0, unit="Hz",
                      description="Band of band pass/stop filter is f_min (A=-3db*gain) .. f_cut (A=-3db*gain)")
    normalized = Parameter(True, structural=True,
                           description="= true, if amplitude at f_cut = -3db, otherwise unmodified filter")
    init = Parameter(Init.SteadyState, structural=True,
                     description="Type of initialization (no init/steady state/initial state/initial output)")
    x_start = Parameter(0.0, shape="nx", description="Initial or guess values of states")
    y_start = Parameter(0.0, description="Initial value of output")
    u_nominal = Parameter(1.0, description="Nominal value of input (used for scaling the states)")
    x = RealOutput("nx", start=lambda block: block.x_start, description="Filter states")

    # sizes, set from analogFilter, filterType and order
    nx = Parameter(2, structural=True, description="Number of states: order, or 2*order for band filters")
    ncr = Parameter(2, structural=True, description="Number of real poles of the prototype")
    nc0 = Parameter(0, structural=True, description="Number of conjugate complex pole pairs of the prototype")
    nr = Parameter(2, structural=True, description="Number of real poles")
    na = Parameter(0, structural=True, description="Number of conjugate complex pole pairs")
    nk = Parameter(0, structural=True, description="Number of output gains k1, k2 (na; 0 for a low pass)")
    # coefficients, computed (parameter_binding): Modelica's parameters with fixed=false
    cr = Parameter(0.0, shape="ncr", description="Coefficients of real poles of the prototype, s + cr (computed)")
    c0 = Parameter(0.0, shape="nc0", description="Coefficients of s^0 of the prototype's pairs (computed)")
    c1 = Parameter(0.0, shape="nc0", description="Coefficients of s^1 of the prototype's pairs (computed)")
    r = Parameter(0.0, shape="nr", description="Real eigenvalues (computed)")
    a = Parameter(0.0, shape="na", description="Real parts of complex conjugate eigenvalues (computed)")
    b = Parameter(0.0, shape="na", description="Imaginary parts of complex conjugate eigenvalues (computed)")
    ku = Parameter(0.0, shape="na", description="Input gains of the pairs (computed)")
    k1 = Parameter(0.0, shape="nk", description="Output gains of x1 of the pairs (computed)")
    k2 = Parameter(0.0, shape="nk", description="Output gains of x2 of the pairs (computed)")

    @classmethod
    def derived_sizes(cls, value: Callable[[str], Any]) -> dict[str, tuple[int, str]]:
        """The sizes from ``analogFilter``, ``filterType`` and ``order``."""
        order = int(value("order"))
        if order < 1:
            raise ParameterError(f"{cls.__name__}.order = {order}", hint="the order of the filter is at least 1")
        sizes = _filter_sizes(value("analogFilter"), value("filterType"), order)
        return {name: (size, "analogFilter, filterType and order") for name, size in sizes.items()}

    def parameter_binding(self, name: str) -> Any:
        array, _, index = name.partition("[")
        if array in _COMPUTED and index:
            return self._coefficients()[array][int(index.rstrip("]")) - 1]
        return super().parameter_binding(name)

    def _coefficients(self) -> dict[str, list[Any]]:
        """Every computed coefficient: the prototype's (numbers) and the roots (expressions of f_cut, f_min)."""
        # kept per path: the expressions name f_cut and f_min by the block's path
        memo = self.__dict__.setdefault("_computed", {})
        found = memo.get(self.path)
        if found is None:
            cr, c0, c1 = prototype(self.analogFilter, self.order, self.normalized, self.A_ripple)
            roots = self._roots(self.f_min, self.f_cut)
            found = memo[self.path] = {"cr": list(cr), "c0": list(c0), "c1": list(c1), "k1": [], "k2": [],
                                       **roots}
        return found

    def build(self) -> None:
        self.check_parameters()

    def check_parameters(self) -> None:
        """Raise ParameterError for the MSL's asserts on numeric values (expressions are left to flattening)."""
        if not self.A_ripple > 0:
            raise ParameterError(f"{where(self)}.A_ripple = {self.A_ripple:g} must be > 0",
                                 hint="A_ripple is the pass band ripple of a Chebyshev filter in dB")
        for name, hint in (("f_cut", "f_cut is the cut-off frequency"),
                           ("u_nominal", "u_nominal scales the states")):
            value = parameter_number(self, name)
            if value is not None and not value > 0:
                raise ParameterError(f"{where(self)}.{name} = {value:g} must be > 0", hint=hint,
                                     components=(self.path,))
        if self._filter_type in (FilterType.BandPass, FilterType.BandStop):
            f_min, f_cut = parameter_number(self, "f_min"), parameter_number(self, "f_cut")
            if f_min is not None and not f_min > 0:
                raise ParameterError(f"{where(self)}.f_min = {f_min:g} must be > 0 for a band pass or band stop "
                                     f"filter", hint="the band is f_min .. f_cut", components=(self.path,))
            if f_min is not None and f_cut is not None and not f_min < f_cut:
                raise ParameterError(f"{where(self)}: the band f_min = {f_min:g} .. f_cut = {f_cut:g} is empty",
                                     hint="the band is f_min .. f_cut, f_min < f_cut",
                                     components=(self.path,))
            if f_min is not None and f_cut is not None:
                self._roots(f_min, f_cut)  # raises where the band transformation has real poles

    @property
    def _filter_type(self) -> FilterType:
        return _enum_value(FilterType, self.filterType)

    def _roots(self, f_min: Any, f_cut: Any) -> Roots:
        return filter_roots(self.analogFilter, self._filter_type, self.order, f_cut, f_min,
                            self.normalized, self.A_ripple)

    def equations(self) -> list:
        filter_type = self._filter_type
        x, nr = self.x, self.nr
        stage_input = self.u / self.u_nominal  # MSL's uu[i]
        equations = []
        for i in range(1, nr + 1):
            equations.append(Eq(der(x[i]), self.r[i] * (x[i] - stage_input)))
            stage_input = x[i] if filter_type is FilterType.LowPass else stage_input - x[i]
        for i in range(1, self.na + 1):
            x1, x2 = x[nr + 2 * i - 1], x[nr + 2 * i]
            a, b = self.a[i], self.b[i]
            equations += [Eq(der(x1), a * x1 - b * x2 + self.ku[i] * stage_input),
                          Eq(der(x2), b * x1 + a * x2)]
            if filter_type is FilterType.LowPass:
                stage_input = x2
            elif filter_type is FilterType.BandPass:
                stage_input = self.k1[i] * x1 + self.k2[i] * x2
            else:
                stage_input = self.k1[i] * x1 + self.k2[i] * x2 + stage_input
        equations.append(Eq(self.y, self.gain * self.u_nominal * stage_input))
        return equations

    def initial_equations(self) -> list:
        return initial_equations_for(self.init, [Eq(der(self.x), 0)], [Eq(self.x, self.x_start)],
                                     [Eq(self.y, self.y_start)] + [Eq(der(self.x[i]), 0) for i in range(1, self.nx)])
