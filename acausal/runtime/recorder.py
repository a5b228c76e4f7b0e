"""The recorder: output grid, result rows, and the columns of the result.

During a run the loop hands the recorder *rows*: a time, the system in force,
the state vector and the discrete values.  Rows are cheap to keep: the
unknowns of a row are computed only when the result is assembled, stretch by
stretch (rows of one system and one set of discrete values, between events),
column by column.  As in the MSL reference files an event gives two rows at
its instant (left and right limit), and a grid point at an event time is
represented by those two rows.
"""

from __future__ import annotations

import math
from typing import Callable

import numpy as np

from ..compiler.translate import ModeSystem, Translation
from ..errors import SimulationError

__all__ = ["Recorder", "output_grid"]


def output_grid(t0: float, t1: float, interval: float) -> np.ndarray:
    """``t0, t0 + interval, ...`` up to ``t1``, with ``t1`` itself as the last point."""
    grid = t0 + interval * np.arange(int(math.floor((t1 - t0) / interval * (1 + 1e-12))) + 1)
    if grid[-1] < t1 - 1e-12 * max(1.0, abs(t1)):
        grid = np.append(grid, t1)
    return grid


class Recorder:
    """Collects the rows of a run on its output grid.

    Attributes
    ----------
    grid : ndarray
        The output points.
    interval : float
    rows : list of (t, ModeSystem, x, discrete)
    """

    def __init__(self, t0: float, t1: float, interval: float) -> None:
        self.grid = output_grid(t0, t1, interval)
        self.interval = interval
        self.rows: list[tuple] = []
        self.next_grid = 0

    @property
    def last_time(self) -> float | None:
        return self.rows[-1][0] if self.rows else None

    @property
    def grid_left(self) -> bool:
        """Whether output points are still to be written."""
        return self.next_grid < len(self.grid)

    def add(self, t: float, system: ModeSystem, x, discrete: dict) -> None:
        """A row at ``t`` (an event's limit, a segment's end, the start)."""
        self.rows.append((float(t), system, np.array(x, dtype=float), self._snapshot(discrete)))

    def skip_grid_through(self, t: float, round_off: bool = True) -> None:
        """Output points up to ``t`` (with ``round_off``, a relative 1e-14 above it too)
        are represented by the rows at ``t``."""
        limit = t * (1 + 1e-14) if round_off else t
        while self.next_grid < len(self.grid) and self.grid[self.next_grid] <= limit:
            self.next_grid += 1

    def emit_grid_until(self, t_end: float, inclusive: bool, system: ModeSystem, x_at: Callable,
                        discrete: dict, check: Callable[[], None] | None = None) -> None:
        """Rows at the output points before ``t_end`` (or up to it), states from ``x_at(t)``.

        ``check`` (optional) is called before each row: a budget that can stop the run.
        """
        grid = self.grid
        while self.next_grid < len(grid) and (grid[self.next_grid] < t_end or
                                              (inclusive and grid[self.next_grid] <= t_end)):
            if check is not None:
                check()
            tg = grid[self.next_grid]
            if not (self.rows and self.rows[-1][0] == tg):
                self.add(tg, system, x_at(tg), discrete)
            self.next_grid += 1

    def _snapshot(self, discrete: dict) -> dict:
        """A copy of the discrete values for a row, shared by the rows that have
        the same values (a large model has thousands of them)."""
        last = self.rows[-1][3] if self.rows else None
        if last is not None and last == discrete:
            return last
        return dict(discrete)

    # -- the result's columns ----------------------------------------------------------

    def columns(self, translation: Translation) -> tuple[np.ndarray, dict[str, np.ndarray], tuple | None]:
        """The result's time and columns, and the first row whose values are not finite.

        Columns: every variable by name (only the demanded ones with an
        output demand), derivatives, discrete values and parameters.  The
        third item is ``(row, names, reason)`` for the first row where a value
        of the system in force could not be computed or is not finite (None
        if there is none).
        """
        flat = translation.flat
        continuous = [v.name for v in flat.variables if not v.is_discrete]
        discrete_names = list(translation.partitioned.discrete_variables)
        derivative_names = []
        for system in translation.systems.values():
            for d in system.structure.derivatives:
                if d not in derivative_names:
                    derivative_names.append(d)
        names = continuous + derivative_names + discrete_names
        if translation.demand is not None:
            names = [n for n in names if n in translation.demand] + discrete_names
        index = {n: k for k, n in enumerate(names)}
        rows = self.rows
        data = np.full((len(rows), len(names)), np.nan)
        times = np.array([row[0] for row in rows], dtype=float)
        # Rows come in stretches with one system and one set of discrete
        # values (between events): each stretch is filled column by column.
        start, plans, bad = 0, {}, None
        names_of = {ident: name for name, ident in translation.cache.identifiers.items()}
        while start < len(rows):
            _, system, _, discrete = rows[start]
            stop = start + 1
            while stop < len(rows) and rows[stop][1] is system and rows[stop][3] is discrete:
                stop += 1
            if system.key not in plans:
                plans[system.key] = fill_plan(system, index)
            found = _fill(data[start:stop], index, rows[start:stop], system, discrete, plans[system.key],
                          names_of)
            if found is not None and bad is None:
                bad = (start + found[0], found[1], found[2])
            start = stop
        columns = {n: data[:, k] for n, k in index.items()}
        for p in flat.parameters:
            if translation.demand is None or p.name in translation.demand:
                columns[p.name] = np.full(len(times), p.value)
        return times, columns, bad


def _fill(block: np.ndarray, index: dict[str, int], rows, system: ModeSystem, discrete: dict,
          plan, names_of: dict[str, str]) -> tuple[int, list[str], str] | None:
    """Write the values of ``rows`` (all of ``system`` and ``discrete``) into ``block``.

    Returns ``(row, names, reason)`` for the first row whose values could not
    all be computed or are not finite, else None.
    """
    targets, sources, aliases = plan
    n_states = len(system.states)
    values = np.full((len(rows), n_states + len(system.unknowns)), np.nan)
    failed = None
    for r, (t, _, x, _) in enumerate(rows):
        values[r, :n_states] = x
        try:
            values[r, n_states:] = system.outputs(t, x)
        except (SimulationError, ArithmeticError, ValueError) as exc:
            # the states are still known, and so are their aliases and the
            # constants; the unknowns of this row stay NaN
            if failed is None:
                name, line = _failing_line(exc, system, names_of)
                failed = (r, [name], f"{type(exc).__name__}: {exc}" + (f", in: {line}" if line else ""))
    finite = np.isfinite(values)
    if not finite.all():
        r = int(np.argmax(~finite.all(axis=1)))
        if failed is None or r < failed[0]:
            own = list(system.states) + list(system.unknowns)
            names = [own[k] for k in np.flatnonzero(~finite[r])]
            failed = (r, names, ", ".join(f"{n} = {values[r, own.index(n)]}" for n in names[:4]))
    block[:, targets] = values[:, sources]
    for column, coeff, source in aliases:
        block[:, column] = coeff if source < 0 else coeff * values[:, source]
    for name, value in discrete.items():
        block[:, index[name]] = float(value)
    return failed


def _failing_line(exc: BaseException, system: ModeSystem, names_of: dict[str, str]) -> tuple[str, str]:
    """The variable whose line of generated code raised ``exc``, and that line."""
    frame = exc.__traceback__
    lineno = None
    while frame is not None:
        if frame.tb_frame.f_code.co_filename.startswith("<acausal"):
            lineno = frame.tb_lineno
        frame = frame.tb_next
    if lineno is None:
        return "a value", ""
    lines = system.code.source.splitlines()
    line = lines[lineno - 1].strip() if 0 < lineno <= len(lines) else ""
    target = line.split("=", 1)[0].strip() if "=" in line else ""
    return names_of.get(target, target or "a value"), line


def fill_plan(system: ModeSystem, index: dict[str, int]):
    """Where a system's values go in the result: ``(targets, sources, aliases)``.

    The system's values are its states then its unknowns; ``targets`` are
    their result columns and ``sources`` their positions (for those the
    result keeps); ``aliases`` are ``(column, coefficient, position or -1)``
    with -1 for a constant.
    """
    own = list(system.states) + list(system.unknowns)
    position = {n: k for k, n in enumerate(own)}
    pairs = [(index[n], k) for k, n in enumerate(own) if n in index]
    aliases = []
    for name, coeff, source in system.alias_plan:
        column = index.get(name)
        if column is None:
            continue
        if source is None:
            aliases.append((column, coeff, -1))
        elif source in position:  # with an output demand, some are not computed
            aliases.append((column, coeff, position[source]))
    return (np.array([c for c, _ in pairs], dtype=int), np.array([k for _, k in pairs], dtype=int),
            aliases)
