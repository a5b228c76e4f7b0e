"""Independent clusters: one system per cluster and per cluster mode, composed at run time.

Two parts of a model that share no continuous variable — two drive trains
side by side, or N friction units driven each by its own source — are
independent: the equations of one never read a variable of the other, so
the discrete state of one cannot change the equations, the matching, the
index reduction or the generated code of the other.  Compiling the whole
model for every combination of their modes costs the product of their mode
counts; compiling each cluster for its own modes costs their sum.

:func:`find_clusters` finds the clusters as the connected components of the
model's incidence taken over every discrete state at once (an equation
``tau = If(locked, sa, mu*fn)`` links ``tau`` with ``sa`` *and* ``fn``): a
union–find over the variables of every continuous equation, every initial
equation and both sides of every relation.  Each cluster has its own
selectors (the discrete symbols its equations read): its key is the
projection of the model's key on them.  :class:`ComposedSystem` puts the
compiled systems of the clusters together behind the interface of one
:class:`~acausal.compiler.modes.ModeSystem`; the state vector is the
clusters' states in cluster order.

Discrete equations are not split: event iteration runs over the whole
discrete part, as before, and only the clusters whose key changed need a
system they have not compiled yet.  A cluster is never cut at a state: two
shafts joined by a spring form one cluster (cutting there needs the states
of one cluster as inputs of the other, and index reduction may reach across).

References
----------
.. [1] R. E. Tarjan, "Efficiency of a good but not linear set union
   algorithm", J. ACM 22(2), 1975 (union–find with path compression).
"""

from __future__ import annotations

import functools
from dataclasses import dataclass, field
from itertools import chain
from typing import Any, Callable, Mapping, Sequence

import numpy as np

from ..names import is_derivative, parse
from .modes import AliasPlan, ModeSystem, RelaxedConstraints
from .partition import PartitionedModel

__all__ = ["Cluster", "Clustering", "ComposedSystem", "ComposedInitialSystem", "find_clusters", "compose"]


@dataclass(frozen=True)
class Cluster:
    """One independent part of a model.

    Attributes
    ----------
    index : int
        Position in :attr:`Clustering.clusters` (ordered by first equation).
    equations, initial_equations : tuple of int
        Positions in the partitioned model's continuous and initial equations.
    variables : tuple of str
        Its continuous variables, in the flat model's order.
    selectors : tuple of int
        Positions in the model's selectors of the discrete symbols its
        equations read: its key is the model's key at these positions.
    relations : tuple of int
        The relations whose crossing functions it computes (those on its
        variables; relations of time and parameters only go to cluster 0).
    parameters : tuple of str
        The parameters its equations and relations read, in the model's order.
    """

    index: int
    equations: tuple[int, ...]
    initial_equations: tuple[int, ...]
    variables: tuple[str, ...]
    selectors: tuple[int, ...]
    relations: tuple[int, ...]
    parameters: tuple[str, ...]

    def project(self, key: tuple) -> tuple:
        """This cluster's part of the model's key."""
        return tuple(key[i] for i in self.selectors)


@dataclass(frozen=True)
class Clustering:
    """The output of :func:`find_clusters`: the model's independent parts."""

    clusters: tuple[Cluster, ...]

    def __len__(self) -> int:
        return len(self.clusters)

    @functools.cached_property
    def crossing_gather(self) -> tuple[int, ...]:
        """The model's crossing vector from the clusters' values laid end to end
        (each relation gives its lhs and rhs): ``model[i] = parts[gather[i]]``."""
        positions = [2 * k + side for c in self.clusters for k in c.relations for side in (0, 1)]
        gather = [0] * len(positions)
        for p, where in enumerate(positions):
            gather[where] = p
        return tuple(gather)


class _UnionFind:
    """Disjoint sets of names (path halving, union by size); iterative, as networkx's."""

    def __init__(self) -> None:
        self.parent: dict[str, str] = {}
        self.size: dict[str, int] = {}

    def find(self, x: str) -> str:
        parent = self.parent
        if x not in parent:
            parent[x] = x
            self.size[x] = 1
            return x
        while parent[x] != x:
            parent[x] = parent[parent[x]]
            x = parent[x]
        return x

    def union(self, names) -> str | None:
        root = None
        for name in names:
            r = self.find(name)
            if root is None:
                root = r
            elif r != root:
                if self.size[r] > self.size[root]:
                    root, r = r, root
                self.parent[r] = root
                self.size[root] += self.size[r]
        return root


def find_clusters(partitioned: PartitionedModel, continuous: Mapping[str, Any]) -> Clustering:
    """The independent clusters of ``partitioned`` (see the module docstring).

    Parameters
    ----------
    partitioned : PartitionedModel
    continuous : mapping
        The continuous variables of the flat model, in its order.
    """
    parameters = set(partitioned.flat.parameter_values)
    selector_position = {s: k for k, s in enumerate(partitioned.selectors)}
    sets = _UnionFind()
    base_of: dict[str, str | None] = {}  # symbol name -> its continuous variable, or None

    def variables_of(symbols) -> list[str]:
        out = []
        for s in symbols:
            name = s.name
            base = base_of.get(name, "")
            if base == "":
                base = parse(name).base if is_derivative(name) else name
                base = base_of[name] = base if base in continuous else None
            if base is not None:
                out.append(base)
        return out

    # (the union order does not matter: the clusters are sorted below)
    equation_symbols = [eq.residual.free_symbols for eq in partitioned.equations]
    initial_symbols = [eq.residual.free_symbols for eq in partitioned.initial_equations]
    relation_symbols = [r.lhs.free_symbols | r.rhs.free_symbols for r in partitioned.relations]
    equation_roots = [sets.union(variables_of(fs)) for fs in equation_symbols]
    initial_roots = [sets.union(variables_of(fs)) for fs in initial_symbols]
    relation_roots = [sets.union(variables_of(fs)) for fs in relation_symbols]

    # clusters in the order of their first equation (deterministic), then of
    # variables no equation reads (structurally an error, reported by the stages)
    order: dict[str, int] = {}
    for root in equation_roots:
        if root is not None:
            order.setdefault(sets.find(root), len(order))
    for name in continuous:
        order.setdefault(sets.find(name), len(order))
    if not order:
        order[""] = 0

    def cluster_of(root) -> int:
        return 0 if root is None else order[sets.find(root)]

    n = len(order)
    equations: list[list[int]] = [[] for _ in range(n)]
    initial: list[list[int]] = [[] for _ in range(n)]
    relations: list[list[int]] = [[] for _ in range(n)]
    variables: list[list[str]] = [[] for _ in range(n)]
    for i, root in enumerate(equation_roots):
        equations[cluster_of(root)].append(i)
    for i, root in enumerate(initial_roots):
        initial[cluster_of(root)].append(i)
    for k, root in enumerate(relation_roots):
        relations[cluster_of(root)].append(k)
    for name in continuous:
        variables[order[sets.find(name)]].append(name)

    symbols: list[set] = []
    for c in range(n):
        found: set = set()
        for i in equations[c]:
            found |= equation_symbols[i]
        for i in initial[c]:
            found |= initial_symbols[i]
        for k in relations[c]:
            found |= relation_symbols[k]
        symbols.append(found)

    # A part no discrete symbol reaches (a fixed support, a source with its
    # sink) has one system whatever the discrete state: it joins the first part
    # that has discrete states, so that a model with one such part is not split.
    switching = [c for c in range(n) if any(s in selector_position for s in symbols[c])]
    into = switching[0] if switching else 0
    kept = set(switching) | {into}
    groups = [c for c in range(n) if c in kept]
    for c in range(n):
        if c not in kept:
            equations[into] += equations[c]
            initial[into] += initial[c]
            relations[into] += relations[c]
            variables[into] += variables[c]
            symbols[into] |= symbols[c]
    variable_order = {name: k for k, name in enumerate(continuous)}
    parameter_order = {p.name: k for k, p in enumerate(partitioned.flat.parameters)}
    clusters = []
    for c in groups:
        chosen = sorted(selector_position[s] for s in symbols[c] if s in selector_position)
        used = sorted((s.name for s in symbols[c] if s.name in parameters), key=parameter_order.__getitem__)
        clusters.append(Cluster(len(clusters), tuple(sorted(equations[c])), tuple(sorted(initial[c])),
                                tuple(sorted(variables[c], key=variable_order.__getitem__)),
                                tuple(chosen), tuple(sorted(relations[c])), tuple(used)))
    return Clustering(tuple(clusters))


# ---------------------------------------------------------------------------
# Composition
# ---------------------------------------------------------------------------


@dataclass(frozen=True)
class ComposedSystem:
    """The systems of a model's clusters for one discrete state, as one system.

    It has the interface the runtime uses of a
    :class:`~acausal.compiler.modes.ModeSystem`: ``states`` (the clusters'
    states in cluster order), ``unknowns``, ``derivatives``, ``crossings``
    (every relation, in the model's order), ``outputs``, ``alias_plan``,
    ``values``; :attr:`parts` are the clusters' own systems, each with its
    stages' outputs for inspection.
    """

    key: tuple
    #: the discrete state in words, or a function giving it (made when first asked for)
    describe: Any = field(repr=False, compare=False)
    parts: tuple[ModeSystem, ...]
    derivatives: Any = field(repr=False, compare=False)
    crossings: Any = field(repr=False, compare=False)
    outputs: Any = field(repr=False, compare=False)
    #: the model's crossing vector from the parts' values laid end to end:
    #: ``model[i] = parts[crossing_gather[i]]``
    crossing_gather: tuple[int, ...] = field(default=(), repr=False)
    #: how many crossing values each part gives
    crossing_counts: tuple[int, ...] = field(default=(), repr=False)
    passes: tuple[tuple[str, float], ...] = ()
    shares: tuple | None = None
    #: the relations of each part (the model's indices)
    part_relations: tuple[tuple[int, ...], ...] = field(default=(), repr=False)
    #: what is made on demand: the description, and :meth:`crossings_for`'s functions
    _made: dict = field(default_factory=dict, repr=False, compare=False)

    # The names are put together from the parts when asked for, not kept: a storm
    # of events visits thousands of discrete states, each composed of all parts.

    @property
    def description(self) -> str:
        """The discrete state in words."""
        found = self._made.get("description")
        if found is None:
            found = self._made["description"] = self.describe if isinstance(self.describe, str) else self.describe()
        return found

    # ... and kept once asked for (in _made, which crossings_for keeps bounded): the run
    # asks for the states of the system in force some fifteen times an event
    @property
    def states(self) -> tuple[str, ...]:
        found = self._made.get("states")
        if found is None:
            found = self._made["states"] = tuple(chain.from_iterable([p.states for p in self.parts]))
        return found

    @property
    def unknowns(self) -> tuple[str, ...]:
        found = self._made.get("unknowns")
        if found is None:
            found = self._made["unknowns"] = tuple(chain.from_iterable([p.unknowns for p in self.parts]))
        return found

    @property
    def alias_plan(self) -> AliasPlan:
        found = self._made.get("alias_plan")
        if found is None:
            found = self._made["alias_plan"] = tuple(chain.from_iterable([p.alias_plan for p in self.parts]))
        return found

    def crossings_for(self, relations: tuple[int, ...]) -> Callable:
        """A ``crossings`` that computes only the values of ``relations`` (the model's
        indices; the other values are NaN): it calls the parts that own them only."""
        found = self._made.get(relations)
        if found is not None:
            return found
        if len(self._made) >= 64:  # bounded: keep the description and names, drop the functions
            for k in [k for k in self._made if k not in ("description", "states", "unknowns", "alias_plan")]:
                del self._made[k]
        owner = {k: p for p, rels in enumerate(self.part_relations) for k in rels}
        slices = _state_slices(self.parts)
        calls = []
        for p in sorted({owner[k] for k in relations}):
            positions = [2 * k + side for k in self.part_relations[p] for side in (0, 1)]
            calls.append((self.parts[p].crossings, slices[p], positions))
        empty = [float("nan")] * (2 * sum(len(r) for r in self.part_relations))

        def crossings(t, x):
            out = empty.copy()
            for f, sl, positions in calls:
                for where, value in zip(positions, f(t, x[sl])):
                    out[where] = value
            return out

        self._made[relations] = crossings
        return crossings

    @property
    def seconds(self) -> float:
        """Seconds spent composing (the parts keep their own pass logs)."""
        return sum(s for _, s in self.passes)

    @property
    def timings(self) -> dict[str, float]:
        return dict(self.passes)

    @property
    def sources(self) -> tuple[str, ...]:
        """The generated source of every part."""
        return tuple(p.code.source for p in self.parts)

    @property
    def derivative_names(self) -> tuple[str, ...]:
        return tuple(d for p in self.parts for d in p.derivative_names)

    @property
    def relaxed(self) -> RelaxedConstraints | None:
        """What the parts' systems of this state left out (a part that constrains one
        motion twice, :class:`~acausal.compiler.modes.RelaxedConstraints`), as one; None
        when none did."""
        found = [p.relaxed for p in self.parts if p.relaxed is not None]
        if not found:
            return None
        return RelaxedConstraints(*(tuple(chain.from_iterable(getattr(r, f) for r in found))
                                    for f in ("components", "left_out", "zeroed")))

    def values(self, t: float, x) -> dict[str, float]:
        """Continuous variables and derivatives at ``(t, x)`` (aliases: see :attr:`alias_plan`)."""
        out = dict(zip(self.states, map(float, x)))
        out.update(zip(self.unknowns, self.outputs(t, x)))
        return out

    def vectorised(self, name: str) -> Callable | None:
        """The numpy form of ``crossings`` or ``outputs`` (see
        :meth:`~acausal.compiler.modes.ModeSystem.vectorised`), composed from the
        parts' once per system; None if a part that has values lacks one."""
        found = self._made.get(("vectorised", name))
        if found is None:
            found = self._made[("vectorised", name)] = (
                self.compose_vectorised(name, [p.vectorised(name) for p in self.parts]) or False)
        return found or None

    def compose_vectorised(self, name: str, functions: Sequence[Callable | None]) -> Callable | None:
        """The numpy form of ``crossings`` or ``outputs`` from the parts' numpy forms
        (``functions``, one per part; None if a part that has values lacks one)."""
        slices = _state_slices(self.parts)
        counts = self.crossing_counts if name == "crossings" else [len(p.unknowns) for p in self.parts]
        chosen = [(f, sl) for f, sl, k in zip(functions, slices, counts) if k]
        if any(f is None for f, _ in chosen):
            return None
        gather = self.crossing_gather
        order = (np.array(gather, dtype=int) if name == "crossings" and list(gather) != list(range(len(gather)))
                 else None)

        def many(t, X):
            blocks = [np.asarray(f(t, X[sl]), dtype=float) for f, sl in chosen]
            stacked = np.concatenate(blocks, axis=0) if blocks else np.empty((0, np.size(t)))
            return stacked if order is None else stacked[order]

        return many


@dataclass(frozen=True)
class ComposedInitialSystem:
    """The initialization problems of a model's clusters for one discrete state, as one.

    ``relaxed`` and ``from_start`` are the parts' (see
    :class:`~acausal.compiler.initial.InitialSystem`), in cluster order.
    """

    key: tuple
    parts: tuple
    unknowns: tuple[str, ...]
    relaxed: tuple[tuple[str, float], ...]
    outputs: Any = field(default=None, repr=False, compare=False)
    from_start: tuple[tuple[str, float], ...] = ()

    @property
    def seconds(self) -> float:
        """0: the parts keep their own time (parts shared between discrete states
        would otherwise count more than once)."""
        return 0.0

    @property
    def sources(self) -> tuple[str, ...]:
        return tuple(p.code.source for p in self.parts)


def _state_slices(parts: Sequence[ModeSystem]) -> list[slice]:
    out, start = [], 0
    for p in parts:
        out.append(slice(start, start + len(p.states)))
        start += len(p.states)
    return out


def compose(key: tuple, description, parts: Sequence[ModeSystem],
            clustering: Clustering) -> ComposedSystem:
    """One system from the clusters' systems ``parts`` (in cluster order) for ``key``
    (``description``: the state in words, or a function giving it when first asked for)."""
    parts = tuple(parts)
    slices = _state_slices(parts)
    derivative_calls = [(p.derivatives, sl) for p, sl in zip(parts, slices) if p.states]
    output_calls = [(p.outputs, sl) for p, sl in zip(parts, slices) if p.unknowns]
    crossing_calls = [(p.crossings, sl) for p, sl, c in zip(parts, slices, clustering.clusters) if c.relations]
    # the parts give their relations' values in cluster order; the model's order is
    # by relation index, two values (lhs, rhs) each
    gather = clustering.crossing_gather
    ordered = gather != tuple(range(len(gather)))

    def derivatives(t, x):
        out: list = []
        for f, sl in derivative_calls:
            out.extend(f(t, x[sl]))
        return out

    def outputs(t, x):
        out: list = []
        for f, sl in output_calls:
            out.extend(f(t, x[sl]))
        return out

    def crossings(t, x):
        out: list = []
        for f, sl in crossing_calls:
            out.extend(f(t, x[sl]))
        return [out[i] for i in gather] if ordered else out

    counts = tuple(2 * len(c.relations) for c in clustering.clusters)
    return ComposedSystem(key, description, parts, derivatives, crossings,
                          outputs, gather, counts, part_relations=tuple(c.relations for c in clustering.clusters))


def compose_initial(key: tuple, parts: Sequence) -> ComposedInitialSystem:
    """One initialization problem from the clusters' problems ``parts``."""
    parts = tuple(parts)
    calls = [p.outputs for p in parts if p.unknowns]

    def outputs(t, x):
        out: list = []
        for f in calls:
            out.extend(f(t, x))
        return out

    return ComposedInitialSystem(key, parts, tuple(u for p in parts for u in p.unknowns),
                                 tuple(r for p in parts for r in p.relaxed), outputs,
                                 tuple(s for p in parts for s in p.from_start))
