"""Stage 2: split the flat model into its continuous and discrete parts.

Every relation on continuous quantities (``sa > tau0_max``, ``time < startTime``)
becomes a *relation indicator*: a Boolean that keeps its value between events
while its argument ``g = lhs - rhs`` is watched for a zero crossing (a time
event when ``g`` depends on time and parameters only).  Discrete equations
then relate Booleans and Integers only.

The *discrete state* of the model is the assignment of every discrete symbol
that selects continuous equations (discrete variables, their ``pre()``
values, relation indicators and ``initial()``).  For each discrete state the
later stages build their own continuous system, lazily.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import networkx as nx
import sympy as sp

from ..errors import ModelDefinitionError
from .flatten import DiscreteEquation, FlatEquation, FlatModel
from ..language import time
from ..names import is_derivative, parse, relation_name

__all__ = ["Relation", "PartitionedModel", "partition"]

_RELATIONS = (sp.StrictGreaterThan, sp.GreaterThan, sp.StrictLessThan, sp.LessThan)


@dataclass(frozen=True)
class Relation:
    """A relation watched for events.

    ``value = g op 0`` with ``g = lhs - rhs``; ``op`` is one of ``>``, ``>=``,
    ``<``, ``<=``.
    """

    index: int
    symbol: sp.Symbol
    lhs: sp.Expr
    rhs: sp.Expr
    op: str
    text: str
    is_time_event: bool  #: g depends on time and parameters only
    #: the components whose equations contain the relation (for their hints)
    components: tuple[str, ...] = ()

    def holds(self, g_value: float) -> bool:
        """The exact value of the relation for ``g = g_value``."""
        if self.op == ">":
            return g_value > 0
        if self.op == ">=":
            return g_value >= 0
        if self.op == "<":
            return g_value < 0
        return g_value <= 0

    @property
    def g(self) -> sp.Expr:
        return self.lhs - self.rhs

    def shifted(self, g_value: float, previous: bool, epsilon: float) -> float:
        """``g`` moved by ``epsilon`` towards keeping the previous value.

        The relation flips exactly where this function crosses zero, so it is
        the function the event locator searches.  Without the margin a holding
        torque that touches its static limit exactly (``sa == tau0_max`` up to
        round-off, ModelicaTest.Rotational.ForUsersGuide.SupportTorque1) would
        start sliding.  Time events get no margin: they are hit exactly.
        """
        if self.is_time_event:
            return g_value
        if self.op in (">", ">="):
            return g_value + epsilon if previous else g_value - epsilon
        return g_value - epsilon if previous else g_value + epsilon

    def holds_with_hysteresis(self, g_value: float, previous: bool, epsilon: float) -> bool:
        """The value of the relation at an event, given its value before it."""
        return self.holds(self.shifted(g_value, previous, epsilon))


@dataclass(frozen=True)
class PartitionedModel:
    """The output of :func:`partition`.

    Attributes
    ----------
    flat : FlatModel
    equations : tuple of FlatEquation
        Continuous equations with relations replaced by indicators.
    initial_equations : tuple of FlatEquation
    discrete_equations : tuple of DiscreteEquation
        In evaluation order (a discrete variable after those it reads).
    relations : tuple of Relation
    selectors : tuple of sympy.Symbol
        The discrete symbols the continuous equations depend on, sorted by
        name: the discrete state is their values in this order.
    discrete_variables : tuple of str
    evaluated_parameters : frozenset of str
        Parameters of relations decided here, from the parameter values alone
        (``p > 0``): their values select equations, so they are structural.
    """

    flat: FlatModel
    equations: tuple[FlatEquation, ...]
    initial_equations: tuple[FlatEquation, ...]
    discrete_equations: tuple[DiscreteEquation, ...]
    relations: tuple[Relation, ...]
    selectors: tuple[sp.Symbol, ...]
    discrete_variables: tuple[str, ...]
    evaluated_parameters: frozenset[str] = frozenset()

    @property
    def is_hybrid(self) -> bool:
        return bool(self.relations or self.discrete_equations)


def partition(flat: FlatModel) -> PartitionedModel:
    """Find relations, order discrete equations and the discrete state."""
    variables = flat.variable_map
    parameters = flat.parameter_values
    continuous = {n for n, v in variables.items() if not v.is_discrete}
    relations: dict[tuple, Relation] = {}
    owners: dict[tuple, dict[str, None]] = {}
    evaluated: set[str] = set()

    def is_continuous_symbol(sym: sp.Symbol) -> bool:
        name = sym.name
        return sym is time or name in continuous or is_derivative(name)

    def replace_relations(expr: sp.Basic, origin) -> sp.Basic:
        if not isinstance(expr, sp.Basic) or not expr.has(*_RELATIONS):
            return expr

        def visit(node: sp.Basic) -> sp.Basic:
            if isinstance(node, _RELATIONS):
                lhs, rhs = visit(node.lhs), visit(node.rhs)
                g = lhs - rhs
                syms = g.free_symbols
                if not any(is_continuous_symbol(s) for s in syms):
                    if all(s.name in parameters for s in syms):
                        evaluated.update(s.name for s in syms)
                        return sp.true if bool(node.func(g.subs({s: parameters[s.name] for s in syms}), 0)) \
                            else sp.false
                    return node.func(lhs, rhs)  # discrete comparison, evaluated at events
                op = {sp.StrictGreaterThan: ">", sp.GreaterThan: ">=", sp.StrictLessThan: "<",
                      sp.LessThan: "<="}[type(node)]
                key = (sp.srepr(g), op)
                owners.setdefault(key, {})[origin.component] = None
                if key not in relations:
                    index = len(relations)
                    # a time event needs the crossing time in closed form: g linear in time
                    is_time = (all(s is time or s.name in parameters for s in syms) and g.has(time)
                               and not sp.diff(g, time).has(time))
                    relations[key] = Relation(index, sp.Symbol(relation_name(index)), lhs, rhs, op,
                                              f"{lhs} {op} {rhs}", is_time)
                return relations[key].symbol
            if not node.args:
                return node
            args = [visit(a) for a in node.args]
            return node.func(*args) if any(a is not b for a, b in zip(args, node.args)) else node

        return visit(expr)

    equations = tuple(FlatEquation(replace_relations(e.residual, e.origin), e.origin)
                      for e in flat.equations)
    initial_equations = tuple(FlatEquation(replace_relations(e.residual, e.origin), e.origin)
                              for e in flat.initial_equations)
    discrete = tuple(DiscreteEquation(e.variable, replace_relations(e.rhs, e.origin), e.origin)
                     for e in flat.discrete_equations)

    relations = {key: dataclasses.replace(rel, components=tuple(c for c in owners[key] if c))
                 for key, rel in relations.items()}

    discrete_names = tuple(n for n, v in variables.items() if v.is_discrete)
    defined = {}
    for eq in discrete:
        if eq.variable in defined:
            raise ModelDefinitionError(
                f"discrete variable {eq.variable} is defined twice: {defined[eq.variable].origin} "
                f"and {eq.origin}", hint="a Boolean or Integer needs exactly one equation")
        defined[eq.variable] = eq
    for name in discrete_names:
        if name not in defined:
            raise ModelDefinitionError(f"discrete variable {name} has no equation",
                                       hint="define it with Eq(variable, expression)")

    # Order discrete equations so that each reads values already computed.
    # Cycles (through continuous unknowns or directly) are solved by the
    # fixed-point iteration at events; we break them deterministically.
    graph = nx.DiGraph()
    graph.add_nodes_from(range(len(discrete)))
    index_of = {eq.variable: i for i, eq in enumerate(discrete)}
    for i, eq in enumerate(discrete):
        for sym in eq.rhs.free_symbols:
            j = index_of.get(sym.name)
            if j is not None and j != i:
                graph.add_edge(j, i)
    condensed = nx.condensation(graph)
    order: list[int] = []
    for scc in nx.lexicographical_topological_sort(
            condensed, key=lambda c: min(condensed.nodes[c]["members"])):
        order.extend(sorted(condensed.nodes[scc]["members"]))
    discrete = tuple(discrete[i] for i in order)

    selector_set: set[sp.Symbol] = set()
    for eq in equations:
        for sym in eq.residual.free_symbols:
            name = parse(sym.name)
            if name.kind in ("relation", "initial") or name.text in discrete_names or (
                    name.kind == "pre" and name.base in discrete_names):
                selector_set.add(sym)
    selectors = tuple(sorted(selector_set, key=lambda s: s.name))
    return PartitionedModel(flat, equations, initial_equations, discrete,
                            tuple(relations.values()), selectors, discrete_names, frozenset(evaluated))
