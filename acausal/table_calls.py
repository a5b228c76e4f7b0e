"""The numbers behind table functions: callables that generated code calls, numpy only.

A table in an equation is a sympy function class (:mod:`acausal.tables`);
what generated code calls is its ``_imp_``, one of the callables here.  They
import neither sympy nor the compiler and pickle with their data, so that a
saved run (:mod:`acausal.compiler.saved`) takes its tables along and a warm
command evaluates them without translating the model.

Each callable takes floats and returns a float, or takes numpy arrays (the
vectorised output functions) and returns an array.

* :class:`SegmentTable`: an ``n x 2`` table, linear between rows and through
  the first or last two rows outside them (CombiTable1D's LinearSegments with
  LastTwoPoints; the friction characteristics ``tau_pos`` and ``mu_pos``);
* :class:`StepTable`: its slopes, piecewise constant;
* :class:`ConstantTable`: a one-row table, or a one-segment slope;
* :class:`TableOutput`: an output of a table of :mod:`acausal.interpolation`
  (``Table1D``, ``Table2D``, ``TimeTable``) at given derivative orders;
* :class:`NextTableEvent`: a ``TimeTable``'s next event instant.
"""

from __future__ import annotations

from bisect import bisect_right
from typing import Any

import numpy as np

__all__ = ["SegmentTable", "StepTable", "ConstantTable", "TableOutput", "NextTableEvent", "TABLE_CALLS"]


class SegmentTable:
    """Linear interpolation through ``(xs[i], ys[i])`` with ``slopes[i]`` on segment ``i``,
    extrapolated through the first two points below and the last two above."""

    def __init__(self, xs: tuple, ys: tuple, slopes: tuple) -> None:
        self.xs, self.ys, self.slopes = tuple(xs), tuple(ys), tuple(slopes)
        # what every call reads (generated code calls it in the right-hand side)
        self._last = len(self.xs) - 2
        self._x_last, self._y_last, self._s_last = self.xs[-1], self.ys[-1], self.slopes[-1]
        self._arrays = None

    def __getstate__(self) -> dict:
        return {"xs": self.xs, "ys": self.ys, "slopes": self.slopes}

    def __setstate__(self, state: dict) -> None:
        self.__init__(state["xs"], state["ys"], state["slopes"])

    def __call__(self, x):
        if isinstance(x, np.ndarray):
            return self.vector(x)
        return self.scalar(float(x))

    def scalar(self, x: float) -> float:
        xs = self.xs
        i = bisect_right(xs, x) - 1
        if i > self._last:  # at or beyond the last breakpoint: anchor at the last row
            return self._y_last + self._s_last * (x - self._x_last)
        if i < 0:
            i = 0
        return self.ys[i] + self.slopes[i] * (x - xs[i])

    def vector(self, x):
        if self._arrays is None:
            self._arrays = (np.array(self.xs), np.array(self.ys), np.array(self.slopes))
        xa, ya, sa = self._arrays
        last = self._last
        arr = np.asarray(x, dtype=float)
        i = np.searchsorted(xa, arr, side="right") - 1
        high = i > last
        i = np.clip(i, 0, last)
        y = np.where(high, self._y_last + self._s_last * (arr - self._x_last), ya[i] + sa[i] * (arr - xa[i]))
        return float(y) if y.ndim == 0 else y


class StepTable:
    """Piecewise constant: ``values[i]`` on ``[xs[i], xs[i+1])``, the first and last value outside."""

    def __init__(self, xs: tuple, values: tuple) -> None:
        self.xs, self.values = tuple(xs), tuple(values)
        self._arrays = None

    def __getstate__(self) -> dict:
        return {"xs": self.xs, "values": self.values}

    def __setstate__(self, state: dict) -> None:
        self.__init__(state["xs"], state["values"])

    def __call__(self, x):
        if isinstance(x, np.ndarray):
            return self.vector(x)
        return self.scalar(float(x))

    def scalar(self, x: float) -> float:
        last = len(self.values) - 1
        i = bisect_right(self.xs, x) - 1
        return self.values[0 if i < 0 else last if i > last else i]

    def vector(self, x):
        if self._arrays is None:
            self._arrays = (np.array(self.xs), np.array(self.values))
        xa, va = self._arrays
        arr = np.asarray(x, dtype=float)
        i = np.clip(np.searchsorted(xa, arr, side="right") - 1, 0, len(self.values) - 1)
        y = va[i]
        return float(y) if y.ndim == 0 else y


class ConstantTable:
    """The same value everywhere."""

    def __init__(self, value: float) -> None:
        self.value = value

    def __call__(self, x):
        if isinstance(x, np.ndarray):
            return self.vector(x)
        return self.value

    def scalar(self, x: float) -> float:
        return self.value

    def vector(self, x):
        arr = np.asarray(x, dtype=float)
        return self.value if arr.ndim == 0 else np.full(arr.shape, self.value)


class TableOutput:
    """An output of a table of :mod:`acausal.interpolation` at derivative ``orders``.

    ``shape`` is ``"1d"`` (``f(u)``: ``Table1D.value(output, u, order)``), ``"2d"``
    (``f(u1, u2)``: ``Table2D.value(u1, u2, o1, o2)``) or ``"time"`` (``f(t,
    next_event, start, shift)``: ``TimeTable.value(output, t, next_event, start,
    shift, order)``).
    """

    def __init__(self, shape: str, table: Any, output: int, orders: tuple) -> None:
        if shape not in ("1d", "2d", "time"):
            raise ValueError(f"a table output's shape is '1d', '2d' or 'time', not {shape!r}")
        self.shape, self.table, self.output, self.orders = shape, table, output, tuple(orders)

    def __call__(self, *args):
        table, orders = self.table, self.orders
        if self.shape == "1d":
            return table.value(self.output, args[0], orders[0])
        if self.shape == "2d":
            return table.value(args[0], args[1], orders[0], orders[1])
        t, next_event, start, shift = args
        return table.value(self.output, t, next_event, start, shift, orders[0])


class NextTableEvent:
    """A ``TimeTable``'s next event instant after scaled time ``t``: ``f(t, start, shift)``."""

    def __init__(self, table: Any) -> None:
        self.table = table

    def __call__(self, t, start, shift):
        if isinstance(t, np.ndarray):
            return np.vectorize(self.table.next_event, otypes=[float])(t, start, shift)
        return self.table.next_event(float(t), float(start), float(shift))


#: The callables of this module: what a saved run may take along as a table function.
TABLE_CALLS = (SegmentTable, StepTable, ConstantTable, TableOutput, NextTableEvent)
