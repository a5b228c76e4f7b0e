"""Boolean forms of ``initial()`` and ``pre(b)`` for use inside ``And``/``Or``/``Not``.

``acausal.language.initial`` and ``pre`` are plain sympy undefined functions,
so ``initial()`` and ``pre(startForward)`` are sympy *expressions*, and sympy's
logic functions reject them (``And(initial(), w > 0)`` raises ``TypeError:
expecting bool or Boolean``).  :func:`is_initial` and :func:`pre_boolean`
return objects that are sympy Booleans, compare equal to ``initial()`` and
``pre(b)`` and have the same ``func`` (so ``acausal.compiler.flatten`` rewrites them to
the symbols ``initial()`` and ``pre(b)`` as usual).  If the language ever
makes ``initial()``/``pre(b)`` Boolean by itself, these helpers return them
unchanged.

``pre(mode)`` of an Integer stays an expression: compare it with
``sympy.Eq(pre(self.mode), Stuck)``.
"""

from __future__ import annotations

import sympy as sp
from sympy.core.function import AppliedUndef, UndefinedFunction
from sympy.logic.boolalg import Boolean as SympyBoolean

from acausal.language import initial, pre

__all__ = ["is_initial", "pre_boolean"]


def _uncached_new(cls, *args):
    # Function.__new__ is cached and the twin class compares equal to the
    # language's function, so a cached (non-Boolean) application could be
    # returned; build the object directly instead.
    return sp.Basic.__new__(cls, *map(sp.sympify, args))


def _boolean_twin(function) -> type:
    """A Boolean-valued undefined function equal (as a class) to ``function``."""
    return UndefinedFunction(function.__name__, bases=(AppliedUndef, SympyBoolean),
                             __dict__={"__new__": _uncached_new}, **dict(function._kwargs))


_INITIAL = _boolean_twin(initial)
_PRE = _boolean_twin(pre)


def is_initial() -> SympyBoolean:
    """``initial()`` usable as a Boolean: true only during initialization."""
    value = initial()
    return value if isinstance(value, SympyBoolean) else _INITIAL()


def pre_boolean(variable: sp.Symbol) -> SympyBoolean:
    """``pre(variable)`` of a Boolean variable, usable in ``And``/``Or``/``Not``."""
    value = pre(variable)
    return value if isinstance(value, SympyBoolean) else _PRE(variable)
