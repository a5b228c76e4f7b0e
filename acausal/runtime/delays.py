"""The history of a run, from which ``delay()`` reads its values.

Every accepted step of the integrator is kept with its dense output and the
system in force (:meth:`DelayHistory.add_step`), every stretch between events
starts with its state right after the event (:meth:`DelayHistory.add_point`),
so the history spans event restarts.  A delayed value at ``t`` is the
delayed expression (the hidden variable ``$delayK`` of
:mod:`acausal.compiler.delays`) evaluated from the states interpolated at
``t - T`` by the dense output of the step that holds it, with the system of
that step.  Before the start time (and at it) it is the expression's value at
the start time.

For fixed delays the largest step is the smallest delay time, so ``t - T``
lies in an accepted step whenever the integrator evaluates the model (a
round-off beyond the last step extrapolates that step's polynomial).  For
variable delays ``t - T`` may lie in the step being taken: the last accepted
step's dense output is extrapolated for the trial evaluations, and the
accepted step (recorded before its output points and crossings are
evaluated) serves from then on.

A discontinuity of the delayed expression at ``t_e`` (an event, the start)
reappears at ``t_e + T``: for fixed delays these instants are *breaks*
(:meth:`DelayHistory.next_break`), where the integrator is restarted without
an event, up to :data:`BREAK_DEPTH` generations (a break at ``t`` makes one at
``t + T`` again, as the discontinuities of a delay differential equation
propagate, smoothing by one order each time).
"""

from __future__ import annotations

import bisect
import heapq
import math

from typing import TYPE_CHECKING, Mapping

import numpy as np

from ..errors import ModelDefinitionError, SolverError

if TYPE_CHECKING:
    from ..compiler.compiled import DelayData

__all__ = ["DelayHistory", "BREAK_DEPTH"]

#: How many generations of breaks a discontinuity makes (t_e + T, t_e + 2T, ...): a
#: jump of a delayed value at ``t_e + T`` is a jump of the k-th derivative at ``t_e + kT``
#: for a delay differential equation; the integrators' orders go up to 8 (DOP853).
BREAK_DEPTH = 8


class DelayHistory:
    """The recorded solution of one run and the values of its delays.

    Parameters
    ----------
    delays : sequence of DelayData
    numbers : mapping
        Delay index -> its delay time (a fixed delay) or its ``delayMax``
        (a variable one), as numbers (the translation's
        :meth:`~acausal.runtime.contract.CompiledModel.delay_numbers`).
    """

    def __init__(self, delays: "tuple[DelayData, ...]", numbers: Mapping[int, float]) -> None:
        self.delays = tuple(delays)
        self.fixed_times: dict[int, float] = {}
        for d in self.delays:
            if d.fixed:
                value = numbers[d.index]
                if not (math.isfinite(value) and value > 0):
                    raise ModelDefinitionError(
                        f"{d.component or '(model)'}: {d.text}: the delay time is {value:g}; it must be > 0",
                        hint="a delay time of 0 is the expression itself: write it without delay()",
                        components=(d.component,))
                self.fixed_times[d.index] = value
            else:
                value = numbers[d.index]
                if not (math.isfinite(value) and value >= 0):
                    raise ModelDefinitionError(f"{d.component or '(model)'}: {d.text}: delayMax is "
                                               f"{value:g}; it must be finite and >= 0",
                                               components=(d.component,))
        self.variables = {d.index: d.variable for d in self.delays}
        self.texts = {d.index: d.text for d in self.delays}
        self.t0 = -math.inf
        self.started = False
        self.start_values: dict[int, float] = {}
        # the entries: (t_a, t_b, dense or None, system, x_a), in time order
        self.starts: list[float] = []
        self.ends: list[float] = []
        self.entries: list[tuple] = []
        self.segment_start = math.nan
        self._readers: dict[tuple[int, int], object] = {}
        self._breaks: list[tuple[float, int]] = []
        self._scheduled: set[float] = set()

    # -- what the runtime records -------------------------------------------------------

    @property
    def max_step(self) -> float:
        """The largest step the integrator may take: the smallest fixed delay time."""
        return min(self.fixed_times.values(), default=math.inf)

    def set_start(self, t0: float, values) -> None:
        """Before integration starts (initialization): the delayed values are the
        expressions' values ``values`` (by variable name) at the start time."""
        self.t0 = t0
        for k, name in self.variables.items():
            if name in values:
                self.start_values[k] = float(values[name])

    def add_point(self, t: float, x, system) -> None:
        """A stretch begins at ``t`` with the states ``x`` (the start, or right after an event)."""
        x = np.array(x, dtype=float)
        if not self.started:
            self.started = True
            self.t0 = t
            for k in self.variables:
                self.start_values[k] = self._read(k, system, t, x)
        self._append(t, t, None, system, x)

    def add_step(self, t_a: float, t_b: float, dense, system) -> None:
        """An accepted step over ``[t_a, t_b]`` with its dense output."""
        self._append(t_a, t_b, dense, system, None)

    def trim_last(self, t_end: float) -> None:
        """The last step ends at ``t_end`` (an event inside it)."""
        t_a, _, dense, system, x = self.entries[-1]
        self.entries[-1] = (t_a, t_end, dense, system, x)
        self.ends[-1] = t_end

    def _append(self, t_a, t_b, dense, system, x) -> None:
        self.starts.append(t_a)
        self.ends.append(t_b)
        self.entries.append((t_a, t_b, dense, system, x))

    # -- breaks ---------------------------------------------------------------------------

    def discontinuity(self, t: float, depth: int = 0, t_stop: float = math.inf) -> None:
        """The delayed expressions may be discontinuous at ``t``: breaks at ``t + T``."""
        if depth >= BREAK_DEPTH:
            return
        for T in sorted(set(self.fixed_times.values())):
            when = t + T
            if when < t_stop and when not in self._scheduled:  # one break per instant
                self._scheduled.add(when)
                heapq.heappush(self._breaks, (when, depth + 1))

    def next_break(self, t: float) -> float:
        """The first break after ``t`` (breaks at or before ``t`` are dropped)."""
        while self._breaks and self._breaks[0][0] <= t:
            heapq.heappop(self._breaks)
        return self._breaks[0][0] if self._breaks else math.inf

    def pass_break(self, t: float, t_stop: float) -> bool:
        """The integration reached ``t``: the breaks there make the next generation.
        Returns whether ``t`` was a break."""
        found = False
        while self._breaks and self._breaks[0][0] <= t:
            when, depth = heapq.heappop(self._breaks)
            if when == t:
                found = True
                self.discontinuity(t, depth, t_stop)
        return found

    # -- what the generated code reads ------------------------------------------------------

    def value(self, k: int, t: float, delay_time: float, delay_max: float) -> float:
        """Delay ``k`` at time ``t`` (its delay time ``delay_time`` now)."""
        if not (0.0 <= delay_time <= delay_max * (1 + 1e-12) + 1e-300):
            raise SolverError(f"at t = {t:.12g} {self.texts[k]}: the delay time {delay_time:.6g} is "
                              f"outside [0, delayMax = {delay_max:.6g}]",
                              hint="Modelica requires 0 <= delayTime <= delayMax at all times")
        tau = t - delay_time
        if not self.started or tau <= self.t0 or not self.entries:
            try:
                return self.start_values[k]
            except KeyError:
                raise SolverError(f"{self.texts[k]}: the value of the delayed expression at the start "
                                  f"time is not known yet") from None
        ends, entries = self.ends, self.entries
        # t - T at an event instant, up to round-off: the left limit while a segment runs up
        # to t (a break at the event plus T), the right limit when the segment starts at t
        eps = 8 * math.ulp(max(abs(t), abs(delay_time), 1.0))
        i = bisect.bisect_left(ends, tau - eps)
        if i >= len(ends):
            i = len(ends) - 1  # beyond the last step: extrapolated
        elif i + 1 < len(entries) and ends[i] <= tau + eps and entries[i + 1][2] is None:
            if t == self.segment_start:
                i += 1
            tau = ends[i]
        t_a, t_b, dense, system, x = entries[i]
        if dense is not None:
            x = dense(tau)
        return self._read(k, system, tau, x)

    def _read(self, k: int, system, t: float, x) -> float:
        reader = self._readers.get((k, id(system)))
        if reader is None:
            reader = self._readers[(k, id(system))] = _reader(system, self.variables[k])
        return reader(t, x)


def _reader(system, name: str):
    """``f(t, x)``: the value of variable ``name`` in ``system`` at ``(t, x)``."""
    coefficient, source = 1.0, name
    for alias, coeff, src in getattr(system, "alias_plan", ()) or ():
        if alias == name:
            coefficient, source = coeff, src
            break
    if source is None:
        value = float(coefficient)
        return lambda t, x: value
    states = list(system.states)
    if source in states:
        i = states.index(source)
        return lambda t, x: coefficient * float(x[i])
    unknowns = list(system.unknowns)
    if source in unknowns:
        j = unknowns.index(source)
        outputs = system.outputs
        return lambda t, x: coefficient * float(outputs(t, x)[j])
    raise SolverError(f"the delayed expression {name} is not computed by the system {system.description}")
