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

Start values are inputs of the generated code.  Each tunable start value
(:attr:`~acausal.compiler.flatten.FlatModel.tunable_starts`: of the state
candidates and the fixed variables) is the parameter ``<variable>.start`` of
the parameter vector, so that the compiled problem serves other start values
without a new translation, as it serves other parameter values.  A
representative of an alias set takes its start as alias elimination merges
it (the first fixed member's, else the first non-zero one, representative
first): an expression of those parameters, a conditional one where which
member's start is taken depends on which are zero.  What the code cannot
take from the vector is recorded in :attr:`InitialSystem.starts`
(:class:`StartDependence`) and checked when the problem is bound to other
values (:func:`bind_start_values`): the first guesses of Newton iterations
are printed as numbers, and fixed start values of aliases must agree.

References
----------
.. [1] Modelica Association, "Modelica Language Specification, Version 3.6",
   2023, section 8.6 "Initialization, initial equation, and initial
   algorithm": start values of states without ``fixed = true`` may be used
   by the tool to complete an under-determined initialization problem.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from typing import Any, Callable, Mapping, Sequence

import sympy as sp

from ..errors import InitializationError, OverDeterminedError
from ..language import real_symbol, time
from ..names import is_derivative
from .algebraic import AlgebraicResult, NewtonSolve, solve_blocks
from .alias import AliasResult, derivative_substitution
from .delays import at_start
from .blt import BLTResult, sort_blt
from .cache import ModelCache
from .codegen import GeneratedCode, generate
from .generated import reset_warm_starts
from .flatten import FlatEquation, FlatVariable, Origin, start_parameter
from .modes import ModeSystem, PassLog
from .structure import augmenting_path, priority_matching

__all__ = ["InitialSystem", "StartDependence", "StartValues", "compile_initial_system", "check_fixed_constants",
           "start_value_relations",
           "bind_start_values", "newton_guesses"]


@dataclass(frozen=True)
class StartDependence:
    """What a compiled system assumes of the tunable start values, beyond the parameter vector.

    Expressions are of the start parameters (``J1.w.start``) and numbers;
    only entries that involve a start parameter are kept.

    Attributes
    ----------
    values : tuple of (str, sympy.Expr)
        The start value of each variable in ``relaxed`` and ``from_start``,
        which the runtime compares with and reports: evaluated anew for
        other values.
    guesses : tuple of (str, sympy.Expr, float)
        Tearing variables of Newton iterations whose first guess is a start
        value: the code holds it as the number printed, so other values
        need the system compiled anew.
    agreeing : tuple of (str, int, sympy.Expr, str, int, sympy.Expr)
        Fixed start values alias elimination merged, ``(a, fa, start_a, b,
        fb, start_b)`` with ``fa*a == fb*b``: the problem imposes ``a``'s,
        and ``b``'s must agree with it.
    """

    values: tuple = ()
    guesses: tuple = ()
    agreeing: tuple = ()

    def __bool__(self) -> bool:
        return bool(self.values or self.guesses or self.agreeing)

    def payload(self) -> dict:
        """As plain data (expressions by ``sympy.srepr``), for the persistent cache and bundles."""
        return {"values": [[n, sp.srepr(e)] for n, e in self.values],
                "guesses": [[n, sp.srepr(e), v] for n, e, v in self.guesses],
                "agreeing": [[a, fa, sp.srepr(sa), b, fb, sp.srepr(sb)] for a, fa, sa, b, fb, sb in self.agreeing]}

    @classmethod
    def from_payload(cls, data: Mapping | None, expression: Callable[[str], sp.Expr]) -> "StartDependence":
        """The inverse of :meth:`payload`; ``expression`` reads a printed expression."""
        if not data:
            return cls()
        return cls(tuple((n, expression(e)) for n, e in data["values"]),
                   tuple((n, expression(e), float(v)) for n, e, v in data["guesses"]),
                   tuple((a, int(fa), expression(sa), b, int(fb), expression(sb))
                         for a, fa, sa, b, fb, sb in data["agreeing"]))

    def guesses_hold(self, symbols: Mapping) -> bool:
        """Whether the first guesses printed into the code are those of these values (``symbols``:
        parameter symbol -> value)."""
        return all(_evaluated(e, symbols) == printed for _, e, printed in self.guesses)

    def check_agreeing(self, symbols: Mapping) -> None:
        """InitializationError for fixed start values of aliases that differ for these values."""
        for a, fa, start_a, b, fb, start_b in self.agreeing:
            value_a, value_b = _evaluated(start_a, symbols), _evaluated(start_b, symbols)
            if abs(fb * value_b - fa * value_a) > 1e-10 * max(1.0, abs(fa * value_a)):
                raise InitializationError(
                    f"conflicting initial values: {a} has fixed start {value_a:g} and {b} has fixed start "
                    f"{value_b:g}, but they are connected so that {b} = {'-' if fa * fb < 0 else ''}{a}",
                    hint="remove fixed=True from one of them, or give them equal start values",
                    components=tuple(dict.fromkeys(n.rpartition(".")[0] for n in (a, b))))


def _evaluated(expression: sp.Expr, symbols: Mapping) -> float:
    return float(expression.xreplace(symbols))


class StartValues:
    """The start value of each variable of a system, as alias elimination merges it, in terms
    of the tunable start values (the parameters ``<variable>.start``).

    Alias elimination (:func:`~acausal.compiler.alias.eliminate_aliases`) gives a
    representative the start of the first fixed member of its set (in name order,
    times the member's sign), else the first non-zero start (representative first),
    else the representative's own.  Here each member's start is its start
    parameter where it has one (else its number), so that the expression holds
    for every value; which member is the first non-zero one becomes a condition.

    Parameters
    ----------
    aliases : mapping
        ``eliminated name -> expression`` (:attr:`AliasResult.aliases`).
    merged : mapping of str to FlatVariable
        The representatives (:attr:`AliasResult.variables`).
    declared : mapping of str to FlatVariable, optional
        The model's variables with the start values of this translation; None:
        each representative alone, with its merged start.
    parameters : mapping
        Parameter symbol -> value (:attr:`ParameterTable.symbols`), start
        parameters included.
    """

    def __init__(self, aliases: Mapping[str, Any], merged: Mapping[str, FlatVariable],
                 declared: Mapping[str, FlatVariable] | None, parameters: Mapping) -> None:
        self.merged = merged
        self.declared = declared if declared is not None else merged
        self.parameters = parameters
        #: representative -> [(member, sign)] of the members alias elimination removed
        self.members: dict[str, list[tuple[str, int]]] = {}
        if declared is not None:
            for name, expression in aliases.items():
                sign, rest = sp.sympify(expression).as_coeff_Mul()
                if isinstance(rest, sp.Symbol) and rest.name in merged and sign in (1, -1):
                    self.members.setdefault(rest.name, []).append((name, int(sign)))
        self._expressions: dict[str, sp.Expr] = {}

    def own(self, name: str) -> sp.Expr:
        """``name``'s own start: its start parameter if it has one, else its number (0 if undeclared)."""
        symbol = real_symbol(start_parameter(name))
        if symbol in self.parameters:
            return symbol
        variable = self.declared.get(name)
        return sp.Float(variable.start) if variable is not None else sp.Integer(0)

    def group(self, name: str) -> tuple[list[str], dict[str, int]]:
        """The alias set of representative ``name`` in name order, and each member's sign."""
        sign = {name: 1, **dict(self.members.get(name, ()))}
        return sorted(sign), sign

    def fixed_members(self, name: str) -> list[str]:
        """The members of ``name``'s alias set with ``fixed=True``, in name order."""
        members, _ = self.group(name)
        return [m for m in members if (v := self.declared.get(m)) is not None and v.fixed]

    def expression(self, name: str) -> sp.Expr:
        """The start value of representative ``name``."""
        found = self._expressions.get(name)
        if found is None:
            found = self._expressions[name] = self._merged(name)
        return found

    def value(self, name: str) -> float:
        """The start value of representative ``name`` for this translation's values."""
        expression = self.expression(name)
        if expression in self.parameters:  # the common case, without substitution
            return float(self.parameters[expression])
        return _evaluated(expression, self.parameters)

    def _merged(self, name: str) -> sp.Expr:
        """The rule of alias elimination's merge, over the members' own starts."""
        members, sign = self.group(name)
        fixed = self.fixed_members(name)
        if fixed:
            return sign[fixed[0]] * self.own(fixed[0])
        # the first non-zero start, representative first; the representative's own if none
        found = self.own(name)
        for member in reversed([name] + [m for m in members if m != name]):
            start = self.own(member)
            if start.is_number:
                if not start.is_zero:  # (not `start != 0`: sympy's Float(0.0) != Integer(0))
                    found = sign[member] * start
            elif sign[member] * start != found:
                found = sp.Piecewise((sign[member] * start, sp.Ne(start, 0)), (found, True))
        return found

    def agreeing(self) -> tuple:
        """:attr:`StartDependence.agreeing` of the fixed representatives."""
        out = []
        for name, variable in self.merged.items():
            if not variable.fixed or name not in self.members:
                continue
            _, sign = self.group(name)
            first, *others = self.fixed_members(name)
            for other in others:
                start_a, start_b = self.own(first), self.own(other)
                if not (start_a.is_number and start_b.is_number):
                    out.append((first, sign[first], start_a, other, sign[other], start_b))
        return tuple(out)


def newton_guesses(algebraic: AlgebraicResult, starts: StartValues) -> tuple[tuple[str, sp.Expr, float], ...]:
    """:attr:`StartDependence.guesses`: the tearing variables of ``algebraic``'s Newton
    iterations whose first guess (their start value) depends on start parameters."""
    out = []
    for step in algebraic.steps:
        if isinstance(step, NewtonSolve):
            for name in step.tears:
                if name in starts.merged:
                    expression = starts.expression(name)
                    if not expression.is_number:
                        out.append((name, expression, starts.value(name)))
    return tuple(out)


def bind_start_values(system: "InitialSystem", symbols: Mapping) -> "InitialSystem | None":
    """``system`` for the start values of ``symbols`` (parameter symbol -> value): its
    ``relaxed`` and ``from_start`` values evaluated anew.

    Returns None when its code does not serve them (a Newton iteration's first
    guess was printed for other start values): it is compiled anew.

    Raises
    ------
    InitializationError
        For fixed start values of aliases that differ.
    """
    starts = system.starts
    if not starts:
        return system
    if not starts.guesses_hold(symbols):
        return None
    starts.check_agreeing(symbols)
    values = {name: _evaluated(e, symbols) for name, e in starts.values}
    return dataclasses.replace(system, relaxed=tuple((n, values.get(n, v)) for n, v in system.relaxed),
                               from_start=tuple((n, values.get(n, v)) for n, v in system.from_start))


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
    #: what the code assumes of the start values beyond the parameter vector (see bind_start_values)
    starts: StartDependence = StartDependence()

    def reset(self) -> None:
        """A new run: the Newton solves start from the start values again."""
        reset_warm_starts(self.outputs)

    @property
    def seconds(self) -> float:
        """Seconds spent building it, its mode's system excluded."""
        return sum(s for _, s in self.passes)

    @property
    def sources(self) -> tuple[str, ...]:
        """The generated source (one; a composed problem has one per cluster)."""
        return (self.code.source,)


def compile_initial_system(mode: ModeSystem, initial_equations: Sequence[FlatEquation], context: str,
                           cache: ModelCache, declared: Mapping[str, FlatVariable] | None = None,
                           delays: Sequence = ()) -> InitialSystem:
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
        The work shared with the model's other systems.  Its parameters
        include the tunable start values (``J1.w.start``), which the fixed
        start values and the start values of states become.
    declared : mapping of str to FlatVariable, optional
        The model's continuous variables with this translation's start
        values: the start of each alias set is merged from its members'
        (see :class:`StartValues`).  None: the representatives' merged
        starts, as the mode's alias elimination made them.

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
        # start values as expressions of the start parameters: the code reads them from the
        # parameter vector (a mode rebound to other values keeps its merged numbers: not used)
        starts = StartValues(mode.aliases.aliases, variables, declared, parameters.symbols)
        state_set = set(mode.structure.states)
        fixed_states, fixed_others = [], []
        for name, var in variables.items():
            if var.fixed:
                eq = FlatEquation(real_symbol(name) - starts.expression(name),
                                  Origin(var.component, "", "fixed start", 0, f"{name} = {starts.value(name):g}"))
                (fixed_states if name in state_set else fixed_others).append((name, eq))
        check_fixed_constants(mode.aliases, parameters.symbols)
        dae = list(mode.structure.equations)
        if delays:
            # at the start time a delayed value is its expression's value now (Modelica 3.7.4.1)
            dae = [FlatEquation(at_start(e.residual, delays, substitution), e.origin) for e in dae]
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
        relaxed = tuple((fixed_names[i - n_fixed0], starts.value(fixed_names[i - n_fixed0]))
                        for i in unmatched)
        from_start: tuple[tuple[str, float], ...] = ()
        if -1 in assign:
            from_start = _complete_with_start_values(equations, incidence, assign, unknowns, u_index,
                                                     unfixed_states, starts)
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
        # the first guesses of Newton iterations are printed as numbers (recorded below)
        guesses = {t: starts.value(t) for step in algebraic.steps if isinstance(step, NewtonSolve)
                   for t in step.tears if t in variables}
        code = generate(algebraic.steps, (), (), unknowns, parameters.names, (),
                        name=context, guesses=guesses, identifiers=cache.identifiers,
                        memo=cache.codegen)
        _, _, outputs = code.make(parameters.vector)
        shown = dict.fromkeys(n for n, _ in (*relaxed, *from_start))
        dependence = StartDependence(
            tuple((n, starts.expression(n)) for n in shown if not starts.expression(n).is_number),
            newton_guesses(algebraic, starts), starts.agreeing())
    return InitialSystem(mode.key, tuple(kept_eqs), tuple(unknowns), relaxed, blt, algebraic, code,
                         tuple(passes.entries), outputs, from_start, dependence)


def _complete_with_start_values(equations: list[FlatEquation], incidence: list[tuple[int, ...]],
                                assign: list[int], unknowns: Sequence[str], u_index: dict[str, int],
                                unfixed_states: Sequence[str], starts: StartValues) -> tuple[tuple[str, float], ...]:
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
        variable = starts.merged.get(name)
        start = starts.expression(name) if variable is not None else sp.Integer(0)
        i = len(equations)
        equations.append(FlatEquation(real_symbol(name) - start,
                                      Origin(variable.component if variable is not None else "",
                                             "", "start value", 0, f"{name} = {_start_of(name, starts):g}")))
        incidence.append((u_index[name],))
        if augmenting_path(i, incidence, assign, lambda j: True, set(), set()):
            chosen.add(name)
            open_unknowns -= 1
        else:
            equations.pop()
            incidence.pop()
    return tuple((n, _start_of(n, starts)) for n in unfixed_states if n in chosen)


def _start_of(name: str, starts: StartValues) -> float:
    """The start value of ``name`` (0 for a state the flat model does not declare)."""
    return starts.value(name) if name in starts.merged else 0.0


def check_fixed_constants(aliases: AliasResult, parameter_symbols) -> None:
    """A fixed start value of a variable the model makes a constant must equal it.

    ``parameter_symbols`` (symbol -> value) may hold the variable's tunable
    start (``<name>.start``): then that value is the one checked, not the one
    alias elimination saw.
    """
    for name, expr, start in aliases.fixed_constants:
        start = float(parameter_symbols.get(real_symbol(start_parameter(name)), start))
        value = float(sp.sympify(expr).xreplace(parameter_symbols))
        if abs(value - start) > 1e-10 * max(1.0, abs(value)):
            raise InitializationError(
                f"conflicting initial values: {name} has fixed start {start}, but the model "
                f"makes it the constant {expr} = {value}",
                hint=f"remove fixed=True from {name} or change its start value",
                components=(name.rpartition(".")[0],))


def start_value_relations(flat, relations, parameter_symbols: Mapping, start_time: float) -> tuple[bool, ...]:
    """Each relation evaluated with the start values of the variables (0 when none is given).

    A guess for the initial event iteration: derivatives count as 0, and a
    relation that cannot be evaluated this way is guessed false.
    """
    variables = flat.variable_map
    guesses = []
    for rel in relations:
        g = sp.sympify(rel.g).xreplace(parameter_symbols)
        values = {time: start_time}
        for sym in g.free_symbols - {time}:
            variable = variables.get(sym.name)
            start = getattr(variable, "start", None) if variable is not None and not is_derivative(sym.name) else None
            values[sym] = start if isinstance(start, (int, float)) else 0.0
        try:
            guesses.append(rel.holds(float(g.xreplace(values))))
        except (TypeError, ValueError, ZeroDivisionError):
            guesses.append(False)
    return tuple(guesses)
