"""Modelica functions, evaluated while a model is read (MLS 3.6, chapter 12).

A model's modifiers may call a function that a package defines: MSL's
Translational ``Friction`` example gives its friction table as
``f_pos = Examples.Utilities.GenerateStribeckFrictionTable(F_prop=1, ...)``.
acausal evaluates such a call when it reads the model, on the values of its
arguments, by running the function's algorithm statement by statement.  The
model then holds the result (a number or an array), as a Modelica tool's
flattening would once it has evaluated the parameters.

What a function may hold:

* ``input`` declarations with defaults (a default may use the inputs before
  it), ``output`` and ``protected`` variables, scalars or arrays whose sizes
  the inputs give (``output Real table[nTable, 2]``); a record input
  (``brushParameters.V``) is given as a dict of its fields' values, each
  checked when the algorithm reads it;
* an ``algorithm`` of assignments ``:=`` to a variable, an element or a slice
  (``table[i, 1] := ...``) or to several outputs (``(a, b) := g(x)``),
  ``for``, ``while``, ``if``/``elseif``/``else``, ``break``, ``return`` and
  ``assert``;
* calls of Modelica's built-in functions, of Modelica.Math's elementary
  functions and of other Modelica functions.

Values follow Modelica's types: an Integer variable holds an exact integer,
a Real one a double (a sympy ``Float``), a Boolean ``true`` or ``false``.  A
function whose result depends on a value that is not known when the model is
read (a variable, or a parameter acausal keeps symbolic) cannot be evaluated:
the error says which condition or size needed the value.  ``external``
functions (C code) are not evaluated.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass
from typing import Any, Callable

import numpy as np
import sympy as sp

from ..arrays import Array
from ..errors import ModelicaError
from . import expressions

__all__ = ["FunctionScope", "call_function"]

#: How deep functions may call functions (a recursion that does not end is an error).
MAX_DEPTH = 64

#: How many iterations a while loop may take before it is taken for endless.
MAX_ITERATIONS = 10_000_000


@dataclass(frozen=True)
class FunctionScope:
    """What a function's body may use besides its own variables (the reader's lookup).

    Attributes
    ----------
    find : callable
        ``find(name, enclosing)`` -> ``(pymoca class, full name)``: the
        function ``name`` names inside the class ``enclosing`` (MLS 5.3).
    constant : callable
        ``constant(name, subscripts, enclosing)``: the value of any other
        name (a package constant, an enumeration literal).
    where : callable
        ``where(word)``: "file:line" of a word in the source, for messages.
    """

    find: Callable[[str, str], tuple[Any, str]]
    constant: Callable[[str, list, str], Any]
    where: Callable[[str], str]


class _Break(Exception):
    """``break``: leaves the innermost loop."""


class _Return(Exception):
    """``return``: leaves the function."""


def call_function(node: Any, full: str, positional: list, named: dict, scope: FunctionScope,
                  depth: int = 0) -> tuple:
    """Evaluate the Modelica function ``node`` on the given argument values.

    Parameters
    ----------
    node : pymoca.ast.Class
        The function's class (``type == "function"``).
    full : str
        Its full Modelica name (for messages and for the lookup of the names
        its body uses).
    positional, named : list, dict
        The argument values (sympy numbers, Booleans, strings or
        :class:`~acausal.arrays.Array`), positional then by name.
    scope : FunctionScope
        The lookup of names outside the function.
    depth : int, optional
        How many calls are already open (recursion guard).

    Returns
    -------
    tuple
        The outputs' values in the order of their declarations.

    Raises
    ------
    ModelicaError
        For an argument the function lacks or given twice, a missing input,
        an ``external`` function, a failing ``assert``, a value that is not
        known when the model is read, and a construct this evaluator does not
        support (the message names the function).
    """
    return _Call(node, full, scope, depth).run(positional, named)


class _Call:
    """One evaluation of a function: its variables and the statements that set them."""

    def __init__(self, node: Any, full: str, scope: FunctionScope, depth: int) -> None:
        if depth > MAX_DEPTH:
            raise ModelicaError(f"{full}: functions call each other more than {MAX_DEPTH} deep",
                                hint="a recursive function must end")
        if getattr(node, "type", "") != "function":
            raise ModelicaError(f"{scope.where(full.rpartition('.')[2])}: {full} is a {node.type}, "
                                "not a function", hint="only functions can be called in expressions")
        self.node, self.full, self.scope, self.depth = node, full, scope, depth
        self.enclosing = full.rpartition(".")[0]
        self.values: dict[str, Any] = {}
        self.types: dict[str, str] = {}
        declared = list(node.symbols.items())
        self.inputs = [name for name, s in declared if "input" in _prefixes(s)]
        self.outputs = [name for name, s in declared if "output" in _prefixes(s)]
        self.others = [name for name, s in declared if name not in self.inputs and name not in self.outputs]

    # -- the call ---------------------------------------------------------------------------
    def run(self, positional: list, named: dict) -> tuple:
        if getattr(self.node, "external", None) or _is_external(self.node):
            raise ModelicaError(f"{self.full} is an external function",
                                hint="acausal evaluates Modelica functions that have an algorithm")
        if len(positional) > len(self.inputs):
            raise ModelicaError(f"{self.full}() takes {len(self.inputs)} inputs, given {len(positional)}")
        given = dict(zip(self.inputs, positional))
        for name, value in named.items():
            if name not in self.inputs:
                raise ModelicaError(f"{self.full}() has no input {name}",
                                    hint=f"its inputs are {', '.join(self.inputs) or 'none'}")
            if name in given:
                raise ModelicaError(f"{self.full}(): input {name} given twice")
            given[name] = value
        for name in self.inputs:
            symbol = self.node.symbols[name]
            self.types[name] = _base_type(symbol)
            if name in given:
                self.values[name] = self._typed(name, given[name])
                continue
            default = _binding(symbol)
            if default is None:
                raise ModelicaError(f"{self.full}(): input {name} is not given and has no default",
                                    hint=f"call it with {name}=...")
            self.values[name] = self._typed(name, self._read(default, f"the default of {name}"))
        for name in [*self.outputs, *self.others]:
            symbol = self.node.symbols[name]
            self.types[name] = _base_type(symbol)
            binding = _binding(symbol)
            if binding is not None:
                self.values[name] = self._typed(name, self._read(binding, f"the binding of {name}"))
            else:
                shape = self._shape(symbol, name)
                self.values[name] = Array(np.full(shape, None, dtype=object), name) if shape else None
        try:
            self._statements(self.node.statements)
        except _Return:
            pass
        except _Break:
            raise ModelicaError(f"{self.full}: break outside a loop") from None
        result = []
        for name in self.outputs:
            value = self.values[name]
            if value is None or (isinstance(value, Array) and any(v is None for v in value.flat)):
                raise ModelicaError(f"{self.full}(): output {name} is not assigned",
                                    hint="every output needs a value when the algorithm ends")
            result.append(value)
        return tuple(result)

    # -- statements ----------------------------------------------------------------------------
    def _statements(self, statements: list) -> None:
        for statement in statements:
            kind = type(statement).__name__
            word = getattr(statement, "value", None)
            if word == "break":
                raise _Break
            if word == "return":
                raise _Return
            if kind == "AssignmentStatement":
                self._assignment(statement)
            elif kind == "ForStatement":
                self._for(statement)
            elif kind == "WhileStatement":
                self._while(statement)
            elif kind == "IfStatement":
                for condition, block in zip(statement.conditions, statement.blocks):
                    if self._condition(condition, "an if-statement"):
                        self._statements(block)
                        break
            else:
                raise ModelicaError(f"{self.full}: the statement {kind} is not supported in functions",
                                    hint="acausal evaluates assignments, for, while, if, break, return "
                                         "and assert")

    def _assignment(self, statement: Any) -> None:
        right = statement.right
        if not statement.left:  # a call alone: assert(...), or a function without outputs
            self._call_statement(right)
            return
        if len(statement.left) == 1:
            self._assign(statement.left[0], self._read(right, _target_text(statement.left[0])))
            return
        outputs = self._call_all(right)  # (a, b) := g(x)
        for target, value in zip(statement.left, outputs):
            if target is not None and _target_text(target):
                self._assign(target, value)

    def _call_statement(self, node: Any) -> None:
        name = _function_name(node)
        if name == "assert":
            positional, named = expressions.call_arguments(node.operands, "assert")
            arguments = dict(zip(("condition", "message", "level"), positional)) | named
            if not self._condition(arguments["condition"], "assert"):
                message = self._read(arguments.get("message"), "assert") if "message" in arguments else ""
                level = _ref_text(arguments.get("level")) if "level" in arguments else "error"
                if not level.endswith("warning"):
                    raise ModelicaError(f"{self.full}(): assertion failed: {message}",
                                        hint="the function's arguments violate its assert")
            return
        self._call_all(node)

    def _call_all(self, node: Any) -> tuple:
        """All the outputs of a call ``g(x)`` of a Modelica function."""
        name = _function_name(node)
        if name is None:
            raise ModelicaError(f"{self.full}: several outputs are assigned from something that is not "
                                "a function call")
        positional, named = expressions.call_arguments(node.operands, name)
        callee, callee_full = self.scope.find(name, self.enclosing)
        return call_function(callee, callee_full, [self._read(p, name) for p in positional],
                             {k: self._read(v, name) for k, v in named.items()}, self.scope, self.depth + 1)

    def _for(self, statement: Any) -> None:
        names = [index.name for index in statement.indices]
        ranges = [self._range(index.expression) for index in statement.indices]
        saved = {name: self.values.get(name, _UNSET) for name in names}
        try:
            for combination in itertools.product(*ranges):
                for name, value in zip(names, combination):
                    self.values[name] = value
                    self.types[name] = "Integer" if isinstance(value, sp.Integer) else "Real"
                try:
                    self._statements(statement.statements)
                except _Break:
                    break
        finally:
            for name, value in saved.items():
                if value is _UNSET:
                    self.values.pop(name, None)
                else:
                    self.values[name] = value

    def _while(self, statement: Any) -> None:
        for _ in range(MAX_ITERATIONS):
            if not self._condition(statement.condition, "a while-loop"):
                return
            try:
                self._statements(statement.statements)
            except _Break:
                return
        raise ModelicaError(f"{self.full}(): a while-loop did not end after {MAX_ITERATIONS} iterations")

    # -- values ------------------------------------------------------------------------------
    def _read(self, node: Any, what: str) -> Any:
        try:
            return expressions.to_sympy(node, self._resolve, self._call_first)
        except ModelicaError as exc:
            if exc.message.startswith(self.full):
                raise
            raise ModelicaError(f"{self.full}(), in {what}: {exc.message}", hint=exc.hint) from None

    def _resolve(self, name: str, subscripts: list) -> Any:
        head = name.split(".")[0]
        if head in self.values:
            value = self.values[head]
            if value is None:
                raise ModelicaError(f"{self.full}(): {head} is used before it is assigned")
            if isinstance(value, dict):  # a record: its field, typed when it is read
                for part in name.split(".")[1:]:
                    if not isinstance(value, dict) or part not in value:
                        raise ModelicaError(f"{self.full}(): {name}: no such field of the record {head}")
                    value = value[part]
                return self._scalar(name, value) if not isinstance(value, dict) else value
            if "." in name:
                raise ModelicaError(f"{self.full}(): {name}: a field of {head}, which is not a record")
            picks = subscripts[0] if subscripts else []
            if picks:
                return value[tuple(picks)] if len(picks) > 1 else value[picks[0]]
            return value
        return self.scope.constant(name, subscripts, self.enclosing)

    def _call_first(self, name: str, positional: list, named: dict) -> Any:
        """A call inside an expression: the function's first output (MLS 12.4.3)."""
        callee, callee_full = self.scope.find(name, self.enclosing)
        outputs = call_function(callee, callee_full, positional, named, self.scope, self.depth + 1)
        if not outputs:
            raise ModelicaError(f"{callee_full}() has no output, and is used in an expression")
        return outputs[0]

    def _condition(self, node: Any, what: str) -> bool:
        value = self._read(node, what)
        if value in (sp.true, True):
            return True
        if value in (sp.false, False):
            return False
        raise ModelicaError(f"{self.full}(): the condition of {what} is not known when the model is read "
                            f"({value})", hint="acausal evaluates functions on parameter values only")

    def _range(self, node: Any) -> list:
        value = self._read(node, "a for-loop")
        if isinstance(value, Array):
            return list(value.flat)
        if isinstance(value, (list, tuple)):
            return [sp.sympify(v) for v in value]
        raise ModelicaError(f"{self.full}(): a for-loop's range is not known when the model is read ({value})")

    def _shape(self, symbol: Any, name: str) -> tuple[int, ...]:
        dims = [d for group in (getattr(symbol, "dimensions", None) or [[None]]) for d in group]
        shape = []
        for dim in dims:
            if dim is None or (type(dim).__name__ == "Primary" and dim.value is None):
                continue
            if type(dim).__name__ == "Slice":  # [:]: the size comes with the first assignment
                return ()
            size = self._read(dim, f"the size of {name}")
            if not (isinstance(size, sp.Integer) or isinstance(size, int)):
                raise ModelicaError(f"{self.full}(): the size of {name} is not known when the model is "
                                    f"read ({size})")
            shape.append(int(size))
        return tuple(shape)

    def _assign(self, target: Any, value: Any) -> None:
        name = target.name
        if name not in self.values:
            raise ModelicaError(f"{self.full}(): {name} is not a variable of the function",
                                hint=f"its variables are {', '.join(sorted(self.values))}")
        if name in self.inputs:
            raise ModelicaError(f"{self.full}(): input {name} is assigned", hint="inputs are read-only")
        if target.child:
            raise ModelicaError(f"{self.full}(): {_target_text(target)}: records are not supported in functions")
        subscripts = [s for group in (target.indices or []) for s in group if s is not None]
        if not subscripts:
            self.values[name] = self._typed(name, value)
            return
        array = self.values[name]
        if not isinstance(array, Array):
            raise ModelicaError(f"{self.full}(): {name} is indexed but not an array")
        keys = tuple(self._subscript(s, f"a subscript of {name}") for s in subscripts)
        positions = tuple(array._zero_based(k, dim) for dim, k in enumerate(keys))
        picked = array.data[positions]
        if isinstance(picked, np.ndarray):
            values = value.data if isinstance(value, Array) else value
            typed = np.empty(picked.shape, dtype=object)
            typed[...] = values
            array.data[positions] = np.vectorize(lambda v: self._scalar(name, v), otypes=[object])(typed)
        else:
            array.data[positions] = self._scalar(name, value)

    def _subscript(self, node: Any, what: str) -> Any:
        if type(node).__name__ == "Slice":
            if getattr(node.start, "value", 0) is None and getattr(node.stop, "value", 0) is None:
                return slice(None)
            start, stop, step = (int(self._read(n, what)) for n in (node.start, node.stop, node.step))
            return slice(start, stop, None if step == 1 else step)
        value = self._read(node, what)
        if isinstance(value, sp.Integer):
            return int(value)
        raise ModelicaError(f"{self.full}(): {what} is not an Integer known when the model is read ({value})")

    def _typed(self, name: str, value: Any) -> Any:
        if isinstance(value, dict):  # a record input: its fields are typed when they are read
            return value
        if isinstance(value, Array):
            data = np.vectorize(lambda v: self._scalar(name, v), otypes=[object])(value.data) \
                if value.data.size else value.data.copy()
            return Array(data, name)
        if isinstance(value, list):
            return self._typed(name, Array(value, name))
        return self._scalar(name, value)

    def _scalar(self, name: str, value: Any) -> Any:
        """A value as the variable's type holds it: exact Integers, double Reals."""
        kind = self.types.get(name, "Real")
        if kind == "String" or isinstance(value, str):
            return value
        if kind == "Boolean" or value in (sp.true, sp.false):
            return value
        value = sp.sympify(value)
        if not value.is_number:
            raise ModelicaError(f"{self.full}(): {name} would hold {value}, which is not known when the "
                                "model is read", hint="acausal evaluates functions on parameter values only")
        if kind == "Integer":
            if not value.is_Integer:
                raise ModelicaError(f"{self.full}(): Integer {name} is given the Real value {value}",
                                    hint="use integer() or div() for an Integer result")
            return value
        return sp.Float(float(value))


_UNSET = object()


def _prefixes(symbol: Any) -> set[str]:
    return {word for prefix in (getattr(symbol, "prefixes", None) or ()) for word in ("input", "output")
            if word in prefix}


def _base_type(symbol: Any) -> str:
    """Integer, Boolean, String or Real (a type derived from Real, such as SI.Force, is Real)."""
    text = symbol.type if isinstance(symbol.type, str) else _ref_text(symbol.type)
    return text if text in ("Integer", "Boolean", "String") else "Real"


def _binding(symbol: Any) -> Any:
    """The expression bound in a declaration (``input Integer n = 100``), or None."""
    for argument in getattr(getattr(symbol, "class_modification", None), "arguments", None) or []:
        value = getattr(argument, "value", None)
        component = getattr(value, "component", None)
        if component is not None and getattr(component, "name", None) == "value":
            modifications = getattr(value, "modifications", None) or []
            if modifications:
                return modifications[-1]
    value = getattr(symbol, "value", None)
    if value is None or (type(value).__name__ == "Primary" and value.value is None):
        return None
    return value


def _is_external(node: Any) -> bool:
    return any(getattr(s, "value", None) == "external" for s in getattr(node, "statements", []) or [])


def _function_name(node: Any) -> str | None:
    operator = getattr(node, "operator", None)
    if operator is None or isinstance(operator, str):
        return None
    return _ref_text(operator)


def _ref_text(ref: Any) -> str:
    if ref is None:
        return ""
    if isinstance(ref, str):
        return ref
    parts = []
    while ref is not None:
        parts.append(ref.name)
        ref = ref.child[0] if getattr(ref, "child", None) else None
    return ".".join(parts)


def _target_text(target: Any) -> str:
    return _ref_text(target)
