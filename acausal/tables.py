"""One-dimensional interpolation tables as sympy functions.

:func:`table_function` turns an ``n x 2`` table into a sympy function class,
the way Modelica's ``CombiTable1D`` with ``smoothness = LinearSegments`` and
``extrapolation = LastTwoPoints`` evaluates it (the friction characteristics
``tau_pos`` and ``mu_pos`` of the Rotational library):

* linear interpolation between rows (column 1 strictly increasing);
* linear extrapolation through the first two rows below the table and through
  the last two rows above it;
* a one-row table is a constant.

The class works symbolically (``T(w)`` is an unevaluated application,
``T(0)`` a Float, ``diff(T(w), w)`` the piecewise-constant slope as another
table function) and numerically (``T._imp_`` / ``T.numeric`` for floats,
``T.evaluate`` for arrays; ``sympy.lambdify`` picks ``_imp_`` up by itself).
"""

from __future__ import annotations

import keyword
import re
import weakref
from typing import Any, Callable

import numpy as np
import sympy as sp
from sympy.core.function import ArgumentIndexError

from .errors import ParameterError
from .table_calls import ConstantTable, NextTableEvent, SegmentTable, StepTable, TableOutput

__all__ = ["check_abscissae", "table_function", "validate_table", "TableFunction", "table_1d_function",
           "table_2d_function", "time_table_functions"]

#: (class name, shape, table bytes) -> class; the same table under the same
#: name always gives the same class, so equations built twice compare equal.
_CLASSES: dict[tuple, type] = {}


def _identifier(name: str) -> str:
    """``name`` as a valid Python identifier: dots and other symbols become '_'."""
    if not isinstance(name, str) or not name:
        raise ParameterError(f"a table function needs a non-empty name, not {name!r}",
                             hint="derive it from the component path, e.g. 'component.table'")
    text = re.sub(r"[^0-9A-Za-z_]", "_", name)
    if text[0].isdigit():
        text = "_" + text
    if keyword.iskeyword(text):
        text += "_"
    return text


def check_abscissae(data: np.ndarray, what: str, column: str, symbol: str, hint: str) -> None:
    """Raise a ParameterError unless the matrix ``data`` is finite and its first
    column strictly increasing (what linear interpolation in a table needs).

    ``what`` names the table in the message, ``column`` its first column in
    words, ``symbol`` the quantity of that column; ``hint`` says how to mend it.
    """
    if not np.all(np.isfinite(data)):
        raise ParameterError(f"{what} contains non-finite values (nan or inf)",
                             hint="every entry must be a finite number")
    steps = np.diff(data[:, 0])
    if np.any(steps <= 0):
        row = int(np.argmax(steps <= 0)) + 1
        raise ParameterError(
            f"{what}: {column} must be strictly increasing, but row {row + 1} "
            f"({symbol} = {data[row, 0]:g}) does not exceed row {row} ({symbol} = {data[row - 1, 0]:g})",
            hint=hint)


def validate_table(table: Any, name: str = "table", *, value_min: float | None = None,
                   value_hint: str | None = None) -> np.ndarray:
    """Check a CombiTable1D table and return it as a read-only float array.

    Parameters
    ----------
    table : array_like, shape (n, 2)
        Rows ``[x, y]``.
    name : str
        How the error messages name the table (e.g. the dotted path of the
        parameter that holds it).
    value_min : float, optional
        Lower bound of the second column (``y >= value_min`` in every row);
        ``None`` (the default) leaves the values unbounded.
    value_hint : str, optional
        Hint of the error raised when a value is below ``value_min`` (why the
        bound holds); a generic one by default.

    Raises
    ------
    ParameterError
        If the table is empty, not ``n x 2``, contains non-finite values, its
        first column is not strictly increasing, or a value of its second
        column is below ``value_min``.  Rows are counted from 1.
    """
    example = "e.g. [[0, 1]] or [[0, 0.5], [1, 0.4]]"
    try:
        data = np.array(table, dtype=float)
    except (TypeError, ValueError) as exc:
        raise ParameterError(f"table {name} is not a numeric matrix: {table!r}",
                             hint=f"give an n x 2 list of rows, {example}") from exc
    if data.size == 0:
        raise ParameterError(f"table {name} is empty",
                             hint=f"give at least one row [x, y], {example}")
    if data.ndim != 2 or data.shape[1] != 2:
        raise ParameterError(f"table {name} must be an n x 2 matrix, but its shape is {data.shape}",
                             hint=f"one row [x, y] per point, {example}")
    check_abscissae(data, f"table {name}", "the first column", "x", "sort the rows by x and remove repeated x values")
    if value_min is not None:
        below = data[:, 1] < value_min
        if np.any(below):
            row = int(np.argmax(below))
            raise ParameterError(
                f"table {name}: the second column must be >= {value_min:g}, but row {row + 1} "
                f"(x = {data[row, 0]:g}) has y = {data[row, 1]:g}",
                hint=value_hint or f"every value of the second column must be at least {value_min:g}")
    data.setflags(write=False)
    return data


def table_function(name: str, table: Any) -> type[sp.Function]:
    """A sympy function class interpolating ``table`` (CombiTable1D, LinearSegments).

    Parameters
    ----------
    name : str
        Name of the generated class (and of the function in generated code);
        characters that are not valid in a Python identifier, such as dots,
        become underscores (``"brake.mu_pos"`` -> ``brake_mu_pos``).
    table : array_like, shape (n, 2)
        Rows ``[x, y]`` with strictly increasing ``x``.

    Returns
    -------
    type
        A subclass of :class:`sympy.Function` with one argument.  Applied to a
        sympy number it evaluates to a Float; its derivative is another table
        function (piecewise constant, the right segment's slope at a
        breakpoint).  ``_imp_``/``numeric`` evaluate a float, ``evaluate`` an
        array.  The same name and table always return the same class.

    Raises
    ------
    ParameterError
        For an invalid table (see :func:`validate_table`).

    Examples
    --------
    >>> T = table_function("T", [[0, 1], [1, 3]])
    >>> T(2), T(-1)
    (5.00000000000000, -1.00000000000000)
    """
    ident = _identifier(name)
    data = validate_table(table, name)
    key = (ident, data.shape, data.tobytes())
    cls = _CLASSES.get(key)
    if cls is None:
        cls = _interpolation_class(ident, data)
        _CLASSES[key] = cls
    return cls


# --------------------------------------------------------------------------


def _make_class(ident: str, imp: SegmentTable | StepTable | ConstantTable, *, constant: float | None,
                derivative: Callable[[], Any], attributes: dict) -> type[sp.Function]:
    """Build the sympy Function subclass around a numeric implementation (:mod:`acausal.table_calls`)."""
    scalar, vector = imp.scalar, imp.vector

    def eval_(cls, x):
        if constant is not None:
            return sp.Float(constant)
        if isinstance(x, sp.Number) and x.is_finite:
            return sp.Float(scalar(float(x)))
        return None

    def evaluate(cls, x):
        """Vectorised evaluation at an array (or scalar) of abscissae."""
        return vector(x)

    def fdiff(self, argindex=1):
        if argindex != 1:
            raise ArgumentIndexError(self, argindex)
        result = derivative()
        return result(self.args[0]) if isinstance(result, type) else result

    def _eval_evalf(self, prec):
        x = self.args[0].evalf(prec)
        if isinstance(x, sp.Number) and x.is_finite:
            return sp.Float(scalar(float(x)), prec)
        return None

    def _eval_is_real(self):
        return self.args[0].is_real

    namespace = {
        "__module__": __name__,
        "__doc__": f"Table function {ident} (linear segments, LastTwoPoints extrapolation).",
        "nargs": 1,
        "eval": classmethod(eval_),
        "evaluate": classmethod(evaluate),
        "fdiff": fdiff,
        "_eval_evalf": _eval_evalf,
        "_eval_is_real": _eval_is_real,
        "_imp_": staticmethod(imp),
        "numeric": staticmethod(imp),
        **attributes,
    }
    return type(ident, (sp.Function,), namespace)


def _interpolation_class(ident: str, data: np.ndarray) -> type[sp.Function]:
    xs = tuple(float(v) for v in data[:, 0])
    ys = tuple(float(v) for v in data[:, 1])
    imp: SegmentTable | ConstantTable
    if len(xs) == 1:
        imp = ConstantTable(ys[0])
        slopes: tuple = ()
        constant: float | None = ys[0]
    else:
        slopes = tuple((ys[i + 1] - ys[i]) / (xs[i + 1] - xs[i]) for i in range(len(xs) - 1))
        imp = SegmentTable(xs, ys, slopes)
        constant = None

    derivative_class: list = []

    def derivative():
        if not slopes:
            return sp.Integer(0)
        if not derivative_class:
            derivative_class.append(_slope_class(f"{ident}_slope", xs, slopes))
        return derivative_class[0]

    return _make_class(ident, imp, constant=constant, derivative=derivative,
                       attributes={"table": data, "breakpoints": xs, "slopes": slopes,
                                   "kind": "linear"})


def _slope_class(ident: str, xs: tuple, slopes: tuple) -> type[sp.Function]:
    imp: StepTable | ConstantTable
    if len(slopes) == 1:
        imp = ConstantTable(slopes[0])
        constant: float | None = slopes[0]
    else:
        imp = StepTable(xs, slopes)
        constant = None
    return _make_class(ident, imp, constant=constant, derivative=lambda: sp.Integer(0),
                       attributes={"breakpoints": xs, "values": slopes, "kind": "steps"})


# --------------------------------------------------------------------------
# The MSL tables (acausal.interpolation) as functions of equations
# --------------------------------------------------------------------------


class TableFunction(sp.Function):
    """An application of an interpolation table of :mod:`acausal.interpolation` in an equation.

    One class per table, output and derivative order (made and cached by
    :func:`table_1d_function`, :func:`table_2d_function` and
    :func:`time_table_functions`): equations built twice compare equal, and the
    generated code calls ``_imp_`` (floats or numpy arrays).  Differentiating
    an application gives the class of the next derivative order (MSL's
    ``derivative`` annotations of ``getTable1DValue``, ``getTable2DValue`` and
    ``getTimeTableValue``), so a table can drive a position source or be
    differentiated by index reduction.

    Class attributes: ``table`` (the numeric table), ``output`` (0-based
    column of the outputs), ``orders`` (derivative orders), ``shape`` (which
    arguments the value is a function of, see the factories), ``data_text``
    (a digest of the table and options, for the compile cache) and
    ``rebuild`` (how another process makes the same class).
    """

    table: Any = None
    output: int = 0
    orders: tuple[int, ...] = ()
    shape: str = ""
    data_text: str = ""
    rebuild: tuple = ()

    @classmethod
    def eval(cls, *args):
        if cls.shape != "next" and all(isinstance(a, sp.Number) and a.is_finite for a in args):
            return sp.Float(cls._imp_(*(float(a) for a in args)))
        return None

    def _eval_evalf(self, prec):
        values = [a.evalf(prec) for a in self.args]
        if all(isinstance(v, sp.Number) and v.is_finite for v in values):
            return sp.Float(type(self)._imp_(*(float(v) for v in values)), prec)
        return None

    def _eval_is_real(self):
        return True

    def fdiff(self, argindex: int = 1):
        shape, args = self.shape, self.args
        if shape == "1d" and argindex == 1:
            return _table_class(self.rebuild, (self.orders[0] + 1,))(*args)
        if shape == "2d" and argindex in (1, 2):
            o1, o2 = self.orders
            orders = (o1 + 1, o2) if argindex == 1 else (o1, o2 + 1)
            return _table_class(self.rebuild, orders)(*args)
        if shape == "time":
            # (time, next event, start, shift): the held next event and the start are
            # piecewise constant; the value is a function of time - shift
            following = _table_class(self.rebuild, (self.orders[0] + 1,))(*args)
            if argindex == 1:
                return following
            if argindex == 4:
                return -following
            if argindex in (2, 3):
                return sp.Integer(0)
        if shape == "next" and argindex in (1, 2, 3):
            return sp.Integer(0)
        raise ArgumentIndexError(self, argindex)

    def __reduce_ex__(self, protocol):
        return _apply_table, (self.rebuild, self.orders, self.args)

    @classmethod
    def related(cls) -> tuple[type, ...]:
        """The classes of this table's derivatives up to the third order (what index
        reduction may make of it; the compile cache finds them by name)."""
        if cls.shape == "next":
            return ()
        if cls.shape == "2d":
            orders = [(a, b) for a in range(4) for b in range(4) if 0 < a + b <= 3]
        else:
            orders = [(k,) for k in range(1, 4)]
        return tuple(_table_class(cls.rebuild, o) for o in orders)


def _apply_table(rebuild: tuple, orders: tuple, args: tuple) -> sp.Expr:
    """A table application (how one is unpickled)."""
    return _table_class(rebuild, orders)(*args)


#: (kind, name, output, table digest, orders) -> class
_TABLE_CLASSES: dict[tuple, type] = {}


#: table -> digest: a table's digest is computed once (weakly held: a model flattened again
#: and again, as in a sweep, makes new table objects of the same data)
_DIGESTS: "weakref.WeakKeyDictionary[Any, str]" = weakref.WeakKeyDictionary()


def _digest(table) -> str:
    """A short text that changes with every number and option of ``table``."""
    found = _DIGESTS.get(table)
    if found is not None:
        return found
    import hashlib

    digest = hashlib.sha256(np.ascontiguousarray(table.data, dtype=float).tobytes())
    options = [type(table).__name__, getattr(table, "columns", None), getattr(table, "smoothness", None),
               getattr(table, "extrapolation", None), getattr(table, "time_events", None), table.data.shape]
    digest.update(repr([int(o) if isinstance(o, int) else o for o in options]).encode())
    text = digest.hexdigest()[:16]
    _DIGESTS[table] = text
    return text


def _table_class(rebuild: tuple, orders: tuple) -> type:
    """The class of the table application ``rebuild`` describes, at derivative ``orders``."""
    shape, name, output, table = rebuild
    key = (shape, name, output, _digest(table), tuple(orders))
    cls = _TABLE_CLASSES.get(key)
    if cls is not None:
        return cls
    ident = _identifier(name)
    suffix = {"1d": f"_y{output + 1}", "2d": "", "time": f"_y{output + 1}", "next": "_next_event"}[shape]
    if any(orders):
        suffix += "_d" + "_".join(str(o) for o in orders)
    evaluate = NextTableEvent(table) if shape == "next" else TableOutput(shape, table, output, orders)
    cls = type(f"{ident}{suffix}", (TableFunction,), {
        "__module__": __name__,
        "__doc__": f"Table {name} ({shape}, output {output + 1}, derivative orders {orders}).",
        "nargs": {"1d": 1, "2d": 2, "time": 4, "next": 3}[shape],
        "table": table,
        "output": output,
        "orders": tuple(orders),
        "shape": shape,
        "data_text": f"{shape} {name} output {output} orders {tuple(orders)} data {_digest(table)}",
        "rebuild": rebuild,
        "_imp_": staticmethod(evaluate),
        "numeric": staticmethod(evaluate),
    })
    _TABLE_CLASSES[key] = cls
    return cls


def table_1d_function(table, output: int, name: str) -> type[sp.Function]:
    """``y(u)``: output ``output`` (0-based) of a :class:`~acausal.interpolation.Table1D`,
    as a sympy function of one argument (its derivatives are the table's)."""
    return _table_class(("1d", name, int(output), table), (0,))


def table_2d_function(table, name: str) -> type[sp.Function]:
    """``y(u1, u2)`` of a :class:`~acausal.interpolation.Table2D`, as a sympy function of
    two arguments (its partial derivatives are the table's)."""
    return _table_class(("2d", name, 0, table), (0, 0))


def time_table_functions(table, output: int, name: str) -> tuple[type[sp.Function], type[sp.Function]]:
    """The two functions a CombiTimeTable's equations call, for output ``output`` (0-based):

    * ``value(t, next_event, start, shift)``: the output of the
      :class:`~acausal.interpolation.TimeTable` at scaled time ``t`` while the
      held next event instant is ``next_event`` (scaled);
    * ``next(t, start, shift)``: the next event instant after ``t`` (scaled),
      what the block's when-clause assigns.
    """
    return (_table_class(("time", name, int(output), table), (0,)),
            _table_class(("next", name, 0, table), (0,)))
