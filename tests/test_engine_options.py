"""EngineOptions: one value, passed through translate() and simulate(), instead of module flags.

Each option switches a technique; both settings must give the same results
(the per-technique tests compare them: ``tests/compiler/test_clusters.py``,
``tests/runtime/test_incremental_events.py``,
``tests/compiler/test_flatten_templates.py``).  Here: the options reach the
stage they switch, translations of other compiler options are kept apart in
the in-process cache, and bad options are refused with a clear error.
"""

from __future__ import annotations

import numpy as np
import pytest

from acausal import EngineOptions, simulate, translate
from acausal.errors import SettingError
from examples.coupled_clutches import CoupledClutches
from tests.compiler.test_clusters import storm


def test_an_option_that_is_not_a_bool_is_refused_by_name():
    with pytest.raises(SettingError, match="EngineOptions.clusters must be True or False"):
        EngineOptions(clusters="no")


def test_options_that_are_not_engine_options_are_refused():
    with pytest.raises(SettingError, match="options must be an EngineOptions"):
        translate(storm(2), options={"clusters": False})


def test_compiler_options_give_translations_of_their_own():
    clustered = translate(storm(3))
    whole = translate(storm(3), options=EngineOptions(clusters=False))
    assert clustered.clustering is not None and len(clustered.clustering.clusters) == 3
    assert whole.clustering is None
    # the in-process cache keeps them apart, and gives each back to its own options
    assert translate(storm(3)) is clustered
    assert translate(storm(3), options=EngineOptions(clusters=False)) is whole
    # the runtime's options do not make a new translation
    assert translate(storm(3), options=EngineOptions(secant=False, incremental_events=False)) is clustered


def test_a_translation_runs_with_other_runtime_options_but_not_other_compiler_options():
    translation = translate(storm(2))
    with pytest.raises(SettingError, match="compiler's fields"):
        simulate(translation, stop_time=0.5, options=EngineOptions(clusters=False))
    full = simulate(translation, stop_time=0.5, options=EngineOptions(incremental_events=False))
    assert full.status == 0
    # the run's evaluator is the one of its options (the parts run apart: each part's own)
    extras = [translation.extras, *(part.extras for part in translation.part_models()[0])]
    assert any(key[-1] is False for found in extras for key in found.get("evaluators", {}))


@pytest.mark.parametrize("make, options", [
    (CoupledClutches, {}),
    (lambda: storm(4), {"stop_time": 1.0, "interval": 0.01}),
])
def test_bisection_alone_finds_the_events_the_secant_finds(make, options):
    """``secant=False`` locates each single crossing by halving alone: the same events, each
    within the 4-ulp bracket both methods stop at, and the same trajectories."""
    secant = simulate(make(), cache=False, **options)
    halving = simulate(make(), cache=False, options=EngineOptions(secant=False), **options)
    assert secant.status == halving.status == 0
    assert [e.changes for e in secant.events] == [e.changes for e in halving.events]
    times = np.array([e.time for e in secant.events])
    np.testing.assert_allclose([e.time for e in halving.events], times, rtol=0, atol=1e-12 * max(1.0, times.max()))
    for name in secant.columns:
        np.testing.assert_allclose(halving[name], secant[name], rtol=1e-9, atol=1e-12)
