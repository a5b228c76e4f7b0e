"""Event iteration evaluates only what changed: the same results as evaluating everything.

``EngineOptions(incremental_events=False)`` switches the incremental passes (and
the incremental search for the relations to watch) off; every model here
must give bit-identical results both ways, on friction models whose
discrete equations read relations, ``pre()`` values and one another.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

from acausal import EngineOptions, Eq, If, Integer, Model, Variable, der, simulate
from examples.coupled_clutches import CoupledClutches
from examples import friction_elements

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "compiler"))
from test_clusters import storm  # noqa: E402


class DiscreteLoop(Model):
    """``a = b`` reads b before b's own equation ``b = if x > 1 then 1 else a``: a
    discrete loop, solved by event iteration (the pass starts from the values
    before); twenty unrelated Integers keep the change small against the model."""

    x = Variable(start=0.0, fixed=True)
    y = Variable()
    a = Integer()
    b = Integer()
    locals().update({f"c{k}": Integer() for k in range(20)})

    def equations(self):
        return [Eq(der(self.x), 1), Eq(self.y, self.a + 10 * self.b), Eq(self.a, self.b),
                Eq(self.b, If(self.x > 1, 1, self.a)),
                *(Eq(getattr(self, f"c{k}"), If(self.x > 5 + k, 1, 0)) for k in range(20))]


def test_a_discrete_loop_reaches_the_fixed_point_a_full_pass_reaches():
    """At t = 1 b becomes 1, then a follows in the next pass: a = b = 1, y = 11."""
    incremental, full = both_ways(DiscreteLoop, stop_time=2.0)
    for result in (incremental, full):
        assert result.status == 0
        assert (result["a"][-1], result["b"][-1], result["y"][-1]) == (1.0, 1.0, 11.0)
    assert [(e.time, e.changes, e.iterations) for e in incremental.events] == \
        [(e.time, e.changes, e.iterations) for e in full.events]


def both_ways(make, **options):
    incremental = simulate(make(), cache=False, **options)
    full = simulate(make(), cache=False, options=EngineOptions(incremental_events=False), **options)
    return incremental, full


@pytest.mark.parametrize("make, options", [
    (CoupledClutches, {}),
    (friction_elements.TestFriction, {}),
    (lambda: storm(5), {"stop_time": 1.0, "interval": 0.01}),
])
def test_incremental_event_iteration_gives_the_same_results(make, options):
    incremental, full = both_ways(make, **options)
    assert incremental.status == full.status == 0
    assert len(incremental.events) > 3
    assert [(e.time, e.changes, e.iterations) for e in incremental.events] == \
        [(e.time, e.changes, e.iterations) for e in full.events]
    np.testing.assert_array_equal(incremental.time, full.time)
    for name in full.names:
        np.testing.assert_array_equal(incremental[name], full[name], err_msg=name)
