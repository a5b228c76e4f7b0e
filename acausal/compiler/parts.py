"""Independent parts of a hybrid model, compiled apart and composed per discrete state.

A model made of parts that share no variable (N drive units side by side,
:mod:`~acausal.compiler.clusters`) compiles one system per part and part
mode, and composes the parts' systems into the system of a discrete state
of the whole model (a :class:`~acausal.compiler.clusters.ComposedSystem`).
Each part has its own :class:`~acausal.compiler.cache.ModelCache` and output
demand; its systems are loaded from, and saved to, the persistent cache
under entries of their own.

:class:`PartSystems` is the part of :class:`~acausal.compiler.translate.Translation`
that does this; it reads the translation's ``clustering``, ``flat``,
``partitioned``, ``demand`` and keeps ``parts``, ``initial_parts`` and
``_cluster_caches``.

:meth:`PartSystems.part_models` offers each part as a compiled model of its
own (:class:`PartModel`: the runtime's ``CompiledModel`` over the part's
systems, relations, discrete variables and discrete program) when the parts
are independent in their discrete part too, so that the runtime can
integrate each part with a solver of its own
(:mod:`acausal.runtime.part_runs`); otherwise it says why not.
"""

from __future__ import annotations

import dataclasses
import functools
import time as _time
from typing import Any, Callable

import numpy as np

from ..errors import StructuralError
from ..language import time as model_time
from ..names import is_derivative, parse, pre_name, relation_name
from .cache import ModelCache
from .clusters import Cluster, ComposedInitialSystem, ComposedSystem, compose
from .compiled import DiscreteProgram
from .flatten import start_parameter
from .initial import InitialSystem, compile_initial_system
from .modes import ModeSystem, PassLog, brief_description, describe_key, shared_system
from .part_shapes import part_shape, renamed_initial, renamed_mode, twin_of
from .rebinding import _bind_mode

__all__ = ["PartModel", "PartSystem", "PartSystems"]


class PartSystems:
    """Compiling and composing the systems of a model's independent parts (see the module docstring)."""

    def _composed(self, key: tuple) -> ComposedSystem | None:
        """The clusters' systems of ``key`` put together (None: compile the whole model)."""
        try:
            parts = [self._part(c, key) for c in self.clustering.clusters]
        except StructuralError:
            # A cluster's equations cannot be solved: the whole model's message names
            # the failure as it does without clusters (and the whole model is compiled
            # from now on, should it succeed after all; the composed systems go).
            self.clustering = None
            for table in (self.systems, self.initial_systems):
                for k in [k for k, v in table.items() if isinstance(v, (ComposedSystem, ComposedInitialSystem))]:
                    del table[k]
            return None
        t0 = _time.perf_counter()
        composed = compose(key, functools.partial(self.describe, key), parts, self.clustering)
        return dataclasses.replace(composed, passes=(("compose", _time.perf_counter() - t0),))

    def part_models(self) -> "tuple[tuple[PartModel, ...], str]":
        """Each independent part as a compiled model of its own, or ``((), why not)``.

        The parts are offered apart when nothing of the discrete part links two
        of them (see :func:`_part_models`); made once per clustering.
        """
        found = getattr(self, "_part_models_made", None)
        if found is None or found[0] is not self.clustering:
            found = self._part_models_made = (self.clustering, _part_models(self))
        return found[1]

    def _cluster_cache(self, cluster: Cluster) -> ModelCache:
        found = self._cluster_caches.get(cluster.index)
        if found is None:
            # the cluster's parameters and the tunable start values of its variables
            starts = [start_parameter(n) for n in cluster.variables]
            found = self._cluster_caches[cluster.index] = self.cache.for_cluster(
                (*cluster.parameters, *(n for n in starts if n in self.cache.parameters.values)))
        return found

    def _cluster_demand(self, cluster: Cluster) -> frozenset[str] | None:
        if self.demand is None:
            return None
        own = set(cluster.variables)
        return frozenset(n for n in self.demand if (parse(n).base if is_derivative(n) else n) in own)

    def _part(self, cluster: Cluster, key: tuple) -> ModeSystem:
        """The system of ``cluster`` for the model's discrete state ``key`` (built on first use)."""
        cache = self._cluster_cache(cluster)
        subkey = cluster.project(key)
        return self._made(self.parts, (cluster.index, subkey), f"part {cluster.index} {subkey!r}", cache,
                          self._load_mode, lambda: self._build_part(cluster, key, cache), self._save_mode)

    def _made(self, table: dict, key, entry: str, cache: ModelCache, load, build, save):
        """``table[key]``: kept, else loaded from disk, else built (and stored on disk)."""
        found = table.get(key)
        if found is not None:
            return found
        system = load(entry, cache)
        if system is None:
            system = build()
            save(entry, system, cache)
        self._store(table, key, system)
        return system

    def _build_part(self, cluster: Cluster, key: tuple, cache: ModelCache, rename: bool = True) -> ModeSystem:
        """Compile (or rebind, or share, or rename) the system of ``cluster`` for ``key``
        (``rename``: False when its stages are needed, see :meth:`_build_initial_part`)."""
        subkey = cluster.project(key)
        rebound = self._rebind_part(cluster, key, cache)
        if rebound is not None:
            self._add_shape(cluster, key, subkey, rebound, cache)
            return rebound
        selectors = [self.selectors[i] for i in cluster.selectors]
        description = describe_key(selectors, subkey, self._relation_texts())
        if rename:
            renamed = self._renamed_part(cluster, subkey, description, cache)
            if renamed is not None:
                return renamed
        context = f"{self.flat.name} [cluster {cluster.index + 1}: {brief_description(description)}]"
        passes = PassLog()
        with passes.run("specialise"):
            sources = [self.partitioned.equations[i] for i in cluster.equations]
            equations = self.specialise(key, sources)
        signature = (cluster.index, tuple(eq.residual for eq in equations))
        twin = self._by_equations.get(signature)
        if twin is not None:
            system = shared_system(twin, subkey, description, context, passes)
        else:
            # (a state that constrains one motion twice is relaxed in a part as in the whole model)
            system = self._by_equations[signature] = self._compiled_or_relaxed(
                subkey, description, context, equations, passes, sources,
                {n: self.continuous[n] for n in cluster.variables}, cache, self._cluster_demand(cluster),
                cluster.relations)
        self._add_shape(cluster, key, subkey, system, cache)
        return system

    def _add_shape(self, cluster: Cluster, key: tuple, subkey: tuple, system: ModeSystem,
                   cache: ModelCache) -> None:
        """The first system of its shape and state (with its stages): the parts of that
        shape are renamed from it."""
        found = self._cluster_shape(cluster, cache) if self.options.part_shapes else None
        if found is not None and system.relaxed is None and system.structure is not None:
            self._by_shape.setdefault((found[0], subkey), (cluster.index, key, found[1:], system))

    def _renamed_part(self, cluster: Cluster, subkey: tuple, description: str,
                      cache: ModelCache) -> ModeSystem | None:
        """The system of an earlier part of ``cluster``'s shape in state ``subkey``, renamed
        and bound to this part's parameters (:mod:`~acausal.compiler.part_shapes`); None
        when there is none, or it does not serve this part."""
        if not self.options.part_shapes:
            return None
        started = _time.perf_counter()
        found = self._cluster_shape(cluster, cache)
        earlier = None if found is None else self._by_shape.get((found[0], subkey))
        if earlier is None or earlier[0] == cluster.index:
            return None
        renaming = twin_of(earlier[2], earlier[0], earlier[1], earlier[3], found[1:], cluster.index,
                           self._renamings)
        system = renamed_mode(renaming, subkey, description, (), cache.parameters, started)
        if system is not None:
            self._renamed[(cluster.index, subkey)] = renaming
        return system

    def _cluster_shape(self, cluster: Cluster, cache: ModelCache):
        """:func:`~acausal.compiler.part_shapes.part_shape` of ``cluster`` (made once; None:
        it is not renamed)."""
        if cluster.index in self._cluster_shapes:
            return self._cluster_shapes[cluster.index]
        partitioned = self.partitioned
        relations = [(r.op, r.lhs, r.rhs) for r in (partitioned.relations[k] for k in cluster.relations)]
        continuous = self.continuous
        attributes = tuple((v.kind, v.start, v.fixed, v.nominal, v.state_select)
                           for v in (continuous[n] for n in cluster.variables))
        names = cache.parameters.names
        values = cache.parameters.values
        found = self._cluster_shapes[cluster.index] = part_shape(
            [partitioned.equations[i].residual for i in cluster.equations],
            [partitioned.initial_equations[i].residual for i in cluster.initial_equations], relations,
            cluster.variables, names, [values[n] == 0 for n in names],
            [self.selectors[i] for i in cluster.selectors], self._cluster_demand(cluster), attributes)
        return found

    def _relation_texts(self) -> dict[str, str]:
        """Relation indicator name -> its text (for descriptions), made once."""
        found = getattr(self, "_relation_texts_made", None)
        if found is None or found[0] is not self.partitioned:
            found = self._relation_texts_made = (self.partitioned,
                                                 {r.symbol.name: r.text for r in self.partitioned.relations})
        return found[1]

    def _rebind_part(self, cluster: Cluster, key: tuple, cache: ModelCache) -> ModeSystem | None:
        """The part compiled by :attr:`rebound_from`, bound to this one's parameters."""
        source_translation = self.rebound_from
        if source_translation is None or source_translation.clustering is not self.clustering:
            return None
        source = source_translation._part(cluster, key)
        if source.shape_of is not None:
            return None  # renamed there: renamed here too, from this translation's part of its shape
        if source.structure is None:  # loaded from disk: compiled once, then every value rebinds
            source = source_translation._build_part(cluster, key, source_translation._cluster_cache(cluster))
            source_translation._store(source_translation.parts, (cluster.index, cluster.project(key)), source)
        if not self._guards_hold(source.algebraic) or not self._guesses_hold(source):
            return None
        return _bind_mode(source, cache.parameters)

    def _initial_part(self, cluster: Cluster, key: tuple) -> InitialSystem:
        """The initialization problem of ``cluster`` for ``key`` (built on first use)."""
        cache = self._cluster_cache(cluster)
        subkey = cluster.project(key)
        return self._made(self.initial_parts, (cluster.index, subkey), f"initial-part {cluster.index} {subkey!r}",
                          cache, self._load_initial, lambda: self._build_initial_part(cluster, key, cache),
                          self._save_initial)

    def _build_initial_part(self, cluster: Cluster, key: tuple, cache: ModelCache) -> InitialSystem:
        subkey = cluster.project(key)
        mode = self._part(cluster, key)
        renaming = self._renamed.get((cluster.index, subkey))
        if renaming is not None and mode.shape_of is not None:
            # renamed from an earlier part of its shape: so is its initialization problem
            source = self._initial_part(self.clustering.clusters[renaming.cluster], renaming.key)
            renamed = renamed_initial(renaming, source, subkey, cache.parameters)
            if renamed is not None:
                return renamed
        if mode.structure is None:  # loaded from disk or renamed: its stages are needed here
            mode = self._build_part(cluster, key, cache, rename=False)
            self._store(self.parts, (cluster.index, subkey), mode)
        source_translation = self.rebound_from
        source = (source_translation._initial_part(cluster, key)
                  if source_translation is not None and source_translation.clustering is self.clustering
                  and mode.passes[:1] and mode.passes[0][0] == "rebind" else None)
        if source is not None and source.algebraic is None:  # loaded from disk: compiled once (as modes)
            source = source_translation._build_initial_part(cluster, key, source_translation._cluster_cache(cluster))
            source_translation._store(source_translation.initial_parts, (cluster.index, subkey), source)
        if source is not None and self._guards_hold(source.algebraic):
            bound = self._bound_initial(source, mode, cache.parameters)
            if bound is not None:
                return bound
        context = (f"initialization of {self.flat.name} "
                   f"[cluster {cluster.index + 1}: {brief_description(mode.description)}]")
        initial = [self.partitioned.initial_equations[i] for i in cluster.initial_equations]
        return compile_initial_system(mode, self.specialise(key, initial), context, cache, self.continuous)



# ---------------------------------------------------------------------------
# The parts as compiled models of their own (integrated apart by the runtime)
# ---------------------------------------------------------------------------


def _no_impure_call(*_args):  # the program of a model with impure functions is never split
    raise RuntimeError("impure function called in a program compiled for the parts")


class _Groups:
    """Union-find over the parts (``("c", index)``), the discrete variables (``("d", name)``)
    and the assertions (``("a", index)``): what the discrete part links."""

    def __init__(self) -> None:
        self.parent: dict = {}

    def find(self, x):
        parent = self.parent
        parent.setdefault(x, x)
        while parent[x] != x:
            parent[x] = parent[parent[x]]
            x = parent[x]
        return x

    def union(self, a, b) -> None:
        ra, rb = self.find(a), self.find(b)
        if ra != rb:
            self.parent[rb] = ra


def _part_models(translation) -> "tuple[tuple[PartModel, ...], str]":
    """The parts of ``translation`` as :class:`PartModel` objects, or ``((), why not)``.

    The parts are independent at run time when no discrete equation, reinit,
    assertion or relation reads values of two parts, and the model has no
    construct that acts on all of them at once (terminate(), terminal(),
    sample clocks, discrete Reals, impure functions, homotopy, delays).
    Relations of time and parameters alone (a source's start time) are given
    to every part that reads them.
    """
    clustering = translation.clustering
    if clustering is None:
        return (), "the model is one part"
    data = translation.data
    for present, why in ((data.clocks, "sample clocks tick in every part at once"),
                         (data.held_variables, "it has discrete Reals"),
                         (data.homotopy, "homotopy() is decided for the whole model"),
                         (data.delays, "it has delay()")):
        if present:
            return (), why
    program = translation.discrete_program(_no_impure_call)
    if program.impure_sites:
        return (), "impure functions keep one state for the whole model"
    if program.terminations:
        return (), "terminate() ends every part at once"
    clusters = clustering.clusters
    owner = {name: c.index for c in clusters for name in c.variables}
    relation_owner = {k: c.index for c in clusters for k in c.relations}
    discrete = set(data.discrete_variables)
    parameters = set(data.parameter_table)
    relations = translation.partitioned.relations
    groups = _Groups()
    #: the free relations (of time and parameters alone) each node reads
    reads: dict = {}
    free: set[int] = set()
    for k, rel in enumerate(relations):
        names = {s.name for s in (rel.lhs.free_symbols | rel.rhs.free_symbols)} - parameters - {"time"}
        if not names:
            free.add(k)
        for name in names:
            what = parse(name)
            base = what.base
            if base in discrete:
                groups.union(("c", relation_owner[k]), ("d", base))
            elif base in owner and owner[base] != relation_owner[k]:
                groups.union(("c", relation_owner[k]), ("c", owner[base]))

    def read(node, name: str) -> bool:
        """``node`` reads ``name``; False for what no part can take alone (terminal())."""
        what = parse(name)
        if what.kind == "terminal":
            return False
        if what.kind == "relation":
            if what.index in free:
                reads.setdefault(node, set()).add(what.index)
            else:
                groups.union(node, ("c", relation_owner[what.index]))
            return True
        base = what.base
        if what.kind == "pre" and parse(base).kind == "relation":
            return read(node, base)
        if base in discrete:
            groups.union(node, ("d", base))
        elif base in owner:
            groups.union(node, ("c", owner[base]))
        return True

    for c in clusters:
        groups.find(("c", c.index))
        for i in c.selectors:
            read(("c", c.index), data.selectors[i])
    for variable, args, _fn, _origin in program.equations:
        for a in args:
            if not read(("d", variable), a):
                return (), "terminal() is decided for the whole model"
    for reinit, fire_args, _f, value_args, _v in program.reinits:
        node = ("c", owner[reinit.variable]) if reinit.variable in owner else ("d", reinit.variable)
        for a in (*fire_args, *value_args):
            if not read(node, a):
                return (), "terminal() is decided for the whole model"
    for i, (_item, args, _f) in enumerate(program.asserts):
        for a in args:
            if not read(("a", i), a):
                return (), "terminal() is decided for the whole model"
    # each group: the one part it touches (none: the first part)
    part_of_root: dict = {}
    for c in clusters:
        root = groups.find(("c", c.index))
        if root in part_of_root:
            first = part_of_root[root]
            linking = sorted(n for kind, n in groups.parent if kind == "d" and groups.find((kind, n)) == root)
            through = f" (through {', '.join(linking[:3])})" if linking else ""
            return (), (f"the discrete part links part {first + 1} and part {c.index + 1}{through}: "
                        f"their events must be decided together")
        part_of_root[root] = c.index

    def part_of(node) -> int:
        return part_of_root.get(groups.find(node), 0)

    free_read: dict[int, set[int]] = {c.index: set() for c in clusters}
    for node, ks in reads.items():
        free_read[part_of(node)] |= ks
    read_anywhere = set().union(*free_read.values())
    # what each part has of the model, each list made in one pass (a storm has thousands of parts)
    n = len(clusters)
    part_of_name = dict(owner)
    discrete_of: list[list[str]] = [[] for _ in range(n)]
    for name in data.discrete_variables:
        part_of_name[name] = c = part_of(("d", name))
        discrete_of[c].append(name)
    variables_of: list[list] = [[] for _ in range(n)]
    for v in data.variables:
        c = part_of_name.get(v.name)
        if c is not None:
            variables_of[c].append(v)
    identifiers_of: list[dict] = [{} for _ in range(n)]
    for name, ident in data.identifiers.items():
        c = part_of_name.get(parse(name).base)
        if c is not None:
            identifiers_of[c][name] = ident
    equations_of: list[list] = [[] for _ in range(n)]
    for eq in program.equations:
        equations_of[part_of_name[eq[0]]].append(eq)
    reinits_of: list[list] = [[] for _ in range(n)]
    for r in program.reinits:
        reinits_of[part_of(("c", owner[r[0].variable]) if r[0].variable in owner else ("d", r[0].variable))].append(r)
    asserts_of: list[list] = [[] for _ in range(n)]
    for i, a in enumerate(program.asserts):
        asserts_of[part_of(("a", i))].append(a)
    table = data.parameter_table
    shared: dict = {}
    models = []
    for c in clusters:
        k = c.index
        # the part's relations: those its system computes, in its order, then the relations of
        # time alone it reads that another part's system computes (so that the crossing values
        # of the watched relations are the system's own, at the same places)
        own = [r for r in c.relations if r not in free or r not in read_anywhere or r in free_read[k]]
        taken = set(own)
        chosen = own + sorted(r for r in free_read[k] if r not in taken)
        # the parameters the part's code and discrete part read (by name; its code has its own vector)
        names = dict.fromkeys(c.parameters)
        for item in (*equations_of[k], *asserts_of[k]):
            names.update((a, None) for a in item[1] if a in table)
        for item in reinits_of[k]:
            names.update((a, None) for a in (*item[1], *item[3]) if a in table)
        for name in names:
            ident = data.identifiers.get(name)
            if ident is not None:
                identifiers_of[k][name] = ident
        part_data = dataclasses.replace(
            data, variables=tuple(variables_of[k]), parameters=(), parameter_names=tuple(names),
            parameter_vector=tuple(table[p] for p in names), identifiers=identifiers_of[k],
            relations=tuple(dataclasses.replace(data.relations[r], index=i, name=relation_name(i))
                            for i, r in enumerate(chosen)),
            clocks=(), delays=(), discrete_variables=tuple(discrete_of[k]), held_variables=())
        models.append(PartModel(translation, c, part_data, tuple(chosen), equations_of[k], reinits_of[k],
                                asserts_of[k], shared))
    return tuple(models), ""


def _renamer(position: dict[int, int]) -> Callable[[str], str]:
    """Names of the model's relations (and their pre values) as the part numbers them."""
    def rename(name: str) -> str:
        what = parse(name)
        if what.kind == "relation":
            return relation_name(position[what.index])
        if what.kind == "pre" and parse(what.base).kind == "relation":
            return pre_name(rename(what.base))
        return name
    return rename


class PartModel:
    """One independent part of a translated model as a compiled model of its own.

    It answers what the runtime asks of a compiled model
    (:class:`~acausal.runtime.contract.CompiledModel`) for the part alone: its
    systems are the translation's systems of the part (``Translation.parts``,
    the same objects a composed system is made of), its relations the part's
    (numbered from 0 in the model's order: the part's own, and the relations
    of time alone it reads), its discrete variables, discrete equations,
    reinits and assertions the part's, its key the part's key
    (:meth:`Cluster.project`).  Compiling and the notes are the translation's.
    """

    def __init__(self, translation, cluster: Cluster, data, relations: tuple[int, ...], equations, reinits,
                 asserts, shared: dict) -> None:
        self.translation = translation
        self.cluster = cluster
        #: the model's indices of the part's relations, in the part's order
        self.relations = relations
        position = {k: i for i, k in enumerate(relations)}
        rename = _renamer(position)
        model = translation.data
        discrete = data.discrete_variables
        self.data = dataclasses.replace(data, selectors=tuple(rename(model.selectors[i]) for i in cluster.selectors))
        self.demand = (None if translation.demand is None
                       else translation._cluster_demand(cluster) | frozenset(discrete))
        self.options = translation.options
        self.notes = translation.notes
        self.extras: dict = {}
        self.systems: dict = {}
        self.initial_systems: dict = {}
        self._program = DiscreteProgram(
            tuple((v, [rename(a) for a in args], fn, origin) for v, args, fn, origin in equations), 0,
            tuple((r, [rename(a) for a in fa], ff, [rename(a) for a in va], vf) for r, fa, ff, va, vf in reinits),
            (), tuple((a, [rename(n) for n in args], f) for a, args, f in asserts))
        self._shared = shared
        self._n_selectors = len(model.selectors)
        # the part's crossing vector from its system's (the cluster's relations, in order)
        # and the relations of time alone it reads besides
        in_system = {k: j for j, k in enumerate(cluster.relations)}
        extra = [k for k in relations if k not in in_system]
        #: the part's relations the system computes at the same places (crossings_for needs no gather)
        self._same_places = next((i for i, (a, b) in enumerate(zip(relations, cluster.relations)) if a != b),
                                 min(len(relations), len(cluster.relations)))
        if not extra and list(relations) == list(cluster.relations):
            self._crossing_plan = None
        else:
            gather = []
            for k in relations:
                if k in in_system:
                    gather += [2 * in_system[k], 2 * in_system[k] + 1]
                else:
                    at = 2 * len(cluster.relations) + 2 * extra.index(k)
                    gather += [at, at + 1]
            self._crossing_plan = (tuple(gather), _free_sides(translation, extra))

    @property
    def translation_seconds(self) -> float:
        return self.translation.translation_seconds

    @property
    def compiled_systems(self) -> int:
        """The part's systems in force so far (the translation counts the model's)."""
        return len(self.systems)

    def _full_key(self, key: tuple) -> "_KeyOfPart":
        """A key of the whole model whose projection on this part is ``key`` (the
        part's equations read nothing else)."""
        return _KeyOfPart(dict(zip(self.cluster.selectors, key)), self._n_selectors)

    def system(self, key: tuple):
        found = self.systems.get(key)
        if found is None:
            mode = self.translation._part(self.cluster, self._full_key(key))
            found = mode if self._crossing_plan is None else PartSystem(mode, *self._crossing_plan,
                                                                           self._same_places)
            self.systems[key] = found
        return found

    def initial_system(self, key: tuple):
        found = self.initial_systems.get(key)
        if found is None:
            found = self.initial_systems[key] = self.translation._initial_part(self.cluster, self._full_key(key))
        return found

    def discrete_program(self, impure_call: Callable) -> DiscreteProgram:
        return self._program

    def time_events(self) -> tuple[tuple, tuple]:
        found = self._shared.get("roots")
        if found is None:
            # the model's roots by relation, once for every part (no discrete Reals: no held instants)
            found = self._shared["roots"] = dict(self.translation.time_events()[0])
        return tuple((i, found[k]) for i, k in enumerate(self.relations) if k in found), ()

    def clock_ticks(self) -> tuple:
        return ()

    def delay_numbers(self) -> dict:
        return {}

    def part_models(self) -> tuple[tuple, str]:
        return (), "the model is one part"

    def reset_warm_starts(self) -> None:
        for system in (*self.systems.values(), *self.initial_systems.values()):
            system.reset()

    def start_value_relations(self, start_time: float) -> tuple[bool, ...]:
        found = self._shared.get(("starts", start_time))
        if found is None:
            found = self._shared[("starts", start_time)] = self.translation.start_value_relations(start_time)
        return tuple(found[k] for k in self.relations)

    def __repr__(self) -> str:
        return (f"<PartModel part {self.cluster.index + 1} of {self.data.name}: {len(self.cluster.variables)} "
                f"variables, {len(self.relations)} relations>")


class _KeyOfPart:
    """A key of the whole model read at one part's selectors: their values, False at every
    other position (which the part's equations do not read).  Indexed as a tuple, without
    building one as long as the model's selectors for each of N parts' systems."""

    __slots__ = ("values", "length")

    def __init__(self, values: dict[int, Any], length: int) -> None:
        self.values = values
        self.length = length

    def __getitem__(self, i: int):
        return self.values.get(i, False)

    def __len__(self) -> int:
        return self.length


def _free_sides(translation, ks: list[int]) -> tuple[Callable, Callable]:
    """``(scalar, vectorised)`` functions of time giving ``lhs, rhs`` of the relations ``ks``
    (of time and parameters alone), laid end to end."""
    import sympy as sp

    time = model_time
    symbols = translation.cache.parameters.symbols
    sides = []
    for k in ks:
        rel = translation.partitioned.relations[k]
        sides += [rel.lhs.xreplace(symbols), rel.rhs.xreplace(symbols)]
    # a number or time itself (a source's start time) needs no generated function
    simple = [float(e) if e.is_Number else None if e == time else False for e in sides]
    if all(v is not False for v in simple):
        plan = tuple(simple)

        def values(t) -> list:
            t = float(t)
            return [t if v is None else v for v in plan]

        def many(t):
            t = np.asarray(t, dtype=float)
            return np.array([t if v is None else np.full(t.shape, v) for v in plan]).reshape(len(plan), *t.shape)

        return values, many
    scalar = sp.lambdify([time], sides, "math")
    vector = sp.lambdify([time], sides, "numpy")

    def values(t) -> list:
        return [float(v) for v in scalar(float(t))]

    def many(t):
        t = np.asarray(t, dtype=float)
        return np.array([np.broadcast_to(np.asarray(v, dtype=float), t.shape) for v in vector(t)])

    return values, many


class PartSystem:
    """A part's system (:class:`~acausal.compiler.modes.ModeSystem`) whose crossing vector
    is the part's relations: its own, and the relations of time alone it reads that
    another part computes (``gather`` picks them from the system's values followed by
    ``sides``' values).  What the runtime asks of a compiled system besides is the
    mode's, named here one by one (``mode`` is the mode's system itself)."""

    parts = None

    def __init__(self, mode: ModeSystem, gather: tuple[int, ...], sides: tuple[Callable, Callable],
                 same_places: int = 0) -> None:
        self.mode = mode
        self.key = mode.key
        self.states = mode.states
        self.unknowns = mode.unknowns
        self.alias_plan = mode.alias_plan
        self.derivatives = mode.derivatives
        self.outputs = mode.outputs
        self.description = mode.description
        self.derivative_names = mode.derivative_names
        self.relaxed = mode.relaxed
        own, (scalar, many) = mode.crossings, sides

        def crossings(t, x):
            values = [*own(t, x), *scalar(t)]
            return [values[i] for i in gather]

        self.crossings = crossings
        self._same_places = same_places
        self._gather = np.array(gather, dtype=int)
        self._many = many
        self._vectorised: dict = {}

    def crossings_for(self, relations: tuple[int, ...]) -> Callable:
        """The system's own function when it computes ``relations`` at their places (the
        relations watched between events: never those of time alone)."""
        if relations and max(relations) < self._same_places:
            return self.mode.crossings
        return self.crossings

    def vectorised_crossings_for(self, relations: tuple[int, ...]) -> Callable | None:
        """The mode's numpy crossings of ``relations`` only, when the mode computes them at
        their places (as :meth:`crossings_for`); None otherwise (the whole function is used)."""
        if relations and max(relations) < self._same_places:
            return self.mode.vectorised_crossings_for(relations)
        return None

    def crossings_of(self, relations: tuple[int, ...]) -> Callable | None:
        """The mode's scalar crossings of ``relations`` only, when the mode computes them at
        their places (as :meth:`crossings_for`); None otherwise (the whole function is used)."""
        if relations and max(relations) < self._same_places:
            return self.mode.crossings_of(relations)
        return None

    def values(self, t: float, x) -> dict[str, float]:
        return self.mode.values(t, x)

    def vectorised(self, name: str) -> Callable | None:
        if name != "crossings":
            return self.mode.vectorised(name)
        found = self._vectorised.get(name)
        if found is None:
            own = self.mode.vectorised("crossings")
            if own is None:
                found = False
            else:
                gather, many = self._gather, self._many

                def found(t, X):
                    values = np.asarray(own(t, X), dtype=float)
                    extra = many(t).reshape(-1, *values.shape[1:]) if values.ndim > 1 else many(t)
                    return np.concatenate([values, extra], axis=0)[gather]
            self._vectorised[name] = found
        return found or None

    @property
    def sources(self) -> tuple[str, ...]:
        """The mode's generated source (where a failing line of its code is looked up)."""
        return self.mode.sources

    def reset(self) -> None:
        """Forget the mode's warm starts (its Newton solves' last solutions)."""
        self.mode.reset()
