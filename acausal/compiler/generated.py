"""What generated code calls, and loading it: the part of code generation a run needs.

The code :mod:`~acausal.compiler.codegen` prints calls a few helpers: the
guarded versions of the functions that overflow (:data:`FLOAT_FUNCTIONS`),
Newton's method for torn algebraic loops (:func:`newton_solve`) and the
dense linear solve (``_solve``).  :func:`load_make` executes a generated
source with them; :func:`vectorised` derives the numpy version of a
generated function from its text.  None of this needs sympy: a compiled
model loaded from its generated source (the persistent cache, a sweep's
bundle) runs with this module and numpy alone.
"""

from __future__ import annotations

import ast
import copy
import itertools
import math
import re
import weakref
from typing import Callable

import numpy as np

from ..errors import SolverError

__all__ = ["FLOAT_FUNCTIONS", "CompiledFunctions", "newton_solve", "load_functions", "load_make", "rows_function",
           "rows_function_of", "vectorised", "vectorised_of", "reset_warm_starts"]


# -- floating-point semantics for the functions that overflow --------------------------------------
#
# Python's ``math.exp(1000.0)`` and ``1e200 ** 2`` raise OverflowError where IEEE 754 arithmetic
# (and ``1e200 * 1e200``) gives an infinity.  The generated code calls these wrappers instead:
# the same ``math`` function, bit for bit, whenever it returns, and the infinity of the right
# sign when it overflows.  Other errors (``math.log(0.0)``, ``0.0 ** -1``) are left as they are.

def _exp(x):
    try:
        return math.exp(x)
    except OverflowError:
        return math.inf


def _expm1(x):
    try:
        return math.expm1(x)
    except OverflowError:
        return math.inf


def _sinh(x):
    try:
        return math.sinh(x)
    except OverflowError:
        return math.copysign(math.inf, x)


def _cosh(x):
    try:
        return math.cosh(x)
    except OverflowError:
        return math.inf


def _gamma(x):
    try:
        return math.gamma(x)
    except OverflowError:  # large x, or x next to zero (gamma ~ 1/x)
        return math.copysign(math.inf, x)


def _lgamma(x):
    try:
        return math.lgamma(x)
    except OverflowError:
        return math.inf


def _pow(a, b):
    """``a ** b``, an infinity where it overflows (negative for a negative base and an odd
    integer exponent, as IEEE's pow)."""
    try:
        return a ** b
    except OverflowError:
        b = float(b)
        return -math.inf if a < 0 and b.is_integer() and b % 2 == 1 else math.inf


#: The names the generated code calls for these functions -> their implementations (bound in
#: the namespace of every generated source).
FLOAT_FUNCTIONS = {"_exp": _exp, "_expm1": _expm1, "_sinh": _sinh, "_cosh": _cosh, "_gamma": _gamma,
                   "_lgamma": _lgamma, "_pow": _pow}


def newton_solve(residual: Callable, guess: np.ndarray, what: str, tol: float = 1e-10,
                 max_iter: int = 50, memo: dict | None = None) -> np.ndarray:
    """Newton's method with a finite-difference Jacobian and step halving.

    Converged where the residual is within ``tol`` of the unknowns' scale
    and so is the step the last Jacobian would take from there. ``memo``
    (one per torn block, kept by the generated code) holds the last
    Jacobian between calls, so that a guess whose residual is already small
    is judged by its step too: an integrator's finite-difference Jacobian
    perturbs a state by 1e-12 and must see the unknowns follow.

    A single unknown that Newton cannot bring to a root (a piecewise-linear
    residual whose branch through the guess has ended, as in an amplifier
    with positive feedback at its switching threshold) is found by bracketing
    instead: :func:`_bracketed_root`, the root nearest to the guess.
    """
    z = np.array(guess, dtype=float)
    r = np.asarray(residual(z), dtype=float)
    start = (z.copy(), r.copy())
    J = memo.get("J") if memo is not None else None
    if J is not None and J.shape != (z.size, z.size):
        J = None
    polished = 0
    for _ in range(max_iter):
        norm = np.max(np.abs(r)) if r.size else 0.0
        scale = 1.0 + np.max(np.abs(z), initial=0.0)
        if norm <= tol * scale:
            # A small residual is not yet a small error where the residual changes
            # little with the unknowns (a blocking semiconductor: 1 uS, so 1e-10 A is
            # 0.1 mV): the Newton step the last Jacobian gives must be small too. A few
            # more iterations at most: beyond them it is round-off of the residual.
            if J is None or norm == 0.0 or polished >= 3:
                return z
            try:
                estimate = np.linalg.solve(J, -r)
            except np.linalg.LinAlgError:
                return z
            if np.max(np.abs(estimate)) <= tol * scale:
                return z
            polished += 1
        n = z.size
        J = np.empty((n, n))
        for k in range(n):
            h = 1e-7 * max(1.0, abs(z[k]))
            dz = z.copy()
            dz[k] += h
            J[:, k] = (np.asarray(residual(dz), dtype=float) - r) / h
        if memo is not None:
            memo["J"] = J
        try:
            step = np.linalg.solve(J, -r)
        except np.linalg.LinAlgError as exc:
            raise SolverError(f"Newton iteration for {what}: singular Jacobian",
                              hint="the equations may not determine these unknowns here") from exc
        if np.max(np.abs(step)) <= max(1e-3 * tol * scale, 4.0 * np.spacing(np.max(np.abs(z)))):
            # a step a thousand times below the tolerance (or below the unknowns' round-off):
            # z is a root to working precision, and what is left of the residual is the
            # round-off of its terms (a conducting thyristor's 1e9 S times the ulp of its voltage)
            return z
        lam = 1.0
        for _ in range(30):
            trial = z + lam * step
            r_trial = np.asarray(residual(trial), dtype=float)
            if np.all(np.isfinite(r_trial)) and np.max(np.abs(r_trial)) < norm:
                break
            lam *= 0.5
        z, r = trial, r_trial
    if z.size == 1:
        root = _bracketed_root(residual, start[0], start[1], tol)
        if root is not None:
            return root
    raise SolverError(f"Newton iteration for {what} did not converge in {max_iter} iterations "
                      f"(residual {np.max(np.abs(r)):.3g})",
                      hint="check start values (they are the initial guesses) of the unknowns named")


def _bracketed_root(residual: Callable, z0: np.ndarray, r0: np.ndarray, tol: float) -> np.ndarray | None:
    """The root of a one-unknown ``residual`` nearest to ``z0``, or None.

    Steps of doubling length go out from ``z0`` in both directions, the same
    distance each way, until the residual changes sign between two points on
    one side; bisection then narrows that bracket to a point that meets
    Newton's tolerance (a sign change across a jump that is not a root is
    passed over). Slower than Newton, but certain for a continuous residual
    once a sign change is found.
    """
    x0 = float(z0[0])
    f0 = float(r0[0])
    if not math.isfinite(f0):
        return None
    scale = max(1.0, abs(x0))
    near = {+1: (x0, f0), -1: (x0, f0)}
    distance = 1e-6 * scale
    while distance <= 1e12 * scale:
        for direction in (+1, -1):
            a, fa = near[direction]
            b = x0 + direction * distance
            fb = float(residual(np.array([b]))[0])
            if not math.isfinite(fb):
                continue
            near[direction] = (b, fb)
            if fa == 0.0:
                return np.array([a])
            if (fa < 0.0) != (fb < 0.0):
                root = _bisect(residual, a, fa, b, fb, tol)
                if root is not None:
                    return np.array([root])
        distance *= 2.0
    return None


def _bisect(residual: Callable, a: float, fa: float, b: float, fb: float, tol: float) -> float | None:
    """A root in the bracket ``[a, b]`` (``fa``, ``fb`` of opposite signs) to Newton's
    tolerance, or None where the sign change is a jump."""
    for _ in range(200):
        m = 0.5 * (a + b)
        fm = float(residual(np.array([m]))[0])
        if abs(fm) <= tol * (1.0 + abs(m)):
            return m
        if m in (a, b) or not math.isfinite(fm):
            return None
        if (fm < 0.0) == (fa < 0.0):
            a, fa = m, fm
        else:
            b, fb = m, fm
    return None


def _linalg_error(what: str):
    return SolverError(f"singular linear system in {what}",
                       hint="the equations do not determine these unknowns at these values (in this "
                            "discrete state): a constraint may be imposed twice, e.g. a closed loop "
                            "of rigid connections, or two elements fix the same quantity")


def _dense_solve(A, b, what):
    try:
        return np.linalg.solve(A, b)
    except np.linalg.LinAlgError:
        raise _linalg_error(what) from None


def load_functions(source: str, count: int, name: str, functions: dict | None = None) -> list[Callable]:
    """The functions ``_f0`` ... ``_f<count-1>`` of a source made by
    :func:`~acausal.compiler.codegen.functions_source`, with the functions it calls."""
    namespace = {"math": math, "np": np, **FLOAT_FUNCTIONS, **(functions or {})}
    exec(compile(source, f"<acausal {name}>", "exec"), namespace)
    return [namespace[f"_f{k}"] for k in range(count)]


def load_make(source: str, functions: dict, name: str) -> Callable:
    """The ``make(p)`` factory of generated ``source`` (which names its system ``name``),
    with the table functions it calls (``functions``: name in the code -> implementation)."""
    namespace = {"math": math, "np": np, "_newton": newton_solve, "_linalg_error": _linalg_error,
                 "_solve": _dense_solve, **FLOAT_FUNCTIONS}
    namespace.update(functions)
    exec(compile(source, f"<acausal {name}>", "exec"), namespace)
    return namespace["make"]


# -- numpy versions of the generated functions ----------------------------------------------------

#: ``math`` functions that numpy computes with the same rounding for every argument (exact
#: or correctly rounded in both).  Every other function is called element by element.
_EXACT_NUMPY = {"copysign": "copysign", "fabs": "abs", "sqrt": "sqrt"}


class _NotVectorisable(Exception):
    """A construct :func:`vectorised` does not translate."""


def vectorised(function: Callable, source: str, rows: tuple[int, ...] | None = None) -> Callable | None:
    """A numpy version of the generated function ``function`` (``crossings`` or ``outputs``).

    ``f(t, X)`` takes ``m`` times and the states as the rows of ``X`` (``n x m``) and
    returns a ``k x m`` array whose column ``j`` equals, bit for bit, the tuple
    ``function(t[j], X[:, j])`` as floats.  It is derived from the function's own
    generated text (``source``, the system's :attr:`GeneratedCode.source`, which stays
    as it is) and bound to the same parameter values:

    * ``+ - * /``, comparisons, ``abs``, ``copysign``, ``sqrt`` are numpy's: these round
      the same on arrays as on scalars;
    * ``a if c else b`` is ``np.where(c, a, b)`` (both branches are evaluated), ``min``
      and ``max`` pick as Python's do;
    * every other function (``math.sin``, ``_exp``, powers, tables) is called element by
      element, on floats: numpy's own ``sin`` and ``**`` can differ from the C library's
      in the last bit.

    Where the scalar function raises, or gives a value that is not finite, ``f`` may
    raise or give a non-finite value: callers evaluate such columns with ``function``
    itself, and call ``f`` under ``np.errstate(divide="raise", invalid="raise")`` so
    that an operation Python's floats could refuse (``x / 0.0``) makes it raise too.
    None when the function holds a construct that is not translated (a Newton
    iteration, a linear system of three or more unknowns).

    With ``rows`` (positions in the returned tuple), ``f`` gives only those values, in
    that order, and computes only what they need (:func:`_live_statements`); it exists
    exactly when the whole function's numpy version does, and its rows equal that
    version's rows ``rows`` bit for bit.
    """
    name = function.__name__
    translated = _translated(source, name, function.__code__.co_filename, rows)
    if translated is None:
        return None
    code, constants = translated
    namespace = dict(function.__globals__)
    cells = function.__closure__ or ()
    namespace.update(zip(function.__code__.co_freevars, (cell.cell_contents for cell in cells)))
    namespace.update(_VECTOR_HELPERS)
    namespace.update(constants)
    exec(code, namespace)
    return namespace[f"{name}_many"]


def _translated(source: str, name: str, filename: str, rows: tuple[int, ...] | None):
    """:func:`_vector_code`'s answer, kept in ``_VECTOR_CODE``."""
    key = (source, name, rows)
    translated = _VECTOR_CODE.get(key, _MISSING)
    if translated is _MISSING:
        # the translation depends on the text only: other parameter values (a sweep,
        # a rebound translation) bind the same code to their own closure
        translated = remember(_VECTOR_CODE, key, _vector_code(source, name, filename, rows), _VECTOR_CODE_SIZE)
    return translated


def remember(memo: dict, key, value, limit: int):
    """``memo[key] = value``, the oldest entries dropped so that at most ``limit`` are kept
    (a dict keeps its insertion order); returns ``value``.  The bounded memos of generated
    functions and of the runtime's plans use it."""
    memo[key] = value
    excess = len(memo) - limit
    if excess > 0:
        # (from a snapshot of the keys, each dropped if still there: the threads of a sweep
        # share these memos, and another may add or drop entries meanwhile)
        for oldest in tuple(memo)[:excess]:
            memo.pop(oldest, None)
    return value


#: Translated numpy functions by (source, name, rows): a code object and the constants it
#: reads, or None where the function cannot be translated.  Bounded, oldest out first.
_VECTOR_CODE: dict = {}
_VECTOR_CODE_SIZE = 256
_MISSING = object()


#: generated function -> its numpy version (or False): made once per compiled function
_VECTORISED: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()

#: generated function -> {rows: its numpy version for those rows (or False)}
_VECTORISED_ROWS: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()

#: How many row selections of one function keep their numpy versions (the oldest goes
#: first): a run watches the relations of its few discrete states.
_ROWS_KEPT = 64


def vectorised_of(system, name: str, rows: tuple[int, ...] | None = None) -> Callable | None:
    """The numpy version (:func:`vectorised`) of ``system.<name>`` (``crossings``,
    ``outputs``) of a system compiled from its own :class:`GeneratedCode`, made once
    per function (and per ``rows``, the values it gives: all without); None where the
    code does not allow one."""
    function = getattr(system, name)
    try:
        if rows is None:
            found = _VECTORISED.get(function)
        else:
            kept = _VECTORISED_ROWS.get(function)
            found = None if kept is None else kept.get(rows)
    except TypeError:  # not weakly referable: not a generated function
        return None
    if found is None:
        code = getattr(system, "code", None)
        source = getattr(code, "source", None)
        found = (vectorised(function, source, rows) if isinstance(source, str) else None) or False
        try:
            if rows is None:
                _VECTORISED[function] = found
            else:
                remember(_VECTORISED_ROWS.setdefault(function, {}), rows, found, _ROWS_KEPT)
        except TypeError:
            pass
    return found or None


#: A line of a generated source indented as the functions ``make`` defines, or less
#: (where the function before it ends).
_OUTER_LINE = re.compile(r"^ {0,4}\S", re.MULTILINE)


def function_tree(source: str, name: str) -> ast.FunctionDef | None:
    """The syntax tree of the function ``name`` that ``make`` defines in a generated
    ``source``, with the line numbers it has there; None where there is none.

    Only the function's own lines are parsed: a large model's source holds three
    such functions of some megabytes each, and parsing the whole of it for one of
    them took seconds and a tree of all three.  (The lines before it become empty
    lines, so the numbers stay.)  Should its lines not parse on their own, the whole
    source is parsed.
    """
    header = source.find(f"\n    def {name}(")
    if header >= 0:
        line_end = source.find("\n", header + 1)
        outer = _OUTER_LINE.search(source, line_end + 1) if line_end >= 0 else None
        end = outer.start() if outer is not None else len(source)
        before = source.count("\n", 0, header)  # the lines before the function's header line
        text = "\n" * before + "def make(p):" + source[header:end]
        try:
            tree = ast.parse(text)
        except SyntaxError:
            tree = None
        found = _defined_in_make(tree, name)
        if found is not None:
            return found
    try:
        tree = ast.parse(source)
    except SyntaxError:
        return None
    return _defined_in_make(tree, name)


def _defined_in_make(tree: ast.Module | None, name: str) -> ast.FunctionDef | None:
    """The function ``name`` defined in the function ``make`` of ``tree``, or None."""
    make = None if tree is None else next(
        (node for node in tree.body if isinstance(node, ast.FunctionDef) and node.name == "make"), None)
    return None if make is None else next(
        (node for node in make.body if isinstance(node, ast.FunctionDef) and node.name == name), None)


def _vector_code(source: str, name: str, filename: str, rows: tuple[int, ...] | None = None):
    """The compiled module defining ``<name>_many`` and its constants, or None (see
    :func:`vectorised`); with ``rows``, returning those values only."""
    if rows is not None and _translated(source, name, filename, None) is None:
        # a function with a construct not translated has no numpy version for any rows
        # either (the constructs are not pruned, see _live_statements)
        return None
    found = function_tree(source, name)
    if found is None or not found.body or not isinstance(found.body[-1], ast.Return):
        return None
    if rows is not None:
        live = _live_statements(found.body, rows)
        if live is None:
            return None
        found.body = live
    varying = _varying_names(found.body)
    constants: dict = {}
    try:
        body = [_vector_statement(stmt, k, varying, constants) for k, stmt in enumerate(found.body)]
    except _NotVectorisable:
        return None
    module = ast.parse(f"def {name}_many(t, x):\n    pass\n")
    module.body[0].body = body
    ast.fix_missing_locations(module)
    return compile(module, filename.rstrip(">") + f" {name}_many>", "exec"), constants


# -- scalar versions of the generated functions that give some of their values ----------------------

def rows_function(function: Callable, source: str, rows: tuple[int, ...]) -> Callable | None:
    """A version of the generated function ``function`` (``crossings``) that gives only its
    values ``rows`` (positions in the returned tuple), in that order, and computes only the
    statements they need (:func:`_live_statements`).

    ``f(t, x)`` returns, bit for bit, ``tuple(function(t, x)[r] for r in rows)``: the kept
    statements are the function's own, taken from its generated text (``source``), in
    their order, and bound to the same values: the function's closure (its parameters,
    and the constants made with them) becomes the closure of ``f`` (read as the
    function reads it), its globals ``f``'s globals.  What ``f`` leaves out cannot raise
    in it: an exception (a singular solve's guard, ``math.log`` of a negative number) of
    a statement only the other values need is the whole function's alone.  None where
    the function's body is not straight-line code (a Newton iteration, which keeps a warm
    start between calls and so must run with every call; a dense linear solve).
    """
    name = function.__name__
    freevars = function.__code__.co_freevars
    code = _rows_code(source, name, function.__code__.co_filename, rows, freevars)
    if code is None:
        return None
    namespace = dict(function.__globals__)
    exec(code, namespace)
    cells = function.__closure__ or ()
    return namespace[f"_make_{name}_rows"](*(cell.cell_contents for cell in cells))


def _rows_code(source: str, name: str, filename: str, rows: tuple[int, ...], freevars: tuple[str, ...]):
    """The compiled module defining ``_make_<name>_rows(<freevars>)``, which returns the
    function of :func:`rows_function`; None where there is none.  Kept in ``_ROWS_CODE``
    (the code depends on the text only: other parameter values bind it to theirs, and
    systems of one text share it, the file name of the first among them, as
    :func:`vectorised`'s code)."""
    key = (source, name, rows, freevars)
    found = _ROWS_CODE.get(key, _MISSING)
    if found is not _MISSING:
        return found
    found = None
    function = function_tree(source, name)
    if function is not None and function.body and isinstance(function.body[-1], ast.Return):
        live = _live_statements(function.body, rows)
        if live is not None:
            # the values the function reads from its closure are the factory's arguments,
            # so that the new function reads them from its closure too (as fast, the same)
            module = ast.parse(f"def _make_{name}_rows({', '.join(freevars)}):\n"
                               f"    def {name}_rows(t, x):\n        pass\n    return {name}_rows\n")
            module.body[0].body[0].body = live
            ast.fix_missing_locations(module)
            found = compile(module, filename.rstrip(">") + f" {name}_rows>", "exec")
    return remember(_ROWS_CODE, key, found, _VECTOR_CODE_SIZE)


#: The code of :func:`rows_function` by (source, name, rows, closure names), or None where
#: there is none.  Bounded, oldest out first.
_ROWS_CODE: dict = {}

#: generated function -> {rows: its version for those rows (or False)}
_ROWS_FUNCTIONS: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()


def rows_function_of(system, name: str, rows: tuple[int, ...]) -> Callable | None:
    """:func:`rows_function` of ``system.<name>`` for a system compiled from its own
    :class:`GeneratedCode`, made once per function and ``rows`` (the last
    ``_ROWS_KEPT`` of them); None where the code does not allow one."""
    function = getattr(system, name)
    try:
        functions = _ROWS_FUNCTIONS.get(function)
    except TypeError:  # not weakly referable: not a generated function
        return None
    found = None if functions is None else functions.get(rows)
    if found is None:
        code = getattr(system, "code", None)
        source = getattr(code, "source", None)
        found = (rows_function(function, source, rows)
                 if isinstance(source, str) and hasattr(function, "__code__") else None) or False
        if functions is None:
            functions = _ROWS_FUNCTIONS[function] = {}
        remember(functions, rows, found, _ROWS_KEPT)
    return found or None


def _live_statements(body: list, rows: tuple[int, ...]) -> list | None:
    """The statements of a generated function's straight-line ``body`` that the values
    ``rows`` of its returned tuple need, and a return of those values; None where the
    body is not of the forms :func:`_vector_statement` translates.

    Backward liveness: from the returned values, a statement is kept if a kept
    statement after it or the returned values read what it assigns (names may be
    assigned again: the temporaries of a linear solve, ``_a``, ``_det``).  The kept
    statements are the original ones, so their values are computed as in the whole
    function, bit for bit.

    A guard ``if <test>: raise`` (a singular linear solve) is kept if its test reads
    a name that a kept statement after it reads: it guards values the rows need,
    where the scalar function raises (and the numpy version raises too, sending the
    instants to the scalar function).  A guard of a solve whose values no kept
    statement reads guards nothing the rows need, and goes with the solve.
    """
    returned = body[-1].value
    if not isinstance(returned, ast.Tuple) or any(not 0 <= r < len(returned.elts) for r in rows):
        return None
    items = [copy.deepcopy(returned.elts[r]) for r in rows]  # (a row asked twice: two nodes)
    live = set().union(*(_reads(item) for item in items))
    kept = []
    for position in range(len(body) - 2, -1, -1):
        stmt = body[position]
        if isinstance(stmt, ast.Assign) and len(stmt.targets) == 1 and isinstance(stmt.targets[0], ast.Name):
            target = stmt.targets[0].id
            if target not in live:
                continue
            live.discard(target)
            live |= _reads(stmt.value)
        elif isinstance(stmt, ast.Assign) and position == 0:
            pass  # the states, ``a, b, = x``: kept (they read ``x`` only)
        elif (isinstance(stmt, ast.If) and not stmt.orelse and len(stmt.body) == 1
              and isinstance(stmt.body[0], ast.Raise)):
            reads = _reads(stmt.test)
            if not reads & live:
                continue
            live |= reads
        else:
            return None
        kept.append(stmt)
    kept.reverse()
    return [*kept, ast.Return(ast.Tuple(items, ast.Load()))]


def _reads(node) -> set[str]:
    """The names an expression reads."""
    return {n.id for n in ast.walk(node) if isinstance(n, ast.Name)}


def _varying_names(body) -> set[str]:
    """The names that vary from instant to instant: ``t``, the states, and what is
    computed from them (the others are parameters and constants)."""
    varying = {"t"}
    for stmt in body:
        if isinstance(stmt, ast.Assign):
            reads = {n.id for n in ast.walk(stmt.value) if isinstance(n, ast.Name)}
            if reads & varying or (isinstance(stmt.value, ast.Name) and stmt.value.id == "x"):
                for target in stmt.targets:
                    varying |= {n.id for n in ast.walk(target) if isinstance(n, ast.Name)}
    return varying


def _vector_statement(stmt, position: int, varying: set[str], constants: dict):
    """One statement of a generated function, for arrays (``constants``: names it binds)."""
    if isinstance(stmt, ast.Assign) and len(stmt.targets) == 1:
        target = stmt.targets[0]
        if isinstance(target, ast.Name):
            return ast.Assign([target], _VectorExpression().visit(stmt.value))
        # the states, ``a, b, = x``: the rows of X
        if (position == 0 and isinstance(target, ast.Tuple) and isinstance(stmt.value, ast.Name)
                and stmt.value.id == "x" and all(isinstance(e, ast.Name) for e in target.elts)):
            return stmt
        raise _NotVectorisable
    if (isinstance(stmt, ast.If) and not stmt.orelse and len(stmt.body) == 1
            and isinstance(stmt.body[0], ast.Raise)):
        # a singular system: raise if any column is singular (the caller then evaluates
        # column by column, and the scalar function raises where it does)
        return ast.If(_call("_v_any", _VectorExpression().visit(stmt.test)), stmt.body, [])
    if isinstance(stmt, ast.Return) and isinstance(stmt.value, ast.Tuple):
        # the values that vary fill their rows at once, the constants theirs
        items = [_VectorExpression().visit(e) for e in stmt.value.elts]
        moving = [any(isinstance(n, ast.Name) and n.id in varying for n in ast.walk(e))
                  for e in stmt.value.elts]
        rows = [[k for k, m in enumerate(moving) if m], [k for k, m in enumerate(moving) if not m]]
        constants["_v_varying_rows"] = np.array(rows[0], dtype=np.intp)
        constants["_v_constant_rows"] = np.array(rows[1], dtype=np.intp)
        return ast.Return(_call(
            "_v_rows", *[ast.Tuple([items[k] for k in r], ast.Load()) for r in rows],
            ast.Name("_v_varying_rows", ast.Load()), ast.Name("_v_constant_rows", ast.Load()),
            ast.Name("t", ast.Load())))
    raise _NotVectorisable


def _call(name, *args) -> ast.Call:
    func = ast.Name(name, ast.Load()) if isinstance(name, str) else name
    return ast.Call(func, list(args), [])


class _VectorExpression(ast.NodeTransformer):
    """Rewrites one generated expression for arrays (see :func:`vectorised`)."""

    _ALLOWED = (ast.Name, ast.Constant, ast.Load, ast.BinOp, ast.UnaryOp, ast.Compare, ast.IfExp,
                ast.Call, ast.Attribute, ast.BoolOp, ast.Add, ast.Sub, ast.Mult, ast.Div, ast.USub,
                ast.UAdd, ast.Not, ast.Eq, ast.NotEq, ast.Lt, ast.LtE, ast.Gt, ast.GtE, ast.And, ast.Or)

    def generic_visit(self, node):
        if not isinstance(node, self._ALLOWED):
            raise _NotVectorisable
        return super().generic_visit(node)

    def visit_Attribute(self, node):  # noqa: N802 - ast API
        # constants of math (math.pi); a function of math is handled in visit_Call
        if (isinstance(node.value, ast.Name) and node.value.id == "math"
                and node.attr in ("pi", "e", "tau", "inf")):
            return node
        raise _NotVectorisable

    def visit_BinOp(self, node):  # noqa: N802
        node.left, node.right = self.visit(node.left), self.visit(node.right)
        if isinstance(node.op, (ast.Add, ast.Sub, ast.Mult, ast.Div)):
            return node
        if isinstance(node.op, ast.Pow):
            return _call("_v_map", ast.Name("_v_pow", ast.Load()), node.left, node.right)
        raise _NotVectorisable

    def visit_Compare(self, node):  # noqa: N802
        if len(node.ops) != 1:
            raise _NotVectorisable
        return self.generic_visit(node)

    def visit_BoolOp(self, node):  # noqa: N802
        for value in node.values:
            if not isinstance(value, (ast.Compare, ast.BoolOp, ast.UnaryOp)):
                raise _NotVectorisable  # ``a and b`` of numbers is one of them, not a Boolean
        values = [self.visit(v) for v in node.values]
        return _call("_v_and" if isinstance(node.op, ast.And) else "_v_or", *values)

    def visit_UnaryOp(self, node):  # noqa: N802
        node = self.generic_visit(node)
        if isinstance(node.op, ast.Not):
            return _call("_v_not", node.operand)
        return node

    def visit_IfExp(self, node):  # noqa: N802
        return _call("_v_where", self.visit(node.test), self.visit(node.body), self.visit(node.orelse))

    def visit_Call(self, node):  # noqa: N802
        if node.keywords or any(isinstance(a, ast.Starred) for a in node.args):
            raise _NotVectorisable
        args = [self.visit(a) for a in node.args]
        func = node.func
        if isinstance(func, ast.Attribute) and isinstance(func.value, ast.Name) and func.value.id == "math":
            exact = _EXACT_NUMPY.get(func.attr)
            if exact is not None:
                return _call(ast.Attribute(ast.Name("np", ast.Load()), exact, ast.Load()), *args)
            return _call("_v_map", func, *args)
        if isinstance(func, ast.Name):
            if func.id == "abs" and len(args) == 1:
                return _call("_v_abs", *args)
            if func.id in ("min", "max") and len(args) >= 2:
                return _call(f"_v_{func.id}", *args)
            if func.id.startswith("_f_") or func.id in FLOAT_FUNCTIONS:  # a table function, _exp ...
                return _call("_v_map", func, *args)
        raise _NotVectorisable


def _is_array(value) -> bool:
    return isinstance(value, np.ndarray) and value.ndim > 0


def _v_map(function, *args):
    """``function`` element by element, on Python numbers (an element that fails gives NaN)."""
    arrays = [a for a in args if isinstance(a, np.ndarray) and a.ndim]
    if not arrays:
        return function(*args)  # no array among the arguments: the scalar code itself
    shape = arrays[0].shape
    if len(shape) == 1 and all(a.shape == shape for a in arrays):
        lists = [a.tolist() if isinstance(a, np.ndarray) and a.ndim
                 else itertools.repeat(a.item() if isinstance(a, np.ndarray) else a) for a in args]
    else:
        broadcast = np.broadcast_arrays(*[np.asarray(a) for a in args])
        shape = broadcast[0].shape
        lists = [a.ravel().tolist() for a in broadcast]
    try:
        return np.fromiter(map(function, *lists), float, math.prod(shape)).reshape(shape)
    except (ArithmeticError, ValueError, TypeError):
        pass
    lists = [list(itertools.islice(items, math.prod(shape))) for items in lists]
    values = []
    for items in zip(*lists):
        try:
            values.append(float(function(*items)))
        except (ArithmeticError, ValueError, TypeError):
            values.append(math.nan)
    return np.array(values, dtype=float).reshape(shape)


def _v_pow(a, b):
    return a ** b


def _v_where(test, a, b):
    if not (_is_array(test) or _is_array(a) or _is_array(b)):
        return a if test else b
    return np.where(test, a, b)


def _v_abs(a):
    return np.abs(a) if _is_array(a) else abs(a)


def _v_max(first, *rest):
    """Python's ``max(a, b, ...)``: a later item replaces the current one only if greater."""
    if not any(_is_array(a) for a in (first, *rest)):
        return max(first, *rest)
    out = first
    for item in rest:
        out = np.where(item > out, item, out)
    return out


def _v_min(first, *rest):
    """Python's ``min(a, b, ...)``."""
    if not any(_is_array(a) for a in (first, *rest)):
        return min(first, *rest)
    out = first
    for item in rest:
        out = np.where(item < out, item, out)
    return out


def _v_and(*values):
    out = values[0]
    for value in values[1:]:
        out = np.logical_and(out, value)
    return out


def _v_or(*values):
    out = values[0]
    for value in values[1:]:
        out = np.logical_or(out, value)
    return out


def _v_not(value):
    return np.logical_not(value)


def _v_any(value) -> bool:
    return bool(np.any(value))


def _v_rows(varying, constant, varying_rows, constant_rows, t) -> np.ndarray:
    """The returned values as the rows of one float array: the values that vary with
    the instant (arrays) and the constants (each filling its row)."""
    m = np.shape(t)[0]
    out = np.empty((len(varying) + len(constant), m))
    try:
        if varying:
            block = np.array(varying, dtype=float)
            if block.shape != (len(varying), m):
                raise ValueError("a value expected to vary is a constant")
            out[varying_rows] = block
        if constant:
            out[constant_rows] = np.array(constant, dtype=float)[:, None]
    except (ValueError, TypeError):  # not the shapes expected: one row at a time
        for k, item in zip((*varying_rows.tolist(), *constant_rows.tolist()), (*varying, *constant)):
            out[k] = item
    return out


_VECTOR_HELPERS = {"_v_map": _v_map, "_v_pow": _v_pow, "_v_where": _v_where, "_v_abs": _v_abs,
                   "_v_max": _v_max, "_v_min": _v_min, "_v_and": _v_and, "_v_or": _v_or, "_v_not": _v_not,
                   "_v_any": _v_any, "_v_rows": _v_rows, "np": np, "math": math}


class CompiledFunctions:
    """What a system of generated functions answers besides its fields (``states``,
    ``unknowns``, ``crossings``, ``outputs``, ``code``): shared by the compiler's
    :class:`~acausal.compiler.modes.ModeSystem` and a saved run's
    :class:`~acausal.compiler.saved.LoadedSystem` (the runtime's ``CompiledSystem``)."""

    #: a system of the whole model has no independent parts (a
    #: :class:`~acausal.compiler.clusters.ComposedSystem` has)
    parts = None

    def crossings_for(self, relations: tuple[int, ...]) -> Callable:
        """A ``crossings`` that computes at least the values of ``relations``: here
        every relation's (the generated function is one)."""
        return self.crossings

    def vectorised(self, name: str) -> Callable | None:
        """The numpy version of ``crossings`` or ``outputs``: ``f(t, X)`` for ``m``
        times and the states as the rows of ``X`` gives a ``k x m`` array whose
        columns equal the scalar function's values bit for bit (:func:`vectorised`);
        None where the code does not allow one."""
        return vectorised_of(self, name)

    def vectorised_crossings_for(self, relations: tuple[int, ...]) -> Callable | None:
        """The numpy version of ``crossings`` for ``relations`` only (the watched ones):
        ``f(t, X)`` gives a ``2 len(relations) x m`` array whose rows ``2j`` and ``2j + 1``
        are the sides of ``relations[j]``, bit for bit the rows ``2k``, ``2k + 1`` of
        :meth:`vectorised` ``("crossings")``, computed without what they do not need
        (made once per system and ``relations``); None where the code does not allow one.
        (Mirrors ``crossings_for``; a system of parts has none.)"""
        rows = tuple(2 * k + side for k in relations for side in (0, 1))
        return vectorised_of(self, "crossings", rows)

    def crossings_of(self, relations: tuple[int, ...]) -> Callable | None:
        """``crossings`` for ``relations`` only (the watched ones): ``f(t, x)`` gives the
        tuple ``(lhs, rhs)`` of ``relations[0]``, then of ``relations[1]`` ..., bit for bit
        those values of ``crossings(t, x)``, computed without what they do not need
        (:func:`rows_function`; made once per system and ``relations``); None where the
        code does not allow one.  (The scalar twin of :meth:`vectorised_crossings_for`;
        a system of parts has none.)"""
        rows = tuple(2 * k + side for k in relations for side in (0, 1))
        return rows_function_of(self, "crossings", rows)

    def values(self, t: float, x) -> dict[str, float]:
        """Continuous variables and derivatives at ``(t, x)`` (aliases: see ``alias_plan``)."""
        out = dict(zip(self.states, map(float, x)))
        out.update(zip(self.unknowns, self.outputs(t, x)))
        return out

    def reset(self) -> None:
        """A new run: the Newton solves start from the start values again (:func:`reset_warm_starts`)."""
        reset_warm_starts(self.outputs)


def reset_warm_starts(function: Callable) -> None:
    """Forget the warm starts of the generated functions ``function`` was made with: each
    Newton solve's last solution (its next first guess) and last Jacobian.  Within a run the
    warm start saves iterations; across runs it would make the second run of a compiled
    system start where the first ended, and so differ from it (or fail where it succeeded)."""
    reset = getattr(function, "reset", None)  # functions not made by generated code have none
    if reset is not None:
        reset()
