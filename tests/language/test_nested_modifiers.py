"""Nested modifiers at construction (issue 14, part 2).

``Top(drive=dict(load=dict(J=4)))`` sets the parameter ``J`` of the
component ``load`` that ``drive``'s build() makes, as Modelica's
``Top m(drive(load(J=4)))``.  Sub-components exist only once build() has
run, so the modifiers are kept and applied when build() assigns the
sub-component; an outer modifier wins over the one build() wrote.

The driven inertia gives the closed form: a constant torque ``tau`` on an
inertia ``J`` starting at rest turns it at ``w(t) = tau/J * t``.
"""

from __future__ import annotations

import numpy as np
import pytest

from acausal import Experiment, Model, simulate
from acausal.compiler.flatten import flatten
from acausal.errors import ModifierError
from acausal.language import Component, Parameter
from acausal.library.blocks import Constant
from acausal.library.rotational import Inertia, Torque

TAU = 2.0  # N.m, the drive's torque


class Drive(Component):
    """A constant torque on an inertia: the two-level component under test."""

    tau = Parameter(TAU, unit="N.m", description="Driving torque")

    def build(self):
        self.source = Constant(k=self.tau)
        self.torque = Torque()
        self.load = Inertia(J=1.0, phi=dict(start=0, fixed=True), w=dict(start=0, fixed=True))
        self.connect(self.source.y, self.torque.tau)
        self.connect(self.torque.flange, self.load.flange_a)


class Top(Model):
    """The model holding the drive: a third level above the inertia."""

    experiment = Experiment(stop_time=1.0, interval=0.1)

    def build(self):
        self.drive = Drive()


def _parameter(model: Component, name: str) -> float:
    flat = flatten(model)
    return {p.name: float(p.value) for p in flat.parameters}[name]


def test_a_nested_modifier_changes_the_simulated_acceleration_as_tau_over_J():
    """J = 4 through drive=dict(load=dict(J=4)): w(t) = tau/J t = 0.5 t (the default J = 1 gives 2 t)."""
    result = simulate(Top(drive=dict(load=dict(J=4.0))))
    t = result.time
    np.testing.assert_allclose(result["drive.load.w"], TAU / 4.0 * t, rtol=1e-6, atol=1e-9)
    np.testing.assert_allclose(result["drive.load.a"], TAU / 4.0, rtol=1e-9)
    default = simulate(Top())
    np.testing.assert_allclose(default["drive.load.w"], TAU / 1.0 * default.time, rtol=1e-6, atol=1e-9)


def test_nested_modifier_and_run_time_parameter_give_the_same_arrays():
    """simulate(Top(drive=dict(load=dict(J=4)))) equals simulate(Top(), parameters={"drive.load.J": 4})."""
    nested = simulate(Top(drive=dict(load=dict(J=4.0))))
    at_run_time = simulate(Top(), parameters={"drive.load.J": 4.0})
    np.testing.assert_array_equal(nested.time, at_run_time.time)
    for name in ("drive.load.phi", "drive.load.w", "drive.load.a"):
        np.testing.assert_allclose(nested[name], at_run_time[name], rtol=1e-12, atol=1e-15, err_msg=name)


def test_a_parameter_of_the_middle_level_and_of_the_top_level_component():
    """One level (drive=dict(tau=...)) and a parameter of the component itself, in one call."""
    model = Top(drive=dict(tau=3.0, load=dict(J=6.0)))
    result = simulate(model)
    np.testing.assert_allclose(result["drive.load.a"], 0.5, rtol=1e-9)


def test_the_outer_modifier_wins_over_the_one_build_wrote():
    """build() writes J=1.0 for the load; Top(drive=dict(load=dict(J=5))) makes it 5."""
    assert _parameter(Top(), "drive.load.J") == 1.0
    assert _parameter(Top(drive=dict(load=dict(J=5.0))), "drive.load.J") == 5.0


def test_variable_attributes_merge_with_those_build_gave():
    """build() fixes w at 0; a nested dict(start=3) changes the start and keeps fixed=True."""
    model = Top(drive=dict(load=dict(w=dict(start=3.0))))
    flat = flatten(model)
    w = next(v for v in flat.variables if v.name == "drive.load.w")
    assert w.start == 3.0 and w.fixed is True
    result = simulate(Top(drive=dict(load=dict(w=dict(start=3.0)))))
    np.testing.assert_allclose(result["drive.load.w"], 3.0 + TAU * result.time, rtol=1e-6)


def test_variable_attribute_modifiers_still_work_at_the_top():
    inertia = Inertia(w=dict(start=1, fixed=True))
    assert inertia.attribute("w", "start") == 1 and inertia.attribute("w", "fixed") is True


def test_unknown_nested_parameter_names_the_dotted_path_and_suggests():
    with pytest.raises(ModifierError) as info:
        flatten(Top(drive=dict(load=dict(Jx=4.0))))
    message = str(info.value)
    assert "Top.drive.load.Jx" in message and "Inertia" in message and "'Jx'" in message
    assert "did you mean J?" in info.value.hint


def test_unknown_sub_component_names_the_path_and_suggests():
    with pytest.raises(ModifierError) as info:
        flatten(Top(drive=dict(lod=dict(J=4.0))))
    assert "Top.drive.lod" in str(info.value) and "'lod'" in str(info.value)
    assert "did you mean load?" in info.value.hint
    with pytest.raises(ModifierError) as info:
        flatten(Top(drivee=dict(load=dict(J=4.0))))
    assert "Top has no parameter, variable or sub-component named 'drivee'" in str(info.value)
    assert "did you mean drive?" in info.value.hint


def test_a_parameter_given_a_dict_and_a_sub_component_given_a_value_are_errors():
    with pytest.raises(ModifierError, match=r"Top\.drive\.tau is a parameter"):
        flatten(Top(drive=dict(tau=dict(start=1))))
    with pytest.raises(ModifierError) as info:
        Top(drive=4.0)  # not a declaration: found at construction
    assert "'drive'" in str(info.value) and "dict" in info.value.hint


def test_a_leaf_component_rejects_an_unknown_dict_at_construction():
    """A class without build() has no sub-components: the error comes at once, as before."""
    with pytest.raises(ModifierError, match="Constant has no parameter or variable named 'kk'"):
        Constant(kk=dict(start=1))


def test_repr_shows_the_nested_modifiers():
    assert repr(Top(drive=dict(load=dict(J=4.0)))) == "Top(drive=dict(load=dict(J=4.0)))"
    model = Top(drive=dict(load=dict(J=4.0)))
    model.ensure_built()
    assert repr(model.drive) == "Drive(load=dict(J=4.0))"
    model.drive.ensure_built()
    assert repr(model.drive.load) == "Inertia(J=4.0, phi=dict(start=0, fixed=True), w=dict(start=0, fixed=True))"


def test_modifiers_of_one_instance_do_not_leak_into_another():
    assert _parameter(Top(drive=dict(load=dict(J=4.0))), "drive.load.J") == 4.0
    assert _parameter(Top(), "drive.load.J") == 1.0


def test_nested_modifier_sets_a_structural_parameter_before_build():
    """Torque(useSupport=True) has a support connector: set from two levels up, build() sees it."""
    model = Top(drive=dict(torque=dict(useSupport=True)))
    model.ensure_built()
    model.drive.ensure_built()
    assert model.drive.torque.useSupport is True
