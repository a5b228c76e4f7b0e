"""Writing Modelica text: any acausal model as a Modelica model.

``dump(model)`` writes

* each component of acausal's library as its Modelica Standard Library class
  with the modifiers it was given (``Modelica.Mechanics.Rotational.Components.
  Inertia inertia1(J=2, w(start=1, fixed=true));``),
* each component of a class of the user's own as a Modelica class of its
  own, written out from its declarations and equations (a sympy to
  Modelica printer, :func:`acausal.modelica.expressions.to_modelica`),
* the model's own parameters, variables and equations, its ``connect``
  statements, and its experiment as ``annotation(experiment(...))``; the
  Modelica class it reproduces (``modelica_class``) as the vendor annotation
  ``__acausal(modelicaClass="...")``.

The text reads back (:func:`acausal.modelica.load`) into the same flat
model, so any Modelica tool can check what acausal computes, and a student
sees one model in both notations.
"""

from __future__ import annotations

import enum
from typing import Any

import numpy as np
import sympy as sp

from ..errors import ModelicaError
from ..language import (BoundConnector, Component, Connector, Model, Parameter, StateSelect, Variable,
                        own_method)

__all__ = ["dump"]

_INDENT = "  "

#: acausal's vendor-specific annotation (MLS 18.1: ``__`` and the tool's name).
_VENDOR = "__acausal"


def _msl_name(klass: type) -> str | None:
    from ..tools.catalog import msl_name

    base = vars(klass).get("_unsized", klass)
    return msl_name(base)


def _enum_name(value: enum.Enum) -> str:
    """``Modelica.Blocks.Types.Init.InitialState`` of an enumeration member acausal has."""
    from .read import _library_index

    _, enumerations = _library_index()
    for modelica, klass in enumerations.items():
        if klass is type(value):
            return f"{modelica}.{value.name}"
    raise ModelicaError(f"no Modelica type for the enumeration {type(value).__name__}")


def _number(value: float) -> str:
    if isinstance(value, (bool, np.bool_)):
        return "true" if value else "false"
    if isinstance(value, (int, np.integer)):
        return str(int(value))
    text = repr(float(value))
    if text in ("inf", "-inf", "nan"):
        raise ModelicaError(f"the value {text} has no Modelica literal")
    return text


def _value(value: Any, name) -> str:
    """A modifier or default value as Modelica text (numbers, Booleans, strings, arrays,
    enumerations, expressions of parameters)."""
    from .expressions import to_modelica

    if isinstance(value, enum.Enum):
        if isinstance(value, StateSelect):
            return f"StateSelect.{value.name}"
        return _enum_name(value)
    if isinstance(value, (bool, np.bool_, int, float, np.integer, np.floating)):
        return _number(value)
    if isinstance(value, str):
        return '"' + value.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(value, (list, tuple, np.ndarray)):
        array = np.asarray(value, dtype=object)
        if array.ndim == 2:  # Modelica's matrix constructor
            return "[" + "; ".join(", ".join(_value(v, name) for v in row) for row in array) + "]"
        return "{" + ", ".join(_value(v, name) for v in array.tolist()) + "}"
    if isinstance(value, sp.Basic):
        return to_modelica(value, name)
    raise ModelicaError(f"the value {value!r} has no Modelica form")


class _Writer:
    def __init__(self, model: Component) -> None:
        self.model = model
        self.classes: dict[type, str] = {}     # own classes written, by class -> their Modelica text
        self.order: list[type] = []

    # -- names relative to a component -------------------------------------------------------
    @staticmethod
    def namer(owner: Component):
        prefix = f"{owner.path}." if owner.path else ""

        def name(symbol) -> str:
            text = symbol.name
            if text.startswith(prefix):
                return text[len(prefix):]
            raise ModelicaError(f"{text} is not a name inside {owner.path or type(owner).__name__}")

        return name

    # -- modifiers ---------------------------------------------------------------------------
    def modifiers(self, component: Component, owner: Component) -> str:
        return _format(_tree(component), self.namer(owner))

    # -- classes -----------------------------------------------------------------------------
    def type_of(self, component: Component) -> str:
        klass = type(component)
        msl = _msl_name(klass)
        if msl is not None and not self._is_own(klass):
            return msl
        base = vars(klass).get("_unsized", klass)
        if base not in self.classes:
            self.classes[base] = ""  # being written (a class that contains itself would loop)
            self.classes[base] = self.own_class(base, component)
            self.order.append(base)
        return base.__name__

    @staticmethod
    def _is_own(klass: type) -> bool:
        module = getattr(vars(klass).get("_unsized", klass), "__module__", "")
        return not module.startswith(("acausal.library", "acausal.components", "library.", "components."))

    def own_class(self, klass: type, instance: Component) -> str:
        kind = "block" if all(getattr(d, "causality", "") or isinstance(d, Parameter)
                              for d in klass.declarations().values() if isinstance(d, Variable)) \
            and any(getattr(d, "causality", "") for d in klass.declarations().values()) else "model"
        lines = [f"{kind} {klass.__name__}" + (f' "{_doc(klass)}"' if _doc(klass) else "")]
        lines += self.body(instance, own=True)
        lines.append(f"end {klass.__name__};")
        return "\n".join(lines)

    def declarations(self, component: Component) -> list[str]:
        from ..arrays import element_name, indices

        lines = []
        name = self.namer(component)
        # a sized class declares every element of an array: Modelica declares the array once
        arrays = type(component).array_declarations() if hasattr(type(component), "array_declarations") else {}
        element_of = {element_name(array, index): array for array, (_, shape) in arrays.items()
                      for index in indices(shape)}
        written: set[str] = set()
        for key, declaration in type(component).declarations().items():
            if not declaration.enabled(component):
                continue
            array = element_of.get(key)
            if array is not None:
                if array in written:
                    continue
                written.add(array)
                text = self.array_declaration(component, array, *arrays[array], name)
            else:
                text = self.declaration(component, key, declaration, name)
            if text:
                lines.append(_INDENT + text)
        return lines

    def array_declaration(self, component: Component, array: str, declaration, shape: tuple[int, ...],
                          name) -> str:
        """The declaration of the whole array ``array`` of ``shape`` (its elements' values and
        attributes as arrays), as the sizes of this instance give it."""
        from ..arrays import element_name, indices

        names = [element_name(array, index) for index in indices(shape)]
        dims = f"[{', '.join(str(n) for n in shape)}]"
        described = f' "{declaration.description}"' if declaration.description else ""

        def whole(values: list) -> str:
            return _value(np.asarray(values + [None], dtype=object)[:-1].reshape(shape).tolist(), name)

        if isinstance(declaration, Connector):
            msl = _msl_name(type(declaration))
            if msl is None:
                raise ModelicaError(f"the connector {type(declaration).__name__} of {type(component).__name__} "
                                    f"has no Modelica class")
            return f"{msl} {array}{dims}{described};"
        if isinstance(declaration, Parameter):
            values = [component.parameter_binding(n) for n in names]
            kinds = {_kind(v) for v in values if v is not None}
            kind = kinds.pop() if len(kinds) == 1 else "Real"
            attributes = [f'unit="{declaration.unit}"'] if declaration.unit else []
            known = all(v is not None for v in values)
            binding = f" = {whole(values)}" if known and names else ""
            if declaration.fixed is not True:
                attributes += ([f"start={whole(values)}"] if known and names else []) + ["fixed=false"]
                binding = ""
            modification = f"({', '.join(attributes)})" if attributes else ""
            return f"parameter {kind} {array}{dims}{modification}{binding}{described}{_evaluate(declaration, kind)};"
        if isinstance(declaration, Variable):
            kind = {"boolean": "Boolean", "integer": "Integer"}.get(declaration.kind, "Real")
            prefix = {"input": "input ", "output": "output "}.get(declaration.causality, "")
            if getattr(declaration, "discrete", False):
                prefix = "discrete " + prefix
            attributes = []
            if declaration.unit and kind == "Real":
                attributes.append(f'unit="{declaration.unit}"')
            starts = [component.attribute(n, "start") for n in names]
            fixed = [bool(component.attribute(n, "fixed")) for n in names]
            if any(s not in (None, 0, 0.0, False) for s in starts) or any(fixed):
                attributes.append(f"start={whole([0.0 if s is None else s for s in starts])}")
            if any(fixed):
                attributes.append(f"fixed={whole(fixed)}" if not all(fixed) else "each fixed=true")
            modification = f"({', '.join(attributes)})" if attributes else ""
            return f"{prefix}{kind} {array}{dims}{modification}{described};"
        return ""

    def declaration(self, component: Component, key: str, declaration, name) -> str:
        described = f' "{declaration.description}"' if declaration.description else ""
        if isinstance(declaration, Connector):
            msl = _msl_name(type(declaration))
            if msl is None:
                raise ModelicaError(f"the connector {type(declaration).__name__} of {type(component).__name__} "
                                    f"has no Modelica class")
            return f"{msl} {key}{described};"
        if isinstance(declaration, Parameter):
            value = component.parameter_binding(key)
            if value is None and declaration.structural:
                # a structural parameter left unset only chooses what build() makes (``m`` is
                # ``n`` unless given): the class is written from what it made, which does not
                # read it, and Modelica has no value to give it
                return ""
            kind = _kind(value)
            attributes = [f'unit="{declaration.unit}"'] if declaration.unit else []
            binding = "" if value is None else f" = {_value(value, name)}"
            if declaration.fixed is not True:  # found by the initial equations, from its start value
                attributes += ([f"start={_value(value, name)}"] if value is not None else []) + ["fixed=false"]
                binding = ""
            modification = f"({', '.join(attributes)})" if attributes else ""
            prefix = "parameter"
            return f"{prefix} {kind} {key}{modification}{binding}{described}{_evaluate(declaration, kind)};"
        if isinstance(declaration, Variable):
            kind = {"boolean": "Boolean", "integer": "Integer"}.get(declaration.kind, "Real")
            prefix = {"input": "input ", "output": "output "}.get(declaration.causality, "")
            if getattr(declaration, "discrete", False):
                prefix = "discrete " + prefix
            attributes = []
            if declaration.unit and kind == "Real":
                attributes.append(f'unit="{declaration.unit}"')
            start = component.attribute(key, "start")
            fixed = component.attribute(key, "fixed")
            if start not in (None, 0, 0.0, False) or fixed:
                attributes.append(f"start={_value(start, name)}")
            if fixed:
                attributes.append("fixed=true")
            modification = f"({', '.join(attributes)})" if attributes else ""
            return f"{prefix}{kind} {key}{modification}{described};"
        return ""

    def body(self, component: Component, own: bool) -> list[str]:
        component.ensure_built()
        lines = self.declarations(component)
        arrays = getattr(component, "_component_arrays", {})
        for child_name, child in component._children.items():
            array_name, bracket, rest = child_name.partition("[")
            if not bracket:
                lines.append(f"{_INDENT}{self.type_of(child)} {child_name}{self.modifiers(child, component)};")
            elif rest == "1]" and array_name in arrays:  # an array of components, where it began
                lines.append(self.component_array(array_name, arrays[array_name], component))
        equations = self.equations(component)
        connects = self.connects(component)
        if equations or connects:
            lines.append("equation")
            lines += [_INDENT + c for c in connects] + [_INDENT + e for e in equations]
        initial = self.equations(component, "initial_equations")
        if initial:
            lines.append("initial equation")
            lines += [_INDENT + e for e in initial]
        return lines

    def component_array(self, array_name: str, array, component: Component) -> str:
        kinds = {self.type_of(element) for element in array}
        if len(kinds) != 1:
            raise ModelicaError(f"the array {array_name} holds components of several classes")
        # one modifier for all elements, a value per element as an array ({1, 2, 3})
        merged = _merged_trees([_tree(element) for element in array], array_name)
        return f"{_INDENT}{kinds.pop()} {array_name}[{len(array)}]{_format(merged, self.namer(component), True)};"

    def connects(self, component: Component) -> list[str]:
        name = self.namer(component)
        out = []
        for a, b in component._connections:
            out.append(f"connect({_end(a, name)}, {_end(b, name)});")
        return out

    def equations(self, component: Component, method: str = "equations") -> list[str]:
        from ..language import Eq  # noqa: F401 - the equations are sympy Equalities
        from .expressions import to_modelica

        name = self.namer(component)
        out = []
        klass = vars(type(component)).get("_unsized", type(component))
        if not self._is_own(klass) and component is not self.model:
            return []
        for base in reversed(type(component).__mro__):
            own = own_method(base, method)
            # an own class is written out whole, its declarations inherited from a library base
            # included: so are that base's equations (FourPin's v1 = p1.v - n1.v)
            if own is None or base is Component:
                continue
            items = own(component) or []
            for item in _flat(items):
                out += _statement(item, name, f"{base.__name__}.{method}()")
        return out


def _tree(component: Component) -> dict:
    """The modifiers ``component`` was given: values, and dicts of variable attributes and of
    sub-components' modifiers."""
    tree: dict[str, Any] = dict(component._modifiers)
    for key, attributes in component._attribute_modifiers.items():
        given = {a: v for a, v in attributes.items() if not (callable(v) and not isinstance(v, sp.Basic))}
        if given:
            tree[key] = given
    for key, nested in component._nested_modifiers.items():
        if nested:
            tree[key] = nested
    return _whole_arrays(component, tree)


def _whole_arrays(component: Component, tree: dict) -> dict:
    """``tree`` with the modifiers of array elements (``a[1]``, ``A[1,2]``, ``x[2](start=...)``)
    brought together into one modifier of the whole array (``a={...}``, ``x(start={...})``).

    A sized component keeps a modifier per element, but Modelica's modification names a
    component without subscripts (MLS 7.2): an array is modified whole.  Elements not given
    take their current value, so the array written is the one the component has.
    """
    arrays = type(component).array_declarations() if hasattr(type(component), "array_declarations") else {}
    if not arrays:
        return tree
    from ..arrays import element_name, indices

    out: dict[str, Any] = {}
    grouped: dict[str, str] = {}  # element name -> its array
    for name, (_, shape) in arrays.items():
        for index in indices(shape):
            grouped[element_name(name, index)] = name
    for key, value in tree.items():
        array = grouped.get(key)
        if array is None:
            out[key] = value
            continue
        if array in out:
            continue  # written with the first element given
        declaration, shape = arrays[array]
        names = [element_name(array, index) for index in indices(shape)]
        if isinstance(declaration, Parameter):
            values = [component._modifiers[n] if n in component._modifiers else component.parameter_binding(n)
                      for n in names]
            out[array] = np.asarray(values + [None], dtype=object)[:-1].reshape(shape).tolist()
        else:
            given = list(dict.fromkeys(attribute for n in names if isinstance(tree.get(n), dict)
                                       for attribute in tree[n]))
            out[array] = {attribute: np.asarray([tree[n][attribute] if attribute in tree.get(n, {})
                                                  else component.attribute(n, attribute) for n in names] + [None],
                                                 dtype=object)[:-1].reshape(shape).tolist()
                          for attribute in given}
    return out


class _PerElement(list):
    """The values of one modifier for each element of an array of components."""


def _merged_trees(trees: list[dict], array: str) -> dict:
    """One modifier tree for an array of components: a value all elements share, or the list
    of the elements' values."""
    keys = list(dict.fromkeys(k for tree in trees for k in tree))
    merged: dict[str, Any] = {}
    for key in keys:
        if any(key not in tree for tree in trees):
            raise ModelicaError(f"{array}: some elements have a modifier of {key} and others not",
                                hint="give it to every element (its default where it is not changed)")
        values = [tree[key] for tree in trees]
        if all(isinstance(v, dict) for v in values):
            merged[key] = _merged_trees(values, f"{array}.{key}")
        elif all(repr(v) == repr(values[0]) for v in values):
            merged[key] = values[0]
        else:
            merged[key] = _PerElement(values)
    return merged


def _format(tree: dict, name, array: bool = False) -> str:
    """A modifier tree as Modelica's modification; for an array of components (``array``) a
    list every element takes is marked ``each``."""
    parts = []
    for key, value in tree.items():
        if isinstance(value, dict):
            parts.append(f"{_attribute(key)}{_format(value, name, array)}")
        elif isinstance(value, _PerElement):
            parts.append(f"{_attribute(key)}={{{', '.join(_value(v, name) for v in value)}}}")
        else:
            prefix = "each " if array and isinstance(value, (list, tuple)) else ""  # every element's array
            parts.append(f"{prefix}{_attribute(key)}={_value(value, name)}")
    return f"({', '.join(parts)})" if parts else ""


def _statement(item, name, where: str) -> list[str]:
    """One item of ``equations()`` as Modelica lines: an equation, a when-clause (with its
    reinit, terminate and assert), an assert."""
    from ..hybrid import Assert, Reinit, Terminate, When
    from .expressions import to_modelica

    if isinstance(item, sp.Equality):
        return [f"{to_modelica(item.lhs, name)} = {to_modelica(item.rhs, name)};"]
    if isinstance(item, Reinit):
        return [f"reinit({to_modelica(item.variable, name)}, {to_modelica(sp.sympify(item.value), name)});"]
    if isinstance(item, Terminate):
        return [f"terminate({_value(item.message, name)});"]
    if isinstance(item, Assert):
        level = ", AssertionLevel.warning" if item.level == "warning" else ""
        return [f"assert({to_modelica(item.condition, name)}, {_value(item.message, name)}{level});"]
    if isinstance(item, When):
        lines = []
        for k, (condition, body) in enumerate(item.branches):
            conditions = condition if isinstance(condition, (list, tuple)) else [condition]
            test = ", ".join(to_modelica(sp.sympify(c), name) for c in conditions)
            test = f"{{{test}}}" if len(conditions) > 1 else test
            lines.append(f"{'when' if k == 0 else 'elsewhen'} {test} then")
            for inner in body:
                lines += [_INDENT + line for line in _statement(inner, name, where)]
        lines.append("end when;")
        return lines
    raise ModelicaError(f"{type(item).__name__} in {where} has no Modelica form yet")


def _flat(items) -> list:
    out = []
    for item in items if isinstance(items, (list, tuple)) else [items]:
        out.extend(_flat(item) if isinstance(item, (list, tuple)) else [item])
    return out


def _end(end, name) -> str:
    if isinstance(end, BoundConnector):
        return name(sp.Symbol(end.path))
    if isinstance(end, sp.Symbol):
        return name(end)
    raise ModelicaError(f"connect({end!r}): an end that is neither a connector nor a signal")


def _kind(value: Any) -> str:
    if isinstance(value, (bool, np.bool_)):
        return "Boolean"
    if isinstance(value, (int, np.integer)) and not isinstance(value, enum.Enum):
        return "Integer"
    if isinstance(value, str):
        return "String"
    return "Real"


def _evaluate(declaration: Parameter, kind: str) -> str:
    """``annotation(Evaluate=...)`` where a parameter's kind alone would not say whether it is
    structural: the reader takes Integer, Boolean and String parameters for structural, Real
    ones for tunable (the annotation says otherwise, MLS 18.3)."""
    if declaration.structural == (kind != "Real"):
        return ""
    return f" annotation(Evaluate={'true' if declaration.structural else 'false'})"


def _attribute(key: str) -> str:
    return {"display_unit": "displayUnit", "state_select": "stateSelect"}.get(key, key)


def _doc(klass: type) -> str:
    from ..language import own_docstring

    first = own_docstring(klass).strip().split("\n\n")[0].replace("\n", " ")
    return first.replace('"', "'")


def dump(model: Component | type, name: str | None = None) -> str:
    """``model`` as Modelica text.

    Parameters
    ----------
    model : Model instance or class
    name : str, optional
        The Modelica model's name (default the class's name).

    Returns
    -------
    str
        One Modelica model; the classes of the user's own components come
        first, then the model.

    Raises
    ------
    ModelicaError
        For what has no Modelica form yet (a when-clause in a user's own
        component, an array of components with different modifiers).
    """
    instance = model() if isinstance(model, type) else model
    writer = _Writer(instance)
    title = name or type(instance).__name__
    lines = [f"model {title}" + (f' "{_doc(type(instance))}"' if _doc(type(instance)) else "")]
    body = writer.body(instance, own=True)
    own = [writer.classes[k] for k in writer.order]
    for text in own:
        lines += [_INDENT + line if line else line for line in text.splitlines()]
    lines += body
    experiment = getattr(type(instance), "experiment", None)
    annotations = []
    if isinstance(instance, Model) and experiment is not None:
        values = [f"StartTime={_number(experiment.start_time)}", f"StopTime={_number(experiment.stop_time)}"]
        if experiment.interval is not None:
            values.append(f"Interval={_number(experiment.interval)}")
        if experiment.tolerance is not None:
            values.append(f"Tolerance={_number(experiment.tolerance)}")
        annotations.append(f"experiment({', '.join(values)})")
    modelica_class = getattr(type(instance), "modelica_class", None)
    if isinstance(instance, Model) and isinstance(modelica_class, str) and modelica_class \
            and modelica_class != title:
        # the class this model reproduces, in acausal's vendor annotation (MLS 18.1): read
        # back, the model keeps its reference results and its instance names
        # (getInstanceName(), which seeds noise, starts with the class's name)
        annotations.append(f"{_VENDOR}(modelicaClass={_value(modelica_class, None)})")
    if annotations:
        lines.append(f"{_INDENT}annotation({', '.join(annotations)});")
    lines.append(f"end {title};")
    return "\n".join(lines) + "\n"
