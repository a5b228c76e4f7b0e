"""Start values given at run time: ``simulate(model, start=...)``, ``--start``, sweeps.

The start values initialization reads (of the states and of the variables
with ``fixed=True``) are parameters of the generated code (``J1.w.start``):
another value rebinds the compiled systems, as another parameter value does,
and gives the arrays the same value given as a modifier gives, bit for bit.
A constant torque ``TAU`` on an inertia ``J`` has the closed form
``w(t) = w0 + TAU/J t`` and ``phi(t) = phi0 + w0 t + TAU/J t^2/2``.
"""

from __future__ import annotations

import warnings
from collections import OrderedDict

import numpy as np
import pytest

import acausal.compiler.translate as translate_module
from acausal import Eq, Experiment, Model, Parameter, Variable, der, simulate, translate
from acausal.errors import InitializationError, ParameterError, SettingError, StartValueWarning
from acausal.library.rotational import ConstantTorque, Inertia
from acausal.tools.cli import main
from acausal.tools.sweep import main_sweep, sweep
from examples.coupled_clutches import CoupledClutches
from examples.first import First

TAU, J = 2.0, 0.5
EXAMPLES = __import__("pathlib").Path(__file__).resolve().parents[2] / "examples"


@pytest.fixture(autouse=True)
def own_translations(monkeypatch):
    """Translations of this module's own: the first translation of a model here is the one
    others rebind to (not a translation an earlier test made for other values)."""
    monkeypatch.setattr(translate_module, "_CACHE", OrderedDict())
    monkeypatch.setattr(translate_module, "_STRUCTURES", OrderedDict())


def assert_identical(a, b):
    """The same run: times, columns and events, bit for bit."""
    assert a.status == b.status == 0, (a.message, b.message)
    assert np.array_equal(a.time, b.time)
    assert list(a.columns) == list(b.columns)
    for name in a.columns:
        assert np.array_equal(a.columns[name], b.columns[name], equal_nan=True), name
    assert [(e.time, e.kind) for e in a.events] == [(e.time, e.kind) for e in b.events]


def rebound_without_compiling(base, translation) -> None:
    """``translation`` reused ``base``'s compiled systems: every system and initialization
    problem was bound to the new vector, none compiled."""
    assert translation.rebound_from is base
    assert translation.systems and translation.initial_systems
    for system in (*translation.systems.values(), *translation.initial_systems.values()):
        assert system.passes[0][0] == "rebind", system.passes


def driven_inertia(phi=None, w=None):
    """ConstantTorque TAU on an inertia J (``phi``, ``w``: its modifiers)."""

    class DrivenInertia(Model):
        experiment = Experiment(stop_time=2.0, interval=0.05)

        def build(self):
            self.src = ConstantTorque(tau_constant=TAU)
            self.body = Inertia(J=J, phi=phi or dict(start=0.0, fixed=True), w=w or dict(start=1.0, fixed=True))
            self.connect(self.src.flange, self.body.flange_a)

    return DrivenInertia()


# -- no new translation, and the modifier's result -------------------------------------------------


def test_coupled_clutches_start_at_run_time_equals_the_modifier_bit_for_bit():
    base = translate(CoupledClutches())
    simulate(base)
    compiled = base.compiled_systems
    rebound = translate(CoupledClutches(), start={"J1.w": 10.5})
    result = simulate(rebound)
    rebound_without_compiling(base, rebound)
    assert base.compiled_systems == compiled  # nothing new compiled for the start value
    assert result["J1.w"][0] == 10.5
    modifier = simulate(CoupledClutches(J1=dict(w=dict(start=10.5))), cache=False)
    assert_identical(result, modifier)
    # the run differs from the model's own start (J1 starts at 10 rad/s)
    assert not np.array_equal(result["J4.w"], simulate(base)["J4.w"])


def test_first_start_at_run_time_equals_the_modifier_bit_for_bit():
    """First's starts are all 0: a non-zero one is no structural zero, and rebinds."""
    base = translate(First())
    simulate(base)
    for variable, value in (("inertia3.w", 2.5), ("inertia2.phi", 0.7), ("spring.phi_rel", -0.01)):
        owner, member = variable.split(".")
        rebound = translate(First(), start={variable: value})
        result = simulate(rebound)
        rebound_without_compiling(base, rebound)
        assert result[variable][0] == value
        assert_identical(result, simulate(First(**{owner: {member: dict(start=value)}}), cache=False))


def test_a_start_value_as_a_parameter_is_the_same_run():
    by_start = simulate(First(), start={"inertia3.w": 1.5})
    by_parameter = simulate(First(), parameters={"inertia3.w.start": 1.5})
    assert_identical(by_start, by_parameter)
    assert by_parameter.stats["translate_seconds"] < 0.5  # flattening only: no system compiled


def test_a_start_value_computed_from_a_parameter_rebinds():
    """w's start is bound to a parameter: another value of it is another start value, rebound."""

    class Bound(Model):
        experiment = Experiment(stop_time=1.0)
        w0 = Parameter(1.0)

        def build(self):
            self.src = ConstantTorque(tau_constant=TAU)
            self.body = Inertia(J=J, phi=dict(start=0.0, fixed=True), w=dict(start=self.w0, fixed=True))
            self.connect(self.src.flange, self.body.flange_a)

    base = translate(Bound())
    simulate(base)
    rebound = translate(Bound(), parameters={"w0": 5.0})
    result = simulate(rebound)
    rebound_without_compiling(base, rebound)
    assert np.max(np.abs(result["body.w"] - (5.0 + TAU / J * result.time))) < 1e-9
    swept = sweep(Bound(), {"w0": [2.0, 3.0]}, ["body.w"], executor="serial", progress=False)
    assert swept.translated_in_workers == 0 and swept.compiled_in_workers == 0
    assert [o.result["body.w"][0] for o in swept.runs] == [2.0, 3.0]


def test_start_values_follow_the_closed_form():
    """phi(t) = phi0 + w0 t + TAU/J t^2/2 for several start values of one translation."""
    base = translate(driven_inertia())
    for phi0, w0 in ((0.0, 1.0), (3.0, -2.0), (-1.5, 10.0)):
        result = simulate(driven_inertia(), start={"body.phi": phi0, "body.w": w0}, rtol=1e-10, atol=1e-10)
        t = result.time
        assert np.max(np.abs(result["body.w"] - (w0 + TAU / J * t))) < 1e-8
        assert np.max(np.abs(result["body.phi"] - (phi0 + w0 * t + TAU / J * t ** 2 / 2))) < 1e-8
    assert translate(driven_inertia(), start={"body.w": 4.0}).rebound_from is base


def test_a_start_value_that_completes_the_initialization_is_reported_with_its_value():
    """The angle is not fixed: it takes its start value, which the warning and the notes name."""
    free = dict(start=0.0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", StartValueWarning)
        base = translate(driven_inertia(phi=free))
        simulate(base)
    with pytest.warns(StartValueWarning) as record:
        result = simulate(driven_inertia(phi=free), start={"body.phi": 2.0}, rtol=1e-10, atol=1e-10)
    message = next(str(w.message) for w in record if issubclass(w.category, StartValueWarning))
    assert "\n  src.phi (= body.phi) = 2\n" in message
    assert any("src.phi (= body.phi) = 2\n" in note for note in result.notes)
    t = result.time
    assert np.max(np.abs(result["body.phi"] - (2.0 + t + TAU / J * t ** 2 / 2))) < 1e-8
    assert translate(driven_inertia(phi=free), start={"body.phi": 2.0}).rebound_from is base


def test_aliased_fixed_start_values_are_checked_with_the_values_given():
    """Two inertias rigidly joined share one angle: their fixed starts must agree."""

    class Joined(Model):
        experiment = Experiment(stop_time=0.5)

        def build(self):
            fixed = dict(start=1.0, fixed=True)
            self.a = Inertia(J=1.0, phi=fixed, w=dict(start=0.0, fixed=True))
            self.b = Inertia(J=1.0, phi=fixed)
            self.connect(self.a.flange_b, self.b.flange_a)

    assert simulate(Joined())["b.phi"][0] == 1.0
    both = simulate(Joined(), start={"a.phi": 2.0, "b.phi": 2.0})
    assert both.status == 0 and both["a.phi"][0] == both["b.phi"][0] == 2.0
    with pytest.raises(InitializationError, match="conflicting initial values: a.phi has fixed start 3 and "
                                                  "b.phi has fixed start 1"):
        simulate(Joined(), start={"a.phi": 3.0})
    with pytest.raises(InitializationError, match="conflicting initial values"):
        simulate(Joined(a=dict(phi=dict(start=3.0))), cache=False)  # the modifier says the same


class Cubic(Model):
    """x' = -x with x(0) the root of x^3 + x = 10 (2): a Newton iteration whose first guess is x's start."""

    experiment = Experiment(stop_time=1.0, interval=0.1)
    x = Variable(start=1.0)
    c = Parameter(10.0)

    def equations(self):
        return [Eq(der(self.x), -self.x)]

    def initial_equations(self):
        return [Eq(self.x ** 3 + self.x, self.c)]


def test_a_start_value_that_is_a_newton_guess_compiles_that_system_anew_and_says_so():
    base = translate(Cubic())
    first = simulate(base)
    rebound = translate(Cubic(), start={"x": 5.0})
    assert rebound.rebound_from is base
    result = simulate(rebound)
    assert result["x"][0] == pytest.approx(2.0, abs=1e-9) and first["x"][0] == pytest.approx(2.0, abs=1e-9)
    assert [s.passes[0][0] for s in rebound.initial_systems.values()] == ["initial equations"]
    assert any("x.start is the first guess of a Newton iteration" in note for note in result.notes)
    assert_identical(result, simulate(Cubic(x=dict(start=5.0)), cache=False))
    # the same guess as the base's: bound, nothing noted
    again = simulate(Cubic(), start={"x": 1.0})
    assert_identical(again, first) and not again.notes


def test_independent_parts_rebind_their_start_values():
    import sys
    from pathlib import Path

    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "compiler"))
    from test_clusters import storm

    base = translate(storm(2))
    simulate(base, stop_time=1.0, interval=0.01)
    rebound = translate(storm(2), start={"j1.w": 1.5, "j0.phi": 0.25})
    result = simulate(rebound, stop_time=1.0, interval=0.01)
    assert rebound.rebound_from is base and rebound.parts
    for system in (*rebound.parts.values(), *rebound.initial_parts.values()):
        assert system.passes[0][0] == "rebind"
    assert result["j1.w"][0] == 1.5 and result["j0.phi"][0] == 0.25
    fresh = simulate(translate(storm(2), cache=False, start={"j1.w": 1.5, "j0.phi": 0.25}),
                     stop_time=1.0, interval=0.01)
    assert_identical(result, fresh)


def test_the_compile_cache_serves_other_start_values(tmp_path, monkeypatch):
    """The persistent cache's key leaves the tunable starts out: a new process loads."""
    monkeypatch.setenv("ACAUSAL_DISK_CACHE", "on")
    monkeypatch.setenv("ACAUSAL_CACHE_DIR", str(tmp_path / "cache"))
    simulate(First())
    translate_module._CACHE.clear()
    translate_module._STRUCTURES.clear()  # as in a new process
    loaded = translate(First(), start={"inertia3.w": 2.5})
    result = simulate(loaded)
    assert {s.passes[0][0] for s in (*loaded.systems.values(), *loaded.initial_systems.values())} == {"load"}
    assert_identical(result, simulate(First(inertia3=dict(w=dict(start=2.5))), cache=False))


# -- errors ----------------------------------------------------------------------------------------


def test_an_unknown_variable_names_the_close_ones():
    with pytest.raises(ParameterError, match="has no variable 'J1.ww'") as info:
        simulate(CoupledClutches(), start={"J1.ww": 3.0})
    assert "J1.w" in info.value.hint


@pytest.mark.parametrize("value, match", [("3", "must be a number"), (True, "must be a number"),
                                          (float("nan"), "nan, not a finite number"),
                                          (float("inf"), "inf, not a finite number")])
def test_a_start_value_must_be_a_finite_number(value, match):
    with pytest.raises(ParameterError, match=match):
        simulate(First(), start={"inertia3.w": value})


def test_a_start_value_initialization_does_not_read_cannot_be_set_at_run_time():
    with pytest.raises(ParameterError, match="inertia3.a is neither fixed nor a state") as info:
        simulate(First(), start={"inertia3.a": 1.0})
    assert "a=dict(start=value)" in info.value.hint and "inertia3.w" in info.value.hint
    with pytest.raises(ParameterError, match="is a Boolean: its start value decides the first discrete state"):
        simulate(CoupledClutches(), start={"clutch1.locked": 1.0})


def test_a_variable_given_as_a_parameter_names_both_routes():
    with pytest.raises(ParameterError, match="has no numeric parameter 'inertia3.w': inertia3.w is a variable") \
            as info:
        simulate(First(), parameters={"inertia3.w": 1.0})
    assert "start={'inertia3.w': value}" in info.value.hint and "w=dict(start=value)" in info.value.hint
    with pytest.raises(ParameterError, match="Jload is a parameter of First, not a variable"):
        simulate(First(), start={"Jload": 1.0})


def test_a_start_value_given_twice_or_to_a_translation_is_refused():
    with pytest.raises(SettingError, match="given twice"):
        simulate(First(), start={"inertia3.w": 1.0}, parameters={"inertia3.w.start": 2.0})
    with pytest.raises(SettingError, match="start= needs the model"):
        simulate(translate(First()), start={"inertia3.w": 1.0})


# -- sweeps and the command line -------------------------------------------------------------------


def test_a_swept_start_value_is_not_translated_in_the_workers():
    result = sweep(CoupledClutches(), {"J1.w.start": [9.5, 10.5]}, ["J1.w", "J4.w"], executor="serial",
                   start={"J2.w": 0.5}, progress=False)
    assert [o.status for o in result.runs] == [0, 0]
    assert result.translated_in_workers == 0 and result.compiled_in_workers == 0
    assert list(result.parameters.columns) == ["J1.w.start"]
    single = simulate(CoupledClutches(J1=dict(w=dict(start=10.5)), J2=dict(w=dict(start=0.5))),
                      outputs=["J1.w", "J4.w"], cache=False)
    assert np.array_equal(result.runs[1].result["J4.w"], single["J4.w"])


def test_a_swept_start_value_that_is_wrong_fails_its_run_only():
    result = sweep(First(), [{"inertia3.w.start": 1.0}, {"inertia3.a.start": 1.0}, {"inertia3.w.start": np.inf}],
                   ["inertia3.w"], executor="serial", progress=False)
    assert [o.status for o in result.runs] == [0, -1, -1]
    assert "neither fixed nor a state" in result.runs[1].message
    assert "not a finite number" in result.runs[2].message


def test_command_line_start_values(tmp_path, capsys):
    first = str(EXAMPLES / "first.py")
    assert main(["simulate", first, "--start", "inertia3.w=2.5", "--out", str(tmp_path / "a.csv")]) == 0
    assert main(["simulate", first, "--param", "inertia3.w.start=2.5", "--out", str(tmp_path / "b.csv")]) == 0
    assert (tmp_path / "a.csv").read_bytes() == (tmp_path / "b.csv").read_bytes()
    assert main(["simulate", first, "--start", "inertia3.x=1", "--out", str(tmp_path / "c.csv")]) == 2
    assert "has no variable 'inertia3.x'" in capsys.readouterr().err
    assert main(["simulate", first, "--start", "inertia3.w", "--out", str(tmp_path / "c.csv")]) == 2
    assert "--start 'inertia3.w': write NAME=VALUE" in capsys.readouterr().err
    code = main_sweep([f"{EXAMPLES / 'coupled_clutches.py'}:CoupledClutches", "--param", "J1.w.start=9.5,10.5",
                       "--output", "J1.w", "--workers", "1", "--out", str(tmp_path / "sweep")])
    assert code == 0
    assert "translated in workers" not in capsys.readouterr().out
