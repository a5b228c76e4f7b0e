"""Fixed-step integrators in the ``OdeSolver`` interface of :mod:`.explicit_rk` (scipy's).

scipy offers only adaptive methods.  Explicit Euler and the classical
Runge-Kutta method with a fixed step are what real-time and embedded targets
run, and what shows why friction elements need ``K_locked``: without error
control, a stuck velocity held only at the acceleration level drifts.

Both take the step size from ``max_step`` (default: 1/1000 of the span) and
land exactly on ``t_bound``.
"""

from __future__ import annotations

import numpy as np
from .explicit_rk import DenseOutput, OdeSolver

__all__ = ["Euler", "RK4"]


class _FixedStep(OdeSolver):
    order = 1

    def __init__(self, fun, t0, y0, t_bound, max_step=np.inf, rtol=None, atol=None,
                 vectorized=False, **extraneous):
        super().__init__(fun, t0, y0, t_bound, vectorized)
        span = abs(t_bound - t0)
        self.h = float(max_step) if np.isfinite(max_step) else span / 1000.0
        self.f = self.fun(self.t, self.y)
        self.y_old = None
        self.f_old = None

    def _step_impl(self):
        h = min(self.h, abs(self.t_bound - self.t)) * self.direction
        if h == 0:
            return False, "step size is zero"
        y_new = self._advance(self.t, self.y, self.f, h)
        if not np.all(np.isfinite(y_new)):
            return False, f"the solution became non-finite at t = {self.t + h:.6g}"
        self.y_old, self.f_old = self.y, self.f
        self.t = self.t + h if abs(self.t_bound - (self.t + h)) > 1e-12 * abs(h) else self.t_bound
        f_new = self.fun(self.t, y_new)
        if not np.all(np.isfinite(f_new)):
            self.t = self.t_old if self.t_old is not None else self.t
            return False, f"the derivatives became non-finite at t = {self.t + h:.6g}"
        self.y = y_new
        self.f = f_new
        return True, None

    def _dense_output_impl(self):
        return _Hermite(self.t_old, self.t, self.y_old, self.y, self.f_old, self.f)


class Euler(_FixedStep):
    """Explicit Euler with a fixed step.

    Its dense output is the straight line between the step's ends: that is
    Euler's own trajectory (the state moves with the slope of the step's
    start).  A cubic interpolant built with the end's slope as well would
    dip below both ends after a breakaway (found by the fuzzing).
    """

    order = 1

    def _advance(self, t, y, f, h):
        return y + h * f

    def _dense_output_impl(self):
        return _Linear(self.t_old, self.t, self.y_old, self.y)


class RK4(_FixedStep):
    """The classical fourth-order Runge-Kutta method with a fixed step."""

    order = 4

    def _advance(self, t, y, f, h):
        k2 = self.fun(t + h / 2, y + h / 2 * f)
        k3 = self.fun(t + h / 2, y + h / 2 * k2)
        k4 = self.fun(t + h, y + h * k3)
        return y + h / 6 * (f + 2 * k2 + 2 * k3 + k4)


class _Linear(DenseOutput):
    """Linear interpolation between two step ends."""

    def __init__(self, t_old, t, y_old, y):
        super().__init__(t_old, t)
        self.y_old, self.y = y_old, y
        self.h = t - t_old

    def _call_impl(self, t):
        s = (np.asarray(t) - self.t_old) / self.h
        if np.ndim(t) == 0:
            return self.y_old + s * (self.y - self.y_old)
        # the same arithmetic as for one point, element by element
        return self.y_old[:, None] + s[None, :] * (self.y - self.y_old)[:, None]


class _Hermite(DenseOutput):
    """Cubic Hermite interpolation between two step ends."""

    def __init__(self, t_old, t, y_old, y, f_old, f):
        super().__init__(t_old, t)
        self.y_old, self.y, self.f_old, self.f = y_old, y, f_old, f
        self.h = t - t_old

    def _call_impl(self, t):
        s = (np.asarray(t) - self.t_old) / self.h
        # y_old + h01*(y - y_old) rather than h00*y_old + h01*y: h00 + h01 = 1 does not
        # hold in floating point, and a constant state must interpolate to itself exactly
        h10 = s**3 - 2 * s**2 + s
        h01 = -2 * s**3 + 3 * s**2
        h11 = s**3 - s**2
        if np.ndim(t) == 0:
            return self.y_old + h01 * (self.y - self.y_old) + h10 * self.h * self.f_old + h11 * self.h * self.f
        return (self.y_old[:, None] + np.outer(self.y - self.y_old, h01) + np.outer(self.h * self.f_old, h10)
                + np.outer(self.h * self.f, h11))
