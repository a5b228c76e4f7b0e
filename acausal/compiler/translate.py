"""The translation driver: run the stages, once per visited discrete state.

:func:`translate` flattens and partitions a model once
(:mod:`~acausal.compiler.flatten`, :mod:`~acausal.compiler.partition`).  The
continuous system of a discrete state is compiled by
:func:`~acausal.compiler.modes.compile_mode` the first time that state is
visited, its initialization problem by
:func:`~acausal.compiler.initial.compile_initial_system`; both are cached on
the :class:`Translation`, with the work they share in its
:class:`~acausal.compiler.cache.ModelCache`.  Translations of models seen
before in this process are reused when their flat models are the same
(:func:`flat_signature`).  The generated code reads the numeric parameters
and the tunable start values (``J1.w.start``: of the states and the fixed
variables) from its parameter vector, so that a model that differs only in
those values reuses the compiled systems (:meth:`Translation.rebound`).
"""

from __future__ import annotations

import dataclasses
import functools
import difflib
import hashlib
import io
import json
import pickle
import re
import time as _time
from collections import OrderedDict
from types import SimpleNamespace
from typing import Any, Callable, Iterable, Mapping

import numpy as np
import sympy as sp

from ..errors import (InitializationError, ModelDefinitionError, SettingError, StructuralError,
                      StructurallySingularError)
from ..language import Component, real_symbol, structural_names, with_structural
from ..names import is_derivative, parse
from ..tables import TableFunction, _table_class
from .algebraic import NewtonSolve
from .cache import ModelCache
from .codegen import GeneratedCode, load_make
from .diskcache import DiskCache, MemoryCache, cache_folder, disk_cache_enabled, model_key
from .clusters import Cluster, Clustering, ComposedInitialSystem, ComposedSystem, compose, compose_initial, find_clusters
from .flatten import FlatEquation, FlatModel, FlatVariable, Origin, flatten, start_parameter
from .initial import (InitialSystem, StartDependence, StartValues, bind_start_values, check_fixed_constants,
                      compile_initial_system, newton_guesses, start_value_relations)
from .modes import ModeSystem, PassLog, RelaxedConstraints, alias_plan, compile_mode, describe_key
from .compiled import ClockData, DelayData, ModelData
from .partition import PartitionedModel, partition
from .discrete import DiscreteProgram, compile_discrete
from .timing import clock_ticks, delay_numbers, held_time_events, time_event_roots
from ..options import DEFAULT_OPTIONS, EngineOptions
from .structure import _incidence, relax_redundant

__all__ = ["ModeSystem", "InitialSystem", "ComposedSystem", "Translation", "TranslationBundle", "translate",
           "flat_signature", "describe_key", "with_start_values"]

#: A call of a table function in generated code (see ``codegen._Printer``).
_CALLED_TABLE = re.compile(r"\b(_f_\w+)\(")

def _value_of(value) -> Any:
    if isinstance(value, (bool, np.bool_)):
        return sp.true if value else sp.false
    return sp.Integer(int(value))


class Translation:
    """A translated model: flat and partitioned once, systems built lazily.

    Attributes
    ----------
    flat : FlatModel
    partitioned : PartitionedModel
    demand : frozenset of str or None
        The outputs the systems compute (None: everything).
    cache : ModelCache
        Parameters, identifiers and the stages' memos, shared by the systems.
    systems : dict
        ``key -> ModeSystem`` for every discrete state compiled so far.
    initial_systems : dict
        ``key -> InitialSystem``, likewise.
    flatten_seconds : float
        Seconds spent flattening and partitioning.
    clustering : Clustering or None
        The model's independent parts when it has several and is hybrid:
        then :attr:`systems` holds :class:`ComposedSystem` objects and
        :attr:`parts` the systems compiled per cluster and cluster key.
    parts : dict
        ``(cluster index, cluster key) -> ModeSystem``.
    extras : dict
        Objects the later layers build once per translation and keep with it
        (the runtime's discrete evaluators): they live exactly as long as the
        translation.
    """

    def __init__(self, flat: FlatModel, partitioned: PartitionedModel, flatten_seconds: float,
                 demand: frozenset[str] | None = None, clusters: bool = True,
                 clustering: Clustering | None = None, disk: bool = True,
                 redundant_constraints: str = "relax", options: EngineOptions = DEFAULT_OPTIONS) -> None:
        self.flat = flat
        #: how the engine works for this translation and the runs of it (:class:`~acausal.options.EngineOptions`)
        self.options = options
        #: what a discrete state that constrains one motion twice gets (see :func:`translate`)
        self.redundant_constraints = redundant_constraints
        self.demand = demand
        self.partitioned = partitioned
        # the tunable start values are parameters of the generated code, after the model's own
        self.cache = ModelCache.of(_with_start_parameters(flat))
        self.continuous = {n: v for n, v in flat.variable_map.items() if not v.is_discrete}
        self.systems: dict[tuple, ModeSystem] = {}
        self.initial_systems: dict[tuple, InitialSystem] = {}
        self.flatten_seconds = flatten_seconds
        self.extras: dict = {}
        #: the translation this one reuses compiled systems from (other parameter values)
        self.rebound_from: Translation | None = None
        #: what a run should know of how this translation was made (a system compiled anew
        #: for start values given at run time); :func:`~acausal.runtime.simulate.simulate`
        #: adds them to the result's notes
        self.notes: list[str] = []
        self._by_equations: dict[tuple, ModeSystem] = {}
        self._discrete_names = frozenset(partitioned.discrete_variables)
        if flat.delays:
            # a delayed value links the equations that read it to its expression's
            # equations through the run's history, which the incidence does not show
            clusters = False
        clusters = clusters and options.clusters
        if clustering is None and clusters and partitioned.selectors:
            found = find_clusters(partitioned, self.continuous)
            clustering = found if len(found) > 1 else None
        self.clustering: Clustering | None = clustering if clusters else None
        self.parts: dict[tuple[int, tuple], ModeSystem] = {}
        self.initial_parts: dict[tuple[int, tuple], InitialSystem] = {}
        self._cluster_caches: dict[int, ModelCache] = {}
        self._compiled_seconds = 0.0  # of every system stored (translation_seconds is hot)
        #: the persistent cache: None = not looked up yet, False = off
        self._disk: DiskCache | None | bool = None if disk else False
        self._tables: dict = {}

    def _store(self, table: dict, key, system) -> None:
        table[key] = system
        self._compiled_seconds += system.seconds

    def unclustered(self) -> "Translation":
        """A translation of the same flat model that compiles the whole model per
        discrete state and never loads systems from the persistent cache: every
        stage's output is there to inspect (what ``acausal explain`` shows)."""
        if self.clustering is None:
            # explained in place (its compiled systems reused): systems loaded from
            # disk are dropped, and nothing more is loaded
            self._disk = False
            for key in [k for k, s in self.systems.items() if getattr(s, "structure", None) is None]:
                del self.systems[key]
            for key in [k for k, s in self.initial_systems.items() if getattr(s, "algebraic", None) is None]:
                del self.initial_systems[key]
            return self
        return Translation(self.flat, self.partitioned, self.flatten_seconds, self.demand, clusters=False,
                           disk=False, options=dataclasses.replace(self.options, clusters=False))

    # -- parameters -----------------------------------------------------------

    @property
    def parameter_names(self) -> tuple[str, ...]:
        """The names of the generated code's parameter vector: the model's numeric parameters,
        then the tunable start values (``J1.w.start``)."""
        return self.cache.parameters.names

    @functools.cached_property
    def data(self) -> ModelData:
        """What the runtime reads of this model, as plain data (:class:`~acausal.compiler.compiled.ModelData`)."""
        flat, partitioned, parameters = self.flat, self.partitioned, self.cache.parameters
        return ModelData(
            name=flat.name, experiment=flat.experiment, variables=tuple(flat.variables),
            parameters=tuple(flat.parameters), parameter_names=tuple(parameters.names),
            parameter_vector=tuple(parameters.vector), structural_parameters=dict(flat.structural_parameters),
            evaluated_parameters=frozenset(partitioned.evaluated_parameters),
            relations=tuple(r.as_data() for r in partitioned.relations),
            clocks=tuple(ClockData(c.index, c.symbol.name, c.text) for c in partitioned.clocks),
            delays=tuple(DelayData(d.index, d.variable, d.fixed, d.component, d.text) for d in flat.delays),
            discrete_variables=tuple(partitioned.discrete_variables),
            held_variables=tuple(partitioned.held_variables),
            selectors=tuple(s.name for s in partitioned.selectors), identifiers=dict(self.cache.identifiers),
            homotopy=flat.homotopy, hints=flat.hints)

    @property
    def parameter_values(self) -> Mapping[str, float]:
        return self.cache.parameters.values

    @property
    def parameter_vector(self) -> tuple[float, ...]:
        return self.cache.parameters.vector

    # -- discrete states ----------------------------------------------------

    @property
    def selectors(self) -> tuple[sp.Symbol, ...]:
        return self.partitioned.selectors

    def key_of(self, assignment: Mapping[str, Any]) -> tuple:
        """The discrete state for values of discrete symbols (by name)."""
        missing = [s.name for s in self.selectors if s.name not in assignment]
        if missing:
            raise KeyError(f"the discrete state of {self.flat.name} needs values for "
                           f"{', '.join(missing)}; acausal.runtime.initialization.start_system() "
                           f"finds the state at the start")
        return tuple(assignment[s.name] for s in self.selectors)

    def describe(self, key: tuple) -> str:
        """The discrete state ``key`` in words."""
        return describe_key(self.selectors, key, {r.symbol.name: r.text for r in self.partitioned.relations})

    def specialise(self, key: tuple, equations=None) -> tuple[FlatEquation, ...]:
        """``equations`` (default: the model's) with the discrete symbols set to ``key``."""
        subs = {s: _value_of(v) for s, v in zip(self.selectors, key)}
        # Parameters that are zero are structural zeros: the matching ignores
        # the terms they multiply, so the generated code must not contain them.
        subs.update(self.cache.parameters.zeros)
        source = self.partitioned.equations if equations is None else equations
        memo = self.cache.specialise
        out = []
        for eq in source:
            # Only the discrete symbols an equation contains decide its form:
            # an equation is specialised once per combination of their values.
            used = memo.used.get(eq.residual)
            if used is None:
                used = memo.used[eq.residual] = tuple(s for s in eq.residual.free_symbols if s in subs)
            form_key = (eq.residual, tuple(subs[s] for s in used))
            residual = memo.forms.get(form_key)
            if residual is None:
                residual = eq.residual.xreplace({s: subs[s] for s in used}) if used else eq.residual
                leftover = [s.name for s in residual.free_symbols
                            if parse(s.name).kind in ("relation", "initial") or s.name in self._discrete_names]
                if leftover:
                    raise StructuralError(f"{eq.origin}: discrete value {leftover[0]} left after "
                                          f"specialisation", components=(eq.origin.component,))
                memo.forms[form_key] = residual
            out.append(eq if residual is eq.residual else FlatEquation(residual, eq.origin))
        return tuple(out)

    # -- other parameter values ----------------------------------------------

    def rebound(self, flat: FlatModel, flatten_seconds: float = 0.0) -> "Translation | None":
        """A translation of ``flat`` (this model's structure with other numeric
        parameter values) that reuses this one's compiled systems, or None.

        The generated code reads its parameters from a vector, so a compiled
        system serves other values as they are, given its new vector.  What
        the values decided while translating must still hold: parameters of
        relations decided from the parameters alone keep their values (else
        None: translate anew), and a system whose solution divides by an
        expression of parameters that is zero for the new values is compiled
        anew (:attr:`AlgebraicResult.nonzero`).
        """
        old = self.parameter_values
        new = flat.parameter_values
        if any(old[n] != new[n] for n in self.partitioned.evaluated_parameters):
            return None
        partitioned = dataclasses.replace(self.partitioned, flat=flat)
        translation = Translation(flat, partitioned, flatten_seconds, self.demand,
                                  clusters=self.clustering is not None, clustering=self.clustering,
                                  redundant_constraints=self.redundant_constraints, options=self.options)
        translation.rebound_from = self
        return translation

    def _rebind(self, key: tuple) -> ModeSystem | None:
        """The system of ``key`` compiled by :attr:`rebound_from`, bound to this one's parameters."""
        if self.rebound_from is None:
            return None
        # compiled by the first translation of the structure, with its memos (its values
        # decide nothing the structure does not, but which coefficients are non-zero)
        base = self.rebound_from
        source = base.system(key)
        if isinstance(source, ComposedSystem):  # the other translation compiles by parts
            return None
        if source.structure is None:
            # loaded from disk: rebinding needs its stages (compiled once, then every value rebinds)
            source = base._build_whole(key)
            base._store(base.systems, key, source)
        if not self._guards_hold(source.algebraic) or not self._guesses_hold(source):
            return None
        return _bind_mode(source, self.cache.parameters)

    def _guards_hold(self, algebraic) -> bool:
        if algebraic is None:  # a system loaded from the persistent cache: no guards known
            return False
        symbols = self.cache.parameters.symbols
        return all(not sp.sympify(g).xreplace(symbols).is_zero for g in algebraic.nonzero)

    def _guesses_hold(self, source: ModeSystem) -> bool:
        """Whether the first guesses of ``source``'s Newton iterations, start values its code
        holds as numbers, are this translation's (else it is compiled anew, with a note)."""
        if not self._other_starts() or not any(isinstance(step, NewtonSolve) for step in source.algebraic.steps):
            return True
        starts = StartValues(source.aliases.aliases, source.aliases.variables, self.continuous,
                             self.cache.parameters.symbols)
        for name, expression, value in newton_guesses(source.algebraic, starts):
            if value != source.aliases.variables[name].start:
                self._note_guess(name, expression, self._where("the system", source.description))
                return False
        return True

    def _other_starts(self) -> bool:
        """Whether this translation's tunable start values differ from :attr:`rebound_from`'s
        (computed once: a sweep over parameters alone never looks at Newton guesses)."""
        found = self.extras.get("other starts")
        if found is None:
            base = self.rebound_from.flat.variable_map
            found = self.extras["other starts"] = any(
                base[n].start != self.continuous[n].start for n in self.flat.tunable_starts)
        return found

    def _where(self, what: str, description: str) -> str:
        """``what`` ('the system', ...) of the discrete state ``description``, in words."""
        return f"{what} of discrete state {description}" if self.partitioned.is_hybrid else what

    def _note_guess(self, name: str, expression: sp.Expr, where: str) -> None:
        """Note that a start value given at run time made a system be compiled anew."""
        given = ", ".join(sorted(s.name for s in expression.free_symbols))
        self.notes.append(f"{given} is the first guess of a Newton iteration for {name} in {where}, which "
                          f"its code holds as a number: that system was compiled anew for this start value")

    # -- building systems -----------------------------------------------------

    def _context(self, description: str) -> str:
        return f"{self.flat.name} [{description}]" if self.partitioned.is_hybrid else self.flat.name

    def system(self, key: tuple) -> ModeSystem:
        """The compiled system of discrete state ``key`` (built on first use)."""
        cached = self.systems.get(key)
        if cached is not None:
            return cached
        if self.clustering is not None:
            composed = self._composed(key)
            if composed is not None:
                self._store(self.systems, key, composed)
                return composed
        return self._made(self.systems, key, f"mode {key!r}", self.cache, self._load_mode,
                          lambda: self._build_whole(key), self._save_mode)

    def _build_whole(self, key: tuple) -> ModeSystem:
        """Compile (or rebind, or share) the whole model's system of ``key``."""
        rebound = self._rebind(key)
        if rebound is not None:
            return rebound
        description = self.describe(key)
        context = self._context(description)
        passes = PassLog()
        with passes.run("specialise"):
            equations = self.specialise(key)
        # Discrete states that differ only in values the equations do not read
        # (the pre() value of a mode no equation reads, say) have the same
        # equations: one compiled system serves them all.
        signature = tuple(eq.residual for eq in equations)
        twin = self._by_equations.get(signature)
        if twin is not None:
            return _shared(twin, key, description, context, passes)
        try:
            try:
                system = compile_mode(key, description, context, equations, passes, self.partitioned,
                                      self.continuous, self.cache, self.demand)
            except StructurallySingularError:
                system = self._relaxed(key, description, context, equations, passes)
                if system is None:
                    raise
        except StructuralError as exc:
            hint = exc.hint
            if self.partitioned.is_hybrid and (self.systems or self.parts):
                # only this discrete state fails: the components concerned may know why
                own = self.flat.hints_for("mode", exc.components)
                hint = "this discrete state only: " + ("; ".join(own) if own else (
                    "its equations do not determine every unknown (or determine some twice); "
                    "check the discrete variables of the components named"))
            zeros = self._zero_suspects(exc)
            if zeros:
                hint = f"{hint}; {zeros}"
            if hint == exc.hint:
                raise
            # the same error, with what the components and parameters add (and its traceback)
            raise exc.with_hint(hint) from None
        self._by_equations[signature] = system
        return system

    def _relaxed(self, key: tuple, description: str, context: str, equations: tuple[FlatEquation, ...],
                 passes: PassLog) -> ModeSystem | None:
        """The system of a discrete state that constrains one motion twice, made
        solvable by :func:`relax_redundant` (None: not of that kind)."""
        if not self.partitioned.is_hybrid or self.redundant_constraints != "relax":
            return None
        symbols = self.cache.parameters.symbols
        # the equations whose form the discrete state selects (not those that changed
        # only because a zero parameter was put in)
        selectors = set(self.selectors)
        selected = [i for i, source in enumerate(self.partitioned.equations)
                    if not selectors.isdisjoint(source.residual.free_symbols)]
        flows = [n for n, v in self.continuous.items() if v.role == "flow"]
        found = relax_redundant(equations, [_incidence(e.residual, symbols) for e in equations],
                                list(self.continuous), selected, flows)
        if found is None:
            return None
        relaxed, relaxation = found
        try:
            system = compile_mode(key, description, context, relaxed, passes, self.partitioned,
                                  self.continuous, self.cache, self.demand)
        except StructuralError:
            return None
        # not warned here: every run that integrates in this state says so (the
        # runtime reads ``relaxed``), also when the system comes from the disk cache
        return dataclasses.replace(system, relaxed=_relaxed_constraints(relaxation, self.continuous))

    # -- clusters ---------------------------------------------------------------

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

    def _build_part(self, cluster: Cluster, key: tuple, cache: ModelCache) -> ModeSystem:
        """Compile (or rebind, or share) the system of ``cluster`` for ``key``."""
        subkey = cluster.project(key)
        rebound = self._rebind_part(cluster, key, cache)
        if rebound is not None:
            return rebound
        selectors = [self.selectors[i] for i in cluster.selectors]
        description = describe_key(selectors, subkey, {r.symbol.name: r.text for r in self.partitioned.relations})
        context = f"{self.flat.name} [cluster {cluster.index + 1}: {description}]"
        passes = PassLog()
        with passes.run("specialise"):
            equations = self.specialise(key, [self.partitioned.equations[i] for i in cluster.equations])
        signature = (cluster.index, tuple(eq.residual for eq in equations))
        twin = self._by_equations.get(signature)
        if twin is not None:
            return _shared(twin, subkey, description, context, passes)
        system = compile_mode(subkey, description, context, equations, passes, self.partitioned,
                              {n: self.continuous[n] for n in cluster.variables}, cache,
                              self._cluster_demand(cluster), cluster.relations)
        self._by_equations[signature] = system
        return system

    def _rebind_part(self, cluster: Cluster, key: tuple, cache: ModelCache) -> ModeSystem | None:
        """The part compiled by :attr:`rebound_from`, bound to this one's parameters."""
        source_translation = self.rebound_from
        if source_translation is None or source_translation.clustering is not self.clustering:
            return None
        source = source_translation._part(cluster, key)
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
        if mode.structure is None:  # loaded from disk: its stages are needed here
            mode = self._build_part(cluster, key, cache)
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
        context = f"initialization of {self.flat.name} [cluster {cluster.index + 1}: {mode.description}]"
        initial = [self.partitioned.initial_equations[i] for i in cluster.initial_equations]
        return compile_initial_system(mode, self.specialise(key, initial), context, cache, self.continuous)

    def _zero_suspects(self, exc: StructuralError) -> str:
        """Parameters that are zero and multiply an undetermined variable, in words ('' if none).

        A zero parameter is a structural zero: the term it multiplies is
        gone, and with it maybe the only equation that determined a variable.
        """
        zeros = self.cache.parameters.zeros
        undetermined = set(exc.undetermined)
        if not zeros or not undetermined:
            return ""
        named = set(exc.components)
        found: list[str] = []
        for eq in self.flat.equations:
            if eq.origin.component not in named:
                continue
            for z in eq.residual.free_symbols & zeros.keys():
                multiplied = sp.expand(eq.residual).coeff(z)
                if any(s.name in undetermined for s in multiplied.free_symbols) and z.name not in found:
                    found.append(z.name)
        if not found:
            return ""
        return (f"{', '.join(f'{n} = 0' for n in found)} removes the term{'s' if len(found) > 1 else ''} "
                f"{'they multiply' if len(found) > 1 else 'it multiplies'}, and with it what determined "
                f"the variables named: give {'them' if len(found) > 1 else 'it'} a non-zero value")

    def initial_system(self, key: tuple) -> InitialSystem:
        """The initialization problem of discrete state ``key`` (with initial() true)."""
        cached = self.initial_systems.get(key)
        if cached is not None:
            return cached
        mode = self.system(key)
        if isinstance(mode, ComposedSystem):
            system = compose_initial(key, [self._initial_part(c, key) for c in self.clustering.clusters])
            self._store(self.initial_systems, key, system)
            return system
        return self._made(self.initial_systems, key, f"initial {key!r}", self.cache, self._load_initial,
                          lambda: self._build_initial(key, mode), self._save_initial)

    def _build_initial(self, key: tuple, mode: ModeSystem) -> InitialSystem:
        if mode.structure is None:  # loaded from disk: its stages are needed here
            mode = self._build_whole(key)
            self._store(self.systems, key, mode)
        base = self.rebound_from
        source = (base.initial_system(key) if base is not None
                  and mode.passes[:1] and mode.passes[0][0] == "rebind" else None)
        if source is not None and source.algebraic is None:
            # loaded from disk: compiled once with its stages, then every value rebinds (as _rebind)
            source = base._build_initial(key, base.system(key))
            base._store(base.initial_systems, key, source)
        if source is not None and self._guards_hold(source.algebraic):
            bound = self._bound_initial(source, mode, self.cache.parameters)
            if bound is not None:
                return bound
        context = f"initialization of {self.flat.name}"
        if self.partitioned.is_hybrid:
            context += f" [{mode.description}]"
        return compile_initial_system(mode, self.specialise(key, self.partitioned.initial_equations),
                                      context, self.cache, self.continuous, self.flat.delays)

    def _bound_initial(self, source: InitialSystem, mode: ModeSystem, parameters) -> InitialSystem | None:
        """``source`` bound to ``parameters`` (None: its Newton guesses are other start values, noted)."""
        bound = _bind_initial(source, mode, parameters)
        if bound is None:
            name, expression, _ = next(g for g in source.starts.guesses
                                       if float(g[1].xreplace(parameters.symbols)) != g[2])
            self._note_guess(name, expression, self._where("the initialization problem", mode.description))
        return bound

    # -- the persistent cache -----------------------------------------------------

    def _disk_cache(self) -> DiskCache | None:
        """The persistent cache of this flat model (None: off, or the model is not cached)."""
        if self._disk is False:
            return None
        if self._disk is None:
            self._disk = False
            if disk_cache_enabled():
                tables = self._table_functions()
                # the entries serve every tunable start value (their code reads them from the
                # parameter vector; what it holds as numbers is checked on load: _fits,
                # bind_start_values), so the key leaves them out
                key = model_key(_without_tunable_starts(self.flat), self.demand, self.clustering is not None,
                                self.redundant_constraints) if tables is not None else None
                if key is not None:
                    self._disk = DiskCache(cache_folder(), key)
                    self._tables = tables
        return self._disk or None

    def _table_functions(self) -> dict | None:
        """Table functions of the equations by class name (None if two share a name), with
        the functions their derivatives are (a class's ``related()``: index reduction may
        call them in generated code, though no flat equation does)."""
        found: dict[str, Any] = {}
        for eq in (*self.flat.equations, *self.flat.initial_equations):
            for f in eq.residual.atoms(sp.Function):
                impl = getattr(type(f), "_imp_", None)
                if impl is None:
                    continue
                related = getattr(type(f), "related", None)
                for cls in (type(f), *(related() if related is not None else ())):
                    if found.setdefault(cls.__name__, cls._imp_) is not cls._imp_:
                        return None
        return found

    def _functions_payload(self, source: str) -> dict | None:
        """The table functions ``source`` calls, as code name -> class name (None: one
        is not a table of this model, and the system is not stored).  Names are read
        from the source itself: a system rebound from another translation was printed
        with that translation's names."""
        out = {}
        for code_name in sorted(set(_CALLED_TABLE.findall(source))):
            class_name = code_name[len("_f_"):]
            if class_name not in self._tables:
                return None
            out[code_name] = class_name
        return out

    def _code_from(self, payload: dict) -> tuple[GeneratedCode, tuple] | None:
        source = payload["source"]
        functions = {name: self._tables[cls] for name, cls in payload["functions"].items()}
        if set(_CALLED_TABLE.findall(source)) - set(functions):
            raise ValueError("the entry's code calls a table it does not name")
        name = source.split("\n", 1)[0].removeprefix("# generated by acausal for ")
        make = load_make(source, functions, name)
        return GeneratedCode(source, make, payload["n_derivative_steps"], payload["n_steps"], None), make

    def _save(self, entry: str, system, cache: ModelCache, fields: dict) -> None:
        """Store ``system``'s code and ``fields`` under ``entry`` (when the cache is on)."""
        disk = self._disk_cache()
        if disk is None:
            return
        if system.passes[:1] and system.passes[0][0] == "rebind":
            # compiled for other parameter values: a compilation for these could make
            # other numeric choices; only what was compiled for the key is stored
            return
        payload = self._payload(system, fields)
        if payload is not None:
            disk.store(entry, payload)

    def _payload(self, system, fields: dict) -> dict | None:
        """``system``'s code and ``fields`` as plain data (None: it calls a table not of this model)."""
        if system.code is None:
            return None
        functions = self._functions_payload(system.code.source)
        if functions is None:
            return None
        return {"key": list(system.key), "source": system.code.source,
                "n_derivative_steps": system.code.n_derivative_steps, "n_steps": system.code.n_steps,
                "functions": functions, **fields}

    def _load(self, entry: str, cache: ModelCache, build):
        """``build(payload, code, functions, passes)`` from the entry stored for ``entry``, or None."""
        disk = self._disk_cache()
        if disk is None:
            return None
        t0 = _time.perf_counter()
        payload = disk.load(entry)
        if payload is None:
            return None
        try:
            if not _fits(payload, cache.parameters.symbols):
                return None  # its solution divides by zero for these values: compiled anew
            # a bundle's store keeps the code made from each entry: the source is
            # loaded once per process, then every run binds its own values
            codes = getattr(disk, "codes", None)
            found = codes.get(entry) if codes is not None else None
            code, make = found if found is not None else self._code_from(payload)
            if codes is not None:
                codes[entry] = (code, make)
            return build(payload, code, make(cache.parameters.vector), (("load", _time.perf_counter() - t0),))
        except InitializationError:
            raise  # a fixed start value that conflicts with these values (see _fits)
        except Exception:  # an entry that does not fit (its checksum matched): compile anew
            return None

    def _save_mode(self, entry: str, system: ModeSystem, cache: ModelCache) -> None:
        # what other start values are checked against (the key leaves them out, see _disk_cache)
        fields = {**_mode_fields(system), **self._guess_fields(system, cache),
                  "fixed_constants": _fixed_constants_field(system.aliases)}
        if isinstance(self._disk, MemoryCache):  # kept for other parameter values (from_bundle)
            fields.update(_bound_fields(system.aliases, system.algebraic))
        self._save(entry, system, cache, fields)

    def _guess_fields(self, system: ModeSystem, cache: ModelCache) -> dict:
        """The start values ``system``'s code holds as Newton guesses, as text (checked by
        :func:`_fits` for other start values)."""
        if system.aliases is None or not any(isinstance(s, NewtonSolve) for s in system.algebraic.steps):
            return {}
        starts = StartValues(system.aliases.aliases, system.aliases.variables, self.continuous,
                             cache.parameters.symbols)
        guesses = newton_guesses(system.algebraic, starts)
        return {"guesses": [[n, sp.srepr(e), system.aliases.variables[n].start] for n, e, _ in guesses]}

    def _load_mode(self, entry: str, cache: ModelCache) -> ModeSystem | None:
        def build(payload, code, functions, passes):
            plan = tuple((n, c, s) for n, c, s in payload["alias_plan"])
            if "aliases" in payload:  # from a bundle: the plan follows these parameter values
                aliases = {n: _expression(e) for n, e in payload["aliases"].items()}
                plan = alias_plan(SimpleNamespace(aliases=aliases), cache.parameters.symbols)
            return ModeSystem(
                tuple(payload["key"]), payload["description"], (), None, None, None, None, code, passes,
                *functions, tuple(payload["states"]), tuple(payload["unknowns"]), plan,
                None if payload["shares"] is None else tuple(payload["shares"]),
                loaded_derivatives=tuple(payload["derivatives"]),
                relaxed=RelaxedConstraints.from_payload(payload.get("relaxed")))
        return self._load(entry, cache, build)

    def _save_initial(self, entry: str, system: InitialSystem, cache: ModelCache) -> None:
        fields = _initial_fields(system)
        if isinstance(self._disk, MemoryCache):  # kept for other parameter values (from_bundle)
            mode = (self.parts.get((int(entry.split()[1]), system.key)) if entry.startswith("initial-part ")
                    else self.systems.get(system.key))
            if not isinstance(mode, ModeSystem) or mode.aliases is None:
                return
            fields.update(_bound_fields(mode.aliases, system.algebraic))
        self._save(entry, system, cache, fields)

    def _load_initial(self, entry: str, cache: ModelCache) -> InitialSystem | None:
        def build(payload, code, functions, passes):
            system = InitialSystem(tuple(payload["key"]), (), tuple(payload["unknowns"]),
                                   tuple((n, v) for n, v in payload["relaxed"]), None, None, code,
                                   passes, functions[2],
                                   tuple((n, v) for n, v in payload.get("from_start", ())),
                                   StartDependence.from_payload(payload.get("starts"), _expression))
            # a bundle's entry serves other start values too (None: a Newton guess differs)
            return bind_start_values(system, cache.parameters.symbols)
        return self._load(entry, cache, build)

    # -- to other processes -------------------------------------------------------

    def export(self) -> "TranslationBundle":
        """This translation as plain data, for processes that run the model without translating it.

        Every system compiled so far is shipped as its persistent-cache payload
        (generated source and plain metadata), with what binding it to other
        parameter values needs as text: its aliases, the expressions its
        solution divides by, the fixed start values it makes constants.
        Systems loaded from the persistent cache (no stages kept) and systems
        that call a table function two tables name alike are left out: a
        process that visits their discrete state compiles it.
        """
        if not self._tables:
            self._tables = self._table_functions() or {}
        payloads: dict[str, dict] = {}

        def add(entry: str, system, fields: dict) -> None:
            payload = self._payload(system, fields)
            if payload is not None:
                payloads[entry] = payload

        # entries named as system(), _part(), initial_system() and _initial_part() name them
        modes = [(f"mode {k!r}", s) for k, s in self.systems.items()]
        modes += [(f"part {i} {k!r}", s) for (i, k), s in self.parts.items()]
        for entry, system in modes:
            if isinstance(system, ModeSystem) and system.aliases is not None:
                cache = self._cluster_cache(self.clustering.clusters[int(entry.split()[1])]) \
                    if entry.startswith("part ") else self.cache
                add(entry, system, {**_mode_fields(system), **_bound_fields(system.aliases, system.algebraic),
                                    **self._guess_fields(system, cache)})
        initials = [(f"initial {k!r}", s, self.systems.get(k)) for k, s in self.initial_systems.items()]
        initials += [(f"initial-part {i} {k!r}", s, self.parts.get((i, k)))
                     for (i, k), s in self.initial_parts.items()]
        for entry, system, mode in initials:
            if isinstance(system, InitialSystem) and system.algebraic is not None \
                    and isinstance(mode, ModeSystem) and mode.aliases is not None:
                add(entry, system, {**_initial_fields(system), **_bound_fields(mode.aliases, system.algebraic)})
        pickler_output = io.BytesIO()
        _BundlePickler(pickler_output, protocol=pickle.HIGHEST_PROTOCOL).dump(
            (self.flat, self.partitioned, self.clustering))
        return TranslationBundle(pickler_output.getvalue(), self.demand, self.redundant_constraints, payloads)

    @classmethod
    def from_bundle(cls, bundle: "TranslationBundle", flat: FlatModel | None = None,
                    store: MemoryCache | None = None) -> "Translation":
        """A translation whose systems are loaded from ``bundle`` (see :meth:`export`), not compiled.

        Parameters
        ----------
        bundle : TranslationBundle
        flat : FlatModel, optional
            The bundle's flat model with other parameter values (its
            parameters replaced, nothing else): the systems are bound to them.
        store : MemoryCache, optional
            The bundle's payloads, read once (:meth:`TranslationBundle.store`):
            shared by the translations of one process, it keeps the code made
            from each payload.

        Returns
        -------
        Translation
            A discrete state the bundle does not hold, or whose solution
            divides by zero for these values, is compiled on first visit as
            usual.  A flat model whose values change what the translation
            decided (a relation of parameters alone, a zero that removes a
            term) is partitioned anew, and every system it needs compiled.
        """
        base, partitioned, clustering = bundle.unpacked()
        flat = base if flat is None else flat
        if not _same_structure(base, partitioned, flat):
            return cls(flat, partition(flat), 0.0, bundle.demand, disk=False,
                       redundant_constraints=bundle.redundant_constraints)
        if flat is not base:
            partitioned = dataclasses.replace(partitioned, flat=flat)
        translation = cls(flat, partitioned, 0.0, bundle.demand, clusters=clustering is not None,
                          clustering=clustering, disk=False, redundant_constraints=bundle.redundant_constraints)
        translation._disk = bundle.store() if store is None else store
        translation._tables = translation._table_functions() or {}
        return translation

    # -- what the runtime asks (acausal.runtime.contract.CompiledModel) ------------

    def discrete_program(self, impure_call: Callable) -> DiscreteProgram:
        """The discrete equations, reinits, terminations and assertions, compiled
        (:func:`~acausal.compiler.discrete.compile_discrete`); each call site of an
        impure function calls ``impure_call(site, function class, *args)``."""
        return compile_discrete(self.flat, self.partitioned, impure_call)

    def time_events(self) -> tuple[tuple, tuple]:
        """``(roots, held)`` of the time events for this translation's parameter values
        (:func:`~acausal.compiler.timing.time_event_roots`,
        :func:`~acausal.compiler.timing.held_time_events`)."""
        relations, symbols = self.partitioned.relations, self.cache.parameters.symbols
        return time_event_roots(relations, symbols), held_time_events(relations, symbols)

    def clock_ticks(self) -> tuple[tuple[float, float], ...]:
        """``(start, interval)`` of every sample clock (:func:`~acausal.compiler.timing.clock_ticks`)."""
        return clock_ticks(self.partitioned.clocks, self.cache.parameters.symbols)

    def delay_numbers(self) -> dict[int, float]:
        """Delay index -> delay time or ``delayMax`` (:func:`~acausal.compiler.timing.delay_numbers`)."""
        return delay_numbers(self.flat.delays, self.cache.parameters.symbols)

    def start_value_relations(self, start_time: float) -> tuple[bool, ...]:
        """Each relation evaluated with the start values of the variables
        (:func:`~acausal.compiler.initial.start_value_relations`)."""
        return start_value_relations(self.flat, self.partitioned.relations, self.cache.parameters.symbols,
                                     start_time)

    # -- summary --------------------------------------------------------------

    def mode_systems(self) -> list[ModeSystem]:
        """Every system compiled so far: the clusters' and the whole model's."""
        return list(self.parts.values()) + [s for s in self.systems.values() if isinstance(s, ModeSystem)]

    @property
    def compiled_systems(self) -> int:
        """How many systems were compiled (discrete states with equal equations share one;
        with clusters, each cluster's systems count)."""
        return sum(s.shares is None for s in self.mode_systems())

    @property
    def translation_seconds(self) -> float:
        """Seconds spent translating so far: flattening, every system compiled, every initialization system."""
        return self.flatten_seconds + self._compiled_seconds

    @property
    def initial_seconds(self) -> float:
        """Seconds spent compiling initialization problems (the clusters' included)."""
        return (sum(s.seconds for s in self.initial_systems.values())
                + sum(s.seconds for s in self.initial_parts.values()))


def _relaxed_constraints(relaxation, variables: Mapping[str, FlatVariable]) -> RelaxedConstraints:
    """A :class:`~acausal.compiler.structure.Relaxation` as the mode system keeps it."""
    left_out = tuple(f"{e.origin.component or '(model)'} ({e.origin.declared_in} eq. {e.origin.index + 1})"
                     for e in relaxation.dropped)
    components = [e.origin.component or "(model)" for e in relaxation.dropped]
    components += [(variables[name].component if name in variables else "") or "(model)"
                   for name in relaxation.zeroed]
    return RelaxedConstraints(tuple(dict.fromkeys(components)), left_out, tuple(relaxation.zeroed))


def _mode_fields(system: ModeSystem) -> dict:
    """A mode system's metadata as the persistent cache stores it."""
    return {"description": system.description, "states": list(system.states),
            "unknowns": list(system.unknowns), "derivatives": list(system.derivative_names),
            "alias_plan": [list(a) for a in system.alias_plan],
            "shares": None if system.shares is None else list(system.shares),
            "relaxed": None if system.relaxed is None else system.relaxed.payload()}


def _initial_fields(system: InitialSystem) -> dict:
    """An initialization system's metadata as the persistent cache stores it."""
    fields = {"unknowns": list(system.unknowns), "relaxed": [list(r) for r in system.relaxed],
              "from_start": [list(r) for r in system.from_start]}
    if system.starts:
        fields["starts"] = system.starts.payload()
    return fields


def _bound_fields(aliases, algebraic) -> dict:
    """What binding a shipped system to other parameter values needs, as text
    (``sympy.srepr``, read back exactly): its aliases, the expressions its
    solution divides by, and the fixed start values its mode makes constants."""
    return {"aliases": {n: sp.srepr(sp.sympify(e)) for n, e in aliases.aliases.items()},
            "nonzero": [sp.srepr(sp.sympify(g)) for g in algebraic.nonzero],
            "fixed_constants": _fixed_constants_field(aliases)}


def _fixed_constants_field(aliases) -> list:
    """The fixed start values a mode makes constants, as text (checked by :func:`_fits`)."""
    return [[n, sp.srepr(sp.sympify(e)), float(start)] for n, e, start in aliases.fixed_constants]


def _without_tunable_starts(flat: FlatModel) -> FlatModel:
    """``flat`` with its tunable start values set to 0: the same for every start value given."""
    if not flat.tunable_starts:
        return flat
    tunable = set(flat.tunable_starts)
    return dataclasses.replace(flat, variables=tuple(dataclasses.replace(v, start=0.0) if v.name in tunable
                                                     else v for v in flat.variables))


@functools.lru_cache(maxsize=65536)
def _expression(text: str) -> sp.Expr:
    """An expression printed by ``sympy.srepr`` (memoised: every run of a sweep reads the same ones).

    Its real symbols are the engine's own (:func:`~acausal.language.real_symbol`):
    once sympy's bounded cache has dropped ``Symbol('time', real=True)``, reading
    it anew would make an equal but distinct ``time``, which the engine, which
    recognises ``time`` by identity, would take for an unknown (and sympy's cache
    of expressions would then hand it to equations built later).
    """
    return sp.sympify(text, locals={"Symbol": _symbol})


def _symbol(name: str, **assumptions) -> sp.Symbol:
    """``Symbol(name, **assumptions)``, the engine's own object for a real symbol."""
    return real_symbol(name) if assumptions == {"real": True} else sp.Symbol(name, **assumptions)


def _is_real_symbol(symbol: sp.Symbol) -> bool:
    """Whether ``symbol`` has the assumptions :func:`real_symbol` gives (``real=True`` only)."""
    return symbol == real_symbol(symbol.name)


def _fits(payload: dict, parameter_symbols) -> bool:
    """Whether a shipped system serves these parameter values (payloads of the
    persistent cache, made for the values of their key, always do).

    Raises
    ------
    InitializationError
        A fixed start value conflicts with the constant these values give it,
        as when a translation is rebound (:func:`_bind_initial`).
    """
    if any(_expression(g).xreplace(parameter_symbols).is_zero for g in payload.get("nonzero", ())):
        return False
    # a Newton iteration's first guess, printed as a number, is a start value given otherwise now
    if any(float(_expression(e).xreplace(parameter_symbols)) != value for _, e, value in payload.get("guesses", ())):
        return False
    if payload.get("fixed_constants"):
        check_fixed_constants(SimpleNamespace(fixed_constants=[
            (n, _expression(e), start) for n, e, start in payload["fixed_constants"]]), parameter_symbols)
    return True


def _same_structure(base: FlatModel, partitioned: PartitionedModel, flat: FlatModel) -> bool:
    """Whether ``flat`` (``base`` with other parameter values) keeps the systems compiled for
    ``base``: the same variables but for their tunable start values (those that are not
    are compiled into the code), the same zero parameters (structural zeros) and the same
    values of the parameters that relations of parameters alone compare."""
    if flat is base:
        return True
    old, new = base.parameter_values, flat.parameter_values
    return (_same_variables(base, flat) and old.keys() == new.keys()
            and all((old[n] == 0) == (new[n] == 0) for n in old)
            and all(old[n] == new[n] for n in partitioned.evaluated_parameters))


def _same_variables(base: FlatModel, flat: FlatModel) -> bool:
    """Whether ``flat``'s variables are ``base``'s but for their tunable start values."""
    if flat.variables == base.variables:
        return True
    if flat.tunable_starts != base.tunable_starts or len(flat.variables) != len(base.variables):
        return False
    tunable = set(base.tunable_starts)
    return all(a == b or (a.name in tunable and dataclasses.replace(a, start=b.start) == b)
               for a, b in zip(flat.variables, base.variables))


def _with_start_parameters(flat: FlatModel) -> FlatModel:
    """``flat`` with its tunable start values appended to its parameters: what the
    translation's parameter table (the generated code's vector) is made of."""
    starts = flat.start_parameters
    return dataclasses.replace(flat, parameters=flat.parameters + starts) if starts else flat


class _BundlePickler(pickle.Pickler):
    """Pickles a flat model for another process: the texts of equations made on demand
    (closures) are printed, table functions (classes made at run time) go by their data."""

    def reducer_override(self, obj):
        if type(obj) is sp.Symbol and obj.assumptions0.get("real") and _is_real_symbol(obj):
            # the receiving process's own symbol of that name: the engine recognises
            # ``time`` by identity, and sympy's bounded cache may have dropped the
            # object a plain unpickling would find
            return real_symbol, (obj.name,)
        if type(obj) is Origin and not isinstance(obj.source, str):
            return Origin, (obj.component, obj.component_class, obj.declared_in, obj.index, obj.text)
        if isinstance(obj, type) and issubclass(obj, sp.Function) and getattr(obj, "kind", None) == "linear" \
                and getattr(obj, "table", None) is not None:
            from ..tables import table_function

            return table_function, (obj.__name__, obj.table)
        if isinstance(obj, type) and issubclass(obj, TableFunction) and obj.rebuild:
            return _table_class, (obj.rebuild, obj.orders)
        return NotImplemented


@dataclasses.dataclass(frozen=True)
class TranslationBundle:
    """A translation as plain data (:meth:`Translation.export`): what another process
    needs to run the model with other parameter values without translating it.

    Attributes
    ----------
    model : bytes
        The flat model, the partitioned model and the clustering, pickled
        (texts of equations printed, table functions by their data).
    demand : frozenset of str or None
        The translation's output demand.
    redundant_constraints : str
        The translation's choice (see :func:`translate`).
    payloads : dict
        ``entry -> payload`` of every compiled system shipped: the persistent
        cache's payloads (generated source, states, unknowns, ...) plus what
        binding them to other values needs, as text.  JSON-able: no closure
        travels, only source.
    digest : str
        SHA-256 of ``model`` and ``payloads``: a process keeps what it read
        from a bundle by it.
    """

    model: bytes
    demand: frozenset[str] | None
    redundant_constraints: str
    payloads: dict
    digest: str = ""

    def __post_init__(self) -> None:
        if not self.digest:
            digest = hashlib.sha256(self.model)
            digest.update(json.dumps(self.payloads, sort_keys=True).encode())
            object.__setattr__(self, "digest", digest.hexdigest())

    def extended(self, payloads: Mapping[str, dict]) -> "TranslationBundle":
        """This bundle with more payloads (systems a process compiled from it, see
        :class:`~acausal.compiler.diskcache.MemoryCache`)."""
        return dataclasses.replace(self, payloads={**self.payloads, **payloads}, digest="")

    def unpacked(self) -> tuple[FlatModel, PartitionedModel, Clustering | None]:
        """The flat model, partitioned model and clustering (unpickled once per process)."""
        return _unpacked(self.model)

    def store(self) -> MemoryCache:
        """The payloads as a persistent-cache replacement (:class:`~acausal.compiler.diskcache.MemoryCache`)."""
        return MemoryCache(self.payloads)


@functools.lru_cache(maxsize=4)
def _unpacked(model: bytes) -> tuple:
    return pickle.loads(model)


def _bind_mode(source: ModeSystem, parameters) -> ModeSystem:
    """``source``'s compiled system bound to the values of ``parameters`` (a ParameterTable)."""
    t0 = _time.perf_counter()
    derivatives, crossings, outputs = source.code.make(parameters.vector)
    plan = alias_plan(source.aliases, parameters.symbols)
    return dataclasses.replace(source, derivatives=derivatives, crossings=crossings, outputs=outputs,
                               alias_plan=plan, passes=(("rebind", _time.perf_counter() - t0),))


def _bind_initial(source: InitialSystem, mode: ModeSystem, parameters) -> InitialSystem | None:
    """``source``'s initialization problem bound to ``parameters`` (start values included), its
    fixed constants checked; None when its code holds other start values as Newton guesses."""
    t0 = _time.perf_counter()
    check_fixed_constants(mode.aliases, parameters.symbols)
    bound = bind_start_values(source, parameters.symbols)
    if bound is None:
        return None
    _, _, outputs = source.code.make(parameters.vector)
    return dataclasses.replace(bound, outputs=outputs, passes=(("rebind", _time.perf_counter() - t0),))


def _shared(twin: ModeSystem, key: tuple, description: str, context: str, passes: PassLog) -> ModeSystem:
    """State ``key``'s system: ``twin``'s compiled functions (both specialise to the same
    equations); the source's first line names this state."""
    _, rest = twin.code.source.split("\n", 1)
    code = dataclasses.replace(twin.code, source=f"# generated by acausal for {context} "
                                                 f"(shared with an equal state)\n{rest}")
    return dataclasses.replace(twin, key=key, description=description, passes=tuple(passes.entries),
                               code=code, shares=twin.key)


#: Translations of recently translated flat models, by :func:`flat_signature` and output demand.
_CACHE: "OrderedDict[tuple, Translation]" = OrderedDict()
#: The first translation of each structure (parameter values abstracted), to rebind.
_STRUCTURES: "OrderedDict[tuple, Translation]" = OrderedDict()
CACHE_SIZE = 16


def flat_signature(flat: FlatModel, tunable: bool = False) -> tuple:
    """Everything a translation is computed from: two flat models with the same
    signature get the same compiled systems.

    The signature is taken from the flat model, not from the Python objects
    that built it: a component's ``equations()`` may read anything (an
    instance attribute, a global, a class attribute changed between runs),
    and whatever it read is in the equations it returned.  Equations count
    by their residuals (sympy compares table functions by their class, so a
    table's data is part of it), variables by all their attributes,
    parameters by their values; origins by where they come from (their text
    follows from the residual).

    With ``tunable``, parameters count only by whether they are zero (a zero
    is a structural zero) and tunable start values not at all (the code
    reads them from the parameter vector, and no equation holds them): the
    signature of the *structure*, which the compiled systems of one
    translation share across parameter and start values (see
    :meth:`Translation.rebound`).
    """
    equations = _Equations(flat)
    return _parameter_part(flat, tunable, equations) + (equations,)


def _parameter_part(flat: FlatModel, tunable: bool, equations: "_Equations") -> tuple:
    model = tuple((p.name, p.value == 0 if tunable else p.value) for p in flat.parameters)
    return (model,) if tunable else (model, equations.starts)


class _Equations:
    """Everything of a flat model's signature but its numeric parameters, hashed once.

    The exact and the structure signature of :func:`translate` share it: a
    large model's equations are then walked and hashed once, not per key and
    per dictionary lookup.
    """

    __slots__ = ("parts", "_hash", "starts")

    def __init__(self, flat: FlatModel) -> None:
        def origin(o) -> tuple:
            return (o.component, o.component_class, o.declared_in, o.index)

        # tunable start values are parameters of the code, not part of the structure:
        # kept apart (the exact signature has them), the variables counted without them
        tunable = set(flat.tunable_starts)
        starts = []
        variables = []
        for v in flat.variables:
            if v.name in tunable:
                starts.append(v.start)
                variables.append(tuple(None if f.name == "start" else _freeze(getattr(v, f.name))
                                       for f in dataclasses.fields(v)))
            else:
                variables.append(tuple(_freeze(getattr(v, f.name)) for f in dataclasses.fields(v)))
        self.starts = tuple(starts)
        self.parts = (
            flat.name, flat.modelica_class, flat.experiment,
            _freeze(flat.structural_parameters),
            tuple(variables), flat.tunable_starts,
            tuple((eq.residual, origin(eq.origin)) for eq in flat.equations),
            tuple((eq.variable, eq.rhs, origin(eq.origin)) for eq in flat.discrete_equations),
            tuple((eq.residual, origin(eq.origin)) for eq in flat.initial_equations),
            _freeze(flat.hints),
            # reinits, terminations and assertions: the runtime's part of the model
            repr(flat.hybrid),
        )
        self._hash = hash(self.parts)

    def __hash__(self) -> int:
        return self._hash

    def __eq__(self, other) -> bool:
        return self is other or (isinstance(other, _Equations) and self._hash == other._hash
                                 and self.parts == other.parts)


def _freeze(value):
    if isinstance(value, dict):
        return tuple(sorted((k, _freeze(v)) for k, v in value.items()))
    if isinstance(value, (list, tuple)):
        return tuple(_freeze(v) for v in value)
    if isinstance(value, np.ndarray):
        return ("array", value.shape, tuple(value.ravel().tolist()))
    if isinstance(value, sp.Basic):
        return ("sympy", sp.srepr(value))
    return (type(value).__name__, repr(value))


def with_start_values(parameters: Mapping[str, float] | None,
                      start: Mapping[str, float] | None) -> dict[str, float] | None:
    """``parameters`` with the start values ``start`` (variable -> value) added as the
    parameters ``<variable>.start``: what :func:`~acausal.compiler.flatten.flatten` takes.

    Raises
    ------
    SettingError
        For a start value given twice with different values (in ``start`` and
        as a parameter ``<variable>.start``), or a name that is not a string.
    """
    if not start:
        return dict(parameters) if parameters else None
    if not isinstance(start, Mapping):
        raise SettingError(f"start= takes a mapping of variable names to values, not {type(start).__name__}",
                           hint="e.g. start={'component.x': 3.0}")
    merged = dict(parameters or {})
    for name, value in start.items():
        if not isinstance(name, str):
            raise SettingError(f"start= names variables by their dotted names, not {name!r}",
                               hint="e.g. start={'component.x': 3.0}")
        key = start_parameter(name)
        if key in merged and merged[key] != value:
            raise SettingError(f"the start value of {name} is given twice: start={{{name!r}: {value!r}}} and "
                               f"parameters={{{key!r}: {merged[key]!r}}}", hint="give it once")
        merged[key] = value
    return merged


def translate(model: Component, outputs: Iterable[str] | None = None, cache: bool = True,
              parameters: Mapping[str, float] | None = None,
              redundant_constraints: str = "relax", disk_cache: bool = True,
              start: Mapping[str, float] | None = None,
              options: EngineOptions | None = None) -> Translation:
    """Flatten and partition ``model``; its systems are compiled on demand.

    Parameters
    ----------
    outputs : iterable of str, optional
        Compute only these variables (and what they and the events need):
        states and equations that cannot influence them are left out.
    cache : bool
        Reuse the translation (and every system compiled so far) of a model
        translated before in this process whose flat model is the same (see
        :func:`flat_signature`).  A model that differs only in the values of
        numeric parameters reuses the compiled systems of the first one, with
        its own parameter vector (:meth:`Translation.rebound`).  The model is
        always flattened: what its components' equations read cannot be
        known otherwise.  Also the persistent compile cache
        (:mod:`~acausal.compiler.diskcache`): systems compiled by an earlier
        process for the same flat model are loaded, new ones are stored.
        False turns both off.
    parameters : mapping, optional
        New values of parameters by dotted name.  Numeric ones are bound
        in place of their modifiers (see
        :func:`~acausal.compiler.flatten.flatten`); a structural one (it
        decides which equations or connectors exist) makes a new instance of
        the model's class with that value (:func:`~acausal.language.with_structural`),
        translated anew.  A name ``<variable>.start`` is a start value (as
        in ``start``).
    redundant_constraints : {'relax', 'error'}
        A discrete state in which two elements constrain the same motion
        (two stuck brakes on one rigid shaft) leaves the split of the holding
        force between them open.  'relax' (the default, what Modelica tools
        do) leaves one constraint out and sets one element's share to zero,
        (:func:`~acausal.compiler.structure.relax_redundant`; the system's
        ``relaxed`` says what, and every run that integrates in that state
        warns with a :class:`~acausal.errors.RedundantConstraintWarning` and
        a note); 'error' raises
        the :class:`~acausal.errors.StructurallySingularError` instead.
    disk_cache : bool
        False: a translation made by this call neither loads from nor stores
        into the persistent compile cache, so that every system it compiles
        keeps its stages (what :meth:`Translation.export` ships).  Such
        translations are cached in this process apart from the others.
    start : mapping, optional
        Start values by variable name, e.g. ``{"J1.w": 3.0}``, in place of
        those the model declares.  Those initialization reads (of state
        candidates and fixed variables, :attr:`FlatModel.tunable_starts`)
        are parameters of the generated code: like numeric parameters, other
        values reuse the compiled systems.  The parameter ``J1.w.start`` is
        the same value.
    options : EngineOptions, optional
        How the engine works (:class:`~acausal.options.EngineOptions`; the
        defaults otherwise).  Translations with other compiler options
        (:attr:`~acausal.options.EngineOptions.compiler_fields`) are cached
        apart; the runtime's are those of the runs (``simulate(translation)``
        uses the translation's unless given others).
    """
    if redundant_constraints not in ("relax", "error"):
        raise SettingError(f"redundant_constraints must be 'relax' or 'error', not {redundant_constraints!r}",
                           hint="'relax' picks a split of the holding force as Modelica tools do")
    if options is None:
        options = DEFAULT_OPTIONS
    elif not isinstance(options, EngineOptions):
        raise SettingError(f"options must be an EngineOptions, not {type(options).__name__}",
                           hint="from acausal import EngineOptions; translate(model, options=EngineOptions(...))")
    t0 = _time.perf_counter()
    parameters = with_start_values(parameters, start)
    if parameters:
        # a structural parameter changes the equations: the model is rebuilt with it
        # (a new instance; the one given is not changed) and translated anew
        structural = structural_names(model, parameters)
        if structural:
            model = with_structural(model, {n: parameters[n] for n in structural})
            parameters = {n: v for n, v in parameters.items() if n not in structural}
    flat = flatten(model, dict(parameters) if parameters else None, templates=options.templates)
    demand = _demand(flat, outputs)
    if not cache:
        return Translation(flat, partition(flat, templates=options.templates), _time.perf_counter() - t0, demand,
                           disk=False, redundant_constraints=redundant_constraints, options=options)
    equations = _Equations(flat)
    # translations without the disk cache are kept apart: theirs keep every stage; so are
    # those of other compiler options (the runtime's are the run's: simulate() passes them)
    key = (_parameter_part(flat, False, equations), equations, demand, redundant_constraints, disk_cache,
           options.compiler_key)
    found = _CACHE.get(key)
    if found is not None:
        _CACHE.move_to_end(key)
        return found
    structure = (_parameter_part(flat, True, equations), equations, demand, redundant_constraints, disk_cache,
                 options.compiler_key)
    base = _STRUCTURES.get(structure)
    translation = base.rebound(flat, _time.perf_counter() - t0) if base is not None else None
    if translation is None:
        translation = Translation(flat, partition(flat, templates=options.templates), _time.perf_counter() - t0,
                                  demand, redundant_constraints=redundant_constraints, disk=disk_cache,
                                  options=options)
        _remember(_STRUCTURES, structure, translation)
    elif not disk_cache:
        translation._disk = False  # rebound from one made without the disk cache: the same
    _remember(_CACHE, key, translation)
    return translation


def _remember(cache: OrderedDict, key: tuple, translation: Translation) -> None:
    cache[key] = translation
    cache.move_to_end(key)
    while len(cache) > CACHE_SIZE:
        cache.popitem(last=False)


def _demand(flat: FlatModel, outputs: Iterable[str] | None) -> frozenset[str] | None:
    """The outputs asked for, checked against the model's names (None: everything)."""
    if outputs is None:
        return None
    known = {v.name for v in flat.variables} | {p.name for p in flat.parameters}
    demand = frozenset(outputs)
    unknown = sorted(n for n in demand if n not in known and not is_derivative(n))
    if unknown:
        close = difflib.get_close_matches(unknown[0], sorted(known), n=3)
        raise ModelDefinitionError(f"{flat.name} has no variable {unknown[0]!r}",
                                   hint=f"did you mean {', '.join(close)}?" if close else
                                   "outputs are dotted variable names, e.g. component.variable")
    # the expressions of delay() are read back from the history: always computed
    demand |= {d.variable for d in flat.delays}
    return frozenset(n for n in demand if n in known and n not in flat.parameter_values
                     or is_derivative(n))
