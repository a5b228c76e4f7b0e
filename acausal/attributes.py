"""Modelica's experiment annotation and the StateSelect attribute, as plain values.

A compiled model carries both (:class:`~acausal.compiler.compiled.ModelData`),
so they live here, apart from the language's symbolic machinery: loading a
compiled model imports this module and not sympy.  :mod:`acausal.language`
exports them as part of the language.
"""

from __future__ import annotations

import enum
from dataclasses import dataclass

__all__ = ["Experiment", "StateSelect"]


class StateSelect(enum.IntEnum):
    """Modelica's StateSelect; the value orders the wish to be a state."""

    never = 0
    avoid = 1
    default = 2
    prefer = 3
    always = 4


@dataclass(frozen=True)
class Experiment:
    """Modelica's experiment annotation.

    ``method`` names the integrator a model needs (e.g. ``"BDF"`` for a stiff
    one), as Modelica tools read it from a vendor annotation
    (``__Dymola_Algorithm``); ``simulate`` uses it unless told otherwise.
    """

    start_time: float = 0.0
    stop_time: float = 1.0
    interval: float | None = None
    tolerance: float | None = None
    method: str | None = None
