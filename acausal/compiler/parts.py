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
"""

from __future__ import annotations

import dataclasses
import functools
import time as _time


from ..errors import StructuralError
from ..names import is_derivative, parse
from .cache import ModelCache
from .clusters import Cluster, ComposedInitialSystem, ComposedSystem, compose
from .flatten import start_parameter
from .initial import InitialSystem, compile_initial_system
from .modes import ModeSystem, PassLog, compile_mode, describe_key, shared_system
from .rebinding import _bind_mode

__all__ = ["PartSystems"]


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
            return shared_system(twin, subkey, description, context, passes)
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

