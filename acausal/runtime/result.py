"""The simulation result: every variable by dotted name, events, status.

Besides the values, a result knows what each column is
(:class:`ColumnInfo`: unit, description, kind, and the names of an Integer
mode's values), and reads and writes three formats:

* :meth:`SimulationResult.to_pandas`, a DataFrame indexed by time;
* :meth:`SimulationResult.to_csv` / :func:`read_csv`, the layout of the MSL
  reference results (``"time"`` and dotted names as headers), optionally with
  ``#unit``, ``#kind`` and ``#description`` rows that readers of those files
  skip as comments;
* :meth:`SimulationResult.to_mat` / :func:`read_mat`, the Dymola/OpenModelica
  result file (``dsres.mat``), described at :func:`read_mat`.

Files are written whole or not at all (:func:`acausal.fileio.atomic_write`:
a write that fails leaves the earlier file as it was), and read only when
they are regular files below a size cap (:data:`MAX_CSV_BYTES`,
:data:`MAX_MAT_BYTES`), checked without blocking on a FIFO.

Plotting lives in the tools layer (:func:`acausal.tools.plotting.plot`);
:meth:`SimulationResult.plot` calls the plotter registered with
:func:`register_plotter`.
"""

from __future__ import annotations

import csv
import html
import io
from dataclasses import dataclass, field
from pathlib import Path
from collections.abc import Callable, Iterator, Mapping, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import SimulationError, SimulationInterrupted
from ..fileio import atomic_write, open_regular
from ..names import parse

if TYPE_CHECKING:  # only for annotations: the result does not need the compiler or pandas
    import pandas

    from ..compiler.flatten import FlatModel

__all__ = ["ColumnInfo", "Event", "SimulationResult", "describe_columns", "read_csv", "read_mat",
           "register_plotter"]

#: What a column can be: a continuous-time Real, a discrete Real (changes only
#: at events), a Boolean, an Integer, or a parameter (constant).
KINDS = ("continuous", "discrete", "boolean", "integer", "parameter")

#: The name, unit and description of the independent variable.
TIME_NAME, TIME_UNIT = "time", "s"

#: Largest CSV file :func:`read_csv` reads unless told otherwise (``max_bytes=``), in bytes.
#: Parsing holds about three times the file in memory and reads some 30 MB/s, so 512 MiB
#: (some 25 million values) is about 1.5 GB and 20 s: past that, the file given is far more
#: likely a mistake (a disk image, a log, a link to the wrong place) than a result.  The
#: reference results of ``acausal compare`` have the same cap.
MAX_CSV_BYTES = 512 * 2**20
#: Largest MAT file :func:`read_mat` reads unless told otherwise (``max_bytes=``), in bytes:
#: 8 bytes a value, so 2 GiB is some 270 million values, a long run of a large model (Dymola
#: writes such files); reading holds about twice the file in memory.
MAX_MAT_BYTES = 2 * 2**30


@dataclass(frozen=True)
class Event:
    """One event instant.

    Attributes
    ----------
    time : float
    kind : str
        ``'initial'`` (the event iteration after initialization), ``'time'``
        (time relations and sample clocks), ``'state'`` or ``'terminal'``.
    relations : tuple of str
        The relations whose crossing fired it (state events), or the time
        relations reached (time events).
    changes : tuple of (str, old, new)
        Discrete variables that changed, with their values before and after,
        then the states a ``reinit`` set (``reinit(v)``).
    iterations : int
        Passes of the event iteration.
    """

    time: float
    kind: str
    relations: tuple[str, ...]
    changes: tuple[tuple[str, object, object], ...]
    iterations: int = 1

    def __str__(self) -> str:
        changed = ", ".join(f"{n}: {a}->{b}" for n, a, b in self.changes) or "no discrete change"
        why = f" ({'; '.join(self.relations)})" if self.relations else ""
        return f"t={self.time:.9g} {self.kind}{why}: {changed}"


# ---------------------------------------------------------------------------
# What a column is
# ---------------------------------------------------------------------------

@dataclass(frozen=True)
class ColumnInfo:
    """What a result column is, besides its values.

    Attributes
    ----------
    name : str
        Dotted name, as in the result (``"inertia1.w"``, ``"der(inertia1.w)"``).
    unit : str
        Declared unit (Modelica syntax, ``"rad/s"``; ``""`` when none).
    description : str
        Declared description (``""`` when unknown, e.g. for a result read from
        a file without it).
    kind : str
        One of :data:`KINDS`.
    labels : tuple of (int, str)
        For an Integer whose component class names each of its values (see
        :func:`describe_columns`): ``(value, name)`` pairs in increasing value.
    """

    name: str
    unit: str = ""
    description: str = ""
    kind: str = "continuous"
    labels: tuple[tuple[int, str], ...] = ()

    @property
    def is_discrete(self) -> bool:
        """A Boolean or an Integer: its values are read as bool or int."""
        return self.kind in ("boolean", "integer")

    def line(self) -> str:
        """One line: ``name [unit] kind: description (labels)``."""
        unit = f" [{self.unit}]" if self.unit else ""
        text = f"{self.name}{unit} {self.kind}"
        if self.description:
            text += f": {self.description}"
        if self.labels:
            text += " (" + ", ".join(f"{v} {n}" for v, n in self.labels) + ")"
        return text


def _per_second(unit: str) -> str:
    """The unit of a time derivative: ``rad`` -> ``rad/s``, ``rad/s`` -> ``rad/s2``."""
    if not unit or unit == "1":
        return "1/s"
    numerator, slash, denominator = unit.partition("/")
    if not slash:
        return f"{unit}/s"
    if denominator == "s":
        return f"{numerator}/s2"
    if denominator.startswith("s") and denominator[1:].isdigit():
        return f"{numerator}/s{int(denominator[1:]) + 1}"
    return f"{numerator}/({denominator.strip('()')}.s)"


class _ColumnTable(Mapping):
    """:func:`describe_columns`' mapping, built on first use (most runs never ask
    what a column is); the kind of a column is found without building it."""

    def __init__(self, flat: "FlatModel", names: list[str]) -> None:
        self._source: tuple | None = (flat, names)
        self._table: dict[str, ColumnInfo] | None = None
        self._discrete = {v.name: v.kind for v in flat.variables if v.is_discrete}

    def kind(self, name: str) -> str:
        """'boolean' or 'integer' for those columns, else 'continuous' (not built for this)."""
        if self._table is not None:
            found = self._table.get(name)
            return found.kind if found is not None else "continuous"
        return self._discrete.get(name, "continuous")

    def _get(self) -> dict[str, ColumnInfo]:
        if self._table is None:
            self._table = _describe(*self._source)
            self._source = None
        return self._table

    def __getitem__(self, name: str) -> ColumnInfo:
        return self._get()[name]

    def __iter__(self) -> Iterator[str]:
        return iter(self._get())

    def __len__(self) -> int:
        return len(self._get())

    def __reduce__(self):  # a copy (pickle, deepcopy) is the plain table
        return dict, (dict(self._get()),)


def describe_columns(flat: "FlatModel", names: Sequence[str]) -> Mapping[str, ColumnInfo]:
    """What each of the result columns ``names`` is, as a mapping computed on first use.

    Units, descriptions, kinds and the names of Integer values come from the
    flat model.  A derivative ``der(x)`` gets the unit of ``x`` per second.

    Parameters
    ----------
    flat : FlatModel
    names : sequence of str
        The result's columns.
    """
    return _ColumnTable(flat, list(names))


def _describe(flat: "FlatModel", names: list[str]) -> dict[str, ColumnInfo]:
    variables = {v.name: v for v in flat.variables}
    parameters = {p.name: p for p in flat.parameters}
    info = {}
    for name in names:
        parsed = parse(name) if name.endswith(")") else None
        if parsed is not None and parsed.kind == "derivative":
            base = variables.get(parsed.base)
            unit = base.unit if base is not None else ""
            for _ in range(parsed.order):
                unit = _per_second(unit)
            info[name] = ColumnInfo(name, unit, f"time derivative of {parsed.base}"
                                    + (f" (order {parsed.order})" if parsed.order > 1 else ""),
                                    "continuous")
        elif name in parameters:
            parameter = parameters[name]
            info[name] = ColumnInfo(name, parameter.unit, parameter.description, "parameter")
        elif name in variables:
            variable = variables[name]
            kind = variable.kind if variable.kind in KINDS else "continuous"
            info[name] = ColumnInfo(name, variable.unit, variable.description, kind, variable.labels)
        else:
            info[name] = ColumnInfo(name)
    return info


def _typed(values: np.ndarray, kind: str) -> np.ndarray:
    """A Boolean column as bool, an Integer one as int64 (as stored, float, if not all finite)."""
    if kind not in ("boolean", "integer") or values.dtype != np.float64 or not np.isfinite(values).all():
        return values
    return values != 0 if kind == "boolean" else np.rint(values).astype(np.int64)


# ---------------------------------------------------------------------------
# Plotting is a tool: the result only knows whom to ask
# ---------------------------------------------------------------------------

_PLOTTER: list[Callable[..., Any]] = []


def register_plotter(plotter: Callable[..., Any]) -> None:
    """Make ``plotter(result, names, **options)`` the function :meth:`SimulationResult.plot` calls.

    :mod:`acausal.tools.plotting` registers its :func:`~acausal.tools.plotting.plot`
    when it is imported (the runtime does not import the tools layer).
    """
    _PLOTTER[:] = [plotter]


# ---------------------------------------------------------------------------
# The result
# ---------------------------------------------------------------------------

_STATUS_WORDS = {0: "ok", 1: "terminated", -1: "failed", -2: "interrupted"}


@dataclass(frozen=True, repr=False)
class SimulationResult:
    """What a simulation computed.

    Like scipy's ``OdeResult`` it carries a status and a message instead of
    raising when a run stops early: everything computed up to the failure
    is kept.  Variables are read by dotted name, ``result["inertia1.w"]``:
    Booleans come back as bool arrays, Integers as int arrays, the rest as
    float arrays (:attr:`columns` holds them all as float).

    Attributes
    ----------
    time : ndarray
        Output times; an event time appears twice (left and right limit), or
        more often when several events happen at one instant (see
        :attr:`event_rows`).
    columns : dict of str to ndarray
        Every column by name, as float.
    status : int
        0 for success, 1 for a run a ``terminate()`` ended (a success, with
        the reason in ``message``), -1 for a run that stopped early (an
        error), -2 for a run interrupted (Ctrl-C).
    message : str
    events : tuple of Event
    modes : tuple of str
        Discrete states visited, in the order first visited.
    compiled_modes : int
        Systems compiled for the discrete states visited or tried during event
        iteration (states whose equations are the same share one).
    stats : dict
        Right-hand side evaluations, steps, seconds spent.
    notes : tuple of str
        Warnings, e.g. fixed start values relaxed as redundant.
    error : Exception or None
        The error that stopped the run.  A :class:`~acausal.errors.SimulationError`
        (or :class:`~acausal.errors.SimulationInterrupted`) given here is
        replaced, at construction, by a copy built with this result as its
        ``result``: ``result.error.result is result``.
    model_name : str
    column_info : dict of str to ColumnInfo
        Unit, description and kind of the columns (see :func:`describe_columns`);
        a column missing here counts as a continuous Real without unit.
    """

    time: np.ndarray
    columns: dict = field(repr=False)
    status: int = 0
    message: str = "The simulation reached the stop time."
    events: tuple = ()
    modes: tuple = ()
    compiled_modes: int = 0
    stats: dict = field(default_factory=dict)
    notes: tuple = ()
    error: BaseException | None = None
    model_name: str = ""
    column_info: Mapping[str, ColumnInfo] = field(default_factory=dict)

    def __post_init__(self) -> None:
        # the error travels with the partial result: its copy is built with it
        if isinstance(self.error, (SimulationError, SimulationInterrupted)) and self.error.result is not self:
            object.__setattr__(self, "error", self.error.with_result(self))

    @property
    def success(self) -> bool:
        """Whether the run ended as the model asked: at the stop time, or by ``terminate()``."""
        return self.status in (0, 1)

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(self.columns)

    # -- reading columns ---------------------------------------------------------------

    def _unknown(self, name: str) -> KeyError:
        """A KeyError for ``name`` that suggests the names it may have meant."""
        import difflib

        known = list(self.columns)
        close = difflib.get_close_matches(name, known, n=3)
        if not close:
            # a name given without its component path ("w"), or with another case
            tail = [n for n in known if n.rpartition(".")[2] == name.rpartition(".")[2]]
            folded = [n for n in known if n.lower() == name.lower()]
            close = (folded + tail)[:3]
        hint = f"; did you mean {', '.join(close)}?" if close else ""
        if name.lower() == TIME_NAME:
            hint = "; the time is result.time"
        return KeyError(f"{name!r} is not a variable of {self.model_name or 'this model'}{hint}")

    def __getitem__(self, name: str) -> np.ndarray:
        try:
            values = self.columns[name]
        except KeyError:
            raise self._unknown(name) from None
        table = self.column_info
        if isinstance(table, _ColumnTable):
            kind = table.kind(name)  # without building the descriptions
        else:
            found = table.get(name)
            kind = found.kind if found is not None else "continuous"
        return _typed(values, kind)

    def __contains__(self, name: str) -> bool:
        return name in self.columns

    def final(self, name: str) -> float:
        return float(self[name][-1])

    def info(self, name: str) -> ColumnInfo:
        """What the column ``name`` is (``"time"`` included).

        Raises
        ------
        KeyError
            For a name that is not a column, with the close names.
        """
        if name == TIME_NAME and name not in self.columns:
            return ColumnInfo(TIME_NAME, TIME_UNIT, "time", "continuous")
        if name not in self.columns:
            raise self._unknown(name)
        found = self.column_info.get(name)
        return found if found is not None else ColumnInfo(name)

    def unit(self, name: str) -> str:
        """The declared unit of ``name`` (``""`` when it has none)."""
        return self.info(name).unit

    def describe(self, name: str) -> str:
        """One line: name, unit, kind and description, e.g.
        ``inertia1.w [rad/s] continuous: Absolute angular velocity of component``."""
        return self.info(name).line()

    @property
    def event_rows(self) -> np.ndarray:
        """A bool per row: True for the rows at an event instant.

        Those are the rows at the time of an entry of :attr:`events` (the
        initial event included) and the rows whose time appears more than
        once (the left and right limits; a result read from a file has no
        :attr:`events` but keeps those).
        """
        time = np.asarray(self.time, dtype=float)
        repeated = np.zeros(len(time), dtype=bool)
        if len(time) > 1:
            same = time[1:] == time[:-1]
            repeated[1:] |= same
            repeated[:-1] |= same
        if self.events:
            repeated |= np.isin(time, np.array([e.time for e in self.events], dtype=float))
        return repeated

    # -- pandas ------------------------------------------------------------------------

    def to_pandas(self, names: Sequence[str] | None = None, *, events: str = "keep",
                  event_column: str | None = "event") -> "pandas.DataFrame":
        """The result as a DataFrame indexed by time (index name ``"time"``).

        Parameters
        ----------
        names : sequence of str, optional
            Columns to include (default: all, parameters too).
        events : {'keep', 'last', 'first'}
            ``'keep'``: every row, an event instant appearing twice or more
            (left limit first, right limit last) so the index has duplicates;
            ``'last'``: one row per time, the last one (the right limit, the
            values after the event); ``'first'``: one row per time, the first
            one (the left limit, the values before it).
        event_column : str or None
            Name of a bool column that is True for the rows at an event
            instant (:attr:`event_rows`); None leaves it out.

        Returns
        -------
        pandas.DataFrame
            Booleans as bool columns, Integers as int64, the rest float64.
            ``df.attrs`` holds ``"units"``, ``"descriptions"`` and
            ``"kinds"`` (dicts by column name, the time's unit under
            ``"time"``), ``"model"`` and ``"status"``.
        """
        import pandas as pd  # lazily: ``import acausal`` stays light

        if events not in ("keep", "last", "first"):
            raise ValueError(f"events={events!r}: choose 'keep', 'last' or 'first'")
        chosen = list(self.columns) if names is None else list(names)
        for name in chosen:
            self.info(name)  # a clear KeyError for an unknown name
        if event_column is not None and event_column in chosen:
            raise ValueError(f"{event_column!r} is a column of {self.model_name or 'this model'}: "
                             f"give event_column another name (or None)")
        time = np.asarray(self.time, dtype=float)
        keep = np.ones(len(time), dtype=bool)
        if events == "last" and len(time) > 1:
            keep[:-1] = time[:-1] != time[1:]
        elif events == "first" and len(time) > 1:
            keep[1:] = time[1:] != time[:-1]
        data: dict[str, np.ndarray] = {name: self[name][keep] for name in chosen}
        if event_column is not None:
            data[event_column] = self.event_rows[keep]
        frame = pd.DataFrame(data, index=pd.Index(time[keep], name=TIME_NAME), copy=False)
        infos = {name: self.info(name) for name in chosen}
        frame.attrs = {
            "units": {TIME_NAME: TIME_UNIT, **{n: i.unit for n, i in infos.items()}},
            "descriptions": {n: i.description for n, i in infos.items()},
            "kinds": {n: i.kind for n, i in infos.items()},
            "model": self.model_name,
            "status": self.status,
        }
        return frame

    # -- plotting ----------------------------------------------------------------------

    def plot(self, names: str | Sequence[str | Sequence[str]] | None = None, **options: Any) -> Any:
        """Plot ``names`` against time with the registered plotter.

        See :func:`acausal.tools.plotting.plot` for the options; that module
        registers itself when imported (``import acausal.tools.plotting``).
        """
        if not _PLOTTER:
            raise RuntimeError("no plotter is registered: import acausal.tools.plotting first "
                               "(or call acausal.tools.plotting.plot(result, names))")
        return _PLOTTER[0](self, names, **options)

    # -- display -----------------------------------------------------------------------

    def _span(self) -> str:
        if len(self.time) == 0:
            return "no output points"
        return f"t = {float(self.time[0]):.6g} .. {float(self.time[-1]):.6g} s"

    def __repr__(self) -> str:
        status = _STATUS_WORDS.get(self.status, f"status {self.status}")
        return (f"<SimulationResult {self.model_name or '(unnamed)'}: {status}, {self._span()}, "
                f"{len(self.time)} points, {len(self.events)} events, {len(self.columns)} signals>")

    def _repr_html_(self, shown: int = 8) -> str:
        """A small table for notebooks: status, message, span and a few signals
        (states first, then Booleans and Integers) with unit, kind, final value
        and description."""
        escape = html.escape
        status = _STATUS_WORDS.get(self.status, f"status {self.status}")
        rows = [("status", status), ("message", self.message), ("span", self._span()),
                ("points", str(len(self.time))), ("events", str(len(self.events))),
                ("signals", str(len(self.columns)))]
        head = "".join(f"<tr><th style='text-align:left'>{escape(k)}</th><td>{escape(v)}</td></tr>"
                       for k, v in rows)
        # the states first (their derivatives are columns), then Booleans and Integers
        rank = {n: 0 if f"der({n})" in self.columns else 1 if self.info(n).is_discrete else 2
                for n in self.columns if self.info(n).kind != "parameter" and not n.startswith("der(")}
        signals = sorted(rank, key=rank.get)[:shown]
        body = []
        for name in signals:
            info = self.info(name)
            value = self[name][-1] if len(self.time) else float("nan")
            final = f"{value:.6g}" if isinstance(value, (float, np.floating)) else str(value)
            body.append("<tr>" + "".join(f"<td>{escape(c)}</td>" for c in (
                name, info.unit, info.kind, final, info.description)) + "</tr>")
        more = len(self.columns) - len(signals)
        tail = (f"<tr><td colspan='5'>… and {more} more (result.names)</td></tr>" if more > 0 else "")
        return (f"<div><b>SimulationResult {escape(self.model_name)}</b>"
                f"<table>{head}</table>"
                "<table><tr><th>signal</th><th>unit</th><th>kind</th><th>final</th>"
                f"<th>description</th></tr>{''.join(body)}{tail}</table></div>")

    def raise_for_status(self) -> "SimulationResult":
        """Raise the stored error if the run failed; return self otherwise."""
        if self.error is not None:
            raise self.error
        return self

    # -- files -------------------------------------------------------------------------

    def to_csv(self, path: str | Path, signals: Sequence[str] | None = None, *,
               metadata: bool = False) -> Path:
        """Write a CSV in the layout of the MSL reference results.

        ``"time"`` first, then dotted names as headers; Booleans as 0/1.

        Parameters
        ----------
        path : str or Path
        signals : sequence of str, optional
            Columns to write (default: all).
        metadata : bool
            Also write, after the header, the rows ``#unit``, ``#kind`` and
            ``#description`` (their first cell names them, the others hold
            each column's value) and a ``#model`` row.  Readers of the
            reference files (and ``pandas.read_csv(..., comment="#")``) skip
            them as comments; :func:`read_csv` reads them back.

        Returns
        -------
        Path
            ``path``.  The file is written whole or not at all: if writing
            fails (an exception, a full disk, an interrupt), an earlier file
            at ``path`` is left as it was (:func:`acausal.fileio.atomic_write`).
        """
        names = list(self.columns) if signals is None else list(signals)
        for n in names:
            self[n]  # clear KeyError for unknown names

        def write(handle) -> None:
            writer = csv.writer(handle)
            writer.writerow(["time"] + names)
            if metadata:
                infos = [self.info(n) for n in names]
                writer.writerow(["#unit"] + [i.unit for i in infos])
                writer.writerow(["#kind"] + [i.kind for i in infos])
                writer.writerow(["#description"] + [i.description for i in infos])
                writer.writerow(["#model", self.model_name])
            data = np.column_stack([self.time] + [np.asarray(self.columns[n], dtype=float)
                                                  for n in names])
            for row in data:
                writer.writerow([repr(float(v)) for v in row])

        return atomic_write(Path(path), write, "w", newline="")

    @classmethod
    def from_csv(cls, path: str | Path) -> "SimulationResult":
        """The result a CSV written by :meth:`to_csv` holds (see :func:`read_csv`)."""
        return read_csv(path)

    def to_mat(self, path: str | Path, signals: Sequence[str] | None = None) -> Path:
        """Write a Dymola/OpenModelica result file (``dsres.mat`` layout, MAT v4).

        Parameters go to ``data_1``, every other column to ``data_2``; the
        layout is described at :func:`read_mat`.  Descriptions carry the unit
        as Dymola writes it, ``"description [unit]"``.

        Parameters
        ----------
        path : str or Path
        signals : sequence of str, optional
            Columns to write (default: all).

        Returns
        -------
        Path
            ``path``, written whole or not at all (as :meth:`to_csv`).
        """
        import scipy.io

        names = list(self.columns) if signals is None else list(signals)
        for n in names:
            self[n]  # clear KeyError for unknown names
        if len(self.time) == 0:
            raise ValueError("the result has no output points to write")
        time = np.asarray(self.time, dtype=float)
        constants = [n for n in names if self.info(n).kind == "parameter"]
        trajectories = [n for n in names if self.info(n).kind != "parameter"]
        all_names = [TIME_NAME] + constants + trajectories
        descriptions = ["Time in [s]"]
        info = [(0, 1, 0, -1)]  # the abscissa: data set 0, column 1, not defined outside
        for k, name in enumerate(constants):
            descriptions.append(_mat_description(self.info(name)))
            info.append((1, k + 2, 0, 0))  # constant: keep the value outside the time range
        for k, name in enumerate(trajectories):
            descriptions.append(_mat_description(self.info(name)))
            info.append((2, k + 2, 0, -1))
        # binTrans: a row per variable, a column per time (data_1: the first and the last)
        data_1 = np.array([[time[0], time[-1]]] + [[float(self.columns[n][0])] * 2 for n in constants],
                          dtype=float)
        data_2 = np.vstack([time] + [np.asarray(self.columns[n], dtype=float) for n in trajectories])
        matrices = {
            "Aclass": _char_rows(["Atrajectory", "1.1", "", "binTrans"]),
            # binTrans: one name (description) per column of the char matrix
            "name": np.ascontiguousarray(_char_rows(all_names).T),
            "description": np.ascontiguousarray(_char_rows(descriptions).T),
            "dataInfo": np.ascontiguousarray(np.array(info, dtype=np.int32).T),
            "data_1": data_1,
            "data_2": np.ascontiguousarray(data_2),
        }
        return atomic_write(Path(path), lambda handle: scipy.io.savemat(handle, matrices, format="4"),
                            "wb")

    @classmethod
    def from_mat(cls, path: str | Path) -> "SimulationResult":
        """The result a Dymola/OpenModelica result file holds (see :func:`read_mat`)."""
        return read_mat(path)

    def summary(self) -> str:
        lines = [f"{self.model_name}: {'ok' if self.success else 'FAILED'} — {self.message}",
                 f"  {_count(len(self.time), 'output point')}, {_count(len(self.events), 'event')}, "
                 f"{_count(len(self.modes), 'discrete state')} visited, "
                 f"{_count(self.compiled_modes, 'system')} compiled"]
        for key in ("steps", "rhs_evaluations", "translate_seconds", "simulate_seconds"):
            if key in self.stats:
                value = self.stats[key]
                lines.append(f"  {key}: {value:.4g}" if isinstance(value, float) else f"  {key}: {value}")
        lines += [f"  note: {n}" for n in self.notes]
        return "\n".join(lines)


def _count(n: int, noun: str) -> str:
    """``1 event``, ``2 events``."""
    return f"{n} {noun}" if n == 1 else f"{n} {noun}s"


# ---------------------------------------------------------------------------
# Readers
# ---------------------------------------------------------------------------

def read_csv(path: str | Path, *, max_bytes: int | None = MAX_CSV_BYTES) -> SimulationResult:
    """Read a CSV written by :meth:`SimulationResult.to_csv` (or any file of its layout).

    The first line names the columns, one of which is ``time``; the
    ``#unit``, ``#kind``, ``#description`` and ``#model`` rows, if present,
    give the columns' metadata (Booleans and Integers then read back as
    bool and int); other lines starting with ``#`` are comments.

    Parameters
    ----------
    path : str or Path
        A regular file (a symbolic link to one is fine).
    max_bytes : int or None
        The largest file read, :data:`MAX_CSV_BYTES` (512 MiB) unless given;
        None reads any size.

    Returns
    -------
    SimulationResult
        With ``message`` naming the file and no :attr:`~SimulationResult.events`
        (event instants are still found by their repeated times).

    Raises
    ------
    OSError
        For a file that cannot be read, that is not a regular file (a FIFO
        or a device is refused at once, without waiting for it), or that is
        larger than ``max_bytes`` (the message names the file, its size and
        the cap); see :func:`acausal.fileio.open_regular`.
    ValueError
        For content that is not a result of this layout.
    """
    path = Path(path)
    meta: dict[str, list[str]] = {}
    header: list[str] | None = None
    rows: list[list[float]] = []
    raw = open_regular(path, max_bytes, hint="read_csv(path, max_bytes=...) reads a larger one")
    # the text as open() would decode it (the locale's encoding, as to_csv writes it)
    with io.TextIOWrapper(raw, newline="") as handle:
        for line, row in enumerate(csv.reader(handle), start=1):
            if not row or not any(cell.strip() for cell in row):
                continue
            first = row[0].strip()
            if first.startswith("#"):
                meta[first[1:]] = row[1:]
                continue
            if header is None:
                header = [cell.strip().strip("'\"") for cell in row]
                continue
            try:
                rows.append([float(cell) for cell in row])
            except ValueError:
                raise ValueError(f"{path}, line {line}: a value is not a number") from None
    if header is None:
        raise ValueError(f"{path} has no header line")
    at_time = next((k for k, n in enumerate(header) if n.lower() == TIME_NAME), None)
    if at_time is None:
        raise ValueError(f"{path} has no 'time' column")
    data = np.array(rows, dtype=float).reshape(len(rows), len(header))
    names = [n for k, n in enumerate(header) if k != at_time]
    # the metadata rows hold one cell per column after the first (the time's)
    positions = [k - 1 for k in range(len(header)) if k != at_time]

    def cell(key: str, position: int) -> str:
        values = meta.get(key, [])
        return values[position] if 0 <= position < len(values) else ""

    columns = {n: data[:, k] for k, n in enumerate(header) if k != at_time}
    info = {}
    for name, position in zip(names, positions):
        kind = cell("kind", position)
        info[name] = ColumnInfo(name, cell("unit", position), cell("description", position),
                                kind if kind in KINDS else "continuous")
    model = (meta.get("model") or [path.stem])[0] or path.stem
    return SimulationResult(data[:, at_time], columns, message=f"read from {path}", model_name=model,
                            column_info=info)


def _char_rows(texts: Sequence[str]) -> np.ndarray:
    """A char matrix with one text per row, padded with blanks (as MAT v4 stores text).

    Text goes as UTF-8 bytes, one byte per char, as Dymola writes it."""
    encoded = [t.encode("utf-8").decode("latin-1") for t in texts]
    width = max(1, max(map(len, encoded), default=1))
    return np.array([list(t.ljust(width)) for t in encoded], dtype="<U1").reshape(len(encoded), width)


def _texts(chars: np.ndarray) -> list[str]:
    """The rows of a char matrix as texts, blanks stripped (inverse of :func:`_char_rows`)."""
    return ["".join(row).rstrip(" \0").encode("latin-1").decode("utf-8", errors="replace")
            for row in np.atleast_2d(chars)]


def _mat_description(info: ColumnInfo) -> str:
    return f"{info.description} [{info.unit}]" if info.unit else info.description


def _parse_mat_description(text: str) -> tuple[str, str]:
    """``"Absolute angle [rad|deg]"`` -> ``("Absolute angle", "rad")``."""
    if text.endswith("]") and "[" in text:
        description, _, unit = text[:-1].rpartition("[")
        return description.rstrip(), unit.partition("|")[0]
    return text, ""


def read_mat(path: str | Path, *, max_bytes: int | None = MAX_MAT_BYTES) -> SimulationResult:
    """Read a Dymola/OpenModelica result file (``dsres.mat`` layout, MAT v4).

    The layout, as Dymola and OpenModelica write it (format 1.1):

    ``Aclass``
        Four text rows: ``Atrajectory``, ``1.1``, (blank), then
        ``binTrans`` (matrices below stored transposed, one variable per
        column) or ``binNormal`` (one variable per row).
    ``name``, ``description``
        Char matrices, one variable per column (``binTrans``), blank padded.
        The description ends with the unit in brackets, ``"text [unit]"``
        (``[unit|displayUnit]`` in Dymola's files).
    ``dataInfo``
        Integers, four per variable (one column each with ``binTrans``):
        the data set (0 for the abscissa time, 1 for ``data_1``, 2 for
        ``data_2``), the column in that set (1-based; negative: the values
        negated, an alias), the interpolation (0 linear) and what holds
        outside the time range (-1 undefined, 0 keep the end values).
    ``data_1``
        Parameters and constants: the first and last time in the first
        column (``binTrans``: row), then one per variable.
    ``data_2``
        Trajectories: time first, then one per variable, one row per output
        point (``binTrans``: one column per point).

    Format 1.0 (``names`` and one ``data`` matrix) is read too.

    Parameters
    ----------
    path : str or Path
        A regular file (a symbolic link to one is fine).
    max_bytes : int or None
        The largest file read, :data:`MAX_MAT_BYTES` (2 GiB) unless given;
        None reads any size.

    Returns
    -------
    SimulationResult
        Parameters as constant columns of kind ``'parameter'``, units
        parsed from the descriptions, no events (event instants are found by
        their repeated times).

    Raises
    ------
    OSError
        For a file that cannot be read, is not a regular file or is larger
        than ``max_bytes``, as :func:`read_csv`.
    ValueError
        For a file that is not a Modelica result file.
    """
    import scipy.io

    path = Path(path)
    with open_regular(path, max_bytes, hint="read_mat(path, max_bytes=...) reads a larger one") as handle:
        mat = scipy.io.loadmat(handle, chars_as_strings=False)
    if "Aclass" not in mat:
        raise ValueError(f"{path} is not a Modelica result file: it has no Aclass matrix")
    aclass = _texts(mat["Aclass"])
    if not aclass or aclass[0] != "Atrajectory":
        raise ValueError(f"{path} is not a simulation result (Aclass starts with {aclass[:1]})")
    transposed = len(aclass) > 3 and aclass[3] == "binTrans"

    def matrix(key: str) -> np.ndarray:
        """``mat[key]`` as ``binNormal`` stores it: a name (a dataInfo entry) per row, a
        data matrix with a variable per column."""
        value = np.atleast_2d(mat[key])
        return value.T if transposed else value

    def texts(key: str) -> list[str]:
        return _texts(matrix(key))

    stem = path.stem
    if len(aclass) > 1 and aclass[1] == "1.0":
        names, data = texts("names"), matrix("data")
        columns = {n: np.ascontiguousarray(data[:, k]) for k, n in enumerate(names) if k}
        return SimulationResult(np.ascontiguousarray(data[:, 0]), columns, message=f"read from {path}",
                                model_name=stem, column_info={n: ColumnInfo(n) for n in columns})
    names, descriptions = texts("name"), texts("description")
    data_info = matrix("dataInfo")
    data_sets = {j: matrix(f"data_{j}") for j in (1, 2) if f"data_{j}" in mat}
    trajectories = data_sets.get(2, data_sets.get(1))
    time = np.ascontiguousarray(trajectories[:, 0])
    columns, info = {}, {}
    for name, text, row in zip(names, descriptions, data_info):
        data_set, column = int(row[0]), int(row[1])
        if data_set == 0:
            continue  # the abscissa
        values = data_sets[data_set][:, abs(column) - 1] * (1.0 if column > 0 else -1.0)
        if data_set == 1:  # a constant: its value at every output point
            values = np.full(len(time), values[0])
        description, unit = _parse_mat_description(text)
        columns[name] = np.ascontiguousarray(values, dtype=float)
        info[name] = ColumnInfo(name, unit, description, "parameter" if data_set == 1 else "continuous")
    return SimulationResult(time, columns, message=f"read from {path}", model_name=stem, column_info=info)
