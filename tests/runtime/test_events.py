"""Event detection helpers checked against their definitions.

Relations are checked with hysteresis (:meth:`Relation.holds_with_hysteresis`);
from many watched relations on the check is done with numpy at once, which
must give exactly the answer of the scalar definition, ties and knife edges
included.
"""

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from acausal import translate
from acausal.runtime.events import evaluator_for
from acausal.runtime.relation_evaluator import _VECTORISE_FROM
from examples.coupled_clutches import CoupledClutches

_EVALUATOR = evaluator_for(translate(CoupledClutches()))
_RELATIONS = _EVALUATOR.relations


class _Crossings:
    """Stands in for a compiled system: returns fixed relation sides."""

    def __init__(self, raw):
        self.raw = tuple(raw)

    def crossings(self, t, x):
        return self.raw

    def crossings_for(self, relations):
        return self.crossings

    parts = None


def _scalar_flips(raw, relations, watched):
    out = []
    for k in watched:
        lhs, rhs = raw[2 * k], raw[2 * k + 1]
        eps = _RELATIONS[k].margin(lhs, rhs, _EVALUATOR.epsilon)
        if _RELATIONS[k].holds_with_hysteresis(lhs - rhs, relations[k], eps) != relations[k]:
            out.append(k)
    return tuple(out)


# sides that sit on, just inside and just outside the hysteresis band
_side = st.sampled_from([0.0, 1.0, -1.0, 1e-10, -1e-10, 2e-10, 1.5, 1e12, -3.0]) | st.floats(-10, 10)


@settings(max_examples=60, derandomize=True, deadline=None)
@given(data=st.data())
def test_vectorised_relation_check_equals_the_scalar_definition(data):
    n = len(_RELATIONS)
    lhs = data.draw(st.lists(_side, min_size=n, max_size=n))
    # rhs near lhs so that many relations sit on their knife edge
    offsets = data.draw(st.lists(st.sampled_from([0.0, 1e-10, -1e-10, 5e-11, -5e-11, 1.0, -1.0]),
                                 min_size=n, max_size=n))
    raw = []
    for a, d in zip(lhs, offsets):
        raw += [a, a + d]
    relations = tuple(data.draw(st.lists(st.booleans(), min_size=n, max_size=n)))
    # watch every relation several times over to pass the vectorising threshold
    watched = tuple(range(n)) * (_VECTORISE_FROM // n + 1)
    expected = _scalar_flips(raw, relations, watched)
    got = _EVALUATOR.flipped_relations(_Crossings(raw), 0.0, (), relations, watched)
    assert len(watched) >= _VECTORISE_FROM
    assert got == expected


def test_time_events_get_no_margin():
    """A time relation flips exactly at its instant, without hysteresis."""
    timed = [k for k, r in enumerate(_RELATIONS) if r.is_time_event]
    assert timed
    n = len(_RELATIONS)
    watched = tuple(timed) * (_VECTORISE_FROM // len(timed) + 1)
    for g in (1e-300, -1e-300, 1e-12, -1e-12):
        raw = np.zeros(2 * n)
        for k in timed:
            raw[2 * k] = g
        relations = tuple(False for _ in range(n))
        expected = _scalar_flips(list(raw), relations, watched)
        got = _EVALUATOR.flipped_relations(_Crossings(raw), 0.0, (), relations, watched)
        assert got == expected
        # exactly: the relation's own value at g decides
        assert set(got) == {k for k in timed if _RELATIONS[k].holds(g)}
