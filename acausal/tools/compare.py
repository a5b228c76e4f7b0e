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
from dataclasses import dataclass, field
from pathlib import Path
from types import MappingProxyType
from typing import Literal

import numpy as np

from ..errors import ReferenceDataError

__all__ = [
    "DEFAULT_REL_TOL",
    "DEFAULT_NOMINAL",
    "Reference",
    "SignalComparison",
    "Comparison",
    "reference_dir",
    "bundled_reference_dir",
    "load_reference",
    "tube_size",
    "tube",
    "compare_signals",
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

#: Largest reference CSV file read, in bytes (of a ``.csv.gz``: decompressed).
_MAX_CSV_BYTES = 512 * 2**20
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
    """
    compressed = path.name.endswith(".gz")
    lines = []
    with _open_regular(path, _MAX_CSV_BYTES) as raw:
        try:
            with (gzip.GzipFile(fileobj=raw, mode="rb") if compressed else raw) as stream:
                reader = csv.reader(_csv_lines(path, stream, compressed))
                for row in reader:
                    if row and not row[0].lstrip().startswith("#") and any(cell.strip() for cell in row):
                        lines.append((reader.line_num, row))
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
    if not lines:
        raise ReferenceDataError(f"{path} is empty", hint="the file should start with a header line")

    header_line, header = lines[0]
    names = [cell.strip().strip("'\"") for cell in header]
    spelled = [name for name in names if name.lower() == "time"]
    if "time" not in names and len(spelled) == 1:
        names[names.index(spelled[0])] = "time"  # newer Dymola versions write "Time"
    if "" in names:
        raise ReferenceDataError(
            f"{path}, line {header_line}: column {names.index('') + 1} has no name",
            hint="the first line must name every column, e.g. \"time\",\"inertia1.w\"",
        )
    duplicates = sorted({name for name in names if names.count(name) > 1})
    if duplicates:
        raise ReferenceDataError(
            f"{path}, line {header_line}: column name(s) {', '.join(duplicates)} appear twice",
            hint="check the delimiter; csv-compare files are comma separated",
        )
    if "time" not in names:
        raise ReferenceDataError(
            f"{path} has no 'time' column (columns: {', '.join(names[:5])}{', ...' if len(names) > 5 else ''})",
            hint="the first line must name the columns, starting with \"time\"",
        )

    rows = lines[1:]
    if len(rows) < 2:
        raise ReferenceDataError(
            f"{path} has {len(rows)} data line(s); a reference curve needs at least 2",
            hint="the file may be truncated; download it again",
        )
    for number, row in rows:
        if len(row) != len(names):
            raise ReferenceDataError(
                f"{path}, line {number}: {len(row)} values for {len(names)} columns",
                hint="every line must hold one value per column; the file may be truncated",
            )

    data = _parse_numbers(path, names, rows)
    if not np.all(np.isfinite(data)):
        line_index, column = np.argwhere(~np.isfinite(data))[0]
        raise ReferenceDataError(
            f"{path}, line {rows[line_index][0]}: {names[column]} is {data[line_index, column]}",
            hint="reference values must be finite numbers",
        )

    time = data[:, names.index("time")]
    backwards = np.flatnonzero(np.diff(time) < 0)
    if backwards.size:
        i = backwards[0]
        raise ReferenceDataError(
            f"{path}: time goes backwards from {time[i]!r} (line {rows[i][0]}) "
            f"to {time[i + 1]!r} (line {rows[i + 1][0]})",
            hint="reference time must be non-decreasing (events appear as two equal times)",
        )

    signals = {}
    for column, name in enumerate(names):
        values = np.ascontiguousarray(data[:, column])
        values.flags.writeable = False
        if name == "time":
            time = values
        else:
            signals[name] = values
    return time, signals


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
        names = names[1:]
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
class SignalComparison:
    """Outcome of the tube test for one signal.

    Attributes
    ----------
    name : str
        Signal name, e.g. ``"inertia3.w"``.
    passed : bool
        True if every checked point lies inside the tube.
    worst_violation : float
        Largest distance outside the tube, in units of ``dy``; 0 if inside
        everywhere, ``inf`` if the signal is missing or NaN.
    first_failure_time : float or None
        Time of the first point outside the tube (None if there is none).
    dy : float
        Tube half-height (absolute), the unit of ``worst_violation``.
    max_abs_error : float
        ``max |y - y_ref|`` at the reference's time points, for information
        (NaN where it cannot be computed).
    failed_points : int
        Number of checked points outside the tube.
    note : str
        Why the signal failed when it is not only a tube violation
        (missing signal, NaN values, result too short); else empty.
    """

    name: str
    passed: bool
    worst_violation: float
    first_failure_time: float | None
    dy: float
    max_abs_error: float
    failed_points: int = 0
    note: str = ""


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

    def table(self) -> str:
        """A plain-text table: one line per signal, then a summary line."""
        header = ("signal", "result", "worst [dy]", "first failure", "max |error|", "note")
        rows = [
            (
                s.name,
                "pass" if s.passed else "FAIL",
                _format_number(s.worst_violation),
                "-" if s.first_failure_time is None else f"{s.first_failure_time:.6g}",
                _format_number(s.max_abs_error),
                s.note,
            )
            for s in self.signals
        ]
        widths = [max(len(row[i]) for row in [header, *rows]) for i in range(len(header))]
        aligned = ["<", "<", ">", ">", ">", "<"]

        def line(cells) -> str:
            return "  ".join(f"{cell:{a}{w}}" for cell, a, w in zip(cells, aligned, widths)).rstrip()

        summary = (
            f"{self.modelica_class}: {len(self.signals) - len(self.failures)} of "
            f"{len(self.signals)} signals passed (tube test, relative tolerance {self.rel_tol:g})"
        )
        return "\n".join([line(header), line(["-" * w for w in widths]), *map(line, rows), summary])


def _format_number(value: float) -> str:
    """Short text for a table cell."""
    if math.isnan(value):
        return "-"
    if value == 0:
        return "0"
    return f"{value:.3g}"


def compare_signals(
    reference: Reference,
    time,
    values: Mapping[str, np.ndarray],
    signals: Iterable[str] | None = None,
    *,
    rel_tol: float = DEFAULT_REL_TOL,
    check_at: CheckAt = "result",
) -> Comparison:
    """Tube-test a simulation result against reference results.

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
        Which points are checked.  ``"result"`` (as csv-compare): the result's
        own samples against the tube at the result's times.  ``"reference"``:
        the result interpolated to the reference's times (at a reference
        event, the result's left or right limit when it has an event at the
        same time).  ``"both"``: the union, the strictest choice.

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

    outcomes = []
    for name in names:
        if name not in values:
            _, dy = tube_size(reference.time, reference.signals[name], rel_tol)
            outcomes.append(
                SignalComparison(
                    name=name, passed=False, worst_violation=math.inf, first_failure_time=None,
                    dy=dy, max_abs_error=math.nan, note="missing from the result",
                )
            )
            continue
        _, result_values = _as_curve(result_time, values[name], f"result signal {name}")
        outcome, _ = _compare_one(reference, name, result_time, result_values, rel_tol, check_at)
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


def plot_signal(
    reference: Reference,
    name: str,
    time,
    values,
    path: str | Path,
    *,
    rel_tol: float = DEFAULT_REL_TOL,
    check_at: CheckAt = "result",
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

    Returns
    -------
    Path
        ``path``.  Points outside the tube are marked with red crosses; the
        title names the signal and says PASS or FAIL.
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
    y = values[name] if isinstance(values, Mapping) else values
    result_time, result_values = _as_curve(time, y, f"result signal {name}")
    outcome, check = _compare_one(reference, name, result_time, result_values, rel_tol, check_at)

    ref_t, ref_y = reference.time, reference.signals[name]
    lower, upper = tube(ref_t, ref_y, rel_tol)

    figure = Figure(figsize=(9, 5))
    FigureCanvasAgg(figure)
    axes = figure.add_subplot()
    axes.fill_between(ref_t, lower, upper, color="tab:blue", alpha=0.2, linewidth=0, label="tube")
    axes.plot(ref_t, ref_y, color="tab:blue", linewidth=1, label="reference")
    axes.plot(result_time, result_values, color="tab:orange", linewidth=1, linestyle="--", label="result")
    bad = check.failed & np.isfinite(check.value)
    if np.any(bad):
        axes.plot(check.time[bad], check.value[bad], "x", color="red", markersize=5,
                  label=f"outside tube ({outcome.failed_points})")
    if outcome.passed:
        verdict = "PASS"
    elif outcome.first_failure_time is not None:
        verdict = (f"FAIL (worst {outcome.worst_violation:.3g} dy outside, "
                   f"first at t = {outcome.first_failure_time:.6g})")
    else:
        verdict = "FAIL"
    details = reference.modelica_class + (f"; {outcome.note}" if outcome.note else "")
    axes.set_title(f"{name}: {verdict}\n{textwrap.shorten(details, 110)}", fontsize=10)
    axes.set_xlabel("time")
    axes.set_ylabel(name)
    axes.grid(True, alpha=0.3)
    axes.legend(loc="best", fontsize=8)
    figure.tight_layout()

    path = Path(path)
    figure.savefig(path, dpi=100)
    return path
