"""How a relation's value is decided from its two sides: one rule, two implementations.

A relation ``lhs op rhs`` (``op`` one of ``>``, ``>=``, ``<``, ``<=``) is
decided on ``g = lhs - rhs``.  Between events the integrator must not flip
it on round-off, so its crossing is watched with a *margin* towards its
current value (hysteresis, Modelica tools do the same); at an event the
value is decided again, under the rules of :func:`decide`.

The rules are written once, in :func:`decide` (plain Python, fast for a
few relations), and once more with numpy in :func:`decide_many` (fast for
many).  The two must give the same answers for the same doubles:
``tests/runtime/test_relation_paths.py`` checks that on random relation
sets (time events at their instant, hysteresis, exact decisions, NaN and
infinite sides), and that whole simulations take the same events whichever
form the event iteration and the crossing watch use.

A relation is described by its *kind* ``(d, strict, timed)``: ``d = +1`` for
``>``/``>=`` and ``-1`` for ``<``/``<=`` (so that ``d*g > 0`` means "holds"
for a strict relation and ``d*g >= 0`` for a non-strict one), ``strict``, and
``timed``: a time event, whose crossing instant is computed in closed form
and which therefore needs no margin.
"""

from __future__ import annotations

from typing import Sequence

import numpy as np

__all__ = ["ROUND_OFF", "Kind", "decide", "decide_many", "kind_arrays"]

#: Relative size of ``lhs - rhs`` that counts as zero for a time event's relation at
#: its own instant: its crossing time is computed in closed form, so what is left of
#: g there is round-off (``(t - T_start) - width`` against ``t - (T_start + width)``).
ROUND_OFF = 1e-13

#: ``(d, strict, timed)``: see the module docstring.
Kind = tuple[float, bool, bool]


def decide(kinds: Sequence[Kind], raw: Sequence[float], previous: Sequence[bool],
           epsilon: float | Sequence[float], *, floor: float | Sequence[float] = 1.0,
           exact: bool = False, fired: frozenset = frozenset(),
           clear: Sequence[bool] | None = None) -> tuple[bool, ...]:
    """The relations' values at an event, from their sides ``raw`` (``lhs_0, rhs_0, lhs_1, ...``).

    The rules, in order, for relation ``k`` with ``g = lhs - rhs``:

    1. A time event that caused this event (``k in fired``) with ``|g|`` within
       round-off of its sides (:data:`ROUND_OFF`) is exactly at its instant:
       ``g`` counts as 0, and the relation takes its own value there (``time
       >= t1`` true, ``time < t1`` false).
    2. A relation whose sides are exactly equal, that was true and that the
       pass before decided clearly (``clear[k]``), stays true (not with
       ``exact``): the guess that pass made because it was true put it at its
       limit, which confirms the guess.
    3. With ``exact``, for a time event, for a relation in ``fired``, or for
       exactly equal sides: ``g`` itself decides.
    4. Otherwise ``g`` is moved by the margin ``epsilon * max(floor, |lhs|, |rhs|)``
       towards the relation's previous value (hysteresis); ``epsilon`` and
       ``floor`` are one number each, or one per relation (a relation free of
       integration noise has a round-off margin relative to its sides alone:
       floor 0).

    Then the relation holds when ``d*g > 0`` (strict) or ``d*g >= 0``.
    NaN sides make every comparison false, as in Python.
    """
    out = []
    margins = epsilon if isinstance(epsilon, (list, tuple)) else None
    floors = floor if isinstance(floor, (list, tuple)) else None
    for k, (d, strict, timed) in enumerate(kinds):
        lhs, rhs = raw[2 * k], raw[2 * k + 1]
        if margins is not None:
            epsilon = margins[k]
        if floors is not None:
            floor = floors[k]
        if timed and k in fired and abs(lhs - rhs) <= ROUND_OFF * max(1.0, abs(lhs), abs(rhs)):
            v = 0.0
        elif lhs == rhs and clear is not None and clear[k] and previous[k] and not exact:
            out.append(True)
            continue
        elif exact or timed or k in fired or lhs == rhs:
            v = d * (lhs - rhs)
        else:
            v = d * ((lhs - rhs) + (d if previous[k] else -d) * (epsilon * max(floor, abs(lhs), abs(rhs))))
        out.append(v > 0 if strict else v >= 0)
    return tuple(out)


def decide_many(kinds: Sequence[Kind], raw, previous: Sequence[bool], epsilon: float | Sequence[float], *,
                floor: float | Sequence[float] = 1.0, exact: bool = False, fired: frozenset = frozenset(),
                clear: Sequence[bool] | None = None, arrays=None) -> tuple[bool, ...]:
    """:func:`decide` with numpy: the same rules, in the same order, on the same doubles.

    ``arrays`` may pass ``kind_arrays(kinds)`` computed once.
    """
    d, strict, timed = kind_arrays(kinds) if arrays is None else arrays
    with np.errstate(invalid="ignore", over="ignore"):  # inf/NaN sides decide as in Python
        values = np.asarray(raw, dtype=float)
        lhs, rhs = values[0::2], values[1::2]
        g = lhs - rhs
        scale = np.maximum(np.maximum(np.abs(lhs), np.abs(rhs)), 1.0)
        in_fired = np.zeros(len(d), dtype=bool)
        if fired:
            in_fired[list(fired)] = True
        previous = np.asarray(previous, dtype=bool)
        # rule 1: a time event at its own instant
        at_root = timed & in_fired & (np.abs(g) <= ROUND_OFF * scale)
        # rule 2: kept true at its limit
        if clear is not None and not exact:
            kept = ~at_root & (lhs == rhs) & np.asarray(clear, dtype=bool) & previous
        else:
            kept = np.zeros(len(d), dtype=bool)
        # rules 3 and 4
        if exact:
            v = d * g
        else:
            plain = timed | in_fired | (lhs == rhs)
            toward = np.where(previous, d, -d)
            margin = np.asarray(epsilon, dtype=float) if isinstance(epsilon, (list, tuple)) else epsilon
            bottom = np.asarray(floor, dtype=float) if isinstance(floor, (list, tuple)) else floor
            sides = np.maximum(np.maximum(np.abs(lhs), np.abs(rhs)), bottom)
            v = d * np.where(plain, g, g + toward * (margin * sides))
        v = np.where(at_root, 0.0, v)
        holds = np.where(strict, v > 0, v >= 0) | kept
    return tuple(holds.tolist())


def kind_arrays(kinds: Sequence[Kind]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(d, strict, timed)`` of ``kinds`` as numpy arrays."""
    return (np.array([k[0] for k in kinds], dtype=float),
            np.array([k[1] for k in kinds], dtype=bool),
            np.array([k[2] for k in kinds], dtype=bool))
