"""The discrete evaluator as a façade over its parts (issue 29).

``DiscreteEvaluator`` composes the relation evaluator, the discrete
equations, the relevance analysis and one ``EventIteration`` per call of
``iterate``.  What an iteration computes for itself (the clear decisions of
each pass, the clock ticks and continuous values of a round) lives on that
iteration object; the evaluator keeps only a documented record of the last
pass, and the parts keep caches.  The scalar and numpy forms of hysteresis
are compared in ``test_relation_paths.py``.
"""

from __future__ import annotations

import pytest

from acausal import translate
from acausal.errors import EventIterationError
from acausal.runtime import event_iteration
from acausal.runtime.events import DiscreteEvaluator, evaluator_for
from acausal.runtime.initialization import initialize
from examples.coupled_clutches import CoupledClutches
from examples.sampled_speed_control import SampledSpeedControl

#: what an event iteration may rebind on the evaluator and its parts: the record of its
#: last pass, what prepare() set (cleared), and caches
_RECORD = {"_relations_now", "_sides", "_judged_against", "_extra", "impure"}
_CACHES = {"relation_evaluator": {"_scalar_plan", "_vector_plan", "_kind_arrays", "_margin_arrays"},
           "program": {"_last_pass"},
           "relevance": set()}


def _bindings(obj) -> dict:
    return {name: id(value) for name, value in vars(obj).items()}


def _started(model):
    translation = translate(model)
    evaluator = DiscreteEvaluator(translation)
    state = initialize(translation, evaluator, translation.data.experiment.start_time)
    return translation, evaluator, state


def test_an_iteration_leaves_only_its_record_and_caches():
    _translation, evaluator, state = _started(CoupledClutches())
    outcome = state.outcome
    before = {"evaluator": _bindings(evaluator), **{part: _bindings(getattr(evaluator, part)) for part in _CACHES}}
    made = []
    original = event_iteration.EventIteration.__init__

    def spy(self, *args, **kwargs):
        original(self, *args, **kwargs)
        made.append(self)

    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(event_iteration.EventIteration, "__init__", spy)
        again = evaluator.iterate(state.time, outcome.values, outcome.discrete, outcome.relations)
        evaluator.iterate(state.time, outcome.values, outcome.discrete, outcome.relations)
    assert again.discrete == outcome.discrete and again.relations == outcome.relations
    assert len(made) == 2 and made[0] is not made[1]  # a new iteration object per call
    after = _bindings(evaluator)
    assert set(after) == set(before["evaluator"])  # no new attribute
    rebound = {name for name in after if after[name] != before["evaluator"][name]}
    assert rebound <= _RECORD
    for part, caches in _CACHES.items():
        now = _bindings(getattr(evaluator, part))
        assert set(now) == set(before[part])
        assert {name for name in now if now[name] != before[part][name]} <= caches
    # the record is the last pass's: its relation values, the sides and clear decisions of it
    assert evaluator._relations_now == made[-1].relations_now == again.relations
    assert evaluator._sides is made[-1].sides
    assert evaluator._judged_against == (made[-1].clear, made[-1].clear_for)


def test_clock_ticks_and_prepared_values_do_not_outlive_an_iteration():
    translation, evaluator, state = _started(SampledSpeedControl())
    assert evaluator.program.clocks and evaluator.program.hybrid
    outcome = state.outcome
    clock = evaluator.program.clocks[0]
    x = [outcome.values[s] for s in outcome.system.states]
    evaluator.prepare(outcome.system, state.time, x)
    assert evaluator._extra[clock.name] is False
    evaluator.iterate(state.time, outcome.values, outcome.discrete, outcome.relations,
                      ticks=frozenset({clock.index}))
    assert evaluator._extra == {}
    # an iteration that fails clears them too
    failing = DiscreteEvaluator(translation, max_iterations=0)
    failing.prepare(outcome.system, state.time, x)
    assert failing._extra
    with pytest.raises(EventIterationError):
        failing.iterate(state.time, outcome.values, outcome.discrete, outcome.relations)
    assert failing._extra == {}


def test_the_facade_answers_as_its_parts():
    translation, evaluator, state = _started(CoupledClutches())
    assert evaluator is not evaluator_for(translation)  # (one made apart; evaluator_for keeps its own)
    assert evaluator.relations is evaluator.relation_evaluator.relations is translation.data.relations
    assert evaluator.asserts is evaluator.program.asserts
    outcome = state.outcome
    # the key of the state the iteration settled in selects the system it returned
    assert translation.system(evaluator.key(outcome.discrete, outcome.discrete, outcome.relations, False)) \
        is outcome.system
