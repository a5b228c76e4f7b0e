"""Unit tests of the flattening stage (:func:`acausal.compiler.flatten.flatten`).

Every expected value is derived by hand from Modelica's rules as the module
docstring states them: a connection set makes its potentials equal and sums
its flows to zero (a connector seen from outside its component with the
opposite sign), an unconnected flow is zero, a disabled conditional
connector has neither variables nor equations, modifiers set parameters and
variable attributes, and every equation remembers where it came from.
"""

from __future__ import annotations

import pytest
import sympy as sp

from acausal import Component, Eq, Model, Parameter, StateSelect, Variable, der, time
from acausal.compiler.flatten import FlatModel, flatten
from acausal.errors import ConnectorError, EquationError, ModelDefinitionError, ModifierError
from acausal.language import real_symbol
from acausal.library.blocks import Constant
from acausal.library.rotational import Fixed, Flange_a, Inertia, Spring, Torque

S = real_symbol


def connect_equations(flat: FlatModel) -> list:
    return [e for e in flat.equations if e.origin.declared_in == "connect"]


def residuals_of(flat: FlatModel, declared_in: str) -> set:
    return {e.residual for e in flat.equations if e.origin.declared_in == declared_in}


# --------------------------------------------------------------------------
# connection sets


class ThreeOnOneNode(Model):
    """a.flange_b, b.flange_a and c.flange_a joined in one connection set."""

    def build(self):
        self.a = Inertia(J=1.0)
        self.b = Inertia(J=2.0)
        self.c = Spring(c=10.0)
        self.connect(self.a.flange_b, self.b.flange_a)
        self.connect(self.a.flange_b, self.c.flange_a)


def test_connection_set_makes_the_potentials_equal():
    """Three flanges in one set: two independent equations that together say phi_a = phi_b = phi_c."""
    flat = flatten(ThreeOnOneNode())
    members = [S("a.flange_b.phi"), S("b.flange_a.phi"), S("c.flange_a.phi")]
    potential = [e.residual for e in connect_equations(flat) if e.residual.free_symbols <= set(members)]
    assert len(potential) == 2
    solution = sp.solve(potential, members[1:], dict=True)
    assert solution == [{members[1]: members[0], members[2]: members[0]}]


def test_connection_set_sums_the_flows_to_zero():
    """One flow equation: tau_a + tau_b + tau_c = 0 (all three seen from inside their components)."""
    flat = flatten(ThreeOnOneNode())
    taus = {S("a.flange_b.tau"), S("b.flange_a.tau"), S("c.flange_a.tau")}
    flow = [e.residual for e in connect_equations(flat) if e.residual.free_symbols & taus]
    assert len(flow) == 1
    total = sum(taus, sp.Integer(0))
    assert sp.expand(flow[0] - total) == 0 or sp.expand(flow[0] + total) == 0


def test_unconnected_flows_are_zero_and_the_model_is_balanced():
    """The three free flanges get tau = 0; 14 component + 3 connect + 3 unconnected = 20 equations for 20 variables."""
    flat = flatten(ThreeOnOneNode())
    assert residuals_of(flat, "unconnected") == {S("a.flange_a.tau"), S("b.flange_b.tau"), S("c.flange_b.tau")}
    # Inertia: 5 equations, 7 variables (phi, w, a, two flanges of phi and tau);
    # Spring: 3 + 1 equations, 6 variables (phi_rel, tau, two flanges)
    assert len(connect_equations(flat)) == 3
    assert len(flat.equations) == 5 + 5 + 4 + 3 + 3 == 20
    assert sum(not v.is_discrete for v in flat.variables) == 7 + 7 + 6 == 20


class Drive(Component):
    """A component with its own flange, connected inside to an inertia."""

    flange = Flange_a()
    Jd = Parameter(2.0)

    def build(self):
        self.body = Inertia(J=self.Jd * 3, w=dict(start=self.Jd, fixed=True))
        self.connect(self.flange, self.body.flange_a)


class DriveAndLoad(Model):
    def build(self):
        self.drive = Drive(Jd=4.0)
        self.load = Inertia(J=1.0)
        self.connect(self.drive.flange, self.load.flange_b)


def test_a_connector_seen_from_outside_enters_the_flow_sum_negated():
    """Inside Drive, drive.flange is an outside connector: drive.body.flange_a.tau - drive.flange.tau = 0.

    At the top level drive.flange is an inside connector again:
    drive.flange.tau + load.flange_b.tau = 0.
    """
    flat = flatten(DriveAndLoad())
    flows = [e.residual for e in connect_equations(flat) if any(s.name.endswith(".tau")
                                                               for s in e.residual.free_symbols)]
    inner = S("drive.body.flange_a.tau") - S("drive.flange.tau")
    outer = S("drive.flange.tau") + S("load.flange_b.tau")
    assert len(flows) == 2
    for expected in (inner, outer):
        assert any(sp.expand(r - expected) == 0 or sp.expand(r + expected) == 0 for r in flows), expected
    # drive.flange is connected (inside and outside): no 'unconnected' equation for it
    assert residuals_of(flat, "unconnected") == {S("drive.body.flange_b.tau"), S("load.flange_a.tau")}


# --------------------------------------------------------------------------
# conditional connectors


class Driven(Model):
    use_support = False

    def build(self):
        self.source = Constant(k=1.0)
        self.torque = Torque(useSupport=self.use_support)
        self.body = Inertia(J=1.0)
        self.connect(self.source.y, self.torque.tau)
        self.connect(self.torque.flange, self.body.flange_a)
        if self.use_support:
            self.housing = Fixed()
            self.connect(self.torque.support, self.housing.flange)


class DrivenWithSupport(Driven):
    use_support = True


def test_disabled_conditional_connector_leaves_its_variables_and_equations_out():
    """Torque(useSupport=False): no torque.support.* variables, no equation reads them, phi_support = 0 instead."""
    flat = flatten(Driven())
    names = {v.name for v in flat.variables}
    assert not any(n.startswith("torque.support.") for n in names)
    used = set().union(*(e.residual.free_symbols for e in flat.equations))
    assert not any(s.name.startswith("torque.support.") for s in used)
    torque_equations = {e.residual for e in flat.equations if e.origin.component == "torque"}
    assert S("torque.phi_support") in torque_equations  # phi_support = 0: the housing is grounded


def test_enabled_conditional_connector_brings_its_variables_and_equations():
    """Torque(useSupport=True): support.phi = phi_support, support.tau = -flange.tau, support connected to the housing."""
    flat = flatten(DrivenWithSupport())
    names = {v.name for v in flat.variables}
    assert {"torque.support.phi", "torque.support.tau"} <= names
    torque_equations = {e.residual for e in flat.equations if e.origin.component == "torque"}
    assert S("torque.support.phi") - S("torque.phi_support") in torque_equations
    assert S("torque.support.tau") + S("torque.flange.tau") in torque_equations
    assert S("torque.phi_support") not in torque_equations
    # the support is in a connection set with the housing's flange
    assert any({S("torque.support.phi"), S("housing.flange.phi")} == e.residual.free_symbols
               for e in connect_equations(flat))


# --------------------------------------------------------------------------
# modifiers


def test_modifiers_reach_parameters_and_variable_attributes():
    """Drive(Jd=4) binds body.J = 3*Jd = 12 and body.w.start = Jd = 4 (fixed); load keeps its defaults."""
    flat = flatten(DriveAndLoad())
    parameters = flat.parameter_values
    assert parameters["drive.Jd"] == 4.0
    assert parameters["drive.body.J"] == 12.0
    assert parameters["load.J"] == 1.0
    variables = flat.variable_map
    assert variables["drive.body.w"].start == 4.0 and variables["drive.body.w"].fixed
    assert variables["drive.body.phi"].start == 0.0 and not variables["drive.body.phi"].fixed
    assert variables["load.w"].start == 0.0 and not variables["load.w"].fixed


def test_modifiers_set_nominal_and_state_select():
    """Inertia(phi=dict(nominal=-5, state_select=prefer)): nominal |−5| = 5, StateSelect.prefer."""

    class M(Model):
        def build(self):
            self.i = Inertia(J=2.0, phi=dict(start=0.5, fixed=True, nominal=-5.0,
                                             state_select=StateSelect.prefer))

    variable = flatten(M()).variable_map["i.phi"]
    assert (variable.start, variable.fixed, variable.nominal) == (0.5, True, 5.0)
    assert variable.state_select == StateSelect.prefer
    assert flatten(M()).variable_map["i.w"].state_select == StateSelect.default


def test_der_of_an_expression_is_expanded_by_the_chain_rule():
    """der(k*x*y + sin(time)) = k*y*der(x) + k*x*der(y) + cos(time); a parameter has no derivative."""

    class Chain(Model):
        k = Parameter(3.0)
        x = Variable(start=1.0, fixed=True)
        y = Variable(start=2.0, fixed=True)
        z = Variable()

        def equations(self):
            return [Eq(der(self.x), -self.x), Eq(der(self.y), 1),
                    Eq(self.z, der(self.k * self.x * self.y + sp.sin(time)))]

    flat = flatten(Chain())
    k, x, y, z = S("k"), S("x"), S("y"), S("z")
    expected = z - (k * y * S("der(x)") + k * x * S("der(y)") + sp.cos(time))
    assert sp.expand(flat.equations[2].residual - expected) == 0
    assert sp.expand(flat.equations[0].residual - (S("der(x)") + x)) == 0


# --------------------------------------------------------------------------
# origins


def test_every_equation_carries_its_origin():
    """Component path, the class whose equations() wrote it, its position there, and its text."""
    flat = flatten(ThreeOnOneNode())
    groups: dict[tuple, list[int]] = {}
    for e in flat.equations:
        groups.setdefault((e.origin.component, e.origin.declared_in), []).append(e.origin.index)
    # Inertia writes 5 equations; Spring inherits 3 from PartialCompliant and adds 1
    assert groups[("a", "Inertia")] == [0, 1, 2, 3, 4]
    assert groups[("b", "Inertia")] == [0, 1, 2, 3, 4]
    assert groups[("c", "PartialCompliant")] == [0, 1, 2]
    assert groups[("c", "Spring")] == [0]
    assert len(groups[("", "connect")]) == 3
    assert {c for c, d in groups if d == "unconnected"} == {"a", "b", "c"}
    spring = [e for e in flat.equations if e.origin.declared_in == "Spring"][0]
    assert spring.origin.component_class == "Spring"
    assert spring.origin.text == "c.tau = c.c*(c.phi_rel - c.phi_rel0)"
    assert "c" in str(spring.origin) and "Spring eq. 1" in str(spring.origin)
    newton = [e for e in flat.equations if e.origin.component == "b" and e.origin.index == 4][0]
    assert newton.origin.text == "b.J*b.a = b.flange_a.tau + b.flange_b.tau"
    # a connection names the members of its set
    for e in connect_equations(flat):
        assert "a.flange_b" in e.origin.text and "b.flange_a" in e.origin.text and "c.flange_a" in e.origin.text


def test_the_origin_of_a_nested_component_is_its_dotted_path():
    """drive.body's equations come from drive.body (class Inertia); the connection inside drive names both ends."""
    flat = flatten(DriveAndLoad())
    body = [e for e in flat.equations if e.origin.declared_in == "Inertia" and e.origin.component == "drive.body"]
    assert len(body) == 5
    assert all(s.name.startswith("drive.body.") for e in body for s in e.residual.free_symbols
               if s.name not in ("der(drive.body.phi)", "der(drive.body.w)"))
    texts = [e.origin.text for e in connect_equations(flat)]
    assert any("drive.flange" in t and "drive.body.flange_a" in t for t in texts)


# --------------------------------------------------------------------------
# errors


def test_a_bool_from_double_equals_is_an_equation_error_naming_the_component():
    """`self.x == 1` is the Python bool False: EquationError naming the path, the class and the equation number."""

    class Careless(Component):
        x = Variable()

        def equations(self):
            return [Eq(self.x, 2), self.x == 1]

    class Holder(Model):
        def build(self):
            self.part = Careless()

    with pytest.raises(EquationError) as info:
        flatten(Holder())
    message = str(info.value)
    assert "part" in message and "Careless" in message and "equation 2" in message
    assert info.value.hint and "Eq(" in info.value.hint
    assert isinstance(info.value, ModelDefinitionError)


def test_connecting_a_disabled_connector_is_a_connection_error_naming_it():
    """Torque(useSupport=False).support does not exist in the instance: ConnectorError naming torque.support."""

    class Disabled(Driven):
        def build(self):
            super().build()
            self.housing = Fixed()
            self.connect(self.torque.support, self.housing.flange)

    with pytest.raises(ConnectorError) as info:
        flatten(Disabled())
    message = str(info.value)
    assert "torque.support" in message and "disabled" in message
    assert "useSupport" in info.value.hint


def test_an_unknown_modifier_is_a_modifier_error_naming_the_component():
    """Inertia(Jx=1) and Inertia(w=dict(strat=0)): ModifierError naming Inertia and the unknown name."""

    class Typo(Model):
        def build(self):
            self.body = Inertia(Jx=1.0)

    with pytest.raises(ModifierError) as info:
        flatten(Typo())  # build() runs during flattening
    assert "Inertia" in str(info.value) and "'Jx'" in str(info.value)
    with pytest.raises(ModifierError) as info:
        Inertia(w=dict(strat=0.0))
    assert "Inertia.w" in str(info.value) and "'strat'" in str(info.value)
    with pytest.raises(ModifierError) as info:
        Inertia(J=dict(start=1.0))
    assert "Inertia.J" in str(info.value)
