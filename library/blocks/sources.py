"""Signal sources (Modelica.Blocks.Sources).

The periodic sources (:class:`Pulse`, :class:`SawTooth`, :class:`Trapezoid`)
count their periods in a when-clause, at exact time events; the tables
(:class:`TimeTable` is a piecewise expression of ``time`` whose switching at
the table times are time events (values right-continuous at a repeated
time); :class:`CombiTimeTable` is MSL 4.1's: a held next time event and
the interpolations of :mod:`acausal.interpolation`.  The Boolean sources are in
:mod:`acausal.library.blocks.booleans`.
"""

from __future__ import annotations

import math
from typing import Any, Callable, Sequence

import sympy as sp

from acausal.components.blocks import SO, IntegerOutput, SignalSource
from acausal.components.declarations import DerivedDefaults, VectorBlock
from acausal.components.logic import is_initial
from acausal.components.tables import (Extrapolation, Smoothness, TableData, TimeEvents, default_columns,
                                       range_asserts)
from acausal.errors import ParameterError
from acausal.hybrid import When, noEvent, sample
from acausal.interpolation import TimeTable as NumericTimeTable
from acausal.language import Component, Eq, If, Integer, Parameter, RealOutput, Variable, initial, pre, time
from acausal.tables import time_table_functions

from .discrete import EPS, SMALL
from .math import RealToInteger

#: Modelica.Constants.inf: what the MSL holds as "no further time event"
MODELICA_INF = 1e60

__all__ = ["Constant", "ContinuousClock", "Step", "Ramp", "Sine", "Cosine", "ExpSine", "Pulse", "SawTooth", "Trapezoid",
           "TimeTable", "CombiTimeTable", "IntegerTable", "Smoothness", "Extrapolation", "TimeEvents"]


class Constant(SO):
    """Generate a constant signal (Modelica.Blocks.Sources.Constant): ``y = k``."""

    modelica_name = "Modelica.Blocks.Sources.Constant"

    k = Parameter(1.0, description="Constant output value")

    def equations(self):
        return [Eq(self.y, self.k)]


class ContinuousClock(SignalSource):
    """Generate current time signal (Modelica.Blocks.Sources.ContinuousClock):
    ``y = offset + (0 if time < startTime else time - startTime)``."""

    modelica_name = "Modelica.Blocks.Sources.ContinuousClock"

    def equations(self):
        return [Eq(self.y, self.offset + If(time < self.startTime, 0, time - self.startTime))]


class Step(SignalSource):
    """Generate a step signal (Modelica.Blocks.Sources.Step).

    ``y = offset + (0 if time < startTime else height)``.
    """

    modelica_name = "Modelica.Blocks.Sources.Step"

    height = Parameter(1.0, description="Height of step")

    def equations(self):
        return [Eq(self.y, self.offset + If(time < self.startTime, 0, self.height))]


class Ramp(SignalSource):
    """Generate a ramp signal (Modelica.Blocks.Sources.Ramp).

    ``offset`` before ``startTime``, then rising linearly by ``height`` over
    ``duration`` seconds, then ``offset + height``.
    """

    modelica_name = "Modelica.Blocks.Sources.Ramp"

    height = Parameter(1.0, description="Height of ramps")
    duration = Parameter(2.0, unit="s", min=0, description="Duration of ramp (= 0.0 gives a Step)")

    def equations(self):
        t0, dt = self.startTime, self.duration
        return [Eq(self.y, self.offset + sp.Piecewise(
            (0, time < t0),
            ((time - t0) * self.height / dt, time < t0 + dt),
            (self.height, True)))]


class _Harmonic(SignalSource):
    """Declarations and output equation shared by Sine and Cosine."""

    amplitude = Parameter(1.0, description="Amplitude of sine wave")
    f = Parameter(1.0, unit="Hz", description="Frequency of sine wave")
    phase = Parameter(0.0, unit="rad", description="Phase of sine wave")
    continuous = Parameter(False, structural=True,
                           description="Make output continuous by starting at offset + amplitude*sin(phase)")

    def _output(self, g):
        wave = g(2 * sp.pi * self.f * (time - self.startTime) + self.phase)
        if self.continuous:
            return Eq(self.y, self.offset + self.amplitude * If(time < self.startTime, g(self.phase), wave))
        return Eq(self.y, self.offset + If(time < self.startTime, 0, self.amplitude * wave))


class Sine(_Harmonic):
    """Generate a sine signal (Modelica.Blocks.Sources.Sine).

    ``y = offset + amplitude*sin(2*pi*f*(time - startTime) + phase)`` from
    ``startTime`` on; before it ``offset``, or with ``continuous`` the value
    ``offset + amplitude*sin(phase)``.
    """

    modelica_name = "Modelica.Blocks.Sources.Sine"

    def equations(self):
        return [self._output(sp.sin)]


class Cosine(_Harmonic):
    """Generate a cosine signal (Modelica.Blocks.Sources.Cosine).

    ``y = offset + amplitude*cos(2*pi*f*(time - startTime) + phase)`` from
    ``startTime`` on; before it ``offset``, or with ``continuous`` the value
    ``offset + amplitude*cos(phase)``.
    """

    modelica_name = "Modelica.Blocks.Sources.Cosine"

    def equations(self):
        return [self._output(sp.cos)]


class ExpSine(SignalSource):
    """Generate an exponentially damped sine signal (Modelica.Blocks.Sources.ExpSine).

    ``y = offset + amplitude*exp(-(time - startTime)*damping)*sin(2*pi*f*(time
    - startTime) + phase)`` from ``startTime`` on, ``offset`` before.
    """

    modelica_name = "Modelica.Blocks.Sources.ExpSine"

    amplitude = Parameter(1.0, description="Amplitude of sine wave")
    f = Parameter(2.0, unit="Hz", description="Frequency of sine wave")
    phase = Parameter(0.0, unit="rad", description="Phase of sine wave")
    damping = Parameter(1.0, unit="1/s", description="Damping coefficient of sine wave")

    def equations(self):
        dt = time - self.startTime
        wave = self.amplitude * sp.exp(-dt * self.damping) * sp.sin(2 * sp.pi * self.f * dt + self.phase)
        return [Eq(self.y, self.offset + If(time < self.startTime, 0, wave))]


# --------------------------------------------------------------------------
# periodic and table sources (hybrid: when-clauses, time events)
# --------------------------------------------------------------------------


class _Periodic(SignalSource):
    """The period counting shared by Pulse, SawTooth and Trapezoid.

    ``count`` is the number of the current period and ``T_start`` its start:
    at initialization ``count = integer((time - startTime)/period)`` and
    ``T_start = startTime + count*period``; at each period boundary
    ``startTime + i*period`` (a time event) ``count`` becomes ``i`` and
    ``T_start`` the event time.

    MSL 4.1 detects the boundary with the relation ``time >= (pre(count) +
    1)*period + startTime``; the engine locates relations of ``time`` with
    discrete variables as state events (to about 1e-10 s), so the boundary
    is written here as ``sample(startTime, period)``, whose ticks are exact
    time events.  ``count = integer((time - startTime)/period + 0.5)`` at a
    tick is ``i``, also at a tick on the start time.
    """

    period = Parameter(1.0, unit="s", min=SMALL, description="Time for one period")
    nperiod = Parameter(-1, structural=True,
                        description="Number of periods (< 0 means infinite number of periods)")
    T_start = Variable(unit="s", discrete=True, description="Start time of current period")  # noqa: N815
    count = Integer(description="Period count")

    def _counting(self):
        periods = (time - self.startTime) / self.period
        first = noEvent(sp.floor(periods))
        return When(initial(), Eq(self.count, first),
                    Eq(self.T_start, self.startTime + first * self.period)) \
            .elsewhen(sample(self.startTime, self.period),
                      Eq(self.count, noEvent(sp.floor(periods + sp.Rational(1, 2)))), Eq(self.T_start, time))

    def _inactive(self):
        """Where the output is ``offset``: before startTime, or after nperiod periods."""
        nperiod = int(self.nperiod)
        if nperiod == 0:
            return sp.true
        if nperiod > 0:
            return sp.Or(time < self.startTime, self.count >= nperiod)
        return time < self.startTime


class Pulse(_Periodic):
    """Generate a pulse signal of type Real (Modelica.Blocks.Sources.Pulse).

    ``offset + amplitude`` during the first ``width`` percent of every period
    from ``startTime`` on, ``offset`` otherwise (and after ``nperiod``
    periods, if ``nperiod >= 0``).
    """

    modelica_name = "Modelica.Blocks.Sources.Pulse"

    amplitude = Parameter(1.0, description="Amplitude of pulse")
    width = Parameter(50.0, min=SMALL, max=100, description="Width of pulse in % of period")

    def equations(self):
        T_width = self.period * self.width / 100
        return [self._counting(),
                Eq(self.y, sp.Piecewise((self.offset, self._inactive()),
                                        (self.offset + self.amplitude, time < self.T_start + T_width),
                                        (self.offset, True)))]


class SawTooth(_Periodic):
    """Generate a saw tooth signal (Modelica.Blocks.Sources.SawTooth).

    ``offset + amplitude*(time - T_start)/period`` in every period from
    ``startTime`` on, ``offset`` before (and after ``nperiod`` periods).
    """

    modelica_name = "Modelica.Blocks.Sources.SawTooth"

    amplitude = Parameter(1.0, description="Amplitude of saw tooth")

    def equations(self):
        return [self._counting(),
                Eq(self.y, sp.Piecewise((self.offset, self._inactive()),
                                        (self.offset + self.amplitude * (time - self.T_start) / self.period,
                                         True)))]


class Trapezoid(_Periodic):
    """Generate trapezoidal signal of type Real (Modelica.Blocks.Sources.Trapezoid).

    In every period: a linear rise by ``amplitude`` over ``rising`` seconds,
    ``width`` seconds at ``offset + amplitude``, a linear fall over
    ``falling`` seconds, then ``offset`` for the rest of the period.
    """

    modelica_name = "Modelica.Blocks.Sources.Trapezoid"

    amplitude = Parameter(1.0, description="Amplitude of trapezoid")
    rising = Parameter(0.0, unit="s", min=0, description="Rising duration of trapezoid")
    width = Parameter(0.5, unit="s", min=0, description="Width duration of trapezoid")
    falling = Parameter(0.0, unit="s", min=0, description="Falling duration of trapezoid")

    def equations(self):
        T_rising = self.rising
        T_width = T_rising + self.width
        T_falling = T_width + self.falling
        tau = time - self.T_start
        # the branches dividing by rising/falling are selected only where those are > 0
        return [self._counting(),
                Eq(self.y, sp.Piecewise(
                    (self.offset, self._inactive()),
                    (self.offset + self.amplitude * tau / self.rising, tau < T_rising),
                    (self.offset + self.amplitude, tau < T_width),
                    (self.offset + self.amplitude * (self.T_start + T_falling - time) / self.falling,
                     tau < T_falling),
                    (self.offset, True), evaluate=False))]



def _rows(table: Any, where: str, columns: int | None = None) -> list[list[float]]:
    """A structural table as rows of floats, the first column non-decreasing."""
    try:
        rows = [[float(v) for v in row] for row in table]
    except (TypeError, ValueError) as exc:
        raise ParameterError(f"{where}.table must be a matrix of numbers, not {table!r}",
                             hint="e.g. table=[[0, 0], [1, 2], [3, 2]] (time in the first column)") from exc
    if not rows:
        raise ParameterError(f"{where}.table is empty", hint="give at least one row [time, value, ...]")
    widths = {len(r) for r in rows}
    if len(widths) != 1 or min(widths) < 2:
        raise ParameterError(f"{where}.table must have rows of equal length >= 2 (time, values)",
                             hint="e.g. table=[[0, 0], [1, 2]]")
    if not all(math.isfinite(v) for r in rows for v in r):
        raise ParameterError(f"{where}.table has non-finite entries", hint="give finite numbers")
    for i in range(1, len(rows)):
        if rows[i][0] < rows[i - 1][0]:
            raise ParameterError(
                f"{where}.table: the time column must not decrease, but row {i + 1} ({rows[i][0]:g}) "
                f"follows row {i} ({rows[i - 1][0]:g})",
                hint="sort the rows by time; a repeated time gives a jump")
    return rows


def _table_value(times: Sequence[float], values: Sequence[float], scaled: Any, at: Callable[[float], Any],
                 *, constant: bool, extrapolation: Extrapolation, nearly: Callable[[float, float], bool]):
    """The table's value at scaled table time ``scaled`` as a Piecewise.

    ``at(t)`` is the relation "the scaled time is before table time t" (a
    time event).  Between rows linear (or constant) interpolation; at a
    repeated time the later row holds (right-continuous); outside the rows
    the extrapolation given.
    """
    n = len(times)
    if n == 1:
        return sp.Float(values[0])

    def line(i: int, j: int):
        slope = (values[j] - values[i]) / (times[j] - times[i])
        return values[i] + slope * (scaled - times[i])

    def outside(first: int, second: int, left: bool):
        if extrapolation is Extrapolation.HoldLastPoint:
            return sp.Float(values[first] if left else values[second])
        # LastTwoPoints (also the values NoExtrapolation reports with its assertion)
        if nearly(times[first], times[second]):
            return sp.Float(values[first] if left else values[second])
        return line(first, second)

    pieces = [(outside(0, 1, True), at(times[0]))]
    for j in range(n - 1):
        if nearly(times[j], times[j + 1]):
            continue  # a jump: the later row holds from this time on
        pieces.append((sp.Float(values[j]) if constant else line(j, j + 1), at(times[j + 1])))
    pieces.append((outside(n - 2, n - 1, False), sp.true))
    return sp.Piecewise(*pieces, evaluate=False)


class TimeTable(DerivedDefaults, SignalSource):
    """Generate a (possibly discontinuous) signal by linear interpolation in a table (Modelica.Blocks.Sources.TimeTable).

    ``table`` rows are ``[time, value]`` (the first time 0, times not
    decreasing; a repeated time is a jump, the later value holding from that
    time on).  The output is ``offset`` before ``startTime``, then
    ``offset`` plus the table interpolated linearly at
    ``(time - shiftTime)/timeScale``, extrapolated through the last two rows
    after the table.  Every table time is a time event.
    """

    modelica_name = "Modelica.Blocks.Sources.TimeTable"

    table = Parameter(((0.0, 0.0),), structural=True,
                      description="Table matrix (time = first column; e.g., table=[0, 0; 1, 1; 2, 4])")
    timeScale = Parameter(1.0, unit="s", min=EPS, description="Time scale of first table column")  # noqa: N815
    shiftTime = Parameter(None, unit="s", description="Shift time of first table column (default startTime)")  # noqa: N815

    derived_defaults = {"shiftTime": lambda block: block.startTime}

    def equations(self):
        where = self.path or type(self).__name__
        rows = _rows(self.table, where)
        if len(rows[0]) != 2:
            raise ParameterError(f"{where}.table must have 2 columns (time, value), not {len(rows[0])}",
                                 hint="use CombiTimeTable for several columns")
        if len(rows) > 1 and rows[0][0] != 0:
            raise ParameterError(f"{where}.table: the first time must be 0, not {rows[0][0]:g}",
                                 hint="shift the table with shiftTime instead")
        times = [r[0] for r in rows]
        scaled = (time - self.shiftTime) / self.timeScale
        value = _table_value(times, [r[1] for r in rows], scaled,
                             lambda t: time < self.shiftTime + t * self.timeScale,
                             constant=False, extrapolation=Extrapolation.LastTwoPoints,
                             nearly=lambda a, b: b - a <= 100 * EPS * abs(b))
        return [Eq(self.y, self.offset + sp.Piecewise((0, time < self.startTime), (value, True),
                                                      evaluate=False))]


class CombiTimeTable(DerivedDefaults, TableData, VectorBlock):
    """Table look-up with respect to time and various interpolation and extrapolation methods (data from matrix/file) (Modelica.Blocks.Sources.CombiTimeTable).

    ``table`` rows are ``[time, value_2, value_3, ...]`` (times not
    decreasing; a repeated time is a jump, the later row holding from that
    time on), from the model or from a file (``tableOnFile``, ``tableName``,
    ``fileName``, ``delimiter``, ``nHeaderLines``).  Output ``y[i]`` is
    ``offset[i]`` plus column ``columns[i]`` at ``time/timeScale`` shifted
    by ``shiftTime`` (``offset`` alone before ``startTime``), with every
    ``smoothness`` and ``extrapolation`` of Modelica.Blocks.Types
    (:mod:`acausal.interpolation`).

    As in the MSL, a when-clause holds the next time event,
    ``when {time >= pre(nextTimeEvent), initial()} then nextTimeEventScaled
    = next event after time/timeScale``, and the outputs interpolate within
    the event interval that ends there: a time event at each table time
    (``timeEvents = Always``, LinearSegments), at the jumps only
    (``AtDiscontinuities``) or none (``NoTimeEvents``; the smooth
    interpolations always), plus the table's start and end, the periods of
    ``Periodic`` and ``startTime``.  One relation whatever the number of
    rows, and a look-up of O(log n).  The outputs' time derivatives are the
    table's own (a Der block after it, or index reduction, differentiates
    the interpolation).
    """

    modelica_name = "Modelica.Blocks.Sources.CombiTimeTable"

    table = Parameter(((0.0, 0.0),), structural=True,
                      description="Table matrix (time = first column; e.g., table=[0, 0; 1, 1; 2, 4])")
    columns = Parameter(None, structural=True,
                        description="Columns of table to be interpolated (default 2, ..., number of columns)")
    smoothness = Parameter(Smoothness.LinearSegments, structural=True,
                           description="Smoothness of table interpolation")
    extrapolation = Parameter(Extrapolation.LastTwoPoints, structural=True,
                              description="Extrapolation of data outside the definition range")
    timeScale = Parameter(1.0, unit="s", min=EPS, description="Time scale of first table column")  # noqa: N815
    offset = Parameter((0.0,), structural=True, description="Offsets of output signals")
    startTime = Parameter(0.0, unit="s", finite=False,  # noqa: N815
                          description="Output = offset for time < startTime")
    shiftTime = Parameter(None, unit="s", description="Shift time of first table column (default startTime)")  # noqa: N815
    timeEvents = Parameter(TimeEvents.Always, structural=True,  # noqa: N815
                           description="Time event handling of table interpolation")
    verboseExtrapolation = Parameter(False, structural=True,  # noqa: N815
                                     description="= true, if warning messages are to be printed if time is "
                                                 "outside the table definition range")
    nextTimeEvent = Variable(start=0.0, fixed=True, unit="s", discrete=True,  # noqa: N815
                             description="Next time event instant (protected)")
    nextTimeEventScaled = Variable(start=0.0, fixed=True, discrete=True,  # noqa: N815
                                   description="Next scaled time event instant (protected)")

    derived_defaults = {"shiftTime": lambda block: block.startTime}

    @classmethod
    def arrays(cls, value):
        offset = value("offset")
        n_offset = len(offset) if isinstance(offset, (list, tuple)) else 1
        matrix = cls.read_matrix(value, cls.__name__)
        nout = max(len(default_columns(matrix, value("columns"))), n_offset)
        return {"y": (nout, lambda i: RealOutput(description="Connector of Real output signals"))}

    def numeric_table(self) -> NumericTimeTable:
        where = self.path or type(self).__name__
        matrix = self.matrix()
        columns = default_columns(matrix, self.columns)
        y = self.vector("y")
        if len(columns) == 1:
            columns = columns * len(y)
        return NumericTimeTable(matrix, columns, Smoothness(self.smoothness), Extrapolation(self.extrapolation),
                                TimeEvents(self.timeEvents), name=where)

    def equations(self):
        where = self.path or type(self).__name__
        table = self.numeric_table()
        y = self.vector("y")
        offset = list(self.offset) if isinstance(self.offset, (list, tuple)) else [self.offset]
        if len(offset) == 1:
            offset = offset * len(y)
        if len(offset) != len(y) or table.n_outputs != len(y):
            raise ParameterError(f"{where}: columns ({table.n_outputs}) and offset ({len(offset)}) have different "
                                 f"sizes", hint="give one offset per column, or a single offset")
        scaled = time / self.timeScale
        start, shift = self.startTime / self.timeScale, self.shiftTime / self.timeScale
        equations = []
        for i, (yi, off) in enumerate(zip(y, offset)):
            value, following = time_table_functions(table, i, f"{where}.table")
            equations.append(Eq(yi, off + value(scaled, self.nextTimeEventScaled, start, shift)))
        # the next event after the one being processed: from the instant that fired (time/timeScale
        # may round below it), from time itself at initialization
        after = If(is_initial(), scaled, sp.Max(scaled, pre(self.nextTimeEventScaled)))
        # no further event: Modelica.Constants.inf (1e60), a finite number, as the MSL holds it
        equations.append(When([time >= pre(self.nextTimeEvent), initial()],
                              Eq(self.nextTimeEventScaled, sp.Min(following(after, start, shift), MODELICA_INF)),
                              Eq(self.nextTimeEvent, self.nextTimeEventScaled * self.timeScale)))
        if len(table.data) > 1:
            inside = sp.Or(time < self.startTime,
                           sp.And(time >= self.shiftTime + table.t_min * self.timeScale,
                                  time <= self.shiftTime + table.t_max * self.timeScale))
            equations += range_asserts(where, Extrapolation(self.extrapolation), bool(self.verboseExtrapolation),
                                       inside, "the time")
        return equations


class _StepTable(Component):
    """What BooleanTable and IntegerTable share: MSL 4.1 builds each from a CombiTimeTable
    with constant segments (``combiTimeTable``) and a conversion of its output."""

    extrapolation = Parameter(Extrapolation.HoldLastPoint, structural=True,
                              description="Extrapolation of data outside the definition range")
    startTime = Parameter(-math.inf, unit="s", finite=False,  # noqa: N815
                          description="Output = 0 (false) for time < startTime")
    shiftTime = Parameter(0.0, unit="s", description="Shift time of table")  # noqa: N815

    def check_extrapolation(self) -> None:
        if Extrapolation(self.extrapolation) is Extrapolation.LastTwoPoints:
            where = self.path or type(self).__name__
            raise ParameterError(f"{where}: unsuitable extrapolation setting LastTwoPoints",
                                 hint="use HoldLastPoint (the default), Periodic or NoExtrapolation")

    def build_steps(self, rows: list, conversion: Component, name: str) -> None:
        """``combiTimeTable`` of ``rows`` (constant segments) feeding ``conversion`` (as ``name``),
        whose output is this block's ``y``."""
        self.combiTimeTable = CombiTimeTable(table=rows, smoothness=Smoothness.ConstantSegments, columns=[2],
                                             extrapolation=self.extrapolation, startTime=self.startTime,
                                             shiftTime=self.shiftTime)
        setattr(self, name, conversion)
        self.connect(getattr(self.combiTimeTable, "y[1]"), conversion.u)
        self.connect(conversion.y, self.y)


class IntegerTable(_StepTable):
    """Generate an Integer output signal based on a table matrix with [time, yi] values
    (Modelica.Blocks.Sources.IntegerTable).

    As MSL 4.1 builds it: a CombiTimeTable with constant segments (times
    strictly increasing, values Integers) and a RealToInteger.  The output
    holds ``table[i, 2]`` from ``table[i, 1]`` on; ``extrapolation``
    (HoldLastPoint by default; LastTwoPoints is refused, as in the MSL),
    ``startTime`` and ``shiftTime`` act as in the CombiTimeTable.
    """

    modelica_name = "Modelica.Blocks.Sources.IntegerTable"

    table = Parameter(((0.0, 0.0),), structural=True,
                      description="Table matrix (time = first column, integer output = second column)")
    y = IntegerOutput(description="Connector of Integer output signal")

    def build(self) -> None:
        where = self.path or type(self).__name__
        self.check_extrapolation()
        rows = _rows(self.table, where, 2)
        if len(rows[0]) != 2:
            raise ParameterError(f"{where}.table must have 2 columns (time, value), not {len(rows[0])}")
        for i in range(1, len(rows)):
            if not rows[i][0] > rows[i - 1][0]:
                raise ParameterError(
                    f"{where}.table: time values of table not strictly increasing: table[{i},1] = "
                    f"{rows[i - 1][0]:g}, table[{i + 1},1] = {rows[i][0]:g}",
                    hint="list each switching instant once, in increasing order")
        for i, (_t, v) in enumerate(rows, start=1):
            if v != int(v):
                raise ParameterError(f"{where}.table: table value is not an Integer: table[{i},2] = {v:g}")
        self.build_steps(rows, RealToInteger(), "realToInteger")
