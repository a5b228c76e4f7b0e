"""Event iteration evaluates only what changed: the same results as evaluating everything.

``acausal.runtime.events.INCREMENTAL`` switches the incremental passes (and
the incremental search for the relations to watch) off; every model here
must give bit-identical results both ways, on friction models whose
discrete equations read relations, ``pre()`` values and one another.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

import acausal.runtime.events as events
from acausal import simulate
from examples.coupled_clutches import CoupledClutches
from examples import friction_elements

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "compiler"))
from test_clusters import storm  # noqa: E402


def both_ways(make, monkeypatch, **options):
    incremental = simulate(make(), cache=False, **options)
    monkeypatch.setattr(events, "INCREMENTAL", False)
    full = simulate(make(), cache=False, **options)
    monkeypatch.setattr(events, "INCREMENTAL", True)
    return incremental, full


@pytest.mark.parametrize("make, options", [
    (CoupledClutches, {}),
    (friction_elements.TestFriction, {}),
    (lambda: storm(5), {"stop_time": 1.0, "interval": 0.01}),
])
def test_incremental_event_iteration_gives_the_same_results(make, options, monkeypatch):
    incremental, full = both_ways(make, monkeypatch, **options)
    assert incremental.status == full.status == 0
    assert len(incremental.events) > 3
    assert [(e.time, e.changes, e.iterations) for e in incremental.events] == \
        [(e.time, e.changes, e.iterations) for e in full.events]
    np.testing.assert_array_equal(incremental.time, full.time)
    for name in full.names:
        np.testing.assert_array_equal(incremental[name], full[name], err_msg=name)
