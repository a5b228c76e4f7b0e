"""Expressions up to a renaming of their symbols: the repeated structure of a model.

A model of N equal units (a drive train of N inertia–bearing–spring units)
has N copies of each solution step that differ only in the names of their
variables and parameters.  :func:`shape` gives a key for such a copy that
does not depend on the names, and the symbols in the order the key numbers
them.  The stages do their symbolic work once per key and rename the result
for the other copies: specialisation and the alias substitution
(:func:`substituted`), solving an equation for one unknown
(:mod:`~acausal.compiler.algebraic`), differentiating one for index
reduction (:mod:`~acausal.compiler.structure`), printing a step (the code
generator keeps the text of one copy as a format string of the identifiers,
:mod:`~acausal.compiler.codegen`).  A renamed expression is rebuilt by
:func:`rename`, without sympy's evaluation.

The renaming is *order-preserving*: symbols are numbered in the order of
their names, so two copies have one key only when their symbols compare in
the same order.  Everything sympy decides by comparing symbols (the order of
the terms of a sum and the factors of a product, which the printed code
evaluates in that order, and what common subexpression elimination finds)
is then the same for both: the renamed text is the text printed for the
copy itself, character for character (``inertia9``/``spring10`` order
differently from ``inertia1``/``spring2``, and get a key of their own).

Numbers and other atoms are part of the key by value (a unit whose
parameter was evaluated to another number is another shape), functions by
their class and implementation (two tables of one name differ).
"""

from __future__ import annotations

from typing import Sequence

import sympy as sp

__all__ = ["Shape", "shape", "placeholders", "rename", "to_placeholders", "from_placeholders", "substituted"]

#: what :func:`shape` returns: (key, names in the order the key numbers them, the symbols by name)
Shape = tuple[tuple, tuple[str, ...], dict]

_SYMBOL = sp.Symbol
#: the assumptions of symbols, numbered (a key holds the number)
_ASSUMPTIONS: dict = {}


#: the token of a node that is no atom: (class, number of arguments) -> token
_TOKENS: dict = {}


def _token(kind, n: int):
    found = _TOKENS.get((kind, n))
    if found is None:
        # (a function by its implementation too: two tables of one name are different)
        found = _TOKENS[(kind, n)] = ((kind, n, getattr(kind, "_imp_", None)) if issubclass(kind, sp.Function)
                                      else (kind, n))
    return found


#: stands, in a key, before what replaces a symbol
_REPLACED = ("replaced",)


def _walk(root, tokens: list, at: list, symbols: dict, substitution) -> bool:
    """Append the tokens of ``root`` in preorder (a symbol that ``substitution`` replaces:
    the tokens of what replaces it); False when it cannot be renamed."""
    stack = [root]
    pop, push, append = stack.pop, stack.extend, tokens.append
    while stack:
        node = pop()
        if isinstance(node, _SYMBOL):
            if substitution is not None:
                replacement = substitution.get(node)
                if replacement is not None and replacement is not node:
                    append(_REPLACED)
                    if not _walk(replacement, tokens, at, symbols, None):
                        return False
                    continue
            name = node.name
            seen = symbols.get(name)
            if seen is None:
                if type(node) is not _SYMBOL:
                    return False
                symbols[name] = node
            elif seen is not node and seen != node:
                return False
            at.append(len(tokens))
            append(name)
            continue
        args = node.args
        if not args:
            append((type(node), node._hashable_content()))
            continue
        append(_token(type(node), len(args)))
        push(reversed(args))
    return True


def shape(roots: Sequence[sp.Basic], names: Sequence[str] = (), head: tuple = (),
          substitution: dict | None = None) -> Shape | None:
    """The key of ``roots`` (and of the variable ``names`` a step defines) up to an
    order-preserving renaming, the names in their order, and the symbols of ``roots``
    by name; None when the expressions hold something the renaming cannot stand for
    (a symbol of another class, two symbols of one name, an argument that is no
    sympy object).  With ``substitution`` (symbol -> expression), the key of the
    roots with their symbols so replaced (and the symbols of what replaces them)."""
    tokens: list = list(head)
    tokens.append(len(roots))
    at: list[int] = []  # positions of symbol names in ``tokens``
    symbols: dict[str, sp.Symbol] = {}
    try:
        for root in roots:
            if not _walk(root, tokens, at, symbols, substitution):
                return None
    except AttributeError:  # an argument that is no sympy object
        return None
    order = sorted(set(symbols).union(names)) if names else sorted(symbols)
    rank = {n: k for k, n in enumerate(order)}
    for k in at:
        tokens[k] = rank[tokens[k]]
    tokens.append(tuple(rank[n] for n in names))
    # (the assumptions of each symbol: a placeholder stands for symbols of its own)
    numbers = _ASSUMPTIONS
    tokens.append(tuple(numbers.setdefault(symbols[n]._assumptions0, len(numbers)) if n in symbols else -1
                        for n in order))
    return tuple(tokens), tuple(order), symbols


def placeholder_name(k: int) -> str:
    """The name standing for the ``k``-th symbol of a shape (names of one length sort as ``k``)."""
    return f"_Q{k:07d}"


def placeholders(roots: Sequence[sp.Basic], order: Sequence[str]) -> tuple[dict, dict[str, str]]:
    """``(substitution, names)``: the symbols of ``roots`` -> their placeholder symbols
    (same assumptions), and every name of ``order`` -> its placeholder's name."""
    names = {n: placeholder_name(k) for k, n in enumerate(order)}
    substitution = {}
    for root in roots:
        for s in root.free_symbols:
            if s not in substitution:
                substitution[s] = placeholder(order.index(s.name), s)
    return substitution, names


def rename(expr: sp.Basic, mapping: dict) -> sp.Basic:
    """``expr`` with its symbols replaced by the symbols ``mapping`` gives them, which
    compare among themselves as those they replace do (an order-preserving renaming).

    Sums and products are rebuilt with their arguments in the order they have (the
    canonical order, which such a renaming keeps), without sympy's evaluation, the
    slow part of ``xreplace``; powers and applied functions without evaluation too
    (a renamed argument is a symbol of the same assumptions); other nodes as sympy
    builds them.
    """
    return _renamed(expr, mapping, {})


def _renamed(node, mapping: dict, done: dict):
    """:func:`rename` of ``node`` (``done``: the nodes renamed so far; a function of the
    module, not a closure, which would be a reference cycle for the collector to free)."""
    if isinstance(node, _SYMBOL):
        return mapping.get(node, node)
    args = node.args
    if not args:
        return node
    found = done.get(node)
    if found is not None:
        return found
    new = tuple([_renamed(a, mapping, done) for a in args])
    kind = type(node)
    if new == args:
        out = node
    elif kind is sp.Add or kind is sp.Mul:
        out = kind._from_args(new, node.is_commutative)
    elif kind is sp.Pow:
        out = sp.Pow(*new, evaluate=False)
    elif isinstance(node, sp.Function):
        # an applied function (sin, a table) as it was built for the first copy: its
        # evaluation decided on arguments that compare as these do
        out = node.func(*new, evaluate=False)
    else:
        out = node.func(*new)
    done[node] = out
    return out


_PLACEHOLDERS: dict = {}


def placeholder(k: int, symbol: sp.Symbol) -> sp.Symbol:
    """The ``k``-th placeholder, with the assumptions of ``symbol``."""
    key = (k, symbol._assumptions0)
    found = _PLACEHOLDERS.get(key)
    if found is None:
        if len(_PLACEHOLDERS) > 100_000:
            _PLACEHOLDERS.clear()
        found = _PLACEHOLDERS[key] = sp.Symbol(placeholder_name(k), **symbol.assumptions0)
    return found


def to_placeholders(expr: sp.Basic, order: Sequence[str], symbols: dict) -> sp.Basic | None:
    """``expr`` (of the symbols named in ``order``, ``symbols``: them by name) with each
    symbol renamed to its placeholder; None when it holds another symbol."""
    if not expr.free_symbols <= set(symbols.values()):
        return None
    return rename(expr, {symbols[n]: placeholder(k, symbols[n]) for k, n in enumerate(order) if n in symbols})


def from_placeholders(template: sp.Basic, order: Sequence[str], symbols: dict) -> sp.Basic:
    """A template of :func:`to_placeholders` with the symbols of another copy put back."""
    return rename(template, {placeholder(k, symbols[n]): symbols[n] for k, n in enumerate(order) if n in symbols})


def substituted(expr: sp.Basic, substitution: dict, memo: dict, exact: dict | None = None) -> sp.Basic:
    """``expr.xreplace(substitution)`` (whose keys are symbols), computed once per shape of
    the expression with its symbols replaced, and renamed for the other copies.

    ``exact`` (optional) keeps the result per expression, returned again (the same
    object) while what replaces its symbols is the same: the stages after it find their
    memos' entries by identity, not by comparing expressions.
    """
    if exact is not None:
        found = exact.get(expr)
        if found is not None:
            replaced, result = found
            if all((now := substitution.get(symbol)) is target or now == target for symbol, target in replaced):
                return result
    found = shape((expr,), substitution=substitution)
    if found is None:
        return expr.xreplace(substitution)
    key, order, symbols = found
    if _REPLACED not in key:
        result = expr  # (nothing to replace)
    else:
        template = memo.get(key, False)
        if template is False:
            result = expr.xreplace(substitution)
            memo[key] = to_placeholders(result, order, symbols)
        elif template is None:
            result = expr.xreplace(substitution)
        else:
            result = from_placeholders(template, order, symbols)
    if exact is not None:
        # (the symbols of expr: those of the key that are no replacement's)
        own = expr.free_symbols
        exact[expr] = (tuple((s, substitution.get(s)) for s in own), result)
    return result
