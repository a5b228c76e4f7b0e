"""Logical blocks (Modelica.Blocks.Logical and Modelica.Blocks.MathBoolean.OnDelay).

Boolean gates, the ``pre``/``edge``/``change`` family, comparisons of Real
signals that produce Booleans, and the event-driven blocks built from them
(Hysteresis, OnOffController, TriggeredTrapezoid, Timer, RSFlipFlop,
ZeroCrossing, OnDelay), as in MSL 4.1.0.

Every Boolean here is a discrete variable: it changes only at events, and a
relation on a Real signal (``u > threshold``) is an event indicator whose
crossing the integrator locates.  The Boolean parameters (``pre_u_start``,
``pre_y_start``, ``Qini``) are structural: they give the ``pre()`` value of a
Boolean at initialization (Modelica's ``initial equation pre(u) = ...``),
which acausal writes as the variable's ``start`` with ``fixed=True``.

A Boolean signal drives a Real input only through a conversion block
(:class:`acausal.library.blocks.booleans.BooleanToReal`).
"""

from __future__ import annotations

import sympy as sp

from acausal.errors import ModifierError
from acausal.hybrid import Assert, When, change, edge, terminate
from acausal.language import Boolean, Component, Eq, If, Parameter, RealInput, RealOutput, Variable, initial, pre, time
from acausal.components.blocks import (BooleanInput, BooleanOutput, PartialBooleanSI2SO, PartialBooleanSI3SO,
                                       PartialBooleanSISO)
from acausal.components.logic import is_initial, pre_boolean

__all__ = [
    "And", "Or", "Xor", "Nand", "Nor", "Not",
    "Pre", "Edge", "FallingEdge", "Change",
    "GreaterThreshold", "GreaterEqualThreshold", "LessThreshold", "LessEqualThreshold",
    "Greater", "GreaterEqual", "Less", "LessEqual",
    "ZeroCrossing", "Switch", "LogicalSwitch", "Hysteresis", "OnOffController",
    "TriggeredTrapezoid", "Timer", "LogicalDelay", "RSFlipFlop", "TerminateSimulation", "AssertCondition",
    "OnDelay",
]


def _fix_pre(component: Component, variable: str, value) -> None:
    """``pre(variable) = value`` at initialization (unless the user modifies the variable's
    start/fixed): Modelica's ``initial equation pre(u) = pre_u_start``.

    ``value`` is a function of the component (it reads structural parameters).
    """
    attributes = component._attribute_modifiers.setdefault(variable, {})
    attributes.setdefault("start", value)
    attributes.setdefault("fixed", True)


# --------------------------------------------------------------------------
# partial blocks (Modelica.Blocks.Interfaces.partialBoolean*)


class PartialBooleanThresholdComparison(Component):
    """A Real input compared with a threshold (Modelica.Blocks.Interfaces.partialBooleanThresholdComparison)."""

    modelica_name = "Modelica.Blocks.Interfaces.partialBooleanThresholdComparison"

    threshold = Parameter(0.0, description="Comparison with respect to threshold")
    u = RealInput(description="Connector of Real input signal")
    y = BooleanOutput(description="Connector of Boolean output signal")


class PartialBooleanComparison(Component):
    """Two Real inputs compared (Modelica.Blocks.Interfaces.partialBooleanComparison)."""

    modelica_name = "Modelica.Blocks.Interfaces.partialBooleanComparison"

    u1 = RealInput(description="Connector of first Real input signal")
    u2 = RealInput(description="Connector of second Real input signal")
    y = BooleanOutput(description="Connector of Boolean output signal")


# --------------------------------------------------------------------------
# gates


class And(PartialBooleanSI2SO):
    """Logical 'and': ``y = u1 and u2`` (Modelica.Blocks.Logical.And)."""

    modelica_name = "Modelica.Blocks.Logical.And"

    def equations(self):
        return [Eq(self.y, sp.And(self.u1, self.u2))]


class Or(PartialBooleanSI2SO):
    """Logical 'or': ``y = u1 or u2`` (Modelica.Blocks.Logical.Or)."""

    modelica_name = "Modelica.Blocks.Logical.Or"

    def equations(self):
        return [Eq(self.y, sp.Or(self.u1, self.u2))]


class Xor(PartialBooleanSI2SO):
    """Logical 'xor': ``y`` is true where exactly one input is (Modelica.Blocks.Logical.Xor)."""

    modelica_name = "Modelica.Blocks.Logical.Xor"

    def equations(self):
        return [Eq(self.y, sp.Xor(self.u1, self.u2))]


class Nand(PartialBooleanSI2SO):
    """Logical 'nand': ``y = not (u1 and u2)`` (Modelica.Blocks.Logical.Nand)."""

    modelica_name = "Modelica.Blocks.Logical.Nand"

    def equations(self):
        return [Eq(self.y, sp.Not(sp.And(self.u1, self.u2)))]


class Nor(PartialBooleanSI2SO):
    """Logical 'nor': ``y = not (u1 or u2)`` (Modelica.Blocks.Logical.Nor)."""

    modelica_name = "Modelica.Blocks.Logical.Nor"

    def equations(self):
        return [Eq(self.y, sp.Not(sp.Or(self.u1, self.u2)))]


class Not(PartialBooleanSISO):
    """Logical 'not': ``y = not u`` (Modelica.Blocks.Logical.Not)."""

    modelica_name = "Modelica.Blocks.Logical.Not"

    def equations(self):
        return [Eq(self.y, sp.Not(self.u))]


# --------------------------------------------------------------------------
# pre, edge, change


class _PreStart(PartialBooleanSISO):
    """``pre_u_start``, the value of ``pre(u)`` at initialization."""

    pre_u_start = Parameter(False, structural=True, description="Start value of pre(u) at initial time")

    def __init__(self, **modifiers) -> None:
        super().__init__(**modifiers)
        _fix_pre(self, "u", lambda block: bool(block.pre_u_start))


class Pre(_PreStart):
    """Breaks algebraic loops by an infinitesimal small time delay (``y = pre(u)``: event
    iteration continues until ``u = pre(u)``) (Modelica.Blocks.Logical.Pre).

    ``y`` is the input's value before the current pass of event iteration, so a
    Boolean loop closed through it settles in one more pass.
    """

    modelica_name = "Modelica.Blocks.Logical.Pre"

    def equations(self):
        return [Eq(self.y, pre_boolean(self.u))]


class Edge(_PreStart):
    """Output ``y`` is true if the input ``u`` has a rising edge (``y = edge(u)``)
    (Modelica.Blocks.Logical.Edge).

    True in one pass of event iteration only: where ``u`` becomes true.
    """

    modelica_name = "Modelica.Blocks.Logical.Edge"

    def equations(self):
        return [Eq(self.y, edge(self.u))]


class FallingEdge(_PreStart):
    """Output ``y`` is true if the input ``u`` has a falling edge (``y = edge(not u)``)
    (Modelica.Blocks.Logical.FallingEdge).

    True in one pass of event iteration only: where ``u`` becomes false.
    """

    modelica_name = "Modelica.Blocks.Logical.FallingEdge"

    not_u = Boolean(description="not u (protected)")

    def __init__(self, **modifiers) -> None:
        super().__init__(**modifiers)
        _fix_pre(self, "not_u", lambda block: not block.pre_u_start)

    def equations(self):
        return [Eq(self.not_u, sp.Not(self.u)), Eq(self.y, edge(self.not_u))]


class Change(_PreStart):
    """Output ``y`` is true if the input ``u`` has a rising or falling edge (``y =
    change(u)``) (Modelica.Blocks.Logical.Change).

    True in one pass of event iteration only: where ``u`` changes.
    """

    modelica_name = "Modelica.Blocks.Logical.Change"

    def equations(self):
        return [Eq(self.y, change(self.u))]


# --------------------------------------------------------------------------
# comparisons


class GreaterThreshold(PartialBooleanThresholdComparison):
    """Output ``y`` is true if input ``u`` is greater than the threshold (Modelica.Blocks.Logical.GreaterThreshold)."""

    modelica_name = "Modelica.Blocks.Logical.GreaterThreshold"

    def equations(self):
        return [Eq(self.y, self.u > self.threshold)]


class GreaterEqualThreshold(PartialBooleanThresholdComparison):
    """Output ``y`` is true if input ``u`` is greater than or equal to the threshold
    (Modelica.Blocks.Logical.GreaterEqualThreshold)."""

    modelica_name = "Modelica.Blocks.Logical.GreaterEqualThreshold"

    def equations(self):
        return [Eq(self.y, self.u >= self.threshold)]


class LessThreshold(PartialBooleanThresholdComparison):
    """Output ``y`` is true if input ``u`` is less than the threshold (Modelica.Blocks.Logical.LessThreshold)."""

    modelica_name = "Modelica.Blocks.Logical.LessThreshold"

    def equations(self):
        return [Eq(self.y, self.u < self.threshold)]


class LessEqualThreshold(PartialBooleanThresholdComparison):
    """Output ``y`` is true if input ``u`` is less than or equal to the threshold
    (Modelica.Blocks.Logical.LessEqualThreshold)."""

    modelica_name = "Modelica.Blocks.Logical.LessEqualThreshold"

    def equations(self):
        return [Eq(self.y, self.u <= self.threshold)]


class Greater(PartialBooleanComparison):
    """Output ``y`` is true if input ``u1`` is greater than input ``u2`` (Modelica.Blocks.Logical.Greater)."""

    modelica_name = "Modelica.Blocks.Logical.Greater"

    def equations(self):
        return [Eq(self.y, self.u1 > self.u2)]


class GreaterEqual(PartialBooleanComparison):
    """Output ``y`` is true if input ``u1`` is greater than or equal to input ``u2``
    (Modelica.Blocks.Logical.GreaterEqual)."""

    modelica_name = "Modelica.Blocks.Logical.GreaterEqual"

    def equations(self):
        return [Eq(self.y, self.u1 >= self.u2)]


class Less(PartialBooleanComparison):
    """Output ``y`` is true if input ``u1`` is less than input ``u2`` (Modelica.Blocks.Logical.Less)."""

    modelica_name = "Modelica.Blocks.Logical.Less"

    def equations(self):
        return [Eq(self.y, self.u1 < self.u2)]


class LessEqual(PartialBooleanComparison):
    """Output ``y`` is true if input ``u1`` is less than or equal to input ``u2``
    (Modelica.Blocks.Logical.LessEqual)."""

    modelica_name = "Modelica.Blocks.Logical.LessEqual"

    def equations(self):
        return [Eq(self.y, self.u1 <= self.u2)]


# --------------------------------------------------------------------------
# switches and event-driven blocks


class ZeroCrossing(Component):
    """Trigger zero crossing of input ``u`` (Modelica.Blocks.Logical.ZeroCrossing).

    ``y`` is true for one pass of event iteration where ``u`` crosses zero
    while ``enable`` stays true; switching ``enable`` itself never counts.
    """

    modelica_name = "Modelica.Blocks.Logical.ZeroCrossing"

    u = RealInput(description="Connector of Real input signal")
    enable = BooleanInput(description="Zero input crossing is triggered if the enable input signal is true")
    y = BooleanOutput(description="Connector of Boolean output signal")
    disable = Boolean(description="not enable (protected)")
    u_pos = Boolean(description="enable and u >= 0 (protected)")

    def __init__(self, **modifiers) -> None:
        super().__init__(**modifiers)
        # initial equation pre(u_pos) = false; pre(enable) = false; pre(disable) = not pre(enable)
        _fix_pre(self, "u_pos", False)
        _fix_pre(self, "enable", False)
        _fix_pre(self, "disable", True)

    def equations(self):
        return [Eq(self.disable, sp.Not(self.enable)),
                Eq(self.u_pos, sp.And(self.enable, self.u >= 0)),
                Eq(self.y, sp.And(change(self.u_pos), sp.Not(edge(self.enable)), sp.Not(edge(self.disable))))]


class Switch(Component):
    """Switch between two Real signals (Modelica.Blocks.Logical.Switch): ``y = u1 if u2 else u3``."""

    modelica_name = "Modelica.Blocks.Logical.Switch"

    u1 = RealInput(description="Connector of first Real input signal")
    u2 = BooleanInput(description="Connector of Boolean input signal")
    u3 = RealInput(description="Connector of second Real input signal")
    y = RealOutput(description="Connector of Real output signal")

    def equations(self):
        return [Eq(self.y, If(self.u2, self.u1, self.u3))]


class LogicalSwitch(PartialBooleanSI3SO):
    """Logical switch (Modelica.Blocks.Logical.LogicalSwitch): ``y = u1 if u2 else u3``."""

    modelica_name = "Modelica.Blocks.Logical.LogicalSwitch"

    def equations(self):
        return [Eq(self.y, sp.Or(sp.And(self.u2, self.u1), sp.And(sp.Not(self.u2), self.u3)))]


class Hysteresis(Component):
    """Transform Real to Boolean signal with Hysteresis (Modelica.Blocks.Logical.Hysteresis).

    ``y = (not pre(y) and u > uHigh) or (pre(y) and u >= uLow)``: ``y``
    switches on where ``u`` rises above ``uHigh`` and off where it falls below
    ``uLow``.  No when-clause: event iteration settles the equation on its own
    ``pre()``, which is ``pre_y_start`` at initialization.
    """

    modelica_name = "Modelica.Blocks.Logical.Hysteresis"

    uLow = Parameter(0.0, description="if y=true and u<uLow, switch to y=false")  # noqa: N815
    uHigh = Parameter(1.0, description="if y=false and u>uHigh, switch to y=true")  # noqa: N815
    pre_y_start = Parameter(False, structural=True, description="Value of pre(y) at initial time")
    u = RealInput(description="Connector of Real input signal")
    y = BooleanOutput(description="Connector of Boolean output signal")

    def __init__(self, **modifiers) -> None:
        super().__init__(**modifiers)
        _fix_pre(self, "y", lambda block: bool(block.pre_y_start))

    def equations(self):
        was = pre_boolean(self.y)
        return [Assert(self.uHigh > self.uLow, "Hysteresis limits wrong (uHigh <= uLow)"),
                Eq(self.y, sp.Or(sp.And(sp.Not(was), self.u > self.uHigh),
                                 sp.And(was, self.u >= self.uLow)))]


class OnOffController(Component):
    """On-off controller (Modelica.Blocks.Logical.OnOffController).

    ``y`` turns on where ``u < reference - bandwidth/2`` and stays on while
    ``u < reference + bandwidth/2``: ``y = (pre(y) and u < reference +
    bandwidth/2) or u < reference - bandwidth/2``.
    """

    modelica_name = "Modelica.Blocks.Logical.OnOffController"

    bandwidth = Parameter(0.1, description="Bandwidth around reference signal")
    pre_y_start = Parameter(False, structural=True, description="Value of pre(y) at initial time")
    reference = RealInput(description="Connector of Real input signal used as reference signal")
    u = RealInput(description="Connector of Real input signal used as measurement signal")
    y = BooleanOutput(description="Connector of Boolean output signal")

    def __init__(self, **modifiers) -> None:
        super().__init__(**modifiers)
        _fix_pre(self, "y", lambda block: bool(block.pre_y_start))

    def equations(self):
        half = self.bandwidth / 2
        return [Eq(self.y, sp.Or(sp.And(pre_boolean(self.y), self.u < self.reference + half),
                                 self.u < self.reference - half))]


class TriggeredTrapezoid(Component):
    """Triggered trapezoid generator (Modelica.Blocks.Logical.TriggeredTrapezoid).

    Where ``u`` becomes true, ``y`` ramps from its current value up to
    ``offset + amplitude`` in ``rising`` seconds (for the whole amplitude);
    where ``u`` becomes false it ramps down to ``offset`` in ``falling``
    seconds.  At initialization ``y`` takes its end value at once.
    """

    modelica_name = "Modelica.Blocks.Logical.TriggeredTrapezoid"

    amplitude = Parameter(1.0, description="Amplitude of trapezoid")
    rising = Parameter(0.0, unit="s", min=0, description="Rising duration of trapezoid")
    falling = Parameter(None, unit="s", min=0, description="Falling duration of trapezoid (default rising)")
    offset = Parameter(0.0, description="Offset of output signal")
    u = BooleanInput(description="Connector of Boolean input signal")
    y = RealOutput(description="Connector of Real output signal")
    endValue = Variable(discrete=True, description="Value of y at time of change (protected)")  # noqa: N815
    rate = Variable(discrete=True, description="Current rising/falling rate (protected)")
    T = Variable(discrete=True, unit="s", description="Predicted time of output change (protected)")

    def parameter_binding(self, name):
        if name == "falling" and "falling" not in self._modifiers:
            return self.rising  # falling = rising
        return super().parameter_binding(name)

    def equations(self):
        u, amplitude, rising, falling = self.u, self.amplitude, self.rising, self.falling
        up = rising > 0
        down = falling > 0
        at_once = sp.Or(sp.And(u, sp.Not(up)), sp.And(sp.Not(u), sp.Not(down)),
                        sp.Not(sp.Abs(amplitude) > 0), is_initial())
        return [
            Eq(self.y, sp.Piecewise((self.endValue - (self.T - time) * self.rate, time < self.T),
                                    (self.endValue, True))),
            When([initial(), u, sp.Not(u)],
                 Eq(self.endValue, If(u, self.offset + amplitude, self.offset)),
                 Eq(self.rate, sp.Piecewise((amplitude / rising, sp.And(u, up)),
                                            (-amplitude / falling, sp.And(sp.Not(u), down)),
                                            (0, True))),
                 Eq(self.T, sp.Piecewise((time, at_once),
                                         (time + (self.endValue - pre(self.y)) / self.rate, True)))),
        ]


class Timer(Component):
    """Timer measuring the time from the time instant where the Boolean input became true
    (Modelica.Blocks.Logical.Timer).

    ``y = time - entryTime`` while ``u`` is true, else 0; ``entryTime`` is the
    instant ``u`` last became true (0 if it is true from the start).
    """

    modelica_name = "Modelica.Blocks.Logical.Timer"

    u = BooleanInput(description="Connector of Boolean input signal")
    y = RealOutput(unit="s", description="Connector of Real output signal")
    entryTime = Variable(discrete=True, unit="s", start=0.0, fixed=True,  # noqa: N815
                         description="Time instant when u became true (protected)")

    def equations(self):
        return [When(self.u, Eq(self.entryTime, time)),
                Eq(self.y, If(self.u, time - self.entryTime, 0))]


class LogicalDelay(Component):
    """Delay boolean signal (Modelica.Blocks.Logical.LogicalDelay).

    ``y1`` follows a rising edge of ``u`` at once and a falling edge
    ``delayTime`` later; ``y2`` follows a rising edge ``delayTime`` later and a
    falling edge at once.  ``tSwitch`` is the instant ``u`` last changed; it
    starts at ``time - 2*delayTime``, so that an input constant from the
    start is not delayed.
    """

    modelica_name = "Modelica.Blocks.Logical.LogicalDelay"

    delayTime = Parameter(0.0, unit="s", min=0, description="Time delay")  # noqa: N815
    u = BooleanInput(description="Connector of Boolean input signal")
    y1 = BooleanOutput(description="Falling edges of u delayed")
    y2 = BooleanOutput(description="Rising edges of u delayed")
    tSwitch = Variable(discrete=True, unit="s", description="Instant of the last change of u (protected)")  # noqa: N815

    def equations(self):
        delay_over = time >= self.tSwitch + self.delayTime
        return [
            # initial equation tSwitch = time - 2*delayTime; when {u, not u} then tSwitch = time
            When(initial(), Eq(self.tSwitch, time - 2 * self.delayTime))
            .elsewhen([self.u, sp.Not(self.u)], Eq(self.tSwitch, time)),
            Eq(self.y1, sp.Or(self.u, sp.Not(delay_over))),
            Eq(self.y2, sp.And(self.u, delay_over)),
        ]


class RSFlipFlop(Component):
    """A basic RS flip flop (Modelica.Blocks.Logical.RSFlipFlop).

    Two Nor gates with the loop broken by a :class:`Pre` block named ``pre``
    (as in MSL): ``Q = not (QI or R)``, ``pre.u = not (S or Q)``,
    ``QI = pre(pre.u)``.  ``S`` sets ``Q``, ``R`` resets it.
    """

    modelica_name = "Modelica.Blocks.Logical.RSFlipFlop"

    Qini = Parameter(False, structural=True, description="Start value of Q at initial time")
    S = BooleanInput(description="Set input")
    R = BooleanInput(description="Reset input")
    Q = BooleanOutput(description="Output")
    QI = BooleanOutput(description="Inverted output")

    def build(self):
        self.nor = Nor()
        self.nor1 = Nor()
        self.pre = Pre(pre_u_start=not self.Qini)
        self.connect(self.S, self.nor.u1)
        self.connect(self.R, self.nor1.u2)
        self.connect(self.nor.y, self.pre.u)
        self.connect(self.nor1.y, self.nor.u2)
        self.connect(self.pre.y, self.nor1.u1)

    def equations(self):
        # MSL: connect(nor1.y, Q) and connect(pre.y, QI).  The engine rejects a connection
        # from an inner output to the composite's own output ("two outputs cannot be
        # connected"), so the outputs are set by equations (the same flat equations).
        return [Eq(self.Q, self.nor1.y), Eq(self.QI, self.pre.y)]


class TerminateSimulation(Component):
    """Terminate simulation if condition is fulfilled (Modelica.Blocks.Logical.TerminateSimulation).

    The condition is given as in Modelica, as the value of the output
    ``condition``: ``TerminateSimulation(condition=time > 1)`` (any Boolean
    expression of the model's signals).  The run ends successfully at the
    event where it becomes true.
    """

    modelica_name = "Modelica.Blocks.Logical.TerminateSimulation"

    terminationText = Parameter("... End condition reached", structural=True,  # noqa: N815
                                description="Text that will be displayed when simulation is terminated")
    condition = BooleanOutput(description="Terminate simulation when condition becomes true")

    def __init__(self, **modifiers) -> None:
        binding = modifiers.pop("condition", None)
        if isinstance(binding, dict):
            modifiers["condition"] = binding
            binding = None
        super().__init__(**modifiers)
        if binding is not None and not isinstance(binding, (bool, sp.Basic)):
            raise ModifierError(f"TerminateSimulation.condition: {binding!r} is not a Boolean expression",
                                hint="TerminateSimulation(condition=time > 1)")
        object.__setattr__(self, "_condition", sp.false if binding is None else sp.sympify(binding))

    def equations(self):
        return [Eq(self.condition, self._condition),
                When(self.condition, terminate(self.terminationText))]


class AssertCondition(Component):
    """Assert when condition is violated (Modelica.Blocks.Logical.AssertCondition, new in MSL 4.1).

    ``assertionLevel="error"`` ends the run where ``u`` is false;
    ``"warning"`` records ``message`` in the result's notes and goes on.
    """

    modelica_name = "Modelica.Blocks.Logical.AssertCondition"

    message = Parameter("Assert block failed", structural=True, description="Message written if u becomes false")
    assertionLevel = Parameter("error", structural=True,  # noqa: N815
                               description="Assertion level (\"error\" or \"warning\")")
    u = BooleanInput(description="Connector of Boolean input signal")

    def equations(self):
        return [Assert(self.u, self.message, str(getattr(self.assertionLevel, "name", self.assertionLevel)))]


# --------------------------------------------------------------------------
# MathBoolean


class OnDelay(PartialBooleanSISO):
    """Delay a rising edge of the input, but do not delay a falling edge
    (Modelica.Blocks.MathBoolean.OnDelay).

    ``y`` becomes true ``delayTime`` after ``u`` became true, if ``u`` is
    still true then; it becomes false with ``u``.  An input true at the start
    is not delayed.
    """

    modelica_name = "Modelica.Blocks.MathBoolean.OnDelay"

    delayTime = Parameter(None, unit="s", description="Delay time")  # noqa: N815
    delaySignal = Boolean(start=False, fixed=True, description="Delayed u (protected)")  # noqa: N815
    t_next = Variable(discrete=True, unit="s", description="Next sample time instant (protected)")

    def __init__(self, **modifiers) -> None:
        super().__init__(**modifiers)
        _fix_pre(self, "u", False)  # initial equation pre(u) = false

    def equations(self):
        return [
            When(initial(), Eq(self.delaySignal, self.u), Eq(self.t_next, time - 1))
            .elsewhen(self.u, Eq(self.delaySignal, sp.true), Eq(self.t_next, time + self.delayTime))
            .elsewhen(sp.Not(self.u), Eq(self.delaySignal, sp.false), Eq(self.t_next, time - 1)),
            Eq(self.y, sp.And(self.delaySignal, time >= self.t_next)),
        ]
