"""Equation templates give the same flat and partitioned model as calling every ``equations()``.

Flattening builds the equations of a repeated component from the first
instance's, renamed (:class:`acausal.compiler.flatten._Template`), and
partition reuses the work done for one instance's relations
(:class:`acausal.compiler.partition._RelationTemplate`).  Both are
optimisations only: every test here flattens and partitions a model both ways
and requires the results to be identical equation by equation -- the same
residuals (compared with ``srepr``: same tree, same argument order, same
number types), in the same order, with the same origins and the same text of
the equation as written -- and the same variables, parameters, relations
(numbered alike), selectors and discrete equations.
"""

from __future__ import annotations

import importlib
import inspect

import pytest
import sympy as sp

from acausal import Component, EngineOptions, Eq, Experiment, If, Model, Parameter, Variable, der, time
from acausal.compiler import flatten as flatten_module
from acausal.compiler.flatten import _Flattener, _Source
from acausal.compiler.partition import partition
from acausal.compiler.translate import translate
from acausal.errors import EquationError
from acausal.library.blocks import Sine
from acausal.library.rotational import (BearingFriction, Clutch, Fixed, IdealGear, Inertia, Spring,
                                        SpringDamper, Torque)

EXAMPLES = ("first", "two_masses", "friction", "coupled_clutches", "friction_elements", "flywheel",
            "bearing_heating", "benchmarks")


def example_models() -> list:
    models = []
    for name in EXAMPLES:
        module = importlib.import_module(f"examples.{name}")
        models += [pytest.param(cls, id=f"{name}.{cls.__name__}") for cls in vars(module).values()
                   if inspect.isclass(cls) and issubclass(cls, Model) and cls is not Model
                   and cls.__module__ == module.__name__]
    return models


def equation_key(eq) -> tuple:
    """Everything a flat or discrete equation holds, in comparable form."""
    o = eq.origin
    main = ("residual", sp.srepr(eq.residual)) if hasattr(eq, "residual") else \
        ("discrete", eq.variable, sp.srepr(eq.rhs))
    return main + (o.component, o.component_class, o.declared_in, o.index, o.text, str(o))


def assert_same_equations(a, b, what: str) -> None:
    assert len(a) == len(b), f"{what}: {len(a)} equations with templates, {len(b)} without"
    for i, (x, y) in enumerate(zip(a, b)):
        assert equation_key(x) == equation_key(y), f"{what}[{i}] differs"


def flatten_both_ways(make):
    """``(with templates, without, the flattener that used them)`` for two fresh instances of a model."""
    flattener = _Flattener(make(), templates=True)
    with_templates = flattener.run()
    without = _Flattener(make(), templates=False).run()
    return with_templates, without, flattener


def assert_same_models(make) -> tuple:
    """Flatten and partition ``make()`` both ways and compare everything; returns the flat
    model made with templates and how many of its equations came from a template."""
    a, b, _ = flatten_both_ways(make)
    for name in ("equations", "initial_equations", "discrete_equations"):
        assert_same_equations(getattr(a, name), getattr(b, name), name)
    assert a.variables == b.variables
    assert a.parameters == b.parameters
    assert repr(a.structural_parameters) == repr(b.structural_parameters)
    assert a.hints == b.hints
    assert (a.name, a.modelica_class, a.experiment) == (b.name, b.modelica_class, b.experiment)

    pa, pb = partition(a, templates=True), partition(b, templates=False)
    for name in ("equations", "initial_equations", "discrete_equations"):
        assert_same_equations(getattr(pa, name), getattr(pb, name), f"partitioned {name}")
    assert pa.relations == pb.relations
    assert [sp.srepr((r.lhs, r.rhs)) for r in pa.relations] == [sp.srepr((r.lhs, r.rhs)) for r in pb.relations]
    assert pa.selectors == pb.selectors
    assert pa.discrete_variables == pb.discrete_variables
    assert pa.evaluated_parameters == pb.evaluated_parameters
    # partitioning the flat model made without templates with templates on changes nothing either
    pc = partition(b, templates=True)
    assert [equation_key(e) for e in pc.equations] == [equation_key(e) for e in pb.equations]
    assert pc.relations == pb.relations
    templated = sum(isinstance(e.origin.source, _Source)
                    for e in a.equations + a.discrete_equations + a.initial_equations)
    return a, templated


@pytest.mark.parametrize("model_class", example_models())
def test_examples_flatten_alike_with_and_without_templates(model_class):
    assert_same_models(model_class)


@pytest.mark.parametrize("n, heat_ports", [(3, False), (25, False), (12, True)])
def test_drive_train_flattens_alike_and_uses_templates(n, heat_ports):
    """The scaling model: 25 units number their relations past $rel9 and $rel99, which sort
    differently from the names before them (new variants of the relation templates)."""
    from examples.benchmarks import drive_train_model

    flat, templated = assert_same_models(lambda: drive_train_model(n, heat_ports=heat_ports))
    if n > 2:
        # every unit but the first two (template, check) comes from a template
        own = [e for e in flat.equations + flat.discrete_equations
               if e.origin.declared_in not in ("connect", "unconnected", "binding")]
        per_unit = sum(e.origin.component in ("inertia3", "bearing3") for e in own)
        assert templated >= (n - 2) * per_unit


def test_templates_are_switched_by_the_engine_options():
    from examples.benchmarks import drive_train_model

    flat = flatten_module.flatten(drive_train_model(4), templates=False)
    assert not any(isinstance(e.origin.source, _Source) for e in flat.equations)
    flat = flatten_module.flatten(drive_train_model(4))
    assert any(isinstance(e.origin.source, _Source) for e in flat.equations)
    # through translate(): the flat model of EngineOptions(templates=False) has no template
    # equation, and it equals the templated one
    untemplated = translate(drive_train_model(4), cache=False, options=EngineOptions(templates=False))
    assert not any(isinstance(e.origin.source, _Source) for e in untemplated.flat.equations)
    assert [str(e) for e in untemplated.flat.equations] == [str(e) for e in flat.equations]


def test_origin_text_of_a_templated_equation_is_printed_on_demand():
    from examples.benchmarks import drive_train_model

    flat = flatten_module.flatten(drive_train_model(4))
    origin = next(e.origin for e in flat.equations if e.origin.component == "inertia4")
    assert isinstance(origin.source, _Source)
    assert origin.text == "inertia4.phi = inertia4.flange_a.phi"
    assert str(origin) == "inertia4 (Inertia eq. 1): inertia4.phi = inertia4.flange_a.phi"


# --------------------------------------------------------------------------
# the template rule: what must not be shared


class ReadsItsBinding(Component):
    """equations() reads a numeric parameter's value: each instance has its own equations."""

    k = Parameter(1.0)
    x = Variable()

    def equations(self):
        return [Eq(self.x, self.parameter_binding("k") * time)]


class ReadsAnAttribute(Component):
    """equations() reads an attribute set by the constructor."""

    x = Variable()

    def __init__(self, rate=1.0, **modifiers):
        super().__init__(**modifiers)
        self.rate = rate

    def equations(self):
        return [Eq(self.x, self.rate * time)]


class ReadsAStartValue(Component):
    """equations() read a variable attribute."""

    x = Variable(start=1.0)

    def equations(self):
        return [Eq(der(self.x), -self.attribute("x", "start") * self.x)]


class ReadsItsParent(Component):
    """equations() read the model around them: nothing in the key can see that."""

    x = Variable()

    def equations(self):
        return [Eq(self.x, self._parent.gain[self.name] * time)]


class Counter(Component):
    """equations() depend on how often they were called (global state)."""

    calls = [0]
    x = Variable()

    def equations(self):
        self.calls[0] += 1
        return [Eq(self.x, self.calls[0] * time)]


def model_of(build, stop_time: float = 1.0):
    class M(Model):
        experiment = Experiment(stop_time=stop_time)
        gain = {}

        def build(self):
            build(self)

    return M


def test_a_numeric_parameter_read_in_equations_is_not_shared():
    def build(m):
        for i, k in enumerate((1.0, 2.0, 3.0, 3.0)):
            setattr(m, f"c{i}", ReadsItsBinding(k=k))

    flat, templated = assert_same_models(model_of(build))
    assert templated == 0
    assert [str(e.residual) for e in flat.equations][:3] == ["c0.x - 1.0*time", "c1.x - 2.0*time",
                                                             "c2.x - 3.0*time"]


def test_an_attribute_set_by_the_constructor_is_part_of_the_key():
    def build(m):
        for i, rate in enumerate((1.0, 1.0, 1.0, 2.0, 2.0, 2.0)):
            setattr(m, f"c{i}", ReadsAnAttribute(rate=rate))

    flat, templated = assert_same_models(model_of(build))
    assert templated == 2  # c2 and c5: the third of each rate
    assert str(flat.equations[5].residual) == "c5.x - 2.0*time"


def test_a_variable_attribute_read_in_equations_is_not_shared():
    def build(m):
        for i, start in enumerate((1.0, 2.0, 3.0)):
            setattr(m, f"c{i}", ReadsAStartValue(x=dict(start=start)))

    _, templated = assert_same_models(model_of(build))
    assert templated == 0


def test_equations_that_read_the_model_are_not_shared():
    """c1 would agree with c0's template, c2 would not: reading the parent gives no template."""

    def build(m):
        m.gain.update(c0=1.0, c1=1.0, c2=2.0, c3=3.0)
        for i in range(4):
            setattr(m, f"c{i}", ReadsItsParent())

    flat, templated = assert_same_models(model_of(build))
    assert templated == 0
    assert str(flat.equations[3].residual) == "c3.x - 3.0*time"


def test_equations_that_read_the_model_are_not_shared_when_the_second_instance_differs():
    def build(m):
        m.gain.update(c0=1.0, c1=2.0, c2=1.0, c3=1.0)
        for i in range(4):
            setattr(m, f"c{i}", ReadsItsParent())

    _, templated = assert_same_models(model_of(build))
    assert templated == 0


def test_global_state_is_caught_by_the_check():
    def build(m):
        for i in range(4):
            setattr(m, f"c{i}", Counter())

    a, b, flattener = flatten_both_ways(model_of(build))
    assert [flattener.templates[k] for k in flattener.templates if k[0] is Counter] == [None]
    # both ways call equations() of every instance (the counts differ only by the calls made)
    assert not any(isinstance(e.origin.source, _Source) for e in a.equations)


def test_structural_parameters_and_conditional_connectors_select_the_template():
    """useSupport switches a connector and the equations; every combination is its own key."""

    def build(m):
        m.fixed = Fixed()
        m.sine = Sine(amplitude=1.0, f=1.0)
        for i in range(6):
            support = i % 2 == 1
            gear = IdealGear(ratio=1.0 + i, useSupport=support)
            inertia = Inertia(J=1.0 + i, phi=dict(start=0.1 * i, fixed=True), w=dict(start=0, fixed=True))
            torque = Torque(useSupport=support)
            setattr(m, f"gear{i}", gear)
            setattr(m, f"inertia{i}", inertia)
            setattr(m, f"torque{i}", torque)
            m.connect(m.sine.y, torque.tau)
            m.connect(torque.flange, gear.flange_a)
            m.connect(gear.flange_b, inertia.flange_a)
            if support:
                m.connect(gear.support, m.fixed.flange)
                m.connect(torque.support, m.fixed.flange)

    _, templated = assert_same_models(model_of(build))
    assert templated > 0


def test_table_functions_named_after_the_instance_are_not_shared():
    """A friction table with two rows stays a function of the instance's path: no template."""

    def build(m):
        m.torque = Torque()
        m.sine = Sine(amplitude=5.0, f=1.0)
        m.connect(m.sine.y, m.torque.tau)
        previous = m.torque.flange
        for i in range(4):
            inertia = Inertia(J=1.0, w=dict(start=1.0, fixed=True), phi=dict(start=0, fixed=True))
            bearing = BearingFriction(tau_pos=[[0.0, 0.5], [1.0, 0.7]], peak=1.2)
            setattr(m, f"inertia{i}", inertia)
            setattr(m, f"bearing{i}", bearing)
            m.connect(previous, inertia.flange_a)
            m.connect(inertia.flange_b, bearing.flange_a)
            previous = bearing.flange_b

    a, _, flattener = flatten_both_ways(model_of(build))
    assert [v for k, v in flattener.templates.items() if k[0] is BearingFriction] == [None]
    assert_same_models(model_of(build))


def test_names_that_sort_differently_get_their_own_template():
    """``time`` sorts after ``a1.x`` but before ``z1.x``, ``der(`` between them: sums of these
    names are ordered differently, so the instances a*, m* and z* need separate variants."""

    class Lag(Component):
        x = Variable(start=0.0, fixed=True)
        T = Parameter(0.5)

        def equations(self):
            return [Eq(self.T * der(self.x) + self.x, If(time > 0.3, time, 0))]

    def build(m):
        for name in ("a1", "a2", "a3", "m1", "m2", "z1", "z2", "z3", "e1", "u1", "u2"):
            setattr(m, name, Lag())

    _, templated = assert_same_models(model_of(build))
    assert templated > 0


def test_relations_of_parameters_are_decided_with_each_instance_s_values():
    class Switch(Component):
        a = Parameter(1.0)
        x = Variable()

        def equations(self):
            return [Eq(self.x, If(self.a > 0.5, time, -time) + If(self.x > 1, 1, 0))]

    def build(m):
        for i, a in enumerate((1.0, 1.0, 1.0, 0.0, 1.0, 0.0)):
            setattr(m, f"s{i}", Switch(a=a))

    _, templated = assert_same_models(model_of(build))
    assert templated > 0


def test_a_failing_equation_fails_alike(monkeypatch):
    class Bad(Component):
        x = Variable()
        broken = Parameter(False, structural=True)

        def equations(self):
            if self.broken:
                return [Eq(self.x, sp.Symbol("nowhere"))]
            return [Eq(self.x, time)]

    def build(m):
        m.c0 = Bad()
        m.c1 = Bad()
        m.c2 = Bad()
        m.c3 = Bad(broken=True)

    messages = []
    for use in (True, False):
        with pytest.raises(EquationError) as error:
            _Flattener(model_of(build)(), templates=use).run()
        messages.append(str(error.value))
    assert messages[0] == messages[1]


def test_the_same_instance_flattened_twice_gives_the_same_model():
    from examples.coupled_clutches import CoupledClutches

    model = CoupledClutches()
    first = _Flattener(model, templates=True).run()
    second = _Flattener(model, templates=False).run()
    assert [equation_key(e) for e in first.equations] == [equation_key(e) for e in second.equations]


def test_springs_and_clutches_between_many_inertias():
    """A longer chain of several classes (spring, clutch with an input, inertia)."""

    def build(m):
        m.sine = Sine(amplitude=1.0, f=2.0)
        m.torque = Torque()
        m.connect(m.sine.y, m.torque.tau)
        previous = m.torque.flange
        for i in range(8):
            inertia = Inertia(J=1.0, phi=dict(start=0, fixed=True), w=dict(start=1.0 * i, fixed=True))
            setattr(m, f"j{i}", inertia)
            m.connect(previous, inertia.flange_a)
            element = Spring(c=100.0) if i % 3 else SpringDamper(c=100.0, d=1.0)
            setattr(m, f"k{i}", element)
            m.connect(inertia.flange_b, element.flange_a)
            if i % 4 == 1:
                clutch = Clutch(fn_max=10.0)
                setattr(m, f"clutch{i}", clutch)
                m.connect(element.flange_b, clutch.flange_a)
                m.connect(m.sine.y, clutch.f_normalized)
                previous = clutch.flange_b
            else:
                previous = element.flange_b

    _, templated = assert_same_models(model_of(build))
    assert templated > 0


class Scaled(Component):
    """A computed attribute: the nominal value of x is an expression of a parameter."""

    k = Parameter(1.0)
    x = Variable(start=0.0, fixed=True, nominal=lambda c: 2 * c.k)

    def equations(self):
        return [Eq(der(self.x), -self.k * self.x)]


def test_computed_attributes_are_evaluated_with_each_instance_s_values():
    def build(m):
        for i, k in enumerate((1.0, 1.0, 1.0, 3.0, 1.0, 3.0, 0.5)):
            setattr(m, f"s{i}", Scaled(k=k))

    flat, templated = assert_same_models(model_of(build))
    assert templated > 0
    assert [v.nominal for v in flat.variables] == [2.0, 2.0, 2.0, 6.0, 2.0, 6.0, 1.0]

