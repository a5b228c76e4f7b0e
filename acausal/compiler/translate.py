"""The translation driver: run the stages, once per visited discrete state.

:func:`translate` flattens and partitions a model once.  The continuous
system of a discrete state — its equations specialised to the values of the
discrete symbols, aliases removed, index reduced, sorted, torn and compiled
— is built by :meth:`Translation.system` the first time that state is
visited and cached afterwards.  Initialization systems are built the same
way.  Each stage's output stays on the :class:`ModeSystem` for inspection.
"""

from __future__ import annotations

import dataclasses
import time as _time
from collections import OrderedDict
from dataclasses import dataclass, field
from typing import Any, Iterable, Mapping

import numpy as np
import sympy as sp

from .algebraic import AlgebraicResult, solve_blocks
from .alias import AliasResult, eliminate_aliases
from .blt import BLTResult, sort_blt
from .codegen import GeneratedCode, generate, needed_steps, python_identifiers
from ..errors import (InitializationError, ModelDefinitionError, OverDeterminedError, StructuralError)
from .flatten import FlatEquation, FlatModel, Origin, flatten
from ..language import Component, real_symbol
from ..names import INITIAL_NAME, der_name, is_derivative, parse
from .partition import PartitionedModel, partition
from .structure import StructuralResult, analyse, check_balance, priority_matching

__all__ = ["ModeSystem", "InitialSystem", "Translation", "translate"]


def _value_of(value) -> Any:
    if isinstance(value, (bool, np.bool_)):
        return sp.true if value else sp.false
    return sp.Integer(int(value))


def describe_key(selectors, key, relation_texts=None) -> str:
    """Readable form of a discrete state: ``clutch.mode=0, clutch.locked=True``.

    Relations that select equations appear as ``(time < step.startTime)=False``.
    """
    parts = []
    relation_texts = relation_texts or {}
    for sym, value in zip(selectors, key):
        kind = parse(sym.name).kind
        if kind == "initial":
            parts.append(f"{INITIAL_NAME}={value}")
        elif kind == "relation":
            parts.append(f"({relation_texts.get(sym.name, sym.name)})={value}")
        else:
            parts.append(f"{sym.name}={value}")
    return ", ".join(parts) or "(continuous)"


@dataclass(frozen=True)
class ModeSystem:
    """The compiled continuous system of one discrete state.

    Attributes
    ----------
    key : tuple
        Values of :attr:`PartitionedModel.selectors`, in that order.
    equations : tuple of FlatEquation
        Specialised equations.
    aliases, structure, blt, algebraic, code
        The outputs of the stages, in pipeline order.
    timings : dict
        Seconds spent in each stage.
    """

    key: tuple
    description: str
    equations: tuple[FlatEquation, ...]
    aliases: AliasResult
    structure: StructuralResult
    blt: BLTResult
    algebraic: AlgebraicResult
    code: GeneratedCode
    timings: dict
    derivatives: Any = field(repr=False, compare=False)
    crossings: Any = field(repr=False, compare=False)
    outputs: Any = field(repr=False, compare=False)
    #: States integrated and unknowns computed: all of them, or with an output
    #: demand only those the demanded outputs, their states and the watched
    #: relations need.
    states: tuple[str, ...] = ()
    unknowns: tuple[str, ...] = ()
    #: The discrete state whose compiled system this one shares, when both
    #: specialise to the same equations (None: compiled for this state).
    shares: tuple | None = None

    def values(self, t: float, x) -> dict[str, float]:
        """Continuous variables and derivatives at ``(t, x)`` (aliases: see events.mode_values)."""
        out = dict(zip(self.states, map(float, x)))
        out.update(zip(self.unknowns, self.outputs(t, x)))
        return out


@dataclass(frozen=True)
class InitialSystem:
    """The compiled initialization problem of one discrete state."""

    key: tuple
    equations: tuple[FlatEquation, ...]
    unknowns: tuple[str, ...]
    relaxed: tuple[tuple[str, float], ...]  #: fixed start values dropped as redundant
    blt: BLTResult
    algebraic: AlgebraicResult
    code: GeneratedCode
    outputs: Any = field(repr=False, compare=False)
    #: Seconds spent building it (matching, BLT, solving, code), its mode's system excluded.
    seconds: float = 0.0


class Translation:
    """A translated model: flat and partitioned once, systems built lazily.

    Attributes
    ----------
    flat : FlatModel
    partitioned : PartitionedModel
    systems : dict
        ``key -> ModeSystem`` for every discrete state compiled so far.
    initial_systems : dict
    """

    def __init__(self, flat: FlatModel, partitioned: PartitionedModel, flatten_seconds: float,
                 demand: frozenset[str] | None = None) -> None:
        self.flat = flat
        self.demand = demand
        self.partitioned = partitioned
        self.parameter_names = tuple(p.name for p in flat.parameters)
        self.parameter_values = dict(flat.parameter_values)
        self.parameter_vector = tuple(self.parameter_values[n] for n in self.parameter_names)
        self._zero_parameters = {real_symbol(n): sp.Integer(0) for n, v in self.parameter_values.items()
                                 if v == 0}
        self.continuous = {n: v for n, v in flat.variable_map.items() if not v.is_discrete}
        self.systems: dict[tuple, ModeSystem] = {}
        self.initial_systems: dict[tuple, InitialSystem] = {}
        self.flatten_seconds = flatten_seconds
        # One Python name per model name, the same in every system's code.
        continuous = list(self.continuous)
        # (second derivatives too, which index reduction may add: named up front, the
        # names do not depend on the order in which discrete states are compiled)
        self._identifiers = python_identifiers(
            [*self.parameter_names, *continuous, *(der_name(n) for n in continuous),
             *(der_name(n, 2) for n in continuous)])
        # The discrete states of a model share most equations: what a stage
        # derived from one equation (its specialisation, derivative, solution,
        # code) is kept here for the next state.  Valid for this model's
        # parameter values only, like everything else in a Translation.
        self._memo: dict[str, dict] = {"specialise": {}, "alias": {}, "structure": {}, "algebraic": {},
                                       "codegen": {}}
        self._parameter_set = set(self.parameter_values)
        self._by_equations: dict[tuple, ModeSystem] = {}
        self._discrete_names = frozenset(partitioned.discrete_variables)

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

    def specialise(self, key: tuple, equations=None) -> tuple[FlatEquation, ...]:
        subs = {s: _value_of(v) for s, v in zip(self.selectors, key)}
        # Parameters that are zero are structural zeros: the matching ignores
        # the terms they multiply, so the generated code must not contain them.
        subs.update(self._zero_parameters)
        source = self.partitioned.equations if equations is None else equations
        memo = self._memo["specialise"]
        out = []
        for eq in source:
            # Only the discrete symbols an equation contains decide its form:
            # an equation is specialised once per combination of their values.
            used = memo.get(eq.residual)
            if used is None:
                used = memo[eq.residual] = tuple(s for s in eq.residual.free_symbols if s in subs)
            key = (eq.residual, tuple(subs[s] for s in used))
            residual = memo.get(key)
            if residual is None:
                residual = eq.residual.xreplace({s: subs[s] for s in used}) if used else eq.residual
                leftover = [s.name for s in residual.free_symbols
                            if parse(s.name).kind in ("relation", "initial") or s.name in self._discrete_names]
                if leftover:
                    raise StructuralError(f"{eq.origin}: discrete value {leftover[0]} left after "
                                          f"specialisation")
                memo[key] = residual
            out.append(eq if residual is eq.residual else FlatEquation(residual, eq.origin))
        return tuple(out)

    # -- building systems -----------------------------------------------------

    def system(self, key: tuple) -> ModeSystem:
        """The compiled system of discrete state ``key`` (built on first use)."""
        cached = self.systems.get(key)
        if cached is not None:
            return cached
        description = describe_key(self.selectors, key,
                                   {r.symbol.name: r.text for r in self.partitioned.relations})
        context = f"{self.flat.name} [{description}]" if self.partitioned.is_hybrid else self.flat.name
        timings = {}
        t0 = _time.perf_counter()
        equations = self.specialise(key)
        timings["specialise"] = _time.perf_counter() - t0
        # Discrete states that differ only in values the equations do not read
        # (pre(mode) of a sliding clutch, say) have the same equations: one
        # compiled system serves them all.
        signature = tuple(eq.residual for eq in equations)
        twin = self._by_equations.get(signature)
        if twin is not None:
            # the same compiled functions; the source's first line names this state
            _, rest = twin.code.source.split("\n", 1)
            code = dataclasses.replace(twin.code, source=f"# generated by acausal for {context} "
                                                         f"(shared with an equal state)\n{rest}")
            system = dataclasses.replace(twin, key=key, description=description, timings=timings,
                                         code=code, shares=twin.key)
            self.systems[key] = system
            return system
        t0 = _time.perf_counter()
        aliases = eliminate_aliases(equations, self.continuous, self._parameter_set,
                                    memo=self._memo["alias"])
        timings["alias"] = _time.perf_counter() - t0
        t0 = _time.perf_counter()
        try:
            try:
                structure = analyse(aliases.equations, aliases.variables, self.parameter_values, context,
                                    self._memo["structure"])
            except StructuralError:
                # Alias elimination may have absorbed the culprit (an extra `w = 0`):
                # check the equations as written, so the message names them all.
                from .structure import _incidence

                values = {real_symbol(n): sp.Float(v) for n, v in self.parameter_values.items()}
                check_balance(equations, [_incidence(e.residual, values) for e in equations],
                              list(self.continuous), context)
                raise
        except StructuralError as exc:
            if self.partitioned.is_hybrid and self.systems:
                # only this discrete state fails: the components concerned may know why
                own = self.flat.hints_for("mode", exc.components)
                hint = "; ".join(own) if own else (
                    "this discrete state only: its equations do not determine every unknown (or "
                    "determine some twice); check the discrete variables of the components named")
                raise exc.with_hint(f"this discrete state only: {hint}" if own else hint) from exc
            raise
        timings["structure"] = _time.perf_counter() - t0
        t0 = _time.perf_counter()
        blt = sort_blt(structure.incidence, structure.matching)
        timings["blt"] = _time.perf_counter() - t0
        t0 = _time.perf_counter()
        algebraic = solve_blocks(structure.equations, structure.unknowns, blt, self.parameter_values,
                                 self._memo["algebraic"])
        timings["algebraic"] = _time.perf_counter() - t0
        t0 = _time.perf_counter()
        crossings = self._crossing_expressions(aliases)
        steps, states, derivs, unknowns = self._demanded(algebraic.steps, structure, aliases, crossings)
        guesses = {n: v.start for n, v in aliases.variables.items()}
        code = generate(steps, states, derivs, unknowns, self.parameter_names, crossings,
                        name=context, guesses=guesses, identifiers=self._identifiers,
                        memo=self._memo["codegen"])
        derivatives, crossing_fn, outputs = code.make(self.parameter_vector)
        timings["codegen"] = _time.perf_counter() - t0
        system = ModeSystem(key, description, equations, aliases, structure, blt, algebraic, code,
                            timings, derivatives, crossing_fn, outputs, tuple(states), tuple(unknowns))
        self.systems[key] = system
        self._by_equations[signature] = system
        return system

    def _demanded(self, steps, structure: StructuralResult, aliases: AliasResult, crossings):
        """The steps, states and unknowns the output demand needs (all without one).

        Closure: the demanded names, then every state a needed step reads,
        then the steps that state's derivative needs, until nothing is added.
        Relations are always computable (events must still be found).
        """
        all_states = list(structure.states)
        if self.demand is None:
            return list(steps), all_states, list(structure.derivatives), list(structure.unknowns)
        targets = set()
        for name in self.demand:
            expr = aliases.aliases.get(name)
            targets |= {s.name for s in expr.free_symbols} if expr is not None else {name}
        for g in crossings:
            targets |= {s.name for s in g.free_symbols}
        derivative_of = dict(zip(structure.states, structure.derivatives))
        needed_states: set[str] = set()
        while True:
            wanted = targets | {derivative_of[s] for s in needed_states}
            chosen = needed_steps(steps, wanted)
            reads = set(wanted)
            for k in chosen:
                reads |= steps[k].reads()
            new_states = {s for s in all_states if s in reads} - needed_states
            if not new_states:
                break
            needed_states |= new_states
        kept_states = [s for s in all_states if s in needed_states]
        kept_steps = [steps[k] for k in chosen]
        defined = {n for step in kept_steps for n in step.defines}
        kept_unknowns = [u for u in structure.unknowns if u in defined]
        return kept_steps, kept_states, [derivative_of[s] for s in kept_states], kept_unknowns

    def _crossing_expressions(self, aliases: AliasResult) -> list[sp.Expr]:
        substitution = {real_symbol(n): e for n, e in aliases.aliases.items()}
        out = []
        for r in self.partitioned.relations:
            out += [sp.sympify(r.lhs).xreplace(substitution), sp.sympify(r.rhs).xreplace(substitution)]
        return out

    def initial_system(self, key: tuple) -> InitialSystem:
        """The initialization problem of discrete state ``key`` (with initial() true)."""
        cached = self.initial_systems.get(key)
        if cached is not None:
            return cached
        mode = self.system(key)
        t_start = _time.perf_counter()
        context = f"initialization of {self.flat.name}"
        if self.partitioned.is_hybrid:
            context += f" [{mode.description}]"
        substitution = {real_symbol(n): e for n, e in mode.aliases.aliases.items()}
        user = [FlatEquation(e.residual.xreplace(substitution), e.origin)
                for e in self.specialise(key, self.partitioned.initial_equations)]
        variables = mode.aliases.variables
        state_set = set(mode.structure.states)
        fixed_states, fixed_others = [], []
        for name, var in variables.items():
            if var.fixed:
                eq = FlatEquation(real_symbol(name) - var.start,
                                  Origin(var.component, "", "fixed start", 0, f"{name} = {var.start:g}"))
                (fixed_states if name in state_set else fixed_others).append((name, eq))
        self._check_fixed_constants(mode.aliases)
        dae = list(mode.structure.equations)
        equations = dae + user + [e for _, e in fixed_states] + [e for _, e in fixed_others]
        fixed_names = [n for n, _ in fixed_states] + [n for n, _ in fixed_others]
        unknowns = list(mode.structure.unknowns) + list(mode.structure.states)
        u_index = {n: k for k, n in enumerate(unknowns)}
        values = {real_symbol(n): sp.Float(v) for n, v in self.parameter_values.items()}
        incidence = []
        for eq in equations:
            names = {s.name for s in eq.residual.free_symbols if s not in values}
            extra = sorted(n for n in names if n not in u_index and n != "time")
            if extra:
                raise InitializationError(f"{context}: {eq.origin} uses {extra[0]}, which is "
                                          f"not an unknown of the initialization problem")
            incidence.append(tuple(sorted(u_index[n] for n in names if n in u_index)))
        assign = priority_matching(incidence, len(unknowns), range(len(equations)))
        matched = set(a for a in assign if a >= 0)
        n_fixed0 = len(dae) + len(user)
        unmatched = [i for i in range(len(equations)) if i not in matched]
        hard = [i for i in unmatched if i < n_fixed0]
        if hard:
            lines = "\n  ".join(str(equations[i].origin) for i in hard[:10])
            raise OverDeterminedError(f"{context} is over-determined:\n  {lines}",
                                      hint="an initial equation may repeat what the model already fixes")
        missing = [unknowns[j] for j, a in enumerate(assign) if a == -1]
        if missing:
            states = [m for m in missing if m in state_set]
            names = ", ".join(states or missing)
            raise InitializationError(
                f"{context}: missing initial values; nothing fixes {names}",
                hint="give start values with fixed=True, e.g. Component(x=dict(start=0, fixed=True)), "
                     "or add initial equations")
        relaxed = tuple((fixed_names[i - n_fixed0], variables[fixed_names[i - n_fixed0]].start)
                        for i in unmatched)
        kept = [i for i in range(len(equations)) if i in matched]
        renumber = {i: k for k, i in enumerate(kept)}
        kept_eqs = [equations[i] for i in kept]
        kept_inc = [incidence[i] for i in kept]
        matching = [0] * len(kept)
        for j, i in enumerate(assign):
            matching[renumber[i]] = j
        blt = sort_blt(kept_inc, matching)
        algebraic = solve_blocks(kept_eqs, unknowns, blt, self.parameter_values, self._memo["algebraic"])
        guesses = {n: v.start for n, v in variables.items()}
        code = generate(algebraic.steps, (), (), unknowns, self.parameter_names, (),
                        name=context, guesses=guesses, identifiers=self._identifiers,
                        memo=self._memo["codegen"])
        _, _, outputs = code.make(self.parameter_vector)
        system = InitialSystem(key, tuple(kept_eqs), tuple(unknowns), relaxed, blt, algebraic, code,
                               outputs, _time.perf_counter() - t_start)
        self.initial_systems[key] = system
        return system

    def _check_fixed_constants(self, aliases: AliasResult) -> None:
        values = {real_symbol(n): sp.Float(v) for n, v in self.parameter_values.items()}
        for name, expr, start in aliases.fixed_constants:
            value = float(sp.sympify(expr).xreplace(values))
            if abs(value - start) > 1e-10 * max(1.0, abs(value)):
                raise InitializationError(
                    f"conflicting initial values: {name} has fixed start {start}, but the model "
                    f"makes it the constant {expr} = {value}",
                    hint=f"remove fixed=True from {name} or change its start value")

    # -- summary --------------------------------------------------------------

    @property
    def compiled_systems(self) -> int:
        """How many systems were compiled (discrete states with equal equations share one)."""
        return sum(s.shares is None for s in self.systems.values())

    @property
    def translation_seconds(self) -> float:
        """Seconds spent translating so far: flattening, every system compiled, every initialization system."""
        return (self.flatten_seconds + sum(sum(s.timings.values()) for s in self.systems.values())
                + sum(s.seconds for s in self.initial_systems.values()))


#: Translations of recently seen models, by model signature (see model_signature).
_CACHE: "OrderedDict[tuple, Translation]" = OrderedDict()
CACHE_SIZE = 16


def model_signature(model: Component) -> tuple:
    """What makes two model instances translate identically.

    The class of every component, its place in the tree, its modifiers
    (parameter values included), its connections, and the experiment.  Two
    instances with the same signature get the same equations, so the
    compiled systems of one serve the other.
    """
    parts = []
    for component in model.walk():
        modifiers = tuple(sorted((k, _freeze(v)) for k, v in component._modifiers.items()))
        attributes = tuple(sorted((k, _freeze(v)) for k, v in component._attribute_modifiers.items()))
        connections = tuple((_end(a), _end(b)) for a, b in component._connections)
        klass = type(component)
        # the class object itself (not its id): the cache then keeps it alive, so a
        # class created later can never be mistaken for it
        parts.append((component.path, klass, modifiers, attributes, connections))
    return (tuple(parts), getattr(model, "experiment", None))


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


def _end(end):
    return getattr(end, "path", None) or getattr(end, "name", repr(end))


def translate(model: Component, outputs: Iterable[str] | None = None, cache: bool = True) -> Translation:
    """Flatten and partition ``model``; its systems are compiled on demand.

    Parameters
    ----------
    outputs : iterable of str, optional
        Compute only these variables (and what they and the events need):
        states and equations that cannot influence them are left out.
    cache : bool
        Reuse the translation (and every system compiled so far) of an
        identical model translated before in this process.
    """
    if cache:
        key = (model_signature(model), None if outputs is None else frozenset(outputs))
        found = _CACHE.get(key)
        if found is not None:
            _CACHE.move_to_end(key)
            return found
        translation = translate(model, outputs, cache=False)
        _CACHE[key] = translation
        while len(_CACHE) > CACHE_SIZE:
            _CACHE.popitem(last=False)
        return translation
    t0 = _time.perf_counter()
    flat = flatten(model)
    partitioned = partition(flat)
    demand = None
    if outputs is not None:
        known = {v.name for v in flat.variables} | {p.name for p in flat.parameters}
        demand = frozenset(outputs)
        unknown = sorted(n for n in demand if n not in known and not is_derivative(n))
        if unknown:
            import difflib

            close = difflib.get_close_matches(unknown[0], sorted(known), n=3)
            raise ModelDefinitionError(f"{flat.name} has no variable {unknown[0]!r}",
                                       hint=f"did you mean {', '.join(close)}?" if close else
                                       "outputs are dotted variable names, e.g. component.variable")
        demand = frozenset(n for n in demand if n in known and n not in flat.parameter_values
                           or is_derivative(n))
    return Translation(flat, partitioned, _time.perf_counter() - t0, demand)

