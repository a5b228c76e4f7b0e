"""The modelling language: declarations, components, connectors and models.

A component is a Python class whose class attributes declare what it has,
the way a Modelica class does::

    class Inertia(PartialTwoFlanges):
        J = Parameter(1.0, unit="kg.m2", min=0)
        phi = Variable(unit="rad")
        w = Variable(unit="rad/s")
        a = Variable(unit="rad/s2")

        def equations(self):
            return [Eq(self.phi, self.flange_a.phi), Eq(self.phi, self.flange_b.phi),
                    Eq(self.w, der(self.phi)), Eq(self.a, der(self.w)),
                    Eq(self.J * self.a, self.flange_a.tau + self.flange_b.tau)]

Instances take Modelica-style modifiers, ``Inertia(J=2, w=dict(start=10,
fixed=True))``.  Models instantiate components in :meth:`Component.build`
and join them with :meth:`Component.connect`.

Inheritance works like Modelica's ``extends``: declarations are collected
along the class hierarchy and every class's own ``equations`` method
contributes its equations (a subclass never calls ``super().equations()``).

Names are resolved late.  ``build`` and ``equations`` are called by the
flattening stage, when every component knows its place in the model, so
``self.inertia1.w`` is the sympy symbol named ``inertia1.w`` (or
``drive.inertia1.w`` when the model is itself used as a component).
"""

from __future__ import annotations

import difflib
import enum
from dataclasses import dataclass
from typing import Any, Callable, Iterator

import sympy as sp

from .errors import ConnectionError_, ModelDefinitionError, ModifierError

__all__ = [
    "time",
    "der",
    "pre",
    "initial",
    "Eq",
    "If",
    "StateSelect",
    "Parameter",
    "Variable",
    "Boolean",
    "Integer",
    "RealInput",
    "RealOutput",
    "Potential",
    "Flow",
    "Connector",
    "Component",
    "Model",
    "Experiment",
    "real_symbol",
]

#: The independent variable.
time = sp.Symbol("time", real=True)

#: ``der(expr)``: time derivative.  Applied to an expression it is expanded by
#: the chain rule during flattening.
der = sp.Function("der")

#: ``pre(v)``: the left limit of discrete variable ``v`` at an event.
pre = sp.Function("pre")

#: ``initial()``: true only while the initialization problem is solved.
initial = sp.Function("initial")

def Eq(lhs, rhs) -> sp.Equality:  # noqa: N802 - the sympy name users know
    """The equation ``lhs = rhs``.

    Unlike ``sympy.Eq`` it is not evaluated: sympy would try to decide
    whether the two sides are equal, which costs a query of its assumption
    system per equation (most of the flattening time of a large model).
    """
    return sp.Equality(lhs, rhs, evaluate=False)



def If(condition, then, otherwise) -> sp.Piecewise:  # noqa: N802 - Modelica keyword
    """``if condition then then else otherwise`` as a sympy Piecewise."""
    return sp.Piecewise((then, condition), (otherwise, True))


def real_symbol(name: str) -> sp.Symbol:
    """The symbol of a continuous quantity (variable, parameter, derivative)."""
    return sp.Symbol(name, real=True)


class StateSelect(enum.IntEnum):
    """Modelica's StateSelect; the value orders the wish to be a state."""

    never = 0
    avoid = 1
    default = 2
    prefer = 3
    always = 4


# --------------------------------------------------------------------------
# Declarations
# --------------------------------------------------------------------------

_VARIABLE_ATTRIBUTES = ("start", "fixed", "nominal", "state_select", "min", "max", "unit")


class Declaration:
    """Something a component class declares; a descriptor on the class."""

    name: str = ""
    kind: str = ""

    def __init__(self, *, unit: str = "", description: str = "", condition=None) -> None:
        self.unit = unit
        self.description = description
        #: Name of a structural parameter, or a callable(component) -> bool.
        self.condition = condition

    def __set_name__(self, owner, name: str) -> None:
        self.name = name

    def enabled(self, component: "Component") -> bool:
        """Whether a conditional declaration exists in this instance."""
        if self.condition is None:
            return True
        if callable(self.condition):
            return bool(self.condition(component))
        return bool(getattr(component, self.condition))


class Parameter(Declaration):
    """A parameter: constant during a simulation.

    Parameters
    ----------
    default : number, array, bool, str or sympy expression
        Default value.  A modifier may bind it to an expression of other
        parameters (``Inertia(J=self.Jmotor)``).
    unit, min, max, description
        As in Modelica.
    structural : bool
        Evaluated at build time (Modelica's ``Evaluate=true``): reading it on
        an instance gives the Python value, so it can select connectors and
        equations (``useSupport``) or shape them (tables).
    fixed : bool
        ``False`` makes it an unknown of the initialization problem, fixed by
        an initial equation (Modelica's ``parameter Real p(fixed=false)``).
    """

    kind = "parameter"

    def __init__(self, default: Any = None, *, unit: str = "", min: float | None = None,
                 max: float | None = None, structural: bool = False, fixed: bool = True,
                 description: str = "", condition=None) -> None:
        super().__init__(unit=unit, description=description, condition=condition)
        self.default = default
        self.min = min
        self.max = max
        self.structural = structural
        self.fixed = fixed

    def __get__(self, obj, objtype=None):
        if obj is None:
            return self
        if self.structural:
            return obj._modifier_value(self.name, self.default)
        return real_symbol(obj._path_of(self.name))


class Variable(Declaration):
    """A continuous-time Real variable.

    ``start``, ``fixed``, ``nominal``, ``state_select``, ``min`` and ``max``
    are Modelica's attributes.  Any of them may be a callable taking the
    component, for attributes that depend on structural parameters.
    """

    kind = "continuous"

    def __init__(self, *, start: Any = 0.0, fixed: bool = False, unit: str = "",
                 nominal: Any = None, state_select: Any = StateSelect.default,
                 min: float | None = None, max: float | None = None,
                 description: str = "", condition=None, causality: str = "") -> None:
        super().__init__(unit=unit, description=description, condition=condition)
        self.start = start
        self.fixed = fixed
        self.nominal = nominal
        self.state_select = state_select
        self.min = min
        self.max = max
        #: "input" or "output" for signal connectors, "" otherwise.
        self.causality = causality

    def make_symbol(self, path: str) -> sp.Symbol:
        return real_symbol(path)

    def __get__(self, obj, objtype=None):
        if obj is None:
            return self
        return self.make_symbol(obj._path_of(self.name))


class RealInput(Variable):
    """A signal input connector (Modelica.Blocks.Interfaces.RealInput)."""

    def __init__(self, **kw) -> None:
        super().__init__(causality="input", **kw)


class RealOutput(Variable):
    """A signal output connector (Modelica.Blocks.Interfaces.RealOutput)."""

    def __init__(self, **kw) -> None:
        super().__init__(causality="output", **kw)


class Boolean(Variable):
    """A discrete Boolean variable; changes only at events."""

    kind = "boolean"

    def __init__(self, *, start: bool = False, fixed: bool = False, description: str = "",
                 condition=None) -> None:
        super().__init__(start=start, fixed=fixed, description=description, condition=condition)

    def make_symbol(self, path: str) -> sp.Symbol:
        return sp.Symbol(path)


class Integer(Variable):
    """A discrete Integer variable; changes only at events."""

    kind = "integer"

    def __init__(self, *, start: int = 0, fixed: bool = False, min: int | None = None,
                 max: int | None = None, description: str = "", condition=None) -> None:
        super().__init__(start=start, fixed=fixed, min=min, max=max, description=description,
                         condition=condition)

    def make_symbol(self, path: str) -> sp.Symbol:
        return sp.Symbol(path, integer=True)


class Potential(Variable):
    """A potential (across) variable of a connector: equal when connected."""

    connector_role = "potential"


class Flow(Variable):
    """A flow (through) variable of a connector: sums to zero when connected.

    Positive means flowing into the component the connector belongs to.
    """

    connector_role = "flow"


class Connector(Declaration):
    """A physical connector class; instances declare connectors on components.

    Subclasses declare :class:`Potential` and :class:`Flow` variables and a
    ``family``; connectors of one family can be connected (Flange_a, Flange_b
    and Support are all "rotational").
    """

    kind = "connector"
    family = "connector"

    def __init__(self, *, condition=None, description: str = "") -> None:
        super().__init__(description=description, condition=condition)

    @classmethod
    def variables(cls) -> dict[str, Variable]:
        found: dict[str, Variable] = {}
        for klass in reversed(cls.__mro__):
            for key, value in vars(klass).items():
                if isinstance(value, (Potential, Flow)):
                    found[key] = value
        return found

    def __get__(self, obj, objtype=None):
        if obj is None:
            return self
        return BoundConnector(self, obj)


class BoundConnector:
    """A connector of one component instance; its variables are symbols."""

    def __init__(self, declaration: Connector, owner: "Component") -> None:
        self._declaration = declaration
        self._owner = owner

    @property
    def declaration(self) -> Connector:
        return self._declaration

    @property
    def owner(self) -> "Component":
        return self._owner

    @property
    def path(self) -> str:
        return self._owner._path_of(self._declaration.name)

    @property
    def enabled(self) -> bool:
        return self._declaration.enabled(self._owner)

    def __getattr__(self, name: str):
        if name.startswith("_"):
            raise AttributeError(name)
        variables = type(self._declaration).variables()
        if name not in variables:
            raise AttributeError(f"connector {self.path} ({type(self._declaration).__name__}) "
                                 f"has no variable {name!r}; it has {sorted(variables)}")
        if not self.enabled:
            raise ConnectionError_(
                f"connector {self.path} is disabled in this instance of "
                f"{type(self._owner).__name__}",
                hint=f"it exists only when {_condition_text(self._declaration)}")
        return variables[name].make_symbol(f"{self.path}.{name}")

    def __repr__(self) -> str:
        return f"<{type(self._declaration).__name__} {self.path}>"


def _condition_text(declaration: Declaration) -> str:
    if isinstance(declaration.condition, str):
        return f"{declaration.condition}=True"
    return "its condition holds"


# --------------------------------------------------------------------------
# Components and models
# --------------------------------------------------------------------------


@dataclass(frozen=True)
class Experiment:
    """Modelica's experiment annotation."""

    start_time: float = 0.0
    stop_time: float = 1.0
    interval: float | None = None
    tolerance: float | None = None


class Component:
    """A component: declarations, equations and (optionally) sub-components.

    Subclasses override :meth:`build` to create sub-components and connect
    them, :meth:`equations` for their equations and :meth:`initial_equations`
    for equations that hold only at initialization.  Modifiers given to the
    constructor set parameters and the attributes of variables.
    """

    def __init__(self, **modifiers: Any) -> None:
        object.__setattr__(self, "_name", "")
        object.__setattr__(self, "_parent", None)
        object.__setattr__(self, "_children", {})
        object.__setattr__(self, "_connections", [])
        object.__setattr__(self, "_built", False)
        object.__setattr__(self, "_modifiers", {})
        object.__setattr__(self, "_attribute_modifiers", {})
        declarations = self.declarations()
        for key, value in modifiers.items():
            self._apply_modifier(key, value, declarations)

    # -- declarations -----------------------------------------------------

    @classmethod
    def declarations(cls) -> dict[str, Declaration]:
        """Every declaration of the class, base classes first."""
        found: dict[str, Declaration] = {}
        for klass in reversed(cls.__mro__):
            for key, value in vars(klass).items():
                if isinstance(value, Declaration):
                    found[key] = value
        return found

    def _apply_modifier(self, key: str, value: Any, declarations: dict[str, Declaration]) -> None:
        where = type(self).__name__
        if key not in declarations:
            candidates = difflib.get_close_matches(key, list(declarations), n=3)
            hint = (f"did you mean {', '.join(candidates)}?" if candidates
                    else f"{where} declares: {', '.join(sorted(declarations))}")
            raise ModifierError(f"{where} has no parameter or variable named {key!r}", hint=hint)
        declaration = declarations[key]
        if isinstance(declaration, Parameter):
            if isinstance(value, dict):
                raise ModifierError(f"{where}.{key} is a parameter: give it a value, not {value!r}",
                                    hint=f"{where}({key}=1.0)")
            self._modifiers[key] = value
        elif isinstance(declaration, Variable):
            if not isinstance(value, dict):
                raise ModifierError(
                    f"{where}.{key} is a variable: modify its attributes with a dict",
                    hint=f"{where}({key}=dict(start={value!r}, fixed=True))")
            unknown = set(value) - set(_VARIABLE_ATTRIBUTES)
            if unknown:
                raise ModifierError(f"{where}.{key} has no attribute {sorted(unknown)[0]!r}",
                                    hint=f"variable attributes are {', '.join(_VARIABLE_ATTRIBUTES)}")
            self._attribute_modifiers.setdefault(key, {}).update(value)
        else:
            raise ModifierError(f"{where}.{key} is a connector and takes no modifier")

    def _modifier_value(self, name: str, default: Any) -> Any:
        return self._modifiers.get(name, default)

    def attribute(self, name: str, attribute: str) -> Any:
        """The value of a variable attribute (start, fixed, ...) after modifiers."""
        declaration = self.declarations()[name]
        if attribute in self._attribute_modifiers.get(name, {}):
            value = self._attribute_modifiers[name][attribute]
        else:
            value = getattr(declaration, attribute)
        return value(self) if callable(value) and not isinstance(value, sp.Basic) else value

    def parameter_binding(self, name: str) -> Any:
        """The value or expression a parameter is bound to, after modifiers."""
        declaration = self.declarations()[name]
        return self._modifiers.get(name, declaration.default)

    # -- tree -------------------------------------------------------------

    def __setattr__(self, key: str, value: Any) -> None:
        if isinstance(value, Component):
            if value._parent is not None:
                raise ModelDefinitionError(
                    f"component {value.path} is already part of a model; "
                    f"cannot also add it as {self._path_of(key)}",
                    hint="create a new instance for each use")
            if key in self.declarations():
                raise ModelDefinitionError(
                    f"{type(self).__name__}.{key} is declared as a "
                    f"{self.declarations()[key].kind}; a sub-component cannot use that name")
            object.__setattr__(value, "_name", key)
            object.__setattr__(value, "_parent", self)
            self._children[key] = value
        object.__setattr__(self, key, value)

    @property
    def name(self) -> str:
        return self._name

    @property
    def path(self) -> str:
        """Dotted name of this instance in its model ('' for the model itself)."""
        if self._parent is None:
            return ""
        parent = self._parent.path
        return f"{parent}.{self._name}" if parent else self._name

    def _path_of(self, member: str) -> str:
        base = self.path
        return f"{base}.{member}" if base else member

    @property
    def children(self) -> dict[str, "Component"]:
        return dict(self._children)

    def walk(self) -> Iterator["Component"]:
        """This component and all below it, depth first, in declaration order."""
        stack = [self]
        while stack:
            node = stack.pop()
            node.ensure_built()
            yield node
            stack.extend(reversed(list(node._children.values())))

    def ensure_built(self) -> None:
        if not self._built:
            object.__setattr__(self, "_built", True)
            self.build()

    # -- what subclasses write ---------------------------------------------

    def build(self) -> None:
        """Create sub-components and connect them (override)."""

    def equations(self) -> list:
        """Equations of this class (override; collected along the MRO)."""
        return []

    def initial_equations(self) -> list:
        """Equations that hold only at initialization (override)."""
        return []

    def connect(self, a, b) -> None:
        """Modelica's ``connect(a, b)`` between two connectors or signals."""
        self._connections.append((a, b))

    def __repr__(self) -> str:
        return f"<{type(self).__name__} {self.path or '(model)'}>"


class Model(Component):
    """A top-level model.

    Class attributes
    ----------------
    modelica_class : str or None
        The Modelica class this model reproduces, used to find reference
        results.
    experiment : Experiment
        Modelica's experiment annotation.
    """

    modelica_class: str | None = None
    experiment: Experiment = Experiment()


def own_method(klass: type, name: str) -> Callable | None:
    """The method ``name`` defined in ``klass`` itself (not inherited)."""
    return vars(klass).get(name)
