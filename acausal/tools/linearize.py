"""Linearization per discrete state, and steady states.

:func:`linearize` returns the matrices ``A, B, C, D`` of the linear model

.. math::

    \\dot{\\delta x} = A\\,\\delta x + B\\,\\delta u, \\qquad
    \\delta y = C\\,\\delta x + D\\,\\delta u

of the continuous system of the discrete state active at an operating point,
and says which discrete state that is.  A hybrid model has one continuous
system per discrete state (a friction element stuck or sliding), so its
linearization depends on the discrete state as much as on the continuous
values: the result names the state by its modes.

The derivatives are exact: they are taken symbolically (sympy) from the
equations of the discrete state after alias elimination and index reduction,
the semi-explicit DAE

.. math::

    0 = F(x, z, u, t),

where ``x`` are the states the engine selected, ``z`` every other unknown
(the derivatives ``der(x)`` among them, the dummy derivatives of index
reduction and the algebraic variables) and ``u`` the inputs.  Where ``F_z``
is regular (the DAE has index 1 in ``z``, which index reduction ensures), the
implicit function theorem gives ``dz = -F_z^{-1} (F_x dx + F_u du)``; the
rows of ``der(x)`` are ``A`` and ``B``, those of the outputs ``C`` and ``D``.
For ``der(x) = f(x, z_a, u)``, ``0 = g(x, z_a, u)`` this is the familiar
``A = f_x - f_z g_z^{-1} g_x``.

:func:`steady_state` solves ``der(x) = 0`` for the states, with the discrete
state found by the runtime's event iteration at the solution.

References
----------
.. [1] K. E. Brenan, S. L. Campbell and L. R. Petzold, *Numerical Solution of
   Initial-Value Problems in Differential-Algebraic Equations*, SIAM, 1996,
   ch. 2 (semi-explicit DAEs of index one and their linearization).
.. [2] Modelica Association, *Modelica Language Specification* 3.6, section
   4.9 (inputs of a model) and the ``linearizeModel`` function of Dymola
   (Dassault Systèmes, *Dymola User Manual* vol. 1, "Linearization"), whose
   ``A, B, C, D`` are those of this module for the top-level inputs.
.. [3] C. C. Pantelides, "The consistent initialization of differential-
   algebraic systems", SIAM J. Sci. Stat. Comput. 9(2), 1988; S. E. Mattsson
   and G. Söderlind, "Index reduction in differential-algebraic equations
   using dummy derivatives", SIAM J. Sci. Comput. 14(3), 1993 (the reduced
   system linearized here).
"""

from __future__ import annotations

import difflib
import math
from dataclasses import dataclass, field
from typing import Any, Mapping, Sequence

import networkx as nx
import numpy as np
import sympy as sp

from ..compiler.alias import eliminate_aliases
from ..compiler.codegen import compile_functions
from ..compiler.structure import StructureMemo, analyse
from ..compiler.translate import Translation, translate
from ..errors import SettingError, SolverError, StructuralError
from ..language import Component, real_symbol, time as time_symbol
from ..names import der_name, is_derivative, parse
from ..runtime.events import evaluator_for, mode_values
from ..runtime.initialization import initialize
from ..runtime.simulate import simulate
from .report_html import StateNamer

__all__ = ["Linearization", "SteadyState", "linearize", "steady_state"]

#: Newton iterations that make the unknowns consistent with the states at an operating point.
_NEWTON_ITERATIONS = 30

#: Rounds of "solve, then event iteration" before :func:`steady_state` gives up.
MAX_ROUNDS = 8


# ---------------------------------------------------------------------------
# Results
# ---------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class Linearization:
    """The linear model of one discrete state at an operating point.

    ``der(x) ≈ A (x - x0) + B (u - u0)`` and ``y ≈ y0 + C (x - x0) + D (u - u0)``.

    Attributes
    ----------
    A, B, C, D : ndarray
        ``n x n``, ``n x m``, ``p x n`` and ``p x m``.
    state_names, input_names, output_names : tuple of str
        The states (in the order of the discrete state's compiled system), the
        inputs and outputs as asked for.
    x0, u0, y0 : ndarray
        The operating point: states, inputs and outputs there.
    t : float
        Its time.
    discrete_key : tuple
        The discrete state (values of the translation's selectors).
    discrete_state : str
        The discrete state named by its modes (e.g. ``c1: Stuck, c2: Forward``;
        see :class:`~acausal.tools.report_html.StateNamer`).
    discrete_description : str
        The engine's description of it, as in
        :attr:`~acausal.runtime.result.SimulationResult.modes`.
    """

    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    D: np.ndarray
    state_names: tuple[str, ...]
    input_names: tuple[str, ...]
    output_names: tuple[str, ...]
    x0: np.ndarray
    u0: np.ndarray
    y0: np.ndarray
    t: float
    discrete_key: tuple
    discrete_state: str
    discrete_description: str = field(repr=False, default="")

    @property
    def eigenvalues(self) -> np.ndarray:
        """The eigenvalues of ``A``, sorted by real part, then imaginary part."""
        values = np.linalg.eigvals(self.A) if self.A.size else np.zeros(0, dtype=complex)
        return np.array(sorted(values, key=lambda v: (v.real, v.imag)))

    def to_control(self):
        """The python-control ``StateSpace`` of ``A, B, C, D``, with the names.

        python-control reserves ``.`` in signal names (it names the signals of
        interconnected systems ``system.signal``): the dots of dotted names
        become ``_`` (``J1.w`` is the state ``J1_w``).

        Raises
        ------
        ImportError
            If python-control is not installed (``pip install control``).
        """
        try:
            import control
        except ImportError as exc:  # an optional dependency: say how to get it
            raise ImportError("Linearization.to_control() needs python-control: pip install control") \
                from exc
        def labels(names):
            return [n.replace(".", "_") for n in names]

        return control.ss(self.A, self.B, self.C, self.D, states=labels(self.state_names),
                          inputs=labels(self.input_names), outputs=labels(self.output_names))

    def __str__(self) -> str:
        with np.printoptions(precision=6, suppress=True, linewidth=120):
            return (f"Linearization at t = {self.t:g} in [{self.discrete_state}]\n"
                    f"  states  {', '.join(self.state_names)}\n"
                    f"  inputs  {', '.join(self.input_names) or '-'}\n"
                    f"  outputs {', '.join(self.output_names) or '-'}\n"
                    f"A =\n{self.A}\nB =\n{self.B}\nC =\n{self.C}\nD =\n{self.D}")


@dataclass(frozen=True, eq=False)
class SteadyState:
    """A steady state: ``der(x) = 0`` for the states solved for.

    Attributes
    ----------
    states : dict
        Every state of the discrete state's system at the solution.
    derivatives : dict
        ``der(x)`` of every state there: zero up to :attr:`residual` for the
        solved states; the held states (:attr:`free`) may move at a constant rate.
    residual : float
        Euclidean norm of the derivatives of the solved states.
    free : tuple of str
        The states held at their guess and not solved for: those asked for
        with ``free=`` and those no derivative depends on.
    values : dict
        Every continuous variable at the solution (aliases included).
    t : float
    discrete_key : tuple
    discrete_state : str
        The discrete state named by its modes.
    discrete_description : str
        The engine's description of it.
    rounds : int
        Discrete states tried (1: the first was consistent).
    """

    states: dict
    derivatives: dict
    residual: float
    free: tuple[str, ...]
    values: dict = field(repr=False)
    t: float
    discrete_key: tuple
    discrete_state: str
    discrete_description: str = field(repr=False, default="")
    rounds: int = 1

    def __getitem__(self, name: str) -> float:
        """The value of variable ``name`` at the steady state."""
        return self.values[name]


# ---------------------------------------------------------------------------
# The DAE of one discrete state, symbolically
# ---------------------------------------------------------------------------


class _StateDAE:
    """``0 = F(x, z, u, t)`` of one discrete state, with its Jacobians compiled.

    Built from the discrete state's specialised equations by the engine's own
    alias elimination and structural analysis, so that the states are those
    its compiled system integrates; the variables named as inputs are made
    free first (see :func:`_free_inputs`).
    """

    def __init__(self, translation: Translation, key: tuple, inputs: Sequence[str],
                 outputs: Sequence[str]) -> None:
        self.translation = translation
        self.key = key
        self.inputs = tuple(inputs)
        parameters = dict(translation.cache.parameters.values)
        equations = translation.specialise(key)
        variables = translation.continuous
        equations, variables = _free_inputs(translation, equations, variables, self.inputs, parameters)
        context = f"the linearization of {translation.flat.name} [{translation.describe(key)}]"
        # the inputs are known values here, like parameters (never zero: a zero parameter
        # is a structural zero, and an input's terms must stay)
        known = {**parameters, **{u: 1.0 for u in self.inputs}}
        self.aliases = eliminate_aliases(equations, variables, set(known))
        try:
            self.structure = analyse(self.aliases.equations, self.aliases.variables, known, context,
                                     StructureMemo())
        except StructuralError as exc:
            if self.inputs:
                raise SettingError(f"{context}: with {', '.join(self.inputs)} as input(s) the equations "
                                   f"cannot be solved: {exc.message}",
                                   hint="an input must be a variable the rest of the model does not "
                                        "determine once its own defining equation is gone") from None
            raise
        structure = self.structure
        inputs_set = {real_symbol(u) for u in self.inputs}
        for i, parent in structure.differentiated:
            touched = inputs_set & structure.equations[parent].residual.free_symbols
            if touched:
                name = sorted(s.name for s in touched)[0]
                raise SettingError(
                    f"{name} cannot be an input of {translation.flat.name}: index reduction "
                    f"differentiates {structure.equations[parent].origin}, which contains it, so the "
                    f"linear model would need der({name})",
                    hint="choose as input a variable that acts on a state's derivative, not one that "
                         "prescribes a state")
        held = {n for n, v in translation.flat.variable_map.items() if v.is_held}
        self.states = tuple(s for s in structure.states if s not in held)
        self.held = tuple(s for s in structure.states if s in held)
        self.unknowns = tuple(structure.unknowns)
        unknown_index = {n: k for k, n in enumerate(self.unknowns)}
        self.derivative_rows = tuple(unknown_index[der_name(s)] for s in self.states)
        self.parameter_names = tuple(parameters)
        self.parameter_vector = np.array([parameters[n] for n in self.parameter_names], dtype=float)
        self.outputs = tuple(outputs)
        output_exprs = [self._output_expression(name) for name in self.outputs]
        self.structural_free = self._structurally_free()

        # Jacobian entries, each d(residual or output)/d(variable), in one compiled function
        columns = {**{s: ("x", k) for k, s in enumerate(self.states)},
                   **{z: ("z", k) for k, z in enumerate(self.unknowns)},
                   **{u: ("u", k) for k, u in enumerate(self.inputs)}}
        entries: list[sp.Expr] = []
        self._places: list[tuple[str, int, str, int]] = []  # (row kind, row, column kind, column)
        residuals = [eq.residual for eq in structure.equations]
        for row_kind, expressions in (("F", residuals), ("y", output_exprs)):
            for i, expr in enumerate(expressions):
                for symbol in sorted(expr.free_symbols, key=lambda s: s.name):
                    column = columns.get(symbol.name)
                    if column is None:
                        continue
                    derivative = sp.diff(expr, symbol)
                    if derivative != 0:
                        entries.append(derivative)
                        self._places.append((row_kind, i, *column))
        self.arguments = ("time", *self.states, *self.unknowns, *self.inputs, *self.held,
                          *self.parameter_names)
        self._check_symbols([*residuals, *output_exprs])
        name = f"the linearization of {translation.flat.name}"
        self._jacobian, self._residuals, self._outputs = compile_functions(
            [self.arguments] * 3,
            [sp.Tuple(*entries), sp.Tuple(*residuals), sp.Tuple(*output_exprs)], name)

    # -- building ------------------------------------------------------------

    def _output_expression(self, name: str) -> sp.Expr:
        """Output ``name`` as an expression of states, unknowns, inputs and parameters."""
        known = set(self.states) | set(self.unknowns) | set(self.inputs) | set(self.held)
        if name in known:
            return real_symbol(name)
        expr = self.aliases.aliases.get(name)
        if expr is not None:
            return sp.sympify(expr)
        if name in self.translation.cache.parameters.values:
            raise SettingError(f"{name} is a parameter of {self.translation.flat.name}, not a variable: "
                               f"it cannot be an output of the linear model")
        close = difflib.get_close_matches(name, sorted(known | set(self.aliases.aliases)), n=3)
        raise SettingError(f"{self.translation.flat.name} has no continuous variable {name!r} in "
                           f"{self.translation.describe(self.key)}",
                           hint=f"did you mean {', '.join(close)}?" if close else
                           "outputs are dotted variable names, e.g. component.variable")

    def _check_symbols(self, expressions) -> None:
        allowed = set(self.arguments)
        for expr in expressions:
            for symbol in expr.free_symbols:
                if symbol.name not in allowed:
                    raise SettingError(f"the linearization of {self.translation.flat.name}: {symbol.name} "
                                       f"is neither a state, an unknown, an input nor a parameter")

    def _structurally_free(self) -> frozenset[str]:
        """The states no derivative depends on (an angle that only integrates a speed).

        Each equation computes the unknown it is matched to from the other
        variables it contains; a state reaches a derivative through that graph
        or not at all.
        """
        structure = self.structure
        graph = nx.DiGraph()
        graph.add_nodes_from(structure.states)
        graph.add_nodes_from(structure.unknowns)
        for i, eq in enumerate(structure.equations):
            solved = structure.unknowns[structure.matching[i]]
            for symbol in eq.residual.free_symbols:
                if symbol.name != solved and symbol.name in graph:
                    graph.add_edge(symbol.name, solved)
        derivatives = {der_name(s) for s in self.states}
        free = set()
        for s in self.states:
            if derivatives.isdisjoint(nx.descendants(graph, s)):
                free.add(s)
        return frozenset(free)

    # -- evaluating ------------------------------------------------------------

    def _argument_vector(self, t: float, x, z, u, held_values) -> list[float]:
        return [float(t), *map(float, x), *map(float, z), *map(float, u), *map(float, held_values),
                *self.parameter_vector]

    def jacobians(self, t: float, x, z, u, held_values):
        """``(F_x, F_z, F_u, H_x, H_z, H_u)`` at the point (H: of the outputs)."""
        n, nz, m, p = len(self.states), len(self.unknowns), len(self.inputs), len(self.outputs)
        blocks = {("F", "x"): np.zeros((nz, n)), ("F", "z"): np.zeros((nz, nz)), ("F", "u"): np.zeros((nz, m)),
                  ("y", "x"): np.zeros((p, n)), ("y", "z"): np.zeros((p, nz)), ("y", "u"): np.zeros((p, m))}
        values = self._jacobian(*self._argument_vector(t, x, z, u, held_values))
        for (row_kind, row, column_kind, column), value in zip(self._places, values):
            blocks[row_kind, column_kind][row, column] += float(value)
        return tuple(blocks[k] for k in (("F", "x"), ("F", "z"), ("F", "u"), ("y", "x"), ("y", "z"), ("y", "u")))

    def residuals(self, t: float, x, z, u, held_values) -> np.ndarray:
        return np.array(self._residuals(*self._argument_vector(t, x, z, u, held_values)), dtype=float)

    def output_values(self, t: float, x, z, u, held_values) -> np.ndarray:
        return np.array(self._outputs(*self._argument_vector(t, x, z, u, held_values)), dtype=float)

    def consistent_unknowns(self, t: float, x, z, u, held_values) -> np.ndarray:
        """``z`` refined by Newton's method so that ``F(x, z, u, t) = 0`` (from ``z`` as a guess)."""
        z = np.array(z, dtype=float)
        scale = 1.0 + max([abs(v) for v in (*x, *z, *u)] or [0.0])
        for _ in range(_NEWTON_ITERATIONS):
            residual = self.residuals(t, x, z, u, held_values)
            if not residual.size or np.max(np.abs(residual)) <= 1e-12 * scale:
                return z
            _, F_z, _, _, _, _ = self.jacobians(t, x, z, u, held_values)
            try:
                z = z - np.linalg.solve(F_z, residual)
            except np.linalg.LinAlgError:
                break
        raise SolverError(f"the linearization of {self.translation.flat.name}: the unknowns of "
                          f"{self.translation.describe(self.key)} could not be made consistent with the "
                          f"states given (residual {np.max(np.abs(residual)):.3g})",
                          hint="give an operating point the model can be in, e.g. a time of a simulation")

    def linear(self, t: float, x, z, u, held_values):
        """``(A, B, C, D)`` at a consistent point."""
        F_x, F_z, F_u, H_x, H_z, H_u = self.jacobians(t, x, z, u, held_values)
        try:
            sensitivity = -np.linalg.solve(F_z, np.hstack([F_x, F_u])) if len(self.unknowns) else \
                np.zeros((0, len(self.states) + len(self.inputs)))
        except np.linalg.LinAlgError:
            raise SolverError(f"the linearization of {self.translation.flat.name} in "
                              f"{self.translation.describe(self.key)}: the Jacobian of the equations "
                              f"with respect to the unknowns is singular at t = {t:g}",
                              hint="the unknowns are not determined by the states here; try another "
                                   "operating point") from None
        n = len(self.states)
        rows = list(self.derivative_rows)
        A = sensitivity[rows, :n]
        B = sensitivity[rows, n:]
        C = H_x + H_z @ sensitivity[:, :n]
        D = H_u + H_z @ sensitivity[:, n:]
        return A, B, C, D


def _free_inputs(translation: Translation, equations, variables: Mapping, inputs: Sequence[str],
                 parameters: Mapping[str, float]):
    """The equations with each input's defining equation removed, and the variables without the inputs.

    An input is a variable whose value the model computes from time and
    parameters alone: a source's output, a variable connected to one, or a
    top-level input.  Such values are found by following the equations that
    have a single unknown left, from time and parameters on; the equation
    that gave the input its value is the one removed (for a top-level input
    that nothing computes, none is).
    """
    if not inputs:
        return equations, variables
    flat_variables = translation.flat.variable_map
    for name in inputs:
        found = flat_variables.get(name)
        if found is None:
            close = difflib.get_close_matches(name, sorted(variables), n=3)
            raise SettingError(f"{translation.flat.name} has no variable {name!r} to use as input",
                               hint=f"did you mean {', '.join(close)}?" if close else
                               "inputs are dotted variable names, e.g. source.y")
        if found.is_discrete or name not in variables:
            raise SettingError(f"{name} is a discrete variable of {translation.flat.name}: inputs are "
                               f"continuous variables")
    if len(set(inputs)) != len(inputs):
        raise SettingError(f"an input is named twice: {', '.join(inputs)}")
    known_names = set(parameters)
    unknowns_of = []
    for eq in equations:
        unknowns_of.append({s.name for s in eq.residual.free_symbols
                            if s is not time_symbol and s.name not in known_names})
    determined: dict[str, int] = {}
    pending = set(range(len(equations)))
    changed = True
    while changed:
        changed = False
        for i in sorted(pending):
            rest = unknowns_of[i] - determined.keys()
            if len(rest) == 1:
                (only,) = rest
                if not is_derivative(only):
                    determined[only] = i
                    pending.discard(i)
                    changed = True
            elif not rest:
                pending.discard(i)
    dropped = set()
    for name in inputs:
        for i, names in enumerate(unknowns_of):
            if der_name(name) in names:
                raise SettingError(f"{name} cannot be an input of {translation.flat.name}: its derivative "
                                   f"appears in {equations[i].origin}",
                                   hint="inputs are values set by sources, not states")
        if name in determined:
            dropped.add(determined[name])
            continue
        if flat_variables[name].causality == "input" and not flat_variables[name].component:
            # a top-level input: no equation computes it (should one, the system left is
            # over-determined and structural analysis says so)
            continue
        raise SettingError(
            f"{name} cannot be an input of {translation.flat.name}: its value depends on the model's "
            f"states, not on time and parameters alone",
            hint="an input is a variable a source sets (a source block's output, a variable connected "
                 "to one) or a top-level input; name the source's output")
    kept = tuple(eq for i, eq in enumerate(equations) if i not in dropped)
    return kept, {n: v for n, v in variables.items() if n not in set(inputs)}


# ---------------------------------------------------------------------------
# Operating points
# ---------------------------------------------------------------------------


@dataclass(frozen=True)
class _Point:
    """A consistent point: time, discrete state and every continuous value."""

    t: float
    key: tuple
    values: dict
    system: Any = field(repr=False, default=None)  #: the compiled system of ``key`` (None: not compilable)


def _translation_of(model: Component | Translation, parameters: Mapping[str, float] | None) -> Translation:
    if isinstance(model, Translation):
        if parameters:
            raise SettingError("parameters= takes effect when the model is translated: pass the model, "
                               "or translate(model, parameters=...) and pass that translation")
        return model
    if not isinstance(model, Component):
        raise SettingError(f"expected a model instance or a Translation, not {type(model).__name__}")
    return translate(model, parameters=dict(parameters) if parameters else None)


def _resolve_discrete(translation: Translation, discrete) -> tuple:
    """A discrete state given as its key or its description (the engine's or by modes)."""
    selectors = translation.selectors
    if isinstance(discrete, tuple):
        if len(discrete) != len(selectors):
            raise SettingError(f"a discrete state of {translation.flat.name} has {len(selectors)} values "
                               f"({', '.join(s.name for s in selectors) or 'none'}), not {len(discrete)}")
        return discrete
    if isinstance(discrete, str):
        namer = StateNamer(translation)
        known = [k for k in (*translation.systems, *translation.initial_systems)]
        for key in dict.fromkeys(known):
            if discrete in (translation.describe(key), namer(key)):
                return key
        names = sorted({namer(k) for k in known})
        raise SettingError(f"no discrete state of {translation.flat.name} compiled so far is named "
                           f"{discrete!r}",
                           hint="give the key (a tuple of the selector values), or simulate the "
                                "translation first; known: " + ("; ".join(names[:6]) or "none"))
    raise SettingError(f"discrete= takes a key (tuple) or a description (str), not {type(discrete).__name__}")


def _start_time(translation: Translation) -> float:
    return float(translation.flat.experiment.start_time)


def _discrete_values(translation: Translation, result, row: int) -> dict:
    """The discrete variables (Booleans, Integers, discrete Reals) in row ``row`` of a result."""
    variables = translation.flat.variable_map
    out = {}
    for name in (*translation.partitioned.discrete_variables, *translation.partitioned.held_variables):
        value = result.columns[name][row]
        kind = variables[name].kind
        out[name] = bool(value) if kind == "boolean" else int(value) if kind == "integer" else float(value)
    return out


def _relation_guess(translation: Translation, t: float, values: Mapping[str, float]) -> tuple[bool, ...]:
    """The exact values of the relations at ``values`` (False where a side cannot be evaluated):
    the reference event iteration compares with."""
    substitution = {real_symbol(n): sp.Float(v) for n, v in translation.cache.parameters.values.items()}
    substitution.update({real_symbol(n): sp.Float(v) for n, v in values.items()
                         if isinstance(v, float) and math.isfinite(v)})
    substitution[time_symbol] = sp.Float(t)
    out = []
    for relation in translation.partitioned.relations:
        try:
            out.append(bool(relation.holds(float(relation.g.xreplace(substitution)))))
        except (TypeError, ValueError):
            out.append(False)
    return tuple(out)


def _settled(translation: Translation, t: float, values: Mapping[str, float], discrete: Mapping,
             relations) -> tuple[tuple, dict, Any, dict, tuple]:
    """Event iteration at ``t`` from ``discrete`` (as pre values): ``(key, values, system, discrete,
    relations)`` of the consistent discrete state (the right limit, where something changes)."""
    evaluator = evaluator_for(translation)
    outcome = evaluator.iterate(t, dict(values), dict(discrete), tuple(relations), initial=False)
    key = evaluator.key(outcome.discrete, outcome.discrete, outcome.relations, False)
    return key, dict(outcome.values), outcome.system, dict(outcome.discrete), tuple(outcome.relations)


def _point_at_time(translation: Translation, at: float) -> _Point:
    """The point a simulation of the model's experiment reaches at time ``at``."""
    start = _start_time(translation)
    if at < start:
        raise SettingError(f"at = {at:g} is before the start time {start:g} of {translation.flat.name}")
    evaluator = evaluator_for(translation)
    if at == start:
        state = initialize(translation, evaluator, start)
        outcome = state.outcome
        key = evaluator.key(outcome.discrete, outcome.discrete, outcome.relations, False)
        return _Point(start, key, dict(outcome.values), outcome.system)
    result = simulate(translation, stop_time=at)
    if not result.success:
        raise SolverError(f"the simulation of {translation.flat.name} to t = {at:g} failed: {result.message}",
                          hint="linearize at an earlier time, or at an operating point (a mapping of "
                               "state values)")
    row = len(result.time) - 1
    t = float(result.time[row])
    discrete_names = {*translation.partitioned.discrete_variables, *translation.partitioned.held_variables}
    values = {n: float(c[row]) for n, c in result.columns.items() if n not in discrete_names}
    discrete = _discrete_values(translation, result, row)
    key, values, system, _, _ = _settled(translation, t, values, discrete,
                                         _relation_guess(translation, t, values))
    return _Point(t, key, values, system)


def _point_given(translation: Translation, at: Mapping[str, float], t: float | None, discrete) -> _Point:
    """The point of the states (or more values) ``at``, its discrete state given or found."""
    t = _start_time(translation) if t is None else float(t)
    given = {str(n): float(v) for n, v in at.items()}
    if discrete is not None:
        key = _resolve_discrete(translation, discrete)
        system = _compiled_or_none(translation, key)
    elif not translation.selectors:
        key, system = (), _compiled_or_none(translation, ())
    else:
        # the discrete state the event iteration settles in at these values, from the
        # state the model starts in
        evaluator = evaluator_for(translation)
        start = initialize(translation, evaluator, t).outcome
        values = {**start.values, **given}
        key, _, system, _, _ = _settled(translation, t, values, start.discrete, start.relations)
    values = dict(given)
    if system is not None:
        missing = [s for s in system.states if s not in given]
        if missing:
            raise SettingError(f"the operating point misses the state{'s' if len(missing) > 1 else ''} "
                               f"{', '.join(missing)} of {translation.flat.name} in "
                               f"{translation.describe(key)}",
                               hint="give a value for every state: " + ", ".join(system.states))
        computed = mode_values(system, t, [given[s] for s in system.states])
        values = {**computed, **given}
    return _Point(t, key, values, system)


def _compiled_or_none(translation: Translation, key: tuple):
    """The compiled system of ``key``, or None where the model alone cannot be solved (an
    input that nothing computes)."""
    try:
        return translation.system(key)
    except StructuralError:
        return None


def _ordered_states(dae: _StateDAE, system) -> list[int]:
    """Positions of the DAE's states in the order of the compiled system's (same set) or their own."""
    if system is not None and set(system.states) == set(dae.states):
        where = {s: k for k, s in enumerate(dae.states)}
        return [where[s] for s in system.states]
    return list(range(len(dae.states)))


def _evaluate(dae: _StateDAE, point: _Point, start_values: Mapping[str, float]):
    """``(x, z, u, held)`` at ``point``, the unknowns made consistent with the states."""
    values = point.values

    def value(name: str) -> float:
        found = values.get(name)
        if found is None:
            found = start_values.get(name, 0.0)
        return float(found)

    missing_inputs = [u for u in dae.inputs if u not in values]
    if missing_inputs:
        raise SettingError(f"the operating point has no value for the input "
                           f"{', '.join(missing_inputs)}", hint="add it to the mapping given as at=")
    x = np.array([value(s) for s in dae.states])
    u = np.array([value(n) for n in dae.inputs])
    held = np.array([value(n) for n in dae.held])
    z = np.array([value(n) for n in dae.unknowns])
    z = dae.consistent_unknowns(point.t, x, z, u, held)
    return x, z, u, held


# ---------------------------------------------------------------------------
# linearize
# ---------------------------------------------------------------------------


def linearize(model_or_translation: Component | Translation, at: float | Mapping[str, float] = None,
              inputs: Sequence[str] = (), outputs: Sequence[str] = (), *,
              t: float | None = None, discrete: tuple | str | None = None,
              parameters: Mapping[str, float] | None = None) -> Linearization:
    """Linearize a model in the discrete state active at an operating point.

    Parameters
    ----------
    model_or_translation : Model instance or Translation
    at : float or mapping
        A time: the model is simulated with its experiment up to that time
        (``simulate(..., stop_time=at)``) and linearized at the states and the
        discrete state reached (its right limit, when an event happens
        exactly there).  Or an operating point: a mapping of the states'
        values (and of the inputs', for inputs that nothing in the model
        computes; other variables are computed).  Default: the start time.
    inputs : sequence of str
        Variables to make the inputs ``u``.  An input is a variable whose
        value the model computes from time and parameters alone: the output
        ``y`` of a source block, a variable connected to one (the input
        ``tau`` of the actuator it drives), or a top-level input.  The
        equation that gives it its value (the source's, or the connection to
        it) is removed and the variable becomes a free signal; its value at
        the operating point is ``u0``.  A variable that depends on the states
        cannot be an input (:class:`~acausal.errors.SettingError` names it),
        nor one whose derivative index reduction would need.
    outputs : sequence of str
        Variables ``y`` (any continuous variable, an alias, a derivative
        ``der(x)`` or an input).
    t : float, optional
        The time of an operating point given as a mapping (default: the
        experiment's start time).
    discrete : tuple or str, optional
        The discrete state of an operating point given as a mapping: its key,
        or its description (the engine's or by modes) among the states
        compiled so far.  Default: the state the event iteration settles in
        at the point, starting from the model's initial discrete state.
    parameters : mapping, optional
        New parameter values by dotted name (with a model, not a translation).

    Returns
    -------
    Linearization
        ``A, B, C, D`` with the names, the operating point and the discrete
        state it belongs to.

    Notes
    -----
    The matrices are exact: the Jacobians of the discrete state's equations
    after alias elimination and index reduction are differentiated
    symbolically and evaluated at the point, and ``A = f_x - f_z g_z^{-1}
    g_x`` is formed by one linear solve with the Jacobian of the equations
    with respect to all unknowns (see the module docstring).  The states are
    those the engine integrates in that discrete state, in the order of its
    compiled system; a discrete Real (held between events) is a constant.

    References
    ----------
    .. [1] K. E. Brenan, S. L. Campbell and L. R. Petzold, *Numerical Solution
       of Initial-Value Problems in Differential-Algebraic Equations*, SIAM,
       1996, ch. 2.
    .. [2] Dassault Systèmes, *Dymola User Manual* vol. 1, "linearizeModel";
       OpenModelica User's Guide, "Linearization".

    Examples
    --------
    >>> lin = linearize(DriveModel(), at=0.5, inputs=["source.y"], outputs=["load.w"])  # doctest: +SKIP
    >>> lin.A, lin.discrete_state                                                      # doctest: +SKIP
    """
    translation = _translation_of(model_or_translation, parameters)
    inputs, outputs = tuple(inputs), tuple(outputs)
    for what, names in (("inputs", inputs), ("outputs", outputs)):
        if isinstance(names, str) or any(not isinstance(n, str) for n in names):
            raise SettingError(f"{what} takes a sequence of variable names")
    if at is None:
        at = _start_time(translation)
    if isinstance(at, Mapping):
        point = _point_given(translation, at, t, discrete)
    else:
        if discrete is not None or t is not None:
            raise SettingError("t= and discrete= describe an operating point given as a mapping; with "
                               "at= a time, the simulation finds both")
        try:
            point = _point_at_time(translation, float(at))
        except StructuralError as exc:
            variables = translation.flat.variable_map
            top_level = [n for n in inputs if n in variables and variables[n].causality == "input"
                         and not variables[n].component]
            if not top_level:
                raise
            raise SettingError(f"{translation.flat.name} cannot be simulated to t = {float(at):g} with "
                               f"{', '.join(top_level)} unset: {exc.message}",
                               hint="linearize at an operating point: at={state: value, ..., "
                                    f"{top_level[0]!r}: value}}") from exc
    dae = _StateDAE(translation, point.key, inputs, outputs)
    starts = {n: v.start for n, v in dae.aliases.variables.items()}
    x, z, u, held = _evaluate(dae, point, starts)
    A, B, C, D = dae.linear(point.t, x, z, u, held)
    y0 = dae.output_values(point.t, x, z, u, held)
    order = _ordered_states(dae, point.system)
    A = A[np.ix_(order, order)]
    B = B[order, :]
    C = C[:, order]
    return Linearization(A, B, C, D, tuple(dae.states[k] for k in order), inputs, outputs,
                         x[order], u, y0, point.t, point.key, StateNamer(translation)(point.key),
                         translation.describe(point.key))


# ---------------------------------------------------------------------------
# steady_state
# ---------------------------------------------------------------------------


def steady_state(model_or_translation: Component | Translation, *, guess: Mapping[str, float] | None = None,
                 t: float = 0.0, discrete: tuple | str | None = None, free: Sequence[str] = (),
                 parameters: Mapping[str, float] | None = None, tol: float = 1e-10) -> SteadyState:
    """Solve ``der(x) = 0`` for the states, in the discrete state consistent with the solution.

    Parameters
    ----------
    model_or_translation : Model instance or Translation
    guess : mapping, optional
        Start values of states (by name); the others start from the model's
        initial values at ``t``.
    t : float
        The time (sources are evaluated there).
    discrete : tuple or str, optional
        The discrete state to start from (key or description); default: the
        one the model is initialized in at ``t``.
    free : sequence of str
        States held at their guess and not solved for.  States that no
        derivative depends on (an angle that integrates a speed) are held
        anyway: the equilibrium is then one of uniform motion, ``der(phi) =
        w*`` (reported in :attr:`SteadyState.derivatives`).
    parameters : mapping, optional
        New parameter values by dotted name (with a model, not a translation).
    tol : float
        The largest accepted norm of the solved derivatives, relative to
        ``1 + max |x|``.

    Returns
    -------
    SteadyState

    Raises
    ------
    SolverError
        If no steady state is found in a discrete state, or the discrete
        state keeps changing.

    Notes
    -----
    Each round solves the discrete state's ``der(x) = 0`` with MINPACK's
    hybrid method (``scipy.optimize.root``, ``'hybr'``) on the compiled
    derivatives, with the exact Jacobian of :func:`linearize`; then the
    runtime's event iteration re-evaluates the relations and discrete
    equations at the solution.  When the discrete state it settles in
    differs (a load above a static limit starts a slip), the next round
    solves in that state.  At most :data:`MAX_ROUNDS` rounds; a state
    visited twice means no consistent steady state (the error names them).

    References
    ----------
    .. [1] J. J. Moré, B. S. Garbow and K. E. Hillstrom, *User Guide for
       MINPACK-1*, Argonne National Laboratory report ANL-80-74, 1980.
    .. [2] M. Otter, H. Elmqvist and S. E. Mattsson, "Hybrid modeling in
       Modelica based on the synchronous data flow principle", CACSD'99, 1999
       (the event iteration that decides the discrete state).
    """
    from scipy.optimize import root  # only here: the tools layer stays light to import

    translation = _translation_of(model_or_translation, parameters)
    evaluator = evaluator_for(translation)
    t = float(t)
    start = initialize(translation, evaluator, t).outcome
    values = dict(start.values)
    discrete_values, relations = dict(start.discrete), tuple(start.relations)
    key = evaluator.key(discrete_values, discrete_values, relations, False)
    if discrete is not None:
        key = _resolve_discrete(translation, discrete)
        discrete_values = _discrete_of_key(translation, key, discrete_values)
    guess = {str(n): float(v) for n, v in (guess or {}).items()}
    values.update(guess)
    unknown = [n for n in (*guess, *free) if n not in translation.continuous]
    if unknown:
        raise SettingError(f"{translation.flat.name} has no continuous variable {unknown[0]!r}")
    namer = StateNamer(translation)
    seen: list[tuple] = []
    for round_ in range(1, MAX_ROUNDS + 1):
        seen.append(key)
        system = translation.system(key)
        states = list(system.states)
        dae = _StateDAE(translation, key, (), ())
        held_free = [s for s in states if s in set(free) or s in dae.structural_free]
        solved = [k for k, s in enumerate(states) if s not in held_free]
        x_full = np.array([values.get(s, 0.0) for s in states], dtype=float)

        def residual(x_solved, x_full=x_full, system=system, solved=solved):
            x = x_full.copy()
            x[solved] = x_solved
            return np.asarray(system.derivatives(t, x), dtype=float)[solved]

        jacobian = _exact_jacobian(dae, system, t, x_full, solved, held_free, values)
        x_solved = x_full[solved]
        if solved:
            found = root(residual, x_solved, jac=jacobian, method="hybr",
                         options={"xtol": 1e-14, "maxfev": 2000})
            x_solved = found.x
            norm = float(np.linalg.norm(residual(x_solved)))
            if not np.isfinite(norm) or norm > tol * (1.0 + float(np.max(np.abs(x_solved)))):
                raise SolverError(
                    f"no steady state of {translation.flat.name} found in [{namer(key)}]: the derivatives "
                    f"of {', '.join(states[k] for k in solved)} stay at norm {norm:.3g} ({found.message})",
                    hint="the states may grow without bound (name them in free=), or give a better "
                         "guess=; a steady state must exist in the discrete state reached")
        else:
            norm = 0.0
        x_full = x_full.copy()
        x_full[solved] = x_solved
        point_values = mode_values(system, t, x_full)
        new_key, new_values, _, new_discrete, new_relations = _settled(
            translation, t, point_values, discrete_values, relations)
        if new_key == key:
            derivatives = dict(zip(states, map(float, system.derivatives(t, x_full))))
            return SteadyState(dict(zip(states, map(float, x_full))),
                               {der_name(s): derivatives[s] for s in states}, norm, tuple(held_free),
                               point_values, t, key, namer(key), translation.describe(key), round_)
        if new_key in seen:
            names = " -> ".join(namer(k) for k in (*seen[seen.index(new_key):], new_key))
            raise SolverError(f"no consistent steady state of {translation.flat.name}: the discrete state "
                              f"alternates ({names})",
                              hint="the equilibrium may lie exactly on a switching condition; try "
                                   "another guess= or parameter values")
        key, values, discrete_values, relations = new_key, {**new_values, **{
            s: v for s, v in zip(states, x_full) if s not in new_values}}, new_discrete, new_relations
    raise SolverError(f"no consistent steady state of {translation.flat.name} after {MAX_ROUNDS} discrete "
                      f"states: {' -> '.join(namer(k) for k in seen)}",
                      hint="give discrete= or a guess= near the steady state")


def _discrete_of_key(translation: Translation, key: tuple, defaults: Mapping) -> dict:
    """Discrete values that select ``key`` (its pre() values where the key holds only those)."""
    out = dict(defaults)
    for symbol, value in zip(translation.selectors, key):
        name = parse(symbol.name)
        if name.kind == "pre" and name.base in out:
            out[name.base] = value
        elif symbol.name in out:
            out[symbol.name] = value
    return out


def _exact_jacobian(dae: _StateDAE, system, t: float, x_full: np.ndarray, solved: list[int],
                    held_free: list[str], values: Mapping[str, float]):
    """``jac(x_solved)`` for :func:`scipy.optimize.root` from the symbolic linearization, or None
    where the DAE's states are not the compiled system's."""
    states = list(system.states)
    if set(states) != set(dae.states) or dae.held:
        return None
    where = [dae.states.index(s) for s in states]
    starts = {n: v.start for n, v in dae.aliases.variables.items()}

    def jacobian(x_solved):
        x = x_full.copy()
        x[solved] = x_solved
        point_values = mode_values(system, t, x)
        point = _Point(t, dae.key, point_values, system)
        xd, z, u, held = _evaluate(dae, point, starts)
        A, _, _, _ = dae.linear(t, xd, z, u, held)
        A = A[np.ix_(where, where)]
        return A[np.ix_(solved, solved)]

    return jacobian
