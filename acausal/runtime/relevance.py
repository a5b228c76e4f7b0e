"""Which relations can change the current discrete state: only those are watched.

Between events the integrator watches relations for crossings.  A relation
that only matters in another discrete state (``sa > tau0_max`` while a
friction element slides) need not be watched: flipping it alone leaves
every discrete variable as it is.  :class:`RelevanceAnalysis` finds the
relations whose flip does change something, by trying the flip on the
discrete equations it can reach (with ``pre()`` = the current values), and
with it the relations of the same component that cross together (*twins*:
``sa > tau0_max`` and ``sa > tau0`` when the peak is 1).  Relations that
select continuous equations are always watched, and so are those whose
flip reaches an equation reading continuous values or clocks (the flip
cannot be tried out without them).  At the next event all relations are
evaluated again anyway.

Its caches (the last answers, kept across events and runs) hold only what
a new check would give: an answer is reused only if nothing it read has
changed since.
"""

from __future__ import annotations

from typing import Mapping, Sequence

import numpy as np

from ..compiler.generated import remember
from ..names import parse, relation_name
from .discrete_equations import DiscreteEquations, cast

__all__ = ["RelevanceAnalysis"]

#: From this many relations on, twins are found with numpy from the pairs of relations
#: of one component and direction (made once) rather than by grouping.
_TWINS_WITH_NUMPY_FROM = 48

#: How many answers of :meth:`RelevanceAnalysis.relevant_relations` are kept (the oldest
#: goes first): the discrete states a run goes through, again at every warm run.
_ANSWERS_KEPT = 256


class RelevanceAnalysis:
    """The relations worth watching in a discrete state (see the module docstring).

    Parameters
    ----------
    relations : sequence of RelationData
        The model's relations.
    directions : sequence of float
        Each relation's ``d`` (+1 for ``>``/``>=``, -1 for ``<``/``<=``).
    program : DiscreteEquations
        The discrete equations the flips are tried on.
    selectors : sequence of str
        The names that select the continuous equations (a relation among them is
        always watched).
    """

    def __init__(self, relations: Sequence, directions: Sequence[float], program: DiscreteEquations,
                 selectors: Sequence[str]) -> None:
        self.relations = relations
        self._directions = directions
        self.program = program
        self._selectors = frozenset(selectors)
        #: for each relation, the discrete equations (in order) its value can reach
        self.downstream = self._downstream_equations()
        #: the relations whose check (:meth:`_flip_changes`) reads each name
        self._checks_reading: dict[str, set[int]] = {}
        for k in range(len(relations)):
            for i in self.downstream[k]:
                variable, args, _fn, _origin = program.equations[i]
                for name in (*args, variable, relation_name(k)):
                    self._checks_reading.setdefault(name, set()).add(k)
        #: relations that cross together at the last event (see :meth:`_twins_at`), and the
        #: relation sides they were found from (found once per event, when relevance is asked)
        self._twins: dict[int, tuple[int, ...]] = {}
        self._twins_from = None
        # caches: the last answers, ``(discrete, relations, {relation: changes}, twins)``; the
        # relations always watched; the pairs of relations of one component and direction;
        # (relation, whether it selects equations) of the state relations
        self._last_answers: tuple | None = None
        self._always: frozenset | None = None
        self._pairs: tuple | None | bool = False
        self._watch_plan: list | None = None
        #: the answers by (discrete values, relations, twins), with the ``_last_answers``
        #: they left (see :meth:`relevant_relations`)
        self._answered: dict[tuple, tuple] = {}

    def _downstream_equations(self) -> dict[int, list[int]]:
        """For each relation, the discrete equations (in order) its value can reach."""
        readers, equations = self.program.readers, self.program.equations
        out = {}
        for k, rel in enumerate(self.relations):
            reached, frontier = set(), [rel.name]
            while frontier:
                name = frontier.pop()
                for i in readers.get(name, ()):
                    if i not in reached:
                        reached.add(i)
                        frontier.append(equations[i][0])
            out[k] = sorted(reached)
        return out

    def relevant_relations(self, discrete: Mapping, relations, sides) -> tuple[int, ...]:
        """State relations whose flip could change something in this discrete state.

        ``sides``: the relations' sides in the last pass of event iteration (as
        ``crossings`` gives them), from which the twins are found.
        """
        if sides is not self._twins_from:
            self._twins, self._twins_from = self._twins_at(sides), sides
        program = self.program
        key = None
        if program.incremental and not program.hybrid:
            # the answer is a function of these alone (no clocks, no continuous values): a
            # state the run (or a run before it) has been in is answered as it was then
            key = (tuple(discrete.items()), tuple(relations), tuple(self._twins.items()))
            found = self._answered.get(key)
            if found is not None:
                self._last_answers = found[0]
                return found[1]
        selector_names = self._selectors
        always = self._always_watched()
        checked = self._relevance_again(discrete, relations)
        if checked is None:
            checked = {k: True for k in always}
            again = [k for k, rel in enumerate(self.relations)
                     if not rel.is_time_event and rel.name not in selector_names and k not in always]
        else:
            again = checked.pop(None)
        if again:
            # the values every flip is tried against: relations as they are, pre = current
            # (no clock ticks and no continuous values: relations whose flip reads those
            # are always watched)
            env = self.program.environment(relations, False, discrete, {})
            env.update(discrete)
            for k in again:
                checked[k] = self._flip_changes(k, env, discrete, relations)
        self._last_answers = (dict(discrete), tuple(relations), dict(checked), self._twins)
        plan = self._watch_plan
        if plan is None:
            plan = self._watch_plan = [(k, rel.name in selector_names) for k, rel in enumerate(self.relations)
                                       if not rel.is_time_event]
        found = tuple([k for k, selects in plan if selects or checked[k]])
        if key is not None:
            remember(self._answered, key, (self._last_answers, found), _ANSWERS_KEPT)
        return found

    def _always_watched(self) -> frozenset:
        """Relations whose flip reaches a discrete equation that reads continuous values
        or clocks: whether the flip changes something cannot be tried out, so they are
        always watched."""
        found = self._always
        if found is None:
            continuous = self.program.continuous_args
            reads_more = set()
            for i, (_variable, args, _fn, _origin) in enumerate(self.program.equations):
                if any(a in continuous or parse(a).kind in ("sample", "terminal") for a in args):
                    reads_more.add(i)
            found = self._always = frozenset(k for k in range(len(self.relations))
                                             if reads_more.intersection(self.downstream[k]))
        return found

    def _relevance_again(self, discrete: Mapping, relations) -> dict | None:
        """The last answers of :meth:`_flip_changes`, and under the key None the relations
        to check again: those whose check reads a discrete value or a relation that
        changed since (None: check all)."""
        last = self._last_answers
        program = self.program
        if last is None or not program.incremental or program.hybrid or len(last[1]) != len(relations) \
                or len(last[0]) != len(discrete) or last[3] != self._twins:
            return None
        old_discrete, old_relations, answers, _twins = last
        names = [program.relation_names[k] for k, (a, b) in enumerate(zip(relations, old_relations)) if a != b]
        for name, value in discrete.items():
            if old_discrete.get(name, not value) != value:
                names += [name, program.pre_key(name)]
        if len(names) * 4 > len(relations) + len(discrete):
            return None
        again = set()
        for name in names:
            again.update(self._checks_reading.get(name, ()))
        out = dict(answers)
        out[None] = sorted(k for k in again if k in answers)
        return out

    # -- twins: relations that cross together ---------------------------------------------

    def _twins_at(self, raw) -> dict[int, tuple[int, ...]]:
        """For each state relation, the others of the same component and direction whose
        sides have the same values in ``raw`` (``sa > tau0_max`` and ``sa > tau0``
        when the peak is 1): they cross together, so whether a crossing matters
        is asked of them together (see :meth:`relevant_relations`)."""
        pairs = self._twin_candidates()
        if pairs is not None:
            # the same answer from the pairs of relations of one component and direction,
            # compared with numpy (NaN sides: below, where a NaN object equals itself)
            a, b = pairs
            with np.errstate(invalid="ignore"):
                values = np.asarray(raw, dtype=float)
            if not np.isnan(values).any():
                same = (values[2 * a] == values[2 * b]) & (values[2 * a + 1] == values[2 * b + 1])
                found: dict[int, list[int]] = {}
                for k, j in zip(a[same].tolist(), b[same].tolist()):
                    found.setdefault(k, []).append(j)
                    found.setdefault(j, []).append(k)
                return {k: tuple(sorted(js)) for k, js in found.items()}
        groups: dict[tuple, list[int]] = {}
        for k, rel in enumerate(self.relations):
            if rel.is_time_event:
                continue
            groups.setdefault((rel.components, self._directions[k], raw[2 * k], raw[2 * k + 1]), []).append(k)
        return {k: tuple(j for j in group if j != k)
                for group in groups.values() if len(group) > 1 for k in group}

    def _twin_candidates(self):
        """``(a, b)``: the pairs of state relations of one component and direction (numpy
        index arrays, ``a < b``), made once; None for a few relations."""
        found = self._pairs
        if found is False:
            found = None
            if len(self.relations) >= _TWINS_WITH_NUMPY_FROM:
                static: dict[tuple, list[int]] = {}
                for k, rel in enumerate(self.relations):
                    if not rel.is_time_event:
                        static.setdefault((rel.components, self._directions[k]), []).append(k)
                pairs = [(k, j) for group in static.values() for i, k in enumerate(group) for j in group[i + 1:]]
                found = (np.array([k for k, _ in pairs], dtype=int), np.array([j for _, j in pairs], dtype=int))
            self._pairs = found
        return found

    # -- trying a flip ------------------------------------------------------------------

    def _flip_changes(self, k: int, env: Mapping, discrete: Mapping, relations) -> bool:
        """Whether flipping relation k, alone or together with its twins, changes a
        discrete variable (pre = current)."""
        if self._flip_changes_of((k,), env, discrete, relations):
            return True
        twins = self._twins.get(k)
        return bool(twins) and self._flip_changes_of((k, *twins), env, discrete, relations)

    def _flip_changes_of(self, ks: tuple[int, ...], env: Mapping, discrete: Mapping, relations) -> bool:
        """Whether flipping the relations ``ks`` together changes a discrete variable (pre = current).

        Only the equations downstream of the relations are evaluated; they see
        ``env`` with the relations flipped.  (A variable they recompute keeps
        its value, or the answer is already yes.)
        """
        flipped = {relation_name(k): not relations[k] for k in ks}
        downstream = self.downstream[ks[0]] if len(ks) == 1 else \
            sorted(set().union(*(self.downstream[k] for k in ks)))
        equations, kinds = self.program.equations, self.program.kinds
        for i in downstream:
            variable, args, fn, _origin = equations[i]
            value = cast(kinds[variable], fn(*[flipped[a] if a in flipped else env[a] for a in args]))
            if value != discrete[variable]:
                return True
        return False
