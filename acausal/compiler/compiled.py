"""The data of a compiled model the runtime reads: plain values, no symbolic expressions.

:class:`ModelData` is what the runtime knows of a model besides its compiled
functions (:mod:`acausal.runtime.contract`): names, kinds, start values and
units of the variables, the parameters and their vector, the relations
(how each is decided: :class:`RelationData`), the sample clocks and the
delays, the discrete state's selectors, the component hints for messages.
The compiler builds it from the flat and partitioned model
(:meth:`~acausal.compiler.translate.Translation.data`); this module imports
nothing but the standard library, so ModelData pickles and loads where
neither sympy nor the compiler is imported (``tests/runtime/test_contract.py``).
"""

from __future__ import annotations

import functools
from dataclasses import dataclass, field
from typing import Any, Callable, Mapping

from ..attributes import Experiment, StateSelect

__all__ = ["FlatVariable", "FlatParameter", "RelationData", "ClockData", "DelayData", "ModelData", "DiscreteProgram",
           "ActionOrigin", "SavedReinit", "SavedTermination", "SavedAssert", "EXACT_MARGIN", "hints_for"]

#: The relative margin of a relation free of integration noise (``RelationData.is_exact``):
#: round-off of its sides, no more.
EXACT_MARGIN = 1e-13


@dataclass(frozen=True)
class FlatParameter:
    """A numeric parameter of the flat model, with its value."""

    name: str
    value: float
    unit: str
    component: str
    description: str = ""
    display_unit: str = ""  #: Modelica's displayUnit, as declared ("" when none)


@dataclass(frozen=True, slots=True)
class FlatVariable:
    """A variable of the flat model with its attributes evaluated to numbers."""

    name: str
    kind: str  #: 'continuous', 'boolean' or 'integer'
    start: float
    fixed: bool
    nominal: float
    state_select: StateSelect
    unit: str
    component: str
    causality: str = ""
    role: str = ""  #: 'potential', 'flow' or ''
    #: names of an Integer's values, ``((value, name), ...)``, from its component's class
    #: constants (:func:`~acausal.language.value_names`); empty where there are none
    labels: tuple[tuple[int, str], ...] = ()
    description: str = ""  #: as declared
    display_unit: str = ""  #: Modelica's displayUnit, as declared or modified ("" when none)

    @property
    def is_discrete(self) -> bool:
        """A Boolean or an Integer: its values select the continuous equations."""
        return self.kind in ("boolean", "integer")

    @property
    def is_held(self) -> bool:
        """A discrete Real: a state with ``der(v) = 0`` whose value changes only at events."""
        return self.kind == "discrete"


@dataclass(frozen=True)
class RelationData:
    """A relation watched for events, as the runtime decides it.

    ``value = g op 0`` with ``g = lhs - rhs``; ``op`` is one of ``>``, ``>=``,
    ``<``, ``<=``.  The compiler's :class:`~acausal.compiler.partition.Relation`
    adds the symbolic sides.
    """

    index: int
    #: the name of the relation's indicator (``$rel3``)
    name: str
    op: str
    text: str
    #: g is linear in time, with coefficients of parameters and held discrete Reals only:
    #: its crossing time is known in advance (recomputed after each event for held values)
    is_time_event: bool
    #: the components whose equations contain the relation (for their hints)
    components: tuple[str, ...] = ()
    #: g is free of integration noise: a function of time, parameters and values constant
    #: between events, assigned without iteration (``exact_relations``); decided with a
    #: round-off margin rather than the crossing margin
    is_exact: bool = False

    def holds(self, g_value: float) -> bool:
        """The exact value of the relation for ``g = g_value``."""
        if self.op == ">":
            return g_value > 0
        if self.op == ">=":
            return g_value >= 0
        if self.op == "<":
            return g_value < 0
        return g_value <= 0

    def shifted(self, g_value: float, previous: bool, epsilon: float) -> float:
        """``g`` moved by ``epsilon`` towards keeping the previous value.

        The relation flips exactly where this function crosses zero, so it is
        the function the event locator searches.  Without the margin a holding
        torque that touches its static limit exactly (``sa == tau0_max`` up to
        round-off, ModelicaTest.Rotational.ForUsersGuide.SupportTorque1) would
        start sliding.  Time events get no margin: they are hit exactly.
        """
        if self.is_time_event:
            return g_value
        if self.op in (">", ">="):
            return g_value + epsilon if previous else g_value - epsilon
        return g_value - epsilon if previous else g_value + epsilon

    def holds_with_hysteresis(self, g_value: float, previous: bool, epsilon: float) -> bool:
        """The value of the relation at an event, given its value before it."""
        return self.holds(self.shifted(g_value, previous, epsilon))

    def margin_parameters(self, epsilon: float) -> tuple[float, float]:
        """``(eps, floor)`` of this relation's margin ``eps * max(floor, |lhs|, |rhs|)`` for
        the crossing margin ``epsilon``: ``(epsilon, 1)``, or for an exact relation
        round-off relative to its sides alone, ``(EXACT_MARGIN, 0)``."""
        return (EXACT_MARGIN, 0.0) if self.is_exact else (epsilon, 1.0)

    def margin(self, lhs: float, rhs: float, epsilon: float) -> float:
        """The margin of this relation at sides ``lhs`` and ``rhs`` (see :meth:`margin_parameters`)."""
        eps, floor = self.margin_parameters(epsilon)
        return eps * max(floor, abs(lhs), abs(rhs))

    def as_data(self) -> "RelationData":
        """This relation as plain data (itself when it is)."""
        if type(self) is RelationData:
            return self
        return RelationData(self.index, self.name, self.op, self.text, self.is_time_event, self.components,
                            self.is_exact)


@dataclass(frozen=True)
class ClockData:
    """A sample clock: its indicator's name (``$sample1``) and its text, for messages."""

    index: int
    name: str
    text: str


@dataclass(frozen=True)
class DelayData:
    """A ``delay()`` of the model: the hidden variable equal to its expression."""

    index: int
    variable: str
    fixed: bool
    component: str
    text: str


@dataclass(frozen=True)
class ModelData:
    """What the runtime reads of a compiled model (see the module docstring).

    Attributes
    ----------
    name : str
    experiment : Experiment
    variables : tuple of FlatVariable
    parameters : tuple of FlatParameter
        The numeric parameters, in declaration order: the order of
        :attr:`parameter_vector`, which the generated code reads.
    parameter_vector : tuple of float
        Their values, then the tunable start values the generated code reads
        (named in :attr:`parameter_names`).
    parameter_names : tuple of str
    structural_parameters : mapping
        Structural parameter -> its value (they chose the equations).
    evaluated_parameters : frozenset of str
        Parameters whose values the translation decided relations from.
    relations, clocks, delays : tuples
    discrete_variables, held_variables : tuples of str
        Booleans and Integers in evaluation order; discrete Reals.
    selectors : tuple of str
        The discrete symbols whose values select a system, in key order.
    identifiers : mapping
        Variable name -> its identifier in generated code (for messages).
    homotopy : str or None
        The hidden Boolean that selects homotopy's simplified expressions.
    hints : mapping
        Component path -> situation -> hint.
    """

    name: str
    experiment: Experiment
    variables: tuple[FlatVariable, ...]
    parameters: tuple[FlatParameter, ...]
    parameter_names: tuple[str, ...]
    parameter_vector: tuple[float, ...]
    structural_parameters: Mapping[str, Any]
    evaluated_parameters: frozenset[str]
    relations: tuple[RelationData, ...]
    clocks: tuple[ClockData, ...]
    delays: tuple[DelayData, ...]
    discrete_variables: tuple[str, ...]
    held_variables: tuple[str, ...]
    selectors: tuple[str, ...]
    identifiers: Mapping[str, str] = field(repr=False)
    homotopy: str | None = None
    hints: Mapping[str, Mapping[str, str]] = field(default_factory=dict, repr=False)

    @functools.cached_property
    def variable_map(self) -> dict[str, FlatVariable]:
        """Variables by name."""
        return {v.name: v for v in self.variables}

    @functools.cached_property
    def parameter_values(self) -> dict[str, float]:
        """Numeric parameter values by name."""
        return {p.name: p.value for p in self.parameters}

    @functools.cached_property
    def parameter_table(self) -> dict[str, float]:
        """Every entry of the parameter vector by name (parameters and tunable start values)."""
        return dict(zip(self.parameter_names, self.parameter_vector))

    def hints_for(self, situation: str, components) -> tuple[str, ...]:
        """The distinct hints the ``components`` (dotted paths) declare for ``situation``.

        A path inside a component (a variable's owner, ``a.b.c`` for ``a.b.c.x``)
        finds the hints of the nearest enclosing component that has some.
        """
        return hints_for(self.hints, situation, components)


@dataclass(frozen=True)
class DiscreteProgram:
    """The compiled discrete part of a model.

    Attributes
    ----------
    equations : tuple
        ``(variable, argument names, function, origin)`` per discrete
        equation, in evaluation order; ``function(*values of the arguments)``.
    impure_sites : int
        How many call sites of impure functions the equations have.
    reinits : tuple
        ``(reinit, fire arguments, fire function, value arguments, value
        function)`` per ``reinit``.
    terminations : tuple
        ``(terminate, arguments, fire function)`` per ``terminate``.
    asserts : tuple
        ``(assert, arguments, condition function)`` per ``assert``.
    source : str or None
        The generated source of the equations' functions (``_f0``, ``_f1``, ...),
        when it calls no table or impure function: what a saved run keeps
        (:mod:`~acausal.compiler.saved`).
    hybrid_source : str or None
        Likewise for the functions of the reinits, terminations and assertions,
        in that order: the reinits' conditions, then their values, the
        terminations' conditions, the assertions' conditions.
    calls : dict
        The tables both sources call (name in the source -> a callable of
        :mod:`acausal.table_calls`), when they are saved.
    """

    equations: tuple[tuple[str, list[str], Callable, Any], ...]
    impure_sites: int
    reinits: tuple
    terminations: tuple
    asserts: tuple
    source: str | None = None
    hybrid_source: str | None = None
    calls: dict = field(default_factory=dict)


@dataclass(frozen=True)
class ActionOrigin:
    """Where a saved reinit, termination or assertion comes from: what the runtime's messages
    need of the compiler's ``Origin`` (its component, and its text)."""

    component: str
    text: str

    def __str__(self) -> str:
        return self.text


@dataclass(frozen=True)
class SavedReinit:
    """A ``reinit`` of a saved run (the runtime reads its variable and origin)."""

    variable: str
    origin: ActionOrigin


@dataclass(frozen=True)
class SavedTermination:
    """A ``terminate`` of a saved run."""

    message: str
    origin: ActionOrigin


@dataclass(frozen=True)
class SavedAssert:
    """An ``assert`` of a saved run."""

    message: str
    level: str
    origin: ActionOrigin


def hints_for(hints: Mapping[str, Mapping[str, str]], situation: str, components) -> tuple[str, ...]:
    """The distinct hints of ``hints`` (component path -> situation -> hint) that the
    ``components`` (dotted paths) declare for ``situation``; a path inside a component
    finds the hints of the nearest enclosing component that has some."""
    out: list[str] = []
    for path in components:
        while True:
            hint = hints.get(path, {}).get(situation)
            if hint is not None or not path:
                break
            path = path.rpartition(".")[0]
        if hint is not None and hint not in out:
            out.append(hint)
    return tuple(out)
