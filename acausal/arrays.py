"""Arrays in the language: Modelica's vectors and matrices, scalarised where they are declared.

A component declares an array with a shape (``Variable(shape=3)``,
``RealInput(3)``, ``Parameter([[0, 1], [-1, 0]])``, ``Flange_a(shape="n")``)
or holds a list of components (``self.cell = [HeatCapacitor(C=1) for _ in
range(n)]``).  Every element is an ordinary scalar declaration named as
Modelica names it (``u[1]``, ``A[1,2]``, ``cell[3].T``), so the engine after
the language sees scalars only: Modelica's semantics, with the stages
unchanged.  What this module adds is the view the model writer works with:

* :class:`Array` — the elements of an array as one value: Modelica's
  1-based indexing (``x[1]``, ``A[1, 2]``; a slice ``x[2:3]`` includes both
  ends, as in Modelica), elementwise arithmetic, ``A @ x`` for the matrix
  product (Modelica writes ``A*x``), ``len``, iteration, ``shape``.
* Equations on arrays: ``Eq(der(x), A @ x + B @ u)`` is one equation per
  element (:func:`~acausal.language.Eq` expands it); sizes are checked and
  a mismatch names both sizes.
* The array functions of Modelica (chapter 10.3): :func:`size`,
  :func:`fill`, :func:`zeros`, :func:`ones`, :func:`sum`, :func:`product`,
  :func:`cat`, :func:`transpose`, :func:`min`, :func:`max`,
  :func:`scalar`, :func:`vector`, :func:`identity`.
* :func:`each`: a modifier value given to every element as it is
  (Modelica's ``each``), for a value that is itself an array or to say so.

References
----------
Modelica Language Specification 3.6, chapter 10 (Arrays): declarations,
indexing and slicing (10.5), array equations and operators (10.6), the
reduction and construction functions (10.3).
"""

from __future__ import annotations

import builtins
import itertools
import re
from typing import Any, Iterable, Iterator, Sequence

import numpy as np
import sympy as sp

from .errors import ArrayIndexError, ArraySizeError

__all__ = ["Array", "each", "Each", "array_groups", "size", "fill", "zeros", "ones", "sum", "product", "cat", "transpose",
           "min", "max", "scalar", "vector", "identity", "element_name", "element_names", "indices",
           "as_array", "is_array_value"]


# -- names ----------------------------------------------------------------------------------


def element_name(name: str, index: Sequence[int]) -> str:
    """Modelica's name of an element: ``u[2]``, ``A[1,2]`` (indices from 1)."""
    return f"{name}[{','.join(str(i) for i in index)}]"


def indices(shape: Sequence[int]) -> Iterator[tuple[int, ...]]:
    """Every index of ``shape``, 1-based, in Modelica's (row-major) order."""
    return itertools.product(*(range(1, n + 1) for n in shape))


def element_names(name: str, shape: Sequence[int]) -> list[str]:
    """The names of every element of the array ``name`` of ``shape``, in order."""
    return [element_name(name, index) for index in indices(shape)]


_ELEMENT = re.compile(r"^(?P<array>.+)\[(?P<index>\d+(?:,\d+)*)\]$")


def array_groups(names: Iterable[str]) -> list[tuple[str, tuple[int, ...] | None, list[str]]]:
    """``names`` with the elements of each array brought together, in order of first appearance.

    Returns ``(name, shape, members)``: for a scalar ``(name, None, [name])``;
    for the elements of an array ``x[1]`` ... ``x[n]`` (or ``A[i,j]``) that are
    all present and alone in their array, ``("x", (n,), [names in index order])``.
    What shows results, the explain page and the flat model uses it to show an
    array as one entry with its size.
    """
    names = list(names)
    found: dict[str, dict[tuple[int, ...], str]] = {}
    for name in names:
        match = _ELEMENT.match(name)
        if match:
            index = tuple(int(i) for i in match.group("index").split(","))
            found.setdefault(match.group("array"), {})[index] = name
    complete: dict[str, tuple[tuple[int, ...], list[str]]] = {}
    for array, members in found.items():
        rank = {len(index) for index in members}
        if len(rank) != 1 or array in names:
            continue
        shape = tuple(builtins.max(index[k] for index in members) for k in range(rank.pop()))
        if len(members) == int(np.prod(shape)):
            complete[array] = (shape, [members[index] for index in indices(shape)])
    out: list[tuple[str, tuple[int, ...] | None, list[str]]] = []
    done: set[str] = set()
    for name in names:
        match = _ELEMENT.match(name)
        array = match.group("array") if match else None
        if array in complete:
            if array not in done:
                done.add(array)
                out.append((array, complete[array][0], complete[array][1]))
        else:
            out.append((name, None, [name]))
    return out


# -- each -----------------------------------------------------------------------------------


class Each:
    """A modifier value every element of an array gets as it is (see :func:`each`)."""

    __slots__ = ("value",)

    def __init__(self, value: Any) -> None:
        self.value = value

    def __repr__(self) -> str:
        return f"each({self.value!r})"

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Each) and np.array_equal(np.asarray(self.value, dtype=object),
                                                          np.asarray(other.value, dtype=object))

    def __hash__(self) -> int:
        return hash(repr(self))


def each(value: Any) -> Each:
    """Modelica's ``each``: give ``value`` to every element of an array.

    ``Sine(f=each(2))`` on an array of components, or
    ``x=dict(start=each(0))`` on an array variable.  A plain number is given
    to every element too; ``each`` is needed for a value that is itself a
    list (a table given to every element of an array of components).
    """
    return Each(value)


def is_array_value(value: Any) -> bool:
    """Whether a modifier or parameter value is an array (a list, tuple, ndarray or :class:`Array`)."""
    return isinstance(value, (list, tuple, np.ndarray, Array))


def distribute(value: Any, shape: tuple[int, ...], what: str) -> list[Any]:
    """``value`` for each element of ``shape`` (row-major): an :class:`Each` or a scalar for
    all, an array of that shape element by element.

    Raises
    ------
    ArraySizeError
        For an array of another shape, naming both shapes.
    """
    count = int(np.prod(shape)) if shape else 1
    if isinstance(value, Each):
        return [value.value] * count
    if not is_array_value(value):
        return [value] * count
    data = value.data if isinstance(value, Array) else np.asarray(value, dtype=object)
    if tuple(data.shape) != tuple(shape):
        raise ArraySizeError(f"{what} has size {_shape_text(shape)}, the value given has size "
                             f"{_shape_text(data.shape)}",
                             hint="give one value per element, or each(value) for a value every "
                                  "element takes")
    return list(data.reshape(-1))


def _shape_text(shape: Sequence[int]) -> str:
    return "[" + ", ".join(str(n) for n in shape) + "]"


# -- the array value ------------------------------------------------------------------------


class Array:
    """The elements of a Modelica array as one value (symbols or expressions).

    Indexing is Modelica's: from 1, ``a[i, j]`` for a matrix, and a slice
    ``a[i:j]`` includes both ends (``a[2:3]`` is the 2nd and 3rd elements);
    ``a[:, 1]`` is the first column.  Arithmetic is elementwise and
    broadcasts a scalar; ``A @ x`` is the matrix product.  ``len(a)`` and
    iteration go along the first dimension; ``a.shape``, ``a.size``,
    ``a.flat`` (the elements in order) and ``a.tolist()`` are as in numpy.

    Parameters
    ----------
    elements : array_like
        Nested sequences or a numpy array of sympy expressions or numbers.
    name : str, optional
        The array's name (messages say which array an index is out of).
    """

    __array_priority__ = 100  # numpy defers to Array's operators
    __slots__ = ("data", "name")

    def __init__(self, elements: Any, name: str = "") -> None:
        if isinstance(elements, Array):
            data = elements.data
        elif isinstance(elements, sp.MatrixBase):
            data = np.array(elements.tolist(), dtype=object)
            if elements.shape[1] == 1:
                data = data.reshape(-1)
        else:
            data = np.empty(np.shape(np.asarray(elements, dtype=object)), dtype=object)
            data[...] = np.asarray(elements, dtype=object)
        self.data = data
        self.name = name

    # -- shape --------------------------------------------------------------------------
    @property
    def shape(self) -> tuple[int, ...]:
        return tuple(self.data.shape)

    @property
    def ndim(self) -> int:
        return self.data.ndim

    @property
    def size(self) -> int:
        return int(self.data.size)

    @property
    def flat(self) -> list:
        """The elements in Modelica's (row-major) order."""
        return list(self.data.reshape(-1))

    def tolist(self) -> list:
        return self.data.tolist()

    def __len__(self) -> int:
        if self.data.ndim == 0:
            raise TypeError("a scalar has no length")
        return self.data.shape[0]

    def __iter__(self) -> Iterator[Any]:
        for item in self.data:
            yield Array(item, self.name) if isinstance(item, np.ndarray) else item

    # -- indexing -----------------------------------------------------------------------
    def __getitem__(self, key: Any) -> Any:
        keys = key if isinstance(key, tuple) else (key,)
        if len(keys) > self.data.ndim:
            raise ArrayIndexError(f"{self._named()} has {self.data.ndim} dimension"
                                  f"{'s' if self.data.ndim != 1 else ''}, indexed with {len(keys)}",
                                  hint=f"its size is {_shape_text(self.shape)}")
        converted = tuple(self._zero_based(k, dim) for dim, k in enumerate(keys))
        picked = self.data[converted]
        return Array(picked, self.name) if isinstance(picked, np.ndarray) else picked

    def _zero_based(self, key: Any, dim: int):
        n = self.data.shape[dim]
        if isinstance(key, slice):
            if key.step not in (None, 1):
                step = key.step
                start = 1 if key.start is None else key.start
                stop = n if key.stop is None else key.stop
                for bound in (start, stop):
                    self._check(bound, n, dim)
                return list(range(start - 1, stop, step)) if step > 0 else list(range(start - 1, stop - 2, step))
            start = 1 if key.start is None else key.start
            stop = n if key.stop is None else key.stop
            if stop < start:
                self._check(start - 1 if start > n else start, n + 1, dim)  # the bounds still count from 1
                return slice(0, 0)  # Modelica's a:b with b < a is empty
            for bound in (start, stop):
                self._check(bound, n, dim)
            return slice(start - 1, stop)  # Modelica's a:b includes b
        if isinstance(key, (list, tuple, np.ndarray)):
            for k in key:
                self._check(k, n, dim)
            return [int(k) - 1 for k in key]
        self._check(key, n, dim)
        return int(key) - 1

    def _check(self, index: Any, n: int, dim: int) -> None:
        if isinstance(index, (bool, np.bool_)) or not isinstance(index, (int, np.integer)):
            raise ArrayIndexError(f"{self._named()}: index {index!r} is not an integer",
                                  hint="Modelica indices are integers from 1")
        if not 1 <= index <= n:
            where = f" in dimension {dim + 1}" if self.data.ndim > 1 else ""
            raise ArrayIndexError(f"{self._named()}: index {index} is out of range{where}; "
                                  f"the size is {_shape_text(self.shape)}",
                                  hint=f"Modelica indices count from 1 to {n}")

    def _named(self) -> str:
        return f"array {self.name}" if self.name else "the array"

    # -- arithmetic ---------------------------------------------------------------------
    def _binary(self, other: Any, operation, symbol: str) -> "Array":
        other_data = _data(other)
        if isinstance(other_data, np.ndarray) and other_data.ndim and self.data.ndim \
                and other_data.shape != self.data.shape:
            raise ArraySizeError(f"elementwise {symbol} of arrays of sizes {_shape_text(self.shape)} "
                                 f"and {_shape_text(other_data.shape)}",
                                 hint="elementwise operations need arrays of one size (A @ x is the "
                                      "matrix product)")
        return Array(operation(self.data, other_data))

    def __add__(self, other):
        return self._binary(other, lambda a, b: a + b, "+")

    def __radd__(self, other):
        return self._binary(other, lambda a, b: b + a, "+")

    def __sub__(self, other):
        return self._binary(other, lambda a, b: a - b, "-")

    def __rsub__(self, other):
        return self._binary(other, lambda a, b: b - a, "-")

    def __mul__(self, other):
        return self._binary(other, lambda a, b: a * b, "*")

    def __rmul__(self, other):
        return self._binary(other, lambda a, b: b * a, "*")

    def __truediv__(self, other):
        return self._binary(other, lambda a, b: a / b, "/")

    def __rtruediv__(self, other):
        return self._binary(other, lambda a, b: b / a, "/")

    def __pow__(self, other):
        return self._binary(other, lambda a, b: a ** b, "^")

    def __neg__(self):
        return Array(-self.data)

    def __pos__(self):
        return self

    def __matmul__(self, other):
        return _matmul(self.data, _data(other))

    def __rmatmul__(self, other):
        return _matmul(_data(other), self.data)

    def applyfunc(self, function) -> "Array":
        """``function`` applied to every element (``x.applyfunc(sympy.sin)``)."""
        out = np.empty(self.data.shape, dtype=object)
        for index in np.ndindex(self.data.shape):
            out[index] = function(self.data[index])
        return Array(out, self.name)

    def _sympy_(self) -> sp.ImmutableMatrix:
        # der(x) and pre(x) of an array: sympy keeps the matrix as the argument,
        # and Eq hands der/pre to every element (see as_array)
        data = self.data.reshape(-1, 1) if self.data.ndim == 1 else self.data
        return sp.ImmutableMatrix(data.tolist())

    def __array__(self, dtype=None, copy=None):
        return self.data if dtype is None else self.data.astype(dtype)

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Array):
            return NotImplemented
        return self.shape == other.shape and all(sp.sympify(a) == sp.sympify(b)
                                                 for a, b in zip(self.flat, other.flat))

    __hash__ = None  # type: ignore[assignment]  # mutable-looking, as numpy arrays

    def __repr__(self) -> str:
        label = f" {self.name}" if self.name else ""
        return f"<Array{label} {_shape_text(self.shape)}: {self.tolist()!r}>"


def _data(value: Any) -> Any:
    if isinstance(value, Array):
        return value.data
    if isinstance(value, sp.MatrixBase):
        return Array(value).data
    if isinstance(value, (list, tuple, np.ndarray)):
        return np.asarray(value, dtype=object)
    return value


def _matmul(a: Any, b: Any) -> Any:
    a, b = np.asarray(a, dtype=object), np.asarray(b, dtype=object)
    if a.ndim == 0 or b.ndim == 0:
        raise ArraySizeError("A @ x needs two arrays; a scalar multiplies with *")
    inner_a, inner_b = a.shape[-1], b.shape[0]
    if inner_a != inner_b:
        raise ArraySizeError(f"matrix product of sizes {_shape_text(a.shape)} and {_shape_text(b.shape)}: "
                             f"{inner_a} columns against {inner_b} rows",
                             hint="the columns of the left factor must match the rows of the right")
    product_ = np.empty(a.shape[:-1] + b.shape[1:], dtype=object)
    for left in np.ndindex(a.shape[:-1]):
        for right in np.ndindex(b.shape[1:]):
            product_[left + right] = sp.Add(*[a[left + (k,)] * b[(k,) + right] for k in range(inner_a)])
    return Array(product_) if product_.ndim else product_[()]


# -- array values of equations --------------------------------------------------------------


def as_array(value: Any) -> Array | None:
    """``value`` as an :class:`Array` when it is one, else None.

    An :class:`Array`, a list, tuple or numpy array, a sympy matrix, and
    ``der(x)`` or ``pre(x)`` of an array (sympy keeps the matrix as the
    argument: the function is applied to every element) are arrays.
    """
    if isinstance(value, Array):
        return value
    if isinstance(value, sp.MatrixBase):
        return Array(value)
    if isinstance(value, (list, tuple, np.ndarray)):
        return Array(np.asarray([v for v in _scalars(value)], dtype=object).reshape(np.shape(
            np.asarray(value, dtype=object)))) if np.asarray(value, dtype=object).ndim else None
    if isinstance(value, sp.Basic) and isinstance(value, sp.core.function.AppliedUndef) \
            and len(value.args) == 1 and isinstance(value.args[0], sp.MatrixBase):
        return Array(value.args[0]).applyfunc(value.func)
    if isinstance(value, sp.Basic) and value.has(sp.MatrixBase):
        raise ArraySizeError(f"{value} mixes an array (in der() or pre()) with other terms",
                             hint="write der(x) or pre(x) of an array alone on one side of the "
                                  "equation, or equations element by element")
    return None


def _scalars(value: Any) -> Iterator[Any]:
    for item in np.asarray(value, dtype=object).reshape(-1):
        yield item


def array_equations(lhs: Any, rhs: Any) -> list[sp.Equality] | None:
    """``lhs = rhs`` element by element when either side is an array (None: neither is).

    A scalar side is taken for every element of the other.

    Raises
    ------
    ArraySizeError
        For two arrays of different sizes, naming both.
    """
    left, right = as_array(lhs), as_array(rhs)
    if left is None and right is None:
        return None
    if left is not None and right is not None and left.shape != right.shape:
        raise ArraySizeError(f"array equation with sizes {_shape_text(left.shape)} and "
                             f"{_shape_text(right.shape)}: {_short(lhs)} = {_short(rhs)}",
                             hint="both sides of an array equation need the same size")
    shape = (left or right).shape
    lefts = left.flat if left is not None else [lhs] * int(np.prod(shape))
    rights = right.flat if right is not None else [rhs] * int(np.prod(shape))
    return [sp.Eq(sp.sympify(a), sp.sympify(b), evaluate=False) for a, b in zip(lefts, rights)]


def _short(value: Any, width: int = 60) -> str:
    text = str(value.tolist() if isinstance(value, Array) else value)
    return text if len(text) <= width else text[:width - 3] + "..."


# -- Modelica's array functions -------------------------------------------------------------


def size(a: Any, dimension: int | None = None):
    """Modelica's ``size(a)`` (the shape) or ``size(a, i)`` (the size of dimension ``i``, from 1)."""
    shape = Array(a).shape
    if dimension is None:
        return shape
    if not 1 <= dimension <= len(shape):
        raise ArrayIndexError(f"size(a, {dimension}) of an array with {len(shape)} dimensions",
                              hint="dimensions count from 1")
    return shape[dimension - 1]


def fill(value: Any, *shape: int) -> Array:
    """Modelica's ``fill(value, n1, n2, ...)``: an array of ``shape`` with every element ``value``."""
    data = np.empty(shape, dtype=object)
    for index in np.ndindex(*shape):
        data[index] = value
    return Array(data)


def zeros(*shape: int) -> Array:
    """Modelica's ``zeros(n1, n2, ...)``."""
    return fill(sp.Integer(0), *shape)


def ones(*shape: int) -> Array:
    """Modelica's ``ones(n1, n2, ...)``."""
    return fill(sp.Integer(1), *shape)


def identity(n: int) -> Array:
    """Modelica's ``identity(n)``: the n x n identity matrix."""
    data = np.empty((n, n), dtype=object)
    for i, j in np.ndindex(n, n):
        data[i, j] = sp.Integer(1 if i == j else 0)
    return Array(data)


def sum(a: Any) -> Any:  # noqa: A001 - Modelica's name
    """Modelica's ``sum(a)``: the sum of every element (0 for an empty array)."""
    return sp.Add(*Array(a).flat)


def product(a: Any) -> Any:
    """Modelica's ``product(a)``: the product of every element (1 for an empty array)."""
    return sp.Mul(*Array(a).flat)


def min(a: Any, *others: Any) -> Any:  # noqa: A001 - Modelica's name
    """Modelica's ``min(a)`` of an array's elements, or ``min(x, y)`` of scalars."""
    values = Array(a).flat if not others else [a, *others]
    if not values:
        raise ArraySizeError("min() of an empty array")
    return sp.Min(*values) if builtins.any(isinstance(v, sp.Basic) for v in values) else builtins.min(values)


def max(a: Any, *others: Any) -> Any:  # noqa: A001 - Modelica's name
    """Modelica's ``max(a)`` of an array's elements, or ``max(x, y)`` of scalars."""
    values = Array(a).flat if not others else [a, *others]
    if not values:
        raise ArraySizeError("max() of an empty array")
    return sp.Max(*values) if builtins.any(isinstance(v, sp.Basic) for v in values) else builtins.max(values)


def transpose(a: Any) -> Array:
    """Modelica's ``transpose(A)`` of a matrix."""
    data = Array(a).data
    if data.ndim != 2:
        raise ArraySizeError(f"transpose() of an array of {data.ndim} dimensions", hint="a matrix has 2")
    return Array(data.T)


def cat(dimension: int, *arrays: Any) -> Array:
    """Modelica's ``cat(k, a, b, ...)``: the arrays joined along dimension ``k`` (from 1)."""
    datas = [Array(a).data for a in arrays]
    try:
        return Array(np.concatenate(datas, axis=dimension - 1))
    except (ValueError, np.exceptions.AxisError) as exc:
        raise ArraySizeError(f"cat({dimension}, ...) of arrays of sizes "
                             f"{', '.join(_shape_text(d.shape) for d in datas)}",
                             hint="all sizes but that of the joined dimension must agree") from exc


def scalar(a: Any) -> Any:
    """Modelica's ``scalar(a)``: the one element of an array of size 1 in every dimension."""
    flat = Array(a).flat
    if len(flat) != 1:
        raise ArraySizeError(f"scalar() of an array of {len(flat)} elements")
    return flat[0]


def vector(a: Any) -> Array:
    """Modelica's ``vector(a)``: the elements as a vector (at most one dimension larger than 1)."""
    array = Array(a)
    if builtins.sum(n > 1 for n in array.shape) > 1:
        raise ArraySizeError(f"vector() of an array of size {_shape_text(array.shape)}",
                             hint="at most one dimension may be larger than 1")
    return Array(array.flat)
