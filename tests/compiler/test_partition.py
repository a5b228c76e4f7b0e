"""Unit tests of the partition stage (:func:`acausal.compiler.partition.partition`).

Expected values follow from the definitions in the module docstring: every
relation on continuous quantities becomes an indicator ``$relK`` watched for
a zero crossing of ``g = lhs - rhs`` (a time event when ``g`` is linear in
time and holds only parameters besides), a relation of parameters alone is
decided at once, the selectors are the discrete symbols the continuous
equations read, and discrete equations come after those they read.
"""

from __future__ import annotations

import pytest
import sympy as sp

from acausal import Boolean, Eq, If, Integer, Model, Parameter, Variable, der, pre, time
from acausal.compiler.flatten import flatten
from acausal.compiler.partition import partition
from acausal.errors import ModelDefinitionError
from acausal.language import real_symbol
from acausal.names import relation_name

S = real_symbol


class Switching(Model):
    """One state x, relations of every kind, and a chain of Booleans declared out of order."""

    t0 = Parameter(0.5)
    x = Variable(start=0.0, fixed=True)
    y = Variable()
    z = Variable()
    u = Variable()
    w = Variable()
    v = Variable()
    c = Boolean()
    b = Boolean()
    a = Boolean()
    unused = Boolean()
    k = Integer()

    def equations(self):
        return [
            Eq(der(self.x), 1),
            # the same relation twice: one indicator
            Eq(self.y, If(self.x > 1, 2, 3) + If(self.x > 1, 10, 0)),
            # time and a parameter only, linear in time: a time event
            Eq(self.z, If(2 * time - 1 > self.t0, 1.0, 0.0)),
            # time only, but not linear in it; time against a state: state events
            Eq(self.u, If(time**2 > 1, 1.0, 0.0) + If(time > self.x, 1.0, 0.0)),
            # parameters only: decided now, no relation
            Eq(self.w, If(self.t0 > 0, 4.0, 5.0) + If(self.b, 1.0, 0.0)),
            Eq(self.v, 2 * self.k + pre(self.k)),
            # discrete equations, each reading the next one declared
            Eq(self.c, self.b),
            Eq(self.b, self.a),
            Eq(self.a, self.x < 2),
            Eq(self.unused, self.x > 5),
            Eq(self.k, If(self.x > 3, 1, 0)),
        ]


@pytest.fixture(scope="module")
def switching():
    return partition(flatten(Switching()))


def relation_by_text(partitioned, text):
    (relation,) = [r for r in partitioned.relations if r.text == text]
    return relation


def test_relations_become_indicator_symbols_with_their_text(switching):
    """x > 1 (used twice), x < 2, x > 5, x > 3, time > x, time**2 > 1, t0 < 2*time - 1: seven indicators $rel0..$rel6."""
    relations = switching.relations
    assert [r.index for r in relations] == list(range(7))
    assert [r.symbol for r in relations] == [sp.Symbol(relation_name(k)) for k in range(7)]
    assert [r.symbol.name for r in relations] == [f"$rel{k}" for k in range(7)]
    texts = {r.text for r in relations}
    assert {"x > 1", "x < 2", "x > 5", "x > 3", "time > x", "time**2 > 1"} <= texts
    for relation in relations:
        if not relation.is_time_event:
            assert relation.text == f"{relation.lhs} {relation.op} {relation.rhs}"
    # a time event is decided at its instant as just after it: t0 < 2*time - 1 (falling g =
    # t0 - 2*time + 1) holds there, so it is kept as <=; its text says what was written
    (timed,) = [r for r in relations if r.text == "t0 < 2*time - 1"]
    assert timed.op == "<=" and timed.holds(0.0)
    # the continuous equation reads the indicator, not the relation
    (y_equation,) = [e for e in switching.equations if S("y") in e.residual.free_symbols]
    indicator = relation_by_text(switching, "x > 1").symbol
    assert y_equation.residual.free_symbols == {S("y"), indicator}
    assert not y_equation.residual.has(sp.StrictGreaterThan)
    # y = (2 if x > 1 else 3) + (10 if x > 1 else 0): 12 when the indicator holds, 3 when not
    assert y_equation.residual.subs(indicator, sp.true) == S("y") - 12
    assert y_equation.residual.subs(indicator, sp.false) == S("y") - 3


def test_a_relation_of_parameters_only_is_decided_at_once(switching):
    """t0 > 0 with t0 = 0.5 is true: w = 4 + (1 if b), no indicator for it."""
    (w_equation,) = [e for e in switching.equations if S("w") in e.residual.free_symbols]
    assert w_equation.residual.free_symbols == {S("w"), sp.Symbol("b")}
    assert sp.simplify(w_equation.residual.subs(sp.Symbol("b"), sp.true) - (S("w") - 5)) == 0
    assert sp.simplify(w_equation.residual.subs(sp.Symbol("b"), sp.false) - (S("w") - 4)) == 0
    assert not any("t0" in r.text and "time" not in r.text for r in switching.relations)


def test_only_a_relation_linear_in_time_of_parameters_is_a_time_event(switching):
    """2*time - 1 > t0 crosses at time = (1 + t0)/2 = 0.75; time**2 > 1 and time > x are state events."""
    events = [r for r in switching.relations if r.is_time_event]
    assert len(events) == 1
    (event,) = events
    assert event.g.free_symbols == {time, S("t0")}
    g = sp.lambdify(time, event.g.subs(S("t0"), 0.5))
    assert event.holds(g(0.76)) and not event.holds(g(0.74))
    assert not relation_by_text(switching, "time**2 > 1").is_time_event
    assert not relation_by_text(switching, "time > x").is_time_event
    assert not relation_by_text(switching, "x > 1").is_time_event


def test_relation_holds_by_its_operator():
    """holds(g) is g > 0, g >= 0, g < 0, g <= 0 for the four operators (checked at g = -1, 0, 1)."""

    class Four(Model):
        x = Variable(start=0.0, fixed=True)
        y = Variable()

        def equations(self):
            return [Eq(der(self.x), 1),
                    Eq(self.y, If(self.x > 1, 1, 0) + If(self.x >= 2, 1, 0) + If(self.x < 3, 1, 0)
                       + If(self.x <= 4, 1, 0))]

    partitioned = partition(flatten(Four()))
    table = {">": (False, False, True), ">=": (False, True, True), "<": (True, False, False),
             "<=": (True, True, False)}
    assert sorted(r.op for r in partitioned.relations) == sorted(table)
    for relation in partitioned.relations:
        assert tuple(relation.holds(g) for g in (-1.0, 0.0, 1.0)) == table[relation.op]
        # g = lhs - rhs: the relation at x = the threshold +- 0.5 agrees with sympy's
        threshold = float(relation.rhs)
        for x in (threshold - 0.5, threshold + 0.5):
            expected = bool(sp.sympify(f"{x} {relation.op} {threshold}"))
            assert relation.holds(float(relation.g.subs(S("x"), x))) == expected


def test_selectors_are_the_discrete_symbols_the_continuous_equations_read(switching):
    """Read by continuous equations: the indicators of x > 1, the time event, time**2 > 1, time > x, and b, k, pre(k).

    Not selectors: a, c and unused (only discrete equations read them) and the
    indicators of x < 2, x > 5, x > 3 (only in discrete equations).
    """
    names = [s.name for s in switching.selectors]
    assert names == sorted(names)
    continuous_relations = {relation_by_text(switching, t).symbol.name
                            for t in ("x > 1", "time**2 > 1", "time > x")}
    continuous_relations.add([r for r in switching.relations if r.is_time_event][0].symbol.name)
    assert set(names) == continuous_relations | {"b", "k", "pre(k)"}
    assert switching.is_hybrid


def test_discrete_equations_come_in_dependency_order(switching):
    """Declared c := b, b := a, a := x < 2, unused, k: evaluated a, b, c (each after what it reads), then unused, k."""
    order = [e.variable for e in switching.discrete_equations]
    assert order == ["a", "b", "c", "unused", "k"]
    assert switching.discrete_variables == ("c", "b", "a", "unused", "k")
    # relations in discrete equations are indicators too
    (a_equation,) = [e for e in switching.discrete_equations if e.variable == "a"]
    assert a_equation.rhs == relation_by_text(switching, "x < 2").symbol


def test_a_continuous_model_has_no_discrete_part():
    """der(x) = -x: no relations, no selectors, not hybrid; the equations pass through unchanged."""

    class Decay(Model):
        x = Variable(start=1.0, fixed=True)

        def equations(self):
            return [Eq(der(self.x), -self.x)]

    flat = flatten(Decay())
    partitioned = partition(flat)
    assert partitioned.relations == () and partitioned.selectors == ()
    assert partitioned.discrete_equations == () and not partitioned.is_hybrid
    assert partitioned.equations == flat.equations


def test_a_discrete_variable_needs_exactly_one_equation():
    """A Boolean without an equation, or with two: ModelDefinitionError naming it."""

    class Missing(Model):
        x = Variable(start=0.0, fixed=True)
        on = Boolean()

        def equations(self):
            return [Eq(der(self.x), 1)]

    with pytest.raises(ModelDefinitionError, match="on has no equation"):
        partition(flatten(Missing()))

    class Twice(Missing):
        def equations(self):
            return [Eq(self.on, self.x > 1), Eq(self.on, self.x > 2)]

    with pytest.raises(ModelDefinitionError, match="on is defined twice"):
        partition(flatten(Twice()))
