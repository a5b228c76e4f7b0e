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

The equations that flattening built from one component template are alike
but for their symbols: the relations of one instance's equation are found
once, and the other instances get the result renamed (:class:`_RelationTemplate`).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from typing import Sequence

import networkx as nx
import sympy as sp
from sympy.printing.repr import ReprPrinter
from sympy.printing.str import StrPrinter

from ..errors import ModelDefinitionError
from .algebraic import _coefficient
from .compiled import EXACT_MARGIN, RelationData  # noqa: F401 - EXACT_MARGIN: where it was
from .flatten import DiscreteEquation, FlatEquation, FlatModel, _NotTemplatable, _Program, _Source, any_node
from ..language import real_symbol, time
from ..hybrid import NoEvent, without_no_event
from ..names import is_derivative, parse, pre_name, relation_name, sample_name

__all__ = ["Relation", "Clock", "PartitionedModel", "partition"]

#: How many relation templates one template equation may have (one per order of the names).
_MAX_VARIANTS = 8

_RELATIONS = (sp.StrictGreaterThan, sp.GreaterThan, sp.StrictLessThan, sp.LessThan)


@dataclass(frozen=True)
class Relation(RelationData):
    """A relation watched for events: :class:`~acausal.compiler.compiled.RelationData`
    (how it is decided) with its symbolic sides.

    ``value = g op 0`` with ``g = lhs - rhs``.
    """

    #: the indicator symbol the equations read in place of the relation
    symbol: sp.Symbol = field(default=None, kw_only=True)
    lhs: sp.Expr = field(default=None, kw_only=True)
    rhs: sp.Expr = field(default=None, kw_only=True)

    @property
    def g(self) -> sp.Expr:
        return self.lhs - self.rhs


@dataclass(frozen=True)
class Clock:
    """``sample(start, interval)``: true at ``start + i*interval`` (i = 0, 1, ...).

    Its ticks are time events computed from the parameter values when a run
    starts (:func:`acausal.runtime.crossings.clock_ticks`).
    """

    index: int
    symbol: sp.Symbol
    start: sp.Expr
    interval: sp.Expr
    text: str


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
        The Booleans and Integers.
    evaluated_parameters : frozenset of str
        Parameters of relations decided here, from the parameter values alone
        (``p > 0``): their values select equations, so they are structural.
    clocks : tuple of Clock
        The ``sample()`` clocks, numbered in the order met.
    held_variables : tuple of str
        The discrete Reals: states of the
        continuous systems whose values only event iteration changes.
    """

    flat: FlatModel
    equations: tuple[FlatEquation, ...]
    initial_equations: tuple[FlatEquation, ...]
    discrete_equations: tuple[DiscreteEquation, ...]
    relations: tuple[Relation, ...]
    selectors: tuple[sp.Symbol, ...]
    discrete_variables: tuple[str, ...]
    evaluated_parameters: frozenset[str] = frozenset()
    clocks: tuple[Clock, ...] = ()
    held_variables: tuple[str, ...] = ()

    @property
    def is_hybrid(self) -> bool:
        return bool(self.relations or self.discrete_equations)


_OPERATORS = {sp.StrictGreaterThan: ">", sp.GreaterThan: ">=", sp.StrictLessThan: "<", sp.LessThan: "<="}


def _is_sample(node: sp.Basic) -> bool:
    return isinstance(node, sp.Function) and node.func.__name__ == "sample" and len(node.args) == 2


def _right_limit_operator(op: str, g: sp.Expr) -> str:
    """The operator that gives a time event's relation, at its instant, the value it has
    just after it.

    A time event is hit exactly, so at the instant ``g = 0``: ``time > 2`` is false there and
    ``time <= 2`` true, as before the instant; with the value at the instant taken for the
    new one the relation would never change (integration freezes relations between events).
    Modelica tools switch such a relation at its event; so does acausal, by deciding it at
    ``g = 0`` as just after (``time > 2`` as ``time >= 2``, ``time <= 2`` as ``time < 2``; for
    a falling ``g`` the other way round).  Elsewhere both operators agree.  A slope that is
    not a number (it reads parameters) keeps the operator as written.
    """
    slope = sp.diff(g, time)
    if not slope.is_number or slope == 0:
        return op
    rising = bool(slope > 0)
    if op in (">", ">="):
        return ">=" if rising else ">"
    return "<" if rising else "<="


def _has_relation(expr: sp.Basic) -> bool:
    """Whether ``expr`` has a relation, a noEvent or a sample() (what partition replaces)."""
    return any_node(expr, lambda node: isinstance(node, (*_RELATIONS, NoEvent)) or _is_sample(node))


class _RelationFinder:
    """Replaces relations by indicators, numbering them in the order they are met."""

    def __init__(self, flat: FlatModel, variables: dict) -> None:
        self.parameters = flat.parameter_values
        self.continuous = {n for n, v in variables.items() if not v.is_discrete}
        self.held = {n for n, v in variables.items() if v.is_held}
        self.relations: dict[tuple, Relation] = {}
        self.owners: dict[tuple, dict[str, None]] = {}
        self.evaluated: set[str] = set()
        self.clocks: dict[tuple, Clock] = {}

    def copy(self) -> "_RelationFinder":
        other = object.__new__(_RelationFinder)
        other.parameters, other.continuous, other.held = self.parameters, self.continuous, self.held
        other.clocks = self.clocks  # shared: templates never meet sample()
        other.relations = dict(self.relations)
        other.owners = {key: dict(found) for key, found in self.owners.items()}
        other.evaluated = set(self.evaluated)
        return other

    def restore(self, other: "_RelationFinder") -> None:
        """Take what ``other`` (a copy of this one) found."""
        self.relations, self.owners, self.evaluated = other.relations, other.owners, other.evaluated

    def is_continuous_symbol(self, sym: sp.Symbol) -> bool:
        name = sym.name
        return sym is time or name in self.continuous or is_derivative(name)

    def is_time_event(self, g: sp.Expr) -> bool:
        """A time event needs the crossing time in closed form: g linear in time, its
        coefficients of parameters and of discrete Reals, which are constant between events
        (``time >= t_next`` is hit exactly, as Modelica tools do)."""
        constant = self.parameters.keys() | self.held
        return (all(s is time or s.name in constant for s in g.free_symbols) and g.has(time)
                and not sp.diff(g, time).has(time))

    def decide(self, relation: type, g: sp.Expr) -> bool:
        """The value of ``g op 0`` for a ``g`` of parameters only."""
        syms = g.free_symbols
        self.evaluated.update(s.name for s in syms)
        return bool(relation(g.subs({s: self.parameters[s.name] for s in syms}), 0))

    def add(self, key: tuple, component: str, make) -> sp.Symbol:
        """The indicator of the relation ``key``; if new, ``make()`` gives its
        ``(lhs, rhs, op, text, is_time)``."""
        self.owners.setdefault(key, {})[component] = None
        found = self.relations.get(key)
        if found is None:
            index = len(self.relations)
            lhs, rhs, op, text, is_time = make()
            found = self.relations[key] = Relation(index, relation_name(index), op, text, is_time,
                                                   symbol=sp.Symbol(relation_name(index)), lhs=lhs, rhs=rhs)
        return found.symbol

    def clock(self, start: sp.Expr, interval: sp.Expr) -> sp.Symbol:
        """The symbol of the clock ``sample(start, interval)`` (one per distinct pair)."""
        for what, value in (("start", start), ("interval", interval)):
            if value.has(time) or any(s.name not in self.parameters for s in value.free_symbols):
                raise ModelDefinitionError(
                    f"sample({start}, {interval}): its {what} is not a parameter expression",
                    hint="sample(start, interval) takes numbers or parameters")
        key = (sp.srepr(start), sp.srepr(interval))
        found = self.clocks.get(key)
        if found is None:
            index = len(self.clocks)
            found = self.clocks[key] = Clock(index, sp.Symbol(sample_name(index)), start, interval,
                                             f"sample({start}, {interval})")
        return found.symbol

    def replace(self, expr: sp.Basic, origin, events: list | None = None) -> sp.Basic:
        """``expr`` with its relations replaced; ``events`` (if given) receives, in order,
        ``("relation", node, g, lhs, rhs, op, indicator)`` for each relation watched and
        ``("decided", node, g, value)`` for each relation of parameters decided."""
        if not isinstance(expr, sp.Basic) or not _has_relation(expr):
            return expr
        parameters = self.parameters

        def visit(node: sp.Basic) -> sp.Basic:
            if isinstance(node, NoEvent):
                # its relations are evaluated as they stand, without events
                return without_no_event(node.args[0])
            if _is_sample(node):
                return self.clock(*node.args)
            if isinstance(node, _RELATIONS):
                lhs, rhs = visit(node.lhs), visit(node.rhs)
                g = lhs - rhs
                syms = g.free_symbols
                if not any(self.is_continuous_symbol(s) for s in syms):
                    if all(s.name in parameters for s in syms):
                        value = self.decide(node.func, g)
                        if events is not None:
                            events.append(("decided", node.func, g, value))
                        return sp.true if value else sp.false
                    return node.func(lhs, rhs)  # discrete comparison, evaluated at events
                written = _OPERATORS[type(node)]
                timed = self.is_time_event(g)
                op = _right_limit_operator(written, g) if timed else written
                key = (sp.srepr(g), op)
                symbol = self.add(key, origin.component,
                                  lambda: (lhs, rhs, op, f"{lhs} {written} {rhs}", timed))
                if events is not None:
                    events.append(("relation", node.func, g, lhs, rhs, op, symbol))
                return symbol
            if not node.args:
                return node
            args = [visit(a) for a in node.args]
            return node.func(*args) if any(a is not b for a, b in zip(args, node.args)) else node

        return visit(expr)


class _RelationTemplate:
    """What partition did to one instance's template equation, ready for another instance.

    Flattening builds the equations of repeated components from a template
    (:class:`~acausal.compiler.flatten._Template`); their origins say which
    (:class:`~acausal.compiler.flatten._Source`).  The first instance of a
    template equation that has relations is visited as usual, and its result,
    with the relations it met (in order), becomes this template.  A further
    instance of the same equation gets

    - each relation's ``g``, ``lhs`` and ``rhs`` renamed to its symbols, and
      the indicator of ``(srepr(g), op)`` (an existing one, or a new one
      numbered in the same order as a visit would);
    - relations of parameters alone decided with its own parameter values,
      which must give the template's value (else it is visited);
    - the template's result renamed to its symbols and indicators, node by
      node without evaluation (as flattening's templates), provided the
      indicators' names sort with the symbols' names as the template's did
      (``$rel10`` sorts before ``$rel9``) and two relations share an
      indicator exactly where the template's did; else it is visited.

    The first use of each template is checked against a visit of the same
    equation; if they differ the equation is visited for every instance.
    """

    def __init__(self, result: sp.Basic, events: list, symbols: list, finder: _RelationFinder) -> None:
        self.verified = False
        #: ("relation", op, is_time, indicator number, root) or ("decided", relation, value, root),
        #: root: where g (then lhs, rhs) is among the roots of ``parts``
        self.events: list[tuple] = []
        indicators: list[sp.Symbol] = []
        roots: list = []
        for event in events:
            if event[0] == "relation":
                _, _, g, lhs, rhs, op, indicator = event
                if indicator not in indicators:
                    indicators.append(indicator)
                # is_time is the same for every instance: their symbols are declared alike
                self.events.append(("relation", op, finder.is_time_event(g), indicators.index(indicator),
                                    len(roots)))
                roots += [g, lhs, rhs]
            else:
                _, relation, g, value = event
                self.events.append(("decided", relation, value, len(roots)))
                roots.append(g)
        n = len(symbols)
        slots = {symbol: i for i, symbol in enumerate(symbols)}
        if len(slots) != n or any(i in slots for i in indicators):
            raise _NotTemplatable("symbols that are not distinct")
        self.parts = _Program(roots, slots, ())  # no indicators in g, lhs, rhs: nested relations are visited
        # srepr(g) (the relation's key) and str(lhs), str(rhs) (its text) with holes for the names
        self.formats = [(_marked(_MarkingRepr, event[2], slots), _marked(_MarkingStr, event[3], slots),
                         _marked(_MarkingStr, event[4], slots)) if event[0] == "relation" else None
                        for event in events]
        #: the slots whose srepr the keys need
        self.printed_slots = sorted({piece for formats in self.formats if formats is not None
                                     for i, piece in enumerate(formats[0]) if i % 2})
        for i, indicator in enumerate(indicators):
            slots[indicator] = n + i
        self.result = _Program([result], slots, ())
        self.n_indicators = len(indicators)
        # the names in the result, in the order they sort
        present = sorted(slots[s] for s in result.free_symbols if s in slots)
        names = [s.name for s in symbols] + [s.name for s in indicators]
        order = sorted(present, key=names.__getitem__)
        self.order = [(a, b, names[a] == names[b]) for a, b in zip(order, order[1:])]
        self.free = present  # slots of the result's free symbols
        if len(present) != len(result.free_symbols):
            raise _NotTemplatable("free symbols outside the slots")

    def apply(self, finder: _RelationFinder, symbols: list, origin) -> tuple | None:
        """``(result, its free symbols)`` for the instance with ``symbols``, with its relations
        added to ``finder``; None (and nothing added) if the template does not apply."""
        n = len(symbols)
        values = self.parts.run(symbols)
        planned = []  # (key, lhs, rhs, op, indicator number, is_time, printed forms)
        roots = self.parts.roots
        reprs: list = [None] * n
        for slot in self.printed_slots:
            reprs[slot] = _REPR._print_Symbol(symbols[slot])
        for event, formats in zip(self.events, self.formats):
            if event[0] == "relation":
                _, op, is_time, number, at = event
                planned.append(((_fill(formats[0], reprs), op), values[roots[at + 1]],
                                values[roots[at + 2]], op, number, is_time, formats))
            else:
                _, relation, value, at = event
                g = values[roots[at]]
                syms = g.free_symbols
                if bool(relation(g.subs({s: finder.parameters[s.name] for s in syms}), 0)) != value:
                    return None
        # the indicators this instance gets, without adding anything yet
        indicators: list = [None] * self.n_indicators
        new: dict[tuple, sp.Symbol] = {}
        count = len(finder.relations)
        for key, _, _, _, number, _, _ in planned:
            found = finder.relations.get(key)
            symbol = found.symbol if found is not None else new.get(key)
            if symbol is None:
                symbol = new[key] = sp.Symbol(relation_name(count + len(new)))
            if indicators[number] is None:
                indicators[number] = symbol
            elif indicators[number] != symbol:
                return None
        if len(set(indicators)) != len(indicators):
            return None
        slots = list(symbols) + indicators
        names = [s.name for s in slots]
        for a, b, equal in self.order:
            if (names[a] != names[b]) if equal else not names[a] < names[b]:
                return None
        # add them as a visit would: in the order met
        for key, lhs, rhs, op, number, is_time, formats in planned:
            finder.add(key, origin.component,
                       lambda lhs=lhs, rhs=rhs, op=op, is_time=is_time, formats=formats:
                       (lhs, rhs, op, f"{_fill(formats[1], names)} {op} {_fill(formats[2], names)}", is_time))
        for event in self.events:
            if event[0] == "decided":
                finder.evaluated.update(s.name for s in values[roots[event[3]]].free_symbols)
        result = self.result.run(slots)[self.result.roots[0]]
        return result, [slots[i] for i in self.free]

    def agrees(self, finder: _RelationFinder, visited: _RelationFinder, result: sp.Basic,
               direct: sp.Basic) -> bool:
        """Whether applying the template (to ``finder``) did what the visit (to ``visited``,
        a copy of ``finder`` before) did."""
        if sp.srepr(result) != sp.srepr(direct) or finder.evaluated != visited.evaluated:
            return False
        if [(key, list(found)) for key, found in finder.owners.items()] != \
                [(key, list(found)) for key, found in visited.owners.items()]:
            return False
        if list(finder.relations) != list(visited.relations):
            return False
        return all(a == b and sp.srepr((a.lhs, a.rhs)) == sp.srepr((b.lhs, b.rhs))
                   for a, b in zip(finder.relations.values(), visited.relations.values()))


#: srepr's printer (for one symbol)
_REPR = ReprPrinter()


class _MarkingRepr(ReprPrinter):
    """srepr, with the symbols of ``slots`` printed as ``NUL slot NUL``."""

    slots: dict = {}

    def _print_Symbol(self, expr):
        slot = self.slots.get(expr)
        return super()._print_Symbol(expr) if slot is None else f"\x00{slot}\x00"


class _MarkingStr(StrPrinter):
    """str(), with the symbols of ``slots`` printed as ``NUL slot NUL``."""

    slots: dict = {}

    def _print_Symbol(self, expr):
        slot = self.slots.get(expr)
        return super()._print_Symbol(expr) if slot is None else f"\x00{slot}\x00"


def _marked(printer: type, expr: sp.Basic, slots: dict) -> list:
    """How ``printer`` prints ``expr``: text pieces, and the slot numbers of its symbols between them.

    The order of a sum's terms comes from the expression, not from the text,
    so it is that of another instance whose names sort alike: filling in its
    names (:func:`_fill`) prints that instance's expression.
    """
    settings = {"order": None} if printer is _MarkingStr else {}  # as str() and srepr() print
    marking = printer(settings)
    marking.slots = slots
    pieces = marking.doprint(expr).split("\x00")
    if len(pieces) % 2 == 0:
        raise _NotTemplatable("a name with a NUL character")
    return [int(piece) if i % 2 else piece for i, piece in enumerate(pieces)]


def _fill(pieces: list, texts: list) -> str:
    return "".join(texts[piece] if i % 2 else piece for i, piece in enumerate(pieces))


def partition(flat: FlatModel, *, templates: bool = True) -> PartitionedModel:
    """Find relations, order discrete equations and the discrete state.

    ``templates`` (:attr:`acausal.options.EngineOptions.templates`) treats the
    equations flattening built from one template
    (:class:`~acausal.compiler.flatten._Template`) alike
    (:class:`_RelationTemplate`); False visits every equation instead.  The
    result is the same.
    """
    variables = flat.variable_map
    finder = _RelationFinder(flat, variables)
    use_templates = templates
    #: (id of a flatten template, its equation) -> relation templates, or None
    variants: dict[tuple, list | None] = {}
    free: dict[int, list] = {}  # id of a new equation -> its free symbols, where known

    def replace(expr: sp.Basic, origin) -> sp.Basic:
        source = origin.source
        if not use_templates or not isinstance(source, _Source):
            return finder.replace(expr, origin)
        key = (id(source.template), source.entry)
        found = variants.get(key, [])
        if found is None:
            return finder.replace(expr, origin)
        if not found and key in variants:  # no relations in this equation of the template
            free[id(expr)] = [source.symbols[i] for i in source.template.free_slots[source.entry]]
            return expr
        for template in found:
            # its first use is checked: the equation is visited as well, on a copy
            before = None if template.verified else finder.copy()
            applied = template.apply(finder, source.symbols, origin)
            if applied is None:
                continue
            result, symbols = applied
            if before is not None:
                direct = before.replace(expr, origin)
                if not template.agrees(finder, before, result, direct):
                    variants[key] = None
                    finder.restore(before)  # the visit's result is the one to keep
                    return direct
                template.verified = True
            free[id(result)] = symbols
            return result
        if len(found) >= _MAX_VARIANTS:
            return finder.replace(expr, origin)
        events: list = []
        result = finder.replace(expr, origin, events)
        if not events and result is expr:
            variants[key] = []  # no relations: every instance's equation stays as it is
            return result
        try:
            template = _RelationTemplate(result, events, source.symbols, finder)
        except _NotTemplatable:
            variants[key] = None
        else:
            variants[key] = found + [template]
        return result

    equations = tuple(FlatEquation(replace(e.residual, e.origin), e.origin) for e in flat.equations)
    initial_equations = tuple(FlatEquation(replace(e.residual, e.origin), e.origin)
                              for e in flat.initial_equations)
    discrete = tuple(DiscreteEquation(e.variable, replace(e.rhs, e.origin), e.origin)
                     for e in flat.discrete_equations)
    relations, owners, evaluated = finder.relations, finder.owners, finder.evaluated

    relations = {key: dataclasses.replace(rel, components=tuple(c for c in owners[key] if c))
                 for key, rel in relations.items()}

    held = tuple(n for n, v in variables.items() if v.is_held)
    if held:
        # during integration pre(v) = v; at the end of event iteration too
        to_held = {sp.Symbol(pre_name(n), real=True): real_symbol(n) for n in held}
        equations = tuple(FlatEquation(eq.residual.xreplace(to_held), eq.origin)
                          if eq.residual.free_symbols & to_held.keys() else eq for eq in equations)
    discrete_names = tuple(n for n, v in variables.items() if v.is_discrete)
    defined = {}
    for eq in discrete:
        if eq.variable in defined:
            raise ModelDefinitionError(
                f"discrete variable {eq.variable} is defined twice: {defined[eq.variable].origin} "
                f"and {eq.origin}", hint="a Boolean or Integer needs exactly one equation")
        defined[eq.variable] = eq
    for name in discrete_names + held:
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
        for sym in free.get(id(eq.rhs)) or eq.rhs.free_symbols:
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
    is_discrete = frozenset(discrete_names)
    for eq in equations:
        for sym in free.get(id(eq.residual)) or eq.residual.free_symbols:
            name = parse(sym.name)
            if name.kind in ("relation", "initial") or name.text in is_discrete or (
                    name.kind == "pre" and name.base in is_discrete):
                selector_set.add(sym)
            elif name.kind in ("sample", "terminal"):
                raise ModelDefinitionError(
                    f"{eq.origin}: {'sample()' if name.kind == 'sample' else 'terminal()'} in a "
                    f"continuous equation", hint="use it in a when-condition, When(sample(0, 0.1), ...), "
                                                 "or give it a Boolean variable of its own")
    selectors = tuple(sorted(selector_set, key=lambda s: s.name))
    exact = exact_relations(equations, tuple(relations.values()), flat)
    relations = {key: dataclasses.replace(rel, is_exact=True) if rel.index in exact else rel
                 for key, rel in relations.items()}
    return PartitionedModel(flat, equations, initial_equations, discrete,
                            tuple(relations.values()), selectors, discrete_names, frozenset(evaluated),
                            tuple(finder.clocks.values()), held)


def exact_relations(equations: Sequence[FlatEquation], relations: Sequence[Relation],
                    flat: FlatModel) -> frozenset[int]:
    """The relations whose two sides carry no integration noise.

    Known are time, the parameters, and everything constant between events
    (discrete variables, pre() values, held discrete Reals, relation
    indicators, ``initial()``).  An equation in which exactly one variable is
    not known yet, linearly with a coefficient of known values, makes that
    variable known (it is assigned, without iteration, from known values:
    a source signal through gains and connections); repeated to a fixed
    point.  A relation whose sides read only known values is exact: time
    events, and also ``fn <= 0`` for a normal force ``fn = fn_max*sin(...)``.

    Such a relation needs no hysteresis against the noise of the integrator,
    only against round-off: two elements whose normal forces rise from 0 at
    one instant (the same sine, other gains) engage in one event, as in
    Modelica tools, instead of each when its force passes the crossing margin.
    """
    if not relations:
        return frozenset()
    variables = flat.variable_map
    parameters = {p.name for p in flat.parameters}
    known: set[str] = {"time", *parameters}
    for name, variable in variables.items():
        if variable.is_discrete or variable.is_held:
            known.add(name)

    def is_known(name: str) -> bool:
        what = parse(name)
        return name in known or what.kind in ("pre", "relation", "initial", "sample", "terminal")

    # a worklist on plain index lists: each equation's count of variables not known yet
    unknown_in: list[list[str]] = []
    readers: dict[str, list[int]] = {}
    for i, eq in enumerate(equations):
        names = sorted({sym.name for sym in eq.residual.free_symbols if not is_known(sym.name)})
        unknown_in.append(names)
        for name in names:
            readers.setdefault(name, []).append(i)
    left = [len(names) for names in unknown_in]
    queue = [i for i, n in enumerate(left) if n == 1]
    while queue:
        i = queue.pop()
        names = [n for n in unknown_in[i] if n not in known]
        if len(names) != 1 or parse(names[0]).kind == "derivative":
            continue  # der(x) is the integrator's: never known here
        name = names[0]
        residual = equations[i].residual
        symbol = next(sym for sym in residual.free_symbols if sym.name == name)
        coefficient = _coefficient(residual, symbol)  # (= residual.diff(symbol), without sympy's machinery)
        if coefficient.has(symbol) or coefficient == 0:
            continue  # not assigned explicitly (iterated): it may carry the solver's noise
        known.add(name)
        for j in readers.get(name, ()):
            left[j] -= 1
            if left[j] == 1:
                queue.append(j)

    def exact(rel: Relation) -> bool:
        left, right = rel.lhs.free_symbols, rel.rhs.free_symbols
        unknown = {s for s in left | right if not is_known(s.name)}
        if not unknown:
            return True
        if not unknown <= (left & right):
            return False  # a symbol on one side only cannot cancel in lhs - rhs
        return all(is_known(s.name) for s in (rel.lhs - rel.rhs).free_symbols)

    return frozenset(rel.index for rel in relations if exact(rel))
