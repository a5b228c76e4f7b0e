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

Values are kept in the declared (SI) units.  A column may also be shown in
a display unit (Modelica's ``displayUnit``, declared as
``Variable(unit="rad/s", display_unit="rpm")`` or asked for per call):
:meth:`SimulationResult.in_unit`, ``to_pandas(display_units=...)``,
``plot(units=...)`` and :meth:`SimulationResult.summary` convert with
:func:`convert_unit` (Modelica's unit syntax, the scales of
:mod:`acausal.compiler.units`, the offset of ``degC`` and ``degF``).  Files
stay in the declared units.

:meth:`SimulationResult.at` reads values at any time in the run's span:
linear between output rows, the left or right limit at an event.

Arrays (``Variable(shape=3)``, arrays of components) are stored one column
per element (``x[1]``, ``cell[2].T``) and read back whole by the name
without indices: ``result["cell.T"]`` is a ``(len(time), n)`` array (see
:class:`SimulationResult`).

Plotting lives in the tools layer (:func:`acausal.tools.plotting.plot`);
:meth:`SimulationResult.plot` calls the plotter registered with
:func:`register_plotter`.
"""

from __future__ import annotations

import csv
import functools
import html
import io
import math
import re
import warnings
from dataclasses import dataclass, field
from fractions import Fraction
from pathlib import Path
from collections.abc import Callable, Iterator, Mapping, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import SimulationError, SimulationInterrupted
from ..fileio import atomic_write, open_regular
from ..names import parse

if TYPE_CHECKING:  # only for annotations: the result does not need the compiler or pandas
    import pandas

    from ..compiler.compiled import ModelData
    from ..compiler.flatten import FlatModel

__all__ = ["ColumnInfo", "Event", "SimulationResult", "convert_unit", "describe_columns", "read_csv",
           "read_mat", "register_plotter"]

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
    display_unit : str
        Declared display unit (Modelica's ``displayUnit``, ``"rpm"``), the unit
        summaries, plots and ``to_pandas(display_units=True)`` show the values
        in; ``""`` when none (the values are shown in ``unit``).
    nominal : float
        Declared nominal value (1 when none): with the run's tolerance, the
        size below which a summary prints the value as 0.
    shape : tuple of int
        ``()`` for a column.  For the name of an array whose elements are
        columns (``"cell.T"`` for ``cell[1].T`` ... ``cell[n].T``, see
        :meth:`SimulationResult.elements`), its size, ``(n,)`` or ``(n, m)``;
        the other attributes are then those the elements share (``""``, or
        the default, where they differ).
    """

    name: str
    unit: str = ""
    description: str = ""
    kind: str = "continuous"
    labels: tuple[tuple[int, str], ...] = ()
    display_unit: str = ""
    nominal: float = 1.0
    shape: tuple[int, ...] = ()

    @property
    def is_discrete(self) -> bool:
        """A Boolean or an Integer: its values are read as bool or int."""
        return self.kind in ("boolean", "integer")

    def line(self) -> str:
        """One line: ``name [unit] kind: description (labels) (display unit ...)``; an
        array's says its size, ``cell.T [K] continuous, array of 10: ...``."""
        unit = f" [{self.unit}]" if self.unit else ""
        text = f"{self.name}{unit} {self.kind}"
        if self.shape:
            text += f", array of {'x'.join(map(str, self.shape))}"
        if self.description:
            text += f": {self.description}"
        if self.labels:
            text += " (" + ", ".join(f"{v} {n}" for v, n in self.labels) + ")"
        if self.display_unit and self.display_unit != self.unit:
            text += f" (display unit {self.display_unit})"
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

    def __init__(self, flat: "FlatModel | ModelData", names: list[str]) -> None:
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


def describe_columns(flat: "FlatModel | ModelData", names: Sequence[str]) -> Mapping[str, ColumnInfo]:
    """What each of the result columns ``names`` is, as a mapping computed on first use.

    Units, descriptions, kinds and the names of Integer values come from the
    flat model.  A derivative ``der(x)`` gets the unit of ``x`` per second.

    Parameters
    ----------
    flat : FlatModel or ModelData
        What declares the variables and parameters (``variables``, ``parameters``).
    names : sequence of str
        The result's columns.
    """
    return _ColumnTable(flat, list(names))


def _describe(flat: "FlatModel | ModelData", names: list[str]) -> dict[str, ColumnInfo]:
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
                                    "continuous",
                                    nominal=_nominal(base.nominal) if base is not None else 1.0)
        elif name in parameters:
            parameter = parameters[name]
            info[name] = ColumnInfo(name, parameter.unit, parameter.description, "parameter",
                                    display_unit=getattr(parameter, "display_unit", "") or "")
        elif name in variables:
            variable = variables[name]
            kind = variable.kind if variable.kind in KINDS else "continuous"
            # display_unit: Modelica's displayUnit, when the flat model carries it
            info[name] = ColumnInfo(name, variable.unit, variable.description, kind, variable.labels,
                                    getattr(variable, "display_unit", "") or "",
                                    _nominal(variable.nominal))
        else:
            info[name] = ColumnInfo(name)
    return info


def _typed(values: np.ndarray, kind: str) -> np.ndarray:
    """A Boolean column as bool, an Integer one as int64 (as stored, float, if not all finite)."""
    if kind not in ("boolean", "integer") or values.dtype != np.float64 or not np.isfinite(values).all():
        return values
    return values != 0 if kind == "boolean" else np.rint(values).astype(np.int64)


def _nominal(value: Any) -> float:
    """A declared nominal value as a positive float (1 when it is not one)."""
    try:
        value = abs(float(value))
    except (TypeError, ValueError):
        return 1.0
    return value if math.isfinite(value) and value > 0 else 1.0


# ---------------------------------------------------------------------------
# Display units
# ---------------------------------------------------------------------------

#: Names accepted for a display unit besides Modelica's unit syntax, and what they stand for.
UNIT_ALIASES = {"rpm": "rev/min", "°C": "degC", "°F": "degF", "°": "deg"}

#: Units of absolute temperature whose zero is not 0 K: unit -> (size in K, its zero in K).
#: Only a unit written alone is one of these: ``degC/s`` is a rate, ``K/s`` in size.
AFFINE_UNITS = {"degC": (1.0, 273.15), "degF": (5.0 / 9.0, 273.15 - 32.0 * 5.0 / 9.0)}

#: Symbols of a plane angle and the power of the angle they carry (``sr`` is rad2).
_ANGLES = {"rad": 1, "deg": 1, "rev": 1, "sr": 2}
_SI_PREFIXES = frozenset("Y Z E P T G M k h da d c m u n p f a z y".split())


def _angle_power(text: str) -> Fraction:
    """The power of the plane angle in a Modelica unit string that :func:`parse_unit` accepted.

    SI counts the radian as 1, and so does the unit check: for converting
    values it is kept as a dimension of its own, so that ``rad/s`` converts to
    ``rpm`` and ``deg/s`` but not to ``Hz`` or ``1/s`` (whose values differ by
    2 pi or not, depending on what they count).
    """
    import sympy

    def weight(symbol: str) -> int:
        for angle, power in _ANGLES.items():
            if symbol == angle or (symbol.endswith(angle) and symbol[:-len(angle)] in _SI_PREFIXES):
                return power
        return 0

    names = set(re.findall(r"[A-Za-z]+", text))
    if not any(weight(n) for n in names):
        return Fraction(0)
    # the Modelica syntax as a product of powers: kg.m2/s2 -> kg*m**(2)/s**(2)
    product = re.sub(r"([A-Za-z]+)([+-]?\d+)", r"\1**(\2)", text).replace(".", "*")
    symbols = {n: sympy.Symbol(n, positive=True) for n in names}
    expression = sympy.parse_expr(product, local_dict=symbols, evaluate=True)
    powers = expression.as_powers_dict()
    return sum((Fraction(str(powers.get(symbols[n], 0))) * weight(n) for n in names), Fraction(0))


@dataclass(frozen=True)
class _Scale:
    """A unit as conversion needs it: dimensions, angle power, size and zero in coherent SI."""

    text: str
    exponents: tuple
    angle: Fraction
    scale: float
    offset: float = 0.0

    def dimension(self) -> str:
        """What the unit measures, in base units: ``1/s``, ``rad/s``, ``kg/(m.s2)``."""
        from ..compiler.units import Unit, format_unit

        base = format_unit(Unit(self.exponents, 1.0))
        if not self.angle:
            return base
        angle = "rad" if self.angle == 1 else f"rad{self.angle}"
        if base == "1":
            return angle
        if base.startswith("1/"):
            return angle + base[1:]
        return f"{angle}.{base}"


@functools.lru_cache(maxsize=256)
def _scale_of(unit: str) -> _Scale:
    """A unit string (Modelica syntax, or one of :data:`UNIT_ALIASES`) as a :class:`_Scale`."""
    from ..compiler.units import parse_unit

    text = unit.strip()
    text = UNIT_ALIASES.get(text, text)
    if text in AFFINE_UNITS:
        size, zero = AFFINE_UNITS[text]
        return _Scale(unit, parse_unit("K").exponents, Fraction(0), size, zero)
    parsed = parse_unit(text)  # a ValueError naming the unit for an unknown one
    if parsed is None:
        raise ValueError("an empty unit")
    return _Scale(unit, parsed.exponents, _angle_power(text), parsed.scale)


def _conversion(unit: str, to: str, name: str = "") -> tuple[float, float]:
    """``(factor, offset)``: a value in ``unit`` is ``value * factor + offset`` in ``to``.

    Raises
    ------
    ValueError
        For an unknown unit, or units that measure different things, naming
        both (and ``name``, the column, when given).
    """
    subject = name or f"a value in {unit!r}"
    if to == unit:
        return 1.0, 0.0
    if not unit:
        raise ValueError(f"{name or 'a value'} has no unit: it cannot be shown in {to!r} "
                         f"(declare its unit, Variable(unit=...))")
    try:
        source = _scale_of(unit)
    except ValueError as exc:
        raise ValueError(f"{name + ' is in ' if name else ''}{unit!r}, a unit acausal cannot convert: "
                         f"{exc}") from None
    try:
        target = _scale_of(to)
    except ValueError as exc:
        raise ValueError(f"{subject} cannot be shown in {to!r}: {exc} (write a unit in Modelica's "
                         f"syntax, e.g. 'rpm', 'deg', 'degC', 'bar', 'mm', 'km/h', 'kW')") from None
    if source.exponents != target.exponents or source.angle != target.angle:
        raise ValueError(f"{subject} cannot be shown in {to!r}: {unit!r} measures "
                         f"{source.dimension()}, {to!r} measures {target.dimension()}")
    return source.scale / target.scale, (source.offset - target.offset) / target.scale


def convert_unit(values: Any, unit: str, to: str, *, name: str = "") -> np.ndarray:
    """``values`` given in ``unit``, converted to the unit ``to``.

    Both are Modelica unit strings (``"rad/s"``, ``"kg.m2"``, ``"bar"``,
    prefixes such as ``"mm"``), or ``"rpm"``, ``"°C"``, ``"°F"``, ``"°"``
    (:data:`UNIT_ALIASES`).  ``degC`` and ``degF`` written alone are absolute
    temperatures, whose zero is not 0 K: 300 K is 26.85 degC.  A temperature
    *difference* declared in ``K`` is shown in ``K`` (in degC it would gain
    the offset).  The radian counts as a dimension here: ``rad/s`` converts
    to ``rpm`` (2 pi/60 rad/s) and ``deg/s``, not to ``Hz``.

    Parameters
    ----------
    values : array_like
    unit, to : str
    name : str, optional
        What the values are, for the messages (``"J1.w"``).

    Returns
    -------
    ndarray
        A new float array; ``values`` is left as it was.

    Raises
    ------
    ValueError
        For an unknown unit, or units that measure different things, naming both.

    Examples
    --------
    >>> convert_unit([0.0, 300.0], "K", "degC")
    array([-273.15,   26.85])
    """
    factor, offset = _conversion(unit, to, name)
    converted = np.asarray(values, dtype=float) * factor
    return converted + offset if offset else converted


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
# Arrays: names whose elements are columns
# ---------------------------------------------------------------------------

#: An index in a name: ``[3]``, ``[1,2]`` (a name asked for may write ``[1, 2]``).
_INDEX = re.compile(r"\[\s*(\d+(?:\s*,\s*\d+)*)\s*\]")

#: Where the indices of a name were: ``(position in the name without them, indices)``.
_Indices = tuple[tuple[int, tuple[int, ...]], ...]


def _split_indices(name: str) -> tuple[str, _Indices]:
    """``name`` without its indices, and where they were.

    ``cell[2].x[1]`` gives ``("cell.x", ((4, (2,)), (6, (1,))))``: each
    position counts in the name without indices, so that the indices of two
    names of one array line up.
    """
    pieces: list[str] = []
    groups: list[tuple[int, tuple[int, ...]]] = []
    end = length = 0
    for match in _INDEX.finditer(name):
        piece = name[end:match.start()]
        pieces.append(piece)
        length += len(piece)
        groups.append((length, tuple(int(i) for i in match.group(1).split(","))))
        end = match.end()
    pieces.append(name[end:])
    return "".join(pieces), tuple(groups)


@dataclass(frozen=True)
class _ArrayColumns:
    """The columns an array name stands for, in Modelica's (row-major) order, and its size."""

    name: str
    shape: tuple[int, ...]
    elements: tuple[str, ...]


def _free_indices(groups: _Indices, fixed: _Indices) -> tuple[int, ...] | None:
    """The indices of a column left open by the indices ``fixed`` of a name asked for
    (None: the column is not an element of that name).

    ``cell[2].x`` (fixed ``((4, (2,)),)``) leaves ``(3,)`` of ``cell[2].x[3]`` open;
    ``A[1]`` leaves ``(2,)`` of ``A[1,2]`` (a row of a matrix).
    """
    own = dict(groups)
    given = dict(fixed)
    for position, indices in fixed:
        found = own.get(position)
        if found is None or found[:len(indices)] != indices:
            return None
    return tuple(i for position, indices in groups for i in indices[len(given.get(position, ())):])


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

    Arrays are stored element by element, one column each, under Modelica's
    names (``x[1]``, ``A[1,2]``, ``cell[3].T``), and read back whole by the
    name without the indices: ``result["x"]`` is ``(len(time), n)``,
    ``result["A"]`` ``(len(time), n, m)``, ``result["cell.T"]`` (an array of
    components) ``(len(time), n)``, elements in index order.  A row or an
    element's array is read with its leading indices given (``A[1]``,
    ``cell[2].x``).  :attr:`arrays` lists them; :meth:`info`, :meth:`unit`,
    :meth:`describe`, :meth:`in_unit`, :meth:`at` and :meth:`final` take
    array names, and the name lists of :meth:`to_pandas`, :meth:`to_csv`,
    :meth:`to_mat`, :meth:`summary` and :meth:`plot` stand an array name for
    its elements.  A name that is a column is always read as that column.

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
        """Every column's name, in the order of :attr:`columns` (array names: :attr:`arrays`)."""
        return tuple(self.columns)

    # -- arrays ------------------------------------------------------------------------

    def _array_table(self) -> tuple[dict[str, list[tuple[str, _Indices]]],
                                    dict[str, _ArrayColumns | KeyError | None]]:
        """The columns with indices by their name without them, and the names resolved so
        far (an array, the error of elements that fill none, or None); built on first use,
        again when columns were added."""
        cached = self.__dict__.get("_arrays")
        if cached is None or cached[0] != len(self.columns):
            table: dict[str, list[tuple[str, _Indices]]] = {}
            for column in self.columns:
                if "[" in column:
                    key, groups = _split_indices(column)
                    if groups:
                        table.setdefault(key, []).append((column, groups))
            cached = (len(self.columns), table, {})
            object.__setattr__(self, "_arrays", cached)  # a cache, not a field: frozen stays frozen
        return cached[1], cached[2]

    def __getstate__(self) -> dict:
        state = dict(self.__dict__)
        state.pop("_arrays", None)  # a copy builds its own
        return state

    def _array(self, name: str) -> _ArrayColumns | None:
        """The array ``name`` stands for, None when it names none.

        ``cell.T`` for the columns ``cell[1].T`` ... ``cell[n].T``; ``x`` for
        ``x[1]`` ...; ``A`` for ``A[1,1]`` ... ``A[n,m]``; ``cell.x`` for
        ``cell[i].x[j]`` (size ``(n, m)``); ``A[2]`` for a row and ``cell[2].x``
        for one element's array; ``der(x)`` for ``der(x[1])`` ...

        Raises
        ------
        KeyError
            When the elements found do not fill a rectangular array (arrays
            of different sizes in the elements of an array of components).
        """
        table, resolved = self._array_table()
        if name in resolved:
            found = resolved[name]
        else:
            found = resolved[name] = self._resolve_array(name, table)
        if isinstance(found, KeyError):
            raise found
        return found

    def _resolve_array(self, name: str, table: Mapping[str, list[tuple[str, _Indices]]]
                       ) -> _ArrayColumns | KeyError | None:
        key, fixed = _split_indices(name)
        found = []
        for column, groups in table.get(key, ()):
            free = _free_indices(groups, fixed)
            if free:
                found.append((free, column))
        if not found:
            return None
        found.sort()  # numeric: x[10] after x[9]
        complete = len({len(free) for free, _ in found}) == 1
        shape = tuple(max(free[d] for free, _ in found) for d in range(len(found[0][0]))) if complete else ()
        # indices from 1, each once, every one up to the largest: a full array
        complete = complete and (min(min(free) for free, _ in found) >= 1
                                 and len({free for free, _ in found}) == len(found) == math.prod(shape))
        if not complete:
            return KeyError(f"{name!r} names {len(found)} elements of {self.model_name or 'this model'} "
                            f"({found[0][1]} ... {found[-1][1]}) that do not fill a rectangular array; "
                            f"read them by name")
        return _ArrayColumns(name, shape, tuple(column for _, column in found))

    @property
    def arrays(self) -> dict[str, tuple[int, ...]]:
        """Every array whose elements are columns, by name, with its size.

        ``{"cell.T": (10,), "x": (3,), "A": (2, 2), "der(x)": (3,)}``: the
        names :meth:`__getitem__`, :meth:`at`, :meth:`info` and the others
        read as one array (rows and elements' arrays, ``A[1]``, ``cell[2].x``,
        are not listed but read too).
        """
        table, _ = self._array_table()
        shapes = {}
        for key in table:
            if key in self.columns:
                continue
            try:
                found = self._array(key)
            except KeyError:
                continue  # elements of different sizes: no array
            if found is not None:
                shapes[key] = found.shape
        return shapes

    def elements(self, name: str) -> tuple[str, ...]:
        """The columns ``name`` stands for, in Modelica's order (row-major, indices numeric).

        ``result.elements("cell.T")`` is ``("cell[1].T", ..., "cell[10].T")``;
        for a column, ``(name,)``.

        Raises
        ------
        KeyError
            For a name that is neither a column nor an array, with the close names.
        """
        if name in self.columns:
            return (name,)
        found = self._array(name)
        if found is None:
            raise self._unknown(name)
        return found.elements

    def _expand(self, names: Sequence[str]) -> list[str]:
        """``names`` with every array name replaced by its elements (other names kept, for
        the caller's KeyError)."""
        out: list[str] = []
        for name in names:
            found = None
            if name not in self.columns:
                try:
                    found = self._array(name)
                except KeyError:
                    pass
            out.extend(found.elements if found is not None else (name,))
        return out

    def _expand_units(self, units: Mapping[str, str]) -> dict[str, str]:
        """A mapping of names to units with every array name replaced by its elements."""
        return {element: unit for name, unit in units.items() for element in self._expand([name])}

    # -- reading columns ---------------------------------------------------------------

    def _unknown(self, name: str) -> KeyError:
        """A KeyError for ``name`` that suggests the names it may have meant."""
        import difflib

        known = list(self.columns)
        table, _ = self._array_table()
        arrays = [key for key in table if key not in self.columns]
        close = difflib.get_close_matches(name, known + arrays, n=3)
        if not close:
            # a name given without its component path ("w"), or with another case
            tail = [n for n in known if n.rpartition(".")[2] == name.rpartition(".")[2]]
            folded = [n for n in known + arrays if n.lower() == name.lower()]
            close = (folded + tail)[:3]
        hint = f"; did you mean {', '.join(close)}?" if close else ""
        key, indices = _split_indices(name)
        if indices and key in table:  # an index out of range
            try:
                found = self._array(key)
            except KeyError:
                found = None
            if found is not None:
                hint = (f"; {key} is an array of {'x'.join(map(str, found.shape))}, "
                        f"{found.elements[0]} ... {found.elements[-1]}")
        if name.lower() == TIME_NAME:
            hint = "; the time is result.time"
        return KeyError(f"{name!r} is not a variable of {self.model_name or 'this model'}{hint}")

    def _kind(self, column: str) -> str:
        """The kind of a column (without building the descriptions when they are not built)."""
        table = self.column_info
        if isinstance(table, _ColumnTable):
            return table.kind(column)
        found = table.get(column)
        return found.kind if found is not None else "continuous"

    def __getitem__(self, name: str) -> np.ndarray:
        """The values of the column ``name``, or of the array ``name`` as one array.

        An array's values have the shape ``(len(time),) + size``: ``result["cell.T"]``
        is ``(len(time), n)`` for the columns ``cell[1].T`` ... ``cell[n].T``, ``result["A"]``
        ``(len(time), n, m)`` for ``A[1,1]`` ... ``A[n,m]`` (see :attr:`arrays`).
        """
        try:
            values = self.columns[name]
        except KeyError:
            found = self._array(name)
            if found is None:
                raise self._unknown(name) from None
            return self._array_values(found)
        return _typed(values, self._kind(name))

    def _array_values(self, found: _ArrayColumns) -> np.ndarray:
        """The elements' columns as one array, ``(len(time),) + size``: bool or int when all
        elements are Booleans or Integers, else float."""
        kinds = {self._kind(column) for column in found.elements}
        kind = kinds.pop() if len(kinds) == 1 else "continuous"
        data = np.column_stack([np.asarray(self.columns[column], dtype=float) for column in found.elements])
        return _typed(data, kind).reshape((data.shape[0],) + found.shape)

    def __contains__(self, name: str) -> bool:
        """Whether ``name`` is a column or an array (what ``result[name]`` reads)."""
        if name in self.columns:
            return True
        try:
            return self._array(name) is not None
        except KeyError:
            return False

    def final(self, name: str) -> float | np.ndarray:
        """The last value of ``name`` as float; for an array, a float array of its size."""
        values = self[name]
        return float(values[-1]) if values.ndim == 1 else np.asarray(values[-1], dtype=float)

    def info(self, name: str) -> ColumnInfo:
        """What the column ``name`` is (``"time"`` included), or the array ``name``.

        An array's :class:`ColumnInfo` has its size as ``shape`` and what its
        elements share: their unit, description, kind, display unit.

        Raises
        ------
        KeyError
            For a name that is neither a column nor an array, with the close names.
        """
        if name == TIME_NAME and name not in self.columns:
            return ColumnInfo(TIME_NAME, TIME_UNIT, "time", "continuous")
        if name not in self.columns:
            found = self._array(name)
            if found is None:
                raise self._unknown(name)
            return self._array_info(found)
        found = self.column_info.get(name)
        return found if found is not None else ColumnInfo(name)

    def _array_info(self, found: _ArrayColumns) -> ColumnInfo:
        infos = [self.info(column) for column in found.elements]

        def shared(attribute: str, default: Any) -> Any:
            values = {getattr(info, attribute) for info in infos}
            return values.pop() if len(values) == 1 else default

        return ColumnInfo(found.name, shared("unit", ""), shared("description", ""),
                          shared("kind", "continuous"), shared("labels", ()), shared("display_unit", ""),
                          shared("nominal", 1.0), found.shape)

    def _one_unit(self, name: str, info: ColumnInfo) -> None:
        """Raise a ValueError when ``name`` is an array whose elements have different units."""
        if not info.shape or info.unit:
            return
        units = sorted({self.info(column).unit for column in self.elements(name)})
        if len(units) > 1:
            raise ValueError(f"the elements of {name} have different units ({', '.join(map(repr, units))}): "
                             f"read them one by one (result.elements({name!r}))")

    def unit(self, name: str) -> str:
        """The declared unit of ``name`` (``""`` when it has none); of an array, its elements' unit.

        Raises
        ------
        KeyError
            For an unknown name.
        ValueError
            For an array whose elements have different units.
        """
        info = self.info(name)
        self._one_unit(name, info)
        return info.unit

    def describe(self, name: str) -> str:
        """One line: name, unit, kind and description, e.g.
        ``inertia1.w [rad/s] continuous: Absolute angular velocity of component``; an array's
        says its size, ``cell.T [K] continuous, array of 10: Temperature of element``."""
        return self.info(name).line()

    # -- units -------------------------------------------------------------------------

    def display_unit(self, name: str) -> str:
        """The unit ``name`` is shown in by default: its declared display unit, else its unit.

        A declared display unit that cannot show the column's unit (a typo,
        another quantity) is not used: a ``UserWarning`` says why, and the
        declared unit is returned.  Booleans and Integers: ``""``.  An
        array's is its elements' (a ValueError when their units differ).
        """
        info = self.info(name)
        self._one_unit(name, info)
        if info.is_discrete:
            return ""
        if not info.display_unit or info.display_unit == info.unit:
            return info.unit
        try:
            _conversion(info.unit, info.display_unit, name)
        except ValueError as exc:
            warnings.warn(f"the declared display unit of {name} is not used: {exc}", UserWarning,
                          stacklevel=2)
            return info.unit
        return info.display_unit

    def in_unit(self, name: str, unit: str | None = None) -> np.ndarray:
        """The values of ``name`` converted to ``unit`` (default: its :meth:`display_unit`).

        ``result.in_unit("J1.w", "rpm")``; ``result.in_unit("time", "min")``;
        ``result.in_unit("cell.T", "degC")`` converts every element of an
        array (shaped as ``result["cell.T"]``).  The result itself keeps its
        values in the declared units.

        Raises
        ------
        KeyError
            For a name that is neither a column nor an array.
        ValueError
            For a unit that does not measure what the column's unit measures
            (naming both), for an unknown unit, for a unit asked of a
            Boolean or Integer, and for an array whose elements have
            different units.
        """
        info = self.info(name)
        self._one_unit(name, info)
        time_asked = name == TIME_NAME and name not in self.columns
        values = np.asarray(self.time, dtype=float) if time_asked else self[name]
        target = self.display_unit(name) if unit is None else unit
        if info.is_discrete:
            if unit is not None and unit not in ("", "1"):
                raise ValueError(f"{name} is {'a Boolean' if info.kind == 'boolean' else 'an Integer'}: "
                                 f"it has no unit to show in {unit!r}")
            return values
        factor, offset = _conversion(info.unit, target, name)
        if factor == 1.0 and offset == 0.0:
            return values
        return np.asarray(values, dtype=float) * factor + offset

    def shown_units(self, names: Sequence[str] | None = None,
                    units: bool | Mapping[str, str] = True) -> dict[str, str]:
        """The unit each of ``names`` (default: every column) is shown in.

        Parameters
        ----------
        names : sequence of str, optional
            Column names; an array name stands for its elements.
        units : bool or mapping of str to str
            True: each column's declared display unit (its unit when it has
            none); False: the declared units; a mapping: the declared display
            units, with these columns in these units (``{"J1.w": "rpm"}``).

        Returns
        -------
        dict of str to str
            By name, for the columns of ``names`` (Booleans and Integers: ``""``).

        Raises
        ------
        KeyError
            For a name (in ``names`` or ``units``) that is not a column.
        ValueError
            For a unit a column cannot be shown in, naming both units.
        """
        chosen = list(self.columns) if names is None else self._expand(names)
        given = self._expand_units(units) if isinstance(units, Mapping) else {}
        for name, unit in given.items():
            if not isinstance(unit, str):
                raise TypeError(f"the unit of {name} must be a str, not {type(unit).__name__}")
            self._check_unit(name, unit)
        shown = {}
        for name in chosen:
            info = self.info(name)
            if name in given:
                shown[name] = given[name]
            elif info.is_discrete:
                shown[name] = ""
            elif units is False:
                shown[name] = info.unit
            else:
                shown[name] = self.display_unit(name)
        return shown

    def _check_unit(self, name: str, unit: str) -> None:
        """Raise the error :meth:`in_unit` would, without converting any values."""
        info = self.info(name)
        if info.is_discrete:
            if unit not in ("", "1"):
                self.in_unit(name, unit)
            return
        _conversion(info.unit, unit, name)

    # -- values at any time ------------------------------------------------------------

    def at(self, t: float | Sequence[float] | np.ndarray, names: str | Sequence[str] | None = None, *,
           side: str = "right") -> Any:
        """The values at time ``t`` (a number or an array of times), between the output rows.

        Continuous Reals are interpolated linearly between the two rows around
        ``t``; discrete Reals, Booleans, Integers and parameters hold the value
        of the last row at or before ``t``.  At an event the result has two
        rows at one time (or more, see :attr:`time`): ``side="right"`` (the
        default) gives the right limit, the values just after the event (the
        last of those rows), ``side="left"`` the left limit, the values just
        before it (the first).  Away from events both give the same.

        The integrator's dense output is not kept (its interpolants cover the
        states only, in the discrete state of their step, and would take
        several times the rows' memory): between rows the error is that of
        linear interpolation, about ``interval**2 * |y''| / 8``.  For values
        exact to the solver's tolerance at given times, run with a smaller
        ``interval``.

        Parameters
        ----------
        t : float or array_like of float
            Times within the run's span, ``time[0] <= t <= time[-1]``.
        names : str or sequence of str, optional
            One column (the values are returned as they are) or several
            (default: every column; a dict is returned).  An array name
            (``"cell.T"``, see :attr:`arrays`) gives its elements' values
            as one array.
        side : {'right', 'left'}
            Which limit an event instant gives.

        Returns
        -------
        float, bool, int or ndarray, or dict of them
            For one name: a value (a number ``t``) or an array shaped as
            ``t``; for an array name, an array shaped as ``t`` followed by the
            array's size (``result.at(2.0, "cell.T")`` has the ``n`` values
            at ``t = 2``); for several: a dict of those by name.  In the
            declared units (:meth:`in_unit` converts).  Booleans as bool,
            Integers as int.

        Raises
        ------
        ValueError
            For a time outside the run's span (naming the span), a time that
            is not a finite number, an unknown ``side``, or a result without
            output points.
        KeyError
            For a name that is neither a column nor an array.
        """
        if side not in ("right", "left"):
            raise ValueError(f"side={side!r}: choose 'right' (the values just after an event) or "
                             f"'left' (just before it)")
        single = isinstance(names, str)
        chosen = list(self.columns) if names is None else [names] if single else list(names)
        arrays: dict[str, _ArrayColumns] = {}
        for name in chosen:
            if name not in self.columns:
                found = self._array(name)
                if found is None:
                    raise self._unknown(name)  # with the close names
                arrays[name] = found
        time = np.asarray(self.time, dtype=float)
        if len(time) == 0:
            raise ValueError(f"{self.model_name or 'the result'} has no output points to read")
        query = np.asarray(t, dtype=float)
        flat = np.atleast_1d(query).ravel()
        if not np.all(np.isfinite(flat)):
            raise ValueError(f"t = {flat[~np.isfinite(flat)][0]} is not a finite time")
        outside = (flat < time[0]) | (flat > time[-1])
        if outside.any():
            stopped = "" if self.success else f" (the run stopped early: {self.message.splitlines()[0]})"
            raise ValueError(f"t = {flat[outside][0]:.12g} is outside the run's span, "
                             f"t = {time[0]:.12g} .. {time[-1]:.12g} s{stopped}")
        after = np.searchsorted(time, flat, side="right")  # the first row later than t
        before = after - 1  # the last row at or before t: the right limit at an event
        if side == "left":
            first = np.searchsorted(time, flat, side="left")  # the first row at t, if any
            before = np.where(time[np.minimum(first, len(time) - 1)] == flat, first, before)
        following = np.minimum(before + 1, len(time) - 1)
        exact = time[before] == flat
        span = time[following] - time[before]
        with np.errstate(invalid="ignore", divide="ignore"):
            weight = np.where(exact | (span <= 0), 0.0, (flat - time[before]) / span)

        def picked(column: str) -> np.ndarray:
            """The values of ``column`` at the times asked, shaped as ``t``."""
            info = self.info(column)
            values = np.asarray(self.columns[column])
            if info.kind == "continuous":
                low, high = values[before], values[following]
                # exactly a row's value at a row (no 0 * inf); linear between rows
                chosen_values = np.where(weight == 0.0, low, low + (high - low) * weight)
            else:
                chosen_values = values[before]
            return _typed(np.asarray(chosen_values, dtype=float), info.kind).reshape(query.shape)

        out = {}
        for name in chosen:
            if name in arrays:  # the elements' values along a last axis (or axes) of the array's size
                found = arrays[name]
                stacked = np.stack([picked(column) for column in found.elements], axis=-1)
                out[name] = stacked.reshape(query.shape + found.shape)
            else:
                values = picked(name)
                # one time: a Python number (float, bool, int), as the docstring says
                out[name] = values[()].item() if query.ndim == 0 else values
        return out[chosen[0]] if single else out

    # -- printing values -----------------------------------------------------------

    def resolution(self, name: str) -> float | None:
        """The size below which a summary prints a value of ``name`` as 0 (declared units).

        The run's absolute tolerance for it: ``atol`` when the run was given
        one number, else ``rtol`` times the variable's nominal value, what the
        integrator allowed as error for a value near zero.  None for a
        parameter, a Boolean or an Integer, and for a result that does not
        record its tolerance (one read from a file): those are printed as
        they are.  Arrays are never changed.
        """
        info = self.info(name)
        if info.kind not in ("continuous", "discrete"):
            return None
        rtol, atol = self.stats.get("rtol"), self.stats.get("atol")
        if isinstance(atol, (int, float)) and not isinstance(atol, bool) and math.isfinite(atol) and atol >= 0:
            return float(atol)
        if isinstance(rtol, (int, float)) and not isinstance(rtol, bool) and math.isfinite(rtol) and rtol > 0:
            return float(rtol) * info.nominal
        return None

    def format_value(self, name: str, value: Any, unit: str | None = None) -> tuple[str, bool]:
        """``value`` (in the declared unit) of ``name`` as a summary prints it, in ``unit``
        (default: the display unit).

        Returns the text (six significant digits, the unit appended; a Boolean
        ``true``/``false``, an Integer with the name of its value) and whether
        the value was printed as 0 because it lies below :meth:`resolution`.
        """
        info = self.info(name)
        if info.kind == "boolean":
            return ("true" if bool(value) else "false"), False
        if info.kind == "integer":
            number = int(value) if np.isfinite(value) else value
            label = dict(info.labels).get(number)
            return (f"{number} ({label})" if label else f"{number}"), False
        target = self.display_unit(name) if unit is None else unit
        factor, offset = _conversion(info.unit, target, name)
        shown = float(value) * factor + offset
        tolerance = self.resolution(name)
        snapped = (tolerance is not None and shown != 0 and math.isfinite(shown)
                   and abs(shown) < tolerance * abs(factor))
        text = "0" if snapped or shown == 0 else f"{shown:.6g}"
        return (f"{text} {target}" if target and target != "1" else text), snapped

    def _summary_signals(self, shown: int) -> list[str]:
        """The signals a summary lists first: states, then Booleans and Integers, then the rest."""
        rank = {}
        for n in self.columns:
            info = self.info(n)
            if info.kind == "parameter" or n.startswith("der("):
                continue
            rank[n] = 0 if f"der({n})" in self.columns else 1 if info.is_discrete else 2
        return sorted(rank, key=rank.get)[:shown]

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
                  event_column: str | None = "event",
                  display_units: bool | Mapping[str, str] = False) -> "pandas.DataFrame":
        """The result as a DataFrame indexed by time (index name ``"time"``).

        Parameters
        ----------
        names : sequence of str, optional
            Columns to include (default: all, parameters too); an array name
            (``"cell.T"``) stands for its elements' columns.
        events : {'keep', 'last', 'first'}
            ``'keep'``: every row, an event instant appearing twice or more
            (left limit first, right limit last) so the index has duplicates;
            ``'last'``: one row per time, the last one (the right limit, the
            values after the event); ``'first'``: one row per time, the first
            one (the left limit, the values before it).
        event_column : str or None
            Name of a bool column that is True for the rows at an event
            instant (:attr:`event_rows`); None leaves it out.
        display_units : bool or mapping of str to str
            False (the default): the values in their declared units.  True:
            the columns that declare a display unit in it
            (``Variable(display_unit="rpm")``).  A mapping: as True, and these
            columns in these units, ``{"J1.w": "rpm", "T": "degC"}`` (see
            :meth:`shown_units`).

        Returns
        -------
        pandas.DataFrame
            Booleans as bool columns, Integers as int64, the rest float64.
            ``df.attrs`` holds ``"units"`` (the unit of each column's values
            in the frame), ``"descriptions"`` and ``"kinds"`` (dicts by
            column name, the time's unit under ``"time"``), ``"model"`` and
            ``"status"``.

        Raises
        ------
        KeyError
            For a name (in ``names`` or ``display_units``) that is not a column.
        ValueError
            For a display unit a column cannot be shown in, naming both units.
        """
        import pandas as pd  # lazily: ``import acausal`` stays light

        if events not in ("keep", "last", "first"):
            raise ValueError(f"events={events!r}: choose 'keep', 'last' or 'first'")
        chosen = list(self.columns) if names is None else self._expand(names)
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
        infos = {name: self.info(name) for name in chosen}
        units = (self.shown_units(chosen, display_units) if display_units is not False
                 else {n: i.unit for n, i in infos.items()})
        data: dict[str, np.ndarray] = {
            name: (self.in_unit(name, units[name]) if units[name] != infos[name].unit else self[name])[keep]
            for name in chosen}
        if event_column is not None:
            data[event_column] = self.event_rows[keep]
        frame = pd.DataFrame(data, index=pd.Index(time[keep], name=TIME_NAME), copy=False)
        frame.attrs = {
            "units": {TIME_NAME: TIME_UNIT, **{n: units[n] if not i.is_discrete else i.unit
                                               for n, i in infos.items()}},
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
        An array name (``"cell.T"``) is a panel with every element; in a
        group of names, its elements join the group (as do the keys of
        ``units=``).
        """
        if not _PLOTTER:
            raise RuntimeError("no plotter is registered: import acausal.tools.plotting first "
                               "(or call acausal.tools.plotting.plot(result, names))")
        if isinstance(options.get("units"), Mapping):
            options["units"] = self._expand_units(options["units"])
        return _PLOTTER[0](self, self._panels(names), **options)

    def _panels(self, names: str | Sequence[str | Sequence[str]] | None) -> Any:
        """The names :meth:`plot` gives the plotter: an array name as a panel of its elements."""
        if names is None:
            return None

        def entry(name: str) -> str | list[str]:
            elements = self._expand([name])
            return name if elements == [name] else elements

        if isinstance(names, str):
            shown = entry(names)
            return shown if isinstance(shown, str) else [shown]
        return [entry(n) if isinstance(n, str) else self._expand(list(n)) for n in names]

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
        and description; values in their display units, those below the run's
        tolerance as 0 (as :meth:`summary`)."""
        escape = html.escape
        status = _STATUS_WORDS.get(self.status, f"status {self.status}")
        rows = [("status", status), ("message", self.message), ("span", self._span()),
                ("points", str(len(self.time))), ("events", str(len(self.events))),
                ("signals", str(len(self.columns)))]
        head = "".join(f"<tr><th style='text-align:left'>{escape(k)}</th><td>{escape(v)}</td></tr>"
                       for k, v in rows)
        # the states first (their derivatives are columns), then Booleans and Integers
        signals = self._summary_signals(shown)
        body = []
        for name in signals:
            info = self.info(name)
            unit = self.display_unit(name)
            final = (self.format_value(name, self.columns[name][-1], unit or None)[0]
                     if len(self.time) else "nan")
            if unit and final.endswith(f" {unit}"):
                final = final[:-len(unit) - 1]  # the unit has a column of its own
            body.append("<tr>" + "".join(f"<td>{escape(c)}</td>" for c in (
                name, unit, info.kind, final, info.description)) + "</tr>")
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
            Columns to write (default: all); an array name stands for its elements.
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
        names = list(self.columns) if signals is None else self._expand(signals)
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
            columns = [np.asarray(self.time, dtype=float)] + [np.asarray(self.columns[n], dtype=float)
                                                              for n in names]
            handle.write(_csv_rows(columns, writer.dialect.lineterminator))

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
            Columns to write (default: all); an array name stands for its elements.

        Returns
        -------
        Path
            ``path``, written whole or not at all (as :meth:`to_csv`).
        """
        import scipy.io

        names = list(self.columns) if signals is None else self._expand(signals)
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

    def summary(self, signals: Sequence[str] | None = None, *, units: Mapping[str, str] | None = None,
                values: bool = True, shown: int = 8) -> str:
        """A few lines: status and message, counts, solver statistics, final values, notes.

        Parameters
        ----------
        signals : sequence of str, optional
            The signals whose final values are listed (default: the states,
            then Booleans and Integers, ``shown`` of them); an array name
            stands for its elements.
        units : mapping of str to str, optional
            Units to show some signals in, ``{"J1.w": "rpm"}``; these signals
            are listed too.  The others are shown in their display unit.
        values : bool
            List final values at all.
        shown : int
            How many signals are listed by default.

        Values whose size is below the run's absolute tolerance for them
        (:meth:`resolution`: ``rtol`` times the nominal value) are printed as
        0, since the run cannot tell them from 0; the arrays keep them.
        """
        lines = [f"{self.model_name}: {'ok' if self.success else 'FAILED'} — {self.message}",
                 f"  {_count(len(self.time), 'output point')}, {_count(len(self.events), 'event')}, "
                 f"{_count(len(self.modes), 'discrete state')} visited, "
                 f"{_count(self.compiled_modes, 'system')} compiled"]
        for key in ("steps", "rhs_evaluations", "translate_seconds", "simulate_seconds"):
            if key in self.stats:
                value = self.stats[key]
                lines.append(f"  {key}: {value:.4g}" if isinstance(value, float) else f"  {key}: {value}")
        if values and len(self.time):
            lines += self._final_values(signals, units or {}, shown)
        lines += [f"  note: {n}" for n in self.notes]
        return "\n".join(lines)

    def _final_values(self, signals: Sequence[str] | None, units: Mapping[str, str], shown: int) -> list[str]:
        """The summary's lines of final values (see :meth:`summary`)."""
        units = self._expand_units(units)
        chosen = self._expand(signals) if signals is not None else self._summary_signals(shown)
        chosen += [n for n in units if n not in chosen]
        if not chosen:
            return []
        shown_in = self.shown_units(chosen, units)
        width = max(map(len, chosen))
        lines = [f"  final values at t = {float(self.time[-1]):.6g} s:"]
        snapped = False
        for name in chosen:
            text, below = self.format_value(name, self.columns[name][-1], shown_in[name] or None)
            snapped |= below
            lines.append(f"    {name:<{width}}  {text}")
        if signals is None:
            rest = len(self._summary_signals(len(self.columns))) - len(self._summary_signals(shown))
            if rest > 0:
                lines.append(f"    ... and {_count(rest, 'more signal')}")
        if snapped:
            lines.append("    (0: smaller than the run's absolute tolerance, rtol x nominal; the arrays "
                         "keep the value)")
        return lines


def _count(n: int, noun: str) -> str:
    """``1 event``, ``2 events``."""
    return f"{n} {noun}" if n == 1 else f"{n} {noun}s"


def _csv_rows(columns: Sequence[np.ndarray], terminator: str) -> str:
    """The rows of equally long float ``columns`` as CSV text, each value as ``repr`` writes it.

    The shortest text that reads back as the same double is ``repr``; it is
    also the cost of writing a result (a 1,000-row result of 80 columns is
    80,000 calls).  A column is formatted once however often it appears
    (aliases share their values) and a constant column (a parameter) once
    per value, compared bit for bit so that -0.0 and 0.0 stay apart.
    """
    formatted: dict[bytes, list[str]] = {}
    texts = []
    for column in columns:
        bits = column.tobytes()
        text = formatted.get(bits)
        if text is None:
            as_int = column.view(np.int64)
            if len(column) and (as_int == as_int[0]).all():
                text = [repr(float(column[0]))] * len(column)
            else:
                text = list(map(repr, column.tolist()))
            formatted[bits] = text
        texts.append(text)
    if not texts or not len(texts[0]):
        return ""
    return terminator.join(map(",".join, zip(*texts))) + terminator


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
