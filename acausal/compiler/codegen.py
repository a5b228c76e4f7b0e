"""Stage 8: generate straight-line Python code from the solution steps.

For one system the generator writes a factory ``make(p)`` that binds the
parameter values and returns functions of ``(t, x)``:

* ``derivatives`` — only the steps the state derivatives need (the hot loop);
* ``crossings`` — only the steps the watched relations need;
* ``outputs`` — every unknown, for the output grid and events.

Expressions are printed for scalars with the ``math`` module (faster than
numpy on scalars) after common subexpression elimination.  The functions
that overflow (``exp``, ``sinh``, ``cosh``, ``expm1``, ``gamma``,
``loggamma``, powers) are printed as this module's guarded versions
(``_exp(x)``, ``_pow(a, b)``, see :data:`FLOAT_FUNCTIONS`): they give an
infinity where IEEE arithmetic does instead of raising ``OverflowError``, so
that a trial step of an integrator that overshoots is rejected, not fatal.
The generated source is kept (:attr:`GeneratedCode.source`) and is the same
text for the same model every time.
"""

from __future__ import annotations

import collections
import keyword
import math
import re
from dataclasses import dataclass, field
from typing import Callable, Sequence

import numpy as np
import sympy as sp
from sympy.printing.pycode import PythonCodePrinter

from .algebraic import Assign, LinearSolve, NewtonSolve
from .canonical import placeholders, shape
from ..errors import SolverError
from .generated import (FLOAT_FUNCTIONS, _linalg_error, load_functions, load_make, newton_solve,  # noqa: F401
                        vectorised)

__all__ = ["CodePlan", "CodegenMemo", "GeneratedCode", "plan_functions", "generate", "needed_steps", "newton_solve", "python_identifiers",
           "compile_functions", "vectorised", "FLOAT_FUNCTIONS"]


#: sympy function name -> the name printed for it
_GUARDED = {"exp": "_exp", "expm1": "_expm1", "sinh": "_sinh", "cosh": "_cosh", "gamma": "_gamma",
            "loggamma": "_lgamma"}


class _Printer(PythonCodePrinter):
    """Python printer that also prints table functions by name, and the functions that
    overflow as their guarded versions (:data:`FLOAT_FUNCTIONS`)."""

    def __init__(self, functions: dict, local: dict[str, str], function_names: dict | None = None) -> None:
        super().__init__({"fully_qualified_modules": True, "standard": "python3"})
        self.functions = functions  #: name in the code -> implementation
        self.function_names = {} if function_names is None else function_names  #: the reverse
        self.local = local

    def _print_Function(self, expr):  # noqa: N802 - sympy API
        impl = getattr(type(expr), "_imp_", None) or getattr(expr.func, "_imp_", None)
        if impl is not None:
            name = self.function_names.get(impl)
            if name is None:  # two tables of one class name (a.b_c, a_b.c) stay apart
                base = name = f"_f_{type(expr).__name__}"
                k = 2
                while name in self.functions:
                    name, k = f"{base}_{k}", k + 1
                self.functions[name], self.function_names[impl] = impl, name
            return f"{name}({', '.join(self._print(a) for a in expr.args)})"
        return super()._print_Function(expr)

    def _print_guarded(self, expr):
        return f"{_GUARDED[type(expr).__name__]}({', '.join(self._print(a) for a in expr.args)})"

    _print_exp = _print_expm1 = _print_sinh = _print_cosh = _print_gamma = _print_loggamma = _print_guarded

    def _print_Pow(self, expr, rational=False):  # noqa: N802
        # square roots and reciprocals as sympy prints them (they cannot overflow to an
        # exception: ``1/x`` gives inf or raises ZeroDivisionError, as every division here)
        if rational or expr.exp == sp.S.Half or (expr.is_commutative and (
                -expr.exp is sp.S.Half or expr.exp is sp.S.NegativeOne)):
            return super()._print_Pow(expr, rational=rational)
        return f"_pow({self._print(expr.base)}, {self._print(expr.exp)})"

    def _print_Symbol(self, expr):  # noqa: N802
        ident = self.local.get(expr.name)
        if ident is None:
            raise SolverError(f"generated code: {expr.name} is not known here")
        return ident

    def _print_Temporary(self, expr):  # noqa: N802
        return expr.name


class Temporary(sp.Symbol):
    """A common subexpression of one step: printed by its own name.

    Its own class, so that a model variable of the same name (``_y_0``) can
    never be taken for it.
    """


@dataclass(frozen=True)
class CodePlan:
    """Which solution steps each generated function runs: the plan, before any printing.

    Attributes
    ----------
    derivatives : tuple of int
        The steps ``derivatives(t, x)`` needs (only those its results depend on).
    crossings : tuple of int
        The steps ``crossings(t, x)`` needs.
    outputs : tuple of int
        Every step: ``outputs(t, x)`` returns every unknown.
    """

    derivatives: tuple[int, ...]
    crossings: tuple[int, ...]
    outputs: tuple[int, ...]


@dataclass(frozen=True)
class GeneratedCode:
    """Generated source and the factory it defines."""

    source: str
    make: Callable = field(repr=False, compare=False)
    n_derivative_steps: int
    n_steps: int
    plan: CodePlan | None = None


def needed_steps(steps: Sequence, targets: set[str]) -> list[int]:
    """Indices of the steps needed for ``targets`` (in order)."""
    needed = set(targets)
    chosen = []
    for k in range(len(steps) - 1, -1, -1):
        step = steps[k]
        if needed & set(step.defines):
            chosen.append(k)
            needed |= step.reads()
    return sorted(chosen)


def python_identifiers(names: Sequence[str], taken: set[str] | None = None) -> dict[str, str]:
    """Readable, distinct Python identifiers for model names (``J1.w`` -> ``J1_w``).

    ``der(J1.w)`` becomes ``der_J1_w``.  Names that would clash with a Python
    keyword or builtin (``max``, ``abs``), with the names the generated code
    uses itself (``t``, ``x``, ``p``, ``math``, ``np``, anything starting with
    ``_``) or with an earlier name get a prefix or a numeric suffix; the
    result depends only on the order of ``names``, so it is the same every run.
    """
    taken = set() if taken is None else taken
    out = {}
    not_word = _NOT_WORD.sub
    for name in names:
        ident = not_word("_", name.replace("(", "_").replace(")", "")) or "v"
        if ident[0].isdigit() or ident.startswith("_") or ident in _RESERVED or keyword.iskeyword(ident):
            ident = "v_" + ident
        candidate, k = ident, 2
        while candidate in taken:
            candidate, k = f"{ident}_{k}", k + 1
        taken.add(candidate)
        out[name] = candidate
    return out


_NOT_WORD = re.compile(r"\W")


#: Names the generated code defines or calls (model names are kept clear of them): its own,
#: and the builtins sympy's printer may emit.  A fixed list, not ``dir(builtins)``: that
#: differs between environments (IPython adds names), and the code must not.
_RESERVED = {"t", "x", "p", "math", "np", "make", "derivatives", "crossings", "outputs",
             "abs", "min", "max", "float", "int", "bool", "pow", "round", "sum", "len", "range",
             "tuple", "list", "dict", "set", "print", "complex", "divmod", "any", "all"}


@dataclass(eq=False)
class CodegenMemo:
    """Code already printed, for the other systems of one model (same identifiers)."""

    steps: dict = field(default_factory=dict)  #: step key -> (code lines, names read)
    functions: dict = field(default_factory=dict)  #: table functions called by the code
    function_names: dict = field(default_factory=dict)
    expressions: dict = field(default_factory=dict)  #: crossing expression -> printed text
    #: shape of a step (:func:`~acausal.compiler.canonical.shape`) -> its code as a format string
    #: of the identifiers (None: that shape is printed step by step)
    templates: dict = field(default_factory=dict)


def generate(steps: Sequence, states: Sequence[str], derivatives: Sequence[str],
             unknowns: Sequence[str], parameters: Sequence[str],
             crossings: Sequence[sp.Expr] = (), name: str = "system",
             guesses: dict[str, float] | None = None, identifiers: dict[str, str] | None = None,
             memo: "CodegenMemo | None" = None) -> GeneratedCode:
    """Generate the code of one system.

    Parameters
    ----------
    steps : sequence of Assign, LinearSolve, NewtonSolve
    states : names read from ``x``
    derivatives : unknowns returned by ``derivatives`` (one per state)
    unknowns : every unknown, in the order ``outputs`` returns them
    parameters : names bound from ``p`` in this order
    crossings : expressions returned by ``crossings``
    guesses : start values, the first guesses of Newton iterations
    identifiers : dict, optional
        Python identifier of each name (see :func:`python_identifiers`); made
        from the names here when not given (and for names missing from it).
        It is not changed.
    memo : CodegenMemo, optional
        Code already written for a step, shared by the systems of one model
        (the discrete states of a hybrid model have most steps in common, and
        printing expressions is the slow part of code generation).  Only
        valid together with the same ``identifiers``.
    """
    guesses = guesses or {}
    identifiers = {} if identifiers is None else identifiers
    missing = [n for n in [*states, *unknowns, *parameters] if n not in identifiers]
    if missing and memo is not None:
        # code in the memo was printed with the identifiers it was given: a name new to them (a
        # derivative of an order index reduction rarely reaches) joins the shared table, clear of
        # every identifier in it, so that code printed earlier stays valid
        if not isinstance(identifiers, dict):
            raise ValueError(f"generate: no identifier for {missing[0]}; a memo needs identifiers "
                             f"naming every variable")
        identifiers.update(python_identifiers(missing, set(identifiers.values())))
        missing = []
    # the model's table is not copied (a model of N parts generates ~4N systems from one table
    # of every name): names new to it and time go in front of it
    own = python_identifiers(missing, set(identifiers.values())) if missing else {}
    own["time"] = "t"
    local = collections.ChainMap(own, identifiers)
    memo = CodegenMemo() if memo is None else memo
    step_memo = memo.steps
    functions: dict = memo.functions
    printer = _Printer(functions, local, memo.function_names)

    # what each step reads (kept with its printed code: finding it is not free)
    keys = [_step_key(step) for step in steps]
    reads = [step_memo[k][1] if k in step_memo else step.reads() for k, step in zip(keys, steps)]
    plan = plan_functions(steps, reads, states, parameters, derivatives, crossings, name)
    blocks_code = []
    templates = memo.templates
    for step, key, step_reads in zip(steps, keys, reads):
        found = step_memo.get(key)
        if found is None:
            found = step_memo[key] = (_renamed_code(step, printer, local, templates), step_reads)
        blocks_code.append(found[0])

    lines = [f"# generated by acausal for {name}", "def make(p):"]
    if parameters:
        lines.append(f"    {', '.join(local[n] for n in parameters)}, = p")
    lines.append("    _state = {}  # each Newton solve's last solution: the next call's first guess")
    memos = []
    for step in steps:
        if isinstance(step, NewtonSolve):
            start = [float(guesses.get(t, 0.0)) for t in step.tears]
            lines.append(f"    _start_{local[step.tears[0]]} = np.array({start!r})")
            lines.append(f"    _memo_{local[step.tears[0]]} = {{}}  # its last Jacobian (newton_solve)")
            memos.append(f"_memo_{local[step.tears[0]]}")
    # a new run starts its Newton solves from the start values again, so that two runs of
    # one compiled system give the same iterates (generated.reset_warm_starts calls it)
    lines += ["    def reset():", "        _state.clear()"] + [f"        {m}.clear()" for m in memos]
    unpack = f"        {', '.join(local[n] for n in states)}, = x" if states else None

    def function(fname: str, chosen: list[int], result: str) -> None:
        lines.append(f"    def {fname}(t, x):")
        if unpack:
            lines.append(unpack)
        for k in chosen:
            lines.extend("        " + line for line in blocks_code[k])
        lines.append(f"        return {result}")

    function("derivatives", plan.derivatives, _tuple(local[d] for d in derivatives))
    printed = memo.expressions
    for g in crossings:
        if g not in printed:
            printed[g] = printer.doprint(g)
    function("crossings", plan.crossings, _tuple(printed[g] for g in crossings))
    function("outputs", plan.outputs, _tuple(local[u] for u in unknowns))
    lines.append("    derivatives.reset = crossings.reset = outputs.reset = reset")
    lines.append("    return derivatives, crossings, outputs")
    source = "\n".join(lines) + "\n"
    return GeneratedCode(source, load_make(source, functions, name), len(plan.derivatives), len(steps), plan)


def plan_functions(steps: Sequence, reads: Sequence[set[str]], states: Sequence[str],
                   parameters: Sequence[str], derivatives: Sequence[str],
                   crossings: Sequence[sp.Expr], name: str = "system") -> CodePlan:
    """Which steps each generated function runs, after checking that every name
    a step or a crossing reads is known where it is read.

    Raises
    ------
    SolverError
        If a step reads a name no earlier step computes (the sort is wrong).
    """
    known = set(states) | set(parameters) | {"time"}
    for step, step_reads in zip(steps, reads):
        if not step_reads <= known:
            raise SolverError(f"generated code for {name}: {sorted(step_reads - known)[0]} is not known "
                              f"where {step.defines[0]} is computed")
        known |= set(step.defines)
    cross_reads = set()
    for g in crossings:
        cross_reads |= {s.name for s in g.free_symbols}
    if not cross_reads <= known:
        raise SolverError(f"generated code for {name}: {sorted(cross_reads - known)[0]} is not known here")
    return CodePlan(tuple(needed_steps(steps, set(derivatives))), tuple(needed_steps(steps, cross_reads)),
                    tuple(range(len(steps))))


def compile_functions(arguments: Sequence[Sequence[str]], expressions: Sequence[sp.Expr],
                      name: str = "functions") -> list[Callable]:
    """Scalar Python functions, ``expressions[k]`` of the names ``arguments[k]``.

    One source and one ``compile`` for all of them (``sympy.lambdify`` costs a
    few milliseconds per expression).  Booleans, relations and if-expressions
    print as Python's own.
    """
    source, functions = functions_source(arguments, expressions, name)
    return load_functions(source, len(expressions), name, functions)


def functions_source(arguments: Sequence[Sequence[str]], expressions: Sequence[sp.Expr],
                     name: str = "functions") -> tuple[str, dict]:
    """The source of :func:`compile_functions` (``_f0``, ``_f1``, ...) and the table or
    impure functions it calls (name in the source -> implementation)."""
    identifiers = python_identifiers(sorted({a for args in arguments for a in args}))
    functions: dict = {}
    printer = _Printer(functions, identifiers)
    templates: dict = {}  # the N equal components' equations are printed once per shape
    lines = [f"# generated by acausal for {name}"]
    for k, (args, expr) in enumerate(zip(arguments, expressions)):
        lines += [f"def _f{k}({', '.join(identifiers[a] for a in args)}):",
                  f"    return {_printed_by_shape(expr, printer, identifiers, templates)}"]
    return "\n".join(lines) + "\n", functions


def _printed_by_shape(expr, printer, local, templates: dict) -> str:
    """``printer.doprint(expr)``, printed once per shape of ``expr``
    (:mod:`~acausal.compiler.canonical`) and the identifiers of this copy put into that
    text: the same text, character for character."""
    expr = sp.sympify(expr)
    found = shape((expr,), (), ("expression",))
    if found is None:
        return printer.doprint(expr)
    key, order, _ = found
    if any(n not in local for n in order):
        return printer.doprint(expr)  # (its error names the unknown name)
    template = templates.get(key, False)
    if template is False:
        template = templates[key] = _expression_template(expr, key, order, printer)
    if template is None:
        return printer.doprint(expr)
    return template.format(*[local[n] for n in order])


def _expression_template(expr, key: tuple, order: Sequence[str], printer) -> str | None:
    """The text of ``expr``'s shape as a format string (``{k}``: the identifier of the
    ``k``-th name of ``order``); None when ``expr`` renamed to placeholders no longer has
    that shape."""
    substitution, names = placeholders([expr], order)
    renamed = expr.xreplace(substitution)
    again = shape((renamed,), (), ("expression",))
    if again is None or again[0] != key or list(again[1]) != [names[n] for n in order]:
        return None
    return _format_string(printer, names, order, lambda tokens: printer.doprint(renamed))


def _format_string(printer, names: dict[str, str], order: Sequence[str], write) -> str:
    """The text ``write(tokens)`` prints with ``printer`` when each placeholder name
    (``names[n]`` for ``n`` of ``order``) prints as ``{k}``, ``k`` its position in
    ``order``: a format string of the identifiers (the text's own braces escaped)."""
    tokens = {names[n]: f"@{k}@" for k, n in enumerate(order)}
    saved = printer.local
    printer.local = tokens
    try:
        text = write(tokens)
    finally:
        printer.local = saved
    return re.sub(r"@(\d+)@", r"{\1}", text.replace("{", "{{").replace("}", "}}"))


def _step_key(step) -> tuple:
    """What the code of a step depends on (its origin only through the error text)."""
    if isinstance(step, Assign):
        return ("assign", step.variable, step.expression)
    inner = tuple((a.variable, a.expression) for a in step.inner)
    if isinstance(step, LinearSolve):
        return ("linear", step.tears, step.A, step.b, inner, step.origins[:3])
    return ("newton", step.tears, inner, step.residuals, step.origins[:3])


def _tuple(items) -> str:
    items = list(items)
    if not items:
        return "()"
    return "(" + ", ".join(items) + ("," if len(items) == 1 else "") + ")"


def _cse_lines(exprs: list[sp.Expr], printer, prefix: str) -> tuple[list[str], list[str]]:
    """Common subexpressions (as lines) and the reduced expressions (printed).

    A lone small expression has nothing to share: it is printed as it is
    (sympy's cse costs far more than it saves there).
    """
    if len(exprs) == 1 and _small(exprs[0]):
        return [], [printer.doprint(exprs[0])]
    symbols = sp.numbered_symbols(prefix, cls=Temporary)
    replacements, reduced = sp.cse(exprs, symbols=symbols, optimizations=None, order="canonical")
    lines = [f"{sym} = {printer.doprint(e)}" for sym, e in replacements]
    return lines, [printer.doprint(e) for e in reduced]


def _small(expr: sp.Expr, limit: int = 12) -> bool:
    """Whether ``expr`` has fewer than ``limit`` nodes (no subexpression worth sharing)."""
    count = 0
    for _ in sp.preorder_traversal(expr):
        count += 1
        if count >= limit:
            return False
    return True


#: stands for a step's origins (the text of its error messages) in a template
_WHAT = "@W@"


def _step_shape(step):
    """:func:`~acausal.compiler.canonical.shape` of a step: its expressions and the
    variables it defines (None: it cannot be renamed)."""
    if isinstance(step, Assign):
        return shape((step.expression,), (step.variable,), ("assign",))
    inner_names = tuple(a.variable for a in step.inner)
    inner = [a.expression for a in step.inner]
    if isinstance(step, LinearSolve):
        roots = [e for row in step.A for e in row] + list(step.b) + inner
        return shape(roots, step.tears + inner_names, ("linear", len(step.tears), len(inner)))
    return shape(inner + list(step.residuals), step.tears + inner_names,
                 ("newton", len(step.tears), len(inner), len(step.residuals)))


def _placeholder_step(step, order: Sequence[str]):
    """``step`` with its symbols and names renamed to the placeholders of ``order`` (and
    its origins to :data:`_WHAT`), and the names' placeholders."""
    if isinstance(step, Assign):
        roots = [step.expression]
    elif isinstance(step, LinearSolve):
        roots = [e for row in step.A for e in row] + list(step.b) + [a.expression for a in step.inner]
    else:
        roots = [a.expression for a in step.inner] + list(step.residuals)
    substitution, names = placeholders(roots, order)

    def assign(a: Assign) -> Assign:
        return Assign(names[a.variable], a.expression.xreplace(substitution), None)

    if isinstance(step, Assign):
        return assign(step), names
    inner = tuple(assign(a) for a in step.inner)
    tears = tuple(names[t] for t in step.tears)
    if isinstance(step, LinearSolve):
        return LinearSolve(tears, tuple(tuple(e.xreplace(substitution) for e in row) for row in step.A),
                           tuple(e.xreplace(substitution) for e in step.b), inner, (_WHAT,)), names
    return NewtonSolve(tears, inner, tuple(e.xreplace(substitution) for e in step.residuals), (_WHAT,)), names


def _renamed_code(step, printer, local, templates: dict) -> list[str]:
    """The lines of one step: printed once per shape (:mod:`~acausal.compiler.canonical`),
    the identifiers of this step put into that text.  The same lines as
    :func:`_step_code` prints for the step itself; steps that cannot be renamed are
    printed so."""
    found = _step_shape(step)
    if found is None:
        return _step_code(step, printer, local)
    key, order, _ = found
    if any(n not in local for n in order):
        return _step_code(step, printer, local)  # (its error names the unknown variable)
    template = templates.get(key, False)
    if template is False:
        template = templates[key] = _template(step, key, order, printer)
    if template is None:
        return _step_code(step, printer, local)
    what = "" if isinstance(step, Assign) else repr("; ".join(step.origins[:3]))
    return template.format(*[local[n] for n in order], w=what).split("\n")


def _template(step, key: tuple, order: Sequence[str], printer) -> str | None:
    """The code of ``step``'s shape as a format string (``{k}``: the identifier of the
    ``k``-th name of ``order``, ``{w}``: the origins' text); None when the step renamed
    to placeholders no longer has that shape (sympy rebuilt it otherwise)."""
    renamed, names = _placeholder_step(step, order)
    again = _step_shape(renamed)
    if again is None or again[0] != key or list(again[1]) != [names[n] for n in order]:
        return None
    text = _format_string(printer, names, order, lambda tokens: "\n".join(_step_code(renamed, printer, tokens)))
    return text.replace(repr(_WHAT), "{w}")


def _step_code(step, printer, local) -> list[str]:
    """The lines of one step.  Its own temporaries are named after the first
    unknown it defines, so the text is the same in every system that has it."""
    own = local[step.defines[0]]
    prefix = f"_{own}_"
    if isinstance(step, Assign):
        pre, (text,) = _cse_lines([step.expression], printer, prefix)
        return pre + [f"{own} = {text}"]
    what = repr("; ".join(step.origins[:3]))
    inner = [(local[a.variable], a.expression) for a in step.inner]
    if isinstance(step, LinearSolve):
        n = len(step.tears)
        flat = [e for row in step.A for e in row] + list(step.b)
        pre, printed = _cse_lines(flat, printer, prefix)
        A = [printed[r * n:(r + 1) * n] for r in range(n)]
        b = printed[n * n:]
        z = [local[t] for t in step.tears]
        lines = list(pre)
        if n == 1:
            lines += [f"_a = {A[0][0]}", "if _a == 0.0:", f"    raise _linalg_error({what})",
                      f"{z[0]} = ({b[0]}) / _a"]
        elif n == 2:
            lines += [f"_a00 = {A[0][0]}", f"_a01 = {A[0][1]}", f"_a10 = {A[1][0]}", f"_a11 = {A[1][1]}",
                      f"_b0 = {b[0]}", f"_b1 = {b[1]}", "_det = _a00 * _a11 - _a01 * _a10",
                      "if _det == 0.0:", f"    raise _linalg_error({what})",
                      f"{z[0]} = (_b0 * _a11 - _a01 * _b1) / _det",
                      f"{z[1]} = (_a00 * _b1 - _b0 * _a10) / _det"]
        else:
            rows = ", ".join("(" + ", ".join(r) + ")" for r in A)
            lines += [f"_A = np.array(({rows},))", f"_b = np.array(({', '.join(b)},))",
                      f"{', '.join(z)}, = _solve(_A, _b, {what})"]
        for var, expr in inner:
            ipre, (text,) = _cse_lines([expr], printer, f"{prefix}i{var}_")
            lines += ipre + [f"{var} = {text}"]
        return lines
    # NewtonSolve: a local residual function over the tearing unknowns
    z = [local[t] for t in step.tears]
    lines = [f"def _res_{own}(_z):", f"    {', '.join(z)}, = _z"]
    for var, expr in inner:
        ipre, (text,) = _cse_lines([expr], printer, f"{prefix}i{var}_")
        lines += ["    " + l for l in ipre] + [f"    {var} = {text}"]
    res_pre, res_printed = _cse_lines(list(step.residuals), printer, prefix)
    lines += ["    " + l for l in res_pre] + [f"    return ({', '.join(res_printed)},)"]
    guess = f"_guess_{own}"
    lines = [f"{guess} = _state.get({own!r})"] + lines
    lines += [f"if {guess} is None:", f"    {guess} = _start_{own}",
              f"_sol_{own} = _newton(_res_{own}, {guess}, {what}, memo=_memo_{own})",
              f"_state[{own!r}] = _sol_{own}",
              f"{', '.join(z)}, = _sol_{own}"]
    for var, expr in inner:
        ipre, (text,) = _cse_lines([expr], printer, f"{prefix}o{var}_")
        lines += ipre + [f"{var} = {text}"]
    return lines
