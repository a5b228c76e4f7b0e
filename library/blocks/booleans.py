"""Boolean signal sources and conversions (Modelica.Blocks.Sources.Boolean*,
Modelica.Blocks.Math.BooleanToReal and RealToBoolean).

The sources' switching instants are events: ``BooleanStep`` and
``BooleanTable`` switch at time events (relations of ``time`` with
parameters, hit exactly), ``BooleanPulse`` starts each pulse at a
``sample()`` instant, ``SampleTrigger`` is ``sample()`` itself.  Boolean
parameters (``startValue``, ``k``) and the table are structural: they decide
which relations the block has.  ``BooleanExpression`` binds its output to an
expression given as ``y=...``; ``RadioButtonSource`` is pressed by a table
and released by other signals.
"""

from __future__ import annotations

import math
from typing import Any

import sympy as sp

from acausal.errors import ParameterError
from acausal.hybrid import When, change, sample
from acausal.language import (Boolean, Component, Eq, If, Parameter, RealInput, RealOutput, Variable, initial, pre,
                              time)
from acausal.components.blocks import BooleanInput, BooleanOutput
from acausal.components.logic import is_initial
from .sources import _BoundOutput, _StepTable

__all__ = ["BooleanConstant", "BooleanStep", "BooleanPulse", "SampleTrigger", "BooleanTable",
           "BooleanToReal", "RealToBoolean", "BooleanExpression", "RadioButtonSource"]


class PartialBooleanSource(Component):
    """A Boolean output (Modelica.Blocks.Interfaces.partialBooleanSource)."""

    modelica_name = "Modelica.Blocks.Interfaces.partialBooleanSource"

    y = BooleanOutput(description="Connector of Boolean output signal")


class BooleanConstant(PartialBooleanSource):
    """Generate constant signal of type Boolean (Modelica.Blocks.Sources.BooleanConstant): ``y = k``."""

    modelica_name = "Modelica.Blocks.Sources.BooleanConstant"

    k = Parameter(True, structural=True, description="Constant output value")

    def equations(self):
        return [Eq(self.y, sp.true if self.k else sp.false)]


class BooleanStep(PartialBooleanSource):
    """Generate step signal of type Boolean (Modelica.Blocks.Sources.BooleanStep).

    ``y = startValue`` before ``startTime`` and ``not startValue`` from it on
    (a time event; at ``time = startTime`` the new value holds).
    """

    modelica_name = "Modelica.Blocks.Sources.BooleanStep"

    startTime = Parameter(0.0, unit="s", description="Time instant of step start")  # noqa: N815
    startValue = Parameter(False, structural=True, description="Output before startTime")  # noqa: N815

    def equations(self):
        after = time >= self.startTime
        return [Eq(self.y, sp.Not(after) if self.startValue else after)]


class BooleanPulse(PartialBooleanSource):
    """Generate pulse signal of type Boolean (Modelica.Blocks.Sources.BooleanPulse).

    True for ``width`` percent of each ``period`` from ``startTime`` on:
    a pulse starts at every ``sample(startTime, period)`` instant
    (``pulseStart = time``) and ends ``period*width/100`` later.
    """

    modelica_name = "Modelica.Blocks.Sources.BooleanPulse"

    width = Parameter(50.0, unit="1", min=0, max=100, description="Width of pulse in % of period")
    period = Parameter(1.0, unit="s", min=0, description="Time for one period")
    startTime = Parameter(0.0, unit="s", description="Time instant of first pulse")  # noqa: N815
    pulseStart = Variable(discrete=True, unit="s", description="Start time of pulse (protected)")  # noqa: N815

    def equations(self):
        t_width = self.period * self.width / 100
        return [
            # initial equation pulseStart = startTime; when sample(startTime, period) then pulseStart = time
            When([initial(), sample(self.startTime, self.period)],
                 Eq(self.pulseStart, If(is_initial(), self.startTime, time))),
            Eq(self.y, sp.And(time >= self.pulseStart, time < self.pulseStart + t_width)),
        ]


class SampleTrigger(PartialBooleanSource):
    """Generate sample trigger signal (Modelica.Blocks.Sources.SampleTrigger).

    ``y = sample(startTime, period)``: true only at the sample instants, in
    the event iteration there.
    """

    modelica_name = "Modelica.Blocks.Sources.SampleTrigger"

    period = Parameter(0.01, unit="s", min=0, description="Sample period")
    startTime = Parameter(0.0, unit="s", description="Time instant of first sample trigger")  # noqa: N815

    def equations(self):
        return [Eq(self.y, sample(self.startTime, self.period))]


class BooleanTable(_StepTable, PartialBooleanSource):
    """Generate a Boolean output signal based on a vector of time instants
    (Modelica.Blocks.Sources.BooleanTable).

    As MSL 4.1 builds it: a CombiTimeTable with constant segments whose
    second column toggles between 0 and 1 at every entry of ``table``
    (strictly increasing times; ``startValue`` before the first), and a
    RealToBoolean (``y = table value >= 0.5``).  So ``y`` is
    right-continuous (at ``time = table[i]`` the new value holds), every
    entry is a time event, ``extrapolation`` (HoldLastPoint by default;
    Periodic repeats the pattern; LastTwoPoints is refused, as in the MSL)
    and ``shiftTime`` act as in the CombiTimeTable, and before a finite
    ``startTime`` the output is false.
    """

    modelica_name = "Modelica.Blocks.Sources.BooleanTable"

    table = Parameter((0.0, 1.0), unit="s", structural=True,
                      description="Vector of time points. At every time point, the output y gets its opposite value")
    startValue = Parameter(False, structural=True, description="Start value of y; at time = table[0], y changes to 'not startValue'")  # noqa: N815,E501

    def _times(self) -> list[float]:
        where = self.path or type(self).__name__
        try:
            times = [float(t) for t in self.table]
        except (TypeError, ValueError) as exc:
            raise ParameterError(f"{where}.table must be a sequence of time instants, not {self.table!r}",
                                 hint="BooleanTable(table=[1, 4, 6])") from exc
        for i in range(1, len(times)):
            if not times[i] > times[i - 1]:
                raise ParameterError(
                    f"{where}.table: time values of table not strictly increasing: table[{i}] = "
                    f"{times[i - 1]:g}, table[{i + 1}] = {times[i]:g}",
                    hint="list each switching instant once, in increasing order")
        if not all(math.isfinite(t) for t in times):
            raise ParameterError(f"{where}.table: the time instants must be finite numbers")
        return times

    def build(self) -> None:
        self.check_extrapolation()
        times = self._times()
        first = 1.0 if self.startValue else 0.0
        if times:
            # the value after the i-th instant (i from 1): 0 and 1 in turn, starting from not startValue
            rows = [[times[0], first]] + [[t, float((i + (1 if self.startValue else 0)) % 2)]
                                          for i, t in enumerate(times, start=1)]
        else:
            rows = [[0.0, first]]
        self.build_steps(rows, RealToBoolean(), "realToBoolean")


class BooleanExpression(_BoundOutput):
    """Set output signal to a time varying Boolean expression (Modelica.Blocks.Sources.BooleanExpression).

    ``BooleanExpression(y=expr)``: ``y = expr``, false by default; ``expr``
    a bool, a sympy relation or logical expression of ``time`` and the
    model's variables (``sympy.And(time >= 1, time < 2)``), or a function
    of the block returning one.
    """

    modelica_name = "Modelica.Blocks.Sources.BooleanExpression"

    y = BooleanOutput(description="Value of Boolean output")
    default_expression = False


class RadioButtonSource(Component):
    """Boolean signal source that mimics a radio button (Modelica.Blocks.Sources.RadioButtonSource).

    The button is pressed (``on`` becomes true) at every instant of
    ``buttonTimeTable`` (where the protected BooleanTable ``table``
    toggles), and released (``on`` becomes false) when an element of
    ``reset`` becomes true; pressing wins over releasing at the same
    instant.  ``reset`` is the MSL's ``input Boolean reset[:]``, bound by
    a modifier: a list of Boolean expressions, each a bool, a sympy
    expression of the model's variables, or a function of the block
    returning one (so two buttons can release each other:
    ``reset=[lambda block: self.stop.on]`` in the model's ``build()``).
    As in the MSL, a release acts through ``pre(reset)`` (one event
    iteration later, at the same time), which breaks the loop between
    buttons that release each other.
    """

    modelica_name = "Modelica.Blocks.Sources.RadioButtonSource"

    buttonTimeTable = Parameter((0.0, 1.0), unit="s", structural=True,  # noqa: N815
                                description="Time instants where button is pressed")
    nReset = Parameter(1, structural=True, min=0, description="Number of reset signals (set from reset)")  # noqa: N815
    on = BooleanOutput(start=False, fixed=True, description="Connector of Boolean output signal")
    reset = Boolean(shape="nReset", description="Reset button to false, if an element of reset becomes true")
    pre_reset = Boolean(shape="nReset", description="pre(reset) (protected)")

    @staticmethod
    def _split(modifiers: dict[str, Any]) -> tuple[dict[str, Any], list]:
        """The modifiers without ``reset`` (with ``nReset`` from it), and the reset expressions."""
        modifiers = dict(modifiers)
        resets = [False]
        if "reset" in modifiers and not isinstance(modifiers["reset"], dict):
            value = modifiers.pop("reset")
            resets = list(value) if isinstance(value, (list, tuple)) else [value]
        modifiers.setdefault("nReset", len(resets))
        if modifiers["nReset"] != len(resets):
            raise ParameterError(f"RadioButtonSource: nReset = {modifiers['nReset']!r}, but reset has "
                                 f"{len(resets)} elements", hint="nReset is set from reset; leave it out")
        return modifiers, resets

    def __new__(cls, *args: Any, **modifiers: Any):
        return super().__new__(cls, *args, **cls._split(modifiers)[0])

    def __init__(self, **modifiers: Any) -> None:
        modifiers, resets = self._split(modifiers)
        super().__init__(**modifiers)
        object.__setattr__(self, "_resets", resets)

    def build(self) -> None:
        self.table = BooleanTable(table=list(self.buttonTimeTable), y=dict(start=False, fixed=True))

    def _reset_expressions(self) -> list:
        expressions = []
        for value in self._resets:
            value = value(self) if callable(value) else value
            expressions.append((sp.true if value else sp.false) if isinstance(value, bool) else value)
        return expressions

    def equations(self):
        equations = [Eq(r, e) for r, e in zip(self.reset, self._reset_expressions())]
        equations += [Eq(p, pre(r)) for p, r in zip(self.pre_reset, self.reset)]
        # the MSL's algorithm assigns on in two when-statements, the press last: it wins
        pressed = When(change(self.table.y), Eq(self.on, sp.true))
        if int(self.nReset) > 0:
            pressed = pressed.elsewhen(list(self.pre_reset), Eq(self.on, sp.false))
        equations.append(pressed)
        return equations


class BooleanToReal(Component):
    """Convert Boolean to Real signal (Modelica.Blocks.Math.BooleanToReal):
    ``y = realTrue if u else realFalse``."""

    modelica_name = "Modelica.Blocks.Math.BooleanToReal"

    realTrue = Parameter(1.0, description="Output signal for true Boolean input")  # noqa: N815
    realFalse = Parameter(0.0, description="Output signal for false Boolean input")  # noqa: N815
    u = BooleanInput(description="Connector of Boolean input signal")
    y = RealOutput(description="Connector of Real output signal")

    def equations(self):
        return [Eq(self.y, If(self.u, self.realTrue, self.realFalse))]


class RealToBoolean(Component):
    """Convert Real to Boolean signal (Modelica.Blocks.Math.RealToBoolean): ``y = u >= threshold``."""

    modelica_name = "Modelica.Blocks.Math.RealToBoolean"

    threshold = Parameter(0.5, description="Output signal y is true, if input u >= threshold")
    u = RealInput(description="Connector of Real input signal")
    y = BooleanOutput(description="Connector of Boolean output signal")

    def equations(self):
        return [Eq(self.y, self.u >= self.threshold)]
