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
import time as _time
from collections import OrderedDict
from typing import Any, Callable, Iterable, Mapping, Sequence

import numpy as np
import sympy as sp

from ..errors import ModelDefinitionError, SettingError, StructuralError, StructurallySingularError
from ..language import Component, structural_names, with_structural
from ..names import is_derivative, parse
from .cache import ModelCache
from .canonical import substituted
from .diskcache import DiskCache
from .clusters import Clustering, ComposedInitialSystem, ComposedSystem, compose_initial, find_clusters
from .flatten import FlatEquation, FlatModel, FlatVariable, flatten, start_parameter
from .initial import InitialSystem, compile_initial_system, start_value_relations
from .modes import (ModeSystem, PassLog, RelaxedConstraints, brief_description, compile_mode, describe_key,
                    shared_system)
from .compiled import ClockData, DelayData, ModelData
from .partition import PartitionedModel, partition
from .discrete import DiscreteProgram, compile_discrete
from .timing import clock_ticks, delay_numbers, held_time_events, time_event_roots
from ..options import DEFAULT_OPTIONS, EngineOptions
from .structure import _incidence, relax_redundant
from .parts import PartSystems
from .persist import PersistentSystems, TranslationBundle
from .rebinding import Rebinding

__all__ = ["ModeSystem", "InitialSystem", "ComposedSystem", "Translation", "TranslationBundle", "translate",
           "flat_signature", "describe_key", "with_start_values"]


def _value_of(value) -> Any:
    if isinstance(value, (bool, np.bool_)):
        return sp.true if value else sp.false
    return sp.Integer(int(value))


class Translation(PartSystems, Rebinding, PersistentSystems):
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
        #: parts compiled for themselves by shape (:mod:`~acausal.compiler.part_shapes`), and the
        #: renaming of each part renamed from one: (cluster, key) -> PartTwin
        self._by_shape: dict[tuple, tuple] = {}
        self._renamed: dict[tuple, object] = {}
        self._cluster_shapes: dict[int, tuple | None] = {}
        self._renamings: dict[tuple, tuple] = {}
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
        positions = self._selector_positions()
        # Parameters that are zero are structural zeros: the matching ignores
        # the terms they multiply, so the generated code must not contain them.
        zeros = self.cache.parameters.zeros
        subs: dict = {}  # the values of the symbols these equations read (a part's equations
        # read a few of a large model's selectors: the others are not looked at)

        def value(s):
            found = subs.get(s)
            if found is None:
                found = subs[s] = zeros[s] if s in zeros else _value_of(key[positions[s]])
            return found

        source = self.partitioned.equations if equations is None else equations
        memo = self.cache.specialise
        out = []
        for eq in source:
            # Only the discrete symbols an equation contains decide its form:
            # an equation is specialised once per combination of their values.
            used = memo.used.get(eq.residual)
            if used is None:
                used = memo.used[eq.residual] = tuple(s for s in eq.residual.free_symbols
                                                      if s in positions or s in zeros)
            form_key = (eq.residual, tuple(value(s) for s in used))
            residual = memo.forms.get(form_key)
            if residual is None:
                residual = substituted(eq.residual, {s: subs[s] for s in used}, memo.shapes) if used \
                    else eq.residual
                leftover = [s.name for s in residual.free_symbols
                            if parse(s.name).kind in ("relation", "initial") or s.name in self._discrete_names]
                if leftover:
                    raise StructuralError(f"{eq.origin}: discrete value {leftover[0]} left after "
                                          f"specialisation", components=(eq.origin.component,))
                memo.forms[form_key] = residual
            out.append(eq if residual is eq.residual else FlatEquation(residual, eq.origin))
        return tuple(out)

    def _selector_positions(self) -> dict:
        """Each selector symbol's position in a key (made once per partitioned model)."""
        found = self.__dict__.get("_positions")
        if found is None or found[0] is not self.partitioned:
            found = self._positions = (self.partitioned, {s: i for i, s in enumerate(self.selectors)})
        return found[1]

    # -- building systems -----------------------------------------------------

    def _context(self, description: str) -> str:
        return f"{self.flat.name} [{brief_description(description)}]" if self.partitioned.is_hybrid else self.flat.name

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
            return shared_system(twin, key, description, context, passes)
        try:
            system = self._compiled_or_relaxed(key, description, context, equations, passes,
                                               self.partitioned.equations, self.continuous, self.cache,
                                               self.demand)
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

    def _compiled_or_relaxed(self, key: tuple, description: str, context: str,
                             equations: Sequence[FlatEquation], passes: PassLog, sources: Sequence[FlatEquation],
                             variables: Mapping[str, FlatVariable], cache: ModelCache,
                             demand: frozenset[str] | None, relations: Sequence[int] | None = None) -> ModeSystem:
        """:func:`compile_mode` of the specialised ``equations`` (of the flat equations
        ``sources``, in their order) over ``variables``: the whole model's, or one
        independent part's.  A discrete state that constrains one motion twice (two
        stuck friction elements on one shaft) is relaxed (:meth:`_relaxed`); other
        structural errors are raised."""
        try:
            return compile_mode(key, description, context, equations, passes, self.partitioned, variables,
                                cache, demand, relations)
        except StructurallySingularError:
            system = self._relaxed(key, description, context, equations, passes, sources, variables, cache,
                                   demand, relations)
            if system is None:
                raise
            return system

    def _relaxed(self, key: tuple, description: str, context: str, equations: Sequence[FlatEquation],
                 passes: PassLog, sources: Sequence[FlatEquation], variables: Mapping[str, FlatVariable],
                 cache: ModelCache, demand: frozenset[str] | None,
                 relations: Sequence[int] | None) -> ModeSystem | None:
        """The system of a discrete state that constrains one motion twice, made
        solvable by :func:`relax_redundant` (None: not of that kind); the arguments
        as :meth:`_compiled_or_relaxed`'s."""
        if not self.partitioned.is_hybrid or self.redundant_constraints != "relax":
            return None
        symbols = cache.parameters.symbols
        # the equations whose form the discrete state selects (not those that changed
        # only because a zero parameter was put in)
        selectors = set(self.selectors)
        selected = [i for i, source in enumerate(sources) if not selectors.isdisjoint(source.residual.free_symbols)]
        flows = [n for n, v in variables.items() if v.role == "flow"]
        found = relax_redundant(equations, [_incidence(e.residual, symbols) for e in equations],
                                list(variables), selected, flows)
        if found is None:
            return None
        relaxed, relaxation = found
        try:
            system = compile_mode(key, description, context, relaxed, passes, self.partitioned, variables,
                                  cache, demand, relations)
        except StructuralError:
            return None
        # not warned here: every run that integrates in this state says so (the
        # runtime reads ``relaxed``), also when the system comes from the disk cache
        return dataclasses.replace(system, relaxed=_relaxed_constraints(relaxation, self.continuous))

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
            context += f" [{brief_description(mode.description)}]"
        return compile_initial_system(mode, self.specialise(key, self.partitioned.initial_equations),
                                      context, self.cache, self.continuous, self.flat.delays)

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

    def reset_warm_starts(self) -> None:
        """Every system compiled so far forgets its warm starts (a run begins): the whole
        model's and the parts' (a composed system is made of the parts' systems, each reset once)."""
        for table in (self.systems, self.initial_systems, self.parts, self.initial_parts):
            for system in table.values():
                if not isinstance(system, (ComposedSystem, ComposedInitialSystem)):
                    system.reset()

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
        with clusters, each cluster's systems count, but not those renamed from a part of
        the same shape)."""
        return sum(s.shares is None and s.shape_of is None for s in self.mode_systems())

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


def _with_start_parameters(flat: FlatModel) -> FlatModel:
    """``flat`` with its tunable start values appended to its parameters: what the
    translation's parameter table (the generated code's vector) is made of."""
    starts = flat.start_parameters
    return dataclasses.replace(flat, parameters=flat.parameters + starts) if starts else flat


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
