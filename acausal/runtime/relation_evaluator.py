"""The relations of a model at an instant: decided at events, watched between them.

A model's relations (``$rel0 = lhs > rhs`` …) are computed by the compiled
systems' ``crossings`` function, which gives both sides of every relation
(``lhs_0, rhs_0, lhs_1, ...``).  :class:`RelationEvaluator` turns those
sides into decisions, always through the one definition of hysteresis in
:mod:`acausal.runtime.relations`:

- at an event, the relations' values (:meth:`RelationEvaluator.relation_values`,
  the rules of :func:`~acausal.runtime.relations.decide`), which of them
  were decided beyond their margin (:meth:`~RelationEvaluator.clearly_decided`)
  and which crossing relations keep the value the crossing gave them
  (:meth:`~RelationEvaluator.keep_crossed`);
- between events, which watched relations have flipped at one instant
  (:meth:`~RelationEvaluator.flipped_relations`, the hot path of event
  detection) or first along a step's samples (:meth:`~RelationEvaluator.first_flip`),
  and a signed distance to the first flip for the search of its instant
  (:meth:`~RelationEvaluator.distance_to_first_flip`).

Each answer has a plain Python path for a few relations and a numpy path
for many; both go through the same functions of
:mod:`~acausal.runtime.relations`, and the tests hold them to the same
answers (``tests/runtime/test_relation_paths.py``, ``test_vectorised.py``).
The evaluator keeps no state of a run: only plans (index arrays, kinds)
made from the relations it was asked about last, so that the watch does not
build them again at every step.
"""

from __future__ import annotations

import math
from typing import Callable, Sequence

import numpy as np

from ..compiler.generated import remember
from .contract import CompiledSystem
from .relations import (decide, decide_many, decided_clearly, decided_clearly_many, holds, holds_many, kind_arrays,
                        margin, shifted, shifted_many, sides_many)

__all__ = ["RelationEvaluator"]

#: From this many relations on (decided at an event, or watched), they are decided with
#: numpy at once.
_VECTORISE_FROM = 48

#: Up to this many watched relations, a composed system computes the crossing
#: functions of the parts that own them only.
_FEW_RELATIONS = 8

#: Samples times (watched relations + 2) from which the relations at the samples of a
#: step are decided in one numpy call rather than sample by sample.
_MANY_FROM = 40

#: How many numpy plans of the crossing watch are kept (the oldest goes first).
_PLANS_KEPT = 32


class RelationEvaluator:
    """The decisions about a model's relations (see the module docstring).

    Parameters
    ----------
    relations : sequence of RelationData
        The model's relations, in the order of the systems' ``crossings``.
    epsilon : float
        The relative crossing margin (``simulate(relation_epsilon=)``).

    Attributes
    ----------
    kinds : list of (d, strict, timed)
        Each relation's kind (:data:`acausal.runtime.relations.Kind`).
    margins, floors : tuple of float
        Each relation's margin ``epsilon * max(floor, |lhs|, |rhs|)``: the crossing
        margin, or round-off relative to the sides alone for a relation free of
        integration noise (``RelationData.is_exact``: two forces rising from 0 on one
        sine cross together).
    """

    def __init__(self, relations: Sequence, epsilon: float) -> None:
        self.relations = relations
        self.epsilon = epsilon
        self.kinds = [(1.0 if r.op in (">", ">=") else -1.0, r.op in (">", "<"), r.is_time_event)
                      for r in relations]
        self.margins, self.floors = (tuple(m) for m in zip(
            *[r.margin_parameters(epsilon) for r in relations])) if relations else ((), ())
        # caches, made on first use: the kinds and margins as numpy arrays, and the plans of
        # the last watch (the same watched tuple and relation values are asked step after step)
        self._kind_arrays: tuple | None = None
        self._margin_arrays: tuple | None = None
        #: the sides and margins of the last event pass's crossings, as ``(raw, sides)``
        self._last_sides: tuple | None = None
        self._scalar_plan: tuple | None = None
        self._vector_plan: tuple | None = None
        #: the numpy plans by (watched, relation values), for the next segment with the same
        self._vector_plans: dict[tuple, tuple] = {}
        #: the numpy crossings of the last segment's watch: (system, watched, function,
        #: whether it gives the watched relations' sides only)
        self._watch_many: tuple | None = None
        #: the scalar crossings of the last segment's watch: (system, watched, function,
        #: whether it gives the watched relations' sides only)
        self._watch_scalar: tuple | None = None
        #: the systems' scalar crossings of some relations (``crossings_of``) by (id of the
        #: system, relations): (system, function or None); asked at every segment and flip
        self._crossings_of: dict[tuple, tuple] = {}

    # -- at an event ----------------------------------------------------------------

    def relation_values(self, system: CompiledSystem, t: float, x, previous, exact: bool = False,
                        fired: frozenset = frozenset(), clear=None, raw=None) -> tuple[bool, ...]:
        """Relation values at ``(t, x)``; with hysteresis against ``previous``.

        Relations in ``fired`` (those whose crossing caused the event) are
        evaluated exactly: their margin has done its job, and in another
        discrete state their arguments may have other units (``sa`` is a
        torque while locked and an acceleration while sliding), so a margin
        in the units of one would wrongly undo the crossing in the other.

        ``clear`` (in event iteration: from the pass before) says which of
        ``previous`` were decided with ``lhs - rhs`` beyond the margin.  Such
        a relation that was true and whose sides are now exactly equal stays
        true: the guess the pass made because it was true put it at its
        limit (a friction element tried sliding sees exactly its sliding
        torque), which confirms the guess rather than deciding against it.
        (A false relation at its limit takes its own value: ``u <= 0`` for
        ``u`` stepped to exactly 0 becomes true.)  ``raw``: the sides, when
        the caller has computed them already.
        """
        if not self.relations:
            return ()
        if raw is None:
            raw = system.crossings(t, x)
        if len(self.kinds) >= _VECTORISE_FROM:
            if self._kind_arrays is None:
                self._kind_arrays = kind_arrays(self.kinds)
            sides = self._sides(raw)
            return decide_many(self.kinds, raw, previous, self.margins, floor=self.floors, exact=exact,
                               fired=fired, clear=clear, arrays=self._kind_arrays, sides=sides)
        return decide(self.kinds, raw, previous, self.margins, floor=self.floors, exact=exact, fired=fired,
                      clear=clear)

    def clearly_decided(self, raw, inherited=None) -> tuple[bool, ...]:
        """Whether each relation's ``lhs - rhs`` (``raw``: the sides, as ``crossings``
        gives them) lies beyond its margin, or is exactly at its limit and kept a
        value decided clearly before (``inherited``: the answer for the pass before)."""
        if len(self.margins) >= _VECTORISE_FROM:
            return decided_clearly_many(raw, *self._margins_many(), inherited, sides=self._sides(raw))
        return decided_clearly(raw, self.margins, self.floors, inherited)

    def _margins_many(self) -> tuple[np.ndarray, np.ndarray]:
        """The margins and floors as numpy arrays (made once)."""
        if self._margin_arrays is None:
            self._margin_arrays = (np.array(self.margins, dtype=float), np.array(self.floors, dtype=float))
        return self._margin_arrays

    def _sides(self, raw) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``sides_many(raw)`` with the relations' margins, kept for the same ``raw``: a pass
        of event iteration decides the relations (:meth:`relation_values`) and then which
        were decided clearly (:meth:`clearly_decided`) from one set of sides, and both
        read the same margins.  (The kept ``raw`` stays referenced, so that ``is`` cannot
        meet another object at its address.)"""
        last = self._last_sides
        if last is not None and last[0] is raw:
            return last[1]
        sides = sides_many(raw, *self._margins_many())
        self._last_sides = (raw, sides)
        return sides

    def keep_crossed(self, raw, fired, guess, before, decided) -> tuple[bool, ...]:
        """``decided`` with each crossed relation that the guess already holds at its
        new value kept there while ``raw`` puts ``lhs - rhs`` within its margin.

        A relation whose crossing caused the event is decided exactly (see
        :meth:`relation_values`), but in the discrete state the crossing selects,
        its arguments may land on zero up to round-off (an ideal diode turning on
        in series with an inductor has ``s`` = current = 0 +- 1e-10 A against
        hundreds of amperes). Deciding that round-off exactly would undo the
        crossing and make event iteration alternate between the two states; the
        crossing itself already said which side the relation goes to, and a
        relation that does leave at once is caught by the crossing watch.
        """
        out = list(decided)
        for k in fired:
            if guess[k] != before[k] and decided[k] != guess[k]:
                lhs, rhs = raw[2 * k], raw[2 * k + 1]
                if abs(lhs - rhs) <= margin(self.margins[k], self.floors[k], lhs, rhs):
                    out[k] = guess[k]
        return tuple(out)

    # -- between events: the crossing watch -----------------------------------------------

    def flipped_relations(self, system: CompiledSystem, t: float, x, relations,
                          watched: tuple[int, ...]) -> tuple[int, ...]:
        """The watched relations whose value at ``(t, x)`` differs from ``relations``.

        The hot path of event detection: only the watched relations are
        evaluated (with hysteresis against their current values), and only their
        sides are computed where the system offers that (:meth:`_watched_scalar`).
        """
        if not watched:
            return ()
        crossings, only_watched = self._watched_scalar(system, watched)
        raw = crossings(t, x)
        if len(watched) >= _VECTORISE_FROM:
            with np.errstate(invalid="ignore", over="ignore"):  # inf/NaN sides decide as in Python
                if only_watched:
                    plan = self._plan(relations, watched)
                    raw = np.asarray(raw, dtype=float)
                    w, flips = plan[0], self._decide(raw[0::2], raw[1::2], plan, False)
                else:
                    w, flips = self._flips(np.asarray(raw, dtype=float), relations, watched)
            return tuple(w[flips].tolist())
        return self._flipped_at(raw, self._scalar_entries(relations, watched, only_watched))

    def _scalar_entries(self, relations, watched: tuple[int, ...], only_watched: bool) -> list[tuple]:
        """What the scalar watch decides each watched relation from: ``(k, position of its
        lhs in the crossings' values, d, strict, timed, previous value, epsilon, floor)``,
        made again only for other watched or relation tuples."""
        plan = self._scalar_plan
        if plan is None or plan[0] is not watched or plan[1] is not relations or plan[2] is not only_watched:
            # (the sides of watched[j] are at 2j in the watched relations' own values,
            # at 2k for relation k in every relation's)
            plan = self._scalar_plan = (watched, relations, only_watched, [
                (k, 2 * j if only_watched else 2 * k, *self.kinds[k], bool(relations[k]), self.margins[k],
                 self.floors[k])
                for j, k in enumerate(watched)])
        return plan[3]

    @staticmethod
    def _flipped_at(raw, entries) -> tuple[int, ...]:
        """The relations of ``entries`` (:meth:`_scalar_entries`) flipped, by their sides in ``raw``."""
        out = []
        for k, i, d, strict, timed, previous, epsilon, floor in entries:
            if holds(shifted(d, previous, raw[i], raw[i + 1], epsilon, floor, timed), strict) != previous:
                out.append(k)
        return tuple(out)

    def distance_to_flip(self, system: CompiledSystem, relations, k: int) -> Callable:
        """``distance(t, x)`` for relation ``k``: the margin-shifted ``g`` that
        :meth:`flipped_relations` decides on, signed to be negative while the
        relation keeps its value in ``relations`` and positive once it has
        flipped (for the search of the flip instant)."""
        return self.distance_to_first_flip(system, relations, (k,))

    def distance_to_first_flip(self, system: CompiledSystem, relations, candidates) -> Callable:
        """``distance(t, x)`` for the first of ``candidates`` to flip: the largest of their
        :meth:`distance_to_flip` values, from one evaluation of their crossing functions.

        It is positive exactly where one of them has flipped, so that the search of
        the flip instant takes its trial points from it when several relations flip in
        one step (twins of one component, or several parts of a storm) instead of
        halving alone."""
        crossings, at = self._candidates_crossings(system, candidates)
        terms = []
        for k in candidates:
            d, _strict, timed = self.kinds[k]
            previous = bool(relations[k])
            terms.append((at[k], -1.0 if previous else 1.0, d, previous, timed, self.margins[k], self.floors[k]))

        def distance(t, x) -> float:
            raw = crossings(t, x)
            best = -math.inf
            for i, sign, d, previous, timed, epsilon, floor in terms:
                value = sign * shifted(d, previous, raw[i], raw[i + 1], epsilon, floor, timed)
                if value > best:
                    best = value
            return best

        return distance

    def flip_search(self, system: CompiledSystem, relations, candidates,
                    with_distance: bool = True) -> tuple[Callable, Callable | None]:
        """``(flipped, distance)`` for the search of the instant at which the first of
        ``candidates`` flips: :meth:`flipped_relations` restricted to them, and
        :meth:`distance_to_first_flip` (None without ``with_distance``).

        The search asks both at each trial point, one after the other with the same
        state (:func:`~acausal.runtime.crossings.bisect_flip`): here they share one
        evaluation of the crossing functions and of the margin-shifted values
        (a memo of the last instant), with the same arithmetic as the two methods.
        Many candidates go to those methods themselves (their numpy path).
        """
        if len(candidates) >= _VECTORISE_FROM:
            def flipped_many(t, x):
                return self.flipped_relations(system, t, x, relations, candidates)
            return flipped_many, (self.distance_to_first_flip(system, relations, candidates)
                                  if with_distance else None)
        crossings, at = self._candidates_crossings(system, candidates)
        terms = []
        for k in candidates:
            d, strict, timed = self.kinds[k]
            previous = bool(relations[k])
            terms.append((k, at[k], d, strict, timed, previous, self.margins[k], self.floors[k]))
        last: list = [None, None, None]  # t, x and the shifted values there

        def shifted_at(t, x) -> list[float]:
            if x is last[1] and t == last[0]:  # the same state object: the same values
                return last[2]
            raw = crossings(t, x)
            values = [shifted(d, previous, raw[i], raw[i + 1], epsilon, floor, timed)
                      for _k, i, d, _strict, timed, previous, epsilon, floor in terms]
            last[:] = (t, x, values)
            return values

        def flipped(t, x) -> tuple[int, ...]:
            return tuple([term[0] for term, value in zip(terms, shifted_at(t, x))
                          if holds(value, term[3]) != term[5]])

        def distance(t, x) -> float:
            best = -math.inf
            for term, value in zip(terms, shifted_at(t, x)):
                # negative while the relation keeps its value, positive once it has flipped
                value = (-1.0 if term[5] else 1.0) * value
                if value > best:
                    best = value
            return best

        return flipped, (distance if with_distance else None)

    def _watched_scalar(self, system: CompiledSystem, watched: tuple[int, ...]) -> tuple[Callable, bool]:
        """``(f, only_watched)``: the scalar crossings the watch calls between events,
        ``f(t, x)`` giving the sides of the ``watched`` relations only (``only_watched``:
        ``lhs, rhs`` of ``watched[0]``, then of ``watched[1]`` ...) where the system
        offers that (``crossings_of``), else every relation's at their places (a system
        of parts: those of the parts that own the watched ones, see ``crossings_for``).

        As for the numpy crossings of a step's samples (:meth:`_watched_many`), the
        unwatched relations' sides are not computed: the relevance analysis decided
        that no flip of theirs changes anything in this discrete state, so between
        events neither their values nor their failures matter (``_check_crossings``
        reports only the watched ones' sides that are not finite).  A side that only
        an unwatched relation reads, and that cannot be computed (``math.log`` of a
        negative number, a singular solve no watched side needs), raises nothing here;
        the check at the end of each step and event iteration still compute the whole
        function.  Kept for the last segment's system and watched tuple (asked at every
        step and trial point).
        """
        last = self._watch_scalar
        if last is not None and last[0] is system and last[1] is watched:
            return last[2], last[3]
        crossings = self._own_crossings(system, watched)
        only_watched = crossings is not None
        if crossings is None:
            crossings = system.crossings_for(watched) if len(watched) <= _FEW_RELATIONS else system.crossings
        self._watch_scalar = (system, watched, crossings, only_watched)
        return crossings, only_watched

    def _own_crossings(self, system: CompiledSystem, relations: tuple[int, ...]) -> Callable | None:
        """The system's ``crossings_of(relations)`` (None where it has none), kept for the
        next segment or search with the same (a run goes back and forth between a few
        discrete states)."""
        key = (id(system), relations)
        found = self._crossings_of.get(key)
        if found is None or found[0] is not system:
            # (optional in the contract: a system of parts has none)
            method = getattr(system, "crossings_of", None)
            found = (system, method(relations) if method is not None else None)
            remember(self._crossings_of, key, found, _PLANS_KEPT)
        return found[1]

    def _candidates_crossings(self, system: CompiledSystem, candidates) -> tuple[Callable, dict[int, int]]:
        """``(f, at)`` for the search of a flip instant: ``f(t, x)`` computes the sides of
        ``candidates`` (their own crossings where the system offers them, as
        :meth:`_watched_scalar`; else ``crossings_for``), and ``at[k]`` is where relation
        ``k``'s ``lhs`` is in its values (``rhs`` follows)."""
        relations = tuple(sorted(candidates))
        crossings = self._own_crossings(system, relations)
        if crossings is not None:
            return crossings, {k: 2 * j for j, k in enumerate(relations)}
        return system.crossings_for(relations), {k: 2 * k for k in relations}

    def first_flip(self, system: CompiledSystem, times, states, relations,
                   watched: tuple[int, ...]) -> tuple[int, tuple[int, ...]] | None:
        """The first of ``times`` at which a watched relation has flipped.

        ``states`` holds the state at each time as a row.  Returns ``(index,
        flipped)`` with ``flipped`` as :meth:`flipped_relations` gives it at that
        instant, or None: exactly what calling :meth:`flipped_relations` at each
        time in turn gives (the first flip, and any error on the way).

        The relations are decided for all times at once, with numpy
        (:meth:`_decide`), on the crossing functions' values: from one numpy call
        when the system's code allows it
        (:meth:`_watched_many`; from an instant at which a watched relation's sides
        are not all finite on, or if it raises, the scalar function
        decides instant by instant), else from the scalar function at each time
        (both of them giving the watched relations' sides only where the system
        offers that: :meth:`_watched_scalar`).
        A few samples of few relations are decided one by one: a numpy call has
        a fixed cost of some tens of microseconds.
        """
        m = len(times)
        if not watched or not m:
            return None
        start = 0
        if m * (len(watched) + 2) >= _MANY_FROM:
            many, only_watched = self._watched_many(system, watched)
            if many is not None:
                found, start = self._first_flip_many(many, only_watched, times, states, relations, watched)
            else:
                found, start = self._first_flip_collected(system, times, states, relations, watched)
            if found is not None or start >= m:
                return found
        if len(watched) >= _VECTORISE_FROM:
            for i in range(start, m):
                hit = self.flipped_relations(system, times[i], states[i], relations, watched)
                if hit:
                    return i, hit
            return None
        # flipped_relations at each instant in turn, with the crossings and what decides
        # the relations looked up once for all of them (a step of a storm's part has few
        # samples, and the lookups cost as much as the decisions)
        crossings, only_watched = self._watched_scalar(system, watched)
        entries = self._scalar_entries(relations, watched, only_watched)
        flipped_at = self._flipped_at
        for i in range(start, m):
            hit = flipped_at(crossings(times[i], states[i]), entries)
            if hit:
                return i, hit
        return None

    def _watched_many(self, system: CompiledSystem, watched: tuple[int, ...]) -> tuple[Callable | None, bool]:
        """``(f, only_watched)``: the system's numpy crossings for the samples of a step,
        giving the sides of the ``watched`` relations only (``only_watched``) where the
        system offers that, else every relation's (None: no numpy form).

        The unwatched relations are not evaluated at the samples at all: the relevance
        analysis decided that no flip of theirs can change anything in this discrete
        state, so their values cannot stop the step (and, as in ``_check_crossings``,
        their sides need not be finite).  A system of generated code computes the
        watched relations' sides without the statements only the others need (for
        StickSlip sliding, the sine input the watched relations of the speed do not
        read); so an unwatched side that cannot be computed at a sample raises nothing
        here, while the scalar path (from a watched side that is not finite, or where
        the numpy function raises) and the check at the step's end still compute the
        whole function.  Kept for the last segment's system and watched tuple (asked
        at every step).
        """
        last = self._watch_many
        if last is not None and last[0] is system and last[1] is watched:
            return last[2], last[3]
        # (optional in the contract: a system of parts has none)
        method = getattr(system, "vectorised_crossings_for", None)
        many = method(watched) if method is not None else None
        only_watched = many is not None
        if many is None:
            many = system.vectorised("crossings")
        self._watch_many = (system, watched, many, only_watched)
        return many, only_watched

    def _first_flip_many(self, many, only_watched: bool, times, states, relations, watched):
        """``(first flip, None)`` or ``(None, index to go on from)`` with the numpy crossings
        (``many``; ``only_watched``: it gives the watched relations' sides only)."""
        m = len(times)
        plan = self._plan(relations, watched)
        try:
            # a division by zero or an invalid operation (where Python's floats could
            # raise) leaves the instants to the scalar function.  (One numpy state for
            # the decisions too: from finite sides they do no invalid operation, and
            # from sides that are not all finite one that raises only hands the same
            # answer to the scalar function from the first instant on.)
            with np.errstate(divide="raise", invalid="raise", over="ignore", under="ignore"):
                raw = many(np.asarray(times, dtype=float), np.asarray(states, dtype=float).T)
                if not only_watched:
                    raw = raw[plan[3]]  # the watched relations' sides, ``lhs, rhs`` of each in turn
                flips = self._decide(raw[0::2], raw[1::2], plan, True)
        except Exception:  # the scalar function raises where it should, or not at all
            return None, 0
        w = plan[0]
        stop = flips.any(axis=0)
        # (the watched relations' sides only: the others do not matter here, see _watched_many)
        finite = np.isfinite(raw)
        unsure = None if finite.all() else ~finite.all(axis=0)
        if unsure is not None:
            stop |= unsure
        if not stop.any():
            return None, m
        first = int(np.argmax(stop))
        if unsure is not None and unsure[first]:
            return None, first  # the scalar function decides from here on
        return (first, tuple(w[flips[:, first]].tolist())), m

    def _first_flip_collected(self, system, times, states, relations, watched):
        """The same with the scalar crossing function called at each time: its values
        are those :meth:`flipped_relations` decides on (the watched relations' own
        crossings where the system offers them, else the whole function)."""
        columns = []
        crossings, only_watched = self._watched_scalar(system, watched)
        if not only_watched:
            crossings = system.crossings
        for t, x in zip(times, states):
            try:
                columns.append(crossings(t, x))
            except Exception:  # flipped_relations raises it, unless a flip comes first
                break
        if not columns:
            return None, 0
        try:
            raw = np.array(columns, dtype=float).T
            with np.errstate(all="ignore"):
                if only_watched:
                    plan = self._plan(relations, watched)
                    w, flips = plan[0], self._decide(raw[0::2], raw[1::2], plan, True)
                else:
                    w, flips = self._flips(raw, relations, watched)
        except (TypeError, ValueError):  # values that are no numbers: decided one by one
            return None, 0
        stop = flips.any(axis=0)
        if not stop.any():
            return None, len(columns)
        first = int(np.argmax(stop))
        return (first, tuple(w[flips[:, first]].tolist())), len(times)

    def _flips(self, values: np.ndarray, relations, watched):
        """``(w, flipped)``: the watched relations' indices, and whether each has
        flipped at each column of ``values`` (the crossing functions' values, one
        instant a column; or one instant as a vector).  Callers silence numpy's
        warnings: inf/NaN sides decide as in Python."""
        plan = self._plan(relations, watched)
        return plan[0], self._decide(values[plan[1]], values[plan[2]], plan, values.ndim == 2)

    @staticmethod
    def _decide(lhs: np.ndarray, rhs: np.ndarray, plan, many_instants: bool) -> np.ndarray:
        """Whether each watched relation has flipped, from its sides (a row per relation
        of ``plan``, a column per instant with ``many_instants``; else vectors)."""
        _w, _left, _right, _sides, vectors, columns, any_timed = plan
        d, strict, previous, epsilon, floor, timed, toward, all_strict = columns if many_instants else vectors
        # (a time event gets no margin: its instant is computed in closed form)
        v = shifted_many(d, previous, lhs, rhs, epsilon, floor, timed if any_timed else None, toward=toward)
        return holds_many(v, strict if all_strict is None else all_strict) != previous

    def _plan(self, relations, watched):
        """The watched relations' indices and kinds as numpy arrays (as vectors, and as
        columns for many instants), made again only for other watched or relation tuples."""
        plan = self._vector_plan
        if plan is None or plan[0] is not watched or plan[1] is not relations:
            # a segment brings new tuples, but as a rule the values of one seen before
            kept = self._vector_plans.get((watched, relations))
            if kept is not None:
                plan = self._vector_plan = (watched, relations, *kept)
                return kept
            w = np.array(watched, dtype=int)
            d = np.array([self.kinds[k][0] for k in watched], dtype=float)
            strict = np.array([self.kinds[k][1] for k in watched], dtype=bool)
            previous = np.array([bool(relations[k]) for k in watched], dtype=bool)
            epsilon = np.array([self.margins[k] for k in watched], dtype=float)
            floor = np.array([self.floors[k] for k in watched], dtype=float)
            timed = np.array([self.kinds[k][2] for k in watched], dtype=bool)
            # the direction of each margin, and whether all or none are strict (one
            # comparison then), kept with the plan rather than made at every step
            toward = np.where(previous, d, -d)
            all_strict = True if strict.all() else False if not strict.any() else None
            vectors = (d, strict, previous, epsilon, floor, timed, toward)
            # (and both sides of each in turn: the rows the watched relations' own numpy
            # crossings give, taken from a function that gives every relation's)
            sides = np.stack([2 * w, 2 * w + 1], axis=1).reshape(-1)
            plan = self._vector_plan = (watched, relations, w, 2 * w, 2 * w + 1, sides, (*vectors, all_strict),
                                        (*(a[:, None] for a in vectors), all_strict), bool(timed.any()))
            remember(self._vector_plans, (watched, relations), plan[2:], _PLANS_KEPT)
        return plan[2:]
