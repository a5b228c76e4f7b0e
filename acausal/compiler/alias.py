"""Stage 4: alias elimination.

Connections produce many equations of the forms ``a = b``, ``a = -b`` and
``a = constant``.  Each set of variables joined by such equations keeps one
representative; the others become aliases (``±representative`` or a
constant) and vanish from the equation system.  Every eliminated name stays
available in results through :attr:`AliasResult.aliases`.

An equation that becomes such a form once the constants found are put in
(``phi_rel = flange_b.phi - flange_a.phi`` with ``flange_a.phi = 0``) is an
alias equation too: after the pass over the equations in their order, the
equations left that are linear with numeric coefficients are taken again,
their constant members folded into the constant, until a pass finds nothing
new (the passes follow the equations' order, so the result is the same every
run).

The representative is the member most likely to be wanted as a state:
highest ``state_select``, then one that appears differentiated, then one with
a fixed start value, then a component variable before a connector variable,
then the one declared first.  Start attributes are merged into it (with the sign
of the alias); two different fixed start values are an error.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import sympy as sp

from ..errors import InitializationError
from ..names import base_name, der_name, derivative_order, is_derivative
from .canonical import substituted
from .flatten import FlatEquation, FlatVariable
from ..language import real_symbol, time

__all__ = ["AliasMemo", "AliasResult", "eliminate_aliases"]


@dataclass(eq=False)
class AliasMemo:
    """What alias elimination keeps for the other discrete states of one model.

    Valid for one set of variables, parameters and ``keep`` (``inputs``,
    checked on every use).
    """

    inputs: tuple | None = None
    candidates: set[str] = field(default_factory=set)  #: variables that may be eliminated
    forms: dict = field(default_factory=dict)  #: residual -> its alias form, or None
    linear: dict = field(default_factory=dict)  #: residual -> its linear form, or None
    derivatives: dict = field(default_factory=dict)  #: residual -> the derivatives it reads
    #: the substitution of the aliases, once per shape (:func:`~acausal.compiler.canonical.substituted`)
    shapes: dict = field(default_factory=dict)
    #: residual -> (its symbols with what replaced them, the result): the same object again
    substituted: dict = field(default_factory=dict)


@dataclass(frozen=True)
class AliasResult:
    """The output of :func:`eliminate_aliases`.

    Attributes
    ----------
    equations : tuple of FlatEquation
        The equations left, with aliases substituted.
    aliases : dict
        ``eliminated name -> expression`` of representatives and parameters.
    variables : dict
        ``name -> FlatVariable`` for the variables left, attributes merged.
    eliminated : tuple of FlatEquation
        The alias equations removed.
    fixed_constants : tuple
        ``(name, expression, start)`` for fixed variables found to be
        constant: checked at initialization.
    """

    equations: tuple[FlatEquation, ...]
    aliases: dict
    variables: dict
    eliminated: tuple[FlatEquation, ...]
    fixed_constants: tuple


def _linear_form(residual: sp.Expr, unknowns: set[str], parameters: set[str]):
    """``([(name, coefficient), ...], constant)`` if the residual is a sum of terms
    ``c*a`` (``c`` a number, ``a`` one of ``unknowns``) and a constant of numbers and
    parameters (not time); None otherwise."""
    found = []
    constant = sp.Integer(0)
    for term in sp.Add.make_args(residual):
        coeff, rest = term.as_coeff_Mul()
        if isinstance(rest, sp.Symbol) and rest.name in unknowns:
            found.append((rest.name, coeff))
        elif not term.has(time) and all(s.name in parameters for s in term.free_symbols):
            constant += term
        else:
            return None
    return found, constant


def _is_alias(found, constant) -> bool:
    """Whether a linear form is alias-like: ``c*a + constant`` (c a non-zero number) or
    ``a ± b``, where constants are numbers and parameters (not time)."""
    if len(found) == 1 and found[0][1] != 0:
        return True
    return len(found) == 2 and constant == 0 and abs(found[0][1]) == abs(found[1][1]) != 0


def eliminate_aliases(equations: tuple[FlatEquation, ...], variables: dict[str, FlatVariable],
                      parameters: set[str], keep: frozenset[str] = frozenset(),
                      memo: AliasMemo | None = None) -> AliasResult:
    """Remove alias equations from ``equations``.

    Parameters
    ----------
    equations : tuple of FlatEquation
    variables : dict
        The continuous unknowns and their attributes.
    parameters : set of str
        Names of parameters (constants for this purpose).
    keep : frozenset of str
        Variables that must not be eliminated.
    memo : AliasMemo, optional
        Shared by calls with the same variables, parameters and ``keep`` (the
        discrete states of one model): keeps the alias form of each equation.
    """
    memo = AliasMemo() if memo is None else memo
    if memo.inputs is None:
        memo.inputs = (variables, parameters, keep)
        memo.candidates = {n for n, v in variables.items() if not v.is_discrete} - keep
    elif memo.inputs != (variables, parameters, keep):
        raise ValueError("eliminate_aliases: this memo belongs to other variables or parameters")
    candidates = memo.candidates
    derivatives_in = memo.derivatives
    differentiated = set()
    for eq in equations:
        found = derivatives_in.get(eq.residual)
        if found is None:
            found = derivatives_in[eq.residual] = \
                tuple(s for s in eq.residual.free_symbols if is_derivative(s.name)) or ()
        for sym in found:
            differentiated.add(base_name(sym.name))

    parent: dict[str, str] = {}
    sign: dict[str, int] = {}  # x = sign[x] * parent[x]
    constant_of: dict[str, sp.Expr] = {}  # root -> value

    def find(x: str) -> tuple[str, int]:
        path_sign = 1
        node = x
        chain = []
        while parent.get(node, node) != node:
            chain.append(node)
            path_sign *= sign[node]
            node = parent[node]
        # compress
        running = path_sign
        for member in chain:
            s = running
            running *= sign[member]
            parent[member], sign[member] = node, s
        return node, path_sign

    def join(found, constant) -> bool:
        """Record the alias equation ``sum(c*a) + constant = 0``; False if it is kept."""
        if len(found) == 1:
            (name, coeff), = found
            root, s = find(name)
            if root in constant_of:
                return False
            # coeff*name + constant = 0 -> name = -constant/coeff; root = s*name
            constant_of[root] = sp.nsimplify(s) * (-constant / coeff)
            return True
        (a, ca), (b, cb) = found
        ra, sa = find(a)
        rb, sb = find(b)
        if ra == rb:
            return False
        if ra in constant_of and rb in constant_of:
            return False
        # ca*a + cb*b = 0 -> a = s*b with s = -cb/ca (= ±1)
        s = int(-cb / ca)
        # a = sa*ra, b = sb*rb  ->  ra = sa*s*sb*rb
        link = sa * s * sb
        if ra in constant_of:  # move the constant to the surviving root
            constant_of[rb] = link * constant_of.pop(ra)
        parent[ra], sign[ra] = rb, link
        return True

    kept_at: list[int] = []  # positions in ``equations``
    removed_at: list[int] = []
    for k, eq in enumerate(equations):
        form = memo.forms.get(eq.residual, False)
        if form is False:
            linear = memo.linear[eq.residual] = _linear_form(eq.residual, candidates, parameters)
            form = memo.forms[eq.residual] = linear if linear is not None and _is_alias(*linear) else None
        (removed_at if form is not None and join(*form) else kept_at).append(k)

    # Equations that are alias equations once the constants are in (a = b - c with c = 0),
    # pass after pass in the equations' order until a pass finds none.
    changed = bool(constant_of)
    while changed:
        changed = False
        still: list[int] = []
        for k in kept_at:
            residual = equations[k].residual
            # (an equation alias-like as written and kept joins nothing new)
            form = None if memo.forms.get(residual) is not None else \
                _folded(residual, memo, candidates, parameters, find, constant_of)
            if form is not None and join(*form):
                removed_at.append(k)
                changed = True
            else:
                still.append(k)
        kept_at = still
    eliminated = [equations[k] for k in sorted(removed_at)]  # in the equations' order
    kept = [equations[k] for k in kept_at]

    # group members by root, choose representatives
    groups: dict[str, list[str]] = {}
    for name in list(parent):
        root, _ = find(name)
        groups.setdefault(root, []).append(name)
    for root in list(constant_of):
        groups.setdefault(root, [root])

    declared = {name: k for k, name in enumerate(variables)}

    def score(name: str):
        v = variables[name]
        return (-int(v.state_select), -(name in differentiated), -int(v.fixed),
                v.role != "", name.count("."), declared[name])

    aliases: dict[str, sp.Expr] = {}
    merged: dict[str, FlatVariable] = {}
    fixed_constants = []
    for root in sorted(groups):
        members = sorted(set(groups[root]) | {root})
        rel = {m: find(m)[1] for m in members}  # m = rel[m] * root
        if root in constant_of:
            value = constant_of[root]
            for m in members:
                aliases[m] = rel[m] * value
                if variables[m].fixed:
                    fixed_constants.append((m, rel[m] * value, variables[m].start))
            continue
        rep = min(members, key=score)
        rep_sym = real_symbol(rep)
        for m in members:
            if m != rep:
                aliases[m] = rel[m] * rel[rep] * rep_sym  # m = rel[m]*root = rel[m]*rel[rep]*rep
        merged[rep] = _merge(rep, members, {m: rel[m] * rel[rep] for m in members}, variables)

    for name, var in variables.items():
        if name not in aliases and name not in merged and not var.is_discrete:
            merged[name] = var
    # declaration order, so later stages break ties the way the model reads
    merged = {name: merged[name] for name in variables if name in merged}

    substitution = {real_symbol(n): e for n, e in aliases.items()}
    for eq in kept:  # (derivative_substitution reads the derivatives only)
        substitution.update(derivative_substitution(derivatives_in[eq.residual], aliases, merged, substitution))
    new_equations = tuple(FlatEquation(substituted(eq.residual, substitution, memo.shapes, memo.substituted),
                                       eq.origin)
                          for eq in kept)
    return AliasResult(new_equations, aliases, merged, tuple(eliminated), tuple(fixed_constants))


def derivative_substitution(symbols, aliases: dict, representatives, known=()) -> dict:
    """``der(a) -> s*der(rep)`` (or 0 for a constant) for the derivatives of aliases among ``symbols``.

    An alias is ``a = s*rep`` (or a constant), so its derivatives are those
    of its representative times ``s``; ``known`` lists symbols already handled.
    """
    found = {}
    for sym in symbols:
        if is_derivative(sym.name) and base_name(sym.name) in aliases and sym not in known:
            order = derivative_order(sym.name)
            expr = aliases[base_name(sym.name)]
            rep_syms = [s for s in expr.free_symbols if s.name in representatives]
            if not rep_syms:
                found[sym] = sp.Integer(0)
            else:
                (rep_sym,) = rep_syms
                found[sym] = expr.coeff(rep_sym) * real_symbol(der_name(rep_sym.name, order))
    return found


def _folded(residual: sp.Expr, memo: AliasMemo, candidates: set[str], parameters: set[str], find,
            constant_of: dict):
    """The alias form of a linear residual whose members found to be constants are folded
    into its constant (``a - b - c`` with ``c = 0``: ``a - b``), or None.

    Only constants are folded: the members left are the equation's own, so that
    ``join`` links them as it links those of an equation written so.
    """
    form = memo.linear.get(residual, False)
    if form is False:
        form = memo.linear[residual] = _linear_form(residual, candidates, parameters)
    if form is None:
        return None
    found, constant = form
    left = []
    folded = False
    for name, coeff in found:
        root, s = find(name)
        if root in constant_of:
            constant = constant + coeff * s * constant_of[root]  # name = s*root
            folded = True
        else:
            left.append((name, coeff))
    if not folded or not left:
        return None
    constant = sp.expand(constant)
    return (left, constant) if _is_alias(left, constant) else None


def _merge(rep: str, members: list[str], factor: dict[str, int], variables: dict[str, FlatVariable]):
    """Attributes of the representative from all members (``m = factor[m] * rep``)."""
    base = variables[rep]
    fixed_from = None
    start = base.start
    for m in members:
        v = variables[m]
        if v.fixed:
            value = factor[m] * v.start
            if fixed_from is not None and abs(value - start) > 1e-10 * max(1.0, abs(start)):
                raise InitializationError(
                    f"conflicting initial values: {fixed_from} has fixed start "
                    f"{variables[fixed_from].start} and {m} has fixed start {v.start}, but they are "
                    f"connected so that {m} = {'-' if factor[m] * factor[fixed_from] < 0 else ''}"
                    f"{fixed_from}",
                    hint="remove fixed=True from one of them")
            if fixed_from is None:
                fixed_from, start = m, value
    if fixed_from is None:
        # no fixed value: take a non-zero start as the guess, representative first
        for m in [rep] + [x for x in members if x != rep]:
            if variables[m].start != 0:
                start = factor[m] * variables[m].start
                break
    state_select = max(variables[m].state_select for m in members)
    nominal = max(variables[m].nominal for m in members)
    return replace(base, start=start, fixed=fixed_from is not None, state_select=state_select,
                   nominal=nominal)
