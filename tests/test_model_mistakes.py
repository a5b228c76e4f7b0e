"""Mistakes in a model's input give a clear error that names the place, before any simulation.

Each test writes one mistake a user makes (a nan parameter, a component name
bound twice, a component created but not stored, a connector connected to
itself, ``math.sin`` on a symbol) and asserts the error class of
:mod:`acausal.errors`, that the message names the component path and the
parameter, connector or equation concerned, and that there is a hint.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from acausal import Component, Eq, Integer, Model, Parameter, Variable, der, simulate
from acausal.compiler.flatten import flatten
from acausal.errors import (
    AcausalError,
    ConnectorError,
    EquationError,
    ModelDefinitionError,
    ParameterError,
)
from acausal.library.blocks import Constant
from acausal.library.rotational import BearingFriction, ConstantTorque, Damper, Fixed, Flange_a, Inertia

NAN, INF = float("nan"), float("inf")
THIS_FILE = Path(__file__).name


def assert_hint(exc: AcausalError, *words: str) -> None:
    assert exc.hint, f"no hint in: {exc}"
    assert "hint:" in str(exc)
    for word in words:
        assert word in exc.hint, f"{word!r} not in hint {exc.hint!r}"


def single(**modifiers):
    """A model holding one Inertia ``j`` with ``modifiers``."""

    class Single(Model):
        def build(self):
            self.j = Inertia(**modifiers)

    return Single()


# --------------------------------------------------------------------------
# 1. non-finite parameter values and start values


@pytest.mark.parametrize("value", [NAN, INF, -INF, np.float64("nan")])
def test_non_finite_parameter_is_rejected_before_simulation(value):
    """Inertia(J=nan) used to simulate to status 0 with nan columns."""
    with pytest.raises(ParameterError) as info:
        simulate(single(J=value, w=dict(start=1, fixed=True), phi=dict(start=0, fixed=True)))
    message = str(info.value)
    assert "parameter j.J" in message and str(float(value)) in message and "finite" in message
    assert info.value.components == ("j",)
    assert_hint(info.value, "Inertia.J", "finite=False")


def test_nan_bound_with_a_minimum_is_rejected():
    """BearingFriction(peak=nan) passed `peak < 1` and never broke away."""

    class Bearing(Model):
        def build(self):
            self.bearing = BearingFriction(peak=NAN)
            self.j = Inertia(J=1)
            self.t = ConstantTorque(tau_constant=0.5)
            self.connect(self.j.flange_a, self.bearing.flange_b)
            self.connect(self.t.flange, self.j.flange_b)

    with pytest.raises(ParameterError) as info:
        flatten(Bearing())
    assert "parameter bearing.peak = nan" in str(info.value)
    assert_hint(info.value, "BearingFriction.peak")


def test_binding_that_evaluates_to_inf_names_the_binding():
    """J=2*self.Jm with Jm = inf (allowed there by finite=False): J itself is not allowed inf."""

    class Bound(Model):
        Jm = Parameter(INF, finite=False)

        def build(self):
            self.j = Inertia(J=2 * self.Jm)

    with pytest.raises(ParameterError) as info:
        flatten(Bound())
    message = str(info.value)
    assert "parameter j.J = 2*Jm evaluates to inf" in message
    assert_hint(info.value, "Inertia.J")


def test_model_parameter_that_is_inf_is_rejected():
    class Bound(Model):
        Jm = Parameter(INF)

        def build(self):
            self.j = Inertia(J=2 * self.Jm)

    with pytest.raises(ParameterError, match=r"parameter Jm = inf is not a finite number"):
        flatten(Bound())


class Unbounded(Component):
    """A component whose parameter may legitimately be infinite."""

    limit = Parameter(INF, finite=False)
    low = Parameter(1.0, min=0, finite=False)
    x = Variable()

    def equations(self):
        return [Eq(der(self.x), -self.x * self.low)]


def test_finite_false_allows_inf_and_shows_in_repr_and_help():
    class Holder(Model):
        def build(self):
            self.u = Unbounded()

    flat = flatten(Holder())
    assert flat.parameter_values["u.limit"] == INF
    assert repr(Unbounded.limit) == "Parameter(inf, finite=False)"
    assert "limit : default inf, finite=False" in Unbounded.__doc__
    assert "finite" not in repr(Inertia.J)  # not shown when it has its default


def test_nan_is_out_of_range_of_a_min_even_when_non_finite_values_are_allowed():
    """`nan < 0` is False; the min/max check must still reject nan."""

    class Holder(Model):
        def build(self):
            self.u = Unbounded(low=NAN)

    with pytest.raises(ParameterError) as info:
        flatten(Holder())
    assert "parameter u.low = nan" in str(info.value) and "minimum 0" in str(info.value)
    assert_hint(info.value, "Unbounded.low", ">= 0")


class Tabled(Component):
    """A component with a structural table parameter it does not check itself."""

    table = Parameter([[0.0, 1.0], [1.0, 2.0]], structural=True)
    x = Variable()

    def equations(self):
        return [Eq(der(self.x), -self.x)]


@pytest.mark.parametrize("table, where", [([[0.0, 1.0], [1.0, NAN]], "table[1][1]"),
                                          (np.array([[0.0, INF]]), "table[0][1]"),
                                          ((0.0, -INF), "table[1]")])
def test_non_finite_table_entry_is_rejected(table, where):
    class Holder(Model):
        def build(self):
            self.t = Tabled(table=table)

    with pytest.raises(ParameterError) as info:
        flatten(Holder())
    assert "parameter t.table has the non-finite entry" in str(info.value)
    assert where in str(info.value)
    assert_hint(info.value, "Tabled.table", "finite entries")


def test_finite_table_and_non_numeric_structural_values_pass():
    class Holder(Model):
        def build(self):
            self.t = Tabled(table=[[0, 1], [2, 3]])

    assert flatten(Holder()).structural_parameters["t.table"] == [[0, 1], [2, 3]]


@pytest.mark.parametrize("attribute", ["start", "nominal"])
@pytest.mark.parametrize("value", [NAN, INF])
def test_non_finite_start_or_nominal_is_rejected(attribute, value):
    with pytest.raises(ParameterError) as info:
        flatten(single(J=1, w={attribute: value, "fixed": True}))
    assert f"{attribute} value of j.w is {value}" in str(info.value)
    assert info.value.components == ("j",)
    assert_hint(info.value, f"Inertia(w=dict({attribute}=")


def test_start_given_by_a_parameter_expression_that_is_inf():
    class Model_(Model):
        big = Parameter(1e308)

        def build(self):
            self.j = Inertia(J=1, w=dict(start=10 * self.big))

    with pytest.raises(ParameterError) as info:
        flatten(Model_())
    assert "start value of j.w is inf (10*big)" in str(info.value)


def test_non_finite_start_of_an_integer_is_an_acausal_error():
    """int(nan) used to raise a bare ValueError."""

    class Counter(Component):
        n = Integer()

        def equations(self):
            return [Eq(self.n, 0)]

    class Holder(Model):
        def build(self):
            self.c = Counter(n=dict(start=NAN))

    with pytest.raises(ParameterError, match=r"start value of c.n is nan"):
        flatten(Holder())


# --------------------------------------------------------------------------
# 2. a component name bound twice


def test_component_name_bound_twice_raises_at_the_second_assignment():
    """The second Damper used to replace the first: "nothing fixes d.phi_rel" much later."""
    lines = []

    class Twice(Model):
        def build(self):
            self.j = Inertia(J=1, w=dict(start=0, fixed=True), phi=dict(start=0, fixed=True))
            self.f = Fixed()
            self.d = Damper()
            self.connect(self.j.flange_b, self.d.flange_a)
            self.connect(self.d.flange_b, self.f.flange)
            self.d = Damper()
            lines.append("reached")

    with pytest.raises(ModelDefinitionError) as info:
        flatten(Twice())
    assert lines == []
    message = str(info.value)
    assert "Twice.d" in message and "Damper" in message and "already" in message
    assert info.value.components == ("d",)
    assert_hint(info.value, "another name")
    assert info.traceback[-1].name == "__setattr__"
    assert any(entry.name == "build" and THIS_FILE in str(entry.path) for entry in info.traceback)


def test_rebinding_non_component_attributes_stays_allowed():
    class Fine(Model):
        def build(self):
            self.n = 1
            self.n = 2
            self.j = Inertia(J=self.n)

    assert flatten(Fine()).parameter_values["j.J"] == 2.0


# --------------------------------------------------------------------------
# 3. a component created but not stored on the model


def test_connecting_a_component_that_is_not_stored_names_it():
    class Orphan(Model):
        def build(self):
            self.j = Inertia(J=1)
            damper = Damper()
            self.connect(self.j.flange_b, damper.flange_a)

    with pytest.raises(ConnectorError) as info:
        flatten(Orphan())
    message = str(info.value)
    assert "connect(j.flange_b, <Damper>.flange_a) in the model" in message
    assert "Damper is not part of the model" in message
    assert_hint(info.value, "self.damper = Damper(")


def test_connecting_into_a_sub_component_of_an_unstored_model_names_the_unstored_one():
    class Drive(Model):
        def build(self):
            self.inertia = Inertia(J=1)

    class Outer(Model):
        def build(self):
            self.j = Inertia(J=1)
            drive = Drive()
            drive.ensure_built()
            self.connect(drive.inertia.flange_a, self.j.flange_b)

    with pytest.raises(ConnectorError) as info:
        flatten(Outer())
    assert "connect(<Drive>.inertia.flange_a, j.flange_b)" in str(info.value)
    assert_hint(info.value, "self.drive = Drive(")


def test_unstored_component_with_the_name_of_a_model_connector_is_not_taken_for_it():
    """An unstored component's connector has the bare path `flange_a`: it must not join the model's own."""

    class Shell(Model):
        flange_a = Flange_a()

        def build(self):
            stray = Inertia(J=1)
            self.connect(self.flange_a, stray.flange_a)

    with pytest.raises(ConnectorError, match=r"Inertia is not part of the model"):
        flatten(Shell())


# --------------------------------------------------------------------------
# 4. connect(a, a)


def test_connector_connected_to_itself():
    class Loop(Model):
        def build(self):
            self.j = Inertia(J=1)
            self.connect(self.j.flange_b, self.j.flange_b)

    with pytest.raises(ConnectorError) as info:
        flatten(Loop())
    assert "connect(j.flange_b, j.flange_b) in the model: connects j.flange_b to itself" in str(info.value)
    assert_hint(info.value, "two different")


def test_signal_connected_to_itself():
    """Used to say "two outputs cannot be connected"."""

    class Loop(Model):
        def build(self):
            self.c = Constant()
            self.connect(self.c.y, self.c.y)

    with pytest.raises(ConnectorError, match=r"connects c.y to itself"):
        flatten(Loop())


# --------------------------------------------------------------------------
# 5. math/numpy functions on symbols


class MathSine(Component):
    x = Variable()

    def equations(self):
        return [Eq(der(self.x), math.sin(self.x))]  # the mistake


class NumpyExp(Component):
    x = Variable()

    def equations(self):
        return [Eq(der(self.x), -self.x)]

    def initial_equations(self):
        return [Eq(self.x, np.exp(self.x))]  # the mistake


class PythonIf(Component):
    x = Variable()

    def equations(self):
        return [Eq(der(self.x), 1 if self.x > 0 else -1)]  # the mistake


def _line_of(klass: type, text: str) -> int:
    import inspect

    source, first = inspect.getsourcelines(klass)
    return first + next(i for i, line in enumerate(source) if text in line)


def _holder(klass):
    class Holder(Model):
        def build(self):
            self.inner = Holder2()

    class Holder2(Component):
        def build(self):
            self.c = klass()

    return Holder()


def test_math_function_on_a_symbol_names_the_component_and_the_line():
    with pytest.raises(EquationError) as info:
        flatten(_holder(MathSine))
    message = str(info.value)
    assert "equations() of inner.c (MathSine) raised TypeError" in message
    assert "Cannot convert expression to float" in message
    assert f"{THIS_FILE}:{_line_of(MathSine, 'math.sin(')}" in message
    assert info.value.components == ("inner.c",)
    assert_hint(info.value, "sympy.sin", "math/numpy")
    assert isinstance(info.value.__cause__, TypeError)


def test_numpy_function_in_initial_equations():
    with pytest.raises(EquationError) as info:
        flatten(_holder(NumpyExp))
    message = str(info.value)
    assert "initial_equations() of inner.c (NumpyExp) raised TypeError" in message
    assert f"{THIS_FILE}:{_line_of(NumpyExp, 'np.exp(')}" in message
    assert_hint(info.value, "sympy functions")


def test_python_if_on_a_symbol_suggests_if():
    with pytest.raises(EquationError) as info:
        flatten(_holder(PythonIf))
    assert "truth value" in str(info.value)
    assert_hint(info.value, "If(condition")


def test_inherited_equations_name_the_declaring_class():
    class Derived(MathSine):
        pass

    class Holder(Model):
        def build(self):
            self.d = Derived()

    with pytest.raises(EquationError, match=r"equations\(\) of d \(Derived, in MathSine\)"):
        flatten(Holder())


def test_acausal_errors_from_equations_pass_unchanged():
    class Checks(Component):
        def equations(self):
            raise ParameterError("checked by the component", hint="its own hint")

    class Holder(Model):
        def build(self):
            self.c = Checks()

    with pytest.raises(ParameterError) as info:
        flatten(Holder())
    assert type(info.value) is ParameterError
    assert info.value.message == "checked by the component" and info.value.hint == "its own hint"
