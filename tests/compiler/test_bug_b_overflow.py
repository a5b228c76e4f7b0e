"""Generated code overflows as IEEE arithmetic does: to an infinity, not to an exception.

``dx/dt = -100 (2/(1 + exp(-x/0.01)) - 1) = -100 tanh(50 x)`` from x(0) = 100 is a
sign-like law: x falls at rate 100 while x >> 0.01, reaches ~0 at t = 1 and stays
there.  An explicit trial step that overshoots far below zero makes ``exp(-x/0.01)``
overflow; Python's ``math.exp`` raises OverflowError there (the run used to stop at
t = 0.276), IEEE arithmetic gives inf, 2/(1 + inf) = 0, and the step goes on.

The law has a closed form: d/dt sinh(50 x) = 50 cosh(50 x) x' = -5000 sinh(50 x), so
sinh(50 x(t)) = sinh(5000) exp(-5000 t).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import sympy as sp
from sympy.codegen.cfunctions import expm1

from acausal import Eq, Model, Variable, der, simulate
from acausal.compiler.algebraic import Assign
from acausal.compiler.codegen import compile_functions, generate, vectorised
from acausal.language import real_symbol

EPS = 0.01  # the width of the switching law
X0 = 100.0
RATE = 100.0


def exact(t):
    """x(t) = asinh(sinh(50 x0) e^{-5000 t}) / 50, evaluated in logarithms (sinh(5000) overflows)."""
    t = np.asarray(t, dtype=float)
    k = 1.0 / (2 * EPS)  # tanh(x/(2 eps)) = 2/(1 + exp(-x/eps)) - 1
    # log of sinh(k x0) e^{-rate k t}; sinh(k x0) = e^{k x0}/2 to double precision
    log_y = k * X0 - math.log(2.0) - RATE * k * t
    small = np.arcsinh(np.exp(np.minimum(log_y, 700.0))) / k
    large = (log_y + math.log(2.0)) / k  # asinh(y) = log(2y) + O(1/y^2)
    return np.where(log_y > 700.0, large, small)


class SignLawExp(Model):
    x = Variable(start=X0, fixed=True)

    def equations(self):
        return [Eq(der(self.x), -RATE * (2 / (1 + sp.exp(-self.x / EPS)) - 1))]


class SignLawPow(Model):
    """The same law through a power: 2**(-x/(eps ln 2)) = exp(-x/eps)."""

    x = Variable(start=X0, fixed=True)

    def equations(self):
        return [Eq(der(self.x), -RATE * (2 / (1 + sp.Integer(2) ** (-self.x / (EPS * math.log(2.0)))) - 1))]


def test_closed_form_of_the_law_itself():
    # the reference: x falls at the rate 100 far from 0, and x(1) = asinh(1/2)/50
    assert exact(0.5) == pytest.approx(50.0, abs=1e-12)
    assert exact(1.0) == pytest.approx(math.asinh(0.5) / 50, rel=1e-12)
    assert exact(2.0) == pytest.approx(0.0, abs=1e-300)


def test_exp_overflow_in_a_trial_step_does_not_stop_the_run_default_settings():
    """The run of the report (RK45, default tolerances) reaches its stop time and follows the law."""
    result = simulate(SignLawExp(), stop_time=2.0, interval=0.01, cache=False)
    assert result.success, result.message
    t = result.time
    x = result["x"]
    assert x[np.searchsorted(t, 0.5)] == pytest.approx(50.0, abs=1e-3)
    assert x[-1] == pytest.approx(0.0, abs=1e-3)
    assert np.max(np.abs(x - exact(t))) <= 1e-3


# numpy scalars (the states) overflow in ``**`` with a RuntimeWarning, Python floats in the guard
@pytest.mark.filterwarnings("ignore:overflow encountered:RuntimeWarning")
@pytest.mark.parametrize("model", [SignLawExp, SignLawPow], ids=["exp", "pow"])
@pytest.mark.parametrize("method", ["RK45", "DOP853", "Radau", "BDF", "LSODA"])
def test_sign_law_matches_closed_form(model, method):
    result = simulate(model(), stop_time=2.0, interval=0.01, method=method, rtol=1e-8, cache=False)
    assert result.success, result.message
    t = result.time
    assert t[-1] == 2.0
    assert np.max(np.abs(result["x"] - exact(t))) <= 1e-6
    assert result["x"][np.searchsorted(t, 0.5)] == pytest.approx(50.0, abs=1e-6)
    assert abs(result["x"][-1]) <= 1e-6


# -- the guarded functions themselves ----------------------------------------------------------------

u, v = real_symbol("u"), real_symbol("v")

#: (expression of u and v, the C library's value where it does not overflow,
#:  arguments that overflow -> the IEEE result, ordinary arguments)
CASES = [
    (sp.exp(u), lambda a, b: math.exp(a), [((1000.0, 0.0), math.inf)], [(1.5, 0.0), (-1000.0, 0.0)]),
    (expm1(u), lambda a, b: math.expm1(a), [((1000.0, 0.0), math.inf)], [(1e-10, 0.0), (-1000.0, 0.0)]),
    (sp.sinh(u), lambda a, b: math.sinh(a), [((1000.0, 0.0), math.inf), ((-1000.0, 0.0), -math.inf)],
     [(0.5, 0.0), (-3.0, 0.0)]),
    (sp.cosh(u), lambda a, b: math.cosh(a), [((1000.0, 0.0), math.inf), ((-1000.0, 0.0), math.inf)],
     [(0.5, 0.0), (-3.0, 0.0)]),
    (sp.gamma(u), lambda a, b: math.gamma(a),
     [((200.0, 0.0), math.inf), ((1e-320, 0.0), math.inf), ((-1e-320, 0.0), -math.inf)],
     [(4.0, 0.0), (0.5, 0.0)]),
    (sp.loggamma(u), lambda a, b: math.lgamma(a), [((1e306, 0.0), math.inf)], [(3.0, 0.0), (1e-320, 0.0)]),
    (u ** v, lambda a, b: a ** b,
     [((1e200, 2.0), math.inf), ((-1e200, 3.0), -math.inf), ((-1e200, 2.0), math.inf),
      ((1e-200, -2.0), math.inf), ((10.0, 400.0), math.inf)],
     [(2.0, 0.5), (-2.0, 3.0), (1e-200, 2.0)]),
    (sp.Integer(2) ** u, lambda a, b: 2 ** a, [((1e4, 0.0), math.inf)], [(0.5, 0.0), (-1e4, 0.0)]),
    (u ** 2, lambda a, b: a ** 2, [((1e200, 0.0), math.inf), ((-1e200, 0.0), math.inf)], [(3.0, 0.0)]),
    (u ** 3, lambda a, b: a ** 3, [((-1e200, 0.0), -math.inf)], [(-3.0, 0.0)]),
]


@pytest.mark.parametrize("expr, reference, overflows, ordinary", CASES,
                         ids=[str(c[0]) for c in CASES])
def test_overflow_gives_signed_infinity_and_ordinary_values_are_unchanged(expr, reference, overflows,
                                                                          ordinary):
    (f,) = compile_functions([("u", "v")], [expr])
    for (a, b), expected in overflows:
        for ua, vb in ((a, b), (np.float64(a), np.float64(b))):  # Python floats and numpy scalars
            with np.errstate(over="ignore"):
                assert f(ua, vb) == expected, (expr, a, b)
    for a, b in ordinary:
        assert f(a, b) == reference(a, b)  # bit for bit: the same C function where it returns


def test_generated_functions_and_their_numpy_versions_overflow_alike():
    x1 = real_symbol("x1")
    steps = [Assign("a", 1 / (1 + sp.exp(-x1 / EPS)), None),
             Assign("b", sp.sinh(x1), None),
             Assign("c", sp.cosh(x1) + x1 ** 3, None)]
    crossings = tuple(real_symbol(n) for n in ("a", "b", "c"))
    code = generate(steps, ("x1",), (), ("a", "b", "c"), (), crossings=crossings, name="overflow")
    _derivatives, crossing_fn, outputs = code.make(())
    X = np.array([[-1e3, -10.0, 0.0, 10.0, 1e3, 1e120]])
    t = np.zeros(X.shape[1])
    for scalar in (crossing_fn, outputs):
        with np.errstate(over="ignore"):
            rows = np.array([scalar(t[j], X[:, j]) for j in range(X.shape[1])], dtype=float).T
        # the logistic function saturates to 0 and 1 where exp overflows
        assert rows[0, 0] == 0.0 and rows[0, 4] == 1.0 and rows[0, 2] == 0.5
        # sinh overflows to -inf and +inf, cosh + x^3 to +inf
        assert rows[1, 0] == -math.inf and rows[1, 4] == math.inf
        assert rows[2, 0] == math.inf and rows[2, 5] == math.inf and rows[2, 2] == 1.0
        many = vectorised(scalar, code.source)
        assert many is not None
        with np.errstate(over="ignore"):
            got = many(t, X)
        assert np.array_equal(got, rows, equal_nan=True)
