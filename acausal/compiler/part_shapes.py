"""Parts of one shape compiled once: an earlier part's code, renamed and bound.

A model of N equal independent parts (a storm of friction units, each a
source, an inertia and a bearing) compiles one system per part and part
mode (:mod:`~acausal.compiler.parts`).  Two parts whose equations, relations,
variables and parameters are equal up to an order-preserving renaming of
their names (:mod:`~acausal.compiler.canonical`), and whose variables have the
same attributes, get the same generated code up to its identifiers: the
code reads states from ``x``, parameters from ``p`` and returns the
derivatives, crossings and outputs by position.  So the second part's system
is the first part's code bound to the second part's parameter vector, with
its names (states, unknowns, aliases) renamed; it computes what the part's
own compilation would, bit for bit (the printed text of one copy is the
text of the other, identifiers aside: the canonical module's guarantee).

What the first part's parameter values decided must hold for the second's,
as when rebinding to other values (:mod:`~acausal.compiler.rebinding`): a
solution that divides by an expression of parameters needs it non-zero for
the new values (else the part is compiled for itself).  Start values are
part of the key (Newton iterations hold them as numbers).

A renamed system has the loaded form of
:class:`~acausal.compiler.modes.ModeSystem` (code and functions, no stage
outputs; :attr:`~acausal.compiler.modes.ModeSystem.shape_of` names the part
it was renamed from).  The initialization problem of such a part is the
renamed problem of the first part (:func:`renamed_initial`).  Only systems a
part compiled itself are stored in the persistent cache.
"""

from __future__ import annotations

import dataclasses
import time as _time
from typing import Mapping, Sequence

import sympy as sp

from ..language import real_symbol
from ..names import der_name, parse
from .canonical import rename, shape
from .initial import InitialSystem, StartDependence, bind_start_values, check_fixed_constants
from .modes import ModeSystem, alias_plan

__all__ = ["PartTwin", "part_shape", "renamed_mode", "renamed_initial"]


@dataclasses.dataclass(frozen=True)
class PartTwin:
    """How one part's names follow from an earlier part of the same shape.

    Attributes
    ----------
    cluster : int
        The earlier part's cluster.
    key : tuple
        The model's discrete state the earlier part's system was built for.
    mode : ModeSystem
        The earlier part's compiled system (with its stages).
    names : mapping
        The earlier part's names -> this part's.
    symbols : mapping
        The same for their symbols.
    """

    cluster: int
    key: tuple
    mode: ModeSystem = dataclasses.field(repr=False)
    names: Mapping[str, str] = dataclasses.field(repr=False)
    symbols: Mapping[sp.Symbol, sp.Symbol] = dataclasses.field(repr=False)

    def name(self, name: str) -> str:
        """This part's name for the earlier part's ``name`` (KeyError: none)."""
        found = self.names.get(name)
        if found is not None:
            return found
        parsed = parse(name)  # a derivative index reduction added, of a variable that is mapped
        if parsed.kind == "derivative" and parsed.base in self.names:
            return der_name(self.names[parsed.base], parsed.order)
        raise KeyError(name)

    def expression(self, expr) -> sp.Expr:
        """The earlier part's ``expr`` in this part's symbols (KeyError: a symbol not mapped)."""
        expr = sp.sympify(expr)
        for s in expr.free_symbols:
            if s not in self.symbols:
                raise KeyError(s.name)
        return rename(expr, dict(self.symbols))


def part_shape(equations: Sequence[sp.Expr], initial_equations: Sequence[sp.Expr],
               relations: Sequence[tuple[str, sp.Expr, sp.Expr]], variables: Sequence[str],
               parameters: Sequence[str], zero: Sequence[bool], selectors: Sequence[sp.Symbol],
               demand: Sequence[str] | None, attributes: tuple) -> tuple[tuple, tuple[str, ...], dict] | None:
    """The key of a part up to an order-preserving renaming, its names in the key's order
    and its symbols by name (None: it cannot be renamed).

    Two parts have one key when their equations, initial equations, relations
    (operator and sides), variables, parameters (the order of the code's ``p``),
    discrete selectors and output demand correspond name for name in the same order,
    the same of their parameters are zero (structural zeros, which specialisation
    removes) and their variables have the same ``attributes`` (kind, start, fixed,
    nominal, stateSelect).  Then, in every discrete state, the specialised equations
    of one are those of the other renamed, and so is everything compiled from them.
    """
    roots = [*equations, *initial_equations]
    for _op, lhs, rhs in relations:
        roots += [sp.sympify(lhs), sp.sympify(rhs)]
    roots.append(sp.Tuple(*[real_symbol(n) for n in variables]))
    roots.append(sp.Tuple(*[real_symbol(n) for n in parameters]))
    roots.append(sp.Tuple(*selectors))
    if demand is not None:
        roots.append(sp.Tuple(*[real_symbol(n) for n in sorted(demand)]))
    head = ("part", len(equations), len(initial_equations), tuple(op for op, _l, _r in relations),
            tuple(zero), demand is None, attributes)
    return shape(roots, head=head)


def twin_of(found: tuple, cluster: int, key: tuple, mode: ModeSystem, this: tuple, this_cluster: int,
            renamings: dict) -> PartTwin:
    """The renaming from an earlier part, cluster ``cluster`` (``found``: its ``(order,
    symbols)`` of :func:`part_shape`), to this one, cluster ``this_cluster`` (``this``: the
    same of this part); the maps of names are made once per pair of parts (``renamings``)."""
    pair = (cluster, this_cluster)
    maps = renamings.get(pair)
    if maps is None:
        order, symbols = found
        this_order, this_symbols = this
        names = dict(zip(order, this_order))
        maps = renamings[pair] = (names, {symbols[a]: this_symbols[b] for a, b in names.items()
                                          if a in symbols and b in this_symbols})
    return PartTwin(cluster, key, mode, *maps)


def renamed_mode(twin: PartTwin, subkey: tuple, description: str, equations: tuple, parameters,
                 started: float) -> ModeSystem | None:
    """The earlier part's system (``twin.mode``) for this part: its code bound to
    ``parameters`` (this part's :class:`~acausal.compiler.cache.ParameterTable`), its
    names renamed; None when its solution divides by an expression of parameters that
    is zero for this part's values, or a name does not map."""
    source = twin.mode
    try:
        for guard in source.algebraic.nonzero:
            if twin.expression(guard).xreplace(parameters.symbols).is_zero:
                return None
        plan = _renamed_plan(twin, parameters)
        states = tuple(twin.name(n) for n in source.states)
        unknowns = tuple(twin.name(n) for n in source.unknowns)
        derivatives = tuple(twin.name(n) for n in source.derivative_names)
    except KeyError:
        return None
    functions = source.code.make(parameters.vector)
    return ModeSystem(subkey, description, equations, None, None, None, None, source.code,
                      (("rename part", _time.perf_counter() - started),), *functions, states, unknowns, plan,
                      loaded_derivatives=derivatives, shape_of=(twin.cluster, source.key))


def _renamed_plan(twin: PartTwin, parameters) -> tuple:
    """The earlier part's alias plan for this part: renamed where an alias reads no
    parameter (its coefficient is a number of the equations), computed from the renamed
    expression with this part's values where it does."""
    source = twin.mode
    plan = []
    for (name, coefficient, of), expr in zip(source.alias_plan, source.aliases.aliases.values()):
        expr = sp.sympify(expr)
        if any(twin.names.get(s.name) in parameters.values for s in expr.free_symbols):
            plan += alias_plan(_Aliases({twin.name(name): twin.expression(expr)}), parameters.symbols)
        else:
            plan.append((twin.name(name), coefficient, None if of is None else twin.name(of)))
    return tuple(plan)


def renamed_initial(twin: PartTwin, source: InitialSystem, subkey: tuple, parameters) -> InitialSystem | None:
    """The earlier part's initialization problem ``source`` for this part (its code bound
    to ``parameters``, names and start-value expressions renamed, this part's fixed
    constants checked); None when a name does not map or its code holds other start
    values as Newton guesses."""
    started = _time.perf_counter()
    try:
        fixed = [(twin.name(n), twin.expression(e), start) for n, e, start in twin.mode.aliases.fixed_constants]
        starts = source.starts
        renamed_starts = StartDependence(
            tuple((twin.name(n), twin.expression(e)) for n, e in starts.values),
            tuple((twin.name(n), twin.expression(e), v) for n, e, v in starts.guesses),
            tuple((twin.name(a), fa, twin.expression(sa), twin.name(b), fb, twin.expression(sb))
                  for a, fa, sa, b, fb, sb in starts.agreeing))
        unknowns = tuple(twin.name(n) for n in source.unknowns)
        relaxed = tuple((twin.name(n), v) for n, v in source.relaxed)
        from_start = tuple((twin.name(n), v) for n, v in source.from_start)
    except KeyError:
        return None
    check_fixed_constants(_Aliases({}, tuple(fixed)), parameters.symbols)
    _, _, outputs = source.code.make(parameters.vector)
    system = InitialSystem(subkey, (), unknowns, relaxed, None, None, source.code, (), outputs,
                           from_start, renamed_starts)
    bound = bind_start_values(system, parameters.symbols)
    if bound is None:
        return None
    return dataclasses.replace(bound, passes=(("rename part", _time.perf_counter() - started),))


def renamed_stage_fields(twin: PartTwin, source_initial: InitialSystem | None = None):
    """What shipping a renamed part to another process needs of the stages it has not
    got (:meth:`~acausal.compiler.persist.PersistentSystems.export`): the earlier part's
    aliases and fixed constants (an object with ``aliases`` and ``fixed_constants``) and
    the expressions its solution divides by (an object with ``nonzero``), in this part's
    names; of its initialization problem ``source_initial`` when given.  KeyError: a name
    does not map."""
    mode = twin.mode
    aliases = _Aliases({twin.name(n): twin.expression(e) for n, e in mode.aliases.aliases.items()},
                       tuple((twin.name(n), twin.expression(e), start)
                             for n, e, start in mode.aliases.fixed_constants))
    algebraic = mode.algebraic if source_initial is None else source_initial.algebraic
    return aliases, _Guards(tuple(twin.expression(g) for g in algebraic.nonzero))


@dataclasses.dataclass(frozen=True)
class _Guards:
    """The field of an :class:`~acausal.compiler.algebraic.AlgebraicResult` that shipping
    a system reads: the expressions its solution divides by."""

    nonzero: tuple


@dataclasses.dataclass(frozen=True)
class _Aliases:
    """The two fields of an :class:`~acausal.compiler.alias.AliasResult` that
    :func:`~acausal.compiler.modes.alias_plan` and
    :func:`~acausal.compiler.initial.check_fixed_constants` read."""

    aliases: dict
    fixed_constants: tuple = ()
