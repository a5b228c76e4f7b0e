"""Modelica expressions to acausal's sympy form and back.

:func:`to_sympy` turns an expression node of pymoca's syntax tree into what
acausal's equations are made of: sympy expressions, sympy Booleans
(relations, ``And``/``Or``/``Not``), ``Piecewise`` for if-expressions,
:class:`~acausal.arrays.Array` for arrays, the operators of
:mod:`acausal.language` (``der``, ``pre``, ``initial``, ``time``) and of
:mod:`acausal.hybrid` (``edge``, ``change``, ``sample``, ``noEvent``,
``floor``, ``div``, ...).  Names are the caller's business: every component
reference is handed to a ``resolve`` callback.  :func:`to_modelica` is the
inverse: it writes such an expression as Modelica text with the fewest
parentheses Modelica's precedence rules allow, and numbers that read back
to the same double.

What is covered, by section of the Modelica Language Specification 3.6:

* 3.2 Operator precedence and associativity: the printer's levels; the
  unary minus is allowed only at the start of a sum (``2*(-x)``,
  ``x^(-2)``), ``^`` is non-associative (``(x^y)^z``).
* 3.4 Arithmetic operators ``+ - * / ^`` and 10.6 their array forms:
  addition and subtraction of arrays of one size (10.6.2), a scalar times
  an array (10.6.3), the matrix and vector products of ``*`` (10.6.4),
  division of an array by a scalar (10.6.5), the elementwise operators
  ``.+ .- .* ./ .^`` (10.6.2, 10.6.3, 10.6.6, 10.6.7) and the power of a
  square matrix (10.6.8).
* 3.5 Relations ``< <= > >= == <>`` (on scalars, 10.6.10) and the
  logical operators ``and``, ``or``, ``not``.
* 3.6 String concatenation (3.6.1), array constructors ``{...}`` (3.6.2,
  10.4), concatenation ``[a, b; c, d]`` (3.6.3, 10.4.2.1), ranges
  ``a:b`` and ``a:s:b`` (3.6.4, 10.4.3), if-expressions (3.6.5: a
  ``Piecewise``, or sympy's ``ITE`` where the branches are Booleans) and
  ``time`` (3.6.7); ``Modelica.Constants.pi`` and ``e`` are ``sympy.pi``
  and ``sympy.E``.  A symbol without assumptions is taken for a Boolean
  variable (``==`` of two is ``Equivalent``), as acausal declares them;
  Real and Integer variables are symbols with ``real=True`` or
  ``integer=True``.
* 3.7 Built-in operators with function syntax: ``abs``, ``sign``, ``sqrt``
  (3.7.1); ``div``, ``mod``, ``rem``, ``ceil``, ``floor``, ``integer``
  (3.7.2); ``sin`` ... ``log10`` (3.7.3) and their ``Modelica.Math``
  versions (with ``asinh``, ``acosh``); ``der`` and ``homotopy`` (3.7.4,
  :func:`acausal.homotopy`); ``initial``, ``terminal``, ``noEvent``, ``smooth``, ``sample``,
  ``pre``, ``edge``, ``change`` (3.7.5).
* 10.3 Array functions: ``ndims``, ``size`` (10.3.1), ``scalar``,
  ``vector`` (10.3.2), ``identity``, ``zeros``, ``ones``, ``fill``
  (10.3.3), ``min``, ``max``, ``sum``, ``product`` with their reduction
  forms ``sum(e for i in r)`` (10.3.4), ``transpose`` (10.3.5), ``cat``
  (10.4.2); array constructors with iterators ``{e for i in r}`` (10.4.1).
* 10.5 Indexing: subscripts (integers, ranges, ``:``, ``end`` as
  :data:`END`) are converted and handed to ``resolve``.
* 12.4.6 Automatic vectorization: the scalar built-in functions apply
  element by element to arrays.

Modelica's ``noEvent`` around a condition (``if noEvent(x > 0) then ...``)
has no sympy form of its own (a sympy Boolean cannot be wrapped in a
function): it is read as ``noEvent`` around the whole if-expression, which
means the same when nothing else in it generates events, and is refused
otherwise.

pymoca 0.12 reads ``a:s:b`` with step and stop swapped and silently drops
named arguments, reduction and constructor iterators, and the difference
between ``[...]`` and ``{...}``; :func:`repair_parser` (called when this
module is imported) corrects its parser so that these reach
:func:`to_sympy` (:func:`call_arguments` separates the named arguments of
a call).  The repair acts on trees parsed after it: import this module
before parsing, and parse with ``bypass_cache=True`` (pymoca's on-disk
cache may hold trees made before the repair).

Not supported (a :class:`~acausal.errors.ModelicaError` names them): other
functions (user-defined functions, ``delay``, ``semiLinear``,
``cardinality``, ``String``, ``Integer``, ``linspace``, ``diagonal``,
``cross``, ``matrix``, ...), named arguments of the built-in operators
(3.7: positional only, ``homotopy`` excepted), enumeration ranges, implicit
iteration ranges (``for i`` without ``in``), and functions with several
outputs.  Floats are doubles: a sympy Float of higher precision is written
as the nearest double.

Examples
--------
>>> import sympy as sp
>>> x, y = sp.symbols("x y", real=True)
>>> to_modelica(-x**2 + x/(2*y))
'-x^2 + x/(2*y)'
>>> to_modelica(sp.Piecewise((1, x > 0), (sp.sqrt(y), True)))
'if x > 0 then 1 else sqrt(y)'
"""

from __future__ import annotations

import enum
import math
import re
from typing import Any, Callable, Sequence

import numpy as np
import sympy as sp
from sympy.core.function import AppliedUndef, UndefinedFunction
from sympy.logic.boolalg import Boolean as SympyBoolean

from .. import arrays, hybrid
from ..arrays import Array
from ..errors import ArrayIndexError, ArraySizeError, ModelicaError
from ..language import der, initial, pre, time

try:  # pymoca is needed to read Modelica text only (pip install acausal[modelica])
    from pymoca import ast as _ast
    from pymoca import parser as _parser
except ImportError:  # pragma: no cover - exercised only without the optional dependency
    _ast = None
    _parser = None

__all__ = ["to_sympy", "to_modelica", "END", "Resolve", "Call", "repair_parser", "call_arguments"]

#: ``resolve(name, subscripts)``: the value of a component reference.
#: ``name`` is the dotted name without subscripts (``"a.b"``), ``subscripts``
#: has one list per part of the name with that part's subscripts, already
#: converted (``a[1].b[2, :]`` gives ``("a.b", [[1], [2, slice(None)]])``, a
#: plain ``x`` gives ``("x", [[]])``).  It returns a sympy symbol or
#: expression, an :class:`~acausal.arrays.Array`, a number, a string or an
#: enumeration value.
Resolve = Callable[[str, list], Any]

#: ``call(name, positional, named)``: the value of a call of a function that is
#: neither built in nor one of Modelica.Math's elementary functions (a
#: Modelica function a package defines); the arguments are already read.
Call = Callable[[str, list, dict], Any]

#: ``end`` inside subscripts: the size of the dimension it indexes.  A
#: subscript holding it is a sympy expression in ``END`` (``x[end - 1]``
#: gives ``END - 1``, ``x[2:end]`` gives ``slice(2, END)``); ``resolve``
#: substitutes the size.
END = sp.Symbol("end", integer=True, positive=True)

# Operators of pymoca's tree made by repair_parser (the tree has no node types for them).
_NAMED = "="          # a named argument: operands [Primary(name), value]
_ITERATE = "for"      # an expression with iterators: operands [expression, ForIndex, ...]
_CONCATENATE = "[]"   # [a, b; c, d]: operands, one Array per row


# =====================================================================================
# Reading: pymoca's tree to sympy
# =====================================================================================


def to_sympy(node: Any, resolve: Resolve, call: Call | None = None) -> Any:
    """A Modelica expression (a node of pymoca's syntax tree) in acausal's form.

    Parameters
    ----------
    node : pymoca.ast node
        An expression: ``Primary``, ``ComponentRef``, ``Expression``,
        ``IfExpression``, ``Array`` or ``Slice`` (a range).
    resolve : callable
        ``resolve(name, subscripts)``, see :data:`Resolve`; called for every
        component reference except ``time``, ``Modelica.Constants.pi`` and
        ``Modelica.Constants.e`` (read as ``sympy.pi`` and ``sympy.E``) and
        the iteration variables of array constructors.
    call : callable, optional
        ``call(name, positional, named)``, see :data:`Call`: the value of a
        call of any other function.  Without it such a call is an error.

    Returns
    -------
    sympy expression, sympy Boolean, Array, list, str or what resolve returns
        Numbers are sympy numbers (an Integer literal an ``Integer``, a Real
        literal a ``Float`` of the same double), Booleans ``sympy.true`` and
        ``sympy.false``, strings Python ``str``, arrays
        :class:`~acausal.arrays.Array`, an integer range ``a:b`` a list of
        Python ints (Real ranges: a list of sympy Floats).  A lone component
        reference is what ``resolve`` returns, unchanged.

    Raises
    ------
    ModelicaError
        For an operator, function or construct acausal does not support
        (the message names it), and for misuse: arrays of sizes that do not
        fit (the array functions' :class:`~acausal.errors.ArraySizeError`
        and :class:`~acausal.errors.ArrayIndexError` become ModelicaError
        with the same message and hint), a string in arithmetic, a range
        whose bounds are not numbers.  What ``resolve`` raises otherwise
        passes through, and so does the
        :class:`~acausal.errors.EquationError` of ``edge()``, ``change()``
        of something that is not a variable.
    """
    if _ast is None:  # pragma: no cover
        raise ModelicaError("reading Modelica needs pymoca", hint="pip install acausal[modelica]")
    try:
        value = _Reader(resolve, call).read(node)
    except (ArraySizeError, ArrayIndexError) as exc:  # from acausal's array functions
        raise ModelicaError(exc.message, hint=exc.hint) from exc
    if isinstance(value, _Literal):
        return hybrid.NoEvent(value.condition)
    return value


class _Literal:
    """A condition under ``noEvent``: a sympy Boolean whose relations give no events.

    sympy cannot wrap a Boolean in a function and keep it a Boolean, so the
    reader carries the mark until an if-expression (or the end of the
    expression) puts ``noEvent`` around a value.
    """

    __slots__ = ("condition",)

    def __init__(self, condition: SympyBoolean) -> None:
        self.condition = condition


class _Builtin:
    """A built-in function: how to apply it and what arguments it takes."""

    __slots__ = ("apply", "least", "most", "names", "elementwise")

    def __init__(self, apply: Callable[..., Any], least: int, most: int | None = -1,
                 names: tuple[str, ...] = (), elementwise: bool = False) -> None:
        self.apply = apply
        self.least = least
        self.most = least if most == -1 else most  # None: any number
        self.names = names                          # parameter names, for named arguments
        self.elementwise = elementwise              # applied element by element (MLS 12.4.6)


_RELATIONS: dict[str, Callable[..., SympyBoolean]] = {
    "<": sp.Lt, "<=": sp.Le, ">": sp.Gt, ">=": sp.Ge, "==": sp.Eq, "<>": sp.Ne}

_ELEMENTARY: dict[str, Callable[..., Any]] = {
    "sin": sp.sin, "cos": sp.cos, "tan": sp.tan, "asin": sp.asin, "acos": sp.acos,
    "atan": sp.atan, "sinh": sp.sinh, "cosh": sp.cosh, "tanh": sp.tanh, "exp": sp.exp,
    "log": sp.log, "log10": lambda u: sp.log(u, 10)}

#: Functions of Modelica.Math read as sympy functions (the elementary ones and these).
_MATH_ONLY: dict[str, Callable[..., Any]] = {"asinh": sp.asinh, "acosh": sp.acosh}

_STRING_ESCAPES = {"'": "'", '"': '"', "?": "?", "\\": "\\", "a": "\a", "b": "\b", "f": "\f",
                   "n": "\n", "r": "\r", "t": "\t", "v": "\v"}


class _Reader:
    """One reading of an expression: the callback and the iteration variables in scope."""

    def __init__(self, resolve: Resolve, call: Call | None = None) -> None:
        self.resolve = resolve
        self.call = call
        self.iterators: dict[str, Any] = {}
        self.in_subscript = 0
        self.builtins = self._builtins()

    # -- nodes ---------------------------------------------------------------------------
    def read(self, node: Any) -> Any:
        if isinstance(node, _ast.Primary):
            return self._primary(node.value)
        if isinstance(node, _ast.ComponentRef):
            return self._reference(node)
        if isinstance(node, _ast.Expression):
            return self._expression(node)
        if isinstance(node, _ast.IfExpression):
            return self._if(node)
        if isinstance(node, _ast.Array):
            return self._stack([self.read(value) for value in node.values])
        if isinstance(node, _ast.Slice):
            return self._range(node)
        if isinstance(node, list):
            raise ModelicaError(f"a parenthesised list of {len(node)} expressions",
                                hint="a function with several outputs cannot be used in an expression")
        raise ModelicaError(f"unsupported Modelica construct {type(node).__name__}")

    @staticmethod
    def _primary(value: Any) -> Any:
        if isinstance(value, bool):
            return sp.true if value else sp.false
        if isinstance(value, int):
            return sp.Integer(value)
        if isinstance(value, float):
            if not math.isfinite(value):
                raise ModelicaError("a number literal beyond the range of Real (a double)")
            return sp.Float(value)
        if isinstance(value, str):
            return re.sub(r"\\(.)", lambda m: _STRING_ESCAPES.get(m.group(1), m.group(0)), value)
        raise ModelicaError(f"unsupported literal {value!r}")

    def _reference(self, node: Any) -> Any:
        parts: list[tuple[str, list]] = []
        part = node
        while part is not None:
            subscripts = [s for group in part.indices for s in group if s is not None]
            parts.append((part.name, subscripts))
            part = part.child[0] if part.child else None
        if parts[0][0] == "" and len(parts) > 1:  # a leading dot: lookup from the top (MLS 5.3.3)
            parts = parts[1:]
        names = [name for name, _ in parts]
        plain = not any(subscripts for _, subscripts in parts)
        if plain and len(names) == 1:
            if names[0] in self.iterators:
                return self.iterators[names[0]]
            if names[0] == "time":
                return time
            if names[0] == "end":
                if self.in_subscript:
                    return END
                raise ModelicaError("'end' outside subscripts", hint="end stands for the size of "
                                    "the dimension it indexes: x[end], x[2:end]")
        if plain and names[:2] == ["Modelica", "Constants"] and names[2:] in (["pi"], ["e"]):
            return sp.pi if names[2] == "pi" else sp.E
        converted = [[self._subscript(s) for s in subscripts] for _, subscripts in parts]
        return self._value(self.resolve(".".join(names), converted))

    def _subscript(self, node: Any) -> Any:
        self.in_subscript += 1
        try:
            if isinstance(node, _ast.Slice):
                if _is_none(node.start) and _is_none(node.stop):
                    return slice(None)  # ':'
                start, stop, step = (self._index(self.read(n)) for n in (node.start, node.stop, node.step))
                return slice(start, stop, None if step == 1 else step)
            return self._index(self.read(node))
        finally:
            self.in_subscript -= 1

    @staticmethod
    def _index(value: Any) -> Any:
        """A subscript value: a Python int when known, a list for an integer vector."""
        if isinstance(value, list):
            return [_Reader._index(v) for v in value]
        if isinstance(value, Array):
            return [_Reader._index(v) for v in value.flat]
        if isinstance(value, (bool, sp.logic.boolalg.BooleanAtom, enum.Enum)):
            return value
        if isinstance(value, (int, np.integer)):
            return int(value)
        if isinstance(value, sp.Integer):
            return int(value)
        if isinstance(value, sp.Basic) and not isinstance(value, sp.Float) and not value.is_Number:
            return value  # a symbolic index (a parameter, END - 1): the resolver decides
        raise ModelicaError(f"subscript {value} is not an Integer", hint="Modelica indices are integers from 1")

    @staticmethod
    def _value(value: Any) -> Any:
        """What resolve returned, with sequences made Arrays and numbers sympy numbers."""
        if isinstance(value, (Array, str, enum.Enum, _Literal)):
            return value
        if isinstance(value, (list, tuple, np.ndarray, sp.MatrixBase)):
            return Array(value)
        if isinstance(value, (bool, np.bool_)):
            return sp.true if value else sp.false
        if isinstance(value, (int, float, np.number)):
            return sp.sympify(value)
        return value

    # -- operators -------------------------------------------------------------------------
    def _expression(self, node: Any) -> Any:
        operator, operands = node.operator, node.operands
        if not isinstance(operator, str):
            return self._call(_dotted(operator), operands)
        if operator in ("der", "initial"):
            return self._call(operator, operands)
        if operator == _CONCATENATE:
            return self._concatenate(operands)
        if operator == _ITERATE:
            return self._comprehension(operands)
        if operator == _NAMED:
            raise ModelicaError(f"named argument {operands[0].value}= outside a function call")
        values = [self.read(operand) for operand in operands]
        if operator in ("+", "-") and len(values) == 1:
            return values[0] if operator == "+" else self._negate(values[0])
        if operator in _RELATIONS:
            return self._relation(operator, *values)
        if operator == "not":
            condition, literal = self._condition(values[0], "not")
            return _literal(sp.Not(condition), literal)
        if operator in ("and", "or"):
            return self._logical(operator, values)
        if len(values) == 2:
            return self._arithmetic(operator, *values)
        raise ModelicaError(f"unsupported Modelica operator {operator!r}")

    def _negate(self, value: Any) -> Any:
        return self._elementwise(lambda a: -a, [value], "-")

    def _arithmetic(self, operator: str, a: Any, b: Any) -> Any:
        if isinstance(a, str) or isinstance(b, str):
            if operator in ("+", ".+") and isinstance(a, str) and isinstance(b, str):
                return a + b  # string concatenation (MLS 3.6.1)
            raise ModelicaError(f"a string in arithmetic: {a!r} {operator} {b!r}",
                                hint="only + joins two strings")
        left, right = _as_array(a), _as_array(b)
        if operator in ("+", "-"):
            if (left is None) != (right is None):
                raise ModelicaError(f"a scalar and an array in {operator} (Modelica 10.6.2)",
                                    hint=f"write .{operator} to apply the scalar to every element")
            return self._elementwise(_OPERATIONS[operator], [a, b], operator)
        if operator == "*":
            if left is not None and right is not None:
                return self._product(left, right)
            return self._elementwise(_OPERATIONS["*"], [a, b], operator)
        if operator == "/":
            if right is not None:
                raise ModelicaError("division by an array (Modelica 10.6.5 divides by scalars only)",
                                    hint="write ./ to divide element by element")
            return self._elementwise(_OPERATIONS["/"], [a, b], operator)
        if operator == "^":
            if right is not None:
                raise ModelicaError("an array exponent in ^", hint="write .^ for elementwise powers")
            if left is not None:
                return self._matrix_power(left, b)
            return self._elementwise(_OPERATIONS["^"], [a, b], operator)
        if operator in (".+", ".-", ".*", "./", ".^"):
            return self._elementwise(_OPERATIONS[operator[1:]], [a, b], operator)
        raise ModelicaError(f"unsupported Modelica operator {operator!r}")

    @staticmethod
    def _product(left: Array, right: Array) -> Any:
        """``*`` of two arrays: the scalar product, matrix-vector or matrix product (MLS 10.6.4)."""
        if left.ndim not in (1, 2) or right.ndim not in (1, 2):
            raise ModelicaError(f"* of arrays of {left.ndim} and {right.ndim} dimensions",
                                hint="* multiplies vectors and matrices; .* multiplies element by element")
        return left @ right

    def _matrix_power(self, matrix: Array, exponent: Any) -> Array:
        """``A^n`` of a square matrix and an Integer ``n >= 0`` (MLS 10.6.8)."""
        n = _integer_value(self._scalar(exponent))
        if matrix.ndim != 2 or matrix.shape[0] != matrix.shape[1] or n is None or n < 0:
            raise ModelicaError(f"^ of an array of size {list(matrix.shape)} and exponent {exponent}",
                                hint="A^n needs a square matrix and a constant Integer n >= 0; "
                                     "write .^ for elementwise powers")
        result = arrays.identity(matrix.shape[0])
        for _ in range(n):
            result = result @ matrix
        return result

    def _elementwise(self, operation: Callable[..., Any], values: Sequence[Any], what: str) -> Any:
        """``operation`` of scalars, or element by element where some values are arrays
        (the others are taken for every element); arrays must have one size."""
        found = [_as_array(v) for v in values]
        shapes = {a.shape for a in found if a is not None}
        if not shapes:
            return _applied(operation, [self._scalar(v) for v in values], what)
        if len(shapes) > 1:
            raise ModelicaError(f"{what} of arrays of sizes "
                                f"{' and '.join(str(list(s)) for s in sorted(shapes))}",
                                hint="element by element operations need arrays of one size")
        shape = shapes.pop()
        out = np.empty(shape, dtype=object)
        for index in np.ndindex(*shape):
            out[index] = _applied(operation, [self._scalar(v if a is None else a.data[index])
                                              for v, a in zip(values, found)], what)
        return Array(out)

    def _relation(self, operator: str, a: Any, b: Any) -> SympyBoolean:
        if _as_array(a) is not None or _as_array(b) is not None:
            raise ModelicaError(f"relation {operator} of arrays", hint="Modelica compares scalars only "
                                "(10.6.10); compare elements, or use a for-equation")
        if isinstance(a, str) and isinstance(b, str):
            outcome = {"<": a < b, "<=": a <= b, ">": a > b, ">=": a >= b, "==": a == b, "<>": a != b}
            return sp.true if outcome[operator] else sp.false
        left, right = self._scalar(a), self._scalar(b)
        if operator in ("==", "<>") and (_is_boolean(left) or _is_boolean(right)):
            left, _ = self._condition(left, operator)
            right, _ = self._condition(right, operator)
            return sp.Equivalent(left, right) if operator == "==" else sp.Xor(left, right)
        try:
            return _RELATIONS[operator](left, right)
        except TypeError as exc:
            raise ModelicaError(f"relation {left} {operator} {right} of values that do not compare") from exc

    def _logical(self, operator: str, values: Sequence[Any]) -> Any:
        conditions = [self._condition(v, operator) for v in values]
        combine = sp.And if operator == "and" else sp.Or
        result = combine(*(c for c, _ in conditions))
        if any(literal for _, literal in conditions):
            others = [c for c, literal in conditions if not literal]
            if any(_generates_events(c) for c in others):
                raise ModelicaError(f"noEvent() in one operand of '{operator}' whose other operands "
                                    f"generate events: {result}",
                                    hint="put noEvent() around every relation of the condition, or "
                                         "around the whole expression")
            return _Literal(result)
        return result

    def _condition(self, value: Any, what: str) -> tuple[SympyBoolean, bool]:
        """``value`` as a sympy Boolean, and whether it stands under noEvent."""
        if isinstance(value, _Literal):
            return value.condition, True
        if isinstance(value, (bool, np.bool_)):
            return (sp.true if value else sp.false), False
        if isinstance(value, AppliedUndef) and not isinstance(value, SympyBoolean) \
                and value.func.__name__ in ("pre", "initial", "edge", "change", "sample"):
            return _boolean_application(value), False
        if isinstance(value, sp.Piecewise) and _boolean_values([pair.expr for pair in value.args]):
            return _boolean_if([pair.cond for pair in value.args[:-1]],
                               [pair.expr for pair in value.args]), False
        if isinstance(value, sp.Symbol) and (value.is_real or value.is_integer):
            raise ModelicaError(f"{what}: {value} is not a Boolean expression",
                                hint="a condition is a relation or a Boolean variable")
        if isinstance(value, SympyBoolean):
            return value, False
        raise ModelicaError(f"{what}: {value} is not a Boolean expression",
                            hint="a condition is a relation or a Boolean variable")

    # -- if-expressions ----------------------------------------------------------------------
    def _if(self, node: Any) -> Any:
        """``if c1 then e1 elseif c2 then e2 else e3`` as a Piecewise, or as nested ``ITE``
        when the branches are Booleans (MLS 3.6.5)."""
        conditions = [self._condition(self.read(c), "if") for c in node.conditions]
        values = [self.read(e) for e in node.expressions]
        found = [_as_array(v) for v in values]
        if all(a is None for a in found):
            return self._choice(conditions, values)
        shapes = {a.shape if a is not None else () for a in found}
        if len(shapes) > 1:
            raise ModelicaError(f"if-expression with branches of sizes "
                                f"{' and '.join(str(list(s)) for s in sorted(shapes))}",
                                hint="every branch of an if-expression has the same size")
        shape = shapes.pop()
        out = np.empty(shape, dtype=object)
        for index in np.ndindex(*shape):
            out[index] = self._choice(conditions, [a.data[index] for a in found])
        return Array(out)

    def _choice(self, conditions: list[tuple[SympyBoolean, bool]], values: list[Any]) -> Any:
        """The value of one if-expression (of scalars); conditions come with their noEvent mark."""
        if any(isinstance(v, str) for v in values):
            for (condition, _), value in zip(conditions, values):  # strings: constant conditions only
                if condition is sp.true:
                    return value
                if condition is not sp.false:
                    raise ModelicaError("an if-expression of strings with a condition that is not constant")
            return values[-1]
        branches = [(v.condition, True) if isinstance(v, _Literal) else (self._scalar(v), False)
                    for v in values]
        boolean = _boolean_values([b for b, _ in branches])
        if not boolean:  # a condition under noEvent as a number: noEvent of its own
            branches = [(hybrid.NoEvent(b) if flag else b, False) for b, flag in branches]
        scalars = [b for b, _ in branches]
        if boolean:
            result = _boolean_if([c for c, _ in conditions], scalars)
        else:
            try:
                result = sp.Piecewise(*zip(scalars, [c for c, _ in conditions]), (scalars[-1], sp.true))
            except TypeError as exc:
                raise ModelicaError(f"if-expression that sympy cannot hold: {exc}") from exc
        if not any(flag for _, flag in conditions + branches):
            return result
        others = [part for part, flag in conditions + branches if not flag]
        if any(_generates_events(part) for part in others):
            raise ModelicaError("noEvent() around a condition of an if-expression whose other parts "
                                "generate events",
                                hint="acausal keeps noEvent() around the whole if-expression; write "
                                     "noEvent(if ... then ... else ...) or noEvent() around every "
                                     "relation inside")
        return _Literal(result) if boolean else hybrid.NoEvent(result)

    # -- arrays ------------------------------------------------------------------------------
    def _stack(self, values: Sequence[Any]) -> Array:
        """``{a, b, ...}``: one dimension added on the left (MLS 10.4)."""
        datas = [_array_data(v) for v in values]
        shapes = {d.shape for d in datas}
        if len(shapes) > 1:
            raise ModelicaError(f"array constructor of elements of sizes "
                                f"{' and '.join(str(list(s)) for s in sorted(shapes))}",
                                hint="every element of {...} has the same size")
        shape = shapes.pop() if shapes else ()
        out = np.empty((len(datas),) + shape, dtype=object)
        for k, data in enumerate(datas):
            if data.ndim:
                out[k] = data
            else:
                out[k] = data[()]  # a scalar (assigning the 0-d array would store the array itself)
        return Array(out)

    def _concatenate(self, rows: Sequence[Any]) -> Array:
        """``[a, b; c, d]``: ``cat(1, cat(2, a, b), cat(2, c, d))`` of the operands made
        at least matrices (MLS 10.4.2.1)."""
        cells = [[_array_data(self.read(v)) for v in row.values] for row in rows]
        n = max([2] + [d.ndim for row in cells for d in row])
        try:
            joined = [np.concatenate([d.reshape(d.shape + (1,) * (n - d.ndim)) for d in row], axis=1)
                      for row in cells]
            return Array(np.concatenate(joined, axis=0))
        except ValueError as exc:
            sizes = "; ".join(", ".join(str(list(d.shape)) for d in row) for row in cells)
            raise ModelicaError(f"[...] of parts of sizes [{sizes}] that do not fit together",
                                hint="the parts of a row have the same number of rows, the rows the "
                                     "same number of columns") from exc

    def _range(self, node: Any) -> list:
        """``a:b`` or ``a:s:b`` as a list of numbers (MLS 10.4.3)."""
        start, step, stop = (self._scalar(self.read(n)) for n in (node.start, node.step, node.stop))
        if isinstance(start, sp.logic.boolalg.BooleanAtom) and isinstance(stop, sp.logic.boolalg.BooleanAtom):
            if step != 1:
                raise ModelicaError("a Boolean range with a step")
            return [b for b in (sp.false, sp.true)  # false:true, false:false, true:true, true:false
                    if (start is sp.false or b is sp.true) and (stop is sp.true or b is sp.false)]
        if not all(isinstance(v, sp.Number) for v in (start, step, stop)):
            raise ModelicaError(f"range {start}:{step}:{stop} whose bounds are not known numbers",
                                hint="the bounds of a range are constants or parameters with values")
        if step == 0:
            raise ModelicaError("range with step 0")
        if all(isinstance(v, sp.Integer) for v in (start, step, stop)):
            first, increment, last = int(start), int(step), int(stop)
            return list(range(first, last + (1 if increment > 0 else -1), increment))
        count = math.floor(float((stop - start) / step))
        return [sp.Float(float(start + i * step)) for i in range(count + 1)]

    def _comprehension(self, operands: Sequence[Any]) -> Array:
        """``{e for i in u, j in v}`` = ``{{e for i in u} for j in v}`` (MLS 10.4.1)."""
        expression, *indices = operands
        ranges: list[tuple[str, list]] = []
        for index in indices:
            if index.expression is None:
                raise ModelicaError(f"iterator {index.name} without a range",
                                    hint="write the range: for i in 1:n")
            values = self.read(index.expression)
            values = values if isinstance(values, list) else _iteration_values(values)
            ranges.append((index.name, values))

        def expand(level: int) -> Any:
            if level < 0:
                return self.read(expression)
            name, values = ranges[level]
            hidden = self.iterators.get(name, _MISSING)
            items = []
            try:
                for value in values:
                    self.iterators[name] = value
                    items.append(expand(level - 1))
            finally:
                if hidden is _MISSING:
                    self.iterators.pop(name, None)
                else:
                    self.iterators[name] = hidden
            return self._stack(items)

        return expand(len(ranges) - 1)

    # -- function calls ----------------------------------------------------------------------
    def _call(self, name: str, operands: Sequence[Any]) -> Any:
        positional, named = call_arguments(operands, name)
        parts = name.split(".")
        if parts[:-1] in (["Modelica", "Math"], ["Math"]):
            short = parts[-1]
            function = _ELEMENTARY.get(short) or _MATH_ONLY.get(short) or (sp.atan2 if short == "atan2" else None)
            if function is None and self.call is not None:
                return self.call(name, [self.read(operand) for operand in positional],
                                 {key: self.read(operand) for key, operand in named.items()})
            if function is None:
                raise ModelicaError(f"unsupported function {name}",
                                    hint="acausal reads the elementary functions of Modelica.Math")
            names = ("u1", "u2") if short == "atan2" else ("u",)
            builtin = _Builtin(function, len(names), names=names, elementwise=True)
        else:
            builtin = self.builtins.get(name)
            if builtin is None and self.call is not None:
                return self.call(name, [self.read(operand) for operand in positional],
                                 {key: self.read(operand) for key, operand in named.items()})
            if builtin is None:
                raise ModelicaError(f"unsupported function {name}()",
                                    hint="acausal reads Modelica's built-in operators and the "
                                         "elementary functions of Modelica.Math")
        if named and not builtin.names:
            raise ModelicaError(f"{name}() with named arguments ({', '.join(named)})",
                                hint="Modelica's built-in operators take positional arguments only")
        arguments = [self.read(operand) for operand in positional]
        if named:
            arguments += [_MISSING] * (len(builtin.names) - len(arguments))
            for key, operand in named.items():
                if key not in builtin.names:
                    raise ModelicaError(f"{name}() has no argument {key}",
                                        hint=f"its arguments are {', '.join(builtin.names)}")
                position = builtin.names.index(key)
                if arguments[position] is not _MISSING:
                    raise ModelicaError(f"{name}(): argument {key} given twice")
                arguments[position] = self.read(operand)
        if _MISSING in arguments or len(arguments) < builtin.least \
                or (builtin.most is not None and len(arguments) > builtin.most):
            wanted = str(builtin.least) if builtin.most == builtin.least else \
                f"{builtin.least} or more" if builtin.most is None else f"{builtin.least} to {builtin.most}"
            raise ModelicaError(f"{name}() takes {wanted} argument{'s' if wanted != '1' else ''}, "
                                f"given {sum(a is not _MISSING for a in arguments)}")
        if builtin.elementwise:
            return self._elementwise(builtin.apply, arguments, f"{name}()")
        return _applied(builtin.apply, arguments, f"{name}()")

    def _builtins(self) -> dict[str, _Builtin]:
        """Modelica's built-in operators with function syntax (MLS 3.7, 10.3)."""
        scalar = self._scalar
        table = {
            # 3.7.1, 3.7.2 numeric and event-triggering functions
            "abs": _Builtin(sp.Abs, 1, elementwise=True),
            "sign": _Builtin(sp.sign, 1, elementwise=True),
            "sqrt": _Builtin(sp.sqrt, 1, elementwise=True),
            "floor": _Builtin(hybrid.floor, 1, elementwise=True),
            "ceil": _Builtin(hybrid.ceil, 1, elementwise=True),
            "integer": _Builtin(hybrid.integer, 1, elementwise=True),
            "div": _Builtin(hybrid.div, 2, elementwise=True),
            "mod": _Builtin(hybrid.mod, 2, elementwise=True),
            "rem": _Builtin(hybrid.rem, 2, elementwise=True),
            # 3.7.3 elementary functions
            **{name: _Builtin(function, 1, elementwise=True) for name, function in _ELEMENTARY.items()},
            "atan2": _Builtin(sp.atan2, 2, elementwise=True),
            # 3.7.4 derivative and special purpose operators
            "der": _Builtin(der, 1, elementwise=True),
            "homotopy": _Builtin(hybrid.homotopy, 2, names=("actual", "simplified")),
            # 3.7.5 event-related operators
            "initial": _Builtin(initial, 0),
            "terminal": _Builtin(hybrid.terminal, 0),
            "pre": _Builtin(pre, 1, elementwise=True),
            "edge": _Builtin(hybrid.edge, 1, elementwise=True),
            "change": _Builtin(hybrid.change, 1, elementwise=True),
            "sample": _Builtin(lambda start, interval: hybrid.sample(scalar(start), scalar(interval)), 2),
            "noEvent": _Builtin(lambda u: self._no_event(u, 0), 1),
            "smooth": _Builtin(lambda order, u: self._no_event(u, order), 2),
            # 10.3 array functions
            "ndims": _Builtin(lambda a: sp.Integer(_array_data(a).ndim), 1),
            "size": _Builtin(self._size, 1, 2),
            "scalar": _Builtin(lambda a: arrays.scalar(self._array(a, "scalar")), 1),
            "vector": _Builtin(lambda a: arrays.vector(_array_data(a)), 1),
            "identity": _Builtin(lambda n: arrays.identity(self._dimension(n, "identity")), 1),
            "zeros": _Builtin(lambda *n: self._fill(sp.Integer(0), n, "zeros"), 1, None),
            "ones": _Builtin(lambda *n: self._fill(sp.Integer(1), n, "ones"), 1, None),
            "fill": _Builtin(lambda value, *n: self._fill(value, n, "fill"), 2, None),
            "min": _Builtin(lambda *a: self._extremum(arrays.min, "min", a), 1, 2),
            "max": _Builtin(lambda *a: self._extremum(arrays.max, "max", a), 1, 2),
            "sum": _Builtin(lambda a: arrays.sum(self._array(a, "sum")), 1),
            "product": _Builtin(lambda a: arrays.product(self._array(a, "product")), 1),
            "transpose": _Builtin(lambda a: arrays.transpose(self._array(a, "transpose")), 1),
            "cat": _Builtin(lambda k, *a: arrays.cat(self._dimension(k, "cat"),
                                                     *(self._array(x, "cat") for x in a)), 2, None),
        }
        return table

    def _no_event(self, value: Any, order: Any) -> Any:
        """``noEvent(u)`` and ``smooth(order, u)`` (MLS 3.7.5): a negative order keeps events."""
        order = _integer_value(self._scalar(order))
        if order is None:
            raise ModelicaError("smooth() with an order that is not a constant Integer")
        if order < 0:
            return value
        if isinstance(value, _Literal):
            return value
        if isinstance(value, SympyBoolean) and not isinstance(value, sp.Symbol):
            return _Literal(value)
        return self._elementwise(hybrid.noEvent, [value], "noEvent()")

    def _size(self, a: Any, dimension: Any = None) -> Any:
        shape = _array_data(a).shape
        if dimension is None:
            return Array([sp.Integer(n) for n in shape])
        k = self._dimension(dimension, "size")
        if not 1 <= k <= len(shape):
            raise ModelicaError(f"size(a, {k}) of an array of {len(shape)} dimensions")
        return sp.Integer(shape[k - 1])

    def _fill(self, value: Any, dimensions: Sequence[Any], what: str) -> Array:
        shape = tuple(self._dimension(n, what) for n in dimensions)
        data = _array_data(value if isinstance(value, (str, Array, list)) else self._scalar(value))
        out = np.empty(shape + data.shape, dtype=object)
        out[...] = data if data.ndim else data[()]
        return Array(out)

    def _extremum(self, function: Callable[..., Any], name: str, values: Sequence[Any]) -> Any:
        if len(values) == 1:
            return function(self._array(values[0], name))
        if any(_as_array(v) is not None for v in values):
            raise ModelicaError(f"{name}(a, b) of arrays", hint=f"{name}(a) of one array, or of two scalars")
        return function(*(self._scalar(v) for v in values))

    def _array(self, value: Any, what: str) -> Array:
        found = _as_array(value)
        if found is None:
            raise ModelicaError(f"{what}() of the scalar {value}", hint=f"{what}() takes an array")
        return found

    def _dimension(self, value: Any, what: str) -> int:
        n = _integer_value(self._scalar(value))
        if n is None or n < 0:
            raise ModelicaError(f"{what}(): {value} is not a constant Integer >= 0",
                                hint="sizes and dimensions are constants or parameters with values")
        return n

    @staticmethod
    def _scalar(value: Any) -> Any:
        """``value`` as a sympy scalar; arrays and strings are refused."""
        if isinstance(value, _Literal):
            raise ModelicaError(f"noEvent() of the condition {value.condition} used as a value",
                                hint="noEvent() of a condition is read inside if-expressions and "
                                     "and/or/not only")
        if isinstance(value, str):
            raise ModelicaError(f"the string {value!r} where a number is needed")
        if _as_array(value) is not None:
            raise ModelicaError(f"an array where a scalar is needed: {value}")
        if isinstance(value, enum.Enum):
            if isinstance(value, int):
                return sp.Integer(int(value))
            raise ModelicaError(f"the enumeration value {value} in arithmetic")
        if isinstance(value, (bool, np.bool_)):
            return sp.true if value else sp.false
        if isinstance(value, sp.Basic):
            return value
        try:
            return sp.sympify(value, strict=True)
        except sp.SympifyError as exc:
            raise ModelicaError(f"the value {value!r} where a number is needed") from exc


_MISSING = object()

_OPERATIONS: dict[str, Callable[[Any, Any], Any]] = {
    "+": lambda a, b: a + b, "-": lambda a, b: a - b, "*": lambda a, b: a * b,
    "/": lambda a, b: a / b, "^": lambda a, b: sp.Pow(a, b)}


def call_arguments(operands: Sequence[Any], function: str = "the function") -> tuple[list, dict[str, Any]]:
    """The positional and the named arguments of a call in pymoca's tree.

    After :func:`repair_parser`, a named argument ``level=AssertionLevel.warning``
    is an ``Expression(operator="=")`` among the operands of a function call
    (an ``Expression`` whose operator is the function's name) or the
    ``arguments`` of an equation-level call (``ast.Function``: ``assert``,
    ``terminate``, ``reinit``).

    Parameters
    ----------
    operands : sequence of pymoca nodes
        The operands or arguments as the tree holds them.
    function : str, optional
        The function's name, for the message.

    Returns
    -------
    list, dict
        The positional argument nodes in order, and ``{name: node}`` of the
        named ones.

    Raises
    ------
    ModelicaError
        For a positional argument after a named one, or a name given twice.
    """
    positional: list = []
    named: dict[str, Any] = {}
    for operand in operands:
        if isinstance(operand, _ast.Expression) and operand.operator == _NAMED:
            key = operand.operands[0].value
            if key in named:
                raise ModelicaError(f"{function}(): argument {key} given twice")
            named[key] = operand.operands[1]
        elif named:
            raise ModelicaError(f"{function}(): a positional argument after a named one")
        else:
            positional.append(operand)
    return positional, named


def _applied(operation: Callable[..., Any], arguments: Sequence[Any], what: str) -> Any:
    """``operation(*arguments)``, with sympy's refusal (a Boolean in arithmetic, say) a
    ModelicaError naming the operation."""
    try:
        return operation(*arguments)
    except (TypeError, AttributeError) as exc:
        shown = ", ".join(str(a) for a in arguments)
        raise ModelicaError(f"cannot apply {what} to {shown} ({exc})",
                            hint="arithmetic and functions take numbers; a Boolean gives a number "
                                 "through an if-expression") from exc


def _dotted(reference: Any) -> str:
    """The dotted name of a function's component reference (a leading dot dropped)."""
    names = []
    part = reference
    while part is not None:
        if part.name:
            names.append(part.name)
        part = part.child[0] if part.child else None
    return ".".join(names)


def _is_none(node: Any) -> bool:
    return isinstance(node, _ast.Primary) and node.value is None


def _literal(condition: SympyBoolean, literal: bool) -> Any:
    return _Literal(condition) if literal else condition


def _as_array(value: Any) -> Array | None:
    if isinstance(value, Array):
        return value
    if isinstance(value, (list, tuple, np.ndarray)):
        return Array(value)
    return None


def _array_data(value: Any) -> np.ndarray:
    """The elements of an array, or a 0-dimensional array holding a scalar."""
    found = _as_array(value)
    if found is not None:
        return found.data
    data = np.empty((), dtype=object)
    data[()] = value
    return data


def _iteration_values(value: Any) -> list:
    """The values an iterator takes over an array: along its first dimension."""
    found = _as_array(value)
    if found is None or found.ndim == 0:
        raise ModelicaError(f"iteration over {value}, which is not a vector")
    return [_Reader._index(v) if isinstance(v, sp.Integer) else v for v in found]


def _integer_value(value: Any) -> int | None:
    if isinstance(value, (int, np.integer)) and not isinstance(value, bool):
        return int(value)
    if isinstance(value, sp.Integer):
        return int(value)
    return None


def _is_logical(value: Any) -> bool:
    """Whether ``value`` is surely a Boolean (a relation, a logical operator, true/false)."""
    return isinstance(value, SympyBoolean) and not isinstance(value, sp.Symbol)


def _is_boolean(value: Any) -> bool:
    """Whether ``value`` is a Boolean: a logical expression, a symbol without assumptions
    (acausal's Boolean variables) or ``pre`` of one."""
    if isinstance(value, AppliedUndef) and value.func.__name__ == "pre" and len(value.args) == 1:
        value = value.args[0]
    if isinstance(value, sp.Symbol):
        return value.is_real is None and value.is_integer is None
    return _is_logical(value)


def _boolean_values(values: Sequence[Any]) -> bool:
    """Whether the branches of an if-expression are Booleans: sympy Booleans, none a Real or
    Integer symbol (acausal's Boolean variables are symbols without assumptions)."""
    return all(isinstance(v, SympyBoolean) and not (isinstance(v, sp.Symbol) and (v.is_real or v.is_integer))
               for v in values)


def _boolean_if(conditions: Sequence[SympyBoolean], values: Sequence[SympyBoolean]) -> SympyBoolean:
    """``if c1 then v1 elseif c2 then v2 else v3`` of Booleans: ITE(c1, v1, ITE(c2, v2, v3))."""
    result = values[-1]
    for condition, value in zip(reversed(conditions), reversed(values[:-1])):
        result = sp.ITE(condition, value, result)
    return result


def _generates_events(expr: Any) -> bool:
    """Whether ``expr`` has relations, event-generating functions or sample() outside noEvent()."""
    if not isinstance(expr, sp.Basic):
        return False
    if isinstance(expr, hybrid.NoEvent):
        return False
    if isinstance(expr, (sp.core.relational.Relational, *hybrid.EVENT_FUNCTIONS)):
        return True
    if isinstance(expr, AppliedUndef) and expr.func.__name__ == "sample":
        return True
    return any(_generates_events(arg) for arg in expr.args)


_BOOLEAN_TWINS: dict[Any, type] = {}


def _uncached_new(cls: type, *args: Any) -> sp.Basic:
    # sympy caches Function.__new__ by argument and the twin compares equal to the
    # plain function: build the object directly so the Boolean class is kept
    return sp.Basic.__new__(cls, *map(sp.sympify, args))


def _boolean_application(value: AppliedUndef) -> SympyBoolean:
    """``pre(b)``, ``initial()`` ... as a sympy Boolean (usable in And/Or/Not and Piecewise).

    The Boolean function class compares equal to the plain one (sympy compares
    undefined functions by name and assumptions), so flattening treats both alike.
    """
    function = value.func
    twin = _BOOLEAN_TWINS.get(function)
    if twin is None:
        twin = _BOOLEAN_TWINS[function] = UndefinedFunction(
            function.__name__, bases=(AppliedUndef, SympyBoolean), __dict__={"__new__": _uncached_new},
            **dict(getattr(function, "_kwargs", {})))
    return twin(*value.args)


# =====================================================================================
# Writing: sympy to Modelica text
# =====================================================================================

# Precedence levels of Modelica's operators, lowest first (MLS 3.2, table 3.1).  The unary
# minus shares the level of + and - (the specification's advice for printers: then
# parentheses come out right around ``1 + (-1)``).
_IF, _OR, _AND, _NOT, _REL, _ADD, _MUL, _POW, _PRIMARY = range(9)

_FUNCTION_NAMES: dict[type, str] = {
    sp.sin: "sin", sp.cos: "cos", sp.tan: "tan", sp.asin: "asin", sp.acos: "acos", sp.atan: "atan",
    sp.atan2: "atan2", sp.sinh: "sinh", sp.cosh: "cosh", sp.tanh: "tanh", sp.exp: "exp",
    sp.log: "log", sp.Abs: "abs", sp.sign: "sign", sp.floor: "floor", sp.ceiling: "ceil",
    sp.Mod: "mod", sp.asinh: "Modelica.Math.asinh", sp.acosh: "Modelica.Math.acosh",
    hybrid.NoEvent: "noEvent", hybrid.floor: "floor", hybrid.ceil: "ceil", hybrid.integer: "integer",
    hybrid.div: "div", hybrid.mod: "mod", hybrid.rem: "rem", hybrid.Homotopy: "homotopy"}

#: Applications of undefined functions written as Modelica operators, by name.
_OPERATOR_NAMES = ("der", "pre", "initial", "sample", "terminal")

_RELATION_TEXT: dict[type, str] = {
    sp.StrictLessThan: "<", sp.LessThan: "<=", sp.StrictGreaterThan: ">", sp.GreaterThan: ">=",
    sp.Equality: "==", sp.Unequality: "<>"}

_ESCAPED = {"\\": "\\\\", '"': '\\"', "\n": "\\n", "\t": "\\t", "\r": "\\r", "\a": "\\a",
            "\b": "\\b", "\f": "\\f", "\v": "\\v"}


def to_modelica(expr: Any, name: Callable[[sp.Symbol], str] = lambda symbol: symbol.name) -> str:
    """Modelica text of an acausal expression, with minimal parentheses.

    Parameters
    ----------
    expr : sympy expression or Boolean, Array, number, str, bool or enumeration value
        What :func:`to_sympy` makes, and what acausal's equations hold.
    name : callable, optional
        The Modelica name of a symbol (the writer quotes or maps names);
        ``symbol.name`` by default.  ``time`` is always written ``time``.

    Returns
    -------
    str
        The expression; reading it back (pymoca, then :func:`to_sympy`) gives
        an equal expression.  Floats are written with ``repr`` (the shortest
        text that reads back to the same double), Rationals as ``p/q``,
        ``sympy.pi`` as ``Modelica.Constants.pi``, a 1-D array as ``{a, b}``
        and a matrix as ``[a, b; c, d]``.

    Raises
    ------
    ModelicaError
        For a node Modelica cannot express (an unknown function, infinity,
        a Piecewise without an otherwise-branch, a number beyond a double),
        naming it.
    """
    return _Writer(name).text(expr, _IF)


class _Writer:
    """Modelica text of sympy expressions, each with its precedence level."""

    def __init__(self, name: Callable[[sp.Symbol], str]) -> None:
        self.name = name

    def text(self, expr: Any, level: int) -> str:
        """The text of ``expr``, parenthesised if its operator binds less than ``level`` needs."""
        body, own = self.write(expr)
        return f"({body})" if own < level else body

    def write(self, expr: Any) -> tuple[str, int]:
        if isinstance(expr, str):
            return '"' + "".join(_ESCAPED.get(c, c) for c in expr) + '"', _PRIMARY
        if isinstance(expr, (bool, np.bool_)):
            return ("true" if expr else "false"), _PRIMARY
        if isinstance(expr, enum.Enum):
            return f"{type(expr).__name__}.{expr.name}", _PRIMARY
        if isinstance(expr, (Array, list, tuple, np.ndarray, sp.MatrixBase)):
            return self._array(Array(expr).data), _PRIMARY
        if isinstance(expr, (int, float, np.number)):
            expr = sp.sympify(expr)
        if not isinstance(expr, sp.Basic):
            raise ModelicaError(f"cannot write {type(expr).__name__} {expr!r} as Modelica")
        return self._basic(expr)

    def _basic(self, expr: sp.Basic) -> tuple[str, int]:
        if expr is sp.true or expr is sp.false:
            return ("true" if expr is sp.true else "false"), _PRIMARY
        if expr.is_Number:
            return self._number(expr)
        if expr is sp.pi:
            return "Modelica.Constants.pi", _PRIMARY
        if expr is sp.E:
            return "exp(1)", _PRIMARY
        if isinstance(expr, sp.Symbol):
            return ("time" if expr == time else self.name(expr)), _PRIMARY
        if isinstance(expr, sp.Add):
            return self._sum(expr)
        if isinstance(expr, sp.Mul):
            return self._product(expr)
        if isinstance(expr, sp.Pow):
            return self._power(expr)
        if isinstance(expr, sp.Piecewise):
            return self._if(expr)
        if isinstance(expr, (sp.And, sp.Or)):
            return self._logical(expr)
        if isinstance(expr, sp.Not):
            return f"not {self.text(expr.args[0], _REL)}", _NOT
        if isinstance(expr, sp.Xor):
            return self._xor(expr)
        if isinstance(expr, sp.Equivalent) and len(expr.args) == 2:
            return f"{self.text(expr.args[0], _ADD)} == {self.text(expr.args[1], _ADD)}", _REL
        if isinstance(expr, sp.ITE):
            return self._if(expr)
        if type(expr) in _RELATION_TEXT:
            return self._relation(expr)
        if isinstance(expr, (sp.Min, sp.Max)):
            return self._extremum(expr)
        function = _FUNCTION_NAMES.get(type(expr))
        if function is not None:
            return self._call(function, expr.args), _PRIMARY
        if isinstance(expr, AppliedUndef) and expr.func.__name__ in _OPERATOR_NAMES:
            return self._call(expr.func.__name__, expr.args), _PRIMARY
        raise ModelicaError(f"cannot write {type(expr).__name__} as Modelica: {expr}",
                            hint="Modelica text covers Modelica's operators and built-in functions")

    def _call(self, function: str, args: Sequence[Any]) -> str:
        return f"{function}({', '.join(self.text(a, _IF) for a in args)})"

    def _number(self, expr: sp.Number) -> tuple[str, int]:
        if expr.is_Rational and max(abs(expr.p), expr.q).bit_length() > 10_000:
            raise ModelicaError(f"an integer of {max(abs(expr.p), expr.q).bit_length()} bits in {type(expr).__name__}",
                                hint="write such a number as a Float")
        if expr.is_Integer:
            return str(int(expr)), (_ADD if expr < 0 else _PRIMARY)
        if expr.is_Rational:
            return f"{expr.p}/{expr.q}", (_ADD if expr < 0 else _MUL)
        if expr.is_Float:
            value = float(expr)
            if not math.isfinite(value) or (value == 0 and expr != 0):
                raise ModelicaError(f"the number {expr} is beyond the range of a double")
            return repr(value), (_ADD if value < 0 or repr(value).startswith("-") else _PRIMARY)
        raise ModelicaError(f"cannot write the number {expr} as Modelica",
                            hint="Modelica has finite Real numbers only")

    def _sum(self, expr: sp.Add) -> tuple[str, int]:
        pieces = []
        for k, term in enumerate(expr.as_ordered_terms()):
            if _is_negative(term):
                pieces.append((" - " if k else "-") + self.text(-term, _MUL))
            else:
                pieces.append((" + " if k else "") + self.text(term, _MUL))
        return "".join(pieces), _ADD

    def _product(self, expr: sp.Mul) -> tuple[str, int]:
        coefficient, rest = expr.as_coeff_Mul()
        negative = coefficient.is_negative
        if negative:
            coefficient = -coefficient
        factors = [f for f in sp.Mul.make_args(rest) if f is not sp.S.One]
        numerator: list[str] = []
        denominator: list[sp.Basic] = []
        inverse_log10 = sp.Pow(sp.log(10), -1)
        logs = [f for f in factors if isinstance(f, sp.log) and len(f.args) == 1]
        if inverse_log10 in factors and len(logs) == 1:  # log(u)/log(10): log10(u)
            factors = [f for f in factors if f is not logs[0] and f != inverse_log10]
            numerator.append(self._call("log10", logs[0].args))
        if coefficient.is_Rational and not coefficient.is_Integer:
            if coefficient.p != 1:
                numerator.insert(0, str(coefficient.p))
            denominator.append(sp.Integer(coefficient.q))
        elif coefficient is not sp.S.One:  # a Float 1.0 is kept: 1.0*x reads back as 1.0*x
            numerator.insert(0, self.text(coefficient, _MUL))
        for factor in factors:
            if isinstance(factor, sp.Pow) and _is_negative(factor.exp):
                denominator.append(sp.Pow(factor.base, -factor.exp))
            else:
                numerator.append(self.text(factor, _MUL if not numerator else _POW))
        text = "*".join(numerator) or "1"
        if denominator:
            if len(denominator) == 1:
                text += "/" + self.text(denominator[0], _POW)
            else:
                text += "/(" + "*".join(self.text(d, _MUL if k == 0 else _POW)
                                        for k, d in enumerate(denominator)) + ")"
        return ("-" + text, _ADD) if negative else (text, _MUL)

    def _power(self, expr: sp.Pow) -> tuple[str, int]:
        base, exponent = expr.base, expr.exp
        if _is_negative(exponent):
            return self._product(sp.Mul(1, expr, evaluate=False))
        if exponent is sp.S.Half:  # not a Float 0.5: x^0.5 stays x^0.5
            return self._call("sqrt", [base]), _PRIMARY
        if base is sp.E:
            return self._call("exp", [exponent]), _PRIMARY
        return f"{self.text(base, _PRIMARY)}^{self.text(exponent, _PRIMARY)}", _POW

    def _relation(self, expr: sp.core.relational.Relational) -> tuple[str, int]:
        lhs, rhs = expr.args
        if isinstance(expr, sp.Unequality) and _is_pre_of(rhs, lhs):
            return self._call("change", [lhs]), _PRIMARY
        return f"{self.text(lhs, _ADD)} {_RELATION_TEXT[type(expr)]} {self.text(rhs, _ADD)}", _REL

    def _logical(self, expr: sp.Basic) -> tuple[str, int]:
        if isinstance(expr, sp.And) and len(expr.args) == 2:
            for b, other in (expr.args, expr.args[::-1]):
                if isinstance(other, sp.Not) and _is_pre_of(other.args[0], b):
                    return self._call("edge", [b]), _PRIMARY  # b and not pre(b)
        word, level = (" and ", _AND) if isinstance(expr, sp.And) else (" or ", _OR)
        return word.join(self.text(a, level + 1) for a in expr.args), level

    def _xor(self, expr: sp.Xor) -> tuple[str, int]:
        """``a <> b`` of Booleans, ``change(v)`` for ``v`` against ``pre(v)``; several
        operands as ``(a <> b) <> c`` (relations do not associate)."""
        args = list(expr.args)
        items: list[tuple[str, int]] = []
        for v in list(args):
            partner = next((other for other in args if _is_pre_of(other, v)), None)
            if partner is not None and v in args:
                args.remove(v)
                args.remove(partner)
                items.append((self._call("change", [v]), _PRIMARY))
        items += [self.write(a) for a in args]
        text, level = items[0]
        for other, other_level in items[1:]:
            left = text if level >= _ADD else f"({text})"
            right = other if other_level >= _ADD else f"({other})"
            text, level = f"{left} <> {right}", _REL
        return text, level

    def _extremum(self, expr: sp.Basic) -> tuple[str, int]:
        function = "min" if isinstance(expr, sp.Min) else "max"
        args = list(expr.args)
        text = self.text(args[-1], _IF)
        for arg in reversed(args[:-1]):  # Modelica's min/max of scalars take two arguments
            text = f"{function}({self.text(arg, _IF)}, {text})"
        return text, _PRIMARY

    def _if(self, expr: sp.Basic) -> tuple[str, int]:
        """A Piecewise or an ITE (sympy's Boolean if) as ``if ... elseif ... else ...``."""
        pairs = _branches(expr)
        while pairs[-1][1] is sp.true and isinstance(pairs[-1][0], (sp.Piecewise, sp.ITE)):
            pairs = pairs[:-1] + _branches(pairs[-1][0])  # else if ...: elseif
        if pairs[-1][1] is not sp.true:
            raise ModelicaError(f"cannot write a Piecewise without an otherwise-branch: {expr}",
                                hint="Modelica's if-expression needs an else-branch; end the "
                                     "Piecewise with (value, True)")
        if len(pairs) == 1:
            return self.write(pairs[0][0])
        parts = []
        for k, (value, condition) in enumerate(pairs[:-1]):
            parts.append(f"{'if' if k == 0 else 'elseif'} {self.text(condition, _OR)} "
                         f"then {self.text(value, _OR)}")
        parts.append(f"else {self.text(pairs[-1][0], _OR)}")
        return " ".join(parts), _IF

    def _array(self, data: np.ndarray) -> str:
        if data.size == 0:
            return f"zeros({', '.join(str(n) for n in data.shape)})"
        if data.ndim == 0:
            return self.text(data[()], _IF)
        if data.ndim == 2:
            return "[" + "; ".join(", ".join(self.text(v, _IF) for v in row) for row in data) + "]"
        if data.ndim == 1:
            return "{" + ", ".join(self.text(v, _IF) for v in data) + "}"
        return "{" + ", ".join(self._array(part) for part in data) + "}"


def _branches(expr: sp.Basic) -> list[tuple[Any, Any]]:
    """The (value, condition) pairs of a Piecewise, or of an ITE (the last condition True)."""
    if isinstance(expr, sp.ITE):
        condition, then, otherwise = expr.args
        return [(then, condition), (otherwise, sp.true)]
    return [(pair.expr, pair.cond) for pair in expr.args]


def _is_negative(expr: Any) -> bool:
    """Whether ``expr`` is written with a leading minus: a negative number or coefficient."""
    if not isinstance(expr, sp.Basic):
        return False
    if expr.is_Number:
        return bool(expr.is_negative)
    if isinstance(expr, sp.Mul):
        coefficient = expr.args[0]
        return coefficient.is_Number and bool(coefficient.is_negative)
    return False


def _is_pre_of(candidate: Any, variable: Any) -> bool:
    """Whether ``candidate`` is ``pre(variable)``."""
    return isinstance(candidate, AppliedUndef) and candidate.func.__name__ == "pre" \
        and candidate.args == (variable,)


# =====================================================================================
# Repairs of pymoca's parser
# =====================================================================================


def repair_parser() -> None:
    """Correct pymoca's parser where it loses what an expression says (idempotent).

    pymoca 0.12 builds its tree so that, silently:

    * ``a:s:b`` has the step as ``stop`` and the stop as ``step`` (``1:2:5``
      would be 1:5:2);
    * named arguments of function calls are dropped
      (``Modelica.Math.atan2(u1=y, u2=x)`` becomes ``atan2()``);
    * iterators are dropped (``sum(x[i] for i in 1:n)`` becomes
      ``sum(x[i])``, ``{i for i in 1:3}`` becomes ``{i}``);
    * ``[1, 2]`` (a 1 x 2 matrix) becomes ``{1, 2}`` (a vector) and
      ``[A, B]`` does not concatenate;
    * the condition of a conditional declaration (``Real x if useX;``,
      MLS 4.4.5) is dropped;
    * a declaration's annotation (``annotation(Evaluate=true)``, MLS 18.3)
      is dropped.

    After the repair a range has ``start``, ``step`` and ``stop`` in place;
    a named argument is ``Expression(operator="=", operands=[Primary(name),
    value])`` among the call's operands; an expression with iterators is
    ``Expression(operator="for", operands=[expression, ForIndex, ...])``
    (the array constructor itself, or the one operand of a reduction); and
    ``[...]`` is ``Expression(operator="[]", operands=[Array(row), ...])``;
    a declaration's condition is the expression ``symbol.condition`` (None
    without one), its annotation the class modification ``symbol.annotation``
    (None without one).  :func:`to_sympy` reads all of them.  pymoca's own node classes are used,
    so trees stay picklable without acausal.  The parse cache of pymoca may
    hold trees made before the repair: parse with ``bypass_cache=True``.
    """
    if _parser is None:  # pragma: no cover
        return
    listener = _parser.ASTListener
    if getattr(listener, "_acausal_repaired", False):
        return

    plain_simple_expression = listener.exitSimple_expression
    plain_call_operands = listener._function_call_operands
    plain_array_arguments = listener.exitPrimary_function_arguments
    plain_expression_list = listener.exitPrimary_expression_list
    plain_declarations = (listener.exitComponent_declaration, listener.exitComponent_declaration1)

    def exit_simple_expression(self, ctx) -> None:
        plain_simple_expression(self, ctx)
        parts = ctx.expr()
        if len(parts) == 3:  # start : step : stop (MLS 3.6.4)
            self.ast[ctx] = _ast.Slice(start=self.ast[parts[0]], step=self.ast[parts[1]],
                                       stop=self.ast[parts[2]])

    def function_call_operands(self, ctx):
        operands = plain_call_operands(self, ctx)
        arguments = ctx.function_arguments()
        if arguments is None:
            return operands
        if arguments.for_indices():
            operands = [_iterated(self, arguments)]
        named = arguments.named_arguments()
        if named is not None:
            operands = operands + [
                _ast.Expression(operator=_NAMED, operands=[
                    _ast.Primary(value=argument.IDENT().getText()),
                    self._function_argument_ast(argument.function_argument())])
                for argument in named.named_argument()]
        return operands

    def exit_array_arguments(self, ctx) -> None:
        plain_array_arguments(self, ctx)
        arguments = ctx.function_arguments()
        if arguments.for_indices():
            self.ast[ctx] = _iterated(self, arguments)

    def exit_expression_list(self, ctx) -> None:
        plain_expression_list(self, ctx)
        rows = [_ast.Array(values=[self.ast[x] for x in row.expression()]) for row in ctx.expression_list()]
        self.ast[ctx] = _ast.Expression(operator=_CONCATENATE, operands=rows)

    def declaration_annotation(self, ctx) -> Any:
        comment = ctx.comment()
        annotation = comment.annotation() if comment is not None else None
        return self.ast.get(annotation) if annotation is not None else None

    def exit_component_declaration(self, ctx) -> None:
        symbol = self.ast[ctx]
        plain_declarations[0](self, ctx)
        condition = ctx.condition_attribute()
        symbol.condition = self.ast[condition.expression()] if condition is not None else None
        symbol.annotation = declaration_annotation(self, ctx)

    def exit_component_declaration1(self, ctx) -> None:  # in a modification: never conditional
        symbol = self.ast[ctx]
        plain_declarations[1](self, ctx)
        symbol.condition = None
        symbol.annotation = declaration_annotation(self, ctx)

    listener.exitComponent_declaration = exit_component_declaration
    listener.exitComponent_declaration1 = exit_component_declaration1
    listener.exitSimple_expression = exit_simple_expression
    listener._function_call_operands = function_call_operands
    listener.exitPrimary_function_arguments = exit_array_arguments
    listener.exitPrimary_expression_list = exit_expression_list
    listener._acausal_repaired = True


def _iterated(listener: Any, arguments: Any) -> Any:
    """``expression for i in r, j in s`` as an Expression node of its own."""
    expression = listener.ast[arguments.function_argument(0).expression()]
    indices = [index for group in arguments.for_indices() for index in listener.ast[group]]
    return _ast.Expression(operator=_ITERATE, operands=[expression, *indices])


repair_parser()
