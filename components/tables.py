"""What the table blocks share (Modelica.Blocks.Tables and Sources.CombiTimeTable):
where the matrix comes from, the interpolation options, and their checks.

The MSL table blocks take their matrix either from the parameter ``table``
or, with ``tableOnFile = true``, from a file (``fileName``, ``tableName``;
``delimiter`` and ``nHeaderLines`` for CSV) or from the user tables
(``fileName = "NoName"``: MSL's ``usertab.c``, here
:func:`acausal.tablefiles.register_usertab`).  :class:`TableData` declares
those parameters; :meth:`TableData.matrix` reads the matrix (files through
:mod:`acausal.tablefiles`, once per file) and names the block in every
error.  The numbers themselves are interpolated by
:mod:`acausal.interpolation`.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import sympy as sp

from acausal.errors import TableError
from acausal.hybrid import Assert, noEvent
from acausal.interpolation import Extrapolation, Smoothness, TimeEvents
from acausal.language import Component, Parameter
from acausal.tablefiles import read_table, usertab

__all__ = ["TableData", "Smoothness", "Extrapolation", "TimeEvents", "default_columns", "range_asserts"]


def _where(block: Component) -> str:
    return block.path or type(block).__name__


class TableData(Component):
    """The table parameters of Modelica.Blocks.Tables.CombiTable1Ds/1Dv/2Ds/2Dv and
    Sources.CombiTimeTable (Modelica's defaults)."""

    tableOnFile = Parameter(False, structural=True,  # noqa: N815 - Modelica names
                            description="= true, if table is defined on file or in function usertab")
    #: (the MSL's default is an empty matrix, which its blocks refuse; a single row of
    #: zeros makes the block usable with its defaults, with output 0)
    table = Parameter(((0.0, 0.0),), structural=True,
                      description="Table matrix (grid = first column; e.g., table=[0, 0; 1, 1])")
    tableName = Parameter("NoName", structural=True,  # noqa: N815
                          description="Table name on file or in function usertab (see docu)")
    fileName = Parameter("NoName", structural=True,  # noqa: N815
                         description="File where matrix is stored (a path or a modelica:// URI)")
    delimiter = Parameter(",", structural=True, description="Column delimiter character for CSV file")
    nHeaderLines = Parameter(0, structural=True,  # noqa: N815
                             description="Number of header lines to ignore for CSV file")
    verboseRead = Parameter(True, structural=True,  # noqa: N815
                            description="= true, if info message that file is loading is to be printed")

    @staticmethod
    def read_matrix(value, where: str) -> np.ndarray:
        """The table matrix from the parameters ``value(name)`` gives (a modifier or the default)."""
        if value("tableOnFile"):
            file_name, table_name = str(value("fileName")), str(value("tableName"))
            if file_name == "NoName":
                if table_name == "NoName":
                    raise TableError(f"{where}: tableOnFile = true and no table name given",
                                     hint='give tableName and fileName, e.g. tableName="tab1", '
                                          'fileName="modelica://Modelica/Resources/Data/Tables/test.txt"')
                return usertab(table_name)
            csv = file_name.lower().endswith(".csv")
            if not csv and table_name == "NoName":
                raise TableError(f"{where}: tableOnFile = true and no table name given for {file_name}",
                                 hint='name the matrix in the file: tableName="tab1"')
            return read_table(file_name, None if csv else table_name, delimiter=str(value("delimiter")),
                              header_lines=int(value("nHeaderLines")), verbose=bool(value("verboseRead")))
        table = value("table")
        try:
            matrix = np.array(table, dtype=float)
        except (TypeError, ValueError) as exc:
            raise TableError(f"{where}.table is not a matrix of numbers: {table!r}",
                             hint="give rows of equal length, e.g. table=[[0, 0], [1, 2]]") from exc
        if matrix.size == 0:
            raise TableError(f"{where}: tableOnFile = false and parameter table is an empty matrix",
                             hint="give the table, e.g. table=[[0, 0], [1, 2]], or read it from a file "
                                  "(tableOnFile=True, tableName, fileName)")
        if matrix.ndim == 1:
            matrix = matrix[None, :]
        return matrix

    def matrix(self) -> np.ndarray:
        """This block's table matrix."""
        return self.read_matrix(lambda name: getattr(self, name), _where(self))


def default_columns(matrix: np.ndarray, columns: Any) -> list[int]:
    """``columns`` as a list of 1-based column numbers (default ``2:size(table, 2)``)."""
    if columns is None:
        return list(range(2, matrix.shape[1] + 1))
    if isinstance(columns, (int, np.integer)):
        return [int(columns)]
    return [int(c) for c in columns]


def range_asserts(where: str, extrapolation: Extrapolation, verbose: bool, inside: sp.Basic,
                  what: str) -> list:
    """The assertions on the abscissa range: an error outside it with ``NoExtrapolation``
    (the C code stops the simulation), a warning with ``verboseExtrapolation``."""
    if extrapolation is Extrapolation.NoExtrapolation:
        return [Assert(noEvent(inside), f"Extrapolation error: {what} of {where} left the table's range",
                       )]
    if verbose and extrapolation in (Extrapolation.LastTwoPoints, Extrapolation.HoldLastPoint):
        return [Assert(noEvent(inside), f"Extrapolation warning: {what} of {where} is outside the table's range",
                       level="warning")]
    return []
