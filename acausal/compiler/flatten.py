"""Stage 1: flatten a model into one list of variables and equations.

Flattening walks the component tree, gives every variable its dotted
Modelica name (``clutch1.flange_a.tau``), turns ``connect()`` statements into
equations (potentials equal, flows sum to zero, unconnected flows zero),
resolves parameter bindings to numbers and expands ``der(expression)`` by the
chain rule.  Every equation remembers where it came from.
"""

from __future__ import annotations

import math
import os
import sysconfig
import traceback
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import sympy as sp

from ..names import INITIAL_NAME, der_name, pre_name
from ..errors import AcausalError, ConnectionError_, EquationError, ModelDefinitionError, ParameterError
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
)

__all__ = [
    "Origin",
    "FlatParameter",
    "FlatVariable",
    "FlatEquation",
    "DiscreteEquation",
    "FlatModel",
    "flatten",
    "INITIAL",
]

#: The symbol ``initial()`` becomes after flattening.
INITIAL = sp.Symbol(INITIAL_NAME)


#: Expression types rebuilt without evaluation while der/pre/initial are expanded:
#: they are simplified anyway when the discrete state is substituted.  Relations
#: are evaluated: one that is always true (der(x)**2 > -1) must not become an event.
_UNEVALUATED = (sp.Piecewise, sp.And, sp.Or, sp.Not)



@dataclass(frozen=True)
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
        if self.declared_in in ("connect", "unconnected", "binding"):
            return f"{where}: {self.declared_in}: {self.text}"
        return f"{where} ({self.declared_in} eq. {self.index + 1}): {self.text}"


@dataclass(frozen=True)
class FlatParameter:
    name: str
    value: float
    unit: str
    component: str


@dataclass(frozen=True)
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

    @property
    def is_discrete(self) -> bool:
        return self.kind in ("boolean", "integer")


@dataclass(frozen=True)
class FlatEquation:
    """``residual = 0``."""

    residual: sp.Expr
    origin: Origin

    def __str__(self) -> str:
        return f"0 = {self.residual}"


@dataclass(frozen=True)
class DiscreteEquation:
    """``variable := rhs`` for a Boolean or Integer variable."""

    variable: str
    rhs: sp.Basic
    origin: Origin


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

    def hints_for(self, situation: str, components) -> tuple[str, ...]:
        """The distinct hints the ``components`` (dotted paths) declare for ``situation``.

        A path inside a component (a variable's owner, ``a.b.c`` for ``a.b.c.x``)
        finds the hints of the nearest enclosing component that has some.
        """
        out: list[str] = []
        for path in components:
            while True:
                hint = self.hints.get(path, {}).get(situation)
                if hint is not None or not path:
                    break
                path = path.rpartition(".")[0]
            if hint is not None and hint not in out:
                out.append(hint)
        return tuple(out)

    @property
    def variable_map(self) -> dict[str, FlatVariable]:
        return {v.name: v for v in self.variables}

    @property
    def parameter_values(self) -> dict[str, float]:
        return {p.name: p.value for p in self.parameters}

    def summary(self) -> str:
        n_cont = sum(not v.is_discrete for v in self.variables)
        return (f"{self.name}: {n_cont} continuous and {len(self.variables) - n_cont} discrete "
                f"variables, {len(self.equations)} equations, {len(self.discrete_equations)} "
                f"discrete equations, {len(self.parameters)} parameters")


# --------------------------------------------------------------------------


def flatten(model: Component, parameters: dict[str, float] | None = None) -> FlatModel:
    """Flatten ``model`` (a :class:`~acausal.language.Model` instance).

    Parameters
    ----------
    parameters : dict, optional
        New values of numeric (tunable) parameters by dotted name, in place
        of their modifiers or defaults; bindings that refer to them follow
        (``J = 2*Jm``).

    Raises
    ------
    ModelDefinitionError
        For equations that are not equations, bad connections, unconnected
        inputs and unresolvable parameter bindings.
    ParameterError
        For a name in ``parameters`` that is not a numeric parameter (a
        structural one selects equations and is set when the model is built).
    """
    return _Flattener(model, parameters).run()


class _Flattener:
    def __init__(self, model: Component, overrides: dict[str, float] | None = None) -> None:
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

    # -- declarations ---------------------------------------------------------

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
        for name in self.unknown_parameters:
            origin = Origin(name.rpartition(".")[0], "", "binding", 0, f"der({name}) = 0")
            self.equations.append(FlatEquation(real_symbol(der_name(name)), origin))
        model = self.model
        return FlatModel(
            name=type(model).__name__,
            modelica_class=getattr(model, "modelica_class", None),
            experiment=getattr(model, "experiment", Experiment()),
            parameters=tuple(FlatParameter(n, values[n], self.parameters[n][1],
                                           self.parameters[n][2].path)
                             for n in self.parameters if n not in self.unknown_parameters),
            structural_parameters=dict(self.structural),
            variables=tuple(self.variables.values()),
            equations=tuple(self.equations),
            discrete_equations=tuple(self.discrete_equations),
            initial_equations=tuple(self.initial_equations),
            hints={c.path: h for c in self.components if (h := component_hints(type(c)))},
        )

    def _declare(self, component: Component) -> None:
        for key, decl in component.declarations().items():
            if isinstance(decl, Parameter):
                path = component._path_of(key)
                binding = component.parameter_binding(key)
                if decl.structural:
                    self.structural[path] = binding
                    continue
                self.parameters[path] = (binding, decl.unit, component)
                if not decl.fixed:
                    self.unknown_parameters.append(path)

    def _apply_overrides(self) -> None:
        """Put the values of ``parameters=`` in place of the bindings they replace."""
        for name, value in self.overrides.items():
            if name in self.structural:
                raise ParameterError(
                    f"parameter {name} is structural: it decides which equations the model has",
                    hint="set it where the component is created (e.g. Component(name=value)); "
                         "only numeric parameters can change between runs")
            if name not in self.parameters:
                import difflib

                close = difflib.get_close_matches(name, sorted(self.parameters), n=3)
                raise ParameterError(f"{type(self.model).__name__} has no numeric parameter {name!r}",
                                     hint=f"did you mean {', '.join(close)}?" if close else
                                     "parameters are named by their dotted path, e.g. component.parameter")
            _binding, unit, component = self.parameters[name]
            self.parameters[name] = (value, unit, component)

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
            for key, decl in component.declarations().items():
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
        if isinstance(value, sp.Basic):
            subs = {s: self.values[s.name] for s in value.free_symbols if s.name in self.values}
            value = value.subs(subs)
        try:
            return float(value)
        except (TypeError, ValueError) as exc:
            raise ModelDefinitionError(f"{what} = {value} is not a number",
                                       hint="attributes take numbers or expressions of parameters") from exc

    def _declare_variables(self, component: Component, values) -> None:
        for key, decl in component.declarations().items():
            if isinstance(decl, Connector):
                if not decl.enabled(component):
                    continue
                path = component._path_of(key)
                for var_name, var in type(decl).variables().items():
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
                self.variables[name] = FlatVariable(
                    name=name, kind="continuous", start=guess, fixed=False, nominal=1.0,
                    state_select=StateSelect.default, unit=unit, component=component.path)

    def _add_variable(self, path: str, decl: Variable, component: Component, key: str | None) -> None:
        def attr(name):
            if key is None:
                value = getattr(decl, name)
                return value(component) if callable(value) and not isinstance(value, sp.Basic) else value
            return component.attribute(key, name)

        kind = "boolean" if isinstance(decl, Boolean) else "integer" if isinstance(decl, Integer) \
            else "continuous"
        nominal = attr("nominal")
        start = given_start = attr("start")
        if kind == "continuous":
            start = self._number(start, f"{path}.start")
        _check_finite_attribute(path, "start", start, given_start, component, key)
        if kind != "continuous":
            start = int(bool(start)) if kind == "boolean" else int(start)
        if nominal is not None:
            given_nominal, nominal = nominal, abs(self._number(nominal, f"{path}.nominal"))
            _check_finite_attribute(path, "nominal", nominal, given_nominal, component, key)
        variable = FlatVariable(
            name=path, kind=kind, start=start, fixed=bool(attr("fixed")),
            nominal=nominal or 1.0,
            state_select=StateSelect(attr("state_select") if kind == "continuous" else 2),
            unit=decl.unit, component=component.path, causality=decl.causality,
            role=getattr(decl, "connector_role", ""))
        self.variables[path] = variable
        if decl.causality:
            self.signal_declarations[path] = (decl, component)

    # -- equations --------------------------------------------------------------

    def _collect_equations(self, component: Component) -> None:
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
                for index, item in enumerate(items):
                    origin = Origin(component.path, type(component).__name__, klass.__name__, index,
                                    item)
                    self._add_equation(item, origin, target)

    def _add_equation(self, item: Any, origin: Origin, target: list) -> None:
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
        """Replace der(), pre() and initial() by plain symbols (chain rule for der)."""
        if not isinstance(expr, sp.Basic) or not expr.has(der, pre, initial):
            return expr

        def rewrite(node: sp.Basic) -> sp.Basic:
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
            if all(a is b for a, b in zip(new_args, node.args)):
                return node
            if isinstance(node, _UNEVALUATED):
                return node.func(*new_args, evaluate=False)
            return node.func(*new_args)

        return rewrite(expr)

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
                    raise ConnectionError_(
                        f"{statement}: that {name} is not part of the model (created, but never "
                        f"stored as an attribute)",
                        hint=f"store the {name} as an attribute and connect that: "
                             f"self.{name[:1].lower()}{name[1:]} = {name}(...)",
                        components=(owner.path,))
                if not end.enabled:
                    raise ConnectionError_(
                        f"{statement}: connector {end.path} is disabled",
                        hint=f"enable it ({_condition(end)}) or remove the connection")
                outside = end.owner is owner
                return ("physical", end.path, outside), end
            if isinstance(end, sp.Symbol) and end.name in self.signal_declarations:
                return ("signal", end.name, False), end
            if isinstance(end, sp.Symbol) and end.name in self.variables:
                raise ConnectionError_(f"{statement}: {end.name} is a variable, not a connector",
                                       hint="connect() joins connectors or signal inputs and outputs")
            raise ConnectionError_(f"{statement}: {end!r} is not a connector of this model",
                                   hint="connect connectors of components stored as attributes "
                                        "(self.name = ...); a disabled conditional connector cannot "
                                        "be connected")

        # every enabled physical connector is an 'inside' element, connected or not
        for component in self.components:
            for key, decl in component.declarations().items():
                if isinstance(decl, Connector) and decl.enabled(component):
                    bound = getattr(component, key)
                    el = ("physical", bound.path, False)
                    parent[el] = el
                    members[el] = bound
                    order.append(el)

        signal_edges: list[tuple[str, str, str]] = []
        connect_text: dict[tuple, str] = {}
        for component in self.components:
            for a, b in component._connections:
                statement = (f"connect({_end_name(a, in_model)}, {_end_name(b, in_model)}) "
                             f"in {component.path or 'the model'}")
                ea, ba = element_of(a, component, statement)
                eb, bb = element_of(b, component, statement)
                if ea == eb:
                    raise ConnectionError_(f"{statement}: connects {ea[1]} to itself",
                                           hint="a connection joins two different connectors; "
                                                "remove it or change one end",
                                           components=(component.path,))
                if ea[0] != eb[0]:
                    raise ConnectionError_(f"{statement}: cannot connect a signal to a physical connector")
                if ea[0] == "signal":
                    signal_edges.append((ea[1], eb[1], statement))
                    continue
                fa, fb = type(ba.declaration).family, type(bb.declaration).family
                if fa != fb:
                    raise ConnectionError_(
                        f"{statement}: {ba.path} is a {type(ba.declaration).__name__} ({fa}) but "
                        f"{bb.path} is a {type(bb.declaration).__name__} ({fb})",
                        hint="only connectors of the same kind can be connected")
                for el, bound in ((ea, ba), (eb, bb)):
                    if el not in parent:
                        parent[el] = el
                        members[el] = bound
                        order.append(el)
                ra, rb = find(ea), find(eb)
                if ra != rb:
                    # keep the earlier-declared element as root: deterministic
                    if order.index(rb) < order.index(ra):
                        ra, rb = rb, ra
                    parent[rb] = ra
                connect_text[find(ea)] = statement

        sets: dict[tuple, list[tuple]] = {}
        for el in order:
            sets.setdefault(find(el), []).append(el)
        for root, elements in sets.items():
            bound0 = members[elements[0]]
            variables = type(bound0.declaration).variables()
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
                            sym - symbols[0],
                            Origin(origin.component, origin.component_class, "connect", 0,
                                   f"{sym.name} = {symbols[0].name}  [{text}]")))
                elif isinstance(var, Flow):
                    total = sum(((-1 if e[2] else 1) * s for e, s in zip(elements, symbols)), sp.Integer(0))
                    self.equations.append(FlatEquation(
                        total, Origin(origin.component, origin.component_class, "connect", 0,
                                      lambda total=total, text=text: f"0 = {total}  [{text}]")))

        # signals: equality per connection; every input must be connected
        connected_inputs = set()
        for a, b, statement in signal_edges:
            da, db = self.signal_declarations[a][0], self.signal_declarations[b][0]
            if da.causality == "output" and db.causality == "output":
                raise ConnectionError_(f"{statement}: two outputs cannot be connected",
                                       hint="connect an output to one or more inputs")
            for name, decl in ((a, da), (b, db)):
                if decl.causality == "input":
                    connected_inputs.add(name)
            self.equations.append(FlatEquation(
                real_symbol(b) - real_symbol(a),
                Origin("", type(self.model).__name__, "connect", 0, f"{b} = {a}")))
        for name, (decl, component) in self.signal_declarations.items():
            if decl.causality == "input" and name not in connected_inputs and component is not self.model:
                # an input driven from inside its own component (hierarchical) is fine
                if self._assigned_inside(name):
                    continue
                raise ConnectionError_(f"input {name} of {type(component).__name__} is not connected",
                                       hint=f"connect a signal source to {name}")

    def _assigned_inside(self, name: str) -> bool:
        sym = real_symbol(name)
        return any(sym in eq.residual.free_symbols and eq.origin.declared_in != "connect"
                   and eq.origin.component != name.rpartition(".")[0] for eq in self.equations)


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
