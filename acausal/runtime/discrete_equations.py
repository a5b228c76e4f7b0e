"""The discrete equations of a model, as the runtime evaluates them.

The compiled model gives its discrete part as a program
(``CompiledModel.discrete_program``): the discrete equations in dependency
order (``variable = fn(*args)``), and the reinits, terminations and
assertions of its when-clauses.  :class:`DiscreteEquations` knows what each
equation reads (relations, ``pre()`` values, ``initial()``, clocks, continuous
values, parameters), builds the names a pass sees (:meth:`~DiscreteEquations.environment`)
and runs one pass over the equations (:meth:`~DiscreteEquations.evaluate`).

A pass is computed from the last one where few of its inputs changed (only
the equations that read something changed are evaluated again): with many
independent parts this keeps event iteration local to the parts concerned.
That last pass is a cache: it is kept across events and runs, and a pass
computed from it has exactly the values a full pass would have.
"""

from __future__ import annotations

import heapq
from typing import Mapping

from ..names import INITIAL_NAME, TERMINAL_NAME, is_relation, parse, pre_name, relation_name
from .contract import CompiledSystem

__all__ = ["DiscreteEquations", "cast", "mode_values", "with_aliases"]


def mode_values(system: CompiledSystem, t: float, x) -> dict[str, float]:
    """All continuous variables at ``(t, x)``: unknowns, states and aliases."""
    return with_aliases(system.values(t, x), system)


def with_aliases(values: dict[str, float], system) -> dict[str, float]:
    """``values`` (changed in place and returned) with the aliases of ``system`` added."""
    for name, coeff, source in getattr(system, "alias_plan", ()) or ():
        if source is None:
            values[name] = coeff
        elif source in values:  # with an output demand, some are not computed
            values[name] = coeff * values[source]
    return values


def cast(kind: str, value):
    """A discrete equation's value as its variable's type."""
    if kind == "boolean":
        return bool(value)
    if kind == "integer":
        return int(value)
    return float(value)


class DiscreteEquations:
    """The discrete part of a model: its equations, what they read, one pass over them.

    Parameters
    ----------
    data : ModelData
        The model's plain data (variables, relations, clocks, parameters).
    program : DiscreteProgram
        The compiled discrete equations, reinits, terminations and assertions.
    incremental : bool
        Whether a pass is computed from the last one where that is cheaper
        (:attr:`acausal.options.EngineOptions.incremental_events`); False
        evaluates every equation, with the same results.

    Attributes
    ----------
    equations : list of (variable, args, fn, origin)
        The discrete equations in evaluation order.
    kinds : dict
        The type of every discrete variable and held (discrete Real) value, by name.
    readers : dict
        For each name, the equations that read it, in evaluation order.
    continuous_args : set
        The continuous values (and their left limits ``pre(u)``) the equations,
        reinits and terminations read.
    hybrid : bool
        Whether the equations read more than discrete values, relations, ``pre()``
        and ``initial()`` (clocks, continuous values, parameters, held values; or
        the model has reinits, terminations or assertions): then every pass
        evaluates everything, since those values are not tracked.
    """

    def __init__(self, data, program, incremental: bool = True) -> None:
        self.incremental = incremental
        self.held = data.held_variables
        variables = data.variable_map
        self.kinds = {n: variables[n].kind for n in (*data.discrete_variables, *self.held)}
        self.equations = list(program.equations)
        self.relation_names = [relation_name(k) for k in range(len(data.relations))]
        self._pre_names: dict[str, str] = {}
        self.readers: dict[str, list[int]] = {}
        for i, (_variable, args, _fn, _origin) in enumerate(self.equations):
            for a in args:
                self.readers.setdefault(a, []).append(i)
        self.relation_free = [eq for eq in self.equations if not any(is_relation(a) for a in eq[1])]
        self.equation_of = {eq[0]: i for i, eq in enumerate(self.equations)}
        # where each argument of each equation comes from in a pass: True for a variable
        # whose own equation comes earlier (its value in this pass), False for what the
        # pass starts from (relations, pre() values, initial(), later variables)
        own = self.equation_of
        self._argument_sources = [[(a, a in own and own[a] < i) for a in args]
                                  for i, (_variable, args, _fn, _origin) in enumerate(self.equations)]
        #: the equations that read a variable's value the pass starts from
        self._early_readers: dict[str, list[int]] = {}
        for i, sources in enumerate(self._argument_sources):
            for a, late in sources:
                if not late and a in self.kinds:
                    self._early_readers.setdefault(a, []).append(i)
        self._read_hybrid(data, program)
        #: cache: the last full pass, ``(pre, initial, relations, the values it started
        #: from, result)``, from which :meth:`evaluate` computes the next one
        self._last_pass: tuple | None = None

    def _read_hybrid(self, data, program) -> None:
        """What the discrete equations read besides discrete values and relations
        (continuous values, their left limits, sample clocks, terminal(), parameters),
        and the reinits, terminations and assertions of ``program``."""
        self.clocks = data.clocks
        own = {*self.kinds, INITIAL_NAME, TERMINAL_NAME}
        parameters = data.parameter_table
        #: the parameters the discrete equations, reinits and assertions read
        self.constants: dict[str, float] = {}

        def continuous_reads(names) -> set[str]:
            out = set()
            for a in names:
                what = parse(a)
                if a in parameters:
                    self.constants[a] = parameters[a]
                    continue
                if a in own or what.kind in ("relation", "sample") or (
                        what.kind == "pre" and what.base in self.kinds):
                    continue
                out.add(a)
            return out

        arguments = [args for _variable, args, _fn, _origin in self.equations]
        self.continuous_args = set().union(*map(continuous_reads, arguments)) if arguments else set()
        self.reinits = list(program.reinits)
        self.terminations = list(program.terminations)
        self.asserts = list(program.asserts)
        for _r, fire_args, _f, value_args, _v in self.reinits:
            self.continuous_args |= continuous_reads(fire_args) | continuous_reads(value_args)
        for _r, fire_args, _f in self.terminations:
            self.continuous_args |= continuous_reads(fire_args)
        self._assert_continuous = set()
        for _a, args, _f in self.asserts:
            self._assert_continuous |= continuous_reads(args)
        #: whether anything reads terminal() (then the run ends with one more event iteration)
        self.uses_terminal = any(TERMINAL_NAME in args for args in arguments) or any(
            TERMINAL_NAME in item[1] for item in (*self.reinits, *self.terminations)) or any(
            TERMINAL_NAME in args for _a, args, _f in self.asserts)
        self.hybrid = bool(self.continuous_args or self.clocks or self.held or self.reinits
                           or self.terminations or self.constants or self.asserts)

    # -- what a pass reads -------------------------------------------------------------

    def environment(self, relations, initial: bool, pre: Mapping, extra: Mapping) -> dict:
        """The names the discrete equations read: relation indicators, initial(), pre values;
        for a hybrid model also terminal() and the clocks (false), the parameters and ``extra``
        (the clocks that tick, terminal(), continuous values: see :meth:`continuous_values`)."""
        env = dict(zip(self.relation_names, relations))
        env[INITIAL_NAME] = initial
        pre_key = self.pre_key
        for name, value in pre.items():
            env[pre_key(name)] = value
        if self.hybrid:
            env[TERMINAL_NAME] = False
            for clock in self.clocks:
                env[clock.name] = False
            env.update(self.constants)
            env.update(extra)
        return env

    def pre_key(self, name: str) -> str:
        """``pre(name)`` as the discrete equations name it (made once per name)."""
        key = self._pre_names.get(name)
        if key is None:
            key = self._pre_names[name] = pre_name(name)
        return key

    def continuous_values(self, system: CompiledSystem, t: float, x, left: Mapping) -> dict:
        """The continuous values the discrete equations read at ``(t, x)``, and the left
        limits (``pre(u)`` of a continuous ``u``, from ``left``)."""
        if not self.continuous_args:
            return {}
        values = mode_values(system, t, x)
        env = {}
        for name in self.continuous_args:
            what = parse(name)
            if what.kind == "pre":
                env[name] = left.get(what.base, values.get(what.base, float("nan")))
            elif name == "time":
                env[name] = t
            else:
                env[name] = values.get(name, float("nan"))
        return env

    def prepared(self, system: CompiledSystem | None, t: float, x) -> dict:
        """The values :meth:`environment` adds outside event iteration (clocks false; with
        ``system``, the continuous values at ``(t, x)``, where ``pre(u)`` of a continuous
        ``u`` is ``u``, as during initialization)."""
        extra = {clock.name: False for clock in self.clocks} if self.hybrid else {}
        if system is not None and self.continuous_args:
            values = mode_values(system, t, x)
            extra.update(self.continuous_values(system, t, x, values))
        return extra

    def state_vector(self, system: CompiledSystem, values: Mapping, discrete: Mapping) -> list:
        """The state vector of ``system``: held values from ``discrete``, the rest from ``values``."""
        return [discrete[s] if s in self.kinds else values[s] for s in system.states]

    # -- one pass ----------------------------------------------------------------------

    def evaluate(self, discrete: Mapping, pre: Mapping, relations, initial: bool, extra: Mapping,
                 relation_free: bool = False) -> dict:
        """One pass over the discrete equations in dependency order.

        With ``relation_free`` only the equations that read no relation are
        evaluated; the others keep their values.
        """
        if not relation_free:
            found = self._evaluate_again(discrete, pre, relations, initial)
            if found is not None:
                return found
        current = dict(discrete)
        env = self.environment(relations, initial, pre, extra)
        env.update(current)
        start = dict(env) if not relation_free else None
        kinds = self.kinds
        for variable, args, fn, origin in (self.relation_free if relation_free else self.equations):
            value = cast(kinds[variable], fn(*[env[a] for a in args]))
            current[variable] = env[variable] = value
        if not relation_free:
            self._last_pass = (dict(pre), initial, tuple(relations), start, dict(current))
        return current

    def _evaluate_again(self, discrete: Mapping, pre: Mapping, relations, initial: bool) -> dict | None:
        """A pass computed from the last one, re-evaluating only the equations whose
        inputs changed (None: evaluate all).

        What an equation reads in a pass: relations, ``pre()`` values and
        initial(); the value a variable has in this pass when its own equation
        comes earlier; and the value the pass *starts* from when it comes later
        (or the variable has none: a discrete loop).  The equations for which
        one of these changed since the last pass are evaluated, in evaluation
        order, and then those reading a result that changed; every other
        equation reads what it read in the last pass, so it keeps its value.
        """
        last = self._last_pass
        if last is None or last[1] != initial or not self.incremental or self.hybrid:
            return None  # (continuous values and clocks are not tracked: evaluate all)
        last_pre, _, before, old_start, old_result = last
        if len(before) != len(relations) or len(old_result) != len(discrete):
            return None
        changed = {self.relation_names[k]: relations[k]
                   for k, (a, b) in enumerate(zip(relations, before)) if a != b}
        for name, value in pre.items():
            if last_pre.get(name, not value) != value:
                changed[self.pre_key(name)] = value
        for name, value in discrete.items():
            if old_start.get(name, not value) != value:
                changed[name] = value
        if len(changed) * 4 > len(self.equations) + len(relations):
            return None  # most of it changed: evaluate all
        start = dict(old_start)
        start.update(changed)
        readers, early, kinds = self.readers, self._early_readers, self.kinds
        todo = set()
        for name in changed:
            # a relation, pre() value or initial(): every reader; a variable: the
            # readers that see the value the pass starts from
            todo.update(early.get(name, ()) if name in kinds else readers.get(name, ()))
        current = dict(old_result)
        for name in changed:
            if name in kinds and name not in self.equation_of:
                current[name] = start[name]  # no equation: it keeps the value it starts with
        heap = sorted(todo)
        done: set[int] = set()
        sources = self._argument_sources
        while heap:
            i = heapq.heappop(heap)
            if i in done:
                continue
            done.add(i)
            variable, args, fn, origin = self.equations[i]
            value = cast(kinds[variable], fn(*[current[a] if late else start[a] for a, late in sources[i]]))
            if value != current[variable]:
                current[variable] = value
                for j in readers.get(variable, ()):
                    if j > i:  # an earlier reader sees the value the pass starts with
                        heapq.heappush(heap, j)
        self._last_pass = (dict(pre), initial, tuple(relations), start, dict(current))
        return current

    # -- assertions ----------------------------------------------------------------------

    def violated_asserts(self, t: float, system: CompiledSystem, x, discrete: Mapping, pre: Mapping,
                         relations, initial: bool, terminal: bool, extra: Mapping) -> list:
        """The assertions violated at ``(t, x)``: ``[(FlatAssert, message)]``, with the
        relation values ``relations`` (``terminal``: at the end of the run, where
        ``terminal()`` is true)."""
        if not self.asserts:
            return []
        env = self.environment(relations, initial, pre, extra)
        env[TERMINAL_NAME] = terminal
        env.update(discrete)
        if self._assert_continuous:
            values = mode_values(system, t, x)
            for name in self._assert_continuous:
                what = parse(name)
                env[name] = t if name == "time" else values.get(what.base if what.kind == "pre" else name,
                                                                float("nan"))
        out = []
        for item, args, fn in self.asserts:
            try:
                holds = fn(*[env[a] for a in args])
            except KeyError:
                continue
            if not holds:
                out.append((item, f"assertion {'failed' if item.level == 'error' else 'warning'} at "
                                  f"t = {t:.12g}: {item.message} ({item.origin})"))
        return out
