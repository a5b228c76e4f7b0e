"""Independent parts integrated apart: a solver per part, results kept per part.

A model whose parts share no variable, and whose discrete part links no two
of them either (:meth:`~acausal.compiler.translate.Translation.part_models`
offers each part as a compiled model of its own), is run part by part: each
part from the start to the stop time with its own solver, step sizes, events
and event iteration over its own relations and discrete variables — the run
of :mod:`acausal.runtime.simulate` on the part alone, which also keeps every
accepted step with its dense output (:class:`StepHistory`).  An event of one
part then costs what the part costs, whatever the number of parts.

The result is the model's: its time axis is the union of the output grid
and of every part's event instants (each event twice, left and right limit,
as a run with one solver writes them), and its events are the parts' events
in time order (the parts' initial event iterations as one).  It is stored
per part (:class:`PartColumns`): each part keeps its own rows (its own time
axis, computed as the part alone computes them) and its history; a column
on the model's axis is assembled when it is read, the part's values at the
other parts' instants from its solver's dense output there.  So a storm of
N parts keeps some N times the rows of one part, not the product of the
rows and every column of the model.

When a part's run does not succeed (an error, a budget, chattering), the
model is simulated again with one solver for all parts
(:class:`~acausal.runtime.simulate` decides), so that a failure reads, and
keeps its partial result, as it always has; the result's notes say so.
"""

from __future__ import annotations

import time as _time
from collections import OrderedDict
from collections.abc import Iterator, Mapping
from typing import Callable, Sequence

import numpy as np

from ..errors import AcausalError, SimulationInterrupted
from .contract import CompiledModel
from .crossings import states_at
from .recorder import Recorder
from .result import Event, SimulationResult, describe_columns

__all__ = ["PartColumns", "StepHistory", "run_parts", "separate_parts"]


def separate_parts(translation: CompiledModel, atol=None, apart: bool = True) -> tuple[tuple, str]:
    """The parts of ``translation`` to run apart, or ``((), why not)`` (``why`` is empty
    for a model of one part, and when ``apart`` is False:
    :attr:`~acausal.options.EngineOptions.parts_apart`)."""
    if not apart:
        return (), ""
    models, why = translation.part_models()
    if not models:
        return (), "" if why == "the model is one part" else why
    if atol is not None and np.ndim(atol) > 0 and np.size(atol) > 1:
        return (), "atol is given per state of the whole model"
    return models, ""


class StepHistory:
    """The accepted steps of a run: ``(t_old, t_end]`` with the dense output (None: the
    state is constant), the state at ``t_end`` and the system and discrete values in force."""

    def __init__(self) -> None:
        self.starts: list[float] = []
        self.ends: list[float] = []
        self.dense: list = []
        self.y_end: list = []
        #: the index in :attr:`segments` of each step
        self.segment_of: list[int] = []
        #: ``(system, discrete values, the dict they were given as)``
        self.segments: list[tuple] = []

    def add(self, t_old: float, t_end: float, dense, y_end, system, discrete) -> None:
        if not t_end > t_old:
            return
        segments = self.segments
        last = segments[-1] if segments else None
        if last is None or last[0] is not system or not (last[2] is discrete or last[1] == discrete):
            segments.append((system, dict(discrete), discrete))
        self.starts.append(float(t_old))
        self.ends.append(float(t_end))
        self.dense.append(dense)
        self.y_end.append(np.array(y_end, dtype=float))
        self.segment_of.append(len(segments) - 1)

    def rows_at(self, times: np.ndarray) -> list[tuple]:
        """Rows ``(t, system, x, discrete)`` at ``times`` (increasing, within the steps):
        the state from the dense output of the step that holds ``t``, its end value at
        its end (as the run's own rows within a step are)."""
        rows: list[tuple] = []
        if not len(times) or not self.ends:
            return rows
        ends = np.asarray(self.ends)
        steps = np.minimum(np.searchsorted(ends, times, side="left"), len(ends) - 1)
        cuts = np.flatnonzero(np.diff(steps)) + 1
        for a, b in zip([0, *cuts.tolist()], [*cuts.tolist(), len(times)]):
            k = int(steps[a])
            chunk = times[a:b]
            end, y_end, dense = self.ends[k], self.y_end[k], self.dense[k]
            if dense is None:
                states = np.tile(y_end, (len(chunk), 1))
            else:
                states = states_at(dense, chunk)
                near = 1e-12 * max(1.0, abs(end))
                states[np.abs(chunk - end) <= near] = y_end
            system, discrete, _ = self.segments[self.segment_of[k]]
            rows.extend((float(t), system, x, discrete) for t, x in zip(chunk.tolist(), states))
        return rows


class _Part:
    """What is kept of one part's run: its own rows' columns and its history."""

    def __init__(self, model, result: SimulationResult, history: StepHistory) -> None:
        self.model = model
        self.time = np.asarray(result.time, dtype=float)
        self.columns = result.columns
        self.names = tuple(result.columns)
        self.history = history


class PartColumns(Mapping):
    """The columns of a run made part by part, assembled on the model's time axis when read.

    Each part keeps its own time axis and columns; a part's block of columns on the
    model's axis is its own rows where it has rows at an instant, and its dense output
    elsewhere (another part's event).  The last blocks assembled are kept (up to
    :attr:`KEEP_BYTES`).  Copied or pickled, it is a plain dict of every column.
    """

    #: Bytes of assembled blocks kept for the next reads.
    KEEP_BYTES = 256 * 2**20

    def __init__(self, time: np.ndarray, parts: Sequence[_Part], names: Sequence[str],
                 parameters: Mapping[str, float]) -> None:
        self.time = time
        self._parts = tuple(parts)
        self._names = tuple(names)
        self._owner = {n: p for p, part in enumerate(self._parts) for n in part.names}
        self._parameters = dict(parameters)
        distinct, starts = np.unique(time, return_index=True)
        self._distinct = distinct
        # each row's instant (index in distinct) and its occurrence at that instant
        self._instant = np.repeat(np.arange(len(distinct)), np.diff(np.append(starts, len(time))))
        self._occurrence = np.arange(len(time)) - starts[self._instant]
        self._blocks: OrderedDict[int, dict] = OrderedDict()
        self._kept = 0

    def __len__(self) -> int:
        return len(self._names)

    def __iter__(self) -> Iterator[str]:
        return iter(self._names)

    def __contains__(self, name) -> bool:
        return name in self._owner or name in self._parameters

    #: A part with more columns than this is assembled column by column (the first part also
    #: holds what no discrete symbol reaches: every unit's fixed support, in a storm).
    BLOCK_COLUMNS = 256

    def __getitem__(self, name: str) -> np.ndarray:
        p = self._owner.get(name)
        if p is None:
            if name in self._parameters:
                return np.full(len(self.time), self._parameters[name])
            raise KeyError(name)
        if len(self._parts[p].names) > self.BLOCK_COLUMNS:
            return self._kept_block((p, name), lambda: self._assemble(self._parts[p], (name,)))[name]
        return self.block(p)[name]

    def block(self, p: int) -> dict[str, np.ndarray]:
        """Every column of part ``p`` on the model's time axis."""
        return self._kept_block(p, lambda: self._assemble(self._parts[p]))

    def _kept_block(self, key, make: Callable[[], dict]) -> dict[str, np.ndarray]:
        found = self._blocks.get(key)
        if found is not None:
            self._blocks.move_to_end(key)
            return found
        found = make()
        self._blocks[key] = found
        self._kept += 8 * len(self.time) * max(len(found), 1)
        while self._kept > self.KEEP_BYTES and len(self._blocks) > 1:
            _, dropped = self._blocks.popitem(last=False)
            self._kept -= 8 * len(self.time) * max(len(dropped), 1)
        return found

    def _assemble(self, part: _Part, only: Sequence[str] | None = None) -> dict[str, np.ndarray]:
        own, distinct = part.time, self._distinct
        left = np.searchsorted(own, distinct, side="left")
        count = np.searchsorted(own, distinct, side="right") - left
        instant = self._instant
        rows_count = count[instant]
        source = left[instant] + np.minimum(self._occurrence, np.maximum(rows_count - 1, 0))
        missing = np.flatnonzero(count == 0)
        names = part.names if only is None else only
        if not len(missing):
            return {n: np.asarray(part.columns[n])[source] for n in names}
        # the part's values at the instants where it has no row: its dense output
        recorder = Recorder(float(distinct[0]), float(distinct[-1]) + 1.0, 1.0)
        recorder.rows = part.history.rows_at(distinct[missing])
        _, extra, _ = recorder.columns(part.model if only is None else _Asking(part.model, only))
        where = np.full(len(distinct), -1)
        where[missing] = np.arange(len(missing))
        at = where[instant]
        from_extra = at >= 0
        out = {}
        for n in names:
            values = np.asarray(part.columns[n])[np.where(from_extra, 0, source)]
            column = extra.get(n)
            values[from_extra] = column[at[from_extra]] if column is not None else np.nan
            out[n] = values
        return out

    def materialized(self) -> dict[str, np.ndarray]:
        """Every column, as a plain dict."""
        return {n: self[n] for n in self._names}

    def __reduce__(self):  # a copy (pickle, deepcopy) is the plain dict
        return (dict, (self.materialized(),))

    def __repr__(self) -> str:
        return f"<PartColumns: {len(self._names)} columns of {len(self._parts)} parts, {len(self.time)} rows>"


class _Asking:
    """A part's compiled model asked for some of its columns only (what the recorder reads:
    ``data``, ``systems``, ``demand``)."""

    def __init__(self, model, names: Sequence[str]) -> None:
        self.data = model.data
        self.systems = model.systems
        self.demand = frozenset(names)


def _merged_time(times: Sequence[np.ndarray]) -> np.ndarray:
    """The union of the parts' time axes: each instant as often as the part that has it
    most often has it (an event's two rows)."""
    values, counts = [], []
    for t in times:
        u, c = np.unique(t, return_counts=True)
        values.append(u)
        counts.append(c)
    every = np.concatenate(values)
    distinct, inverse = np.unique(every, return_inverse=True)
    most = np.zeros(len(distinct), dtype=int)
    np.maximum.at(most, inverse, np.concatenate(counts))
    return np.repeat(distinct, most)


def _merged_events(per_part: Sequence[Sequence[Event]]) -> tuple[Event, ...]:
    """The parts' events in time order (ties in part order), their initial event iterations as one."""
    initial = [e for events in per_part for e in events if e.kind == "initial"]
    others = sorted(((e.time, p, i, e) for p, events in enumerate(per_part) for i, e in enumerate(events)
                     if e.kind != "initial"), key=lambda item: item[:3])
    out = []
    if initial:
        out.append(Event(initial[0].time, "initial", tuple(r for e in initial for r in e.relations),
                         tuple(c for e in initial for c in e.changes), max(e.iterations for e in initial)))
    out.extend(item[3] for item in others)
    return tuple(out)


def _column_names(translation, parts: Sequence[_Part]) -> list[str]:
    """The columns in the order a run with one solver gives them: continuous variables,
    derivatives, discrete variables (parameters after them)."""
    data = translation.data
    owned = {n for part in parts for n in part.names}
    discrete = [n for n in data.discrete_variables if n in owned]
    continuous = [v.name for v in data.variables if not v.is_discrete and v.name in owned]
    taken = set(discrete) | set(continuous)
    derivatives = [n for part in parts for n in part.names if n not in taken]
    return continuous + derivatives + discrete


def run_parts(translation, models: Sequence, make_run: Callable, t0: float, t1: float, interval: float,
              t_setup: float, *, notes: Sequence[str] = (), progress=None, max_steps: int | None = None,
              timeout: float | None = None, compile_seconds_before: float = 0.0
              ) -> tuple[SimulationResult | None, str]:
    """Run each part of ``models`` on its own (``make_run(model)``: the run of one
    part) and merge the results; ``(None, why)`` when a part's run did not succeed
    (the caller then runs the model with one solver)."""
    wall_start = _time.perf_counter()
    parts: list[_Part] = []
    events, modes, part_notes = [], [], []
    steps, nfev, part_steps = 0, 0, []
    n = len(models)
    for p, model in enumerate(models):
        run = make_run(model)
        run.history = StepHistory()
        run.compile_seconds_before = translation.translation_seconds
        if max_steps is not None:
            run.max_steps = max_steps - steps
        if timeout is not None:
            run.timeout = timeout - (_time.perf_counter() - wall_start)
            if run.timeout <= 0:
                return None, f"the time budget ran out after {p} of {n} parts"
        if progress is not None:
            def report(t, a, b, _p=p):
                share = (_p + ((t - a) / (b - a) if b > a else 1.0)) / n
                progress(a + share * (b - a), a, b)
            run.progress = report
        try:
            result = run.execute(t0, t1, interval, _time.perf_counter())
        except SimulationInterrupted:
            raise
        except AcausalError as exc:
            # (a part that cannot be compiled or initialized: the whole model says why, as always)
            return None, f"part {p + 1} of {n} stopped: {exc.message}"
        if result.status != 0:
            return None, f"part {p + 1} of {n} stopped: {result.message}"
        steps += run.steps
        nfev += run.nfev
        part_steps.append(run.steps)
        events.append(result.events)
        modes.extend(result.modes)
        part_notes.extend(result.notes)
        parts.append(_Part(model, result, run.history))
    if progress is not None:
        progress(t1, t0, t1)
    time = _merged_time([part.time for part in parts])
    data = translation.data
    names = _column_names(translation, parts)
    parameters = {p.name: p.value for p in data.parameters
                  if translation.demand is None or p.name in translation.demand}
    columns = PartColumns(time, parts, [*names, *parameters], parameters)
    merged_events = _merged_events(events)
    translate_seconds = translation.translation_seconds - compile_seconds_before
    stats = {
        "steps": steps,
        "rhs_evaluations": nfev,
        "events": len(merged_events),
        "translate_seconds": translate_seconds,
        "simulate_seconds": _time.perf_counter() - t_setup - translate_seconds,
        "method": run.method,
        "rtol": run.rtol,
        "atol": run.atol,
        "parts": n,
        "part_steps": tuple(part_steps),
    }
    said = (f"{n} independent parts integrated separately (each its own solver, step sizes and events; "
            f"rows at another part's events from its dense output)")
    all_notes = tuple(dict.fromkeys((*notes, said, *part_notes)))
    return SimulationResult(time, columns, 0, "The simulation reached the stop time.", merged_events,
                            tuple(dict.fromkeys(modes)), translation.compiled_systems, stats, all_notes, None,
                            data.name, describe_columns(data, list(columns))), ""
