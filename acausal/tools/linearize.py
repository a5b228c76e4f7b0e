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
state found by the runtime's event iteration at the solution, and checks
that the result is one: every derivative at rest, the discrete state the one
the event iteration reproduces there, the states no equation determines
named.

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
import html
import math
import warnings
from dataclasses import dataclass, field
from typing import Any, Mapping, Sequence

import networkx as nx
import numpy as np
import sympy as sp

from ..compiler.alias import eliminate_aliases
from ..compiler.codegen import compile_functions
from ..compiler.structure import StructureMemo, analyse
from ..compiler.translate import Translation, translate
from ..errors import InitializationError, SettingError, SimulationError, SolverError, StructuralError
from ..language import Component, real_symbol, time as time_symbol
from ..names import der_name, is_derivative, parse
from ..runtime.events import evaluator_for, mode_values
from ..runtime.initialization import initialize, start_guess
from ..runtime.simulate import simulate
from .report_html import StateNamer

__all__ = ["Linearization", "SteadyState", "UndeterminedStateWarning", "linearize", "steady_state"]

#: Newton iterations that make the unknowns consistent with the states at an operating point.
_NEWTON_ITERATIONS = 30

#: Relative tolerance of those unknowns (of the residuals, relative to the largest value).  The
#: matrices are exact up to it and to the round-off of one linear solve, so an entry below it
#: relative to the largest entry of its matrix is printed as 0 (the arrays keep it).
CONSISTENCY_TOL = 1e-12

#: An eigenvalue within this of zero, relative to the largest entry of ``A``, is printed as 0:
#: a multiple eigenvalue is only accurate to about the square root of the machine epsilon.
EIGENVALUE_TOL = 1e-8

#: The relative accuracy taken for values a steady state keeps at their guess: such guesses are
#: mostly a simulation's values, accurate to its tolerance (simulate's default rtol).  Whether
#: they belong to the discrete state is judged with relation margins of this size, and a kept
#: value below it is printed as 0 (a stuck speed of -1.000011e-10).
GUESS_RTOL = 1e-6

#: Rows and columns of a matrix (rows of a state table) a repr shows before it elides the rest.
_SHOWN = 12

#: Rounds of "solve, then event iteration" before :func:`steady_state` gives up.
MAX_ROUNDS = 8


# ---------------------------------------------------------------------------
# Results
# ---------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class Linearization:
    """The linear model of one discrete state at an operating point.

    ``der(x) ≈ A (x - x0) + B (u - u0)`` and ``y ≈ y0 + C (x - x0) + D (u - u0)``.

    ``repr()`` is a short summary (model, discrete state, time, sizes,
    eigenvalues); in a notebook the matrices show as tables with the names
    (:meth:`_repr_html_`); ``str()`` prints them as text.  What is printed
    shows an entry below :data:`CONSISTENCY_TOL` times the largest of its
    matrix as 0 (round-off of the linear solve: a ``-0.`` or ``1e-17``); the
    arrays keep their values.

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
    model : str
        The name of the model.
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
    model: str = ""

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

    # -- display -----------------------------------------------------------------

    def _heading(self) -> str:
        model = f" of {self.model}" if self.model else ""
        return f"Linearization{model} at t = {_number(self.t)} in [{self.discrete_state or 'no discrete state'}]"

    def _sizes(self) -> str:
        n, m, p = len(self.state_names), len(self.input_names), len(self.output_names)
        return (f"{_count(n, 'state')}, {_count(m, 'input')}, {_count(p, 'output')}: "
                f"A {n}x{n}, B {n}x{m}, C {p}x{n}, D {p}x{m}")

    def _eigenvalue_text(self, limit: int = 8) -> str:
        values = self.eigenvalues
        if not values.size:
            return "none"
        zero = EIGENVALUE_TOL * max(1.0, float(np.max(np.abs(self.A))))
        texts = _complex_texts(values, zero)
        shown = ", ".join(texts[:limit])
        return shown + (f", ... ({len(texts) - limit} more)" if len(texts) > limit else "")

    def __repr__(self) -> str:
        return f"{self._heading()}\n  {self._sizes()}\n  eigenvalues: {self._eigenvalue_text()}"

    def __str__(self) -> str:
        with np.printoptions(precision=6, suppress=True, linewidth=120):
            matrices = "\n".join(f"{name} =\n{_printed(matrix, _matrix_zero(matrix))}"
                                 for name, matrix in zip("ABCD", (self.A, self.B, self.C, self.D)))
            return (f"{self._heading()}\n"
                    f"  states  {', '.join(self.state_names)}\n"
                    f"  inputs  {', '.join(self.input_names) or '-'}\n"
                    f"  outputs {', '.join(self.output_names) or '-'}\n"
                    f"  eigenvalues {self._eigenvalue_text(limit=len(self.state_names))}\n"
                    f"{matrices}")

    def _repr_html_(self) -> str:
        """The summary and ``A, B, C, D`` as tables with the state, input and output names."""
        states, inputs, outputs = self.state_names, self.input_names, self.output_names
        tables = [_html_matrix("A", self.A, states, states), _html_matrix("B", self.B, states, inputs),
                  _html_matrix("C", self.C, outputs, states), _html_matrix("D", self.D, outputs, inputs)]
        return (f"<div><p><b>{html.escape(self._heading())}</b><br>{html.escape(self._sizes())}<br>"
                f"eigenvalues: {html.escape(self._eigenvalue_text())}</p>"
                f"<div style=\"display:flex;flex-wrap:wrap;gap:1.5em;align-items:flex-start\">"
                f"{''.join(tables)}</div></div>")


@dataclass(frozen=True, eq=False)
class SteadyState:
    """A steady state: ``der(x) = 0`` for the states at rest, in a consistent discrete state.

    ``repr()`` lists the discrete state and every state with its value and
    ``der(x)``; in a notebook the same is a table (:meth:`_repr_html_`).  A
    number below :attr:`tolerance` is printed as 0; the dicts keep their
    values.

    Attributes
    ----------
    states : dict
        Every state of the discrete state's system at the solution.
    derivatives : dict
        ``der(x)`` of every state there (keys ``der(name)``): at most
        :attr:`tolerance` for the states at rest; the states in :attr:`free`
        that are not :attr:`undetermined` may move at a constant rate.
    residual : float
        The largest ``|der(x)|`` of the states at rest (0 when there are none).
    free : tuple of str
        The states held and not solved for: those asked for with ``free=``,
        those that integrate states at rest and that no derivative depends
        on (an angle of a speed: uniform motion), and the
        :attr:`undetermined` ones.
    values : dict
        Every continuous variable at the solution (aliases included).
    t : float
    discrete_key : tuple
    discrete_state : str
        The discrete state named by its modes, as ``acausal explain`` names
        it (e.g. ``bearing: Stuck (locked)``).
    discrete_description : str
        The engine's description of it.
    rounds : int
        Discrete states tried (1: the first was consistent).
    undetermined : tuple of str
        States that no equation of the discrete state determines at rest
        (the speed of a stuck friction element: its derivative is 0 whatever
        its value): kept at the guess, or at the value the model starts
        with.  :func:`steady_state` warns about them
        (:class:`UndeterminedStateWarning`).  Their derivatives are at rest.
    residuals : dict
        ``|der(x)|`` of each state at rest, by state name.
    discrete_values : dict
        The discrete variables (modes, Booleans, discrete Reals) in the
        discrete state, as the event iteration at the solution leaves them.
    tolerance : float
        The largest ``|der(x)|`` accepted at rest: ``tol * (1 + max |x|)``
        over the states at rest.
    model : str
        The name of the model.
    units : dict
        The unit of each state ('' where none).
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
    undetermined: tuple[str, ...] = ()
    residuals: dict = field(default_factory=dict)
    discrete_values: dict = field(default_factory=dict, repr=False)
    tolerance: float = 0.0
    model: str = ""
    units: dict = field(default_factory=dict, repr=False)

    def __getitem__(self, name: str) -> float:
        """The value of variable ``name`` at the steady state."""
        return self.values[name]

    @property
    def moving(self) -> tuple[str, ...]:
        """The held states that move at a constant rate: ``|der(x)|`` above :attr:`tolerance`
        and :data:`GUESS_RTOL` (the rate of an angle is a speed, perhaps a guessed one)."""
        return tuple(s for s in self.free if s not in self.undetermined
                     and abs(self.derivatives[der_name(s)]) > self._kept_zero)

    @property
    def _kept_zero(self) -> float:
        """Below this a value kept at its guess, or the rate of a held state, is printed as 0."""
        return max(self.tolerance, GUESS_RTOL)

    # -- display -----------------------------------------------------------------

    def _heading(self) -> str:
        model = f" of {self.model}" if self.model else ""
        rounds = f" (after {_count(self.rounds, 'discrete state')} tried)" if self.rounds > 1 else ""
        return (f"SteadyState{model} at t = {_number(self.t)} in "
                f"[{self.discrete_state or 'no discrete state'}]{rounds}")

    def _rows(self) -> list[tuple[str, str, str, str, str]]:
        """``(state, value, unit, der(x), note)`` for each state, numbers below the tolerance as 0:
        the solved states' values and derivatives below :attr:`tolerance`, the held states' below
        :data:`GUESS_RTOL` too (kept values, and rates that are such values)."""
        rows = []
        for name, value in self.states.items():
            if name in self.undetermined:
                note = "undetermined: kept as it was"
            elif name in self.moving:
                note = "free: moves at a constant rate"
            elif name in self.free:
                note = "free"
            else:
                note = ""
            zero = self._kept_zero if name in self.free else self.tolerance
            rows.append((name, _number(value, zero), self.units.get(name, ""),
                         _number(self.derivatives[der_name(name)], zero), note))
        return rows

    def _footer(self) -> str:
        return f"max |der(x)| at rest = {_number(self.residual, self.tolerance)} (tolerance {self.tolerance:.3g})"

    def __repr__(self) -> str:
        rows = self._rows()
        shown = rows[:_SHOWN]
        header = ("state", "value", "unit", "der(x)", "")
        widths = [max(len(r[k]) for r in (header, *shown)) for k in range(4)]
        lines = [self._heading()]
        for row in (header, *shown):
            cells = [row[0].ljust(widths[0]), row[1].rjust(widths[1]), row[2].ljust(widths[2]),
                     row[3].rjust(widths[3]), row[4]]
            lines.append("  " + "  ".join(cells).rstrip())
        if len(rows) > len(shown):
            lines.append(f"  ... ({len(rows) - len(shown)} more states)")
        lines.append("  " + self._footer())
        return "\n".join(lines)

    def _repr_html_(self) -> str:
        """The discrete state and a table of the states: value, unit, ``der(x)``, and what is held."""
        rows = self._rows()
        body = "".join(
            "<tr>" + "".join(f"<td style=\"text-align:{align}\">{html.escape(cell)}</td>"
                             for cell, align in zip(row, ("left", "right", "left", "right", "left"))) + "</tr>"
            for row in rows[:_SHOWN])
        more = (f"<tr><td colspan=\"5\">... {len(rows) - _SHOWN} more states</td></tr>"
                if len(rows) > _SHOWN else "")
        return (f"<div><p><b>{html.escape(self._heading())}</b></p>"
                f"<table><thead><tr><th>state</th><th>value</th><th>unit</th><th>der(x)</th><th></th></tr>"
                f"</thead><tbody>{body}{more}</tbody></table>"
                f"<p>{html.escape(self._footer())}</p></div>")


class UndeterminedStateWarning(UserWarning):
    """A steady state left states at their guess: no equation of its discrete state determines them.

    The states are listed in :attr:`SteadyState.undetermined`.
    """


# -- printing ---------------------------------------------------------------------


def _number(value: float, zero: float = 0.0, digits: int = 6) -> str:
    """``value`` to ``digits`` significant digits; ``0`` where ``|value| <= zero`` (a ``-0.`` too)."""
    value = float(value)
    if abs(value) <= zero:
        return "0"
    return f"{value:.{digits}g}"


def _count(n: int, noun: str) -> str:
    """``1 state``, ``2 states``."""
    return f"{n} {noun}" if n == 1 else f"{n} {noun}s"


def _matrix_zero(matrix: np.ndarray) -> float:
    """The magnitude below which an entry of ``matrix`` is printed as 0."""
    return CONSISTENCY_TOL * float(np.max(np.abs(matrix))) if matrix.size else 0.0


def _printed(matrix: np.ndarray, zero: float) -> np.ndarray:
    """A copy of ``matrix`` for printing: entries with ``|x| <= zero`` made +0.0 (no ``-0.``)."""
    return np.where(np.abs(matrix) <= zero, 0.0, matrix)


def _complex_texts(values: np.ndarray, zero: float) -> list[str]:
    """Eigenvalues as text to 4 digits, parts below ``zero`` as 0, each conjugate pair as ``a±bj``."""
    texts, k = [], 0
    values = list(values)
    while k < len(values):
        v = values[k]
        re_, im = (0.0 if abs(v.real) <= zero else v.real), (0.0 if abs(v.imag) <= zero else v.imag)
        if im == 0.0:
            texts.append(_number(re_, zero, 4))
            k += 1
            continue
        pair = k + 1 < len(values) and abs(values[k + 1] - np.conj(v)) <= max(zero, 1e-12 * abs(v))
        sign = "±" if pair else ("+" if im > 0 else "-")
        texts.append(f"{_number(re_, zero, 4)}{sign}{abs(im):.4g}j" if re_ else
                     f"{'±' if pair else ('' if im > 0 else '-')}{abs(im):.4g}j")
        k += 2 if pair else 1
    return texts


def _html_matrix(name: str, matrix: np.ndarray, rows: Sequence[str], columns: Sequence[str]) -> str:
    """``matrix`` as a small HTML table headed by ``name``, the names as row and column headers."""
    zero = _matrix_zero(matrix)
    shown_rows, shown_columns = min(len(rows), _SHOWN), min(len(columns), _SHOWN)
    head = "".join(f"<th>{html.escape(c)}</th>" for c in columns[:shown_columns])
    if len(columns) > shown_columns:
        head += f"<th>... {len(columns) - shown_columns} more</th>"
    body = []
    for i in range(shown_rows):
        cells = "".join(f"<td style=\"text-align:right\">{_number(matrix[i, j], zero)}</td>"
                        for j in range(shown_columns))
        if len(columns) > shown_columns:
            cells += "<td></td>"
        body.append(f"<tr><th style=\"text-align:left\">{html.escape(rows[i])}</th>{cells}</tr>")
    if len(rows) > shown_rows:
        body.append(f"<tr><td colspan=\"{shown_columns + 1}\">... {len(rows) - shown_rows} more rows</td></tr>")
    if not matrix.size:
        body.append(f"<tr><td>(empty: {matrix.shape[0]}x{matrix.shape[1]})</td></tr>")
    return (f"<table><caption style=\"text-align:left\"><b>{name}</b></caption>"
            f"<thead><tr><th></th>{head}</tr></thead><tbody>{''.join(body)}</tbody></table>")


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
        #: for each state, the states whose derivative depends on it (structurally)
        self.reaches = self._derivatives_reached()
        #: the states no derivative depends on (an angle that only integrates a speed)
        self.structural_free = frozenset(s for s, reached in self.reaches.items() if not reached)
        #: those of them whose derivative is a linear combination of the other states: they may
        #: move at a constant rate in a steady state (an angle, a position), the others may not
        self.integrators = self._integrators()

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

    def _derivatives_reached(self) -> dict[str, frozenset[str]]:
        """For each state ``s``, the states whose derivative depends on ``s``.

        Each equation computes the unknown it is matched to from the other
        variables it contains; a state reaches a derivative through that graph
        or not at all.  The pattern is structural: a derivative that depends on
        a state only through a term that vanishes at some point still counts
        (a quadratic load at rest), one whose equations do not contain the
        state does not (the speed of a stuck friction element: ``der(w) = 0``).
        """
        graph = self._dependency_graph()
        state_of = {der_name(s): s for s in self.states}
        return {s: frozenset(state_of[n] for n in nx.descendants(graph, s) if n in state_of)
                for s in self.states}

    def _dependency_graph(self) -> nx.DiGraph:
        """Edges from each variable to the unknowns computed from it (by their matched equations)."""
        structure = self.structure
        graph = nx.DiGraph()
        graph.add_nodes_from(structure.states)
        graph.add_nodes_from(structure.unknowns)
        for i, eq in enumerate(structure.equations):
            solved = structure.unknowns[structure.matching[i]]
            for symbol in eq.residual.free_symbols:
                if symbol.name != solved and symbol.name in graph:
                    graph.add_edge(symbol.name, solved)
        return graph

    def _relation_inputs(self) -> set[str]:
        """The states some relation of the model depends on in this discrete state."""
        graph = self._dependency_graph()
        aliases = self.aliases.aliases
        read: set[str] = set()
        for relation in self.translation.partitioned.relations:
            for symbol in sp.sympify(relation.lhs - relation.rhs).free_symbols:
                found = aliases.get(symbol.name)
                names = {v.name for v in sp.sympify(found).free_symbols} if found is not None else {symbol.name}
                read |= {n for n in names if n in graph}
        return {s for s in self.states if s in read or not read.isdisjoint(nx.descendants(graph, s))}

    def _integrators(self) -> frozenset[str]:
        """The states no derivative depends on whose derivative integrates other states.

        ``der(s)`` must follow from states that some derivative depends on
        through a chain of the matched equations, each linear and homogeneous
        in its variables with constant coefficients (``der(phi) = w``,
        ``der(J2.phi) = J1.w + spring.w_rel``), and where the units are known,
        each of those states must have the unit of ``der(s)`` (a speed for an
        angle, a velocity for a position).  Then ``s`` moves at a constant
        rate while those states are at rest, which is how a steady state holds
        an angle or a position.  A state whose derivative is anything else is
        not an integrator: at a steady state it must be at rest like the
        others (a housing temperature heated by ``tau*w`` with no way for the
        heat out, even where ``tau`` is a constant and ``der(T) = tau*w/C``
        is linear: ``K/s`` is no speed).  Nor is a state a relation depends
        on: moving, it would change the discrete state in finite time (a
        spring stretched by a drive until the mass it pulls breaks away).
        """
        structure = self.structure
        equation_of = {structure.unknowns[structure.matching[i]]: eq.residual
                       for i, eq in enumerate(structure.equations)}
        states = set(self.states)
        at_rest = states - self.structural_free
        variables = states | set(structure.unknowns) | set(self.held) | set(self.inputs)

        def sources(unknown: str, visiting: frozenset) -> frozenset[str] | None:
            """The states ``unknown`` is a linear combination of, or None where it is not one."""
            if unknown in visiting:
                return frozenset()  # a loop of linear equations: its other members judge it
            residual = equation_of.get(unknown)
            if residual is None or time_symbol in residual.free_symbols:
                return None
            symbols = {v for v in residual.free_symbols if v.name in variables}
            if not _homogeneous_linear(residual, symbols):
                return None
            found: set[str] = set()
            for v in symbols:
                if v.name in states:
                    if v.name not in at_rest:
                        return None
                    found.add(v.name)
                elif v.name != unknown:
                    inner = sources(v.name, visiting | {unknown})
                    if inner is None:
                        return None
                    found |= inner
            return frozenset(found)

        variables_of = self.translation.flat.variable_map
        watched = self._relation_inputs()
        out = set()
        for s in self.structural_free - watched:
            integrated = sources(der_name(s), frozenset())
            if integrated is not None and all(_rate_of(_unit_of(variables_of, s), _unit_of(variables_of, v))
                                              for v in integrated):
                out.add(s)
        return frozenset(out)

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
            if not residual.size or np.max(np.abs(residual)) <= CONSISTENCY_TOL * scale:
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


def _unit_of(variables: Mapping, name: str):
    """The parsed unit of variable ``name``, or None where it has none (or one not understood)."""
    from ..compiler.units import parse_unit

    found = variables.get(name)
    try:
        return parse_unit(getattr(found, "unit", "") or "")
    except ValueError:
        return None


def _rate_of(position, rate) -> bool:
    """Whether a quantity of unit ``rate`` is a rate of change of one of unit ``position`` (True
    where a unit is unknown: the structure alone decides then)."""
    from ..compiler.units import SECOND

    return position is None or rate is None or rate.same_as(position / SECOND)


def _homogeneous_linear(expr: sp.Expr, symbols: set) -> bool:
    """Whether ``expr`` is ``sum(c_i * v_i)`` over ``symbols`` with coefficients free of them."""
    expanded = sp.expand(expr)
    for symbol in symbols:
        if sp.diff(expanded, symbol).free_symbols & symbols:
            return False
    return sp.expand(expanded.xreplace({symbol: 0 for symbol in symbols})) == 0


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
                         translation.describe(point.key), translation.flat.name)


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
        States held at their guess, not solved for and free to move: their
        derivatives need not vanish.  A state that no derivative depends on
        and whose derivative integrates states at rest (an angle of a speed,
        a position of a velocity) is held anyway: the equilibrium is then one
        of uniform motion, ``der(phi) = w*`` (reported in
        :attr:`SteadyState.derivatives`).  Any other state no derivative
        depends on (the temperature of a housing with no heat path out) must
        be at rest like the rest, and is undetermined.
    parameters : mapping, optional
        New parameter values by dotted name (with a model, not a translation).
    tol : float
        The largest accepted ``|der(x)|`` of every state at rest, relative
        to ``1 + max |x|`` over those states.

    Returns
    -------
    SteadyState

    Raises
    ------
    SolverError
        If no steady state is found in a discrete state (a derivative of a
        state at rest stays above the tolerance, whether the solve did not
        converge or nothing can balance it), or the discrete state keeps
        changing.
    InitializationError
        If the solution is not consistent with its discrete state: states
        that no equation of it determines were kept at their guess, and at
        those values the model's own initialization chooses another discrete
        state (a friction element "stuck" while its speed is not 0).

    Warns
    -----
    UndeterminedStateWarning
        When states are kept at their guess because no equation of the
        discrete state determines them (:attr:`SteadyState.undetermined`).

    Notes
    -----
    Each round works in one discrete state.  Its states are split
    structurally, from the matched equations of the discrete state (the
    dependency graph of :func:`linearize`): those held (``free=``, and those
    no derivative depends on whose derivative is a linear combination of
    states at rest, through linear equations: angles and positions), and
    the others, which must be at rest.  A
    maximum matching between the equations ``der(x_i) = 0`` of the states at
    rest and the states they depend on (each equation tried with its own
    state first) gives a square, structurally regular system; the states it
    leaves unmatched are determined by no equation at rest (the speed of a
    stuck friction element, whose ``der(w) = 0`` holds whatever ``w``): they
    are kept at their guess, warned about and reported in
    :attr:`SteadyState.undetermined`.  The system is solved with MINPACK's
    hybrid method (``scipy.optimize.root``, ``'hybr'``) on the compiled
    derivatives, with the exact Jacobian of :func:`linearize`; then every
    derivative of a state at rest is checked, the unmatched equations
    included (a drive without losses has ``der(w) = tau/J`` whatever ``w``).

    Then the runtime's event iteration (as :func:`~acausal.runtime.simulate.simulate`
    runs it at an event) re-evaluates the relations and discrete equations
    at the solution, from the discrete state of the round, with the
    relations' exact values at the solution as their values before.  When
    the discrete state it settles in differs (a load above a static limit
    starts a slip), the next round solves in that state.  At most
    :data:`MAX_ROUNDS` rounds; a state visited twice means no consistent
    steady state (the error names them).  A discrete state the event
    iteration reproduces must also have relation values that agree with the
    solution beyond their margins.  Where states were kept at their guess,
    the discrete state must moreover be the one the model's initialization
    chooses at the solution (from the start values of its discrete
    variables, as :func:`~acausal.runtime.initialization.initialize` does),
    since no equation of it says whether the guessed values belong to it;
    a state named in ``free=`` is not checked this way.

    References
    ----------
    .. [1] J. J. Moré, B. S. Garbow and K. E. Hillstrom, *User Guide for
       MINPACK-1*, Argonne National Laboratory report ANL-80-74, 1980.
    .. [2] M. Otter, H. Elmqvist and S. E. Mattsson, "Hybrid modeling in
       Modelica based on the synchronous data flow principle", CACSD'99, 1999
       (the event iteration that decides the discrete state).
    .. [3] I. S. Duff, "On algorithms for obtaining a maximum transversal",
       ACM Trans. Math. Software 7(3), 1981 (the matching of equations to states).

    Examples
    --------
    >>> found = steady_state(DriveModel(), guess={"rotor.w": 10.0})  # doctest: +SKIP
    >>> found["rotor.w"], found.discrete_state, found.undetermined     # doctest: +SKIP
    """
    translation = _translation_of(model_or_translation, parameters)
    evaluator = evaluator_for(translation)
    t = float(t)
    if isinstance(free, str) or any(not isinstance(n, str) for n in free):
        raise SettingError("free takes a sequence of state names")
    free = tuple(free)
    start = initialize(translation, evaluator, t).outcome
    values = dict(start.values)
    discrete_values, relations = dict(start.discrete), tuple(start.relations)
    key = evaluator.key(discrete_values, discrete_values, relations, False)
    if discrete is not None:
        key = _resolve_discrete(translation, discrete)
        discrete_values = _discrete_of_key(translation, key, discrete_values)
    guess = {str(n): float(v) for n, v in (guess or {}).items()}
    values.update(guess)
    #: where each state's current value came from, for what is said of the states kept as they are
    came_from = {n: "its guess" if n in guess else "the model's start" for n in values}
    unknown = [n for n in (*guess, *free) if n not in translation.continuous]
    if unknown:
        raise SettingError(f"{translation.flat.name} has no continuous variable {unknown[0]!r}")
    name = translation.flat.name
    namer = StateNamer(translation)
    seen: list[tuple] = []
    for round_ in range(1, MAX_ROUNDS + 1):
        seen.append(key)
        system = translation.system(key)
        states = list(system.states)
        dae = _StateDAE(translation, key, (), ())
        plan = _rest_plan(dae, states, free)
        x, message = _solve_at_rest(dae, system, plan, t, np.array([values.get(s, 0.0) for s in states],
                                                                     dtype=float))
        for k in plan.solved:
            came_from[states[k]] = f"solved in [{namer(key)}]"
        derivatives = np.asarray(system.derivatives(t, x), dtype=float)
        at_rest = plan.at_rest
        tolerance = tol * (1.0 + max((abs(float(x[k])) for k in at_rest), default=0.0))
        failure = _not_at_rest(translation, namer, key, plan, x, derivatives, tolerance, message)
        try:
            point_values = mode_values(system, t, x)
            # the relations before the event iteration: their exact values at the solution (not those
            # of the point the round started from, which the margins would otherwise favour)
            exact = evaluator.relation_values(system, t, x, relations, exact=True) if relations else ()
            new_key, new_values, _, new_discrete, new_relations = _settled(
                translation, t, point_values, discrete_values, exact)
        except (SimulationError, ArithmeticError, ValueError):
            # the event iteration may fail at a point that is no steady state (a solve gone
            # astray): then that is the news, not what the event iteration made of it
            if failure is not None:
                raise failure from None
            raise
        if failure is not None and new_key == key:
            raise failure
        # (not at rest, but in a discrete state the event iteration leaves: the next round
        # solves in the state it settles in)
        if new_key == key:
            _check_relations(translation, evaluator, namer, key, system, t, x, new_relations)
            undetermined = [states[k] for k in plan.undetermined]
            if undetermined:
                kept = {s: came_from.get(s, "the model's start") for s in undetermined}
                _check_undetermined(translation, namer, key, system, t, point_values, kept)
                warnings.warn(_undetermined_message(translation, namer, key, point_values, kept),
                              UndeterminedStateWarning, stacklevel=2)
            variables = translation.flat.variable_map
            residuals = {states[k]: abs(float(derivatives[k])) for k in at_rest}
            return SteadyState(
                dict(zip(states, map(float, x))), {der_name(s): float(d) for s, d in zip(states, derivatives)},
                max(residuals.values(), default=0.0),
                tuple(s for k, s in enumerate(states) if k not in plan.solved),
                point_values, t, key, namer(key), translation.describe(key), round_,
                undetermined=tuple(undetermined), residuals=residuals, discrete_values=dict(new_discrete),
                tolerance=tolerance, model=name,
                units={s: (getattr(variables.get(s), "unit", "") or "") for s in states})
        if new_key in seen:
            names = " -> ".join(namer(k) for k in (*seen[seen.index(new_key):], new_key))
            raise SolverError(f"no consistent steady state of {name}: the discrete state alternates ({names})",
                              hint="the equilibrium may lie exactly on a switching condition; try "
                                   "another guess= or parameter values")
        key, values, discrete_values, relations = new_key, {**new_values, **{
            s: v for s, v in zip(states, x) if s not in new_values}}, new_discrete, new_relations
    raise SolverError(f"no consistent steady state of {name} after {MAX_ROUNDS} discrete "
                      f"states: {' -> '.join(namer(k) for k in seen)}",
                      hint="give discrete= or a guess= near the steady state")


@dataclass(frozen=True)
class _RestPlan:
    """How :func:`steady_state` treats the states of one discrete state (positions in its system).

    Attributes
    ----------
    held : tuple of int
        Not solved for, and free to move: named in ``free=``, integrators
        (angles, positions: :meth:`_StateDAE._integrators`), or discrete
        Reals (held between events).
    undetermined : tuple of int
        At rest, but no equation ``der(x) = 0`` is left to determine them:
        kept as they are.
    solved : tuple of int
        The states solved for ...
    equations : tuple of int
        ... from ``der(x) = 0`` of these states (as many, matched in order).
    unbalanced : tuple of int
        States at rest whose ``der(x) = 0`` is matched to no state: it depends
        on none left to solve for, so it holds or fails as it is.
    """

    held: tuple[int, ...]
    undetermined: tuple[int, ...]
    solved: tuple[int, ...]
    equations: tuple[int, ...]
    unbalanced: tuple[int, ...]

    @property
    def at_rest(self) -> tuple[int, ...]:
        """The states whose derivatives must vanish: all but the held ones."""
        return tuple(sorted((*self.solved, *self.undetermined)))


def _rest_plan(dae: _StateDAE, states: Sequence[str], free: Sequence[str]) -> _RestPlan:
    """Which states are held, solved for (from which ``der(x) = 0``) or undetermined.

    The equations ``der(x_i) = 0`` of the states at rest are matched to the
    states they depend on structurally (:attr:`_StateDAE.reaches`), each
    equation trying its own state first, so that a state is reported
    undetermined only where its own equation does not contain it (``der(w)
    = 0`` of a stuck element) and no other equation is left for it.
    """
    position = {s: k for k, s in enumerate(states)}
    free = set(free)
    held = [s for s in states if s in free or s in dae.integrators or s in dae.held]
    candidates = [s for s in states if s not in set(held)]
    adjacency: dict[str, list[str]] = {e: [] for e in candidates}
    for s in candidates:
        # a state the DAE does not know (none expected) counts as reaching every equation
        reached = dae.reaches.get(s)
        for e in candidates:
            if reached is None or e in reached:
                adjacency[e].append(s)
    for e, around in adjacency.items():
        if e in around:  # its own state first
            around.remove(e)
            around.insert(0, e)
    owner = _maximum_matching(candidates, adjacency)
    pairs = sorted((position[e], position[s]) for s, e in owner.items())
    matched_equations = {e for e in owner.values()}
    return _RestPlan(held=tuple(position[s] for s in held),
                     undetermined=tuple(position[s] for s in candidates if s not in owner),
                     solved=tuple(s for _, s in pairs), equations=tuple(e for e, _ in pairs),
                     unbalanced=tuple(position[e] for e in candidates if e not in matched_equations))


def _maximum_matching(equations: Sequence[str], adjacency: Mapping[str, Sequence[str]]) -> dict[str, str]:
    """A maximum matching ``{state: equation}`` by augmenting paths (breadth first).

    The equations are taken in order, and each one's candidates in the order
    of ``adjacency``: an equation takes the first free state it reaches, its
    preferred one where that is free.
    """
    owner: dict[str, str] = {}     # state -> equation
    state_of: dict[str, str] = {}  # equation -> state
    for root_equation in equations:
        parent: dict[str, str] = {}  # state -> the equation that reached it
        queue = [root_equation]
        found = None
        while queue and found is None:
            equation = queue.pop(0)
            for s in adjacency[equation]:
                if s in parent:
                    continue
                parent[s] = equation
                if s not in owner:
                    found = s
                    break
                queue.append(owner[s])
        while found is not None:  # flip the path: each equation on it takes the state after it
            equation = parent[found]
            before = state_of.get(equation)
            owner[found], state_of[equation] = equation, found
            found = before
    return owner


def _solve_at_rest(dae: _StateDAE, system, plan: _RestPlan, t: float, x: np.ndarray) -> tuple[np.ndarray, str]:
    """``(x, message)``: the states of ``plan.solved`` solved from ``der(x) = 0`` of ``plan.equations``
    (MINPACK's hybrid method with the exact Jacobian), the others as given; the solver's message."""
    from scipy.optimize import root  # only here: the tools layer stays light to import

    if not plan.solved:
        return x, ""
    rows, columns = list(plan.equations), list(plan.solved)

    def residual(x_solved):
        trial = x.copy()
        trial[columns] = x_solved
        return np.asarray(system.derivatives(t, trial), dtype=float)[rows]

    found = root(residual, x[columns], jac=_exact_jacobian(dae, system, t, x, rows, columns), method="hybr",
                 options={"xtol": 1e-14, "maxfev": 2000})
    solved = x.copy()
    solved[columns] = found.x
    return solved, str(found.message)


def _rate_unit(unit: str) -> str:
    """The unit of ``der(x)`` for ``x`` in ``unit`` (``K`` -> ``K/s``, ``rad/s`` -> ``rad/s2``)."""
    if not unit or unit == "1":
        return "1/s"
    if unit.endswith("/s"):
        return unit + "2"
    return f"{unit}/s"


def _not_at_rest(translation: Translation, namer: StateNamer, key: tuple, plan: _RestPlan, x: np.ndarray,
                 derivatives: np.ndarray, tolerance: float, message: str) -> SolverError | None:
    """The :class:`SolverError` to raise unless every state at rest has ``|der(x)| <= tolerance``."""
    states = translation.system(key).states
    variables = translation.flat.variable_map
    bad = [k for k in plan.at_rest if not abs(float(derivatives[k])) <= tolerance]  # NaN fails too
    if not bad:
        return None
    bad.sort(key=lambda k: -abs(float(derivatives[k])) if np.isfinite(derivatives[k]) else -math.inf)

    def rate(k: int) -> str:
        unit = _rate_unit(getattr(variables.get(states[k]), "unit", "") or "")
        return f"{der_name(states[k])} = {float(derivatives[k]):.3g} {unit}"

    listed = ", ".join(rate(k) for k in bad[:4]) + (f" and {len(bad) - 4} more" if len(bad) > 4 else "")
    unbalanced = [states[k] for k in bad if k in plan.unbalanced]
    if unbalanced:
        hint = (f"{', '.join(der_name(s) for s in unbalanced)} depends on no state left to solve for in "
                f"this discrete state, so nothing there can bring it to zero (a drive without losses, a "
                f"storage filled with no path out); name the state in free= if it may change at a "
                f"constant rate")
    else:
        hint = ("the states may grow without bound (name them in free=), or give a better guess=; a "
                "steady state must exist in the discrete state reached")
    # the solver's word matters for the states it solved for, not for an equation it had no state for
    solver = f" (the solver: {message})" if message and any(k in plan.solved for k in bad) else ""
    return SolverError(f"no steady state of {translation.flat.name} found in [{namer(key)}]: at the point "
                       f"reached {listed} (tolerance {tolerance:.3g}){solver}", hint=hint)


def _check_relations(translation: Translation, evaluator, namer: StateNamer, key: tuple, system, t: float,
                     x: np.ndarray, relations: Sequence[bool]) -> None:
    """Raise :class:`InitializationError` where a relation's value in the discrete state contradicts
    the continuous solution: its two sides lie beyond its margin, on the other side.

    A relation within its margin (the hysteresis of event detection) may
    take either value: the equilibrium is then on a switching condition.
    """
    n = len(relations)
    if not n:
        return
    raw = system.crossings(t, x)
    exact = evaluator.relation_values(system, t, x, relations, exact=True, raw=raw)
    # decided alike from either side of the margin: the solution fixes the value
    high = evaluator.relation_values(system, t, x, (True,) * n, raw=raw)
    low = evaluator.relation_values(system, t, x, (False,) * n, raw=raw)
    wrong = [k for k in range(n) if high[k] == low[k] and raw[2 * k] != raw[2 * k + 1]
             and bool(relations[k]) != bool(exact[k])]
    if wrong:
        texts = [r.text for r in translation.partitioned.relations]
        listed = ", ".join(f"{texts[k]} is {'true' if relations[k] else 'false'} "
                           f"({raw[2 * k]:.6g} against {raw[2 * k + 1]:.6g})" for k in wrong[:4])
        raise InitializationError(
            f"the steady state of {translation.flat.name} in [{namer(key)}] is not consistent with its "
            f"discrete state: {listed}",
            hint="the discrete state's relations must hold at the solution; try another guess= or discrete=")


def _check_undetermined(translation: Translation, namer: StateNamer, key: tuple, system, t: float,
                        values: Mapping[str, float], kept: Mapping[str, str]) -> None:
    """Raise :class:`InitializationError` if the model's initialization at ``values`` chooses
    another discrete state than ``key``: the states kept at their guess do not belong to it.

    Keys that differ only in relations at their limit (within the margins of
    :data:`GUESS_RTOL`: an inertia at rest exactly at the edge of a backlash
    gap) are the same discrete state to this check: either value is right.
    ``kept`` names the states kept as they were, and where each value came from.
    """
    chosen = _chosen_from_start(translation, t, values)
    if chosen is None or chosen == key:
        return
    states = system.states
    undecided = _undecided_relations(translation, system, t, [values[s] for s in states])
    differing = [parse(symbol.name) for symbol, a, b in zip(translation.selectors, key, chosen) if a != b]
    if all(name.kind == "relation" and name.index in undecided for name in differing):
        return
    undetermined = list(kept)
    them = "it" if len(undetermined) == 1 else "them"
    point = ", ".join(f"{s} = {values[s]:.6g}" for s in states)
    raise InitializationError(
        f"the steady state of {translation.flat.name} found in [{namer(key)}] is not consistent with that "
        f"discrete state: no equation of it determines {', '.join(undetermined)}, kept at "
        f"{_kept_text(values, kept)}, and at the point found ({point}) the model's initialization "
        f"chooses [{namer(chosen)}]",
        hint=f"give guess= values of {', '.join(undetermined)} that [{namer(key)}] can hold (those the model "
             f"has when it enters that state), start from another discrete=, or name {them} in free= to "
             f"keep {them} as given without this check")


def _undecided_relations(translation: Translation, system, t: float, x) -> set[int]:
    """The relations at their limit at ``(t, x)``: decided differently from either side of a margin
    of :data:`GUESS_RTOL`, or with both sides equal."""
    relations = translation.partitioned.relations
    if not relations:
        return set()
    evaluator = evaluator_for(translation, relation_epsilon=GUESS_RTOL)
    raw = system.crossings(t, x)
    n = len(relations)
    high = evaluator.relation_values(system, t, x, (True,) * n, raw=raw)
    low = evaluator.relation_values(system, t, x, (False,) * n, raw=raw)
    return {k for k in range(n) if high[k] != low[k] or raw[2 * k] == raw[2 * k + 1]}


def _kept_text(values: Mapping[str, float], kept: Mapping[str, str]) -> str:
    """``rotor.w = 1 (its guess), housing.T = 293.15 (the model's start)``."""
    return ", ".join(f"{s} = {values[s]:.6g} ({origin})" for s, origin in kept.items())


def _undetermined_message(translation: Translation, namer: StateNamer, key: tuple, values: Mapping[str, float],
                          kept: Mapping[str, str]) -> str:
    return (f"steady state of {translation.flat.name} in [{namer(key)}]: no equation of this discrete state "
            f"determines {', '.join(kept)}; kept at {_kept_text(values, kept)} "
            f"(SteadyState.undetermined lists {'it' if len(kept) == 1 else 'them'})")


def _chosen_from_start(translation: Translation, t: float, values: Mapping[str, float]) -> tuple | None:
    """The discrete state the model's own initialization settles in at the continuous ``values``.

    The loop of :func:`~acausal.runtime.initialization.initialize` without
    its continuous solve: the discrete variables from their start values,
    ``pre()`` of the fixed ones held at their starts, the relations judged
    with no history (within the margin, ``g`` counts as 0), iterated to a
    fixed point with ``initial()`` true; then the event iteration with
    ``initial()`` false that follows initialization.  The states are those
    of ``values``; the other unknowns follow from them in each discrete
    state tried.  The relations are judged with margins of
    :data:`GUESS_RTOL` (the runtime's event iteration with that
    ``relation_epsilon``): the values judged include guesses.  None where
    that cannot be evaluated (it does not settle, a domain error, a state of
    another discrete state that ``values`` lacks).
    """
    variables = translation.flat.variable_map
    # margins of the accuracy of guessed values: a stuck speed of -1e-10 from a simulation is 0
    evaluator = evaluator_for(translation, relation_epsilon=GUESS_RTOL)
    discrete, relations = start_guess(translation)
    fixed_pre = {n: discrete[n] for n in discrete if variables[n].fixed}
    at_zero = tuple(rel.holds(0.0) for rel in translation.partitioned.relations)
    try:
        for _ in range(evaluator.max_iterations):
            pre = {**discrete, **fixed_pre}
            system = translation.system(evaluator.key(discrete, pre, relations, True))
            x = [discrete[s] if s in discrete else values[s] for s in system.states]
            new_relations = evaluator.relation_values(system, t, x, at_zero)
            evaluator.prepare(system, t, x)
            new_discrete = evaluator.evaluate_discrete(discrete, pre, new_relations, True)
            if new_discrete == discrete and new_relations == relations:
                break
            discrete, relations = new_discrete, new_relations
        else:
            return None
        evaluator.prepare(None, t, x)
        outcome = evaluator.iterate(t, {**values, **mode_values(system, t, x)}, discrete, relations,
                                    initial=False)
    except (KeyError, ArithmeticError, StructuralError, SimulationError):
        return None
    finally:
        evaluator.prepare(None, t, ())
    return evaluator.key(outcome.discrete, outcome.discrete, outcome.relations, False)


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


def _exact_jacobian(dae: _StateDAE, system, t: float, x_full: np.ndarray, rows: list[int], columns: list[int]):
    """``jac(x_solved)`` for :func:`scipy.optimize.root` from the symbolic linearization: the
    derivatives of states ``rows`` with respect to states ``columns`` (positions in the compiled
    system), or None where the DAE's states are not the compiled system's."""
    states = list(system.states)
    if set(states) != set(dae.states) or dae.held:
        return None
    where = [dae.states.index(s) for s in states]
    starts = {n: v.start for n, v in dae.aliases.variables.items()}

    def jacobian(x_solved):
        x = x_full.copy()
        x[columns] = x_solved
        point_values = mode_values(system, t, x)
        point = _Point(t, dae.key, point_values, system)
        xd, z, u, held = _evaluate(dae, point, starts)
        A, _, _, _ = dae.linear(t, xd, z, u, held)
        A = A[np.ix_(where, where)]
        return A[np.ix_(rows, columns)]

    return jacobian
