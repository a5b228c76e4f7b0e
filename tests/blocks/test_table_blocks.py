"""The table blocks in models: derivatives through index reduction, range errors, bad
tables, the Boolean and Integer tables, many rows (issue 22, item 6).

Every expected value is computed here from the table's data by hand or by the
numeric core (:mod:`acausal.interpolation`, itself checked against the MSL
references in tests/language/test_interpolation.py).
"""

from __future__ import annotations

import numpy as np
import pytest

from acausal import Experiment, Model, simulate
from acausal.errors import ParameterError, TableError
from acausal.interpolation import Table1D
from acausal.library.blocks import (
    BooleanTable, CombiTable1Dv, CombiTable2Dv, CombiTimeTable, Constant, ContinuousClock, Extrapolation,
    IntegerTable, Smoothness)
from acausal.library.translational import Mass, Position

ROWS = [[0.0, 0.0], [0.5, 0.2], [1.0, 0.1], [1.5, 0.4], [2.0, 0.4]]


class TableDrivesMass(Model):
    """An Akima time table is the position of a mass (Position, exact): the force on the
    flange is m times the table's second derivative, which index reduction takes from it."""

    experiment = Experiment(stop_time=2.0, interval=0.002)

    def build(self):
        self.table = CombiTimeTable(table=ROWS, smoothness=Smoothness.ContinuousDerivative)
        self.position = Position(exact=True)
        self.mass = Mass(m=3.0)
        self.connect(getattr(self.table, "y[1]"), self.position.s_ref)
        self.connect(self.position.flange, self.mass.flange_a)


def test_a_table_drives_a_position_source_through_its_derivatives():
    result = simulate(TableDrivesMass())
    assert result.success, result.message
    core = Table1D(ROWS, smoothness=Smoothness.ContinuousDerivative)   # the same spline
    t = result.time
    inner = (t > 0.01) & (t < 1.99)
    s, v, a = (core.value(0, t, order) for order in (0, 1, 2))
    np.testing.assert_allclose(result["mass.s"], s, atol=1e-12)
    np.testing.assert_allclose(result["mass.v"][inner], v[inner], atol=1e-9)
    # the force the source exerts: m * a (flange.f of the mass's free end is 0)
    np.testing.assert_allclose(result["mass.a"][inner], a[inner], atol=1e-7)
    assert np.max(np.abs(a)) > 0.5  # the check has teeth: the table is curved


class LeavesItsTable(Model):
    experiment = Experiment(stop_time=3.0, interval=0.01)

    def build(self):
        self.table = CombiTimeTable(table=ROWS, extrapolation=Extrapolation.NoExtrapolation)


def test_no_extrapolation_stops_the_run_naming_the_table_and_keeps_the_result():
    result = simulate(LeavesItsTable())
    assert not result.success
    assert "Extrapolation error" in result.message and "table" in result.message
    # the result up to there is kept: the table's values while inside it
    assert 1.99 <= result.time[-1] <= 2.02
    inside = result.time <= 2.0
    np.testing.assert_allclose(result["table.y[1]"][inside],
                               np.interp(result.time[inside], *np.array(ROWS).T), atol=1e-12)


@pytest.mark.parametrize("table, error, words", [
    ([[0, 1], [1, 2], [1, 3]], TableError, ["table", "row 3"]),   # 1-D abscissae must increase strictly
    ([[0, 1], [1, float("nan")]], ParameterError, ["table[1][1]", "nan"]),
])
def test_a_bad_table_names_the_block_and_the_row(table, error, words):
    class Bad(Model):
        def build(self):
            self.clock = ContinuousClock()
            self.lookup = CombiTable1Dv(table=table)
            self.connect(self.clock.y, getattr(self.lookup, "u[1]"))

    with pytest.raises(error) as raised:
        simulate(Bad())
    message = str(raised.value)
    assert "lookup" in message
    for word in words:
        assert word in message


def test_a_missing_file_names_the_file_and_the_block():
    class Missing(Model):
        def build(self):
            self.table = CombiTimeTable(tableOnFile=True, tableName="tab1", fileName="no/such/file.txt")

    with pytest.raises(TableError, match=r"no/such/file\.txt"):
        simulate(Missing())


class Toggles(Model):
    experiment = Experiment(stop_time=5.0, interval=0.01)

    def build(self):
        self.once = BooleanTable(table=[1.0, 2.0, 2.5])
        self.periodic = BooleanTable(table=[0.0, 0.25, 0.5], extrapolation=Extrapolation.Periodic)
        self.steps = IntegerTable(table=[[0, 1], [1, 3], [2, -2], [3, 7]])


def test_boolean_and_integer_tables_switch_at_their_times():
    result = simulate(Toggles())
    assert result.success, result.message
    t = result.time
    # right-continuous: the new value holds from the table time on (at an event, the
    # second row holds the right limit)
    right = np.append(np.diff(t) > 0, True)
    once = (t >= 1.0) & (t < 2.0) | (t >= 2.5)
    assert np.array_equal(result["once.y"][right].astype(bool), once[right])
    # a square wave: on from 0 to 0.25, off from 0.25 to 0.5, repeated every 0.5
    phase = np.mod(t, 0.5)
    periodic = phase < 0.25
    periodic_result = result["periodic.y"].astype(bool)
    away = (np.abs(phase - 0.25) > 1e-9) & (np.minimum(phase, 0.5 - phase) > 1e-9)  # not at a switch
    assert np.array_equal(periodic_result[right & away], periodic[right & away])
    steps = np.select([t < 1, t < 2, t < 3], [1, 3, -2], 7)
    assert np.array_equal(result["steps.y"][right], steps[right])


def test_many_rows_look_up_the_same_values():
    """A 2-D table of 300 x 300 points and a 1-D table of 100,000 rows give the numeric core's
    values (the lookup is a bisection, not a piecewise expression of every row)."""
    u = np.linspace(-1, 1, 300)
    grid = np.outer(np.sin(3 * u), np.cos(2 * u))
    table2d = np.zeros((301, 301))
    table2d[0, 1:], table2d[1:, 0], table2d[1:, 1:] = u, u, grid
    x = np.linspace(0, 10, 100_000)
    table1d = np.column_stack([x, np.sin(x)])

    class Large(Model):
        experiment = Experiment(stop_time=0.9, interval=0.01)

        def build(self):
            self.clock = ContinuousClock()
            self.half = Constant(k=0.3)
            self.surface = CombiTable2Dv(table=table2d.tolist())
            self.curve = CombiTable1Dv(table=table1d.tolist())
            self.connect(self.clock.y, getattr(self.surface, "u1[1]"))
            self.connect(self.half.y, getattr(self.surface, "u2[1]"))
            self.connect(self.clock.y, getattr(self.curve, "u[1]"))

    result = simulate(Large())
    assert result.success, result.message
    t = result.time
    np.testing.assert_allclose(result["curve.y[1]"], np.sin(t), atol=1e-8)
    # bilinear in the cell: compare with the exact function, to the grid's resolution
    np.testing.assert_allclose(result["surface.y[1]"], np.sin(3 * t) * np.cos(0.6), atol=2e-3)
