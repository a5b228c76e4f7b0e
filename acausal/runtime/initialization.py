"""Stage 10: initialization — consistent values at the start time.

The initialization problem is the model's equations (including those index
reduction differentiated) plus one equation ``v = start`` for every variable
with ``fixed=True`` plus the initial equations, solved for every variable
and derivative with ``initial()`` true.  Discrete variables with
``fixed=True`` have ``pre(v) = start``; the discrete equations and the
continuous problem are iterated to a fixed point.

A fixed start value that the others already determine (an inertia whose
speed follows from a gear and another inertia) is *relaxed*: dropped from the
problem, then checked — equal, it is reported in the result's notes;
different, it is a conflict and an error.

An under-determined problem is completed as Dymola and OpenModelica complete
it: the states that nothing else determines take their start values (0 when
none is given; the choice of states is structural, see
:mod:`acausal.compiler.initial`).  A :class:`~acausal.errors.StartValueWarning`
lists them with their values, and the result's notes say the same.

As Dymola and OpenModelica do, one event iteration with ``initial()`` false
follows (the MSL reference rows at the start time depend on it).

Start values given at run time (``simulate(model, start=...)``) are the
translation's: its flat model's variables carry them (the discrete start
values and the guesses of relations read here), and the compiled problem
reads those of states and fixed variables from its parameter vector, its
``relaxed`` and ``from_start`` values evaluated for them
(:func:`~acausal.compiler.initial.bind_start_values`).
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from typing import Mapping, Sequence

from ..errors import AcausalError, InitializationError, SolverError, StartValueWarning
from ..compiler.run_context import active_history
from .contract import CompiledModel, CompiledSystem
from .crossings import ticking_at
from .events import DiscreteEvaluator, EventOutcome, mode_values, with_aliases

__all__ = ["InitialState", "initialize", "start_guess", "start_system", "start_value_message"]


@dataclass(frozen=True)
class InitialState:
    """Values at the start time, after the post-initialization event iteration.

    Attributes
    ----------
    initial_values : dict
        The solution of the initialization problem (``initial()`` true).
    initial_discrete : dict
    outcome : EventOutcome
        The event iteration that follows; its system is the first one
        integrated.
    notes : tuple of str
    """

    time: float
    initial_values: dict
    initial_discrete: dict
    initial_relations: tuple
    outcome: EventOutcome
    notes: tuple[str, ...]
    #: the sample clocks that tick at the start time (in the event iteration that follows)
    ticks: frozenset = frozenset()


def start_guess(translation: CompiledModel) -> tuple[dict, tuple[bool, ...]]:
    """The discrete values and relation values initialization starts from: the
    start values (discrete Reals included) and every relation false.

    With ``initial()`` true, ``evaluator.key(discrete, discrete, relations, True)``
    is the first discrete state :func:`initialize` tries.
    """
    data = translation.data
    variables = data.variable_map
    discrete = {n: (bool(variables[n].start) if variables[n].kind == "boolean" else int(variables[n].start))
                for n in data.discrete_variables}
    # discrete Reals: their start values, until a when-clause with initial() sets them
    discrete.update({n: float(variables[n].start) for n in data.held_variables})
    return discrete, tuple(False for _ in data.relations)


def initialize(translation: CompiledModel, evaluator: DiscreteEvaluator, start_time: float) -> InitialState:
    """Solve the initialization problem at ``start_time``."""
    data = translation.data
    variables = data.variable_map
    # a run starts here: its impure functions start from empty states, and each of their
    # call sites computes one value in the iteration of the initialization problem
    evaluator.start_run()
    evaluator.open_instant()
    discrete, relations = start_guess(translation)
    fixed_pre = {n: discrete[n] for n in discrete if variables[n].fixed}
    # homotopy(): first solved with the simplified expressions, whose solution decides the
    # discrete state the actual ones are solved from (hybrid.homotopy)
    simplified = data.homotopy
    if simplified is not None:
        discrete[simplified] = True
    at_zero = tuple(rel.holds(0.0) for rel in data.relations)
    notes: list[str] = []
    values = None
    history = [dict(discrete)]
    guessed = False
    held = set(data.held_variables)
    assigned: dict[str, float] = {}  # discrete Reals a when-clause with initial() sets
    for _ in range(evaluator.max_iterations):
        pre = {**discrete, **fixed_pre}
        key = evaluator.key(discrete, pre, relations, True)
        try:
            problem = translation.initial_system(key)
            outputs = _with_held_values(translation, problem, assigned)
            values = dict(zip(problem.unknowns, outputs(start_time, ())))
        except (AcausalError, ArithmeticError, ValueError) as failure:
            if simplified is not None and discrete[simplified]:
                # the simplified problem is singular or cannot be solved: the actual
                # one alone (MLS 3.7.4.4)
                discrete, relations = start_guess(translation)
                history.append(dict(discrete))
                continue
            if guessed or (isinstance(failure, AcausalError) and not isinstance(failure, SolverError)):
                raise
            # the first guess (every relation false) selects a branch that cannot be
            # evaluated (1/|w| at w = 0, a domain error) or solved here: guess again from
            # the start values, as a Modelica tool starts its mixed system from them
            guessed = True
            relations = translation.start_value_relations(start_time)
            continue
        system = translation.system(key)
        delays = active_history() if data.delays else None
        if delays is not None and not delays.started:
            # the delayed values at the start time: their expressions' values now
            delays.set_start(start_time, with_aliases(dict(values), system))
        x = evaluator._states(system, values, discrete)
        # |g| within the relation margin counts as g = 0, as at events: a load one
        # ulp above a static limit does not start a slip at t = 0 either
        new_relations = evaluator.relation_values(system, start_time, x, at_zero)
        evaluator.prepare(system, start_time, x)
        new_discrete = evaluator.evaluate_discrete(discrete, pre, new_relations, True)
        # a discrete Real that nothing but its start determined in the problem, and that the
        # discrete equations set otherwise (when initial() then r = ...), takes that value in
        # the problem too: Modelica's initialization solves both together
        new_assigned = {name: new_discrete[name] for name, start in _held_from_start(translation, problem, held)
                        if new_discrete[name] != start}
        if new_discrete == discrete and new_relations == relations and new_assigned == assigned:
            if simplified is None or not discrete[simplified]:
                break
            new_discrete = {**new_discrete, simplified: False}  # the end of the homotopy path
            notes.append(f"initialization: homotopy() solved with its simplified expressions first, "
                         f"then with the actual ones from the discrete state that solution decided")
        discrete, relations, assigned = new_discrete, new_relations, new_assigned
        history.append(dict(discrete))
    else:
        changing = sorted({n for a, b in zip(history, history[1:]) for n in a if a[n] != b[n]})
        owners = tuple(dict.fromkeys(n.rpartition(".")[0] for n in changing))
        own = data.hints_for("event_iteration", owners)
        raise InitializationError(
            f"initialization of {data.name}: the discrete variables did not settle in "
            f"{evaluator.max_iterations} iterations; still changing: {', '.join(changing) or 'unknown'}",
            hint="; ".join(("check the start values of the Boolean and Integer variables named and "
                            "the conditions that set them", *own)), components=owners)
    evaluator.close_instant()
    x = evaluator._states(system, values, discrete)
    values = mode_values(system, start_time, x)
    evaluator.prepare(None, start_time, x)
    for name, start in problem.relaxed:
        actual = values[name]
        if abs(actual - start) > 1e-8 * max(1.0, abs(start), abs(actual)):
            raise InitializationError(
                f"initialization of {data.name}: conflicting initial values: {name} has fixed "
                f"start {start:g}, but the other fixed values make it {actual:.9g}",
                hint=f"remove fixed=True from {name} (it is determined by the rest of the model)")
        notes.append(f"fixed start of {name} = {start:g} is implied by the others; not imposed again")
    if problem.from_start:
        message = start_value_message(data.name, problem.from_start,
                                      declared_aliases(system, variables, [n for n, _ in problem.from_start]))
        notes.append(message)
        warnings.warn(message, StartValueWarning, stacklevel=2)
    # a sample clock whose first tick is the start time ticks in this event iteration
    ticks = ticking_at(start_time, translation.clock_ticks())
    outcome = evaluator.iterate(start_time, values, discrete, relations, initial=False, ticks=ticks)
    return InitialState(start_time, values, discrete, relations, outcome, tuple(notes), ticks)


def _held_from_start(translation: CompiledModel, problem, held: set[str]) -> list[tuple[str, float]]:
    """The discrete Reals whose value the initialization problem takes from their start
    values, with those values: a fixed start (for a discrete variable Modelica's
    ``pre(r) = start``, which makes ``r`` the start unless a when-clause with ``initial()``
    assigns it) not implied by the rest, or a start taken because nothing determines it."""
    if not held:
        return []
    start_of = translation.data.parameter_table
    relaxed = {name for name, _ in problem.relaxed}
    variables = translation.data.variable_map
    found = [(name, start_of.get(f"{name}.start", float(variables[name].start))) for name in sorted(held)
             if variables[name].fixed and name not in relaxed]
    taken = {name for name, _ in found}
    found += [(name, value) for name, value in problem.from_start if name in held and name not in taken]
    return found


def _with_held_values(translation: CompiledModel, problem, assigned: Mapping[str, float]):
    """``problem.outputs``, or its code bound to start values in which the discrete Reals of
    ``assigned`` start at their assigned values (their start is what the problem reads for
    them: they are among its ``from_start``).  A problem composed of clusters keeps its own."""
    code = getattr(problem, "code", None)
    if not assigned or code is None:
        return problem.outputs
    data = translation.data
    index = {name: k for k, name in enumerate(data.parameter_names)}
    vector = list(data.parameter_vector)
    for name, value in assigned.items():
        k = index.get(f"{name}.start")
        if k is None:
            return problem.outputs
        vector[k] = float(value)
    return code.make(tuple(vector))[2]


def declared_aliases(system, variables: Mapping, names: Sequence[str]) -> dict[str, list[str]]:
    """The variables equal to each of ``names`` that components declare (connector variables left out).

    Alias elimination keeps one name per set of equal variables, often a
    component the user did not think of (a source's angle rather than the
    angle of the body it drives); the others make a message recognisable.
    """
    wanted = set(names)
    found: dict[str, list[str]] = {n: [] for n in names}
    for alias, coefficient, source in getattr(system, "alias_plan", ()) or ():
        variable = variables.get(alias)
        if source in wanted and coefficient == 1 and variable is not None and not variable.role:
            found[source].append(alias)
    return found


def start_value_message(model: str, from_start: Sequence[tuple[str, float]],
                        aliases: Mapping[str, Sequence[str]] | None = None) -> str:
    """The warning (and note) naming the states initialised from their start values.

    The first line names the components, then one line per state, then the hint.

    Parameters
    ----------
    model : str
        The model's name.
    from_start : sequence of (str, float)
        The states and the start values they took.
    aliases : mapping of str to sequence of str, optional
        Other names of each state, shown after it.
    """
    aliases = aliases or {}

    def named(name: str) -> str:
        others = aliases.get(name) or ()
        return f"{name} (= {', '.join(others)})" if others else name

    count = len(from_start)
    owners = dict.fromkeys(other.rpartition(".")[0] or other for name, _ in from_start
                           for other in (name, *(aliases.get(name) or ())))
    lines = [f"{', '.join(owners)}: {count} state{'s' if count > 1 else ''} without fixed=True "
             f"initialised from {'their' if count > 1 else 'its'} start value{'s' if count > 1 else ''} "
             f"(initialization of {model}: nothing else determines {'them' if count > 1 else 'it'})"]
    lines += [f"  {named(name)} = {value:g}" for name, value in from_start]
    lines.append("  hint: give fixed=True or initial equations to choose")
    return "\n".join(lines)


def start_system(translation: CompiledModel) -> CompiledSystem:
    """The system in force at the start time, after initialization.

    Convenient for inspecting a model: it runs the initialization (and its
    event iteration) to find the discrete state.
    """
    state = initialize(translation, DiscreteEvaluator(translation), translation.data.experiment.start_time)
    return state.outcome.system
