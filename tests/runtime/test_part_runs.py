"""Independent parts integrated apart (:mod:`acausal.runtime.part_runs`).

A model of parts that share no variable and whose discrete part links none of
them is run part by part: each part with its own solver, from start to stop,
as the part alone would run; the result's time axis is the union of the
grid and every part's events, and it is stored per part.
"""

from __future__ import annotations

import copy
import pickle

import numpy as np
import pytest

from acausal import EngineOptions, Eq, Integer, Model, When, pre, simulate
from acausal.compiler.translate import translate
from acausal.errors import StructuralError
from acausal.runtime.part_runs import PartColumns
from examples.benchmarks import add_storm_unit

#: one solver for every part, as before the parts ran apart
ONE_SOLVER = EngineOptions(parts_apart=False)

SETTINGS = dict(stop_time=1.0, interval=0.01)


def units(ks, *, frequency=None, counter: bool = False, extra_equation: bool = False) -> Model:
    """Units ``k`` in ``ks``: Sine(f = 1 + 0.13 k) -> Torque -> Inertia -> BearingFriction, side by side.

    ``frequency``: ``{k: f}`` in place of that; ``counter``: an Integer counting the
    instants both first units spin forward fast (a discrete equation that reads two parts);
    ``extra_equation``: one equation too many for the second unit."""
    ks = tuple(ks)

    class Units(Model):
        def build(self):
            for k in ks:
                add_storm_unit(self, k, (frequency or {}).get(k, 1.0 + 0.13 * k), names=("s", "t", "j", "f"))

        def equations(self):
            a, b = (getattr(self, f"j{k}") for k in ks[:2]) if len(ks) > 1 else (None, None)
            out = []
            if counter:
                out.append(When((a.w > 0.05) & (b.w > 0.05), Eq(self.n, pre(self.n) + 1)))
            if extra_equation:
                out.append(Eq(b.w, 0))
            return out

    if counter:
        class Units(Units):  # noqa: F811 - the same units, with the counter
            n = Integer(start=0)

    Units.__name__ = Units.__qualname__ = "Units" + "_".join(map(str, ks))
    return Units()


def own_rows(result, p: int):
    """Part ``p``'s own time axis and columns (as the part alone computed them)."""
    part = result.columns._parts[p]
    return part.time, part.columns


def test_the_parts_of_a_storm_run_apart_and_say_so():
    result = simulate(units((1, 2, 3)), **SETTINGS, cache=False)
    assert result.status == 0, result.message
    assert isinstance(result.columns, PartColumns)
    assert result.stats["parts"] == 3 and len(result.stats["part_steps"]) == 3
    assert sum(result.stats["part_steps"]) == result.stats["steps"]
    assert any("3 independent parts integrated separately" in note for note in result.notes)
    # the time axis: the grid and every part's events, each event twice
    assert np.all(np.diff(result.time) >= 0)
    for event in result.events[1:]:
        assert np.count_nonzero(result.time == event.time) >= 2
    assert np.all(np.isin(np.round(np.arange(0, 1.0001, 0.01), 12), np.round(result.time, 12)))
    assert [e.kind for e in result.events[:1]] == ["initial"]
    assert [e.time for e in result.events] == sorted(e.time for e in result.events)


def test_a_part_run_equals_each_part_alone_bit_for_bit():
    """Each part's rows are those of the part simulated as a model of its own, bit for bit,
    and its values at the other parts' event instants come from its dense output."""
    ks = (1, 2, 3)
    result = simulate(units(ks), **SETTINGS, cache=False)
    assert result.status == 0, result.message
    for p, k in enumerate(ks):
        alone = simulate(units((k,)), **SETTINGS, cache=False)
        assert alone.status == 0 and "stats" and "parts" not in alone.stats
        time, columns = own_rows(result, p)
        np.testing.assert_array_equal(time, alone.time)
        assert [(e.time, e.kind, e.changes) for e in result.events if e.kind != "initial"
                and any(c[0].startswith(f"f{k}.") for c in e.changes)] == \
            [(e.time, e.kind, e.changes) for e in alone.events if e.kind != "initial" and e.changes]
        # (the first part also holds what no discrete symbol reaches: the other units' fixed supports)
        shared = [name for name in columns if name in alone.columns]
        assert len(shared) > 30
        assert all(alone.info(n).kind == "parameter" or n.endswith("phi_support")
                   for n in alone.names if n not in columns)
        for name in shared:
            np.testing.assert_array_equal(columns[name], alone[name], err_msg=name)
            # on the model's axis: the part's own rows at its instants (first and last row there)
            merged = result[name]
            first = np.searchsorted(result.time, alone.time, side="left")
            last = np.searchsorted(result.time, alone.time, side="right") - 1
            own_first = np.searchsorted(alone.time, alone.time, side="left")
            own_last = np.searchsorted(alone.time, alone.time, side="right") - 1
            np.testing.assert_array_equal(merged[first], alone[name][own_first], err_msg=name)
            np.testing.assert_array_equal(merged[last], alone[name][own_last], err_msg=name)
    # at another part's event a part has no event: its two rows are equal, on its dense output
    w1 = result["j1.w"]
    own_time, _ = own_rows(result, 0)
    others = [e.time for e in result.events if e.kind == "state" and e.time not in set(own_time)]
    assert others
    for t in others:
        rows = np.flatnonzero(result.time == t)
        assert len(rows) >= 2 and np.all(w1[rows] == w1[rows[0]])
        assert min(own_time[own_time < t][-1:]) < t < min(own_time[own_time > t][:1])


def test_an_event_in_one_part_leaves_the_other_parts_steps_untouched():
    """Unit 2 driven at another frequency (other events, other steps): unit 1's steps,
    right-hand side evaluations and rows stay what they were."""
    a = simulate(units((1, 2)), **SETTINGS, cache=False)
    b = simulate(units((1, 2), frequency={2: 2.9}), **SETTINGS, cache=False)
    assert a.status == b.status == 0
    assert a.stats["part_steps"][0] == b.stats["part_steps"][0]
    assert a.stats["part_steps"][1] != b.stats["part_steps"][1]
    ta, ca = own_rows(a, 0)
    tb, cb = own_rows(b, 0)
    np.testing.assert_array_equal(ta, tb)
    for name in ca:
        np.testing.assert_array_equal(ca[name], cb[name], err_msg=name)
    # one solver for both: every event of unit 2 restarts unit 1's integration too
    one = simulate(units((1, 2)), **SETTINGS, cache=False, options=ONE_SOLVER)
    assert one.stats["steps"] > max(a.stats["part_steps"])


def test_a_part_run_matches_one_solver_to_the_tolerance():
    translation = translate(units((1, 2, 3)), cache=False)
    apart = simulate(translation, **SETTINGS)
    one = simulate(translation, **SETTINGS, options=ONE_SOLVER)
    assert "parts" not in one.stats and not isinstance(one.columns, PartColumns)
    assert sorted(apart.names) == sorted(one.names)
    assert [(e.kind, e.changes) for e in apart.events] == [(e.kind, e.changes) for e in one.events]
    np.testing.assert_allclose([e.time for e in apart.events], [e.time for e in one.events], atol=1e-4)
    t = np.linspace(0.0, 1.0, 37)
    for name in ("j1.w", "j2.phi", "j3.w", "f3.sa", "f2.mode"):
        np.testing.assert_allclose(apart.at(t, name), one.at(t, name), atol=2e-3, err_msg=name)
    assert apart.final("j3.w") == pytest.approx(one.final("j3.w"), abs=1e-5)


def test_the_result_reads_writes_and_copies_as_a_plain_one(tmp_path):
    result = simulate(units((1, 2)), **SETTINGS, cache=False)
    frame = result.to_pandas()
    assert frame.shape[0] == len(result.time) and frame.shape[1] >= len(result.names)
    np.testing.assert_array_equal(frame["j2.w"].to_numpy(), result["j2.w"])
    result.to_csv(tmp_path / "r.csv")
    assert (tmp_path / "r.csv").stat().st_size > 0
    assert result["s1.amplitude"].shape == result.time.shape  # a parameter's column
    assert "j1.w" in result and "nothing" not in result
    with pytest.raises(KeyError):
        result.columns["nothing"]
    for copied in (pickle.loads(pickle.dumps(result)), copy.deepcopy(result)):
        assert type(copied.columns) is dict
        np.testing.assert_array_equal(copied["j1.w"], result["j1.w"])


def test_a_discrete_equation_of_two_parts_keeps_one_solver_and_says_why():
    result = simulate(units((1, 2), counter=True), **SETTINGS, cache=False)
    assert result.status == 0, result.message
    assert "parts" not in result.stats
    assert any("integrated with one solver: the discrete part links part 1 and part 2" in note
               for note in result.notes), result.notes


def test_a_part_that_fails_is_run_again_with_one_solver():
    """A budget runs out in a part: the model runs with one solver, whose failure and partial
    result read as they always have; the notes say why."""
    result = simulate(units((1, 2)), **SETTINGS, cache=False, max_steps=20)
    assert result.status == -1 and "budget of 20 steps" in result.message
    assert len(result.time) > 1
    assert any("integrated with one solver: part 1 of 2 stopped" in note for note in result.notes)


def test_a_structural_error_in_one_part_reads_as_the_whole_models():
    with pytest.raises(StructuralError) as apart:
        simulate(units((1, 2, 3), extra_equation=True), stop_time=1.0, cache=False)
    with pytest.raises(StructuralError) as whole:
        simulate(units((1, 2, 3), extra_equation=True), stop_time=1.0, cache=False,
                 options=EngineOptions(clusters=False))
    assert str(apart.value) == str(whole.value)


def test_an_output_demand_runs_the_parts_apart():
    result = simulate(units((1, 2)), **SETTINGS, cache=False, outputs=["j2.w"])
    full = simulate(units((1, 2)), **SETTINGS, cache=False)
    assert result.status == 0 and result.stats["parts"] == 2
    assert "j2.w" in result.names and "j1.w" not in result.names
    # (the part computes what j2.w and its events need: other states, other steps)
    assert [(e.kind, e.changes) for e in result.events] == [(e.kind, e.changes) for e in full.events]
    t = np.linspace(0.0, 1.0, 41)
    np.testing.assert_allclose(result.at(t, "j2.w"), full.at(t, "j2.w"), atol=1e-4)


def test_a_new_parameter_value_runs_the_parts_apart_as_a_fresh_translation():
    base = translate(units((1, 2)), cache=False)
    simulate(base, **SETTINGS)
    rebound = simulate(units((1, 2)), **SETTINGS, parameters={"j2.J": 0.5})
    fresh = simulate(translate(units((1, 2)), cache=False, parameters={"j2.J": 0.5}), **SETTINGS)
    assert rebound.status == fresh.status == 0 and rebound.stats["parts"] == 2
    np.testing.assert_array_equal(rebound.time, fresh.time)
    for name in ("j1.w", "j2.w", "f2.sa"):
        np.testing.assert_array_equal(rebound[name], fresh[name], err_msg=name)


def test_a_part_of_many_columns_is_assembled_column_by_column(monkeypatch):
    result = simulate(units((1, 2, 3)), **SETTINGS, cache=False)
    whole = {name: result[name] for name in result.names}
    monkeypatch.setattr(PartColumns, "BLOCK_COLUMNS", 2)
    apart = simulate(units((1, 2, 3)), **SETTINGS, cache=False)
    for name in apart.names:
        np.testing.assert_array_equal(apart[name], whole[name], err_msg=name)


class _StuckPairBesideAUnit(Model):
    """Two bearings stuck on one shaft (the holding torque's split is open: the discrete
    state constrains one motion twice and is relaxed) beside an independent storm unit."""

    def build(self):
        from acausal.library.rotational import BearingFriction, ConstantTorque, Inertia

        self.torque = ConstantTorque(tau_constant=0.5)
        self.inertia = Inertia(J=1.0, phi=dict(start=0.25, fixed=True), w=dict(start=0.0, fixed=True))
        self.bf1 = BearingFriction(tau_pos=[[0.0, 1.0]])
        self.bf2 = BearingFriction(tau_pos=[[0.0, 2.0]])
        self.connect(self.torque.flange, self.inertia.flange_a)
        self.connect(self.inertia.flange_b, self.bf1.flange_a)
        self.connect(self.bf1.flange_b, self.bf2.flange_a)
        add_storm_unit(self, 1, 1.13, names=("s", "t", "j", "f"))


def _warned(options: EngineOptions):
    from acausal.errors import RedundantConstraintWarning

    with pytest.warns(RedundantConstraintWarning) as caught:
        result = simulate(_StuckPairBesideAUnit(), **SETTINGS, cache=False, options=options)
    return result, [str(w.message) for w in caught if issubclass(w.category, RedundantConstraintWarning)]


def test_a_part_that_constrains_one_motion_twice_is_relaxed_and_runs_apart():
    """The stuck pair's part is relaxed as the whole model is (bf2's share of the holding
    torque set to 0): the parts run apart, not again with one solver after the part failed,
    and the stuck part's columns are the whole model's, bit for bit."""
    result, said = _warned(EngineOptions())
    assert result.status == 0, result.message
    assert isinstance(result.columns, PartColumns)
    assert any("2 independent parts integrated separately" in note for note in result.notes)
    assert not any("one solver" in note for note in result.notes)
    assert said and all(text.startswith("bf2: two equations constrain") for text in said)
    assert "left out: bf2 (PartialFriction eq. 4)" in said[0] and "set to 0: bf2.flange_a.tau" in said[0]
    whole, _ = _warned(EngineOptions(clusters=False))
    for name in ("inertia.w", "inertia.phi", "bf1.tau", "bf2.tau", "bf1.sa"):
        np.testing.assert_array_equal(result[name], whole[name], err_msg=name)
    # the shaft holds: the torque is taken by bf1 alone, below its static limit of 1 N.m
    assert np.all(result["inertia.w"] == 0) and np.all(result["inertia.phi"] == 0.25)
    np.testing.assert_allclose(np.abs(result["bf1.tau"]), 0.5)
    np.testing.assert_array_equal(result["bf2.tau"], 0)
    np.testing.assert_allclose(result["j1.w"], whole["j1.w"], atol=1e-4)


def test_a_composed_system_says_what_its_parts_relaxed():
    """With one solver for the parts, the composed system of a state whose part was relaxed
    carries that part's relaxation: the run warns, and the model stays compiled part by part."""
    result, said = _warned(ONE_SOLVER)
    assert result.status == 0, result.message
    assert said and all(text.startswith("bf2: two equations constrain") for text in said)
    translation = translate(_StuckPairBesideAUnit(), cache=False, options=ONE_SOLVER)
    with pytest.warns(Warning):
        simulate(translation, **SETTINGS)
    assert translation.clustering is not None  # (it used to fall back to the whole model)
    relaxed = [s.relaxed for s in translation.systems.values() if s.relaxed is not None]
    assert relaxed and all(r.components == ("bf2",) for r in relaxed)


def test_a_parts_system_is_a_compiled_system_that_hands_nothing_on_to_its_mode():
    """A part's system whose crossing vector is not its mode's (it reads a relation of time
    alone another part computes) names what it takes from its mode; nothing else of the
    mode is reached through it (its mode's watched crossings, say, are not the part's)."""
    from acausal.compiler.parts import PartSystem
    from acausal.runtime.contract import CompiledSystem

    translation = translate(units((1, 2, 3)), cache=False)
    simulate(translation, **SETTINGS)
    models, _ = translation.part_models()
    systems = [s for m in models for s in m.systems.values() if isinstance(s, PartSystem)]
    assert systems
    for system in systems:
        mode = system.mode
        assert isinstance(system, CompiledSystem)
        assert system.derivative_names == mode.derivative_names and system.relaxed is mode.relaxed
        assert system.sources == mode.sources and system.states == mode.states
        for name in ("structure", "code", "passes", "timings"):  # the mode's own, for inspection
            assert hasattr(mode, name) and not hasattr(system, name), name
