"""Stage 11: the discrete part at events — the façade the simulation loop calls.

:class:`DiscreteEvaluator` composes the parts, each in a module of its own:

- :mod:`acausal.runtime.relations`: the one definition of how a relation is
  decided (hysteresis), in plain Python and with numpy;
- :mod:`acausal.runtime.relation_evaluator`: the relations' values at an
  event and the crossing watch between events;
- :mod:`acausal.runtime.discrete_equations`: the discrete equations, one pass
  over them, the assertions;
- :mod:`acausal.runtime.relevance`: which relations can change the current
  discrete state (only those are watched);
- :mod:`acausal.runtime.event_iteration`: Modelica's event iteration (``pre()``,
  fixed point), with scratch state of its own per iteration.

Impure functions (:class:`acausal.functions.ImpureFunction`) in the
discrete equations draw once per event iteration and call site, from a
state the run owns (:class:`ImpureCalls`): the passes of one iteration see
the value its first evaluation computed.
"""

from __future__ import annotations

import copy
from dataclasses import dataclass, field
from typing import Callable, Mapping

from .contract import CompiledModel, CompiledSystem
from .discrete_equations import DiscreteEquations, mode_values, with_aliases
from .event_iteration import EventIteration, EventOutcome, StateKey
from .relation_evaluator import RelationEvaluator
from .relevance import RelevanceAnalysis

__all__ = ["DiscreteEvaluator", "EventOutcome", "ImpureCalls", "evaluator_for", "mode_values", "with_aliases"]


def evaluator_for(translation: CompiledModel, relation_epsilon: float = 1e-10,
                  max_iterations: int = 20, incremental: bool = True) -> "DiscreteEvaluator":
    """The discrete-part evaluator of ``translation``, built once per setting and kept
    with the translation (compiling the discrete equations is a few milliseconds)."""
    cache = translation.extras.setdefault("evaluators", {})
    key = (relation_epsilon, max_iterations, incremental)
    if key not in cache:
        cache[key] = DiscreteEvaluator(translation, relation_epsilon, max_iterations, incremental)
    return cache[key]


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


class DiscreteEvaluator:
    """The discrete part of a translated model at events, for a run and its tools.

    A façade over the parts that do the work, each in its module:

    - :attr:`relation_evaluator` (:class:`~acausal.runtime.relation_evaluator.RelationEvaluator`):
      the relations' values at an event and the crossing watch between events;
    - :attr:`program` (:class:`~acausal.runtime.discrete_equations.DiscreteEquations`):
      the discrete equations, one pass over them, the assertions;
    - :attr:`relevance` (:class:`~acausal.runtime.relevance.RelevanceAnalysis`):
      which relations to watch in a discrete state;
    - :class:`~acausal.runtime.event_iteration.EventIteration`: one event iteration,
      made anew for each call of :meth:`iterate`.

    What it keeps between calls: the run's impure functions (:attr:`impure`), the
    values :meth:`prepare` set for :meth:`evaluate_discrete` outside event iteration,
    and the record of the last pass of the last event iteration (its relation values,
    which the assertions between events read; the relations' sides, from which the
    relevance analysis finds the relations that cross together; which relations it
    decided clearly, against which the next iteration's first pass is judged).  The
    parts keep caches only: plans, and the last pass and relevance answers, reused
    only where they give what a fresh computation would.
    """

    def __init__(self, translation: CompiledModel, relation_epsilon: float = 1e-10,
                 max_iterations: int = 20, incremental: bool = True) -> None:
        self.translation = translation
        #: whether a pass of event iteration re-evaluates only what changed since the
        #: last and the relevant relations are found again only where something changed
        #: (:attr:`acausal.options.EngineOptions.incremental_events`); False evaluates
        #: everything, with the same results
        self.incremental = incremental
        #: the model's data (names, kinds, relations, clocks: plain values)
        self.data = data = translation.data
        self.relations = data.relations
        self.epsilon = relation_epsilon
        self.max_iterations = max_iterations
        #: the run's impure functions (their state, the values of this event's call sites)
        self.impure = ImpureCalls()
        # compiled by the translation (the one callback into the compiler); the call
        # sites of impure functions call back into this evaluator
        program = translation.discrete_program(self._impure_call)
        self.impure_sites = program.impure_sites
        self.program = DiscreteEquations(data, program, incremental)
        self.relation_evaluator = RelationEvaluator(data.relations, relation_epsilon)
        self.relevance = RelevanceAnalysis(data.relations, [d for d, _s, _t in self.relation_evaluator.kinds],
                                           self.program, data.selectors)
        self._key = StateKey(data.selectors)
        self.asserts = self.program.asserts
        #: whether anything reads terminal() (then the run ends with one more event iteration)
        self.uses_terminal = self.program.uses_terminal
        #: what :meth:`prepare` set: the values the discrete equations read outside event
        #: iteration (cleared by :meth:`iterate`)
        self._extra: dict = {}
        #: the record of the last pass of event iteration: its relation values (what the
        #: assertions between events read), the relations' sides (from which the relevance
        #: analysis finds the relations that cross together), and which relations it decided
        #: beyond their margin with the values it produced (what the first pass of the next
        #: event iteration is judged against: see :mod:`acausal.runtime.event_iteration`)
        self._relations_now: tuple | None = None
        self._sides = None
        self._judged_against: tuple = (None, None)

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

    # -- discrete states and equations -------------------------------------------------

    def key(self, discrete: Mapping, pre: Mapping, relations, initial: bool) -> tuple:
        """The discrete state: each selector's value in the selectors' order (a relation's
        value as a bool, ``pre(v)`` from ``pre``, a discrete variable from ``discrete``,
        ``initial()``)."""
        return self._key(discrete, pre, relations, initial)

    def prepare(self, system: CompiledSystem | None, t: float, x) -> None:
        """Set the continuous values the discrete equations read (outside event iteration:
        during initialization, where ``pre(u)`` of a continuous ``u`` is ``u``); None clears."""
        self._extra = self.program.prepared(system, t, x)

    def evaluate_discrete(self, discrete: Mapping, pre: Mapping, relations, initial: bool,
                          relation_free: bool = False) -> dict:
        """One pass over the discrete equations in dependency order, with the values
        :meth:`prepare` set (see :meth:`DiscreteEquations.evaluate`)."""
        return self.program.evaluate(discrete, pre, relations, initial, self._extra, relation_free)

    def _states(self, system: CompiledSystem, values: Mapping, discrete: Mapping) -> list:
        """The state vector of ``system``: held values from ``discrete``, the rest from ``values``."""
        return self.program.state_vector(system, values, discrete)

    def check_asserts(self, t: float, system: CompiledSystem, x, discrete: Mapping, pre: Mapping,
                      initial: bool = False, terminal: bool = False) -> list:
        """The assertions violated at ``(t, x)``: ``[(FlatAssert, message)]`` (``terminal``:
        at the end of the run, where ``terminal()`` is true), with the relation values of
        the last event iteration."""
        return self.program.violated_asserts(t, system, x, discrete, pre, self._relations_now or (), initial,
                                             terminal, self._extra)

    # -- relations ----------------------------------------------------------------------

    def relation_values(self, system: CompiledSystem, t: float, x, previous, exact: bool = False,
                        fired: frozenset = frozenset(), clear=None, raw=None) -> tuple[bool, ...]:
        """Relation values at ``(t, x)``, with hysteresis against ``previous``
        (:meth:`RelationEvaluator.relation_values`)."""
        return self.relation_evaluator.relation_values(system, t, x, previous, exact, fired, clear, raw)

    def clearly_decided(self, raw, inherited=None) -> tuple[bool, ...]:
        """Which relations ``raw`` puts beyond their margin (:meth:`RelationEvaluator.clearly_decided`)."""
        return self.relation_evaluator.clearly_decided(raw, inherited)

    def flipped_relations(self, system: CompiledSystem, t: float, x, relations,
                          watched: tuple[int, ...]) -> tuple[int, ...]:
        """The watched relations flipped at ``(t, x)`` (:meth:`RelationEvaluator.flipped_relations`)."""
        return self.relation_evaluator.flipped_relations(system, t, x, relations, watched)

    def first_flip(self, system: CompiledSystem, times, states, relations,
                   watched: tuple[int, ...]) -> tuple[int, tuple[int, ...]] | None:
        """The first of ``times`` with a flipped watched relation (:meth:`RelationEvaluator.first_flip`)."""
        return self.relation_evaluator.first_flip(system, times, states, relations, watched)

    def distance_to_flip(self, system: CompiledSystem, relations, k: int) -> Callable:
        """``distance(t, x)`` to relation ``k``'s flip (:meth:`RelationEvaluator.distance_to_flip`)."""
        return self.relation_evaluator.distance_to_flip(system, relations, k)

    def distance_to_first_flip(self, system: CompiledSystem, relations, candidates) -> Callable:
        """``distance(t, x)`` to the first flip of ``candidates``
        (:meth:`RelationEvaluator.distance_to_first_flip`)."""
        return self.relation_evaluator.distance_to_first_flip(system, relations, candidates)

    def flip_search(self, system: CompiledSystem, relations, candidates,
                    with_distance: bool = True) -> tuple[Callable, Callable | None]:
        """``(flipped, distance)`` for the search of the first flip of ``candidates``, from
        one evaluation per instant (:meth:`RelationEvaluator.flip_search`)."""
        return self.relation_evaluator.flip_search(system, relations, candidates, with_distance)

    def relevant_relations(self, discrete: Mapping, relations) -> tuple[int, ...]:
        """State relations whose flip could change something in this discrete state
        (:meth:`RelevanceAnalysis.relevant_relations`, with the twins found from the
        last pass of event iteration)."""
        return self.relevance.relevant_relations(discrete, relations, self._sides)

    # -- event iteration ------------------------------------------------------------

    def iterate(self, t: float, values: Mapping[str, float], pre: Mapping, relations_before,
                initial: bool = False, fired: frozenset = frozenset(), ticks: frozenset = frozenset(),
                terminal: bool = False) -> EventOutcome:
        """Modelica event iteration at time ``t`` (see :meth:`EventIteration.run`); each
        impure call site computes at most one value in it."""
        iteration = EventIteration(self.translation, self.program, self.relation_evaluator, self._key,
                                   self.max_iterations, self._judged_against)
        if self.impure_sites:
            self.open_instant()
        try:
            return iteration.run(t, values, pre, relations_before, initial, fired, ticks, terminal)
        finally:
            if self.impure_sites:
                self.close_instant()
            # what prepare() set does not outlive an event iteration; what its last pass
            # decided is kept for the assertions and the relevance analysis
            self._extra = {}
            if iteration.relations_now is not None:
                self._relations_now = iteration.relations_now
            if iteration.sides is not None:
                self._sides = iteration.sides
            self._judged_against = (iteration.clear, iteration.clear_for)
