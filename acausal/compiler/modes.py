"""The mode compiler: stages 3-8 for one discrete state (its continuous system).

A discrete state fixes the value of every discrete symbol (Boolean and
Integer variables, their ``pre()`` values, relation indicators,
``initial()``).  :func:`compile_mode` specialises the model's equations to
those values and runs the continuous pipeline on them:

``alias`` → ``structure`` → ``blt`` → ``algebraic`` → ``codegen``

Each stage's output stays on the returned :class:`ModeSystem`, and so does
the *pass log*: ``(pass name, seconds)`` for every pass run, in order, as
OpenModelica's backend keeps its module list.  ``acausal explain`` and the
benchmarks read the log instead of timing the stages again.
"""

from __future__ import annotations

import dataclasses
import time as _time
from contextlib import contextmanager
from dataclasses import dataclass, field
from typing import Any, Iterator, Mapping, Sequence

import sympy as sp

from ..errors import StructuralError
from ..language import real_symbol
from ..names import INITIAL_NAME, parse
from .algebraic import AlgebraicResult, solve_blocks
from .alias import AliasResult, eliminate_aliases
from .blt import BLTResult, sort_blt
from .cache import ModelCache
from .codegen import GeneratedCode, generate, needed_steps
from .generated import CompiledFunctions
from .flatten import FlatEquation, FlatVariable
from .partition import PartitionedModel
from .structure import StructuralResult, _incidence, analyse, check_balance

__all__ = ["ModeSystem", "PassLog", "RelaxedConstraints", "compile_mode", "describe_key", "shared_system"]


def describe_key(selectors, key, relation_texts=None) -> str:
    """Readable form of a discrete state: ``c.mode=0, c.locked=True``.

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


#: How long a discrete state's description may be where it names generated code and
#: messages (:func:`brief_description`).
BRIEF_DESCRIPTION = 300


def brief_description(description: str, limit: int = BRIEF_DESCRIPTION) -> str:
    """``description`` (of :func:`describe_key`) as it names a system's generated code and
    messages: whole when short, else its first values and how many more there are.

    A drive train of 1000 bearings has a discrete state of 4000 values: written out, it
    would be the first line of the generated source, the file name of its code objects
    and part of every message and traceback.  The system keeps the whole description.
    """
    if len(description) <= limit:
        return description
    items = description.split(", ")
    kept, length = [], 0
    for item in items:
        if length + len(item) + 2 > limit and kept:
            break
        kept.append(item)
        length += len(item) + 2
    return f"{', '.join(kept)}, ... ({len(items) - len(kept)} more)"


class PassLog:
    """``(pass name, seconds)`` of every pass run, in order."""

    def __init__(self) -> None:
        self.entries: list[tuple[str, float]] = []

    @contextmanager
    def run(self, name: str) -> Iterator[None]:
        """Time the pass ``name`` (a pass that raises is not logged)."""
        t0 = _time.perf_counter()
        yield
        self.entries.append((name, _time.perf_counter() - t0))


@dataclass(frozen=True)
class RelaxedConstraints:
    """What was left out of a discrete state that constrains one motion twice.

    Kept on its :class:`ModeSystem` (and in the persistent cache with it), so
    that every run that integrates in that state says so, whether the system
    was compiled in this process or loaded (see :meth:`message`).

    Attributes
    ----------
    components : tuple of str
        The components concerned: those whose equation was left out or
        whose share was set to zero.
    left_out : tuple of str
        The equations left out, each as ``component (declaring class eq. k)``.
    zeroed : tuple of str
        The flow variables set to zero in their place.
    """

    components: tuple[str, ...]
    left_out: tuple[str, ...]
    zeroed: tuple[str, ...]

    def message(self, model: str, state: str) -> str:
        """The warning and note: components first, one fact per line."""
        return "\n".join((
            f"{', '.join(self.components)}: two equations constrain the same unknowns in a discrete "
            f"state of {model}",
            f"  left out: {'; '.join(self.left_out)}",
            f"  set to 0: {', '.join(self.zeroed)} (the share the equations leave undetermined)",
            f"  discrete state: {state}",
            "  hint: translate(..., redundant_constraints='error') refuses such a state instead"))

    def payload(self) -> list:
        """As plain data, for the persistent cache."""
        return [list(self.components), list(self.left_out), list(self.zeroed)]

    @classmethod
    def from_payload(cls, payload) -> "RelaxedConstraints | None":
        return None if payload is None else cls(*(tuple(map(str, part)) for part in payload))


#: ``(name, coefficient, source)``: ``name = coefficient * source``, or
#: ``name = coefficient`` when source is None.
AliasPlan = tuple[tuple[str, float, "str | None"], ...]


@dataclass(frozen=True)
class ModeSystem(CompiledFunctions):
    """The compiled continuous system of one discrete state.

    Attributes
    ----------
    key : tuple
        Values of :attr:`PartitionedModel.selectors`, in that order.
    description : str
        The key in words.
    equations : tuple of FlatEquation
        The equations specialised to the key.
    aliases, structure, blt, algebraic, code
        The outputs of the stages, in pipeline order.
    passes : tuple of (str, float)
        The pass log: every pass run for this system and its seconds.
    derivatives, crossings, outputs : callable
        The compiled functions (see :class:`~acausal.compiler.codegen.GeneratedCode`).
    states, unknowns : tuple of str
        States integrated and unknowns computed: all of them, or with an
        output demand only those the demanded outputs, their states and the
        watched relations need.
    alias_plan : tuple
        How each alias follows from the computed values:
        ``(name, coefficient, source)`` with ``name = coefficient * source``,
        or ``name = coefficient`` when source is None.
    shares : tuple or None
        The discrete state whose compiled system this one shares, when both
        specialise to the same equations (None: compiled for this state).
    loaded_derivatives : tuple of str or None
        For a system loaded from the persistent cache
        (:mod:`~acausal.compiler.diskcache`): the derivatives of its states.
        Such a system has its code and functions only: ``equations`` is
        empty and the stages' outputs (``aliases`` ... ``algebraic``) are
        None; what needs them compiles the state anew.
    relaxed : RelaxedConstraints or None
        For a state that constrains one motion twice: what was left out to
        make it solvable (None: nothing).
    shape_of : tuple or None
        For a part of a model renamed from an earlier part of the same shape
        (:mod:`~acausal.compiler.part_shapes`): that part's cluster and
        discrete state.  Such a system has the loaded form (code and
        functions, no stage outputs).
    """

    key: tuple
    description: str
    equations: tuple[FlatEquation, ...]
    aliases: AliasResult | None
    structure: StructuralResult | None
    blt: BLTResult | None
    algebraic: AlgebraicResult | None
    code: GeneratedCode
    passes: tuple[tuple[str, float], ...]
    derivatives: Any = field(repr=False, compare=False)
    crossings: Any = field(repr=False, compare=False)
    outputs: Any = field(repr=False, compare=False)
    states: tuple[str, ...] = ()
    unknowns: tuple[str, ...] = ()
    alias_plan: AliasPlan = field(default=(), repr=False)
    shares: tuple | None = None
    loaded_derivatives: tuple[str, ...] | None = None
    relaxed: RelaxedConstraints | None = None
    shape_of: tuple | None = None

    @property
    def timings(self) -> dict[str, float]:
        """Seconds per pass (the pass log as a dict)."""
        return dict(self.passes)

    @property
    def seconds(self) -> float:
        """Seconds spent building this system (for a state that shares another's
        system: only its specialisation)."""
        return sum(s for _, s in self.passes)

    @property
    def sources(self) -> tuple[str, ...]:
        """The generated source (one; a composed system has one per cluster)."""
        return (self.code.source,)

    @property
    def derivative_names(self) -> tuple[str, ...]:
        """The derivatives of the states the structure chose."""
        if self.structure is None:
            return tuple(self.loaded_derivatives or ())
        return tuple(self.structure.derivatives)



def compile_mode(key: tuple, description: str, context: str, equations: tuple[FlatEquation, ...],
                 passes: PassLog, partitioned: PartitionedModel,
                 continuous: Mapping[str, FlatVariable], cache: ModelCache,
                 demand: frozenset[str] | None = None,
                 relations: Sequence[int] | None = None) -> ModeSystem:
    """Run the continuous pipeline on the specialised ``equations`` of state ``key``.

    Parameters
    ----------
    key, description : the discrete state and its description
    context : str
        How messages name the system (model and state).
    equations : tuple of FlatEquation
        The model's equations specialised to ``key``.
    passes : PassLog
        The log so far (specialisation); the passes run here are added.
    partitioned : PartitionedModel
        For the relations, whose crossing functions every system computes.
    continuous : mapping
        The continuous variables of the flat model.
    cache : ModelCache
        The work shared with the model's other systems.
    demand : frozenset of str, optional
        Compute only what these outputs (and the events) need.
    relations : sequence of int, optional
        The relations whose crossing functions this system computes (default:
        all; a cluster's system computes its own, see
        :mod:`~acausal.compiler.clusters`).

    Raises
    ------
    StructuralError
        If the equations cannot be solved as posed.
    """
    parameters = cache.parameters
    with passes.run("alias"):
        aliases = eliminate_aliases(equations, continuous, set(parameters.values), memo=cache.alias)
    with passes.run("structure"):
        try:
            structure = analyse(aliases.equations, aliases.variables, parameters.values, context,
                                cache.structure)
        except StructuralError:
            # Alias elimination may have absorbed the culprit (an extra `w = 0`):
            # check the equations as written, so the message names them all.
            check_balance(equations, [_incidence(e.residual, parameters.symbols) for e in equations],
                          list(continuous), context)
            raise
    with passes.run("blt"):
        blt = sort_blt(structure.incidence, structure.matching)
    with passes.run("algebraic"):
        algebraic = solve_blocks(structure.equations, structure.unknowns, blt, parameters.values,
                                 cache.algebraic)
    with passes.run("codegen"):
        crossings = crossing_expressions(partitioned, aliases, relations)
        steps, states, derivs, unknowns = demanded(algebraic.steps, structure, aliases, crossings, demand)
        guesses = {n: v.start for n, v in aliases.variables.items()}
        code = generate(steps, states, derivs, unknowns, parameters.names, crossings,
                        name=context, guesses=guesses, identifiers=cache.identifiers,
                        memo=cache.codegen)
        derivatives, crossing_fn, outputs = code.make(parameters.vector)
        plan = alias_plan(aliases, parameters.symbols)
    return ModeSystem(key, description, equations, aliases, structure, blt, algebraic, code,
                      tuple(passes.entries), derivatives, crossing_fn, outputs, tuple(states),
                      tuple(unknowns), plan)


def alias_plan(aliases: AliasResult, parameter_symbols: Mapping[sp.Symbol, sp.Float]) -> AliasPlan:
    """How each alias follows from the system's values (see :attr:`ModeSystem.alias_plan`)."""
    plan = []
    for name, expr in aliases.aliases.items():
        expr = sp.sympify(expr).xreplace(parameter_symbols)
        symbols = list(expr.free_symbols)
        if not symbols:
            plan.append((name, float(expr), None))
        else:
            (symbol,) = symbols
            plan.append((name, float(expr.coeff(symbol)), symbol.name))
    return tuple(plan)


def crossing_expressions(partitioned: PartitionedModel, aliases: AliasResult,
                         relations: Sequence[int] | None = None) -> list[sp.Expr]:
    """Both sides of every relation (or of ``relations``), aliases replaced: the
    crossing functions' values."""
    substitution = {real_symbol(n): e for n, e in aliases.aliases.items()}
    out = []
    chosen = partitioned.relations if relations is None else [partitioned.relations[k] for k in relations]
    for r in chosen:
        out += [sp.sympify(r.lhs).xreplace(substitution), sp.sympify(r.rhs).xreplace(substitution)]
    return out


def demanded(steps: Sequence, structure: StructuralResult, aliases: AliasResult,
             crossings: Sequence[sp.Expr], demand: frozenset[str] | None):
    """The steps, states and unknowns the output demand needs (all without one).

    Closure: the demanded names, then every state a needed step reads, then
    the steps that state's derivative needs, until nothing is added.
    Relations are always computable (events must still be found).
    """
    all_states = list(structure.states)
    if demand is None:
        return list(steps), all_states, list(structure.derivatives), list(structure.unknowns)
    targets = set()
    for name in demand:
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


def shared_system(twin: ModeSystem, key: tuple, description: str, context: str, passes: PassLog) -> ModeSystem:
    """State ``key``'s system: ``twin``'s compiled functions (both specialise to the same
    equations); the source's first line names this state."""
    _, rest = twin.code.source.split("\n", 1)
    code = dataclasses.replace(twin.code, source=f"# generated by acausal for {context} "
                                                 f"(shared with an equal state)\n{rest}")
    return dataclasses.replace(twin, key=key, description=description, passes=tuple(passes.entries),
                               code=code, shares=twin.key)
