"""Stage 9: the initialization problem of one discrete state, compiled.

The initialization problem is the system's equations (those index reduction
differentiated included) plus the initial equations plus one equation
``v = start`` for every variable with ``fixed=True``, solved for every
unknown and state with ``initial()`` true.  Its unknowns are matched with
priority to the model's and the user's equations; a fixed start value left
unmatched is *relaxed*: the others already determine it (an element whose
speed follows from a constraint and another element's speed).  The runtime
then checks it (:mod:`acausal.runtime.initialization`): equal, it is noted;
different, it is a conflict.

An *under-determined* problem is completed as Modelica tools complete it:
states without ``fixed=True`` take their start values (0 when none is
given).  The Modelica specification leaves the choice of those states to
the tool [1]_; acausal's choice is structural and deterministic.  After the
model's equations, the initial equations and the fixed start values are
matched (in that priority), one candidate equation ``x = x.start`` per state
``x`` without ``fixed=True`` is matched last: first those of the states left
unmatched (each is free, so exactly these states take their start values),
then, in the order of the states, those that complete the matching through
an augmenting path (an unknown left unmatched that is not itself a state,
e.g. a derivative whose equation index reduction consumed).  Candidates
left unmatched are dropped: the rest of the problem determines those
states.  The states chosen are recorded in :attr:`InitialSystem.from_start`
and the runtime warns with :class:`~acausal.errors.StartValueWarning`.
Unknowns that even the start values leave undetermined remain an
:class:`~acausal.errors.InitializationError`.

The problem is sorted (BLT), solved block by block and compiled as a mode
system is, with its own pass log.

References
----------
.. [1] Modelica Association, "Modelica Language Specification, Version 3.6",
   2023, section 8.6 "Initialization, initial equation, and initial
   algorithm": start values of states without ``fixed = true`` may be used
   by the tool to complete an under-determined initialization problem.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Sequence

import sympy as sp

from ..errors import InitializationError, OverDeterminedError
from ..language import real_symbol
from .algebraic import AlgebraicResult, solve_blocks
from .alias import AliasResult, derivative_substitution
from .blt import BLTResult, sort_blt
from .cache import ModelCache
from .codegen import GeneratedCode, generate
from .flatten import FlatEquation, Origin
from .modes import ModeSystem, PassLog
from .structure import augmenting_path, priority_matching

__all__ = ["InitialSystem", "compile_initial_system", "check_fixed_constants"]


@dataclass(frozen=True)
class InitialSystem:
    """The compiled initialization problem of one discrete state.

    Attributes
    ----------
    key : tuple
        The discrete state.
    equations : tuple of FlatEquation
        The equations solved (relaxed fixed starts left out).
    unknowns : tuple of str
        The mode's unknowns, then its states: what ``outputs`` returns.
    relaxed : tuple of (str, float)
        Fixed start values dropped as implied by the others.
    blt, algebraic, code
        The stages' outputs.
    passes : tuple of (str, float)
        The pass log (its mode system's passes not included).
    from_start : tuple of (str, float)
        States without ``fixed=True`` that the problem took from their start
        values (name, value) because nothing else determines them, in the
        order of the states; empty when the problem is fully determined.
    """

    key: tuple
    equations: tuple[FlatEquation, ...]
    unknowns: tuple[str, ...]
    relaxed: tuple[tuple[str, float], ...]
    blt: BLTResult
    algebraic: AlgebraicResult
    code: GeneratedCode
    passes: tuple[tuple[str, float], ...] = ()
    outputs: Any = field(default=None, repr=False, compare=False)
    # last, with a default: positional construction (the persistent cache's loader) stays valid
    from_start: tuple[tuple[str, float], ...] = ()

    @property
    def seconds(self) -> float:
        """Seconds spent building it, its mode's system excluded."""
        return sum(s for _, s in self.passes)

    @property
    def sources(self) -> tuple[str, ...]:
        """The generated source (one; a composed problem has one per cluster)."""
        return (self.code.source,)


def compile_initial_system(mode: ModeSystem, initial_equations: Sequence[FlatEquation], context: str,
                           cache: ModelCache) -> InitialSystem:
    """The initialization problem of ``mode``'s discrete state.

    Parameters
    ----------
    mode : ModeSystem
        The system of the state (with ``initial()`` true).
    initial_equations : sequence of FlatEquation
        The model's initial equations, specialised to the state.
    context : str
        How messages name the problem.
    cache : ModelCache
        The work shared with the model's other systems.

    Raises
    ------
    OverDeterminedError
        If the model's or the user's equations are more than the unknowns need.
    InitializationError
        If an unknown is left undetermined even with the start values of the
        states without ``fixed=True``, or an equation reads something that is
        not an unknown of the problem.

    Notes
    -----
    An under-determined problem takes the start values of states without
    ``fixed=True`` (see the module docstring); they are listed in the
    result's ``from_start``.
    """
    passes = PassLog()
    parameters = cache.parameters
    with passes.run("initial equations"):
        substitution = {real_symbol(n): e for n, e in mode.aliases.aliases.items()}
        # der() of an alias in an initial equation is der() of its representative
        for e in initial_equations:
            substitution.update(derivative_substitution(e.residual.free_symbols, mode.aliases.aliases,
                                                        mode.aliases.variables, substitution))
        user = [FlatEquation(e.residual.xreplace(substitution), e.origin) for e in initial_equations]
        variables = mode.aliases.variables
        state_set = set(mode.structure.states)
        fixed_states, fixed_others = [], []
        for name, var in variables.items():
            if var.fixed:
                eq = FlatEquation(real_symbol(name) - var.start,
                                  Origin(var.component, "", "fixed start", 0, f"{name} = {var.start:g}"))
                (fixed_states if name in state_set else fixed_others).append((name, eq))
        check_fixed_constants(mode.aliases, parameters.symbols)
        dae = list(mode.structure.equations)
        equations = dae + user + [e for _, e in fixed_states] + [e for _, e in fixed_others]
        fixed_names = [n for n, _ in fixed_states] + [n for n, _ in fixed_others]
        unknowns = list(mode.structure.unknowns) + list(mode.structure.states)
        # a state may be a name the flat model does not declare (der(x) of a second
        # order state): no fixed start, start 0
        unfixed_states = [n for n in mode.structure.states
                          if n not in variables or not variables[n].fixed]
    with passes.run("matching"):
        u_index = {n: k for k, n in enumerate(unknowns)}
        incidence = []
        for eq in equations:
            names = {s.name for s in eq.residual.free_symbols if s not in parameters.symbols}
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
                                      hint="an initial equation may repeat what the model already fixes",
                                      components=tuple(dict.fromkeys(equations[i].origin.component
                                                                     for i in hard)))
        relaxed = tuple((fixed_names[i - n_fixed0], variables[fixed_names[i - n_fixed0]].start)
                        for i in unmatched)
        from_start: tuple[tuple[str, float], ...] = ()
        if -1 in assign:
            from_start = _complete_with_start_values(equations, incidence, assign, unknowns, u_index,
                                                     unfixed_states, variables)
        missing = [unknowns[j] for j, a in enumerate(assign) if a == -1]
        if missing:
            names = ", ".join(missing)
            raise InitializationError(
                f"{context}: missing initial values; nothing fixes {names}, not even the start "
                f"values of the states",
                hint="add initial equations that determine them, or fixed=True on their start values",
                components=tuple(dict.fromkeys(m.rpartition(".")[0] for m in missing)))
        # the start-value equations appended are all matched (the others were not kept)
        matched = set(a for a in assign if a >= 0)
        kept = [i for i in range(len(equations)) if i in matched]
        renumber = {i: k for k, i in enumerate(kept)}
        kept_eqs = [equations[i] for i in kept]
        kept_inc = [incidence[i] for i in kept]
        matching = [0] * len(kept)
        for j, i in enumerate(assign):
            matching[renumber[i]] = j
    with passes.run("blt"):
        blt = sort_blt(kept_inc, matching)
    with passes.run("algebraic"):
        algebraic = solve_blocks(kept_eqs, unknowns, blt, parameters.values, cache.algebraic)
    with passes.run("codegen"):
        guesses = {n: v.start for n, v in variables.items()}
        code = generate(algebraic.steps, (), (), unknowns, parameters.names, (),
                        name=context, guesses=guesses, identifiers=cache.identifiers,
                        memo=cache.codegen)
        _, _, outputs = code.make(parameters.vector)
    return InitialSystem(mode.key, tuple(kept_eqs), tuple(unknowns), relaxed, blt, algebraic, code,
                         tuple(passes.entries), outputs, from_start)


def _complete_with_start_values(equations: list[FlatEquation], incidence: list[tuple[int, ...]],
                                assign: list[int], unknowns: Sequence[str], u_index: dict[str, int],
                                unfixed_states: Sequence[str], variables) -> tuple[tuple[str, float], ...]:
    """Complete an under-determined initialization matching with ``x = x.start`` equations.

    ``assign`` (unknown -> equation or -1) is a maximum matching of the
    model's equations, the initial equations and the fixed start values; it
    is extended in place, and the equations chosen are appended to
    ``equations`` and ``incidence``.  The candidates are the states without
    ``fixed=True`` (``unfixed_states``): first those left unmatched, then
    the others in order (their equation can still complete the matching by
    an augmenting path).  Candidates are appended one at a time and dropped
    again when they cannot be matched, so the matching already found (and
    with it which fixed starts were relaxed) is never changed in which
    equations it covers.

    Returns
    -------
    tuple of (str, float)
        The states taken from their start values, in the order of the states.
    """
    free = {unknowns[j] for j, a in enumerate(assign) if a == -1}
    ordered = ([n for n in unfixed_states if n in free]
               + [n for n in unfixed_states if n not in free])
    chosen: set[str] = set()
    open_unknowns = len(free)
    for name in ordered:
        if not open_unknowns:
            break
        variable = variables.get(name)
        start = _start_of(name, variables)
        i = len(equations)
        equations.append(FlatEquation(real_symbol(name) - start,
                                      Origin(variable.component if variable is not None else "",
                                             "", "start value", 0, f"{name} = {start:g}")))
        incidence.append((u_index[name],))
        if augmenting_path(i, incidence, assign, lambda j: True, set(), set()):
            chosen.add(name)
            open_unknowns -= 1
        else:
            equations.pop()
            incidence.pop()
    return tuple((n, _start_of(n, variables)) for n in unfixed_states if n in chosen)


def _start_of(name: str, variables) -> float:
    """The start value of ``name`` (0 for a state the flat model does not declare)."""
    variable = variables.get(name)
    return float(variable.start) if variable is not None else 0.0


def check_fixed_constants(aliases: AliasResult, parameter_symbols) -> None:
    """A fixed start value of a variable the model makes a constant must equal it."""
    for name, expr, start in aliases.fixed_constants:
        value = float(sp.sympify(expr).xreplace(parameter_symbols))
        if abs(value - start) > 1e-10 * max(1.0, abs(value)):
            raise InitializationError(
                f"conflicting initial values: {name} has fixed start {start}, but the model "
                f"makes it the constant {expr} = {value}",
                hint=f"remove fixed=True from {name} or change its start value",
                components=(name.rpartition(".")[0],))
