"""When things happen, from the parameters: time events, sample clocks and delay times.

The runtime asks these numbers of a translation
(:meth:`~acausal.compiler.translate.Translation.time_events`,
:meth:`~acausal.compiler.translate.Translation.clock_ticks`,
:meth:`~acausal.compiler.translate.Translation.delay_numbers`) once per run;
the symbolic work (a relation's slope in time, a clock's interval, a delay
time as an expression of parameters) stays here, with the compiler, so that
the runtime handles numbers and functions only.
"""

from __future__ import annotations

import math
from typing import Callable, Mapping, Sequence

import sympy as sp

from ..errors import ModelDefinitionError
from ..language import time as time_symbol
from .codegen import functions_source
from .generated import load_functions

__all__ = ["time_event_roots", "held_time_events", "held_time_event_source", "clock_ticks", "delay_numbers"]


def time_event_roots(relations: Sequence, parameter_symbols: Mapping) -> tuple[tuple[int, float], ...]:
    """``(relation index, instant)`` of every time event (``inf`` if it never crosses).

    Kept for the last few ``(relations, parameter_symbols)`` seen (the same objects,
    holding the same values): each run of a translation asks again, and the
    symbolic work costs a fraction of a millisecond.
    """
    key = (id(relations), id(parameter_symbols))
    values = tuple(item for pair in parameter_symbols.items() for item in pair)
    found = _ROOTS.get(key)
    if (found is not None and found[0] is relations and found[1] is parameter_symbols
            and len(found[2]) == len(values) and all(a is b for a, b in zip(found[2], values))
            and len(found[3]) == len(relations) and all(a is b for a, b in zip(found[3], relations))):
        return found[4]
    roots = _time_event_roots(relations, parameter_symbols)
    _ROOTS[key] = (relations, parameter_symbols, values, tuple(relations), roots)
    while len(_ROOTS) > 16:
        del _ROOTS[next(iter(_ROOTS))]
    return roots


#: (id(relations), id(parameter symbols)) -> (relations, symbols, their items, the relations, roots)
_ROOTS: dict = {}


def _time_event_roots(relations: Sequence, parameter_symbols: Mapping) -> tuple[tuple[int, float], ...]:
    roots = []
    for rel in relations:
        if rel.is_time_event:
            g = sp.sympify(rel.g).xreplace(parameter_symbols)
            if g.free_symbols - {time_symbol}:
                continue  # reads held values: see held_time_events
            slope = float(sp.diff(g, time_symbol))
            offset = float(g.xreplace({time_symbol: 0}))
            roots.append((rel.index, -offset / slope if slope else math.inf))
    return tuple(roots)


def held_time_events(relations: Sequence, parameter_symbols: Mapping) -> tuple[
        tuple[int, tuple[str, ...], Callable[..., float]], ...]:
    """The time events whose crossing time depends on held discrete Reals.

    ``time >= t_next`` with a discrete ``t_next`` crosses at ``t_next``: a time
    event, but one whose instant is known only once the event that sets
    ``t_next`` is over.  Returns ``(relation index, names, root)`` per such
    relation, ``root(*values)`` being the crossing time for the held values
    of ``names`` (made from :func:`held_time_event_source`).
    """
    source, items = held_time_event_source(relations, parameter_symbols)
    roots = load_functions(source, len(items), "the held time events")
    return tuple((index, names, root) for (index, names), root in zip(items, roots))


def held_time_event_source(relations: Sequence, parameter_symbols: Mapping) -> tuple[
        str, tuple[tuple[int, tuple[str, ...]], ...]]:
    """The generated source of the held time events' roots (``_f0``, ``_f1``, ... as
    :func:`~acausal.compiler.codegen.functions_source` writes them) and ``(relation
    index, names of the held values)`` per root: what a saved run keeps of them."""
    items, expressions = [], []
    for rel in relations:
        if not rel.is_time_event:
            continue
        g = sp.sympify(rel.g).xreplace(parameter_symbols)
        held = sorted((s for s in g.free_symbols if s is not time_symbol), key=lambda s: s.name)
        if not held:
            continue
        slope = sp.diff(g, time_symbol)
        offset = g.xreplace({time_symbol: 0})
        items.append((rel.index, tuple(s.name for s in held)))
        expressions.append(sp.Piecewise((-offset / slope, sp.Ne(slope, 0)), (sp.oo, True)))
    source, _calls = functions_source([names for _index, names in items], expressions, "the held time events")
    return source, tuple(items)


def clock_ticks(clocks: Sequence, parameter_symbols: Mapping) -> tuple[tuple[float, float], ...]:
    """``(start, interval)`` of every sample clock, as numbers.

    Raises
    ------
    ValueError
        For an interval that is not a positive finite number.
    """
    out = []
    for clock in clocks:
        start = float(sp.sympify(clock.start).xreplace(parameter_symbols))
        interval = float(sp.sympify(clock.interval).xreplace(parameter_symbols))
        if not (math.isfinite(start) and math.isfinite(interval) and interval > 0):
            raise ValueError(f"{clock.text}: the interval must be a positive number and the start "
                             f"finite (start = {start}, interval = {interval})")
        out.append((start, interval))
    return tuple(out)


def delay_numbers(delays: Sequence, parameter_symbols: Mapping) -> dict[int, float]:
    """Delay index -> its delay time (a fixed delay) or its ``delayMax`` (a variable one),
    as numbers for these parameter values.

    Raises
    ------
    ModelDefinitionError
        For a delay time that is not a number for these values.
    """
    numbers = {}
    for d in delays:
        expr = d.delay_time if d.fixed else d.delay_max
        value = sp.sympify(expr).xreplace(parameter_symbols)
        try:
            numbers[d.index] = float(value)
        except TypeError:
            raise ModelDefinitionError(f"the delay time {expr} is not a number for these parameter values",
                                       components=(d.component,) if d.component else ()) from None
    return numbers
