"""Declarations the component libraries share: arrays sized by structural parameters,
parameters whose defaults are expressions of other parameters.

:class:`VectorBlock` gives a component array declarations (Modelica's
``RealInput u[n]``), :class:`DerivedDefaults` parameters that default to an
expression of other parameters (``parameter Real uMin = -uMax``).  Both are
mixins of a component's other bases (Rotational and Translational ``Move``
take their input vector ``u[3]`` from VectorBlock; ElastoGap's ``f_ref``
defaults to ``c*s_ref`` through DerivedDefaults).
"""

from __future__ import annotations

from typing import Any, Callable, Mapping

import sympy as sp

from acausal.errors import ModelDefinitionError, ModifierError
from acausal.language import ArrayMember, Component, Declaration

__all__ = ["VectorBlock", "DerivedDefaults"]

#: (class, sizes) -> the subclass declaring those elements; one class per shape.
_SIZED: dict[tuple, type] = {}


class VectorBlock(Component):
    """A component with array declarations whose sizes depend on structural parameters.

    A subclass lists its arrays in :meth:`arrays`: for each array name its
    size and a function making the declaration of element ``i`` (counted
    from 1).  An instance is of a subclass (with the same name) declaring the
    elements ``name[1]`` ... ``name[n]``, so the flat model names them as
    Modelica does (``stateSpace.x[1]``).  A modifier of a whole array is
    applied to each element (Modelica's ``each``); a list of dicts gives one
    per element; ``**{"x[2]": dict(start=1)}`` modifies a single element.

    It is the language's arrays (``Variable(shape=...)``) for arrays whose
    elements differ in more than their index (a description per element):
    ``self.u`` is the :class:`~acausal.arrays.Array` of the elements and
    ``acausal show`` lists ``u[3]`` as one entry, as for a declared array.
    """

    #: array name -> size, in the sized subclasses.
    _array_sizes: Mapping[str, int] = {}

    @classmethod
    def arrays(cls, value: Callable[[str], Any]) -> dict[str, tuple[int, Callable[[int], Declaration]]]:
        """``{array: (size, declaration_of_element)}``; ``value(p)`` reads structural parameter ``p``."""
        return {}

    def __new__(cls, **modifiers: Any):
        base = vars(cls).get("_unsized", cls)
        declarations = base.declarations()

        def value(name: str) -> Any:
            if name in modifiers:
                return modifiers[name]
            return declarations[name].default

        arrays = base.arrays(value)
        sizes = tuple((name, int(size)) for name, (size, _) in arrays.items())
        key = (base, sizes)
        klass = _SIZED.get(key)
        if klass is None:
            namespace: dict[str, Any] = {
                "__module__": base.__module__,
                "__qualname__": base.__qualname__,
                "__doc__": vars(base).get("__doc__"),
                "_unsized": base,
                "_array_sizes": dict(sizes),
            }
            for name, (size, make) in arrays.items():
                for i in range(1, int(size) + 1):
                    namespace[f"{name}[{i}]"] = make(i)
            doc = namespace["__doc__"]
            if doc is not None and not isinstance(doc, str):
                namespace["__doc__"] = getattr(doc, "_own", None)
            shapes = {name: (int(size),) for name, (size, _) in arrays.items()}
            namespace["_array_shapes"] = shapes
            for name, shape in shapes.items():
                # the whole array as one attribute, described by its first element
                namespace[name] = ArrayMember(namespace[f"{name}[1]"] if shape[0] else Declaration(), shape)
            klass = _SIZED[key] = type(base.__name__, (base,), namespace)
            for name in shapes:
                namespace[name].__set_name__(klass, name)
        return object.__new__(klass)

    @classmethod
    def array_declarations(cls):
        """The arrays, with the sizes the defaults give for a class that is not sized yet."""
        if "_unsized" in vars(cls):
            return super().array_declarations()
        defaults = cls.declarations()
        found = {}
        for name, (size, make) in cls.arrays(lambda p: defaults[p].default).items():
            declaration = make(1) if size else Declaration()
            found[name] = (declaration, (int(size),))
        return found

    def __init__(self, **modifiers: Any) -> None:
        sizes = type(self)._array_sizes
        expanded: dict[str, Any] = {}
        for key, value in modifiers.items():
            if key in sizes and key not in type(self).declarations():
                n = sizes[key]
                if isinstance(value, dict):
                    for i in range(1, n + 1):
                        expanded[f"{key}[{i}]"] = dict(value)
                elif isinstance(value, (list, tuple)) and all(isinstance(v, dict) for v in value):
                    if len(value) != n:
                        raise ModifierError(f"{type(self).__name__}.{key} has {n} elements, "
                                            f"the modifier gives {len(value)}",
                                            hint=f"give one dict per element or a single dict "
                                                 f"for each element: {key}=dict(start=0)")
                    for i, v in enumerate(value, start=1):
                        expanded[f"{key}[{i}]"] = dict(v)
                else:
                    raise ModifierError(f"{type(self).__name__}.{key} is an array of variables: "
                                        f"modify its elements' attributes with a dict",
                                        hint=f"{type(self).__name__}({key}=dict(start=0, fixed=True))")
            else:
                expanded[key] = value
        super().__init__(**expanded)

    def vector(self, name: str) -> list[sp.Symbol]:
        """The symbols of the elements ``name[1]`` ... ``name[n]``."""
        n = type(self)._array_sizes.get(name)
        if n is None:
            raise ModelDefinitionError(f"{type(self).__name__} has no array {name!r}")
        return [getattr(self, f"{name}[{i}]") for i in range(1, n + 1)]


class DerivedDefaults(Component):
    """A component whose parameters default to expressions of its other parameters.

    ``derived_defaults = {"uMin": lambda block: -block.uMax}`` binds ``uMin``
    to ``-uMax`` unless a modifier gives it a value (Modelica's
    ``parameter Real uMin = -uMax``).  The parameter's declared default
    is ignored; give it ``None``.
    """

    derived_defaults: Mapping[str, Callable[[Component], Any]] = {}

    def parameter_binding(self, name: str) -> Any:
        if name not in self._modifiers:
            for klass in type(self).__mro__:
                derived = vars(klass).get("derived_defaults", {})
                if name in derived:
                    return derived[name](self)
        return super().parameter_binding(name)
