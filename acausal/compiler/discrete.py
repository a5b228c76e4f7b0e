"""The discrete part of a model, compiled: discrete equations, reinits, terminations, assertions.

The runtime's event iteration (:class:`~acausal.runtime.events.DiscreteEvaluator`)
evaluates these functions by name; it asks a translation for them once
(:meth:`~acausal.compiler.translate.Translation.discrete_program`) and never
sees the symbolic expressions.  Impure functions
(:class:`~acausal.functions.ImpureFunction`: a random number generator's
next value) are bound here to their call sites, and each call site calls back
into the evaluator of the run (``impure_call``), which keeps the functions'
state.
"""

from __future__ import annotations

import functools
from typing import Callable

from ..functions import ImpureFunction, impure_applications
from ..table_calls import TABLE_CALLS
from .compiled import DiscreteProgram
from .codegen import functions_source
from .generated import load_functions

__all__ = ["DiscreteProgram", "compile_discrete", "ImpureSite"]


def _names(expr) -> list[str]:
    return sorted(s.name for s in expr.free_symbols)


def compile_discrete(flat, partitioned, impure_call: Callable) -> DiscreteProgram:
    """Compile the discrete equations of ``partitioned`` and the hybrid constructs of ``flat``.

    ``impure_call(site, function class, *args)`` is what each call site of an
    impure function evaluates (see :func:`_bind_impure_sites`).
    """
    equations = partitioned.discrete_equations
    arguments = [_names(eq.rhs) for eq in equations]
    right_sides, impure_sites = _bind_impure_sites([eq.rhs for eq in equations], impure_call)
    name = f"the discrete equations of {flat.name}"
    source, called = functions_source(arguments, right_sides, name)
    functions = load_functions(source, len(right_sides), name, called)
    compiled = tuple((eq.variable, args, fn, eq.origin) for eq, args, fn in zip(equations, arguments, functions))

    hybrid = flat.hybrid
    reinits, terminations, asserts = hybrid.reinits, hybrid.terminations, hybrid.asserts
    # one source for every function of the when-clauses and assertions, in this order:
    # the reinits' conditions, the reinits' values, the terminations', the assertions'
    expressions = [*(r.fires for r in reinits), *(r.value for r in reinits),
                   *(r.fires for r in terminations), *(a.condition for a in asserts)]
    context = f"the when-clauses of {flat.name}"
    hybrid_source, hybrid_called = functions_source([_names(e) for e in expressions], expressions, context)
    fns = load_functions(hybrid_source, len(expressions), context, hybrid_called)
    n_r, n_t = len(reinits), len(terminations)
    compiled_reinits = tuple((r, _names(r.fires), fns[i], _names(r.value), fns[n_r + i])
                             for i, r in enumerate(reinits))
    compiled_terminations = tuple((r, _names(r.fires), fns[2 * n_r + i]) for i, r in enumerate(terminations))
    compiled_asserts = tuple((a, _names(a.condition), fns[2 * n_r + n_t + i]) for i, a in enumerate(asserts))
    # a source that calls tables alone can be saved with them (acausal.table_calls); an impure
    # function's call site calls back into the run's evaluator: its source is not saved
    saveable = all(isinstance(f, TABLE_CALLS) for f in (*called.values(), *hybrid_called.values()))
    return DiscreteProgram(compiled, impure_sites, compiled_reinits, compiled_terminations, compiled_asserts,
                           source if saveable else None, hybrid_source if saveable else None,
                           {**called, **hybrid_called} if saveable else {})


def _bind_impure_sites(expressions, call: Callable) -> tuple[list, int]:
    """``expressions`` with every impure application replaced by a function of its
    own call site, whose code calls ``call(site, function class, *args)``; and the
    number of sites.  Sites are numbered equation by equation (inner calls first)."""
    out, site = [], 0
    for expr in expressions:
        found = impure_applications(expr)
        if not found:
            out.append(expr)
            continue
        replaced: dict = {}
        for application in found:  # inner calls first: their replacements go into the outer ones
            cls = type(application)
            bound = type(f"{cls.__name__}_site{site}", (ImpureSite,), {
                "__module__": __name__, "_imp_": staticmethod(functools.partial(call, site, cls))})
            replaced[application] = bound(*(a.xreplace(replaced) for a in application.args))
            site += 1
        out.append(expr.xreplace(replaced))
    return out, site


class ImpureSite(ImpureFunction):
    """One call site of an impure function in the compiled discrete equations
    (made by :func:`_bind_impure_sites`; its ``_imp_`` calls the run's evaluator)."""
