"""Compiled systems kept beyond one translation: the persistent compile cache and bundles.

Two ways a compiled system outlives the translation that compiled it:

* **The persistent compile cache** (:mod:`~acausal.compiler.diskcache`): each
  system's generated source and the fields it is rebuilt from, stored under
  the flat model's key, loaded by a later process instead of compiled.
* **Bundles** (:class:`TranslationBundle`): a translation as plain data --
  the pickled flat and partitioned model and every compiled system's
  payload -- shipped to the workers of a sweep (:meth:`PersistentSystems.export`,
  :meth:`PersistentSystems.from_bundle`).

:class:`PersistentSystems` is the part of
:class:`~acausal.compiler.translate.Translation` that does this; it reads the
translation's ``flat``, ``demand``, ``clustering``, ``redundant_constraints``,
``continuous`` and system tables, and keeps ``_disk`` (the cache: None = not
looked up yet, False = off) and ``_tables`` (the model's table functions).
"""

from __future__ import annotations

import dataclasses
import functools
import hashlib
import io
import json
import pickle
import re
import time as _time
from types import SimpleNamespace
from typing import Any, Mapping

import sympy as sp

from ..errors import InitializationError
from ..language import real_symbol
from ..table_calls import TABLE_CALLS
from .run_context import delayed_value
from .timing import held_time_event_source, time_event_roots
from ..tables import TableFunction, _table_class
from .algebraic import NewtonSolve
from .cache import ModelCache
from .codegen import GeneratedCode
from .generated import load_make
from .diskcache import DiskCache, MemoryCache, cache_folder, disk_cache_enabled, model_key
from .clusters import Clustering
from .flatten import FlatModel, Origin
from .initial import (InitialSystem, StartDependence, StartValues, bind_start_values, check_fixed_constants,
                      newton_guesses)
from .modes import ModeSystem, RelaxedConstraints, alias_plan
from .part_shapes import renamed_stage_fields
from .partition import PartitionedModel, partition

__all__ = ["PersistentSystems", "TranslationBundle"]

#: A call of a table function in generated code (see ``codegen._Printer``).
_CALLED_TABLE = re.compile(r"\b(_f_\w+)\(")


class PersistentSystems:
    """Saving and loading compiled systems (see the module docstring)."""

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
        if system.passes[:1] and system.passes[0][0] in ("rebind", "rename part"):
            # compiled for other parameter values (or another part): a compilation for these could
            # make other numeric choices; only what was compiled for the key is stored
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
        if system.shape_of is not None:
            return  # renamed from another part (part_shapes): only what a part compiled is stored
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
                plan = _bundle_plan(self._disk, entry, payload, cache.parameters)
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

    # -- a run saved whole (acausal.compiler.saved) ------------------------------

    def saved(self) -> "SavedModel | str":
        """What a warm command needs to run this model again without the compiler
        (:class:`~acausal.compiler.saved.SavedModel`), or why it cannot be saved.

        Saved are models whose run needs no more than continuous systems of the
        whole model, discrete equations and discrete Reals, when-clauses
        (reinit, terminate), assertions, tables (:mod:`acausal.table_calls`,
        pickled with their data), delays, sample clocks and time events; the
        others (impure functions, independent parts compiled apart, an output
        demand, homotopy) are translated by every command, as before.
        """
        from .saved import SavedModel

        flat, partitioned = self.flat, self.partitioned
        discrete = hybrid = None
        if partitioned.discrete_equations or flat.hybrid:
            program = self.discrete_program(lambda *args: None)
            if program.source is None:
                return "the model's discrete equations call an impure function"
            if program.hybrid_source is None:
                return "the model's when-clauses or assertions call an impure function"
            discrete = {"source": program.source, "calls": dict(program.calls),
                        "equations": [[variable, list(args), str(origin)]
                                      for variable, args, _fn, origin in program.equations]}
            if flat.hybrid:
                hybrid = _hybrid_payload(program)
        reasons = [
            (self.demand is not None, "an output demand"),
            (flat.homotopy is not None, "homotopy()"),
            (bool(self.parts or self.initial_parts), "independent parts"),
        ]
        for found, what in reasons:
            if found:
                return f"the model has {what}"
        roots = time_event_roots(partitioned.relations, self.cache.parameters.symbols)
        held_source, held_items = held_time_event_source(partitioned.relations, self.cache.parameters.symbols)
        timing = {"roots": tuple(roots), "held_source": held_source, "held": held_items,
                  "clock_ticks": self.clock_ticks(), "delay_numbers": self.delay_numbers()}
        if not self._tables:
            self._tables = self._table_functions() or {}
        systems, initial = [], []
        tables: dict[str, Any] = {}  # the tables the systems call, by class name

        def plain(payload: dict | None) -> bool:
            if payload is None:
                return False
            for class_name in payload["functions"].values():
                tables[class_name] = self._tables[class_name]
                if not (isinstance(tables[class_name], TABLE_CALLS) or tables[class_name] is delayed_value):
                    return False
            return True

        for system in self.systems.values():
            if not isinstance(system, ModeSystem) or system.relaxed is not None or system.code is None:
                return "a discrete state's system is not a plain one"
            payload = self._payload(system, _mode_fields(system))
            if not plain(payload):
                return "a system calls a function that is not a table of this model"
            systems.append(payload)
        for system in self.initial_systems.values():
            if not isinstance(system, InitialSystem) or system.code is None:
                return "an initialization problem is not a plain one"
            payload = self._payload(system, _initial_fields(system))
            if not plain(payload):
                return "an initialization problem calls a function that is not a table of this model"
            initial.append(payload)
        return SavedModel(self.data, self.options, tuple(systems), tuple(initial), timing, discrete, hybrid, tables)

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
            elif isinstance(system, ModeSystem) and system.shape_of is not None:
                # renamed from another part (part_shapes): that part's stages, in this one's names
                fields = self._renamed_fields(entry, system)
                if fields is not None:
                    add(entry, system, {**_mode_fields(system), **fields})
        initials = [(f"initial {k!r}", s, self.systems.get(k)) for k, s in self.initial_systems.items()]
        initials += [(f"initial-part {i} {k!r}", s, self.parts.get((i, k)))
                     for (i, k), s in self.initial_parts.items()]
        for entry, system, mode in initials:
            if isinstance(system, InitialSystem) and system.algebraic is not None \
                    and isinstance(mode, ModeSystem) and mode.aliases is not None:
                add(entry, system, {**_initial_fields(system), **_bound_fields(mode.aliases, system.algebraic)})
            elif isinstance(system, InitialSystem) and isinstance(mode, ModeSystem) and mode.shape_of is not None:
                fields = self._renamed_fields(entry, mode, initial=True)
                if fields is not None:
                    add(entry, system, {**_initial_fields(system), **fields})
        pickler_output = io.BytesIO()
        _BundlePickler(pickler_output, protocol=pickle.HIGHEST_PROTOCOL).dump(
            (self.flat, self.partitioned, self.clustering))
        return TranslationBundle(pickler_output.getvalue(), self.demand, self.redundant_constraints, payloads)

    def _renamed_fields(self, entry: str, mode: ModeSystem, initial: bool = False) -> dict | None:
        """The bound fields (and Newton guesses) of the part renamed from another
        (:mod:`~acausal.compiler.part_shapes`) that ``entry`` names, from the other part's
        stages renamed; None when they cannot be had (the part is then left out)."""
        index, key = int(entry.split()[1]), mode.key  # ("part 3 (...)", "initial-part 3 (...)")
        renaming = self._renamed.get((index, key))
        if renaming is None or renaming.mode.aliases is None:
            return None
        try:
            source_initial = None
            if initial:
                source_initial = self.initial_parts.get((renaming.cluster, renaming.mode.key))
                if source_initial is None or source_initial.algebraic is None:
                    return None
            aliases, guards = renamed_stage_fields(renaming, source_initial)
            fields = _bound_fields(aliases, guards)
            if not initial and any(isinstance(s, NewtonSolve) for s in renaming.mode.algebraic.steps):
                twin_cache = self._cluster_cache(self.clustering.clusters[renaming.cluster])
                starts = StartValues(renaming.mode.aliases.aliases, renaming.mode.aliases.variables,
                                     self.continuous, twin_cache.parameters.symbols)
                fields["guesses"] = [[renaming.name(n), sp.srepr(renaming.expression(e)), v]
                                     for n, e, v in newton_guesses(renaming.mode.algebraic, starts)]
        except KeyError:
            return None
        return fields

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


def _hybrid_payload(program) -> dict:
    """The reinits, terminations and assertions of a compiled discrete ``program`` as
    plain data: their generated source, arguments, messages and origins (as text, each
    origin once: the runtime tells two reinits of one when-clause apart by identity)."""
    from .compiled import ActionOrigin

    origins: list[ActionOrigin] = []
    index: dict[int, int] = {}

    def origin_index(origin) -> int:
        if id(origin) not in index:
            index[id(origin)] = len(origins)
            origins.append(ActionOrigin(origin.component, str(origin)))
        return index[id(origin)]

    return {"source": program.hybrid_source, "origins": origins,
            "reinits": [[r.variable, origin_index(r.origin), list(fire_args), list(value_args)]
                        for r, fire_args, _f, value_args, _v in program.reinits],
            "terminations": [[r.message, origin_index(r.origin), list(args)]
                             for r, args, _f in program.terminations],
            "asserts": [[a.message, a.level, origin_index(a.origin), list(args)]
                        for a, args, _f in program.asserts]}


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
        SHA-256 of ``model``, ``demand``, ``redundant_constraints`` and
        ``payloads``: a process keeps what it read from a bundle by it (two
        sweeps of one model with other outputs are other bundles).
    """

    model: bytes
    demand: frozenset[str] | None
    redundant_constraints: str
    payloads: dict
    digest: str = ""

    def __post_init__(self) -> None:
        if not self.digest:
            digest = hashlib.sha256(self.model)
            demand = None if self.demand is None else sorted(self.demand)
            digest.update(json.dumps([demand, self.redundant_constraints]).encode())
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


def _bundle_plan(store, entry: str, payload: dict, parameters) -> tuple:
    """A shipped system's alias plan for ``parameters`` (a ParameterTable).

    The plan depends only on the values of the parameters its aliases read,
    which most runs of a sweep leave as they are: a bundle's store keeps it by
    those values (as ``repr``, so that -0.0 and 0.0 stay apart), so that the
    sympy work is done once per process and distinct values.
    """
    plans = getattr(store, "plans", None)
    if plans is None:
        aliases = {n: _expression(e) for n, e in payload["aliases"].items()}
        return alias_plan(SimpleNamespace(aliases=aliases), parameters.symbols)
    reads = plans.get(entry)
    if reads is None:
        aliases = {n: _expression(e) for n, e in payload["aliases"].items()}
        reads = plans[entry] = tuple(sorted({s.name for e in aliases.values() for s in e.free_symbols}
                                            & parameters.values.keys()))
    key = (entry, tuple(repr(parameters.values[n]) for n in reads))
    plan = plans.get(key)
    if plan is None:
        aliases = {n: _expression(e) for n, e in payload["aliases"].items()}
        plan = plans[key] = alias_plan(SimpleNamespace(aliases=aliases), parameters.symbols)
    return plan


@functools.lru_cache(maxsize=4)
def _unpacked(model: bytes) -> tuple:
    return pickle.loads(model)


