"""Compare a simulation result with the Modelica Association reference results.

The Modelica Association checks every release of the Modelica Standard Library
(MSL) against reference results with its tool *csv-compare*
(github.com/modelica-tools/csv-compare).  This module re-implements that
*tube test* so that acausal can be held to the same standard.

The tube test
-------------
For a reference signal ``y_ref(t)`` on ``[t_start, t_end]`` and a relative
tolerance ``r`` (2e-3 for the MSL) csv-compare 2.1 builds a tube of

* half-width  ``dx = r * max(t_end - t_start, |t_start|, 1e-12)``, and
* half-height ``dy = r * max(y_max - y_min, |y_min|, 1e-3)``,

where ``y_max`` and ``y_min`` are taken over the whole reference signal (for
the usual ``t_start = 0`` the width is simply ``r * (t_end - t_start)``).
Picture a rectangle of ``2 dx`` by ``2 dy`` centred on every point of the
reference curve, the curve being linear between its samples.  The tube is
the region swept by that rectangle, so at a time ``t``

* ``lower(t) = min(y_ref on [t - dx, t + dx]) - dy``
* ``upper(t) = max(y_ref on [t - dx, t + dx]) + dy``.

Near a jump the tube therefore widens by ``dx`` on either side, so a result
whose event comes a little early or late still passes.  (csv-compare's
``Rectangle`` algorithm computes exactly these envelopes as polylines through
the rectangles' corners.)

A result passes when each of its values lies inside the tube (the bounds
themselves count as inside).  Like csv-compare, :func:`compare_signals` by
default checks the result's *own* samples against the tube evaluated at the
result's time points; ``check_at="reference"`` checks instead the result
interpolated to the reference's time points, ``check_at="both"`` checks both.

How far outside a point lies is measured in units of ``dy``::

    excess = max(lower - y, y - upper, 0) / dy

so a worst violation of 0 means "inside everywhere" and 1 means "one tube
half-height outside".

Discrete signals
----------------
A Boolean or an Integer (a mode, say) is judged by *when it changes*, not
by the tube: each change of the reference must be matched by a change of
the result to the same value within ``dx``, and farther than ``dx`` from the
reference's changes the values must be equal.  The table lists the times
the reference changes at instead of a meaningless ``max |error|``.  Which
signals are discrete comes from the model (:func:`signal_info`, the flat
variables' kinds) or from a Boolean or integer result column; the
reference must hold integers only.

Deliberate differences from csv-compare, which make the test stricter only:

* a result that does not cover the reference's time range (to within
  ``dx``) fails, where csv-compare silently checks the points it has;
* a NaN in the result fails, where csv-compare's comparisons let it pass;
* a signal missing from the result fails, where csv-compare skips it.

The MSL 4.0.0 reference results were produced for csv-compare 2.0.3, whose
half-height was ``r * max(0.0004 * (t_end - t_start), y_max - y_min +
|y_min|)`` (for ``t_start = 0``); csv-compare 2.1 replaced the sum by the
maximum above and introduced the nominal value 1e-3.  This module follows 2.1.

Reference data
--------------
The reference results come from github.com/modelica/MAP-LIB_ReferenceResults
(branch v4.1.0).  :func:`reference_dir` says where they are looked for: one
folder per Modelica class, for instance
``Modelica.Mechanics.Rotational.Examples.First/`` holding ``First.csv`` (or
``First.csv.gz``), ``comparisonSignals.txt`` and ``creation.txt``; the nested
layout of a MAP-LIB checkout (``Modelica/Mechanics/.../First/``) works too.

The references of the five bundled examples ship with acausal (in
``acausal.library``, folder ``reference/msl-4.1.0``, gzip-compressed; see its
README.md and LICENSE) and are used by default.  For other classes point
``ACAUSAL_REFERENCE_DIR`` (or ``--reference-dir``, or the ``directory``
argument) at a full MAP-LIB_ReferenceResults checkout.

Examples
--------
>>> ref = load_reference("Modelica.Mechanics.Rotational.Examples.First")  # doctest: +SKIP
>>> result = compare_signals(ref, t, {"inertia3.w": w3, ...})             # doctest: +SKIP
>>> print(result.table())                                                 # doctest: +SKIP
>>> plot_comparison(ref, t, {"inertia3.w": w3, ...}, "First.png",
...                 info=signal_info(model))                              # doctest: +SKIP
"""

from __future__ import annotations

import csv
import gzip
import importlib.util
import math
import os
import re
import stat
import textwrap
import zlib
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field, replace
from pathlib import Path
from time import perf_counter
from types import MappingProxyType
from typing import Literal

import numpy as np

from ..errors import ReferenceDataError

__all__ = [
    "DEFAULT_REL_TOL",
    "DEFAULT_NOMINAL",
    "Reference",
    "SignalInfo",
    "SignalComparison",
    "Comparison",
    "ComparisonReport",
    "ModelOutcome",
    "reference_dir",
    "bundled_reference_dir",
    "load_reference",
    "tube_size",
    "tube",
    "compare_signals",
    "signal_info",
    "comparison_figure",
    "plot_comparison",
    "plot_signal",
]

#: Relative tolerance the Modelica Association uses for the MSL (csv-compare ``--tolerance``).
DEFAULT_REL_TOL = 2e-3

#: Smallest y range csv-compare uses for the tube height, so that signals which
#: are zero up to round-off do not get an impossibly narrow tube.
DEFAULT_NOMINAL = 1e-3

#: Smallest x range (csv-compare's guard against a single time point).
_MIN_BASE_X = 1e-12

_ENV_VAR = "ACAUSAL_REFERENCE_DIR"
_SOURCE_HINT = (
    "the reference results come from github.com/modelica/MAP-LIB_ReferenceResults "
    "(branch v4.1.0); put the class's folder there or set the environment variable "
    f"{_ENV_VAR} to the folder that holds them"
)
_BUNDLED_HINT = (
    "only the references of the bundled examples ship with acausal; for other classes "
    "use a checkout of github.com/modelica/MAP-LIB_ReferenceResults (branch v4.1.0): "
    f"set the environment variable {_ENV_VAR} to its folder or pass --reference-dir"
)

CheckAt = Literal["result", "reference", "both"]

#: Largest reference CSV file read, in bytes (of a ``.csv.gz``: decompressed).  The largest
#: MAP-LIB reference is 3.4 MB; at this cap the numbers of the worst file (one-character
#: cells, 4x the text as float64) stay within 1 GiB.
_MAX_CSV_BYTES = 256 * 2**20
#: Lines of a reference CSV file converted to numbers at a time (the text held at once).
_BLOCK_ROWS = 4096
#: Largest ``comparisonSignals.txt`` or ``creation.txt`` read, in bytes.
_MAX_TEXT_BYTES = 2**20
#: Longest line of a reference CSV file, in bytes (a MAP-LIB line holds a few hundred).
_MAX_LINE_BYTES = 2**20
#: How far the CSV's first and last time may lie from creation.txt's StartTime and
#: StopTime, relative to ``max(StopTime - StartTime, |StartTime|, |StopTime|)``.
_TIME_RANGE_RTOL = 1e-6
_TEXT_HINT = "a reference file is UTF-8 text as in MAP-LIB_ReferenceResults; download the folder again"


# ---------------------------------------------------------------------------
# Where the reference data lives
# ---------------------------------------------------------------------------


def reference_dir(override: str | Path | None = None) -> Path:
    """The folder holding one sub-folder of reference results per Modelica class.

    Parameters
    ----------
    override : str or Path, optional
        Use this folder.

    Returns
    -------
    Path
        ``override`` if given, else the environment variable
        ``ACAUSAL_REFERENCE_DIR`` if set (and not empty), else the folder
        bundled with acausal (:func:`bundled_reference_dir`), which holds the
        references of the five bundled examples only.  The folder need not exist.
    """
    if override is not None:
        return Path(override)
    from_env = os.environ.get(_ENV_VAR)
    if from_env:
        return Path(from_env)
    return bundled_reference_dir()


def bundled_reference_dir() -> Path:
    """The reference results that ship with acausal: ``reference/msl-4.1.0`` in ``acausal.library``.

    Found without importing ``acausal.library`` (which would load the component
    libraries); in this repository it is ``library/reference/msl-4.1.0``.
    """
    spec = importlib.util.find_spec("acausal.library")
    if spec is not None and spec.submodule_search_locations:
        package = Path(next(iter(spec.submodule_search_locations)))
    else:  # not found as a package: fall back to the repository layout
        package = Path(__file__).resolve().parents[2] / "library"
    return package / "reference" / "msl-4.1.0"


# ---------------------------------------------------------------------------
# Loading reference results
# ---------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class Reference:
    """Reference results of one Modelica class.

    Attributes
    ----------
    modelica_class : str
        Full name, e.g. ``"Modelica.Mechanics.Rotational.Examples.First"``.
    time : numpy.ndarray
        Time points (read-only), non-decreasing; an event time appears twice
        (left and right limit).
    signals : Mapping[str, numpy.ndarray]
        Every column of the CSV file except ``time`` (read-only arrays).
    compared : tuple of str
        The signals the Modelica Association compares (``comparisonSignals.txt``).
    start_time, stop_time : float
        The experiment's StartTime and StopTime (``creation.txt``).
    interval : float or None
        The output Interval, if ``creation.txt`` gives one.
    tolerance : float or None
        The integrator Tolerance, if ``creation.txt`` gives one.
    path : Path
        The folder the data was read from.
    """

    modelica_class: str
    time: np.ndarray = field(repr=False)
    signals: Mapping[str, np.ndarray] = field(repr=False)
    compared: tuple[str, ...]
    start_time: float
    stop_time: float
    interval: float | None
    tolerance: float | None
    path: Path = field(repr=False)


def load_reference(modelica_class: str, directory: str | Path | None = None) -> Reference:
    """Read the reference results of one Modelica class.

    Parameters
    ----------
    modelica_class : str
        Full class name, which is also the name of its folder.
    directory : str or Path, optional
        Folder holding the class folders; see :func:`reference_dir` (default:
        ``ACAUSAL_REFERENCE_DIR``, else the references bundled with acausal).
        A class folder is named by the dotted class name, or nested by its
        parts as in a MAP-LIB_ReferenceResults checkout.  The results are read
        from ``<Name>.csv`` or, when that is absent, ``<Name>.csv.gz``.

    Returns
    -------
    Reference

    Raises
    ------
    ReferenceDataError
        If the folder or one of its files is missing or malformed, or a
        compared signal is not in the CSV file.  The message says which folder
        was searched.
    """
    root = reference_dir(directory)
    if not modelica_class or any(sep in modelica_class for sep in ("/", "\\")) or modelica_class.startswith("."):
        raise ReferenceDataError(
            f"{modelica_class!r} is not a Modelica class name",
            hint="pass the full dotted name, e.g. 'Modelica.Mechanics.Rotational.Examples.First'",
        )
    folder = root / modelica_class
    nested = root.joinpath(*modelica_class.split("."))
    if not folder.is_dir() and nested.is_dir():
        # a MAP-LIB_ReferenceResults checkout nests the class path in folders
        folder = nested
    if not folder.is_dir():
        bundled = root == bundled_reference_dir()
        where = (f"the references bundled with acausal ({root})" if bundled
                 else f"{root} (from {_source_of(directory)})")
        looked = (f"folder {folder} does not exist" if nested == folder
                  else f"neither folder {folder} nor {nested} exists")
        raise ReferenceDataError(
            f"no reference results for {modelica_class} in {where}: {looked}"
            + _available_classes(root),
            hint=_BUNDLED_HINT if bundled else _SOURCE_HINT,
        )

    csv_path = _find_csv(folder, modelica_class)
    time, signals = _read_csv(csv_path)
    compared = _read_comparison_signals(folder / "comparisonSignals.txt")
    missing = [name for name in compared if name not in signals]
    if missing:
        raise ReferenceDataError(
            f"{folder / 'comparisonSignals.txt'} lists {', '.join(missing)}, "
            f"which {'is' if len(missing) == 1 else 'are'} not a column of {csv_path}",
            hint="the reference folder is inconsistent; download it again",
        )
    settings = _read_creation(folder / "creation.txt")
    _check_time_range(csv_path, folder / "creation.txt", time, settings)

    return Reference(
        modelica_class=modelica_class,
        time=time,
        signals=MappingProxyType(signals),
        compared=compared,
        start_time=settings["StartTime"],
        stop_time=settings["StopTime"],
        interval=settings.get("Interval"),
        tolerance=settings.get("Tolerance"),
        path=folder,
    )


def _source_of(directory: str | Path | None) -> str:
    """Which setting chose the reference folder (for error messages)."""
    return "--reference-dir or the directory argument" if directory is not None else f"${_ENV_VAR}"


def _available_classes(root: Path) -> str:
    """A sentence listing the classes present under ``root`` (for error messages)."""
    if not root.is_dir():
        return f" (the reference folder {root} itself does not exist)"
    names = sorted(p.name for p in root.iterdir() if p.is_dir())
    if not names:
        return f" (the reference folder {root} is empty)"
    return f"; classes available in {root}: {', '.join(names)}"


def _find_csv(folder: Path, modelica_class: str) -> Path:
    """The CSV file of a class folder.

    ``<LastNamePart>.csv``, else ``<LastNamePart>.csv.gz``, else the only
    ``*.csv`` there, else the only ``*.csv.gz``.
    """
    expected = folder / f"{modelica_class.rsplit('.', 1)[-1]}.csv"
    compressed = expected.with_name(expected.name + ".gz")
    for path in (expected, compressed):
        if path.is_file():
            return path
    candidates = sorted(folder.glob("*.csv")) or sorted(folder.glob("*.csv.gz"))
    if len(candidates) == 1:
        return candidates[0]
    raise ReferenceDataError(
        f"reference results file {expected} (or {compressed.name}) not found"
        + (f" (and {folder} holds several CSV files)" if candidates else ""),
        hint=_SOURCE_HINT,
    )


def _read_csv(path: Path) -> tuple[np.ndarray, dict[str, np.ndarray]]:
    """Read a reference CSV file into a time array and read-only signal arrays.

    The first non-comment line holds the (possibly quoted) column names, one
    of which must be ``time``; every further non-empty line holds one number
    per column.  Lines starting with ``#`` are comments, as in csv-compare.
    A ``.gz`` file is decompressed while it is read.  The file must be a
    regular file (a symbolic link to one is fine) of UTF-8 text, at most
    ``_MAX_CSV_BYTES`` long (decompressed) with lines of at most
    ``_MAX_LINE_BYTES``.

    The numbers are converted block by block as the lines stream in (a block
    of ``_BLOCK_ROWS`` lines as text at a time), and kept per column: the
    memory held is that of the numbers (8 bytes each) plus one block, never
    the text of the whole file (a list of the text cells took 32 times the
    decompressed size).
    """
    compressed = path.name.endswith(".gz")
    names: list[str] | None = None
    pieces: list[list[np.ndarray]] = []   # per column, the blocks converted so far
    block: list[list[str]] = []
    block_lines: list[int] = []
    first_lines: list[int] = []           # the line number of the first row of each block
    rows = 0

    def convert() -> None:
        nonlocal rows
        data = _parse_numbers(path, names, list(zip(block_lines, block)))
        for column, values in zip(pieces, data.T):
            column.append(np.array(values))  # a copy: the block's array goes
        first_lines.append(block_lines[0])
        rows += len(block)
        block.clear()
        block_lines.clear()

    with _open_regular(path, _MAX_CSV_BYTES) as raw:
        try:
            with (gzip.GzipFile(fileobj=raw, mode="rb") if compressed else raw) as stream:
                reader = csv.reader(_csv_lines(path, stream, compressed))
                for row in reader:
                    if not row or row[0].lstrip().startswith("#") or not any(cell.strip() for cell in row):
                        continue
                    if names is None:
                        names = _column_names(path, reader.line_num, row)
                        pieces = [[] for _ in names]
                        continue
                    if len(row) != len(names):
                        raise ReferenceDataError(
                            f"{path}, line {reader.line_num}: {len(row)} values for {len(names)} columns",
                            hint="every line must hold one value per column; the file may be truncated",
                        )
                    block.append(row)
                    block_lines.append(reader.line_num)
                    if len(block) == _BLOCK_ROWS:
                        convert()
        except csv.Error as error:
            raise ReferenceDataError(
                f"{path}, line {reader.line_num}: {error}",
                hint="a reference result is a comma-separated file with one short line per time point",
            ) from None
        except (gzip.BadGzipFile, EOFError, zlib.error) as error:
            raise ReferenceDataError(
                f"{path} cannot be decompressed: {error}",
                hint="the file may be truncated or not gzip-compressed; copy it again",
            ) from None
        except OSError as error:
            raise ReferenceDataError(f"{path} cannot be read: {error}", hint=_SOURCE_HINT) from None
    if names is None:
        raise ReferenceDataError(f"{path} is empty", hint="the file should start with a header line")
    if block:
        convert()
    if rows < 2:
        raise ReferenceDataError(
            f"{path} has {rows} data line(s); a reference curve needs at least 2",
            hint="the file may be truncated; download it again",
        )

    def line_of(index: int) -> int:
        """The file's line number of data row ``index`` (rows of a block are consecutive lines
        up to blank and comment lines: exact for the first of a block, else the block's)."""
        k = index // _BLOCK_ROWS
        return first_lines[k] + (index - k * _BLOCK_ROWS)

    columns = {}
    for name, column in zip(names, pieces):
        values = np.concatenate(column) if len(column) > 1 else column[0]
        column.clear()  # the blocks go as the column is built
        bad = np.flatnonzero(~np.isfinite(values))
        if bad.size:
            raise ReferenceDataError(
                f"{path}, line {line_of(int(bad[0]))}: {name} is {values[bad[0]]}",
                hint="reference values must be finite numbers",
            )
        values.flags.writeable = False
        columns[name] = values

    time = columns.pop("time")
    backwards = np.flatnonzero(np.diff(time) < 0)
    if backwards.size:
        i = int(backwards[0])
        raise ReferenceDataError(
            f"{path}: time goes backwards from {time[i]!r} (line {line_of(i)}) "
            f"to {time[i + 1]!r} (line {line_of(i + 1)})",
            hint="reference time must be non-decreasing (events appear as two equal times)",
        )
    return time, columns


def _column_names(path: Path, line: int, header: list[str]) -> list[str]:
    """The column names of a reference CSV's header line, checked (``time`` among them)."""
    names = [cell.strip().strip("'\"") for cell in header]
    spelled = [name for name in names if name.lower() == "time"]
    if "time" not in names and len(spelled) == 1:
        names[names.index(spelled[0])] = "time"  # newer Dymola versions write "Time"
    if "" in names:
        raise ReferenceDataError(
            f"{path}, line {line}: column {names.index('') + 1} has no name",
            hint="the first line must name every column, e.g. \"time\",\"inertia1.w\"",
        )
    duplicates = sorted({name for name in names if names.count(name) > 1})
    if duplicates:
        raise ReferenceDataError(
            f"{path}, line {line}: column name(s) {', '.join(duplicates)} appear twice",
            hint="check the delimiter; csv-compare files are comma separated",
        )
    if "time" not in names:
        raise ReferenceDataError(
            f"{path} has no 'time' column (columns: {', '.join(names[:5])}{', ...' if len(names) > 5 else ''})",
            hint="the first line must name the columns, starting with \"time\"",
        )
    return names


def _parse_numbers(path: Path, names: list[str], rows: list[tuple[int, list[str]]]) -> np.ndarray:
    """Convert the CSV cells to floats, naming the first cell that is not a number."""
    try:
        return np.array([row for _, row in rows], dtype=float)
    except ValueError:
        pass
    # Slow path, only to find the offending cell for the message.
    for number, row in rows:
        for name, cell in zip(names, row):
            try:
                float(cell)
            except ValueError:
                raise ReferenceDataError(
                    f"{path}, line {number}: value {cell!r} of column {name} is not a number",
                    hint="reference values must be numbers (booleans as 0/1)",
                ) from None
    raise ReferenceDataError(f"{path}: cannot read the values as numbers", hint="check the file's format")


def _read_comparison_signals(path: Path) -> tuple[str, ...]:
    """Read ``comparisonSignals.txt``: ``time`` on the first line, then one name per line."""
    if not path.exists():
        raise ReferenceDataError(
            f"{path} not found; it lists the signals to compare",
            hint=_SOURCE_HINT,
        )
    names = [line.strip() for line in _read_text(path).splitlines()]
    names = [name for name in names if name]
    if names and names[0] == "time":
        # 'time' alone: the Modelica Association's reference compares no signal (a
        # model whose check is that it runs, e.g. ModelicaTest.Tables.CombiTable2Ds.Test15)
        return tuple(names[1:])
    if not names:
        raise ReferenceDataError(
            f"{path} lists no signals",
            hint="the file should hold 'time' on its first line, then one signal name per line",
        )
    return tuple(names)


# `StopTime=1 // from model` -- a key, '=', a number, maybe a // comment.
_SETTING = re.compile(r"^\s*(StartTime|StopTime|Interval|Tolerance)\s*[=:]\s*([^\s/;]+)")


def _read_creation(path: Path) -> dict[str, float]:
    """Read the experiment settings from ``creation.txt``.

    The file holds ``Key=value`` lines (comments after ``//``) among other
    text; StartTime and StopTime are required, Interval and Tolerance optional.
    """
    if not path.exists():
        raise ReferenceDataError(
            f"{path} not found; it holds the experiment settings (StartTime, StopTime, ...)",
            hint=_SOURCE_HINT,
        )
    settings: dict[str, float] = {}
    for number, line in enumerate(_read_text(path).splitlines(), start=1):
        match = _SETTING.match(line)
        if match is None:
            continue
        key, text = match.groups()
        try:
            settings[key] = float(text)
        except ValueError:
            raise ReferenceDataError(
                f"{path}, line {number}: {key} = {text!r} is not a number",
                hint="expected a line such as 'StopTime=1 // from model'",
            ) from None
        if not math.isfinite(settings[key]):
            raise ReferenceDataError(
                f"{path}, line {number}: {key} = {text!r} is not a finite number",
                hint="expected a line such as 'StopTime=1 // from model'",
            )
    missing = [key for key in ("StartTime", "StopTime") if key not in settings]
    if missing:
        raise ReferenceDataError(
            f"{path} does not give {' and '.join(missing)}",
            hint="expected lines such as 'StartTime=0' and 'StopTime=1'",
        )
    return settings


def _check_time_range(csv_path: Path, creation_path: Path, time: np.ndarray,
                      settings: Mapping[str, float]) -> None:
    """The CSV's time column must run from creation.txt's StartTime to its StopTime.

    Within ``_TIME_RANGE_RTOL`` of ``max(StopTime - StartTime, |StartTime|,
    |StopTime|)`` (as csv-compare's time base, so that times written in single
    precision still pass); a mismatch means a truncated file, or files of
    different runs.
    """
    start, stop = settings["StartTime"], settings["StopTime"]
    if not stop > start:
        raise ReferenceDataError(
            f"{creation_path}: StopTime = {stop!r} is not after StartTime = {start!r}",
            hint="creation.txt is malformed; download the folder again",
        )
    tolerance = _TIME_RANGE_RTOL * max(stop - start, abs(start), abs(stop))
    first, last = float(time[0]), float(time[-1])
    if abs(first - start) > tolerance or abs(last - stop) > tolerance:
        raise ReferenceDataError(
            f"{csv_path}: the time column runs from {first!r} to {last!r}, but {creation_path} "
            f"gives StartTime = {start!r} and StopTime = {stop!r}",
            hint="the CSV file may be truncated, or the files come from different runs; "
                 "download the class folder again",
        )


# ---------------------------------------------------------------------------
# Reading reference files safely
# ---------------------------------------------------------------------------


def _open_regular(path: Path, limit: int):
    """``path`` opened for reading bytes, if it is a regular file of at most ``limit`` bytes.

    Symbolic links are followed.  A FIFO, a device (``/dev/zero``), a directory
    or a socket is refused before it is read (a FIFO is opened without
    blocking, and checked again once open).
    """
    try:
        info = os.stat(path)
        if not stat.S_ISREG(info.st_mode):
            raise _not_regular(path, info.st_mode)
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_BINARY", 0))
    except OSError as error:
        raise ReferenceDataError(f"{path} cannot be read: {error.strerror or error}",
                                 hint=_SOURCE_HINT) from None
    try:
        info = os.fstat(fd)  # the file opened may not be the one examined
        if not stat.S_ISREG(info.st_mode):
            raise _not_regular(path, info.st_mode)
        if info.st_size > limit:
            raise ReferenceDataError(
                f"{path} is {_size(info.st_size)} long; a reference file of this kind may have "
                f"at most {_size(limit)}",
                hint="check that the reference folder holds reference results and nothing else",
            )
        return os.fdopen(fd, "rb")
    except BaseException:
        os.close(fd)
        raise


def _not_regular(path: Path, mode: int) -> ReferenceDataError:
    kinds = ((stat.S_ISDIR, "a directory"), (stat.S_ISFIFO, "a FIFO (named pipe)"),
             (stat.S_ISCHR, "a character device"), (stat.S_ISBLK, "a block device"),
             (stat.S_ISSOCK, "a socket"))
    kind = next((text for test, text in kinds if test(mode)), "not a regular file")
    link = f" (a symbolic link to {os.path.realpath(path)})" if os.path.islink(path) else ""
    return ReferenceDataError(
        f"{path}{link} is not a regular file: it is {kind}",
        hint="a reference file must be a regular file (a symbolic link to one is fine)",
    )


def _size(size: int) -> str:
    return f"{size / 2**20:.3g} MiB" if size >= 2**20 else f"{size} bytes"


def _read_text(path: Path, limit: int | None = None) -> str:
    """A small text file (``comparisonSignals.txt``, ``creation.txt``), checked and decoded."""
    limit = _MAX_TEXT_BYTES if limit is None else limit
    with _open_regular(path, limit) as stream:
        try:
            data = stream.read(limit + 1)
        except OSError as error:
            raise ReferenceDataError(f"{path} cannot be read: {error}", hint=_SOURCE_HINT) from None
    if len(data) > limit:
        raise ReferenceDataError(f"{path} is longer than {_size(limit)}",
                                 hint="check that the reference folder holds reference results")
    return _decode(path, data, 1)


def _csv_lines(path: Path, stream, compressed: bool):
    """The lines of a CSV file as text, each checked (length, NUL bytes, UTF-8), with the total size.

    A line broken by a lone carriage return (old Mac files) is split there,
    as Python's universal newlines would.
    """
    total = 0
    number = 0
    while True:
        raw = stream.readline(_MAX_LINE_BYTES + 1)
        if not raw:
            return
        number += 1
        total += len(raw)
        if total > _MAX_CSV_BYTES:
            raise ReferenceDataError(
                f"{path} holds more than {_size(_MAX_CSV_BYTES)}{' decompressed' if compressed else ''}, "
                f"more than a reference file may have",
                hint="check that the reference folder holds reference results and nothing else",
            )
        if len(raw) > _MAX_LINE_BYTES:
            raise ReferenceDataError(
                f"{path}, line {number}: longer than {_size(_MAX_LINE_BYTES)}",
                hint="a reference result has one short line per time point; this is not one",
            )
        text = _decode(path, raw, number)
        if "\r" in text.rstrip("\r\n"):
            pieces = _LINE_BREAK.findall(text)
            number += len(pieces) - 1
            yield from pieces
        else:
            yield text


_LINE_BREAK = re.compile(r"[^\r\n]*(?:\r\n|\r|\n)|[^\r\n]+$")


def _decode(path: Path, data: bytes, first_line: int) -> str:
    """``data`` (lines of ``path`` from ``first_line`` on) as text: UTF-8, a BOM allowed at the start."""
    if first_line == 1:
        if data.startswith((b"\xff\xfe", b"\xfe\xff")):
            raise ReferenceDataError(f"{path} is UTF-16 text, not UTF-8",
                                     hint="convert it to UTF-8 (e.g. iconv -f UTF-16 -t UTF-8)")
        if data.startswith(b"\xef\xbb\xbf"):
            data = data[3:]
    nul = data.find(b"\0")
    if nul >= 0:
        line = first_line + data.count(b"\n", 0, nul)
        raise ReferenceDataError(
            f"{path}, line {line}: NUL byte; this is a binary (or UTF-16) file, not UTF-8 text",
            hint=_TEXT_HINT,
        )
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as error:
        line = first_line + data.count(b"\n", 0, error.start)
        raise ReferenceDataError(
            f"{path}, line {line}: not UTF-8 text (byte 0x{data[error.start]:02x}); "
            f"the file may be binary or in another encoding",
            hint=_TEXT_HINT,
        ) from None


# ---------------------------------------------------------------------------
# The tube
# ---------------------------------------------------------------------------


def _check_time(time, what: str) -> np.ndarray:
    """Check and convert a time grid: non-empty, 1-D, finite, non-decreasing."""
    t = np.asarray(time, dtype=float)
    if t.ndim != 1 or t.size == 0:
        raise ValueError(f"{what}: time must be a non-empty 1-D array, got shape {t.shape}")
    if not np.all(np.isfinite(t)):
        raise ValueError(f"{what}: time contains NaN or infinity")
    if np.any(np.diff(t) < 0):
        raise ValueError(f"{what}: time must be non-decreasing (events as repeated times)")
    return t


def _as_curve(time, values, what: str = "reference") -> tuple[np.ndarray, np.ndarray]:
    """Check and convert a curve: 1-D float arrays of equal length, time non-decreasing."""
    t = _check_time(time, what)
    y = np.asarray(values, dtype=float)
    if y.shape != t.shape:
        raise ValueError(f"{what}: {t.size} time points but values of shape {y.shape}")
    return t, y


def tube_size(time, values, rel_tol: float = DEFAULT_REL_TOL) -> tuple[float, float]:
    """Half-width ``dx`` and half-height ``dy`` of the tube around a reference curve.

    Parameters
    ----------
    time, values : array_like
        The reference curve.
    rel_tol : float
        Relative tolerance (csv-compare ``--tolerance``).

    Returns
    -------
    dx, dy : float
        ``dx = rel_tol * max(t_end - t_start, |t_start|, 1e-12)`` and
        ``dy = rel_tol * max(y_max - y_min, |y_min|, 1e-3)``.
    """
    t, y = _as_curve(time, values)
    if not np.all(np.isfinite(y)):
        raise ValueError("reference: values contain NaN or infinity")
    base_x = max(t[-1] - t[0], abs(t[0]), _MIN_BASE_X)
    base_y = max(y.max() - y.min(), abs(y.min()), DEFAULT_NOMINAL)
    return rel_tol * float(base_x), rel_tol * float(base_y)


def tube(time, values, rel_tol: float = DEFAULT_REL_TOL, at=None) -> tuple[np.ndarray, np.ndarray]:
    """Lower and upper bound of the csv-compare tube around a reference curve.

    Parameters
    ----------
    time, values : array_like
        The reference curve (time non-decreasing; an event is a repeated time).
    rel_tol : float
        Relative tolerance; see :func:`tube_size`.
    at : array_like, optional
        Times to evaluate the bounds at (any order); default: ``time``.

    Returns
    -------
    lower, upper : numpy.ndarray
        ``min`` / ``max`` of the piecewise-linear reference over
        ``[t - dx, t + dx]``, minus / plus ``dy``.  NaN where that window
        misses the reference entirely (``t`` more than ``dx`` outside it).
    """
    t, y = _as_curve(time, values)
    dx, dy = tube_size(t, y, rel_tol)
    query = t if at is None else np.asarray(at, dtype=float)
    window_min, window_max = _window_min_max(t, y, query, dx)
    return window_min - dy, window_max + dy


def _window_min_max(t: np.ndarray, y: np.ndarray, query: np.ndarray, dx: float) -> tuple[np.ndarray, np.ndarray]:
    """Min and max of the piecewise-linear curve (t, y) over ``[q - dx, q + dx]`` for each q.

    A linear piece takes its extremes at its ends, so the extremes over a
    window are among (a) the samples inside the window and (b) the curve's
    values at the window's two ends, where these fall inside the data range.
    """
    query = np.asarray(query, dtype=float)
    start, stop = query - dx, query + dx
    # Samples t[first:last] are exactly those with start <= t <= stop.
    first = np.searchsorted(t, start, side="left")
    last = np.searchsorted(t, stop, side="right")

    lowest = np.full(query.shape, np.nan)
    highest = np.full(query.shape, np.nan)
    some = last > first
    if np.any(some):
        lowest[some] = _RangeExtreme(y, np.minimum).query(first[some], last[some])
        highest[some] = _RangeExtreme(y, np.maximum).query(first[some], last[some])

    # Window ends strictly between two samples: t[first-1] < start <= t[first]
    # and t[last-1] <= stop < t[last].  The two samples differ in time, so the
    # interpolation is well defined even on a grid with repeated event times.
    for after, end in ((first, start), (last, stop)):
        inside = (after > 0) & (after < t.size)
        if not np.any(inside):
            continue
        value = _interpolate_between(t, y, after[inside] - 1, after[inside], end[inside])
        # fmin/fmax ignore the NaN of windows that hold no sample.
        lowest[inside] = np.fmin(lowest[inside], value)
        highest[inside] = np.fmax(highest[inside], value)
    return lowest, highest


def _interpolate_between(t: np.ndarray, y: np.ndarray, i0: np.ndarray, i1: np.ndarray, at: np.ndarray) -> np.ndarray:
    """Linear interpolation at ``at`` on the pieces from sample ``i0`` to ``i1`` (``t[i0] < t[i1]``)."""
    weight = (at - t[i0]) / (t[i1] - t[i0])
    return y[i0] + weight * (y[i1] - y[i0])


class _RangeExtreme:
    """Min or max of ``values[first:last]`` for many ranges at once (a sparse table).

    ``levels[k][i]`` is the extreme of ``values[i : i + 2**k]``.  A range of
    length ``L`` is covered by two (overlapping) blocks of length
    ``2**floor(log2(L))``, so each query costs two look-ups, after an
    ``O(n log n)`` build.
    """

    def __init__(self, values: np.ndarray, combine) -> None:
        self._combine = combine
        self._levels = [np.asarray(values, dtype=float)]
        span = 1
        while 2 * span <= len(values):
            previous = self._levels[-1]
            self._levels.append(combine(previous[:-span], previous[span:]))
            span *= 2

    def query(self, first: np.ndarray, last: np.ndarray) -> np.ndarray:
        """Extreme of ``values[first[i]:last[i]]`` for each i; every range non-empty."""
        length = last - first
        level = np.floor(np.log2(length)).astype(int)
        result = np.empty(length.shape)
        for k in np.unique(level):
            pick = level == k
            table = self._levels[k]
            result[pick] = self._combine(table[first[pick]], table[last[pick] - (1 << k)])
        return result


# ---------------------------------------------------------------------------
# Comparing a result with the reference
# ---------------------------------------------------------------------------


@dataclass(frozen=True)
class SignalInfo:
    """What the model says about one compared signal (its unit, kind, value names).

    Attributes
    ----------
    unit : str
        The variable's unit, e.g. ``"rad/s"``; empty if it has none or it is not known.
    kind : str
        The flat variable's kind (``FlatVariable.kind``): ``"continuous"``,
        ``"discrete"`` (a Real changed at events only), ``"boolean"`` or
        ``"integer"``; empty if not known (then the kind is read from the values).
    labels : Mapping[int, str]
        Names of the values of an Integer or Boolean, e.g. ``{0: "Stuck", 1: "Forward"}``;
        empty if none are known.
    """

    unit: str = ""
    kind: str = ""
    labels: Mapping[int, str] = field(default_factory=dict)


@dataclass(frozen=True)
class SignalComparison:
    """Outcome of the comparison of one signal.

    A continuous signal is tube-tested.  A discrete signal (a Boolean or an
    Integer) is judged by its changes: each change of the reference must be
    matched, within ``dx``, by a change of the result to the same value, and
    away from the reference's changes (farther than ``dx``) the values must
    be equal.

    Attributes
    ----------
    name : str
        Signal name, e.g. ``"inertia3.w"``.
    passed : bool
        True if every checked point lies inside the tube (continuous), or
        every change is matched and the values agree (discrete).
    worst_violation : float
        Largest distance outside the tube, in units of ``dy``; 0 if inside
        everywhere, ``inf`` if the signal is missing or NaN.  (For a discrete
        signal the tube test's figure too, for information only.)
    first_failure_time : float or None
        Time of the first point outside the tube, or (discrete) of the first
        unmatched change or differing value; None if there is none.
    dy : float
        Tube half-height (absolute), the unit of ``worst_violation``.
    max_abs_error : float
        ``max |y - y_ref|`` at the reference's time points, for information
        (NaN where it cannot be computed).
    failed_points : int
        Number of checked points outside the tube (discrete: points whose
        value differs plus changes not matched).
    note : str
        Why the signal failed when it is not only a tube violation
        (missing signal, NaN values, result too short); for a discrete signal
        also the times at which it changes.
    discrete : bool
        Whether the signal was judged as a discrete signal.
    dx : float
        Tube half-width (seconds): how far a change may lie from the reference's.
    unit : str
        The signal's unit, if known (see :class:`SignalInfo`).
    reference_changes : tuple of float
        Times at which the reference changes (discrete signals).
    result_changes : tuple of float
        Times at which the result changes (discrete signals).
    unmatched_changes : tuple of float
        Reference changes the result does not make within ``dx`` (discrete signals).
    """

    name: str
    passed: bool
    worst_violation: float
    first_failure_time: float | None
    dy: float
    max_abs_error: float
    failed_points: int = 0
    note: str = ""
    discrete: bool = False
    # Facts about the signal and the tube rather than the verdict: left out of ==.
    dx: float = field(default=math.nan, compare=False)
    unit: str = field(default="", compare=False)
    reference_changes: tuple[float, ...] = field(default=(), compare=False)
    result_changes: tuple[float, ...] = field(default=(), compare=False)
    unmatched_changes: tuple[float, ...] = field(default=(), compare=False)


#: Column headers of :meth:`Comparison.table`, and what each means (the legend).
_COLUMNS = (
    ("signal", "the compared variable"),
    ("result", "a continuous signal passes when every point lies inside the tube, a discrete one "
               "(Boolean, Integer) when it makes each change of the reference within dx and has its "
               "values elsewhere"),
    ("outside tube [dy]", "how far the worst point lies outside the tube, in tube half-heights dy "
                          "(0: inside everywhere; - for discrete signals)"),
    ("first failure [s]", "time of the first point outside the tube, or of the first change not matched"),
    ("max |error|", "largest |result - reference| at the reference's time points, in the signal's "
                    "unit, for information only (- for discrete signals)"),
    ("note", "why a signal failed beyond the tube; for a discrete signal the times it changes at "
             "(0.5x2: two changes within dx of 0.5)"),
)


@dataclass(frozen=True)
class Comparison:
    """Outcome of the tube test for all compared signals of one Modelica class.

    Attributes
    ----------
    modelica_class : str
        The class whose reference results were used.
    signals : tuple of SignalComparison
        One entry per compared signal, in the reference's order.
    rel_tol : float
        Relative tolerance of the tube.
    """

    modelica_class: str
    signals: tuple[SignalComparison, ...]
    rel_tol: float = DEFAULT_REL_TOL

    @property
    def passed(self) -> bool:
        """True if every signal passed."""
        return all(signal.passed for signal in self.signals)

    @property
    def failures(self) -> tuple[SignalComparison, ...]:
        """The signals that failed."""
        return tuple(signal for signal in self.signals if not signal.passed)

    def __getitem__(self, name: str) -> SignalComparison:
        """The comparison of the signal called ``name``."""
        for signal in self.signals:
            if signal.name == name:
                return signal
        raise KeyError(f"{name!r} was not compared; compared: {', '.join(s.name for s in self.signals)}")

    def table(self, legend: bool = True) -> str:
        """A plain-text table: a header, one line per signal, the legend, then a summary line.

        Parameters
        ----------
        legend : bool
            Explain the columns and the tube's size below the table.
        """
        header = tuple(name for name, _ in _COLUMNS)
        rows = [
            (
                s.name,
                "pass" if s.passed else "FAIL",
                "-" if s.discrete else _format_number(s.worst_violation),
                "-" if s.first_failure_time is None else f"{s.first_failure_time:.6g}",
                "-" if s.discrete else _with_unit(_format_number(s.max_abs_error), s.unit),
                s.note,
            )
            for s in self.signals
        ]
        widths = [max(len(row[i]) for row in [header, *rows]) for i in range(len(header))]
        aligned = ["<", "<", ">", ">", ">", "<"]

        def line(cells) -> str:
            return "  ".join(f"{cell:{a}{w}}" for cell, a, w in zip(cells, aligned, widths)).rstrip()

        discrete = sum(s.discrete for s in self.signals)
        kinds = (f"; {_plural(discrete, 'discrete signal')} judged by the times "
                 f"{'it changes' if discrete == 1 else 'they change'}" if discrete else "")
        summary = (
            f"{self.modelica_class}: {len(self.signals) - len(self.failures)} of "
            f"{len(self.signals)} signals passed (tube test, relative tolerance {self.rel_tol:g}{kinds})"
        )
        lines = [line(header), line(["-" * w for w in widths]), *map(line, rows)]
        if legend:
            lines += self.legend().splitlines()
        return "\n".join([*lines, summary])

    def legend(self) -> str:
        """What the columns of :meth:`table` mean and how large the tube is, one line each."""
        dx = next((s.dx for s in self.signals if math.isfinite(s.dx)), math.nan)
        size = (f"tube: half-width dx = {dx:.4g} s (relative tolerance {self.rel_tol:g} of the time range), "
                f"half-height dy = {self.rel_tol:g} * max(y_max - y_min, |y_min|, {DEFAULT_NOMINAL:g}) "
                f"of the reference, per signal")
        if not math.isfinite(dx):
            size = size.replace(f"dx = {dx:.4g} s", "dx")
        explained = [f"  {name}: {meaning}" for name, meaning in _COLUMNS[1:]]
        return "\n".join(["legend:", *explained, f"  {size}"])


# ---------------------------------------------------------------------------
# Several models: one table, one legend
# ---------------------------------------------------------------------------

#: Column headers of :class:`ComparisonReport`'s table, and what each means (its legend).
_MODEL_COLUMNS = (
    ("model", "the model compared"),
    ("result", "pass: every compared signal passed; FAIL: some did not; run failed: the simulation "
               "stopped early (what it computed was compared); error: the model could not be loaded, "
               "translated or compared; interrupted: not compared"),
    ("signals", "passing / compared"),
    ("outside tube [dy]", "the worst distance of a continuous signal outside its tube, in tube "
                          "half-heights dy (0: inside everywhere)"),
    ("first failure [s]", "the earliest time a signal left its tube or missed a change of the reference"),
    ("time [s]", "seconds spent on the model: loading, translating, simulating, comparing"),
    ("note", "the signals that failed, or why the model was not compared"),
)

#: Widths of the columns after the first, fixed so that rows can be printed as models finish.
_MODEL_WIDTHS = (11, 7, 17, 17, 8)


@dataclass(frozen=True)
class ModelOutcome:
    """One model's row in a :class:`ComparisonReport`.

    Attributes
    ----------
    model : str
        How the model was named (``FILE.py:Class``).
    comparison : Comparison or None
        None when the model was not compared.
    result : str
        ``'pass'``, ``'FAIL'``, ``'run failed'``, ``'error'`` or ``'interrupted'``.
    note : str
        Why it was not compared, or what else went wrong.
    seconds : float
    """

    model: str
    comparison: Comparison | None = None
    result: str = "error"
    note: str = ""
    seconds: float = math.nan

    @property
    def passed(self) -> bool:
        return self.result == "pass"

    def cells(self) -> tuple[str, ...]:
        comparison = self.comparison
        if comparison is None:
            signals = worst = first = "-"
        else:
            continuous = [s.worst_violation for s in comparison.signals if not s.discrete]
            failures = [s.first_failure_time for s in comparison.signals if s.first_failure_time is not None]
            signals = f"{len(comparison.signals) - len(comparison.failures)}/{len(comparison.signals)}"
            worst = _format_number(max(continuous)) if continuous else "-"
            first = f"{min(failures):.6g}" if failures else "-"
        note = self.note
        if comparison is not None and comparison.failures:
            names = [s.name for s in comparison.failures]
            failed = "failed: " + ", ".join(names[:3]) + (f" and {len(names) - 3} more" if len(names) > 3 else "")
            note = f"{failed}; {note}" if note else failed
        seconds = f"{self.seconds:.2f}" if math.isfinite(self.seconds) else "-"
        return (self.model, self.result, signals, worst, first, seconds, _one_line(note))


def _one_line(text: str, width: int = 120) -> str:
    """The first line of ``text``, cut to ``width`` characters."""
    line = text.strip().splitlines()[0] if text.strip() else ""
    return line if len(line) <= width else line[:width - 3] + "..."


class ComparisonReport:
    """What ``acausal compare`` prints for several models: a row per model, one legend.

    A row can be printed as soon as its model is done (:meth:`header`, then
    :meth:`start` and :meth:`add` for each model), since the columns' widths
    are fixed by the names of the models given; :meth:`table` is the whole
    table.

    Parameters
    ----------
    models : sequence of str
        The names of the models to compare, for the width of the first column.
    """

    def __init__(self, models: Iterable[str]) -> None:
        self.outcomes: list[ModelOutcome] = []
        self._widths = (max([len(_MODEL_COLUMNS[0][0]), *map(len, models)]), *_MODEL_WIDTHS)
        self._started: tuple[str, float, int] | None = None  # model, perf_counter, outcomes before

    def start(self, model: str) -> None:
        """The work on ``model`` begins (for its time column)."""
        self._started = (model, perf_counter(), len(self.outcomes))

    def _line(self, cells: Iterable[str]) -> str:
        aligned = "<<>>>>"
        cells = list(cells)
        fixed = "  ".join(f"{cell:{a}{w}}" for cell, a, w in zip(cells, aligned, self._widths))
        return f"{fixed}  {cells[-1]}".rstrip()

    def header(self) -> str:
        """The column headers and a rule under them (two lines)."""
        names = [name for name, _ in _MODEL_COLUMNS]
        return "\n".join([self._line(names), self._line(["-" * w for w in self._widths] + ["----"])])

    def add(self, outcome: ModelOutcome) -> str:
        """Record ``outcome``; returns its row.

        Its time is the time since :meth:`start` for the model unless it
        gives one; a second outcome for the model started replaces the first.
        """
        if self._started is not None and self._started[0] == outcome.model:
            if not math.isfinite(outcome.seconds):
                outcome = replace(outcome, seconds=perf_counter() - self._started[1])
            del self.outcomes[self._started[2]:]
        self.outcomes.append(outcome)
        return self.row()

    def row(self, index: int = -1) -> str:
        """The row of an outcome added (default: the last)."""
        return self._line(self.outcomes[index].cells())

    def has(self, model: str) -> bool:
        """Whether an outcome was added for ``model`` since it was started."""
        return (self._started is not None and self._started[0] == model
                and len(self.outcomes) > self._started[2])

    def table(self) -> str:
        """The header and a row per model added."""
        return "\n".join([self.header(), *(self._line(o.cells()) for o in self.outcomes)])

    @property
    def passed(self) -> int:
        """How many models passed."""
        return sum(o.passed for o in self.outcomes)

    def legend(self, signals: bool = False) -> str:
        """What the columns mean and how large the tubes are; with ``signals``, also the
        columns of the per-signal tables (``--verbose``)."""
        tolerances = sorted({o.comparison.rel_tol for o in self.outcomes if o.comparison is not None})
        relative = ", ".join(f"{t:g}" for t in tolerances) or f"{DEFAULT_REL_TOL:g}"
        lines = ["legend:", *(f"  {name}: {meaning}" for name, meaning in _MODEL_COLUMNS[1:])]
        if signals:
            lines += ["  per-signal tables:",
                      *(f"    {name}: {meaning}" for name, meaning in _COLUMNS[1:])]
        lines.append(f"  tube (relative tolerance r = {relative}): half-width dx = r * the reference's time "
                     f"range, half-height dy = r * max(y_max - y_min, |y_min|, {DEFAULT_NOMINAL:g}) of "
                     f"the reference, per signal")
        if not signals:
            lines.append("  every signal of each model: --verbose, or compare one model alone")
        return "\n".join(lines)


def _plural(count: int, noun: str) -> str:
    """``1 change``, ``2 changes``: the count with the noun in the right number."""
    return f"{count} {noun}" if count == 1 else f"{count} {noun}s"


def _with_unit(text: str, unit: str) -> str:
    """``0.0012 rad/s``; the text alone when there is no unit or no number."""
    return f"{text} {unit}" if unit and unit != "1" and text != "-" else text


def _format_number(value: float) -> str:
    """Short text for a table cell."""
    if math.isnan(value):
        return "-"
    if value == 0:
        return "0"
    return f"{value:.3g}"


def signal_info(model, names: Iterable[str] | None = None) -> dict[str, SignalInfo]:
    """Unit, kind and value names of a model's variables, for the comparison's table and plots.

    Parameters
    ----------
    model : Component, Translation or FlatModel
        The model (it is flattened here), its translation or its flat model.
    names : iterable of str, optional
        The variables wanted; default: every variable of the flat model.

    Returns
    -------
    dict of str to SignalInfo
        By variable name; names that are not variables of the flat model
        (aliases, say) are left out.

    Notes
    -----
    An Integer's values are named as the flat model names them
    (:func:`acausal.language.value_names`: the capitalised int constants of
    the declaring component's class, e.g. ``Stuck = 0``, ``Forward = 1``).
    A Boolean's values are named false and true.
    """
    if hasattr(model, "variables"):
        flat = model
    elif hasattr(model, "flat"):
        flat = model.flat
    else:
        from ..compiler.flatten import flatten

        flat = flatten(model)
    wanted = None if names is None else set(names)
    out = {}
    for variable in flat.variables:
        if wanted is not None and variable.name not in wanted:
            continue
        labels: dict[int, str] = {}
        if variable.kind == "boolean":
            labels = {0: "false", 1: "true"}
        elif variable.kind == "integer":
            labels = dict(variable.labels)
        out[variable.name] = SignalInfo(unit=variable.unit or "", kind=variable.kind, labels=labels)
    return out


def compare_signals(
    reference: Reference,
    time,
    values: Mapping[str, np.ndarray],
    signals: Iterable[str] | None = None,
    *,
    rel_tol: float = DEFAULT_REL_TOL,
    check_at: CheckAt = "result",
    info: Mapping[str, SignalInfo] | None = None,
) -> Comparison:
    """Compare a simulation result with reference results: the tube test, or change times for discrete signals.

    Parameters
    ----------
    reference : Reference
        From :func:`load_reference`.
    time : array_like
        The result's time points, non-decreasing (an event may appear twice).
    values : Mapping[str, array_like]
        The result's signals by name, each as long as ``time``.
    signals : iterable of str, optional
        Names to compare; default: ``reference.compared``.
    rel_tol : float
        Relative tolerance of the tube (the MSL uses 2e-3).
    check_at : {"result", "reference", "both"}
        Which points of a continuous signal are checked.  ``"result"`` (as
        csv-compare): the result's own samples against the tube at the
        result's times.  ``"reference"``: the result interpolated to the
        reference's times (at a reference event, the result's left or right
        limit when it has an event at the same time).  ``"both"``: the union,
        the strictest choice.
    info : Mapping[str, SignalInfo], optional
        Units and kinds of the signals (from :func:`signal_info`).  A signal
        whose kind is ``"boolean"`` or ``"integer"`` is judged as a discrete
        signal (when the reference holds integers only); without a known
        kind, one whose result column has a Boolean or integer type is.

    Returns
    -------
    Comparison

    Raises
    ------
    ValueError
        If ``time`` or a value array is malformed, or ``check_at`` unknown.
    ReferenceDataError
        If a requested signal is not in the reference data.
    """
    if check_at not in ("result", "reference", "both"):
        raise ValueError(f"check_at must be 'result', 'reference' or 'both', not {check_at!r}")
    names = reference.compared if signals is None else tuple(signals)
    unknown = [name for name in names if name not in reference.signals]
    if unknown:
        raise ReferenceDataError(
            f"{', '.join(unknown)} not in the reference results of {reference.modelica_class}",
            hint=f"available: {', '.join(reference.signals)}",
        )
    result_time = _check_time(time, "result")
    info = info or {}

    outcomes = []
    for name in names:
        if name not in values:
            dx, dy = tube_size(reference.time, reference.signals[name], rel_tol)
            outcomes.append(
                SignalComparison(
                    name=name, passed=False, worst_violation=math.inf, first_failure_time=None,
                    dy=dy, max_abs_error=math.nan, note="missing from the result", dx=dx,
                    unit=info.get(name, SignalInfo()).unit,
                )
            )
            continue
        _, result_values = _as_curve(result_time, values[name], f"result signal {name}")
        outcome, _, _ = _judge(reference, name, result_time, result_values, rel_tol, check_at,
                               info.get(name), values[name])
        outcomes.append(outcome)
    return Comparison(reference.modelica_class, tuple(outcomes), rel_tol)


@dataclass(frozen=True, eq=False)
class _Check:
    """Every checked point of one signal (shared by the comparison and the plot)."""

    time: np.ndarray
    value: np.ndarray
    lower: np.ndarray
    upper: np.ndarray
    excess: np.ndarray  # in units of dy; inf for NaN values
    dx: float
    dy: float

    @property
    def failed(self) -> np.ndarray:
        return self.excess > 0


def _check_points(reference: Reference, name: str, time: np.ndarray, y: np.ndarray,
                  rel_tol: float, check_at: CheckAt) -> _Check:
    """Evaluate the tube test of one signal at the points ``check_at`` selects."""
    ref_t, ref_y = reference.time, reference.signals[name]
    dx, dy = tube_size(ref_t, ref_y, rel_tol)

    times, points = [], []
    if check_at in ("result", "both"):
        times.append(time)
        points.append(y)
    if check_at in ("reference", "both"):
        times.append(ref_t)
        points.append(_sample(time, y, ref_t))
    t = np.concatenate(times)
    v = np.concatenate(points)
    order = np.argsort(t, kind="stable")
    t, v = t[order], v[order]

    window_min, window_max = _window_min_max(ref_t, ref_y, t, dx)
    # Points whose window misses the reference (more than dx outside its time
    # range) are not checked, as in csv-compare; NaN samples (reference times
    # the result does not reach) are dropped here and reported as "too short".
    keep = np.isfinite(window_min) & ~(np.isnan(v) & _outside(time, t))
    t, v = t[keep], v[keep]
    lower, upper = window_min[keep] - dy, window_max[keep] + dy
    with np.errstate(invalid="ignore"):
        excess = np.maximum(np.maximum(lower - v, v - upper), 0.0) / dy
    excess[np.isnan(v)] = math.inf
    return _Check(t, v, lower, upper, excess, dx, dy)


def _outside(result_time: np.ndarray, t: np.ndarray) -> np.ndarray:
    """True where ``t`` lies outside the result's time range."""
    return (t < result_time[0]) | (t > result_time[-1])


def _judge(reference: Reference, name: str, time: np.ndarray, y: np.ndarray, rel_tol: float,
           check_at: CheckAt, info: SignalInfo | None, raw=None
           ) -> tuple[SignalComparison, _Check, "_DiscreteCheck | None"]:
    """Compare one signal present in the result: as a discrete signal if it is one, else by the tube.

    Also returns the tube test's checked points, and the discrete test's
    findings (None for a continuous signal), for the plot.
    """
    outcome, check = _compare_one(reference, name, time, y, rel_tol, check_at)
    unit = info.unit if info is not None else ""
    if not _is_discrete(reference.signals[name], info, raw):
        return replace(outcome, unit=unit, dx=check.dx), check, None
    found = _compare_changes(reference.time, reference.signals[name], time, y, check.dx)
    # the coverage and NaN notes of the tube test hold for a discrete signal too
    notes = [text for text in outcome.note.split("; ") if text]
    outcome = replace(
        outcome,
        passed=found.passed and not notes,
        first_failure_time=found.first_failure_time,
        failed_points=int(found.mismatch_time.size + len(found.unmatched)),
        note="; ".join([found.describe(), *notes]),
        discrete=True,
        dx=check.dx,
        unit=unit,
        reference_changes=tuple(c.time for c in found.reference),
        result_changes=tuple(c.time for c in found.result),
        unmatched_changes=tuple(c.time for c in found.unmatched),
    )
    return outcome, check, found


def _is_discrete(reference_values: np.ndarray, info: SignalInfo | None, raw=None) -> bool:
    """Whether a signal is judged as a discrete signal.

    When the reference holds integers only, and the model declares the
    variable a Boolean or an Integer (``info.kind``), or, without a known
    kind, the result's column has a Boolean or integer type.  A float column
    of integer values alone does not make a signal discrete: a Real step
    from 0 to 1 keeps the tube test.
    """
    if not np.all(reference_values == np.round(reference_values)):
        return False
    if info is not None and info.kind:
        return info.kind in ("boolean", "integer")
    return raw is not None and np.asarray(raw).dtype.kind in "biu"


@dataclass(frozen=True)
class _Change:
    """A change of a discrete signal from ``before`` to ``after``, seen between ``start`` and ``stop``.

    At an event (two samples at one time) ``start == stop``; a signal sampled
    on a grid without event rows shows a change only between two sample times.
    """

    start: float
    stop: float
    before: float
    after: float

    @property
    def time(self) -> float:
        """The first time the new value is seen."""
        return self.stop

    def distance(self, other: "_Change") -> float:
        """Time between the two changes' intervals (0 if they overlap)."""
        return max(0.0, other.start - self.stop, self.start - other.stop)


def _changes(t: np.ndarray, y: np.ndarray) -> list[_Change]:
    """The changes of a discrete signal, those at one instant merged (first value to last)."""
    differ = np.flatnonzero((y[1:] != y[:-1]) & np.isfinite(y[1:]) & np.isfinite(y[:-1]))
    out: list[_Change] = []
    for i in differ:
        change = _Change(float(t[i]), float(t[i + 1]), float(y[i]), float(y[i + 1]))
        last = out[-1] if out else None
        # several passes of an event iteration at one instant are one change
        if (last is not None and last.start == last.stop == change.start == change.stop):
            out[-1] = _Change(last.start, last.stop, last.before, change.after)
        else:
            out.append(change)
    # a value that is left and resumed at the same instant did not change
    return [c for c in out if c.before != c.after]


@dataclass(frozen=True, eq=False)
class _DiscreteCheck:
    """What the comparison of a discrete signal found."""

    reference: list[_Change]
    result: list[_Change]
    unmatched: list[_Change]  # reference changes the result does not make within dx
    extra: list[_Change]      # result changes farther than dx from every reference change
    mismatch_time: np.ndarray   # checked points where the values differ
    mismatch_value: np.ndarray  # the result's value there
    dx: float

    @property
    def passed(self) -> bool:
        return not self.unmatched and self.mismatch_time.size == 0

    @property
    def first_failure_time(self) -> float | None:
        times = [c.time for c in self.unmatched] + self.mismatch_time[:1].tolist()
        return float(min(times)) if times else None

    def describe(self) -> str:
        """``changes at 0.2304 0.3083 (all within dx)``, or what went wrong."""
        if not self.reference:
            text = "no changes" + (", as the reference" if not self.result else "")
        else:
            text = f"changes at {_times(self.reference, self.dx)}"
            if not self.unmatched:
                text += " (all within dx)"
        if self.unmatched:
            text += f"; not matched within dx: {_times(self.unmatched, self.dx)}"
        if self.extra:
            text += f"; result also changes at {_times(self.extra, self.dx)}"
        elif self.mismatch_time.size:
            text += f"; values differ at {_plural(int(self.mismatch_time.size), 'point')}"
        return text


def _times(changes: list[_Change], dx: float, shown: int = 8) -> str:
    """``0.2304 0.3083x2 … (12 in all)``: the first change times, then how many there are.

    Changes closer than ``dx`` to the first of their group (a pulse within
    one event, say) would print as the same time; they are shown once, with
    their count.
    """
    groups: list[list[_Change]] = []
    for change in changes:
        if groups and change.time - groups[-1][0].time <= dx:
            groups[-1].append(change)
        else:
            groups.append([change])
    text = " ".join(f"{group[0].time:.5g}" + (f"x{len(group)}" if len(group) > 1 else "")
                    for group in groups[:shown])
    return text + (f" … ({len(changes)} in all)" if len(groups) > shown else "")


def _compare_changes(ref_t: np.ndarray, ref_y: np.ndarray, t: np.ndarray, y: np.ndarray,
                     dx: float) -> _DiscreteCheck:
    """Judge a discrete signal by its changes.

    Each change of the reference must be matched by a change of the result
    within ``dx`` to the same value (several changes of the result close
    together count if one of them reaches it), and at every sample time of
    either curve farther than ``dx`` from the reference's changes the two
    values must be equal.  The value between samples is the last sample's
    (a discrete signal holds its value).
    """
    reference, result = _changes(ref_t, ref_y), _changes(t, y)
    unmatched = [change for change in reference
                 if not any(c.after == change.after and c.distance(change) <= dx for c in result)]
    extra = [c for c in result if all(c.distance(r) > dx for r in reference)]

    # Every sample of both curves, away from the reference's changes.
    points = np.concatenate([t, ref_t])
    ours = np.concatenate([y, _hold(t, y, ref_t)])
    theirs = np.concatenate([_hold(ref_t, ref_y, t), ref_y])
    checked = (points >= ref_t[0]) & (points <= ref_t[-1]) & (points >= t[0]) & (points <= t[-1])
    if reference:
        starts = np.array([c.start for c in reference]) - dx
        stops = np.array([c.stop for c in reference]) + dx
        # the widened intervals are in order, their ends non-decreasing: the
        # last one starting before a point is the one that may hold it
        k = np.searchsorted(starts, points, side="right") - 1
        near = (k >= 0) & (points <= stops[np.maximum(k, 0)])
        checked &= ~near
    with np.errstate(invalid="ignore"):
        differ = checked & ~(ours == theirs)
    # a time both curves sample is one point, not two: unique (time, ours, reference) rows, in time order
    mismatches = np.unique(np.column_stack([points[differ], ours[differ], theirs[differ]]), axis=0)
    return _DiscreteCheck(
        reference=reference, result=result, unmatched=unmatched, extra=extra,
        mismatch_time=mismatches[:, 0], mismatch_value=mismatches[:, 1], dx=dx,
    )


def _hold(t: np.ndarray, y: np.ndarray, at: np.ndarray) -> np.ndarray:
    """Values of a held (piecewise constant) curve at the times ``at``: the last sample at or before.

    At an event (a repeated time) this is the value after it; NaN before the
    curve starts and after it ends.
    """
    index = np.searchsorted(t, at, side="right") - 1
    out = np.full(np.shape(at), np.nan)
    inside = (index >= 0) & (np.asarray(at) <= t[-1])
    out[inside] = y[index[inside]]
    return out


def _compare_one(reference: Reference, name: str, time: np.ndarray, y: np.ndarray,
                 rel_tol: float, check_at: CheckAt) -> tuple[SignalComparison, _Check]:
    """The tube test of one signal present in the result, and its checked points."""
    check = _check_points(reference, name, time, y, rel_tol, check_at)
    failed = check.failed
    notes = []
    if np.any(np.isnan(y)):
        notes.append("result contains NaN")

    # A result that stops early (or starts late) must not pass just because
    # the points it has are fine.
    ref_start, ref_stop = reference.time[0], reference.time[-1]
    if time[0] > ref_start + check.dx or time[-1] < ref_stop - check.dx:
        notes.append(f"result covers [{time[0]:g}, {time[-1]:g}] of [{ref_start:g}, {ref_stop:g}]")

    # For information only: the plain error at the reference times the result covers.
    errors = np.abs(_sample(time, y, reference.time) - reference.signals[name])
    covered = np.isfinite(errors)
    if np.any(np.isnan(y)) or not np.any(covered):
        max_abs_error = math.nan
    else:
        max_abs_error = float(np.max(errors[covered]))

    outcome = SignalComparison(
        name=name,
        passed=not np.any(failed) and not notes,
        worst_violation=float(np.max(check.excess)) if check.excess.size else (math.inf if notes else 0.0),
        first_failure_time=float(check.time[failed][0]) if np.any(failed) else None,
        dy=check.dy,
        max_abs_error=max_abs_error,
        failed_points=int(np.count_nonzero(failed)),
        note="; ".join(notes),
        dx=check.dx,
    )
    return outcome, check


def _sample(t: np.ndarray, y: np.ndarray, at: np.ndarray) -> np.ndarray:
    """Values of the curve (t, y) at the times ``at``, respecting events.

    Where the curve has samples exactly at a time of ``at``, the first
    occurrence of that time in ``at`` takes the curve's first sample there
    (left limit) and later occurrences take its last sample (right limit);
    a reference event pair thus meets the result's event pair side by side.
    Elsewhere the curve is interpolated linearly; outside its range: NaN.
    """
    at = np.asarray(at, dtype=float)
    left = np.searchsorted(t, at, side="left")
    right = np.searchsorted(t, at, side="right")
    out = np.full(at.shape, np.nan)

    exact = right > left
    first_occurrence = np.ones(at.shape, dtype=bool)
    first_occurrence[1:] = at[1:] != at[:-1]
    pick = np.where(first_occurrence, left, right - 1)
    out[exact] = y[pick[exact]]

    # Not a sample time: t[left-1] < at < t[left], two distinct times.
    between = ~exact & (left > 0) & (left < t.size)
    out[between] = _interpolate_between(t, y, left[between] - 1, left[between], at[between])
    return out


# ---------------------------------------------------------------------------
# Plotting
# ---------------------------------------------------------------------------

#: Height of one signal's panel in a model's figure, in inches.
_PANEL_HEIGHT = 2.1


def comparison_figure(
    reference: Reference,
    time,
    values: Mapping[str, np.ndarray],
    signals: Iterable[str] | None = None,
    *,
    info: Mapping[str, SignalInfo] | None = None,
    rel_tol: float = DEFAULT_REL_TOL,
    check_at: CheckAt = "result",
):
    """One figure for a model's comparison: a panel per compared signal, sharing the time axis.

    Parameters
    ----------
    reference : Reference
        From :func:`load_reference`.
    time : array_like
        The result's time points.
    values : Mapping[str, array_like]
        The result's signals by name.
    signals : iterable of str, optional
        The signals to draw; default: ``reference.compared``.
    info : Mapping[str, SignalInfo], optional
        Units, kinds and value names (from :func:`signal_info`): the y labels
        then carry units, and an Integer's ticks the names of its values.
    rel_tol, check_at
        As for :func:`compare_signals`.

    Returns
    -------
    matplotlib.figure.Figure
        With an Agg canvas (no pyplot state is touched).  Each panel shows
        the reference, the tube shaded between its bounds (for a discrete
        signal: the band of ``dx`` around each reference change), the result
        dashed, and failures as red crosses; its title says PASS or FAIL.
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    names = reference.compared if signals is None else tuple(signals)
    if not names:
        raise ValueError("no signals to plot")
    result_time = _check_time(time, "result")
    figure = Figure(figsize=(9, 0.9 + _PANEL_HEIGHT * len(names)), layout="constrained")
    FigureCanvasAgg(figure)
    axes = figure.subplots(len(names), 1, sharex=True, squeeze=False)[:, 0]
    outcomes = [
        _draw_panel(panel, reference, name, result_time, values, (info or {}).get(name), rel_tol, check_at)
        for panel, name in zip(axes, names)
    ]
    passed = sum(outcome.passed for outcome in outcomes)
    figure.suptitle(f"{reference.modelica_class}: {passed} of {len(outcomes)} signals passed "
                    f"(relative tolerance {rel_tol:g})", fontsize=11)
    axes[-1].set_xlabel("time [s]")
    return figure


def plot_comparison(
    reference: Reference,
    time,
    values: Mapping[str, np.ndarray],
    path: str | Path,
    signals: Iterable[str] | None = None,
    *,
    info: Mapping[str, SignalInfo] | None = None,
    per_signal: bool = False,
    rel_tol: float = DEFAULT_REL_TOL,
    check_at: CheckAt = "result",
) -> list[Path]:
    """Write a model's comparison figure (:func:`comparison_figure`) as a PNG, and per-signal files if asked.

    Parameters
    ----------
    reference, time, values, signals, info, rel_tol, check_at
        As for :func:`comparison_figure`.
    path : str or Path
        The PNG file of the whole figure.
    per_signal : bool
        Also write one PNG per signal beside it, named by the signal
        (``J1.w.png``; characters other than letters, digits, ``.``, ``_``
        and ``-`` become ``_``).  Signals missing from the result are skipped.

    Returns
    -------
    list of Path
        The files written, the model's figure first.
    """
    path = Path(path)
    names = reference.compared if signals is None else tuple(signals)
    figure = comparison_figure(reference, time, values, names, info=info, rel_tol=rel_tol,
                               check_at=check_at)
    figure.savefig(path, dpi=90)
    written = [path]
    if per_signal:
        for name in names:
            if name not in values:
                continue
            written.append(plot_signal(reference, name, time, values, path.parent / f"{_file_safe(name)}.png",
                                       rel_tol=rel_tol, check_at=check_at,
                                       info=(info or {}).get(name)))
    return written


def _file_safe(name: str) -> str:
    """A signal name as a file name: characters other than letters, digits, ``._-`` as ``_``."""
    return re.sub(r"[^A-Za-z0-9._-]+", "_", name)


def plot_signal(
    reference: Reference,
    name: str,
    time,
    values,
    path: str | Path,
    *,
    rel_tol: float = DEFAULT_REL_TOL,
    check_at: CheckAt = "result",
    info: SignalInfo | None = None,
) -> Path:
    """Plot one signal's reference, tube and result into a PNG file.

    Parameters
    ----------
    reference : Reference
        From :func:`load_reference`.
    name : str
        The signal to plot.
    time : array_like
        The result's time points.
    values : Mapping[str, array_like] or array_like
        The result's signals by name, or the values of ``name`` alone.
    path : str or Path
        The PNG file to write.
    rel_tol, check_at
        As for :func:`compare_signals`.
    info : SignalInfo, optional
        The signal's unit, kind and value names (see :func:`signal_info`).

    Returns
    -------
    Path
        ``path``.  Drawn as one panel of :func:`comparison_figure`; the title
        also names the Modelica class.
    """
    # Imported here so that comparing does not need matplotlib; the Agg
    # canvas draws to a file without touching pyplot's global state.
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    if name not in reference.signals:
        raise ReferenceDataError(
            f"{name} not in the reference results of {reference.modelica_class}",
            hint=f"available: {', '.join(reference.signals)}",
        )
    curves = values if isinstance(values, Mapping) else {name: values}
    figure = Figure(figsize=(9, 5), layout="constrained")
    FigureCanvasAgg(figure)
    axes = figure.add_subplot()
    _draw_panel(axes, reference, name, _check_time(time, "result"), curves, info, rel_tol, check_at,
                subtitle=reference.modelica_class)
    axes.set_xlabel("time [s]")
    path = Path(path)
    figure.savefig(path, dpi=100)
    return path


def _draw_panel(axes, reference: Reference, name: str, time: np.ndarray, values: Mapping,
                info: SignalInfo | None, rel_tol: float, check_at: CheckAt,
                subtitle: str = "") -> SignalComparison:
    """Draw one signal's comparison into ``axes``; return its outcome."""
    if name not in reference.signals:
        raise ReferenceDataError(
            f"{name} not in the reference results of {reference.modelica_class}",
            hint=f"available: {', '.join(reference.signals)}",
        )
    ref_t, ref_y = reference.time, reference.signals[name]
    unit = info.unit if info is not None else ""
    if name in values:
        _, y = _as_curve(time, values[name], f"result signal {name}")
        outcome, check, found = _judge(reference, name, time, y, rel_tol, check_at, info, values[name])
    else:
        dx, dy = tube_size(ref_t, ref_y, rel_tol)
        y, check, found = None, None, None
        outcome = SignalComparison(name, False, math.inf, None, dy, math.nan,
                                   note="missing from the result", dx=dx, unit=unit)

    if found is not None:
        _draw_discrete(axes, ref_t, ref_y, time, y, found, info)
    else:
        lower, upper = tube(ref_t, ref_y, rel_tol)
        axes.fill_between(ref_t, lower, upper, color="tab:blue", alpha=0.2, linewidth=0, label="tube")
        axes.plot(ref_t, ref_y, color="tab:blue", linewidth=1, label="reference")
        if y is not None:
            axes.plot(time, y, color="tab:orange", linewidth=1, linestyle="--", label="result")
            bad = check.failed & np.isfinite(check.value)
            if np.any(bad):
                axes.plot(check.time[bad], check.value[bad], "x", color="red", markersize=5,
                          label=f"outside tube ({outcome.failed_points})")

    if outcome.passed:
        verdict = "PASS"
    elif outcome.first_failure_time is not None:
        verdict = ("FAIL (first at t = " if outcome.discrete
                   else f"FAIL (worst {outcome.worst_violation:.3g} dy outside, first at t = ")
        verdict += f"{outcome.first_failure_time:.6g})"
    else:
        verdict = "FAIL"
    details = "; ".join(text for text in (subtitle, outcome.note) if text)
    title = f"{name}: {verdict}" + (f"\n{textwrap.shorten(details, 110)}" if details else "")
    axes.set_title(title, fontsize=9)
    axes.set_ylabel(f"{name} [{unit}]" if unit and unit != "1" else name, fontsize=8)
    axes.grid(True, alpha=0.3)
    axes.legend(loc="upper right", fontsize=7, framealpha=0.6)
    return outcome


def _draw_discrete(axes, ref_t: np.ndarray, ref_y: np.ndarray, time: np.ndarray, y: np.ndarray,
                   found: _DiscreteCheck, info: SignalInfo | None) -> None:
    """A discrete signal: steps, the band of ``dx`` around each reference change, value names as ticks."""
    for index, change in enumerate(found.reference):
        axes.axvspan(change.start - found.dx, change.stop + found.dx, color="tab:blue", alpha=0.2,
                     linewidth=0, label="reference change ± dx" if index == 0 else None)
    axes.plot(ref_t, ref_y, color="tab:blue", linewidth=1, drawstyle="steps-post", label="reference")
    axes.plot(time, y, color="tab:orange", linewidth=1, linestyle="--", drawstyle="steps-post", label="result")
    if found.unmatched:
        axes.plot([c.time for c in found.unmatched], [c.after for c in found.unmatched], "x", color="red",
                  markersize=7, label=f"change not matched ({len(found.unmatched)})")
    if found.mismatch_time.size:
        axes.plot(found.mismatch_time, found.mismatch_value, "x", color="red", markersize=5,
                  label=f"value differs ({found.mismatch_time.size})")

    levels = np.unique(np.concatenate([ref_y, y[np.isfinite(y)]]))
    labels = dict(info.labels) if info is not None else {}
    if levels.size and all(float(level).is_integer() and int(level) in labels for level in levels):
        axes.set_yticks(levels, [labels[int(level)] for level in levels], fontsize=8)
    elif levels.size <= 12:
        axes.set_yticks(levels, [f"{level:g}" for level in levels], fontsize=8)
    if levels.size:
        axes.set_ylim(levels[0] - 0.5, levels[-1] + 0.5)
