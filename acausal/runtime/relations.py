"""How a relation's value is decided from its two sides: one rule, two implementations.

A relation ``lhs op rhs`` (``op`` one of ``>``, ``>=``, ``<``, ``<=``) is
decided on ``g = lhs - rhs``.  Between events the integrator must not flip
it on round-off, so its crossing is watched with a *margin* towards its
current value (hysteresis, Modelica tools do the same); at an event the
value is decided again, under the rules of :func:`decide`.

Hysteresis itself is written here once, in two forms side by side: the
margin (:func:`margin`), the relation's ``g`` moved by it towards the value
the relation had (:func:`shifted`), whether a value holds (:func:`holds`),
and whether a relation was decided beyond its margin
(:func:`decided_clearly`), each in plain Python (fast for a few relations)
and with numpy (``..._many``, fast for many).  Every place that decides a
relation goes through them: the rules at an event (:func:`decide`,
:func:`decide_many`), and the crossing watch and the search of a flip's
instant (:class:`acausal.runtime.relation_evaluator.RelationEvaluator`).
The two forms must give the same answers for the same doubles:
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

__all__ = ["ROUND_OFF", "Kind", "decide", "decide_many", "decided_clearly", "decided_clearly_many", "holds",
           "holds_many", "kind_arrays", "margin", "margin_many", "shifted", "shifted_many", "sides_many"]

#: Relative size of ``lhs - rhs`` that counts as zero for a time event's relation at
#: its own instant: its crossing time is computed in closed form, so what is left of
#: g there is round-off (``(t - T_start) - width`` against ``t - (T_start + width)``).
ROUND_OFF = 1e-13

#: ``(d, strict, timed)``: see the module docstring.
Kind = tuple[float, bool, bool]


# -- hysteresis: the margin, g moved by it, and the decision, in both forms --------------
#
# Each pair below is the same arithmetic on the same doubles, operation for operation,
# so that the plain and the numpy form round alike (a numpy maximum of NaN is NaN where
# Python's max may skip it, but a NaN side makes g NaN and every comparison false either way).


def margin(epsilon: float, floor: float, lhs: float, rhs: float) -> float:
    """The margin of a relation with sides ``lhs`` and ``rhs``: ``epsilon * max(floor, |lhs|, |rhs|)``.

    ``epsilon`` is the relative margin and ``floor`` the smallest scale it is
    relative to (1 for the crossing margin; 0 for a relation free of
    integration noise, whose margin is round-off of its sides alone).
    """
    return epsilon * max(floor, abs(lhs), abs(rhs))


def margin_many(epsilon, floor, lhs: np.ndarray, rhs: np.ndarray) -> np.ndarray:
    """:func:`margin` with numpy (``epsilon`` and ``floor`` numbers or arrays that broadcast)."""
    scale = np.maximum(np.abs(lhs), np.abs(rhs))
    np.maximum(scale, floor, out=scale)
    return epsilon * scale


def shifted(d: float, previous: bool, lhs: float, rhs: float, epsilon: float, floor: float,
            plain: bool = False) -> float:
    """``d * g`` with ``g = lhs - rhs`` moved by the margin towards the relation's ``previous`` value.

    The relation holds when the result is ``> 0`` (strict) or ``>= 0``
    (:func:`holds`), so it keeps ``previous`` until ``g`` has passed its limit
    by the margin: the integrator's round-off cannot flip it (hysteresis).
    The result crosses zero exactly where the relation flips, so it is also
    the function the search of the flip instant follows.  ``plain``: no
    margin (a time event, whose instant is computed in closed form; an exact
    decision).  ``d`` is +1 for ``>``/``>=`` and -1 for ``<``/``<=``.
    """
    if plain:
        return d * (lhs - rhs)
    return d * ((lhs - rhs) + (d if previous else -d) * margin(epsilon, floor, lhs, rhs))


def shifted_many(d, previous, lhs: np.ndarray, rhs: np.ndarray, epsilon, floor, plain=None,
                 toward=None, margins=None) -> np.ndarray:
    """:func:`shifted` with numpy; ``plain`` None (a margin everywhere) or a mask (callers
    silence numpy's warnings: inf/NaN sides decide as in Python).  ``toward``: the
    direction of the margin, ``np.where(previous, d, -d)``, when the caller keeps it;
    ``margins``: :func:`margin_many` of these sides, when the caller has computed it."""
    g = lhs - rhs
    if toward is None:
        toward = np.where(previous, d, -d)
    if margins is None:
        margins = margin_many(epsilon, floor, lhs, rhs)
    moved = g + toward * margins
    return d * (moved if plain is None else np.where(plain, g, moved))


def holds(value: float, strict: bool) -> bool:
    """Whether a relation holds for its signed value ``d * g`` (:func:`shifted`)."""
    return value > 0 if strict else value >= 0


def holds_many(value: np.ndarray, strict) -> np.ndarray:
    """:func:`holds` with numpy (``strict`` an array, or one bool for all)."""
    if strict is True or strict is False:
        return value > 0 if strict else value >= 0
    return np.where(strict, value > 0, value >= 0)


def decided_clearly(raw: Sequence[float], epsilon: Sequence[float], floor: Sequence[float],
                    inherited: Sequence[bool] | None = None) -> tuple[bool, ...]:
    """Whether each relation's ``lhs - rhs`` (``raw``: ``lhs_0, rhs_0, lhs_1, ...``) lies beyond
    its margin, or is exactly at its limit and keeps the answer before (``inherited``;
    None: not clear).  This is the ``clear`` that :func:`decide`'s rule 2 reads."""
    out = []
    for k, (eps, bottom) in enumerate(zip(epsilon, floor)):
        lhs, rhs = raw[2 * k], raw[2 * k + 1]
        if lhs == rhs:
            out.append(bool(inherited is not None and inherited[k]))
        else:
            out.append(abs(lhs - rhs) > margin(eps, bottom, lhs, rhs))
    return tuple(out)


def decided_clearly_many(raw, epsilon: np.ndarray, floor: np.ndarray,
                         inherited: Sequence[bool] | None = None, sides=None) -> tuple[bool, ...]:
    """:func:`decided_clearly` with numpy (``epsilon`` and ``floor`` as arrays).  ``sides``:
    ``(lhs, rhs, margins)`` of ``raw`` as arrays (:func:`sides_many`), when the caller has
    them (event iteration decides the relations from the same sides first)."""
    with np.errstate(invalid="ignore", over="ignore"):  # a NaN side makes the comparison false
        lhs, rhs, margins = sides_many(raw, epsilon, floor) if sides is None else sides
        clear = np.abs(lhs - rhs) > margins
        equal = lhs == rhs
        if equal.any():
            clear[equal] = False if inherited is None else np.asarray(inherited, dtype=bool)[equal]
    return tuple(clear.tolist())


# -- the rules at an event ---------------------------------------------------------------


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
       pass before decided clearly (``clear[k]``, :func:`decided_clearly`),
       stays true (not with ``exact``): the guess that pass made because it
       was true put it at its limit, which confirms the guess.
    3. With ``exact``, for a time event, for a relation in ``fired``, or for
       exactly equal sides: ``g`` itself decides.
    4. Otherwise ``g`` is moved by the margin ``epsilon * max(floor, |lhs|, |rhs|)``
       towards the relation's previous value (hysteresis, :func:`shifted`);
       ``epsilon`` and ``floor`` are one number each, or one per relation (a
       relation free of integration noise has a round-off margin relative to
       its sides alone: floor 0).

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
        if timed and k in fired and abs(lhs - rhs) <= margin(ROUND_OFF, 1.0, lhs, rhs):
            v = 0.0
        elif lhs == rhs and clear is not None and clear[k] and previous[k] and not exact:
            out.append(True)
            continue
        else:
            v = shifted(d, previous[k], lhs, rhs, epsilon, floor,
                        plain=exact or timed or k in fired or lhs == rhs)
        out.append(holds(v, strict))
    return tuple(out)


def decide_many(kinds: Sequence[Kind], raw, previous: Sequence[bool], epsilon: float | Sequence[float], *,
                floor: float | Sequence[float] = 1.0, exact: bool = False, fired: frozenset = frozenset(),
                clear: Sequence[bool] | None = None, arrays=None, sides=None) -> tuple[bool, ...]:
    """:func:`decide` with numpy: the same rules, in the same order, on the same doubles.

    ``arrays`` may pass ``kind_arrays(kinds)`` computed once; ``sides``, ``(lhs, rhs,
    margins)`` of ``raw`` (:func:`sides_many` with these ``epsilon`` and ``floor``), shared
    with :func:`decided_clearly_many` of the same sides.
    """
    d, strict, timed = kind_arrays(kinds) if arrays is None else arrays
    with np.errstate(invalid="ignore", over="ignore"):  # inf/NaN sides decide as in Python
        if sides is None:
            values = np.asarray(raw, dtype=float)
            lhs, rhs, given = values[0::2], values[1::2], None
        else:
            lhs, rhs, given = sides
        in_fired = np.zeros(len(d), dtype=bool)
        if fired:
            in_fired[list(fired)] = True
        previous = np.asarray(previous, dtype=bool)
        # rule 1: a time event at its own instant
        at_root = timed & in_fired & (np.abs(lhs - rhs) <= margin_many(ROUND_OFF, 1.0, lhs, rhs))
        # rule 2: kept true at its limit
        if clear is not None and not exact:
            kept = ~at_root & (lhs == rhs) & np.asarray(clear, dtype=bool) & previous
        else:
            kept = np.zeros(len(d), dtype=bool)
        # rules 3 and 4
        margins = floors = None  # (only to compute the margins, unless ``sides`` has them)
        if given is None:
            margins = np.asarray(epsilon, dtype=float) if isinstance(epsilon, (list, tuple)) else epsilon
            floors = np.asarray(floor, dtype=float) if isinstance(floor, (list, tuple)) else floor
        plain = True if exact else timed | in_fired | (lhs == rhs)
        v = shifted_many(d, previous, lhs, rhs, margins, floors, plain=plain, margins=given)
        v = np.where(at_root, 0.0, v)
        return tuple((holds_many(v, strict) | kept).tolist())


def sides_many(raw, epsilon, floor) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(lhs, rhs, margins)``: the sides of ``raw`` (``lhs_0, rhs_0, lhs_1, ...``) as arrays
    and each relation's :func:`margin_many`, the numbers :func:`decide_many` and
    :func:`decided_clearly_many` both read (computed once for a pass of event iteration)."""
    values = np.asarray(raw, dtype=float)
    lhs, rhs = values[0::2], values[1::2]
    with np.errstate(invalid="ignore", over="ignore"):  # inf/NaN sides decide as in Python
        return lhs, rhs, margin_many(epsilon, floor, lhs, rhs)


def kind_arrays(kinds: Sequence[Kind]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(d, strict, timed)`` of ``kinds`` as numpy arrays."""
    return (np.array([k[0] for k in kinds], dtype=float),
            np.array([k[1] for k in kinds], dtype=bool),
            np.array([k[2] for k in kinds], dtype=bool))
