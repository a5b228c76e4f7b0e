"""Checks of parameter values that the component libraries share.

A component checks its numeric parameters in ``build()`` so that a bad value
is reported before any equation is generated, naming the component
(:func:`where`) and the parameter.  A parameter bound to an expression of
other parameters is left to flattening, which evaluates it.
"""

from __future__ import annotations

import numbers
from typing import Any

import sympy as sp

from acausal.errors import ParameterError

__all__ = ["where", "parameter_number", "check_min", "check_positive"]


def where(component: Any) -> str:
    """The component's dotted path for messages (its class name while it is not part of a model)."""
    return component.path or type(component).__name__


def parameter_number(component: Any, name: str) -> float | None:
    """The numeric value of parameter ``name``, or None if it is bound to an expression of other parameters."""
    value = component.parameter_binding(name)
    if isinstance(value, sp.Basic):
        return float(value) if value.is_number else None
    return float(value) if isinstance(value, numbers.Real) else None


def check_min(component: Any, name: str, minimum: float, hint: str) -> None:
    """Raise ParameterError if the numeric parameter ``name`` is below ``minimum``.

    Parameters
    ----------
    component : Component
    name : str
        The parameter.
    minimum : float
        The least value allowed (``value >= minimum``).
    hint : str
        What the parameter means and why it must not be smaller.
    """
    value = parameter_number(component, name)
    if value is not None and value < minimum:
        raise ParameterError(f"{where(component)}.{name} = {value:g} is below its minimum {minimum:g}",
                             hint=hint)


def check_positive(component: Any, name: str, hint: str) -> None:
    """Raise ParameterError if the numeric parameter ``name`` is not > 0 (the error names the component)."""
    value = parameter_number(component, name)
    if value is not None and not value > 0:
        raise ParameterError(f"{where(component)}.{name} = {value:g} must be > 0", hint=hint,
                             components=(component.path,))
