"""Modelica's event iteration at one instant, with scratch state of its own.

At an event instant, with the ``pre()`` values held fixed, the continuous
equations (of the discrete state the current guess selects) and the
discrete equations are solved together by fixed-point iteration; then, if a
discrete variable differs from its ``pre()`` value, ``pre`` takes the new
values and the whole is repeated until nothing changes (Otter, Elmqvist &
Mattsson 1999 [1]_; Dymola and OpenModelica do the same).  A fixed point
that cycles is searched for instead, as a mixed-system solver does.

:class:`EventIteration` is made anew for every iteration: what one pass
leaves for the next lives in it and ends with it.  What it hands on is its
result, :class:`EventOutcome`, and a record of its last pass: the relation
values and sides (:attr:`EventIteration.relations_now`,
:attr:`EventIteration.sides`), which the caller keeps for the assertions and
the relevance analysis until the next event, and which relations that pass
decided beyond their margin (:attr:`EventIteration.clear`,
:attr:`EventIteration.clear_for`).  That last one is also what the first
pass of the *next* iteration is judged against (``judged_against``), as it
always was: a relation that is exactly at its limit there (a time event's
``time < T`` at ``T`` in a state event at ``T``) keeps the value it was
clearly decided to have at the event before.  Starting each iteration from
nothing instead is a change of results (one more or one fewer event at such
an instant), so it is left to a change of its own.

:class:`StateKey` turns discrete values into the key of the discrete state
(which compiled system is in force).

References
----------
.. [1] M. Otter, H. Elmqvist and S. E. Mattsson, "Hybrid modeling in Modelica
   based on the synchronous data flow principle", Proc. CACSD'99, 1999.
"""

from __future__ import annotations

import itertools
import operator
from dataclasses import dataclass
from typing import Mapping, Sequence

from ..errors import EventIterationError, SimulationError
from ..names import TERMINAL_NAME, parse
from .contract import CompiledModel, CompiledSystem
from .discrete_equations import DiscreteEquations, mode_values
from .relation_evaluator import RelationEvaluator

__all__ = ["EventIteration", "EventOutcome", "StateKey"]

#: Event iteration that cycles searches the combinations of at most this many relations
#: (2**n solves) for a consistent one (:meth:`EventIteration._search_relations`).
_SEARCHED_RELATIONS = 8


@dataclass(frozen=True)
class EventOutcome:
    """The fixed point reached by event iteration."""

    discrete: dict
    relations: tuple[bool, ...]
    system: CompiledSystem
    values: dict
    iterations: int
    changes: tuple
    #: the states reinitialized: ``(state, value before, value after)``
    reinits: tuple = ()
    #: the messages of the terminate() calls that fired (the run ends)
    terminated: tuple[str, ...] = ()


def _getter(items: list):
    """``m -> tuple(m[i] for i in items)`` at C speed (operator.itemgetter, always a tuple)."""
    if not items:
        return lambda _m: ()
    if len(items) == 1:
        only = items[0]
        return lambda m: (m[only],)
    return operator.itemgetter(*items)


class StateKey:
    """The key of a discrete state: each selector's value in the selectors' order.

    A selector is a relation (its value as a bool), ``pre(v)`` (from the
    ``pre`` values), a discrete variable, or ``initial()``.
    """

    def __init__(self, selectors: Sequence[str]) -> None:
        #: the selectors, parsed (``.kind``, ``.index``, ``.base``)
        self.names = tuple(parse(name) for name in selectors)
        # the selectors' values gathered by kind (C-level itemgetters), then put in the
        # selectors' order
        groups: dict[str, list] = {"relation": [], "pre": [], "discrete": []}
        where = []
        for name in self.names:
            if name.kind == "initial":
                where.append(("initial", 0))
                continue
            kind = name.kind if name.kind in ("relation", "pre") else "discrete"
            item = name.index if kind == "relation" else name.base if kind == "pre" else name.text
            where.append((kind, len(groups[kind])))
            groups[kind].append(item)
        offsets = {"relation": 0, "pre": len(groups["relation"]),
                   "discrete": len(groups["relation"]) + len(groups["pre"]),
                   "initial": len(groups["relation"]) + len(groups["pre"]) + len(groups["discrete"])}
        self._of_relations, self._of_pre, self._of_discrete = (
            _getter(groups["relation"]), _getter(groups["pre"]), _getter(groups["discrete"]))
        self._order = _getter([offsets[kind] + k for kind, k in where])

    def __call__(self, discrete: Mapping, pre: Mapping, relations, initial: bool) -> tuple:
        return self._order((*map(bool, self._of_relations(relations)), *self._of_pre(pre),
                            *self._of_discrete(discrete), bool(initial)))


class EventIteration:
    """One event iteration (see the module docstring); :meth:`run` performs it.

    Parameters
    ----------
    translation : CompiledModel
        The compiled model: its systems (one per discrete state) and data.
    program : DiscreteEquations
        The discrete equations, reinits and terminations.
    relations : RelationEvaluator
        How the relations are decided.
    key : StateKey
        The key of the discrete state a guess selects.
    max_iterations : int
        The most passes of each loop of the iteration.
    judged_against : (clear, clear_for)
        What the first pass is judged against: the record of the last pass of
        the iteration before (``(None, None)``: nothing).

    Attributes
    ----------
    clear, clear_for : tuple of bool or None
        Which relations the last pass decided beyond their margin
        (:meth:`RelationEvaluator.clearly_decided`), and the relation values it
        produced.
    relations_now : tuple of bool or None
        The relation values the last pass decided.
    sides : sequence of float or None
        The relations' sides in the last pass (None for a model without relations).
    """

    def __init__(self, translation: CompiledModel, program: DiscreteEquations, relations: RelationEvaluator,
                 key: StateKey, max_iterations: int, judged_against: tuple = (None, None)) -> None:
        self.translation = translation
        self.program = program
        self.relations = relations
        self.key = key
        self.max_iterations = max_iterations
        # which relations the last pass decided beyond their margin, and the relation values
        # it produced (what the next pass is judged against, see :meth:`_pass`): the first
        # pass starts from ``judged_against``, the caller's record of the last pass before
        self.clear: tuple[bool, ...] | None = judged_against[0]
        self.clear_for: tuple[bool, ...] | None = judged_against[1]
        # scratch, of this iteration only: this round's clock ticks, terminal() and
        # continuous values (what the environment of a pass adds)
        self._extra: dict = {}
        self.relations_now: tuple[bool, ...] | None = None
        self.sides = None

    def run(self, t: float, values: Mapping[str, float], pre: Mapping, relations_before,
            initial: bool = False, fired: frozenset = frozenset(), ticks: frozenset = frozenset(),
            terminal: bool = False) -> EventOutcome:
        """Modelica event iteration at time ``t``.

        Parameters
        ----------
        values : mapping
            Continuous values (states at least) at the event: the left limits.
        pre : mapping
            Discrete values before the event (discrete Reals included).
        relations_before : sequence of bool
            Relation values before the event (the hysteresis reference).
        fired : frozenset of int
            Indices of the relations whose crossing caused the event.
        ticks : frozenset of int
            The sample clocks that tick at ``t``: their ``sample()`` is true in
            this iteration, and false in the one that follows it at the same
            instant (as during integration).
        terminal : bool
            Whether ``terminal()`` is true (the iteration at the end of a run).

        After the fixed point, the reinits whose when-clause fired set their
        states, and the iteration is repeated from there (and once more
        without the clocks' ticks): the states' new values may change
        relations, and ``sample()`` is false again after its instant.
        """
        program = self.program
        left = dict(values)
        first_pre = dict(pre)
        passes = 0
        all_reinits: list = []
        terminated: list[str] = []
        done_reinits: dict[str, object] = {}
        outcome = None
        for _round in range(self.max_iterations):
            self._extra = {clock.name: clock.index in ticks for clock in program.clocks} \
                if program.hybrid else {}
            if terminal:
                self._extra[TERMINAL_NAME] = True
            outcome, reinits, stops = self._iterate_once(t, values, pre, relations_before, initial, fired,
                                                         left)
            passes += outcome.iterations
            terminated += [m for m in stops if m not in terminated]
            for name, (value, origin) in reinits.items():
                if name in done_reinits and done_reinits[name] is not origin:
                    raise EventIterationError(
                        f"at t = {t:.12g} two reinits of {name} are active at one event: "
                        f"{done_reinits[name]} and {origin}",
                        hint="at most one reinit per state and event; combine the when-clauses",
                        components=(origin.component,))
                done_reinits[name] = origin
            if not reinits and not ticks:
                break
            values = dict(outcome.values)
            for name, (value, _origin) in reinits.items():
                if name not in values or name not in outcome.system.states:
                    raise EventIterationError(
                        f"at t = {t:.12g} reinit({name}) ({_origin}): {name} is not a state of the "
                        f"system in force", hint="reinit applies to continuous states only",
                        components=(_origin.component,))
                all_reinits.append((name, values[name], value))
                values[name] = value
            # again from the new states, with sample() false; pre = the values reached
            pre = dict(outcome.discrete)
            relations_before = outcome.relations
            # a time event's relations stay at their instant (relations.ROUND_OFF); the others
            # are judged with their margins again
            fired, ticks = frozenset(k for k in fired if self.relations.kinds[k][2]), frozenset()
        else:
            self._fail(t, [], "reinitialization at events")
        changes = tuple((n, first_pre[n], outcome.discrete[n]) for n in outcome.discrete
                        if n in first_pre and outcome.discrete[n] != first_pre[n])
        return EventOutcome(outcome.discrete, outcome.relations, outcome.system, outcome.values, passes,
                            changes, tuple(all_reinits), tuple(terminated))

    def _iterate_once(self, t, values, pre, relations_before, initial, fired, left):
        """The fixed point from ``pre``, and what the when-clauses that fired ask for:
        ``(outcome, {state: (value, origin)}, [terminate messages])``."""
        program = self.program
        pre = dict(pre)
        first_pre = dict(pre)
        discrete = dict(pre)
        relations = tuple(relations_before)
        history = []
        passes = 0
        reinits: dict[str, tuple] = {}
        stops: list[str] = []
        for _outer in range(self.max_iterations):
            seen = []
            inner = [dict(discrete)]
            for _inner in range(self.max_iterations):
                passes += 1
                new_discrete, new_relations = self._pass(t, values, discrete, pre, relations,
                                                         relations_before, initial, fired, left)
                if new_discrete == discrete and new_relations == relations:
                    break
                state = (tuple(sorted(new_discrete.items())), new_relations)
                if state in seen:
                    # The fixed-point iteration cycles: search for a consistent
                    # assignment instead (as OpenModelica's mixed-system solver does).
                    found = self._search(t, values, pre, new_relations, relations_before, initial, fired,
                                         seen, new_discrete)
                    if found is None:
                        # No assignment is consistent while pre() is held (a friction element
                        # at its breakaway torque whose sliding torque is lower): take one
                        # step of Modelica's event iteration, the values the first pass gave,
                        # and let pre() follow them (pre(startForward) then keeps it sliding).
                        # The outer iteration still fails if that does not settle either.
                        discrete, relations = dict(seen[0][0]), seen[0][1]
                        inner.append(dict(discrete))
                        break
                    new_discrete, new_relations = found
                seen.append(state)
                inner.append(dict(new_discrete))
                discrete, relations = new_discrete, new_relations
            else:
                self._fail(t, history + inner, "the mixed continuous/discrete system")
            history.append(dict(discrete))
            if program.reinits or program.terminations:
                self._fired_actions(t, values, discrete, pre, relations, initial, left, reinits, stops)
            if discrete == pre:
                system = self.translation.system(self.key(discrete, pre, relations, initial))
                x = program.state_vector(system, values, discrete)
                full = mode_values(system, t, x)
                changes = tuple((n, first_pre[n], discrete[n]) for n in discrete
                                if discrete[n] != first_pre[n])
                return EventOutcome(discrete, relations, system, full, passes, changes), reinits, stops
            pre = dict(discrete)
            # The new pre values first act on the discrete equations that read no
            # relation: relation values still describe the previous discrete
            # state (sa is an acceleration while sliding, a torque while locked)
            # and must be recomputed before they decide anything.  So a friction
            # element that has just stopped (pre(mode) = Stuck) is tried locked
            # first, and static friction holds a load it can hold.
            discrete = program.evaluate(discrete, pre, relations, initial, self._extra, relation_free=True)
        self._fail(t, history, "event iteration")

    def _fired_actions(self, t, values, discrete, pre, relations, initial, left, reinits, stops) -> None:
        """The reinits and terminations whose when-clause fires with these values
        (each clause fires in one round of event iteration: where its condition
        becomes true against ``pre``)."""
        program = self.program
        env = program.environment(relations, initial, pre, self._extra)
        env.update(discrete)
        system = self.translation.system(self.key(discrete, pre, relations, initial))
        x = program.state_vector(system, values, discrete)
        env.update(program.continuous_values(system, t, x, left))
        for item, fire_args, fires, value_args, value in program.reinits:
            if fires(*[env[a] for a in fire_args]):
                earlier = reinits.get(item.variable)
                if earlier is not None and earlier[1] is not item.origin:
                    raise EventIterationError(
                        f"at t = {t:.12g} two reinits of {item.variable} are active at one event: "
                        f"{earlier[1]} and {item.origin}",
                        hint="at most one reinit per state and event; combine the when-clauses",
                        components=(item.origin.component,))
                reinits[item.variable] = (float(value(*[env[a] for a in value_args])), item.origin)
        for item, fire_args, fires in program.terminations:
            if fires(*[env[a] for a in fire_args]) and item.message not in stops:
                stops.append(item.message)

    def _pass(self, t, values, discrete, pre, relations, relations_before, initial, fired, left=None):
        """Solve the continuous part for a guess, then re-evaluate the discrete part."""
        program, evaluator = self.program, self.relations
        system = self.translation.system(self.key(discrete, pre, relations, initial))
        x = program.state_vector(system, values, discrete) if program.held else \
            [values[s] for s in system.states]
        # hysteresis against the pass before (the first pass: against the values
        # before the event), and a relation that pass decided clearly keeps its
        # value when this guess puts it exactly at its limit
        clear = self.clear if self.clear_for is not None and relations == self.clear_for else None
        raw = system.crossings(t, x) if evaluator.relations else None
        new_relations = evaluator.relation_values(system, t, x, relations, fired=fired, clear=clear, raw=raw)
        if fired and evaluator.relations:
            new_relations = evaluator.keep_crossed(raw, fired, relations, relations_before, new_relations)
        if evaluator.relations:
            self.clear, self.clear_for = evaluator.clearly_decided(raw, clear), new_relations
            self.sides = raw
        if program.continuous_args:
            self._extra.update(program.continuous_values(system, t, x, values if left is None else left))
        self.relations_now = new_relations
        return program.evaluate(discrete, pre, new_relations, initial, self._extra), new_relations

    # -- a fixed point that cycles ----------------------------------------------------------

    def _search(self, t, values, pre, relations, relations_before, initial, fired, cycle, current):
        """The first consistent assignment with fewest flips from the pre values.

        Only discrete variables that select continuous equations are searched,
        and only those of the components whose variables were cycling; the
        others follow from the discrete equations.
        """
        kinds = self.program.kinds
        cycling = {n for (a, _), (b, _) in zip(cycle, cycle[1:] + cycle[:1])
                   for (n, va), (_, vb) in zip(a, b) if va != vb}
        owners = {n.rpartition(".")[0] for n in cycling}
        selectors = [name for name in self.translation.data.selectors
                     if name in kinds and name.rpartition(".")[0] in owners]
        booleans = [n for n in selectors if kinds[n] == "boolean"]
        if not booleans:  # no Boolean chooses the equations: the relations themselves may
            return self._search_relations(t, values, pre, relations_before, initial, fired, cycle, current)
        base = {**current, **{n: pre[n] for n in booleans}}

        def flipped(chosen):
            return {**base, **{n: not base[n] for n in chosen}}, relations

        return self._first_consistent(t, values, pre, relations_before, initial, fired, booleans, flipped,
                                      lambda guess, _r, result, _rels: all(result[n] == guess[n] for n in selectors))

    def _search_relations(self, t, values, pre, relations_before, initial, fired, cycle, current):
        """The first consistent assignment of the relations that change along ``cycle``
        and the others of their components, fewest flips from the last pass's values first.

        A relation that selects equations directly (``if V0*v_in > vps then vps
        else ...``, a limiter in a loop of positive feedback) can make each pass
        undo the last: at its threshold the branch it leaves and the branch it
        enters each decide for the other, and only a third branch (the opposite
        limit) is consistent. As a mixed-system solver does, every combination
        of the relations involved is tried, each solved and re-evaluated; the
        first that reproduces itself is taken.
        """
        relations = self.relations.relations
        # only relations that select equations (a when-condition's loop is a discrete one,
        # decided by event iteration itself); time events are decided by the clock
        selecting = {name.index for name in self.key.names if name.kind == "relation"
                     and not relations[name.index].is_time_event}
        changing = {k for (_, a), (_, b) in zip(cycle, cycle[1:] + cycle[:1])
                    for k, (va, vb) in enumerate(zip(a, b)) if va != vb and k in selecting}
        # with them, the other relations of their components (the opposite limit)
        owners = {c for k in changing for c in relations[k].components}
        cycling = sorted(changing | {k for k in selecting if owners & set(relations[k].components)})
        if not changing or len(cycling) > _SEARCHED_RELATIONS:
            return None
        base = cycle[-1][1]

        def flipped(chosen):
            return current, tuple(not v if k in chosen else v for k, v in enumerate(base))

        return self._first_consistent(t, values, pre, relations_before, initial, fired, cycling, flipped,
                                      lambda _d, guess, _result, rels: all(rels[k] == guess[k] for k in cycling))

    def _first_consistent(self, t, values, pre, relations_before, initial, fired, items, flipped, consistent):
        """The first guess ``flipped(chosen)`` = ``(discrete, relations)`` that a pass
        reproduces (``consistent(discrete, relations, result, result_relations)``), the
        subsets ``chosen`` of ``items`` tried with fewest flips first; or None."""
        # every guess is judged against the same pass: the last of the cycle
        judged_against = (self.clear, self.clear_for)
        for flips in range(len(items) + 1):
            for chosen in itertools.combinations(items, flips):
                discrete, relations = flipped(set(chosen))
                self.clear, self.clear_for = judged_against
                try:
                    result, rels = self._pass(t, values, discrete, pre, relations, relations_before, initial, fired)
                except SimulationError:
                    continue  # e.g. a singular system in an impossible configuration
                if consistent(discrete, relations, result, rels):
                    return result, rels
        return None

    def _fail(self, t: float, history, what: str):
        """Raise the error of an iteration that does not settle, naming what kept changing."""
        program = self.program
        changing = sorted({n for a, b in zip(history, history[1:]) for n in a if a[n] != b[n]})
        owners = tuple(dict.fromkeys(n.rpartition(".")[0] for n in changing))
        looping = [n for n in changing
                   if program.kinds.get(n) == "discrete" and not n.rpartition(".")[2].startswith("$")]
        if looping:
            origin = program.equations[program.equation_of[looping[0]]][3]
            raise EventIterationError(
                f"at t = {t:.12g} an algebraic loop through a when-clause: the new value of "
                f"{looping[0]} ({origin}) changes the values it is computed from, and "
                f"{what} does not settle in {self.max_iterations} iterations",
                hint="a when-clause samples values at its event; break the loop, e.g. assign "
                     "from pre() of the values that depend on the variable",
                components=owners)
        hint = "the discrete variables named may flip each other back and forth; check the " \
               "conditions that set them"
        own = self.translation.data.hints_for("event_iteration", owners)
        raise EventIterationError(
            f"{what} at t = {t:.12g} did not converge in {self.max_iterations} iterations; "
            f"still changing: {', '.join(changing) or 'unknown'}",
            hint="; ".join((hint, *own)), components=owners)
