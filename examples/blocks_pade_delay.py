"""ModelicaTest.Blocks.PadeDelay1: the PadeDelay block against the MSL 3.2.1 implementation.

A step (at t = 0.1, from 0.1 to 1.1) and a sine (2 Hz, from t = 0.1 on)
each drive two 10th-order Pade approximations of a 0.2 s delay: the
``PadeDelay`` block (``balance = false``, the textbook controller canonical
form) and ``PadeDelayOld``, the block as MSL 3.2.1 wrote it, kept in the
test model to check that both give the same output.  ``PadeDelayOld`` is
written here from the test model, with the old coefficient function: the
transfer function's denominator and numerator in falling powers of s, and
a state vector whose highest derivative is an algebraic variable.

Run ``acausal compare examples/blocks_pade_delay.py`` to check it against
the MSL reference results.
"""

from __future__ import annotations

import sympy as sp

from acausal import Eq, Experiment, Model, Parameter, Variable, der
from acausal.hybrid import Assert
from acausal.components.blocks import SISO
from acausal.library.blocks import Feedback, Sine, Step
from acausal.library.blocks.nonlinear import PadeDelay


def old_pade_coefficients(T: float, n: int, m: int) -> tuple[list[float], list[float]]:
    """``(b, a)``: numerator and denominator of the ``(m, n)`` Pade approximation of
    ``exp(-T*s)``, in falling powers of s (the MSL 3.2.1 ``padeCoefficients``)."""
    a, b = [1.0], [1.0]
    for i in range(1, n + 1):
        a.append(a[-1] * (T * ((n - i + 1) / (n + m - i + 1)) / i))
        if i <= m:
            b.append(-b[-1] * (T * ((m - i + 1) / (n + m - i + 1)) / i))
    return b[::-1], a[::-1]


class PadeDelayOld(SISO):
    """Pade approximation of delay block with fixed DelayTime (from MSL 3.2.1), as
    ModelicaTest.Blocks.PadeDelay1 declares it.

    ``u = a*[x1dot; x]`` and ``y = [zeros(n - m); b]*[x1dot; x]`` with
    ``der(x[1]) = x1dot``, ``der(x[i]) = x[i-1]``; initially ``x[n] = u``.
    """

    modelica_name = "ModelicaTest.Blocks.PadeDelay1.PadeDelayOld"

    delayTime = Parameter(1.0, unit="s", structural=True,  # noqa: N815
                          description="Delay time of output with respect to input signal")
    n = Parameter(1, structural=True, min=1, description="Order of Pade approximation")
    m = Parameter(None, structural=True, min=1, description="Order of numerator (default n)")
    x = Variable(shape="n", description="State of transfer function from controller canonical form")
    x1dot = Variable(description="Derivative of first state of TransferFcn")
    xn = Variable(description="Highest order state of TransferFcn")

    def _orders(self) -> tuple[int, int]:
        n = int(self.n)
        return n, n if self.m is None else int(self.m)

    def equations(self):
        n, m = self._orders()
        b, a = old_pade_coefficients(float(self.delayTime), n, m)
        x = list(self.x)
        chain = [self.x1dot] + x
        numerator = [0.0] * (n - m) + b
        return [Eq(der(x[0]), self.x1dot), *[Eq(der(x[i]), x[i - 1]) for i in range(1, n)],
                Eq(self.xn, x[-1]),
                Eq(self.u, sp.Add(*[sp.Float(k) * v for k, v in zip(a, chain)])),
                Eq(self.y, sp.Add(*[sp.Float(k) * v for k, v in zip(numerator, chain)]))]

    def initial_equations(self):
        return [Eq(self.x[self.n], self.u)]


class PadeDelay1(Model):
    """ModelicaTest.Blocks.PadeDelay1."""

    modelica_class = "ModelicaTest.Blocks.PadeDelay1"
    experiment = Experiment(start_time=0.0, stop_time=1.0, interval=0.0002)

    n = Parameter(10, structural=True, description="Order of Pade approximation")
    delayTime = Parameter(0.2, unit="s", structural=True,  # noqa: N815
                          description="Delay time of output with respect to input signal")

    def build(self):
        self.padeDelayOld1 = PadeDelayOld(delayTime=self.delayTime, n=self.n)
        self.padeDelay1 = PadeDelay(balance=False, delayTime=self.delayTime, n=self.n)
        self.step = Step(startTime=0.1, offset=0.1)
        self.compare1 = Feedback()
        self.padeDelayOld2 = PadeDelayOld(delayTime=self.delayTime, n=self.n)
        self.padeDelay2 = PadeDelay(balance=False, delayTime=self.delayTime, n=self.n)
        self.compare2 = Feedback()
        self.Sine = Sine(startTime=0.1, offset=0.1, f=2)
        self.connect(self.step.y, self.padeDelayOld1.u)
        self.connect(self.step.y, self.padeDelay1.u)
        self.connect(self.padeDelayOld1.y, self.compare1.u1)
        self.connect(self.padeDelay1.y, self.compare1.u2)
        self.connect(self.padeDelayOld2.y, self.compare2.u1)
        self.connect(self.padeDelay2.y, self.compare2.u2)
        self.connect(self.padeDelayOld2.u, self.Sine.y)
        self.connect(self.padeDelay2.u, self.Sine.y)

    def equations(self):
        message = "PadeDelay: Old and new implementation does not give the same result"
        return [Assert(sp.Abs(self.compare1.y) <= 1e-3, message), Assert(sp.Abs(self.compare2.y) <= 1e-3, message)]


if __name__ == "__main__":
    from acausal import simulate

    result = simulate(PadeDelay1())
    print(result.summary())
