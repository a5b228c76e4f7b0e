"""Run-time parameters: tunable values reuse the compiled systems (issue 11, item 3).

Every check compares with a model translated anew for the same values: the
compiled systems of the first translation, bound to another parameter
vector, must give the very same numbers.
"""

from __future__ import annotations

import numpy as np
import pytest

from acausal import Eq, Experiment, If, Model, Parameter, Variable, der, simulate, translate
from acausal.errors import InitializationError, ParameterError, SettingError
from acausal.library.rotational import Inertia
from examples.coupled_clutches import CoupledClutches
from examples.first import First


def _same(a, b) -> bool:
    return np.array_equal(a.time, b.time) and all(
        np.array_equal(a[n], b[n], equal_nan=True) for n in a.names)


@pytest.mark.parametrize("model, parameters", [
    (CoupledClutches, {"clutch1.fn_max": 100.0}),
    (CoupledClutches, {"clutch2.fn_max": 5.0, "J1.J": 2.5}),
    (First, {"inertia2.J": 4.0, "damper.d": 3.0}),
])
def test_a_tunable_parameter_gives_the_result_of_a_fresh_translation(model, parameters):
    simulate(model())  # the first translation of the structure, with the model's own values
    reused = simulate(model(), parameters=parameters)
    fresh = simulate(model(), parameters=parameters, cache=False)
    assert _same(reused, fresh)
    assert not _same(reused, simulate(model()))  # and the values did change something


def test_a_rebound_translation_compiles_nothing_anew():
    base = translate(CoupledClutches())
    simulate(base)
    rebound = translate(CoupledClutches(), parameters={"clutch1.fn_max": 7.0})
    assert rebound.rebound_from is base
    simulate(rebound)
    assert rebound.systems
    assert all(s.passes[0][0] == "rebind" for s in rebound.systems.values())
    assert all(s.passes[0][0] == "rebind" for s in rebound.initial_systems.values())
    assert rebound.parameter_values["clutch1.fn_max"] == 7.0
    assert base.parameter_values["clutch1.fn_max"] == 20.0  # the first keeps its own values


def test_a_zero_is_structural_and_the_result_says_so():
    result = simulate(CoupledClutches(), parameters={"clutch1.fn_max": 0.0})
    assert result.status == 0
    assert any("clutch1.fn_max = 0" in note and "translated" in note for note in result.notes)
    assert _same(result, simulate(CoupledClutches(), parameters={"clutch1.fn_max": 0.0}, cache=False))


def test_bindings_follow_a_changed_parameter():
    class Bound(Model):
        experiment = Experiment(stop_time=1.0)
        Jm = Parameter(1.0)
        tau = Parameter(2.0)

        def build(self):
            from acausal.library.rotational import ConstantTorque

            self.j = Inertia(J=2 * self.Jm, phi=dict(start=0, fixed=True), w=dict(start=0, fixed=True))
            self.src = ConstantTorque(tau_constant=self.tau)
            self.connect(self.src.flange, self.j.flange_a)

    result = simulate(Bound(), parameters={"Jm": 4.0}, rtol=1e-9)
    assert result["j.J"][0] == 8.0
    assert result.final("j.w") == pytest.approx(2.0 / 8.0 * 1.0, rel=1e-8)  # w = tau/J * t


class Divides(Model):
    """y = x/(a - b): solved by dividing by a parameter expression."""

    experiment = Experiment(stop_time=1.0)
    a = Parameter(2.0)
    b = Parameter(1.0)
    x = Variable(start=1.0, fixed=True)
    y = Variable(start=1.0)

    def equations(self):
        return [Eq(der(self.x), -self.x), Eq((self.a - self.b) * self.y, self.x)]


def test_a_system_that_divides_by_a_vanishing_parameter_expression_is_compiled_anew():
    base = translate(Divides())
    simulate(base)
    rebound = translate(Divides(), parameters={"a": 1.0, "b": 1.0})
    # a - b = 0: y cannot be found; both the rebound and a fresh translation say so
    # the same way (not with a division by zero in the old code)
    with pytest.raises(InitializationError) as reused:
        simulate(rebound)
    with pytest.raises(InitializationError) as fresh:
        simulate(Divides(), parameters={"a": 1.0, "b": 1.0}, cache=False)
    # not bound to the old code (which divides by a - b = 0): compiled for these values
    assert not any(s.passes[0][0] == "rebind" for s in rebound.systems.values())
    assert "ZeroDivisionError" not in reused.value.message
    assert reused.value.message == fresh.value.message


def test_a_parameter_a_relation_compares_with_a_constant_is_structural():
    class Switch(Model):
        experiment = Experiment(stop_time=1.0)
        p = Parameter(1.0)
        x = Variable(start=0.0, fixed=True)

        def equations(self):
            return [Eq(der(self.x), If(self.p > 0, 1, -1))]

    assert simulate(Switch()).final("x") == pytest.approx(1.0)
    flipped = simulate(Switch(), parameters={"p": -1.0})
    assert flipped.final("x") == pytest.approx(-1.0)
    assert any("p = -1" in note and "structural" in note for note in flipped.notes)


class _Bearing(Model):
    """An inertia spinning down on a bearing (Coulomb friction tau0)."""

    def build(self):
        from acausal.library.rotational import BearingFriction

        self.j = Inertia(J=1, phi=dict(start=0, fixed=True), w=dict(start=1, fixed=True))
        self.b = BearingFriction(**self.bearing_modifiers)
        self.connect(self.j.flange_b, self.b.flange_a)

    bearing_modifiers: dict = {}


class _LowFrictionBearing(_Bearing):
    bearing_modifiers = {"tau_pos": [[0.0, 0.25]]}


def test_a_structural_parameter_translates_anew_and_says_so():
    """tau_pos (a table: structural) given as a parameter equals the model built with it."""
    model = _Bearing()
    default = simulate(model, stop_time=5.0)
    changed = simulate(model, stop_time=5.0, parameters={"b.tau_pos": [[0.0, 0.25]]})
    built = simulate(_LowFrictionBearing(), stop_time=5.0, cache=False)
    assert _same(changed, built)
    assert any("b.tau_pos" in note and "structural" in note for note in changed.notes), changed.notes
    # w = 1 - tau0*t until it stops: at t = 1 the default has stopped, the low friction not
    k = int(np.searchsorted(changed.time, 1.0))
    assert changed["j.w"][k] == pytest.approx(0.75, abs=1e-6)
    assert default["j.w"][k] == pytest.approx(0.0, abs=1e-6)
    # the model given is not changed
    assert model.b.tau_pos == [[0.0, 1.0]]
    assert _same(simulate(model, stop_time=5.0), default)


def test_unknown_names_are_refused():
    with pytest.raises(ParameterError) as info:
        simulate(_Bearing(), parameters={"j.JJ": 2.0})
    assert "j.J" in info.value.hint
    with pytest.raises(SettingError):
        simulate(translate(_Bearing()), parameters={"j.J": 2.0})


def test_parameters_on_the_command_line(tmp_path):
    from acausal.tools.cli import main

    out = tmp_path / "cc.csv"
    assert main(["simulate", "examples/coupled_clutches.py", "--param", "clutch1.fn_max=100",
                 "--out", str(out)]) == 0
    header = out.read_text().splitlines()[0].split(",")
    column = [c.strip('"') for c in header].index("clutch1.fn_max")
    last = out.read_text().splitlines()[-1].split(",")
    assert float(last[column]) == 100.0
    assert main(["simulate", "examples/coupled_clutches.py", "--param", "clutch1.fn_max",
                 "--out", str(out)]) == 2


def test_a_structural_parameter_rebuilds_what_build_keeps_in_lists():
    """A model whose build() keeps its components in a list: the new instance makes its own."""
    from acausal.language import with_structural

    class Kept(_Bearing):
        def build(self):
            super().build()
            self.kept = [self.j, self.b]

    model = Kept()
    simulate(model, stop_time=1.0)  # built
    fresh = with_structural(model, {"b.tau_pos": [[0.0, 0.25]]})
    result = simulate(fresh, stop_time=1.0, cache=False)
    assert result.status == 0
    assert all(c._parent is fresh for c in fresh.kept)
    assert all(c._parent is model for c in model.kept)
