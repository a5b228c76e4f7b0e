"""The MSL interpolation tables in numpy (acausal.interpolation).

What the tests hold the code to comes from outside it:

* the MSL 4.1.0 regression results of ModelicaTest.Tables (CombiTable1Ds,
  CombiTable2Ds, CombiTimeTable; Dymola runs of the C code), compared with the
  csv-compare tube, for every test whose table is written in the model (the
  tables, options and inputs are transcribed below from the ModelicaTest
  models);
* closed forms (data on a line or a plane, the example of the CombiTimeTable
  documentation) and properties of the methods (C1 continuity, monotonicity,
  periodicity, derivatives as finite differences);
* scipy's Akima1DInterpolator (akima and makima) and RegularGridInterpolator.
"""

from __future__ import annotations

import csv
import functools
import math
import os
import timeit
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.interpolate import Akima1DInterpolator, RegularGridInterpolator

from acausal.errors import ParameterError, TableError
from acausal.interpolation import Extrapolation, Smoothness, Table1D, Table2D, TimeEvents, TimeTable

S, E = Smoothness, Extrapolation
SPLINES = [S.ContinuousDerivative, S.ModifiedContinuousDerivative,
           S.MonotoneContinuousDerivative1, S.MonotoneContinuousDerivative2]
ALL_SMOOTHNESS = [S.LinearSegments, S.ConstantSegments, *SPLINES]
FAST = settings(max_examples=40, derandomize=True, deadline=None)


# ======================================================================================
# the MSL reference results
# ======================================================================================

REFERENCE = Path(os.environ.get("ACAUSAL_REFERENCE_DIR") or "/work/shared/reference/msl-4.1.0")


@functools.lru_cache(maxsize=None)
def reference(folder: str) -> tuple[dict[str, np.ndarray], tuple[str, ...]]:
    """The columns of a reference result (time first) and its comparison signals."""
    path = REFERENCE / folder
    if not path.is_dir():
        pytest.skip(f"no MSL reference results {folder} in {REFERENCE} (ACAUSAL_REFERENCE_DIR)")
    with open(next(path.glob("*.csv")), newline="") as file:
        rows = csv.reader(file)
        header = next(rows)
        values = np.array([[float(v) for v in row] for row in rows])
    columns = {"time": values[:, 0]}
    columns.update({name: values[:, k] for k, name in enumerate(header) if k})
    signals = tuple(line.strip() for line in (path / "comparisonSignals.txt").read_text().splitlines()
                    if line.strip() and line.strip().lower() != "time")
    return columns, signals


def _window_extrema(values: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """min and max of ``values[lo[k]:hi[k]]`` for every k (a sparse table, O(1) per window)."""
    mins, maxs = [values], [values]
    width = 1
    while 2 * width <= len(values):
        mins.append(np.minimum(mins[-1][:-width], mins[-1][width:]))
        maxs.append(np.maximum(maxs[-1][:-width], maxs[-1][width:]))
        width *= 2
    level = np.floor(np.log2(hi - lo)).astype(int)
    span = 1 << level
    low = np.array([mins[k][i] for k, i in zip(level, lo)])
    low = np.minimum(low, [mins[k][i] for k, i in zip(level, hi - span)])
    high = np.array([maxs[k][i] for k, i in zip(level, lo)])
    high = np.maximum(high, [maxs[k][i] for k, i in zip(level, hi - span)])
    return low, high


def outside_tube(time: np.ndarray, ref: np.ndarray, ours: np.ndarray) -> np.ndarray:
    """Where ``ours`` leaves the csv-compare tube around ``ref`` (sampled at ``time``).

    Half-width ``dx = 2e-3 (t_end - t_start)``, half-height
    ``dy = 2e-3 max(y_max - y_min, |y_min|, 1e-3)``; the bounds at ``t`` are the
    extrema of the reference over ``[t - dx, t + dx]`` widened by ``dy``.
    """
    dx = 2e-3 * (time[-1] - time[0])
    dy = 2e-3 * max(ref.max() - ref.min(), abs(ref.min()), 1e-3)
    lo = np.searchsorted(time, time - dx, side="left")
    hi = np.searchsorted(time, time + dx, side="right")
    low, high = _window_extrema(ref, lo, hi)
    return (ours < low - dy) | (ours > high + dy)


def assert_matches_reference(folder: str, ours: dict[str, np.ndarray]) -> None:
    """Every comparison signal of ``folder`` lies in the tube (ours computed by the test)."""
    columns, signals = reference(folder)
    missing = [s for s in signals if s not in ours]
    assert not missing, f"{folder}: no model for the signals {missing}"
    failures = []
    for signal in signals:
        bad = outside_tube(columns["time"], columns[signal], ours[signal])
        if bad.any():
            k = int(np.argmax(bad))
            failures.append(f"{signal}: {int(bad.sum())} points outside the tube, first at "
                            f"t = {columns['time'][k]!r}: {ours[signal][k]!r} (reference {columns[signal][k]!r})")
    assert not failures, f"{folder}:\n" + "\n".join(failures)


# --------------------------------------------------------------------------------------
# ModelicaTest.Tables.CombiTable1Ds: u = clock.y = time; d_t_new.y and d2_t_new.y are the
# first and second derivative of y[1] (d_t_new2, d2_t_new2 those of y[2])

RPN14 = [[7.99, 0], [8.09, 2.76429e-5], [8.19, 4.37498e-2], [8.7, 0.169183], [9.2, 0.469428],
         [10, 0.94374], [12, 0.998636], [15, 0.999919], [20, 0.999994]]
AKIMA3 = [[0, 10], [2, 10], [3, 10], [5, 10], [6, 10], [8, 10], [9, 10.5], [11, 15], [12, 50],
          [14, 60], [15, 85]]
TICKET1039 = [[0, 5], [1, 3], [2, 1], [3, 1], [4, 1], [5, 3]]
FIVE_ROWS = [[0.3, 0, 0], [0.4, 1, -1], [0.5, 0, 0], [0.6, -1, 1], [0.7, 0, 0]]

COMBI_TABLE_1DS = {   # test: (table, columns, smoothness)
    "Test1": ([[0, 1]], None, S.LinearSegments),
    "Test2": ([[0.5, 1]], None, S.LinearSegments),
    "Test3": ([[0.3, 0], [0.4, 1], [0.5, 0], [0.6, -1], [0.7, 0]], None, S.ContinuousDerivative),
    "Test4": (FIVE_ROWS, None, S.ContinuousDerivative),
    "Test5": (FIVE_ROWS, [3], S.ContinuousDerivative),
    "Test6": (FIVE_ROWS, [2, 3], S.ContinuousDerivative),
    "Test7": ([[0, 1], [1, 0]], None, S.LinearSegments),
    "Test8": ([[0.25, 1], [1.25, 0]], None, S.LinearSegments),
    "Test11": ([[0, 1], [0.5, 2], [1, 0]], None, S.LinearSegments),
    "Test12": ([[0, 1], [0.5, 2], [1, 0]], None, S.LinearSegments),
    "Test15": (TICKET1039, None, S.ContinuousDerivative),
    "Test16": ([[0, 3], [1, 1], [2, 1], [3, 1], [4, 3], [5, 5]], None, S.ContinuousDerivative),
    "Test26": (TICKET1039, None, S.MonotoneContinuousDerivative1),
    "Test27": (AKIMA3, None, S.MonotoneContinuousDerivative1),
    "Test28": (RPN14, None, S.MonotoneContinuousDerivative1),
    "Test29": ([[0, 1, 2]], None, S.ContinuousDerivative),
    "Test30": (TICKET1039, None, S.MonotoneContinuousDerivative2),
    "Test31": (AKIMA3, None, S.MonotoneContinuousDerivative2),
    "Test32": (RPN14, None, S.MonotoneContinuousDerivative2),
    "Test34": (TICKET1039, None, S.ModifiedContinuousDerivative),
}


@pytest.mark.parametrize("test", COMBI_TABLE_1DS)
def test_combi_table_1ds_matches_msl_reference(test):
    folder = f"ModelicaTest.Tables.CombiTable1Ds.{test}"
    t = reference(folder)[0]["time"]
    data, columns, smoothness = COMBI_TABLE_1DS[test]
    table = Table1D(data, columns, smoothness, name=test)
    ours = {"clock.y": t}
    for i in range(table.n_outputs):
        ours[f"t_new.y[{i + 1}]"] = table.value(i, t)
        suffix = "" if i == 0 else str(i + 1)
        ours[f"d_t_new{suffix}.y"] = table.value(i, t, order=1)
        ours[f"d2_t_new{suffix}.y"] = table.value(i, t, order=2)
    assert_matches_reference(folder, ours)


# --------------------------------------------------------------------------------------
# ModelicaTest.Tables.CombiTable2Ds: the inputs are clocks, constants and sines; the Der
# blocks' outputs follow by the chain rule from the partial derivatives

BIG = [[0, 0, 5, 10, 15, 20, 25, 30, 35, 40],
       [0, 58.2, 61.5, 47.9, 62.3, 34.6, 45.5, 38.2, 41.2, 41.7],
       [5, 37.2, 40, 27, 41.3, 14.1, 24.5, 17.3, 20.2, 20.8],
       [10, 22.4, 22.5, 14.6, 22.5, 4.7, 7.2, 1.8, 2.1, 2.1],
       [15, 21.8, 20.5, 12.8, 17.6, 5.8, 7.6, 0.8, 0.6, 0.6],
       [20, 16.8, 14.4, 8.1, 6.9, 6.2, 0.6, 0.1, 0, 0],
       [25, 12, 8, 5.3, 2.9, 0.6, 0, 0, 0, 0],
       [30, 7.4, 4.8, 1.4, 0.1, 0, 0, 0, 0, 0],
       [35, 3.2, 0.7, 0, 0, 0, 0, 0, 0, 0],
       [40, 0, 0, 0, 0, 0, 0, 0, 0, 0],
       [45, 0, 0, 0, 0, 0, 0, 0, 0, 0],
       [50, 0, 0, 0, 0, 0, 0, 0, 0, 0]]
TABLE_R = [[0, 75, 83, 88], [18, 778, 773, 769], [28, 970, -950, 938], [33, 860, 1030, 1039]]
TABLE_L = [[0, 75, 80, 88], [18, 1039, 1030, 860], [23, 938, -950, 970], [33, 769, 773, 778]]


def clock(t):
    """Modelica.Blocks.Sources.ContinuousClock: value, first and second derivative."""
    return t, np.ones_like(t), np.zeros_like(t)


def constant(k):
    return lambda t: (np.full_like(t, k), np.zeros_like(t), np.zeros_like(t))


def sine(amplitude, f, phase, offset, start=0.0):
    """Modelica.Blocks.Sources.Sine: ``offset + amplitude sin(2 pi f (t - start) + phase)`` from ``start``."""
    def signal(t):
        w, arg, on = 2 * np.pi * f, 2 * np.pi * f * (t - start) + phase, t >= start
        return (offset + np.where(on, amplitude * np.sin(arg), 0.0), np.where(on, amplitude * w * np.cos(arg), 0.0),
                np.where(on, -amplitude * w * w * np.sin(arg), 0.0))
    return signal


def table_2d_signals(table: Table2D, u1, u2, t):
    """y, dy/dt and d2y/dt2 of a 2-D table fed with the signals ``u1(t)`` and ``u2(t)``."""
    (a, da, dda), (b, db, ddb) = u1(t), u2(t)
    y = table.value(a, b)
    dy = table.value(a, b, 1, 0) * da + table.value(a, b, 0, 1) * db
    d2y = (table.value(a, b, 2, 0) * da ** 2 + 2 * table.value(a, b, 1, 1) * da * db
           + table.value(a, b, 0, 2) * db ** 2 + table.value(a, b, 1, 0) * dda + table.value(a, b, 0, 1) * ddb)
    return y, dy, d2y


TWO = constant(2)
COMBI_TABLE_2DS = {   # test: (table, smoothness, u1, u2, names of the inputs)
    "Test1": (BIG, S.ContinuousDerivative, clock, TWO, ("clock.y", "const.y")),
    "Test2": (BIG, S.ContinuousDerivative, TWO, clock, ("const.y", "clock.y")),
    "Test3": (BIG, S.ContinuousDerivative, clock, clock, ("clock1.y", "clock2.y")),
    "Test4": (BIG, S.LinearSegments, clock, TWO, ("clock.y", "const.y")),
    "Test5": (BIG, S.LinearSegments, TWO, clock, ("const.y", "clock.y")),
    "Test6": (BIG, S.LinearSegments, clock, clock, ("clock1.y", "clock2.y")),
    "Test7": (BIG, S.ConstantSegments, clock, TWO, ("clock.y", "const.y")),
    "Test8": (BIG, S.ConstantSegments, TWO, clock, ("const.y", "clock.y")),
    "Test9": (BIG, S.ConstantSegments, clock, clock, ("clock1.y", "clock2.y")),
    # Ticket #1820: small Akima tables
    "Test24": ([[0, 0, 1], [0.5, 1, 2]], S.ContinuousDerivative, clock, clock, ("clock1.y", "clock2.y")),
    "Test25": ([[0, 0.5], [0, 1], [1, 2]], S.ContinuousDerivative, clock, clock, ("clock1.y", "clock2.y")),
    "Test26": ([[0, 0, 0.5, 1], [0.5, 1, 2, 1]], S.ContinuousDerivative, clock, clock, ("clock1.y", "clock2.y")),
    "Test27": ([[0, 0.5], [0, 1], [0.5, 2], [1, 1]], S.ContinuousDerivative, clock, clock,
               ("clock1.y", "clock2.y")),
    "Test28": ([[0, 0, 1], [0, 0, 1], [1, 1, 1]], S.ContinuousDerivative, clock, clock, ("clock1.y", "clock2.y")),
    "Test29": ([[0, 0, 0.5, 1], [0, 1, 2, 1], [1, 1, 1, 1]], S.ContinuousDerivative, clock, clock,
               ("clock1.y", "clock2.y")),
    "Test30": ([[0, 0, 1], [0, 1, 1], [0.5, 2, 1], [1, 1, 1]], S.ContinuousDerivative, clock, clock,
               ("clock1.y", "clock2.y")),
}


@pytest.mark.parametrize("test", COMBI_TABLE_2DS)
def test_combi_table_2ds_matches_msl_reference(test):
    folder = f"ModelicaTest.Tables.CombiTable2Ds.{test}"
    t = reference(folder)[0]["time"]
    data, smoothness, u1, u2, (name1, name2) = COMBI_TABLE_2DS[test]
    y, dy, d2y = table_2d_signals(Table2D(data, smoothness, name=test), u1, u2, t)
    ours = {"t_new.y": y, "d_t_new.y": dy, "d2_t_new.y": d2y, name1: u1(t)[0], name2: u2(t)[0]}
    assert_matches_reference(folder, ours)


@pytest.mark.parametrize("test, smoothness", [("Test19", S.ConstantSegments), ("Test20", S.LinearSegments),
                                               ("Test21", S.ContinuousDerivative)])
def test_combi_table_2ds_degenerate_tables_match_msl_reference(test, smoothness):
    """Ticket #1307: 2-D tables of one column or row, and of two columns, beside a 1-D table."""
    folder = f"ModelicaTest.Tables.CombiTable2Ds.{test}"
    t = reference(folder)[0]["time"]
    one_column = [[1, 1], [2, 4], [3, 9], [4, 16]]
    two_columns = [[1, 0, 6], [2, 4, 4], [3, 9, 9], [4, 16, 16]]
    blocks = {"combiTable2D1D": (one_column, "der1.y"), "combiTable2D1DT": (np.transpose(one_column), "der2.y"),
              "combiTable2D": (two_columns, "der4.y"), "combiTable2DT": (np.transpose(two_columns), "der5.y")}
    ours = {"clock1.y": t}
    for block, (data, der) in blocks.items():
        ours[f"{block}.y"], ours[der], _ = table_2d_signals(Table2D(data, smoothness), clock, clock, t)
    table_1d = Table1D([[2, 4], [3, 9], [4, 16]], smoothness=smoothness)
    ours["combiTable1D.y[1]"], ours["der3.y"] = table_1d.value(0, t), table_1d.value(0, t, order=1)
    assert_matches_reference(folder, ours)


@pytest.mark.parametrize("test", ["Test22", "Test23"])
def test_combi_table_2ds_akima_extrapolation_matches_msl_reference(test):
    """Ticket #1465: Akima surfaces extrapolated in u1 or u2, below and above, with sines as inputs."""
    folder = f"ModelicaTest.Tables.CombiTable2Ds.{test}"
    t = reference(folder)[0]["time"]
    if test == "Test22":
        inputs = {"sine_R.y": sine(3, 0.5, np.pi / 2, 33), "sine_L.y": sine(-3, 0.5, np.pi / 2, 18)}
        fast_r, slow_r = inputs["sine_R.y"], constant(81)
        fast_l, slow_l = inputs["sine_L.y"], constant(82)
    else:
        inputs = {"cosine_R.y": sine(3, 10, np.pi / 2, 33), "sine_R.y": sine(10, 1 / 3, 0, 81, start=1),
                  "cosine_L.y": sine(-3, 10, np.pi / 2, 18), "sine_L.y": sine(-10, 1 / 3, 0, 82, start=1)}
        fast_r, slow_r = inputs["cosine_R.y"], inputs["sine_R.y"]
        fast_l, slow_l = inputs["cosine_L.y"], inputs["sine_L.y"]
    ours = {name: signal(t)[0] for name, signal in inputs.items()}
    for key, data, u1, u2 in (("1R", TABLE_R, fast_r, slow_r), ("2R", np.transpose(TABLE_R), slow_r, fast_r),
                              ("1L", TABLE_L, fast_l, slow_l), ("2L", np.transpose(TABLE_L), slow_l, fast_l)):
        y, dy, _ = table_2d_signals(Table2D(data, S.ContinuousDerivative), u1, u2, t)
        ours[f"combiTable2D_{key}.y"], ours[f"der_{key}.y"] = y, dy
    assert_matches_reference(folder, ours)


@pytest.mark.parametrize("test", ["Test15", "Test16", "Test17"])
def test_combi_table_2ds_surface_tests(test):
    """Tests 15 to 17 draw surfaces of a table read from a file: nothing to compare."""
    signals = reference(f"ModelicaTest.Tables.CombiTable2Ds.{test}")[1]
    assert signals == (), f"{test} now has comparison signals {signals}: compare them"
    pytest.skip(f"CombiTable2Ds.{test} draws a surface; its reference result has no signals")


# --------------------------------------------------------------------------------------
# ModelicaTest.Tables.CombiTimeTable: simulated time, sampled as an event-driven simulator
# samples it (the block's when-clause at time >= pre(nextTimeEvent))

def event_driven(table: TimeTable, i: int, time: np.ndarray, start: float, shift: float, order: int = 0):
    """The output sampled at ``time`` with next_event held as the block holds it.

    At ``t >= next_event`` an event happens: the first of the reference's two rows
    at that time gets the value before the event (left), the second the value after it.
    """
    held = np.empty(len(time))
    next_event = table.next_event(time[0], start, shift)
    for k, t in enumerate(time):
        if t >= next_event:
            before = next_event
            next_event = table.next_event(t, start, shift)
            held[k] = before if k + 1 < len(time) and time[k + 1] == t else next_event
        else:
            held[k] = next_event
    return table.value(i, time, held, start, shift, order)


PERIODIC_TABLE = [[0.1, 0], [0.3, 0], [0.5, -1], [0.51, -2], [0.51, -3], [0.6, -2], [0.7, -2], [0.7, -2], [1, -4]]
TEST68_TABLE = [[9.81594, 0], [90.7974, 7.2727], [181.5948, 23.1818], [279.7548, 43.6364],
                [382.8222, 67.2732], [478.5276, 88.1822], [623.31, 109.5452], [746.01, 125.4542],
                [895.704, 141.3632], [1013.496, 149.0912], [1057.668, 169.5452], [1121.472, 179.5452],
                [1207.362, 191.8182], [1332.516, 205.4542], [1442.946, 214.0912], [1604.91, 224.0912],
                [1747.242, 231.8182], [1943.556, 240.9092], [2157.054, 248.6362], [2346.012, 256.8182],
                [2544.786, 264.5452], [2760.738, 274.0912], [3190.182, 292.7272], [3418.404, 303.1822],
                [3663.804, 312.7272], [3909.204, 322.7272], [4053.99, 326.8182], [4164.42, 331.8182]]
TEST87_TABLE = [[1, 0], [2, 0], [3, 0], [4, 0.5], [5, 0.5], [5.5, 1.2], [7, 1.2], [8, 0.1], [9, 0], [9.5, 0.3],
                [10, 0.6]]


def _derivatives(prefix: str, suffix: str = "") -> tuple[str, str, str]:
    return f"{prefix}{suffix}.y[1]", f"d_{prefix}{suffix}.y", f"d2_{prefix}{suffix}.y"


COMBI_TIME_TABLE = {   # test: [(TimeTable arguments, startTime, shiftTime, offset, signals of orders 0, 1, 2)]
    "Test1": [(dict(data=PERIODIC_TABLE, extrapolation=E.Periodic), 0, 0, 0, _derivatives("t_new"))],
    "Test4": [(dict(data=[[0.3, 0], [0.4, 1], [0.5, 0], [0.6, -1], [0.7, 0]], smoothness=S.ContinuousDerivative),
               0, 0, 0, _derivatives("t_new"))],
    # Ticket #1619: startTime > t_min > 0 (shiftTime defaults to startTime)
    "Test68": [(dict(data=TEST68_TABLE, extrapolation=E.HoldLastPoint), 0, 0, 33.1818, ("startTime_0.y[1]",)),
               (dict(data=TEST68_TABLE, extrapolation=E.HoldLastPoint), 2000, 2000, 33.1818, ("startTime.y[1]",))],
    "Test73": [(dict(data=TICKET1039, smoothness=S.MonotoneContinuousDerivative1), 0, 0, 0, _derivatives("t_new")),
               (dict(data=TICKET1039, smoothness=S.ContinuousDerivative), 0, 0, 0, _derivatives("t_new", "_2"))],
    "Test77": [(dict(data=TICKET1039, smoothness=S.MonotoneContinuousDerivative2), 0, 0, 0, _derivatives("t_new")),
               (dict(data=TICKET1039, smoothness=S.ContinuousDerivative), 0, 0, 0, _derivatives("t_new", "_2"))],
    # Ticket #2233: the simulation starts at t_max; BooleanTable(table={0, 0.4, 1}) is a
    # CombiTimeTable of the rows [0, 0; 0, 1; 0.4, 0; 1, 1] with startTime = -inf
    "Test83": [(dict(data=[[0, 1], [0.4, 0], [1, 1]], columns=[2], smoothness=S.ConstantSegments,
                     extrapolation=E.HoldLastPoint), 0, 0, 0, ("t_new.y[1]",)),
               (dict(data=[[0, 0], [0, 1], [0.4, 0], [1, 1]], columns=[2], smoothness=S.ConstantSegments,
                     extrapolation=E.HoldLastPoint), -math.inf, 0, 0, ("booleanTable.combiTimeTable.y[1]",))],
    "Test87": [(dict(data=TEST87_TABLE, smoothness=smoothness), 0, 0, 0, _derivatives("t_new", suffix))
               for suffix, smoothness in (("", S.ModifiedContinuousDerivative), ("_2", S.ContinuousDerivative),
                                          ("_3", S.MonotoneContinuousDerivative1),
                                          ("_4", S.MonotoneContinuousDerivative2))],
}


@pytest.mark.parametrize("test", COMBI_TIME_TABLE)
def test_combi_time_table_matches_msl_reference(test):
    folder = f"ModelicaTest.Tables.CombiTimeTable.{test}"
    t = reference(folder)[0]["time"]
    ours = {}
    for arguments, start, shift, offset, signals in COMBI_TIME_TABLE[test]:
        table = TimeTable(**arguments, name=test)
        for order, signal in enumerate(signals):
            ours[signal] = offset + event_driven(table, 0, t, start, shift, order)
    if test == "Test83":   # BooleanTable's RealToBoolean (threshold 0.5)
        ours["booleanTable.y"] = ours["booleanTable.realToBoolean.y"] = \
            (ours["booleanTable.combiTimeTable.y[1]"] >= 0.5).astype(float)
    assert_matches_reference(folder, ours)


# ======================================================================================
# closed forms and properties
# ======================================================================================

KNOTS = [0.0, 0.5, 1.25, 2.0, 3.0, 4.5]


@pytest.mark.parametrize("smoothness", [S.LinearSegments, *SPLINES])
@pytest.mark.parametrize("extrapolation", [E.LastTwoPoints, E.NoExtrapolation])
def test_every_interpolation_reproduces_a_straight_line(smoothness, extrapolation):
    """On data along a line every method (but constant segments) is that line, extrapolated too."""
    x = np.array(KNOTS)
    table = Table1D(np.c_[x, 3 - 2 * x, 0.5 * x], smoothness=smoothness, extrapolation=extrapolation)
    u = np.linspace(-2, 7, 181)
    np.testing.assert_allclose(table.value(0, u), 3 - 2 * u, rtol=1e-13, atol=1e-13)
    np.testing.assert_allclose(table.value(1, u), 0.5 * u, rtol=1e-13, atol=1e-13)
    np.testing.assert_allclose(table.value(0, u, order=1), -2, rtol=1e-13)
    np.testing.assert_allclose(table.value(0, u, order=2), 0, atol=1e-12)


@pytest.mark.parametrize("smoothness", ALL_SMOOTHNESS)
@pytest.mark.parametrize("extrapolation", list(E))
def test_every_interpolation_reproduces_a_constant(smoothness, extrapolation):
    table = Table1D(np.c_[KNOTS, np.full(len(KNOTS), 1.5)], smoothness=smoothness, extrapolation=extrapolation)
    u = np.linspace(-3, 8, 111)
    assert np.all(table.value(0, u) == 1.5)
    assert np.all(table.value(0, u, order=1) == 0)


@pytest.mark.parametrize("smoothness", ALL_SMOOTHNESS)
def test_the_table_goes_through_its_rows(smoothness):
    data = np.c_[KNOTS, [1.0, -2.0, 0.5, 4.0, 4.0, 3.0]]
    table = Table1D(data, smoothness=smoothness)
    for x, y in data:
        assert table.value(0, x) == pytest.approx(y, abs=1e-14)


def test_linear_segments_and_their_extrapolation():
    table = Table1D([[0, 0], [1, 2], [2, 3]], name="ramp")
    assert (table.value(0, 0.5), table.value(0, 1.5), table.value(0, 3.0), table.value(0, -1.0)) == (1, 2.5, 4, -2)
    assert (table.value(0, 0.5, order=1), table.value(0, 3.0, order=1), table.value(0, 0.5, order=2)) == (2, 1, 0)
    held = Table1D([[0, 0], [1, 2], [2, 3]], extrapolation=E.HoldLastPoint)
    assert (held.value(0, -5.0), held.value(0, 7.0), held.value(0, 7.0, order=1)) == (0, 3, 0)
    # inside, up to u_max itself, the last segment is in force: its slope, not the held one
    assert held.value(0, 2.0, order=1) == 1


def test_constant_segments_take_the_row_at_or_below():
    table = Table1D([[0, 1], [1, 2], [2, 5]], smoothness=S.ConstantSegments, extrapolation=E.HoldLastPoint)
    u = np.array([0.0, 0.999, 1.0, 1.5, 2.0, 3.0, -1.0])
    np.testing.assert_array_equal(table.value(0, u), [1, 1, 2, 2, 5, 5, 1])
    np.testing.assert_array_equal(table.value(0, u, order=1), 0)
    # LastTwoPoints extrapolates linearly through the last two rows (as the C code)
    linear = Table1D([[0, 1], [1, 2], [2, 5]], smoothness=S.ConstantSegments)
    assert (linear.value(0, 3.0), linear.value(0, -1.0), linear.value(0, 3.0, order=1)) == (8, 0, 3)


@pytest.mark.parametrize("smoothness", SPLINES)
def test_spline_extrapolation_continues_with_the_end_slope(smoothness):
    x = np.array(KNOTS)
    table = Table1D(np.c_[x, np.sin(x)], smoothness=smoothness)
    for end, beyond in ((x[0], -1.5), (x[-1], 6.0)):
        slope = table.value(0, np.nextafter(end, 2.0) if end == x[0] else end, order=1)
        assert table.value(0, beyond) == pytest.approx(table.value(0, end) + slope * (beyond - end), rel=1e-13)
        assert table.value(0, beyond, order=1) == pytest.approx(slope, rel=1e-12)
        assert table.value(0, beyond, order=2) == 0
    held = Table1D(np.c_[x, np.sin(x)], smoothness=smoothness, extrapolation=E.HoldLastPoint)
    assert held.value(0, 9.0) == pytest.approx(np.sin(x[-1]), rel=1e-15)


@pytest.mark.parametrize("smoothness", SPLINES)
def test_splines_of_two_rows_are_linear_and_of_one_row_constant(smoothness):
    """As the C code: fewer than three rows make no spline."""
    two = Table1D([[1, 2], [3, 6]], smoothness=smoothness)
    assert (two.value(0, 2.0), two.value(0, 5.0), two.value(0, 2.0, order=2)) == (4, 10, 0)
    one = Table1D([[1, 2, 7]], smoothness=smoothness, extrapolation=E.NoExtrapolation)
    assert (one.value(0, -4.0), one.value(1, 9.0), one.value(1, 9.0, order=1)) == (2, 7, 0)
    assert one.outside(100.0) is False


@pytest.mark.parametrize("smoothness", SPLINES)
@FAST
@given(st.lists(st.floats(-10, 10, allow_nan=False), min_size=3, max_size=9),
       st.lists(st.floats(0.1, 3.0), min_size=8, max_size=8))
def test_splines_are_continuously_differentiable_at_the_knots(smoothness, ys, gaps):
    x = np.concatenate([[0.0], np.cumsum(gaps[:len(ys) - 1])])
    table = Table1D(np.c_[x, ys], smoothness=smoothness)
    scale = max(1.0, max(map(abs, ys)))
    for knot in x[1:-1]:
        left = np.nextafter(knot, -np.inf)
        assert table.value(0, left) == pytest.approx(table.value(0, knot), abs=1e-12 * scale)
        assert table.value(0, left, order=1) == pytest.approx(table.value(0, knot, order=1), abs=1e-8 * scale)


@pytest.mark.parametrize("smoothness", [S.MonotoneContinuousDerivative1, S.MonotoneContinuousDerivative2])
@FAST
@given(st.lists(st.floats(0, 100, allow_nan=False), min_size=3, max_size=10),
       st.lists(st.floats(0.05, 5.0), min_size=9, max_size=9), st.booleans())
def test_monotone_splines_preserve_monotone_data(smoothness, steps, gaps, decreasing):
    """Fritsch-Butland and Steffen interpolants of monotone data are monotone (Akima's need not be)."""
    x = np.concatenate([[0.0], np.cumsum(gaps[:len(steps) - 1])])
    y = np.cumsum(steps) * (-1 if decreasing else 1)
    table = Table1D(np.c_[x, y], smoothness=smoothness)
    u = np.linspace(x[0], x[-1], 2001)
    values = table.value(0, u) * (-1 if decreasing else 1)
    assert np.all(np.diff(values) >= -1e-9 * max(1.0, np.abs(y).max()))
    slopes = table.value(0, u, order=1) * (-1 if decreasing else 1)
    assert np.all(slopes >= -1e-9 * max(1.0, np.abs(y).max()))


def test_akima_overshoots_where_the_monotone_splines_do_not():
    """Ticket #1717's data set AKIMA 3: a monotone step, on which Akima's spline dips."""
    u = np.linspace(0, 15, 3001)
    dips = {s: np.diff(Table1D(AKIMA3, smoothness=s).value(0, u)).min() for s in SPLINES}
    assert dips[S.ContinuousDerivative] < -1e-3
    assert dips[S.MonotoneContinuousDerivative1] >= 0 and dips[S.MonotoneContinuousDerivative2] >= 0


@pytest.mark.parametrize("smoothness", ALL_SMOOTHNESS)
@FAST
@given(st.integers(-640, 640))
def test_periodic_extrapolation_repeats_the_table(smoothness, k):
    """value(u + T) == value(u) (abscissae on a binary grid, so u + T is exact).

    At the ends of the period, as in the C code, an abscissa above the table moves
    down to u_max (the last segment in force), one below it up to u_min.
    """
    table = Table1D([[0.25, 1], [0.5, 3], [1.0, 2], [1.5, -1], [2.25, 1]], smoothness=smoothness,
                    extrapolation=E.Periodic)
    u = 0.25 + (1 + k % 127) / 64      # inside (0.25, 2.25)
    for periods in (-3, -1, 1, 2, 5):
        assert table.value(0, u + 2.0 * periods) == table.value(0, u)
        assert table.value(0, u + 2.0 * periods, order=1) == table.value(0, u, order=1)
    for periods in (1, 3):
        assert table.value(0, 0.25 + 2.0 * periods, order=1) == table.value(0, 2.25, order=1)
        assert table.value(0, 0.25 - 2.0 * periods, order=1) == table.value(0, 0.25, order=1)
    assert table.outside(u + 4.0) is True     # the block's NoExtrapolation check is the plain range


@pytest.mark.parametrize("smoothness", SPLINES)
def test_derivatives_are_finite_differences(smoothness):
    x = np.array(KNOTS)
    table = Table1D(np.c_[x, np.exp(-x) * np.cos(2 * x)], smoothness=smoothness)
    middles = (x[:-1] + x[1:]) / 2 + 0.1 * np.diff(x)
    h = 1e-5
    for order in (1, 2, 3):
        central = (table.value(0, middles + h, order - 1) - table.value(0, middles - h, order - 1)) / (2 * h)
        np.testing.assert_allclose(table.value(0, middles, order), central, rtol=1e-6, atol=1e-6)
    assert np.all(table.value(0, middles, order=4) == 0)


@pytest.mark.parametrize("method, smoothness", [("akima", S.ContinuousDerivative),
                                                ("makima", S.ModifiedContinuousDerivative)])
@FAST
@given(st.lists(st.integers(-50, 50), min_size=3, max_size=12), st.lists(st.integers(1, 5), min_size=11,
                                                                          max_size=11))
def test_akima_and_makima_agree_with_scipy_inside_the_table(method, smoothness, ys, gaps):
    """Inside [u_min, u_max] scipy's Akima1DInterpolator is the same spline.

    Where they differ: scipy treats a knot whose two Akima weights sum to at most
    1e-9 of the largest sum as one without weights (the MSL only one whose weights
    are exactly zero), and outside the table scipy continues the end cubics
    (extrapolate=True) or gives nan, the MSL a line with the end slope.  Integer
    data keep the weights either zero or far from that threshold.
    """
    x = np.concatenate([[0.0], np.cumsum(gaps[:len(ys) - 1])]).astype(float)
    y = np.array(ys, dtype=float)
    ours = Table1D(np.c_[x, y], smoothness=smoothness)
    theirs = Akima1DInterpolator(x, y, method=method)
    u = np.linspace(x[0], x[-1], 301)
    np.testing.assert_allclose(ours.value(0, u), theirs(u), rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(ours.value(0, u, order=1), theirs(u, nu=1), rtol=1e-10, atol=1e-10)


# --------------------------------------------------------------------------------------
# scalars and arrays

@FAST
@given(st.sampled_from(ALL_SMOOTHNESS), st.sampled_from(list(E)),
       st.lists(st.floats(-3, 9, allow_nan=False), min_size=1, max_size=20), st.integers(0, 3))
def test_scalar_and_array_evaluation_agree_bit_for_bit_1d(smoothness, extrapolation, us, order):
    table = Table1D(np.c_[KNOTS, np.sin(KNOTS), np.cos(KNOTS)], smoothness=smoothness, extrapolation=extrapolation)
    for i in range(2):
        array = table.value(i, np.array(us), order)
        scalars = [table.value(i, u, order) for u in us]
        assert all(type(s) is float for s in scalars)
        assert array.tolist() == scalars


@FAST
@given(st.sampled_from([S.LinearSegments, S.ContinuousDerivative, S.ConstantSegments]), st.sampled_from(list(E)),
       st.lists(st.tuples(st.floats(-20, 70), st.floats(-20, 60)), min_size=1, max_size=12),
       st.integers(0, 2), st.integers(0, 2))
def test_scalar_and_array_evaluation_agree_bit_for_bit_2d(smoothness, extrapolation, points, order1, order2):
    table = Table2D(BIG, smoothness, extrapolation)
    u1, u2 = np.array(points).T
    array = table.value(u1, u2, order1, order2)
    assert array.tolist() == [table.value(a, b, order1, order2) for a, b in points]


@FAST
@given(st.sampled_from(ALL_SMOOTHNESS), st.sampled_from(list(E)), st.sampled_from(list(TimeEvents)),
       st.lists(st.floats(-2, 4), min_size=1, max_size=12), st.floats(-1, 1), st.floats(-1, 1), st.integers(0, 2))
def test_scalar_and_array_evaluation_agree_bit_for_bit_time_table(smoothness, extrapolation, events, ts, start,
                                                                  shift, order):
    data = [[0, 0], [0.5, 1], [1, 3], [1.5, 2], [2, 2.5]]
    if smoothness not in SPLINES:
        data.insert(2, [0.5, -1])
    table = TimeTable(data, None, smoothness, extrapolation, events)
    held = [table.next_event(t, start, shift) for t in ts]
    array = table.value(0, np.array(ts), np.array(held), start, shift, order)
    assert array.tolist() == [table.value(0, t, b, start, shift, order) for t, b in zip(ts, held)]
    # a scalar next_event with an array of times
    assert table.value(0, np.array(ts), held[0], start, shift, order).tolist() == \
        [table.value(0, t, held[0], start, shift, order) for t in ts]


def test_arrays_keep_their_shape_and_scalars_become_floats():
    table = Table1D([[0, 0], [1, 1]])
    assert table.value(0, np.zeros((2, 3))).shape == (2, 3)
    assert type(table.value(0, 1)) is float and type(table.value(0, np.float32(0.5))) is float
    surface = Table2D(BIG)
    assert surface.value(np.zeros((4, 1)), np.zeros(5)).shape == (4, 5)
    assert surface.outside(np.array([-1.0, 1.0]), 1.0).tolist() == [True, False]


def test_a_look_up_costs_about_as_much_in_a_large_table_as_in_a_small_one():
    """O(log n): bisection, no scan of the rows (timed generously against jitter)."""
    def cost(n):
        x = np.linspace(0.0, 1.0, n)
        table = Table1D(np.c_[x, np.sin(x)], smoothness=S.ContinuousDerivative)
        return min(timeit.repeat(lambda: table.value(0, 0.377), number=2000, repeat=5))
    assert cost(100_000) < 3 * cost(10)


# --------------------------------------------------------------------------------------
# 2-D tables

def plane_table(f, x, y):
    data = np.zeros((len(x) + 1, len(y) + 1))
    data[0, 1:], data[1:, 0] = y, x
    data[1:, 1:] = f(x[:, None], y[None, :])
    return data


X1, X2 = np.array([0.0, 1.0, 2.5, 3.0, 5.0]), np.array([-1.0, 0.0, 0.5, 2.0])


@pytest.mark.parametrize("smoothness", [S.LinearSegments, S.ContinuousDerivative])
def test_2d_interpolation_reproduces_a_plane_and_extrapolates_it(smoothness):
    def plane(a, b):
        return 1.0 + 2.0 * a - 3.0 * b
    table = Table2D(plane_table(plane, X1, X2), smoothness)
    u1, u2 = np.meshgrid(np.linspace(-2, 7, 37), np.linspace(-3, 4, 29))
    np.testing.assert_allclose(table.value(u1, u2), plane(u1, u2), rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(table.value(u1, u2, 1, 0), 2.0, rtol=1e-12)
    np.testing.assert_allclose(table.value(u1, u2, 0, 1), -3.0, rtol=1e-12)
    np.testing.assert_allclose(table.value(u1, u2, 1, 1), 0.0, atol=1e-12)


def test_bilinear_reproduces_a_bilinear_function_everywhere():
    def f(a, b):
        return 0.5 - a + 2 * b + 0.75 * a * b
    table = Table2D(plane_table(f, X1, X2))
    u1, u2 = np.meshgrid(np.linspace(-2, 7, 19), np.linspace(-3, 4, 15))
    np.testing.assert_allclose(table.value(u1, u2), f(u1, u2), rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(table.value(u1, u2, 1, 1), 0.75, rtol=1e-12)


def test_bilinear_agrees_with_scipy_regular_grid_interpolator():
    rng = np.random.default_rng(7)
    z = rng.normal(size=(len(X1), len(X2)))
    table = Table2D(plane_table(lambda a, b: z, X1, X2))
    theirs = RegularGridInterpolator((X1, X2), z, method="linear")
    points = np.c_[rng.uniform(X1[0], X1[-1], 500), rng.uniform(X2[0], X2[-1], 500)]
    np.testing.assert_allclose(table.value(points[:, 0], points[:, 1]), theirs(points), rtol=1e-12, atol=1e-12)


def test_akima_surface_is_continuously_differentiable_across_cells():
    table = Table2D(BIG, S.ContinuousDerivative)
    u2 = np.linspace(-3, 43, 47)
    for knot in (5.0, 20.0, 45.0):
        left = np.nextafter(knot, -np.inf)
        for orders in ((0, 0), (1, 0), (0, 1)):
            np.testing.assert_allclose(table.value(left, u2, *orders), table.value(knot, u2, *orders),
                                       rtol=1e-9, atol=1e-9)


def test_2d_partial_derivatives_are_finite_differences():
    table = Table2D(BIG, S.ContinuousDerivative)
    rng = np.random.default_rng(3)
    u1, u2 = rng.uniform(-5, 55, 200), rng.uniform(-5, 45, 200)
    h = 1e-5
    # the partial derivative (o1, o2) as a central difference along (e1, e2) of the partial (b1, b2)
    checks = {(1, 0): (1, 0, 0, 0), (0, 1): (0, 1, 0, 0), (2, 0): (1, 0, 1, 0), (1, 1): (0, 1, 1, 0),
              (0, 2): (0, 1, 0, 1)}
    for (o1, o2), (e1, e2, b1, b2) in checks.items():
        above = table.value(u1 + h * e1, u2 + h * e2, b1, b2)
        below = table.value(u1 - h * e1, u2 - h * e2, b1, b2)
        np.testing.assert_allclose(table.value(u1, u2, o1, o2), (above - below) / (2 * h), rtol=1e-5, atol=1e-5)


def test_2d_hold_last_point_clamps_the_inputs():
    for smoothness in (S.LinearSegments, S.ContinuousDerivative, S.ConstantSegments):
        table = Table2D(BIG, smoothness, E.HoldLastPoint)
        u1, u2 = np.array([-10.0, 60.0, 60.0, 12.0]), np.array([-7.0, 3.0, 99.0, 41.0])
        np.testing.assert_array_equal(table.value(u1, u2), table.value(np.clip(u1, 0, 50), np.clip(u2, 0, 40)))
        np.testing.assert_array_equal(table.value(u1, u2, 1, 0)[:3], 0)
        np.testing.assert_array_equal(table.value(u1, u2, 0, 1)[[0, 2, 3]], 0)


def test_2d_periodic_extrapolation_repeats_the_table():
    table = Table2D(BIG, S.ContinuousDerivative, E.Periodic)
    u1, u2 = np.linspace(1, 49, 13), np.linspace(1, 39, 13)
    np.testing.assert_allclose(table.value(u1 + 100, u2 - 80), table.value(u1, u2), rtol=1e-12)


def test_a_2d_table_of_one_row_ignores_u1():
    table = Table2D([[0, 1, 2, 3], [7, 1, 4, 9]], S.ContinuousDerivative)
    as_1d = Table1D([[1, 1], [2, 4], [3, 9]], smoothness=S.ContinuousDerivative)
    u = np.linspace(0, 4, 41)
    np.testing.assert_array_equal(table.value(123.0, u), as_1d.value(0, u))
    np.testing.assert_array_equal(table.value(-5.0, u, 1, 0), 0)
    assert table.outside(1e9, 2.0) is False and table.outside(0.0, 4.0) is True
    assert Table2D([[0, 1], [7, 3]]).value(-4.0, 12.0) == 3.0


# --------------------------------------------------------------------------------------
# time tables

def test_time_table_example_of_the_combi_time_table_documentation():
    """Sources.mo: extrapolation = LastTwoPoints, timeEvents = AtDiscontinuities."""
    table = TimeTable([[0, 0], [1, 0], [1, 1], [2, 4], [3, 9], [4, 16]],
                      time_events=TimeEvents.AtDiscontinuities, name="doc")
    held = table.next_event(0.0, 0.0, 0.0)
    assert held == 1.0
    assert table.value(0, 1.0, held, 0.0, 0.0) == 0.0          # before the event
    held = table.next_event(1.0, 0.0, 0.0)
    assert held == 4.0 and table.value(0, 1.0, held, 0.0, 0.0) == 1.0   # after it
    assert table.value(0, 1.5, held, 0.0, 0.0) == 2.5
    assert table.value(0, 2.0, held, 0.0, 0.0) == 4.0
    held = table.next_event(4.0, 0.0, 0.0)
    assert held == math.inf and table.value(0, 5.0, held, 0.0, 0.0) == 23.0


def events(table, start=0.0, shift=0.0, t=-1.0, until=10.0):
    found = []
    while t < until:
        t = table.next_event(t, start, shift)
        found.append(t)
    return found


def test_time_events_follow_the_options():
    data = [[0, 0], [1, 0], [1, 1], [2, 4], [3, 9], [4, 16]]
    assert events(TimeTable(data)) == [0, 1, 2, 3, 4, math.inf]
    assert events(TimeTable(data, time_events=TimeEvents.AtDiscontinuities)) == [0, 1, 4, math.inf]
    assert events(TimeTable(data, time_events=TimeEvents.NoTimeEvents)) == [0, 4, math.inf]
    assert events(TimeTable(data, smoothness=S.ConstantSegments, time_events=TimeEvents.NoTimeEvents)) == \
        [0, 1, 2, 3, 4, math.inf]
    smooth = [[0, 0], [1, 0], [2, 4], [3, 9], [4, 16]]
    assert events(TimeTable(smooth, smoothness=S.ContinuousDerivative)) == [0, 4, math.inf]
    # startTime comes first, then the shifted table events after it
    assert events(TimeTable(data), start=2.5, shift=1.0) == [2.5, 3, 4, 5, math.inf]
    # periodic: every period again
    assert events(TimeTable(smooth, smoothness=S.ContinuousDerivative, extrapolation=E.Periodic),
                  start=-1.0, t=-1.0, until=9.0) == [0, 4, 8, 12]
    assert events(TimeTable(data, extrapolation=E.Periodic), start=0.5, shift=0.5, t=0.0, until=6.0) == \
        [0.5, 1.5, 2.5, 3.5, 4.5, 5.5, 6.5]
    assert events(TimeTable([[0.5, 2, 3]])) == [0.0, math.inf]      # one row: no table events


def test_nearly_equal_times_are_a_jump():
    """The C code's isNearlyEqual: times closer than 1e-10 relative are one time, a jump."""
    table = TimeTable([[0, 0], [1, 1], [1 + 1e-12, 5], [2, 5]])
    assert events(table) == [0, 1, 2, math.inf]
    assert table.value(0, 1.0, 1.0, 0, 0) == 1.0 and table.value(0, 1.0, 2.0, 0, 0) == 5.0
    assert table.value(0, 1.0 + 5e-13, 2.0, 0, 0, order=1) == 0.0
    with pytest.raises(TableError, match="rows 2 to 4"):
        TimeTable([[0, 0], [1, 1], [1 + 1e-12, 5], [1 + 2e-12, 6]])
    separate = TimeTable([[0, 0], [1, 1], [1 + 1e-9, 5], [2, 5]])
    assert events(separate) == [0, 1, 1 + 1e-9, 2, math.inf]


def test_time_table_is_zero_before_start_and_jumps_at_start():
    table = TimeTable([[0, 1], [10, 11]])
    start = shift = 2.0
    held = table.next_event(0.0, start, shift)
    assert held == 2.0
    assert table.value(0, 1.0, held, start, shift) == 0.0
    assert table.value(0, 2.0, held, start, shift) == 0.0      # at the start event, before it
    held = table.next_event(2.0, start, shift)
    assert held == 12.0 and table.value(0, 2.0, held, start, shift) == 1.0
    assert table.value(0, 7.0, held, start, shift, order=1) == 1.0
    assert table.value(0, 1.0, 2.0, start, shift, order=1) == 0.0


def test_time_table_holds_the_segment_in_force_past_the_event():
    """An integrator's overshoot past the event instant extends the segment, it does not jump."""
    table = TimeTable([[0, 0], [1, 2], [1, 5], [2, 5]])
    held = table.next_event(0.5, 0.0, 0.0)
    assert held == 1.0
    assert table.value(0, 1.0 + 1e-9, held, 0.0, 0.0) == pytest.approx(2.0 + 2e-9)
    held = table.next_event(1.0, 0.0, 0.0)
    assert table.value(0, 1.0 - 1e-9, held, 0.0, 0.0) == 5.0
    # without events the table is evaluated as it stands: the right value at the jump
    plain = TimeTable([[0, 0], [1, 2], [1, 5], [2, 5]], time_events=TimeEvents.NoTimeEvents)
    held = plain.next_event(0.0, 0.0, 0.0)
    assert held == 2.0 and plain.value(0, 1.0, held, 0.0, 0.0) == 5.0 and plain.value(0, 0.5, held, 0.0, 0.0) == 1.0


def test_time_table_extrapolations():
    data = [[1, 1], [2, 3], [4, 2]]
    for extrapolation, left, right in ((E.HoldLastPoint, 1, 2), (E.LastTwoPoints, -1, 1),
                                       (E.NoExtrapolation, -1, 1)):
        table = TimeTable(data, extrapolation=extrapolation)
        assert table.value(0, 0.0, table.next_event(0.0, -5, 0), -5, 0) == left
        assert table.value(0, 6.0, table.next_event(6.0, -5, 0), -5, 0) == right
    periodic = TimeTable(data, extrapolation=E.Periodic)
    for t in (1.5, 2.5, 3.75):
        for k in (-2, 1, 3):
            assert periodic.value(0, t + 3 * k, periodic.next_event(t + 3 * k, -50, 0), -50, 0) == \
                pytest.approx(periodic.value(0, t, periodic.next_event(t, -50, 0), -50, 0), rel=1e-14)


def test_time_table_spline_continues_with_its_end_slope():
    """Akima's end slope by hand: the secants at the end are 0, 2 and, extended, 4, 6;
    their weights |6 - 4| and |2 - 0| are equal, so the slope is (2 + 4) / 2 = 3."""
    table = TimeTable(TICKET1039, smoothness=S.ContinuousDerivative)
    held = table.next_event(6.0, 0, 0)
    assert held == math.inf
    assert [table.value(0, 7.0, held, 0, 0, order) for order in (0, 1, 2)] == [3 + 3 * 2, 3, 0]
    assert Table1D(TICKET1039, smoothness=S.ContinuousDerivative).value(0, 7.0) == 9


# ======================================================================================
# errors
# ======================================================================================

BAD_TABLES = [   # (class, arguments, words the message must contain)
    (Table1D, dict(data=[]), ["empty"]),
    (Table1D, dict(data=[[]]), ["empty"]),
    (Table1D, dict(data=[0, 1, 2]), ["dimension"]),
    (Table1D, dict(data=[[[0, 1]]]), ["dimension"]),
    (Table1D, dict(data=[[0, 1], [1]]), ["numeric matrix"]),
    (Table1D, dict(data=[["a", 1]]), ["numeric matrix"]),
    (Table1D, dict(data=[[0], [1]]), ["too small"]),
    (Table1D, dict(data=[[0, 1], [1, np.nan]]), ["row 2", "column 2"]),
    (Table1D, dict(data=[[0, 1], [np.inf, 2]]), ["row 2", "column 1"]),
    (Table1D, dict(data=[[0, 1], [1, 2], [1, 3]]), ["row 3", "row 2"]),
    (Table1D, dict(data=[[0, 1], [2, 2], [1, 3]]), ["row 3", "row 2"]),
    (Table1D, dict(data=[[0, 1], [1, 2]], columns=[3]), ["column 3", "1..2"]),
    (Table1D, dict(data=[[0, 1], [1, 2]], columns=[0]), ["column 0"]),
    (Table1D, dict(data=[[0, 1], [1, 2]], columns=[1.5]), ["whole numbers"]),
    (Table1D, dict(data=[[0, 1], [1, 2]], smoothness=7), ["smoothness 7"]),
    (Table1D, dict(data=[[0, 1], [1, 2]], extrapolation=0), ["extrapolation 0"]),
    (TimeTable, dict(data=[[0, 1], [1, 2]], time_events=9), ["time_events 9"]),
    (TimeTable, dict(data=[[0, 1], [2, 2], [1, 3]]), ["row 3", "row 2"]),
    (TimeTable, dict(data=[[0, 1], [1, 2], [1, 3], [1, 4]]), ["rows 2 to 4"]),
    (TimeTable, dict(data=[[0, 1], [1, 2], [1, 3]], smoothness=S.ContinuousDerivative), ["row 3", "row 2"]),
    (TimeTable, dict(data=[[1, 1], [1, 2]], extrapolation=E.Periodic), ["periodic"]),
    (TimeTable, dict(data=[[0, 1], [1, np.nan]]), ["row 2", "column 2"]),
    (Table2D, dict(data=[[0, 1, 2]]), ["too small"]),
    (Table2D, dict(data=[[0, 1, 2], [1, 3, 4], [1, 5, 6]]), ["row 3", "row 2"]),
    (Table2D, dict(data=[[0, 2, 1], [1, 3, 4]]), ["row 1, column 3", "row 1, column 2"]),
    (Table2D, dict(data=[[0, 1, 2], [1, 3, np.nan]]), ["row 2", "column 3"]),
    (Table2D, dict(data=[[0, 1, 2], [1, 3, 4]], smoothness=S.MonotoneContinuousDerivative1),
     ["not available for 2-D"]),
    (Table2D, dict(data=[[0, 1, 2], [1, 3, 4]], extrapolation=11), ["extrapolation 11"]),
]


@pytest.mark.parametrize("cls, arguments, words", BAD_TABLES)
def test_bad_tables_raise_table_error_naming_table_and_row(cls, arguments, words):
    with pytest.raises(TableError) as raised:
        cls(**arguments, name="plant.curve")
    error = raised.value
    assert isinstance(error, ParameterError) and isinstance(error, ValueError)
    assert "'plant.curve'" in error.message
    for word in words:
        assert word in error.message
    assert error.hint


def test_the_corner_of_a_2d_table_is_not_checked():
    assert Table2D([[np.nan, 1, 2], [1, 3, 4]]).value(1.0, 1.5) == 3.5


def test_repeated_times_are_jumps_of_a_linear_time_table_and_tables_accept_any_sequence():
    table = TimeTable(((0, 1), (1, 2), (1, 3)), name="steps")
    assert table.t_min == 0 and table.t_max == 1 and table.columns == (2,) and table.n_outputs == 1
    assert not table.data.flags.writeable
    assert Table1D(np.array([[0, 1, 2], [1, 2, 3]]), columns=(3, 2)).value(1, 0.5) == 1.5
    with pytest.raises(IndexError):
        Table1D([[0, 1], [1, 2]]).value(1, 0.5)
    with pytest.raises(ValueError):
        Table1D([[0, 1], [1, 2]]).value(0, 0.5, order=-1)
