"""``delay(expr, delayTime[, delayMax])``: the delayed value as an input of the generated code.

Flattening (:func:`extract_delays`) rewrites every ``delay(u, T[, Tmax])`` of
a continuous equation into two things:

* a hidden variable ``<component>.$delayK`` with the equation ``$delayK = u``:
  every compiled system computes the delayed expression like any unknown, so
  the runtime can evaluate it at any past time from the recorded states;
* in place of the delay, :class:`DelayedValue` applied to ``(K, time, T, Tmax)``
  (``Tmax = T`` for a fixed delay): a function of time only, as a table of time
  is, whose implementation the generated code calls.  It reads the history of
  the run in progress (:func:`activate`, set by :mod:`acausal.runtime.delays`).

At the start time ``time - T <= time.start``, so the delay is ``u`` itself: the
initialization problem reads the hidden variable in place of the delayed value
(:func:`at_start`).

The class is one module-level class with a module-level implementation
(:func:`~acausal.compiler.run_context.delayed_value`, light: a saved run calls
it without the compiler): the persistent compile cache finds it by name in the
flat equations, and a pickled translation refers to it by reference.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Mapping

import sympy as sp

from ..errors import ModelDefinitionError
from ..hybrid import Delay
from ..language import real_symbol, time
from .run_context import activate, active_history, delayed_value

__all__ = ["FlatDelay", "DelayedValue", "extract_delays", "at_start", "activate", "active_history",
           "DELAY_STEM"]

#: The stem of the hidden variables: ``<component>.$delay3``.
DELAY_STEM = "$delay"

class DelayedValue(sp.Function):
    """``DelayedValue(k, time, T, Tmax)``: the value of delay ``k``'s expression at ``time - T``.

    Made by flattening in place of ``delay(u, T, Tmax)``; evaluated by the
    runtime's history.  Its time derivative is not available (index reduction
    through a delayed value is not supported).
    """

    nargs = 4
    _imp_ = staticmethod(delayed_value)

    def _eval_is_real(self):
        return True


@dataclass(frozen=True)
class FlatDelay:
    """One ``delay()`` of the flat model.

    Attributes
    ----------
    index : int
        ``k`` of its :class:`DelayedValue` and of the hidden variable.
    variable : str
        The hidden variable equal to the delayed expression.
    delay_time, delay_max : sympy expression
        ``delay_max`` is ``delay_time`` for a fixed delay.
    fixed : bool
        The delay time is an expression of parameters alone.
    component : str
        The component whose equation wrote the delay.
    text : str
        The delay as written, for messages.
    """

    index: int
    variable: str
    delay_time: sp.Expr
    delay_max: sp.Expr
    fixed: bool
    component: str
    text: str


def extract_delays(equations, variables: dict, parameters: Mapping, hidden_variable: Callable,
                   discrete_texts=(), equation_type: Callable = None) -> tuple[list, list[FlatDelay]]:
    """Replace every ``delay()`` of the continuous ``equations`` (see the module docstring).

    Parameters
    ----------
    equations : list of FlatEquation
    variables : dict
        The flat variables by name (only read).
    parameters : mapping
        The names of the numeric parameters (a delay time of these alone is fixed).
    hidden_variable : callable
        ``hidden_variable(component) -> name``: declares a new continuous variable.
    discrete_texts : iterable of (str, sympy expression)
        Where a delay may not appear (discrete equations, assertions), for the error.
    equation_type : callable
        ``equation_type(residual, origin)``: the flat equation (flattening's ``FlatEquation``).

    Returns
    -------
    (equations, delays)
        The new equations (the rewritten ones and one ``$delayK = u`` per delay).
    """
    FlatEquation = equation_type  # noqa: N806 - the data type of the equations handed in
    for where, expr in discrete_texts:
        if isinstance(expr, sp.Basic) and expr.has(Delay):
            raise ModelDefinitionError(f"delay() in {where}: delayed values are supported in continuous "
                                       f"equations only",
                                       hint="compute the delayed value in a continuous equation of a "
                                            "variable and use that variable here")
    delays: list[FlatDelay] = []
    added: list = []
    out = []
    for eq in equations:
        if not eq.residual.has(Delay):
            out.append(eq)
            continue
        residual = eq.residual
        # innermost first: a delay inside a delayed expression is replaced before its host
        while True:
            nodes = [n for n in sp.postorder_traversal(residual) if isinstance(n, Delay)]
            if not nodes:
                break
            node = nodes[0]
            replacement = _tap(node, eq.origin, len(delays), variables, parameters, hidden_variable,
                               delays, added, FlatEquation)
            residual = residual.xreplace({node: replacement})
        out.append(FlatEquation(residual, eq.origin))
    return out + added, delays


def _tap(node, origin, k: int, variables, parameters, hidden_variable, delays, added, equation_type):
    expr, delay_time = node.args[0], node.args[1]
    delay_max = node.args[2] if len(node.args) == 3 else None
    where = f"{origin.component or '(model)'}: delay({', '.join(map(str, node.args))})"

    def of_parameters(e) -> bool:
        return all(s.name in parameters for s in e.free_symbols)

    fixed = of_parameters(delay_time)
    if not fixed and delay_max is None:
        raise ModelDefinitionError(f"{where}: the delay time reads variables, so delay() needs "
                                   f"delayMax: delay(expr, delayTime, delayMax)",
                                   hint="give delayMax, a parameter expression bounding the delay time; "
                                        "the history kept is at least that long",
                                   components=(origin.component,))
    if delay_max is not None and not of_parameters(delay_max):
        raise ModelDefinitionError(f"{where}: delayMax must be an expression of parameters",
                                   components=(origin.component,))
    name = hidden_variable(origin.component)
    symbol = real_symbol(name)
    added.append(equation_type(symbol - expr, origin))
    delays.append(FlatDelay(k, name, delay_time, delay_time if fixed else delay_max, fixed,
                            origin.component, where.split(": ", 1)[1]))
    return DelayedValue(sp.Integer(k), time, delay_time, delay_time if fixed else delay_max)


def at_start(expr: sp.Expr, delays, substitution: Mapping | None = None) -> sp.Expr:
    """``expr`` at the start time: each delayed value is its expression's value now
    (its hidden variable, through ``substitution`` when alias elimination removed it)."""
    if not isinstance(expr, sp.Basic) or not expr.has(DelayedValue):
        return expr
    variable = {d.index: real_symbol(d.variable) for d in delays}
    substitution = substitution or {}

    def now(node):
        symbol = variable[int(node.args[0])]
        return substitution.get(symbol, symbol)

    return expr.replace(lambda n: isinstance(n, DelayedValue), now)
