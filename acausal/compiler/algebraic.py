"""Stage 7: algebraic loops — how each BLT block is solved.

* A block of one equation linear in its unknown becomes an assignment.
* A larger block is *torn* (Elmqvist & Otter 1994): a few tearing unknowns
  are guessed, the other equations are solved one after the other in terms
  of them, and the equations left over are residuals.  When the block is
  linear the residuals are linear in the tearing unknowns, so the step is a
  small linear solve (closed form for one or two unknowns).  Otherwise the
  residuals are zeroed by Newton's method.
* An equation is only solved for an unknown when it is linear in it with a
  coefficient that is not zero for the parameter values at hand; asked to
  solve anything else, the error names the equation and the unknown.

References
----------
.. [1] H. Elmqvist and M. Otter, "Methods for tearing systems of equations in
   object-oriented modeling", Proc. ESM'94, 326-332, 1994.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable, Sequence

import sympy as sp

from .blt import BLTResult
from .canonical import from_placeholders, shape, to_placeholders
from .flatten import FlatEquation
from ..language import parameter_symbols, real_symbol

__all__ = ["Assign", "LinearSolve", "NewtonSolve", "AlgebraicResult", "AlgebraicMemo", "solve_blocks", "tear"]


@dataclass(frozen=True, slots=True)
class Assign:
    """``variable = expression``."""

    variable: str
    expression: sp.Expr
    origin: object  #: the Origin of the equation it comes from (printed on demand)

    @property
    def defines(self) -> tuple[str, ...]:
        return (self.variable,)

    def reads(self) -> set[str]:
        return {s.name for s in self.expression.free_symbols}


@dataclass(frozen=True)
class LinearSolve:
    """Solve ``A z = b`` for the tearing unknowns ``z``, then the inner assignments."""

    tears: tuple[str, ...]
    A: tuple[tuple[sp.Expr, ...], ...]
    b: tuple[sp.Expr, ...]
    inner: tuple[Assign, ...]
    origins: tuple[str, ...]

    @property
    def defines(self) -> tuple[str, ...]:
        return self.tears + tuple(a.variable for a in self.inner)

    def reads(self) -> set[str]:
        return _reads([e for row in self.A for e in row] + list(self.b), self.inner, self.defines)


@dataclass(frozen=True)
class NewtonSolve:
    """Zero ``residuals`` over ``tears`` (inner assignments computed inside)."""

    tears: tuple[str, ...]
    inner: tuple[Assign, ...]
    residuals: tuple[sp.Expr, ...]
    origins: tuple[str, ...]

    @property
    def defines(self) -> tuple[str, ...]:
        return self.tears + tuple(a.variable for a in self.inner)

    def reads(self) -> set[str]:
        return _reads(self.residuals, self.inner, self.defines)


def _reads(expressions, inner: Sequence[Assign], defines: Sequence[str]) -> set[str]:
    """The names a torn block reads: its expressions' and its inner assignments', less its own."""
    names = set()
    for e in expressions:
        names |= {s.name for s in e.free_symbols}
    for a in inner:
        names |= a.reads()
    return names - set(defines)


@dataclass(frozen=True)
class AlgebraicResult:
    """Solution steps in BLT order, plus statistics for the teaching view."""

    steps: tuple
    torn_blocks: int
    linear_blocks: int
    nonlinear_blocks: int
    #: expressions of parameters the steps divide by: non-zero for the values the
    #: system was solved with; other values must keep them so for it to stay valid
    nonzero: tuple = ()


def _linear_coefficient(residual: sp.Expr, var: sp.Symbol) -> sp.Expr | None:
    """``d residual / d var`` when each term holding ``var`` is ``c*var`` (c free of it).

    The common case, found without sympy's differentiation (the slow part of
    solving a large model); None when some term is anything else.
    """
    coefficients = []
    for term in sp.Add.make_args(residual):
        if not term.has(var):
            continue
        if term == var:  # (equal, not always the same object: sympy's symbol cache is bounded)
            coefficients.append(sp.Integer(1))
            continue
        if not isinstance(term, sp.Mul):
            return None
        rest = [f for f in term.args if f.has(var)]
        if len(rest) != 1 or rest[0] != var:
            return None
        coefficients.append(sp.Mul(*[f for f in term.args if f != var]))
    return sp.Add(*coefficients)


def _derivative(expr: sp.Expr, var: sp.Symbol) -> sp.Expr | None:
    """``sp.diff(expr, var)`` for sums and products in which ``var`` occurs in one factor
    of each product (built as sympy builds it, so the same expression); None otherwise.

    The case :func:`_linear_coefficient` does not take (``k*(var - c)/d``), without
    sympy's differentiation machinery, which costs about a millisecond per call.
    """
    if expr == var:
        return sp.Integer(1)
    if isinstance(expr, sp.Add):
        parts = []
        for term in expr.args:
            d = _derivative(term, var) if term.has(var) else sp.Integer(0)
            if d is None:
                return None
            parts.append(d)
        return sp.Add(*parts)
    if isinstance(expr, sp.Mul):
        args = expr.args
        holding = [k for k, f in enumerate(args) if f.has(var)]
        if len(holding) != 1:
            return None
        (k,) = holding
        d = _derivative(args[k], var)
        if d is None:
            return None
        # (sympy's Leibniz rule for one derivative: 1 * Mul(factors, the one differentiated))
        return sp.Mul(*args[:k], d, *args[k + 1:])
    return None


def _coefficient(residual: sp.Expr, var: sp.Symbol) -> sp.Expr:
    """``d residual / d var``: the fast forms first, sympy's ``diff`` for the rest."""
    coeff = _linear_coefficient(residual, var)
    if coeff is None:
        coeff = _derivative(residual, var)
        if coeff is None:
            coeff = sp.diff(residual, var)
    return coeff


def _solve_for(residual: sp.Expr, var: sp.Symbol, values: dict) -> sp.Expr | None:
    """``var`` from ``residual = 0`` if linear in it with a non-zero coefficient."""
    return _solve_with_guard(residual, var, values)[0]


def _solve_with_guard(residual: sp.Expr, var: sp.Symbol, values: dict) -> tuple[sp.Expr | None, sp.Expr | None]:
    """:func:`_solve_for`, and the coefficient divided by when it depends on parameters only
    (its being non-zero was decided by the parameter values: a guard for other values)."""
    coeff = _linear_coefficient(residual, var)
    if coeff is None:
        coeff = _coefficient(residual, var)
        if coeff.has(var):
            return None, None
    numeric = coeff.xreplace(values)
    if numeric.is_zero:
        return None, None
    rest = residual.xreplace({var: sp.Integer(0)})
    if coeff == 1:
        return -rest, None
    if coeff == -1:
        return rest, None
    guard = coeff if coeff.free_symbols and coeff.free_symbols <= values.keys() else None
    return -rest / coeff, guard


def _solved(residual: sp.Expr, var: sp.Symbol, values: dict, shapes: dict) -> tuple[sp.Expr | None, sp.Expr | None]:
    """:func:`_solve_with_guard`, solved once per shape of ``(residual, var)`` (the
    equal units of a model: :mod:`~acausal.compiler.canonical`) and renamed for the
    other copies; whether the coefficient is zero is decided for each copy's values."""
    found = shape((residual, var))
    if found is None:
        return _solve_with_guard(residual, var, values)
    key, order, symbols = found
    template = shapes.get(key, False)
    if template is False:
        template = shapes[key] = _solution_template(residual, var, order, symbols)
    if template is None:
        return _solve_with_guard(residual, var, values)
    if template == ():
        return None, None  # not linear in var
    coeff_t, solution_t = template
    coeff = from_placeholders(coeff_t, order, symbols)
    numeric = coeff if isinstance(coeff, sp.Number) else coeff.xreplace(values)
    if numeric.is_zero:
        return None, None
    solution = from_placeholders(solution_t, order, symbols)
    if coeff == 1 or coeff == -1:
        return solution, None
    return solution, (coeff if coeff.free_symbols and coeff.free_symbols <= values.keys() else None)


def _solution_template(residual: sp.Expr, var: sp.Symbol, order, symbols) -> tuple | None:
    """``(coefficient, solution)`` of ``residual = 0`` for ``var`` with placeholders for
    its symbols (``()``: not linear in it; None: cannot be renamed)."""
    coeff = _coefficient(residual, var)
    if coeff.has(var):
        return ()
    rest = residual.xreplace({var: sp.Integer(0)})
    solution = -rest if coeff == 1 else rest if coeff == -1 else -rest / coeff
    coeff_t, solution_t = to_placeholders(coeff, order, symbols), to_placeholders(solution, order, symbols)
    return None if coeff_t is None or solution_t is None else (coeff_t, solution_t)


@dataclass(eq=False)
class AlgebraicMemo:
    """The solution of each block, for the other discrete states of one model."""

    parameter_values: dict | None = None  #: the values it is valid for (checked on use)
    values: dict = field(default_factory=dict)  #: parameter symbol -> sympy Float
    solutions: dict = field(default_factory=dict)  #: (residual, unknown) -> expression or None
    torn: dict = field(default_factory=dict)  #: (residuals, unknowns, origins) -> step
    shapes: dict = field(default_factory=dict)  #: shape of (residual, unknown) -> solution (:func:`_solved`)


def solve_blocks(equations: Sequence[FlatEquation], unknowns: Sequence[str], blt: BLTResult,
                 parameter_values: dict[str, float], memo: AlgebraicMemo | None = None) -> AlgebraicResult:
    """Turn each block into solution steps.

    ``memo`` (optional) keeps the solution of each block for other calls with
    the same parameter values: the discrete states of one model share most
    blocks.
    """
    memo = AlgebraicMemo() if memo is None else memo
    if memo.parameter_values is None:
        memo.parameter_values = dict(parameter_values)
        memo.values = parameter_symbols(parameter_values)
    elif memo.parameter_values != parameter_values:
        raise ValueError("solve_blocks: this memo belongs to other parameter values")
    values = memo.values
    steps = []
    guards: dict = {}
    torn = linear = nonlinear = 0
    for block in blt.blocks:
        eqs = [equations[i] for i in block.equations]
        names = [unknowns[j] for j in block.unknowns]
        if block.size == 1:
            key = (eqs[0].residual, names[0])
            if key not in memo.solutions:
                memo.solutions[key] = _solved(eqs[0].residual, real_symbol(names[0]), values, memo.shapes)
            expr, guard = memo.solutions[key]
            if guard is not None:
                guards[guard] = None
            if expr is not None:
                steps.append(Assign(names[0], expr, eqs[0].origin))
                continue
            nonlinear += 1
            steps.append(NewtonSolve((names[0],), (), (eqs[0].residual,), (str(eqs[0].origin),)))
            continue
        # (the origins too: the step names its equations in error messages)
        key = (tuple(e.residual for e in eqs), tuple(names), tuple(e.origin for e in eqs))
        found = memo.torn.get(key)
        if found is None:
            found = memo.torn[key] = _tear(eqs, names, values)
        step, step_guards = found
        guards.update(dict.fromkeys(step_guards))
        torn += 1
        if isinstance(step, LinearSolve):
            linear += 1
        else:
            nonlinear += 1
        steps.append(step)
    return AlgebraicResult(tuple(steps), torn, linear, nonlinear, tuple(guards))


def tear(incidence: Sequence[set[int]], n_unknowns: int,
         solvable: Callable[[int, int], bool],
         safe: Callable[[int, int], bool] | None = None) -> tuple[list[tuple[int, int]], list[int], list[int]] | None:
    """Greedy tearing of one block, on index lists.

    Equations with a single unknown left that they can be solved for are
    solved, in turn; when none is left, the unknown occurring in most of the
    remaining equations is *torn* (guessed; ties: the first in block order).
    With ``safe``, solutions it accepts come first: another one is taken
    only when no safe one is left, one at a time (so that a chain of safe
    solutions is not cut by a division the chain would have made needless).

    Parameters
    ----------
    incidence : sequence of set of int
        ``incidence[i]``: the block's unknowns equation ``i`` contains.
    n_unknowns : int
    solvable : callable
        ``solvable(i, j)``: whether equation ``i`` can be solved for unknown
        ``j`` (the symbolic work is the caller's).
    safe : callable, optional
        ``safe(i, j)``: whether that solution is preferred (:func:`_tear`:
        it divides by no expression of other unknowns, which may vanish).

    Returns
    -------
    (solved, tears, residuals) or None
        ``solved``: ``(equation, unknown)`` pairs in solution order;
        ``tears``: the torn unknowns; ``residuals``: the equations left, one
        per torn unknown.  None when tearing does not balance.

    References
    ----------
    .. [1] H. Elmqvist and M. Otter, "Methods for tearing systems of equations
       in object-oriented modeling", Proc. ESM'94, 326-332, 1994.
    """
    unknown = set(range(n_unknowns))
    remaining = list(range(len(incidence)))
    solved: list[tuple[int, int]] = []
    tears: list[int] = []
    while remaining and unknown:
        progress = False
        for only_safe in ((True, False) if safe is not None else (None,)):
            for i in list(remaining):
                free = incidence[i] & unknown
                if len(free) != 1:
                    continue
                (j,) = free
                if not solvable(i, j) or (only_safe and not safe(i, j)):
                    continue
                solved.append((i, j))
                unknown.discard(j)
                remaining.remove(i)
                progress = True
                if only_safe is False:
                    break  # one unsafe solution, then the safe ones it enables
            if progress:
                break
        if progress:
            continue
        counts = {j: sum(j in incidence[i] for i in remaining) for j in unknown}
        choice = max(sorted(unknown), key=lambda j: counts[j])
        tears.append(choice)
        unknown.discard(choice)
    if unknown or len(remaining) != len(tears):
        return None
    return solved, tears, remaining


def _tear(eqs: list[FlatEquation], names: list[str], values: dict):
    """The solution step of a block of several equations: tear, then solve.

    Returns the step and the parameter expressions its inner assignments divide by.
    """
    symbols = {n: real_symbol(n) for n in names}
    position = {n: j for j, n in enumerate(names)}
    incidence = [{position[s.name] for s in e.residual.free_symbols if s.name in position} for e in eqs]
    solutions: dict[tuple[int, int], tuple[sp.Expr, sp.Expr | None]] = {}

    def solvable(i: int, j: int) -> bool:
        expr, guard = _solve_with_guard(eqs[i].residual, symbols[names[j]], values)
        if expr is not None:
            solutions[(i, j)] = (expr, guard)
        return expr is not None

    def safe(i: int, j: int) -> bool:
        # the coefficient divided by is a number or an expression of parameters: an
        # expression of other unknowns may vanish while the model runs (0*y = 0)
        residual, var = eqs[i].residual, symbols[names[j]]
        return _coefficient(residual, var).free_symbols <= values.keys()

    plan = tear(incidence, len(names), solvable, safe)
    if plan is None:
        # tearing failed to balance: solve the whole block simultaneously
        tears, inner, residual_eqs, guards = list(names), [], list(range(len(eqs))), ()
    else:
        solved, torn, residual_eqs = plan
        inner = [Assign(names[j], solutions[(i, j)][0], eqs[i].origin) for i, j in solved]
        guards = tuple(g for i, j in solved if (g := solutions[(i, j)][1]) is not None)
        tears = [names[j] for j in torn]
    origins = tuple(str(e.origin) for e in eqs)
    # Express the residuals in the tearing unknowns only
    substitution: dict = {}
    for a in inner:
        substitution[symbols[a.variable]] = a.expression.xreplace(substitution)
    residuals = [eqs[i].residual.xreplace(substitution) for i in residual_eqs]
    tear_syms = [symbols[n] for n in tears]
    jacobian = [[_coefficient(r, z) for z in tear_syms] for r in residuals]
    if all(not entry.has(*tear_syms) for row in jacobian for entry in row):
        zero = {z: sp.Integer(0) for z in tear_syms}
        b = tuple(-r.xreplace(zero) for r in residuals)
        return (LinearSolve(tuple(tears), tuple(tuple(row) for row in jacobian), b, tuple(inner), origins),
                guards)
    return NewtonSolve(tuple(tears), tuple(inner), tuple(eqs[i].residual for i in residual_eqs), origins), guards
