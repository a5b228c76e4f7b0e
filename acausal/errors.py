"""Every error acausal raises on purpose.

Each exception subclasses the built-in a Python user would expect
(``ValueError`` for bad models and parameters, ``RuntimeError`` for failures
during simulation), so ``except ValueError`` keeps working.  Messages name the
component, the variable or the equation concerned and end with a hint.
"""

from __future__ import annotations

__all__ = [
    "AcausalError",
    "ModelDefinitionError",
    "EquationError",
    "ModifierError",
    "ConnectionError_",
    "ParameterError",
    "StructuralError",
    "OverDeterminedError",
    "UnderDeterminedError",
    "StructurallySingularError",
    "InitializationError",
    "SimulationError",
    "EventIterationError",
    "ChatteringError",
    "SolverError",
    "ReferenceDataError",
]


class AcausalError(Exception):
    """Base class of every error acausal raises deliberately."""

    def __init__(self, message: str, hint: str | None = None) -> None:
        self.hint = hint
        text = message if hint is None else f"{message}\n  hint: {hint}"
        super().__init__(text)


class ModelDefinitionError(AcausalError, ValueError):
    """A model or component is written wrongly (declarations, build)."""


class EquationError(ModelDefinitionError):
    """An equation is not an equation (e.g. a Python bool from ``==``)."""


class ModifierError(ModelDefinitionError, TypeError):
    """A modifier names something the component does not declare."""


class ConnectionError_(ModelDefinitionError):
    """A connect() joins incompatible or disabled connectors.

    Named with a trailing underscore so it does not shadow the built-in
    ``ConnectionError`` (which is about sockets).
    """


class ParameterError(ModelDefinitionError):
    """A parameter value is out of its allowed range or malformed."""


class StructuralError(AcausalError, ValueError):
    """The equation system is not solvable as posed."""


class OverDeterminedError(StructuralError):
    """More equations than unknowns (in the whole model or one part of it)."""


class UnderDeterminedError(StructuralError):
    """More unknowns than equations."""


class StructurallySingularError(StructuralError):
    """Balanced in count, but some equations cannot be matched to unknowns."""


class InitializationError(AcausalError, ValueError):
    """Initial values are missing, conflicting or cannot be solved."""


class SimulationError(AcausalError, RuntimeError):
    """A simulation stopped before its end; the partial result is attached.

    Attributes
    ----------
    result : acausal.result.SimulationResult or None
        Everything computed up to the failure.
    """

    def __init__(self, message: str, hint: str | None = None, result=None) -> None:
        super().__init__(message, hint)
        self.result = result


class EventIterationError(SimulationError):
    """Event iteration did not reach a fixed point of the discrete variables."""


class ChatteringError(SimulationError):
    """Too many events in a vanishing window of time."""


class SolverError(SimulationError):
    """The numerical integrator or an algebraic solve failed."""


class ReferenceDataError(AcausalError, ValueError):
    """Reference result files are missing or malformed."""
