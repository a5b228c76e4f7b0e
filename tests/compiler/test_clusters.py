"""Per-cluster mode systems: independent parts compiled apart give the whole model's results.

Each test compares the composed run (one system per part and part mode,
:mod:`acausal.compiler.clusters`) with the whole-model run
(``EngineOptions(clusters=False)``, one system per discrete state of the whole model).
"""

from __future__ import annotations

import numpy as np
import pytest

from acausal import EngineOptions, Eq, Model, simulate
from acausal.compiler.clusters import ComposedSystem
from acausal.compiler.modes import ModeSystem
from acausal.compiler.translate import translate
from acausal.errors import StructuralError
from acausal.library.blocks import Sine
from acausal.library.rotational import BearingFriction, Inertia, Torque
from examples.benchmarks import add_storm_unit
from examples.coupled_clutches import CoupledClutches


def storm(n: int, extra_equation: bool = False, coupled_start: bool = False) -> Model:
    """N independent units Sine -> Torque -> Inertia -> BearingFriction (an event storm)."""

    class Storm(Model):
        def build(self):
            for k in range(n):
                add_storm_unit(self, k, 1.0 + 0.13 * k, names=("s", "t", "j", "f"),
                               w_fixed=not (coupled_start and k == 1))

        def equations(self):
            # an equation too many for unit 1 only
            return [Eq(self.j1.w, 0)] if extra_equation else []

        def initial_equations(self):
            # the start speed of unit 1 from unit 0's: the two are initialized together
            return [Eq(self.j1.w, self.j0.w)] if coupled_start else []

    Storm.__name__ = Storm.__qualname__ = f"Storm{n}"
    return Storm()


#: compile the whole model per discrete state (no clusters)
WHOLE = EngineOptions(clusters=False)


@pytest.fixture(autouse=True)
def one_solver(monkeypatch):
    """These tests hold the composed systems to the whole model's, bit for bit: with one
    solver for every part (the runs of the parts apart are tested in
    tests/runtime/test_part_runs.py)."""
    from acausal.runtime import simulate as simulate_module

    # every run here, of a model or of a translation, as EngineOptions(parts_apart=False) runs it
    monkeypatch.setattr(simulate_module, "separate_parts", lambda *args, **kwargs: ((), ""))


def run_both(make, **options):
    outputs = options.get("outputs")
    clustered = translate(make(), outputs, cache=False)
    composed = simulate(clustered, **options)
    whole_translation = translate(make(), outputs, cache=False, options=WHOLE)
    whole = simulate(whole_translation, **options)
    return clustered, composed, whole_translation, whole


def assert_same_results(a, b):
    assert a.status == b.status == 0, (a.message, b.message)
    np.testing.assert_array_equal(a.time, b.time)
    assert [(e.time, e.changes) for e in a.events] == [(e.time, e.changes) for e in b.events]
    assert sorted(a.names) == sorted(b.names)
    for name in a.names:
        np.testing.assert_allclose(a[name], b[name], rtol=1e-9, atol=1e-12, err_msg=name)


def test_independent_units_are_clusters_with_their_own_discrete_symbols():
    translation = translate(storm(3), cache=False)
    clusters = translation.clustering.clusters
    assert len(clusters) == 3
    for k, cluster in enumerate(clusters):
        owners = {name.split(".")[0] for name in cluster.variables}
        # the unit's inertia and bearing; parts without discrete states (a torque's
        # fixed support angle) join the first cluster
        assert {o for o in owners if o[0] in "jf"} == {f"j{k}", f"f{k}"}, owners
        selectors = {translation.selectors[i].name for i in cluster.selectors}
        assert selectors and all(f"f{k}." in s or s.startswith("$rel") for s in selectors), selectors
    # every selector and every relation belongs to exactly one cluster
    chosen = [i for c in clusters for i in c.selectors]
    assert sorted(chosen) == list(range(len(translation.selectors)))
    relations = [k for c in clusters for k in c.relations]
    assert sorted(relations) == list(range(len(translation.partitioned.relations)))


def test_a_rigid_train_is_one_part_and_compiles_as_before():
    """CoupledClutches: one part; the same systems and the same results as without clusters."""
    clustered, composed, whole_translation, whole = run_both(CoupledClutches)
    assert clustered.clustering is None
    assert all(isinstance(s, ModeSystem) for s in clustered.systems.values())
    assert clustered.compiled_systems == whole_translation.compiled_systems
    assert_same_results(composed, whole)


def test_composed_run_equals_whole_model_run_on_a_storm():
    make = lambda: storm(4)  # noqa: E731
    clustered, composed, _, whole = run_both(make, stop_time=1.0, interval=0.01)
    assert all(isinstance(s, ComposedSystem) for s in clustered.systems.values())
    assert len(composed.events) > 10
    assert_same_results(composed, whole)


def test_compiled_systems_grow_linearly_with_the_units():
    counts = {}
    for n in (2, 4):
        # every part compiled for itself (equal parts are compiled once with part_shapes,
        # tests/compiler/test_part_shapes.py)
        translation = translate(storm(n), cache=False, options=EngineOptions(part_shapes=False))
        simulate(translation, stop_time=1.0, interval=0.01)
        counts[n] = translation.compiled_systems
        # each part is compiled for its own modes only
        for (index, subkey), part in translation.parts.items():
            assert len(subkey) == len(translation.clustering.clusters[index].selectors)
    assert counts[4] == 2 * counts[2]
    whole = translate(storm(4), cache=False, options=WHOLE)
    simulate(whole, stop_time=1.0, interval=0.01)
    assert counts[4] <= whole.compiled_systems


def test_a_new_parameter_value_rebinds_every_part():
    base = translate(storm(2))
    simulate(base, stop_time=1.0, interval=0.01)
    rebound = translate(storm(2), parameters={"j1.J": 0.5})
    assert rebound.rebound_from is base
    result = simulate(rebound, stop_time=1.0, interval=0.01)
    assert rebound.parts and all(p.passes[0][0] == "rebind" for p in rebound.parts.values()
                                 if p.shares is None)
    fresh = simulate(translate(storm(2), cache=False, parameters={"j1.J": 0.5}), stop_time=1.0, interval=0.01)
    assert_same_results(result, fresh)
    # the new inertia changes unit 1 only
    untouched = simulate(translate(storm(2), cache=False), stop_time=1.0, interval=0.01)
    assert not np.allclose(result["j1.w"], np.interp(result.time, untouched.time, untouched["j1.w"]))


def test_an_output_demand_gives_the_whole_models_demanded_values():
    """With outputs=[...], the parts keep what the output and the events need, as the whole model does."""
    clustered, composed, _, whole = run_both(lambda: storm(3), stop_time=1.0, interval=0.01,
                                             outputs=["j1.w"])
    assert_same_results(composed, whole)
    # and the values are those of the full run, to the integration tolerance
    full = simulate(storm(3), stop_time=1.0, interval=0.01, cache=False)
    np.testing.assert_allclose(composed["j1.w"][::5], np.interp(composed.time[::5], full.time, full["j1.w"]),
                               atol=1e-4)


def test_a_structural_error_in_one_part_reads_as_the_whole_models():
    with pytest.raises(StructuralError) as clustered:
        simulate(storm(3, extra_equation=True), stop_time=1.0, cache=False)
    with pytest.raises(StructuralError) as whole:
        simulate(storm(3, extra_equation=True), stop_time=1.0, cache=False, options=WHOLE)
    assert type(clustered.value) is type(whole.value)
    assert str(clustered.value) == str(whole.value)
    assert "j1" in str(clustered.value)


def test_an_initial_equation_joins_the_parts_it_relates():
    translation = translate(storm(3, coupled_start=True), cache=False)
    assert len(translation.clustering.clusters) == 2
    joined = translation.clustering.clusters[0]
    assert {"j0.w", "j1.w"} <= set(joined.variables)
    clustered, composed, _, whole = run_both(lambda: storm(3, coupled_start=True),
                                             stop_time=1.0, interval=0.01)
    assert_same_results(composed, whole)


class _LockedPairAndUnit(Model):
    """Two bearings on one shaft (both stuck: a state the engine refuses with
    ``redundant_constraints='error'``) beside an independent stick-slip unit: a part
    that fails mid-run."""

    def build(self):
        from acausal.library.rotational import ConstantTorque

        rest = dict(start=0.0, fixed=True)
        self.torque = ConstantTorque(tau_constant=0.0)
        self.inertia = Inertia(J=1.0, phi=rest, w=dict(start=1.0, fixed=True))
        self.bf1 = BearingFriction(tau_pos=[[0.0, 1.0]])
        self.bf2 = BearingFriction(tau_pos=[[0.0, 2.0]])
        self.connect(self.torque.flange, self.inertia.flange_a)
        self.connect(self.inertia.flange_b, self.bf1.flange_a)
        self.connect(self.bf1.flange_b, self.bf2.flange_a)
        self.s = Sine(amplitude=2.0, f=1.0)
        self.t = Torque()
        self.j = Inertia(J=1.0, phi=rest, w=rest)
        self.f = BearingFriction(tau_pos=[[0.0, 1.0]], peak=1.2)
        self.connect(self.s.y, self.t.tau)
        self.connect(self.t.flange, self.j.flange_a)
        self.connect(self.j.flange_b, self.f.flange_a)


def test_a_part_that_fails_mid_run_leaves_a_usable_translation(tmp_path):
    """The failing part sends the translation back to the whole model; what it composed
    before goes, so that explain and a new parameter value still work."""
    from acausal.tools.explain import explain

    translation = translate(_LockedPairAndUnit(), cache=False, redundant_constraints="error")
    assert translation.clustering is not None
    result = simulate(translation, stop_time=2.0)
    whole = simulate(_LockedPairAndUnit(), stop_time=2.0, cache=False, redundant_constraints="error",
                     options=WHOLE)
    assert result.status == whole.status == -1
    assert result.message == whole.message
    assert translation.clustering is None
    assert not any(isinstance(s, ComposedSystem) for s in translation.systems.values())
    assert "Independent parts" not in str(explain(translation, out_dir=tmp_path))
    base = translate(_LockedPairAndUnit())
    simulate(base, stop_time=2.0)
    rebound = translate(_LockedPairAndUnit(), parameters={"j.J": 2.0})
    assert rebound.rebound_from is base
    assert simulate(rebound, stop_time=0.2).status == 0
