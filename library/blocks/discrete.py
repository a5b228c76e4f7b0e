"""Discrete input/output blocks with fixed sample period (Modelica.Blocks.Discrete).

Every block but the triggered ones extends :class:`DiscreteBlock`: it samples
at ``startTime + i*samplePeriod`` (``sample()``, exact time events, the first
one at ``startTime`` itself, also when that is the start of the simulation)
and records in ``firstTrigger`` whether the current sample is the first.

The blocks with array connectors or states (:class:`TransferFunction`,
:class:`StateSpace`) name their elements as Modelica does (``x[1]``,
``y[1]``): read them with ``block.x[1]`` or
:meth:`~acausal.components.declarations.VectorBlock.vector`, connect to
``block.u[1]``.  A modifier of the whole array applies to each
element (Modelica's ``each``): ``StateSpace(..., x=dict(start=0, fixed=True))``.
"""

from __future__ import annotations

from typing import Any, Callable

import sympy as sp

from acausal.components.blocks import SISO, BooleanInput
from acausal.components.declarations import VectorBlock
from acausal.errors import ModelDefinitionError
from acausal.hybrid import When, noEvent, sample
from acausal.language import (
    Boolean,
    Component,
    Eq,
    If,
    Parameter,
    RealInput,
    RealOutput,
    Variable,
    initial,
    pre,
    time,
)

__all__ = [
    "DiscreteBlock",
    "DiscreteSISO",
    "DiscreteMIMO",
    "Sampler",
    "ZeroOrderHold",
    "FirstOrderHold",
    "UnitDelay",
    "TransferFunction",
    "StateSpace",
    "TriggeredSampler",
    "TriggeredMax",
]

#: ModelicaServices.Machine.eps: the difference between 1 and the next float.
EPS = 2.2204460492503131e-16

#: ModelicaServices.Machine.small: the smallest positive normal float.
SMALL = 2.2250738585072014e-308


def _matrix(value: Any, name: str, owner: str) -> list[list[Any]]:
    """A structural matrix parameter as a list of rows (a flat sequence is a column)."""
    rows = [list(r) if isinstance(r, (list, tuple)) or hasattr(r, "__len__") else [r] for r in value]
    widths = {len(r) for r in rows}
    if len(widths) > 1:
        raise ModelDefinitionError(f"{owner}.{name}: rows of different lengths {sorted(widths)}",
                                   hint=f"give {name} as a list of equally long rows, e.g. [[0, 1], [-1, -0.1]]")
    return rows


def _vector(value: Any, name: str, owner: str) -> list[Any]:
    values = list(value) if isinstance(value, (list, tuple)) or hasattr(value, "__len__") else [value]
    if not values:
        raise ModelDefinitionError(f"{owner}.{name} is empty", hint=f"give {name} at least one element")
    return values


# --------------------------------------------------------------------------
# bases
# --------------------------------------------------------------------------


class DiscreteBlock(Component):
    """Base class of discrete control blocks (Modelica.Blocks.Interfaces.DiscreteBlock).

    ``sampleTrigger = sample(startTime, samplePeriod)`` is true at the sample
    instants only; ``firstTrigger`` becomes true at the first of them and
    false from the second on (``time <= startTime + samplePeriod/2`` at the
    sample).  Both are protected in Modelica, but recorded.
    """

    modelica_name = "Modelica.Blocks.Interfaces.DiscreteBlock"

    samplePeriod = Parameter(0.1, unit="s", min=100 * EPS, description="Sample period of component")  # noqa: N815
    startTime = Parameter(0.0, unit="s", description="First sample time instant")  # noqa: N815
    sampleTrigger = Boolean(description="True, if sample time instant")  # noqa: N815
    firstTrigger = Boolean(start=False, fixed=True,  # noqa: N815
                           description="Rising edge signals first sample instant")

    def equations(self):
        return [
            Eq(self.sampleTrigger, sample(self.startTime, self.samplePeriod)),
            # noEvent: a relation in a when-clause is only evaluated at its events
            When(self.sampleTrigger,
                 Eq(self.firstTrigger, noEvent(time <= self.startTime + self.samplePeriod / 2))),
        ]


class DiscreteSISO(DiscreteBlock, SISO):
    """Single input, single output discrete block (Modelica.Blocks.Interfaces.DiscreteSISO)."""

    modelica_name = "Modelica.Blocks.Interfaces.DiscreteSISO"


class DiscreteMIMO(DiscreteBlock, VectorBlock):
    """Multiple input, multiple output discrete block (Modelica.Blocks.Interfaces.DiscreteMIMO).

    The inputs ``u[1..nin]`` and outputs ``y[1..nout]``; the sizes come from
    :meth:`sizes` (the structural parameters ``nin`` and ``nout`` here).
    """

    modelica_name = "Modelica.Blocks.Interfaces.DiscreteMIMO"

    nin = Parameter(1, structural=True, min=1, description="Number of inputs")
    nout = Parameter(1, structural=True, min=1, description="Number of outputs")

    @classmethod
    def sizes(cls, value: Callable[[str], Any]) -> tuple[int, int]:
        """``(nin, nout)`` from the structural parameters."""
        return int(value("nin")), int(value("nout"))

    @classmethod
    def arrays(cls, value):
        nin, nout = cls.sizes(value)
        return {
            "u": (nin, lambda i: RealInput(description="Connector of Real input signals")),
            "y": (nout, lambda i: RealOutput(description="Connector of Real output signals")),
        }


# --------------------------------------------------------------------------
# the blocks
# --------------------------------------------------------------------------


class Sampler(DiscreteSISO):
    """Ideal sampling of continuous signals (Modelica.Blocks.Discrete.Sampler).

    ``y = u`` at initialization and at every sample instant from
    ``startTime`` on, held in between; before ``startTime`` the previous
    value (``y(start=0, fixed=true)``).
    """

    modelica_name = "Modelica.Blocks.Discrete.Sampler"

    y = RealOutput(start=0.0, fixed=True, description="Connector of Real output signal")

    def equations(self):
        return [When([self.sampleTrigger, initial()],
                     Eq(self.y, noEvent(If(time >= self.startTime, self.u, pre(self.y)))))]


class ZeroOrderHold(DiscreteSISO):
    """Zero order hold of a sampled-data system (Modelica.Blocks.Discrete.ZeroOrderHold).

    ``ySample`` is ``u`` at initialization and at the sample instants;
    ``y = pre(ySample)``, which delays it by one event iteration only (it
    breaks algebraic loops through the block).
    """

    modelica_name = "Modelica.Blocks.Discrete.ZeroOrderHold"

    ySample = RealOutput(start=0.0, fixed=True, description="Sampled input")  # noqa: N815

    def equations(self):
        return [
            When([self.sampleTrigger, initial()],
                 Eq(self.ySample, noEvent(If(time >= self.startTime, self.u, pre(self.ySample))))),
            Eq(self.y, pre(self.ySample)),
        ]


class FirstOrderHold(DiscreteSISO):
    """First order hold of a sampled-data system (Modelica.Blocks.Discrete.FirstOrderHold).

    At each sample the input is stored (``uSample``, with the previous one in
    ``pre_uSample``) and the slope ``c`` of the last two samples computed (0
    at the first); in between ``y = pre_uSample + pre(c)*(time - tSample)``
    extrapolates.  The variables start from ``u`` and ``time`` at
    initialization (Modelica's initial equations on their ``pre`` values).
    """

    modelica_name = "Modelica.Blocks.Discrete.FirstOrderHold"

    tSample = Variable(unit="s", discrete=True, description="Time of sample")  # noqa: N815
    uSample = Variable(discrete=True, description="Value of sample")  # noqa: N815
    pre_uSample = Variable(discrete=True, description="Value of previous sample")  # noqa: N815
    c = Variable(discrete=True, description="Slope")

    def equations(self):
        return [
            When(initial(), Eq(self.tSample, time), Eq(self.uSample, self.u),
                 Eq(self.pre_uSample, self.u), Eq(self.c, 0))
            .elsewhen(self.sampleTrigger,
                      Eq(self.tSample, time),
                      Eq(self.uSample, self.u),
                      Eq(self.pre_uSample, pre(self.uSample)),
                      Eq(self.c, If(self.firstTrigger, 0,
                                    (self.uSample - self.pre_uSample) / self.samplePeriod))),
            Eq(self.y, self.pre_uSample + pre(self.c) * (time - self.tSample)),
        ]


class UnitDelay(DiscreteSISO):
    """Unit delay block (Modelica.Blocks.Discrete.UnitDelay): ``y = pre(u)`` at the samples.

    As in the MSL, ``pre(u)`` of a continuous input is its value at the
    sample instant, so ``y`` is the input sampled (no delay by a period);
    ``y = y_start`` until the first sample after the start.
    """

    modelica_name = "Modelica.Blocks.Discrete.UnitDelay"

    y_start = Parameter(0.0, description="Initial value of output signal")
    y = RealOutput(start=lambda block: block.y_start, fixed=True, description="Connector of Real output signal")

    def equations(self):
        return [When(self.sampleTrigger, Eq(self.y, pre(self.u)))]


class TransferFunction(DiscreteSISO, VectorBlock):
    """Discrete transfer function (Modelica.Blocks.Discrete.TransferFunction).

    ``y/u = (b[1]*z^(nb-1) + ... + b[nb]) / (a[1]*z^(na-1) + ... + a[na])``
    in controller canonical form.  At each sample
    ``x1 = (u - a[2:na]*pre(x))/a[1]``, ``xext = [x1; pre(x)]``,
    ``x = xext[1:na-1]`` and ``y = [zeros(na-nb); b]*xext``.  The states
    ``x[1..na-1]``, ``x1`` and ``xext[1..na]`` start at 0 (fixed).
    """

    modelica_name = "Modelica.Blocks.Discrete.TransferFunction"

    b = Parameter((1.0,), structural=True,
                  description="Numerator coefficients of transfer function (descending powers of z)")
    a = Parameter((1.0,), structural=True,
                  description="Denominator coefficients of transfer function (descending powers of z)")
    x1 = Variable(start=0.0, fixed=True, discrete=True, description="Scalar state of the canonical form")

    @classmethod
    def arrays(cls, value):
        na = len(_vector(value("a"), "a", cls.__name__))
        return {
            "x": (na - 1, lambda i: RealOutput(start=0.0, fixed=True, description=(
                "State of transfer function from controller canonical form"))),
            "xext": (na, lambda i: Variable(start=0.0, fixed=True, discrete=True,
                                            description="Extended state vector")),
        }

    def equations(self):
        b = _vector(self.b, "b", type(self).__name__)
        a = _vector(self.a, "a", type(self).__name__)
        na, nb = len(a), len(b)
        if nb > na:
            raise ModelDefinitionError(f"{self.path}: the numerator has more coefficients ({nb}) than the "
                                       f"denominator ({na}): the transfer function is not proper",
                                       hint="give a at least as many coefficients as b")
        x = self.vector("x")
        xext = self.vector("xext")
        previous = [pre(v) for v in x]
        padded = [0] * (na - nb) + list(b)
        return [When(
            self.sampleTrigger,
            Eq(self.x1, (self.u - sum((a[k + 1] * previous[k] for k in range(na - 1)), sp.Integer(0))) / a[0]),
            Eq(xext[0], self.x1),
            [Eq(xext[k + 1], previous[k]) for k in range(na - 1)],
            [Eq(x[k], xext[k]) for k in range(na - 1)],
            Eq(self.y, sum((padded[j] * xext[j] for j in range(na)), sp.Integer(0))),
        )]


class StateSpace(DiscreteMIMO):
    """Discrete linear state space system (Modelica.Blocks.Discrete.StateSpace).

    At each sample ``x = A*pre(x) + B*u`` and ``y = C*pre(x) + D*u``.  The
    inputs are ``u[1..nin]`` (``nin`` = columns of B), the outputs
    ``y[1..nout]`` (``nout`` = rows of C), the states ``x[1..n]``.  As in the
    MSL the states have no fixed start; give one with
    ``x=dict(start=0, fixed=True)``.
    """

    modelica_name = "Modelica.Blocks.Discrete.StateSpace"

    A = Parameter(((1.0, 0.0), (0.0, 1.0)), structural=True, description="Matrix A of state space model")
    B = Parameter(((1.0,), (1.0,)), structural=True, description="Matrix B of state space model")
    C = Parameter(((1.0, 1.0),), structural=True, description="Matrix C of state space model")
    D = Parameter(None, structural=True,
                  description="Matrix D of state space model (default zeros(size(C,1), size(B,2)))")

    @classmethod
    def sizes(cls, value):
        B = _matrix(value("B"), "B", cls.__name__)
        C = _matrix(value("C"), "C", cls.__name__)
        return len(B[0]), len(C)

    @classmethod
    def arrays(cls, value):
        arrays = super().arrays(value)
        n = len(_matrix(value("A"), "A", cls.__name__))
        arrays["x"] = (n, lambda i: RealOutput(description="State vector"))
        return arrays

    def equations(self):
        name = type(self).__name__
        A, B, C = (_matrix(getattr(self, p), p, name) for p in ("A", "B", "C"))
        u, y, x = self.vector("u"), self.vector("y"), self.vector("x")
        n, nin, nout = len(x), len(u), len(y)
        for label, size, source in (("nin", nin, "the columns of B"), ("nout", nout, "the rows of C")):
            if label in self._modifiers and int(self._modifiers[label]) != size:
                raise ModelDefinitionError(f"{self.path}: {label} = {self._modifiers[label]} differs from "
                                           f"{source} ({size})",
                                           hint=f"leave {label} out: StateSpace takes it from {source}")
        D = self.D
        D = [[0.0] * nin for _ in range(nout)] if D is None else _matrix(D, "D", name)
        for label, matrix, rows, cols in (("A", A, n, n), ("B", B, n, nin), ("C", C, nout, n),
                                          ("D", D, nout, nin)):
            if len(matrix) != rows or any(len(r) != cols for r in matrix):
                raise ModelDefinitionError(f"{self.path}: {label} is not {rows} x {cols}",
                                           hint="A is n x n, B n x nin, C nout x n, D nout x nin")
        previous = [pre(v) for v in x]

        def product(M, i, vector):
            return sum((M[i][j] * vector[j] for j in range(len(vector))), sp.Integer(0))

        return [When(
            self.sampleTrigger,
            [Eq(x[i], product(A, i, previous) + product(B, i, u)) for i in range(n)],
            [Eq(y[i], product(C, i, previous) + product(D, i, u)) for i in range(nout)],
        )]


class TriggeredSampler(SISO):
    """Triggered sampling of continuous signals (Modelica.Blocks.Discrete.TriggeredSampler).

    ``y = u`` where ``trigger`` becomes true (a trigger already true at the
    start does not fire), ``y = y_start`` before the first trigger.
    """

    modelica_name = "Modelica.Blocks.Discrete.TriggeredSampler"

    y_start = Parameter(0.0, description="Initial value of output signal")
    y = RealOutput(start=lambda block: block.y_start, fixed=True, description="Connector of Real output signal")
    trigger = BooleanInput(description="Sampling when trigger becomes true")

    def equations(self):
        return [When(self.trigger, Eq(self.y, self.u))]


class TriggeredMax(SISO):
    """Compute maximum, absolute value of continuous signal at trigger instants (Modelica.Blocks.Discrete.TriggeredMax).

    ``y = max(pre(y), |u|)`` where ``trigger`` becomes true; ``y = 0`` at the start.
    """

    modelica_name = "Modelica.Blocks.Discrete.TriggeredMax"

    y = RealOutput(start=0.0, fixed=True, description="Connector of Real output signal")
    trigger = BooleanInput(description="Trigger input")

    def equations(self):
        return [When(self.trigger, Eq(self.y, sp.Max(pre(self.y), sp.Abs(self.u))))]
