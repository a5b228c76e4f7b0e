"""Stage 1: flatten a model into one list of variables and equations.

Flattening walks the component tree, gives every variable its dotted
Modelica name (``clutch1.flange_a.tau``), turns ``connect()`` statements into
equations (potentials equal, flows sum to zero, unconnected flows zero),
resolves parameter bindings to numbers and expands ``der(expression)`` by the
chain rule.  Every equation remembers where it came from.

A component class repeated many times is flattened once per structural
configuration; further instances get those equations renamed to their own
symbols (:class:`_Template`, which states when that is exact).
"""

from __future__ import annotations

import dataclasses
import enum
import functools
import math
import os
import re
import sysconfig
import traceback
import types
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Mapping, Sequence

import numpy as np
import sympy as sp
from sympy.core.function import AppliedUndef, UndefinedFunction

from ..names import INITIAL_NAME, TERMINAL_NAME, der_name, parse, pre_name
from .. import hybrid
from ..hybrid import EVENT_FUNCTIONS, Delay, Homotopy, NoEvent, Reinit, Terminate, When
from ..errors import AcausalError, ConnectorError, EquationError, ModelDefinitionError, ParameterError
from ..functions import impure_applications
from .compiled import FlatParameter, FlatVariable, hints_for
from ..language import (
    Boolean,
    BoundConnector,
    Component,
    Connector,
    Experiment,
    Flow,
    Integer,
    Parameter,
    Potential,
    StateSelect,
    Variable,
    component_hints,
    der,
    initial,
    pre,
    real_symbol,
    time,
    value_names,
)

__all__ = [
    "Origin",
    "FlatParameter",
    "FlatVariable",
    "FlatEquation",
    "DiscreteEquation",
    "FlatReinit",
    "FlatAssert",
    "FlatTermination",
    "HybridPart",
    "FlatModel",
    "flatten",
    "INITIAL",
    "START",
    "start_parameter",
    "check_start_values",
    "tunable_starts_of",
]

#: The symbol ``initial()`` becomes after flattening.
INITIAL = sp.Symbol(INITIAL_NAME)

#: The symbol ``terminal()`` becomes after flattening.
TERMINAL = sp.Symbol(TERMINAL_NAME)

#: The suffix of a tunable start value's parameter name: ``J1.w.start`` is the start of ``J1.w``.
START = ".start"


def start_parameter(variable: str) -> str:
    """The name of the parameter that holds ``variable``'s tunable start value."""
    return variable + START


_ORDER_RELATIONS = (sp.StrictGreaterThan, sp.GreaterThan, sp.StrictLessThan, sp.LessThan)


def any_node(expr: sp.Basic, test) -> bool:
    """Whether some node of ``expr`` passes ``test``, in one walk of the tree (sympy's
    ``has`` walks it once per class asked for), shared subtrees visited once."""
    stack, seen = [expr], set()
    while stack:
        node = stack.pop()
        if test(node):
            return True
        for arg in node.args:
            if id(arg) not in seen:
                seen.add(id(arg))
                stack.append(arg)
    return False


#: What :meth:`_Flattener._expand` rewrites: der/pre/initial/sample/terminal applications,
#: noEvent, homotopy, event-generating functions and relations (discrete values mirrored).
_REWRITTEN = (AppliedUndef, NoEvent, Homotopy, *EVENT_FUNCTIONS, *_ORDER_RELATIONS)


def _needs_rewrite(expr: sp.Basic) -> bool:
    """Whether ``expr`` has something :meth:`_Flattener._expand` rewrites."""
    return any_node(expr, lambda node: isinstance(node, _REWRITTEN))


#: Expression types rebuilt without evaluation while der/pre/initial are expanded:
#: they are simplified anyway when the discrete state is substituted.  Relations
#: are evaluated: one that is always true (der(x)**2 > -1) must not become an event.
_UNEVALUATED = (sp.Piecewise, sp.And, sp.Or, sp.Not)



@dataclass(frozen=True, slots=True)
class Origin:
    """Where an equation or variable comes from, for messages and teaching."""

    component: str  #: dotted path of the instance ('' for the model)
    component_class: str  #: class of the instance
    declared_in: str  #: class whose ``equations`` wrote it (or 'connect')
    index: int  #: position in that list
    source: object  #: the equation as written (text, or the object printed on demand)

    @property
    def text(self) -> str:
        """The equation as written (printed only when asked: printing is slow)."""
        if isinstance(self.source, str):
            return self.source
        if callable(self.source):
            return self.source()
        return _text(self.source)

    def __str__(self) -> str:
        where = self.component or "(model)"
        if self.declared_in in ("connect", "unconnected", "binding", "relaxation"):
            return f"{where}: {self.declared_in}: {self.text}"
        return f"{where} ({self.declared_in} eq. {self.index + 1}): {self.text}"


@dataclass(frozen=True, slots=True)
class FlatEquation:
    """``residual = 0``."""

    residual: sp.Expr
    origin: Origin

    def __str__(self) -> str:
        return f"0 = {self.residual}"


@dataclass(frozen=True, slots=True)
class DiscreteEquation:
    """``variable := rhs`` for a Boolean or Integer variable."""

    variable: str
    rhs: sp.Basic
    origin: Origin


@dataclass(frozen=True)
class FlatReinit:
    """``reinit(variable, value)``, done at the event where ``fires`` is true."""

    variable: str
    value: sp.Basic
    fires: sp.Basic
    origin: Origin


@dataclass(frozen=True)
class FlatAssert:
    """``assert(condition, message, level)``; checked where ``fires`` is true (always: None)."""

    condition: sp.Basic
    message: str
    level: str
    origin: Origin
    fires: sp.Basic | None = None


@dataclass(frozen=True)
class FlatTermination:
    """``terminate(message)``, at the event where ``fires`` is true."""

    message: str
    fires: sp.Basic
    origin: Origin


@dataclass(frozen=True)
class HybridPart:
    """What a model's when-clauses and assertions ask the runtime to do at events.

    The assignments of when-clauses are discrete equations of the flat model
    (``v = if <fires> then expr else pre(v)``); what is here acts on the
    run itself.
    """

    reinits: tuple[FlatReinit, ...] = ()
    asserts: tuple[FlatAssert, ...] = ()
    terminations: tuple[FlatTermination, ...] = ()

    def __bool__(self) -> bool:
        return bool(self.reinits or self.asserts or self.terminations)


@dataclass(frozen=True)
class FlatModel:
    """The flat model: the output of :func:`flatten`.

    Attributes
    ----------
    parameters : tuple of FlatParameter
        Numeric parameters (bindings resolved).
    structural_parameters : dict
        ``name -> value`` of parameters evaluated at build time.
    variables : tuple of FlatVariable
        Continuous and discrete variables, in declaration order.
    equations : tuple of FlatEquation
        Continuous equations, component equations first, then connections.
    discrete_equations : tuple of DiscreteEquation
    initial_equations : tuple of FlatEquation
    hints : dict
        ``component path -> {situation: hint}`` for the components that
        declare hints (:attr:`acausal.language.Component.hints`).
    """

    name: str
    modelica_class: str | None
    experiment: Experiment
    parameters: tuple[FlatParameter, ...]
    structural_parameters: dict
    variables: tuple[FlatVariable, ...]
    equations: tuple[FlatEquation, ...]
    discrete_equations: tuple[DiscreteEquation, ...]
    initial_equations: tuple[FlatEquation, ...]
    functions: dict = field(default_factory=dict)
    hints: dict = field(default_factory=dict)
    hybrid: HybridPart = field(default_factory=HybridPart)
    #: the variables whose start values are *tunable*: inputs of the generated code, read
    #: from the parameter vector as the parameters ``<variable>.start``
    #: (:attr:`start_parameters`), so that another value needs no new translation
    tunable_starts: tuple[str, ...] = ()
    #: the ``delay()`` operators of the continuous equations (:mod:`acausal.compiler.delays`)
    delays: tuple = ()
    #: the hidden Boolean that selects homotopy()'s simplified expressions (None: no homotopy)
    homotopy: str | None = None

    def hints_for(self, situation: str, components) -> tuple[str, ...]:
        """The distinct hints the ``components`` (dotted paths) declare for ``situation``.

        A path inside a component (a variable's owner, ``a.b.c`` for ``a.b.c.x``)
        finds the hints of the nearest enclosing component that has some.
        """
        return hints_for(self.hints, situation, components)

    @property
    def variable_map(self) -> dict[str, FlatVariable]:
        return {v.name: v for v in self.variables}

    @property
    def parameter_values(self) -> dict[str, float]:
        return {p.name: p.value for p in self.parameters}

    @property
    def start_parameters(self) -> tuple[FlatParameter, ...]:
        """The tunable start values as parameters ``<variable>.start`` (values: the variables' starts).

        They are not among :attr:`parameters` (results, ``explain`` and the
        unit check list the model's own parameters), but the translation
        puts them after those in its parameter vector
        (:class:`~acausal.compiler.translate.Translation`).
        """
        if not self.tunable_starts:
            return ()
        variables = self.variable_map
        return tuple(FlatParameter(start_parameter(n), variables[n].start, variables[n].unit,
                                   variables[n].component, f"start value of {n}")
                     for n in self.tunable_starts)

    def with_starts(self, starts: Mapping[str, float]) -> "FlatModel":
        """This flat model with other tunable start values (``variable -> value``).

        Raises
        ------
        ParameterError
            For a name that is not a tunable start (see :func:`check_start_values`).
        """
        starts = check_start_values(self, starts)
        if not starts:
            return self
        variables = tuple(dataclasses.replace(v, start=starts[v.name]) if v.name in starts else v
                          for v in self.variables)
        return dataclasses.replace(self, variables=variables)

    def summary(self) -> str:
        n_cont = sum(not v.is_discrete for v in self.variables)
        return (f"{self.name}: {n_cont} continuous and {len(self.variables) - n_cont} discrete "
                f"variables, {len(self.equations)} equations, {len(self.discrete_equations)} "
                f"discrete equations, {len(self.parameters)} parameters")


# --------------------------------------------------------------------------


def flatten(model: Component, parameters: dict[str, float] | None = None, *, templates: bool = True) -> FlatModel:
    """Flatten ``model`` (a :class:`~acausal.language.Model` instance).

    Parameters
    ----------
    parameters : dict, optional
        New values of numeric (tunable) parameters by dotted name, in place
        of their modifiers or defaults; bindings that refer to them follow
        (``J = 2*Jm``).  A name ``<variable>.start`` is the variable's start
        value, in place of its modifier or default; those of state
        candidates and fixed variables are tunable
        (:attr:`FlatModel.tunable_starts`).
    templates : bool
        Build the equations of repeated components from templates
        (:class:`_Template`, :attr:`acausal.options.EngineOptions.templates`).
        False calls every instance's ``equations()``; the flat model is the
        same (``tests/compiler/test_flatten_templates.py``).

    Raises
    ------
    ModelDefinitionError
        For equations that are not equations, bad connections, unconnected
        inputs and unresolvable parameter bindings.
    ParameterError
        For a name in ``parameters`` that is not a numeric parameter (a
        structural one selects equations and is set when the model is built;
        a variable's start value is named ``<variable>.start``), and for a
        start value that is not a finite number or not tunable.
    """
    return _Flattener(model, parameters, templates=templates).run()


class _Flattener:
    def __init__(self, model: Component, overrides: dict[str, float] | None = None, *,
                 templates: bool = True) -> None:
        if not isinstance(model, Component):
            raise ModelDefinitionError(f"flatten() takes a Model instance, not {type(model).__name__}",
                                       hint="instantiate the class first: flatten(MyModel())")
        self.model = model
        self.overrides = dict(overrides or {})
        self.components: list[Component] = list(model.walk())
        self.parameters: dict[str, tuple[Any, str, Component]] = {}
        self.structural: dict[str, Any] = {}
        self.variables: dict[str, FlatVariable] = {}
        self.signal_declarations: dict[str, tuple[Variable, Component]] = {}
        self.equations: list[FlatEquation] = []
        self.discrete_equations: list[DiscreteEquation] = []
        self.initial_equations: list[FlatEquation] = []
        self.unknown_parameters: list[str] = []
        #: template key -> _Template, or None where templates are not used
        self.templates: dict[tuple, list[_Template] | None] | None = (
            {} if templates else None)
        self._plans: dict[type, tuple] = {}  # class -> (structural, conditional, structural names)
        self._class_declarations: dict[type, dict] = {}
        self._keys: dict[int, tuple | None] = {}  # id of a component -> its template key
        self._computed_templates: dict[tuple, _ValueTemplate | None] = {}
        #: id -> (value, its _ValueTemplate, symbols) of computed attributes built from a template
        self._built_values: dict[int, tuple] = {}
        self._connector_variables: dict[type, dict] = {}
        self._forms: dict[tuple, list] = {}  # connection equations: kind -> [_Program or None, verified]
        # the hybrid part (when-clauses, event-generating functions, assertions)
        self.reinits: list[FlatReinit] = []
        self.asserts: list[FlatAssert] = []
        self.terminations: list[FlatTermination] = []
        self.when_assigned: dict[str, Origin] = {}
        self.hidden_count = 0  #: hidden variables made so far (when-conditions, held values)
        self.hybrid_count = 0  #: hybrid items met (a component with some is built without template)
        self.origin: Origin | None = None  #: the equation being added
        self._mirrors: dict[str, sp.Symbol] = {}  #: discrete name -> its discrete Real mirror
        #: start values given with the parameters (``J1.w.start``), by variable
        self.start_overrides: dict[str, Any] = {}
        #: the variables some equation differentiates (found by :meth:`_state_candidates`)
        self.differentiated: set[str] = set()
        #: the name of the hidden Boolean of homotopy() (:meth:`_homotopy_switch`), once made
        self.homotopy_switch: str | None = None

    # -- declarations ---------------------------------------------------------

    def _per_template(self, eq: FlatEquation, memo: dict, test: Callable[[sp.Basic], Any]) -> Any:
        """``test(eq.residual)``, once per equation of a template (:class:`_Template`): its
        instances have one structure, their symbols renamed, so a test of the structure
        (a function applied, a derivative read) holds for all or none."""
        source = eq.origin.source
        if getattr(self, "delays", None) or not isinstance(source, _Source):
            return test(eq.residual)  # (delays extracted: the residuals are no longer the templates')
        key = (id(source.template), source.entry)
        found = memo.get(key)
        if found is None:
            found = memo[key] = test(eq.residual)
        return found

    def _refuse_impure_calls(self) -> None:
        """An impure function (a hidden state, :class:`~acausal.functions.ImpureFunction`) is
        called at events only: in the discrete equations, never in a continuous one."""
        memo: dict = {}
        for eq in (*self.equations, *self.initial_equations):
            if not self._per_template(eq, memo, lambda r: bool(impure_applications(r))):
                continue
            found = impure_applications(eq.residual)
            if found:
                raise EquationError(
                    f"{eq.origin}: the impure function {type(found[0]).__name__} is called in a "
                    f"continuous equation", hint="call it in a when-clause, whose value is held "
                    "between events", components=(eq.origin.component,))

    def run(self) -> FlatModel:
        for component in self.components:
            self._declare(component)
        self._apply_overrides()
        values = self._resolve_parameters()
        self.values = values
        for component in self.components:
            self._declare_variables(component, values)
        for component in self.components:
            self._collect_equations(component)
        self._connect()
        self._extract_delays()
        for name in self.unknown_parameters:
            origin = Origin(name.rpartition(".")[0], "", "binding", 0, f"der({name}) = 0")
            self.equations.append(FlatEquation(real_symbol(der_name(name)), origin))
        self._hold_discrete_reals()
        self._refuse_impure_calls()
        self._state_candidates()
        tunable = self._tunable_starts()
        _check_start_names(self._model_name(), self.variables, tunable, self.start_overrides, self.parameters)
        model = self.model
        return FlatModel(
            name=type(model).__name__,
            modelica_class=getattr(model, "modelica_class", None),
            experiment=getattr(model, "experiment", Experiment()),
            parameters=tuple(FlatParameter(n, values[n], self.parameters[n][1],
                                           self.parameters[n][2].path, self._description(n),
                                           self._description(n, "display_unit"))
                             for n in self.parameters if n not in self.unknown_parameters),
            structural_parameters=dict(self.structural),
            variables=tuple(self.variables.values()),
            equations=tuple(self.equations),
            discrete_equations=tuple(self.discrete_equations),
            initial_equations=tuple(self.initial_equations),
            hints={c.path: h for c in self.components if (h := component_hints(type(c)))},
            hybrid=HybridPart(tuple(self.reinits), tuple(self.asserts), tuple(self.terminations)),
            tunable_starts=tunable,
            delays=tuple(self.delays),
            homotopy=self.homotopy_switch,
        )

    def _model_name(self) -> str:
        return type(self.model).__name__

    def _tunable_starts(self) -> tuple[str, ...]:
        """The variables whose start value initialization reads: those with ``fixed=True``
        and the state candidates (differentiated in some equation), continuous or discrete
        Reals, in declaration order.

        Their start values become inputs of the generated initialization code
        (parameters ``<name>.start``).  Others stay numbers of the flat model:
        a Boolean's or an Integer's start selects the first discrete state,
        and an algebraic variable's start is at most a first guess of a
        Newton iteration, printed into the code.  Hidden variables (``$...``)
        take the starts flattening gives them.
        """
        return tuple(name for name, v in self.variables.items()
                     if v.kind in ("continuous", "discrete") and "$" not in name
                     and (v.fixed or name in self.differentiated))

    def _description(self, parameter: str, attribute: str = "description") -> str:
        """The declared description (or another text ``attribute``, ``display_unit``) of
        ``parameter`` (a dotted name of this model)."""
        component = self.parameters[parameter][2]
        key = parameter[len(component.path) + 1:] if component.path else parameter
        return getattr(self._declarations(component).get(key), attribute, "") or ""

    def _declarations(self, component: Component) -> dict:
        """``component.declarations()``, computed once per class (it walks the class hierarchy)."""
        klass = type(component)
        found = self._class_declarations.get(klass)
        if found is None:
            found = self._class_declarations[klass] = klass.declarations()
        return found

    def _declare(self, component: Component) -> None:
        # parameter_binding() looks the declaration up again: done here unless a class overrides it
        plain = type(component).parameter_binding is Component.parameter_binding
        for key, decl in self._declarations(component).items():
            if isinstance(decl, Parameter):
                path = component._path_of(key)
                binding = component._modifiers.get(key, decl.default) if plain \
                    else component.parameter_binding(key)
                if decl.structural:
                    self.structural[path] = binding
                    continue
                self.parameters[path] = (binding, decl.unit, component)
                if not decl.fixed:
                    self.unknown_parameters.append(path)

    def _apply_overrides(self) -> None:
        """Put the values of ``parameters=`` in place of the bindings they replace.

        A name ``<variable>.start`` is a start value: it is set when the
        variable is declared (:meth:`_add_variable`) and checked once the
        model's equations tell which start values are tunable.
        """
        for name, value in self.overrides.items():
            if name in self.structural:
                raise ParameterError(
                    f"parameter {name} is structural: it decides which equations the model has",
                    hint="set it where the component is created (e.g. Component(name=value)); "
                         "only numeric parameters can change between runs")
            if name not in self.parameters:
                if name.endswith(START):
                    self.start_overrides[name[:-len(START)]] = value
                    continue
                import difflib

                if self._declares_variable(name):
                    owner, _, member = name.rpartition(".")
                    raise ParameterError(
                        f"{self._model_name()} has no numeric parameter {name!r}: {name} is a variable",
                        hint=f"a variable's start value is given at run time with start={{{name!r}: value}} "
                             f"(--start {name}=VALUE on the command line, or the parameter "
                             f"'{start_parameter(name)}'), or where its component is created, "
                             f"e.g. {member}=dict(start=value)",
                        components=(owner,))
                close = difflib.get_close_matches(name, sorted(self.parameters), n=3)
                raise ParameterError(f"{self._model_name()} has no numeric parameter {name!r}",
                                     hint=f"did you mean {', '.join(close)}?" if close else
                                     "parameters are named by their dotted path, e.g. component.parameter")
            _binding, unit, component = self.parameters[name]
            self.parameters[name] = (value, unit, component)

    def _declares_variable(self, name: str) -> bool:
        """Whether ``name`` is a variable some component declares (a connector's included),
        known before the variables are made."""
        by_path = {c.path: c for c in self.components}
        owner, _, member = name.rpartition(".")
        component = by_path.get(owner)
        if component is not None and isinstance(self._declarations(component).get(member), Variable):
            return True
        holder, _, connector = owner.rpartition(".")
        component = by_path.get(holder)
        declaration = self._declarations(component).get(connector) if component is not None else None
        return isinstance(declaration, Connector) and member in type(declaration).variables()

    def _resolve_parameters(self) -> dict[str, float]:
        """Evaluate every parameter binding to a number, following references."""
        values: dict[str, float] = {}
        resolving: list[str] = []

        def resolve(name: str) -> float:
            if name in values:
                return values[name]
            if name in resolving:
                cycle = " -> ".join(resolving[resolving.index(name):] + [name])
                raise ParameterError(f"parameter bindings form a cycle: {cycle}",
                                     hint="give one of them a numeric value")
            binding, _unit, component = self.parameters[name]
            resolving.append(name)
            try:
                value = self._evaluate_binding(name, binding, component, resolve)
            finally:
                resolving.pop()
            values[name] = value
            return value

        for name in self.parameters:
            if name in self.unknown_parameters and self.parameters[name][0] is None:
                values[name] = 0.0  # found by the initialization problem
                continue
            resolve(name)
        # finite and min/max checks (nan compares False: "not value >= min" catches it)
        for component in self.components:
            for key, decl in self._declarations(component).items():
                if not isinstance(decl, Parameter):
                    continue
                path = component._path_of(key)
                if decl.structural:
                    if decl.finite:
                        _check_finite(path, self.structural[path], component, key)
                    continue
                value = values[path]
                if decl.finite:
                    _check_finite(path, value, component, key, binding=self.parameters[path][0])
                not_a_number = math.isnan(value)
                if decl.min is not None and not value >= decl.min:
                    raise ParameterError(f"parameter {path} = {value} is "
                                         f"{'not a number, so not above' if not_a_number else 'below'} "
                                         f"its minimum {decl.min}",
                                         hint=f"{type(component).__name__}.{key} must be >= {decl.min}",
                                         components=(component.path,))
                if decl.max is not None and not value <= decl.max:
                    raise ParameterError(f"parameter {path} = {value} is "
                                         f"{'not a number, so not below' if not_a_number else 'above'} "
                                         f"its maximum {decl.max}",
                                         hint=f"{type(component).__name__}.{key} must be <= {decl.max}",
                                         components=(component.path,))
        return values

    def _evaluate_binding(self, name, binding, component, resolve) -> float:
        if binding is None:
            raise ParameterError(f"parameter {name} has no value",
                                 hint=f"give it one: {type(component).__name__}({name.rpartition('.')[2]}=...)")
        if isinstance(binding, (bool, np.bool_)):
            return float(binding)
        if isinstance(binding, (int, float, np.number)):
            return float(binding)
        if isinstance(binding, sp.Basic):
            subs = {}
            for sym in binding.free_symbols:
                if sym.name not in self.parameters:
                    raise ParameterError(f"parameter {name} is bound to {binding}, but {sym.name} "
                                         f"is not a parameter",
                                         hint="bind parameters only to numbers or other parameters")
                subs[sym] = resolve(sym.name)
            value = binding.subs(subs)
            try:
                return float(value)
            except TypeError as exc:
                raise ParameterError(f"parameter {name} = {binding} does not evaluate to a number") from exc
        raise ParameterError(f"parameter {name} has a value of type {type(binding).__name__}: {binding!r}",
                             hint="numeric parameters take numbers or expressions of parameters; "
                                  "declare it structural=True for other values")

    def _number(self, value: Any, what: str) -> float:
        built = self._built_values.pop(id(value), None) if isinstance(value, sp.Basic) else None
        if built is not None and built[0] is value:
            # a computed attribute renamed from a template: evaluated once per set of values
            _, template, symbols = built
            values = tuple(self.values.get(s.name, _MISSING) for s in symbols)
            number = template.numbers.get(values)
            if number is None:
                number = template.numbers[values] = self._evaluate(value, what)
            return number
        return self._evaluate(value, what)

    def _evaluate(self, value: Any, what: str) -> float:
        if isinstance(value, sp.Basic):
            subs = {s: self.values[s.name] for s in value.free_symbols if s.name in self.values}
            value = value.subs(subs)
        try:
            return float(value)
        except (TypeError, ValueError) as exc:
            raise ModelDefinitionError(f"{what} = {value} is not a number",
                                       hint="attributes take numbers or expressions of parameters") from exc

    def _declare_variables(self, component: Component, values) -> None:
        for key, decl in self._declarations(component).items():
            if isinstance(decl, Connector):
                if not decl.enabled(component):
                    continue
                path = component._path_of(key)
                variables = self._connector_variables.get(type(decl))
                if variables is None:
                    variables = self._connector_variables[type(decl)] = type(decl).variables()
                for var_name, var in variables.items():
                    self._add_variable(f"{path}.{var_name}", var, component, None)
            elif isinstance(decl, Variable):
                if not decl.enabled(component):
                    continue
                self._add_variable(component._path_of(key), decl, component, key)
        # A parameter with fixed=False is an unknown of the initialization
        # problem, constant afterwards: a variable with der(p) = 0 whose start
        # (its binding, if numeric) is the first guess.
        for name in self.unknown_parameters:
            binding, unit, owner = self.parameters[name]
            if owner is component:
                guess = 0.0 if binding is None or isinstance(binding, sp.Basic) else float(binding)
                if name in self.start_overrides:
                    guess = _start_value(name, self.start_overrides[name])
                self.variables[name] = FlatVariable(
                    name=name, kind="continuous", start=guess, fixed=False, nominal=1.0,
                    state_select=StateSelect.default, unit=unit, component=component.path)

    def _add_variable(self, path: str, decl: Variable, component: Component, key: str | None) -> None:
        # Component.attribute(key, name) with the declaration at hand, unless a class overrides it
        modified = {} if key is None else component._attribute_modifiers.get(key, {})
        plain = key is None or type(component).attribute is Component.attribute

        def attr(name):
            if not plain:
                return component.attribute(key, name)
            value = modified[name] if name in modified else getattr(decl, name)
            if callable(value) and not isinstance(value, sp.Basic):
                return self._computed(component, (label, name, value), value)
            return value

        label = key if key is not None else path[len(component.path) + 1:]

        kind = "boolean" if isinstance(decl, Boolean) else "integer" if isinstance(decl, Integer) \
            else "discrete" if getattr(decl, "discrete", False) else "continuous"
        nominal = attr("nominal")
        start = given_start = attr("start")
        if kind in ("continuous", "discrete") and path in self.start_overrides:
            start = given_start = _start_value(path, self.start_overrides[path])
        elif kind in ("continuous", "discrete"):
            start = self._number(start, f"{path}.start")
        _check_finite_attribute(path, "start", start, given_start, component, key)
        if kind in ("boolean", "integer"):
            start = int(bool(start)) if kind == "boolean" else int(start)
        if nominal is not None:
            given_nominal, nominal = nominal, abs(self._number(nominal, f"{path}.nominal"))
            _check_finite_attribute(path, "nominal", nominal, given_nominal, component, key)
        variable = FlatVariable(
            name=path, kind=kind, start=start, fixed=bool(attr("fixed")),
            nominal=nominal or 1.0,
            state_select=StateSelect(attr("state_select") if kind in ("continuous", "discrete") else 2),
            unit=decl.unit, component=component.path, causality=decl.causality,
            role=getattr(decl, "connector_role", ""),
            labels=value_names(type(component), attr("min"), attr("max")) if kind == "integer" else (),
            description=decl.description, display_unit=attr("display_unit") or "")
        self.variables[path] = variable
        if decl.causality:
            self.signal_declarations[path] = (decl, component)
        self._built_values.clear()

    # -- equations --------------------------------------------------------------

    def _collect_equations(self, component: Component) -> None:
        if self.templates is None:
            self._call_equations(component)
            return
        key = self._template_key(component)
        if key is None:
            self._call_equations(component)
            return
        variants = self.templates.get(key, [])
        if variants is None:  # this key builds every instance directly
            self._call_equations(component)
            return
        path = component.path
        for template in variants:
            symbols = template.symbols_for(self, path)
            if symbols is None:
                continue
            if template.verified:
                template.add(self, path, symbols)
                return
            # its first use: build the instance both ways; the template serves
            # further instances only if the two agree
            start = self._sizes()
            self._call_equations(component)
            if template.agrees(self, path, symbols, start):
                template.verified = True
            else:
                self.templates[key] = None
            return
        if len(variants) >= _MAX_VARIANTS:
            self._call_equations(component)
            return
        # no template applies: call equations(), recording what it reads, and keep the result
        start = self._sizes()
        hybrid_before = self.hybrid_count
        reads = self._call_equations_recorded(component)
        if self.hybrid_count != hybrid_before:
            reads = None  # hidden variables and when-clauses are made per instance
        template = _Template.make(self, component, start, reads, self._plans[type(component)][2])
        if template is None:
            self.templates[key] = None
        else:
            self.templates[key] = variants + [template]

    def _template_key(self, component: Component) -> tuple | None:
        """What the equations of a leaf component may depend on besides its path (see
        :class:`_Template`), or None if it is not a leaf."""
        found = self._keys.get(id(component), self)
        if found is self:
            found = self._keys[id(component)] = self._make_template_key(component)
        return found

    def _make_template_key(self, component: Component) -> tuple | None:
        if component._parent is None or component._children or component._connections:
            return None
        klass = type(component)
        plan = self._plans.get(klass)
        if plan is None:
            declarations = self._declarations(component)
            structural = tuple((name, d.default) for name, d in declarations.items()
                               if isinstance(d, Parameter) and d.structural)
            conditional = tuple(d for d in declarations.values() if d.condition is not None)
            plan = self._plans[klass] = (structural, conditional, frozenset(n for n, _ in structural))
        structural, conditional, _ = plan
        modifiers = component._modifiers
        try:
            key = [klass]
            key.extend(_freeze(modifiers.get(name, default)) for name, default in structural)
            key.extend(bool(d.enabled(component)) for d in conditional)
            key.extend((name, _freeze(value)) for name, value in vars(component).items()
                       if name not in _FRAMEWORK_ATTRIBUTES)
        except _NotTemplatable:
            return None
        except Exception:  # noqa: BLE001 - a failing condition: built directly, which reports it
            return None
        return tuple(key)

    def _declared_as(self, name: str) -> tuple:
        """How a symbol's name is declared, as far as its equations' flattening depends on it."""
        if name in self.parameters:
            return ("parameter", name in self.unknown_parameters)
        variable = self.variables.get(name)
        if variable is not None:
            return ("variable", variable.kind)
        return ("undeclared",)

    def _sizes(self) -> tuple[int, int, int]:
        return len(self.equations), len(self.initial_equations), len(self.discrete_equations)

    def _call_equations_recorded(self, component: Component) -> set | None:
        """:meth:`_call_equations`, recording what the equations read (:meth:`_recorded`)."""
        return self._recorded(component, lambda: self._call_equations(component))[1]

    def _recorded(self, component: Component, call) -> tuple[Any, set | None]:
        """``(call(), reads)`` with what ``call`` reads of ``component`` recorded.

        The component's modifier dictionaries record their reads and its parent is
        replaced by a :class:`_ParentGuard`.  ``reads`` are the names of the
        parameter modifiers read, or None if ``call`` read a variable's attribute
        modifiers, the modifiers as a whole, or anything of the parent but its path.
        """
        modifiers = _RecordingDict(component._modifiers)
        attributes = _RecordingDict(component._attribute_modifiers)
        original = component._modifiers, component._attribute_modifiers, component._parent
        guard = _ParentGuard(original[2])
        object.__setattr__(component, "_modifiers", modifiers)
        object.__setattr__(component, "_attribute_modifiers", attributes)
        object.__setattr__(component, "_parent", guard)
        try:
            result = call()
        finally:
            object.__setattr__(component, "_modifiers", original[0])
            object.__setattr__(component, "_attribute_modifiers", original[1])
            object.__setattr__(component, "_parent", original[2])
            for recorder, dictionary in zip((modifiers, attributes), original):
                if recorder.changed:  # the call changed them: keep what it did
                    dictionary.clear()
                    dictionary.update(recorder)
        if modifiers.everything or modifiers.changed or attributes.everything or attributes.changed \
                or attributes.read or guard._touched:
            return result, None
        return result, modifiers.read

    def _computed(self, component: Component, label: tuple, function) -> Any:
        """``function(component)``, a computed variable attribute (:class:`_ValueTemplate`)."""
        key = self._template_key(component) if self.templates is not None else None
        if key is None:
            return function(component)
        key = (key, label)
        template = self._computed_templates.get(key, self)
        if template is self:  # the first instance
            value, reads = self._recorded(component, lambda: function(component))
            made = None
            if reads is not None and reads <= self._plans[type(component)][2]:
                try:
                    made = _ValueTemplate(self, component, value)
                except _NotTemplatable:
                    pass
            self._computed_templates[key] = made
            return value
        if template is None:
            return function(component)
        symbols = template.symbols_for(self, component.path)
        if symbols is None:
            return function(component)
        if not template.verified:
            value = function(component)
            if template.agrees(value, symbols):
                template.verified = True
            else:
                self._computed_templates[key] = None
            return value
        value = template.build(symbols)
        if isinstance(value, sp.Basic):
            self._built_values[id(value)] = (value, template, symbols)
        return value

    def _call_equations(self, component: Component) -> None:
        for klass in reversed(type(component).__mro__):
            for method_name, target in (("equations", self.equations),
                                        ("initial_equations", self.initial_equations)):
                method = vars(klass).get(method_name)
                if method is None:
                    continue
                try:
                    items = method(component)
                except AcausalError:
                    raise
                except (TypeError, ValueError, AttributeError, ArithmeticError, LookupError,
                        NameError) as exc:
                    raise _equations_failed(exc, component, klass, method_name) from exc
                if items is None:
                    continue
                if not isinstance(items, (list, tuple)):
                    items = [items]
                # an array equation is a list of its elements' equations (Eq of arrays)
                items = _scalar_items(items)
                for index, item in enumerate(items):
                    origin = Origin(component.path, type(component).__name__, klass.__name__, index,
                                    item)
                    self._add_equation(item, origin, target)

    def _add_equation(self, item: Any, origin: Origin, target: list) -> None:
        self.origin = origin
        if isinstance(item, (When, hybrid.Assert, Reinit, Terminate)):
            self.hybrid_count += 1
            if target is not self.equations:
                raise EquationError(f"{origin}: {type(item).__name__} among the initial equations",
                                    hint="when-clauses, reinit, assert and terminate belong in equations()")
            if isinstance(item, When):
                self._add_when(item, origin)
            elif isinstance(item, hybrid.Assert):
                self.asserts.append(FlatAssert(self._at_events(item.condition), item.message, item.level,
                                               origin))
            else:
                raise EquationError(f"{origin}: {type(item).__name__.lower()}() outside a when-clause",
                                    hint=f"write When(condition, {type(item).__name__.lower()}(...)); "
                                         f"it acts at the event where the condition becomes true")
            return
        if isinstance(item, (bool, np.bool_)) or item in (sp.true, sp.false):
            raise EquationError(
                f"equation {origin.index + 1} of {origin.declared_in} in {origin.component or 'the model'} "
                f"is the Python value {item}, not an equation",
                hint="write Eq(lhs, rhs) (or lhs - rhs); `lhs == rhs` compares the two sides "
                     "and gives a bool")
        if isinstance(item, sp.Equality):
            lhs, rhs = item.lhs, item.rhs
            if isinstance(lhs, sp.Symbol) and lhs.name in self.variables \
                    and self.variables[lhs.name].is_discrete:
                if target is not self.equations:
                    target.append(FlatEquation(self._expand(lhs - rhs), origin))
                    return
                self.discrete_equations.append(DiscreteEquation(lhs.name, self._expand(rhs), origin))
                return
            residual = lhs - rhs
        elif isinstance(item, sp.Basic) and not isinstance(item, sp.logic.boolalg.Boolean):
            residual = item
        elif isinstance(item, (int, float)):
            residual = sp.Float(item)
        else:
            raise EquationError(
                f"equation {origin.index + 1} of {origin.declared_in} in {origin.component or 'the model'} "
                f"is a {type(item).__name__} ({item!r}), not an equation",
                hint="write Eq(lhs, rhs) with sympy expressions")
        self._check_symbols(residual, origin)
        target.append(FlatEquation(self._expand(residual), origin))

    def _check_symbols(self, expr: sp.Basic, origin: Origin) -> None:
        for sym in expr.free_symbols:
            if sym is time or sym.name in self.variables or sym.name in self.parameters:
                continue
            raise EquationError(f"{origin}: unknown name {sym.name}",
                                hint="every symbol must be a declared variable or parameter of the "
                                     "model (a disabled conditional connector has no variables)")

    def _expand(self, expr: sp.Basic) -> sp.Basic:
        """Replace der(), pre() and initial() by plain symbols (chain rule for der), and
        the event-generating functions by values held between events."""
        if not isinstance(expr, sp.Basic) or not _needs_rewrite(expr):
            return expr

        literal = [0]  # inside noEvent: relations are evaluated as they stand, nothing to mirror

        def rewrite(node: sp.Basic) -> sp.Basic:
            if isinstance(node, NoEvent):
                literal[0] += 1
                try:
                    inner = rewrite(hybrid.plain_form(node.args[0]))
                finally:
                    literal[0] -= 1
                return inner if literal[0] else NoEvent(inner)  # noEvent(noEvent(u)) = noEvent(u)
            if isinstance(node, EVENT_FUNCTIONS):
                return self._held_event_function(node.func, [rewrite(a) for a in node.args])
            if isinstance(node, Homotopy):
                actual, simplified = (rewrite(a) for a in node.args)
                return sp.Piecewise((simplified, self._homotopy_switch()), (actual, True))
            if isinstance(node, sp.Function) and node.func.__name__ == "terminal" and not node.args:
                return TERMINAL
            if isinstance(node, sp.Function) and node.func == pre:
                (arg,) = node.args
                arg = rewrite(arg)
                if not isinstance(arg, sp.Symbol):
                    raise EquationError(f"pre() takes a variable, not {arg}")
                return sp.Symbol(pre_name(arg.name), **arg.assumptions0)
            if isinstance(node, sp.Function) and node.func == initial:
                return INITIAL
            if isinstance(node, sp.Function) and node.func == der:
                (arg,) = node.args
                return self._time_derivative(rewrite(arg))
            if not node.args:
                return node
            new_args = [rewrite(a) for a in node.args]
            if isinstance(node, _ORDER_RELATIONS) and not literal[0]:
                return self._mirror_discrete(node, new_args)
            if all(a is b for a, b in zip(new_args, node.args)):
                return node
            if isinstance(node, _UNEVALUATED):
                return node.func(*new_args, evaluate=False)
            return node.func(*new_args)

        return rewrite(expr)

    def _mirror_discrete(self, node: sp.Basic, args: list) -> sp.Basic:
        """A relation between continuous and discrete values, with each discrete value
        (``pre(n)``, an Integer, ``pre(x)`` of a discrete Real) replaced by a discrete
        Real that mirrors it.

        The relation's crossing function is computed by the continuous system,
        which knows no Integers or Booleans (they select its equations); a
        mirror is one of its states, set at events to the value mirrored.
        """
        relation = node if all(a is b for a, b in zip(args, node.args)) else node.func(*args)
        symbols = relation.free_symbols
        discrete, continuous = [], False
        for sym in symbols:
            what = parse(sym.name)
            base = self.variables.get(what.base if what.kind in ("pre", "variable") else "")
            if base is not None and (base.is_discrete or (what.kind == "pre" and base.is_held)):
                # (pre() of a discrete Real, too: between events it is the value held, but the
                # continuous system knows only that value, not its left limit)
                discrete.append(sym)
            elif sym is time or what.kind == "derivative" or (
                    base is not None and not base.is_discrete and what.kind == "variable"):
                continuous = True
        if not (discrete and continuous):
            return relation
        self.hybrid_count += 1
        mirrors = {}
        for sym in sorted(discrete, key=lambda s: s.name):
            mirror = self._mirrors.get(sym.name)
            if mirror is None:
                component = self.origin.component if self.origin is not None else ""
                mirror = self._mirrors[sym.name] = self._hidden_variable("mirror", "discrete", component)
                origin = Origin(component, "", "mirror", 0, f"{mirror.name} = {sym.name}")
                self.discrete_equations.append(DiscreteEquation(mirror.name, sym, origin))
            mirrors[sym] = mirror
        return relation.xreplace(mirrors)

    # -- the hybrid part ----------------------------------------------------------

    def _extract_delays(self) -> None:
        """``delay(u, T)`` becomes a value read from the run's history and a hidden
        variable ``$delayK = u`` (:func:`acausal.compiler.delays.extract_delays`)."""
        from .delays import DELAY_STEM, extract_delays

        def hidden(component: str) -> str:
            name = f"{component + '.' if component else ''}{DELAY_STEM}{self.hidden_count}"
            self.hidden_count += 1
            self.variables[name] = FlatVariable(
                name=name, kind="continuous", start=0.0, fixed=False, nominal=1.0,
                state_select=StateSelect(2), unit="", component=component)
            return name

        # (origin, expression) of the equations delay() may not appear in; an origin is
        # printed only for a model that has a delay (printing one costs a sympy printout)
        elsewhere = [(d.origin, d.rhs) for d in self.discrete_equations]
        elsewhere += [(a.origin, a.condition) for a in self.asserts]
        elsewhere += [(r.origin, r.value) for r in self.reinits]
        elsewhere += [(e.origin, e.residual) for e in self.initial_equations]
        parameters = {n for n in self.parameters if n not in self.unknown_parameters}
        memo: dict = {}
        if not any(self._per_template(e, memo, lambda r: r.has(Delay)) for e in self.equations) and not any(
                isinstance(x, sp.Basic) and x.has(Delay) for _, x in elsewhere):
            self.delays = []
            return
        equations, self.delays = extract_delays(self.equations, self.variables, parameters, hidden,
                                                [(f"{origin}", x) for origin, x in elsewhere], FlatEquation)
        self.equations[:] = equations

    def _homotopy_switch(self) -> sp.Symbol:
        """The hidden Boolean ``$homotopy`` that selects the ``simplified`` expressions of
        ``homotopy()`` (made once per model). It keeps its value (``$homotopy = pre($homotopy)``,
        start false): only initialization sets it, for its first solve
        (:func:`acausal.runtime.initialization.initialize`)."""
        if self.homotopy_switch is None:
            symbol = self._hidden_variable("homotopy", "boolean", "")
            self.homotopy_switch = symbol.name
            origin = Origin("", "", "homotopy", 0, f"{symbol.name} = pre({symbol.name})")
            self.discrete_equations.append(DiscreteEquation(symbol.name, sp.Symbol(pre_name(symbol.name)),
                                                            origin))
        return sp.Symbol(self.homotopy_switch)

    def _hidden_variable(self, stem: str, kind: str, component: str) -> sp.Symbol:
        """A variable the engine introduces (a when-condition, a held value), named
        ``<component>.$<stem><n>`` so that messages name its component."""
        name = f"{component + '.' if component else ''}${stem}{self.hidden_count}"
        self.hidden_count += 1
        self.variables[name] = FlatVariable(
            name=name, kind=kind, start=0, fixed=False, nominal=1.0,
            state_select=StateSelect.prefer if kind == "discrete" else StateSelect(2), unit="",
            component=component)
        return real_symbol(name) if kind == "discrete" else sp.Symbol(name)

    def _add_when(self, when: When, origin: Origin) -> None:
        """A when-clause: each assigned variable becomes the discrete equation
        ``v = if fires_1 then e_1 elseif fires_2 then e_2 ... else pre(v)``.

        The right-hand sides are evaluated only at the events where the clause
        fires, so their relations generate no events of their own (as under
        ``noEvent``).  A condition ``c`` gets a hidden Boolean ``$when`` (= c); its element fires
        where it becomes true after initialization: ``$when and not pre($when) and
        not initial()``.  ``initial()`` itself fires during initialization.
        """
        component = origin.component
        assignments: dict[str, list] = {}
        branch_fires = []
        for conditions, items in when.branches:
            parts = []
            for condition in conditions:
                condition = self._expand(sp.sympify(condition))
                if condition == INITIAL:
                    parts.append(INITIAL)
                    continue
                hidden = self._hidden_variable("when", "boolean", component)
                self.discrete_equations.append(DiscreteEquation(hidden.name, condition, origin))
                parts.append(sp.And(hidden, sp.Not(sp.Symbol(pre_name(hidden.name))), sp.Not(INITIAL)))
            fires = sp.Or(*parts)
            branch_fires.append(fires)
            reinitialized: set[str] = set()
            for item in items:
                if isinstance(item, sp.Equality):
                    target = item.lhs
                    if not isinstance(target, sp.Symbol) or target.name not in self.variables:
                        raise EquationError(
                            f"{origin}: the when-equation {item} does not assign a variable",
                            hint="inside a when-clause write Eq(v, expression) with a declared "
                                 "variable v on the left")
                    assignments.setdefault(target.name, []).append((self._expand(NoEvent(item.rhs)), fires))
                elif isinstance(item, Reinit):
                    name = item.variable.name
                    if name not in self.variables or self.variables[name].kind != "continuous":
                        raise EquationError(
                            f"{origin}: reinit({name}) is not of a continuous variable",
                            hint="reinit applies to continuous states (variables that appear "
                                 "differentiated, der(x))", components=(component,))
                    if name in reinitialized:
                        raise EquationError(f"{origin}: {name} is reinitialized twice in one branch",
                                            hint="one reinit per state and when-clause",
                                            components=(component,))
                    reinitialized.add(name)
                    self.reinits.append(FlatReinit(name, self._at_events(item.value), fires, origin))
                elif isinstance(item, Terminate):
                    self.terminations.append(FlatTermination(item.message, fires, origin))
                elif isinstance(item, hybrid.Assert):
                    # checked where the clause fires: "not fires or condition"
                    self.asserts.append(FlatAssert(sp.Or(sp.Not(fires), self._at_events(item.condition)),
                                                   item.message, item.level, origin, fires))
                else:
                    raise EquationError(
                        f"{origin}: {item!r} cannot stand in a when-clause",
                        hint="a when-clause holds Eq(v, expression), reinit(x, value), "
                             "terminate(message) and Assert(...)")
        for name, pieces in assignments.items():
            earlier = self.when_assigned.get(name)
            if earlier is not None:
                raise ModelDefinitionError(
                    f"{name} is assigned in two when-clauses: {earlier} and {origin}",
                    hint="Modelica's single-assignment rule: a variable is assigned in one "
                         "when-clause; put both conditions in one clause (a list of conditions, "
                         "or elsewhen)", components=(component,))
            self.when_assigned[name] = origin
            variable = self.variables[name]
            if variable.kind == "continuous":
                # a Real assigned in a when-clause is a discrete Real (Modelica 3.8)
                self.variables[name] = dataclasses.replace(variable, kind="discrete")
            symbol = (real_symbol(name) if variable.kind in ("continuous", "discrete") else
                      sp.Symbol(name, integer=True) if variable.kind == "integer" else sp.Symbol(name))
            keep = sp.Symbol(pre_name(name), **symbol.assumptions0)
            self.discrete_equations.append(DiscreteEquation(
                name, sp.Piecewise(*pieces, (keep, True), evaluate=False), origin))

    def _at_events(self, expr: Any) -> sp.Basic:
        """An expression the runtime evaluates itself (a reinit's value, an assertion):
        expanded as under noEvent, and without the noEvent (partition never sees it)."""
        return hybrid.without_no_event(self._expand(NoEvent(sp.sympify(expr))))

    def _held_event_function(self, func: type, args: list) -> sp.Basic:
        """An event-generating function of continuous arguments, as values held between
        events (``floor`` is the one primitive; see :func:`_held_floor`)."""
        if func in (hybrid.floor, hybrid.integer):
            return self._held_floor(args[0])
        if func is hybrid.ceil:
            return -self._held_floor(-args[0])
        x, y = args
        quotient = x / y
        if func is hybrid.mod:
            return x - self._held_floor(quotient) * y
        # truncation toward zero: floor of |q| with the sign of q; at q = 0 both are 0
        truncated = NoEvent(sp.Piecewise((self._held_floor(quotient), quotient >= 0),
                                         (-self._held_floor(-quotient), True)))
        return truncated if func is hybrid.div else x - truncated * y

    def _held_floor(self, q: sp.Basic) -> sp.Basic:
        """``floor(q)`` held between events, with the two relations that end it.

        The hidden discrete Real ``h`` is ``floor(q)`` at initialization; at an
        event where ``q >= h + 1`` it steps up, where ``q < h`` it steps down, and
        otherwise it keeps its value.  (Reading the relations, not floor(q) alone,
        keeps a q one ulp short of the integer it just crossed from stepping back.)
        """
        if not q.has(time) and all(s.name in self.parameters for s in q.free_symbols):
            return sp.floor(q)  # of parameters only: a constant
        component = self.origin.component if self.origin is not None else ""
        held = self._hidden_variable("floor", "discrete", component)
        origin = self.origin or Origin(component, "", "floor", 0, f"floor({q})")
        self.discrete_equations.append(DiscreteEquation(held.name, sp.Piecewise(
            (sp.floor(q), INITIAL),
            (sp.Max(sp.floor(q), held + 1), q >= held + 1),
            (sp.Min(sp.floor(q), held - 1), q < held),
            (held, True), evaluate=False), origin))
        return held

    def _hold_discrete_reals(self) -> None:
        """``der(v) = 0`` for every discrete Real: the integrator carries its value
        between events, and the event iteration sets it."""
        assigned = {eq.variable for eq in self.discrete_equations}
        for name, variable in list(self.variables.items()):
            if variable.kind != "discrete":
                continue
            if name not in assigned:
                raise ModelDefinitionError(
                    f"discrete Real {name} is never assigned",
                    hint="assign it in a when-clause: When(condition, Eq(v, expression))",
                    components=(variable.component,))
            self.variables[name] = dataclasses.replace(variable, fixed=True)
            origin = Origin(variable.component, "", "discrete", 0, f"der({name}) = 0 (held between events)")
            self.equations.append(FlatEquation(real_symbol(der_name(name)), origin))
        # reinit only of states: of variables that appear differentiated
        differentiated = {parse(s.name).base for eq in self.equations for s in eq.residual.free_symbols
                          if parse(s.name).kind == "derivative"} if self.reinits else set()
        for item in self.reinits:
            if item.variable not in differentiated:
                raise EquationError(
                    f"{item.origin}: reinit({item.variable}): {item.variable} is not a state "
                    f"(der({item.variable}) appears in no equation)",
                    hint="reinit applies to continuous states only; reinitialize the state this "
                         "variable is computed from", components=(item.origin.component,))

    def _state_candidates(self) -> None:
        """A variable declared with ``state_select`` prefer or always that no
        equation differentiates gets the equation ``$der = der(v)`` (a hidden
        variable), so that it is a state candidate, as Dymola and OpenModelica
        take it: index reduction then differentiates what determines it, and
        state selection weighs it with the others."""
        memo: dict = {}
        differentiated = {parse(s.name).base for eq in self.equations
                          if self._per_template(eq, memo, _reads_derivatives)
                          for s in eq.residual.free_symbols if parse(s.name).kind == "derivative"}
        self.differentiated = differentiated
        for name, variable in list(self.variables.items()):
            if (variable.kind != "continuous" or name in differentiated
                    or variable.state_select < StateSelect.prefer):
                continue
            differentiated.add(name)
            hidden = self._hidden_variable("der", "continuous", variable.component)
            self.variables[hidden.name] = dataclasses.replace(self.variables[hidden.name],
                                                              state_select=StateSelect.never)
            origin = Origin(variable.component, "", "state_select", 0,
                            f"{hidden.name} = der({name}) ({name} has state_select="
                            f"{variable.state_select.name}: a state candidate)")
            self.equations.append(FlatEquation(real_symbol(hidden.name) - real_symbol(der_name(name)), origin))

    def _time_derivative(self, expr: sp.Basic) -> sp.Basic:
        result = sp.diff(expr, time) if expr.has(time) else sp.Integer(0)
        for sym in sorted(expr.free_symbols, key=lambda s: s.name):
            if sym is time or sym.name in self.parameters and sym.name not in self.unknown_parameters:
                continue
            if sym.name in self.variables and self.variables[sym.name].is_discrete:
                continue  # piecewise constant
            result += sp.diff(expr, sym) * real_symbol(der_name(sym.name))
        return result

    # -- connections ------------------------------------------------------------

    def _connect(self) -> None:
        parent: dict[tuple, tuple] = {}
        members: dict[tuple, dict] = {}  # element -> info
        order: list[tuple] = []
        position: dict[tuple, int] = {}  # element -> its index in order

        def find(x):
            while parent[x] != x:
                parent[x] = parent[parent[x]]
                x = parent[x]
            return x

        in_model = {id(c) for c in self.components}

        def element_of(end, owner: Component, statement: str):
            if isinstance(end, BoundConnector):
                if id(end.owner) not in in_model:
                    root = _root(end.owner)
                    name = type(root).__name__
                    raise ConnectorError(
                        f"{statement}: that {name} is not part of the model (created, but never "
                        f"stored as an attribute)",
                        hint=f"store the {name} as an attribute and connect that: "
                             f"self.{name[:1].lower()}{name[1:]} = {name}(...)",
                        components=(owner.path,))
                if not end.enabled:
                    raise ConnectorError(
                        f"{statement}: connector {end.path} is disabled",
                        hint=f"enable it ({_condition(end)}) or remove the connection")
                outside = end.owner is owner
                return ("physical", end.path, outside), end
            if isinstance(end, sp.Symbol) and end.name in self.signal_declarations:
                return ("signal", end.name, False), end
            if isinstance(end, sp.Symbol) and end.name in self.variables:
                raise ConnectorError(f"{statement}: {end.name} is a variable, not a connector",
                                       hint="connect() joins connectors or signal inputs and outputs")
            raise ConnectorError(f"{statement}: {end!r} is not a connector of this model",
                                   hint="connect connectors of components stored as attributes "
                                        "(self.name = ...); a disabled conditional connector cannot "
                                        "be connected")

        # every enabled physical connector is an 'inside' element, connected or not
        for component in self.components:
            for key, decl in self._declarations(component).items():
                if isinstance(decl, Connector) and decl.enabled(component):
                    bound = getattr(component, key)
                    el = ("physical", bound.path, False)
                    parent[el] = el
                    members[el] = bound
                    position[el] = len(order)
                    order.append(el)

        signal_edges: list[tuple[str, str, Component, str]] = []
        connect_text: dict[tuple, str] = {}
        for component in self.components:
            for a, b in component._connections:
                statement = (f"connect({_end_name(a, in_model)}, {_end_name(b, in_model)}) "
                             f"in {component.path or 'the model'}")
                ea, ba = element_of(a, component, statement)
                eb, bb = element_of(b, component, statement)
                if ea == eb:
                    raise ConnectorError(f"{statement}: connects {ea[1]} to itself",
                                           hint="a connection joins two different connectors; "
                                                "remove it or change one end",
                                           components=(component.path,))
                if ea[0] != eb[0]:
                    raise ConnectorError(f"{statement}: cannot connect a signal to a physical connector")
                if ea[0] == "signal":
                    signal_edges.append((ea[1], eb[1], component, statement))
                    continue
                fa, fb = type(ba.declaration).family, type(bb.declaration).family
                if fa != fb:
                    raise ConnectorError(
                        f"{statement}: {ba.path} is a {type(ba.declaration).__name__} ({fa}) but "
                        f"{bb.path} is a {type(bb.declaration).__name__} ({fb})",
                        hint="only connectors of the same kind can be connected")
                for el, bound in ((ea, ba), (eb, bb)):
                    if el not in parent:
                        parent[el] = el
                        members[el] = bound
                        position[el] = len(order)
                        order.append(el)
                ra, rb = find(ea), find(eb)
                if ra != rb:
                    # keep the earlier-declared element as root: deterministic
                    if position[rb] < position[ra]:
                        ra, rb = rb, ra
                    parent[rb] = ra
                connect_text[find(ea)] = statement

        sets: dict[tuple, list[tuple]] = {}
        for el in order:
            sets.setdefault(find(el), []).append(el)
        for root, elements in sets.items():
            bound0 = members[elements[0]]
            variables = self._connector_variables.get(type(bound0.declaration))
            if variables is None:
                variables = self._connector_variables[type(bound0.declaration)] = \
                    type(bound0.declaration).variables()
            if len(elements) == 1:
                for var_name, var in variables.items():
                    if isinstance(var, Flow) and not elements[0][2]:
                        name = f"{bound0.path}.{var_name}"
                        origin = Origin(bound0.owner.path, type(bound0.owner).__name__, "unconnected", 0,
                                        f"{name} = 0")
                        self.equations.append(FlatEquation(real_symbol(name), origin))
                continue
            text = " ~ ".join(f"{members[e].path}" for e in elements)
            for var_name, var in variables.items():
                symbols = [real_symbol(f"{members[e].path}.{var_name}") for e in elements]
                origin = Origin("", type(self.model).__name__, "connect", 0, "")
                if isinstance(var, Potential):
                    for sym in symbols[1:]:
                        self.equations.append(FlatEquation(
                            self._formed(("potential",), [sym, symbols[0]],
                                         lambda sym=sym, first=symbols[0]: sym - first),
                            Origin(origin.component, origin.component_class, "connect", 0,
                                   f"{sym.name} = {symbols[0].name}  [{text}]")))
                elif isinstance(var, Flow):
                    signs = tuple(-1 if e[2] else 1 for e in elements)
                    total = self._formed(("flow", signs), symbols, lambda signs=signs, symbols=symbols: sum(
                        (sign * s for sign, s in zip(signs, symbols)), sp.Integer(0)))
                    self.equations.append(FlatEquation(
                        total, Origin(origin.component, origin.component_class, "connect", 0,
                                      lambda total=total, text=text: f"0 = {total}  [{text}]")))

        # signals: connection sets with one driver each; every input must be connected
        connected_inputs = self._connect_signals(signal_edges)
        for name, (decl, component) in self.signal_declarations.items():
            if decl.causality == "input" and name not in connected_inputs and component is not self.model:
                # an input driven from inside its own component (hierarchical) is fine
                if self._assigned_inside(name):
                    continue
                raise ConnectorError(f"input {name} of {type(component).__name__} is not connected",
                                       hint=f"connect a signal source to {name}")

    def _formed(self, kind: tuple, symbols: list, build) -> sp.Basic:
        """``build()``, an expression of ``symbols`` (a connection equation of the given
        ``kind``), renamed without evaluation from the first one of its kind whose
        symbols' names sort alike (as equation templates are; checked at the first reuse)."""
        if self.templates is None or len(set(symbols)) != len(symbols) \
                or any(type(s) is not sp.Symbol for s in symbols):
            return build()
        names = [s.name for s in symbols]
        key = (kind, tuple(sorted(range(len(names)), key=names.__getitem__)))
        form = self._forms.get(key)
        if form is None:
            expr = build()
            try:
                program = _Program([expr], {s: i for i, s in enumerate(symbols)}, ())
            except _NotTemplatable:
                program = None
            self._forms[key] = [program, False]
            return expr
        program, verified = form
        if program is None:
            return build()
        renamed = program.run(symbols)[program.roots[0]]
        if not verified:
            expr = build()
            if sp.srepr(renamed) == sp.srepr(expr):
                form[1] = True
            else:
                form[0] = None
            return expr
        return renamed

    def _connect_signals(self, edges: list) -> set[str]:
        """Equations of the signal connections; returns the inputs that are driven by one.

        As in Modelica (spec 9.2), the signals joined by connect() form
        connection sets, and each set has exactly one driver.  Which end
        drives depends on where the connect() is written: an output of a
        component inside is a source and its input a sink, while the writing
        component's own connectors act the other way round (its input feeds
        what is inside, its output is fed from inside).  A composite's input
        or output is thus a sink on one side and a source on the other; the
        driver is the member that is never a sink.  Every other member equals
        the driver: a continuous equation for Reals, a discrete one for
        Boolean and Integer signals.
        """
        parent: dict[str, str] = {}
        order: list[str] = []
        sink: set[str] = set()
        statements: dict[str, str] = {}

        def find(x: str) -> str:
            while parent[x] != x:
                parent[x] = parent[parent[x]]
                x = parent[x]
            return x

        for a, b, owner, statement in edges:
            for name in (a, b):
                if name not in parent:
                    parent[name] = name
                    order.append(name)
                    statements[name] = statement
                decl, component = self.signal_declarations[name]
                own = component is owner
                if (decl.causality == "input") != own:
                    sink.add(name)
            parent[find(a)] = find(b)
            va, vb = self.variables[a], self.variables[b]
            if (va.is_discrete or vb.is_discrete) and va.kind != vb.kind:
                raise ConnectorError(f"{statement}: a {va.kind} signal cannot be connected to a "
                                       f"{vb.kind} one", hint="convert it with a block (e.g. "
                                                              "BooleanToReal) first")
        sets: dict[str, list[str]] = {}
        for name in order:
            sets.setdefault(find(name), []).append(name)
        for members in sets.values():
            drivers = [m for m in members if m not in sink]
            if len(drivers) > 1:
                raise ConnectorError(f"{statements[drivers[1]]}: {' and '.join(drivers[:2])} both drive "
                                       f"one connection set (two outputs cannot be connected)",
                                       hint="connect an output to one or more inputs")
            if not drivers:
                continue  # no driver: its inputs are reported as not connected below
            source = drivers[0]
            for target in members:
                if target == source:
                    continue
                origin = Origin("", type(self.model).__name__, "connect", 0, f"{target} = {source}")
                if self.variables[source].is_discrete:
                    kind = self.variables[source].kind
                    value = sp.Symbol(source, integer=True) if kind == "integer" else sp.Symbol(source)
                    self.discrete_equations.append(DiscreteEquation(target, value, origin))
                else:
                    self.equations.append(FlatEquation(real_symbol(target) - real_symbol(source), origin))
        return {name for members in sets.values() if any(m not in sink for m in members)
                for name in members if name in sink}

    def _assigned_inside(self, name: str) -> bool:
        """Whether an equation of an enclosing component (not a connection, not the input's own
        component) gives the input ``name`` its value: a Real input in an equation, a Boolean or
        Integer one (a symbol of another kind: matched by name) also in a discrete equation."""
        owner = name.rpartition(".")[0]
        for eq in self.equations:
            if eq.origin.declared_in != "connect" and eq.origin.component != owner \
                    and any(s.name == name for s in eq.residual.free_symbols):
                return True
        return any(getattr(eq, "variable", None) == name and eq.origin.component != owner
                   for eq in self.discrete_equations)


def _condition(end: BoundConnector) -> str:
    cond = end.declaration.condition
    return f"{cond}=True" if isinstance(cond, str) else "its condition"


def _end_name(end, in_model: set[int] | frozenset[int] = frozenset()) -> str:
    """How a connect() statement names an end; ``<Class>.path`` for a connector of a
    component whose id is not in ``in_model`` (not stored in the model)."""
    if isinstance(end, BoundConnector):
        if in_model and id(end.owner) not in in_model:
            return f"<{type(_root(end.owner)).__name__}>.{end.path}"
        return end.path
    if isinstance(end, sp.Symbol):
        return end.name
    return repr(end)


def _text(item: Any) -> str:
    if isinstance(item, sp.Equality):
        return f"{item.lhs} = {item.rhs}"
    return f"0 = {item}" if isinstance(item, sp.Basic) else repr(item)


def _root(component: Component) -> Component:
    """The top of the tree ``component`` belongs to."""
    while component._parent is not None:
        component = component._parent
    return component


def _first_non_finite(value: Any) -> tuple[str, Any] | None:
    """``(index, entry)`` of the first nan or inf in a number ('' index) or a numeric
    list/array (``[i][j]``); None if there is none or the value is not numeric."""
    if isinstance(value, (float, np.floating)):
        return None if math.isfinite(value) else ("", value)
    if isinstance(value, (list, tuple, np.ndarray)):
        try:
            data = np.asarray(value)
        except (TypeError, ValueError):  # ragged or not numeric: not a table
            return None
        if data.dtype.kind not in "fc":
            return None
        bad = np.argwhere(~np.isfinite(data))
        if bad.size:
            index = tuple(int(i) for i in bad[0])
            return "".join(f"[{i}]" for i in index), data[index].item()
    return None


def _check_finite(path: str, value: Any, component: Component, key: str, binding: Any = None) -> None:
    """ParameterError for a parameter value (or table entry) that is nan or infinite."""
    found = _first_non_finite(value)
    if found is None:
        return
    index, entry = found
    where = f"{type(component).__name__}.{key}"
    if index:
        message = f"parameter {path} has the non-finite entry {entry} at {key}{index}"
    elif isinstance(binding, sp.Basic) and not binding.is_number:
        message = f"parameter {path} = {binding} evaluates to {entry}, not a finite number"
    else:
        message = f"parameter {path} = {entry} is not a finite number"
    raise ParameterError(message,
                         hint=f"give {where} {'finite entries' if index else 'a finite value'} (a "
                              f"declaration that accepts nan or inf says Parameter(..., finite=False))",
                         components=(component.path,))


def _check_finite_attribute(path: str, attribute: str, value: Any, given: Any,
                            component: Component, key: str | None) -> None:
    """ParameterError for a start or nominal value that is nan or infinite."""
    if not isinstance(value, (float, np.floating)) or math.isfinite(value):
        return
    as_given = f" ({given})" if isinstance(given, sp.Basic) and not given.is_number else ""
    example = (f"{type(component).__name__}({key}=dict({attribute}=...))" if key
               else f"a finite {attribute} in the declaration of {path.rpartition('.')[2]}")
    raise ParameterError(f"{attribute} value of {path} is {value}{as_given}, not a finite number",
                         hint=f"give it a finite {attribute}: {example}",
                         components=(component.path,))


def _start_value(variable: str, value: Any) -> float:
    """A start value given at run time as a float: ParameterError for anything but a finite number."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise ParameterError(f"the start value of {variable} must be a number, not {value!r}",
                             hint=f"e.g. start={{{variable!r}: 1.5}}", components=(variable.rpartition(".")[0],))
    if not math.isfinite(value):
        raise ParameterError(f"the start value of {variable} is {float(value)}, not a finite number",
                             hint="start values must be finite numbers", components=(variable.rpartition(".")[0],))
    return float(value)


def check_start_values(flat: FlatModel, starts: Mapping[str, Any]) -> dict[str, float]:
    """``starts`` (variable name -> value) checked against ``flat``'s tunable start values.

    Returns
    -------
    dict
        The values as floats.

    Raises
    ------
    ParameterError
        For a name that is not a variable of ``flat`` (with the names it may
        mean), a variable whose start is not tunable
        (:attr:`FlatModel.tunable_starts`: neither a state candidate nor
        fixed, or a Boolean or Integer), and a value that is not a finite number.
    """
    _check_start_names(flat.name, flat.variable_map, flat.tunable_starts, starts,
                       {p.name for p in flat.parameters})
    return {name: _start_value(name, value) for name, value in starts.items()}


def tunable_starts_of(flat: FlatModel, variables: Sequence[FlatVariable],
                      overrides: Mapping[str, Any] = ()) -> tuple[tuple[float, ...], bool]:
    """The tunable start values of another flattening of ``flat``'s model, without its equations.

    Parameters
    ----------
    flat : FlatModel
        The model as translated.
    variables : sequence of FlatVariable
        The declared variables of the model flattened for other values
        (parameter values and start values, ``overrides``), e.g. by a sweep
        that does not flatten every run's equations (hidden variables, which
        only the equations make, are missing).
    overrides : mapping
        The values given for that flattening: their names ``<variable>.start``
        are checked (:func:`check_start_values`).

    Returns
    -------
    starts : tuple of float
        The start values of ``flat.tunable_starts``, in that order.
    other : bool
        Whether ``variables`` differ from ``flat``'s in anything but those
        start values (then the model has other attributes, and needs a
        translation of its own).
    """
    check_start_values(flat, {name[:-len(START)]: value for name, value in dict(overrides).items()
                              if name.endswith(START) and name not in flat.parameter_values})
    known = flat.variable_map
    tunable = set(flat.tunable_starts)
    found: dict[str, float] = {}
    other = False
    for variable in variables:
        mine = known.get(variable.name)
        if variable == mine:
            continue
        if mine is None:
            other = True
        elif variable.name in tunable and dataclasses.replace(variable, start=mine.start) == mine:
            found[variable.name] = variable.start
        else:
            other = True
    return tuple(found.get(n, known[n].start) for n in flat.tunable_starts), other


def _check_start_names(model: str, variables: Mapping[str, FlatVariable], tunable: Sequence[str],
                       names, parameters) -> None:
    """ParameterError for the first of ``names`` (variables) whose start value is not tunable."""
    if not names:
        return
    tunable_set = set(tunable)
    for name in names:
        if name in tunable_set:
            continue
        owner = name.rpartition(".")[0]
        variable = variables.get(name)
        if variable is None or "$" in name:
            import difflib

            if name in parameters:
                raise ParameterError(f"{name} is a parameter of {model}, not a variable: it has no start value",
                                     hint=f"set its value with parameters={{{name!r}: value}} "
                                          f"(--param {name}=VALUE)", components=(owner,))
            close = difflib.get_close_matches(name, sorted(tunable_set), n=3) or \
                difflib.get_close_matches(name, sorted(n for n in variables if "$" not in n), n=3)
            raise ParameterError(f"{model} has no variable {name!r} whose start value could be set",
                                 hint=f"did you mean {', '.join(close)}?" if close else
                                 "start values are named by the variable's dotted path, e.g. component.variable",
                                 components=(owner,))
        member = name.rpartition(".")[2]
        if variable.is_discrete:
            why = (f"{name} is {'a Boolean' if variable.kind == 'boolean' else 'an Integer'}: its start "
                   f"value decides the first discrete state")
        else:
            why = (f"{name} is neither fixed nor a state (no equation differentiates it): its start is at "
                   f"most the first guess of an iteration, part of the translated model")
        # the component's own tunable starts first, then the names closest to the one given
        import difflib

        nearby = [n for n in tunable if n.rpartition(".")[0] == owner]
        nearby += [n for n in difflib.get_close_matches(name, sorted(tunable_set), n=4) if n not in nearby]
        examples = ", ".join(nearby[:4] or sorted(tunable_set)[:4]) or "none"
        raise ParameterError(f"the start value of {name} cannot be set at run time: {why}",
                             hint=f"give it where the component is created, e.g. {member}=dict(start=value) "
                                  f"(a new translation); the start values {model} takes at run time are "
                                  f"those of its states and fixed variables, e.g. {examples}",
                             components=(owner,))


#: Folders whose frames are not the user's: the standard library, installed packages, the engine.
_NOT_USER_CODE = tuple(str(Path(p).resolve()) + os.sep for p in {
    *(sysconfig.get_paths().get(k) for k in ("stdlib", "platstdlib", "purelib", "platlib")),
    str(Path(__file__).resolve().parents[1])} if p)


def _user_frame(exc: BaseException) -> traceback.FrameSummary | None:
    """The deepest frame of the user's code in the traceback of an exception raised
    inside a call made by flatten (the first frame below flatten's, if none is)."""
    frames = traceback.extract_tb(exc.__traceback__)[1:]
    for frame in reversed(frames):
        try:
            filename = str(Path(frame.filename).resolve())
        except (OSError, ValueError):
            continue
        if not filename.startswith(_NOT_USER_CODE) and not frame.filename.startswith("<frozen"):
            return frame
    return frames[0] if frames else None


def _scalar_items(items) -> list:
    """``equations()``'s items with the lists an array equation makes spliced in, in order."""
    if not any(isinstance(item, (list, tuple)) for item in items):
        return list(items)
    out: list = []
    for item in items:
        if isinstance(item, (list, tuple)):
            out.extend(_scalar_items(item))
        else:
            out.append(item)
    return out


def _equations_failed(exc: Exception, component: Component, klass: type, method_name: str) -> EquationError:
    """The EquationError for an exception raised while calling ``klass.<method_name>``."""
    name = type(component).__name__
    of = name if klass.__name__ == name else f"{name}, in {klass.__name__}"
    frame = _user_frame(exc)
    at = ""
    if frame is not None:
        at = f"\n  at {frame.filename}:{frame.lineno}" + (f": {frame.line}" if frame.line else "")
    if isinstance(exc, TypeError) and "truth value" in str(exc):
        hint = ("a Python if/and/or/not on a symbolic condition cannot be decided when the equations "
                "are collected; write If(condition, a, b) or sympy.And/Or/Not")
    else:
        hint = "use sympy functions (sympy.sin, sympy.exp, ...) on symbols, not math/numpy ones"
    return EquationError(f"{method_name}() of {component.path or 'the model'} ({of}) raised "
                         f"{type(exc).__name__}: {exc}{at}",
                         hint=hint, components=(component.path,))


# --------------------------------------------------------------------------
# Equation templates
#
# A large model repeats a few component classes many times (a drive train of
# N units has N inertias, N bearings and N - 1 spring-dampers).  Calling
# ``equations()`` of every instance builds the same expressions again and
# again through sympy's automatic evaluation and assumption queries, and
# expands der() by the chain rule each time.  Instead, the first instance of
# a class (in a given structural configuration) is flattened as usual and its
# result kept as a *template*; a further instance gets the template's
# expressions with its own symbols put in, rebuilt node by node without any
# evaluation.  The rule for when a template applies is in _Template's docstring.


class _NotTemplatable(Exception):
    """Raised while making a template: this result cannot be renamed safely."""


#: The instance attributes every Component has; the rest (set by a constructor or
#: build()) is part of the template key.
_FRAMEWORK_ATTRIBUTES = frozenset({"_name", "_parent", "_children", "_connections", "_built",
                                   "_modifiers", "_attribute_modifiers"})

#: How many templates one key may have (one per order of the names, see _Template).
_MAX_VARIANTS = 4

_MISSING = object()


def _freeze(value: Any) -> Any:
    """A hashable stand-in for ``value`` that is equal for equal values of the same type.

    Raises _NotTemplatable for a value it cannot compare safely.
    """
    if value is None or isinstance(value, (bool, int, float, complex, str, bytes)):
        return (type(value), value)
    if isinstance(value, (tuple, list)):
        return (type(value), tuple(_freeze(v) for v in value))
    if isinstance(value, (set, frozenset)):
        return (type(value), frozenset(_freeze(v) for v in value))
    if isinstance(value, dict):
        return (type(value), tuple((_freeze(k), _freeze(v)) for k, v in value.items()))
    if isinstance(value, np.ndarray):
        if value.dtype.hasobject:
            raise _NotTemplatable("an object array")
        return (np.ndarray, value.dtype.str, value.shape, value.tobytes())
    if isinstance(value, np.generic):
        return (type(value), value.item())
    if isinstance(value, enum.Enum):
        return (type(value), value)
    if isinstance(value, sp.Basic):
        return (sp.Basic, sp.srepr(value))
    if isinstance(value, (type, types.FunctionType, types.BuiltinFunctionType, types.MethodType,
                          functools.partial)):
        return ("object", id(value))  # the same object (they are alive during flattening)
    raise _NotTemplatable(f"a {type(value).__name__}")


class _RecordingDict(dict):
    """A component's modifier dictionary that records how it is read.

    While the first instance of a template key runs its ``equations()``, the
    component's ``_modifiers`` and ``_attribute_modifiers`` are replaced by
    these: every access by key is recorded in ``read``, any access to the
    whole (iteration, length, copies, comparison) sets ``everything``, and
    any change sets ``changed`` (and ``everything``).
    """

    def __init__(self, data) -> None:
        super().__init__(data)
        self.read: set = set()
        self.everything = False
        self.changed = False

    def __getitem__(self, key):
        self.read.add(key)
        return dict.__getitem__(self, key)

    def get(self, key, default=None):
        self.read.add(key)
        return dict.get(self, key, default)

    def __contains__(self, key):
        self.read.add(key)
        return dict.__contains__(self, key)

    __hash__ = None


def _recording(name: str, changes: bool):
    method = getattr(dict, name)

    def recorded(self, *args, **kwargs):
        self.everything = True
        if changes:
            self.changed = True
        return method(self, *args, **kwargs)

    recorded.__name__ = name
    return recorded


for _name in ("__iter__", "__len__", "__reversed__", "keys", "values", "items", "copy", "__eq__", "__ne__",
              "__repr__", "__or__", "__ror__", "__reduce__", "__reduce_ex__"):
    setattr(_RecordingDict, _name, _recording(_name, changes=False))
for _name in ("__setitem__", "__delitem__", "setdefault", "pop", "popitem", "update", "clear", "__ior__"):
    setattr(_RecordingDict, _name, _recording(_name, changes=True))
del _name


#: The slots every sympy object has; the others (``is_commutative``) are copied.
_BASIC_SLOTS = frozenset({"_mhash", "_args", "_assumptions", "__dict__", "__weakref__"})

#: class -> its own slot descriptors (beyond _BASIC_SLOTS)
_SLOT_DESCRIPTORS: dict[type, tuple] = {}

_basic_new = sp.Basic.__new__


class _ParentGuard:
    """Stands for a component's parent while the component's equations are recorded.

    It gives the parent's ``path`` (the component's own path is made from it);
    reading anything else of it is passed on to the parent and recorded in
    ``_touched``: those equations depend on more than the component.
    """

    __slots__ = ("_target", "_touched")

    def __init__(self, target) -> None:
        object.__setattr__(self, "_target", target)
        object.__setattr__(self, "_touched", False)

    @property
    def path(self) -> str:
        return self._target.path

    @property
    def __class__(self):  # isinstance() sees the parent's class
        return type(self._target)

    def __getattr__(self, name: str):
        object.__setattr__(self, "_touched", True)
        return getattr(self._target, name)

    def __setattr__(self, name: str, value) -> None:
        object.__setattr__(self, "_touched", True)
        setattr(self._target, name, value)


def _slot_descriptors(klass: type) -> tuple:
    found = _SLOT_DESCRIPTORS.get(klass)
    if found is None:
        found = []
        for base in klass.__mro__:
            names = vars(base).get("__slots__", ())
            for name in (names,) if isinstance(names, str) else names:
                if name not in _BASIC_SLOTS:
                    found.append(vars(base)[name])
        found = _SLOT_DESCRIPTORS[klass] = tuple(found)
    return found


def _model_function_name_ok(klass: type, forbidden_names: tuple) -> bool:
    """False for a class made by the model (not sympy's own: an undefined function, a table)
    whose name contains one of ``forbidden_names`` (the instance's path or name)."""
    module = getattr(klass, "__module__", None) or ""
    if module.startswith("sympy.") and not isinstance(klass, UndefinedFunction):
        return True
    return not any(name in klass.__name__ for name in forbidden_names)


def _symbol_constructor_assumptions(symbol: sp.Symbol) -> dict:
    """The assumptions ``symbol`` was created with (so that the same cached symbol results)."""
    original = getattr(symbol, "_assumptions_orig", None)
    return dict(original) if original is not None else dict(symbol.assumptions0)


class _Program:
    """Straight-line instructions rebuilding some expressions from new symbols.

    ``symbol_slots`` numbers the symbols of ``roots``; :meth:`run` takes the
    new symbols in that order.  ``values`` holds them, then the template's
    other leaves (numbers: the same objects for every instance), then one
    entry per node; each step creates one node of the template with its
    arguments taken from ``values``, exactly as the template's node was (same
    class, arguments in the same order, same slot values), without calling
    the class's constructor, so without any evaluation or assumption query.
    Subexpressions shared in the template are shared in the result.
    """

    def __init__(self, roots, symbol_slots: dict, forbidden_names: tuple) -> None:
        self.values: list = [None] * len(symbol_slots)
        self.steps: list[tuple] = []
        memo: dict[int, int] = {}  # id of a node (alive in roots while compiling) -> its entry
        self.roots = [self._compile(root, memo, symbol_slots, forbidden_names) for root in roots]

    def _compile(self, node, memo, symbol_slots, forbidden_names) -> int:
        key = id(node)
        found = memo.get(key)
        if found is not None:
            return found
        if not isinstance(node, sp.Basic):
            raise _NotTemplatable(f"a {type(node).__name__} in an expression")
        if not node.args:
            if type(node) is sp.Symbol:
                slot = symbol_slots.get(node)
                if slot is None:
                    raise _NotTemplatable(f"the symbol {node.name}")
                memo[key] = slot
                return slot
            if isinstance(node, sp.Symbol) or not (
                    isinstance(node, sp.logic.boolalg.BooleanAtom) or node.is_number is True
                    or isinstance(node, sp.Function) and _model_function_name_ok(type(node), forbidden_names)):
                raise _NotTemplatable(f"the atom {node!r}")
            self.values.append(node)  # the same object in every instance: it has no symbols
            memo[key] = slot = len(self.values) - 1
            return slot
        klass = type(node)
        if not _model_function_name_ok(klass, forbidden_names):
            raise _NotTemplatable(f"the function {klass.__name__} named after the instance")
        args = tuple(self._compile(a, memo, symbol_slots, forbidden_names) for a in node.args)
        slots = []
        for descriptor in _slot_descriptors(klass):
            try:
                value = descriptor.__get__(node, klass)
            except AttributeError:
                continue
            if value is not None and not isinstance(value, bool):
                raise _NotTemplatable(f"slot {descriptor!r} of {klass.__name__}")
            slots.append((descriptor, value))
        attributes = {}
        argset = False
        for name, value in getattr(node, "__dict__", {}).items():
            if name == "_argset" and value == frozenset(node.args):
                argset = True
            elif name == "nargs" and isinstance(value, sp.Basic) and not value.free_symbols:
                attributes[name] = value
            else:
                raise _NotTemplatable(f"attribute {name} of {klass.__name__}")
        self.values.append(None)
        slot = len(self.values) - 1
        self.steps.append((slot, klass, args, tuple(slots), attributes, argset))
        memo[key] = slot
        return slot

    def run(self, symbols: list) -> list:
        values = self.values.copy()
        values[:len(symbols)] = symbols
        new = _basic_new
        for slot, klass, args, slots, attributes, argset in self.steps:
            arguments = [values[i] for i in args]
            node = new(klass, *arguments)
            for descriptor, value in slots:
                descriptor.__set__(node, value)
            if attributes or argset:
                state = node.__dict__
                state.update(attributes)
                if argset:
                    state["_argset"] = frozenset(arguments)
            values[slot] = node
        return values


def _reads_derivatives(expr: sp.Basic) -> bool:
    """Whether ``expr`` reads a derivative ``der(x)``."""
    return any(parse(s.name).kind == "derivative" for s in expr.free_symbols)


class _Source:
    """The source of a templated equation's Origin: its text, printed on demand."""

    __slots__ = ("template", "symbols", "entry")

    def __init__(self, template: "_Template", symbols: list, entry: int) -> None:
        self.template = template
        self.symbols = symbols
        self.entry = entry

    def expression(self) -> Any:
        """The equation as the instance's equations() wrote it."""
        template = self.template
        root = template.source_roots[self.entry]
        if root is None:
            return template.source_constants[self.entry]
        return template.sources.run(self.symbols)[template.sources.roots[root]]

    def __call__(self) -> str:
        return _text(self.expression())

    def __reduce__(self):  # a copy (pickle, deepcopy) keeps the text
        return (str, (self(),))


class _Renaming:
    """The symbols in some expressions of one component instance, and how to name another's.

    Every symbol must be the instance's own (a variable or parameter under its
    path, or ``der()``/``pre()`` of one) or ``time`` or ``initial()``.  Slots
    are numbered in a fixed order; :meth:`symbols_for` gives another
    instance's symbols in the same slots, or None if its names do not sort as
    these do (ties included) or are not declared alike.
    """

    def __init__(self, flattener: "_Flattener", component: Component, expressions: list) -> None:
        path = component.path
        prefix = path + "."
        symbols: set = set()
        for expr in expressions:
            symbols |= expr.atoms(sp.Symbol)
        constants = {time: None, INITIAL: None}
        renamed = sorted((s for s in symbols if s not in constants), key=lambda s: (s.name, str(s.assumptions0)))
        fixed = sorted((s for s in symbols if s in constants), key=lambda s: s.name)
        self.parts: list[tuple] = []  # (head, tail, constructor assumptions) or (None, symbol, None)
        self.checks: list[tuple[int, tuple]] = []  # (slot, how the name is declared)
        for slot, symbol in enumerate(renamed):
            if type(symbol) is not sp.Symbol:
                raise _NotTemplatable(f"the {type(symbol).__name__} {symbol}")
            name = symbol.name
            what = parse(name)
            if what.kind not in ("variable", "derivative", "pre") or not what.base.startswith(prefix):
                raise _NotTemplatable(f"the symbol {name} is not {path}'s")
            at = name.find(what.base)
            self.parts.append((name[:at], name[at + len(path):], _symbol_constructor_assumptions(symbol)))
            if what.kind == "variable":
                self.checks.append((slot, flattener._declared_as(name)))
        for symbol in fixed:
            self.parts.append((None, symbol, None))
        names = [s.name for s in renamed + fixed]
        order = sorted(range(len(names)), key=names.__getitem__)
        self.order = [(a, b, names[a] == names[b]) for a, b in zip(order, order[1:])]
        self.slot_of_name: dict[str, int] = {}
        for slot, name in enumerate(names):
            self.slot_of_name.setdefault(name, slot)
        self.slots = {s: i for i, s in enumerate(renamed + fixed)}
        #: function classes named after the instance cannot be renamed
        self.forbidden = tuple({re.sub(r"[^0-9A-Za-z_]", "_", path), component.name})

    def symbols_for(self, flattener: "_Flattener", path: str) -> list | None:
        names = [tail.name if head is None else head + path + tail for head, tail, _ in self.parts]
        for a, b, equal in self.order:
            if (names[a] != names[b]) if equal else not names[a] < names[b]:
                return None
        for slot, declared in self.checks:
            if flattener._declared_as(names[slot]) != declared:
                return None
        return [tail if head is None else _symbol(name, assumptions)
                for (head, tail, assumptions), name in zip(self.parts, names)]


def _symbol(name: str, assumptions: dict) -> sp.Symbol:
    """``sympy.Symbol(name, **assumptions)`` for assumptions sympy has already checked."""
    if assumptions == _REAL_ASSUMPTIONS:  # a continuous quantity: from the unbounded memo
        return real_symbol(name)
    if _new_symbol is None:
        return sp.Symbol(name, **assumptions)
    return _new_symbol(sp.Symbol, name, **assumptions)


#: The constructor assumptions of a real symbol (``real_symbol``'s).
_REAL_ASSUMPTIONS = _symbol_constructor_assumptions(real_symbol("_"))


#: Symbol's cached constructor without the check of the assumptions (private to sympy: if it
#: is not there, Symbol() is used)
_new_symbol = getattr(sp.Symbol, "_Symbol__xnew_cached_", None)


class _ValueTemplate:
    """A computed attribute (``Variable(nominal=function)``) of one instance, for another.

    The function is called with the first instance of a template key (recorded
    as equations() are, see :class:`_Template`); its value (a number, or an
    expression of the instance's parameters) serves the further instances of
    the key, renamed, under the same rules as equations, with the same check
    at the first reuse.  ``numbers`` keeps what the expression evaluated to,
    by the values of its symbols.
    """

    def __init__(self, flattener: "_Flattener", component: Component, value: Any) -> None:
        self.verified = False
        self.numbers: dict[tuple, float] = {}
        if isinstance(value, sp.Basic):
            self.plain = None
            self.renaming = _Renaming(flattener, component, [value])
            self.program = _Program([value], self.renaming.slots, self.renaming.forbidden)
        elif value is None or type(value) in (bool, int, float, str) or isinstance(value, enum.Enum):
            self.plain = value
            self.renaming = None
        else:
            raise _NotTemplatable(f"a {type(value).__name__}")

    def symbols_for(self, flattener: "_Flattener", path: str) -> list | None:
        return [] if self.renaming is None else self.renaming.symbols_for(flattener, path)

    def build(self, symbols: list) -> Any:
        if self.renaming is None:
            return self.plain
        return self.program.run(symbols)[self.program.roots[0]]

    def agrees(self, value: Any, symbols: list) -> bool:
        built = self.build(symbols)
        if isinstance(value, sp.Basic) or isinstance(built, sp.Basic):
            return isinstance(value, sp.Basic) and isinstance(built, sp.Basic) and \
                sp.srepr(value) == sp.srepr(built)
        return type(value) is type(built) and value == built


class _Template:
    """The flattened equations of one component instance, ready to be given to another.

    **The rule.**  The equations of instance B are those of instance A with A's
    symbols renamed to B's (``A.x`` -> ``B.x``, ``der(A.x)`` -> ``der(B.x)``) when

    1. **A and B have the same template key** (:meth:`_Flattener._template_key`):
       both are leaves (no sub-components, no connections of their own) of the
       same class, with equal values of every structural parameter, the same
       conditional declarations enabled, and equal values of every other
       attribute set on the instance (by its constructor or ``build()``; an
       attribute whose value cannot be compared, such as another component,
       gives no key).  Numeric parameters are symbols in the equations and are
       not part of the key.  Instead, A's ``equations()`` run with A's modifier
       dictionaries recording what is read (:class:`_RecordingDict`) and A's
       parent replaced by a :class:`_ParentGuard`: the key gets no template if
       they read any modifier but a structural parameter's (``parameter_binding``),
       a variable attribute (``attribute``), the modifiers as a whole, or
       anything of the parent but its path (``self._parent.gain``).
    2. **A's result can be renamed**: every symbol in it (residuals, discrete
       right-hand sides, the equations as written) is A's own (a variable,
       parameter, ``der()`` or ``pre()`` of one under A's path) or ``time`` or
       ``initial()``; every other leaf is a number; no function class is named
       after A (a table with two rows or more is: such a key gets no
       template); no node carries state that cannot be copied.
    3. **The names sort alike**: sympy orders the arguments of sums, products
       and ``And``/``Or`` by comparing names, and decides some canonical forms
       by that order (which sign a sum keeps), so B's names must sort in the
       same order, ties included, as A's.  ``time`` sorts after ``bearing1.w``
       but before ``spring1.w``: a key keeps up to _MAX_VARIANTS templates,
       one per order met.
    4. **Each template is checked once**: the first instance it would serve is
       built both ways, and the template is used only if the renamed result is
       identical (``srepr``) to what ``equations()`` returns (residuals,
       discrete equations, equations as written, origins).  This catches what
       1-3 cannot see, such as equations reading a global variable, as far as
       that instance differs.  If they differ, the key builds every instance
       directly.
    5. B's renamed symbols must be declared the same way as A's (variable or
       parameter, its kind, fixed or not); otherwise B is built directly (and
       any error is raised as usual).

    What remains assumed: ``equations()`` is a function of the component (its
    declarations, modifiers, attributes and path), as the language defines it,
    not of state elsewhere (a global counter, a closure) that happens to
    agree for A and the instance checked under 4.

    **The renaming** creates each node with ``Basic.__new__`` and the template
    node's arguments and slots (:class:`_Program`): no evaluation and no
    assumption query, and, under 3, the same canonical form as sympy's
    evaluation gives B's equations.  The equations as written
    (``Origin.source``) are rebuilt only when their text is asked for
    (:class:`_Source`).  Computed variable attributes (``nominal=function``)
    follow the same rule (:class:`_ValueTemplate`), and so do the connection
    equations, by the signs and the order of their names (:meth:`_Flattener._formed`).
    """

    def __init__(self, flattener: "_Flattener", component: Component, equations: list, initial: list,
                 discrete: list) -> None:
        self.verified = False
        self.path = component.path
        self.component_class = type(component).__name__
        roots, source_items = [], []
        #: (declared_in, index, root, source): root and source number the expressions below
        self.equation_entries: list[tuple] = []
        self.initial_entries: list[tuple] = []
        #: (declared_in, index, variable name, root, source)
        self.discrete_entries: list[tuple] = []
        for entries, items in ((self.equation_entries, equations), (self.initial_entries, initial)):
            for eq in items:
                entries.append((eq.origin.declared_in, eq.origin.index, len(roots), len(source_items)))
                roots.append(eq.residual)
                source_items.append(eq.origin.source)
        for eq in discrete:
            self.discrete_entries.append((eq.origin.declared_in, eq.origin.index, eq.variable, len(roots),
                                          len(source_items)))
            roots.append(eq.rhs)
            source_items.append(eq.origin.source)
        for item in source_items:
            if not (isinstance(item, sp.Basic) or type(item) in (int, float)):
                raise _NotTemplatable(f"the equation {item!r}")

        self.renaming = renaming = _Renaming(flattener, component, roots + [
            s for s in source_items if isinstance(s, sp.Basic)])
        #: discrete variable name -> the slot of a symbol of that name
        self.variables = {eq.variable: renaming.slot_of_name[eq.variable] for eq in discrete}

        slots, forbidden = renaming.slots, renaming.forbidden
        self.main = _Program(roots, slots, forbidden)
        #: the slots of each root's free symbols (partition reads them instead of walking the tree)
        self.free_slots = [sorted(slots[s] for s in root.free_symbols) for root in roots]
        self.sources = _Program([s for s in source_items if isinstance(s, sp.Basic)], slots, forbidden)
        self.source_roots: list[int | None] = []
        self.source_constants: list = []
        k = 0
        for item in source_items:
            if isinstance(item, sp.Basic):
                self.source_roots.append(k)
                self.source_constants.append(None)
                k += 1
            else:
                self.source_roots.append(None)
                self.source_constants.append(item)

    @classmethod
    def make(cls, flattener: "_Flattener", component: Component, start: tuple, reads: set | None,
             structural: frozenset) -> "_Template | None":
        """The template of ``component``'s equations, just flattened (from ``start``), or None."""
        if reads is None or not reads <= structural:
            return None
        try:
            return cls(flattener, component, flattener.equations[start[0]:],
                       flattener.initial_equations[start[1]:], flattener.discrete_equations[start[2]:])
        except _NotTemplatable:
            return None

    def symbols_for(self, flattener: "_Flattener", path: str) -> list | None:
        """The symbols of the instance at ``path`` in slot order, or None if this template
        does not apply to it (rules 3 and 5)."""
        return self.renaming.symbols_for(flattener, path)

    def build(self, path: str, symbols: list) -> tuple[list, list, list]:
        """``(equations, initial equations, discrete equations)`` of the instance at ``path``."""
        values = self.main.run(symbols)
        roots = self.main.roots
        klass = self.component_class
        out: tuple[list, list, list] = ([], [], [])
        for target, entries in ((out[0], self.equation_entries), (out[1], self.initial_entries)):
            for declared_in, index, root, source in entries:
                target.append(FlatEquation(values[roots[root]], Origin(path, klass, declared_in, index,
                                                                       _Source(self, symbols, source))))
        for declared_in, index, variable, root, source in self.discrete_entries:
            out[2].append(DiscreteEquation(symbols[self.variables[variable]].name, values[roots[root]],
                                           Origin(path, klass, declared_in, index,
                                                  _Source(self, symbols, source))))
        return out

    def add(self, flattener: "_Flattener", path: str, symbols: list) -> None:
        """Add the equations of the instance at ``path`` to the flat model."""
        equations, initial, discrete = self.build(path, symbols)
        flattener.equations.extend(equations)
        flattener.initial_equations.extend(initial)
        flattener.discrete_equations.extend(discrete)

    def agrees(self, flattener: "_Flattener", path: str, symbols: list, start: tuple) -> bool:
        """Whether the template gives exactly what the equations() of the instance at
        ``path`` just gave (added to the flat model from ``start``)."""
        built = self.build(path, symbols)
        direct = (flattener.equations[start[0]:], flattener.initial_equations[start[1]:],
                  flattener.discrete_equations[start[2]:])
        return all(len(a) == len(b) and all(_same_equation(x, y) for x, y in zip(a, b))
                   for a, b in zip(built, direct))


def _same_equation(a, b) -> bool:
    """Whether two flat or discrete equations are identical, origins and sources included."""
    if type(a) is not type(b):
        return False
    if isinstance(a, DiscreteEquation):
        if a.variable != b.variable or sp.srepr(a.rhs) != sp.srepr(b.rhs):
            return False
    elif sp.srepr(a.residual) != sp.srepr(b.residual):
        return False
    oa, ob = a.origin, b.origin
    if (oa.component, oa.component_class, oa.declared_in, oa.index) != \
            (ob.component, ob.component_class, ob.declared_in, ob.index):
        return False
    sa = oa.source.expression() if isinstance(oa.source, _Source) else oa.source
    sb = ob.source.expression() if isinstance(ob.source, _Source) else ob.source
    if isinstance(sa, sp.Basic) or isinstance(sb, sp.Basic):
        return isinstance(sa, sp.Basic) and isinstance(sb, sp.Basic) and sp.srepr(sa) == sp.srepr(sb)
    return type(sa) is type(sb) and sa == sb
