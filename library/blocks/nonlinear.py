"""Discontinuous or non-differentiable algebraic control blocks (Modelica.Blocks.Nonlinear).

Without ``strict`` the switching of a limiter is a state event (the relation
``u > uMax`` is watched and its crossing located); with ``strict = True`` it
is evaluated literally (``noEvent``), as Modelica's ``strict`` option says.
Modelica's ``homotopy(actual, simplified)`` is the actual expression here:
the engine has no homotopy-based initialization, so ``homotopyType`` is
accepted for compatibility and has no effect.

:class:`PadeDelay` approximates a delay by a rational transfer function;
:class:`FixedDelay` and :class:`VariableDelay` are exact, with Modelica's
``delay()`` operator (:func:`acausal.hybrid.delay`): the runtime reads the
delayed input back from the recorded solution.
"""

from __future__ import annotations

import enum
from typing import Sequence

import numpy as np
import sympy as sp

from acausal.components.blocks import SISO
from acausal.components.declarations import DerivedDefaults
from acausal.hybrid import Assert, delay, noEvent
from acausal.errors import ParameterError
from acausal.language import Eq, Parameter, RealInput, Variable, der

from .types import Init, _init_type
from .discrete import SMALL

__all__ = ["LimiterHomotopy", "VariableLimiterHomotopy", "Limiter", "VariableLimiter", "DeadZone",
           "SlewRateLimiter", "PadeDelay", "pade_coefficients", "balance_abc"]


class LimiterHomotopy(enum.IntEnum):
    """Homotopy type of Limiter (Modelica.Blocks.Types.LimiterHomotopy); no effect here."""

    NoHomotopy = 1
    Linear = 2
    UpperLimit = 3
    LowerLimit = 4


# set after the body: in an IntEnum's body a str would become a member
LimiterHomotopy.modelica_name = "Modelica.Blocks.Types.LimiterHomotopy"


class VariableLimiterHomotopy(enum.IntEnum):
    """Homotopy type of VariableLimiter (Modelica.Blocks.Types.VariableLimiterHomotopy); no effect here."""

    NoHomotopy = 1
    Linear = 2
    Fixed = 3


# set after the body: in an IntEnum's body a str would become a member
VariableLimiterHomotopy.modelica_name = "Modelica.Blocks.Types.VariableLimiterHomotopy"


def _literal(expr, strict: bool):
    """``expr`` under noEvent if ``strict`` (no events), else as is (state events)."""
    return noEvent(expr) if strict else expr


class Limiter(DerivedDefaults, SISO):
    """Limit the range of a signal (Modelica.Blocks.Nonlinear.Limiter).

    ``y = uMax`` if ``u > uMax``, ``uMin`` if ``u < uMin``, else ``u``.
    """

    modelica_name = "Modelica.Blocks.Nonlinear.Limiter"

    uMax = Parameter(1.0, description="Upper limits of input signals")  # noqa: N815
    uMin = Parameter(None, description="Lower limits of input signals (default -uMax)")  # noqa: N815
    strict = Parameter(False, structural=True, description="= true, if strict limits with noEvent(..)")
    homotopyType = Parameter(LimiterHomotopy.Linear, structural=True,  # noqa: N815
                             description="Simplified model for homotopy-based initialization (no effect here)")

    derived_defaults = {"uMin": lambda block: -block.uMax}

    def equations(self):
        limited = sp.Piecewise((self.uMax, self.u > self.uMax), (self.uMin, self.u < self.uMin),
                               (self.u, True))
        return [Assert(self.uMax >= self.uMin, "Limiter: Limits must be consistent. However, uMax < uMin"),
                Eq(self.y, _literal(limited, self.strict))]


class VariableLimiter(SISO):
    """Limit the range of a signal with variable limits (Modelica.Blocks.Nonlinear.VariableLimiter).

    ``y = limit1`` if ``u > limit1``, ``limit2`` if ``u < limit2``, else
    ``u``; the limits are inputs (``limit1 >= limit2`` is asserted).
    """

    modelica_name = "Modelica.Blocks.Nonlinear.VariableLimiter"

    strict = Parameter(False, structural=True, description="= true, if strict limits with noEvent(..)")
    homotopyType = Parameter(VariableLimiterHomotopy.Linear, structural=True,  # noqa: N815
                             description="Simplified model for homotopy-based initialization (no effect here)")
    ySimplified = Parameter(0.0, description="Fixed value of output in simplified model (no effect here)")  # noqa: N815
    limit1 = RealInput(description="Connector of Real input signal used as maximum of input u")
    limit2 = RealInput(description="Connector of Real input signal used as minimum of input u")

    def equations(self):
        limited = sp.Piecewise((self.limit1, self.u > self.limit1), (self.limit2, self.u < self.limit2),
                               (self.u, True))
        return [Assert(self.limit1 >= self.limit2, "Input signals are not consistent: limit1 < limit2"),
                Eq(self.y, _literal(limited, self.strict))]


class DeadZone(DerivedDefaults, SISO):
    """Provide a region of zero output (Modelica.Blocks.Nonlinear.DeadZone).

    ``y = u - uMax`` if ``u > uMax``, ``u - uMin`` if ``u < uMin``, else 0.
    """

    modelica_name = "Modelica.Blocks.Nonlinear.DeadZone"

    uMax = Parameter(1.0, description="Upper limits of dead zones")  # noqa: N815
    uMin = Parameter(None, description="Lower limits of dead zones (default -uMax)")  # noqa: N815

    derived_defaults = {"uMin": lambda block: -block.uMax}

    def equations(self):
        return [Assert(self.uMax >= self.uMin, "DeadZone: Limits must be consistent. However, uMax < uMin"),
                Eq(self.y, sp.Piecewise((self.u - self.uMax, self.u > self.uMax),
                                        (self.u - self.uMin, self.u < self.uMin), (0, True)))]


class SlewRateLimiter(DerivedDefaults, SISO):
    """Limit the slew rate of a signal (Modelica.Blocks.Nonlinear.SlewRateLimiter).

    ``der(y) = (u - y)/Td`` clipped to ``[Falling, Rising]``: ``y`` follows
    ``u`` with the time constant ``Td`` but never faster than the rates.  By
    default (``initType = SteadyState``) ``y = u`` at the start.
    """

    modelica_name = "Modelica.Blocks.Nonlinear.SlewRateLimiter"

    Rising = Parameter(1.0, min=SMALL, description="Maximum rising slew rate [+small..+inf) [1/s]")
    Falling = Parameter(None, max=-SMALL, description="Maximum falling slew rate (-inf..-small] [1/s] "
                                                      "(default -Rising)")
    Td = Parameter(0.001, unit="s", min=SMALL, description="Derivative time constant")
    initType = Parameter(Init.SteadyState, structural=True,  # noqa: N815
                         description="Type of initialization (SteadyState implies y = u)")
    y_start = Parameter(0.0, description="Initial or guess value of output (= state)")
    strict = Parameter(False, structural=True, description="= true, if strict limits with noEvent(..)")
    val = Variable(description="(u - y)/Td (protected)")

    derived_defaults = {"Falling": lambda block: -block.Rising}

    def __init__(self, **modifiers) -> None:
        super().__init__(**modifiers)
        self._attribute_modifiers.setdefault("y", {}).setdefault("start", lambda block: block.y_start)

    def equations(self):
        rate = _literal(sp.Piecewise((self.Falling, self.val < self.Falling),
                                     (self.Rising, self.val > self.Rising), (self.val, True)), self.strict)
        return [Eq(self.val, (self.u - self.y) / self.Td), Eq(der(self.y), rate)]

    def initial_equations(self):
        init = _init_type(self.initType)
        if init is Init.SteadyState:
            return [Eq(self.y, self.u)]
        if init in (Init.InitialState, Init.InitialOutput):
            return [Eq(self.y, self.y_start)]
        return []


# --------------------------------------------------------------------------
# Pade approximation of a delay
# --------------------------------------------------------------------------


def balance_abc(A: np.ndarray, B: np.ndarray, C: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """A balanced form of the system ``[A, B; C, 0]`` by a diagonal state transformation
    (Modelica.Math.Matrices.balanceABC).

    Returns ``(scale, As, Bs, Cs)`` with ``T = diag(scale)``, ``As = inv(T)*A*T``,
    ``Bs = inv(T)*B`` and ``Cs = C*T``: the row and column norms of each
    state are brought close to each other.  The scale factors are powers of
    2, so the transformation introduces no round-off.  The iteration is the
    MSL's (that of LAPACK's dgebal, with the rows of B and the columns of C
    counted in).
    """
    As, Bs, Cs = (np.array(M, dtype=float, copy=True) for M in (A, B, C))
    n = As.shape[0]
    scale = np.ones(n)
    radix = 2.0
    radix2 = radix * radix
    unconverged = True
    while unconverged:
        unconverged = False
        for i in range(n):
            column = np.sum(np.abs(As[:, i])) - abs(As[i, i]) + np.sum(np.abs(Cs[:, i]))
            row = np.sum(np.abs(As[i, :])) - abs(As[i, i]) + np.sum(np.abs(Bs[i, :]))
            both = column + row
            factor = 1.0
            bound = row / radix
            while not (column >= bound or column == 0):
                factor *= radix
                column *= radix2
            bound = row * radix
            while not (column < bound or row == 0):
                factor /= radix
                column /= radix2
            if not (column + row) / factor >= 0.95 * both:
                scale[i] *= factor
                As[i, :] /= factor
                As[:, i] *= factor
                Bs[i, :] /= factor
                Cs[:, i] *= factor
                unconverged = True
    return scale, As, Bs, Cs


def pade_coefficients(T: float, n: int, m: int, balance: bool = False
                      ) -> tuple[np.ndarray, float, np.ndarray, float, np.ndarray]:
    """The state-space coefficients of the ``(m, n)`` Pade approximation of ``exp(-T*s)``
    (Modelica.Blocks.Nonlinear.PadeDelay.padeCoefficients2).

    The transfer function ``b(s)/a(s)`` (numerator of degree ``m``,
    denominator of degree ``n``) matches the Taylor series of the delay up
    to order ``n + m``.  It is realised in controller canonical form,
    ``der(x[1]) = a1*x + b11*u``, ``der(x[i]) = s[i-1]*x[i-1]``, ``y = c*x +
    d*u``; with ``balance`` the form is balanced (:func:`balance_abc`), which
    keeps the coefficients of a short delay or a high order within a few
    decades of each other, otherwise ``b11 = 1/a[1]`` and ``s`` is all ones.

    Returns
    -------
    a1, b11, c, d, s
        First row of A, ``B[1, 1]``, the C row, D, and the state scaling
        (``x[i]`` is ``s[i-1]`` times the integral of ``x[i-1]``).
    """
    a = np.ones(n + 1)
    b = np.ones(m + 1)
    nm = n + m
    # coefficients in rising powers of s: a[0] + a[1]*s + ... (b alternates in sign: a delay)
    for i in range(1, n + 1):
        a[i] = a[i - 1] * (T * ((n - i + 1) / (nm - i + 1)) / i)
        if i <= m:
            b[i] = -b[i - 1] * (T * ((m - i + 1) / (nm - i + 1)) / i)
    # in falling powers of s, the numerator padded to the denominator's degree
    a = a[::-1]
    bb = np.concatenate([np.zeros(n - m), b[::-1]])
    d = bb[0] / a[0]
    c_row = bb[1:] - d * a[1:]
    if not balance:
        return -a[1:] / a[0], 1 / a[0], c_row, d, np.ones(n - 1)
    A = np.zeros((n, n))
    A[0, :] = -a[1:] / a[0]
    A[np.arange(1, n), np.arange(n - 1)] = 1.0
    B = np.zeros((n, 1))
    B[0, 0] = 1 / a[0]
    scale, As, Bs, Cs = balance_abc(A, B, c_row.reshape(1, n))
    return As[0, :], Bs[0, 0], Cs[0, :], d, scale[:-1] / scale[1:]


class PadeDelay(SISO):
    """Pade approximation of delay block with fixed delayTime (use balance=true; this is not the default to be
    backwards compatible) (Modelica.Blocks.Nonlinear.PadeDelay).

    ``y`` is ``u`` delayed by about ``delayTime``: the transfer function
    ``b(s)/a(s)`` of the ``(m, n)`` Pade approximant of ``exp(-delayTime*s)``
    (:func:`pade_coefficients`), in controller canonical form with states
    ``x[n]``, balanced with ``balance = True`` (recommended; the MSL's
    default is False for backwards compatibility).  Initialization: with
    ``balance`` in steady state (``der(x) = 0``), otherwise ``x[n] = u``
    (the other states at their start values, as in the MSL).

    The MSL computes the coefficients in its initial equations (parameters
    with ``fixed=false``); here they are computed when the equations are
    written, so ``delayTime``, ``n``, ``m`` and ``balance`` are structural.
    """

    modelica_name = "Modelica.Blocks.Nonlinear.PadeDelay"

    # the MSL gives delayTime only a start value (1), which a tool proposes
    delayTime = Parameter(1.0, unit="s", structural=True,  # noqa: N815
                          description="Delay time of output with respect to input signal")
    n = Parameter(1, structural=True, min=1, description="Order of Pade delay")
    m = Parameter(None, structural=True, min=1,
                  description="Order of numerator (usually m=n, or m=n-1; default n)")
    balance = Parameter(False, structural=True,
                        description="= true, if state space system is balanced (highly recommended), otherwise "
                                    "textbook version")
    x = Variable(shape="n", description="State of transfer function from controller canonical form "
                                        "(balance=false), or balanced controller canonical form (balance=true)")

    def coefficients(self) -> tuple[np.ndarray, float, np.ndarray, float, np.ndarray]:
        """``(a1, b11, c, d, s)`` of :func:`pade_coefficients` for this block's parameters."""
        where = self.path or type(self).__name__
        n = int(self.n)
        m = n if self.m is None else int(self.m)
        if not 1 <= m <= n:
            raise ParameterError(f"{where}: the order of the numerator m = {m} must lie in 1..n = {n}",
                                 hint="usually m = n (the default) or m = n - 1")
        return pade_coefficients(float(self.delayTime), n, m, bool(self.balance))

    def equations(self):
        a1, b11, c, d, scaling = self.coefficients()
        x = list(self.x)
        equations = [Eq(der(x[0]), _dot(a1, x) + sp.Float(b11) * self.u)]
        equations += [Eq(der(x[i]), sp.Float(scaling[i - 1]) * x[i - 1]) for i in range(1, len(x))]
        equations.append(Eq(self.y, _dot(c, x) + sp.Float(d) * self.u))
        return equations

    def initial_equations(self):
        if self.balance:
            return [Eq(der(state), 0) for state in self.x]
        # the MSL keeps the textbook version's initialization, for backwards compatibility
        return [Eq(self.x[self.n], self.u)]


def _dot(coefficients: Sequence[float], symbols: Sequence[sp.Expr]) -> sp.Expr:
    """``sum(coefficients[i]*symbols[i])`` with the coefficients as sympy Floats."""
    return sp.Add(*[sp.Float(k) * v for k, v in zip(coefficients, symbols)])


class FixedDelay(SISO):
    """Delay block with fixed DelayTime (Modelica.Blocks.Nonlinear.FixedDelay).

    ``y = u(time - delayTime)`` for ``time > time.start + delayTime``, and
    ``y = u(time.start)`` before, with Modelica's ``delay(u, delayTime)``.

    Parameters
    ----------
    delayTime : float, default 1
        Delay time of output with respect to input signal, in s; tunable,
        ``> 0`` (a zero delay is refused when the run starts).

    Notes
    -----
    The integrator's step is at most ``delayTime``, and a jump of ``u`` at an
    event reappears in ``y`` exactly ``delayTime`` later, where the
    integrator restarts (see ``docs/hybrid.md``).

    Examples
    --------
    >>> from acausal.library.blocks import FixedDelay
    >>> FixedDelay.modelica_name
    'Modelica.Blocks.Nonlinear.FixedDelay'
    """

    modelica_name = "Modelica.Blocks.Nonlinear.FixedDelay"

    # the MSL gives delayTime only a start value (1), which a tool proposes
    delayTime = Parameter(1.0, unit="s",  # noqa: N815
                          description="Delay time of output with respect to input signal")

    def equations(self):
        return [Eq(self.y, delay(self.u, self.delayTime))]


class VariableDelay(SISO):
    """Delay block with variable DelayTime (Modelica.Blocks.Nonlinear.VariableDelay).

    ``y = u(time - delayTime)`` for ``time > time.start + delayTime``, and
    ``y = u(time.start)`` before, with Modelica's
    ``delay(u, delayTime, delayMax)``; the delay time is an input.

    Parameters
    ----------
    delayMax : float, default 1
        Maximum delay time, in s (``>= 0``).  The input must keep
        ``0 <= delayTime <= delayMax``; the run stops with an error naming
        the time where it does not.

    Notes
    -----
    The step is not bounded by the delay time: where ``time - delayTime``
    lies in the step being taken, the trial evaluations extrapolate the last
    accepted step (see ``docs/hybrid.md``).

    Examples
    --------
    >>> from acausal.library.blocks import VariableDelay
    >>> VariableDelay.modelica_name
    'Modelica.Blocks.Nonlinear.VariableDelay'
    """

    modelica_name = "Modelica.Blocks.Nonlinear.VariableDelay"

    delayMax = Parameter(1.0, unit="s", min=0, description="Maximum delay time")  # noqa: N815
    delayTime = RealInput(description="Delay time of output with respect to input signal")  # noqa: N815

    def equations(self):
        return [Eq(self.y, delay(self.u, self.delayTime, self.delayMax))]
