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

import copy
import difflib
import re
import enum
import functools
import inspect
from dataclasses import dataclass
from typing import Any, Callable, Iterator, Mapping

import numpy as np
import sympy as sp

from . import arrays
from .arrays import Array, Each, distribute, element_name, indices, is_array_value
from .errors import ArraySizeError, ConnectorError, ModelDefinitionError, ModifierError
from .attributes import Experiment, StateSelect  # noqa: F401 - part of the language

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
    "value_names",
    "RealInput",
    "RealOutput",
    "Potential",
    "Flow",
    "Connector",
    "Component",
    "ComponentArray",
    "Model",
    "Experiment",
    "real_symbol",
    "structural_names",
    "with_structural",
    "finish_hooks",
    "describe",
    "own_docstring",
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

# sympy makes undefined functions classes with ``__module__ = None``, which
# pydoc cannot document (``help(acausal)`` crashed).  Naming their module
# and giving them a docstring changes neither equality nor hashing: sympy
# compares undefined functions by name and assumptions only, so ``der(x)``
# is still ``sympy.Function("der")(x)``.
for _function, _doc in (
        (der, "der(expr): the time derivative of ``expr`` (Modelica's ``der``).\n\n"
              "A sympy undefined function, ``sympy.Function('der')``.  Applied to an\n"
              "expression it is expanded by the chain rule during flattening."),
        (pre, "pre(v): the left limit of the discrete variable ``v`` at an event (Modelica's ``pre``).\n\n"
              "A sympy undefined function, ``sympy.Function('pre')``."),
        (initial, "initial(): true only while the initialization problem is solved "
                  "(Modelica's ``initial()``).\n\n"
                  "A sympy undefined function, ``sympy.Function('initial')``.")):
    _function.__module__ = __name__
    _function.__doc__ = _doc
del _function, _doc

def Eq(lhs, rhs) -> sp.Equality | list[sp.Equality]:  # noqa: N802 - the sympy name users know
    """The equation ``lhs = rhs``; for arrays, one equation per element.

    Unlike ``sympy.Eq`` it is not evaluated: sympy would try to decide
    whether the two sides are equal, which costs a query of its assumption
    system per equation (most of the flattening time of a large model).

    When a side is an array (:class:`~acausal.arrays.Array`, a list, or
    ``der(x)`` of an array) the result is the list of the elements'
    equations, in Modelica's order; a scalar side is taken for every
    element.  ``equations()`` may return such lists among its equations.

    Raises
    ------
    ArraySizeError
        For two arrays of different sizes (naming both).
    """
    expanded = arrays.array_equations(lhs, rhs)
    if expanded is not None:
        return expanded
    return sp.Equality(lhs, rhs, evaluate=False)



def If(condition, then, otherwise) -> sp.Piecewise:  # noqa: N802 - Modelica keyword
    """``if condition then then else otherwise`` as a sympy Piecewise."""
    return sp.Piecewise((then, condition), (otherwise, True))


#: The situations in which the engine adds a component's own hint (see
#: :attr:`Component.hints`) to an error, and what each means.
HINT_SITUATIONS = {
    "mode": "a discrete state reached after the start cannot be solved (a structural error "
            "whose equations include the component's)",
    "event_iteration": "event iteration does not settle while the component's discrete "
                       "variables keep changing",
    "chattering": "events pile up without time passing while the component's relations or "
                  "discrete variables keep switching",
}


def component_hints(klass: type) -> dict[str, str]:
    """The hints of a component class, its bases' included (nearest class wins).

    Raises
    ------
    ModelDefinitionError
        For a situation that is not one of :data:`HINT_SITUATIONS`.
    """
    merged: dict[str, str] = {}
    for base in reversed(klass.__mro__):
        own = vars(base).get("hints")
        if not own:
            continue
        unknown = sorted(set(own) - set(HINT_SITUATIONS))
        if unknown:
            raise ModelDefinitionError(f"{base.__name__}.hints: unknown situation {unknown[0]!r}",
                                       hint=f"the situations are {', '.join(HINT_SITUATIONS)}")
        merged.update(own)
    return merged


#: The real symbols made so far, by name.  sympy's own cache of symbols is bounded
#: (1000 entries): a model of 100 000 names would make each anew (70 µs each).
_REAL_SYMBOLS: dict[str, sp.Symbol] = {"time": time}

#: Beyond this many names the memo starts afresh (a long session of many models).
_REAL_SYMBOLS_MAX = 1_000_000


def real_symbol(name: str) -> sp.Symbol:
    """The symbol of a continuous quantity (variable, parameter, derivative)."""
    found = _REAL_SYMBOLS.get(name)
    if found is None:
        if len(_REAL_SYMBOLS) >= _REAL_SYMBOLS_MAX:
            _REAL_SYMBOLS.clear()
            _REAL_SYMBOLS["time"] = time
        found = _REAL_SYMBOLS[name] = sp.Symbol(name, real=True)
    return found


def parameter_symbols(values: Mapping[str, float]) -> dict[sp.Symbol, sp.Float]:
    """``{symbol: sympy Float}`` for parameter values by name: what substitution needs."""
    return {real_symbol(n): sp.Float(v) for n, v in values.items()}


# --------------------------------------------------------------------------
# Declarations
# --------------------------------------------------------------------------

_VARIABLE_ATTRIBUTES = ("start", "fixed", "nominal", "state_select", "min", "max", "unit", "display_unit")


@functools.lru_cache(maxsize=None)
def _constructor_defaults(klass: type) -> tuple[tuple[str, bool, Any], ...]:
    """(name, positional, default) for each named argument of ``klass(...)``.

    ``**kw`` is followed to the base class constructor (``RealInput(**kw)``
    takes Variable's arguments).  The default is the attribute of an instance
    made without arguments, so ``causality`` of a RealInput defaults to
    "input"; it is the signature's default if that instance cannot be made.
    """
    arguments: dict[str, inspect.Parameter] = {}
    for base in klass.__mro__:
        init = vars(base).get("__init__")
        if init is None:
            continue
        parameters = list(inspect.signature(init).parameters.values())[1:]
        for parameter in parameters:
            if (parameter.kind in (parameter.POSITIONAL_OR_KEYWORD, parameter.KEYWORD_ONLY)
                    and parameter.name not in arguments):
                arguments[parameter.name] = parameter
        if not any(parameter.kind is parameter.VAR_KEYWORD for parameter in parameters):
            break
    try:
        plain = klass()
    except Exception:  # noqa: BLE001 - a subclass whose constructor needs arguments
        plain = None
    return tuple((name, parameter.kind is parameter.POSITIONAL_OR_KEYWORD,
                  getattr(plain, name, parameter.default))
                 for name, parameter in arguments.items())


def _same(a: Any, b: Any) -> bool:
    """Equal values of the same type (``0`` differs from ``0.0`` and from False)."""
    if a is b:
        return True
    if type(a) is not type(b):
        return False
    try:
        return bool(a == b)
    except Exception:  # noqa: BLE001 - arrays and other values without a truth value
        return False


def _value_text(value: Any) -> str:
    """repr of an attribute value; enums by name, functions without their address."""
    if isinstance(value, enum.Enum):
        return f"{type(value).__name__}.{value.name}"
    if (callable(value) and not isinstance(value, (sp.Basic, type))
            and hasattr(value, "__qualname__")):
        return f"<function {value.__qualname__}>"
    return repr(value)


def _short(text: str, width: int = 60) -> str:
    return text if len(text) <= width else text[:width - 3] + "..."


def _dict_text(modifiers: Mapping[str, Any]) -> str:
    """Modifiers as the ``dict(...)`` call that gives them, nested ones too."""
    parts = [f"{key}={_dict_text(value) if isinstance(value, dict) else _short(_value_text(value), 40)}"
             for key, value in modifiers.items()]
    return f"dict({', '.join(parts)})"


def _attribute_text(value: Any) -> str:
    """A variable attribute in a docstring; one given as a function of the component is "computed"."""
    if callable(value) and not isinstance(value, sp.Basic):
        return "computed"
    return _short(_value_text(value))


class Declaration:
    """Something a component class declares; a descriptor on the class."""

    name: str = ""
    kind: str = ""

    def __init__(self, *, unit: str = "", description: str = "", condition=None, shape=None) -> None:
        self.unit = unit
        self.description = description
        #: Name of a structural parameter, or a callable(component) -> bool.
        self.condition = condition
        #: None for a scalar; for an array its size per dimension, each an int, the
        #: name of a structural parameter, Modelica's ``"size(A, 1)"`` of an array
        #: parameter, or a function of ``value(name)`` (``3``, ``"n"``, ``(2, "n")``)
        self.shape = shape

    def __set_name__(self, owner, name: str) -> None:
        self.name = name

    def enabled(self, component: "Component") -> bool:
        """Whether a conditional declaration exists in this instance."""
        if self.condition is None:
            return True
        if callable(self.condition):
            return bool(self.condition(component))
        return bool(getattr(component, self.condition))

    def _changed_attributes(self) -> dict[str, Any]:
        """The constructor arguments whose value differs from the default, in signature order."""
        return {name: getattr(self, name) for name, _, default in _constructor_defaults(type(self))
                if hasattr(self, name) and not _same(getattr(self, name), default)}

    def __repr__(self) -> str:
        """The constructor call, e.g. ``Parameter(1.0, unit='kg.m2', min=0)``.

        Only arguments that differ from their defaults are shown; the leading
        positional argument (a parameter's default value) without its name.
        """
        changed = self._changed_attributes()
        arguments = []
        keywords_only = False
        for name, positional, _ in _constructor_defaults(type(self)):
            if name not in changed:
                keywords_only = True
                continue
            value = _value_text(changed[name])
            arguments.append(value if positional and not keywords_only else f"{name}={value}")
        return f"{type(self).__name__}({', '.join(arguments)})"

    def _doc_entry(self) -> tuple[str, str]:
        """(section, summary) of this declaration in its component's docstring."""
        return "Variables", type(self).__name__

    def _doc_condition(self) -> list[str]:
        if self.condition is None:
            return []
        if isinstance(self.condition, str):
            return [f"if {self.condition}"]
        return ["conditional"]


class Parameter(Declaration):
    """A parameter: constant during a simulation.

    Parameters
    ----------
    default : number, array, bool, str or sympy expression
        Default value.  A modifier may bind it to an expression of other
        parameters (``Inertia(J=self.Jmotor)``).
    unit, min, max, description
        As in Modelica.
    display_unit : str
        Modelica's ``displayUnit``: the unit results show the value in
        (``"deg"``, ``"bar"``); the value itself stays in ``unit``.
    structural : bool
        Evaluated at build time (Modelica's ``Evaluate=true``): reading it on
        an instance gives the Python value, so it can select connectors and
        equations (``useSupport``) or shape them (tables).
    fixed : bool
        ``False`` makes it an unknown of the initialization problem, fixed by
        an initial equation (Modelica's ``parameter Real p(fixed=false)``).
    finite : bool
        ``True`` (the default): flattening rejects a value (or a table entry)
        that is nan or infinite.  ``False`` for the rare parameter whose
        equations give ``inf`` a meaning.
    shape : int, str or tuple, optional
        For an array parameter, its size (see :class:`Variable`).  A
        numeric parameter whose value is a list or an array
        (``Parameter([[0, 1], [-1, 0]])``) is an array of that shape without
        saying so; its elements are tunable parameters ``A[1,2]``, its shape
        is structural.
    """

    kind = "parameter"

    def __init__(self, default: Any = None, *, unit: str = "", min: float | None = None,
                 max: float | None = None, structural: bool = False, fixed: bool = True,
                 finite: bool = True, description: str = "", condition=None,
                 display_unit: str = "", shape=None) -> None:
        super().__init__(unit=unit, description=description, condition=condition, shape=shape)
        self.display_unit = display_unit
        self.default = default
        self.min = min
        self.max = max
        self.structural = structural
        self.fixed = fixed
        self.finite = finite

    def __get__(self, obj, objtype=None):
        if obj is None:
            return self
        if self.structural:
            return obj._modifier_value(self.name, self.default)
        return real_symbol(obj._path_of(self.name))

    def _doc_entry(self) -> tuple[str, str]:
        parts = ["no default" if self.default is None else f"default {_short(_value_text(self.default))}"]
        if self.unit:
            parts.append(f"unit {self.unit}")
        parts += [f"{bound} {_value_text(getattr(self, bound))}" for bound in ("min", "max")
                  if getattr(self, bound) is not None]
        if self.structural:
            parts.append("structural")
        if self.fixed is not True:
            parts.append(f"fixed={_value_text(self.fixed)}")
        if self.finite is not True:
            parts.append(f"finite={_value_text(self.finite)}")
        return "Parameters", ", ".join(parts + self._doc_condition())


class Variable(Declaration):
    """A continuous-time Real variable.

    ``start``, ``fixed``, ``nominal``, ``state_select``, ``min`` and ``max``
    are Modelica's attributes.  Any of them may be a callable taking the
    component, for attributes that depend on structural parameters.
    ``display_unit`` is Modelica's ``displayUnit`` (``"rpm"``, ``"degC"``):
    the unit results show the variable in; its values stay in ``unit``.

    ``shape`` makes it an array (Modelica's ``Real x[3]``): an int, the name
    of a structural parameter, or a tuple of those for a matrix.  Its
    elements are variables ``x[1]`` ... (``A[1,2]`` for a matrix), and
    ``self.x`` is an :class:`~acausal.arrays.Array` of them.  An attribute
    given as a list sets each element (``start=[1, 0, 0]``); a number or
    :func:`~acausal.arrays.each` sets all of them.
    """

    kind = "continuous"

    def __init__(self, *, start: Any = 0.0, fixed: bool = False, unit: str = "",
                 nominal: Any = None, state_select: Any = StateSelect.default,
                 min: float | None = None, max: float | None = None,
                 description: str = "", condition=None, causality: str = "",
                 discrete: bool = False, display_unit: str = "", shape=None) -> None:
        super().__init__(unit=unit, description=description, condition=condition, shape=shape)
        self.display_unit = display_unit
        #: Modelica's ``discrete Real``: changes only at events (assigned in a when-clause)
        self.discrete = discrete
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

    def _doc_entry(self) -> tuple[str, str]:
        # Signal connectors (RealInput, RealOutput) are listed with the connectors.
        section = "Connectors" if self.causality else "Variables"
        parts = [("discrete Real" if self.discrete else "Real") if type(self) is Variable
                 else type(self).__name__]
        if self.unit:
            parts.append(f"unit {self.unit}")
        changed = self._changed_attributes()
        for attribute in ("start", "min", "max"):
            if changed.get(attribute) is not None:
                parts.append(f"{attribute} {_attribute_text(changed[attribute])}")
        if self.fixed is True:
            parts.append("fixed")
        elif "fixed" in changed:
            parts.append(f"fixed {_attribute_text(self.fixed)}")
        return section, ", ".join(parts + self._doc_condition())


class RealInput(Variable):
    """A signal input connector (Modelica.Blocks.Interfaces.RealInput); ``RealInput(3)`` or
    ``RealInput("nin")`` declares a vector of them."""

    def __init__(self, shape=None, **kw) -> None:
        super().__init__(causality="input", shape=shape, **kw)


class RealOutput(Variable):
    """A signal output connector (Modelica.Blocks.Interfaces.RealOutput); ``RealOutput(3)``
    declares a vector of them."""

    def __init__(self, shape=None, **kw) -> None:
        super().__init__(causality="output", shape=shape, **kw)


class Boolean(Variable):
    """A discrete Boolean variable; changes only at events."""

    kind = "boolean"

    def __init__(self, *, start: bool = False, fixed: bool = False, description: str = "",
                 condition=None, causality: str = "", shape=None) -> None:
        super().__init__(start=start, fixed=fixed, description=description, condition=condition,
                         causality=causality, shape=shape)

    def make_symbol(self, path: str) -> sp.Symbol:
        return sp.Symbol(path)


class Integer(Variable):
    """A discrete Integer variable; changes only at events."""

    kind = "integer"

    def __init__(self, *, start: int = 0, fixed: bool = False, min: int | None = None,
                 max: int | None = None, description: str = "", condition=None,
                 causality: str = "", shape=None) -> None:
        super().__init__(start=start, fixed=fixed, min=min, max=max, description=description,
                         condition=condition, causality=causality, shape=shape)

    def make_symbol(self, path: str) -> sp.Symbol:
        return sp.Symbol(path, integer=True)


def value_names(klass: type, low: Any, high: Any) -> tuple[tuple[int, str], ...]:
    """Names of the values ``low..high`` of an Integer declared by ``klass``, if it gives them.

    The engine knows nothing of what an Integer's values mean, so the names
    are found generically: ``klass`` (or a base class; the most derived one
    first) must have one public ``int`` constant whose name starts with a
    capital letter for every value from ``low`` to ``high``, as ``Stuck = 0``,
    ``Forward = 1`` ...  Otherwise (no integer bounds, more than 32 values, a
    value unnamed) there are none.  Results, comparisons and the teaching
    page all show modes by these names (:attr:`FlatVariable.labels
    <acausal.compiler.flatten.FlatVariable.labels>`).
    """
    if type(low) is not int or type(high) is not int or not 0 < high - low + 1 <= 32:
        return ()
    return _value_names(klass, low, high)


@functools.lru_cache(maxsize=None)
def _value_names(klass: type, low: int, high: int) -> tuple[tuple[int, str], ...]:
    named: dict[int, str] = {}
    for base in klass.__mro__:
        for attribute, value in vars(base).items():
            if (type(value) is int and attribute[:1].isupper() and not attribute.isupper()
                    and low <= value <= high):
                named.setdefault(value, attribute)  # the most derived class names it first
    return tuple(sorted(named.items())) if len(named) == high - low + 1 else ()


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

    def __init__(self, *, condition=None, description: str = "", shape=None) -> None:
        super().__init__(description=description, condition=condition, shape=shape)

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

    def _doc_entry(self) -> tuple[str, str]:
        return "Connectors", ", ".join([type(self).__name__] + self._doc_condition())


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
            raise ConnectorError(
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


_DOC_SECTIONS = ("Parameters", "Connectors", "Variables")


def _declarations_doc(component_class: type["Component"], own: str | None) -> str | None:
    """``own`` (the class's docstring) followed by numpydoc sections listing its declarations.

    The class's own declarations come first, then those of its bases in
    method resolution order.
    """
    import textwrap

    declarations = component_class.declarations()
    names = dict.fromkeys(name for klass in component_class.__mro__ for name in vars(klass)
                          if name in declarations)
    sections: dict[str, list[str]] = {title: [] for title in _DOC_SECTIONS}
    for name in names:
        declaration = declarations[name]
        title, summary = declaration._doc_entry()
        lines = sections[title]
        lines.append(f"{name} : {summary}" if summary else name)
        if declaration.description:
            lines += textwrap.wrap(declaration.description, width=76, initial_indent="    ",
                                   subsequent_indent="    ", break_on_hyphens=False)
    # a docstring with a section of the same title (its own "Parameters" on
    # how to choose them) keeps it; the generated one is titled apart
    cleaned = inspect.cleandoc(own) if own else ""
    titled = {(f"Declared {title.lower()}" if f"\n{title}\n{'-' * len(title)}" in f"\n{cleaned}" else title): lines
              for title, lines in sections.items()}
    text = "\n\n".join("\n".join([title, "-" * len(title), *lines])
                       for title, lines in titled.items() if lines)
    if not text:
        return own
    return f"{inspect.cleandoc(own)}\n\n{text}" if own else text


class _ComponentDoc:
    """The ``__doc__`` of a Component subclass: its docstring plus its declarations.

    A descriptor in the class dictionary (``type.__doc__`` calls its
    ``__get__``), so the text is made on first read, not when the class is
    created.
    """

    __slots__ = ("_owner", "_own", "_text")

    def __init__(self, owner: type["Component"], own: str | None) -> None:
        self._owner = owner
        self._own = own
        self._text: str | None = None

    def __get__(self, obj, objtype=None) -> str | None:
        if self._text is None:
            try:
                self._text = _declarations_doc(self._owner, self._own) or ""
            except Exception:  # noqa: BLE001 - reading a docstring must never fail
                return self._own
        return self._text or self._own


def own_docstring(klass: type) -> str:
    """The docstring a class wrote itself, without the generated declaration sections ('' if none)."""
    own = vars(klass).get("__doc__")
    if isinstance(own, _ComponentDoc):
        own = own._own
    return inspect.cleandoc(own) if isinstance(own, str) else ""


def describe(subject: Any, width: int = 100) -> str:
    """A table of what a component (class or instance) or connector class declares.

    One table per kind: parameters (default or, for an instance, the value a
    modifier gave), connectors, variables (start, fixed), each with unit,
    min, max and description; for a model, the sub-components its build()
    makes, with their modifiers.  ``acausal show`` prints it.

    Parameters
    ----------
    subject : Component subclass, Component instance or Connector subclass
        What to describe.
    width : int
        Line width the descriptions are wrapped to.

    Returns
    -------
    str
        The text, a title line, the first paragraph of the docstring, the tables.
    """
    instance = subject if isinstance(subject, Component) else None
    klass = type(subject) if instance is not None else subject
    if not (isinstance(klass, type) and issubclass(klass, (Component, Connector))):
        raise TypeError(f"describe() takes a component class, a component or a connector class, "
                        f"not {subject!r}")
    title = repr(instance) if instance is not None else f"{klass.__name__} ({klass.__module__}.{klass.__qualname__})"
    summary = own_docstring(klass).split("\n\n", 1)[0]
    blocks = [title] + ([summary] if summary else [])
    if issubclass(klass, Connector):
        rows = [[name, getattr(variable, "connector_role", ""), variable.unit, variable.description]
                for name, variable in klass.variables().items()]
        blocks.append(_table("Variables", ["name", "role", "unit", "description"], rows, width))
        return "\n\n".join(blocks) + "\n"
    sections = _declaration_rows(klass, instance)
    for title, (header, rows) in sections.items():
        if rows:
            blocks.append(_table(title, header, rows, width))
    blocks.append(_subcomponents_text(klass, instance, width))
    return "\n\n".join(block for block in blocks if block) + "\n"


def _declaration_rows(klass: type["Component"], instance: "Component | None") -> dict[str, tuple[list, list]]:
    """{section title: (column names, rows)} of a component's declarations, its own first."""
    declarations = klass.declarations()
    # a sized class lists each array once, by its size (u[3]), not element by element
    arrays = klass.array_declarations()
    elements = {element_name(name, index): name for name, (_, shape) in arrays.items() for index in indices(shape)}
    ordered = dict.fromkeys(name for base in klass.__mro__ for name in vars(base)
                            if (name in declarations and name not in elements) or name in arrays)
    ordered.update(dict.fromkeys(arrays))  # arrays a class makes without declaring them by name
    parameters: list[list[str]] = []
    connectors: list[list[str]] = []
    variables: list[list[str]] = []

    def bound(value: Any) -> str:
        return "" if value is None else _attribute_text(value)

    def shaped(name: str, declaration: Declaration) -> str:
        """``u[3]`` for an array of a sized class, ``u[nin]`` for one of a class."""
        if name in arrays:
            return element_name(name, arrays[name][1])
        if isinstance(declaration, Parameter) and not declaration.structural and declaration.shape is None \
                and is_array_value(declaration.default):
            # an array parameter whose size its value gives: Modelica's A[:, :]
            return f"{name}[{', '.join(':' for _ in np.shape(np.asarray(declaration.default, dtype=object)))}]"
        if declaration.shape is not None:
            dims = declaration.shape if isinstance(declaration.shape, tuple) else (declaration.shape,)
            return f"{name}[{', '.join(_dimension_text(d) for d in dims)}]"
        return name

    def array_values(name: str, read: Callable[[str], Any]) -> Any:
        shape = arrays[name][1]
        if any(element_name(name, index) not in declarations for index in indices(shape)):
            return None  # a class not sized yet: its elements are not declared
        return np.array([read(element_name(name, index)) for index in indices(shape)],
                        dtype=object).reshape(shape).tolist()

    for name in ordered:
        declaration = arrays[name][0] if name in arrays else declarations[name]
        label = shaped(name, declaration)
        notes = declaration._doc_condition()
        if isinstance(declaration, Parameter):
            value = declaration.default
            if name in arrays:
                value = array_values(name, lambda e: (instance._modifiers.get(e, declarations[e].default)
                                                      if instance is not None else declarations[e].default))
                if instance is not None and any(e in instance._modifiers for e, a in elements.items() if a == name):
                    notes.insert(0, "modified")
            elif instance is not None and name in instance._modifiers:
                value = instance._modifiers[name]
                notes.insert(0, "modified")
            if declaration.structural:
                notes.append("structural")
            if declaration.fixed is not True:
                notes.append(f"fixed={_value_text(declaration.fixed)}")
            parameters.append([label, "" if value is None else _attribute_text(value), declaration.unit,
                               bound(declaration.min), bound(declaration.max), ", ".join(notes),
                               declaration.description])
        elif isinstance(declaration, Connector):
            connectors.append([label, type(declaration).__name__, "", ", ".join(notes), declaration.description])
        elif isinstance(declaration, Variable):
            modified = instance._attribute_modifiers.get(name, {}) if instance is not None else {}
            if name in arrays and instance is not None:
                own = [e for e, a in elements.items() if a == name]
                modified = {key: array_values(name, lambda e, key=key: instance.attribute(e, key))
                            for key in _VARIABLE_ATTRIBUTES
                            if any(key in instance._attribute_modifiers.get(e, {}) for e in own)}

            def attribute(key: str) -> Any:
                return modified.get(key, getattr(declaration, key))

            if modified:
                notes.insert(0, "modified")
            kind = type(declaration).__name__
            if type(declaration) is Variable:
                kind = "discrete Real" if declaration.discrete else "Real"
            if declaration.causality:  # signal connectors are listed with the connectors
                connectors.append([label, kind, declaration.unit, ", ".join(notes), declaration.description])
                continue
            fixed = attribute("fixed")
            if fixed is True:
                notes.append("fixed")
            elif fixed is not False:
                notes.append(f"fixed {_attribute_text(fixed)}")
            variables.append([label, kind, declaration.unit, bound(attribute("start")), bound(attribute("min")),
                              bound(attribute("max")), ", ".join(notes), declaration.description])
    return {
        "Parameters": (["name", "value" if instance is not None else "default", "unit", "min", "max", "notes",
                        "description"], parameters),
        "Connectors": (["name", "type", "unit", "notes", "description"], connectors),
        "Variables": (["name", "type", "unit", "start", "min", "max", "notes", "description"], variables),
    }


def _subcomponents_text(klass: type["Component"], instance: "Component | None", width: int) -> str:
    """The table of the sub-components build() makes, on a fresh copy ('' for a class without build)."""
    if not _may_have_subcomponents(klass):
        return ""
    try:
        # a fresh instance: describing must not build the user's (structural
        # parameters may still be set on it before it is built)
        model = with_structural(instance, {}) if instance is not None else klass()
        model.ensure_built()
    except Exception as exc:  # noqa: BLE001 - describing must not fail on a model that cannot be built
        return f"Components\n  (unknown: build() raised {type(exc).__name__}: {_short(str(exc), 80)})"
    rows = [[name, type(child).__name__, repr(child)] for name, child in model._children.items()]
    if not rows:
        return ""
    return _table("Components", ["name", "class", "as built"], rows, width)


def _table(title: str, header: list[str], rows: list[list[str]], width: int) -> str:
    """A titled text table; the last column (a description) wraps under itself."""
    import textwrap

    columns = [[str(cell) for cell in column] for column in zip(header, *rows)]
    # columns left empty in every row are dropped (a table without units has no unit column)
    keep = [index for index, column in enumerate(columns) if index == 0 or any(column[1:])]
    header = [header[index] for index in keep]
    rows = [[str(row[index]) for index in keep] for row in rows]
    widths = [max(len(cell) for cell in column) for column in zip(header, *rows)]
    indent = 2
    last_start = indent + sum(widths[:-1]) + 2 * (len(widths) - 1)
    last_width = max(30, width - last_start)

    def line(cells: list[str]) -> list[str]:
        head = "".join(cell.ljust(w + 2) for cell, w in zip(cells[:-1], widths[:-1]))
        wrapped = textwrap.wrap(cells[-1], width=last_width, break_on_hyphens=False) or [""]
        out = [(" " * indent + head + wrapped[0]).rstrip()]
        out += [" " * last_start + more for more in wrapped[1:]]
        return out

    rule = ["-" * w for w in widths[:-1]] + ["-" * min(widths[-1], last_width)]
    lines = [title] + line(header) + line(rule)
    for row in rows:
        lines += line(row)
    return "\n".join(lines)


# --------------------------------------------------------------------------
# Arrays of declarations and of components
# --------------------------------------------------------------------------


class ArrayMember:
    """What an array declaration becomes in a sized class: the whole array as one attribute.

    The sized class (:meth:`Component.__new__`) declares every element as an
    ordinary scalar declaration (``u[1]``, ``A[1,2]``); this descriptor
    gives ``self.u`` as an :class:`~acausal.arrays.Array` of their symbols
    (of bound connectors, for a connector array) and keeps the array's own
    declaration for ``show`` and ``describe``.
    """

    def __init__(self, declaration: Declaration, shape: tuple[int, ...]) -> None:
        self.declaration = declaration
        self.shape = shape

    def __set_name__(self, owner, name: str) -> None:
        self.name = name

    def __get__(self, obj, objtype=None):
        if obj is None:
            return self
        data = np.empty(self.shape, dtype=object)
        for index in indices(self.shape):
            data[tuple(i - 1 for i in index)] = getattr(obj, element_name(self.name, index))
        return Array(data, obj._path_of(self.name))


class ComponentArray(list):
    """An array of components, indexed from 1 as in Modelica (``self.cell[1]``).

    Made by assigning a list of components in ``build()``
    (``self.cell = [HeatCapacitor(C=1) for _ in range(n)]``), or by
    :meth:`of`; element ``i`` is the sub-component ``cell[i]``.  Iteration,
    ``len`` and Modelica-style slices (``cell[2:3]``, both ends included)
    work; ``cell.T`` is the :class:`~acausal.arrays.Array` of every
    element's ``T`` (a connector of each element gives an array of
    connectors, which ``connect`` joins element by element).
    """

    name = ""

    def __getitem__(self, key):
        view = Array(np.array(list(self) + [None], dtype=object)[:-1], self.name)
        picked = view[key]
        return ComponentArray(picked.flat) if isinstance(picked, Array) else picked

    def __getattr__(self, member: str):
        if member.startswith("_"):
            raise AttributeError(member)
        return Array([getattr(element, member) for element in self], f"{self.name}.{member}")

    @classmethod
    def of(cls, klass: type["Component"], n: int, **modifiers: Any) -> "ComponentArray":
        """``n`` instances of ``klass``; a modifier given as a list of ``n`` values gives one
        to each element, any other value (or :func:`~acausal.arrays.each`) to all.

        ``ComponentArray.of(Sine, 3, f=[1, 2, 3], amplitude=2)`` is Modelica's
        ``Sine sine[3](f={1, 2, 3}, each amplitude=2)``.
        """
        per_element = {key: _per_element(value, n, f"{klass.__name__}[{n}].{key}")
                       for key, value in modifiers.items()}
        return cls(klass(**{key: values[i] for key, values in per_element.items()}) for i in range(n))


def _per_element(value: Any, n: int, what: str) -> list[Any]:
    """A modifier of an array of ``n`` components for each element (see :meth:`ComponentArray.of`)."""
    if isinstance(value, dict):
        inner = {key: _per_element(v, n, f"{what}.{key}") for key, v in value.items()}
        return [{key: values[i] for key, values in inner.items()} for i in range(n)]
    if isinstance(value, Each) or not is_array_value(value):
        return [value.value if isinstance(value, Each) else value] * n
    if len(value) != n:
        raise ArraySizeError(f"{what} is given {len(value)} values for {n} components",
                             hint="give one value per element, or each(value) for all of them")
    return list(value)


def _resolved_shape(declaration: Declaration, name: str, value: Callable[[str], Any]) -> tuple[int, ...] | None:
    """The shape of an array declaration in an instance (None: a scalar).

    ``value(p)`` reads the structural parameter ``p`` (or a parameter's own
    value, whose shape an array parameter takes when it declares none).
    """
    shape = declaration.shape
    if shape is None:
        if isinstance(declaration, Parameter) and not declaration.structural:
            own = value(name)
            if is_array_value(own) and not isinstance(own, Each):
                return tuple(np.shape(np.asarray(own.data if isinstance(own, Array) else own, dtype=object)))
        return None
    dims = shape if isinstance(shape, tuple) else (shape,)
    resolved = []
    for dim in dims:
        size_ = _dimension(dim, value, name)
        if isinstance(size_, (bool, np.bool_)) or not isinstance(size_, (int, np.integer)) or size_ < 0:
            raise ModelDefinitionError(f"the size of array {name} is {size_!r}"
                                       + (f" (the parameter {dim})" if isinstance(dim, str) else ""),
                                       hint="an array's size is an integer >= 0, or the name of a "
                                            "structural Integer parameter")
        resolved.append(int(size_))
    return tuple(resolved)


_SIZE_OF = re.compile(r"^\s*size\(\s*([A-Za-z_]\w*)\s*,\s*(\d+)\s*\)\s*$")


def _dimension(dim: Any, value: Callable[[str], Any], name: str) -> Any:
    """One entry of a declared shape: an int; the name of a structural parameter; Modelica's
    ``"size(A, 1)"`` of an array parameter's value; or a function of ``value``."""
    if isinstance(dim, str):
        found = _SIZE_OF.match(dim)
        if found is None:
            return value(dim)
        array, k = found.group(1), int(found.group(2))
        given = value(array)
        dims = np.shape(np.asarray(given.data if isinstance(given, Array) else given, dtype=object))
        if not 1 <= k <= len(dims):
            raise ModelDefinitionError(f"the size of array {name} is {dim}, but {array} has {len(dims)} "
                                       f"dimension{'s' if len(dims) != 1 else ''}",
                                       hint=f"give {array} as a nested list with {k} dimensions")
        return dims[k - 1]
    if callable(dim):
        return dim(value)
    return dim


def _dimension_text(dim: Any) -> str:
    """How ``show`` writes one declared dimension: ``3``, ``n``, ``size(A, 1)``, or the ``text``
    a function of the sizes carries (``n1 + n2``; ``:`` without one)."""
    if isinstance(dim, (str, int)):
        return str(dim)
    return str(getattr(dim, "text", ":"))


def _element_declaration(declaration: Declaration, name: str, index: tuple[int, ...],
                         shape: tuple[int, ...], own_value: Any) -> Declaration:
    """The scalar declaration of element ``index`` of the array ``name``."""
    element = copy.copy(declaration)
    element.shape = None
    position = int(np.ravel_multi_index(tuple(i - 1 for i in index), shape)) if shape else 0
    if isinstance(declaration, Parameter):
        element.default = _pick(own_value, position, shape, name)
    elif isinstance(declaration, Variable):
        for attribute in ("start", "nominal", "min", "max", "fixed"):
            setattr(element, attribute, _element_attribute(getattr(declaration, attribute), position,
                                                           shape, f"{name}.{attribute}"))
    element.__set_name__(None, element_name(name, index))
    return element


def _pick(value: Any, position: int, shape: tuple[int, ...], what: str) -> Any:
    if value is None:
        return None
    return distribute(value, shape, what)[position]


def _element_attribute(value: Any, position: int, shape: tuple[int, ...], what: str) -> Any:
    """An attribute of one element: a list is per element; a function of the component is
    evaluated then picked; anything else is every element's."""
    if callable(value) and not isinstance(value, (sp.Basic, Each)):
        return lambda component: _pick(value(component), position, shape, what)
    return _pick(value, position, shape, what)


_SIZED: dict[tuple, type] = {}


def _sized_class(base: type, shapes: tuple, sized_by: tuple) -> type:
    """The subclass of ``base`` that declares every element of its arrays of ``shapes``
    (``((name, shape), ...)``) as a scalar; one per base class and sizes (see
    :meth:`Component.__new__`)."""
    key = (base, shapes)
    klass = _SIZED.get(key)
    if klass is not None:
        return klass
    everything = base.declarations()
    namespace: dict[str, Any] = {"__module__": base.__module__, "__qualname__": base.__qualname__,
                                 "_unsized": base, "_array_shapes": dict(shapes), "_sized_by": dict(sized_by)}
    own_doc = vars(base).get("__doc__")
    namespace["__doc__"] = getattr(own_doc, "_own", own_doc)
    for name, shape in shapes:
        declaration = everything[name]
        # the class's own default, never an instance's modifier (the sized class is
        # shared by every instance of these sizes; modifiers are applied per instance)
        own = declaration.default if isinstance(declaration, Parameter) else None
        if own is not None and (isinstance(own, Each) or not is_array_value(own)) is False \
                and tuple(np.shape(np.asarray(own, dtype=object))) != shape:
            own = None  # a default of another size: the value given where it is made counts
        for index in indices(shape):
            namespace[element_name(name, index)] = _element_declaration(declaration, name, index, shape, own)
        namespace[name] = ArrayMember(declaration, shape)
    klass = _SIZED[key] = type(base.__name__, (base,), namespace)
    for name, _ in shapes:
        namespace[name].__set_name__(klass, name)
    return klass


def _new_sized(base: type, shapes: tuple, sized_by: tuple) -> "Component":
    """An empty instance of a sized class, for unpickling (its state follows)."""
    return object.__new__(_sized_class(base, shapes, sized_by))


#: The component classes that define :meth:`Component.finished` themselves (a subclass of one inherits it).
_FINISHING_CLASSES: set[type] = set()


class Component:
    """A component: declarations, equations and (optionally) sub-components.

    Subclasses override :meth:`build` to create sub-components and connect
    them, :meth:`equations` for their equations and :meth:`initial_equations`
    for equations that hold only at initialization.  Modifiers given to the
    constructor set parameters and the attributes of variables.

    The docstring of a subclass gets sections listing its parameters,
    connectors and variables (inherited ones included), so that
    ``help(Inertia)`` shows ``J``, its default and its unit.
    """

    #: What this component knows about a failure that concerns it, by situation
    #: (the keys of :data:`HINT_SITUATIONS`).  The engine has no domain
    #: knowledge: it adds these hints to an error about this component's
    #: equations or variables.  Inherited along the class hierarchy; a subclass
    #: adds to or overrides its bases' entries.
    hints: Mapping[str, str] = {}

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        own = vars(cls).get("__doc__")
        if isinstance(own, _ComponentDoc):  # type(name, bases, dict(vars(other)))
            own = own._own
        cls.__doc__ = _ComponentDoc(cls, own)
        if "finished" in vars(cls):
            # simulate() looks for finish hooks only once some class defines one
            _FINISHING_CLASSES.add(cls)

    def __new__(cls, *args: Any, **modifiers: Any):
        """An instance of ``cls``, or of its *sized* class when it declares arrays.

        The sized class declares every element of every array as a scalar
        (``u[1]``, ``A[1,2]``), with the sizes the structural parameters and
        the modifiers given here (an array parameter's value) make; one
        sized class per base class and sizes.  Everything after the language
        sees scalars only.
        """
        base = vars(cls).get("_unsized", cls)
        declared = [(name, d) for name, d in base.declarations().items()
                    if d.shape is not None or (isinstance(d, Parameter) and not d.structural)]
        if not declared:
            return object.__new__(cls)
        everything = base.declarations()
        read: list[str] = []  # what the sizes are read from

        def value(name: str) -> Any:
            read.append(name)
            if name in modifiers:
                return modifiers[name]
            if name not in everything:
                raise ModelDefinitionError(f"{base.__name__}: an array size names {name!r}, which it "
                                           f"does not declare", hint="name a structural parameter")
            found = everything[name]
            return found.default if isinstance(found, Parameter) else None

        shapes = {}
        for name, declaration in declared:
            shape = _resolved_shape(declaration, name, value)
            if shape is not None:
                shapes[name] = shape
        if not shapes:
            return object.__new__(cls)
        # the structural parameters the sizes were read from: changing one later is refused
        sized_by = {d: value(d) for d in dict.fromkeys(read)
                    if isinstance(everything.get(d), Parameter) and everything[d].structural}
        klass = _sized_class(base, tuple(shapes.items()), tuple(sized_by.items()))
        return object.__new__(klass)

    #: In a sized class: the shape of each array it declares, ``{"u": (3,)}``.
    _array_shapes: Mapping[str, tuple[int, ...]] = {}

    def __reduce_ex__(self, protocol):
        # an instance of a sized class pickles by its base class and sizes (the sized class
        # is made at run time, so pickle cannot find it by its name)
        reduced = super().__reduce_ex__(protocol)
        klass = type(self)
        if "_unsized" not in vars(klass) or "_sized_by" not in vars(klass):
            return reduced
        sized = (klass._unsized, tuple(klass._array_shapes.items()), tuple(klass._sized_by.items()))
        return (_new_sized, sized, *reduced[2:])

    def __init__(self, **modifiers: Any) -> None:
        object.__setattr__(self, "_name", "")
        object.__setattr__(self, "_parent", None)
        object.__setattr__(self, "_children", {})
        object.__setattr__(self, "_connections", [])
        object.__setattr__(self, "_built", False)
        object.__setattr__(self, "_modifiers", {})
        object.__setattr__(self, "_attribute_modifiers", {})
        #: Modifiers of sub-components by their name, ``{"clutch": {"fn_max": 100}}``
        #: (Modelica's ``m(clutch(fn_max=100))``).  Sub-components exist only once
        #: build() has run: each gets its entry when build() assigns it.
        object.__setattr__(self, "_nested_modifiers", {})
        #: Arrays of sub-components by name (their elements are children ``name[i]``).
        object.__setattr__(self, "_component_arrays", {})
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
                elif isinstance(value, ArrayMember):
                    found.pop(key, None)  # declared element by element in this (sized) class
        return found

    @classmethod
    def array_declarations(cls) -> dict[str, tuple[Declaration, tuple[int, ...]]]:
        """The arrays of a sized class: ``{name: (declaration, shape)}``, in declaration order."""
        return {name: (vars(cls)[name].declaration, shape) for name, shape in cls._array_shapes.items()}

    def _apply_array_modifier(self, key: str, value: Any, declarations: dict[str, Declaration]) -> None:
        """A modifier of a whole array, given to its elements (a list element by element,
        a number or :func:`~acausal.arrays.each` to all)."""
        declaration, shape = type(self).array_declarations()[key]
        what = f"{self._modifier_owner()}.{key}"
        names = [element_name(key, index) for index in indices(shape)]
        if isinstance(declaration, Parameter):
            if isinstance(value, dict):
                raise ModifierError(f"{what} is a parameter: give it a value, not {value!r}")
            for name, element in zip(names, distribute(value, shape, what)):
                self._apply_modifier(name, element, declarations)
        elif isinstance(declaration, Variable):
            if not isinstance(value, dict):
                raise ModifierError(f"{what} is an array of variables: modify its attributes with a dict",
                                    hint=f"{type(self).__name__}({key}=dict(start=[...]))")
            per_attribute = {attribute: distribute(v, shape, f"{what}.{attribute}")
                             for attribute, v in value.items()}
            for position, name in enumerate(names):
                self._apply_modifier(name, {a: values[position] for a, values in per_attribute.items()},
                                     declarations)
        else:
            raise ModifierError(f"{what} is an array of connectors and takes no modifier")

    def _apply_modifier(self, key: str, value: Any, declarations: dict[str, Declaration]) -> None:
        """Apply the modifier ``key=value``: a parameter's value, a variable's attributes
        (a dict) or a sub-component's modifiers (a dict).

        A dict for a name the class does not declare is kept for the
        sub-component of that name, which build() creates later; build()
        checks that it did (:meth:`_check_nested_modifiers`).
        """
        owner = self._modifier_owner()
        where = type(self).__name__
        if key in type(self)._array_shapes:
            self._apply_array_modifier(key, value, declarations)
            return
        if key not in declarations:
            if isinstance(value, dict) and key in self._component_arrays:
                for element, modifiers in zip(self._component_arrays[key],
                                              _per_element(value, len(self._component_arrays[key]),
                                                           f"{owner}.{key}")):
                    self._apply_modifier(element.name, modifiers, declarations)
                return
            if isinstance(value, dict) and key in self._children:
                self._nested_modifiers[key] = _merged(self._nested_modifiers.get(key, {}), value)
                self._children[key]._apply_modifiers(value)
                return
            if isinstance(value, dict) and _may_have_subcomponents(type(self)) and not self._built:
                self._nested_modifiers[key] = _merged(self._nested_modifiers.get(key, {}), value)
                return
            raise self._unknown_modifier(key, value)
        declaration = declarations[key]
        if isinstance(declaration, Parameter):
            if isinstance(value, dict):
                raise ModifierError(f"{owner}.{key} is a parameter: give it a value, not {value!r}",
                                    hint=f"{where}({key}=1.0)")
            sized_by = vars(type(self)).get("_sized_by", {})
            if key in sized_by and not _same(value, sized_by[key]):
                raise ModifierError(
                    f"{owner}.{key} = {value!r} sizes arrays that were made with {key} = {sized_by[key]!r}",
                    hint=f"give {key} where the component is created ({where}({key}={value!r})): array "
                         f"sizes are fixed when the component is made")
            self._modifiers[key] = value
        elif isinstance(declaration, Variable):
            if not isinstance(value, dict):
                raise ModifierError(
                    f"{owner}.{key} is a variable: modify its attributes with a dict",
                    hint=f"{where}({key}=dict(start={value!r}, fixed=True))")
            unknown = set(value) - set(_VARIABLE_ATTRIBUTES)
            if unknown:
                raise ModifierError(f"{owner}.{key} has no attribute {sorted(unknown)[0]!r}",
                                    hint=f"variable attributes are {', '.join(_VARIABLE_ATTRIBUTES)}")
            self._attribute_modifiers.setdefault(key, {}).update(value)
        else:
            raise ModifierError(f"{owner}.{key} is a connector and takes no modifier")

    def _apply_modifiers(self, modifiers: Mapping[str, Any]) -> None:
        """Apply several modifiers; later ones (the outer ones) win over those applied before."""
        declarations = self.declarations()
        for key, value in modifiers.items():
            self._apply_modifier(key, value, declarations)

    def _modifier_owner(self) -> str:
        """How a modifier error names this component: its class, or, once it is part of
        a model, the model's class and the dotted path (``Drive.clutch``)."""
        if self._parent is None:
            return type(self).__name__
        root = self
        while root._parent is not None:
            root = root._parent
        return f"{type(root).__name__}.{self.path}"

    def _unknown_modifier(self, key: str, value: Any) -> ModifierError:
        """The error for a modifier naming nothing this component has, with the close names."""
        owner = self._modifier_owner()
        kind = type(self).__name__
        names = list(self.declarations())
        if self._built:
            names += list(self._children)
        candidates = difflib.get_close_matches(key, names, n=3)
        if candidates:
            hint = f"did you mean {', '.join(candidates)}?"
        else:
            hint = f"{kind} declares: {', '.join(sorted(names))}"
            if _may_have_subcomponents(type(self)) and not isinstance(value, dict):
                hint += "; a sub-component made in build() takes a dict of modifiers, name=dict(p=1)"
        what = "parameter, variable or sub-component" if self._built else "parameter or variable"
        # placed in a model: the modifier came from outside, so name its full dotted path
        where = kind if owner == kind else f"{owner}.{key}: {kind}"
        return ModifierError(f"{where} has no {what} named {key!r}", hint=hint)

    def _check_nested_modifiers(self) -> None:
        """After build(): every sub-component named by a modifier exists.

        Raises
        ------
        ModifierError
            For a modifier naming no declaration and no sub-component.
        """
        for key in self._nested_modifiers:
            if key not in self._children and key not in self._component_arrays:
                raise self._unknown_modifier(key, self._nested_modifiers[key])

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
        # a list of new components is an array of components; a list of components this
        # model already has (kept for convenience) stays a plain attribute
        if isinstance(value, (list, tuple)) and value and not key.startswith("_") \
                and all(isinstance(v, Component) and v._parent is None for v in value):
            self._add_component_array(key, value)
            return
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
            if key in self._children:
                # Replacing it would leave the first one in the connections made so far.
                raise ModelDefinitionError(
                    f"{type(self).__name__}.{key} is already a sub-component "
                    f"({type(self._children[key]).__name__} {self._path_of(key)}); "
                    f"assigning a {type(value).__name__} to it again would replace it",
                    hint=f"give the second one another name (self.{key}2 = ...)",
                    components=(self._path_of(key),))
            object.__setattr__(value, "_name", key)
            object.__setattr__(value, "_parent", self)
            self._children[key] = value
            nested = self._nested_modifiers.get(key)
            if nested:
                # after the modifiers build() gave it: the outer modifier wins, as in Modelica
                value._apply_modifiers(nested)
        object.__setattr__(self, key, value)

    def _add_component_array(self, key: str, elements) -> None:
        """``self.key = [c1, c2, ...]``: the sub-components ``key[1]``, ``key[2]``, ... and the
        :class:`ComponentArray` ``self.key`` (a modifier of ``key`` reaches every element)."""
        if key in self._component_arrays or key in self._children:
            raise ModelDefinitionError(f"{type(self).__name__}.{key} is already a sub-component or an "
                                       f"array of them", hint=f"give the second one another name")
        array = ComponentArray(elements)
        array.name = self._path_of(key)
        nested = self._nested_modifiers.get(key)
        self._component_arrays[key] = array
        for i, element in enumerate(elements, start=1):
            setattr(self, f"{key}[{i}]", element)
        if nested:
            # the outer modifier, element by element (a list gives one value to each)
            for element, modifiers in zip(elements, _per_element(nested, len(elements), array.name)):
                element._apply_modifiers(modifiers)
        object.__setattr__(self, key, array)

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
            self._check_nested_modifiers()

    # -- what subclasses write ---------------------------------------------

    def build(self) -> None:
        """Create sub-components and connect them (override)."""

    def equations(self) -> list:
        """Equations of this class (override; collected along the MRO)."""
        return []

    def initial_equations(self) -> list:
        """Equations that hold only at initialization (override)."""
        return []

    def finished(self, result: Any) -> None:
        """Act once on the result of a successful run (override; the default does nothing).

        :func:`~acausal.runtime.simulate.simulate` calls it, for every
        component of the simulated model whose class overrides it (in the
        order of :meth:`walk`), with the
        :class:`~acausal.runtime.result.SimulationResult` of a run that
        succeeded (``result.success``: it reached the stop time or a
        ``terminate()``), after the run and before returning the result: what
        Modelica writes in ``when terminal()`` and cannot compute in
        equations (a file, a transform of sampled values).  It is not called
        for a failed run, nor when ``simulate`` is given a translation (which
        holds no component instances).  Read values from ``result`` (this
        component's columns are ``f"{self.path}.name"``); the result cannot
        be changed.  A :class:`~acausal.errors.SimulationError` raised here
        makes the run a failure: ``simulate`` returns the result with
        status -1 and that error, and calls no further hooks.
        """

    def connect(self, a, b) -> None:
        """Modelica's ``connect(a, b)`` between two connectors or signals.

        Two arrays of them (``mux.y`` and ``demux.u``, ``cell.port`` of an
        array of components, slices such as ``cell[1:3].port``) are
        connected element by element; their sizes must agree.

        Raises
        ------
        ArraySizeError
            For two arrays of different sizes, or an array and a scalar.
        """
        left, right = isinstance(a, (Array, list, tuple)), isinstance(b, (Array, list, tuple))
        if not (left or right):
            self._connections.append((a, b))
            return
        shape_a = Array(a).shape if left else ()
        shape_b = Array(b).shape if right else ()
        if shape_a != shape_b:
            def named(x, shape):
                return (f"{getattr(x, 'name', '') or 'an array'} of size [{', '.join(map(str, shape))}]"
                        if shape else f"the scalar {getattr(x, 'path', x)}")
            raise ArraySizeError(f"{self._modifier_owner()}: connect({named(a, shape_a)}, {named(b, shape_b)})",
                                 hint="connect arrays of one size, or their elements one by one "
                                      "(connect(a[1], b[2]))")
        for x, y in zip(Array(a).flat, Array(b).flat):
            self._connections.append((x, y))

    def __repr__(self) -> str:
        """The constructor call with the modifiers, e.g. ``Clutch(fn_max=100)``.

        Parameter values first, then variable attributes and sub-component
        modifiers as dicts; a long value is cut short.  Attributes computed
        by a function of the component are left out: a class sets those for
        its own variables (an integrator's start from its parameter).
        """
        arguments = [f"{key}={_short(_value_text(value), 40)}" for key, value in self._modifiers.items()]
        for key, attributes in self._attribute_modifiers.items():
            given = {name: value for name, value in attributes.items()
                     if not (callable(value) and not isinstance(value, sp.Basic))}
            if given:
                arguments.append(f"{key}={_dict_text(given)}")
        arguments += [f"{key}={_dict_text(value)}" for key, value in self._nested_modifiers.items() if value]
        return f"{type(self).__name__}({', '.join(arguments)})"


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


def _resolve(model: Component, dotted: str) -> tuple[Component, str]:
    """The component and the member name of a dotted path (building what it passes)."""
    *path, member = dotted.split(".")
    node = model
    for part in path:
        node.ensure_built()
        child = node._children.get(part)
        if child is None:
            raise ModifierError(f"{type(model).__name__} has no component {'.'.join(path)!r}",
                                hint="parameters are named by their dotted path, e.g. component.parameter")
        node = child
    return node, member


def structural_names(model: Component, names) -> list[str]:
    """Those of the dotted parameter ``names`` that are structural parameters of ``model``."""
    out = []
    for name in names:
        try:
            node, member = _resolve(model, name)
        except ModifierError:
            continue  # not a component path: flattening says what it is
        declaration = node.declarations().get(member)
        if isinstance(declaration, Parameter) and declaration.structural:
            out.append(name)
    return out


def with_structural(model: Component, values: Mapping[str, Any]) -> Component:
    """A new, unbuilt instance of ``model``'s class with the structural parameters
    ``values`` (dotted paths) set, as Modelica re-translates for a new value.

    The new instance has the model's modifiers and its own attributes, but
    for those holding components (its ``build()`` makes them again); each
    component named gets its value before it is built, so that its
    ``build()`` and its conditional declarations see it.  ``model`` itself
    is not changed.
    """
    fresh = object.__new__(type(model))
    tree = {"_name", "_parent", "_children", "_connections", "_built", "_modifiers", "_attribute_modifiers",
            "_nested_modifiers", "_component_arrays"}
    for key, value in vars(model).items():
        if key in tree or key in model._children or _holds_components(value):
            continue  # what build() makes is made again
        object.__setattr__(fresh, key, value)
    Component.__init__(fresh)
    fresh._modifiers.update(model._modifiers)
    for key, attributes in model._attribute_modifiers.items():
        fresh._attribute_modifiers[key] = dict(attributes)
    for key, nested in model._nested_modifiers.items():
        fresh._nested_modifiers[key] = _merged({}, nested)
    # the shallow ones first: a component's value is set before the components it builds
    for name in sorted(values, key=lambda n: (n.count("."), n)):
        node, member = _resolve(fresh, name)
        declaration = node.declarations().get(member)
        if not (isinstance(declaration, Parameter) and declaration.structural):
            raise ModifierError(f"{name} is not a structural parameter of {type(model).__name__}")
        if node._built and node is not fresh:
            raise ModifierError(f"{name}: {node.path} was built before its structural parameter could be set",
                                hint="set it where the component is created")
        node._apply_modifier(member, values[name], node.declarations())
    return fresh


def _may_have_subcomponents(klass: type) -> bool:
    """Whether instances of ``klass`` may make sub-components: its build() is its own or a base's."""
    return klass.build is not Component.build


def _merged(inner: Mapping[str, Any], outer: Mapping[str, Any]) -> dict[str, Any]:
    """``inner`` modifiers updated by ``outer`` ones, dicts merged key by key (the outer wins)."""
    merged = dict(inner)
    for key, value in outer.items():
        if isinstance(value, dict) and isinstance(merged.get(key), dict):
            merged[key] = _merged(merged[key], value)
        else:
            merged[key] = dict(value) if isinstance(value, dict) else value
    return merged


def _holds_components(value: Any) -> bool:
    """Whether ``value`` is a component or a list, tuple, set or dict holding one."""
    if isinstance(value, Component):
        return True
    if isinstance(value, dict):
        return any(_holds_components(v) for v in value.values())
    if isinstance(value, (list, tuple, set, frozenset)):
        return any(_holds_components(v) for v in value)
    return False


def finish_hooks(model: Component) -> list[Component]:
    """The components of ``model`` whose class overrides :meth:`Component.finished`, in
    :meth:`Component.walk` order; ``[]`` at once, without walking, while no class loaded defines one."""
    if not _FINISHING_CLASSES:
        return []
    return [node for node in model.walk() if type(node).finished is not Component.finished]


def own_method(klass: type, name: str) -> Callable | None:
    """The method ``name`` defined in ``klass`` itself (not inherited)."""
    return vars(klass).get(name)
