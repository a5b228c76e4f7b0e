"""Unit tests of the fixed-step integrators (:mod:`acausal.runtime.integrators`).

On dx/dt = -x, x(0) = 1 the exact solution is exp(-t).  Explicit Euler
multiplies by 1 - h per step, the classical Runge-Kutta method by the
Taylor polynomial 1 - h + h^2/2 - h^3/6 + h^4/24; their global errors are
O(h) and O(h^4), so halving the step divides the error by about 2 and 16.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from acausal import Eq, Experiment, Model, Variable, der, simulate
from acausal.runtime.integrators import RK4, Euler


def decay(t, y):
    return -y


def integrate(method, h: float, t_bound: float = 1.0):
    """(final time, final value, steps taken) for dx/dt = -x from x(0) = 1."""
    solver = method(decay, 0.0, np.array([1.0]), t_bound, max_step=h)
    steps = 0
    while solver.status == "running":
        message = solver.step()
        assert message is None, message
        steps += 1
    assert solver.status == "finished"
    return solver.t, float(solver.y[0]), steps


def error(method, h: float) -> float:
    _, x, _ = integrate(method, h)
    return abs(x - math.exp(-1.0))


@pytest.mark.parametrize("method, steps, expected_ratio, tolerance", [
    (Euler, (0.01, 0.005, 0.0025), 2.0, 0.01),
    (RK4, (0.1, 0.05, 0.025), 16.0, 0.05),
])
def test_halving_the_step_shows_the_order_of_convergence(method, steps, expected_ratio, tolerance):
    """Error ratios for h -> h/2 approach 2 (Euler, order 1) and 16 (RK4, order 4)."""
    errors = [error(method, h) for h in steps]
    ratios = [errors[k] / errors[k + 1] for k in range(len(errors) - 1)]
    for ratio in ratios:
        assert ratio == pytest.approx(expected_ratio, rel=tolerance)
    # closer to the asymptotic value as the step shrinks
    assert abs(ratios[-1] - expected_ratio) < abs(ratios[0] - expected_ratio)
    assert math.log2(ratios[-1]) == pytest.approx(method.order, abs=0.05)


def test_one_step_applies_the_methods_amplification_factor():
    """h = 0.3 over [0, 1]: three full steps and one of 0.1 that lands exactly on t = 1.

    Euler: 0.7^3 * 0.9 = 0.3087; RK4: R(0.3)^3 * R(0.1) with R(h) = 1 - h + h^2/2 - h^3/6 + h^4/24.
    """
    t, x, steps = integrate(Euler, 0.3)
    assert t == 1.0 and steps == 4
    assert x == pytest.approx(0.7**3 * 0.9, rel=1e-14)

    def R(h):
        return 1 - h + h**2 / 2 - h**3 / 6 + h**4 / 24

    t, x, steps = integrate(RK4, 0.3)
    assert t == 1.0 and steps == 4
    assert x == pytest.approx(R(0.3) ** 3 * R(0.1), rel=1e-14)


def test_the_dense_output_interpolates_within_a_step():
    """Cubic Hermite on one step matches both ends and is O(h^4) accurate in between."""
    solver = RK4(decay, 0.0, np.array([1.0]), 1.0, max_step=0.1)
    solver.step()
    dense = solver.dense_output()
    assert dense(0.0)[0] == pytest.approx(1.0, abs=1e-15)
    assert dense(0.1)[0] == pytest.approx(float(solver.y[0]), abs=1e-15)
    # Hermite interpolation error <= h^4/384 * max|x''''| = 0.1^4/384 plus the RK4 step error
    assert dense(0.05)[0] == pytest.approx(math.exp(-0.05), abs=1e-6)


class Decay(Model):
    experiment = Experiment(stop_time=1.0, interval=0.25)
    x = Variable(start=1.0, fixed=True)

    def equations(self):
        return [Eq(der(self.x), -self.x)]


@pytest.mark.parametrize("method, expected_ratio", [("Euler", 2.0), ("RK4", 16.0)])
def test_simulate_runs_the_fixed_step_methods_with_max_step(method, expected_ratio):
    """simulate(method=..., max_step=h): x(1) is the method's own value (1 - h)^(1/h) for Euler, and halving h
    divides the error by 2 or 16."""
    h = 0.05 if method == "RK4" else 0.01
    errors = []
    for step in (h, h / 2):
        result = simulate(Decay(), method=method, max_step=step)
        assert result.success
        assert result.time[-1] == 1.0
        errors.append(abs(result["x"][-1] - math.exp(-1.0)))
        if method == "Euler":
            assert result["x"][-1] == pytest.approx((1 - step) ** round(1 / step), rel=1e-12)
    assert errors[0] / errors[1] == pytest.approx(expected_ratio, rel=0.05)


def test_fixed_step_dense_output_keeps_a_constant_state_exact():
    """The Hermite interpolation of the fixed-step methods returns a constant state unchanged."""

    class Still(Model):
        experiment = Experiment(stop_time=1.0)
        x = Variable(start=0.9, fixed=True)

        def equations(self):
            return [Eq(der(self.x), 0)]

    for method in ("RK4", "Euler"):
        result = simulate(Still(), method=method, max_step=3e-3, interval=1e-3)
        assert (result["x"] == 0.9).all(), method
