"""Stage 11: the discrete part at events — Modelica's event iteration.

At an event instant, with the ``pre()`` values held fixed, the continuous
equations (of the discrete state the current guess selects) and the
discrete equations are solved together by fixed-point iteration; then, if a
discrete variable differs from its ``pre()`` value, ``pre`` takes the new
values and the whole is repeated until nothing changes (Otter, Elmqvist &
Mattsson 1999; Dymola and OpenModelica do the same).

Relations are evaluated with the continuous values at the event, with a
small hysteresis against their value before it (see
:meth:`acausal.compiler.partition.Relation.shifted`).

Impure functions (:class:`acausal.functions.ImpureFunction`) in the
discrete equations draw once per event iteration and call site, from a
state the run owns (:class:`ImpureCalls`): the passes of one iteration see
the value its first evaluation computed.

References
----------
.. [1] M. Otter, H. Elmqvist and S. E. Mattsson, "Hybrid modeling in Modelica
   based on the synchronous data flow principle", Proc. CACSD'99, 1999.
"""

from __future__ import annotations

import copy
import heapq
import itertools
import math
import operator
from dataclasses import dataclass, field
from typing import Callable, Mapping

import numpy as np

from ..errors import EventIterationError, SimulationError
from ..names import INITIAL_NAME, TERMINAL_NAME, is_relation, parse, pre_name, relation_name
from .contract import CompiledModel, CompiledSystem
from .relations import decide, decide_many, kind_arrays

__all__ = ["DiscreteEvaluator", "EventOutcome", "ImpureCalls", "evaluator_for", "mode_values"]


#: From this many watched relations on, they are checked with numpy at once.
_VECTORISE_FROM = 48

#: Up to this many watched relations, a composed system computes the crossing
#: functions of the parts that own them only.
_FEW_RELATIONS = 8

#: Event iteration that cycles searches the combinations of at most this many relations
#: (2**n solves) for a consistent one (:meth:`DiscreteEvaluator._search_relations`).
_SEARCHED_RELATIONS = 8

#: Samples times (watched relations + 2) from which the relations at the samples of a
#: step are decided in one numpy call rather than sample by sample.
_MANY_FROM = 40


def mode_values(system: CompiledSystem, t: float, x) -> dict[str, float]:
    """All continuous variables at ``(t, x)``: unknowns, states and aliases."""
    return with_aliases(system.values(t, x), system)


def with_aliases(values: dict[str, float], system) -> dict[str, float]:
    """``values`` (changed in place and returned) with the aliases of ``system`` added."""
    for name, coeff, source in getattr(system, "alias_plan", ()) or ():
        if source is None:
            values[name] = coeff
        elif source in values:  # with an output demand, some are not computed
            values[name] = coeff * values[source]
    return values


def evaluator_for(translation: CompiledModel, relation_epsilon: float = 1e-10,
                  max_iterations: int = 20, incremental: bool = True) -> "DiscreteEvaluator":
    """The discrete-part evaluator of ``translation``, built once per setting and kept
    with the translation (compiling the discrete equations is a few milliseconds)."""
    cache = translation.extras.setdefault("evaluators", {})
    key = (relation_epsilon, max_iterations, incremental)
    if key not in cache:
        cache[key] = DiscreteEvaluator(translation, relation_epsilon, max_iterations, incremental)
    return cache[key]


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


@dataclass
class ImpureCalls:
    """The state of a run's impure functions (:class:`~acausal.functions.ImpureFunction`).

    Attributes
    ----------
    streams : dict
        Each function's state, by its ``stream``: the dict its ``_impure_``
        reads and changes (empty until its first call in the run).
    values : dict
        The value of each call site in the event iteration in progress (by
        site number); cleared when the next one opens.
    open : bool
        Whether an event iteration (or the initialization) is in progress: only
        then does a call change its state.
    calls : int
        How many values were computed with their side effect in this run.
    """

    streams: dict = field(default_factory=dict)
    values: dict = field(default_factory=dict)
    open: bool = False
    calls: int = 0


def _getter(items: list):
    """``m -> tuple(m[i] for i in items)`` at C speed (operator.itemgetter, always a tuple)."""
    if not items:
        return lambda _m: ()
    if len(items) == 1:
        only = items[0]
        return lambda m: (m[only],)
    return operator.itemgetter(*items)


def _cast(kind: str, value):
    """A discrete equation's value as its variable's type."""
    if kind == "boolean":
        return bool(value)
    if kind == "integer":
        return int(value)
    return float(value)


class DiscreteEvaluator:
    """Evaluates relations and discrete equations of a translated model."""

    def __init__(self, translation: CompiledModel, relation_epsilon: float = 1e-10,
                 max_iterations: int = 20, incremental: bool = True) -> None:
        self.translation = translation
        #: whether a pass of event iteration re-evaluates only what changed since the
        #: last (:meth:`_evaluate_again`) and the relevant relations are found again only
        #: where something changed (:attr:`acausal.options.EngineOptions.incremental_events`);
        #: False evaluates everything, with the same results
        self.incremental = incremental
        #: the model's data (names, kinds, relations, clocks: plain values)
        self.data = data = translation.data
        self.relations = data.relations
        self.epsilon = relation_epsilon
        self.max_iterations = max_iterations
        variables = data.variable_map
        self.held = data.held_variables
        self.kinds = {n: variables[n].kind for n in (*data.discrete_variables, *self.held)}
        #: the run's impure functions (their state, the values of this event's call sites)
        self.impure = ImpureCalls()
        # compiled by the translation (the one callback into the compiler); the call
        # sites of impure functions call back into this evaluator
        program = translation.discrete_program(self._impure_call)
        self.impure_sites = program.impure_sites
        self.equations = list(program.equations)
        arguments = [args for _variable, args, _fn, _origin in self.equations]
        self._setup_hybrid(translation, program, arguments)
        #: the equations reading each name, in evaluation order
        self._readers: dict[str, list[int]] = {}
        for i, (_variable, args, _fn, _origin) in enumerate(self.equations):
            for a in args:
                self._readers.setdefault(a, []).append(i)
        self._downstream = self._downstream_equations()
        self._selector_names = tuple(parse(name) for name in data.selectors)
        self._vector_plan = None
        #: which relations the last pass of event iteration decided beyond their
        #: margin, and the relation values it produced (see :meth:`_pass`)
        self._clear: tuple[bool, ...] | None = None
        self._clear_for = None
        self._scalar_plan = None
        self._kinds = [(1.0 if r.op in (">", ">=") else -1.0, r.op in (">", "<"), r.is_time_event)
                       for r in self.relations]
        #: each relation's margin, epsilon * max(floor, |lhs|, |rhs|): the crossing margin, or
        #: round-off relative to the sides alone for a relation free of integration noise
        #: (Relation.is_exact: two forces rising from 0 on one sine cross together)
        self._margins, self._floors = (tuple(m) for m in zip(
            *[r.margin_parameters(relation_epsilon) for r in self.relations])) if self.relations else ((), ())
        self._relation_names = [relation_name(k) for k in range(len(self.relations))]
        self._pre_names: dict[str, str] = {}
        self._selector_set = frozenset(data.selectors)
        #: the last pass: (pre, initial, relations, the values it started from, result)
        self._last: tuple | None = None
        self._relation_free = [eq for eq in self.equations if not any(is_relation(a) for a in eq[1])]
        self._equation_of = {eq[0]: i for i, eq in enumerate(self.equations)}
        # where each argument of each equation comes from in a pass: True for a variable
        # whose own equation comes earlier (its value in this pass), False for what the
        # pass starts from (relations, pre() values, initial(), later variables)
        own = self._equation_of
        self._argument_sources = [[(a, a in own and own[a] < i) for a in args]
                                  for i, (_variable, args, _fn, _origin) in enumerate(self.equations)]
        #: the equations that read a variable's value the pass starts from
        self._early_readers: dict[str, list[int]] = {}
        for i, sources in enumerate(self._argument_sources):
            for a, late in sources:
                if not late and a in self.kinds:
                    self._early_readers.setdefault(a, []).append(i)
        #: relations that cross together at the last event (see :meth:`_twins_at`)
        self._twins: dict[int, tuple[int, ...]] = {}
        #: the relations' sides in the last pass of event iteration, and those the
        #: twins were found from (found once per event, when relevance is asked)
        self._raw_last = self._twins_from = None
        #: the relations whose relevance check (:meth:`_flip_changes`) reads each name
        self._checks_reading: dict[str, set[int]] = {}
        for k in range(len(self.relations)):
            for i in self._downstream[k]:
                variable, args, _fn, _origin = self.equations[i]
                for name in (*args, variable, relation_name(k)):
                    self._checks_reading.setdefault(name, set()).add(k)
        self._last_relevance: tuple | None = None
        self._kind_arrays: tuple | None = None
        self._relations_now: tuple | None = None
        self._margin_arrays: tuple | None = None
        self._key_plan = None
        #: (relation, whether it is a selector) of the state relations, and the pairs of state
        #: relations of one component and direction: made on first use
        self._watch_plan: list | None = None
        self._pairs = False

    def _setup_hybrid(self, translation: CompiledModel, program, arguments) -> None:
        """What the discrete equations read besides discrete values and relations
        (continuous values, their left limits, sample clocks, terminal()), and the
        reinits, terminations and assertions of ``program``."""
        self.clocks = self.data.clocks
        own = {*self.kinds, INITIAL_NAME, TERMINAL_NAME}
        parameters = self.data.parameter_table
        #: the parameters the discrete equations, reinits and assertions read
        self._constants: dict[str, float] = {}

        def continuous_reads(names) -> set[str]:
            out = set()
            for a in names:
                what = parse(a)
                if a in parameters:
                    self._constants[a] = parameters[a]
                    continue
                if a in own or what.kind in ("relation", "sample") or (
                        what.kind == "pre" and what.base in self.kinds):
                    continue
                out.add(a)
            return out

        self._continuous_args = set().union(*map(continuous_reads, arguments)) if arguments else set()
        self.reinits = list(program.reinits)
        self.terminations = list(program.terminations)
        self.asserts = list(program.asserts)
        for _r, fire_args, _f, value_args, _v in self.reinits:
            self._continuous_args |= continuous_reads(fire_args) | continuous_reads(value_args)
        for _r, fire_args, _f in self.terminations:
            self._continuous_args |= continuous_reads(fire_args)
        self._assert_continuous = set()
        for _a, args, _f in self.asserts:
            self._assert_continuous |= continuous_reads(args)
        #: whether anything reads terminal() (then the run ends with one more event iteration)
        self.uses_terminal = any(TERMINAL_NAME in args for args in arguments) or any(
            TERMINAL_NAME in item[1] for item in (*self.reinits, *self.terminations)) or any(
            TERMINAL_NAME in args for _a, args, _f in self.asserts)
        #: values the environment of a pass adds (clocks, terminal(), continuous values)
        self._extra: dict = {}
        self._hybrid = bool(self._continuous_args or self.clocks or self.held or self.reinits
                            or self.terminations or self._constants or self.asserts)

    # -- impure functions ---------------------------------------------------------

    def start_run(self) -> None:
        """A new run: the impure functions start from empty states again."""
        self.impure = ImpureCalls()

    def open_instant(self) -> None:
        """An event iteration (or the initialization) begins: each impure call site
        computes one value in it, at its first evaluation."""
        self.impure.values = {}
        self.impure.open = True

    def close_instant(self) -> None:
        """The event iteration is over: impure calls no longer change their state."""
        self.impure.open = False

    def _impure_call(self, site: int, function: type, *args):
        """What the generated code of call site ``site`` evaluates (see :class:`ImpureCalls`)."""
        calls = self.impure
        if not calls.open:
            # a question about a possible event (which relations to watch): the value the
            # next call would give, computed on a copy so that the state does not move
            return function._impure_(copy.deepcopy(calls.streams.get(function.stream, {})), *args)
        if site in calls.values:
            return calls.values[site]
        value = function._impure_(calls.streams.setdefault(function.stream, {}), *args)
        calls.values[site] = value
        calls.calls += 1
        return value

    def _continuous_env(self, system: CompiledSystem, t: float, x, left: Mapping) -> dict:
        """The continuous values the discrete equations read at ``(t, x)``, and the left
        limits (``pre(u)`` of a continuous ``u``)."""
        if not self._continuous_args:
            return {}
        values = mode_values(system, t, x)
        env = {}
        for name in self._continuous_args:
            what = parse(name)
            if what.kind == "pre":
                env[name] = left.get(what.base, values.get(what.base, float("nan")))
            elif name == "time":
                env[name] = t
            else:
                env[name] = values.get(name, float("nan"))
        return env

    def prepare(self, system: CompiledSystem | None, t: float, x) -> None:
        """Set the continuous values the discrete equations read (outside event iteration:
        during initialization, where ``pre(u)`` of a continuous ``u`` is ``u``); None clears."""
        self._extra = {clock.name: False for clock in self.clocks} if self._hybrid else {}
        if system is not None and self._continuous_args:
            values = mode_values(system, t, x)
            self._extra.update(self._continuous_env(system, t, x, values))

    def _states(self, system: CompiledSystem, values: Mapping, discrete: Mapping) -> list:
        """The state vector of ``system``: held values from ``discrete``, the rest from ``values``."""
        return [discrete[s] if s in self.kinds else values[s] for s in system.states]

    def check_asserts(self, t: float, system: CompiledSystem, x, discrete: Mapping, pre: Mapping,
                      initial: bool = False, terminal: bool = False) -> list:
        """The assertions violated at ``(t, x)``: ``[(FlatAssert, message)]`` (``terminal``:
        at the end of the run, where ``terminal()`` is true)."""
        if not self.asserts:
            return []
        env = self._environment(self._relations_now or (), initial, pre)
        env[TERMINAL_NAME] = terminal
        env.update(discrete)
        if self._assert_continuous:
            values = mode_values(system, t, x)
            for name in self._assert_continuous:
                what = parse(name)
                env[name] = t if name == "time" else values.get(what.base if what.kind == "pre" else name,
                                                                float("nan"))
        out = []
        for item, args, fn in self.asserts:
            try:
                holds = fn(*[env[a] for a in args])
            except KeyError:
                continue
            if not holds:
                out.append((item, f"assertion {'failed' if item.level == 'error' else 'warning'} at "
                                  f"t = {t:.12g}: {item.message} ({item.origin})"))
        return out

    def _downstream_equations(self) -> dict[int, list[int]]:
        """For each relation, the discrete equations (in order) its value can reach."""
        readers = self._readers
        out = {}
        for k, rel in enumerate(self.relations):
            reached, frontier = set(), [rel.name]
            while frontier:
                name = frontier.pop()
                for i in readers.get(name, ()):
                    if i not in reached:
                        reached.add(i)
                        frontier.append(self.equations[i][0])
            out[k] = sorted(reached)
        return out

    # -- keys -----------------------------------------------------------------

    def key(self, discrete: Mapping, pre: Mapping, relations, initial: bool) -> tuple:
        """The discrete state: each selector's value in the selectors' order (a relation's
        value as a bool, ``pre(v)`` from ``pre``, a discrete variable from ``discrete``,
        ``initial()``)."""
        plan = self._key_plan
        if plan is None:
            plan = self._key_plan = self._make_key_plan()
        of_relations, of_pre, of_discrete, order = plan
        return order((*map(bool, of_relations(relations)), *of_pre(pre), *of_discrete(discrete), bool(initial)))

    def _make_key_plan(self):
        """``key``'s getters, made once: the selectors' values gathered by kind (C-level
        itemgetters), then put in the selectors' order."""
        groups: dict[str, list] = {"relation": [], "pre": [], "discrete": []}
        where = []
        for name in self._selector_names:
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
        return (_getter(groups["relation"]), _getter(groups["pre"]), _getter(groups["discrete"]),
                _getter([offsets[kind] + k for kind, k in where]))

    # -- relations --------------------------------------------------------------

    def relation_values(self, system: CompiledSystem, t: float, x, previous, exact: bool = False,
                        fired: frozenset = frozenset(), clear=None, raw=None):
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
        ``u`` stepped to exactly 0 becomes true.)
        """
        if not self.relations:
            return ()
        if raw is None:
            raw = system.crossings(t, x)
        if len(self._kinds) >= _VECTORISE_FROM:
            if self._kind_arrays is None:
                self._kind_arrays = kind_arrays(self._kinds)
            return decide_many(self._kinds, raw, previous, self._margins, floor=self._floors, exact=exact,
                               fired=fired, clear=clear, arrays=self._kind_arrays)
        return decide(self._kinds, raw, previous, self._margins, floor=self._floors, exact=exact, fired=fired,
                      clear=clear)

    def clearly_decided(self, raw, inherited=None) -> tuple[bool, ...]:
        """Whether each relation's ``lhs - rhs`` (``raw``: the sides, as ``crossings``
        gives them) lies beyond its margin, or is exactly at its limit and kept a
        value decided clearly before (``inherited``: the answer for the pass before)."""
        self._raw_last = raw
        if len(self._margins) >= _VECTORISE_FROM:
            # the same doubles as below, with numpy: |lhs - rhs| > eps * max(floor, |lhs|, |rhs|)
            # (a NaN side makes the comparison false either way)
            if self._margin_arrays is None:
                self._margin_arrays = (np.array(self._margins, dtype=float), np.array(self._floors, dtype=float))
            margins, floors = self._margin_arrays
            with np.errstate(invalid="ignore", over="ignore"):
                values = np.asarray(raw, dtype=float)
                lhs, rhs = values[0::2], values[1::2]
                scale = np.maximum(np.maximum(floors, np.abs(lhs)), np.abs(rhs))
                clear = np.abs(lhs - rhs) > margins * scale
                equal = lhs == rhs
                if equal.any():
                    clear[equal] = False if inherited is None else np.asarray(inherited, dtype=bool)[equal]
            return tuple(clear.tolist())
        out = []
        for k, (epsilon, floor) in enumerate(zip(self._margins, self._floors)):
            lhs, rhs = raw[2 * k], raw[2 * k + 1]
            if lhs == rhs:
                out.append(bool(inherited is not None and inherited[k]))
            else:
                out.append(abs(lhs - rhs) > epsilon * max(floor, abs(lhs), abs(rhs)))
        return tuple(out)

    def flipped_relations(self, system: CompiledSystem, t: float, x, relations,
                          watched: tuple[int, ...]) -> tuple[int, ...]:
        """The watched relations whose value at ``(t, x)`` differs from ``relations``.

        The hot path of event detection: only the watched relations are
        evaluated (with hysteresis against their current values).
        """
        if not watched:
            return ()
        raw = (system.crossings_for(watched) if len(watched) <= _FEW_RELATIONS else system.crossings)(t, x)
        if len(watched) >= _VECTORISE_FROM:
            return self._flipped_vectorised(raw, relations, watched)
        # Relation.holds_with_hysteresis, inlined: g = lhs - rhs moved by the margin
        # towards the previous value, d = +1 for > and >=, -1 for < and <=; then
        # d * (g ± eps) > 0 (strict) or >= 0 -- the same roundings (negation and
        # adding -eps are exact)
        plan = self._scalar_plan
        if plan is None or plan[0] is not watched or plan[1] is not relations:
            plan = self._scalar_plan = (watched, relations, [
                (k, 2 * k, *self._relation_kind(k, relations[k]), self._margins[k], self._floors[k])
                for k in watched])
        out = []
        for k, i, d, toward, strict, timed, previous, epsilon, floor in plan[2]:
            lhs, rhs = raw[i], raw[i + 1]
            if timed:
                v = d * (lhs - rhs)
            else:
                v = d * ((lhs - rhs) + toward * (epsilon * max(floor, abs(lhs), abs(rhs))))
            if (v > 0 if strict else v >= 0) != previous:
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
        crossings = system.crossings_for(tuple(sorted(candidates)))
        terms = []
        for k in candidates:
            d, toward, _strict, timed, previous = self._relation_kind(k, relations[k])
            terms.append((2 * k, -1.0 if previous else 1.0, d, timed, toward, self._margins[k], self._floors[k]))

        def distance(t, x) -> float:
            raw = crossings(t, x)
            best = -math.inf
            for i, sign, d, timed, toward, epsilon, floor in terms:
                lhs, rhs = raw[i], raw[i + 1]
                if timed:
                    value = sign * (d * (lhs - rhs))
                else:
                    value = sign * (d * ((lhs - rhs) + toward * (epsilon * max(floor, abs(lhs), abs(rhs)))))
                if value > best:
                    best = value
            return best

        return distance

    def _relation_kind(self, k: int, previous: bool) -> tuple[float, float, bool, bool, bool]:
        """``(d, toward, strict, timed, previous)`` of relation ``k``: ``d`` is +1 for ``>``
        and ``>=``, -1 for ``<`` and ``<=``; the margin moves ``g`` by ``toward * eps``."""
        rel = self.relations[k]
        d = 1.0 if rel.op in (">", ">=") else -1.0
        return d, d if previous else -d, rel.op in (">", "<"), rel.is_time_event, bool(previous)

    def _flipped_vectorised(self, raw, relations, watched) -> tuple[int, ...]:
        """:meth:`flipped_relations` for many relations at once, with numpy.

        The same arithmetic as :meth:`Relation.holds_with_hysteresis`, written
        so that every operation rounds the same way: ``d * (g ± eps)`` with
        ``d = ±1`` compared with 0 (``>`` for strict relations, ``>=`` not).
        """
        with np.errstate(invalid="ignore", over="ignore"):  # inf/NaN sides decide as in Python
            w, flips = self._flips(np.asarray(raw, dtype=float), relations, watched)
        return tuple(w[flips].tolist())

    def _plan(self, relations, watched):
        plan = self._vector_plan
        if plan is None or plan[0] is not watched or plan[1] is not relations:
            w = np.array(watched, dtype=int)
            kinds = [self._relation_kind(k, relations[k]) for k in watched]
            d = np.array([kind[0] for kind in kinds])
            toward = np.array([kind[1] for kind in kinds])
            strict = np.array([kind[2] for kind in kinds], dtype=bool)
            timed = np.array([kind[3] for kind in kinds], dtype=bool)
            previous = np.array([kind[4] for kind in kinds], dtype=bool)
            margin = np.array([self._margins[k] for k in watched])
            floor = np.array([self._floors[k] for k in watched])
            columns = tuple(a[:, None] for a in (d, toward, strict, previous, margin, floor))
            plan = self._vector_plan = (watched, relations, w, 2 * w, 2 * w + 1,
                                        (d, toward, strict, previous, margin, floor), columns, timed,
                                        bool(timed.any()))
        return plan

    def _flips(self, values: np.ndarray, relations, watched):
        """``(w, flipped)``: the watched relations' indices, and whether each has
        flipped at each column of ``values`` (the crossing functions' values, one
        instant a column; or one instant as a vector)."""
        _, _, w, left, right, vectors, columns, timed, any_timed = self._plan(relations, watched)
        d, toward, strict, previous, margin, floor = columns if values.ndim == 2 else vectors
        lhs, rhs = values[left], values[right]
        # (callers silence numpy's warnings: inf/NaN sides decide as in Python)
        eps = np.maximum(np.abs(lhs), np.abs(rhs))
        np.maximum(eps, floor, out=eps)
        eps *= margin
        if any_timed:
            eps[timed] = 0.0
        v = lhs - rhs
        v += toward * eps
        v *= d
        holds = np.where(strict, v > 0, v >= 0)
        return w, holds != previous

    def first_flip(self, system: CompiledSystem, times, states, relations,
                   watched: tuple[int, ...]) -> tuple[int, tuple[int, ...]] | None:
        """The first of ``times`` at which a watched relation has flipped.

        ``states`` holds the state at each time as a row.  Returns ``(index,
        flipped)`` with ``flipped`` as :meth:`flipped_relations` gives it at that
        instant, or None: exactly what calling :meth:`flipped_relations` at each
        time in turn gives (the first flip, and any error on the way).

        The relations are decided for all times at once, with numpy
        (:meth:`_flips`), on the crossing functions' values: from one numpy call
        when the system's code allows it
        (the system's ``vectorised("crossings")``; from an instant
        whose values are not all finite on, or if it raises, the scalar function
        decides instant by instant), else from the scalar function at each time.
        A few samples of few relations are decided one by one: a numpy call has
        a fixed cost of some tens of microseconds.
        """
        m = len(times)
        if not watched or not m:
            return None
        start = 0
        if m * (len(watched) + 2) >= _MANY_FROM:
            many = system.vectorised("crossings")
            if many is not None:
                found, start = self._first_flip_many(many, times, states, relations, watched)
            else:
                found, start = self._first_flip_collected(system, times, states, relations, watched)
            if found is not None or start >= m:
                return found
        for i in range(start, m):
            hit = self.flipped_relations(system, times[i], states[i], relations, watched)
            if hit:
                return i, hit
        return None

    def _first_flip_many(self, many, times, states, relations, watched):
        """``(first flip, None)`` or ``(None, index to go on from)`` with the numpy crossings."""
        m = len(times)
        try:
            # a division by zero or an invalid operation (where Python's floats could
            # raise) leaves the instants to the scalar function
            with np.errstate(divide="raise", invalid="raise", over="ignore", under="ignore"):
                raw = many(np.asarray(times, dtype=float), np.asarray(states, dtype=float).T)
            with np.errstate(all="ignore"):
                w, flips = self._flips(raw, relations, watched)
        except Exception:  # the scalar function raises where it should, or not at all
            return None, 0
        stop = flips.any(axis=0)
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
        are those :meth:`flipped_relations` decides on."""
        columns = []
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
                w, flips = self._flips(raw, relations, watched)
        except (TypeError, ValueError):  # values that are no numbers: decided one by one
            return None, 0
        stop = flips.any(axis=0)
        if not stop.any():
            return None, len(columns)
        first = int(np.argmax(stop))
        return (first, tuple(w[flips[:, first]].tolist())), len(times)

    # -- discrete equations -------------------------------------------------------

    def evaluate_discrete(self, discrete: Mapping, pre: Mapping, relations, initial: bool,
                          relation_free: bool = False) -> dict:
        """One pass over the discrete equations in dependency order.

        With ``relation_free`` only the equations that read no relation are
        evaluated; the others keep their values.
        """
        if not relation_free:
            found = self._evaluate_again(discrete, pre, relations, initial)
            if found is not None:
                return found
        current = dict(discrete)
        env = self._environment(relations, initial, pre)
        env.update(current)
        start = dict(env) if not relation_free else None
        for variable, args, fn, origin in (self._relation_free if relation_free else self.equations):
            value = _cast(self.kinds[variable], fn(*[env[a] for a in args]))
            current[variable] = env[variable] = value
        if not relation_free:
            self._last = (dict(pre), initial, tuple(relations), start, dict(current))
        return current

    def _evaluate_again(self, discrete: Mapping, pre: Mapping, relations, initial: bool) -> dict | None:
        """A pass computed from the last one, re-evaluating only the equations whose
        inputs changed (None: evaluate all).

        What an equation reads in a pass: relations, ``pre()`` values and
        initial(); the value a variable has in this pass when its own equation
        comes earlier; and the value the pass *starts* from when it comes later
        (or the variable has none: a discrete loop).  The equations for which
        one of these changed since the last pass are evaluated, in evaluation
        order, and then those reading a result that changed; every other
        equation reads what it read in the last pass, so it keeps its value.
        With many independent parts this keeps event iteration local to the
        parts concerned.
        """
        last = self._last
        if last is None or last[1] != initial or not self.incremental or self._hybrid:
            return None  # (continuous values and clocks are not tracked: evaluate all)
        last_pre, _, before, old_start, old_result = last
        if len(before) != len(relations) or len(old_result) != len(discrete):
            return None
        changed = {self._relation_names[k]: relations[k]
                   for k, (a, b) in enumerate(zip(relations, before)) if a != b}
        for name, value in pre.items():
            if last_pre.get(name, not value) != value:
                changed[self._pre_key(name)] = value
        for name, value in discrete.items():
            if old_start.get(name, not value) != value:
                changed[name] = value
        if len(changed) * 4 > len(self.equations) + len(relations):
            return None  # most of it changed: evaluate all
        start = dict(old_start)
        start.update(changed)
        readers, early = self._readers, self._early_readers
        todo = set()
        for name in changed:
            # a relation, pre() value or initial(): every reader; a variable: the
            # readers that see the value the pass starts from
            todo.update(early.get(name, ()) if name in self.kinds else readers.get(name, ()))
        current = dict(old_result)
        for name in changed:
            if name in self.kinds and name not in self._equation_of:
                current[name] = start[name]  # no equation: it keeps the value it starts with
        heap = sorted(todo)
        done: set[int] = set()
        sources = self._argument_sources
        while heap:
            i = heapq.heappop(heap)
            if i in done:
                continue
            done.add(i)
            variable, args, fn, origin = self.equations[i]
            value = _cast(self.kinds[variable], fn(*[current[a] if late else start[a] for a, late in sources[i]]))
            if value != current[variable]:
                current[variable] = value
                for j in readers.get(variable, ()):
                    if j > i:  # an earlier reader sees the value the pass starts with
                        heapq.heappush(heap, j)
        self._last = (dict(pre), initial, tuple(relations), start, dict(current))
        return current

    def _environment(self, relations, initial: bool, pre: Mapping) -> dict:
        """The names the discrete equations read: relation indicators, initial(), pre values."""
        env = dict(zip(self._relation_names, relations))
        env[INITIAL_NAME] = initial
        pre_key = self._pre_key
        for name, value in pre.items():
            env[pre_key(name)] = value
        if self._hybrid:
            env[TERMINAL_NAME] = False
            for clock in self.clocks:
                env[clock.name] = False
            env.update(self._constants)
            env.update(self._extra)
        return env

    def _pre_key(self, name: str) -> str:
        """``pre(name)`` as the discrete equations name it (made once per name)."""
        key = self._pre_names.get(name)
        if key is None:
            key = self._pre_names[name] = pre_name(name)
        return key

    def relevant_relations(self, discrete: Mapping, relations) -> tuple[int, ...]:
        """State relations whose flip could change something in this discrete state.

        A relation that only matters in another mode (``sa > tau0_max`` while
        sliding) need not be watched: flipping it alone leaves every discrete
        variable as it is.  Relations that select continuous equations are
        always watched.  At the next event all relations are re-evaluated.
        """
        if self._raw_last is not self._twins_from:
            self._twins, self._twins_from = self._twins_at(self._raw_last), self._raw_last
        selector_names = self._selector_set
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
            env = self._environment(relations, False, discrete)
            env.update(discrete)
            for k in again:
                checked[k] = self._flip_changes(k, env, discrete, relations)
        self._last_relevance = (dict(discrete), tuple(relations), dict(checked), self._twins)
        plan = self._watch_plan
        if plan is None:
            plan = self._watch_plan = [(k, rel.name in selector_names) for k, rel in enumerate(self.relations)
                                       if not rel.is_time_event]
        return tuple([k for k, selects in plan if selects or checked[k]])

    def _always_watched(self) -> frozenset:
        """Relations whose flip reaches a discrete equation that reads continuous values
        or clocks: whether the flip changes something cannot be tried out, so they are
        always watched."""
        found = getattr(self, "_always", None)
        if found is None:
            reads_more = set()
            for i, (_variable, args, _fn, _origin) in enumerate(self.equations):
                if any(a in self._continuous_args or parse(a).kind in ("sample", "terminal") for a in args):
                    reads_more.add(i)
            found = self._always = frozenset(k for k in range(len(self.relations))
                                             if reads_more.intersection(self._downstream[k]))
        return found

    def _relevance_again(self, discrete: Mapping, relations) -> dict | None:
        """The last answers of :meth:`_flip_changes`, and under the key None the relations
        to check again: those whose check reads a discrete value or a relation that
        changed since (None: check all)."""
        last = self._last_relevance
        if last is None or not self.incremental or self._hybrid or len(last[1]) != len(relations) \
                or len(last[0]) != len(discrete) or last[3] != self._twins:
            return None
        old_discrete, old_relations, answers, _twins = last
        names = [self._relation_names[k] for k, (a, b) in enumerate(zip(relations, old_relations)) if a != b]
        for name, value in discrete.items():
            if old_discrete.get(name, not value) != value:
                names += [name, self._pre_key(name)]
        if len(names) * 4 > len(relations) + len(discrete):
            return None
        again = set()
        for name in names:
            again.update(self._checks_reading.get(name, ()))
        out = dict(answers)
        out[None] = sorted(k for k in again if k in answers)
        return out

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
            groups.setdefault((rel.components, self._kinds[k][0], raw[2 * k], raw[2 * k + 1]), []).append(k)
        return {k: tuple(j for j in group if j != k)
                for group in groups.values() if len(group) > 1 for k in group}

    def _twin_candidates(self):
        """``(a, b)``: the pairs of state relations of one component and direction (numpy
        index arrays, ``a < b``), made once; None for a few relations."""
        found = self._pairs
        if found is False:
            found = None
            if len(self.relations) >= _VECTORISE_FROM:
                static: dict[tuple, list[int]] = {}
                for k, rel in enumerate(self.relations):
                    if not rel.is_time_event:
                        static.setdefault((rel.components, self._kinds[k][0]), []).append(k)
                pairs = [(k, j) for group in static.values() for i, k in enumerate(group) for j in group[i + 1:]]
                found = (np.array([k for k, _ in pairs], dtype=int), np.array([j for _, j in pairs], dtype=int))
            self._pairs = found
        return found

    def _flip_changes(self, k: int, env: Mapping, discrete: Mapping, relations) -> bool:
        """Whether flipping relation k, alone or together with its twins, changes a
        discrete variable (pre = current)."""
        if self._flip_changes_of((k,), env, discrete, relations):
            return True
        twins = self._twins.get(k)
        return bool(twins) and self._flip_changes_of((k, *twins), env, discrete, relations)

    def _flip_changes_of(self, ks: tuple[int, ...], env: Mapping, discrete: Mapping, relations) -> bool:
        """Whether flipping relation k alone changes a discrete variable (pre = current).

        Only the equations downstream of the relation are evaluated; they see
        ``env`` with the relation flipped.  (A variable they recompute keeps
        its value, or the answer is already yes.)
        """
        flipped = {relation_name(k): not relations[k] for k in ks}
        downstream = self._downstream[ks[0]] if len(ks) == 1 else \
            sorted(set().union(*(self._downstream[k] for k in ks)))
        for i in downstream:
            variable, args, fn, _origin = self.equations[i]
            value = _cast(self.kinds[variable], fn(*[flipped[a] if a in flipped else env[a] for a in args]))
            if value != discrete[variable]:
                return True
        return False

    # -- event iteration ------------------------------------------------------------

    def iterate(self, t: float, values: Mapping[str, float], pre: Mapping, relations_before,
                initial: bool = False, fired: frozenset = frozenset(), ticks: frozenset = frozenset(),
                terminal: bool = False) -> EventOutcome:
        """Modelica event iteration at time ``t`` (see :meth:`_iterate`); each impure
        call site computes at most one value in it."""
        if not self.impure_sites:
            return self._iterate(t, values, pre, relations_before, initial, fired, ticks, terminal)
        self.open_instant()
        try:
            return self._iterate(t, values, pre, relations_before, initial, fired, ticks, terminal)
        finally:
            self.close_instant()

    def _iterate(self, t: float, values: Mapping[str, float], pre: Mapping, relations_before,
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
        left = dict(values)
        first_pre = dict(pre)
        passes = 0
        all_reinits: list = []
        terminated: list[str] = []
        done_reinits: dict[str, object] = {}
        outcome = None
        for _round in range(self.max_iterations):
            self._extra = {clock.name: clock.index in ticks for clock in self.clocks} \
                if self._hybrid else {}
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
            fired, ticks = frozenset(k for k in fired if self._kinds[k][2]), frozenset()
        else:
            self._fail(t, [], "reinitialization at events")
        self._extra = {}
        changes = tuple((n, first_pre[n], outcome.discrete[n]) for n in outcome.discrete
                        if n in first_pre and outcome.discrete[n] != first_pre[n])
        return EventOutcome(outcome.discrete, outcome.relations, outcome.system, outcome.values, passes,
                            changes, tuple(all_reinits), tuple(terminated))

    def _iterate_once(self, t, values, pre, relations_before, initial, fired, left):
        """The fixed point from ``pre``, and what the when-clauses that fired ask for:
        ``(outcome, {state: (value, origin)}, [terminate messages])``."""
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
            if self.reinits or self.terminations:
                self._fired_actions(t, values, discrete, pre, relations, initial, left, reinits, stops)
            if discrete == pre:
                system = self.translation.system(self.key(discrete, pre, relations, initial))
                x = self._states(system, values, discrete)
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
            discrete = self.evaluate_discrete(discrete, pre, relations, initial, relation_free=True)
        self._fail(t, history, "event iteration")

    def _fired_actions(self, t, values, discrete, pre, relations, initial, left, reinits, stops) -> None:
        """The reinits and terminations whose when-clause fires with these values
        (each clause fires in one round of event iteration: where its condition
        becomes true against ``pre``)."""
        env = self._environment(relations, initial, pre)
        env.update(discrete)
        system = self.translation.system(self.key(discrete, pre, relations, initial))
        x = self._states(system, values, discrete)
        env.update(self._continuous_env(system, t, x, left))
        for item, fire_args, fires, value_args, value in self.reinits:
            if fires(*[env[a] for a in fire_args]):
                earlier = reinits.get(item.variable)
                if earlier is not None and earlier[1] is not item.origin:
                    raise EventIterationError(
                        f"at t = {t:.12g} two reinits of {item.variable} are active at one event: "
                        f"{earlier[1]} and {item.origin}",
                        hint="at most one reinit per state and event; combine the when-clauses",
                        components=(item.origin.component,))
                reinits[item.variable] = (float(value(*[env[a] for a in value_args])), item.origin)
        for item, fire_args, fires in self.terminations:
            if fires(*[env[a] for a in fire_args]) and item.message not in stops:
                stops.append(item.message)

    def _pass(self, t, values, discrete, pre, relations, relations_before, initial, fired, left=None):
        """Solve the continuous part for a guess, then re-evaluate the discrete part."""
        system = self.translation.system(self.key(discrete, pre, relations, initial))
        x = self._states(system, values, discrete) if self.held else [values[s] for s in system.states]
        # hysteresis against the pass before (the first pass: against the values
        # before the event), and a relation that pass decided clearly keeps its
        # value when this guess puts it exactly at its limit
        clear = self._clear if self._clear_for is not None and relations == self._clear_for else None
        raw = system.crossings(t, x) if self.relations else None
        new_relations = self.relation_values(system, t, x, relations, fired=fired, clear=clear, raw=raw)
        if fired and self.relations:
            new_relations = self._keep_crossed(raw, fired, relations, relations_before, new_relations)
        if self.relations:
            self._clear, self._clear_for = self.clearly_decided(raw, clear), new_relations
        if self._continuous_args:
            self._extra.update(self._continuous_env(system, t, x, values if left is None else left))
        self._relations_now = new_relations
        return self.evaluate_discrete(discrete, pre, new_relations, initial), new_relations

    def _keep_crossed(self, raw, fired, guess, before, decided) -> tuple[bool, ...]:
        """``decided`` with each crossed relation that the guess already holds at its
        new value kept there while this pass puts ``lhs - rhs`` within its margin.

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
                if abs(lhs - rhs) <= self._margins[k] * max(self._floors[k], abs(lhs), abs(rhs)):
                    out[k] = guess[k]
        return tuple(out)

    def _search(self, t, values, pre, relations, relations_before, initial, fired, cycle, current):
        """The first consistent assignment with fewest flips from the pre values.

        Only discrete variables that select continuous equations are searched,
        and only those of the components whose variables were cycling; the
        others follow from the discrete equations.
        """
        cycling = {n for (a, _), (b, _) in zip(cycle, cycle[1:] + cycle[:1])
                   for (n, va), (_, vb) in zip(a, b) if va != vb}
        owners = {n.rpartition(".")[0] for n in cycling}
        selectors = [name for name in self.data.selectors
                     if name in self.kinds and name.rpartition(".")[0] in owners]
        booleans = [n for n in selectors if self.kinds[n] == "boolean"]
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
        # only relations that select equations (a when-condition's loop is a discrete one,
        # decided by event iteration itself); time events are decided by the clock
        selecting = {name.index for name in self._selector_names if name.kind == "relation"
                     and not self.relations[name.index].is_time_event}
        changing = {k for (_, a), (_, b) in zip(cycle, cycle[1:] + cycle[:1])
                    for k, (va, vb) in enumerate(zip(a, b)) if va != vb and k in selecting}
        # with them, the other relations of their components (the opposite limit)
        owners = {c for k in changing for c in self.relations[k].components}
        cycling = sorted(changing | {k for k in selecting if owners & set(self.relations[k].components)})
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
        judged_against = (self._clear, self._clear_for)
        for flips in range(len(items) + 1):
            for chosen in itertools.combinations(items, flips):
                discrete, relations = flipped(set(chosen))
                self._clear, self._clear_for = judged_against
                try:
                    result, rels = self._pass(t, values, discrete, pre, relations, relations_before, initial, fired)
                except SimulationError:
                    continue  # e.g. a singular system in an impossible configuration
                if consistent(discrete, relations, result, rels):
                    return result, rels
        return None

    def _fail(self, t: float, history, what: str):
        changing = sorted({n for a, b in zip(history, history[1:]) for n in a if a[n] != b[n]})
        owners = tuple(dict.fromkeys(n.rpartition(".")[0] for n in changing))
        looping = [n for n in changing if self.kinds.get(n) == "discrete" and not n.rpartition(".")[2].startswith("$")]
        if looping:
            origin = self.equations[self._equation_of[looping[0]]][3]
            raise EventIterationError(
                f"at t = {t:.12g} an algebraic loop through a when-clause: the new value of "
                f"{looping[0]} ({origin}) changes the values it is computed from, and "
                f"{what} does not settle in {self.max_iterations} iterations",
                hint="a when-clause samples values at its event; break the loop, e.g. assign "
                     "from pre() of the values that depend on the variable",
                components=owners)
        hint = "the discrete variables named may flip each other back and forth; check the " \
               "conditions that set them"
        own = self.data.hints_for("event_iteration", owners)
        raise EventIterationError(
            f"{what} at t = {t:.12g} did not converge in {self.max_iterations} iterations; "
            f"still changing: {', '.join(changing) or 'unknown'}",
            hint="; ".join((hint, *own)), components=owners)
