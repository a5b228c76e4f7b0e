"""Parts of one shape compiled once (:mod:`acausal.compiler.part_shapes`).

A part equal to an earlier one up to its names takes the earlier part's
generated code, bound to its own parameters.  Each test holds such a run to
the run that compiles every part for itself (``EngineOptions(part_shapes=False)``),
bit for bit, and checks which parts were renamed.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from acausal import EngineOptions, Model, simulate
from acausal.compiler.translate import translate
from acausal.library.blocks import Sine
from acausal.library.rotational import BearingFriction, Inertia, Torque
from examples.benchmarks import add_storm_unit

#: every part compiled for itself
COMPILED = EngineOptions(part_shapes=False)


def storm(n: int, unit=None) -> Model:
    """``n`` independent friction units (Sine -> Torque -> Inertia -> BearingFriction),
    unit ``k`` driven at ``1 + 0.13 k`` Hz; ``unit(model, k)`` adds unit ``k`` instead
    where it returns True."""

    class Storm(Model):
        def build(self):
            for k in range(n):
                if unit is None or not unit(self, k):
                    add_storm_unit(self, k, 1.0 + 0.13 * k)

    Storm.__name__ = Storm.__qualname__ = f"Storm{n}"
    return Storm()


def run(model: Model, options: EngineOptions | None = None):
    translation = translate(model, cache=False, **({} if options is None else {"options": options}))
    return translation, simulate(translation, stop_time=1.0)


def assert_same(a, b) -> None:
    assert a.status == b.status
    assert np.array_equal(a.time, b.time)
    assert list(a.columns) == list(b.columns)
    for c in a.columns:
        assert np.array_equal(a[c], b[c], equal_nan=True), c
    assert [str(e) for e in a.events] == [str(e) for e in b.events]


def renamed_units(translation) -> set[int]:
    """The clusters with a system renamed from another part."""
    return {index for (index, _key), system in translation.parts.items() if system.shape_of is not None}


def unit_of(translation, index: int) -> str:
    """The unit number of cluster ``index`` (from its variables' names)."""
    names = translation.clustering.clusters[index].variables
    return names[0].split(".")[0].lstrip("abcdefghijklmnopqrstuvwxyz")


def test_equal_units_are_renamed_and_give_what_their_own_compilation_gives():
    shared, result = run(storm(10))
    compiled, expected = run(storm(10), COMPILED)
    assert_same(result, expected)
    # every unit after the first of each state is renamed, none when switched off
    assert len(renamed_units(shared)) >= 4
    assert not renamed_units(compiled)
    assert len(result.events) > 20  # the units stick and slip: several discrete states each
    for (index, _key), system in shared.parts.items():
        own = set(shared.clustering.clusters[index].variables)
        # a renamed system is named after its own unit, and so is its initialization problem
        assert {s for s in system.states} <= own
        assert {u for u in system.unknowns if not u.startswith("der(")} <= own
    renamed_initial = [p for p in shared.initial_parts.values() if p.passes[:1] and p.passes[0][0] == "rename part"]
    assert renamed_initial
    for (index, _key), problem in shared.initial_parts.items():
        own = set(shared.clustering.clusters[index].variables)
        assert {u for u in problem.unknowns if not u.startswith("der(")} <= own


def test_each_renamed_unit_reads_its_own_parameters():
    """The drive of unit k is 2 sin(2 pi f_k t) with its own frequency (analytic)."""
    _, result = run(storm(5))
    t = result.time
    for k in range(5):
        f = 1.0 + 0.13 * k
        assert np.allclose(result[f"sine{k}.y"], 2.0 * np.sin(2.0 * math.pi * f * t), rtol=0, atol=1e-12)
        # the torque applied to the inertia is the drive: J dw/dt = drive - friction torque
        assert np.allclose(result[f"torque{k}.tau"], result[f"sine{k}.y"], rtol=0, atol=1e-12)


def other_start(model: Model, k: int) -> bool:
    """Unit 2 starts turning (another start value: another shape)."""
    if k != 2:
        return False
    sine, torque = Sine(amplitude=2.0, f=1.26), Torque()
    inertia = Inertia(J=1.0, phi=dict(start=0.0, fixed=True), w=dict(start=0.5, fixed=True))
    bearing = BearingFriction(tau_pos=[[0.0, 1.0]], peak=1.2)
    for name, component in zip(("sine", "torque", "inertia", "bearing"), (sine, torque, inertia, bearing)):
        setattr(model, f"{name}{k}", component)
    model.connect(sine.y, torque.tau)
    model.connect(torque.flange, inertia.flange_a)
    model.connect(inertia.flange_b, bearing.flange_a)
    return True


def zero_amplitude(model: Model, k: int) -> bool:
    """Unit 3 is not driven: a zero amplitude is a structural zero (another shape)."""
    if k != 3:
        return False
    add_storm_unit(model, k, 1.39)
    getattr(model, f"sine{k}").amplitude = 0.0
    return True


@pytest.mark.parametrize("unit", [other_start, zero_amplitude], ids=["start value", "zero parameter"])
def test_a_unit_of_another_shape_is_compiled_for_itself(unit):
    shared, result = run(storm(5, unit))
    _, expected = run(storm(5, unit), COMPILED)
    assert_same(result, expected)
    odd = 2 if unit is other_start else 3
    renamed = {unit_of(shared, i) for i in renamed_units(shared)}
    assert str(odd) not in renamed
    assert renamed  # the other units still are


def test_renamed_parts_are_not_stored_on_disk_and_a_warm_run_is_the_same(tmp_path, monkeypatch):
    monkeypatch.setenv("ACAUSAL_DISK_CACHE", "on")
    monkeypatch.setenv("ACAUSAL_CACHE_DIR", str(tmp_path / "cache"))
    cold_translation = translate(storm(4), cache=False)
    cold = simulate(cold_translation, stop_time=1.0)
    stored = list((tmp_path / "cache").rglob("*.json"))
    compiled = sum(1 for s in cold_translation.parts.values() if s.shape_of is None)
    initial = sum(1 for p in cold_translation.initial_parts.values()
                  if not (p.passes[:1] and p.passes[0][0] == "rename part"))
    assert len(stored) <= compiled + initial
    warm = simulate(translate(storm(4), cache=False), stop_time=1.0)
    assert_same(warm, cold)


def test_equal_units_are_compiled_once_whatever_their_number():
    counts = {}
    for n in (3, 6):
        for options in (None, COMPILED):
            translation, _ = run(storm(n), options)
            counts[n, options is None] = translation.compiled_systems
    # units 1.. are equal up to their names (unit 0 also holds the relations of time alone)
    assert counts[6, True] == counts[3, True]
    assert counts[6, False] > counts[3, False] > counts[3, True]


def test_a_new_parameter_value_rebinds_one_part_of_each_shape_and_renames_the_others():
    base = translate(storm(6))
    simulate(base, stop_time=1.0)
    compiled_before = base.compiled_systems
    rebound = translate(storm(6), parameters={"inertia3.J": 0.5})
    assert rebound.rebound_from is base
    result = simulate(rebound, stop_time=1.0)
    kinds = {system.passes[0][0] for system in rebound.parts.values()}
    assert kinds <= {"rebind", "rename part", "specialise"}  # (specialise: a state sharing another's)
    assert "rename part" in kinds and "rebind" in kinds
    assert rebound.compiled_systems == sum(1 for s in rebound.parts.values()
                                           if s.shares is None and s.shape_of is None)
    # nothing compiled anew: every system rebound, renamed or shared
    assert not [s.description for s in rebound.parts.values() if "alias" in dict(s.passes)]
    assert compiled_before == base.compiled_systems
    fresh = simulate(translate(storm(6), cache=False, parameters={"inertia3.J": 0.5},
                               options=COMPILED), stop_time=1.0)
    assert_same(result, fresh)
    # the new inertia changes unit 3 only
    _, untouched = run(storm(6))
    assert not np.allclose(result["inertia3.w"], np.interp(result.time, untouched.time, untouched["inertia3.w"]))
    assert np.array_equal(result["inertia4.w"][:5], untouched["inertia4.w"][:5])


def test_a_bundle_ships_the_renamed_parts_and_a_worker_compiles_nothing():
    import dataclasses
    import pickle

    from acausal.compiler.translate import Translation

    translation = translate(storm(5), cache=False)
    expected = simulate(translation, stop_time=1.0)
    assert renamed_units(translation)
    bundle = pickle.loads(pickle.dumps(translation.export()))
    entries = {k for k in bundle.payloads}
    assert {f"part {i} {k!r}" for (i, k) in translation.parts} <= entries
    assert {f"initial-part {i} {k!r}" for (i, k) in translation.initial_parts} <= entries
    flat = bundle.unpacked()[0]
    loaded = Translation.from_bundle(bundle, flat)
    assert_same(simulate(loaded, stop_time=1.0), expected)
    assert all(s.passes[0][0] == "load" for s in [*loaded.parts.values(), *loaded.initial_parts.values()])
    # other values of a renamed unit's parameters: its shipped system rebinds to them
    other = dataclasses.replace(flat, parameters=tuple(
        dataclasses.replace(p, value=0.5) if p.name == "inertia3.J" else p for p in flat.parameters))
    worker = simulate(Translation.from_bundle(bundle, other), stop_time=1.0)
    fresh = simulate(translate(storm(5), cache=False, parameters={"inertia3.J": 0.5}, options=COMPILED),
                     stop_time=1.0)
    assert_same(worker, fresh)
