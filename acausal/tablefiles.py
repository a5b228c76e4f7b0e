"""Interpolation tables read from files, as the Modelica Standard Library reads them.

``Modelica.Blocks.Sources.CombiTimeTable`` and ``Modelica.Blocks.Tables.CombiTable1Ds``,
``1Dv``, ``2Ds`` and ``2Dv`` take their matrix from a file when ``tableOnFile = true``:
``fileName`` names the file (often through ``loadResource("modelica://...")``),
``tableName`` the matrix in it, and for CSV files ``delimiter`` and ``nHeaderLines``
say how to read it.  This module reads those files the way MSL 4.1.0 does
(``ModelicaIO.c`` and ``ModelicaStandardTables.c``):

* **Text** (any extension but ``.mat`` and ``.csv``): the first line starts with
  ``#1``, then each matrix is declared by a line ``double name(rows,columns)``
  (or ``float``), followed by its values in row-wise order.  The values are
  separated by blanks, tabs, commas or semicolons; a row may span several lines
  and a line may hold several rows; ``#`` starts a comment; a UTF-8 byte order
  mark is ignored.
* **MAT** (``.mat``): MATLAB v4, v6 and v7 files through :func:`scipy.io.loadmat`,
  v7.3 (HDF5) files through the optional ``h5py``.  A dotted table name such as
  ``"s.tab1"`` picks a field of a 1x1 struct.
* **CSV** (``.csv``): ``header_lines`` lines are skipped, every further line is
  a row, values are separated by ``delimiter`` (and blanks or tabs).  The table
  name is ignored: the whole file is the table.

:func:`load_resource` resolves ``modelica://`` and ``file://`` URIs the way
``Modelica.Utilities.Files.loadResource`` does, searching the package folders
under the roots of the ``MODELICAPATH`` environment variable
(:func:`modelica_path`).  :func:`usertab` stands for MSL's ``usertab.c``: tables
registered with :func:`register_usertab` are what a block with
``tableOnFile = true`` and ``fileName = "NoName"`` reads.

Every table comes back as a read-only two-dimensional float array; reads are
cached by file, modification time, size and reading options, so a model that
reads one file in several blocks reads it once.  Every problem raises
:class:`~acausal.errors.TableError` naming the file, the table and, where it
applies, the line, row and column, with a hint.

Where this reader differs from MSL 4.1.0, it is stricter about data that MSL
would use although it is almost certainly wrong, and lenient where MSL fails on
harmless layout:

* more values after a text table than its declared size is an error (MSL warns
  and uses the declared rows); a CSV row with more values than the first row is
  an error (MSL ignores the surplus); a nan or infinite entry is an error;
* blank lines in a CSV file are skipped, a UTF-8 byte order mark at the start of
  a CSV file is ignored, and the extensions ``.mat`` and ``.csv`` are recognised
  in any case (MSL knows only all-lower or all-upper case).
"""

from __future__ import annotations

import os
import pathlib
import re
import threading
import urllib.parse
import urllib.request
from bisect import bisect_right
from collections import OrderedDict
from typing import Any, Callable

import numpy as np

from .errors import TableError

__all__ = ["load_resource", "modelica_path", "read_table", "register_usertab", "usertab"]


# ---------------------------------------------------------------------------
# Resources: MODELICAPATH and modelica:// URIs
# ---------------------------------------------------------------------------

def modelica_path() -> list[pathlib.Path]:
    """The library roots listed in the ``MODELICAPATH`` environment variable.

    Returns
    -------
    list of pathlib.Path
        The roots in the order given, as Modelica tools search them; the
        entries are separated by :data:`os.pathsep` (``:`` on POSIX, ``;`` on
        Windows) and empty entries are skipped.  An unset variable gives ``[]``.
    """
    value = os.environ.get("MODELICAPATH", "")
    return [pathlib.Path(entry) for entry in value.split(os.pathsep) if entry.strip()]


def load_resource(uri: str) -> str:
    """The absolute path of a resource, as ``Modelica.Utilities.Files.loadResource``.

    Parameters
    ----------
    uri : str
        One of

        * ``"modelica://Package.Sub/path/in/package"``: the package is looked up
          as a folder ``<root>/Package`` (or a versioned folder such as
          ``<root>/Package 4.1.0``) under each root of :func:`modelica_path`, in
          order; each nested package is a sub-folder (a class stored in a file
          rather than a folder shares the folder of that file); the path that
          follows is relative to the folder of the innermost package and may be
          percent-encoded;
        * ``"file:///absolute/path"`` (percent-encoded as usual);
        * a plain path, absolute or relative to the working directory.

    Returns
    -------
    str
        The absolute file name.  For a ``modelica://`` URI, the first root whose
        package holds the file; if none holds it, the place in the first package
        found (so that an error about the missing file names that place).

    Raises
    ------
    TableError
        The URI is malformed, or no root of ``MODELICAPATH`` holds the package.
    """
    if isinstance(uri, os.PathLike):
        uri = os.fspath(uri)
    if not isinstance(uri, str) or not uri.strip():
        raise TableError(f"a file name or URI must be a non-empty string, not {uri!r}",
                         hint='give e.g. "modelica://Package/Resources/Data/table.txt" or a path')
    scheme = uri.split(":", 1)[0].lower() if ":" in uri else ""
    if scheme == "modelica":
        return _resolve_modelica_uri(uri)
    if scheme == "file":
        return _resolve_file_uri(uri)
    return os.path.abspath(uri)


_CLASS_NAME = re.compile(r"[^\W\d]\w*(?:\.[^\W\d]\w*)*")


def _resolve_modelica_uri(uri: str) -> str:
    """``modelica://Package.Sub/path`` -> the file under the first root that has it."""
    rest = uri.split(":", 1)[1]
    if not rest.startswith("//"):
        raise TableError(f'"{uri}" is not a Modelica URI of the form "modelica://Package/path"',
                         hint="write two slashes after \"modelica:\" and the package name after them")
    class_name, _, resource = rest[2:].partition("/")
    if not _CLASS_NAME.fullmatch(class_name):
        raise TableError(f'"{uri}" does not name a package after "modelica://" (found "{class_name}")',
                         hint='write the package as a dotted class name, e.g. "modelica://Modelica.Blocks/..."')
    packages = class_name.split(".")
    parts = [urllib.parse.unquote(part) for part in resource.split("/") if part]

    roots = modelica_path()
    first_place = None
    for root in roots:
        folder = _package_folder(root, packages[0])
        if folder is None:
            continue
        for sub in packages[1:]:
            if not (folder / sub).is_dir():
                break       # stored in a file: it and its classes share this folder
            folder = folder / sub
        place = folder.joinpath(*parts)
        if place.exists():
            return os.path.abspath(place)
        first_place = first_place or place
    if first_place is not None:
        return os.path.abspath(first_place)

    searched = ", ".join(f'"{root}"' for root in roots) or "none: MODELICAPATH is not set"
    raise TableError(
        f'cannot resolve "{uri}": no package "{packages[0]}" (a folder "{packages[0]}" or '
        f'"{packages[0]} <version>") under the MODELICAPATH roots searched ({searched})',
        hint=f"set MODELICAPATH to the folder that holds the {packages[0]} package folder "
             f'(several roots separated by "{os.pathsep}")')


def _package_folder(root: pathlib.Path, name: str) -> pathlib.Path | None:
    """The folder of top-level package ``name`` under ``root``, if there is one.

    A folder named exactly ``name`` comes first; else the folder ``"name <version>"``
    with the highest version; else the folder of a single-file package ``name.mo``.
    """
    plain = root / name
    if plain.is_dir():
        return plain
    try:
        entries = list(os.scandir(root))
    except OSError:
        return None
    versioned = [entry for entry in entries
                 if entry.name.startswith(name + " ") and entry.is_dir()]
    if versioned:
        best = max(versioned, key=lambda entry: _version_key(entry.name[len(name) + 1:]))
        return pathlib.Path(best.path)
    if any(entry.is_file() and (entry.name == name + ".mo" or
                                (entry.name.startswith(name + " ") and entry.name.endswith(".mo")))
           for entry in entries):
        return root
    return None


def _version_key(version: str) -> tuple[int, ...]:
    """``"4.1.0"`` -> ``(4, 1, 0)``, so that versions sort as numbers."""
    return tuple(int(number) for number in re.findall(r"\d+", version))


def _resolve_file_uri(uri: str) -> str:
    """``file:///abs/path`` (or ``file://localhost/abs/path``) -> the local path."""
    parsed = urllib.parse.urlsplit(uri)
    path = urllib.request.url2pathname(parsed.path)
    if parsed.netloc not in ("", "localhost"):
        path = "//" + parsed.netloc + path      # a network share
    if not path:
        raise TableError(f'"{uri}" names no file', hint='write "file:///absolute/path/to/file"')
    return os.path.abspath(path)


# ---------------------------------------------------------------------------
# Reading a table
# ---------------------------------------------------------------------------

#: (path, mtime, size, table, delimiter, header lines) -> read-only matrix, newest last
_CACHE: OrderedDict[tuple, np.ndarray] = OrderedDict()
_CACHE_SIZE = 64
_CACHE_LOCK = threading.Lock()


def read_table(file_name: str, table_name: str | None = None, *, delimiter: str = ",",
               header_lines: int = 0, verbose: bool = False) -> np.ndarray:
    """Read an interpolation table from a file, as MSL's ``tableOnFile = true``.

    Parameters
    ----------
    file_name : str
        The file: a path, or a ``modelica://`` or ``file://`` URI (resolved with
        :func:`load_resource`).  Its extension, in any case, chooses the format:
        ``.mat`` a MATLAB MAT file, ``.csv`` a CSV file, anything else the MSL
        text format.
    table_name : str, optional
        The matrix in a text or MAT file (``"s.tab1"`` for the field ``tab1`` of
        the struct ``s`` in a MAT file).  Ignored for CSV files, required for the
        others.
    delimiter : str
        CSV only: the one character between values (blanks and tabs separate
        values too).
    header_lines : int
        CSV only: how many lines at the top of the file to skip (``nHeaderLines``).
    verbose : bool
        Print a line when the file is actually read (not for a cached read), as
        MSL's ``verboseRead``.

    Returns
    -------
    numpy.ndarray
        The matrix, two-dimensional, float, finite and read-only.  A MAT file's
        matrix is returned as MATLAB shows it.

    Raises
    ------
    TableError
        The file is missing or unreadable, the table is not in it, its declared
        size disagrees with its values, it is empty or not two-dimensional, or an
        entry is not a finite number.
    """
    path, uri = _table_path(file_name, table_name)
    kind = _kind(path)
    if kind == "csv":
        if not isinstance(delimiter, str) or len(delimiter) != 1:
            raise TableError(f'invalid column delimiter {delimiter!r} for CSV file "{path}": '
                             "it must be a single character",
                             hint='use e.g. delimiter="," or delimiter=";"')
        if isinstance(header_lines, bool) or not isinstance(header_lines, int) or header_lines < 0:
            raise TableError(f'invalid number of header lines {header_lines!r} for CSV file "{path}"',
                             hint="header_lines (nHeaderLines) must be an integer >= 0")
        key_options = (None, delimiter, header_lines)
    else:
        if table_name is not None and not isinstance(table_name, str):
            raise TableError(f'the table name for file "{path}" must be a string, not {table_name!r}',
                             hint="give the name of the matrix in the file")
        if table_name is not None and (table_name == "NoName" or not table_name.strip()):
            table_name = None
        key_options = (table_name, None, None)

    try:
        status = os.stat(path)
    except OSError as error:
        raise _missing_file(path, uri, table_name, kind, error) from error
    if not os.path.isfile(path):
        raise TableError(f'"{path}"{_from(uri)} is not a file (reading table {_quoted(table_name)})',
                         hint="give the name of a file, not of a folder")

    key = (os.path.realpath(path), status.st_mtime_ns, status.st_size, *key_options)
    with _CACHE_LOCK:
        cached = _CACHE.get(key)
        if cached is not None:
            _CACHE.move_to_end(key)
            return cached

    if verbose:
        print(f'... loading "{table_name if kind != "csv" else "Values"}" from "{path}"')
    where = (f'CSV file "{path}"{_from(uri)}' if kind == "csv"
             else f'table {_quoted(table_name)} in file "{path}"{_from(uri)}')
    if kind == "csv":
        matrix = _read_csv(path, where, delimiter, header_lines)
    elif kind == "mat":
        matrix = _read_mat(path, table_name, where)
    else:
        matrix = _read_text(path, table_name, where)

    matrix = np.ascontiguousarray(matrix, dtype=float)
    matrix.setflags(write=False)
    with _CACHE_LOCK:
        _CACHE[key] = matrix
        while len(_CACHE) > _CACHE_SIZE:
            _CACHE.popitem(last=False)
    return matrix


def _table_path(file_name: Any, table_name: Any) -> tuple[str, str | None]:
    """The absolute path of ``file_name`` and the URI it came from (``None`` for a plain path)."""
    if isinstance(file_name, os.PathLike):
        file_name = os.fspath(file_name)
    if not isinstance(file_name, str) or not file_name.strip() or file_name == "NoName":
        raise TableError(f"no file name given for a table read from file (got {file_name!r})",
                         hint="give fileName, or read the table from usertab() instead of a file")
    try:
        path = load_resource(file_name)
    except TableError as error:
        what = f'table "{table_name}"' if isinstance(table_name, str) else "a table"
        raise TableError(f"cannot read {what}: {error.message}", hint=error.hint) from error
    scheme = file_name.split(":", 1)[0].lower() if ":" in file_name else ""
    return path, (file_name if scheme in ("modelica", "file") else None)


def _kind(path: str) -> str:
    """``"mat"``, ``"csv"`` or ``"text"``, by the extension in any case."""
    suffix = pathlib.PurePath(path).suffix.lower()
    return {".mat": "mat", ".csv": "csv"}.get(suffix, "text")


def _from(uri: str | None) -> str:
    return f' (from "{uri}")' if uri else ""


def _quoted(table_name: str | None) -> str:
    return f'"{table_name}"' if table_name is not None else "(no name given)"


def _missing_file(path: str, uri: str | None, table_name: str | None, kind: str,
                  error: OSError) -> TableError:
    """The error for a file that cannot be found or opened."""
    what = "the CSV table" if kind == "csv" else f"table {_quoted(table_name)}"
    reason = "no such file" if isinstance(error, FileNotFoundError) else (error.strerror or str(error))
    if uri and uri.split(":", 1)[0].lower() == "modelica":
        roots = ", ".join(f'"{root}"' for root in modelica_path())
        hint = (f"the package was found but holds no such file; check the path in the URI "
                f"(MODELICAPATH roots: {roots})")
    elif uri:
        hint = "check the path in the URI"
    else:
        hint = (f"a relative fileName is read from the working directory ({os.getcwd()}); "
                'give an absolute path or a "modelica://" URI')
    return TableError(f'cannot read {what}: file "{path}"{_from(uri)}: {reason}', hint=hint)


def _read_bytes_as_text(path: str, where: str) -> str:
    """The file's text (UTF-8; stray bytes, which only comments may hold, replaced)."""
    try:
        data = pathlib.Path(path).read_bytes()
    except OSError as error:
        raise TableError(f"{where}: cannot read the file: {error.strerror or error}",
                         hint="check the file's permissions") from error
    text = data.decode("utf-8", errors="replace")
    return text[1:] if text.startswith("\ufeff") else text


def _lines(text: str) -> list[str]:
    """The file's lines as C's ``fgets`` sees them: split at ``\\n`` only (a ``\\r``
    is a separator within the line); a final newline adds no empty line."""
    lines = text.split("\n")
    if lines and lines[-1] == "":
        lines.pop()
    return lines


# Numbers as the C library's strtod reads them in the "C" locale.
_DECIMAL = r"[+-]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][+-]?\d+)?"
_DECIMAL_RE = re.compile(_DECIMAL)
_DECIMALS_RE = re.compile(rf"{_DECIMAL}(?: {_DECIMAL})*")
_SPECIAL_RE = re.compile(r"[+-]?(?:inf(?:inity)?|nan(?:\([0-9A-Za-z_]*\))?)", re.IGNORECASE)
_HEX_RE = re.compile(r"[+-]?0[xX](?:[0-9a-fA-F]+(?:\.[0-9a-fA-F]*)?|\.[0-9a-fA-F]+)(?:[pP][+-]?\d+)?")


def _numbers(tokens: list[str]) -> tuple[list[float], int | None]:
    """The tokens as floats, up to the first one that is not a number.

    Returns the values and the index of the first token that is not a number
    (``None`` if all are).  ``inf`` and ``nan`` are numbers here; the finiteness
    check comes later and names row and column.
    """
    if _DECIMALS_RE.fullmatch(" ".join(tokens)):
        return [float(token) for token in tokens], None
    values = []
    for index, token in enumerate(tokens):
        if _DECIMAL_RE.fullmatch(token):
            values.append(float(token))
        elif _SPECIAL_RE.fullmatch(token):
            values.append(float(token.split("(")[0]))
        elif _HEX_RE.fullmatch(token):
            values.append(float.fromhex(token))
        else:
            return values, index
    return values, None


def _check_finite(matrix: np.ndarray, where: str, line_of: Callable[[int, int], int] | None = None) -> None:
    """Raise a TableError naming the first entry that is nan or infinite."""
    bad = ~np.isfinite(matrix)
    if bad.any():
        row, col = (int(i) for i in np.argwhere(bad)[0])
        line = f" (line {line_of(row, col)})" if line_of else ""
        raise TableError(f"{where}: row {row + 1}, column {col + 1}{line} is {matrix[row, col]}, "
                         "not a finite number",
                         hint="every entry of a table must be a finite number; mend the file")


def _check_shape(matrix: np.ndarray, where: str) -> None:
    if matrix.ndim != 2:
        raise TableError(f"{where} is not a matrix: it has {matrix.ndim} dimensions {matrix.shape}",
                         hint="a table must be a two-dimensional matrix")
    if matrix.size == 0:
        raise TableError(f"{where} is empty (size {matrix.shape[0]}x{matrix.shape[1]})",
                         hint="a table needs at least one row and one column")


# ---------------------------------------------------------------------------
# The MSL text format
# ---------------------------------------------------------------------------

_HEADER_START = re.compile(r"[ \t(,)\r]*(?:double|float)(?:[ \t(,)\r]|$)")
_HEADER_TOKENS = re.compile(r"[^ \t(,)\r]+")
_VALUE_TOKENS = re.compile(r"[^ \t,;\r]+")
_VALUE_SEPARATORS = " \t,;\r"
_SIZE = re.compile(r"\+?\d+")


def _read_text(path: str, table: str | None, where: str) -> np.ndarray:
    """A matrix of an MSL text file ("#1" format)."""
    lines = _lines(_read_bytes_as_text(path, where))
    if not lines or not lines[0].startswith("#1"):
        found = f'"{lines[0][:20]}"' if lines and lines[0] else "an empty line" if lines else "an empty file"
        raise TableError(f'{where}: the first line must start with "#1" (the format version), '
                         f"found {found}",
                         hint='a table text file starts with the line "#1", then '
                              '"double name(rows,columns)" and the values; a .mat or .csv file '
                              "needs that extension")
    names: list[str] = []
    bad_size_line = None
    for index in range(1, len(lines)):
        header = _table_header(lines[index])
        if header is None:
            continue
        name, size = header
        names.append(name)
        if name != table:
            continue
        if size is None:
            bad_size_line = bad_size_line or index + 1
            continue
        return _read_text_block(lines, index, size, where)

    if bad_size_line is not None:
        raise TableError(f"{where}: line {bad_size_line}: the declaration has no valid size",
                         hint=f'declare the matrix as "double {table}(rows,columns)" with two '
                              "non-negative integers")
    listing = ", ".join(f'"{name}"' for name in dict.fromkeys(names)) or "none"
    if table is None:
        raise TableError(f'no table name given for file "{path}"; the matrices in it: {listing}',
                         hint="give tableName, the name of one of the matrices in the file")
    raise TableError(f"{where}: not found; the matrices declared in the file: {listing}",
                     hint='each matrix is declared by a line "double name(rows,columns)"; '
                          "check tableName and the file")


def _table_header(line: str) -> tuple[str, tuple[int, int] | None] | None:
    """``"double name(rows,cols) # ..."`` -> (name, (rows, cols)); (name, None) for a
    declaration without a valid size; None for any other line."""
    if not _HEADER_START.match(line):
        return None
    tokens = _HEADER_TOKENS.findall(line)
    if len(tokens) < 2:
        return None
    name = tokens[1]
    if len(tokens) < 4 or not (_SIZE.fullmatch(tokens[2]) and _SIZE.fullmatch(tokens[3])):
        return name, None
    return name, (int(tokens[2]), int(tokens[3]))


def _value_tokens(line: str) -> list[str]:
    """The value tokens of a data line, up to a ``#`` that starts a token (a comment)."""
    hash_at = line.find("#")
    if hash_at >= 0 and (hash_at == 0 or line[hash_at - 1] in _VALUE_SEPARATORS):
        line = line[:hash_at]
    tokens = _VALUE_TOKENS.findall(line)
    for index, token in enumerate(tokens):
        if token.startswith("#"):
            return tokens[:index]
    return tokens


def _is_data_line(line: str) -> bool:
    body = line.lstrip(" \t")
    return bool(body) and body[0] != "#"


def _read_text_block(lines: list[str], header_index: int, size: tuple[int, int], where: str) -> np.ndarray:
    """The values after the declaration on line ``header_index + 1``, row by row."""
    rows, cols = size
    declared = f"declared as ({rows},{cols})"
    if rows == 0 or cols == 0:
        raise TableError(f"{where} is empty ({declared}, line {header_index + 1})",
                         hint="a table needs at least one row and one column")
    total = rows * cols
    values: list[float] = []
    starts: list[int] = []        # index of the first value of each data line
    line_numbers: list[int] = []  # ... and its line number
    index = header_index + 1
    while index < len(lines) and len(values) < total:
        line = lines[index]
        index += 1
        if not _is_data_line(line):
            continue
        tokens = _value_tokens(line)
        if not tokens:
            continue
        starts.append(len(values))
        line_numbers.append(index)
        wanted = tokens[: total - len(values)]
        numbers, bad = _numbers(wanted)
        if bad is not None:
            position = len(values) + len(numbers)
            row, col = divmod(position, cols)
            token = wanted[bad]
            if token in ("double", "float"):
                raise TableError(f'{where}: line {index}: the next declaration ("{token} ...") comes '
                                 f"where row {row + 1}, column {col + 1} of the matrix {declared} "
                                 f"was expected - the table ends before its declared {rows} rows",
                                 hint="correct the declared size or add the missing rows")
            raise TableError(f'{where}: line {index}: "{token}" is not a number (row {row + 1}, '
                             f"column {col + 1} of the matrix {declared})",
                             hint="the values must be numbers separated by blanks, tabs, commas or "
                                  "semicolons")
        values.extend(numbers)
        if len(tokens) > len(wanted):
            extra = tokens[len(wanted)]
            problem = ("holds more values than the declared size" if _DECIMAL_RE.fullmatch(extra)
                       else f'has "{extra}" after the last value')
            raise TableError(f"{where}: line {index} {problem} ({declared})",
                             hint="correct the declared size or remove the surplus values")

    if len(values) < total:
        raise TableError(f"{where}: the file ends (line {len(lines)}) after {len(values)} of the "
                         f"{total} values of the matrix {declared}",
                         hint="correct the declared size or add the missing rows")
    for later in range(index, len(lines)):
        if not _is_data_line(lines[later]):
            continue
        tokens = _value_tokens(lines[later])
        if tokens and _DECIMAL_RE.fullmatch(tokens[0]):
            raise TableError(f"{where}: line {later + 1} holds more values than the declared size "
                             f"({declared}); the matrix ends on line {index}",
                             hint="correct the declared size to the number of rows that follow")
        break

    matrix = np.array(values, dtype=float).reshape(rows, cols)

    def line_of(row: int, col: int) -> int:
        return line_numbers[bisect_right(starts, row * cols + col) - 1]

    _check_finite(matrix, where, line_of)
    return matrix


# ---------------------------------------------------------------------------
# CSV
# ---------------------------------------------------------------------------

def _read_csv(path: str, where: str, delimiter: str, header_lines: int) -> np.ndarray:
    """The matrix of a CSV file, as MSL 4.1 reads it.

    ``header_lines`` lines are skipped; each further line is a row, its values
    separated by ``delimiter``, blanks, tabs (a ``\\r`` too); runs of separators
    count as one.  Unlike MSL, blank lines are skipped rather than rejected and a
    row with more values than the first is an error rather than cut short.
    """
    lines = _lines(_read_bytes_as_text(path, where))
    if len(lines) < header_lines:
        raise TableError(f"{where}: the file has {len(lines)} lines, fewer than the "
                         f"{header_lines} header lines to skip",
                         hint="correct header_lines (nHeaderLines)")
    separators = " \t\r" + delimiter
    tokens_re = re.compile(f"[^{re.escape(separators)}]+")
    rows: list[list[float]] = []
    line_numbers: list[int] = []
    for number, line in enumerate(lines[header_lines:], start=header_lines + 1):
        tokens = tokens_re.findall(line)
        if not tokens:
            continue
        values, bad = _numbers(tokens)
        if bad is not None:
            first = not rows
            hint = ("the data lines hold plain numbers only; skip the heading lines with "
                    f"header_lines (nHeaderLines, now {header_lines})" if first else
                    "the data lines hold plain numbers only")
            raise TableError(f'{where}: line {number}: "{tokens[bad]}" is not a number '
                             f"(row {len(rows) + 1}, column {bad + 1})", hint=hint)
        if rows and len(values) != len(rows[0]):
            raise TableError(f"{where}: line {number} (row {len(rows) + 1}) has {len(values)} values, "
                             f"the first row (line {line_numbers[0]}) {len(rows[0])}",
                             hint=f'every row needs the same number of values separated by "{delimiter}"')
        rows.append(values)
        line_numbers.append(number)
    if not rows:
        raise TableError(f"{where} holds no data after its {header_lines} header lines",
                         hint="a table needs at least one row; check header_lines (nHeaderLines)")
    matrix = np.array(rows, dtype=float)
    _check_finite(matrix, where, lambda row, col: line_numbers[row])
    return matrix


# ---------------------------------------------------------------------------
# MAT files
# ---------------------------------------------------------------------------

_NUMERIC_MATLAB_CLASSES = frozenset({"double", "single", "int8", "uint8", "int16", "uint16", "int32",
                                     "uint32", "int64", "uint64", "logical"})


def _read_mat(path: str, table: str | None, where: str) -> np.ndarray:
    """A matrix of a MATLAB MAT file (v4, v6, v7; v7.3 with h5py)."""
    from scipy.io import matlab

    try:
        with open(path, "rb") as stream:
            major, _ = matlab.matfile_version(stream)
    except (ValueError, matlab.MatReadError, OSError) as error:
        raise TableError(f"{where}: not a MATLAB MAT file ({error})",
                         hint="save the table with MATLAB's save, scipy.io.savemat or Scilab's "
                              'savematfile, or give a text file the MSL "#1" format and another '
                              "extension than .mat") from error
    if major == 2:
        matrix = _read_mat73(path, table, where)
    else:
        matrix = _read_mat5(path, table, where, matlab)
    _check_shape(matrix, where)
    _check_finite(matrix, where)
    return matrix


def _read_mat5(path: str, table: str | None, where: str, matlab: Any) -> np.ndarray:
    """A matrix of a v4, v6 or v7 MAT file through scipy."""
    def damaged(error: Exception) -> TableError:
        return TableError(f'{where}: cannot read the MAT file: {error}',
                          hint="the file may be damaged or truncated; save it again")

    try:
        names = [entry[0] for entry in matlab.whosmat(path)]
    except Exception as error:   # scipy raises many types for a damaged file
        raise damaged(error) from error
    parts = table.split(".") if table is not None else [None]
    if parts[0] not in names:
        raise _not_in_mat(path, table, where, names)
    try:
        value = matlab.loadmat(path, variable_names=[parts[0]], squeeze_me=False,
                               struct_as_record=True)[parts[0]]
    except Exception as error:
        raise damaged(error) from error

    for depth, field in enumerate(parts[1:], start=1):
        owner = ".".join(parts[:depth])
        fields = getattr(getattr(value, "dtype", None), "names", None)
        if not isinstance(value, np.ndarray) or not fields:
            raise TableError(f'{where}: "{owner}" is not a struct, so it has no field "{field}"',
                             hint="a dotted table name picks a field of a 1x1 struct")
        if value.shape != (1, 1):
            raise TableError(f'{where}: "{owner}" is a {"x".join(map(str, value.shape))} struct array, '
                             "not a 1x1 struct", hint="a dotted table name needs a 1x1 struct")
        if field not in fields:
            raise TableError(f'{where}: the struct "{owner}" has no field "{field}"; its fields: '
                             + ", ".join(f'"{name}"' for name in fields),
                             hint="check tableName")
        value = value[0, 0][field]
    return _numeric_matrix(value, where)


def _numeric_matrix(value: Any, where: str) -> np.ndarray:
    """A MAT variable as a float matrix, or the TableError saying why it is not one."""
    if not isinstance(value, np.ndarray) or value.dtype.names or value.dtype.kind not in "biufc":
        kind = ("sparse" if hasattr(value, "toarray") else type(value).__name__) \
            if not isinstance(value, np.ndarray) else (
            "a struct" if value.dtype.names else "text" if value.dtype.kind in "US" else
            "a cell array or object")
        raise TableError(f"{where} is not a numeric matrix ({kind})",
                         hint="store the table as a full (not sparse) real matrix of numbers")
    if value.dtype.kind == "c":
        raise TableError(f"{where} is complex", hint="a table must be real-valued")
    if value.ndim != 2:
        raise TableError(f"{where} is not a matrix: it has {value.ndim} dimensions {value.shape}",
                         hint="a table must be a two-dimensional matrix")
    return value.astype(float)


def _not_in_mat(path: str, table: str | None, where: str, names: list[str]) -> TableError:
    listing = ", ".join(f'"{name}"' for name in names) or "none"
    if table is None:
        return TableError(f'no table name given for MAT file "{path}"; its variables: {listing}',
                          hint="give tableName, the name of one of the variables")
    return TableError(f'{where}: no variable "{table.split(".")[0]}" in the file; its variables: {listing}',
                      hint="check tableName (a dotted name picks a field of a struct)")


def _read_mat73(path: str, table: str | None, where: str) -> np.ndarray:
    """A matrix of a v7.3 (HDF5) MAT file through h5py, transposed back to MATLAB's view."""
    try:
        import h5py
    except ImportError as error:
        raise TableError(f"{where}: the file is a MAT v7.3 (HDF5) file, which needs h5py",
                         hint="pip install h5py, or save the file in MAT v7 format "
                              "(MATLAB: save -v7)") from error
    try:
        handle = h5py.File(path, "r")
    except OSError as error:
        raise TableError(f"{where}: cannot read the MAT v7.3 file: {error}",
                         hint="the file may be damaged or truncated; save it again") from error
    with handle:
        names = [name for name in handle.keys() if not name.startswith("#")]
        parts = table.split(".") if table is not None else [None]
        if parts[0] not in names:
            raise _not_in_mat(path, table, where, names)
        node = handle[parts[0]]
        for depth, field in enumerate(parts[1:], start=1):
            owner = ".".join(parts[:depth])
            if not isinstance(node, h5py.Group) or _matlab_class(node) != "struct":
                raise TableError(f'{where}: "{owner}" is not a struct, so it has no field "{field}"',
                                 hint="a dotted table name picks a field of a 1x1 struct")
            if field not in node:
                fields = ", ".join(f'"{name}"' for name in node.keys())
                raise TableError(f'{where}: the struct "{owner}" has no field "{field}"; its fields: {fields}',
                                 hint="check tableName")
            node = node[field]
            if isinstance(node, h5py.Dataset) and h5py.check_ref_dtype(node.dtype) is not None:
                raise TableError(f'{where}: "{owner}" is a struct array, not a 1x1 struct',
                                 hint="a dotted table name needs a 1x1 struct")
        return _mat73_matrix(node, where, h5py)


def _matlab_class(node: Any) -> str:
    value = node.attrs.get("MATLAB_class", b"")
    return value.decode() if isinstance(value, bytes) else str(value)


def _mat73_matrix(node: Any, where: str, h5py: Any) -> np.ndarray:
    """A v7.3 dataset as a float matrix (MATLAB stores the transpose)."""
    matlab_class = _matlab_class(node)
    if not isinstance(node, h5py.Dataset) or (matlab_class and matlab_class not in _NUMERIC_MATLAB_CLASSES):
        kind = matlab_class or "an HDF5 group"
        if isinstance(node, h5py.Group) and "MATLAB_sparse" in node.attrs:
            kind = "sparse"
        raise TableError(f"{where} is not a numeric matrix ({kind})",
                         hint="store the table as a full (not sparse) real matrix of numbers")
    if node.attrs.get("MATLAB_empty", 0):
        raise TableError(f"{where} is empty", hint="a table needs at least one row and one column")
    if node.dtype.names:
        raise TableError(f"{where} is complex", hint="a table must be real-valued")
    if node.ndim != 2:
        raise TableError(f"{where} is not a matrix: it has {node.ndim} dimensions",
                         hint="a table must be a two-dimensional matrix")
    return np.asarray(node[()], dtype=float).T


# ---------------------------------------------------------------------------
# usertab
# ---------------------------------------------------------------------------

_USERTABS: dict[str, np.ndarray] = {}


def register_usertab(name: str, table: Any) -> None:
    """Register a table under ``name``, as an entry of MSL's ``usertab.c``.

    Parameters
    ----------
    name : str
        The table name a block gives as ``tableName`` (with ``tableOnFile = true``
        and ``fileName = "NoName"``).  Registering a name again replaces its table.
    table : array_like
        A non-empty two-dimensional matrix of finite numbers (stored as a
        read-only float copy).

    Raises
    ------
    TableError
        The name is empty or the matrix is not a non-empty 2-D matrix of finite numbers.
    """
    if not isinstance(name, str) or not name.strip() or name == "NoName":
        raise TableError(f"a usertab table needs a name, not {name!r}",
                         hint="register it under the tableName the block gives")
    where = f'usertab table "{name}"'
    try:
        matrix = np.array(table, dtype=float)
    except (TypeError, ValueError) as error:
        raise TableError(f"{where} is not a matrix of numbers ({error})",
                         hint="give a 2-D list or array of numbers") from error
    _check_shape(matrix, where)
    _check_finite(matrix, where)
    matrix.setflags(write=False)
    _USERTABS[name] = matrix


def usertab(name: str) -> np.ndarray:
    """The table registered under ``name`` with :func:`register_usertab`.

    Parameters
    ----------
    name : str
        The block's ``tableName``.

    Returns
    -------
    numpy.ndarray
        The registered matrix (read-only).

    Raises
    ------
    TableError
        No table is registered under ``name``; the message lists those that are.
    """
    try:
        return _USERTABS[name]
    except (KeyError, TypeError):
        listing = ", ".join(f'"{key}"' for key in sorted(_USERTABS)) or "none"
        raise TableError(f'the table "{name}" is not defined in usertab (tableOnFile with fileName '
                         f'"NoName"); registered tables: {listing}',
                         hint="register it with acausal.tablefiles.register_usertab(name, matrix), "
                              "or give fileName") from None
