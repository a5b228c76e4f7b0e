"""The numeric core of the Modelica Standard Library's interpolation tables.

Three classes evaluate tables the way MSL 4.1.0 does in
``ModelicaStandardTables.c`` (the external C code behind
``Modelica.Blocks.Tables.CombiTable1Ds/1Dv``, ``CombiTable2Ds/2Dv`` and
``Modelica.Blocks.Sources.CombiTimeTable``), in pure numpy:

* :class:`Table1D` -- a univariate table ``y_i(u)`` (CombiTable1D);
* :class:`Table2D` -- a bivariate table ``y(u1, u2)`` (CombiTable2D);
* :class:`TimeTable` -- a table of time (CombiTimeTable), stateless: the time
  events the C code tracks in its table object are an argument here.

Each evaluates a Python float to a Python float (``bisect`` on lists, no
numpy on that path) and a numpy array elementwise (``searchsorted``); both
paths do the same floating-point operations in the same order, so they agree
bit for bit.  A look-up costs O(log n) in the number of rows; the spline
coefficients are computed once, when the table is made.

Interpolation (:class:`Smoothness`)
    ``LinearSegments`` (linear, bilinear in 2-D), ``ConstantSegments``
    (the value of the row at or below the abscissa), and cubic Hermite splines
    whose knot slopes come from Akima's rule (``ContinuousDerivative``, the
    only spline of the 2-D table, there Akima's bivariate rule), its modified
    form (``ModifiedContinuousDerivative``, "makima"), Fritsch and Butland's
    monotone rule (``MonotoneContinuousDerivative1``) or Steffen's
    (``MonotoneContinuousDerivative2``).  Splines of one or two rows are
    linear (as in the C code); a 2-D Akima table of at most 2 x 2 values is
    bilinear, one of a single row or column is a 1-D Akima spline, and one
    with only two rows or columns of values extends them linearly (MSL
    tickets #1307 and #1820).

Extrapolation (:class:`Extrapolation`)
    ``HoldLastPoint`` holds the end value, ``LastTwoPoints`` continues with
    the end slope (linear through the last two rows for linear and constant
    segments; the slope of the spline at its end for the splines; in 2-D the
    first-order Taylor extension of the surface at its edge, including the
    mixed term at a corner), ``Periodic`` repeats the table.
    ``NoExtrapolation`` evaluates like ``LastTwoPoints``: the block asserts
    ``not table.outside(u)`` itself (the C code stops the simulation instead).

Derivatives
    ``order`` gives the derivatives MSL's ``getDer...Value`` and
    ``getDer2...Value`` functions give for a unit input rate (first and second
    derivative with respect to the abscissa), and beyond those the further
    derivatives of the piece in use (a cubic's third derivative, then zero).
    A derivative is that of the value function: at a knot it is the one of
    the segment to its right, as the C code's ``findRowIndex`` picks it; the
    2-D table, like the C code, uses the right-hand side of its last knot for
    a derivative along that axis (the extension beyond it).

References
----------
.. [1] H. Akima, "A new method of interpolation and smooth curve fitting based
   on local procedures", Journal of the ACM 17(4), 589-602, 1970.
   https://doi.org/10.1145/321607.321609
.. [2] H. Akima, "A method of bivariate interpolation and smooth surface
   fitting based on local procedures", Communications of the ACM 17(1),
   18-20, 1974.  https://doi.org/10.1145/360767.360779
.. [3] F. N. Fritsch and J. Butland, "A method for constructing local monotone
   piecewise cubic interpolants", SIAM Journal on Scientific and Statistical
   Computing 5(2), 300-304, 1984.  https://doi.org/10.1137/0905021
.. [4] M. Steffen, "A simple method for monotonic interpolation in one
   dimension", Astronomy and Astrophysics 239, 443-450, 1990.
.. [5] C. Moler (with C. Ionita), "Makima piecewise cubic interpolation",
   Cleve's Corner, MathWorks blog, 2019; MATLAB ``makima``.
   https://blogs.mathworks.com/cleve/2019/04/29/makima-piecewise-cubic-interpolation/
.. [6] Modelica Standard Library 4.1.0, ``Modelica/Resources/C-Sources/
   ModelicaStandardTables.c``, ``Modelica.Blocks.Tables`` and
   ``Modelica.Blocks.Sources.CombiTimeTable``.
"""

from __future__ import annotations

import enum
import math
import operator
from bisect import bisect_left, bisect_right
from typing import Any

import numpy as np

from .errors import TableError

__all__ = ["Smoothness", "Extrapolation", "TimeEvents", "Table1D", "Table2D", "TimeTable"]


class Smoothness(enum.IntEnum):
    """How a table interpolates between its rows (``Modelica.Blocks.Types.Smoothness``)."""

    LinearSegments = 1
    ContinuousDerivative = 2            # Akima spline
    ConstantSegments = 3
    MonotoneContinuousDerivative1 = 4   # Fritsch-Butland spline
    MonotoneContinuousDerivative2 = 5   # Steffen spline
    ModifiedContinuousDerivative = 6    # modified Akima spline (makima)


class Extrapolation(enum.IntEnum):
    """What a table gives outside its abscissa range (``Modelica.Blocks.Types.Extrapolation``)."""

    HoldLastPoint = 1
    LastTwoPoints = 2
    Periodic = 3
    NoExtrapolation = 4


class TimeEvents(enum.IntEnum):
    """Which table times of a CombiTimeTable are time events (``Modelica.Blocks.Types.TimeEvents``)."""

    Always = 1
    AtDiscontinuities = 2
    NoTimeEvents = 3


_SPLINES = frozenset({Smoothness.ContinuousDerivative, Smoothness.ModifiedContinuousDerivative,
                      Smoothness.MonotoneContinuousDerivative1, Smoothness.MonotoneContinuousDerivative2})

#: relative tolerance of the C code's isNearlyEqual (its _EPSILON)
_EPSILON = 1e-10


# --------------------------------------------------------------------------------------
# checks of the table data
# --------------------------------------------------------------------------------------

def _matrix(data: Any, name: str, kind: str, min_rows: int) -> np.ndarray:
    """``data`` as a finite float matrix with at least ``min_rows`` rows and 2 columns."""
    example = "e.g. [[0, 1], [1, 3]]"
    try:
        matrix = np.array(data, dtype=float)
    except (TypeError, ValueError) as exc:
        raise TableError(f"table {name!r} is not a numeric matrix",
                         hint=f"give a list of equally long rows of numbers or a 2-D array, {example}") from exc
    if matrix.size == 0:
        raise TableError(f"table {name!r} is empty (shape {matrix.shape})",
                         hint=f"give at least {min_rows} row(s) of at least 2 columns, {example}")
    if matrix.ndim != 2:
        raise TableError(f"table {name!r} has {matrix.ndim} dimension(s), not 2",
                         hint="give a matrix, one list per row; a single row is [[u, y1, y2]]")
    rows, cols = matrix.shape
    if rows < min_rows or cols < 2:
        raise TableError(f"table {name!r} of shape {rows} x {cols} is too small for {kind}",
                         hint=f"{kind} needs at least {min_rows} row(s) and 2 columns")
    bad = ~np.isfinite(matrix)
    if kind.startswith("2-D"):
        bad[0, 0] = False   # the corner of a 2-D table is not used
    if bad.any():
        row, col = (int(k) for k in np.argwhere(bad)[0])
        raise TableError(f"table {name!r}: row {row + 1}, column {col + 1} is {matrix[row, col]!r}",
                         hint="every entry of a table must be a finite number")
    matrix.setflags(write=False)
    return matrix


def _option(cls: type[enum.IntEnum], value: Any, name: str, what: str) -> Any:
    """``value`` as a member of the enum ``cls`` (members or their integer values)."""
    try:
        return cls(value)
    except (ValueError, TypeError):
        choices = ", ".join(f"{cls.__name__}.{m.name} ({m.value})" for m in cls)
        raise TableError(f"table {name!r}: unknown {what} {value!r}",
                         hint=f"use one of {choices}") from None


def _columns(columns: Any, n_cols: int, name: str) -> tuple[int, ...]:
    """The 1-based column numbers to interpolate (default: 2 .. n_cols)."""
    if columns is None:
        return tuple(range(2, n_cols + 1))
    try:
        chosen = tuple(operator.index(c) for c in np.atleast_1d(np.asarray(columns, dtype=object)))
    except TypeError:
        raise TableError(f"table {name!r}: columns must be whole numbers, not {columns!r}",
                         hint="give 1-based column numbers, e.g. columns=(2, 3)") from None
    for c in chosen:
        if not 1 <= c <= n_cols:
            raise TableError(f"table {name!r}: column {c} is out of range 1..{n_cols}",
                             hint=f"the table has {n_cols} columns; column 1 is the abscissa")
    return chosen


def _check_increasing(x: np.ndarray, name: str, what: str, strict: bool,
                      place: Any, hint: str) -> None:
    """Raise unless ``x`` increases (strictly, or never decreases).

    ``place(k)`` names entry ``k`` of ``x`` in the table (e.g. "row 3").
    """
    steps = np.diff(x)
    bad = steps <= 0 if strict else steps < 0
    if bad.any():
        k = int(np.argmax(bad)) + 1
        relation = "is not greater than" if strict else "is less than"
        raise TableError(f"table {name!r}: {what} {x[k]:.17g} in {place(k)} {relation} "
                         f"{x[k - 1]:.17g} in {place(k - 1)}", hint=hint)


def _check_order(order: Any) -> int:
    order = operator.index(order)
    if order < 0:
        raise ValueError(f"the order of a derivative must be >= 0, not {order}")
    return order


def _nearly_equal(a: Any, b: Any) -> Any:
    """The C code's isNearlyEqual: ``|b - a| < 1e-10 * max(|a|, |b|, 1e-10)``."""
    scale = np.maximum(np.maximum(np.abs(a), np.abs(b)), _EPSILON) * _EPSILON
    return np.abs(b - a) < scale


# --------------------------------------------------------------------------------------
# univariate cubic Hermite splines (computed once, for all columns at a time)
# --------------------------------------------------------------------------------------

def _secants(x: np.ndarray, Y: np.ndarray) -> np.ndarray:
    """Divided differences ``(y[i+1] - y[i]) / (x[i+1] - x[i])``, shape (n-1, k)."""
    return (Y[1:] - Y[:-1]) / (x[1:] - x[:-1])[:, None]


def _akima_slopes(x: np.ndarray, Y: np.ndarray, modified: bool) -> np.ndarray:
    """Knot slopes of Akima's spline [1]_, or of the modified Akima spline [5]_.

    The secants are extended by two on each side along a parabola (Akima's
    end conditions, as the C code).  The slope at a knot weights the two
    adjacent secants by the change of the secants on the far side of each:
    ``s = (w_r d_l + w_l d_r) / (w_l + w_r)``, ``w_l = |d_l - d_ll|`` and
    ``w_r = |d_rr - d_r|``.  The modified rule adds ``|d_ll + d_l| / 2`` and
    ``|d_r + d_rr| / 2`` to the weights, which damps overshoots where the data
    are flat.  Where both weights vanish the slope is the mean of the adjacent
    secants (Akima) or zero (modified).
    """
    d = _secants(x, Y)
    n = len(x)
    D = np.empty((n + 3, d.shape[1]))
    D[2:n + 1] = d
    D[1] = 2 * D[2] - D[3]
    D[0] = 3 * D[2] - 2 * D[3]
    D[n + 1] = 2 * D[n] - D[n - 1]
    D[n + 2] = 3 * D[n] - 2 * D[n - 1]
    far_left, left, right, far_right = D[:-3], D[1:-2], D[2:-1], D[3:]   # four secants around each knot
    w_right = np.abs(far_right - right)
    w_left = np.abs(left - far_left)
    if modified:
        w_right_total = w_right + w_left + (0.5 * np.abs(far_right + right) + 0.5 * np.abs(left + far_left))
        w_left = w_left + 0.5 * np.abs(left + far_left)
        total, fallback = w_right_total, np.zeros_like(left)
    else:
        total, fallback = w_right + w_left, 0.5 * left + 0.5 * right
    with np.errstate(divide="ignore", invalid="ignore"):
        a = w_left / total
        weighted = (1 - a) * left + a * right
    return np.where(total > 0, weighted, fallback)


def _fritsch_butland_slopes(x: np.ndarray, Y: np.ndarray) -> np.ndarray:
    """Knot slopes of Fritsch and Butland's monotone spline [3]_.

    An interior slope is the weighted harmonic mean of the adjacent secants,
    ``3 (h_l + h_r) / ((h_l + 2 h_r) / d_l + (h_r + 2 h_l) / d_r)``, and zero
    where they differ in sign or one is zero (a local extremum).  The end
    slopes are the end secants (as the C code).
    """
    d = _secants(x, Y)
    h = np.diff(x)[:, None]
    S = np.empty_like(Y)
    S[0], S[-1] = d[0], d[-1]
    dl, dr, hl, hr = d[:-1], d[1:], h[:-1], h[1:]
    with np.errstate(divide="ignore", invalid="ignore"):
        mean = 3 * (hl + hr) / ((hl + 2 * hr) / dl + (hr + 2 * hl) / dr)
    S[1:-1] = np.where((dl == 0) | (dr == 0) | ((dl < 0) & (dr > 0)) | ((dl > 0) & (dr < 0)), 0.0, mean)
    return S


def _steffen_slopes(x: np.ndarray, Y: np.ndarray) -> np.ndarray:
    """Knot slopes of Steffen's monotone spline [4]_.

    An interior slope is that of the parabola through the knot and its two
    neighbours, ``(d_l h_r + d_r h_l) / (h_l + h_r)``, limited to twice the
    smaller adjacent secant (and zero where the secants differ in sign or one
    is zero).  The end slopes are the end secants (as the C code, where
    Steffen's paper has a limited parabola).
    """
    d = _secants(x, Y)
    h = np.diff(x)[:, None]
    S = np.empty_like(Y)
    S[0], S[-1] = d[0], d[-1]
    dl, dr, hl, hr = d[:-1], d[1:], h[:-1], h[1:]
    parabola = (dl * hr + dr * hl) / (hl + hr)
    half = 0.5 * np.abs(parabola)
    limit = np.where(dl > 0, 2.0, -2.0) * np.minimum(np.abs(dl), np.abs(dr))
    slope = np.where((half > np.abs(dl)) | (half > np.abs(dr)), limit, parabola)
    S[1:-1] = np.where((dl == 0) | (dr == 0) | ((dl < 0) & (dr > 0)) | ((dl > 0) & (dr < 0)), 0.0, slope)
    return S


_SLOPES = {
    Smoothness.ContinuousDerivative: lambda x, Y: _akima_slopes(x, Y, modified=False),
    Smoothness.ModifiedContinuousDerivative: lambda x, Y: _akima_slopes(x, Y, modified=True),
    Smoothness.MonotoneContinuousDerivative1: _fritsch_butland_slopes,
    Smoothness.MonotoneContinuousDerivative2: _steffen_slopes,
}


def _hermite(x: np.ndarray, Y: np.ndarray, S: np.ndarray) -> np.ndarray:
    """Power-basis coefficients of the cubic Hermite segments with knot slopes ``S``.

    Returns ``C`` of shape (n-1, k, 4): on segment ``i``,
    ``y = C0 + C1 v + C2 v^2 + C3 v^3`` with ``v = u - x[i]``.
    """
    d = _secants(x, Y)
    h = np.diff(x)[:, None]
    C = np.empty((len(x) - 1, Y.shape[1], 4))
    C[..., 0] = Y[:-1]
    C[..., 1] = S[:-1]
    C[..., 2] = (3 * d - 2 * S[:-1] - S[1:]) / h
    C[..., 3] = (S[:-1] + S[1:] - 2 * d) / (h * h)
    return C


def _horner(c0: Any, c1: Any, c2: Any, c3: Any, v: Any, order: int) -> Any:
    """Derivative ``order`` of ``c0 + c1 v + c2 v^2 + c3 v^3`` (floats or arrays alike)."""
    if order == 0:
        return ((c3 * v + c2) * v + c1) * v + c0
    if order == 1:
        return (3.0 * c3 * v + 2.0 * c2) * v + c1
    if order == 2:
        return 6.0 * c3 * v + 2.0 * c2
    if order == 3:
        return 6.0 * c3 + 0.0 * c0
    return 0.0 * c0


def _wrap_scalar(u: float, lo: float, hi: float) -> float:
    """``u`` moved by whole periods ``hi - lo`` into ``[lo, hi]`` (unchanged inside)."""
    period = hi - lo
    if u < lo:
        u = u + math.ceil((lo - u) / period) * period
    elif u > hi:
        u = u - math.ceil((u - hi) / period) * period
    return min(max(u, lo), hi)


def _wrap_array(u: np.ndarray, lo: float, hi: float) -> np.ndarray:
    period = hi - lo
    with np.errstate(invalid="ignore"):
        up = u + np.ceil((lo - u) / period) * period
        down = u - np.ceil((u - hi) / period) * period
    u = np.where(u < lo, up, np.where(u > hi, down, u))
    return np.minimum(np.maximum(u, lo), hi)


# --------------------------------------------------------------------------------------
# a piecewise cubic curve with its two extrapolation pieces
# --------------------------------------------------------------------------------------

class _Curve:
    """Piecewise cubic ``y_j(u)`` on knots ``x`` for the columns ``j`` of ``Y``.

    Pieces are numbered ``q = 0 .. n``: ``q = 0`` extrapolates below ``x[0]``,
    ``q = i + 1`` is the segment from row ``i`` to row ``i + 1``, ``q = n``
    extrapolates above ``x[-1]``.  Piece ``q`` is a cubic in ``u - origin[q]``.
    """

    def __init__(self, x: np.ndarray, Y: np.ndarray, smoothness: Smoothness,
                 extrapolation: Extrapolation, jumps: bool = False) -> None:
        n, k = Y.shape
        self.n = n
        self.x = np.ascontiguousarray(x, dtype=float)
        self.x_list = self.x.tolist()
        self.lo, self.hi = float(x[0]), float(x[-1])
        self.Y = np.ascontiguousarray(Y, dtype=float)
        self.Y_list = self.Y.T.tolist()
        self.constant = smoothness == Smoothness.ConstantSegments
        self.periodic = extrapolation == Extrapolation.Periodic and n > 1
        if n <= 2 and smoothness in _SPLINES:
            smoothness = Smoothness.LinearSegments
        origin = np.empty(n + 1)
        origin[0], origin[1:n], origin[n] = x[0], x[:-1], x[-1]
        coef = np.zeros((n + 1, k, 4))
        if n == 1:
            coef[..., 0] = Y[0]
        else:
            if smoothness in _SPLINES:
                segments = _hermite(x, Y, _SLOPES[smoothness](x, Y))
                w, last = x[-1] - x[-2], segments[-1]
                left_slope = segments[0, :, 1]
                right_slope = (3 * last[:, 3] * w + 2 * last[:, 2]) * w + last[:, 1]
            else:
                # a repeated abscissa (a jump of a time table) is a segment of no length:
                # it gives the value of its upper row and no slope
                flat = _nearly_equal(x[:-1], x[1:]) if jumps else np.zeros(n - 1, bool)
                with np.errstate(divide="ignore", invalid="ignore"):
                    slope = np.where(flat[:, None], 0.0, _secants(x, Y))
                segments = np.zeros((n - 1, k, 4))
                if smoothness == Smoothness.ConstantSegments:
                    segments[..., 0] = Y[:-1]
                else:
                    segments[..., 0] = np.where(flat[:, None], Y[1:], Y[:-1])
                    segments[..., 1] = slope
                left_slope, right_slope = slope[0], slope[-1]
            if extrapolation == Extrapolation.HoldLastPoint:
                left_slope, right_slope = 0.0 * left_slope, 0.0 * right_slope
            coef[1:n] = segments
            coef[0, :, 0], coef[0, :, 1] = Y[0], left_slope
            coef[n, :, 0], coef[n, :, 1] = Y[-1], right_slope
        self.origin = origin
        self.origin_list = origin.tolist()
        self.coef = np.ascontiguousarray(coef.transpose(1, 0, 2))            # (k, n+1, 4)
        self.coef_list = self.coef.tolist()                                 # [col][q] -> [c0, c1, c2, c3]

    # the piece holding u: the in-table segment, or an extrapolation piece
    def piece_scalar(self, u: float, right_at_max: bool) -> int:
        if u < self.lo:
            return 0
        if u > self.hi or (right_at_max and u == self.hi):
            return self.n
        return min(bisect_right(self.x_list, u), self.n - 1)

    def piece_array(self, u: np.ndarray, right_at_max: bool) -> np.ndarray:
        q = np.minimum(np.searchsorted(self.x, u, side="right"), self.n - 1)
        right = (u > self.hi) | (u == self.hi) if right_at_max else u > self.hi
        return np.where(u < self.lo, 0, np.where(right, self.n, q))

    def at_scalar(self, col: int, q: int, u: float, order: int) -> float:
        c0, c1, c2, c3 = self.coef_list[col][q]
        return _horner(c0, c1, c2, c3, u - self.origin_list[q], order)

    def at_array(self, col: int, q: np.ndarray, u: np.ndarray, order: int) -> np.ndarray:
        c = self.coef[col][q]
        return _horner(c[..., 0], c[..., 1], c[..., 2], c[..., 3], u - self.origin[q], order)

    def scalar(self, col: int, u: float, order: int, right_at_max: bool = False) -> float:
        """The table's value (derivative ``order``) at ``u`` for column ``col``."""
        if self.n == 1:
            return self.Y_list[col][0] if order == 0 else 0.0
        if self.periodic:
            u = _wrap_scalar(u, self.lo, self.hi)
            right_at_max = False
        q = self.piece_scalar(u, right_at_max)
        if self.constant and 0 < q < self.n:
            if order:
                return 0.0
            return self.Y_list[col][min(bisect_right(self.x_list, u), self.n) - 1]
        return self.at_scalar(col, q, u, order)

    def array(self, col: int, u: np.ndarray, order: int, right_at_max: bool = False) -> np.ndarray:
        if self.n == 1:
            return np.full(u.shape, self.Y[0, col] if order == 0 else 0.0)
        if self.periodic:
            u = _wrap_array(u, self.lo, self.hi)
            right_at_max = False
        q = self.piece_array(u, right_at_max)
        y = self.at_array(col, q, u, order)
        if self.constant:
            inside = (q > 0) & (q < self.n)
            row = np.minimum(np.searchsorted(self.x, u, side="right"), self.n) - 1
            y = np.where(inside, self.Y[row, col] if order == 0 else 0.0, y)
        return y


def _is_scalar(u: Any) -> bool:
    return isinstance(u, (float, int)) or (isinstance(u, np.generic) and np.ndim(u) == 0)


def _output(y: Any) -> Any:
    """A 0-d array result as a numpy scalar, any other array as it is."""
    return y[()] if isinstance(y, np.ndarray) and y.ndim == 0 else y


# --------------------------------------------------------------------------------------
# CombiTable1D
# --------------------------------------------------------------------------------------

class Table1D:
    """A univariate interpolation table (CombiTable1Ds / CombiTable1Dv).

    Parameters
    ----------
    data : array_like, shape (n, m)
        The table matrix: column 1 holds the abscissae ``u`` (strictly
        increasing), the others the ordinates.  Lists, tuples and arrays are
        accepted; ``n >= 1``, ``m >= 2``.
    columns : sequence of int, optional
        The 1-based numbers of the columns to interpolate, one output each;
        ``2 .. m`` by default (MSL's ``columns = 2:size(table, 2)``).
    smoothness : Smoothness or int, optional
        The interpolation (default ``LinearSegments``).
    extrapolation : Extrapolation or int, optional
        The extrapolation (default ``LastTwoPoints``).
    name : str, keyword-only
        How error messages name the table.

    Attributes
    ----------
    name : str
    data : numpy.ndarray
        The table matrix (read-only float array).
    columns : tuple of int
    smoothness : Smoothness
    extrapolation : Extrapolation
    n_outputs : int
        ``len(columns)``.
    u_min, u_max : float
        The first and last abscissa.

    Raises
    ------
    TableError
        For an empty or non-numeric matrix, one that is not 2-D or has fewer
        than 2 columns, a non-finite entry, abscissae that do not strictly
        increase, a column number out of range, an unknown option.

    Notes
    -----
    Splines of fewer than three rows are linear, and a table of one row is
    constant (no interpolation, no extrapolation, as the C code).  Inside the
    table the value at ``u_max`` comes from the last segment (derivatives
    included); beyond it extrapolation takes over.  ``ConstantSegments`` gives
    the value of the row at or below ``u`` and extrapolates, with
    ``LastTwoPoints``, linearly through the last two rows (as the C code).

    Examples
    --------
    >>> table = Table1D([[0, 0], [1, 2], [2, 3]])
    >>> table.value(0, 0.5), table.value(0, 0.5, order=1), table.value(0, 3.0)
    (1.0, 2.0, 4.0)
    """

    def __init__(self, data: Any, columns: Any = None, smoothness: Any = Smoothness.LinearSegments,
                 extrapolation: Any = Extrapolation.LastTwoPoints, *, name: str = "table") -> None:
        self.name = str(name)
        self.smoothness = _option(Smoothness, smoothness, self.name, "smoothness")
        self.extrapolation = _option(Extrapolation, extrapolation, self.name, "extrapolation")
        self.data = _matrix(data, self.name, "a 1-D table", min_rows=1)
        self.columns = _columns(columns, self.data.shape[1], self.name)
        x = self.data[:, 0]
        _check_increasing(x, self.name, "abscissa", True, lambda k: f"row {k + 1}",
                          hint="the first column of a 1-D table must be strictly increasing: "
                               "sort the rows and remove repeated abscissae")
        self.n_outputs = len(self.columns)
        self.u_min, self.u_max = float(x[0]), float(x[-1])
        self._curve = _Curve(x, self.data[:, [c - 1 for c in self.columns]],
                             self.smoothness, self.extrapolation)

    def __repr__(self) -> str:
        return (f"Table1D({self.name!r}, {self.data.shape[0]} rows, columns={self.columns}, "
                f"{self.smoothness.name}, {self.extrapolation.name})")

    def value(self, i: int, u: Any, order: int = 0) -> Any:
        """Output ``i`` at ``u``, or its derivative of ``order`` with respect to ``u``.

        Parameters
        ----------
        i : int
            0-based index into :attr:`columns`.
        u : float or array_like
            The abscissa; an array is evaluated elementwise.
        order : int, optional
            0 for the value (MSL's ``getTable1DValue``), 1 for ``dy/du``
            (``getDerTable1DValue``), 2 for ``d2y/du2``
            (``getDer2Table1DValue``); higher orders give the further
            derivatives of the piece in use.

        Returns
        -------
        float or numpy.ndarray
            A Python float for a scalar ``u``, an array of ``u``'s shape
            otherwise.
        """
        order = _check_order(order) if order else 0
        col = self._output_index(i)
        if type(u) is float:
            return self._curve.scalar(col, u, order)
        if _is_scalar(u):
            return float(self._curve.scalar(col, float(u), order))
        return _output(self._curve.array(col, np.asarray(u, dtype=float), order))

    def outside(self, u: Any) -> Any:
        """Whether ``u`` lies outside ``[u_min, u_max]``.

        The block asserts ``not outside(u)`` for ``NoExtrapolation``.  A table
        of one row is never outside (the C code does not interpolate it).
        """
        if self.data.shape[0] == 1:
            return False if _is_scalar(u) else np.zeros(np.shape(u), bool)
        if _is_scalar(u):
            return bool(u < self.u_min or u > self.u_max)
        u = np.asarray(u, dtype=float)
        return _output((u < self.u_min) | (u > self.u_max))

    def _output_index(self, i: int) -> int:
        if not 0 <= i < self.n_outputs:
            raise IndexError(f"table {self.name!r} has {self.n_outputs} output(s); index {i} is out of range")
        return i


# --------------------------------------------------------------------------------------
# CombiTable2D
# --------------------------------------------------------------------------------------

_HERMITE = np.array([[1.0, 0.0, 0.0, 0.0],     # power-basis coefficients of the cubic with
                     [0.0, 0.0, 1.0, 0.0],     # values f(0), f(1) and slopes f'(0), f'(1)
                     [-3.0, 3.0, -2.0, -1.0],  # on [0, 1]
                     [2.0, -2.0, 1.0, 1.0]])


def _extended_knots(k: np.ndarray) -> np.ndarray:
    """Two more knots on each side of ``k`` for Akima's bivariate end conditions [2]_.

    Two knots extend linearly; more extend by mirroring the spacings at the ends.
    """
    if len(k) == 2:
        return np.array([3 * k[0] - 2 * k[1], 2 * k[0] - k[1], k[0], k[1],
                         2 * k[1] - k[0], 3 * k[1] - 2 * k[0]])
    return np.concatenate([[2 * k[0] - k[2], k[0] + k[1] - k[2]], k,
                           [k[-1] + k[-2] - k[-3], 2 * k[-1] - k[-3]]])


def _extend_values(ke: np.ndarray, V: np.ndarray) -> None:
    """Fill the two values beyond each end of the rows of ``V`` (knots ``ke``), in place.

    The values beyond an end make the secants there follow Akima's end rule
    (the secant beyond the end ``2 d0 - d1``, the next one ``3 d0 - 2 d1``,
    where ``d0`` is the end secant and ``d1`` its neighbour), with the knots
    of :func:`_extended_knots`; two values extend linearly.
    """
    if len(ke) == 6:
        V[:, 0] = 3 * V[:, 2] - 2 * V[:, 3]
        V[:, 1] = 2 * V[:, 2] - V[:, 3]
        V[:, 4] = 2 * V[:, 3] - V[:, 2]
        V[:, 5] = 3 * V[:, 3] - 2 * V[:, 2]
        return
    # left end: knots ke[0..4], known values V[2..4]
    a, b, c = ke[3] - ke[4], ke[2] - ke[3], ke[1] - ke[2]
    if a == 0 or b == 0 or c == 0:
        V[:, 0] = V[:, 1] = V[:, 2]
    else:
        d, e, f = ke[0] - ke[1], V[:, 3] - V[:, 4], V[:, 2] - V[:, 3]
        V[:, 1] = c * (2 * f / b - e / a) + V[:, 2]
        V[:, 0] = V[:, 1] + d * ((V[:, 1] - V[:, 2]) / c + f / b - e / a)
    # right end: knots ke[-5..-1], known values V[-5..-3]
    a, b, c = ke[-4] - ke[-5], ke[-3] - ke[-4], ke[-2] - ke[-3]
    if a == 0 or b == 0 or c == 0:
        V[:, -2] = V[:, -1] = V[:, -3]
    else:
        d, e, f = ke[-1] - ke[-2], V[:, -4] - V[:, -5], V[:, -3] - V[:, -4]
        V[:, -2] = c * (2 * f / b - e / a) + V[:, -3]
        V[:, -1] = V[:, -2] + d * ((V[:, -2] - V[:, -3]) / c + f / b - e / a)


def _akima_weighted(d1: np.ndarray, d2: np.ndarray, d3: np.ndarray, d4: np.ndarray):
    """Akima's slope from four consecutive secants, and the weights it used.

    ``(w2 d2 + w3 d3) / (w2 + w3)`` with ``w2 = |d4 - d3|``, ``w3 = |d2 - d1|``;
    the mean of ``d2`` and ``d3`` where both weights vanish (the weights are
    then 1 and 1 for the cross derivative).
    """
    w2, w3 = np.abs(d4 - d3), np.abs(d2 - d1)
    flat = (d1 == d2) & (d3 == d4)
    with np.errstate(divide="ignore", invalid="ignore"):
        slope = np.where(flat, 0.5 * d2 + 0.5 * d3, (w2 * d2 + w3 * d3) / (w2 + w3))
    return slope, np.where(flat, 1.0, w2), np.where(flat, 1.0, w3)


def _akima_surface(x: np.ndarray, y: np.ndarray, Z: np.ndarray) -> np.ndarray:
    """Bicubic coefficients of Akima's bivariate interpolation [2]_, shape (n1-1, n2-1, 4, 4).

    The values are extended by two knots beyond each edge (first along ``y``,
    then along ``x`` including the corners); the partial derivatives ``z_x``,
    ``z_y`` and ``z_xy`` at each knot follow Akima's weighting of the
    neighbouring secants; each grid cell is the bicubic Hermite patch of the
    values and derivatives at its corners.  ``A[i, j, a, b]`` multiplies
    ``(u1 - x[i])**a (u2 - y[j])**b``.
    """
    n1, n2 = Z.shape
    xe, ye = _extended_knots(x), _extended_knots(y)
    Ze = np.empty((n1 + 4, n2 + 4))
    Ze[2:-2, 2:-2] = Z
    _extend_values(ye, Ze[2:-2])
    _extend_values(xe, Ze.T)
    Dx = (Ze[1:] - Ze[:-1]) / (xe[1:] - xe[:-1])[:, None]          # secants along x, (n1+3, n2+4)
    Dy = (Ze[:, 1:] - Ze[:, :-1]) / (ye[1:] - ye[:-1])[None, :]    # secants along y, (n1+4, n2+3)
    I, J = slice(2, n1 + 2), slice(2, n2 + 2)                       # the knots in the extended grid
    zx, wx2, wx3 = _akima_weighted(Dx[0:n1, J], Dx[1:n1 + 1, J], Dx[2:n1 + 2, J], Dx[3:n1 + 3, J])
    zy, wy2, wy3 = _akima_weighted(Dy[I, 0:n2], Dy[I, 1:n2 + 1], Dy[I, 2:n2 + 2], Dy[I, 3:n2 + 3])
    hx_l, hx_r = (xe[2:n1 + 2] - xe[1:n1 + 1])[:, None], (xe[3:n1 + 3] - xe[2:n1 + 2])[:, None]
    e22 = (Dy[I, 1:n2 + 1] - Dy[1:n1 + 1, 1:n2 + 1]) / hx_l
    e23 = (Dy[I, 2:n2 + 2] - Dy[1:n1 + 1, 2:n2 + 2]) / hx_l
    e32 = (Dy[3:n1 + 3, 1:n2 + 1] - Dy[I, 1:n2 + 1]) / hx_r
    e33 = (Dy[3:n1 + 3, 2:n2 + 2] - Dy[I, 2:n2 + 2]) / hx_r
    zxy = (wx2 * (wy2 * e22 + wy3 * e23) + wx3 * (wy2 * e32 + wy3 * e33)) / ((wx2 + wx3) * (wy2 + wy3))
    hx = np.diff(x)[:, None]
    hy = np.diff(y)[None, :]

    def corners(V: np.ndarray):
        return V[:-1, :-1], V[:-1, 1:], V[1:, :-1], V[1:, 1:]

    z00, z01, z10, z11 = corners(Z)
    x00, x01, x10, x11 = (v * hx for v in corners(zx))
    y00, y01, y10, y11 = (v * hy for v in corners(zy))
    c00, c01, c10, c11 = (v * hx * hy for v in corners(zxy))
    F = np.stack([np.stack([z00, z01, y00, y01], -1), np.stack([z10, z11, y10, y11], -1),
                  np.stack([x00, x01, c00, c01], -1), np.stack([x10, x11, c10, c11], -1)], -2)
    A = np.einsum("ak,ijkl,bl->ijab", _HERMITE, F, _HERMITE)
    powers = np.arange(4)
    return A / (hx[..., None, None] ** powers[:, None] * hy[..., None, None] ** powers[None, :])


def _bilinear_surface(x: np.ndarray, y: np.ndarray, Z: np.ndarray) -> np.ndarray:
    """Bilinear coefficients per grid cell, shape (n1-1, n2-1, 4, 4) (as :func:`_akima_surface`)."""
    hx, hy = np.diff(x)[:, None], np.diff(y)[None, :]
    z00, z01, z10, z11 = Z[:-1, :-1], Z[:-1, 1:], Z[1:, :-1], Z[1:, 1:]
    A = np.zeros((len(x) - 1, len(y) - 1, 4, 4))
    A[..., 0, 0] = z00
    A[..., 0, 1] = (z01 - z00) / hy
    A[..., 1, 0] = (z10 - z00) / hx
    A[..., 1, 1] = ((z11 - z10) - (z01 - z00)) / (hx * hy)
    return A


def _basis(v: Any, w: Any, d: Any, side: int, order: int, hold: bool) -> tuple:
    """The weights of ``1, v, v^2, v^3`` that evaluate a cubic along one axis (scalars).

    ``v`` is the local coordinate in the cell, ``w`` the cell width, ``d`` the
    distance beyond the table edge, ``side`` -1, 0 or +1 below, inside or
    above the table.  Outside, the cubic is held at the edge (``hold``) or
    continued along its tangent there.
    """
    if side == 0:
        if order == 0:
            return 1.0, v, v * v, v * v * v
        if order == 1:
            return 0.0, 1.0, 2.0 * v, 3.0 * v * v
        if order == 2:
            return 0.0, 0.0, 2.0, 6.0 * v
        if order == 3:
            return 0.0, 0.0, 0.0, 6.0
        return 0.0, 0.0, 0.0, 0.0
    p = w if side > 0 else 0.0
    if order == 0:
        if hold:
            return 1.0, p, p * p, p * p * p
        return 1.0, p + d, p * p + 2.0 * p * d, p * p * p + 3.0 * p * p * d
    if order == 1 and not hold:
        return 0.0, 1.0, 2.0 * p, 3.0 * p * p
    return 0.0, 0.0, 0.0, 0.0


def _basis_array(v: np.ndarray, w: np.ndarray, d: np.ndarray, side: np.ndarray,
                 order: int, hold: bool) -> tuple:
    """:func:`_basis` elementwise (the same operations, selected per element)."""
    inside = _basis(v, w, d, 0, order, hold)
    p = np.where(side > 0, w, 0.0)
    beyond = _basis(v, p, d, 1, order, hold)
    return tuple(np.where(side == 0, a, b) for a, b in zip(inside, beyond))


def _contract(A: Any, b1: tuple, b2: tuple) -> Any:
    """``sum_a b1[a] sum_b A[a][b] b2[b]`` for 16 coefficients ``A`` (row-major)."""
    rows = [((A[4 * a] * b2[0] + A[4 * a + 1] * b2[1]) + A[4 * a + 2] * b2[2]) + A[4 * a + 3] * b2[3]
            for a in range(4)]
    return ((b1[0] * rows[0] + b1[1] * rows[1]) + b1[2] * rows[2]) + b1[3] * rows[3]


class Table2D:
    """A bivariate interpolation table (CombiTable2Ds / CombiTable2Dv).

    Parameters
    ----------
    data : array_like, shape (n1 + 1, n2 + 1)
        The table matrix: ``data[1:, 0]`` are the abscissae of ``u1`` and
        ``data[0, 1:]`` those of ``u2`` (each strictly increasing),
        ``data[1:, 1:]`` the values; ``data[0, 0]`` is not used.
    smoothness : Smoothness or int, optional
        ``LinearSegments`` (bilinear, the default), ``ContinuousDerivative``
        (Akima's bivariate spline) or ``ConstantSegments``; the MSL has no
        other 2-D interpolation.
    extrapolation : Extrapolation or int, optional
        The extrapolation in each direction (default ``LastTwoPoints``).
    name : str, keyword-only
        How error messages name the table.

    Attributes
    ----------
    name, data, smoothness, extrapolation
        As given (``data`` a read-only float array).
    u1_min, u1_max, u2_min, u2_max : float
        The ranges of the abscissae.

    Raises
    ------
    TableError
        For a malformed matrix (as :class:`Table1D`), fewer than 2 rows or
        columns, abscissae that do not strictly increase, an unknown option or
        a spline the MSL does not offer in 2-D.

    Notes
    -----
    A table of a single value is constant; one of a single row (or column) of
    values interpolates along ``u2`` (``u1``) only, as a 1-D table would, and
    ignores the other input.  Akima's spline needs at least 3 values along
    one axis; with fewer it is bilinear (MSL tickets #1307 and #1820).
    ``ConstantSegments`` with ``LastTwoPoints`` extrapolates bilinearly from
    the edge cell, as the C code.

    Derivatives are those of the value function.  The C code deviates there
    in two corners, which this class does not copy: with ``HoldLastPoint``
    the derivative along the table edge is that of the linear interpolation
    whatever the smoothness (not the Akima curve's, nor zero for constant
    segments), and the second derivative with respect to ``u1`` below
    ``u2_min`` multiplies the whole expression by ``u2 - u2_min``.
    """

    def __init__(self, data: Any, smoothness: Any = Smoothness.LinearSegments,
                 extrapolation: Any = Extrapolation.LastTwoPoints, *, name: str = "table") -> None:
        self.name = str(name)
        self.smoothness = _option(Smoothness, smoothness, self.name, "smoothness")
        self.extrapolation = _option(Extrapolation, extrapolation, self.name, "extrapolation")
        if self.smoothness not in (Smoothness.LinearSegments, Smoothness.ContinuousDerivative,
                                   Smoothness.ConstantSegments):
            raise TableError(f"table {self.name!r}: {self.smoothness.name} is not available for 2-D tables",
                             hint="use LinearSegments, ContinuousDerivative (Akima) or ConstantSegments")
        self.data = _matrix(data, self.name, "2-D interpolation", min_rows=2)
        x, y, Z = self.data[1:, 0], self.data[0, 1:], self.data[1:, 1:]
        _check_increasing(x, self.name, "u1 abscissa", True, lambda k: f"row {k + 2}",
                          hint="the first column (below row 1) of a 2-D table must be strictly increasing")
        _check_increasing(y, self.name, "u2 abscissa", True, lambda k: f"row 1, column {k + 2}",
                          hint="the first row (right of column 1) of a 2-D table must be strictly increasing")
        self.u1_min, self.u1_max = float(x[0]), float(x[-1])
        self.u2_min, self.u2_max = float(y[0]), float(y[-1])
        n1, n2 = Z.shape
        self._hold = self.extrapolation == Extrapolation.HoldLastPoint
        self._periodic = self.extrapolation == Extrapolation.Periodic
        if n1 == 1 or n2 == 1:
            # one value, or one row / column of values: a 1-D table along the other input
            self._along = 0 if n1 == 1 and n2 == 1 else (2 if n1 == 1 else 1)
            knots, values = (y, Z[0]) if n1 == 1 else (x, Z[:, 0])
            self._curve = _Curve(knots, values[:, None], self.smoothness, self.extrapolation)
            return
        self._along = None
        self._x, self._y = np.array(x), np.array(y)
        self._x_list, self._y_list = self._x.tolist(), self._y.tolist()
        self._Z, self._Z_list = np.array(Z), Z.tolist()
        self._hx, self._hy = np.diff(self._x), np.diff(self._y)
        self._hx_list, self._hy_list = self._hx.tolist(), self._hy.tolist()
        self._constant = self.smoothness == Smoothness.ConstantSegments
        if self.smoothness == Smoothness.ContinuousDerivative and (n1 > 2 or n2 > 2):
            A = _akima_surface(self._x, self._y, self._Z)
        else:
            A = _bilinear_surface(self._x, self._y, self._Z)
        self._A = np.ascontiguousarray(A.reshape(n1 - 1, n2 - 1, 16))
        self._A_list = self._A.tolist()

    def __repr__(self) -> str:
        n1, n2 = self.data.shape
        return (f"Table2D({self.name!r}, {n1 - 1} x {n2 - 1} values, "
                f"{self.smoothness.name}, {self.extrapolation.name})")

    def value(self, u1: Any, u2: Any, order1: int = 0, order2: int = 0) -> Any:
        """The value at ``(u1, u2)``, or ``d^(order1+order2) y / du1^order1 du2^order2``.

        Parameters
        ----------
        u1, u2 : float or array_like
            The inputs; arrays broadcast against each other.
        order1, order2 : int, optional
            The orders of the partial derivative.  MSL's ``getDerTable2DValue``
            and ``getDer2Table2DValue`` give up to ``order1 + order2 = 2``;
            higher orders are the further derivatives of the piece in use.

        Returns
        -------
        float or numpy.ndarray
            A Python float for scalar inputs, an array of the broadcast shape
            otherwise.
        """
        order1 = _check_order(order1) if order1 else 0
        order2 = _check_order(order2) if order2 else 0
        if _is_scalar(u1) and _is_scalar(u2):
            return float(self._scalar(float(u1), float(u2), order1, order2))
        u1, u2 = np.broadcast_arrays(np.asarray(u1, dtype=float), np.asarray(u2, dtype=float))
        return _output(self._array(u1, u2, order1, order2))

    def outside(self, u1: Any, u2: Any) -> Any:
        """Whether ``(u1, u2)`` lies outside the table's rectangle.

        An input along which the table has a single value is never outside
        (the C code does not interpolate along it).
        """
        n1, n2 = self.data.shape[0] - 1, self.data.shape[1] - 1
        if _is_scalar(u1) and _is_scalar(u2):
            out1 = n1 > 1 and (u1 < self.u1_min or u1 > self.u1_max)
            out2 = n2 > 1 and (u2 < self.u2_min or u2 > self.u2_max)
            return bool(out1 or out2)
        u1, u2 = np.broadcast_arrays(np.asarray(u1, dtype=float), np.asarray(u2, dtype=float))
        out = np.zeros(u1.shape, bool)
        if n1 > 1:
            out |= (u1 < self.u1_min) | (u1 > self.u1_max)
        if n2 > 1:
            out |= (u2 < self.u2_min) | (u2 > self.u2_max)
        return _output(out)

    # -- one input at a time ----------------------------------------------------------

    def _axis_scalar(self, knots: list, u: float, order: int) -> tuple[int, int]:
        """The cell of ``u`` along one axis and the side: -1 below, 0 inside, +1 above."""
        if not self._periodic:
            if u < knots[0]:
                return 0, -1
            if u > knots[-1] or (order > 0 and u == knots[-1]):
                return len(knots) - 2, 1
        return min(max(bisect_right(knots, u) - 1, 0), len(knots) - 2), 0

    def _scalar(self, u1: float, u2: float, o1: int, o2: int) -> float:
        if self._along is not None:
            return self._along_scalar(u1, u2, o1, o2)
        x, y = self._x_list, self._y_list
        if self._periodic:
            u1 = _wrap_scalar(u1, x[0], x[-1])
            u2 = _wrap_scalar(u2, y[0], y[-1])
        i, s1 = self._axis_scalar(x, u1, o1)
        j, s2 = self._axis_scalar(y, u2, o2)
        if self._constant and ((s1 == 0 and s2 == 0) or self._hold):
            if o1 or o2:
                return 0.0
            row = min(max(bisect_right(x, u1) - 1, 0), len(x) - 1)
            col = min(max(bisect_right(y, u2) - 1, 0), len(y) - 1)
            return self._Z_list[row][col]
        b1 = _basis(u1 - x[i], self._hx_list[i], u1 - (x[0] if s1 < 0 else x[-1]), s1, o1, self._hold)
        b2 = _basis(u2 - y[j], self._hy_list[j], u2 - (y[0] if s2 < 0 else y[-1]), s2, o2, self._hold)
        return _contract(self._A_list[i][j], b1, b2)

    def _along_scalar(self, u1: float, u2: float, o1: int, o2: int) -> float:
        """A table with a single value, or a single row or column of values."""
        if self._along == 0:
            return self._curve.scalar(0, 0.0, 0) if o1 == o2 == 0 else 0.0
        u, order, other = (u2, o2, o1) if self._along == 2 else (u1, o1, o2)
        if other:
            return 0.0          # the table does not depend on the other input
        return self._curve.scalar(0, u, order, right_at_max=order > 0)

    # -- arrays -----------------------------------------------------------------------

    def _axis_array(self, knots: np.ndarray, u: np.ndarray, order: int) -> tuple[np.ndarray, np.ndarray]:
        cell = np.clip(np.searchsorted(knots, u, side="right") - 1, 0, len(knots) - 2)
        if self._periodic:
            return cell, np.zeros(u.shape, int)
        above = (u > knots[-1]) | ((u == knots[-1]) if order > 0 else False)
        side = np.where(u < knots[0], -1, np.where(above, 1, 0))
        cell = np.where(side < 0, 0, np.where(side > 0, len(knots) - 2, cell))
        return cell, side

    def _array(self, u1: np.ndarray, u2: np.ndarray, o1: int, o2: int) -> np.ndarray:
        if self._along is not None:
            u, order, other = (u2, o2, o1) if self._along == 2 else (u1, o1, o2)
            if self._along == 0 or other:
                return np.full(u1.shape, self._along_scalar(0.0, 0.0, o1, o2))
            return self._curve.array(0, u, order, right_at_max=order > 0)
        x, y = self._x, self._y
        if self._periodic:
            u1 = _wrap_array(u1, x[0], x[-1])
            u2 = _wrap_array(u2, y[0], y[-1])
        i, s1 = self._axis_array(x, u1, o1)
        j, s2 = self._axis_array(y, u2, o2)
        b1 = _basis_array(u1 - x[i], self._hx[i], u1 - np.where(s1 < 0, x[0], x[-1]), s1, o1, self._hold)
        b2 = _basis_array(u2 - y[j], self._hy[j], u2 - np.where(s2 < 0, y[0], y[-1]), s2, o2, self._hold)
        A = self._A[i, j]
        result = _contract([A[..., k] for k in range(16)], b1, b2)
        if self._constant:
            flat = ((s1 == 0) & (s2 == 0)) | self._hold
            row = np.clip(np.searchsorted(x, u1, side="right") - 1, 0, len(x) - 1)
            col = np.clip(np.searchsorted(y, u2, side="right") - 1, 0, len(y) - 1)
            result = np.where(flat, self._Z[row, col] if not (o1 or o2) else 0.0, result)
        return result


# --------------------------------------------------------------------------------------
# CombiTimeTable
# --------------------------------------------------------------------------------------

class TimeTable:
    """A table of time (CombiTimeTable), evaluated in scaled time without state.

    Parameters
    ----------
    data : array_like, shape (n, m)
        The table matrix: column 1 holds the times (non-decreasing; strictly
        increasing for the splines; a time given twice is a jump, three times
        is an error), the others the values.
    columns : sequence of int, optional
        The 1-based numbers of the columns to interpolate (default ``2 .. m``).
    smoothness : Smoothness or int, optional
        The interpolation (default ``LinearSegments``).
    extrapolation : Extrapolation or int, optional
        The extrapolation (default ``LastTwoPoints``).
    time_events : TimeEvents or int, optional
        Which table times are time events for ``LinearSegments`` (default
        ``Always``); ``ConstantSegments`` always has them, the splines never
        (as ``Modelica.Blocks.Sources.CombiTimeTable`` passes the option on).
    name : str, keyword-only
        How error messages name the table.

    Attributes
    ----------
    name, data, columns, smoothness, extrapolation, time_events, n_outputs
        As for :class:`Table1D`.
    t_min, t_max : float
        The first and last time of the table (unshifted).
    effective_time_events : TimeEvents
        The time events in force: ``time_events`` for ``LinearSegments``,
        ``Always`` for ``ConstantSegments``, ``NoTimeEvents`` for the splines.

    Notes
    -----
    Times here are scaled (``time / timeScale``); ``start`` and ``shift``
    are ``startTime / timeScale`` and ``shiftTime / timeScale``, arguments
    so that they stay tunable.

    The *event instants* are ``start`` and, after it, the table's event times
    shifted by ``shift``: ``t_min``, ``t_max`` and, with ``Always``, every
    table time between them (``AtDiscontinuities``: every repeated time),
    repeated every period ``t_max - t_min`` with ``Periodic`` extrapolation.
    A table of one row has none.  The engine holds the next instant
    (:meth:`next_event`) and hands it to :meth:`value`: the *event interval in
    force* runs from the instant before it to it, and the value is that of the
    table's segments inside that interval, their polynomials extended when the
    time lies a little outside (an integrator's overshoot).  So at a jump the
    value is the left limit until the engine has moved to the next instant,
    and the right limit after.  Before ``start`` (an interval ending at or
    before it) the value is 0.
    """

    def __init__(self, data: Any, columns: Any = None, smoothness: Any = Smoothness.LinearSegments,
                 extrapolation: Any = Extrapolation.LastTwoPoints,
                 time_events: Any = TimeEvents.Always, *, name: str = "table") -> None:
        self.name = str(name)
        self.smoothness = _option(Smoothness, smoothness, self.name, "smoothness")
        self.extrapolation = _option(Extrapolation, extrapolation, self.name, "extrapolation")
        self.time_events = _option(TimeEvents, time_events, self.name, "time_events")
        self.data = _matrix(data, self.name, "a time table", min_rows=1)
        self.columns = _columns(columns, self.data.shape[1], self.name)
        t = self.data[:, 0]
        n = len(t)
        spline = self.smoothness in _SPLINES
        _check_increasing(t, self.name, "time", spline, lambda k: f"row {k + 1}",
                          hint="the times of a spline table must be strictly increasing" if spline else
                          "sort the rows by time; a time given twice marks a jump")
        self.n_outputs = len(self.columns)
        self.t_min, self.t_max = float(t[0]), float(t[-1])
        self._periodic = self.extrapolation == Extrapolation.Periodic and n > 1
        if self._periodic and not self.t_max > self.t_min:
            raise TableError(f"table {self.name!r}: periodic extrapolation needs t_max > t_min, "
                             f"but both are {self.t_min!r}",
                             hint="give rows at more than one time, or another extrapolation")
        self._curve = _Curve(t, self.data[:, [c - 1 for c in self.columns]], self.smoothness,
                             self.extrapolation, jumps=True)
        # groups of rows at (nearly) the same time: rows lo .. hi
        same = _nearly_equal(t[:-1], t[1:])
        if (same[:-1] & same[1:]).any():
            k = int(np.argmax(same[:-1] & same[1:]))
            raise TableError(f"table {self.name!r}: rows {k + 1} to {k + 3} all have the time "
                             f"{t[k]:.17g}; at most two rows may share a time (a jump)",
                             hint="keep the value before and the value after the jump only")
        lo = np.concatenate([[0], np.nonzero(~same)[0] + 1])
        hi = np.concatenate([lo[1:] - 1, [n - 1]])
        if self.smoothness == Smoothness.LinearSegments:
            mode = self.time_events
        elif self.smoothness == Smoothness.ConstantSegments:
            mode = TimeEvents.Always
        else:
            mode = TimeEvents.NoTimeEvents
        self.effective_time_events = mode
        if mode == TimeEvents.Always:
            event = np.ones(len(lo), bool)
        elif mode == TimeEvents.AtDiscontinuities:
            event = hi > lo
        else:
            event = np.zeros(len(lo), bool)
        event[0] = event[-1] = n > 1         # t_min and t_max always are events
        lo, hi = lo[event], hi[event]
        self._period = self.t_max - self.t_min
        if self._periodic:
            self._end_lo = int(lo[-1])        # t_max closes a period: it is t_min of the next
            lo, hi = lo[:-1], hi[:-1]
        self._ev_list = t[lo].tolist()        # the event times of the table (of one period)
        self._ev_lo_list, self._ev_hi_list = lo.tolist(), hi.tolist()

    def __repr__(self) -> str:
        return (f"TimeTable({self.name!r}, {self.data.shape[0]} rows, columns={self.columns}, "
                f"{self.smoothness.name}, {self.extrapolation.name})")

    # -- event instants -----------------------------------------------------------------

    def _instant(self, g: int, shift: float) -> float:
        """Event instant number ``g`` (every integer with periodic extrapolation)."""
        if not self._periodic:
            return self._ev_list[g] + shift
        k, j = divmod(g, len(self._ev_list))
        return self._ev_list[j] + (k * self._period + shift)

    def _first_instant(self, b: float, shift: float, strict: bool) -> int:
        """The number of the first event instant ``>= b`` (``> b`` if ``strict``)."""
        ev, m = self._ev_list, len(self._ev_list)
        passes = (lambda s: s > b) if strict else (lambda s: s >= b)
        if not self._periodic:
            g = (bisect_right if strict else bisect_left)(ev, b - shift)
            while g > 0 and passes(ev[g - 1] + shift):
                g -= 1
            while g < m and not passes(ev[g] + shift):
                g += 1
            return g
        k = math.floor((b - shift - self.t_min) / self._period)
        g = k * m + (bisect_right if strict else bisect_left)(ev, b - (k * self._period + shift))
        while passes(self._instant(g - 1, shift)):
            g -= 1
        while not passes(self._instant(g, shift)):
            g += 1
        return g

    def next_event(self, t: float, start: float, shift: float) -> float:
        """The first event instant after ``t`` (``math.inf`` if there is none).

        Parameters
        ----------
        t : float
            The time (scaled) at which the engine asks, at the start and at
            each of these events.
        start, shift : float
            ``startTime / timeScale`` and ``shiftTime / timeScale``.
        """
        t, start, shift = float(t), float(start), float(shift)
        if t < start:
            return start
        if not self._ev_list or not math.isfinite(t):
            return math.inf
        g = self._first_instant(t, shift, strict=True)
        if not self._periodic and g == len(self._ev_list):
            return math.inf
        return float(self._instant(g, shift))

    # -- values ---------------------------------------------------------------------------

    def _interval_scalar(self, b: float, start: float, shift: float) -> tuple[int, int, float]:
        """The pieces ``(q_lo, q_hi)`` of the event interval ending at ``b``, and its time offset."""
        n = self._curve.n
        g = self._first_instant(b, shift, strict=False)
        if not self._periodic:
            m = len(self._ev_list)
            q_hi = self._ev_lo_list[g] if g < m else n
            if g > 0 and self._instant(g - 1, shift) > start:
                q_lo = self._ev_hi_list[g - 1] + 1
            else:
                q_lo = bisect_right(self._curve.x_list, start - shift)
            return min(q_lo, q_hi), q_hi, shift
        m = len(self._ev_list)
        k, j = divmod(g - 1, m)        # the interval runs from event j to event j + 1 of period k
        offset = k * self._period + shift
        q_hi = self._end_lo if j + 1 == m else self._ev_lo_list[j + 1]
        if self._instant(g - 1, shift) > start:
            q_lo = self._ev_hi_list[j] + 1
        else:
            q_lo = bisect_right(self._curve.x_list, start - offset)
        q_hi = min(max(q_hi, 1), n - 1)
        return min(max(q_lo, 1), q_hi), q_hi, offset

    def value(self, i: int, t: Any, next_event: Any, start: float, shift: float, order: int = 0) -> Any:
        """Output ``i`` (without the block's offset) at time ``t``, or its derivative.

        Parameters
        ----------
        i : int
            0-based index into :attr:`columns`.
        t : float or array_like
            The time (scaled).
        next_event : float or array_like
            The event instant the engine holds: :meth:`next_event` of the time
            of the last event (broadcasts against ``t``).
        start, shift : float
            ``startTime / timeScale`` and ``shiftTime / timeScale``.
        order : int, optional
            0 for the value, 1 and 2 for its first and second derivative with
            respect to (scaled) time, higher orders as :meth:`Table1D.value`.

        Returns
        -------
        float or numpy.ndarray
        """
        order = _check_order(order) if order else 0
        if not 0 <= i < self.n_outputs:
            raise IndexError(f"table {self.name!r} has {self.n_outputs} output(s); index {i} is out of range")
        start, shift = float(start), float(shift)
        if _is_scalar(t) and _is_scalar(next_event):
            return float(self._scalar(i, float(t), float(next_event), start, shift, order))
        t, b = np.broadcast_arrays(np.asarray(t, dtype=float), np.asarray(next_event, dtype=float))
        return _output(self._array(i, t, b, start, shift, order))

    def _scalar(self, col: int, t: float, b: float, start: float, shift: float, order: int) -> float:
        curve = self._curve
        if not b > start:
            return 0.0
        if curve.n == 1:
            return curve.Y_list[col][0] if order == 0 else 0.0
        if self._periodic and not math.isfinite(b):
            return curve.scalar(col, t - shift, order)
        q_lo, q_hi, offset = self._interval_scalar(b, start, shift)
        tau = t - offset
        q = min(max(bisect_right(curve.x_list, tau), q_lo), q_hi)
        return curve.at_scalar(col, q, tau, order)

    def _array(self, col: int, t: np.ndarray, b: np.ndarray, start: float, shift: float,
               order: int) -> np.ndarray:
        curve = self._curve
        out = np.zeros(t.shape)
        if curve.n == 1:
            return np.where(b > start, curve.Y[0, col] if order == 0 else 0.0, out)
        # one event interval per distinct next_event (few: the engine holds one at a time)
        b_values, inverse = np.unique(b, return_inverse=True)
        inverse = inverse.reshape(b.shape)
        for k, b_k in enumerate(b_values.tolist()):
            if not b_k > start:
                continue
            mask = inverse == k
            if self._periodic and not math.isfinite(b_k):
                out[mask] = curve.array(col, t[mask] - shift, order)
                continue
            q_lo, q_hi, offset = self._interval_scalar(b_k, start, shift)
            tau = t[mask] - offset
            q = np.clip(np.searchsorted(curve.x, tau, side="right"), q_lo, q_hi)
            out[mask] = curve.at_array(col, q, tau, order)
        return out
