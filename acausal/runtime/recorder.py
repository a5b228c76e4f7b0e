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

import itertools
import math
import operator
from typing import Callable

import numpy as np

from ..errors import SimulationError
from .contract import CompiledModel, CompiledSystem

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
    rows : list of (t, CompiledSystem, x, discrete)
        The rows (made from the chunks the recorder keeps; assign to replace them).
    """

    def __init__(self, t0: float, t1: float, interval: float) -> None:
        self.grid = output_grid(t0, t1, interval)
        self.interval = interval
        self.next_grid = 0
        # The rows are kept as chunks ``(times, system, states, discrete)``, the states
        # of a chunk as the rows of one array: a step writes its output points as one
        # chunk, and the columns are assembled from the chunks (a row at a time, each
        # its own tuple and state view, cost more than the values' own computation).
        self._chunks: list[tuple[np.ndarray, CompiledSystem, np.ndarray, dict]] = []
        self._count = 0
        self._last: tuple[float, dict] | None = None  # the last row's time and discrete values

    @property
    def rows(self) -> list[tuple]:
        """The rows ``(t, system, x, discrete)`` (a new list: assign to replace them)."""
        return [(t, system, x, discrete) for times, system, states, discrete in self._chunks
                for t, x in zip(times.tolist(), states)]

    @rows.setter
    def rows(self, rows) -> None:
        self._chunks, self._count, self._last = [], 0, None
        for t, system, x, discrete in rows:
            self._append(np.array([float(t)]), system, np.array(x, dtype=float).reshape(1, -1), discrete)

    def _append(self, times: np.ndarray, system: CompiledSystem, states: np.ndarray, discrete: dict) -> None:
        """A chunk of rows: increasing ``times``, ``states`` (owned by the recorder) as rows."""
        self._chunks.append((times, system, states, discrete))
        self._count += len(times)
        self._last = (float(times[-1]), discrete)

    @property
    def row_count(self) -> int:
        """How many rows there are."""
        return self._count

    @property
    def last_time(self) -> float | None:
        return self._last[0] if self._last is not None else None

    @property
    def grid_left(self) -> bool:
        """Whether output points are still to be written."""
        return self.next_grid < len(self.grid)

    def add(self, t: float, system: CompiledSystem, x, discrete: dict) -> None:
        """A row at ``t`` (an event's limit, a segment's end, the start)."""
        x = x.copy() if type(x) is np.ndarray and x.dtype == np.float64 else np.array(x, dtype=float)
        t = float(t)
        self._append(np.array([t]), system, x.reshape(1, -1), self._snapshot(discrete))

    def skip_grid_through(self, t: float, round_off: bool = True) -> None:
        """Output points up to ``t`` (with ``round_off``, a relative 1e-14 above it too)
        are represented by the rows at ``t``."""
        limit = t * (1 + 1e-14) if round_off else t
        while self.next_grid < len(self.grid) and self.grid[self.next_grid] <= limit:
            self.next_grid += 1

    def emit_grid_until(self, t_end: float, inclusive: bool, system: CompiledSystem, x_at: Callable,
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
            if not (self._last is not None and self._last[0] == tg):
                self.add(tg, system, x_at(tg), discrete)
            self.next_grid += 1

    def pending(self, t_end: float, inclusive: bool) -> np.ndarray:
        """The output points :meth:`emit_grid_until` would write up to ``t_end`` (none written yet)."""
        if not t_end == t_end:  # NaN: no point is before it
            return self.grid[:0]
        stop = int(np.searchsorted(self.grid, t_end, side="right" if inclusive else "left"))
        return self.grid[self.next_grid:max(self.next_grid, stop)]

    def emit_rows(self, times: np.ndarray, states: np.ndarray, system: CompiledSystem, discrete: dict,
                  check: Callable[[], None] | None = None) -> None:
        """Rows at the next output points ``times`` (from :meth:`pending`), the states as rows.

        The same rows as :meth:`emit_grid_until` with ``x_at`` giving ``states``
        (a point at the time of the last row is represented by it).  ``check`` is
        called once, before the rows.  The rows are appended as a block; where
        :meth:`add` is overridden (a subclass, a test), each row goes through it.
        """
        times = np.asarray(times, dtype=float)
        if check is not None:
            check()
        if type(self).add is not _ADD:
            add = self.add
            for tg, x in zip(times.tolist(), states):
                if not (self._last is not None and self._last[0] == tg):
                    add(tg, system, x, discrete)
                self.next_grid += 1
            return
        first = 1 if (len(times) and self._last is not None and self._last[0] == times[0]) else 0
        if len(times) > first:
            # the points are increasing: only the first can fall on the last row's time
            snapshot = self._snapshot(discrete)
            block = np.array(states[first:], dtype=float)
            self._append(np.array(times[first:], dtype=float), system, block.reshape(len(block), -1), snapshot)
        self.next_grid += len(times)

    def _snapshot(self, discrete: dict) -> dict:
        """A copy of the discrete values for a row, shared by the rows that have
        the same values (a large model has thousands of them)."""
        last = self._last[1] if self._last is not None else None
        if last is not None and last == discrete:
            return last
        return dict(discrete)

    # -- the result's columns ----------------------------------------------------------

    def columns(self, translation: CompiledModel) -> tuple[np.ndarray, dict[str, np.ndarray], tuple | None]:
        """The result's time and columns, and the first row whose values are not finite.

        Columns: every variable by name (only the demanded ones with an
        output demand), derivatives, discrete values and parameters.  The
        third item is ``(row, names, reason)`` for the first row where a value
        of the system in force could not be computed or is not finite (None
        if there is none).
        """
        model = translation.data
        names, index, parameters = _column_names(translation)
        n = self._count
        chunks = self._chunks
        times = np.concatenate([c[0] for c in chunks]) if chunks else np.empty(0)
        # Rows come in stretches with one system and one set of discrete
        # values (between events): each stretch is filled column by column.
        stretches = _stretches(chunks)
        _prepare_outputs(stretches)
        # one row per column (each column of the result is then one contiguous row of it)
        data = np.full((len(names), n), np.nan)
        plans, bad, part_plans = {}, None, {}
        if _fill_by_part(data, times, stretches, index, part_plans):
            # every value computed and finite, part by part: the discrete values stretch by stretch
            for start, stop, _, _, discrete in stretches:
                _fill_discrete(data[:, start:stop], index, discrete)
            stretches = []
        for start, stop, system, states, discrete in stretches:
            if system.key not in plans:
                plans[system.key] = _kept_plan(translation, system, names, index, part_plans)
            found = _fill(data[:, start:stop], index, times[start:stop], states, system, discrete,
                          plans[system.key], model.identifiers)
            if found is not None and bad is None:
                bad = (start + found[0], found[1], found[2])
        columns = {n: data[k] for n, k in index.items()}
        # the parameters' columns (their values read at each run): those of float values
        # in one array, a row each as ``data``; others as numpy makes them of their values
        floats = [p.value for p in parameters if type(p.value) is float]
        constant = iter(())
        if floats:
            constant = np.empty((len(floats), len(times)))
            constant[:] = np.array(floats, dtype=float)[:, None]
            constant = iter(constant)
        for p in parameters:  # (in the model's order)
            columns[p.name] = next(constant) if type(p.value) is float else np.full(len(times), p.value)
        return times, columns, bad


def _column_names(translation: CompiledModel) -> tuple[list[str], dict[str, int], list]:
    """``(names, index, parameters)``: the result's columns of variables (continuous,
    derivatives, discrete; only the demanded ones with an output demand), their rows,
    and the parameters that have columns.

    They depend only on the translation's model, its output demand and the systems it
    has entered (the derivatives are the systems'), so they are kept with the
    translation while those are the same objects (a warm run enters no system).
    """
    model = translation.data
    kept = getattr(translation, "extras", None)
    # (one snapshot of the systems for the key and the names: the threads of a sweep share
    # a translation, and another may enter a new discrete state meanwhile)
    systems = tuple(translation.systems.values())
    key = (model, translation.demand, systems)  # (kept: their addresses stay theirs)
    if kept is not None:
        found = kept.get("column_names")
        if found is not None and len(found[0][2]) == len(systems) and all(
                map(operator.is_, (*found[0][:2], *found[0][2]), (*key[:2], *systems))):
            return found[1]
    continuous = [v.name for v in model.variables if not v.is_discrete]
    discrete_names = list(model.discrete_variables)
    derivative_names: dict[str, None] = {}  # (in order of first appearance)
    for system in systems:
        derivative_names.update(dict.fromkeys(system.derivative_names))
    names = continuous + list(derivative_names) + discrete_names
    if translation.demand is not None:
        names = [n for n in names if n in translation.demand] + discrete_names
    index = {n: k for k, n in enumerate(names)}
    parameters = [p for p in model.parameters if translation.demand is None or p.name in translation.demand]
    found = (names, index, parameters)
    if kept is not None:
        kept["column_names"] = (key, found)
    return found


#: :meth:`Recorder.add` as defined here (an override makes :meth:`Recorder.emit_rows` call it per row)
_ADD = Recorder.add


def _kept_plan(translation: CompiledModel, system: CompiledSystem, names: list[str], index: dict[str, int],
               memo: dict):
    """:func:`fill_plan` of ``system`` for the columns ``names`` (``index``), kept with the
    translation for its next run whose columns are the same (a warm run enters the
    systems of the runs before it)."""
    kept = getattr(translation, "extras", None)
    if kept is None:
        return fill_plan(system, index, memo)
    plans = kept.setdefault("fill_plans", {})
    found = plans.get(system.key)
    if found is None or found[0] is not system or found[1] != names:
        found = plans[system.key] = (system, list(names), fill_plan(system, index, memo))
    return found[2]


def _stretches(chunks) -> list[tuple[int, int, CompiledSystem, np.ndarray, dict]]:
    """The rows of ``chunks`` in stretches of one system and one set of discrete values
    (the same objects): ``(start, stop, system, states, discrete)``, the states as rows
    (those of one system have one length)."""
    out = []
    start = 0
    run: list = []
    for chunk in chunks:
        if run and not (chunk[1] is run[0][1] and chunk[3] is run[0][3]):
            stop = start + sum(len(c[0]) for c in run)
            out.append((start, stop, run[0][1], _joined(run), run[0][3]))
            start, run = stop, []
        run.append(chunk)
    if run:
        out.append((start, start + sum(len(c[0]) for c in run), run[0][1], _joined(run), run[0][3]))
    return out


def _joined(run) -> np.ndarray:
    return run[0][2] if len(run) == 1 else np.concatenate([c[2] for c in run])


#: About how many values (states and unknowns times rows) :func:`_fill` computes at
#: once: the working arrays of a stretch of a large model stay some megabytes, not
#: copies of the result (every value is computed element by element, so the blocks
#: change no bit).
_FILL_BLOCK_VALUES = 1 << 20

#: The fewest rows a block of :func:`_fill` has (a numpy call costs about the same for
#: few rows as for many).
_FILL_BLOCK_ROWS = 64


def _prepare_outputs(stretches) -> None:
    """Make the numpy version of each stretch's ``outputs`` before the result's array
    exists (made once per system and kept): for a model of tens of thousands of
    equations, translating the function's text takes memory of the order of the
    result's, which is then not needed at the same time.  Composed systems fill part by
    part (:func:`_fill_by_part`) and are left alone."""
    seen = set()
    for start, stop, system, _states, _discrete in stretches:
        if stop - start > 1 and system.parts is None and system.unknowns and id(system) not in seen:
            seen.add(id(system))
            system.vectorised("outputs")


def _fill(block: np.ndarray, index: dict[str, int], times: np.ndarray, states: np.ndarray,
          system: CompiledSystem, discrete: dict, plan, identifiers: dict[str, str]) -> tuple[int, list[str], str] | None:
    """Write the values of the rows at ``times`` with ``states`` (as rows; all of ``system``
    and ``discrete``) into ``block`` (one row per column of the result, one column per row).

    Returns ``(row, names, reason)`` for the first row whose values could not
    all be computed or are not finite, else None.  The rows are computed in blocks
    (:data:`_FILL_BLOCK_VALUES`), so that the working arrays of a large model stay small.
    """
    m = len(times)
    rows = max(_FILL_BLOCK_ROWS, _FILL_BLOCK_VALUES // max(len(system.states) + len(system.unknowns), 1))
    if m <= rows:
        return _fill_rows(block, index, times, states, system, discrete, plan, identifiers)
    failed = None
    for a in range(0, m, rows):
        b = min(a + rows, m)
        found = _fill_rows(block[:, a:b], index, times[a:b], states[a:b], system, discrete, plan, identifiers)
        if found is not None and failed is None:
            failed = (a + found[0], found[1], found[2])
    return failed


def _fill_rows(block: np.ndarray, index: dict[str, int], times: np.ndarray, states: np.ndarray,
               system: CompiledSystem, discrete: dict, plan,
               identifiers: dict[str, str]) -> tuple[int, list[str], str] | None:
    """:func:`_fill` for one block of rows."""
    targets, sources, aliases = plan
    n_states = len(system.states)
    m = len(times)
    # (a row per value, a column per row of the result, as ``block``)
    values = np.full((n_states + len(system.unknowns), m), np.nan)
    if n_states:
        values[:n_states] = states.T
    failed = None
    # the unknowns of all rows in one numpy call where the code allows it; rows whose
    # values are not all finite (or all rows, if it raises) are computed row by row
    redo = range(m)
    many = system.vectorised("outputs") if m > 1 and system.unknowns else None
    if many is not None:
        try:
            # a division by zero or an invalid operation (where Python's floats could
            # raise): every row by the scalar function
            with np.errstate(divide="raise", invalid="raise", over="ignore", under="ignore"):
                out = many(times, values[:n_states])
            values[n_states:] = out
            # (as a rule every value is finite: one check, and the rows only otherwise)
            redo = [] if np.isfinite(out).all() else np.flatnonzero(~np.isfinite(out).all(axis=0)).tolist()
        except Exception:  # the scalar function raises where it should, or not at all
            redo = range(m)
    for r in redo:
        t, x = float(times[r]), states[r]
        try:
            values[n_states:, r] = system.outputs(t, x)
        except (SimulationError, ArithmeticError, ValueError) as exc:
            # the states are still known, and so are their aliases and the
            # constants; the unknowns of this row stay NaN
            values[n_states:, r] = np.nan
            if failed is None:
                # (model name -> identifier, turned round only for a failure's message)
                names_of = {ident: name for name, ident in identifiers.items()}
                name, line = _failing_line(exc, system, names_of)
                failed = (r, [name], f"{type(exc).__name__}: {exc}" + (f", in: {line}" if line else ""))
    finite = np.isfinite(values)
    if not finite.all():
        r = int(np.argmax(~finite.all(axis=0)))
        if failed is None or r < failed[0]:
            own = list(system.states) + list(system.unknowns)
            names = [own[k] for k in np.flatnonzero(~finite[:, r])]
            failed = (r, names, ", ".join(f"{n} = {values[own.index(n), r]}" for n in names[:4]))
    block[targets] = values[sources]
    (const_cols, const_vals), (var_cols, var_coeffs, var_srcs) = aliases
    block[const_cols] = const_vals[:, None]
    block[var_cols] = var_coeffs[:, None] * values[var_srcs]
    _fill_discrete(block, index, discrete)
    return failed


def _fill_discrete(block: np.ndarray, index: dict[str, int], discrete: dict) -> None:
    """The discrete values' columns of ``block`` (its rows)."""
    chosen = [(index[name], float(v)) for name, v in discrete.items() if name in index]
    if chosen:  # (with an output demand, only the discrete values demanded have columns)
        columns, values_ = zip(*chosen)
        block[list(columns)] = np.array(values_)[:, None]


def _fill_by_part(data: np.ndarray, times: np.ndarray, stretches, index: dict[str, int], memo: dict) -> bool:
    """The continuous columns of rows of composed systems, filled part by part: one
    evaluation of a part's outputs for all the consecutive rows in which the part is the
    same (a storm of events changes one part at a time, so that is once per event of
    the part, not once per part and event).  The same values as :func:`_fill` stretch
    by stretch; False (and nothing to keep) where that does not apply or a value is not
    finite or cannot be computed: :func:`_fill` then says which.
    """
    if not stretches:
        return False
    systems = [stretch[2] for stretch in stretches]
    parts0 = systems[0].parts
    if parts0 is None or any(s.parts is None or len(s.parts) != len(parts0) for s in systems):
        return False
    if len({stretch[3].shape[1] for stretch in stretches}) != 1:  # state vectors of different lengths
        return False
    states = np.concatenate([stretch[3] for stretch in stretches])
    # where each part's states start in each system's state vector (once per system)
    offsets = {}
    for system in systems:
        if id(system) not in offsets:
            offsets[id(system)] = list(itertools.accumulate((len(q.states) for q in system.parts), initial=0))
    for p in range(len(parts0)):
        run_start, run_part, run_offset = None, None, None
        for (a, b, *_), system in zip(stretches, systems):
            part = system.parts[p]
            offset = offsets[id(system)][p]
            if part is run_part and offset == run_offset:
                continue
            if run_part is not None and not _fill_part(data, run_start, a, run_part, run_offset, states, times,
                                                         index, memo):
                return False
            run_start, run_part, run_offset = a, part, offset
        if not _fill_part(data, run_start, stretches[-1][1], run_part, run_offset, states, times, index, memo):
            return False
    return True


def _fill_part(data, start: int, stop: int, part, offset: int, states, times, index, memo) -> bool:
    """Rows ``start:stop`` of ``part`` (its states at ``offset``); False if a value is not finite."""
    found = memo.get(id(part))
    if found is None or found[0] is not part:
        found = memo[id(part)] = (part, fill_plan(part, index))
    targets, sources, ((const_cols, const_vals), (var_cols, var_coeffs, var_srcs)) = found[1]
    n_states = len(part.states)
    m = stop - start
    values = np.empty((n_states + len(part.unknowns), m))  # (a row per value, as ``data``)
    values[:n_states] = states[start:stop, offset:offset + n_states].T
    if part.unknowns:
        many = part.vectorised("outputs") if m > 1 else None
        try:
            if many is not None:
                with np.errstate(divide="raise", invalid="raise", over="ignore", under="ignore"):
                    values[n_states:] = many(times[start:stop], values[:n_states])
            else:
                for r in range(m):
                    values[n_states:, r] = part.outputs(float(times[start + r]), values[:n_states, r])
        except Exception:
            return False
    if not np.isfinite(values).all():
        return False
    block = data[:, start:stop]
    block[targets] = values[sources]
    block[const_cols] = const_vals[:, None]
    block[var_cols] = var_coeffs[:, None] * values[var_srcs]
    return True


def _failing_line(exc: BaseException, system: CompiledSystem, names_of: dict[str, str]) -> tuple[str, str]:
    """The variable whose line of generated code raised ``exc``, and that line."""
    identifiers = {ident: name for name, ident in names_of.items()}
    return generated_line(exc, system.sources, identifiers)


def generated_line(exc: BaseException, sources, identifiers) -> tuple[str, str]:
    """The variable and the line of generated code where ``exc`` was raised
    (``("a value", "")`` when it was not raised in generated code).

    ``sources``: the generated sources that may hold it (each names its system
    on its first line, as its file name does); ``identifiers``: model name ->
    Python identifier.
    """
    frame, name, lineno = exc.__traceback__, None, None
    while frame is not None:
        filename = frame.tb_frame.f_code.co_filename
        if filename.startswith("<acausal "):
            name, lineno = filename[len("<acausal "):-1], frame.tb_lineno
        frame = frame.tb_next
    if name is None:
        return "a value", ""
    for source in sources:
        if source.split("\n", 1)[0].startswith(f"# generated by acausal for {name}"):
            lines = source.splitlines()
            line = lines[lineno - 1].strip() if 0 < lineno <= len(lines) else ""
            target = line.split("=", 1)[0].strip() if "=" in line else ""
            if not target.isidentifier():  # not an assignment (a raise, a call)
                return "a value", line
            names_of = {ident: model_name for model_name, ident in identifiers.items()}
            return names_of.get(target, target), line
    return "a value", ""


def fill_plan(system: CompiledSystem, index: dict[str, int], memo: dict | None = None):
    """Where a system's values go in the result: ``(targets, sources, aliases)``.

    The system's values are its states then its unknowns; ``targets`` are
    their result columns and ``sources`` their positions (for those the
    result keeps); ``aliases`` are ``(columns, coefficients)`` of the
    constants and ``(columns, coefficients, positions)`` of the others.  A
    composed system's plan is put together from its parts' (kept in ``memo``
    by part, with the part).
    """
    if system.parts is not None:
        return _composed_plan(system.parts, index, {} if memo is None else memo)
    own = list(system.states) + list(system.unknowns)
    position = {n: k for k, n in enumerate(own)}
    pairs = [(index[n], k) for k, n in enumerate(own) if n in index]
    constants, varying = [], []
    for name, coeff, source in system.alias_plan:
        column = index.get(name)
        if column is None:
            continue
        if source is None:
            constants.append((column, coeff))
        elif source in position:  # with an output demand, some are not computed
            varying.append((column, coeff, position[source]))
    return (np.array([c for c, _ in pairs], dtype=int), np.array([k for _, k in pairs], dtype=int),
            ((np.array([c for c, _ in constants], dtype=int), np.array([v for _, v in constants], dtype=float)),
             (np.array([c for c, _, _ in varying], dtype=int), np.array([v for _, v, _ in varying], dtype=float),
              np.array([k for _, _, k in varying], dtype=int))))


def _composed_plan(parts, index: dict[str, int], memo: dict):
    n_states = sum(len(p.states) for p in parts)
    state_at, unknown_at = 0, n_states
    targets, sources, const_cols, const_vals, var_cols, var_coeffs, var_srcs = ([] for _ in range(7))
    for part in parts:
        found = memo.get(id(part))
        if found is None or found[0] is not part:
            found = memo[id(part)] = (part, fill_plan(part, index))
        t, src, ((cc, cv), (vc, vk, vs)) = found[1]
        ns = len(part.states)

        def shift(positions):
            return np.where(positions < ns, positions + state_at, positions - ns + unknown_at)

        targets.append(t)
        sources.append(shift(src))
        const_cols.append(cc)
        const_vals.append(cv)
        var_cols.append(vc)
        var_coeffs.append(vk)
        var_srcs.append(shift(vs))
        state_at += ns
        unknown_at += len(part.unknowns)

    def joined(arrays, dtype):
        return np.concatenate(arrays).astype(dtype, copy=False) if arrays else np.empty(0, dtype)

    return (joined(targets, int), joined(sources, int),
            ((joined(const_cols, int), joined(const_vals, float)),
             (joined(var_cols, int), joined(var_coeffs, float), joined(var_srcs, int))))
