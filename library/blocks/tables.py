"""Modelica.Blocks.Tables: one- and two-dimensional interpolation tables.

``CombiTable1Ds`` (one input, the columns as outputs), ``CombiTable1Dv``
(input ``u[i]`` looks up column ``columns[i]``), ``CombiTable2Ds`` (two
inputs, one output) and ``CombiTable2Dv`` (vectors of input pairs), written
from the MSL 4.1.0 sources: the matrix from the model or from a file
(:class:`acausal.components.tables.TableData`), the six interpolations and
four extrapolations of ``Modelica.Blocks.Types`` and their derivatives
(:mod:`acausal.interpolation`), so an input that is differentiated by index
reduction, or a ``Der`` block after the table, sees the table's own
derivatives.  No table generates events (as in the MSL).
"""

from __future__ import annotations

import sympy as sp

from acausal.components.declarations import VectorBlock
from acausal.components.tables import (Extrapolation, Smoothness, TableData, default_columns, range_asserts)
from acausal.errors import TableError
from acausal.interpolation import Table1D, Table2D
from acausal.language import Eq, Parameter, RealInput, RealOutput
from acausal.tables import table_1d_function, table_2d_function

__all__ = ["CombiTable1Ds", "CombiTable1Dv", "CombiTable2Ds", "CombiTable2Dv"]


def _where(block) -> str:
    return block.path or type(block).__name__


class _Options(TableData):
    """The interpolation options of the table blocks (Modelica.Blocks.Types)."""

    modelica_name = None  # the docstring names the package of its options' types: no MSL class

    smoothness = Parameter(Smoothness.LinearSegments, structural=True, description="Smoothness of table interpolation")
    extrapolation = Parameter(Extrapolation.LastTwoPoints, structural=True,
                              description="Extrapolation of data outside the definition range")
    verboseExtrapolation = Parameter(False, structural=True,  # noqa: N815
                                     description="= true, if warning messages are to be printed if table input "
                                                 "is outside the definition range")


class _Table1D(_Options, VectorBlock):
    """Shared by CombiTable1Ds and CombiTable1Dv: the numeric table and its outputs."""

    columns = Parameter(None, structural=True,
                        description="Columns of table to be interpolated (default 2, ..., number of columns)")

    @classmethod
    def _size(cls, value) -> int:
        where = cls.__name__
        return len(default_columns(cls.read_matrix(value, where), value("columns")))

    def numeric_table(self) -> Table1D:
        matrix = self.matrix()
        return Table1D(matrix, default_columns(matrix, self.columns), Smoothness(self.smoothness),
                       Extrapolation(self.extrapolation), name=_where(self))

    def looked_up(self, inputs: list) -> list:
        """``y[i] = table_i(inputs[i])`` and the range assertions."""
        table = self.numeric_table()
        where = _where(self)
        equations = []
        for i, (y, u) in enumerate(zip(self.vector("y"), inputs)):
            equations.append(Eq(y, table_1d_function(table, i, f"{where}.table")(u)))
        for k, u in enumerate(dict.fromkeys(inputs)):
            inside = sp.And(u >= table.u_min, u <= table.u_max)
            name = "u" if len(set(inputs)) == 1 else f"u[{k + 1}]"
            equations += range_asserts(where, Extrapolation(self.extrapolation), bool(self.verboseExtrapolation),
                                       inside, f"the input {name}")
        return equations


class CombiTable1Ds(_Table1D):
    """Table look-up in one dimension (matrix/file) with one input and n outputs (Modelica.Blocks.Tables.CombiTable1Ds).

    ``y[i]`` interpolates column ``columns[i]`` of the table at the input
    ``u`` (column 1 holds the abscissa, strictly increasing).
    ``smoothness``: LinearSegments (default), ContinuousDerivative (Akima),
    ConstantSegments, MonotoneContinuousDerivative1 (Fritsch-Butland),
    MonotoneContinuousDerivative2 (Steffen), ModifiedContinuousDerivative
    (modified Akima); ``extrapolation``: LastTwoPoints (default, the end
    slope), HoldLastPoint, Periodic, NoExtrapolation (an error naming the
    table when ``u`` leaves its range).  The table may be read from a file
    (``tableOnFile``, ``tableName``, ``fileName``).
    """

    modelica_name = "Modelica.Blocks.Tables.CombiTable1Ds"

    u = RealInput(description="Connector of Real input signal")

    @classmethod
    def arrays(cls, value):
        return {"y": (cls._size(value), lambda i: RealOutput(description="Connector of Real output signals"))}

    def equations(self):
        n = len(self.vector("y"))
        return self.looked_up([self.u] * n)


class CombiTable1Dv(_Table1D):
    """Table look-up in one dimension (matrix/file) with n inputs and n outputs (Modelica.Blocks.Tables.CombiTable1Dv).

    ``y[i]`` interpolates column ``columns[i]`` at the input ``u[i]``; the
    options are those of :class:`CombiTable1Ds`.
    """

    modelica_name = "Modelica.Blocks.Tables.CombiTable1Dv"

    @classmethod
    def arrays(cls, value):
        n = cls._size(value)
        return {"u": (n, lambda i: RealInput(description="Connector of Real input signals")),
                "y": (n, lambda i: RealOutput(description="Connector of Real output signals"))}

    def equations(self):
        return self.looked_up(self.vector("u"))


class _Table2D(_Options):
    """Shared by CombiTable2Ds and CombiTable2Dv."""

    def numeric_table(self) -> Table2D:
        smoothness = Smoothness(self.smoothness)
        return Table2D(self.matrix(), smoothness, Extrapolation(self.extrapolation), name=_where(self))

    def looked_up(self, pairs: list, outputs: list) -> list:
        table = self.numeric_table()
        where = _where(self)
        function = table_2d_function(table, f"{where}.table")
        equations = [Eq(y, function(u1, u2)) for y, (u1, u2) in zip(outputs, pairs)]
        for k, (u1, u2) in enumerate(pairs):
            inside = sp.And(u1 >= table.u1_min, u1 <= table.u1_max, u2 >= table.u2_min, u2 <= table.u2_max)
            name = "the inputs u1, u2" if len(pairs) == 1 else f"the inputs u1[{k + 1}], u2[{k + 1}]"
            equations += range_asserts(where, Extrapolation(self.extrapolation), bool(self.verboseExtrapolation),
                                       inside, name)
        return equations


class CombiTable2Ds(_Table2D):
    """Table look-up in two dimensions (matrix/file) with two inputs and one output (Modelica.Blocks.Tables.CombiTable2Ds).

    ``table[1, 2:]`` holds the abscissae of ``u2``, ``table[2:, 1]`` those
    of ``u1`` (both strictly increasing), the rest the values.
    ``smoothness``: LinearSegments (bilinear, default), ContinuousDerivative
    (bicubic Akima), ConstantSegments; ``extrapolation`` as for the 1-D
    tables.
    """

    modelica_name = "Modelica.Blocks.Tables.CombiTable2Ds"

    table = Parameter(((0.0, 0.0), (0.0, 0.0)), structural=True,
                      description="Table matrix (grid u1 = first column, grid u2 = first row; "
                                  "e.g., table=[0, 0; 0, 1])")
    u1 = RealInput(description="Connector of Real input signal 1")
    u2 = RealInput(description="Connector of Real input signal 2")
    y = RealOutput(description="Connector of Real output signal")

    def equations(self):
        return self.looked_up([(self.u1, self.u2)], [self.y])


class CombiTable2Dv(_Table2D, VectorBlock):
    """Table look-up in two dimensions (matrix/file) with n input pairs and n outputs (Modelica.Blocks.Tables.CombiTable2Dv).

    ``y[i]`` is the table at ``(u1[i], u2[i])``; ``n`` is a structural
    parameter (default 1); the options are those of :class:`CombiTable2Ds`.
    """

    modelica_name = "Modelica.Blocks.Tables.CombiTable2Dv"

    n = Parameter(1, structural=True, description="Number of inputs (= number of outputs)")
    table = Parameter(((0.0, 0.0), (0.0, 0.0)), structural=True,
                      description="Table matrix (grid u1 = first column, grid u2 = first row; "
                                  "e.g., table=[0, 0; 0, 1])")

    @classmethod
    def arrays(cls, value):
        n = int(value("n"))
        if n < 1:
            raise TableError(f"{cls.__name__}.n must be at least 1, not {n}", hint="n = number of input pairs")
        return {"u1": (n, lambda i: RealInput(description="Connector of Real input signals 1")),
                "u2": (n, lambda i: RealInput(description="Connector of Real input signals 2")),
                "y": (n, lambda i: RealOutput(description="Connector of Real output signals"))}

    def equations(self):
        return self.looked_up(list(zip(self.vector("u1"), self.vector("u2"))), self.vector("y"))

