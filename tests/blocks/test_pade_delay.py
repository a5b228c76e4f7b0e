"""Modelica.Blocks.Nonlinear.PadeDelay against the Pade approximant of exp(-T*s) computed independently.

The reference transfer functions come from ``scipy.interpolate.pade`` of the
Taylor series of the delay (and, as a second check, from the explicit
formula of the Pade approximant's coefficients); the block is checked
through its coefficients (textbook and balanced forms), through the linear
system the engine makes of it (``acausal.tools.linearize``), and through a
simulated step response against ``scipy.signal``.  ModelicaTest.Blocks.PadeDelay1
lies in the csv-compare tube of the MSL reference.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import interpolate, signal

from acausal import Experiment, Model, simulate
from acausal.errors import ParameterError
from acausal.library.blocks import Step
from acausal.library.blocks.nonlinear import PadeDelay, balance_abc, pade_coefficients
from acausal.tools.linearize import linearize

OMEGA = np.logspace(-2, 2, 41)

# the textbook form fixes x[n] only, the other states start at their start values (as in the MSL)
pytestmark = pytest.mark.filterwarnings("ignore::acausal.errors.StartValueWarning")


def reference_response(T: float, n: int, m: int, omega: np.ndarray) -> np.ndarray:
    """H(j*omega) of the (m, n) Pade approximant of exp(-T*s): scipy's Pade of the Taylor series."""
    taylor = [(-T) ** k / math.factorial(k) for k in range(n + m + 1)]
    numerator, denominator = interpolate.pade(taylor, n, m)
    s = 1j * omega
    return numerator(s) / denominator(s)


def explicit_response(T: float, n: int, m: int, omega: np.ndarray) -> np.ndarray:
    """H(j*omega) from the closed form of the Pade coefficients:
    p_k = (m+n-k)! m! / ((m+n)! k! (m-k)!) (-T)^k, q_k = (m+n-k)! n! / ((m+n)! k! (n-k)!) T^k."""
    f = math.factorial
    s = 1j * omega
    p = sum(f(m + n - k) * f(m) / (f(m + n) * f(k) * f(m - k)) * (-T * s) ** k for k in range(m + 1))
    q = sum(f(m + n - k) * f(n) / (f(m + n) * f(k) * f(n - k)) * (T * s) ** k for k in range(n + 1))
    return p / q


def state_space(a1, b11, c, d, scaling):
    """A, B, C, D of der(x[1]) = a1*x + b11*u, der(x[i]) = s[i-1]*x[i-1], y = c*x + d*u."""
    n = len(a1)
    A = np.zeros((n, n))
    A[0, :] = a1
    for i in range(1, n):
        A[i, i - 1] = scaling[i - 1]
    B = np.zeros((n, 1))
    B[0, 0] = b11
    return A, B, np.asarray(c, dtype=float).reshape(1, n), np.array([[d]])


def frequency_response(A, B, C, D, omega: np.ndarray) -> np.ndarray:
    """C (j*omega*I - A)^-1 B + D, solved per frequency."""
    n = A.shape[0]
    return np.array([(C @ np.linalg.solve(1j * w * np.eye(n) - A, B) + D)[0, 0] for w in omega])


@pytest.mark.parametrize("T, n, m", [(1.0, 1, 1), (0.2, 3, 3), (0.5, 4, 3), (1.0, 6, 6), (2.0, 5, 4)])
@pytest.mark.parametrize("balance", [False, True])
def test_coefficients_give_the_pade_approximant(T, n, m, balance):
    response = frequency_response(*state_space(*pade_coefficients(T, n, m, balance)), OMEGA)
    expected = reference_response(T, n, m, OMEGA)
    np.testing.assert_allclose(response, expected, rtol=1e-8, atol=1e-10)
    np.testing.assert_allclose(response, explicit_response(T, n, m, OMEGA), rtol=1e-8, atol=1e-10)


def test_pade_approximant_of_a_delay_is_all_pass_for_equal_orders():
    """m = n: |H(j*omega)| = 1 and the phase follows -omega*T at low frequency."""
    T = 0.3
    response = frequency_response(*state_space(*pade_coefficients(T, 5, 5, True)), OMEGA)
    np.testing.assert_allclose(np.abs(response), 1.0, rtol=1e-9)
    low = OMEGA < 3.0
    np.testing.assert_allclose(np.unwrap(np.angle(response))[low], -OMEGA[low] * T, rtol=1e-6)


def test_balancing_shrinks_the_coefficients_without_round_off():
    """The MSL's example: delayTime = 0.001 and n = 4 give coefficients from 1 to 1e12 unbalanced."""
    textbook = state_space(*pade_coefficients(0.001, 4, 4, False))
    balanced = state_space(*pade_coefficients(0.001, 4, 4, True))
    system = lambda A, B, C, D: np.block([[A, B], [C, D]])  # noqa: E731
    assert np.max(np.abs(textbook[0])) > 1e11
    assert np.linalg.norm(system(*balanced)) < 1e-6 * np.linalg.norm(system(*textbook))
    A, B, C, _ = textbook
    scale, As, Bs, Cs = balance_abc(A, B, C)
    assert np.all(np.log2(scale) == np.round(np.log2(scale)))  # powers of 2: exact
    T = np.diag(scale)
    np.testing.assert_array_equal(As, np.diag(1 / scale) @ A @ T)
    np.testing.assert_array_equal(Bs, np.diag(1 / scale) @ B)
    np.testing.assert_array_equal(Cs, C @ T)


def test_orders_are_checked():
    model = _Delayed(n=2, m=3)
    with pytest.raises(ParameterError, match="m = 3"):
        simulate(model)


class _Delayed(Model):
    """A step at t = 0.1 through a PadeDelay."""

    experiment = Experiment(stop_time=2.0, interval=0.01)

    def __init__(self, **pade) -> None:
        self._pade = pade
        super().__init__()

    def build(self):
        self.step = Step(startTime=0.1)
        self.delay = PadeDelay(**self._pade)
        self.connect(self.step.y, self.delay.u)


@pytest.mark.parametrize("balance", [False, True])
def test_linearized_block_has_the_pade_transfer_function(balance):
    T, n, m = 0.4, 4, 3
    lin = linearize(_Delayed(delayTime=T, n=n, m=m, balance=balance), at=0.0, inputs=["delay.u"],
                    outputs=["delay.y"])
    response = frequency_response(lin.A, lin.B, lin.C, lin.D, OMEGA)
    np.testing.assert_allclose(response, reference_response(T, n, m, OMEGA), rtol=1e-8, atol=1e-10)


@pytest.mark.parametrize("balance", [False, True])
def test_step_response_is_the_pade_approximants(balance):
    """Both initializations start in steady state (u = 0): y is the approximant's step response from t = 0.1."""
    T, n = 0.5, 3
    result = simulate(_Delayed(delayTime=T, n=n, balance=balance), rtol=1e-10, atol=1e-12)
    taylor = [(-T) ** k / math.factorial(k) for k in range(2 * n + 1)]
    numerator, denominator = interpolate.pade(taylor, n, n)
    after = result.time > 0.1 + 1e-9
    # scipy simulates from the first time point given: start it at the step
    since_step = np.concatenate([[0.0], result.time[after] - 0.1])
    _, expected = signal.step(signal.lti(numerator.coeffs, denominator.coeffs), T=since_step)
    expected = expected[1:]
    np.testing.assert_allclose(result["delay.y"][after], expected, atol=1e-7)
    np.testing.assert_allclose(result["delay.y"][result.time < 0.1], 0.0, atol=1e-12)
    # the delay: the response stays small before ~T and settles at the step's height
    assert result.at(2.0, "delay.y") == pytest.approx(1.0, abs=1e-3)
