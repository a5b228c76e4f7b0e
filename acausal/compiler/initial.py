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

The problem is sorted (BLT), solved block by block and compiled as a mode
system is, with its own pass log.
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
from .structure import priority_matching

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
        If an unknown is left undetermined, or an equation reads something
        that is not an unknown of the problem.
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
        missing = [unknowns[j] for j, a in enumerate(assign) if a == -1]
        if missing:
            states = [m for m in missing if m in state_set]
            names = ", ".join(states or missing)
            raise InitializationError(
                f"{context}: missing initial values; nothing fixes {names}",
                hint="give start values with fixed=True, e.g. Component(x=dict(start=0, fixed=True)), "
                     "or add initial equations",
                components=tuple(dict.fromkeys(m.rpartition(".")[0] for m in (states or missing))))
        relaxed = tuple((fixed_names[i - n_fixed0], variables[fixed_names[i - n_fixed0]].start)
                        for i in unmatched)
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
                         tuple(passes.entries), outputs)


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
