"""acausal: Modelica-like acausal modelling in Python.

Write components and models with :mod:`acausal.language`, then
:func:`simulate` them.  The engine runs one stage per module, in the order
data flows:

``flatten`` → ``partition`` → (per discrete state) ``alias`` → ``structure``
→ ``blt`` → ``algebraic`` → ``codegen``, driven by ``translate``; then
``events``, ``initialization`` and ``simulate``.  ``compare`` checks results
against the Modelica reference results; ``explain`` shows the stages.
"""

from . import errors
from .errors import *  # noqa: F401,F403
from .arrays import Array, each
from .language import (
    Boolean,
    Component,
    ComponentArray,
    Connector,
    Eq,
    Experiment,
    Flow,
    If,
    Integer,
    Model,
    Parameter,
    Potential,
    RealInput,
    RealOutput,
    StateSelect,
    Variable,
    der,
    describe,
    initial,
    pre,
    time,
)
from .functions import prescribed
from .hybrid import (Assert, When, ceil, change, delay, div, edge, floor, homotopy, integer, mod, noEvent, reinit,
                     rem, sample, smooth, terminal, terminate)
from .runtime.result import Event, SimulationResult
from .runtime.simulate import METHODS, simulate
from .compiler.translate import Translation, translate
from .options import EngineOptions

__version__ = "0.1.0"


def _plot(result, names=None, **options):
    """``SimulationResult.plot``: the plotter lives with the tools (matplotlib is loaded
    only when a result is plotted)."""
    from .tools.plotting import plot

    return plot(result, names, **options)


from .runtime.result import register_plotter as _register_plotter  # noqa: E402

_register_plotter(_plot)

__all__ = [
    # the language
    "Boolean", "Component", "Connector", "Eq", "Experiment", "Flow", "If", "Integer", "Model",
    "Parameter", "Potential", "RealInput", "RealOutput", "StateSelect", "Variable", "der", "initial",
    "pre", "time", "describe",
    # arrays (acausal.arrays has Modelica's array functions)
    "Array", "ComponentArray", "each",
    # the hybrid language (Modelica chapter 8)
    "When", "reinit", "edge", "change", "sample", "terminal", "noEvent", "smooth", "homotopy", "Assert", "terminate",
    "floor", "ceil", "integer", "div", "mod", "rem", "delay",
    # functions with given derivatives (Modelica's derivative annotation)
    "prescribed",
    # the engine
    "METHODS", "EngineOptions", "Event", "SimulationResult", "Translation", "simulate", "translate",
    # the errors
    *errors.__all__,
]
