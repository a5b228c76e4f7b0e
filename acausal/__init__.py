"""acausal: Modelica-like acausal modelling in Python.

Write components and models with :mod:`acausal.language`, then
:func:`simulate` them.  The engine runs one stage per module, in the order
data flows:

``flatten`` → ``partition`` → (per discrete state) ``alias`` → ``structure``
→ ``blt`` → ``algebraic`` → ``codegen``, driven by ``translate``; then
``events``, ``initialization`` and ``simulate``.  ``compare`` checks results
against the Modelica reference results; ``explain`` shows the stages.
"""

import importlib

from . import errors
from .errors import *  # noqa: F401,F403

#: Where each public name lives.  They are imported on first use (PEP 562), so that
#: ``import acausal`` and the runtime (a compiled model run from the cache, a sweep's
#: worker) load neither sympy nor networkx until a model is written or translated.
_EXPORTS = {
    **dict.fromkeys(("Array", "each"), "arrays"),
    **dict.fromkeys(("Boolean", "Component", "ComponentArray", "Connector", "Eq", "Experiment", "Flow", "If",
                     "Integer", "Model", "Parameter", "Potential", "RealInput", "RealOutput", "StateSelect",
                     "Variable", "der", "describe", "initial", "pre", "time"), "language"),
    "prescribed": "functions",
    **dict.fromkeys(("Assert", "When", "ceil", "change", "delay", "div", "edge", "floor", "homotopy", "integer",
                     "mod", "noEvent", "reinit", "rem", "sample", "smooth", "terminal", "terminate"), "hybrid"),
    **dict.fromkeys(("Event", "SimulationResult"), "runtime.result"),
    **dict.fromkeys(("METHODS", "simulate"), "runtime.simulate"),
    **dict.fromkeys(("Translation", "translate"), "compiler.translate"),
    "EngineOptions": "options",
}


def __getattr__(name: str):
    module = _EXPORTS.get(name)
    if module is None:
        raise AttributeError(f"module 'acausal' has no attribute {name!r}")
    value = getattr(importlib.import_module(f".{module}", __name__), name)
    globals()[name] = value  # found once: later lookups are plain attribute reads
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_EXPORTS))


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
