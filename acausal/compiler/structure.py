"""Stage 5: structural analysis — balance, matching, index reduction, states.

The equations left after alias elimination are analysed as a bipartite
graph of equations and unknowns:

1. *Balance and singularity.*  Each variable and its derivatives form one
   "family"; a solvable DAE matches every equation to a distinct family.
   This check runs first because Pantelides' algorithm does not terminate on
   a structurally singular system.
2. *Index reduction* (Pantelides 1988): equations that constrain states only
   are differentiated until every equation can be matched to a highest
   derivative or an algebraic variable.
3. *State selection* (dummy derivatives, Mattsson & Söderlind 1993): for
   each level of differentiated equations as many derivatives as equations
   become ordinary algebraic unknowns, chosen by ``state_select``.
4. *Matching* of the final system: every equation to the unknown it solves.

The graph algorithms work on plain index lists (``G[i]`` = unknowns of
equation ``i``, ``A[j]`` = index of ``der(v_j)`` or -1, ``B[i]`` = index of the
derivative of equation ``i`` or -1), as in ModiaBase.jl.

References
----------
.. [1] C. C. Pantelides, "The consistent initialization of differential-
   algebraic systems", SIAM J. Sci. Stat. Comput. 9(2), 213-231, 1988.
.. [2] S. E. Mattsson and G. Söderlind, "Index reduction in differential-
   algebraic equations using dummy derivatives", SIAM J. Sci. Comput. 14(3),
   677-692, 1993.
.. [3] J. E. Hopcroft and R. M. Karp, "An n^5/2 algorithm for maximum
   matchings in bipartite graphs", SIAM J. Comput. 2(4), 1973.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass, field
from typing import Callable, Iterable, Sequence

import networkx as nx
import sympy as sp

from ..errors import (
    OverDeterminedError,
    StructurallySingularError,
    StructuralError,
    UnderDeterminedError,
)
from .canonical import from_placeholders, shape, to_placeholders
from .flatten import FlatEquation, FlatVariable, Origin
from ..names import base_name, der_name, derivative_order, parse
from ..functions import settle
from ..language import StateSelect, parameter_symbols, real_symbol, time

__all__ = [
    "StructureMemo",
    "StructuralResult",
    "analyse",
    "pantelides",
    "augmenting_path",
    "priority_matching",
    "maximum_matching",
    "check_balance",
    "Relaxation",
    "relax_redundant",
    "differentiate",
]


# --------------------------------------------------------------------------
# Matching helpers on plain lists
# --------------------------------------------------------------------------


def augmenting_path(root: int, G: Sequence[Sequence[int]], assign: list[int],
                    allowed: Callable[[int], bool], visited_eqs: set[int],
                    visited_vars: set[int]) -> bool:
    """Try to match equation ``root`` by an augmenting path (iterative DFS).

    ``assign[j]`` is the equation matched to unknown ``j`` or -1; it is
    updated in place on success.  The equations and unknowns visited are
    added to the two sets (Pantelides colours them).
    """
    visited_eqs.add(root)
    for j in G[root]:
        if allowed(j) and assign[j] == -1:
            assign[j] = root
            return True
    stack = [(root, iter(G[root]))]
    via: list[int] = []
    while stack:
        eq, candidates = stack[-1]
        for j in candidates:
            if not allowed(j) or j in visited_vars:
                continue
            visited_vars.add(j)
            nxt = assign[j]
            if nxt in visited_eqs:
                continue
            visited_eqs.add(nxt)
            for k in G[nxt]:
                if allowed(k) and assign[k] == -1:
                    assign[k] = nxt
                    assign[j] = eq
                    for level, v in enumerate(via):
                        assign[v] = stack[level][0]
                    return True
            via.append(j)
            stack.append((nxt, iter(G[nxt])))
            break
        else:
            stack.pop()
            if via:
                via.pop()
    return False


def priority_matching(G: Sequence[Sequence[int]], n_vars: int, order: Sequence[int],
                      allowed: Callable[[int], bool] = lambda j: True) -> list[int]:
    """Maximum matching that matches equations in ``order`` first.

    Returns ``assign`` (unknown -> equation or -1).  Equations earlier in
    ``order`` are never left unmatched in favour of later ones (greedy on a
    transversal matroid).
    """
    assign = [-1] * n_vars
    for i in order:
        augmenting_path(i, G, assign, allowed, set(), set())
    return assign


def maximum_matching(G: Sequence[Sequence[int]], n_vars: int) -> list[int]:
    """A maximum matching by Hopcroft-Karp (networkx): ``assign`` as in
    :func:`priority_matching`, without its priorities.

    O(E sqrt(V)): one augmenting path per equation, as
    :func:`priority_matching` finds them, can cost O(V) each on a long drive
    train whose equations come in an unlucky order.

    References
    ----------
    .. [1] J. E. Hopcroft and R. M. Karp, "An n^5/2 algorithm for maximum
       matchings in bipartite graphs", SIAM J. Comput. 2(4), 225-231, 1973.
    """
    graph = nx.Graph()
    graph.add_nodes_from(range(len(G)))
    graph.add_nodes_from(range(len(G), len(G) + n_vars))
    graph.add_edges_from((i, len(G) + j) for i, row in enumerate(G) for j in row)
    mate = _bipartite_matching(graph, list(range(len(G))))
    return [mate.get(len(G) + j, -1) for j in range(n_vars)]


def _bipartite_matching(graph: nx.Graph, top_nodes: list) -> dict:
    """networkx's Hopcroft-Karp, or this module's iterative matching where it cannot go.

    networkx searches augmenting paths recursively: a path through thousands
    of equations (a long chain declared in an unlucky order) exceeds Python's
    recursion limit.  The equation-by-equation matching finds the same
    maximum, slower.
    """
    try:
        return nx.bipartite.hopcroft_karp_matching(graph, top_nodes=top_nodes)
    except RecursionError:
        top = set(top_nodes)
        bottom = [n for n in graph if n not in top]
        index = {n: k for k, n in enumerate(bottom)}
        G = [sorted(index[m] for m in graph[n]) for n in top_nodes]
        mate = {}
        for j, i in enumerate(priority_matching(G, len(bottom), range(len(top_nodes)))):
            if i >= 0:
                mate[top_nodes[i]], mate[bottom[j]] = bottom[j], top_nodes[i]
        return mate


# --------------------------------------------------------------------------
# Differentiation
# --------------------------------------------------------------------------


def _derivative_text(origin: Origin) -> str:
    return f"d/dt[{origin.text}]"


def differentiate(residual: sp.Expr, parameters: set[str]) -> sp.Expr:
    """Total time derivative of a residual, derivatives as ``der(x)`` symbols.

    Term by term: a term ``c*x`` (``c`` of parameters and numbers) gives
    ``c*der(x)`` directly, which is most terms of a model; others go through
    sympy's differentiation by each variable (and time).
    """
    # The partial derivatives are summed per variable before they multiply
    # der(x), so that terms cancel as in d/dx of the whole residual: the
    # derivative of x*(y + 2) - x*y must not depend on y.
    partial: dict[sp.Symbol, list] = {}
    of_time = []
    for term in sp.Add.make_args(residual):
        variables = [s for s in term.free_symbols if s != time and s.name not in parameters]
        if len(variables) == 1 and not term.has(time):
            (sym,) = variables
            # (compared with ==: sympy's symbol cache is bounded, equal symbols
            # are not always the same object)
            if term == sym:
                partial.setdefault(sym, []).append(sp.Integer(1))
                continue
            if isinstance(term, sp.Mul) and sum(f == sym for f in term.args) == 1 \
                    and all(f == sym or not f.has(sym) for f in term.args):
                partial.setdefault(sym, []).append(sp.Mul(*[f for f in term.args if f != sym]))
                continue
        if term.has(time):
            of_time.append(sp.diff(term, time))
        for sym in variables:
            partial.setdefault(sym, []).append(sp.diff(term, sym))
    result = sp.Add(*of_time)
    for sym in sorted(partial, key=lambda s: s.name):
        result += sp.Add(*partial[sym]) * real_symbol(der_name(sym.name))
    return result


def _differentiated(residual: sp.Expr, parameters: set[str], shapes: dict) -> sp.Expr:
    """:func:`differentiate`, once per shape of the residual (with the derivatives it
    may hold, and which of its symbols are parameters or time), renamed for the other
    copies (:mod:`~acausal.compiler.canonical`)."""
    found = shape((residual,))
    if found is None:
        return differentiate(residual, parameters)
    _, order, symbols = found
    kinds = tuple(2 if symbols[n] == time else 1 if n in parameters else 0 for n in order)
    derivatives = [real_symbol(der_name(n)) for n, kind in zip(order, kinds) if kind == 0]
    found = shape([residual, *derivatives])
    if found is None:
        return differentiate(residual, parameters)
    key, order, symbols = found
    key = (key, kinds)
    template = shapes.get(key, False)
    if template is False:
        result = differentiate(residual, parameters)
        shapes[key] = to_placeholders(result, order, symbols)
        return result
    if template is None:
        return differentiate(residual, parameters)
    return from_placeholders(template, order, symbols)


# --------------------------------------------------------------------------
# Result
# --------------------------------------------------------------------------


@dataclass(frozen=True)
class StructuralResult:
    """The output of :func:`analyse`.

    Attributes
    ----------
    equations : tuple of FlatEquation
        Original equations followed by those differentiated by index
        reduction.
    states : tuple of str
        Continuous states, in a deterministic order.
    derivatives : tuple of str
        ``derivatives[k]`` is the unknown holding the derivative of
        ``states[k]``.
    unknowns : tuple of str
        Everything solved from the states at each evaluation.
    matching : tuple of int
        ``matching[i]`` = index in ``unknowns`` solved by equation ``i``.
    incidence : tuple of tuple of int
        Unknowns (indices) occurring in each equation.
    differentiated : tuple of (int, int)
        ``(i, k)``: equation ``i`` is the time derivative of equation ``k``.
    dummy_derivatives : tuple of str
        Derivatives made algebraic by state selection.
    """

    equations: tuple[FlatEquation, ...]
    states: tuple[str, ...]
    derivatives: tuple[str, ...]
    unknowns: tuple[str, ...]
    matching: tuple[int, ...]
    incidence: tuple[tuple[int, ...], ...]
    differentiated: tuple[tuple[int, int], ...]
    dummy_derivatives: tuple[str, ...]

    @property
    def index_reduced(self) -> bool:
        return bool(self.differentiated)


def _incidence(residual: sp.Expr, values: dict) -> set[str]:
    """Unknowns occurring in a residual (parameters and time excluded).

    Parameters equal to zero were already replaced by 0 when the equations
    were specialised (a damper with d = 0 does not make its torque depend on
    its speed); a combination that happens to vanish, (a + b)*u with
    b = -a, keeps ``u``: the structure must describe the code generated
    from the same expressions.
    """
    return {s.name for s in residual.free_symbols if s is not time and s not in values}


# --------------------------------------------------------------------------
# Balance check
# --------------------------------------------------------------------------


def check_balance(equations: Sequence[FlatEquation], incidence: Sequence[set[str]],
                  families: Sequence[str], context: str = "the model",
                  unknown_label: str = "variables") -> None:
    """Raise a clear error unless equations and variable families match perfectly."""
    graph = nx.Graph()
    eq_nodes = [("e", i) for i in range(len(equations))]
    graph.add_nodes_from(eq_nodes, bipartite=0)
    graph.add_nodes_from((("v", f) for f in families), bipartite=1)
    family_set = set(families)
    for i, names in enumerate(incidence):
        for name in sorted(names):
            fam = base_name(name)
            if fam in family_set:
                graph.add_edge(("e", i), ("v", fam))
    matching = _bipartite_matching(graph, eq_nodes)
    unmatched_eqs = [i for i in range(len(equations)) if ("e", i) not in matching]
    unmatched_vars = [f for f in families if ("v", f) not in matching]
    if not unmatched_eqs and not unmatched_vars:
        return
    # Follow alternating paths from the unmatched ones: the whole over- or
    # under-determined part (Dulmage-Mendelsohn), so the message names the
    # components involved and not an arbitrary equation of them.
    over_eqs = _alternating_reach([("e", i) for i in unmatched_eqs], graph, matching)
    under_vars = _alternating_reach([("v", f) for f in unmatched_vars], graph, matching)
    over = sorted(i for kind, i in over_eqs if kind == "e")
    under = [f for f in families if ("v", f) in under_vars]
    n_eq, n_var = len(equations), len(families)
    lines = []
    if over:
        lines.append(f"equations in the over-determined part ({len(over)} equations, "
                     f"{len(unmatched_eqs)} more than their variables need):")
        lines += [f"    {equations[i].origin}" for i in over[:12]]
        if len(over) > 12:
            lines.append(f"    ... and {len(over) - 12} more")
    if under:
        lines.append(f"{unknown_label} in the under-determined part ({len(under)} {unknown_label}, "
                     f"{len(unmatched_vars)} more than their equations determine):")
        lines.append("    " + ", ".join(under[:20]) + (" ..." if len(under) > 20 else ""))
    detail = "\n  ".join(lines)
    components = _components_of([equations[i].origin for i in over], under)
    if n_eq > n_var:
        raise OverDeterminedError(
            f"{context} is over-determined: {n_eq} equations for {n_var} {unknown_label}\n  {detail}",
            hint="two components may prescribe the same quantity (a fixed value or a source where "
                 "the connection already determines it), or an equation is written twice",
            components=components)
    if n_eq < n_var:
        raise UnderDeterminedError(
            f"{context} is under-determined: {n_eq} equations for {n_var} {unknown_label}\n  {detail}",
            hint="a component may be missing (a fixed reference or a source that determines the "
                 "variables named), or a connector is left unconnected where it should not be",
            components=components, undetermined=tuple(under))
    raise StructurallySingularError(
        f"{context} is structurally singular: {n_eq} equations and {n_var} {unknown_label}, but they "
        f"cannot be paired\n  {detail}",
        hint="some equations constrain the same variables while others are left free; check the "
             "connections of the components named",
        components=components, undetermined=tuple(under))


@dataclass(frozen=True)
class Relaxation:
    """How a structurally singular discrete state was made solvable.

    Attributes
    ----------
    dropped : tuple of FlatEquation
        Equations left out: each constrains what the others already do
        (two stuck friction elements on one rigid shaft both say that its
        acceleration is zero).
    zeroed : tuple of str
        Flow variables set to zero in their place: the share of the
        holding force or torque that the equations leave open.
    """

    dropped: tuple[FlatEquation, ...]
    zeroed: tuple[str, ...]

    def __str__(self) -> str:
        left_out = "; ".join(f"{e.origin.component or '(model)'} ({e.origin.declared_in} eq. "
                             f"{e.origin.index + 1})" for e in self.dropped)
        return f"left out {left_out} and set {', '.join(self.zeroed)} = 0"


def relax_redundant(equations: Sequence[FlatEquation], incidence: Sequence[set[str]],
                    families: Sequence[str], droppable: Sequence[int], flows: Sequence[str]
                    ) -> tuple[tuple[FlatEquation, ...], Relaxation] | None:
    """Make a square but structurally singular system solvable, as Modelica tools do.

    When two elements lock the same motion (two stuck brakes on one rigid
    shaft), their two constraints say the same thing and the split of the
    holding torque is left open: the system is square but cannot be
    matched.  Each deficient pairing is repaired by leaving out one equation
    of the over-determined part that the discrete state selected
    (``droppable``, indices into ``equations``) and setting one flow
    variable of the under-determined part to zero: the one nearest to the
    dropped equation, ties broken by name (:func:`_share_to_zero`), so that
    the choice is a share of the redundant constraint itself and does not
    depend on the declaration order.  (The MSL Rotational
    Users Guide, RequirementsForSimulationTool, leaves the choice to the
    tool; a least-norm split gives the same mode decisions in the cases
    tried, see docs/hard-cases.md, case 5.)

    Returns the new equations and what was changed, or None when the system
    is not of this kind (not square, already matchable, or the deficiency
    lies elsewhere than in selected equations and flows).
    """
    if len(equations) != len(families):
        return None
    equations = list(equations)
    column = {f: j for j, f in enumerate(families)}
    # plain index lists (integers match deterministically, whatever the hash seed)
    G = [sorted({column[base_name(n)] for n in names if base_name(n) in column}) for names in incidence]
    flow_columns = [column[f] for f in flows if f in column]
    droppable = set(droppable)
    dropped: list[FlatEquation] = []
    zeroed: list[str] = []
    for _ in range(len(equations)):
        assign = maximum_matching(G, len(families))  # assign[j]: the equation of column j
        mate = [-1] * len(G)
        for j, i in enumerate(assign):
            if i != -1:
                mate[i] = j
        unmatched_eqs = [i for i in range(len(G)) if mate[i] == -1]
        if not unmatched_eqs:
            return (tuple(equations), Relaxation(tuple(dropped), tuple(zeroed))) if dropped else None
        unmatched_cols = [j for j in range(len(families)) if assign[j] == -1]
        # Dulmage-Mendelsohn: what alternating paths reach from the unmatched ones
        over = _reach(unmatched_eqs, lambda i: (assign[j] for j in G[i] if assign[j] != -1))
        readers: list[list[int]] = [[] for _ in families]
        for i, row in enumerate(G):
            for j in row:
                readers[j].append(i)
        under = _reach(unmatched_cols, lambda j: (mate[i] for i in readers[j] if mate[i] != -1))
        # an equation the matching left over is the natural one to drop; else the
        # last selected equation of the over-determined part (both deterministic)
        choices = [i for i in unmatched_eqs if i in droppable] or sorted(over & droppable)[-1:]
        if not choices:
            return None
        drop = choices[0]
        zero = _share_to_zero(G, readers, drop, [j for j in flow_columns if j in under], families,
                              matched=len(G) - len(unmatched_eqs))
        if zero is None:
            return None
        name = families[zero]
        dropped.append(equations[drop])
        zeroed.append(name)
        origin = equations[drop].origin
        equations[drop] = FlatEquation(real_symbol(name), Origin(
            origin.component, origin.component_class, "relaxation", origin.index,
            f"{name} = 0 (in place of a redundant constraint)"))
        G[drop] = [zero]
        droppable.discard(drop)
        flow_columns.remove(zero)
    return None


def _share_to_zero(G: list[list[int]], readers: list[list[int]], drop: int, candidates: list[int],
                   families: Sequence[str], matched: int) -> int | None:
    """The flow column to set to zero in place of equation ``drop``, or None.

    The share left open belongs to the redundant constraint itself: of the
    flows of the under-determined part, the one nearest to the dropped
    equation in the equation-variable graph (a torque of the locked loop,
    not a heat flow that merely depends on it through a loss power), ties
    broken by name, so that the choice does not depend on the order in which
    the model declares its components.  A candidate is taken only if the
    matching grows with it (the system gets one step closer to solvable).
    """
    distance = {}
    frontier, d = [drop], 0
    seen_eqs = {drop}
    while frontier:
        following = []
        for i in frontier:
            for j in G[i]:
                if j not in distance:
                    distance[j] = d
                    for k in readers[j]:
                        if k not in seen_eqs:
                            seen_eqs.add(k)
                            following.append(k)
        frontier, d = following, d + 1
    ordered = sorted(candidates, key=lambda j: (distance.get(j, len(G) + 1), families[j]))
    for zero in ordered:
        trial = list(G)
        trial[drop] = [zero]
        if sum(a != -1 for a in maximum_matching(trial, len(families))) > matched:
            return zero
    return None


def _reach(start: Sequence[int], step: Callable[[int], Iterable[int]]) -> set[int]:
    """Nodes reached from ``start`` by repeating ``step`` (iteratively)."""
    seen = set(start)
    frontier = list(start)
    while frontier:
        for node in step(frontier.pop()):
            if node not in seen:
                seen.add(node)
                frontier.append(node)
    return seen


def _components_of(origins, variables=()) -> tuple[str, ...]:
    """The components the origins and variables named belong to, in first-seen order."""
    paths = [o.component for o in origins] + [name.rpartition(".")[0] for name in variables]
    # (the model itself, '', is no component: hints declared on it would apply to every error)
    return tuple(dict.fromkeys(p for p in paths if p))


def _alternating_reach(start, graph, matching):
    seen = set(start)
    frontier = list(start)
    while frontier:
        node = frontier.pop()
        for nb in graph.neighbors(node):
            mate = matching.get(nb)
            if mate is not None and mate not in seen:
                seen.add(mate)
                frontier.append(mate)
    return seen


# --------------------------------------------------------------------------
# Index reduction and state selection
# --------------------------------------------------------------------------


@dataclass(eq=False)
class StructureMemo:
    """What structural analysis keeps for the other discrete states of one model."""

    parameter_values: dict | None = None  #: the values it is valid for (checked on use)
    parameters: set[str] = field(default_factory=set)
    values: dict = field(default_factory=dict)  #: parameter symbol -> sympy Float
    derivatives: dict = field(default_factory=dict)  #: residual -> its time derivative
    settled: dict = field(default_factory=dict)  #: residual -> the same, settled (functions.settle)
    shapes: dict = field(default_factory=dict)  #: shape -> time derivative (:func:`_differentiated`)

    def settle(self, residual: sp.Expr) -> sp.Expr:
        """``residual`` with functions of given derivatives replaced by their values (memoised)."""
        found = self.settled.get(residual)
        if found is None:
            found = self.settled[residual] = settle(residual)
        return found

    def bind(self, parameter_values: dict[str, float]) -> None:
        """Take ``parameter_values``, or check that they are the ones taken."""
        if self.parameter_values is None:
            self.parameter_values = dict(parameter_values)
            self.parameters = set(parameter_values)
            self.values = parameter_symbols(parameter_values)
        elif self.parameter_values != parameter_values:
            raise ValueError("analyse: this memo belongs to other parameter values")


class IndexTooHigh(Exception):
    """Pantelides differentiated an equation more often than a solvable system can need.

    Attributes
    ----------
    equation : int
        The original equation whose derivative chain grew too long.
    """

    def __init__(self, equation: int) -> None:
        super().__init__(equation)
        self.equation = equation


def pantelides(G: list[list[int]], A: list[int], add_derivative: Callable[[int], int],
               differentiate_equation: Callable[[int], list[int]]) -> list[int]:
    """Pantelides' index reduction on plain index lists.

    Parameters
    ----------
    G : list of list of int
        ``G[i]``: the variables of equation ``i``.  Extended in place with the
        differentiated equations.
    A : list of int
        ``A[j]``: the index of ``der(v_j)``, or -1.  Extended in place (by
        ``add_derivative``) as derivatives are added.
    add_derivative : callable
        ``add_derivative(j)`` adds ``der(v_j)`` (appending to ``A`` and setting
        ``A[j]``) and returns its index.
    differentiate_equation : callable
        ``differentiate_equation(i)`` adds the time derivative of equation
        ``i`` and returns its incidence (adding the variables it has).  The
        symbolic differentiation is the caller's: this function only sees
        index lists.

    Returns
    -------
    list of int
        ``B[i]``: the index of the derivative of equation ``i``, or -1.

    Raises
    ------
    IndexTooHigh
        When an equation would be differentiated more than ``len(G)`` times
        (more than the number of original equations): the index of a
        solvable system cannot be that high, so the system is structurally
        singular, and without this bound the algorithm never ends on it
        (the trap the design notes name; ModelingToolkit caps iterations too).

    References
    ----------
    .. [1] C. C. Pantelides, "The consistent initialization of
       differential-algebraic systems", SIAM J. Sci. Stat. Comput. 9(2),
       pp. 213-231, 1988.
    """
    B: list[int] = [-1] * len(G)
    assign: list[int] = [-1] * len(A)
    order: list[int] = [0] * len(G)  # how often each equation is a derivative of an original one
    limit = len(G)

    def highest(j: int) -> bool:
        return A[j] == -1

    for k in range(len(G)):
        i = k
        while True:
            if order[i] > limit:
                raise IndexTooHigh(k)
            visited_eqs: set[int] = set()
            visited_vars: set[int] = set()
            assign.extend([-1] * (len(A) - len(assign)))
            if augmenting_path(i, G, assign, highest, visited_eqs, visited_vars):
                break
            # differentiate the coloured part (step 3b): new variables, then new equations
            for j in sorted(visited_vars):
                if A[j] == -1:
                    add_derivative(j)
            assign.extend([-1] * (len(A) - len(assign)))
            for l in sorted(visited_eqs):
                B[l] = len(G)
                G.append(differentiate_equation(l))
                B.append(-1)
                order.append(order[l] + 1)
            assign.extend([-1] * (len(A) - len(assign)))
            for j in sorted(visited_vars):
                if assign[j] != -1:
                    assign[A[j]] = B[assign[j]]
            i = B[i]
    return B


def analyse(equations: Sequence[FlatEquation], variables: dict[str, FlatVariable],
            parameter_values: dict[str, float], context: str = "the model",
            memo: "StructureMemo | None" = None) -> StructuralResult:
    """Balance check, Pantelides, dummy derivatives and final matching.

    Parameters
    ----------
    equations : sequence of FlatEquation
        Continuous equations (after alias elimination).
    variables : dict
        The continuous unknowns left (name -> FlatVariable, attributes merged).
    parameter_values : dict
        For structural zeros.
    memo : StructureMemo, optional
        Shared by calls with the same parameter values (the discrete states
        of one model): keeps the time derivative of each equation differentiated.
    """
    memo = StructureMemo() if memo is None else memo
    memo.bind(parameter_values)
    parameters, values = memo.parameters, memo.values
    derivative_of = memo.derivatives
    order_of = {name: k for k, name in enumerate(variables)}

    # variable list V with derivative chains: A[j] = index of der(V[j]) or -1
    V: list[str] = []
    index: dict[str, int] = {}
    A: list[int] = []

    def add_var(name: str) -> int:
        if name in index:
            return index[name]
        base = base_name(name)
        if base not in variables:
            raise StructuralError(f"{context}: {name} is neither a variable nor a parameter")
        if derivative_order(name) > 0:
            lower = add_var(parse(name).lower)
        else:
            lower = -1
        index[name] = len(V)
        V.append(name)
        A.append(-1)
        if lower >= 0:
            A[lower] = index[name]
        return index[name]

    eqs: list[FlatEquation] = list(equations)
    # the incidence is that of the settled residuals: a function with given derivatives
    # depends on the one signal it evaluates to (functions.settle)
    incidence_names = [_incidence(memo.settle(eq.residual), values) for eq in eqs]
    for names in incidence_names:
        for name in sorted(names, key=lambda n: (order_of.get(base_name(n), 0), derivative_order(n))):
            add_var(name)
    families = [n for n in variables]
    check_balance(eqs, incidence_names, families, context)

    G: list[list[int]] = [sorted(index[n] for n in names) for names in incidence_names]
    parent_eq: list[int] = [-1] * len(eqs)

    def add_derivative(j: int) -> int:
        return add_var(der_name(V[j]))

    def differentiate_equation(l: int) -> list[int]:
        # the time derivative of equation l becomes a new equation; its incidence
        derivative = derivative_of.get(eqs[l].residual)
        if derivative is None:
            derivative = derivative_of[eqs[l].residual] = _differentiated(eqs[l].residual, parameters,
                                                                          memo.shapes)
        origin = eqs[l].origin
        new_origin = Origin(origin.component, origin.component_class, origin.declared_in,
                            origin.index, functools.partial(_derivative_text, origin))
        eqs.append(FlatEquation(derivative, new_origin))
        parent_eq.append(l)
        names = _incidence(memo.settle(derivative), values)
        for name in sorted(names, key=lambda n: (derivative_order(n), n)):
            add_var(name)
        return sorted(index[n] for n in names)

    try:
        B = pantelides(G, A, add_derivative, differentiate_equation)
    except IndexTooHigh as exc:
        origin = eqs[exc.equation].origin
        raise StructurallySingularError(
            f"{context}: index reduction differentiated {origin} more than {len(equations)} times "
            f"without finding a solvable system",
            hint="the equations do not determine some variables whatever their derivatives: a "
                 "quantity may be fixed twice, or a coefficient that is zero (a zero parameter) may "
                 "have removed the only term that determined a variable",
            components=_components_of([origin])) from None

    dummies = _select_dummy_derivatives(eqs, G, A, V, B, parent_eq, variables, order_of, context)

    states = [V[j] for j in range(len(V)) if A[j] != -1 and V[A[j]] not in dummies]
    states.sort(key=lambda n: (order_of[base_name(n)], derivative_order(n)))
    derivatives = [der_name(s) for s in states]
    state_set = set(states)
    unknowns = [v for v in V if v not in state_set]
    unknowns.sort(key=lambda n: (order_of[base_name(n)], derivative_order(n)))
    u_index = {n: k for k, n in enumerate(unknowns)}
    incidence = [tuple(sorted(u_index[V[j]] for j in G[i] if V[j] in u_index)) for i in range(len(eqs))]

    if len(eqs) != len(unknowns):
        raise StructuralError(f"{context}: after index reduction {len(eqs)} equations for "
                              f"{len(unknowns)} unknowns (internal inconsistency)")
    assign_u = maximum_matching(incidence, len(unknowns))
    if any(a == -1 for a in assign_u):
        # not perfect: the equation-ordered matching names the culprits the way
        # the model reads (the original equations are matched first)
        assign_u = priority_matching(incidence, len(unknowns), range(len(eqs)))
    if any(a == -1 for a in assign_u):
        missing = [unknowns[j] for j, a in enumerate(assign_u) if a == -1]
        matched = set(assign_u)
        lonely = [eqs[i].origin for i in range(len(eqs)) if i not in matched]
        raise StructurallySingularError(
            f"{context}: after state selection no equation is left for {', '.join(missing[:8])}; "
            f"unmatched equations: " + "; ".join(str(o) for o in lonely[:5]),
            hint="the states chosen may be constrained twice; try state_select on the variables named",
            components=_components_of(lonely, missing))
    matching = [-1] * len(eqs)
    for j, i in enumerate(assign_u):
        matching[i] = j
    differentiated = tuple((i, parent_eq[i]) for i in range(len(eqs)) if parent_eq[i] >= 0)
    # no stage after this one differentiates: the later ones get the settled equations
    eqs = [eq if (r := memo.settle(eq.residual)) is eq.residual else FlatEquation(r, eq.origin) for eq in eqs]
    return StructuralResult(tuple(eqs), tuple(states), tuple(derivatives), tuple(unknowns),
                            tuple(matching), tuple(incidence), differentiated,
                            tuple(sorted(dummies, key=lambda n: (order_of[base_name(n)], n))))


def _select_dummy_derivatives(eqs, G, A, V, B, parent_eq, variables, order_of, context) -> set[str]:
    """Mattsson-Söderlind: pick, level by level, derivatives to make algebraic."""
    level_eqs = [i for i in range(len(eqs)) if parent_eq[i] >= 0 and B[i] == -1]
    dummies: set[str] = set()
    candidates: list[int] | None = None
    while level_eqs:
        if candidates is None:
            cols = sorted({j for i in level_eqs for j in G[i]
                           if A[j] == -1 and derivative_order(V[j]) > 0})
        else:
            cols = candidates
        # Most eager to become a dummy first: low state_select; then higher
        # derivative order (keep w as a state rather than der(phi)); then the
        # later-declared variable, so the first inertia of a chain keeps its states.
        def eagerness(j: int):
            base = base_name(V[j])
            return (int(variables[base].state_select), -derivative_order(V[j]), -order_of[base], V[j])

        ordered = sorted(cols, key=eagerness)
        row_pos = {i: r for r, i in enumerate(level_eqs)}
        col_set = set(ordered)
        # incremental bipartite matching, columns in preference order
        col_adj = {j: [] for j in ordered}
        for i in level_eqs:
            for j in G[i]:
                if j in col_set:
                    col_adj[j].append(row_pos[i])
        row_mate = [-1] * len(level_eqs)
        chosen = []
        for j in ordered:
            if len(chosen) == len(level_eqs):
                break
            if augmenting_path(j, _ColumnView(col_adj), row_mate, lambda r: True, set(), set()):
                chosen.append(j)
        if len(chosen) < len(level_eqs):
            names = ", ".join(str(eqs[i].origin) for i in level_eqs[:5])
            raise StructurallySingularError(
                f"{context}: cannot select states for the constraint equations {names}",
                hint="the constraints may be redundant (e.g. a closed loop of rigid connections)",
                components=_components_of([eqs[i].origin for i in level_eqs]))
        for j in chosen:
            # ``always`` asks for the variable itself to be a state: only a dummy first
            # derivative denies it.  A dummy der(der(x)) makes der(x) algebraic, while x
            # stays a state (its derivative der(x) is then computed, not integrated).
            if (derivative_order(V[j]) == 1
                    and variables[base_name(V[j])].state_select == StateSelect.always):
                raise StructuralError(
                    f"{context}: {base_name(V[j])} has state_select=always but cannot be a state "
                    f"because of the constraint {eqs[level_eqs[0]].origin}",
                    hint="lower its state_select or remove the constraint",
                    components=_components_of([eqs[level_eqs[0]].origin], [base_name(V[j])]))
            dummies.add(V[j])
        # one level down: the equations these were differentiated from, if
        # they are derivatives themselves; candidates: integrals of the chosen
        level_eqs = [parent_eq[i] for i in level_eqs if parent_eq[parent_eq[i]] >= 0]
        integral = {A[k]: k for k in range(len(V)) if A[k] != -1}
        candidates = sorted(integral[j] for j in chosen if j in integral
                            and derivative_order(V[integral[j]]) > 0)
    return dummies


class _ColumnView:
    """Adapter so :func:`augmenting_path` matches columns (as 'equations') to rows."""

    def __init__(self, adjacency: dict[int, list[int]]) -> None:
        self.adjacency = adjacency

    def __getitem__(self, j: int) -> list[int]:
        return self.adjacency[j]
