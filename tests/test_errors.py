"""Bad models give clear errors.

Each test asserts the exception class from :mod:`acausal.errors`, that the
message names the component and the variable or equation concerned, and
that there is a hint.  The classification (over-determined, singular, ...)
is derived by counting equations and unknowns by hand.
"""

from __future__ import annotations

import pytest
import sympy as sp

from acausal import Component, Eq, Model, Variable, simulate, time
from acausal.errors import (
    AcausalError,
    ConnectorError,
    EquationError,
    InitializationError,
    ModelDefinitionError,
    ModifierError,
    OverDeterminedError,
    ParameterError,
    StartValueWarning,
    StructurallySingularError,
    UnderDeterminedError,
)
from acausal.compiler.translate import translate
from acausal.runtime.initialization import start_system
from acausal.library.blocks import Constant
from acausal.library.rotational import Fixed, Inertia, Torque
from acausal.library.thermal import HeatCapacitor


def compile_model(model):
    """Translate and compile the continuous system (no simulation)."""
    translation = translate(model)
    return start_system(translation)


def assert_hint(exc: AcausalError, *words: str) -> None:
    """The error carries a hint (attribute and in the text), mentioning ``words``."""
    assert exc.hint, f"no hint in: {exc}"
    assert "hint:" in str(exc)
    for word in words:
        assert word in exc.hint, f"{word!r} not in hint {exc.hint!r}"


# --------------------------------------------------------------------------
# structural errors


def test_fixed_on_both_flanges_is_structurally_singular():
    """Fixed on both flanges of one Inertia: 11 equations for 11 unknowns, but phi is set twice and the two Fixed torques by nothing.

    Modelica's connection rules keep the count balanced (each Fixed brings
    flange.phi = phi0 and its free flange.tau), so the fault is singularity,
    not a surplus: the message names both Fixed equations and both reaction
    torques.
    """

    class TwoFixed(Model):
        def build(self):
            self.inertia = Inertia(J=1)
            self.f1 = Fixed()
            self.f2 = Fixed()
            self.connect(self.f1.flange, self.inertia.flange_a)
            self.connect(self.f2.flange, self.inertia.flange_b)

    with pytest.raises(StructurallySingularError) as info:
        compile_model(TwoFixed())
    message = str(info.value)
    assert "TwoFixed" in message
    assert "11 equations and 11 variables" in message
    assert "f1 (Fixed eq. 1)" in message and "f2 (Fixed eq. 1)" in message
    assert "f2.flange" in message and "inertia.flange_b" in message
    assert "f1.flange.tau" in message and "f2.flange.tau" in message
    assert_hint(info.value)


def test_extra_equation_is_over_determined_and_named():
    """An Inertia subclass adding a = sin(time) has one equation too many: OverDeterminedError naming it."""

    class DrivenInertia(Inertia):
        def equations(self):
            return [Eq(self.a, sp.sin(time))]

    class Over(Model):
        def build(self):
            self.body = DrivenInertia(J=1, phi=dict(start=0, fixed=True), w=dict(start=0, fixed=True))

    with pytest.raises(OverDeterminedError) as info:
        compile_model(Over())
    message = str(info.value)
    assert "1 more than their variables need" in message
    assert "body (DrivenInertia eq. 1): body.a = sin(time)" in message
    assert "body (Inertia eq. 5)" in message  # the other equation that determines body.a
    assert_hint(info.value)


def test_extra_alias_equation_is_named_in_over_determined_error():
    """An Inertia subclass adding w = 0 is over-determined; the message names that equation though alias elimination absorbs it."""

    class StoppedInertia(Inertia):
        def equations(self):
            return [Eq(self.w, 0)]

    class Over(Model):
        def build(self):
            self.body = StoppedInertia(J=1, phi=dict(start=0, fixed=True))
            self.source = Constant(k=1)
            self.torque = Torque()
            self.connect(self.source.y, self.torque.tau)
            self.connect(self.torque.flange, self.body.flange_a)

    with pytest.raises(OverDeterminedError) as info:
        compile_model(Over())
    assert "body (StoppedInertia eq. 1): body.w = 0" in str(info.value)
    assert_hint(info.value)


def test_contradicting_constant_equations_are_both_named():
    """x = 1 and x = 2 in one component: over-determined, and both equations should be named."""

    class Twice(Component):
        x = Variable()

        def equations(self):
            return [Eq(self.x, 1), Eq(self.x, 2)]

    class Over(Model):
        def build(self):
            self.part = Twice()

    with pytest.raises(OverDeterminedError) as info:
        compile_model(Over())
    message = str(info.value)
    assert "part (Twice eq. 1): part.x = 1" in message and "part (Twice eq. 2): part.x = 2" in message
    assert "1 more than their variables need" in message
    assert_hint(info.value)


def test_variable_without_equation_is_under_determined():
    """An Inertia subclass declaring an extra Variable nothing determines: UnderDeterminedError naming it."""

    class LooseInertia(Inertia):
        slack = Variable()

    class Under(Model):
        def build(self):
            self.body = LooseInertia(J=1, phi=dict(start=0, fixed=True), w=dict(start=0, fixed=True))

    with pytest.raises(UnderDeterminedError) as info:
        compile_model(Under())
    message = str(info.value)
    assert "body.slack" in message
    assert "Under" in message
    assert_hint(info.value)


def test_two_equations_in_one_variable_are_structurally_singular():
    """x**2 + t = 1 and x*t = 3 constrain only x while y is in no equation: equal count, no pairing."""

    class Lopsided(Component):
        x = Variable()
        y = Variable()

        def equations(self):
            return [Eq(self.x**2 + time, 1), Eq(self.x * time, 3)]

    class Singular(Model):
        def build(self):
            self.part = Lopsided()

    with pytest.raises(StructurallySingularError) as info:
        compile_model(Singular())
    message = str(info.value)
    assert "part (Lopsided eq. 1)" in message and "part (Lopsided eq. 2)" in message
    assert "part.y" in message
    assert_hint(info.value)


# --------------------------------------------------------------------------
# initialization


def test_unfixed_states_take_start_values_with_a_warning_naming_them():
    """A torque-driven Inertia with no fixed start: phi and w take their start values, and a
    StartValueWarning names them (Modelica tools do the same; it used to be an error)."""

    class Missing(Model):
        def build(self):
            self.body = Inertia(J=1)
            self.source = Constant(k=1)
            self.torque = Torque()
            self.connect(self.source.y, self.torque.tau)
            self.connect(self.torque.flange, self.body.flange_a)

    with pytest.warns(StartValueWarning) as record:
        result = simulate(Missing())
    message = str(record[0].message)
    assert "body.phi" in message and "body.w" in message
    assert "Missing" in message
    assert "fixed=True" in message  # what to do to choose them
    assert result["body.w"][0] == 0.0


def test_rigidly_connected_inertias_with_different_fixed_angles_conflict():
    """i1.phi fixed at 0 and i2.phi fixed at 1, but i2.phi = i1.phi through the connection."""

    class Conflict(Model):
        def build(self):
            self.i1 = Inertia(J=1, phi=dict(start=0, fixed=True), w=dict(start=0, fixed=True))
            self.i2 = Inertia(J=1, phi=dict(start=1, fixed=True))
            self.connect(self.i1.flange_b, self.i2.flange_a)

    with pytest.raises(InitializationError) as info:
        simulate(Conflict())
    message = str(info.value)
    assert "i1.phi" in message and "i2.phi" in message
    assert "conflicting" in message
    assert_hint(info.value, "fixed=True")


def test_fixed_start_against_a_fixed_housing_conflicts():
    """Inertia phi fixed at 1 but connected to Fixed(phi0=0.5): names the inertia angle and the Fixed's phi0."""

    class Conflict(Model):
        def build(self):
            self.body = Inertia(J=1, phi=dict(start=1, fixed=True))
            self.housing = Fixed(phi0=0.5)
            self.connect(self.housing.flange, self.body.flange_a)

    with pytest.raises(InitializationError) as info:
        simulate(Conflict())
    message = str(info.value)
    assert "body.phi" in message and "housing.phi0" in message
    assert "0.5" in message
    assert_hint(info.value, "body.phi")


# --------------------------------------------------------------------------
# model definition errors


def test_python_bool_instead_of_equation():
    """`self.x == 1` is a Python bool: EquationError naming component, class and equation number, hinting at Eq."""

    class Careless(Component):
        x = Variable()

        def equations(self):
            return [Eq(self.x, 2), self.x == 1]

    class Model1(Model):
        def build(self):
            self.part = Careless()

    with pytest.raises(EquationError) as info:
        compile_model(Model1())
    message = str(info.value)
    assert "equation 2" in message and "Careless" in message and "part" in message
    assert "bool" in message or "False" in message
    assert_hint(info.value, "Eq(")


def test_connecting_flange_to_heat_port():
    """A rotational Flange and a HeatPort are different connector families: ConnectorError."""

    class Mixed(Model):
        def build(self):
            self.body = Inertia(J=1)
            self.mass = HeatCapacitor(C=1)
            self.connect(self.body.flange_a, self.mass.port)

    with pytest.raises(ConnectorError) as info:
        compile_model(Mixed())
    message = str(info.value)
    assert "body.flange_a" in message and "mass.port" in message
    assert "rotational" in message and "thermal" in message
    assert_hint(info.value)


def test_connecting_a_disabled_conditional_connector():
    """Torque(useSupport=False).support does not exist: connecting it is a ConnectorError hinting at useSupport."""

    class Disabled(Model):
        def build(self):
            self.torque = Torque(useSupport=False)
            self.fixed = Fixed()
            self.source = Constant(k=1)
            self.body = Inertia(J=1)
            self.connect(self.source.y, self.torque.tau)
            self.connect(self.torque.flange, self.body.flange_a)
            self.connect(self.torque.support, self.fixed.flange)

    with pytest.raises(ConnectorError) as info:
        compile_model(Disabled())
    message = str(info.value)
    assert "torque.support" in message and "disabled" in message
    assert_hint(info.value, "useSupport")


def test_reading_a_variable_of_a_disabled_connector():
    """torque.support.phi on a Torque without support raises ConnectorError at once, naming the connector."""

    class Disabled(Model):
        def build(self):
            self.torque = Torque(useSupport=False)

    model = Disabled()
    model.ensure_built()
    with pytest.raises(ConnectorError) as info:
        model.torque.support.phi
    assert "torque.support" in str(info.value)
    assert_hint(info.value, "useSupport")


def test_unknown_modifier_suggests_the_close_name():
    """Inertia(JJ=1) has no JJ: ModifierError naming Inertia and JJ and suggesting J."""
    with pytest.raises(ModifierError) as info:
        Inertia(JJ=1)
    message = str(info.value)
    assert "Inertia" in message and "'JJ'" in message
    assert_hint(info.value)
    assert "did you mean J?" in info.value.hint


def test_unconnected_real_input():
    """A Torque whose tau input nothing drives: ConnectorError naming the input torque.tau."""

    class Unconnected(Model):
        def build(self):
            self.torque = Torque()
            self.body = Inertia(J=1, phi=dict(start=0, fixed=True), w=dict(start=0, fixed=True))
            self.connect(self.torque.flange, self.body.flange_a)

    with pytest.raises(ConnectorError) as info:
        compile_model(Unconnected())
    message = str(info.value)
    assert "torque.tau" in message and "not connected" in message and "Torque" in message
    assert_hint(info.value, "torque.tau")


def test_parameter_below_its_minimum():
    """Inertia(J=-1) violates min=0: ParameterError naming body.J and the bound."""

    class Negative(Model):
        def build(self):
            self.body = Inertia(J=-1)

    with pytest.raises(ParameterError) as info:
        translate(Negative())
    message = str(info.value)
    assert "body.J" in message and "-1" in message and "minimum 0" in message
    assert_hint(info.value, "J")


def test_errors_are_value_errors():
    """Model errors subclass ValueError so `except ValueError` keeps working (errors.py contract)."""
    for cls in (OverDeterminedError, UnderDeterminedError, StructurallySingularError, InitializationError,
                EquationError, ConnectorError, ModifierError, ParameterError):
        assert issubclass(cls, ValueError) and issubclass(cls, AcausalError)


# -- hints: the engine speaks no domain; components add their own ------------------


class _GearLoop(Model):
    """Two ideal gears closing a loop with ratio product 1: a redundant rigid constraint."""

    def build(self):
        from acausal.library.rotational import IdealGear

        self.torque = Torque()
        self.source = Constant(k=1.0)
        self.j1 = Inertia(J=1, phi=dict(start=0, fixed=True), w=dict(start=0, fixed=True))
        self.j2 = Inertia(J=1)
        self.g1 = IdealGear(ratio=2)
        self.g2 = IdealGear(ratio=0.5)
        self.connect(self.source.y, self.torque.tau)
        self.connect(self.torque.flange, self.j1.flange_a)
        self.connect(self.j1.flange_b, self.g1.flange_a)
        self.connect(self.g1.flange_b, self.j2.flange_a)
        self.connect(self.j2.flange_b, self.g2.flange_a)
        self.connect(self.g2.flange_b, self.j1.flange_a)


def test_a_singular_loop_of_ideal_gears_gets_a_hint_without_friction():
    # the loop is singular for these ratios: found while solving for the initial values
    with pytest.raises(InitializationError) as info:
        simulate(_GearLoop())
    error = info.value
    assert "singular" in error.message and "g1" in error.message
    assert error.hint and "friction" not in error.hint.lower() and "loop" in error.hint


def test_component_hints_are_inherited_and_checked():
    from acausal.language import component_hints

    class Base(Component):
        hints = {"mode": "base says"}

    class Child(Base):
        hints = {"chattering": "child says"}

    assert component_hints(Child) == {"mode": "base says", "chattering": "child says"}

    class Typo(Component):
        hints = {"modes": "x"}

    with pytest.raises(ModelDefinitionError, match="unknown situation 'modes'"):
        component_hints(Typo)


def test_a_component_hint_reaches_a_structural_error_of_a_later_mode():
    # two bearings locking one shaft: the second discrete state (both stuck) is refused
    # when asked to; the hint comes from the friction elements, not from the engine
    from acausal.library.rotational import BearingFriction

    class TwoBearings(Model):
        def build(self):
            self.source = Constant(k=0.5)
            self.torque = Torque()
            self.j = Inertia(J=1, phi=dict(start=0, fixed=True), w=dict(start=1, fixed=True))
            self.b1 = BearingFriction(tau_pos=[[0, 1]])
            self.b2 = BearingFriction(tau_pos=[[0, 1]])
            self.connect(self.source.y, self.torque.tau)
            self.connect(self.torque.flange, self.j.flange_a)
            self.connect(self.j.flange_b, self.b1.flange_a)
            self.connect(self.j.flange_b, self.b2.flange_a)

    result = simulate(TwoBearings(), stop_time=3.0, redundant_constraints="error")
    assert result.status == -1
    assert "holding torque" in result.error.hint
    assert {"b1", "b2"} & set(result.error.components)


def test_a_zero_parameter_that_removes_a_term_is_named_in_the_hint():
    # J = 0 with a friction element: the inertia's balance loses J*a, and nothing
    # determines the acceleration; the hint names the parameter
    from acausal.library.rotational import BearingFriction, ConstantTorque

    class ZeroInertia(Model):
        J = 0.0

        def build(self):
            self.src = ConstantTorque(tau_constant=0.5)
            self.j = Inertia(J=self.J, phi=dict(start=0, fixed=True), w=dict(start=1, fixed=True))
            self.b = BearingFriction(tau_pos=[[0, 1]])
            self.connect(self.src.flange, self.j.flange_a)
            self.connect(self.j.flange_b, self.b.flange_a)

    with pytest.raises(StructurallySingularError) as info:
        simulate(ZeroInertia())
    assert "j.J = 0" in info.value.hint
    assert "b.K_locked" not in info.value.hint  # zero, but it multiplies nothing undetermined
    # the same model with J > 0 runs
    class SmallInertia(ZeroInertia):
        J = 0.1

    assert simulate(SmallInertia(), stop_time=0.5).status == 0


def test_the_earlier_name_of_the_connector_error_still_catches_it():
    """``ConnectionError_`` (the name before issue 24) is the same class: old ``except`` clauses work."""
    from acausal.errors import ConnectionError_

    class Mixed(Model):
        def build(self):
            self.body = Inertia(J=1)
            self.mass = HeatCapacitor(C=1)
            self.connect(self.body.flange_a, self.mass.port)

    with pytest.raises(ConnectionError_) as info:
        compile_model(Mixed())
    assert type(info.value) is ConnectorError and isinstance(info.value, ValueError)
